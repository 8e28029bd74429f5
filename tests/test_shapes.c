// Procedural shapes: closure, counts, exact volumes and sane per-corner
// attributes; the structures (tower, bridge, balcony) also stand on the
// ground only where they should and fracture into closed pieces.
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
  check_counts(&m, 48 * 24, 49 * 25, 2 * 48 * 24);
  double volume = check_common(BK_SHAPE_TORUS, &m);
  const double big_r = 1.0, small_r = 0.35;
  const int n = 48, k = 24;
  // Inscribed 24-gon tube swept along a 48-gon ring: each factor is the
  // polygon/circle area ratio n sin(2 pi / n) / (2 pi), and the side quads are
  // planar, so the polyhedral volume has this closed form exactly.
  double ring = n * sin(2.0 * PI / n) / (2.0 * PI), tube = k * sin(2.0 * PI / k) / (2.0 * PI);
  double smooth = 2.0 * PI * PI * big_r * small_r * small_r;
  ENSURE_REL(volume, smooth * ring * tube, 1e-12);
  ENSURE_REL(volume, smooth, 0.015);
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

// ---------------------------------------------------------------- structures

/// uvs in metres and unmirrored, as the boxes have them: each triangle's uv
/// image is congruent to the triangle (same edge lengths) with the same
/// turning sense seen from outside; v is the height on vertical faces and u
/// is x on horizontal ones.
static void check_metre_uvs(const char* name, const bk_mesh* m) {
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    const bk_corner* c[3] = {&m->corners[m->indices[3 * t]], &m->corners[m->indices[3 * t + 1]],
                             &m->corners[m->indices[3 * t + 2]]};
    for (int k = 0; k < 3; ++k) {
      const bk_corner *a = c[k], *b = c[(k + 1) % 3];
      double world = bk_v3_length(bk_v3_sub(m->positions[b->position], m->positions[a->position]));
      double flat = hypot(b->uv[0] - a->uv[0], b->uv[1] - a->uv[1]);
      ENSURE_MSG(fabs(world - flat) < 1e-5, "%s: triangle %u edge %d is %g m but %g in uv", name, t, k, world,
                 flat);
    }
    double turn = (c[1]->uv[0] - c[0]->uv[0]) * (c[2]->uv[1] - c[0]->uv[1]) -
                  (c[1]->uv[1] - c[0]->uv[1]) * (c[2]->uv[0] - c[0]->uv[0]);
    ENSURE_MSG(turn > 0.0, "%s: triangle %u has a mirrored texture", name, t);
    for (int k = 0; k < 3; ++k) {
      bk_vec3 p = m->positions[c[k]->position], n = corner_normal(c[k]);
      if (fabs(n.y) < 1e-6) ENSURE_SMALL(c[k]->uv[1], p.y, 1e-6);
      if (fabs(n.y) > 1.0 - 1e-6) ENSURE_SMALL(c[k]->uv[0], p.x, 1e-6);
    }
  }
}

/// Area of the downward faces on the ground (y = 0): where an anchored
/// object is held. `inside` says which ground points may be held.
static double ground_area(const char* name, const bk_mesh* m, bool (*inside)(bk_vec3 p)) {
  for (uint32_t i = 0; i < m->position_count; ++i)
    if (m->positions[i].y == 0.0)
      ENSURE_MSG(inside(m->positions[i]), "%s: (%g, %g, %g) touches the ground", name, m->positions[i].x,
                 m->positions[i].y, m->positions[i].z);
  double area = 0.0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
    bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
    bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
    if (a.y == 0.0 && b.y == 0.0 && c.y == 0.0)
      area += 0.5 * -bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a)).y; // facing down: positive
  }
  return area;
}

/// Fractures the shape into 64 pieces by `pattern`: every node valid and
/// closed, children's and leaves' volumes adding up to their parent's and
/// the source's, the fragments bonded into one piece.
static void check_fractures(bk_shape shape, bk_fracture_pattern pattern) {
  const char* name = bk_shape_name(shape);
  bk_mesh m = {0};
  bk_shape_build(shape, &m);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = 64;
  def.pattern = pattern;
  bk_mesh_tree tree = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(&m, &def, &tree, &err), "%s %s: %s", name, bk_fracture_pattern_name(pattern),
             err.message);
  // A planes cut through a concave piece may leave more parts than asked.
  ENSURE_MSG(tree.leaf_count >= 64, "%s %s: %u leaves", name, bk_fracture_pattern_name(pattern),
             tree.leaf_count);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
  ENSURE_MSG(st.open_nodes == 0, "%s %s: %u open nodes", name, bk_fracture_pattern_name(pattern),
             st.open_nodes);
  ENSURE_REL(st.source_volume, bk_mesh_volume(&m), 1e-15);
  ENSURE_REL(st.leaf_volume_sum, st.source_volume, 1e-9);
  ENSURE(st.max_child_rel_error <= 1e-9 && st.min_leaf_volume > 0.0);
  for (uint32_t i = 0; i < tree.node_count; ++i) {
    ENSURE_MSG(bk_mesh_validate(&tree.nodes[i].mesh, &err), "%s node %u: %s", name, i, err.message);
    ENSURE_MSG(bk_mesh_is_closed(&tree.nodes[i].mesh), "%s node %u is open", name, i);
  }
  ENSURE(tree.bond_count >= tree.leaf_count - 1);
  fprintf(stderr, "    %s %s: %u leaves, %u nodes, %u bonds\n", name, bk_fracture_pattern_name(pattern),
          tree.leaf_count, tree.node_count, tree.bond_count);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&m);
}

static void check_bounds(const bk_mesh* m, bk_vec3 lo, bk_vec3 hi) {
  bk_aabb box = bk_mesh_bounds(m);
  ENSURE(box.min.y == 0.0);
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(box.min, lo)), 0.0, 1e-15);
  ENSURE_SMALL(bk_v3_length(bk_v3_sub(box.max, hi)), 0.0, 1e-15);
}

static bool tower_footprint(bk_vec3 p) { return fabs(p.x) <= 0.4 && fabs(p.z) <= 0.4; }

static void test_tower(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_TOWER, &m);
  check_counts(&m, 8, 24, 12);
  ENSURE_SMALL(check_common(BK_SHAPE_TOWER, &m), 0.8 * 4.0 * 0.8, 1e-12);
  check_convex_normals(&m);
  check_bounds(&m, bk_v3(-0.4, 0.0, -0.4), bk_v3(0.4, 4.0, 0.4));
  check_metre_uvs("tower", &m);
  ENSURE_SMALL(ground_area("tower", &m, tower_footprint), 0.8 * 0.8, 1e-12);
  bk_mesh_free(&m);
  check_fractures(BK_SHAPE_TOWER, BK_PATTERN_PLANES);
  check_fractures(BK_SHAPE_TOWER, BK_PATTERN_VORONOI);
}

/// Only the legs (0.5 m thick, 0.2 m in from the deck's ends) stand on the ground.
static bool bridge_legs(bk_vec3 p) { return fabs(p.x) >= 1.8 && fabs(p.x) <= 2.3 && fabs(p.z) <= 0.6; }

static void test_bridge(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_BRIDGE, &m);
  // A 12-corner Pi profile: 24 positions, a quad per edge and two caps of 10 ears.
  check_counts(&m, 24, 72, 44);
  const double deck = 5.0 * 0.3, legs = 2.0 * 0.5 * 1.5, width = 1.2;
  ENSURE_SMALL(check_common(BK_SHAPE_BRIDGE, &m), (deck + legs) * width, 1e-12);
  check_bounds(&m, bk_v3(-2.5, 0.0, -0.6), bk_v3(2.5, 1.8, 0.6));
  check_metre_uvs("bridge", &m);
  ENSURE_SMALL(ground_area("bridge", &m, bridge_legs), 2.0 * 0.5 * width, 1e-12);
  // The span is open underneath: nothing between the legs below the deck's underside at 1.5 m.
  for (uint32_t i = 0; i < m.position_count; ++i)
    if (fabs(m.positions[i].x) < 1.8) ENSURE(m.positions[i].y >= 1.5);
  bk_mesh_free(&m);
  check_fractures(BK_SHAPE_BRIDGE, BK_PATTERN_PLANES);
  check_fractures(BK_SHAPE_BRIDGE, BK_PATTERN_VORONOI);
}

/// Only the wall (0.3 m thick, centred on z = 0) stands on the ground; the slab hangs from it.
static bool balcony_wall(bk_vec3 p) { return fabs(p.z) <= 0.15 && fabs(p.x) <= 1.2; }

static void test_balcony(void) {
  bk_mesh m = {0};
  bk_shape_build(BK_SHAPE_BALCONY, &m);
  // An 8-corner L profile: 16 positions, a quad per edge and two caps of 6 ears.
  check_counts(&m, 16, 48, 28);
  const double wall = 0.3 * 3.0, slab = 1.2 * 0.2, width = 2.4;
  ENSURE_SMALL(check_common(BK_SHAPE_BALCONY, &m), (wall + slab) * width, 1e-12);
  check_bounds(&m, bk_v3(-1.2, 0.0, -0.15), bk_v3(1.2, 3.0, 1.35));
  check_metre_uvs("balcony", &m);
  ENSURE_SMALL(ground_area("balcony", &m, balcony_wall), 0.3 * width, 1e-12);
  // The slab sticks out of the wall's front between 1.8 and 2 m up.
  for (uint32_t i = 0; i < m.position_count; ++i)
    if (m.positions[i].z > 0.15) ENSURE(m.positions[i].y == 1.8 || m.positions[i].y == 2.0);
  bk_mesh_free(&m);
  check_fractures(BK_SHAPE_BALCONY, BK_PATTERN_PLANES);
  check_fractures(BK_SHAPE_BALCONY, BK_PATTERN_VORONOI);
}

/// The extrusion itself: a polygon with a corner in the middle of an edge
/// still closes (the corner is never left on an ear's edge), and what it
/// cannot extrude it refuses without touching the mesh.
static void test_extrude(void) {
  // A square with a corner half-way along its top edge; one unit deep.
  static const double notched[][2] = {{0, 0}, {1, 0}, {1, 1}, {0.5, 1}, {0, 1}};
  bk_extrusion def = {.profile = notched,
                      .corner_count = 5,
                      .x_axis = bk_v3(1, 0, 0),
                      .y_axis = bk_v3(0, 1, 0),
                      .depth_from = 0.0,
                      .depth_to = 1.0};
  bk_mesh m = {0};
  ENSURE(bk_shape_extrude(&m, &def));
  bk_mesh_compute_tangents(&m);
  check_counts(&m, 10, 30, 16);
  ENSURE(bk_mesh_is_closed(&m));
  ENSURE_SMALL(bk_mesh_volume(&m), 1.0, 1e-15);
  check_metre_uvs("notched square", &m);

  static const double clockwise[][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
  bk_extrusion bad = def;
  bad.profile = clockwise;
  bad.corner_count = 4;
  ENSURE(!bk_shape_extrude(&m, &bad));
  bad = def;
  bad.corner_count = 2;
  ENSURE(!bk_shape_extrude(&m, &bad));
  bad = def;
  bad.depth_to = bad.depth_from;
  ENSURE(!bk_shape_extrude(&m, &bad));
  check_counts(&m, 10, 30, 16);
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
  RUN(test_tower);
  RUN(test_bridge);
  RUN(test_balcony);
  RUN(test_extrude);
  RUN(test_rebuild_is_deterministic);
  return 0;
}
