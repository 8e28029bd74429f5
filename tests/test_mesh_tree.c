// Mesh trees: every node closed and consistently oriented, leaf counts,
// volume conservation (leaves vs source, children vs parent), contiguous leaf
// ranges, determinism, and bonds from true contacts.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"

static bk_mesh_tree build(bk_mesh* mesh, uint32_t pieces, uint64_t seed) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(mesh, &desc, &tree, &err), "%s", err.message);
  return tree;
}

static bk_mesh load_shape(const char* name) {
  bk_mesh mesh = {0};
  bk_shape shape = BK_SHAPE_CUBE;
  if (strcmp(name, "bunny") == 0) {
    bk_error err = {0};
    ENSURE_MSG(bk_obj_load(BK_ASSET_DIR "/meshes/bunny.obj", &mesh, &err), "%s", err.message);
  } else {
    ENSURE(bk_shape_from_name(name, &shape));
    bk_shape_build(shape, &mesh);
  }
  return mesh;
}

// Structure: parents and children agree, children contiguous, leaf ranges
// nest, leaves numbered in order.
static void check_structure(const bk_mesh_tree* tree) {
  ENSURE(tree->node_count >= 1 && tree->nodes[0].parent == BK_NULL_INDEX);
  ENSURE(tree->nodes[0].leaf_begin == 0 && tree->nodes[0].leaf_end == tree->leaf_count);
  uint32_t leaves_seen = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[i];
    ENSURE(node->leaf_begin < node->leaf_end);
    if (node->child_count == 0) {
      ENSURE(node->leaf_end == node->leaf_begin + 1);
      ENSURE(tree->leaf_nodes[node->leaf_begin] == i);
      leaves_seen++;
      continue;
    }
    ENSURE(node->child_count >= 2);
    uint32_t expect = node->leaf_begin;
    for (uint32_t c = 0; c < node->child_count; ++c) {
      const bk_mesh_tree_node* child = &tree->nodes[node->first_child + c];
      ENSURE(child->parent == i);
      ENSURE(child->depth == node->depth + 1);
      ENSURE(child->leaf_begin == expect); // children tile the parent's range in order
      expect = child->leaf_end;
    }
    ENSURE(expect == node->leaf_end);
  }
  ENSURE(leaves_seen == tree->leaf_count);
}

static void check_tree(const char* name, uint32_t pieces, bool exact_count) {
  bk_mesh mesh = load_shape(name);
  bk_mesh_tree tree = build(&mesh, pieces, 3000);
  check_structure(&tree);
  if (exact_count) ENSURE_MSG(tree.leaf_count == pieces, "%s: %u leaves", name, tree.leaf_count);
  ENSURE_MSG(tree.leaf_count >= pieces, "%s: %u leaves for %u pieces", name, tree.leaf_count, pieces);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(&tree);
  ENSURE_MSG(st.open_nodes == 0, "%s: %u nodes are not closed", name, st.open_nodes);
  ENSURE_REL(st.leaf_volume_sum, st.source_volume, 1e-9);
  ENSURE_MSG(st.max_child_rel_error <= 1e-9, "%s: child volume error %g", name, st.max_child_rel_error);
  ENSURE(st.min_leaf_volume > 0.0);
  ENSURE_REL(st.source_volume, bk_mesh_volume(&mesh), 1e-15);
  // Every node's stored moments match its mesh, and every leaf is one piece
  // with no faces pointing the wrong way (positive volume).
  for (uint32_t i = 0; i < tree.node_count; ++i) {
    ENSURE_REL(tree.nodes[i].moments.v, bk_mesh_volume(&tree.nodes[i].mesh), 1e-12);
    bk_error err = {0};
    ENSURE_MSG(bk_mesh_validate(&tree.nodes[i].mesh, &err), "%s node %u: %s", name, i, err.message);
  }
  ENSURE(tree.bond_count >= tree.leaf_count - 1); // a solid's fragments are connected
  fprintf(stderr, "    %s x%u: %u leaves, %u nodes, depth %u, %u bonds, leaf volume error %.2e\n", name,
          pieces, tree.leaf_count, tree.node_count, tree.max_depth, tree.bond_count,
          fabs(st.leaf_volume_sum - st.source_volume) / st.source_volume);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&mesh);
}

static void test_cube_256(void) { check_tree("cube", 256, true); }
static void test_torus_256(void) { check_tree("torus", 256, false); }
static void test_eggshell_256(void) { check_tree("eggshell", 256, false); }
static void test_bunny_256(void) { check_tree("bunny", 256, false); }
static void test_cube_4096(void) { check_tree("cube", 4096, true); }

static bool meshes_equal(const bk_mesh* a, const bk_mesh* b) {
  return a->position_count == b->position_count && a->corner_count == b->corner_count &&
         a->triangle_count == b->triangle_count &&
         memcmp(a->positions, b->positions, sizeof(bk_vec3) * a->position_count) == 0 &&
         memcmp(a->corners, b->corners, sizeof(bk_corner) * a->corner_count) == 0 &&
         memcmp(a->indices, b->indices, sizeof(uint32_t) * 3 * a->triangle_count) == 0;
}

static bool trees_equal(const bk_mesh_tree* a, const bk_mesh_tree* b) {
  if (a->node_count != b->node_count || a->leaf_count != b->leaf_count || a->bond_count != b->bond_count)
    return false;
  for (uint32_t i = 0; i < a->node_count; ++i)
    if (!meshes_equal(&a->nodes[i].mesh, &b->nodes[i].mesh)) return false;
  return memcmp(a->bonds, b->bonds, sizeof(bk_bond) * a->bond_count) == 0;
}

static void test_determinism(void) {
  bk_mesh mesh = load_shape("torus");
  bk_mesh_tree a = build(&mesh, 64, 11), b = build(&mesh, 64, 11), c = build(&mesh, 64, 12);
  ENSURE(trees_equal(&a, &b));
  ENSURE(!trees_equal(&a, &c));
  bk_mesh_tree_free(&a);
  bk_mesh_tree_free(&b);
  bk_mesh_tree_free(&c);
  bk_mesh_free(&mesh);
}

static void test_one_piece_is_the_source(void) {
  bk_mesh mesh = load_shape("cube");
  bk_mesh_tree tree = build(&mesh, 1, 3000);
  ENSURE(tree.node_count == 1 && tree.leaf_count == 1 && tree.bond_count == 0);
  ENSURE(meshes_equal(&tree.nodes[0].mesh, &mesh));
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&mesh);
}

// A cube cut once: exactly one bond whose area is the cut's cross-section.
static void test_single_cut_bond(void) {
  bk_mesh mesh = load_shape("cube");
  for (uint64_t seed = 1; seed <= 20; ++seed) {
    bk_fracture_def desc = bk_default_fracture_def();
    desc.pieces = 2;
    desc.seed = seed;
    bk_mesh_tree tree = {0};
    bk_error err = {0};
    ENSURE_MSG(bk_mesh_tree_build(&mesh, &desc, &tree, &err), "%s", err.message);
    ENSURE(tree.leaf_count == 2 && tree.bond_count == 1);
    // The cap of either child on the cut is the cross-section: its area.
    const bk_mesh* leaf = &bk_mesh_tree_leaf(&tree, 0)->mesh;
    double cap_area = 0.0;
    bk_vec3 cap_centroid = {0};
    for (uint32_t t = 0; t < leaf->triangle_count; ++t) {
      if (leaf->materials[t] != BK_MATERIAL_INTERIOR) continue;
      bk_vec3 p0 = leaf->positions[bk_mesh_tri_position(leaf, t, 0)];
      bk_vec3 p1 = leaf->positions[bk_mesh_tri_position(leaf, t, 1)];
      bk_vec3 p2 = leaf->positions[bk_mesh_tri_position(leaf, t, 2)];
      double area = 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(p1, p0), bk_v3_sub(p2, p0)));
      cap_area += area;
      cap_centroid = bk_v3_add(cap_centroid, bk_v3_scale(bk_v3_add(p0, bk_v3_add(p1, p2)), area / 3.0));
    }
    cap_centroid = bk_v3_scale(cap_centroid, 1.0 / cap_area);
    const bk_bond* bond = &tree.bonds[0];
    ENSURE(bond->leaf_a == 0 && bond->leaf_b == 1);
    ENSURE_REL(bond->area, cap_area, 1e-9);
    ENSURE_SMALL(bk_v3_length(bk_v3_sub(bond->centroid, cap_centroid)), 0.0, 1e-9);
    // The normal is the cut's, pointing from leaf a into leaf b.
    bk_vec3 ca = bk_moments_to_mass(bk_mesh_tree_leaf(&tree, 0)->moments).centroid;
    bk_vec3 cb = bk_moments_to_mass(bk_mesh_tree_leaf(&tree, 1)->moments).centroid;
    ENSURE(bk_v3_dot(bond->normal, bk_v3_sub(cb, ca)) > 0.0);
    ENSURE_SMALL(fabs(bk_v3_dot(bond->normal, tree.nodes[0].plane.normal)), 1.0, 1e-12);
    bk_mesh_tree_free(&tree);
  }
  bk_mesh_free(&mesh);
}

// Bonds only join leaves that touch: the two leaves' caps share the bond's
// centroid plane, and leaves far apart are never bonded (unlike bounding-box
// overlap, which bonds neighbours across corners).
static void test_bonds_are_true_contacts(void) {
  bk_mesh mesh = load_shape("cube");
  bk_mesh_tree tree = build(&mesh, 64, 5);
  double total = 0.0;
  for (uint32_t i = 0; i < tree.bond_count; ++i) {
    const bk_bond* bond = &tree.bonds[i];
    ENSURE(bond->leaf_a < bond->leaf_b && bond->leaf_b < tree.leaf_count);
    ENSURE(bond->area > 0.0);
    ENSURE_SMALL(bk_v3_length(bond->normal), 1.0, 1e-12);
    if (i) ENSURE(bond->leaf_a > tree.bonds[i - 1].leaf_a || bond->leaf_b > tree.bonds[i - 1].leaf_b);
    // The centroid lies on the boundary of both leaves: inside both boxes.
    for (int k = 0; k < 2; ++k) {
      bk_aabb box = bk_mesh_tree_leaf(&tree, k ? bond->leaf_b : bond->leaf_a)->bounds;
      ENSURE(bond->centroid.x >= box.min.x - 1e-9 && bond->centroid.x <= box.max.x + 1e-9);
      ENSURE(bond->centroid.y >= box.min.y - 1e-9 && bond->centroid.y <= box.max.y + 1e-9);
      ENSURE(bond->centroid.z >= box.min.z - 1e-9 && bond->centroid.z <= box.max.z + 1e-9);
    }
    total += bond->area;
  }
  // Every interior face of every leaf is matched by its neighbour's: the sum of
  // bond areas equals half the total interior (cap) area of the leaves.
  double interior = 0.0;
  for (uint32_t l = 0; l < tree.leaf_count; ++l) {
    const bk_mesh* leaf = &bk_mesh_tree_leaf(&tree, l)->mesh;
    for (uint32_t t = 0; t < leaf->triangle_count; ++t) {
      if (leaf->materials[t] != BK_MATERIAL_INTERIOR) continue;
      bk_vec3 p0 = leaf->positions[bk_mesh_tri_position(leaf, t, 0)];
      bk_vec3 p1 = leaf->positions[bk_mesh_tri_position(leaf, t, 1)];
      bk_vec3 p2 = leaf->positions[bk_mesh_tri_position(leaf, t, 2)];
      interior += 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(p1, p0), bk_v3_sub(p2, p0)));
    }
  }
  ENSURE_REL(total, 0.5 * interior, 1e-9);
  bk_mesh_tree_free(&tree);
  bk_mesh_free(&mesh);
}

static void test_refuses_open_mesh(void) {
  bk_mesh mesh = load_shape("cube");
  mesh.triangle_count -= 1; // drop one triangle: three open edges
  bk_fracture_def desc = bk_default_fracture_def();
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE(!bk_mesh_tree_build(&mesh, &desc, &tree, &err));
  ENSURE_MSG(strstr(err.message, "not watertight: 3 open edges") != NULL, "%s", err.message);
  ENSURE(tree.node_count == 0 && tree.nodes == NULL);
  // The repair closes the simple hole, after which the mesh fractures.
  ENSURE(bk_mesh_fill_holes(&mesh, &err) == 1);
  ENSURE(bk_mesh_is_closed(&mesh));
  ENSURE_REL(bk_mesh_volume(&mesh), 1.0, 1e-12);
  bk_mesh_free(&mesh);
}

static void test_rejects_bad_desc(void) {
  bk_mesh mesh = load_shape("cube");
  bk_fracture_def desc = bk_default_fracture_def();
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  desc.texture_scale = NAN;
  ENSURE(!bk_mesh_tree_build(&mesh, &desc, &tree, &err));
  ENSURE_MSG(strstr(err.message, "texture_scale") != NULL, "%s", err.message);
  desc = bk_default_fracture_def();
  desc.jitter = -1.0;
  ENSURE(!bk_mesh_tree_build(&mesh, &desc, &tree, &err));
  ENSURE_MSG(strstr(err.message, "jitter") != NULL, "%s", err.message);
  desc = bk_default_fracture_def();
  desc.pieces = 5000000;
  ENSURE(!bk_mesh_tree_build(&mesh, &desc, &tree, &err));
  ENSURE_MSG(strstr(err.message, "pieces") != NULL, "%s", err.message);
  bk_mesh_free(&mesh);
}

int main(void) {
  RUN(test_one_piece_is_the_source);
  RUN(test_single_cut_bond);
  RUN(test_bonds_are_true_contacts);
  RUN(test_determinism);
  RUN(test_refuses_open_mesh);
  RUN(test_rejects_bad_desc);
  RUN(test_cube_256);
  RUN(test_torus_256);
  RUN(test_eggshell_256);
  RUN(test_bunny_256);
  RUN(test_cube_4096);
  return 0;
}
