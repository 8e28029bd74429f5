// Writes the binary fuzz inputs that the project itself makes: small valid
// .mtree files (seeds for fuzz_mtree and fuzz_bonds), damaged copies of one
// (seeds for the loader's header checks), and crafted, checksum-valid trees
// that reproduce known bond defects (regressions for fuzz_bonds). Run it after
// a change of the .mtree format:
//
//   cmake --build build --target fuzz_make_corpus && build/fuzz_make_corpus tests/fuzz
//
// The text inputs (OBJ files) are written by hand and not touched.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

static const char* root_dir;

static void die(const char* what, const char* message) {
  fprintf(stderr, "fuzz_make_corpus: %s: %s\n", what, message);
  exit(1);
}

static void path_of(char* out, size_t size, const char* relative) {
  snprintf(out, size, "%s/%s", root_dir, relative);
}

static void save_tree(const bk_mesh_tree* tree, const char* relative) {
  char path[4096];
  path_of(path, sizeof path, relative);
  bk_error err = {{0}};
  if (!bk_mesh_tree_save(tree, path, &err)) die(relative, err.message);
  printf("wrote %s\n", path);
}

static void write_bytes(const char* relative, const uint8_t* data, size_t size) {
  char path[4096];
  path_of(path, sizeof path, relative);
  FILE* f = fopen(path, "wb");
  if (!f || fwrite(data, 1, size, f) != size || fclose(f) != 0) die(relative, "cannot write");
  printf("wrote %s\n", path);
}

static void store_f64(uint8_t* p, double v) {
  uint64_t bits = 0;
  memcpy(&bits, &v, sizeof bits);
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(bits >> (8 * i));
}

// Saves a tree whose root is damaged in a way the saver refuses to write:
// the valid tree is encoded, then `count` doubles at `offset` bytes into the
// root's record (which starts with its bounds, then 10 moments, then its
// plane) are overwritten with `values` and the checksum is fixed. The record
// is found by its bounds, so this does not depend on the header's layout.
static void save_damaged_root(const bk_mesh_tree* tree, size_t offset, const double* values, int count,
                              const char* relative) {
  uint8_t* data = NULL;
  size_t size = 0;
  bk_error err = {{0}};
  if (!bk_mesh_tree_save_memory(tree, relative, &data, &size, &err)) die(relative, err.message);
  uint8_t bounds[48];
  const bk_aabb* box = &tree->nodes[0].bounds;
  const double corners[6] = {box->min.x, box->min.y, box->min.z, box->max.x, box->max.y, box->max.z};
  for (int k = 0; k < 6; ++k)
    store_f64(bounds + 8 * k, corners[k]);
  size_t at = 32;
  while (at + sizeof bounds <= size && memcmp(data + at, bounds, sizeof bounds) != 0)
    at++;
  if (at + offset + 8 * (size_t)count > size) die(relative, "the root's record is not in the saved bytes");
  for (int k = 0; k < count; ++k)
    store_f64(data + at + offset + 8 * (size_t)k, values[k]);
  uint64_t hash = bk_hash_bytes(BK_FNV_OFFSET, data + 32, size - 32);
  for (int i = 0; i < 8; ++i)
    data[24 + i] = (uint8_t)(hash >> (8 * i));
  write_bytes(relative, data, size);
  free(data);
}

static uint8_t* read_bytes(const char* relative, size_t* size) {
  char path[4096];
  path_of(path, sizeof path, relative);
  void* data = NULL;
  bk_error err = {{0}};
  if (!bk_file_read(path, (uint64_t)1 << 20, "1 MiB", &data, size, &err)) die(relative, err.message);
  return data;
}

static void build(const bk_mesh* mesh, uint32_t pieces, uint64_t seed, bk_mesh_tree* tree) {
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  bk_error err = {{0}};
  if (!bk_mesh_tree_build(mesh, &desc, tree, &err)) die("build", err.message);
}

// Gives every triangle of every leaf one material.
static void set_material(bk_mesh_tree* tree, uint8_t material) {
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_mesh* leaf = &tree->nodes[tree->leaf_nodes[l]].mesh;
    memset(leaf->materials, material, leaf->triangle_count);
  }
}

static const char tetrahedron_obj[] = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
                                      "f 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n";

// Damaged copies of a valid file, one per check of the header and the payload.
static void write_damaged(const char* valid) {
  size_t size = 0;
  uint8_t* data = read_bytes(valid, &size);
  uint8_t* copy = malloc(size);
  write_bytes("corpus/fuzz_mtree/empty.mtree", data, 0);
  write_bytes("corpus/fuzz_mtree/header_only.mtree", data, 32);
  write_bytes("corpus/fuzz_mtree/truncated.mtree", data, size / 2);
  memcpy(copy, data, size);
  copy[0] = 'X';
  write_bytes("corpus/fuzz_mtree/bad_magic.mtree", copy, size);
  memcpy(copy, data, size);
  copy[8] = 1; // version 1
  write_bytes("corpus/fuzz_mtree/old_version.mtree", copy, size);
  memcpy(copy, data, size);
  for (int i = 0; i < 4; ++i) // the byte-order marker as a big-endian writer stores it
    copy[12 + i] = data[15 - i];
  write_bytes("corpus/fuzz_mtree/big_endian.mtree", copy, size);
  memcpy(copy, data, size);
  copy[size - 1] ^= 0x40; // payload changed, checksum not
  write_bytes("corpus/fuzz_mtree/bad_checksum.mtree", copy, size);
  free(copy);
  free(data);
}

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: fuzz_make_corpus TESTS_FUZZ_DIR\n");
    return 2;
  }
  root_dir = argv[1];
  bk_mesh tetra = {0}, cube = {0};
  bk_error err = {{0}};
  if (!bk_obj_parse(tetrahedron_obj, sizeof tetrahedron_obj - 1, "tetrahedron", &tetra, &err))
    die("tetrahedron", err.message);
  bk_shape_build(BK_SHAPE_CUBE, &cube);

  bk_mesh_tree tree = {0};
  build(&tetra, 2, 1, &tree);
  save_tree(&tree, "corpus/fuzz_mtree/tetrahedron_2.mtree");
  save_tree(&tree, "corpus/fuzz_bonds/tetrahedron_2.mtree");

  // Regression: all of a cap group's edges cancel (a degenerate cap triangle
  // a, a, b on the cut), so its outline has no corners at all. It is the only
  // cap triangle left, so its group is the first to use the outline buffer.
  {
    bk_mesh* leaf = &tree.nodes[tree.leaf_nodes[0]].mesh;
    uint32_t cap = 0;
    while (cap < leaf->triangle_count && leaf->materials[cap] != BK_MATERIAL_INTERIOR)
      cap++;
    if (cap == leaf->triangle_count) die("tetrahedron_2", "leaf 0 has no cap");
    uint32_t a = leaf->indices[3 * cap], b = leaf->indices[3 * cap + 1], tag = leaf->tags[cap];
    set_material(&tree, BK_MATERIAL_OUTER);
    bk_mesh_add_triangle(leaf, a, a, b, BK_MATERIAL_INTERIOR, tag);
    save_tree(&tree, "regressions/fuzz_bonds/cancelling_cap_outline.mtree");
  }
  bk_mesh_tree_free(&tree);

  // Regression: leaves without any cap triangle, so no bond candidates at all.
  build(&tetra, 2, 1, &tree);
  set_material(&tree, BK_MATERIAL_OUTER);
  save_tree(&tree, "regressions/fuzz_bonds/no_cap_triangles.mtree");
  bk_mesh_tree_free(&tree);

  // Regression: a leaf whose cap on one cut also appears turned over, so the
  // leaf lies on both sides of the cut and overlaps itself.
  build(&tetra, 2, 1, &tree);
  {
    bk_mesh* leaf = &tree.nodes[tree.leaf_nodes[0]].mesh;
    uint32_t triangles = leaf->triangle_count;
    for (uint32_t t = 0; t < triangles; ++t)
      if (leaf->materials[t] == BK_MATERIAL_INTERIOR)
        bk_mesh_add_triangle(leaf, leaf->indices[3 * t], leaf->indices[3 * t + 2], leaf->indices[3 * t + 1],
                             BK_MATERIAL_INTERIOR, leaf->tags[t]);
  }
  save_tree(&tree, "regressions/fuzz_bonds/self_bond_turned_cap.mtree");
  bk_mesh_tree_free(&tree);

  // Regression: a cut plane whose normal is not of unit length (the file
  // stores the plane as four numbers). The loader now refuses it (a split
  // plane's normal must have length 1), and so does the saver, hence
  // save_damaged_root.
  build(&tetra, 2, 1, &tree);
  {
    bk_vec3 n = bk_v3_scale(tree.nodes[0].plane.normal, 0.9997);
    const double normal[3] = {n.x, n.y, n.z};
    save_damaged_root(&tree, 16 * 8, normal, 3, "regressions/fuzz_bonds/non_unit_plane_normal.mtree");
  }
  bk_mesh_tree_free(&tree);

  // Regression: root bounds that do not contain the mesh (min > max, far
  // away); the tree's origin is derived from them. The loader and the saver
  // now refuse it (stored bounds must be the mesh's).
  build(&cube, 3, 3, &tree);
  {
    const double max[3] = {-6.7e155, -8.0, 0.5};
    save_damaged_root(&tree, 3 * 8, max, 3, "regressions/fuzz_bonds/bad_root_bounds.mtree");
  }
  bk_mesh_tree_free(&tree);

  build(&tetra, 4, 2, &tree);
  save_tree(&tree, "corpus/fuzz_bonds/tetrahedron_4.mtree");
  bk_mesh_tree_free(&tree);
  build(&cube, 3, 3, &tree);
  save_tree(&tree, "corpus/fuzz_mtree/cube_3.mtree");
  save_tree(&tree, "corpus/fuzz_bonds/cube_3.mtree");
  bk_mesh_tree_free(&tree);

  write_damaged("corpus/fuzz_mtree/tetrahedron_2.mtree");
  bk_mesh_free(&tetra);
  bk_mesh_free(&cube);
  return 0;
}
