// bk_physics shapes: hulls (built exactly, simplified to a vertex budget and
// shrunk by the margin), spheres, boxes, planes and compounds, and the shape
// queries.
#include "physics_internal.hpp"

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <LinearMath/btConvexHull.h>
#include <LinearMath/btConvexHullComputer.h>

namespace {

const uint32_t max_hull_vertices = 64;

/// Exact convex hull of points (double precision): volume, vertex count and the
/// distance from the origin to the nearest face plane (negative when the
/// origin is outside). Flat or degenerate input gives volume 0.
struct HullInfo {
  double volume = 0.0;
  double inner_radius = 0.0;
  std::vector<uint32_t> vertices; // indices into the input of the hull's vertices
};

HullInfo analyze_hull(const double* xyz, uint32_t count) {
  HullInfo info;
  if (count < 4 || count > (uint32_t)std::numeric_limits<int>::max()) return info;
  btConvexHullComputer hc;
  hc.compute(xyz, 3 * (int)sizeof(double), (int)count, 0, 0);
  int nv = hc.vertices.size();
  if (nv < 4 || hc.original_vertex_index.size() != nv) return info;
  info.vertices.reserve((size_t)nv);
  bk_vec3 ref = bk_v3(0, 0, 0);
  auto point = [&](int v) {
    const double* p = xyz + 3 * (size_t)hc.original_vertex_index[v];
    return bk_v3(p[0], p[1], p[2]);
  };
  for (int v = 0; v < nv; ++v) {
    info.vertices.push_back((uint32_t)hc.original_vertex_index[v]);
    ref = bk_v3_add(ref, point(v));
  }
  ref = bk_v3_scale(ref, 1.0 / nv);

  // Faces are polygons; fan them from their first vertex. Each face also
  // gives a plane (Newell normal) for the inner radius.
  double volume6 = 0.0, min_distance = INFINITY;
  for (int f = 0; f < hc.faces.size(); ++f) {
    const btConvexHullComputer::Edge* first = &hc.edges[hc.faces[f]];
    bk_vec3 a = point(first->getSourceVertex());
    bk_vec3 normal = bk_v3(0, 0, 0);
    const btConvexHullComputer::Edge* e = first;
    do {
      bk_vec3 p = point(e->getSourceVertex()), q = point(e->getTargetVertex());
      normal = bk_v3_add(normal, bk_v3_cross(p, q));
      e = e->getNextEdgeOfFace();
    } while (e != first);
    e = first->getNextEdgeOfFace();
    bk_vec3 b = point(e->getSourceVertex());
    for (e = e->getNextEdgeOfFace(); e != first; e = e->getNextEdgeOfFace()) {
      bk_vec3 c = point(e->getSourceVertex());
      volume6 += bk_v3_dot(bk_v3_sub(a, ref), bk_v3_cross(bk_v3_sub(b, ref), bk_v3_sub(c, ref)));
      b = c;
    }
    double length = bk_v3_length(normal);
    if (length > 0.0) min_distance = fmin(min_distance, bk_v3_dot(normal, a) / length);
  }
  // Bullet lists face edges counter-clockwise seen from outside, so the
  // volume is positive; guard against the opposite order anyway.
  double sign = volume6 < 0.0 ? -1.0 : 1.0;
  info.volume = fabs(volume6) / 6.0;
  info.inner_radius = std::isfinite(min_distance) ? sign * min_distance : 0.0;
  return info;
}

HullInfo analyze_hull(const std::vector<btVector3>& points) {
  std::vector<double> xyz;
  xyz.reserve(points.size() * 3);
  for (const btVector3& p : points) {
    xyz.push_back(p.x());
    xyz.push_back(p.y());
    xyz.push_back(p.z());
  }
  return analyze_hull(xyz.data(), (uint32_t)points.size());
}

/// At most max_vertices of the hull vertices, chosen by Bullet's incremental
/// hull builder (it adds the farthest point first until the limit).
std::vector<btVector3> simplify_hull(const std::vector<btVector3>& points, uint32_t max_vertices) {
  HullDesc desc(QF_TRIANGLES, (unsigned)points.size(), points.data(), sizeof(btVector3));
  desc.mMaxVertices = max_vertices;
  HullLibrary library;
  HullResult result;
  std::vector<btVector3> out;
  if (library.CreateConvexHull(desc, result) == QE_OK) {
    for (unsigned i = 0; i < result.mNumOutputVertices && i < max_vertices; ++i)
      out.push_back(result.m_OutputVertices[(int)i]);
  }
  library.ReleaseResult(result);
  return out;
}

} // namespace

// ---------------------------------------------------------------- shapes

bool bk_physics_prepare_hull(const bk_vec3* points, uint32_t count, uint32_t max_vertices, double margin,
                             bk_hull_prepared* out) {
  if (!out) return false;
  out->vertex_count = 0;
  if (!points || count < 4 || !(margin >= 0.0)) return false;
  for (uint32_t i = 0; i < count; ++i)
    if (!bk_v3_is_finite(points[i])) return false;
  if (max_vertices == 0 || max_vertices > max_hull_vertices) max_vertices = max_hull_vertices;
  if (max_vertices < 4) max_vertices = 4;
  try {
    static_assert(sizeof(bk_vec3) == 3 * sizeof(double), "bk_vec3 must be three packed doubles");
    HullInfo exact = analyze_hull(&points[0].x, count);
    if (exact.vertices.size() < 4) return false;
    std::vector<btVector3> vertices;
    vertices.reserve(exact.vertices.size());
    for (uint32_t v : exact.vertices)
      vertices.push_back(to_bt(points[v]));
    if (vertices.size() > max_vertices) vertices = simplify_hull(vertices, max_vertices);

    // Judge flatness on the single-precision vertices Bullet will use.
    HullInfo final_hull = analyze_hull(vertices);
    btVector3 lo = vertices.empty() ? btVector3(0, 0, 0) : vertices[0], hi = lo;
    for (const btVector3& p : vertices) {
      lo.setMin(p);
      hi.setMax(p);
    }
    double extent = (hi - lo).length();
    if (final_hull.vertices.size() < 4 || !(final_hull.volume > 1e-9 * extent * extent * extent))
      return false;
    // Rounding to float may have pushed a nearly coplanar vertex inside.
    std::vector<btVector3> kept;
    kept.reserve(final_hull.vertices.size());
    for (uint32_t v : final_hull.vertices)
      kept.push_back(vertices[v]);
    vertices.swap(kept);

    // Shrink the hull by the collision margin so its rounded surface is the
    // fragment's own. Fragments share faces exactly: unshrunk, neighbouring
    // cores would touch at distance zero, and every such pair would take
    // Bullet's slow penetration-depth path (EPA) instead of GJK. The clamp
    // keeps slivers from collapsing; the margin becomes the actual shrink.
    if (margin > 0.0) {
      btConvexHullComputer shrunk;
      btScalar applied = shrunk.compute(&vertices[0].x(), (int)sizeof(btVector3), (int)vertices.size(),
                                        (btScalar)margin, (btScalar)0.3);
      if (applied > 0 && shrunk.vertices.size() >= 4) {
        vertices.assign(&shrunk.vertices[0], &shrunk.vertices[0] + shrunk.vertices.size());
        margin = applied;
        // Moving faces inward splits corners where more than three faces
        // meet; keep the vertex budget (the result stays inside the core).
        if (vertices.size() > max_vertices) vertices = simplify_hull(vertices, max_vertices);
      }
    }
    if (vertices.size() > BK_HULL_PREPARED_MAX) return false;
    for (size_t i = 0; i < vertices.size(); ++i)
      out->vertices[i] = bk_v3(vertices[i].x(), vertices[i].y(), vertices[i].z());
    out->vertex_count = (uint32_t)vertices.size();
    out->margin = margin;
    out->volume = final_hull.volume;
    out->inner_radius =
        final_hull.inner_radius > 0.0 ? final_hull.inner_radius : 0.25 * (hi - lo)[(hi - lo).minAxis()];
    return true;
  } catch (...) {
    out->vertex_count = 0;
    return false;
  }
}

bk_shape_id bk_physics_create_prepared_hull(bk_physics* w, const bk_hull_prepared* prepared) {
  const bk_shape_id null_id = {0, 0};
  if (!w || !prepared || prepared->vertex_count < 4 || prepared->vertex_count > BK_HULL_PREPARED_MAX)
    return null_id;
  try {
    std::vector<btVector3> vertices;
    vertices.reserve(prepared->vertex_count);
    for (uint32_t i = 0; i < prepared->vertex_count; ++i)
      vertices.push_back(to_bt(prepared->vertices[i]));
    btConvexHullShape* hull =
        new btConvexHullShape(&vertices[0].x(), (int)vertices.size(), sizeof(btVector3));
    hull->setMargin((btScalar)prepared->margin);
    // The constructor cached the bounds with Bullet's default 4 cm margin;
    // stale, they made every fragment overlap dozens of neighbours.
    hull->recalcLocalAabb();
    bk_shape_id id = w->add_shape(hull, ShapeKind::hull, prepared->inner_radius);
    ShapeSlot* slot = w->shape(id);
    if (slot) slot->hull_volume = prepared->volume;
    return id;
  } catch (...) {
    return null_id;
  }
}

double bk_physics_hull_margin(const bk_physics* w) { return w ? w->margin : 0.0; }

bk_shape_id bk_physics_create_hull(bk_physics* w, const bk_vec3* points, uint32_t count,
                                   uint32_t max_vertices) {
  if (!w) return bk_shape_id{0, 0};
  // Prepared and made in one go (the same hull bk_physics_prepare_hull and
  // bk_physics_create_prepared_hull make in two).
  bk_hull_prepared* prepared = new bk_hull_prepared;
  bk_shape_id id = bk_physics_prepare_hull(points, count, max_vertices, w->margin, prepared)
                       ? bk_physics_create_prepared_hull(w, prepared)
                       : bk_shape_id{0, 0};
  delete prepared;
  return id;
}

bk_shape_id bk_physics_copy_hull(bk_physics* w, bk_shape_id hull, bk_transform transform) {
  const ShapeSlot* s = w ? w->shape(hull) : nullptr;
  if (!s || s->kind != ShapeKind::hull || !transform_is_finite(transform)) return bk_shape_id{0, 0};
  try {
    const btConvexHullShape* from = static_cast<const btConvexHullShape*>(s->shape);
    const double volume = s->hull_volume; // s may move when the new slot is added
    int count = from->getNumPoints();
    if (count < 4) return bk_shape_id{0, 0};
    std::vector<btVector3> vertices((size_t)count);
    // Moved in double precision, rounded once.
    for (int i = 0; i < count; ++i)
      vertices[(size_t)i] = to_bt(bk_transform_point(transform, to_bk(from->getUnscaledPoints()[i])));
    btConvexHullShape* moved = new btConvexHullShape(&vertices[0].x(), count, sizeof(btVector3));
    moved->setMargin(from->getMargin());
    // As in bk_physics_create_hull: the constructor's bounds used the default margin.
    moved->recalcLocalAabb();
    // The sphere inside it about the new origin is not known without its
    // faces; 0 lets continuous collision take a quarter of its least extent.
    bk_shape_id id = w->add_shape(moved, ShapeKind::hull, 0.0);
    ShapeSlot* slot = w->shape(id);
    if (slot) slot->hull_volume = volume;
    return id;
  } catch (...) {
    return bk_shape_id{0, 0};
  }
}

bk_shape_id bk_physics_create_sphere(bk_physics* w, double radius) {
  if (!w || !(std::isfinite(radius) && radius > 0.0)) return bk_shape_id{0, 0};
  return w->add_shape(new btSphereShape((btScalar)radius), ShapeKind::sphere, radius);
}

bk_shape_id bk_physics_create_box(bk_physics* w, bk_vec3 half_extents) {
  bk_vec3 h = half_extents;
  if (!w || !bk_v3_is_finite(h) || !(h.x > 0.0 && h.y > 0.0 && h.z > 0.0)) return bk_shape_id{0, 0};
  double smallest = fmin(h.x, fmin(h.y, h.z));
  btBoxShape* box = new btBoxShape(to_bt(h));
  // Bullet keeps the box's outer size and puts the margin inside it, so the
  // margin must stay below the smallest half extent.
  box->setMargin((btScalar)fmin(w->margin, 0.5 * smallest));
  return w->add_shape(box, ShapeKind::box, smallest);
}

bk_shape_id bk_physics_create_plane(bk_physics* w, bk_vec3 normal, double offset) {
  double length = bk_v3_length(normal);
  if (!w || !bk_v3_is_finite(normal) || !std::isfinite(offset) || !(length > 0.0 && std::isfinite(length)))
    return bk_shape_id{0, 0};
  btStaticPlaneShape* plane =
      new btStaticPlaneShape(to_bt(bk_v3_scale(normal, 1.0 / length)), (btScalar)(offset / length));
  return w->add_shape(plane, ShapeKind::plane, 0.0);
}

bk_shape_id bk_physics_create_compound(bk_physics* w, uint32_t expected_children) {
  if (!w) return bk_shape_id{0, 0};
  int capacity = expected_children < 1024 ? (int)expected_children : 1024;
  return w->add_shape(new btCompoundShape(true, capacity), ShapeKind::compound, 0.0);
}

void bk_physics_compound_add(bk_physics* w, bk_shape_id compound, bk_shape_id child, bk_transform local) {
  if (!w) return;
  ShapeSlot* parent = w->shape(compound);
  ShapeSlot* c = w->shape(child);
  // Children are convex (planes are infinite; nested compounds are not supported).
  if (!parent || !c || parent->kind != ShapeKind::compound || c->kind == ShapeKind::plane ||
      c->kind == ShapeKind::compound || !transform_is_finite(local))
    return;
  try {
    parent->children.push_back(child.index);
  } catch (...) {
    return;
  }
  ++c->uses;
  static_cast<btCompoundShape*>(parent->shape)->addChildShape(to_bt(local), c->shape);
}

void bk_physics_destroy_shape(bk_physics* w, bk_shape_id shape) {
  if (!w) return;
  ShapeSlot* s = w->shape(shape);
  // A shape still used by a body or a compound is left alone (destroying it
  // would leave them pointing at freed memory).
  if (!s || s->uses > 0) return;
  w->destroy_shape_slot(shape.index);
}

bool bk_physics_shape_valid(const bk_physics* w, bk_shape_id shape) { return w && w->shape(shape); }

uint32_t bk_physics_hull_vertices(const bk_physics* w, bk_shape_id hull, bk_vec3* out, uint32_t capacity) {
  const ShapeSlot* s = w ? w->shape(hull) : nullptr;
  if (!s || s->kind != ShapeKind::hull) return 0;
  const btConvexHullShape* shape = static_cast<const btConvexHullShape*>(s->shape);
  uint32_t n = (uint32_t)shape->getNumPoints();
  for (uint32_t i = 0; out && i < n && i < capacity; ++i)
    out[i] = to_bk(shape->getUnscaledPoints()[i]);
  return n;
}

double bk_physics_hull_volume(const bk_physics* w, bk_shape_id hull) {
  const ShapeSlot* s = w ? w->shape(hull) : nullptr;
  if (!s || s->kind != ShapeKind::hull) return 0.0;
  return s->hull_volume;
}

uint32_t bk_physics_shape_count(const bk_physics* w) { return w ? w->shapes.live : 0; }
