// Refinement of a tree (bk_mesh_fracture_leaf + bk_mesh_tree_splice): the
// grown tree is as exact as a built one. Every leaf closed, the pieces'
// volumes adding up to the refined leaf's, the tree valid, each divided
// bond's parts adding up to its area, and every bond checked against a
// brute-force measure of every pair of leaves' contact.
#include <stdlib.h>
#include <string.h>

#include <breakables/authoring.h>

#include "ensure.h"
#include "tree_bonds.h"
#include "tree_bytes.h"

static double noise = 0.0; // the source trees' cut faces' noise amplitude

static bk_mesh_tree build(bk_shape shape, bk_fracture_pattern pattern, uint32_t pieces) {
  bk_mesh mesh = {0};
  bk_shape_build(shape, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = pattern;
  def.pieces = pieces;
  def.noise_amplitude = noise;
  def.aspect_bias = 1.5;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

// Refines leaf `leaf` around its centroid's corner (radial, or the given
// pattern) and checks what the splice says it did.
static bk_splice_info refine(bk_mesh_tree* tree, uint32_t leaf, bk_fracture_pattern pattern,
                             uint32_t pieces) {
  const bk_mesh_tree_node* n = bk_mesh_tree_leaf(tree, leaf);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = pattern;
  def.pieces = pieces;
  def.seed = 77 + leaf;
  def.impact = n->bounds.max; // a corner: dense pieces there
  def.threads = 1;
  double leaf_volume = n->moments.v;
  uint32_t old_leaves = tree->leaf_count, old_nodes = tree->node_count, old_bonds = tree->bond_count;
  // The leaf's bonds and their areas before.
  double* area_before = calloc(old_bonds + 1u, sizeof(double));
  uint32_t* other_before = calloc(old_bonds + 1u, sizeof(uint32_t));
  for (uint32_t j = 0; j < old_bonds; ++j) {
    const bk_bond* b = &tree->bonds[j];
    area_before[j] = b->leaf_a == leaf || b->leaf_b == leaf ? b->area : 0.0;
    other_before[j] = b->leaf_a == leaf ? b->leaf_b : b->leaf_a;
  }
  bk_mesh_tree pieces_tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_fracture_leaf(&n->mesh, tree->nodes[0].bounds, &def, &pieces_tree, &err), "%s",
             err.message);
  bk_splice_info info = {0};
  ENSURE_MSG(bk_mesh_tree_splice(tree, leaf, &pieces_tree, &info, &err), "%s", err.message);
  ENSURE(info.leaf == leaf && info.leaf_count >= 2);
  ENSURE(tree->leaf_count == old_leaves + info.leaf_count - 1);
  ENSURE(info.first_node == old_nodes && tree->node_count == old_nodes + info.node_count);
  ENSURE(tree->nodes[info.node].child_count > 0);
  // The pieces add up to the leaf.
  double sum = 0.0;
  for (uint32_t p = 0; p < info.leaf_count; ++p)
    sum += bk_mesh_tree_leaf(tree, leaf + p)->moments.v;
  ENSURE_REL(sum, leaf_volume, 1e-9);
  // Each divided bond's parts add up to its area: its first part at its
  // index, the others appended (a piece with the same neighbour).
  uint32_t grow = info.leaf_count - 1, divided = 0;
  for (uint32_t j = 0; j < old_bonds; ++j) {
    if (area_before[j] == 0.0) continue;
    divided++;
    uint32_t other = other_before[j] > leaf ? other_before[j] + grow : other_before[j];
    double parts = tree->bonds[j].area;
    ENSURE(tree->bonds[j].leaf_a == other || tree->bonds[j].leaf_b == other);
    for (uint32_t k = info.first_bond; k < info.first_bond + info.bond_count; ++k) {
      const bk_bond* b = &tree->bonds[k];
      bool a_piece = b->leaf_a >= leaf && b->leaf_a < leaf + info.leaf_count;
      bool b_piece = b->leaf_b >= leaf && b->leaf_b < leaf + info.leaf_count;
      if ((a_piece && b->leaf_b == other) || (b_piece && b->leaf_a == other)) parts += b->area;
    }
    ENSURE_REL(parts, area_before[j], 1e-9);
  }
  ENSURE(divided == info.bonds_divided);
  free(area_before);
  free(other_before);
  return info;
}

static void check_tree(const bk_mesh_tree* tree) {
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_validate(tree, &err), "%s", err.message);
  bk_mesh_tree_stats stats = bk_mesh_tree_measure(tree);
  ENSURE(stats.open_nodes == 0);
  ENSURE_REL(stats.leaf_volume_sum, stats.source_volume, 1e-9);
}

static void test_refine(bk_shape shape, bk_fracture_pattern source_pattern,
                        bk_fracture_pattern refine_pattern) {
  bk_mesh_tree tree = build(shape, source_pattern, 12);
  check_bonds_brute_force(&tree, 1e-9); // the measure agrees with the build's bonds
  uint32_t leaves = tree.leaf_count;
  bk_splice_info first = refine(&tree, 3, refine_pattern, 12);
  check_tree(&tree);
  // Refine a piece of the refined leaf, and a leaf after it (renumbered).
  refine(&tree, first.leaf + 1, refine_pattern, 6);
  refine(&tree, tree.leaf_count - 1, refine_pattern, 8);
  check_tree(&tree);
  check_bonds_brute_force(&tree, 1e-9);
  ENSURE(tree.leaf_count > leaves + 12);
  // Same refinements, same bytes.
  bk_mesh_tree again = build(shape, source_pattern, 12);
  bk_splice_info again_first = refine(&again, 3, refine_pattern, 12);
  refine(&again, again_first.leaf + 1, refine_pattern, 6);
  refine(&again, again.leaf_count - 1, refine_pattern, 8);
  ENSURE(trees_same_bytes(&tree, &again));
  bk_mesh_tree_free(&again);
  bk_mesh_tree_free(&tree);
}

// Contacts measured ahead (as a refinement worker does) splice the same
// bytes as contacts measured at the splice; a neighbour changed since (here:
// refined first) is measured again at the splice.
static void test_measured_ahead(void) {
  bk_mesh_tree here = build(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 12);
  bk_mesh_tree ahead = build(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 12);
  const uint32_t leaf = 5;
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = BK_PATTERN_RADIAL;
  def.pieces = 16;
  def.impact = bk_mesh_tree_leaf(&here, leaf)->bounds.min;
  bk_error err = {0};
  // The neighbours, as a worker would capture them before another
  // refinement changes one of them.
  bk_piece_neighbour neighbours[64];
  uint32_t count = 0, changed = UINT32_MAX;
  for (uint32_t j = 0; j < ahead.bond_count && count < 64; ++j) {
    const bk_bond* b = &ahead.bonds[j];
    if (b->leaf_a != leaf && b->leaf_b != leaf) continue;
    uint32_t other = b->leaf_a == leaf ? b->leaf_b : b->leaf_a;
    if (other > leaf && changed == UINT32_MAX) changed = other; // keeps `leaf`'s number when refined
    neighbours[count++] =
        (bk_piece_neighbour){ahead.leaf_nodes[other], bk_mesh_tree_leaf(&ahead, other)->mesh, b->area};
  }
  ENSURE(count >= 2 && changed != UINT32_MAX);
  bk_mesh_tree pieces_here = {0}, pieces_ahead = {0};
  ENSURE(bk_mesh_fracture_leaf(&bk_mesh_tree_leaf(&here, leaf)->mesh, here.nodes[0].bounds, &def,
                               &pieces_here, &err));
  ENSURE(bk_mesh_fracture_leaf(&bk_mesh_tree_leaf(&ahead, leaf)->mesh, ahead.nodes[0].bounds, &def,
                               &pieces_ahead, &err));
  bk_piece_contacts contacts = {0};
  bk_mesh_measure_piece_contacts(&bk_mesh_tree_leaf(&ahead, leaf)->mesh, ahead.nodes[0].bounds, &pieces_ahead,
                                 neighbours, count, &contacts);
  ENSURE(contacts.neighbour_count == count && contacts.piece_count == pieces_ahead.leaf_count);
  // One neighbour refined meanwhile, in both trees alike.
  refine(&here, changed, BK_PATTERN_VORONOI, 6);
  refine(&ahead, changed, BK_PATTERN_VORONOI, 6);
  ENSURE_MSG(bk_mesh_tree_splice(&here, leaf, &pieces_here, NULL, &err), "%s", err.message);
  ENSURE_MSG(bk_mesh_tree_splice_measured(&ahead, leaf, &pieces_ahead, &contacts, NULL, &err), "%s",
             err.message);
  ENSURE(trees_same_bytes(&here, &ahead));
  check_tree(&ahead);
  check_bonds_brute_force(&ahead, 1e-9);
  bk_piece_contacts_free(&contacts);
  bk_mesh_tree_free(&here);
  bk_mesh_tree_free(&ahead);
}

// A splice that does not fit its leaf leaves everything as it was.
static void test_refused(void) {
  bk_mesh_tree tree = build(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 8);
  bk_mesh_tree before = build(BK_SHAPE_WALL, BK_PATTERN_VORONOI, 8);
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = BK_PATTERN_VORONOI;
  def.pieces = 4;
  bk_mesh_tree pieces = {0};
  bk_error err = {0};
  // Pieces of leaf 2 spliced in for leaf 5: their volume is not its.
  ENSURE(
      bk_mesh_fracture_leaf(&bk_mesh_tree_leaf(&tree, 2)->mesh, tree.nodes[0].bounds, &def, &pieces, &err));
  ENSURE(!bk_mesh_tree_splice(&tree, 5, &pieces, NULL, &err));
  ENSURE_MSG(strstr(err.message, "refine: the pieces of leaf 5 have volume"), "%s", err.message);
  ENSURE(!bk_mesh_tree_splice(&tree, 99, &pieces, NULL, &err));
  ENSURE_MSG(strstr(err.message, "leaf 99 is not a leaf"), "%s", err.message);
  ENSURE(trees_same_bytes(&tree, &before));
  bk_mesh_tree_free(&pieces);
  bk_mesh_tree_free(&before);
  bk_mesh_tree_free(&tree);
}

int main(void) {
  test_refine(BK_SHAPE_WALL, BK_PATTERN_VORONOI, BK_PATTERN_RADIAL);
  test_refine(BK_SHAPE_WALL, BK_PATTERN_PLANES, BK_PATTERN_VORONOI);
  test_refine(BK_SHAPE_TORUS, BK_PATTERN_PLANES, BK_PATTERN_PLANES);
  noise = 0.02; // curved cut faces: each bond is many small tilted contacts
  test_refine(BK_SHAPE_TORUS, BK_PATTERN_VORONOI, BK_PATTERN_RADIAL);
  noise = 0.0;
  test_measured_ahead();
  test_refused();
  printf("refine tree ok\n");
  return 0;
}
