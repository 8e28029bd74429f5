// Decimation for drawing far away: closed meshes stay closed, the surface
// stays within a few tolerances of the original both ways, flat solids keep
// their exact volume, material borders and attributes survive, open or
// non-manifold parts never move.
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"

// Closest point on triangle abc to p (Ericson, Real-Time Collision Detection, 5.1.5).
static bk_vec3 closest_on_triangle(bk_vec3 p, bk_vec3 a, bk_vec3 b, bk_vec3 c) {
  bk_vec3 ab = bk_v3_sub(b, a), ac = bk_v3_sub(c, a), ap = bk_v3_sub(p, a);
  double d1 = bk_v3_dot(ab, ap), d2 = bk_v3_dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return a;
  bk_vec3 bp = bk_v3_sub(p, b);
  double d3 = bk_v3_dot(ab, bp), d4 = bk_v3_dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return b;
  double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return bk_v3_add(a, bk_v3_scale(ab, d1 / (d1 - d3)));
  bk_vec3 cp = bk_v3_sub(p, c);
  double d5 = bk_v3_dot(ab, cp), d6 = bk_v3_dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return c;
  double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return bk_v3_add(a, bk_v3_scale(ac, d2 / (d2 - d6)));
  double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return bk_v3_add(b, bk_v3_scale(bk_v3_sub(c, b), (d4 - d3) / ((d4 - d3) + (d5 - d6))));
  double denom = 1.0 / (va + vb + vc);
  return bk_v3_add(a, bk_v3_add(bk_v3_scale(ab, vb * denom), bk_v3_scale(ac, vc * denom)));
}

static double distance_to_surface(bk_vec3 p, const bk_mesh* m) {
  double best = INFINITY;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 q = closest_on_triangle(p, m->positions[bk_mesh_tri_position(m, t, 0)],
                                    m->positions[bk_mesh_tri_position(m, t, 1)],
                                    m->positions[bk_mesh_tri_position(m, t, 2)]);
    best = fmin(best, bk_v3_length(bk_v3_sub(p, q)));
  }
  return best;
}

// Largest distance from the points of `a` (vertices and triangle centroids) to the surface of `b`.
static double one_sided_distance(const bk_mesh* a, const bk_mesh* b) {
  double worst = 0.0;
  for (uint32_t p = 0; p < a->position_count; ++p)
    worst = fmax(worst, distance_to_surface(a->positions[p], b));
  for (uint32_t t = 0; t < a->triangle_count; ++t) {
    bk_vec3 c = bk_v3_scale(bk_v3_add(a->positions[bk_mesh_tri_position(a, t, 0)],
                                      bk_v3_add(a->positions[bk_mesh_tri_position(a, t, 1)],
                                                a->positions[bk_mesh_tri_position(a, t, 2)])),
                            1.0 / 3.0);
    worst = fmax(worst, distance_to_surface(c, b));
  }
  return worst;
}

static double radius_of(const bk_mesh* m) {
  bk_aabb box = bk_mesh_bounds(m);
  return 0.5 * bk_v3_length(bk_v3_sub(box.max, box.min));
}

static uint32_t count_material(const bk_mesh* m, uint8_t material) {
  uint32_t n = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    n += m->materials[t] == material;
  return n;
}

// Every corner of `out` is a copy of a corner of `in` (attributes untouched).
static void ensure_corners_copied(const bk_mesh* in, const bk_mesh* out) {
  for (uint32_t c = 0; c < out->corner_count; ++c) {
    bool found = false;
    for (uint32_t k = 0; k < in->corner_count && !found; ++k)
      found = memcmp(out->corners[c].normal, in->corners[k].normal, sizeof(float) * 3) == 0 &&
              memcmp(out->corners[c].uv, in->corners[k].uv, sizeof(float) * 2) == 0;
    ENSURE_MSG(found, "corner %u has attributes no input corner has", c);
  }
}

// Decimates `m` at `fraction` of its radius and checks what every result must satisfy.
static void check_decimation(const char* name, const bk_mesh* m, double fraction, bk_mesh* out) {
  double tolerance = fraction * radius_of(m);
  uint32_t n = bk_mesh_decimate(m, tolerance, out);
  ENSURE(n == out->triangle_count);
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_validate(out, &err), "%s: %s", name, err.message);
  bk_closure closure = bk_mesh_check_closure(out);
  ENSURE_MSG(bk_mesh_is_closed(out), "%s: open %u overused %u degenerate %u", name, closure.open_edges,
             closure.overused_edges, closure.degenerate_edges);
  ENSURE_MSG(n <= m->triangle_count && n >= 4, "%s: %u triangles from %u", name, n, m->triangle_count);
  // Both ways: nothing sticks out, and nothing (a thin part, a rim) was eaten away.
  double out_to_in = one_sided_distance(out, m), in_to_out = one_sided_distance(m, out);
  double bound = 3.0 * tolerance + 1e-9 * radius_of(m); // rounding, for a zero tolerance
  ENSURE_MSG(out_to_in <= bound && in_to_out <= bound, "%s: surfaces %.4g and %.4g apart, tolerance %.4g",
             name, out_to_in, in_to_out, tolerance);
  ENSURE_MSG(bk_mesh_volume(out) > 0.0, "%s: turned inside out", name);
  for (uint8_t material = 0; material <= BK_MATERIAL_INTERIOR; ++material)
    ENSURE_MSG((count_material(m, material) > 0) == (count_material(out, material) > 0),
               "%s: material %u lost or made up", name, material);
  ensure_corners_copied(m, out);
}

static void test_curved_shapes_lose_triangles(void) {
  const bk_shape shapes[] = {BK_SHAPE_TORUS, BK_SHAPE_EGGSHELL};
  for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; ++i) {
    bk_mesh m = {0}, out = {0};
    bk_shape_build(shapes[i], &m);
    check_decimation(bk_shape_name(shapes[i]), &m, 0.02, &out);
    ENSURE_MSG(out.triangle_count * 2 < m.triangle_count, "%s: %u triangles from %u",
               bk_shape_name(shapes[i]), out.triangle_count, m.triangle_count);
    ENSURE_REL(bk_mesh_volume(&out), bk_mesh_volume(&m), 0.1);
    // However large the tolerance, the surface stays closed and the right way out.
    bk_mesh_free(&out);
    check_decimation(bk_shape_name(shapes[i]), &m, 10.0, &out);
    // A zero tolerance takes only collapses that move nothing: a curved surface keeps every triangle.
    bk_mesh_free(&out);
    ENSURE(bk_mesh_decimate(&m, 0.0, &out) == m.triangle_count);
    bk_mesh_free(&out);
    bk_mesh_free(&m);
  }
}

static void test_flat_solids_keep_their_shape(void) {
  // A cube has nothing to spare within a tenth of its size: every corner is a real one.
  bk_mesh cube = {0}, out = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  check_decimation("cube", &cube, 0.1, &out);
  ENSURE(out.triangle_count == cube.triangle_count);
  ENSURE_SMALL(bk_mesh_volume(&out), bk_mesh_volume(&cube), 1e-12);
  bk_mesh_free(&out);
  // Extra vertices on the faces of a flat solid go for free, with not a bit of volume.
  bk_mesh pillar = {0};
  bk_shape_build(BK_SHAPE_PILLAR, &pillar);
  check_decimation("pillar", &pillar, 0.0, &out);
  ENSURE_SMALL(bk_mesh_volume(&out), bk_mesh_volume(&pillar), 1e-9 * bk_mesh_volume(&pillar));
  bk_mesh_free(&out);
  bk_mesh_free(&pillar);
  bk_mesh_free(&cube);
}

static void test_fragments(void) {
  // Shards of curved and flat shapes: outer surface and cut faces both stay.
  const bk_shape shapes[] = {BK_SHAPE_EGGSHELL, BK_SHAPE_TORUS, BK_SHAPE_WALL};
  for (size_t i = 0; i < sizeof shapes / sizeof shapes[0]; ++i) {
    bk_mesh source = {0};
    bk_shape_build(shapes[i], &source);
    bk_fracture_def desc = bk_default_fracture_def();
    desc.pieces = 48;
    bk_mesh_tree tree = {0};
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_tree_build(&source, &desc, &tree, &err), "%s", err.message);
    uint64_t before = 0, after = 0;
    for (uint32_t n = 1; n < tree.node_count; ++n) {
      bk_mesh out = {0};
      char name[64];
      snprintf(name, sizeof name, "%s node %u", bk_shape_name(shapes[i]), n);
      check_decimation(name, &tree.nodes[n].mesh, 0.08, &out);
      before += tree.nodes[n].mesh.triangle_count;
      after += out.triangle_count;
      bk_mesh_free(&out);
    }
    // What SIMPLE draws in the renderer: curved shards lose more than half.
    if (shapes[i] != BK_SHAPE_WALL)
      ENSURE_MSG(2 * after < before, "%s: %llu triangles from %llu", bk_shape_name(shapes[i]),
                 (unsigned long long)after, (unsigned long long)before);
    bk_mesh_tree_free(&tree);
    bk_mesh_free(&source);
  }
}

static void test_open_parts_stay_put(void) {
  // The torus with one triangle gone: the hole's rim never moves.
  bk_mesh m = {0}, out = {0};
  bk_shape_build(BK_SHAPE_TORUS, &m);
  uint32_t hole[3] = {bk_mesh_tri_position(&m, 0, 0), bk_mesh_tri_position(&m, 0, 1),
                      bk_mesh_tri_position(&m, 0, 2)};
  bk_vec3 rim[3] = {m.positions[hole[0]], m.positions[hole[1]], m.positions[hole[2]]};
  memmove(&m.indices[0], &m.indices[3], sizeof(uint32_t) * 3 * (m.triangle_count - 1));
  memmove(&m.materials[0], &m.materials[1], m.triangle_count - 1);
  memmove(&m.tags[0], &m.tags[1], sizeof(uint32_t) * (m.triangle_count - 1));
  m.triangle_count--;
  uint32_t n = bk_mesh_decimate(&m, 0.02 * radius_of(&m), &out);
  ENSURE(n * 2 < m.triangle_count);
  bk_closure closure = bk_mesh_check_closure(&out);
  ENSURE_MSG(closure.open_edges == 3 && closure.overused_edges == 0 && closure.degenerate_edges == 0,
             "open %u overused %u degenerate %u", closure.open_edges, closure.overused_edges,
             closure.degenerate_edges);
  for (int k = 0; k < 3; ++k) {
    bool kept = false;
    for (uint32_t p = 0; p < out.position_count && !kept; ++p)
      kept = memcmp(&out.positions[p], &rim[k], sizeof(bk_vec3)) == 0;
    ENSURE_MSG(kept, "rim position %d moved", k);
  }
  bk_mesh_free(&out);
  // Nothing to work with: an empty mesh gives an empty one.
  bk_mesh empty = {0};
  ENSURE(bk_mesh_decimate(&empty, 1.0, &out) == 0 && out.triangle_count == 0);
  bk_mesh_free(&m);
}

int main(void) {
  test_curved_shapes_lose_triangles();
  test_flat_solids_keep_their_shape();
  test_fragments();
  test_open_parts_stay_put();
  puts("test_decimate: ok");
  return 0;
}
