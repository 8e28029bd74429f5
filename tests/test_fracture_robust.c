// Fracture on hostile geometry: meshes far from the origin, tiny and huge
// meshes, slivers, shells that cannot be capped, and bond computation on
// trees with no caps or with caps that fold onto themselves. Every tree that
// comes back is watertight with its volume kept, or the fracture says why not.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"
#ifdef BK_BREAKABLES_EXE // the CLI's side runs where the demo is built (CI always builds it)
#define RUN_STDERR_PATH BK_TEST_TMP "/fracture_robust_stderr.txt"
#include "run_exe.h"
#endif

static void unit_cube(bk_mesh* m, bk_vec3 offset, double scale) {
  memset(m, 0, sizeof *m);
  bk_shape_build(BK_SHAPE_CUBE, m);
  bk_aabb box = bk_mesh_bounds(m);
  for (uint32_t i = 0; i < m->position_count; ++i)
    m->positions[i] = bk_v3_add(bk_v3_scale(bk_v3_sub(m->positions[i], box.min), scale), offset);
}

// Builds with the default parameters, the texture tile scaled with the mesh.
static bk_mesh_tree build_scaled(const bk_mesh* m, uint32_t pieces, double scale) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.texture_scale *= scale;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(m, &desc, &tree, &err), "%s", err.message);
  return tree;
}

static bk_mesh_tree build(const bk_mesh* m, uint32_t pieces) { return build_scaled(m, pieces, 1.0); }

// Every node closed, children adding up to their parent, leaves to the root.
static void ensure_sound(const bk_mesh_tree* tree) {
  bk_mesh_tree_stats st = bk_mesh_tree_measure(tree);
  ENSURE_MSG(st.open_nodes == 0, "%u open nodes", st.open_nodes);
  ENSURE_REL(st.leaf_volume_sum, st.source_volume, 1e-9);
  ENSURE(st.max_child_rel_error <= 1e-9);
  for (uint32_t b = 0; b < tree->bond_count; ++b) {
    const bk_bond* bond = &tree->bonds[b];
    ENSURE(bond->leaf_a < bond->leaf_b && bond->leaf_b < tree->leaf_count);
    ENSURE(bond->area > 0.0 && bk_v3_is_finite(bond->centroid));
  }
}

// A unit cube at x = 1e9 cuts exactly as the one at the origin: same pieces,
// same bonds (areas, and centroids shifted by the offset), and its mass
// properties (taken about the tree's origin) are as exact as at the origin.
static void test_far_from_origin(void) {
  bk_mesh near_mesh = {0}, far_mesh = {0};
  unit_cube(&near_mesh, bk_v3(0, 0, 0), 1.0);
  unit_cube(&far_mesh, bk_v3(1e9, 0, 0), 1.0);
  bk_mesh_tree near_tree = build(&near_mesh, 8), far_tree = build(&far_mesh, 8);
  ensure_sound(&far_tree);
  ENSURE(far_tree.leaf_count == 8);
  ENSURE(far_tree.bond_count == near_tree.bond_count && far_tree.bond_count > 0);
  for (uint32_t b = 0; b < far_tree.bond_count; ++b) {
    const bk_bond *f = &far_tree.bonds[b], *n = &near_tree.bonds[b];
    ENSURE(f->leaf_a == n->leaf_a && f->leaf_b == n->leaf_b);
    ENSURE_REL(f->area, n->area, 1e-6);
    ENSURE_SMALL(f->centroid.x - 1e9, n->centroid.x, 1e-6);
    ENSURE_SMALL(f->centroid.y, n->centroid.y, 1e-6);
  }
  bk_mass_properties whole = bk_mesh_tree_mass(&far_tree, far_tree.nodes[0].moments);
  ENSURE_SMALL(whole.centroid.x, 1e9 + 0.5, 1e-6);
  ENSURE_SMALL(whole.centroid.y, 0.5, 1e-12);
  ENSURE_REL(whole.volume, 1.0, 1e-12);
  // A unit cube's inertia about its centre is 1/6 on the diagonal, 0 off it.
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k)
      ENSURE_SMALL(whole.inertia[i][k], i == k ? 1.0 / 6.0 : 0.0, 1e-12);
  bk_moments leaves = {0};
  for (uint32_t l = 0; l < far_tree.leaf_count; ++l)
    leaves = bk_moments_add(leaves, bk_mesh_tree_leaf(&far_tree, l)->moments);
  bk_mass_properties sum = bk_mesh_tree_mass(&far_tree, leaves);
  ENSURE_SMALL(sum.inertia[0][0], 1.0 / 6.0, 1e-12);
  // Cap uvs stay small (relative to the object, whole tiles dropped), so
  // floats keep their precision on the cut faces.
  for (uint32_t l = 0; l < far_tree.leaf_count; ++l) {
    const bk_mesh* m = &bk_mesh_tree_leaf(&far_tree, l)->mesh;
    for (uint32_t c = 0; c < m->corner_count; ++c)
      ENSURE(fabsf(m->corners[c].uv[0]) < 100.0f && fabsf(m->corners[c].uv[1]) < 100.0f);
  }
  bk_mesh_tree_free(&near_tree);
  bk_mesh_tree_free(&far_tree);
  bk_mesh_free(&near_mesh);
  bk_mesh_free(&far_mesh);
}

// Scaling a mesh by a power of two scales its tree exactly; other scales
// within the accepted sizes cut as the unit mesh does (same triangle count,
// not the 8x that absolute tolerances gave). Sizes whose moments do not fit
// doubles are refused by size, not as "wound inward".
static void test_scale(void) {
  bk_mesh unit = {0};
  unit_cube(&unit, bk_v3(0, 0, 0), 1.0);
  bk_mesh_tree reference = build(&unit, 64);
  const double scales[] = {0x1p-40, 0x1p40, 1e-20, 3e25};
  for (size_t i = 0; i < sizeof scales / sizeof *scales; ++i) {
    bk_mesh m = {0};
    unit_cube(&m, bk_v3(0, 0, 0), scales[i]);
    bk_mesh_tree tree = build_scaled(&m, 64, scales[i]);
    ensure_sound(&tree);
    bk_mesh_tree_stats a = bk_mesh_tree_measure(&reference), b = bk_mesh_tree_measure(&tree);
    ENSURE_MSG(tree.leaf_count == reference.leaf_count && b.leaf_triangles <= a.leaf_triangles * 11 / 10,
               "scale %g: %u leaves, %u triangles (unit: %u, %u)", scales[i], tree.leaf_count,
               b.leaf_triangles, reference.leaf_count, a.leaf_triangles);
    if (i < 2) { // powers of two: the same tree, scaled
      ENSURE(b.leaf_triangles == a.leaf_triangles && tree.bond_count == reference.bond_count);
      for (uint32_t l = 0; l < tree.leaf_count; ++l)
        ENSURE(bk_mesh_tree_leaf(&tree, l)->moments.v ==
               bk_mesh_tree_leaf(&reference, l)->moments.v * scales[i] * scales[i] * scales[i]);
    }
    bk_mesh_tree_free(&tree);
    bk_mesh_free(&m);
  }
  const double refused[] = {1e-100, 1e-300, 1e100};
  for (size_t i = 0; i < sizeof refused / sizeof *refused; ++i) {
    bk_mesh m = {0};
    unit_cube(&m, bk_v3(0, 0, 0), refused[i]);
    bk_fracture_def desc = bk_default_fracture_def();
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    ENSURE(!bk_mesh_tree_build(&m, &desc, &tree, &err));
    ENSURE_MSG(strstr(err.message, "across") && !strstr(err.message, "inward"), "%s", err.message);
    ENSURE(tree.node_count == 0);
    bk_mesh_free(&m);
  }
  // A texture tile so small that cut-face uvs would lose all precision.
  bk_fracture_def desc = bk_default_fracture_def();
  desc.texture_scale = 1e-7;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE(!bk_mesh_tree_build(&unit, &desc, &tree, &err));
  ENSURE_MSG(strstr(err.message, "texture_scale"), "%s", err.message);
  bk_mesh_tree_free(&reference);
  bk_mesh_free(&unit);
}

static void add_tetrahedron(bk_mesh* m, const bk_vec3 p[4]) {
  uint32_t base = m->position_count;
  for (int i = 0; i < 4; ++i) {
    bk_mesh_add_position(m, p[i]);
    bk_corner c = {.position = base + (uint32_t)i};
    bk_mesh_add_corner(m, &c);
  }
  const uint32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  for (int f = 0; f < 4; ++f)
    bk_mesh_add_triangle(m, base + faces[f][0], base + faces[f][1], base + faces[f][2], BK_MATERIAL_OUTER, 0);
}

// Slivers: a tetrahedron of unit base and heights down to 1e-10 is cut into
// all its pieces, each sound (every cut is checked; one that would leave a
// piece open or change the volume is replaced by another plane).
static void test_slivers(void) {
  const double heights[] = {1e-7, 3e-8, 1e-9, 1e-10};
  for (size_t i = 0; i < sizeof heights / sizeof *heights; ++i) {
    bk_mesh m = {0};
    add_tetrahedron(&m, (const bk_vec3[4]){{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, heights[i]}});
    bk_mesh_tree tree = build(&m, 8);
    ensure_sound(&tree);
    ENSURE_MSG(tree.leaf_count == 8, "height %g: %u leaves", heights[i], tree.leaf_count);
    bk_mesh_tree_free(&tree);
    bk_mesh_free(&m);
  }
  // A surface closed against its own back (a triangle and its reverse, as
  // the hole filler makes of a lone triangle) encloses only rounding noise:
  // refused as flat, not cut into pieces of noise.
  bk_mesh flat = {0};
  const bk_vec3 p[3] = {{0, 1, 0}, {1, 0, 0}, {0.3, 0.3, 3e-3}};
  for (uint32_t i = 0; i < 3; ++i) {
    bk_mesh_add_position(&flat, p[i]);
    bk_corner c = {.position = i};
    bk_mesh_add_corner(&flat, &c);
  }
  bk_mesh_add_triangle(&flat, 0, 1, 2, BK_MATERIAL_OUTER, 0);
  bk_mesh_add_triangle(&flat, 2, 1, 0, BK_MATERIAL_OUTER, 0);
  bk_fracture_def desc = bk_default_fracture_def();
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  bool built = bk_mesh_tree_build(&flat, &desc, &tree, &err);
  ENSURE_MSG(!built || bk_mesh_tree_measure(&tree).source_volume > 0.0, "built a tree of nothing");
  ENSURE_MSG(!built && (strstr(err.message, "almost no volume") || strstr(err.message, "no volume")), "%s",
             err.message);
  bk_mesh_free(&flat);
}

// A cube nested in a cube: overlapping shells are fractured each on its own
// (test_shells.c has the details), all 64 pieces and a warning naming them.
// Two cubes touching along a face (separate vertices) overlap nothing, but
// no plane through both can be capped (their cross-sections share an edge),
// so they too are fractured each on its own: all 64 pieces, named as touching.
static void test_nested_shells(void) {
  bk_mesh outer = {0}, inner = {0};
  unit_cube(&outer, bk_v3(0, 0, 0), 1.0);
  unit_cube(&inner, bk_v3(0.25, 0.25, 0.25), 0.5);
  bk_mesh_append(&outer, &inner);
  bk_mesh_tree tree = build(&outer, 64);
  ensure_sound(&tree);
  ENSURE_MSG(tree.leaf_count == 64 && tree.shortfall.uncut == 0, "%u leaves", tree.leaf_count);
  char text[400];
  ENSURE(!bk_mesh_tree_shortfall_text(&tree, text, sizeof text) && text[0] == 0);
  ENSURE(bk_mesh_tree_overlap_text(&tree, text, sizeof text));
  ENSURE_MSG(strstr(text, "shells 1 and 2 overlap"), "%s", text);
  bk_mesh_tree_free(&tree);
  bk_mesh touching = {0}, right = {0};
  unit_cube(&touching, bk_v3(0, 0, 0), 1.0);
  unit_cube(&right, bk_v3(1, 0, 0), 1.0);
  bk_mesh_append(&touching, &right);
  tree = build(&touching, 64);
  ensure_sound(&tree);
  ENSURE_MSG(tree.leaf_count == 64 && tree.shortfall.uncut == 0, "%u leaves", tree.leaf_count);
  ENSURE(!bk_mesh_tree_shortfall_text(&tree, text, sizeof text));
  ENSURE(tree.overlap.pairs == 1 && tree.overlap.touching &&
         bk_mesh_tree_overlap_text(&tree, text, sizeof text));
  ENSURE_MSG(strstr(text, "shells 1 and 2 touch ("), "%s", text);
  bk_mesh_tree_free(&tree);
  // A tree with all its pieces has no shortfall text.
  tree = build(&inner, 8);
  ENSURE(!bk_mesh_tree_shortfall_text(&tree, text, sizeof text) && text[0] == 0);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&outer);
  bk_mesh_free(&inner);
  bk_mesh_free(&touching);
  bk_mesh_free(&right);
}

// Bonds of a tree whose leaves carry no caps: none (and no sorting of an
// empty list, which is undefined for a null array).
static void test_bonds_without_caps(void) {
  bk_mesh cube = {0};
  unit_cube(&cube, bk_v3(0, 0, 0), 1.0);
  bk_mesh_tree tree = build(&cube, 4);
  ENSURE(tree.bond_count > 0);
  for (uint32_t l = 0; l < tree.leaf_count; ++l) {
    bk_mesh* m = &tree.nodes[tree.leaf_nodes[l]].mesh;
    for (uint32_t t = 0; t < m->triangle_count; ++t)
      m->materials[t] = BK_MATERIAL_OUTER;
  }
  bk_mesh_tree_compute_bonds(&tree);
  ENSURE(tree.bond_count == 0 && tree.bonds == NULL);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&cube);
}

// A leaf whose caps on a cut are two triangles folded onto each other (as a
// crafted cache file can hold) covers no area: its outline is empty, so it
// bonds with nothing, and nothing reads an outline corner that is not there.
static void test_bonds_folded_caps(void) {
  bk_mesh cube = {0};
  unit_cube(&cube, bk_v3(0, 0, 0), 1.0);
  bk_mesh_tree tree = build(&cube, 2);
  ENSURE(tree.leaf_count == 2 && tree.bond_count == 1);
  bk_mesh* m = &tree.nodes[tree.leaf_nodes[0]].mesh;
  uint32_t first_cap = UINT32_MAX;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    if (m->materials[t] == BK_MATERIAL_INTERIOR) {
      if (first_cap == UINT32_MAX) first_cap = t;
      m->materials[t] = BK_MATERIAL_OUTER;
    }
  ENSURE(first_cap != UINT32_MAX);
  // Two zero-area triangles over the same three points on the cut, wound
  // opposite ways: both count as one side's caps and every edge cancels.
  uint32_t a = m->indices[3 * first_cap], b = m->indices[3 * first_cap + 1];
  bk_vec3 pa = m->positions[m->corners[a].position];
  bk_corner mid = m->corners[a];
  mid.position = bk_mesh_add_position(m, pa); // a second position at a's point: exactly zero area
  uint32_t c = bk_mesh_add_corner(m, &mid);
  uint32_t tag = m->tags[first_cap];
  bk_mesh_add_triangle(m, a, b, c, BK_MATERIAL_INTERIOR, tag);
  bk_mesh_add_triangle(m, a, c, b, BK_MATERIAL_INTERIOR, tag);
  bk_mesh_tree_compute_bonds(&tree);
  ENSURE_MSG(tree.bond_count == 0, "%u bonds", tree.bond_count);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&cube);
}

// The command line: overlapping shells are a warning on stderr and in --json
// (pieces_made, warnings), with exit 0; a far cube gives all 8 and none.
// (Fewer pieces than asked has no CLI case left: the nested cubes were it,
// and cubes touching along a face were the other; test_shells.c has those.)
#ifdef BK_BREAKABLES_EXE
static void write_obj(const char* path, const bk_mesh* m) {
  bk_error err = {0};
  ENSURE_MSG(bk_obj_save(path, m, 1, &err), "%s", err.message);
}

static void test_cli(void) {
  bk_mesh outer = {0}, inner = {0}, far_mesh = {0};
  unit_cube(&outer, bk_v3(0, 0, 0), 1.0);
  unit_cube(&inner, bk_v3(0.25, 0.25, 0.25), 0.5);
  bk_mesh_append(&outer, &inner);
  unit_cube(&far_mesh, bk_v3(1e9, 0, 0), 1.0);
  write_obj(BK_TEST_TMP "/robust_nested.obj", &outer);
  write_obj(BK_TEST_TMP "/robust_far.obj", &far_mesh);
  // Overlapping shells: all pieces, and a warning naming the shells.
  run_result* r = run("fracture --mesh '" BK_TEST_TMP "/robust_nested.obj' --pieces 64 --json");
  ENSURE_MSG(r->status == 0, "%s", r->err);
  ENSURE_MSG(strstr(r->err, "warning:") && strstr(r->err, "shells 1 and 2 overlap (volumes 1 and 0.125 m^3"),
             "%s", r->err);
  ENSURE_MSG(strstr(r->out, "\"pieces_requested\": 64") && strstr(r->out, "\"pieces_made\": 64"), "%s",
             r->out);
  ENSURE_MSG(strstr(r->out, "\"warnings\": [\"shells 1 and 2 overlap") &&
                 strstr(r->out, "each was fractured on its own"),
             "%s", r->out);
  r = run("fracture --mesh '" BK_TEST_TMP "/robust_far.obj' --pieces 8 --json");
  ENSURE_MSG(r->status == 0 && strstr(r->out, "\"pieces_made\": 8") && strstr(r->out, "\"warnings\": []") &&
                 !strstr(r->out, "\"bonds\": 0,") && r->err[0] == 0,
             "%s%s", r->out, r->err);
  bk_mesh_free(&outer);
  bk_mesh_free(&inner);
  bk_mesh_free(&far_mesh);
}
#endif

int main(void) {
  test_far_from_origin();
  test_scale();
  test_slivers();
  test_nested_shells();
  test_bonds_without_caps();
  test_bonds_folded_caps();
#ifdef BK_BREAKABLES_EXE
  test_cli();
#endif
  puts("test_fracture_robust: ok");
  return 0;
}
