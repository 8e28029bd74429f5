// Procedural shapes: closure, counts, exact volumes and sane per-corner attributes.
#include <string.h>

#include "bk_geom.h"
#include "ensure.h"

#define PI 3.14159265358979323846

static bk_vec3 corner_normal(const bk_corner* c) { return bk_v3(c->normal[0], c->normal[1], c->normal[2]); }
static bk_vec3 corner_tangent(const bk_corner* c) {
  return bk_v3(c->tangent[0], c->tangent[1], c->tangent[2]);
}

/// Checks every shape must satisfy and returns its volume.
static double check_common(bk_shape shape, const bk_mesh* m) {
  const char* name = bk_shape_name(shape);
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_validate(m, &err), "%s: %s", name, err.message);
  bk_closure closure = bk_mesh_check_closure(m);
  ENSURE_MSG(bk_mesh_is_closed(m), "%s: open %u overused %u degenerate %u", name, closure.open_edges,
             closure.overused_edges, closure.degenerate_edges);
  double volume = bk_mesh_volume(m);
  ENSURE_MSG(volume > 0.0, "%s: volume %g", name, volume);
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    ENSURE(m->materials[t] == BK_MATERIAL_OUTER);
    ENSURE(m->tags[t] == 0);
  }
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const bk_corner* c = &m->corners[i];
    bk_vec3 n = corner_normal(c), t = corner_tangent(c);
    ENSURE_SMALL(bk_v3_length(n), 1.0, 1e-5);
    ENSURE_SMALL(bk_v3_length(t), 1.0, 1e-4);
    ENSURE_SMALL(bk_v3_dot(n, t), 0.0, 1e-4);
    ENSURE(c->tangent[3] == 1.0f || c->tangent[3] == -1.0f);
  }
  // Corner normals must agree with the winding: each lies on the outer side
  // of the triangle it belongs to.
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
    bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
    bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
    bk_vec3 face = bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
    for (int k = 0; k < 3; ++k)
      ENSURE_MSG(bk_v3_dot(face, corner_normal(&m->corners[m->indices[3 * t + k]])) > 0.0,
                 "%s: triangle %u corner %d normal against winding", name, t, k);
  }
  return volume;
}

/// For convex shapes every corner normal points away from the centroid.
static void check_convex_normals(const bk_mesh* m) {
  bk_vec3 centroid = bk_moments_to_mass(bk_mesh_moments(m)).centroid;
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    bk_vec3 d = bk_v3_sub(m->positions[m->corners[i].position], centroid);
    ENSURE(bk_v3_dot(corner_normal(&m->corners[i]), d) > 0.0);
  }
}

static void check_counts(const bk_mesh* m, uint32_t positions, uint32_t corners, uint32_t triangles) {
  ENSURE(m->position_count == positions);
  ENSURE(m->corner_count == corners);
  ENSURE(m->triangle_count == triangles);
}

static void test_names(void) {
  for (int i = 0; i < BK_SHAPE_COUNT; ++i) {
    bk_shape back = BK_SHAPE_COUNT;
    const char* name = bk_shape_name((bk_shape)i);
    ENSURE(name && strcmp(name, "unknown") != 0);
    ENSURE(bk_shape_from_name(name, &back));
    ENSURE(back == (bk_shape)i);
    for (int j = 0; j < i; ++j)
      ENSURE(strcmp(name, bk_shape_name((bk_shape)j)) != 0);
  }
  ENSURE(strcmp(bk_shape_name(BK_SHAPE_CUBE), "cube") == 0);
  ENSURE(strcmp(bk_shape_name(BK_SHAPE_EGGSHELL), "eggshell") == 0);
  bk_shape untouched = BK_SHAPE_PILLAR;
  ENSURE(!bk_shape_from_name("dodecahedron", &untouched));
  ENSURE(!bk_shape_from_name("", &untouched));
  ENSURE(!bk_shape_from_name("Cube", &untouched));
  ENSURE(!bk_shape_from_name(NULL, &untouched));
  ENSURE(untouched == BK_SHAPE_PILLAR);
  ENSURE(bk_shape_name(BK_SHAPE_COUNT) != NULL);
}

static void test_cube(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_CUBE, &m);
  check_counts(&m, 8, 24, 12);
  ENSURE_SMALL(check_common(BK_SHAPE_CUBE, &m), 1.0, 1e-12);
  check_convex_normals(&m);
  bk_aabb box = bk_mesh_bounds(&m);
  ENSURE(box.min.x == -0.5 && box.min.y == -0.5 && box.min.z == -0.5);
  ENSURE(box.max.x == 0.5 && box.max.y == 0.5 && box.max.z == 0.5);
  // Flat faces: each face's uvs span exactly the unit square.
  for (uint32_t i = 0; i < m.corner_count; ++i) {
    ENSURE(m.corners[i].uv[0] == 0.0f || m.corners[i].uv[0] == 1.0f);
    ENSURE(m.corners[i].uv[1] == 0.0f || m.corners[i].uv[1] == 1.0f);
  }
  bk_mesh_free(&m);
}

static void test_torus(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_TORUS, &m);
  check_counts(&m, 400, 441, 800);
  double volume = check_common(BK_SHAPE_TORUS, &m);
  const double big_r = 1.0, small_r = 0.35;
  const int n = 20;
  // Inscribed 20-gon tube swept along a 20-gon ring: each factor is the
  // polygon/circle area ratio n sin(2 pi / n) / (2 pi), and the side quads are
  // planar, so the polyhedral volume has this closed form exactly.
  double ratio = n * sin(2.0 * PI / n) / (2.0 * PI);
  double smooth = 2.0 * PI * PI * big_r * small_r * small_r;
  ENSURE_REL(volume, smooth * ratio * ratio, 1e-12);
  ENSURE_REL(volume, smooth, 0.035);
  // Normals point away from the tube's centre circle.
  for (uint32_t i = 0; i < m.corner_count; ++i) {
    bk_vec3 p = m.positions[m.corners[i].position];
    double rho = sqrt(p.x * p.x + p.z * p.z);
    bk_vec3 centre = bk_v3(p.x / rho * big_r, 0.0, p.z / rho * big_r);
    bk_vec3 d = bk_v3_sub(p, centre);
    ENSURE_SMALL(bk_v3_length(d), small_r, 1e-12);
    ENSURE_SMALL(bk_v3_dot(corner_normal(&m.corners[i]), bk_v3_scale(d, 1.0 / small_r)), 1.0, 1e-6);
  }
  bk_mesh_free(&m);
}

/// Area of a regular n-gon over the area of its circumcircle: how much volume
/// an inscribed n-segment surface of revolution loses against the smooth one.
static double polygon_ratio(int n) { return n * sin(2.0 * PI / n) / (2.0 * PI); }

static void test_eggshell(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_EGGSHELL, &m);
  ENSURE(fabs((double)m.corner_count - 878.0) <= 0.15 * 878.0);
  ENSURE(fabs((double)m.triangle_count - 1520.0) <= 0.15 * 1520.0);
  ENSURE(m.triangle_count % 2 == 0);
  double shell = check_common(BK_SHAPE_EGGSHELL, &m);

  // The outer surface is the first half of the triangles and is closed by itself.
  bk_mesh outer = {0};
  bk_mesh_copy(&outer, &m);
  outer.triangle_count = m.triangle_count / 2;
  ENSURE(bk_mesh_is_closed(&outer));
  double outer_volume = bk_mesh_volume(&outer);
  bk_mesh_free(&outer);
  ENSURE(shell < outer_volume);
  ENSURE(shell > 0.05 * outer_volume); // a shell, not a sliver

  // Proportions: about 0.6 tall, 0.45 wide, resting on y = 0.
  bk_aabb box = bk_mesh_bounds(&m);
  ENSURE_SMALL(box.min.y, 0.0, 1e-12);
  ENSURE_SMALL(box.max.y, 0.6, 1e-9);
  ENSURE_SMALL(box.max.x - box.min.x, 0.45, 0.02);
  ENSURE_SMALL(box.max.z - box.min.z, 0.45, 0.02);

  // Smooth egg volume by Simpson's rule on pi r(y)^2 dy with the same
  // profile; the mesh is an inscribed 20-gon in every ring, slightly smaller.
  const double a = 0.2208, b = 0.3, k = 0.2;
  const int steps = 2000;
  double smooth = 0.0;
  for (int i = 0; i <= steps; ++i) {
    double t = PI * i / steps;
    double r = a * sin(t) * (1.0 + k * cos(t)), dy = b * sin(t);
    double w = (i == 0 || i == steps) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    smooth += w * PI * r * r * dy;
  }
  smooth *= (PI / steps) / 3.0;
  ENSURE(outer_volume < smooth);
  ENSURE_REL(outer_volume, smooth * polygon_ratio(20), 0.01);

  // Shell volume ~ thickness x mean of the two surface areas.
  bk_mesh inner = {0};
  bk_mesh_copy(&inner, &m);
  // Inner triangles follow the outer ones: shift them to the front.
  memmove(inner.indices, inner.indices + 3 * (m.triangle_count / 2),
          sizeof(uint32_t) * 3 * (m.triangle_count / 2));
  inner.triangle_count = m.triangle_count / 2;
  ENSURE(bk_mesh_is_closed(&inner));
  ENSURE(bk_mesh_volume(&inner) < 0.0); // faces the cavity
  ENSURE_SMALL(outer_volume + bk_mesh_volume(&inner), shell, 1e-12);
  double mean_area = 0.5 * bk_mesh_area(&m); // m holds both surfaces
  ENSURE_REL(shell, 0.03 * mean_area, 0.05);

  // Outer normals point away from the egg's middle, inner ones towards it.
  bk_vec3 middle = bk_v3(0.0, 0.3, 0.0);
  for (uint32_t t = 0; t < m.triangle_count; ++t) {
    double facing = t < m.triangle_count / 2 ? 1.0 : -1.0;
    for (int c = 0; c < 3; ++c) {
      const bk_corner* corner = &m.corners[m.indices[3 * t + c]];
      bk_vec3 d = bk_v3_sub(m.positions[corner->position], middle);
      ENSURE(facing * bk_v3_dot(corner_normal(corner), d) > 0.0);
    }
  }
  bk_mesh_free(&inner);
  bk_mesh_free(&m);
}

static void check_box_shape(bk_shape shape, double sx, double sy, double sz) {
  bk_mesh m = {0};
  bk_shape_build(shape, &m);
  check_counts(&m, 8, 24, 12);
  ENSURE_SMALL(check_common(shape, &m), sx * sy * sz, 1e-12);
  check_convex_normals(&m);
  bk_aabb box = bk_mesh_bounds(&m);
  ENSURE(box.min.y == 0.0);
  ENSURE_SMALL(box.max.y, sy, 1e-15);
  ENSURE_SMALL(box.min.x, -0.5 * sx, 1e-15);
  ENSURE_SMALL(box.max.x, 0.5 * sx, 1e-15);
  ENSURE_SMALL(box.min.z, -0.5 * sz, 1e-15);
  ENSURE_SMALL(box.max.z, 0.5 * sz, 1e-15);
  // uvs in metres: each face's uv extent equals its world extent.
  for (uint32_t f = 0; f < 6; ++f) {
    double umin = INFINITY, umax = -INFINITY, vmin = INFINITY, vmax = -INFINITY;
    bk_vec3 lo = bk_v3(INFINITY, INFINITY, INFINITY), hi = bk_v3(-INFINITY, -INFINITY, -INFINITY);
    for (uint32_t k = 0; k < 6; ++k) {
      const bk_corner* c = &m.corners[m.indices[6 * f + k]];
      umin = fmin(umin, c->uv[0]), umax = fmax(umax, c->uv[0]);
      vmin = fmin(vmin, c->uv[1]), vmax = fmax(vmax, c->uv[1]);
      lo = bk_v3_min(lo, m.positions[c->position]);
      hi = bk_v3_max(hi, m.positions[c->position]);
    }
    double e[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    double du = umax - umin, dv = vmax - vmin;
    // One extent is zero (the face's own axis); the other two match du and dv.
    double spans = e[0] + e[1] + e[2];
    ENSURE_SMALL(du + dv, spans, 1e-6);
    ENSURE(fabs(du - e[0]) < 1e-6 || fabs(du - e[1]) < 1e-6 || fabs(du - e[2]) < 1e-6);
  }
  bk_mesh_free(&m);
}

static void test_wall(void) { check_box_shape(BK_SHAPE_WALL, 2.0, 1.2, 0.2); }

static void test_slab(void) { check_box_shape(BK_SHAPE_SLAB, 1.2, 0.15, 0.8); }

static void test_pillar(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_PILLAR, &m);
  check_counts(&m, 18, 50, 32);
  const double r = 0.25, h = 2.0;
  ENSURE_SMALL(check_common(BK_SHAPE_PILLAR, &m), 2.0 * sqrt(2.0) * r * r * h, 1e-12);
  check_convex_normals(&m);
  bk_aabb box = bk_mesh_bounds(&m);
  ENSURE(box.min.y == 0.0);
  ENSURE_SMALL(box.max.y, h, 1e-15);
  for (uint32_t i = 0; i < m.position_count; ++i) {
    bk_vec3 p = m.positions[i];
    double rho = sqrt(p.x * p.x + p.z * p.z);
    ENSURE(rho < 1e-15 || fabs(rho - r) < 1e-12);
  }
  // Side uvs run along the perimeter in metres: total length 8 edges.
  float umax = 0.0f;
  for (uint32_t i = 0; i < m.corner_count; ++i)
    umax = fmaxf(umax, m.corners[i].uv[0]);
  ENSURE_SMALL(umax, 8.0 * 2.0 * r * sin(PI / 8.0), 1e-6);
  bk_mesh_free(&m);
}

static void test_rebuild_is_deterministic(void) {
  for (int i = 0; i < BK_SHAPE_COUNT; ++i) {
    bk_mesh a = {0}, b = {0};
    bk_shape_build((bk_shape)i, &a);
    bk_shape_build((bk_shape)i, &b);
    ENSURE(bk_mesh_hash(&a) == bk_mesh_hash(&b));
    bk_mesh_free(&a);
    bk_mesh_free(&b);
  }
}

int main(void) {
  RUN(test_names);
  RUN(test_cube);
  RUN(test_torus);
  RUN(test_eggshell);
  RUN(test_wall);
  RUN(test_slab);
  RUN(test_pillar);
  RUN(test_rebuild_is_deterministic);
  return 0;
}
