// bk_physics bodies: the body description's defaults and validation, creating
// and destroying bodies, and the bk_physics_body_* API.
#include "physics_internal.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace {

const double default_friction = 0.6;
const double default_restitution = 0.1;

} // namespace

// ---------------------------------------------------------------- bodies

bk_body_def bk_default_body_def(void) {
  bk_body_def d = {};
  d.transform = bk_transform_identity();
  d.friction = default_friction;
  d.restitution = default_restitution;
  return d;
}

namespace {

bool check_finite(double value, const char* field, bk_error* err) {
  if (std::isfinite(value)) return true;
  return bk_error_set(err, "body: %s must be finite (got %g)", field, value);
}

bool check_finite(bk_vec3 v, const char* field, bk_error* err) {
  if (bk_v3_is_finite(v)) return true;
  return bk_error_set(err, "body: %s must be finite (got %g, %g, %g)", field, v.x, v.y, v.z);
}

bool validate_body(const bk_physics* w, const bk_body_def* d, bk_error* err) {
  if (!w) return bk_error_set(err, "body: world is NULL");
  if (!d) return bk_error_set(err, "body: description is NULL");
  const ShapeSlot* shape = w->shape(d->shape);
  if (!shape)
    return bk_error_set(err, "body: shape {%u, %u} is not a valid shape id", d->shape.index,
                        d->shape.generation);
  if (!(std::isfinite(d->mass) && d->mass >= 0.0))
    return bk_error_set(err, "body: mass must be finite and >= 0 (got %g)", d->mass);
  if (shape->kind == ShapeKind::plane && d->mass != 0.0)
    return bk_error_set(err, "body: mass must be 0 for a plane shape (planes are static only; got %g)",
                        d->mass);
  bk_vec3 I = d->inertia;
  if (!check_finite(I, "inertia", err)) return false;
  if (d->mass > 0.0 && !(I.x > 0.0 && I.y > 0.0 && I.z > 0.0))
    return bk_error_set(err, "body: inertia must be > 0 on a dynamic body (got %g, %g, %g)", I.x, I.y, I.z);
  if (!check_finite(d->transform.position, "transform.position", err)) return false;
  if (!quat_is_finite(d->transform.rotation))
    return bk_error_set(err, "body: transform.rotation must be finite");
  bk_quat q = d->transform.rotation;
  double q_length = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!(q_length > 0.5 && q_length < 2.0))
    return bk_error_set(err, "body: transform.rotation must be a unit quaternion (length %g)", q_length);
  if (!check_finite(d->linear_velocity, "linear_velocity", err) ||
      !check_finite(d->angular_velocity, "angular_velocity", err) ||
      !check_finite(d->friction, "friction", err) || !check_finite(d->restitution, "restitution", err) ||
      !check_finite(d->rolling_friction, "rolling_friction", err) ||
      !check_finite(d->linear_damping, "linear_damping", err) ||
      !check_finite(d->angular_damping, "angular_damping", err) ||
      !check_finite(d->ccd_radius, "ccd_radius", err))
    return false;
  if (d->friction < 0.0) return bk_error_set(err, "body: friction must be >= 0 (got %g)", d->friction);
  if (!(d->restitution >= 0.0 && d->restitution <= 1.0))
    return bk_error_set(err, "body: restitution must be in [0, 1] (got %g)", d->restitution);
  if (d->rolling_friction < 0.0)
    return bk_error_set(err, "body: rolling_friction must be >= 0 (got %g)", d->rolling_friction);
  if (!(d->linear_damping >= 0.0 && d->linear_damping <= 1.0))
    return bk_error_set(err, "body: linear_damping must be in [0, 1] (got %g)", d->linear_damping);
  if (!(d->angular_damping >= 0.0 && d->angular_damping <= 1.0))
    return bk_error_set(err, "body: angular_damping must be in [0, 1] (got %g)", d->angular_damping);
  if (d->ccd_radius < 0.0) return bk_error_set(err, "body: ccd_radius must be >= 0 (got %g)", d->ccd_radius);
  return true;
}

/// Radius of a sphere around the body origin that stays inside the shape:
/// Bullet sweeps it for continuous collision detection.
double embedded_radius(const ShapeSlot& s) {
  if (s.inner_radius > 0.0) return s.inner_radius;
  btVector3 lo, hi;
  s.shape->getAabb(btTransform::getIdentity(), lo, hi);
  btVector3 size = hi - lo;
  return 0.25 * size[size.minAxis()];
}

} // namespace

bk_body_id bk_physics_create_body(bk_physics* w, const bk_body_def* desc, bk_error* err) {
  const bk_body_id null_id = {0, 0};
  if (!validate_body(w, desc, err)) return null_id;
  const bk_body_def& d = *desc;
  uint32_t index;
  try {
    index = w->bodies.allocate();
  } catch (...) {
    bk_error_set(err, "body: out of memory");
    return null_id;
  }
  ShapeSlot& shape = w->shapes.slots[d.shape.index];
  bool dynamic = d.mass > 0.0;
  btVector3 inertia = dynamic ? to_bt(d.inertia) : btVector3(0, 0, 0);
  btRigidBody::btRigidBodyConstructionInfo info((btScalar)d.mass, nullptr, shape.shape, inertia);
  info.m_startWorldTransform = to_bt(d.transform);
  info.m_friction = (btScalar)d.friction;
  info.m_restitution = (btScalar)d.restitution;
  info.m_linearDamping = (btScalar)d.linear_damping;
  info.m_angularDamping = (btScalar)d.angular_damping;
  info.m_rollingFriction = (btScalar)d.rolling_friction;
  info.m_spinningFriction = (btScalar)d.rolling_friction;
  if (dynamic) {
    // A body sleeps after sleep_time below both thresholds. Bullet's angular
    // threshold (1 rad/s) is fixed whatever the size, but a pile of 5 cm
    // shards buzzes at 1-3 rad/s (up to 0.2 m/s at their bounding spheres) and never
    // sleeps. The angular threshold here is the same edge speed for every
    // size, never below Bullet's: shards settle, a toppling slab does not
    // freeze mid-fall.
    btVector3 center;
    btScalar radius = 0;
    shape.shape->getBoundingSphere(center, radius);
    info.m_linearSleepingThreshold = (btScalar)sleep_linear_speed;
    info.m_angularSleepingThreshold =
        (btScalar)std::max(sleep_angular_speed, sleep_edge_speed / std::max((double)radius, 1e-3));
  }
  btRigidBody* body = new btRigidBody(info);
  body->setUserIndex((int)index);
  if (dynamic) {
    body->setLinearVelocity(to_bt(d.linear_velocity));
    body->setAngularVelocity(to_bt(d.angular_velocity));
    if (d.ccd) {
      double radius = d.ccd_radius > 0.0 ? d.ccd_radius : embedded_radius(shape);
      body->setCcdMotionThreshold((btScalar)(0.5 * radius));
      body->setCcdSweptSphereRadius((btScalar)radius);
    }
    if (d.disable_sleep) body->setActivationState(DISABLE_DEACTIVATION);
  }
  BodySlot& s = w->bodies.slots[index];
  s.body = body;
  s.shape = d.shape.index;
  s.mass = dynamic ? d.mass : 0.0;
  s.inertia = inertia;
  s.user_data = d.user_data;
  ++shape.uses;
  if (d.debris) {
    // Filtered from its birth: a body added to the broadphase pairs with
    // every box it overlaps at once.
    int group = 0, mask = 0;
    bk_physics::filter_of(true, dynamic, &group, &mask);
    w->world.addRigidBody(body, group, mask);
  } else {
    w->world.addRigidBody(body);
  }
  return bk_body_id{index, s.generation};
}

void bk_physics_destroy_body(bk_physics* w, bk_body_id body) {
  if (w && w->body(body)) w->destroy_body_slot(body.index);
}

void bk_physics_destroy_bodies(bk_physics* w, const bk_body_id* bodies, uint32_t count) {
  if (!w || !bodies) return;
  std::vector<uint32_t> indices;
  indices.reserve(count);
  for (uint32_t i = 0; i < count; ++i)
    if (w->body(bodies[i]) && w->bodies.slots[bodies[i].index].body->getUserIndex() != removing_index) {
      w->bodies.slots[bodies[i].index].body->setUserIndex(removing_index); // so that a repeat is skipped
      indices.push_back(bodies[i].index);
    }
  w->destroy_body_slots(indices.data(), (uint32_t)indices.size());
}

bool bk_physics_body_valid(const bk_physics* w, bk_body_id body) { return w && w->body(body); }

uint32_t bk_physics_body_count(const bk_physics* w) { return w ? w->bodies.live : 0; }

bk_transform bk_physics_body_transform(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? to_bk(s->body->getCenterOfMassTransform()) : bk_transform_identity();
}

void bk_physics_body_set_transform(bk_physics* w, bk_body_id body, bk_transform transform) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || !transform_is_finite(transform)) return;
  w->thaw(*s, true);
  s->body->setCenterOfMassTransform(to_bt(transform));
  if (!s->parked) w->world.updateSingleAabb(s->body); // a parked body has no box till it is back
  if (s->mass > 0.0 && !s->pinned) s->body->activate(true);
}

bk_vec3 bk_physics_body_linear_velocity(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? to_bk(s->body->getLinearVelocity()) : bk_v3(0, 0, 0);
}

bk_vec3 bk_physics_body_angular_velocity(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? to_bk(s->body->getAngularVelocity()) : bk_v3(0, 0, 0);
}

void bk_physics_body_set_velocity(bk_physics* w, bk_body_id body, bk_vec3 linear, bk_vec3 angular) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0 || s->pinned || !bk_v3_is_finite(linear) || !bk_v3_is_finite(angular)) return;
  w->thaw(*s, true);
  s->body->setLinearVelocity(to_bt(linear));
  s->body->setAngularVelocity(to_bt(angular));
  s->body->activate(true);
}

void bk_physics_body_set_mass(bk_physics* w, bk_body_id body, double mass, bk_vec3 inertia) {
  BodySlot* s = w ? w->body(body) : nullptr;
  // Static bodies stay static: turning one dynamic would need new broadphase filters.
  if (!s || s->mass == 0.0 || !(std::isfinite(mass) && mass > 0.0) || !bk_v3_is_finite(inertia) ||
      !(inertia.x > 0.0 && inertia.y > 0.0 && inertia.z > 0.0))
    return;
  s->mass = mass;
  s->inertia = to_bt(inertia);
  if (s->pinned) return; // it takes them when unpinned
  w->thaw(*s, true);
  s->body->setMassProps((btScalar)mass, to_bt(inertia));
  s->body->updateInertiaTensor();
  s->body->activate(true);
}

void bk_physics_body_set_surface(bk_physics* w, bk_body_id body, double friction, double restitution) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || !(std::isfinite(friction) && friction >= 0.0) || !(restitution >= 0.0 && restitution <= 1.0))
    return;
  s->body->setFriction((btScalar)friction);
  s->body->setRestitution((btScalar)restitution);
}

double bk_physics_body_mass(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? s->mass : 0.0;
}

bk_vec3 bk_physics_body_inertia(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0) return bk_v3(0, 0, 0);
  return to_bk(s->inertia);
}

void bk_physics_body_apply_impulse(bk_physics* w, bk_body_id body, bk_vec3 impulse, bk_vec3 world_point) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0 || s->pinned || !bk_v3_is_finite(impulse) || !bk_v3_is_finite(world_point)) return;
  w->thaw(*s, true);
  bk_vec3 arm = bk_v3_sub(world_point, to_bk(s->body->getCenterOfMassPosition()));
  s->body->applyImpulse(to_bt(impulse), to_bt(arm));
  s->body->activate(true);
}

bool bk_physics_body_awake(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && s->mass > 0.0 && !s->parked && s->body->isActive();
}

uint64_t bk_physics_body_user_data(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? s->user_data : 0;
}

void bk_physics_body_set_debris(bk_physics* w, bk_body_id body, bool debris) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s) return;
  try {
    w->changed_pairs.reserve(w->changed_pairs.size() + 1);
    w->gained_pairs.reserve(w->gained_pairs.size() + 1);
  } catch (...) {
    return; // out of memory: the filter stays as it was
  }
  w->set_debris(*s, debris);
}

bool bk_physics_body_debris(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && bk_physics::is_debris(*s);
}

bool bk_physics_body_set_shape(bk_physics* w, bk_body_id body, bk_shape_id shape) {
  BodySlot* s = w ? w->body(body) : nullptr;
  const ShapeSlot* n = w ? w->shape(shape) : nullptr;
  if (!s || !n || (n->kind == ShapeKind::plane && s->mass > 0.0)) return false;
  if (s->shape == shape.index) return true;
  try {
    w->changed_pairs.reserve(w->changed_pairs.size() + 1);
  } catch (...) {
    return false;
  }
  w->set_shape(*s, shape.index);
  return true;
}

bk_shape_id bk_physics_body_shape(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s ? bk_shape_id{s->shape, w->shapes.slots[s->shape].generation} : bk_shape_id{0, 0};
}

void bk_physics_body_set_pinned(bk_physics* w, bk_body_id body, bool pinned) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s || s->mass == 0.0 || s->pinned == pinned) return;
  if (pinned) {
    if (!bk_physics::frozen(*s)) w->freeze(*s);
    s->pinned = true;
  } else {
    // Restless, so that it falls if what held it went meanwhile; resting,
    // it sleeps again within sleep_time.
    s->pinned = false;
    w->thaw(*s, true);
  }
}

bool bk_physics_body_pinned(const bk_physics* w, bk_body_id body) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  return s && s->pinned;
}

// The exact rotation matrix of a body (world_state.c): a quaternion read
// from it and set again comes back through float rounding a little off, so
// a saved world keeps the matrix itself.
extern "C" void bk_physics_body_basis(const bk_physics* w, bk_body_id body, double out[9]) {
  const BodySlot* s = w ? w->body(body) : nullptr;
  for (int k = 0; k < 9; ++k)
    out[k] = k % 4 == 0 ? 1.0 : 0.0;
  if (!s) return;
  const btMatrix3x3& m = s->body->getCenterOfMassTransform().getBasis();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      out[3 * r + c] = m[r][c];
}

extern "C" void bk_physics_body_set_basis(bk_physics* w, bk_body_id body, const double m[9]) {
  BodySlot* s = w ? w->body(body) : nullptr;
  if (!s) return;
  btTransform t = s->body->getCenterOfMassTransform();
  t.getBasis().setValue((btScalar)m[0], (btScalar)m[1], (btScalar)m[2], (btScalar)m[3], (btScalar)m[4],
                        (btScalar)m[5], (btScalar)m[6], (btScalar)m[7], (btScalar)m[8]);
  s->body->setCenterOfMassTransform(t);
  if (!s->parked) w->world.updateSingleAabb(s->body);
}
