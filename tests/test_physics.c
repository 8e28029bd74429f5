// Physics layer: free fall and resting contact, contact reports (impulse,
// normal direction, approach speed, substeps), continuous collision, hull
// construction, compounds, id generations, validation, ray casts, cleanup.
#include <math.h>
#include <stdint.h>
#include <string.h>

#include <breakables/bullet.h>

#include "bk_geom.h"
#include "ensure.h"

static const double g = 9.81;
static const double pi = 3.14159265358979323846;
static const double dt = 1.0 / 60.0;

static double range(bk_rng* rng, double lo, double hi) { return lo + (hi - lo) * bk_rng_unit(rng); }

#define MAX_CONTACTS 4096
static bk_contact contacts[MAX_CONTACTS];

static bk_physics* make_world(void) {
  bk_error err = {{0}};
  bk_physics_def desc = bk_default_physics_def();
  bk_physics* w = bk_physics_create(&desc, &err);
  ENSURE_MSG(w, "%s", err.message);
  return w;
}

static bk_body_id make_ground(bk_physics* w) {
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_plane(w, bk_v3(0, 1, 0), 0.0);
  ENSURE(!bk_shape_is_null(d.shape));
  bk_error err = {{0}};
  bk_body_id ground = bk_physics_create_body(w, &d, &err);
  ENSURE_MSG(!bk_body_is_null(ground), "%s", err.message);
  return ground;
}

/// Principal inertia of a solid box with the given half extents.
static bk_vec3 box_inertia(double mass, bk_vec3 h) {
  return bk_v3(mass * (h.y * h.y + h.z * h.z) / 3.0, mass * (h.x * h.x + h.z * h.z) / 3.0,
               mass * (h.x * h.x + h.y * h.y) / 3.0);
}

/// A 1 kg cube of side 0.5 m with its centre at (0, y, 0).
static bk_body_id make_box(bk_physics* w, double y, bool disable_sleep) {
  bk_vec3 h = bk_v3(0.25, 0.25, 0.25);
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_box(w, h);
  d.mass = 1.0;
  d.inertia = box_inertia(1.0, h);
  d.transform.position = bk_v3(0, y, 0);
  d.disable_sleep = disable_sleep;
  bk_error err = {{0}};
  bk_body_id box = bk_physics_create_body(w, &d, &err);
  ENSURE_MSG(!bk_body_is_null(box), "%s", err.message);
  return box;
}

static uint32_t step_and_get_contacts(bk_physics* w, double step_dt, int max_substeps, int* substeps) {
  int n = bk_physics_step(w, step_dt, max_substeps);
  if (substeps) *substeps = n;
  uint32_t count = bk_physics_contacts(w, contacts, MAX_CONTACTS);
  ENSURE(count <= MAX_CONTACTS);
  return count;
}

static void test_defaults(void) {
  bk_physics_def d = bk_default_physics_def();
  ENSURE(d.gravity.x == 0.0 && d.gravity.y == -9.81 && d.gravity.z == 0.0);
  ENSURE_SMALL(d.fixed_dt, 1.0 / 60.0, 1e-15);
  ENSURE(d.contact_capacity == 65536);
  ENSURE(d.default_margin == 0.004);

  // Values are taken as given: zero gravity is zero gravity, and a zero
  // fixed_dt is refused by name rather than replaced by a default.
  bk_physics_def zero = bk_default_physics_def();
  zero.gravity = bk_v3(0, 0, 0);
  bk_physics* w = bk_physics_create(&zero, NULL);
  ENSURE(w);
  ENSURE(bk_v3_length(bk_physics_gravity(w)) == 0.0);
  bk_physics_set_gravity(w, bk_v3(0, 0, -1));
  ENSURE(bk_physics_gravity(w).z == -1.0);
  bk_physics_destroy(w);
  bk_physics_def all_zero = {0};
  bk_error zero_err = {{0}};
  ENSURE(bk_physics_create(&all_zero, &zero_err) == NULL);
  ENSURE_MSG(strstr(zero_err.message, "fixed_dt"), "%s", zero_err.message);

  bk_body_def b = bk_default_body_def();
  ENSURE(b.friction == 0.6 && b.restitution == 0.1);
  ENSURE(b.transform.rotation.w == 1.0 && b.mass == 0.0);
}

static void test_fall_and_rest(void) {
  bk_physics* w = make_world();
  make_ground(w);
  bk_body_id box = make_box(w, 2.0, false);

  // 15 substeps of 1/60 s: Bullet's semi-implicit Euler gets the velocity
  // exactly and the position to within g t dt / 2 (2 cm here, ~1.2 % of y).
  for (int i = 0; i < 15; ++i)
    ENSURE(bk_physics_step(w, dt, 1) == 1);
  double t = 0.25;
  bk_transform x = bk_physics_body_transform(w, box);
  ENSURE_REL(bk_physics_body_linear_velocity(w, box).y, -g * t, 0.01);
  ENSURE_SMALL(x.position.y, 2.0 - 0.5 * g * t * t, 0.5 * g * t * dt + 1e-4);
  ENSURE_REL(x.position.y, 2.0 - 0.5 * g * t * t, 0.015);
  ENSURE_SMALL(x.position.x, 0.0, 1e-6);

  for (int i = 15; i < 180; ++i)
    bk_physics_step(w, dt, 1);
  x = bk_physics_body_transform(w, box);
  ENSURE_SMALL(x.position.y, 0.25, 0.02);
  ENSURE_SMALL(bk_v3_length(bk_physics_body_linear_velocity(w, box)), 0.0, 0.05);
  ENSURE(fabs(x.rotation.w) > 0.9999);
  bk_physics_destroy(w);
}

static void test_contacts(void) {
  bk_physics* w = make_world();
  bk_body_id ground = make_ground(w);
  bk_body_id box = make_box(w, 2.0, true);

  // The impact: some contact closes at about sqrt(2 g h) with h = 1.75 m.
  double max_approach = 0.0;
  for (int i = 0; i < 60; ++i) {
    uint32_t n = step_and_get_contacts(w, dt, 1, NULL);
    for (uint32_t k = 0; k < n; ++k)
      max_approach = fmax(max_approach, contacts[k].approach_speed);
  }
  ENSURE_MSG(max_approach > 5.0, "max approach speed %g", max_approach);
  ENSURE(max_approach < sqrt(2.0 * g * 1.75) + 0.5);

  // Settle, then every step reports the resting contacts.
  for (int i = 0; i < 120; ++i)
    bk_physics_step(w, dt, 1);
  for (int i = 0; i < 60; ++i) {
    uint32_t n = step_and_get_contacts(w, dt, 1, NULL);
    ENSURE(n >= 1);
    double sum = 0.0;
    for (uint32_t k = 0; k < n; ++k) {
      const bk_contact* c = &contacts[k];
      bool box_is_a = bk_body_equal(c->a, box) && bk_body_equal(c->b, ground);
      bool box_is_b = bk_body_equal(c->b, box) && bk_body_equal(c->a, ground);
      ENSURE(box_is_a || box_is_b);
      // The normal points from b towards a.
      ENSURE_SMALL(c->normal.y, box_is_a ? 1.0 : -1.0, 1e-4);
      ENSURE(c->impulse > 0.0);
      ENSURE(fabs(c->approach_speed) < 0.3);
      ENSURE_SMALL(c->point.y, 0.0, 0.02);
      ENSURE(fabs(c->point.x) <= 0.26 && fabs(c->point.z) <= 0.26);
      sum += c->impulse;
    }
    ENSURE_REL(sum, 1.0 * g * dt, 0.2);
  }

  // Capacity: fewer stored than counted, and the count is unaffected.
  bk_physics_step(w, dt, 1);
  uint32_t total = bk_physics_contacts(w, NULL, 0);
  ENSURE(total >= 1);
  ENSURE(bk_physics_contacts(w, contacts, 1) == total);
  bk_physics_destroy(w);
}

static void test_contact_capacity(void) {
  bk_physics_def desc = bk_default_physics_def();
  desc.contact_capacity = 2;
  bk_physics* w = bk_physics_create(&desc, NULL);
  ENSURE(w);
  make_ground(w);
  make_box(w, 0.25, true);
  for (int i = 0; i < 30; ++i)
    bk_physics_step(w, dt, 1);
  for (uint32_t k = 0; k < MAX_CONTACTS; ++k)
    contacts[k].impulse = -1.0;
  uint32_t total = bk_physics_contacts(w, contacts, MAX_CONTACTS);
  ENSURE_MSG(total > 2, "total %u", total);
  ENSURE(contacts[0].impulse > 0.0 && contacts[1].impulse > 0.0);
  ENSURE(contacts[2].impulse == -1.0);
  bk_physics_destroy(w);
}

static void test_substep_contacts(void) {
  bk_physics* w = make_world();
  make_ground(w);
  make_box(w, 0.25, true);
  for (int i = 0; i < 60; ++i)
    bk_physics_step(w, dt, 1);
  int substeps = 0;
  uint32_t single = step_and_get_contacts(w, dt, 1, &substeps);
  ENSURE(substeps == 1 && single >= 1);
  uint32_t four = step_and_get_contacts(w, 4.0 * dt, 4, &substeps);
  ENSURE(substeps == 4);
  ENSURE_MSG(four >= 4 * single - 2 && four <= 4 * single + 2, "single %u, four substeps %u", single, four);

  // max_substeps caps the work; the extra time is dropped.
  ENSURE(bk_physics_step(w, 10.0 * dt, 3) == 3);
  ENSURE(bk_physics_step(w, dt, 3) == 1);
  // Partial steps accumulate.
  ENSURE(bk_physics_step(w, 0.5 * dt, 1) == 0);
  ENSURE(bk_physics_contacts(w, NULL, 0) == 0);
  ENSURE(bk_physics_step(w, 0.5 * dt, 1) == 1);
  ENSURE(bk_physics_step(w, -1.0, 1) == 0);
  ENSURE(bk_physics_step(w, NAN, 1) == 0);
  bk_physics_destroy(w);
}

/// Shoots a small fast sphere at a thin static wall at x = 0; returns its final x.
static double shoot_at_wall(bool ccd) {
  bk_physics_def desc = bk_default_physics_def();
  desc.gravity = bk_v3(0, 0, 0);
  bk_physics* w = bk_physics_create(&desc, NULL);
  ENSURE(w);
  bk_body_def wall = bk_default_body_def();
  wall.shape = bk_physics_create_box(w, bk_v3(0.01, 1.0, 1.0));
  ENSURE(!bk_body_is_null(bk_physics_create_body(w, &wall, NULL)));

  double r = 0.02, m = 0.1;
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_sphere(w, r);
  d.mass = m;
  double I = 0.4 * m * r * r;
  d.inertia = bk_v3(I, I, I);
  d.transform.position = bk_v3(-1.0, 0.1, 0.0);
  d.linear_velocity = bk_v3(300.0, 0, 0);
  d.ccd = ccd;
  bk_body_id ball = bk_physics_create_body(w, &d, NULL);
  ENSURE(!bk_body_is_null(ball));
  double max_approach = 0.0;
  for (int i = 0; i < 30; ++i) {
    uint32_t n = step_and_get_contacts(w, dt, 1, NULL);
    for (uint32_t k = 0; k < n; ++k) {
      max_approach = fmax(max_approach, contacts[k].approach_speed);
      // Contacts lie on the wall's near face.
      ENSURE_SMALL(contacts[k].point.x, -0.01, 1e-3);
      ENSURE_SMALL(fabs(contacts[k].normal.x), 1.0, 1e-4);
    }
  }
  double x = bk_physics_body_transform(w, ball).position.x;
  if (ccd) ENSURE_MSG(max_approach > 100.0, "max approach speed %g", max_approach);
  bk_physics_destroy(w);
  return x;
}

static void test_ccd(void) {
  double with_ccd = shoot_at_wall(true);
  ENSURE_MSG(with_ccd < -0.01, "ball at x = %g with CCD", with_ccd);
  double without = shoot_at_wall(false);
  ENSURE_MSG(without > 0.01, "ball at x = %g without CCD (expected to tunnel)", without);
}

static void test_hulls(void) {
  bk_physics* w = make_world();
  bk_rng rng = bk_rng_seed(7, 1);

  // Cube corners plus interior points: exactly the 8 corners survive.
  bk_vec3 points[600];
  uint32_t n = 0;
  for (int i = 0; i < 8; ++i)
    points[n++] = bk_v3(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  for (int i = 0; i < 100; ++i)
    points[n++] = bk_v3(range(&rng, -0.49, 0.49), range(&rng, -0.49, 0.49), range(&rng, -0.49, 0.49));
  bk_shape_id cube = bk_physics_create_hull(w, points, n, 0);
  ENSURE(!bk_shape_is_null(cube));
  bk_vec3 vertices[64];
  ENSURE(bk_physics_hull_vertices(w, cube, vertices, 64) == 8);
  // The core is the cube shrunk by the collision margin (the margin grows it back).
  double core = 0.5 - bk_default_physics_def().default_margin;
  for (int i = 0; i < 8; ++i) {
    ENSURE_SMALL(fabs(vertices[i].x), core, 2e-4); // Bullet quantizes while shrinking
    ENSURE_SMALL(fabs(vertices[i].y), core, 2e-4); // Bullet quantizes while shrinking
    ENSURE_SMALL(fabs(vertices[i].z), core, 2e-4); // Bullet quantizes while shrinking
  }
  ENSURE_SMALL(bk_physics_hull_volume(w, cube), 1.0, 1e-9);
  ENSURE(bk_physics_hull_vertices(w, cube, NULL, 0) == 8);

  // 500 points on the unit sphere: simplified to at most 64 vertices.
  for (n = 0; n < 500; ++n)
    points[n] = bk_rng_direction(&rng);
  bk_shape_id ball = bk_physics_create_hull(w, points, n, 0);
  ENSURE(!bk_shape_is_null(ball));
  uint32_t count = bk_physics_hull_vertices(w, ball, vertices, 64);
  ENSURE_MSG(count >= 4 && count <= 64, "%u vertices", count);
  // Core vertices lie just inside the sphere (shrunk by the margin).
  for (uint32_t i = 0; i < count; ++i) {
    ENSURE(bk_v3_length(vertices[i]) <= 1.0 + 1e-6);
    ENSURE(bk_v3_length(vertices[i]) >= 1.0 - 3.0 * bk_default_physics_def().default_margin);
  }
  double sphere_volume = 4.0 / 3.0 * pi;
  ENSURE_REL(bk_physics_hull_volume(w, ball), sphere_volume, 0.10);
  ENSURE(bk_physics_hull_volume(w, ball) < sphere_volume);

  // A smaller vertex budget is honoured too.
  bk_shape_id coarse = bk_physics_create_hull(w, points, n, 16);
  ENSURE(!bk_shape_is_null(coarse));
  count = bk_physics_hull_vertices(w, coarse, NULL, 0);
  ENSURE_MSG(count >= 4 && count <= 16, "%u vertices", count);

  // Degenerate input.
  ENSURE(bk_shape_is_null(bk_physics_create_hull(w, points, 3, 0)));
  bk_vec3 flat[20];
  for (int i = 0; i < 20; ++i)
    flat[i] = bk_v3(range(&rng, -1, 1), 0.3 * i, 2.0);
  for (int i = 0; i < 20; ++i)
    flat[i].z = 2.0 + 0.5 * flat[i].x - 0.25 * flat[i].y; // one tilted plane
  ENSURE(bk_shape_is_null(bk_physics_create_hull(w, flat, 20, 0)));
  bk_vec3 same[6];
  for (int i = 0; i < 6; ++i)
    same[i] = bk_v3(1, 2, 3);
  ENSURE(bk_shape_is_null(bk_physics_create_hull(w, same, 6, 0)));
  flat[3].x = NAN;
  ENSURE(bk_shape_is_null(bk_physics_create_hull(w, flat, 20, 0)));

  // Non-hull shapes have no hull data; bad parameters give null shapes.
  bk_shape_id sphere = bk_physics_create_sphere(w, 0.5);
  ENSURE(bk_physics_hull_vertices(w, sphere, vertices, 64) == 0 && bk_physics_hull_volume(w, sphere) == 0.0);
  ENSURE(bk_shape_is_null(bk_physics_create_sphere(w, 0.0)));
  ENSURE(bk_shape_is_null(bk_physics_create_sphere(w, NAN)));
  ENSURE(bk_shape_is_null(bk_physics_create_box(w, bk_v3(1, 0, 1))));
  ENSURE(bk_shape_is_null(bk_physics_create_plane(w, bk_v3(0, 0, 0), 1.0)));
  ENSURE(bk_physics_shape_count(w) == 4);
  bk_physics_destroy(w);
}

// A hull moved into another frame (a body's principal frame) without
// computing it again: the same core vertices, moved, and the same volume.
static void test_copy_hull(void) {
  bk_physics* w = make_world();
  bk_rng rng = bk_rng_seed(11, 1);
  bk_vec3 points[200];
  for (uint32_t i = 0; i < 200; ++i)
    points[i] = bk_v3_add(bk_v3(0.4, 1.0, -0.3), bk_v3_scale(bk_rng_direction(&rng), range(&rng, 0.05, 0.3)));
  bk_shape_id hull = bk_physics_create_hull(w, points, 200, 0);
  ENSURE(!bk_shape_is_null(hull));
  bk_transform move = {bk_v3(-0.4, -1.0, 0.3), bk_quat_normalize((bk_quat){0.3, -0.2, 0.5, 0.8})};
  bk_shape_id moved = bk_physics_copy_hull(w, hull, move);
  ENSURE(!bk_shape_is_null(moved));
  bk_vec3 from[64], to[64];
  uint32_t count = bk_physics_hull_vertices(w, hull, from, 64);
  ENSURE(count >= 4 && bk_physics_hull_vertices(w, moved, to, 64) == count);
  for (uint32_t i = 0; i < count; ++i)
    ENSURE(bk_v3_length(bk_v3_sub(to[i], bk_transform_point(move, from[i]))) < 1e-6);
  ENSURE(bk_physics_hull_volume(w, moved) == bk_physics_hull_volume(w, hull));
  // Only a live hull, moved by a finite transform.
  ENSURE(bk_shape_is_null(bk_physics_copy_hull(w, bk_physics_create_sphere(w, 0.5), move)));
  ENSURE(bk_shape_is_null(bk_physics_copy_hull(w, (bk_shape_id){999, 1}, move)));
  move.position.x = NAN;
  ENSURE(bk_shape_is_null(bk_physics_copy_hull(w, hull, move)));
  ENSURE(bk_physics_shape_count(w) == 3);
  bk_physics_destroy(w);
}

static bk_shape_id unit_cube_hull(bk_physics* w) {
  bk_vec3 corners[8];
  for (int i = 0; i < 8; ++i)
    corners[i] = bk_v3(i & 1 ? 0.5 : -0.5, i & 2 ? 0.5 : -0.5, i & 4 ? 0.5 : -0.5);
  bk_shape_id cube = bk_physics_create_hull(w, corners, 8, 0);
  ENSURE(!bk_shape_is_null(cube));
  return cube;
}

static void test_compounds(void) {
  bk_physics* w = make_world();
  make_ground(w);
  bk_shape_id cube = unit_cube_hull(w);

  // Two unit cubes side by side: a 2 x 1 x 1 body of 2 kg.
  bk_shape_id pair[2];
  for (int k = 0; k < 2; ++k) {
    pair[k] = bk_physics_create_compound(w, 2);
    ENSURE(!bk_shape_is_null(pair[k]));
    bk_transform left = bk_transform_identity(), right = bk_transform_identity();
    left.position.x = -0.5;
    right.position.x = 0.5;
    bk_physics_compound_add(w, pair[k], cube, left);
    bk_physics_compound_add(w, pair[k], cube, right);
  }
  bk_body_id bodies[2];
  for (int k = 0; k < 2; ++k) {
    bk_body_def d = bk_default_body_def();
    d.shape = pair[k];
    d.mass = 2.0;
    d.inertia = box_inertia(2.0, bk_v3(1.0, 0.5, 0.5));
    d.transform.position = bk_v3(0, 2.0, 3.0 * k);
    bodies[k] = bk_physics_create_body(w, &d, NULL);
    ENSURE(!bk_body_is_null(bodies[k]));
  }
  ENSURE(bk_physics_body_mass(w, bodies[0]) == 2.0);

  // A shape in use can not be destroyed; the call is ignored.
  bk_physics_destroy_shape(w, cube);
  bk_physics_destroy_shape(w, pair[0]);
  ENSURE(bk_physics_shape_valid(w, cube) && bk_physics_shape_valid(w, pair[0]));

  for (int i = 0; i < 180; ++i)
    bk_physics_step(w, dt, 1);
  for (int k = 0; k < 2; ++k) {
    bk_transform x = bk_physics_body_transform(w, bodies[k]);
    ENSURE_SMALL(x.position.y, 0.5, 0.02);
    ENSURE_SMALL(x.position.x, 0.0, 1e-3);
    ENSURE_SMALL(x.position.z, 3.0 * k, 1e-3);
    ENSURE_MSG(fabs(x.rotation.w) > 0.9999, "rotation (%g, %g, %g, %g)", x.rotation.x, x.rotation.y,
               x.rotation.z, x.rotation.w);
  }

  // Tear down in a valid order: bodies, then compounds, then their child.
  bk_physics_destroy_body(w, bodies[1]);
  bk_physics_destroy_shape(w, pair[1]);
  ENSURE(!bk_physics_shape_valid(w, pair[1]));
  bk_physics_destroy_shape(w, cube);
  ENSURE(bk_physics_shape_valid(w, cube)); // still in pair[0]
  bk_physics_destroy_body(w, bodies[0]);
  bk_physics_destroy_shape(w, pair[0]);
  bk_physics_destroy_shape(w, cube);
  ENSURE(!bk_physics_shape_valid(w, cube));
  ENSURE(bk_physics_shape_count(w) == 1); // the ground plane
  ENSURE(bk_physics_body_count(w) == 1);

  // Compounds take convex children only.
  bk_shape_id outer = bk_physics_create_compound(w, 0);
  bk_shape_id inner = bk_physics_create_compound(w, 0);
  bk_shape_id plane = bk_physics_create_plane(w, bk_v3(0, 1, 0), 0);
  bk_physics_compound_add(w, outer, inner, bk_transform_identity());
  bk_physics_compound_add(w, outer, plane, bk_transform_identity());
  bk_physics_compound_add(w, outer, outer, bk_transform_identity());
  bk_physics_destroy_shape(w, inner);
  bk_physics_destroy_shape(w, plane);
  ENSURE(!bk_physics_shape_valid(w, inner) && !bk_physics_shape_valid(w, plane));

  // The world takes whatever is left, compounds and children included.
  bk_shape_id cube2 = unit_cube_hull(w);
  bk_physics_compound_add(w, outer, cube2, bk_transform_identity());
  bk_body_def d = bk_default_body_def();
  d.shape = outer;
  d.mass = 1.0;
  d.inertia = bk_v3(1, 1, 1);
  ENSURE(!bk_body_is_null(bk_physics_create_body(w, &d, NULL)));
  bk_physics_destroy(w);
}

static void test_ids(void) {
  bk_physics* w = make_world();
  bk_body_id ground = make_ground(w);
  bk_body_id box = make_box(w, 1.0, false);
  ENSURE(bk_physics_body_valid(w, box));
  ENSURE(bk_physics_body_count(w) == 2);
  bk_physics_destroy_body(w, box);
  ENSURE(!bk_physics_body_valid(w, box));
  ENSURE(bk_physics_body_count(w) == 1);

  bk_body_id again = make_box(w, 1.0, false);
  ENSURE(again.index == box.index);
  ENSURE(again.generation != box.generation && again.generation != 0);
  ENSURE(!bk_physics_body_valid(w, box));

  // Stale and null ids are harmless everywhere.
  bk_body_id null_body = {0, 0};
  bk_body_id ids[2] = {box, null_body};
  for (int k = 0; k < 2; ++k) {
    bk_body_id id = ids[k];
    bk_physics_destroy_body(w, id);
    bk_physics_body_set_transform(w, id, bk_transform_identity());
    bk_physics_body_set_velocity(w, id, bk_v3(1, 2, 3), bk_v3(0, 0, 0));
    bk_physics_body_set_mass(w, id, 3.0, bk_v3(1, 1, 1));
    bk_physics_body_apply_impulse(w, id, bk_v3(1, 0, 0), bk_v3(0, 0, 0));
    ENSURE(bk_physics_body_mass(w, id) == 0.0);
    ENSURE(bk_v3_length(bk_physics_body_linear_velocity(w, id)) == 0.0);
    ENSURE(bk_v3_length(bk_physics_body_angular_velocity(w, id)) == 0.0);
    ENSURE(!bk_physics_body_awake(w, id));
    ENSURE(bk_physics_body_user_data(w, id) == 0);
    ENSURE(bk_physics_body_transform(w, id).rotation.w == 1.0);
  }
  bk_shape_id null_shape = {0, 0};
  bk_shape_id dead = bk_physics_create_sphere(w, 1.0);
  bk_physics_destroy_shape(w, dead);
  bk_shape_id shapes[2] = {dead, null_shape};
  for (int k = 0; k < 2; ++k) {
    ENSURE(!bk_physics_shape_valid(w, shapes[k]));
    bk_physics_destroy_shape(w, shapes[k]);
    bk_physics_compound_add(w, shapes[k], shapes[k], bk_transform_identity());
    ENSURE(bk_physics_hull_vertices(w, shapes[k], NULL, 0) == 0);
    ENSURE(bk_physics_hull_volume(w, shapes[k]) == 0.0);
  }
  ENSURE(bk_physics_body_count(w) == 2 && bk_physics_shape_count(w) == 3); // plane and two boxes
  // A NULL world is harmless too.
  ENSURE(bk_physics_step(NULL, dt, 1) == 0);
  ENSURE(!bk_physics_body_valid(NULL, again));
  bk_physics_destroy(NULL);

  // Body state round trips.
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_sphere(w, 0.1);
  d.mass = 2.0;
  d.inertia = bk_v3(0.008, 0.008, 0.008);
  d.user_data = UINT64_C(0x1234567890abcdef);
  d.transform.position = bk_v3(5, 5, 5);
  d.transform.rotation = (bk_quat){0, 0, 0, 0}; // not a rotation: refused by name
  bk_error rotation_err = {{0}};
  ENSURE(bk_body_is_null(bk_physics_create_body(w, &d, &rotation_err)));
  ENSURE_MSG(strstr(rotation_err.message, "transform.rotation"), "%s", rotation_err.message);
  d.transform.rotation = bk_quat_identity();
  bk_body_id ball = bk_physics_create_body(w, &d, NULL);
  ENSURE(!bk_body_is_null(ball));
  ENSURE(bk_physics_body_user_data(w, ball) == UINT64_C(0x1234567890abcdef));
  ENSURE(bk_physics_body_transform(w, ball).rotation.w == 1.0);
  ENSURE(bk_physics_body_awake(w, ball));
  ENSURE(!bk_physics_body_awake(w, ground));
  bk_transform t = {{1, 2, 3}, bk_quat_axis_angle(bk_v3(0, 0, 1), 0.5)};
  bk_physics_body_set_transform(w, ball, t);
  bk_transform back = bk_physics_body_transform(w, ball);
  ENSURE_SMALL(back.position.y, 2.0, 1e-6);
  ENSURE_SMALL(fabs(back.rotation.z), fabs(t.rotation.z), 1e-6);
  bk_physics_body_set_velocity(w, ball, bk_v3(1, 0, 0), bk_v3(0, 2, 0));
  ENSURE_SMALL(bk_physics_body_linear_velocity(w, ball).x, 1.0, 1e-6);
  ENSURE_SMALL(bk_physics_body_angular_velocity(w, ball).y, 2.0, 1e-6);
  bk_physics_body_set_mass(w, ball, 4.0, bk_v3(0.016, 0.016, 0.016));
  ENSURE(bk_physics_body_mass(w, ball) == 4.0);
  bk_physics_body_set_mass(w, ball, 0.0, bk_v3(1, 1, 1)); // not allowed: ignored
  ENSURE(bk_physics_body_mass(w, ball) == 4.0);
  // An impulse through the centre changes only the linear velocity, by J / m.
  bk_physics_body_set_velocity(w, ball, bk_v3(0, 0, 0), bk_v3(0, 0, 0));
  bk_physics_body_apply_impulse(w, ball, bk_v3(0, 0, 8), back.position);
  ENSURE_SMALL(bk_physics_body_linear_velocity(w, ball).z, 2.0, 1e-6);
  ENSURE_SMALL(bk_v3_length(bk_physics_body_angular_velocity(w, ball)), 0.0, 1e-6);
  bk_physics_destroy(w);
}

static void expect_body_error(bk_physics* w, const bk_body_def* d, const char* field) {
  bk_error err = {{0}};
  bk_body_id id = bk_physics_create_body(w, d, &err);
  ENSURE(bk_body_is_null(id));
  ENSURE_MSG(strstr(err.message, field) != NULL, "message \"%s\" should name %s", err.message, field);
}

static void test_validation(void) {
  bk_physics* w = make_world();
  bk_body_def good = bk_default_body_def();
  good.shape = bk_physics_create_box(w, bk_v3(0.5, 0.5, 0.5));
  good.mass = 1.0;
  good.inertia = bk_v3(1, 1, 1);

  bk_body_def d = good;
  d.mass = NAN;
  expect_body_error(w, &d, "mass");
  d = good;
  d.mass = -1.0;
  expect_body_error(w, &d, "mass");
  d = good;
  d.inertia.y = 0.0;
  expect_body_error(w, &d, "inertia");
  d = good;
  d.shape.generation += 5;
  expect_body_error(w, &d, "shape");
  d = good;
  d.shape = (bk_shape_id){0, 0};
  expect_body_error(w, &d, "shape");
  d = good;
  d.linear_velocity.x = INFINITY;
  expect_body_error(w, &d, "linear_velocity");
  d = good;
  d.transform.position.z = NAN;
  expect_body_error(w, &d, "transform");
  d = good;
  d.rolling_friction = -0.01;
  expect_body_error(w, &d, "rolling_friction");
  d.rolling_friction = NAN;
  expect_body_error(w, &d, "rolling_friction");
  d = good;
  d.shape = bk_physics_create_plane(w, bk_v3(0, 1, 0), 0.0);
  expect_body_error(w, &d, "mass"); // planes are static only
  ENSURE(bk_physics_body_count(w) == 0);

  // A static body needs no inertia.
  d = good;
  d.mass = 0.0;
  d.inertia = bk_v3(0, 0, 0);
  ENSURE(!bk_body_is_null(bk_physics_create_body(w, &d, NULL)));
  bk_physics_destroy(w);

  bk_error err = {{0}};
  bk_physics_def desc = bk_default_physics_def();
  desc.fixed_dt = -0.01;
  ENSURE(bk_physics_create(&desc, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "fixed_dt"), "%s", err.message);
  desc.fixed_dt = 0.5;
  ENSURE(bk_physics_create(&desc, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "fixed_dt"), "%s", err.message);
  desc.fixed_dt = NAN;
  ENSURE(bk_physics_create(&desc, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "fixed_dt"), "%s", err.message);
  desc = bk_default_physics_def();
  desc.gravity.y = NAN;
  ENSURE(bk_physics_create(&desc, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "gravity"), "%s", err.message);
  desc = bk_default_physics_def();
  desc.default_margin = -0.1;
  ENSURE(bk_physics_create(&desc, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "default_margin"), "%s", err.message);
  // fixed_dt = 0 is taken as given (and refused), not replaced by a default;
  // a zero margin is a real value.
  desc = bk_default_physics_def();
  desc.fixed_dt = 0.0;
  ENSURE(bk_physics_create(&desc, &err) == NULL);
  ENSURE_MSG(strstr(err.message, "fixed_dt"), "%s", err.message);
  desc = bk_default_physics_def();
  desc.default_margin = 0.0;
  w = bk_physics_create(&desc, &err);
  ENSURE(w);
  ENSURE(bk_physics_step(w, 1.0 / 60.0, 1) == 1);
  bk_physics_destroy(w);
}

static void test_ray_cast(void) {
  bk_physics* w = make_world();
  bk_body_id ground = make_ground(w);
  bk_ray_hit hit;
  ENSURE(bk_physics_ray_cast(w, bk_v3(0.3, 4.0, -0.2), bk_v3(0.3, -1.0, -0.2), &hit));
  ENSURE(bk_body_equal(hit.body, ground));
  ENSURE_SMALL(hit.fraction, 0.8, 1e-5);
  ENSURE_SMALL(hit.point.x, 0.3, 1e-5);
  ENSURE_SMALL(hit.point.y, 0.0, 1e-4);
  ENSURE_SMALL(hit.point.z, -0.2, 1e-5);
  ENSURE_SMALL(hit.normal.y, 1.0, 1e-5);

  // A box in the way is hit first.
  bk_body_id box = make_box(w, 1.0, false);
  ENSURE(bk_physics_ray_cast(w, bk_v3(0.1, 4.0, 0.0), bk_v3(0.1, -1.0, 0.0), &hit));
  ENSURE(bk_body_equal(hit.body, box));
  ENSURE_SMALL(hit.point.y, 1.25, 1e-4);
  ENSURE_SMALL(hit.fraction, 2.75 / 5.0, 1e-5);

  // Misses.
  ENSURE(!bk_physics_ray_cast(w, bk_v3(5, 4, 0), bk_v3(5, 1, 0), &hit));
  ENSURE(!bk_physics_ray_cast(w, bk_v3(5, 4, 0), bk_v3(5, 4, 0), &hit));
  bk_physics_destroy(w);
}

static void test_churn(void) {
  bk_physics* w = make_world();
  make_ground(w);
  bk_rng rng = bk_rng_seed(11, 1);
  enum { N = 1000 };
  static bk_body_id bodies[N];
  static bk_shape_id shapes[N];
  for (int i = 0; i < N; ++i) {
    bk_vec3 pts[12];
    for (int k = 0; k < 12; ++k)
      pts[k] = bk_v3(range(&rng, -0.1, 0.1), range(&rng, -0.1, 0.1), range(&rng, -0.1, 0.1));
    shapes[i] = i % 3 == 0   ? bk_physics_create_hull(w, pts, 12, 0)
                : i % 3 == 1 ? bk_physics_create_box(w, bk_v3(0.05, 0.05, 0.05))
                             : bk_physics_create_sphere(w, 0.05);
    ENSURE(!bk_shape_is_null(shapes[i]));
    bk_body_def d = bk_default_body_def();
    d.shape = shapes[i];
    d.mass = 0.1;
    d.inertia = bk_v3(1e-3, 1e-3, 1e-3);
    d.transform.position = bk_v3((i % 10) * 0.3, 0.2 + (i / 100) * 0.3, ((i / 10) % 10) * 0.3);
    d.ccd = i % 2 == 0;
    bodies[i] = bk_physics_create_body(w, &d, NULL);
    ENSURE(!bk_body_is_null(bodies[i]));
  }
  ENSURE(bk_physics_body_count(w) == N + 1 && bk_physics_shape_count(w) == N + 1);
  for (int i = 0; i < 10; ++i)
    bk_physics_step(w, dt, 1);
  // Destroy in a scrambled order.
  for (int i = 0; i < N; ++i) {
    int k = (i * 7919) % N;
    bk_physics_destroy_body(w, bodies[k]);
    bk_physics_destroy_shape(w, shapes[k]);
  }
  ENSURE(bk_physics_body_count(w) == 1 && bk_physics_shape_count(w) == 1);
  bk_physics_step(w, dt, 1);
  bk_physics_destroy(w);
}

/// A dynamic box (half extents h) at p.
static bk_body_def box_desc(bk_physics* w, bk_vec3 h, double mass, bk_vec3 p) {
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_box(w, h);
  d.mass = mass;
  d.inertia = box_inertia(mass, h);
  d.transform.position = p;
  return d;
}

static bk_body_id create_body(bk_physics* w, const bk_body_def* d) {
  bk_error err = {{0}};
  bk_body_id body = bk_physics_create_body(w, d, &err);
  ENSURE_MSG(!bk_body_is_null(body), "%s", err.message);
  return body;
}

/// A small stone box (half extents h) at p.
static bk_body_id make_small_box(bk_physics* w, bk_vec3 h, bk_vec3 p, double friction, double rolling) {
  bk_body_def d = box_desc(w, h, 8.0 * h.x * h.y * h.z * 2400.0, p);
  d.friction = friction;
  d.rolling_friction = rolling;
  return create_body(w, &d);
}

/// A world without gravity.
static bk_physics* make_weightless_world(void) {
  bk_error err = {{0}};
  bk_physics_def desc = bk_default_physics_def();
  desc.gravity = bk_v3(0, 0, 0);
  bk_physics* w = bk_physics_create(&desc, &err);
  ENSURE_MSG(w, "%s", err.message);
  return w;
}

// Bodies whose boxes are a few centimetres apart are broadphase pairs (the
// tree's boxes are fattened) but get no narrowphase work and no manifold.
static void test_near_pairs_skip_narrowphase(void) {
  bk_physics* w = make_weightless_world();
  const bk_vec3 h = bk_v3(0.05, 0.05, 0.05);
  // A row of 10 cm cubes, 3 cm apart: far enough to never touch, close
  // enough for the broadphase's fattened boxes (2 cm contact threshold and
  // 1 cm tree margin on each side) to overlap.
  for (int i = 0; i < 8; ++i)
    make_small_box(w, h, bk_v3(0.13 * i, 1.0, 0.0), 0.6, 0.0);
  for (int i = 0; i < 10; ++i)
    bk_physics_step(w, dt, 1);
  bk_physics_stats s = bk_physics_get_stats(w);
  ENSURE(s.bodies == 8);
  ENSURE_MSG(s.pairs >= 7, "pairs %u", s.pairs);
  ENSURE_MSG(s.manifolds == 0, "manifolds %u for bodies 3 cm apart", s.manifolds);
  ENSURE(s.contact_points == 0);
  // 8 cm apart they are not even pairs (with Bullet's 5 cm tree margin they
  // were: pairs are walked every step, so a heap of shards paid for ~26 each).
  bk_physics_destroy(w);
  w = make_weightless_world();
  for (int i = 0; i < 8; ++i)
    make_small_box(w, h, bk_v3(0.18 * i, 1.0, 0.0), 0.6, 0.0);
  for (int i = 0; i < 10; ++i)
    bk_physics_step(w, dt, 1);
  s = bk_physics_get_stats(w);
  ENSURE_MSG(s.pairs == 0, "pairs %u for boxes 8 cm apart", s.pairs);
  // Touching cubes do get manifolds with points.
  bk_physics_destroy(w);
  w = make_world();
  make_ground(w);
  for (int i = 0; i < 4; ++i)
    make_small_box(w, h, bk_v3(0.1 * i, 0.05, 0.0), 0.6, 0.0);
  for (int i = 0; i < 30; ++i)
    bk_physics_step(w, dt, 1);
  s = bk_physics_get_stats(w);
  ENSURE_MSG(s.manifolds >= 4 && s.contact_points >= 16, "manifolds %u points %u", s.manifolds,
             s.contact_points);
  bk_physics_destroy(w);
}

/// A hull box (half extents h), dynamic when mass > 0, at p with velocities.
static bk_body_id make_hull_box(bk_physics* w, bk_vec3 h, double mass, bk_vec3 p, bk_vec3 v, bk_vec3 spin) {
  bk_vec3 corners[8];
  for (int i = 0; i < 8; ++i)
    corners[i] = bk_v3(i & 1 ? h.x : -h.x, i & 2 ? h.y : -h.y, i & 4 ? h.z : -h.z);
  bk_body_def d = bk_default_body_def();
  d.shape = bk_physics_create_hull(w, corners, 8, 0);
  ENSURE(!bk_shape_is_null(d.shape));
  d.mass = mass;
  if (mass > 0.0) d.inertia = box_inertia(mass, h);
  d.transform.position = p;
  d.linear_velocity = v;
  d.angular_velocity = spin;
  d.disable_sleep = true;
  return create_body(w, &d);
}

/// Whether the last step reported a contact between bodies a and b.
static bool touched(const bk_physics* w, bk_body_id a, bk_body_id b) {
  uint32_t n = bk_physics_contacts(w, contacts, MAX_CONTACTS);
  for (uint32_t i = 0; i < n && i < MAX_CONTACTS; ++i)
    if ((bk_body_equal(contacts[i].a, a) && bk_body_equal(contacts[i].b, b)) ||
        (bk_body_equal(contacts[i].a, b) && bk_body_equal(contacts[i].b, a)))
      return true;
  return false;
}

// Hulls a few millimetres apart skip the narrowphase and keep no manifold
// while they provably stay apart; moving or turning towards each other, they
// still collide on time.
static void test_separated_hulls(void) {
  bk_physics* w = make_weightless_world();
  const bk_vec3 h = bk_v3(0.05, 0.05, 0.05);
  // 3 mm apart: inside the narrowphase's reach (5 mm between exact boxes).
  bk_body_id left = make_hull_box(w, h, 1.0, bk_v3(0, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0));
  bk_body_id right = make_hull_box(w, h, 1.0, bk_v3(0.103, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0));
  for (int i = 0; i < 10; ++i) {
    bk_physics_step(w, dt, 1);
    ENSURE(!touched(w, left, right));
  }
  bk_physics_stats s = bk_physics_get_stats(w);
  ENSURE_MSG(s.pairs == 1 && s.manifolds == 0, "pairs %u manifolds %u for hulls 3 mm apart", s.pairs,
             s.manifolds);
  // Pushed together at 0.3 m/s (5 mm a step): they touch and part, never
  // overlapping by more than a step's motion (Bullet's own narrowphase gives
  // the same track: 2 mm, then 4.6 mm, then the overlap is pushed out).
  bk_physics_body_set_velocity(w, left, bk_v3(0.3, 0, 0), bk_v3(0, 0, 0));
  int first_touch = -1;
  for (int i = 0; i < 60; ++i) {
    bk_physics_step(w, dt, 1);
    if (first_touch < 0 && touched(w, left, right)) first_touch = i;
    double gap =
        bk_physics_body_transform(w, right).position.x - bk_physics_body_transform(w, left).position.x;
    ENSURE_MSG(gap > 0.1 - 0.005, "step %d: centres %.4f m apart (cubes are 0.1 m)", i, gap);
  }
  ENSURE_MSG(first_touch >= 0 && first_touch <= 1, "first contact at step %d", first_touch);
  double apart =
      bk_physics_body_transform(w, right).position.x - bk_physics_body_transform(w, left).position.x;
  ENSURE_MSG(apart > 0.1 - 0.0005, "centres %.4f m apart after the push", apart);
  bk_physics_destroy(w);

  // Turning only: a 1 m plank spins about its centre (0.9 m/s at its end)
  // towards a static cube 4 mm beside its end. The plank's end moves, its
  // centre does not, so the pair's motion bound must count the rotation.
  w = make_weightless_world();
  // The block first: the pair is then (block, plank), and in the block's
  // frame the plank's centre stays put while its end sweeps.
  bk_body_id block = make_hull_box(w, h, 0.0, bk_v3(0.44, 1, 0.104), bk_v3(0, 0, 0), bk_v3(0, 0, 0));
  bk_body_id plank =
      make_hull_box(w, bk_v3(0.5, 0.01, 0.05), 2.0, bk_v3(0, 1, 0), bk_v3(0, 0, 0), bk_v3(0, 0, 0));
  for (int i = 0; i < 5; ++i)
    bk_physics_step(w, dt, 1);
  ENSURE(!touched(w, plank, block));
  ENSURE(bk_physics_get_stats(w).manifolds == 0);
  // Spin about y, clockwise seen from above: the end at +x moves towards +z.
  bk_physics_body_set_velocity(w, plank, bk_v3(0, 0, 0), bk_v3(0, -2.0, 0));
  first_touch = -1;
  for (int i = 0; i < 30 && first_touch < 0; ++i) {
    bk_physics_step(w, dt, 1);
    if (touched(w, plank, block)) first_touch = i;
  }
  // 4 mm at 15 mm a step: the first or the second step.
  ENSURE_MSG(first_touch >= 0 && first_touch <= 1, "first contact at step %d", first_touch);
  // The plank's side under the block never goes more than a step's motion
  // into it (the block's face is at z = 0.054).
  for (int i = 0; i < 30; ++i) {
    bk_physics_step(w, dt, 1);
    bk_vec3 side = bk_transform_point(bk_physics_body_transform(w, plank), bk_v3(0.44, 0, 0.05));
    ENSURE_MSG(side.z < 0.054 + 0.015, "step %d: the plank's side is at z = %.4f", i, side.z);
  }
  bk_physics_destroy(w);
}

enum { SHARDS = 60 };

/// Number of the given bodies that are awake.
static int count_awake(const bk_physics* w, const bk_body_id* bodies, int count) {
  int awake = 0;
  for (int i = 0; i < count; ++i)
    awake += bk_physics_body_awake(w, bodies[i]);
  return awake;
}

/// A world with a ground and a heap of SHARDS small boxes dropped on it in
/// layers over x in [-0.3, x_max], z in [-0.3, 0.3].
static bk_physics* make_heap_world(uint64_t seed, double x_max, bk_body_id shards[SHARDS]) {
  bk_physics* w = make_world();
  make_ground(w);
  bk_rng rng = bk_rng_seed(seed, 1);
  for (int i = 0; i < SHARDS; ++i) {
    bk_vec3 h = bk_v3(range(&rng, 0.02, 0.05), range(&rng, 0.01, 0.03), range(&rng, 0.02, 0.05));
    bk_vec3 p = bk_v3(range(&rng, -0.3, x_max), 0.05 + 0.06 * (i / 6), range(&rng, -0.3, 0.3));
    shards[i] = make_small_box(w, h, p, 0.7, 0.1 * cbrt(8.0 * h.x * h.y * h.z));
  }
  return w;
}

/// A box (half extents h) that never sleeps, spinning about y at `spin` rad/s.
static bk_body_id make_sleepless_box(bk_physics* w, bk_vec3 h, double mass, bk_vec3 p, double spin) {
  bk_body_def d = box_desc(w, h, mass, p);
  d.angular_velocity = bk_v3(0.0, spin, 0.0);
  d.disable_sleep = true;
  return create_body(w, &d);
}

/// Every shard lies on the ground: none fell through, none was flung off.
static void ensure_on_ground(const bk_physics* w, const bk_body_id shards[SHARDS]) {
  for (int i = 0; i < SHARDS; ++i) {
    double y = bk_physics_body_transform(w, shards[i]).position.y;
    ENSURE_MSG(y > 0.0 && y < 0.5, "shard %d at y %g", i, y);
  }
}

// A heap of small shards comes to rest and sleeps within a few seconds, and
// it sleeps even while a body elsewhere (not touching it) keeps moving:
// islands are formed by contacts, not by overlapping boxes.
static void test_piles_sleep(void) {
  bk_body_id shards[SHARDS];
  bk_physics* w = make_heap_world(7, 0.22, shards);
  // A puck spinning in place forever, a few centimetres from
  // the heap: near enough for the broadphase to pair it with shards, which
  // made Bullet's islands (built from those pairs) keep the heap awake.
  bk_body_id puck = make_sleepless_box(w, bk_v3(0.1, 0.02, 0.1), 1.0, bk_v3(0.47, 0.02, 0.0), 3.0);
  int slept_at = -1;
  for (int step = 0; step < 8 * 60 && slept_at < 0; ++step) {
    bk_physics_step(w, dt, 1);
    if (count_awake(w, shards, SHARDS) == 0) slept_at = step;
  }
  ENSURE_MSG(slept_at >= 0, "the heap of %d shards was still awake after 8 s", SHARDS);
  ENSURE(bk_physics_body_awake(w, puck));
  bk_physics_stats s = bk_physics_get_stats(w);
  ENSURE_MSG(s.awake_bodies == 1, "awake %u", s.awake_bodies);
  ENSURE_MSG(s.pairs > (uint32_t)SHARDS, "pairs %u: the puck should be near the heap", s.pairs);
  ensure_on_ground(w, shards); // asleep, none fell through
  // A hit on the heap wakes it.
  bk_physics_body_apply_impulse(w, shards[0], bk_v3(0.0, 0.5, 0.0),
                                bk_physics_body_transform(w, shards[0]).position);
  bk_physics_step(w, dt, 1);
  ENSURE(bk_physics_body_awake(w, shards[0]));
  bk_physics_destroy(w);
}

// A body that never sleeps rests on a heap: Bullet would keep the heap's
// whole island awake; here calm shards freeze one by one and only what the
// restless body touches stays awake. A frozen shard still holds up what
// rests on it, a restless body wakes what it hits, and a frozen body whose
// support is destroyed falls.
static void test_calm_bodies_freeze(void) {
  bk_body_id shards[SHARDS];
  bk_physics* w = make_heap_world(11, 0.3, shards);
  // A block that never sleeps lands on top of the heap: its island (with
  // Bullet's rules, the whole heap) never would.
  bk_body_id block = make_sleepless_box(w, bk_v3(0.08, 0.04, 0.08), 2.0, bk_v3(0.0, 0.9, 0.0), 0.0);
  for (int step = 0; step < 6 * 60; ++step)
    bk_physics_step(w, dt, 1);
  int awake = count_awake(w, shards, SHARDS);
  ENSURE_MSG(awake <= 12, "%d of %d shards awake 6 s after they fell", awake, SHARDS);
  ENSURE(bk_physics_body_awake(w, block));
  ensure_on_ground(w, shards); // frozen shards hold up the block and each other
  // A box dropped onto the heap wakes the shards it lands on.
  bk_body_id dropped = make_small_box(w, bk_v3(0.08, 0.08, 0.08), bk_v3(-0.15, 0.6, -0.15), 0.7, 0.0);
  int most_awake = 0;
  for (int step = 0; step < 30; ++step) {
    bk_physics_step(w, dt, 1);
    int now = count_awake(w, shards, SHARDS);
    most_awake = now > most_awake ? now : most_awake;
  }
  ENSURE_MSG(most_awake > awake, "the falling box woke no shard (%d awake before, %d after)", awake,
             most_awake);
  ENSURE(bk_physics_body_transform(w, dropped).position.y > 0.08);
  bk_physics_destroy(w);

  // A box on a box: both freeze; destroy the lower one and the upper falls.
  w = make_world();
  make_ground(w);
  const bk_vec3 h = bk_v3(0.1, 0.1, 0.1);
  bk_body_id lower = make_small_box(w, h, bk_v3(0, 0.1, 0), 0.7, 0.0);
  bk_body_id upper = make_small_box(w, h, bk_v3(0, 0.3, 0), 0.7, 0.0);
  for (int step = 0; step < 3 * 60; ++step)
    bk_physics_step(w, dt, 1);
  ENSURE(!bk_physics_body_awake(w, lower) && !bk_physics_body_awake(w, upper));
  ENSURE_SMALL(bk_physics_body_mass(w, upper), 8.0 * 0.001 * 2400.0, 1e-9); // kept while frozen
  ENSURE(bk_physics_body_inertia(w, upper).x > 0.0);
  bk_physics_destroy_body(w, lower);
  for (int step = 0; step < 60; ++step)
    bk_physics_step(w, dt, 1);
  double y = bk_physics_body_transform(w, upper).position.y;
  ENSURE_MSG(y < 0.15, "the upper box stayed at y %g after its support went", y);
  bk_physics_destroy(w);
}

int main(void) {
  RUN(test_defaults);
  RUN(test_fall_and_rest);
  RUN(test_contacts);
  RUN(test_contact_capacity);
  RUN(test_substep_contacts);
  RUN(test_ccd);
  RUN(test_hulls);
  RUN(test_copy_hull);
  RUN(test_compounds);
  RUN(test_ids);
  RUN(test_validation);
  RUN(test_ray_cast);
  RUN(test_churn);
  RUN(test_near_pairs_skip_narrowphase);
  RUN(test_separated_hulls);
  RUN(test_piles_sleep);
  RUN(test_calm_bodies_freeze);
  fprintf(stderr, "test_physics: all passed\n");
  return 0;
}
