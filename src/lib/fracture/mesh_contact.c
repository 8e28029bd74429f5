// The contact of two closed meshes, measured triangle pair by triangle pair:
// interior (cap) triangles of both in one plane, facing opposite ways, are
// clipped against each other in that plane, which gives the contact's area
// and centroid exactly (the bonds of a tree measure the same overlaps cut by
// cut, bonds.c). Used to divide a refined leaf's bonds among its pieces
// (leaf_refine.c) and, pair by pair of leaves, as a brute-force check.
#include <string.h>

#include "mesh_contact.h"

static bool boxes_touch(bk_aabb a, bk_aabb b, double tolerance);

// An interior triangle whose box touches `within`, measured (else false).
static bool tri_measure(const bk_mesh* mesh, uint32_t t, bk_aabb within, double tolerance, tri_info* out) {
  if (!bk_material_is_interior(mesh->materials[t])) return false;
  for (int k = 0; k < 3; ++k)
    out->p[k] = mesh->positions[bk_mesh_tri_position(mesh, t, (uint32_t)k)];
  out->box = (bk_aabb){bk_v3_min(out->p[0], bk_v3_min(out->p[1], out->p[2])),
                       bk_v3_max(out->p[0], bk_v3_max(out->p[1], out->p[2]))};
  if (!boxes_touch(out->box, within, tolerance)) return false;
  bk_vec3 n = bk_v3_cross(bk_v3_sub(out->p[1], out->p[0]), bk_v3_sub(out->p[2], out->p[0]));
  double length = bk_v3_length(n);
  if (!(length > 0.0)) return false; // no area: touches nothing
  out->normal = bk_v3_scale(n, 1.0 / length);
  out->offset = bk_v3_dot(out->normal, out->p[0]);
  return true;
}

static double tri_area(const tri_info* t) {
  return 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(t->p[1], t->p[0]), bk_v3_sub(t->p[2], t->p[0])));
}

static bool boxes_touch(bk_aabb a, bk_aabb b, double tolerance) {
  return a.min.x <= b.max.x + tolerance && b.min.x <= a.max.x + tolerance && a.min.y <= b.max.y + tolerance &&
         b.min.y <= a.max.y + tolerance && a.min.z <= b.max.z + tolerance && b.min.z <= a.max.z + tolerance;
}

// In one plane, facing opposite ways: each triangle's corners lie on the
// other's plane (either way round: a sliver's own normal is imprecise).
static bool tri_facing(const tri_info* a, const tri_info* b, double tolerance) {
  if (!(bk_v3_dot(a->normal, b->normal) < -0.99)) return false;
  bool b_on_a = true, a_on_b = true;
  for (int k = 0; k < 3; ++k) {
    b_on_a &= fabs(bk_v3_dot(a->normal, b->p[k]) - a->offset) <= tolerance;
    a_on_b &= fabs(bk_v3_dot(b->normal, a->p[k]) - b->offset) <= tolerance;
  }
  return b_on_a || a_on_b;
}

// Clips a convex polygon (n points) to the left of the directed line a->b.
static uint32_t clip_left(const double (*in)[2], uint32_t n, const double a[2], const double b[2],
                          double (*out)[2]) {
  double ex = b[0] - a[0], ey = b[1] - a[1];
  double side[9] = {0};
  for (uint32_t i = 0; i < n; ++i)
    side[i] = ex * (in[i][1] - a[1]) - ey * (in[i][0] - a[0]);
  uint32_t m = 0;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t j = i + 1 == n ? 0 : i + 1;
    if (side[i] >= 0.0) {
      out[m][0] = in[i][0];
      out[m][1] = in[i][1];
      m++;
    }
    if ((side[i] >= 0.0) != (side[j] >= 0.0)) {
      double s = side[i] / (side[i] - side[j]);
      out[m][0] = in[i][0] + (in[j][0] - in[i][0]) * s;
      out[m][1] = in[i][1] + (in[j][1] - in[i][1]) * s;
      m++;
    }
  }
  return m;
}

// The overlap of two facing triangles, measured in a's plane: its area and
// area-weighted centroid added to *area and *moment.
static void overlap_add(const tri_info* a, const tri_info* b, double* area, bk_vec3* moment) {
  bk_vec3 u = {0}, v = {0};
  bk_plane_basis(a->normal, &u, &v);
  bk_vec3 o = a->p[0];
  double poly[2][9][2] = {{{0}}};
  double tri[3][2] = {{0}};
  for (int k = 0; k < 3; ++k) {
    bk_vec3 d = bk_v3_sub(a->p[k], o);
    poly[0][k][0] = bk_v3_dot(d, u);
    poly[0][k][1] = bk_v3_dot(d, v);
    bk_vec3 e = bk_v3_sub(b->p[k], o);
    tri[k][0] = bk_v3_dot(e, u);
    tri[k][1] = bk_v3_dot(e, v);
  }
  // b faces the other way: seen in a's basis it turns clockwise.
  double turn =
      (tri[1][0] - tri[0][0]) * (tri[2][1] - tri[0][1]) - (tri[1][1] - tri[0][1]) * (tri[2][0] - tri[0][0]);
  if (turn > 0.0) return; // not facing after all
  uint32_t n = 3, cur = 0;
  for (int k = 0; k < 3 && n >= 3; ++k) { // b's edges, reversed: counter-clockwise
    const double* p = tri[(3 - k) % 3];
    const double* q = tri[(5 - k) % 3];
    n = clip_left((const double(*)[2])poly[cur], n, p, q, poly[1 - cur]);
    cur = 1 - cur;
  }
  double a_area = 0.0;
  bk_vec3 centroid = {0};
  if (!bk_polygon_lift((const double(*)[2])poly[cur], n, o, u, v, &a_area, &centroid)) return;
  *area += a_area;
  *moment = bk_v3_add(*moment, bk_v3_scale(centroid, a_area));
}

bool bk_polygon_lift(const double (*points)[2], uint32_t n, bk_vec3 origin, bk_vec3 u, bk_vec3 v,
                     double* area, bk_vec3* centroid) {
  double twice = 0.0, cx = 0.0, cy = 0.0;
  for (uint32_t i = 0; n >= 3 && i < n; ++i) {
    const double* p = points[i];
    const double* q = points[i + 1 == n ? 0 : i + 1];
    double cross = p[0] * q[1] - q[0] * p[1];
    twice += cross;
    cx += (p[0] + q[0]) * cross;
    cy += (p[1] + q[1]) * cross;
  }
  if (!(twice > 0.0)) return false;
  *area = 0.5 * twice;
  *centroid =
      bk_v3_add(origin, bk_v3_add(bk_v3_scale(u, cx / (3.0 * twice)), bk_v3_scale(v, cy / (3.0 * twice))));
  return true;
}

bk_contact_measure bk_contact_finish(double area, bk_vec3 moment, bk_vec3 normal) {
  bk_contact_measure out = {0};
  if (!(area > 0.0)) return out;
  out.area = area;
  out.centroid = bk_v3_scale(moment, 1.0 / area);
  out.normal = bk_v3_normalize(normal); // a's outward normal: from a to b
  return out;
}

void bk_contact_sides_free(bk_contact_side* side) {
  bk_free(side->tris);
  memset(side, 0, sizeof *side);
}

void bk_contact_side_gather(const bk_mesh* mesh, bk_aabb within, double tolerance, bk_contact_side* out) {
  memset(out, 0, sizeof *out);
  out->tris = bk_alloc(sizeof(tri_info) * (mesh->triangle_count + 1u));
  out->box = (bk_aabb){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  tri_info* tris = out->tris;
  for (uint32_t t = 0; t < mesh->triangle_count; ++t) {
    tri_info info = {0};
    if (!tri_measure(mesh, t, within, tolerance, &info)) continue;
    tris[out->count++] = info;
    out->box.min = bk_v3_min(out->box.min, info.box.min);
    out->box.max = bk_v3_max(out->box.max, info.box.max);
  }
}

void bk_contact_side_subset(const bk_contact_side* from, bk_aabb within, double tolerance,
                            bk_contact_side* out) {
  memset(out, 0, sizeof *out);
  out->tris = bk_alloc(sizeof(tri_info) * (from->count + 1u));
  out->box = (bk_aabb){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  const tri_info* all = from->tris;
  tri_info* tris = out->tris;
  for (uint32_t i = 0; i < from->count; ++i) {
    if (!boxes_touch(all[i].box, within, tolerance)) continue;
    tris[out->count++] = all[i];
    out->box.min = bk_v3_min(out->box.min, all[i].box.min);
    out->box.max = bk_v3_max(out->box.max, all[i].box.max);
  }
}

void bk_contact_side_keep_facing(bk_contact_side* side, const bk_contact_side* other, double tolerance) {
  tri_info* tris = side->tris;
  const tri_info* others = other->tris;
  uint32_t kept = 0;
  side->box = (bk_aabb){{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (uint32_t i = 0; i < side->count; ++i) {
    bool facing = false;
    for (uint32_t j = 0; j < other->count && !facing; ++j)
      facing =
          boxes_touch(tris[i].box, others[j].box, tolerance) && tri_facing(&tris[i], &others[j], tolerance);
    if (!facing) continue;
    tris[kept++] = tris[i];
    side->box.min = bk_v3_min(side->box.min, tris[i].box.min);
    side->box.max = bk_v3_max(side->box.max, tris[i].box.max);
  }
  side->count = kept;
}

bk_contact_measure bk_contact_sides_measure(const bk_contact_side* a, const bk_contact_side* b,
                                            double tolerance) {
  if (!a->count || !b->count || !boxes_touch(a->box, b->box, tolerance)) return (bk_contact_measure){0};
  const tri_info* ta = a->tris;
  const tri_info* tb = b->tris;
  double area = 0.0;
  bk_vec3 moment = {0}, normal = {0};
  for (uint32_t i = 0; i < a->count; ++i) {
    if (!boxes_touch(ta[i].box, b->box, tolerance)) continue;
    for (uint32_t j = 0; j < b->count; ++j) {
      if (!boxes_touch(ta[i].box, tb[j].box, tolerance) || !tri_facing(&ta[i], &tb[j], tolerance)) continue;
      double before = area;
      overlap_add(&ta[i], &tb[j], &area, &moment);
      normal = bk_v3_add(normal, bk_v3_scale(ta[i].normal, area - before));
    }
  }
  return bk_contact_finish(area, moment, normal);
}

double bk_contact_side_area(const bk_contact_side* side) {
  const tri_info* t = side->tris;
  double area = 0.0;
  for (uint32_t i = 0; i < side->count; ++i)
    area += tri_area(&t[i]);
  return area;
}

// Whether point p (on t's plane, within tolerance) lies inside triangle t.
static bool inside_triangle(const tri_info* t, bk_vec3 p, double tolerance) {
  if (fabs(bk_v3_dot(t->normal, p) - t->offset) > tolerance) return false;
  for (int k = 0; k < 3; ++k) {
    bk_vec3 edge = bk_v3_sub(t->p[(k + 1) % 3], t->p[k]);
    bk_vec3 inward = bk_v3_cross(t->normal, edge); // points into the triangle
    double length = bk_v3_length(inward);
    if (!(length > 0.0) || bk_v3_dot(inward, bk_v3_sub(p, t->p[k])) < -tolerance * length) return false;
  }
  return true;
}

bk_contact_measure bk_contact_side_parts_of(const bk_contact_side* a, const bk_contact_side* on,
                                            double tolerance) {
  if (!a->count || !on->count || !boxes_touch(a->box, on->box, tolerance)) return (bk_contact_measure){0};
  const tri_info* ta = a->tris;
  const tri_info* to = on->tris;
  double area = 0.0;
  bk_vec3 moment = {0}, normal = {0};
  for (uint32_t i = 0; i < a->count; ++i) {
    if (!boxes_touch(ta[i].box, on->box, tolerance)) continue;
    bk_vec3 centroid = bk_v3_scale(bk_v3_add(ta[i].p[0], bk_v3_add(ta[i].p[1], ta[i].p[2])), 1.0 / 3.0);
    for (uint32_t j = 0; j < on->count; ++j) {
      if (!boxes_touch(ta[i].box, to[j].box, tolerance) || !(bk_v3_dot(ta[i].normal, to[j].normal) > 0.99) ||
          !inside_triangle(&to[j], centroid, tolerance))
        continue;
      double part = tri_area(&ta[i]);
      area += part;
      moment = bk_v3_add(moment, bk_v3_scale(centroid, part));
      normal = bk_v3_add(normal, bk_v3_scale(ta[i].normal, part));
      break;
    }
  }
  return bk_contact_finish(area, moment, normal);
}

bool bk_contact_side_plane(const bk_contact_side* side, double tolerance, bk_plane* plane) {
  const tri_info* t = side->tris;
  if (!side->count) return false;
  // The largest triangle's plane: the most precise normal.
  uint32_t best = 0;
  for (uint32_t i = 1; i < side->count; ++i)
    if (tri_area(&t[i]) > tri_area(&t[best])) best = i;
  *plane = (bk_plane){t[best].normal, t[best].offset};
  for (uint32_t i = 0; i < side->count; ++i)
    for (int k = 0; k < 3; ++k)
      if (!(fabs(bk_plane_distance(*plane, t[i].p[k])) <= tolerance) ||
          !(bk_v3_dot(t[i].normal, plane->normal) > 0.0))
        return false;
  return true;
}

bk_contact_measure bk_contact_side_on_plane(const bk_contact_side* a, bk_plane plane, double tolerance) {
  const tri_info* t = a->tris;
  double area = 0.0;
  bk_vec3 moment = {0}, normal = {0};
  for (uint32_t i = 0; i < a->count; ++i) {
    if (!bk_tri_on_plane(&t[i], plane, tolerance)) continue;
    double part = tri_area(&t[i]);
    bk_vec3 centroid = bk_v3_scale(bk_v3_add(t[i].p[0], bk_v3_add(t[i].p[1], t[i].p[2])), 1.0 / 3.0);
    area += part;
    moment = bk_v3_add(moment, bk_v3_scale(centroid, part));
    normal = bk_v3_add(normal, bk_v3_scale(t[i].normal, part));
  }
  return bk_contact_finish(area, moment, normal);
}

bk_contact_measure bk_mesh_contact(const bk_mesh* a, const bk_mesh* b, double tolerance) {
  bk_contact_measure out = {0};
  if (!a || !b || !(tolerance >= 0.0)) return out;
  bk_aabb box_a = bk_mesh_bounds(a), box_b = bk_mesh_bounds(b);
  if (!boxes_touch(box_a, box_b, tolerance)) return out;
  bk_contact_side side_a = {0}, side_b = {0};
  bk_contact_side_gather(a, box_b, tolerance, &side_a);
  bk_contact_side_gather(b, box_a, tolerance, &side_b);
  out = bk_contact_sides_measure(&side_a, &side_b, tolerance);
  bk_contact_sides_free(&side_a);
  bk_contact_sides_free(&side_b);
  return out;
}
