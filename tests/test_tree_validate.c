// bk_mesh_tree_validate: a real tree of every pattern passes; a tree with
// one field corrupted at a time (bond leaf out of range, leaf volume
// negative, zero, huge or NaN, negative inertia, bond area zero or negative,
// bond centroid far away or outside its leaves, a normal not of unit length,
// a broken parent link) fails with a message naming the index and the
// field, and every consumer refuses it the same way: the runtime (with no
// allocation from the bad tree: the sanitizer build would see an overflow),
// .mtree and .glb saving, .mtree and .glb loading, and `breakables sim`.
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <breakables/runtime.h>

#include "bk_fracture.h"
#include "ensure.h"

static bk_mesh_tree build(const char* shape_name, bk_fracture_def d) {
  bk_shape shape = BK_SHAPE_CUBE;
  ENSURE(bk_shape_from_name(shape_name, &shape));
  bk_mesh source = {0};
  bk_shape_build(shape, &source);
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  d.threads = 1;
  ENSURE_MSG(bk_mesh_tree_build(&source, &d, &tree, &err), "%s", err.message);
  bk_mesh_free(&source);
  return tree;
}

static bk_fracture_def def_of(bk_fracture_pattern pattern, uint32_t pieces) {
  bk_fracture_def d = bk_default_fracture_def();
  d.pattern = pattern;
  d.pieces = pieces;
  return d;
}

// ---------------------------------------------------------------- valid trees

static void test_every_pattern_passes(void) {
  for (int p = 0; p < BK_PATTERN_COUNT; ++p) {
    for (int s = 0; s < 2; ++s) {
      bk_fracture_def d = def_of((bk_fracture_pattern)p, 24);
      // A cross through a torus: each quarter's prism crosses the ring twice.
      enum { W = 32, H = 32 };
      static uint8_t map[W * H];
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
          map[y * W + x] = (x == W / 2 || y == H / 3) ? 255 : 0;
      if (d.pattern == BK_PATTERN_CUTOUT) {
        d.cutout_pixels = map;
        d.cutout_width = W;
        d.cutout_height = H;
        d.cutout_axis = 1;
      }
      bk_mesh_tree tree = build(s ? "torus" : "cube", d);
      bk_error err = {0};
      ENSURE_MSG(bk_mesh_tree_validate(&tree, &err), "%s %s: %s", bk_fracture_pattern_name(d.pattern),
                 s ? "torus" : "cube", err.message);
      bk_mesh_tree_free(&tree);
    }
  }
  // Noisy cut faces.
  bk_fracture_def d = def_of(BK_PATTERN_PLANES, 16);
  d.noise_amplitude = 0.02;
  bk_mesh_tree tree = build("torus", d);
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_validate(&tree, &err), "noisy planes: %s", err.message);
  bk_mesh_tree_free(&tree);
}

// A cut-out face can cross the source twice (a torus's ring, a bridge's two
// legs, seen across) and separate different leaves in each place: a bond
// is the contact its two leaves share, inside both of them, never the
// face's other crossing (a bond used to take every triangle of its face,
// and a face on three leaves made no bond at all).
static void check_cutout_bonds(const char* shape, uint32_t axis, bool grid) {
  enum { W = 64, H = 64 };
  static uint8_t map[W * H];
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      map[y * W + x] = (grid ? x % 16 == 0 || y % 16 == 0 : x == W / 2 || y == H / 2) ? 255 : 0;
  bk_fracture_def d = def_of(BK_PATTERN_CUTOUT, 1);
  d.cutout_pixels = map;
  d.cutout_width = W;
  d.cutout_height = H;
  d.cutout_axis = axis;
  bk_mesh_tree tree = build(shape, d);
  for (uint32_t b = 0; b < tree.bond_count; ++b) {
    const bk_bond* bond = &tree.bonds[b];
    for (int side = 0; side < 2; ++side) {
      bk_aabb box = bk_mesh_tree_leaf(&tree, side ? bond->leaf_b : bond->leaf_a)->bounds;
      double slack = 1e-9;
      ENSURE_MSG(bond->centroid.x >= box.min.x - slack && bond->centroid.x <= box.max.x + slack &&
                     bond->centroid.y >= box.min.y - slack && bond->centroid.y <= box.max.y + slack &&
                     bond->centroid.z >= box.min.z - slack && bond->centroid.z <= box.max.z + slack,
                 "%s: bond %u (leaves %u and %u): centroid (%g, %g, %g) outside leaf %u", shape, b,
                 bond->leaf_a, bond->leaf_b, bond->centroid.x, bond->centroid.y, bond->centroid.z,
                 side ? bond->leaf_b : bond->leaf_a);
    }
  }
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_validate(&tree, &err), "%s: %s", shape, err.message);
  bk_mesh_tree_free(&tree);
}

static void test_cutout_bonds_inside_their_leaves(void) {
  check_cutout_bonds("torus", 2, true);
  check_cutout_bonds("bridge", 0, false);
}

// ---------------------------------------------------------------- corruptions

// The .mtree layout (tree_cache.c): a 32-byte header, then the payload's
// fixed fields, then the nodes (fixed part, then the mesh), the leaf list
// and the bonds.
enum {
  HEADER_BYTES = 32,
  PAYLOAD_FIXED_BYTES = 8 + 4 + 8 + 3 * 8 + 4 + 4 + 4 + 8 + 24 + 8 + 24 + 24 + 8 + 3 * 4 + 2 * 8 + 4 * 4,
  NODE_FIXED_BYTES = 6 * 8 + 10 * 8 + 4 * 8 + 6 * 4 + 3 * 4,
  BOND_BYTES = 2 * 4 + 7 * 8,
};

static size_t node_offset(const bk_mesh_tree* t, uint32_t node) {
  size_t at = HEADER_BYTES + PAYLOAD_FIXED_BYTES;
  for (uint32_t i = 0; i < node; ++i) {
    const bk_mesh* m = &t->nodes[i].mesh;
    at += NODE_FIXED_BYTES + (size_t)m->position_count * 24 + (size_t)m->corner_count * 40 +
          (size_t)m->triangle_count * 17;
  }
  return at;
}

static size_t bond_offset(const bk_mesh_tree* t, size_t file_size, uint32_t bond) {
  return file_size - (size_t)(t->bond_count - bond) * BOND_BYTES;
}

// The corrupted tree's .mtree bytes: the valid tree's bytes with the one
// field written over and the checksum made right again, so only the new
// checks stand between the file and its reader.
static void patch(uint8_t* bytes, size_t size, size_t at, const void* value, size_t value_size) {
  memcpy(bytes + at, value, value_size); // the test host is little-endian, as the file
  uint64_t sum = bk_hash_bytes(BK_FNV_OFFSET, bytes + HEADER_BYTES, size - HEADER_BYTES);
  memcpy(bytes + 24, &sum, sizeof sum);
}

typedef enum field {
  BOND_LEAF,
  LEAF_VOLUME,
  LEAF_MOMENT_YY,
  BOND_AREA,
  BOND_CENTROID,
  BOND_NORMAL,
  NODE_PARENT,
} field;

typedef struct corruption {
  const char* what;
  field field;
  double value;       // the new value (a leaf index for BOND_LEAF, a node for NODE_PARENT)
  const char* expect; // in the message, after the index
} corruption;

// Applies a corruption to the tree and to its .mtree bytes (when bytes).
static void corrupt_tree(bk_mesh_tree* t, const corruption* c, uint32_t leaf, uint32_t bond, uint8_t* bytes,
                         size_t size) {
  uint32_t node = t->leaf_nodes[leaf];
  size_t n_at = bytes ? node_offset(t, node) : 0, b_at = bytes ? bond_offset(t, size, bond) : 0;
  bk_bond* b = &t->bonds[bond];
  switch (c->field) {
  case BOND_LEAF: {
    uint32_t v = (uint32_t)c->value;
    b->leaf_b = v;
    if (bytes) patch(bytes, size, b_at + 4, &v, 4);
    break;
  }
  case LEAF_VOLUME:
    t->nodes[node].moments.v = c->value;
    if (bytes) patch(bytes, size, n_at + 48, &c->value, 8);
    break;
  case LEAF_MOMENT_YY: {
    double v = c->value * t->nodes[node].moments.yy;
    t->nodes[node].moments.yy = v;
    if (bytes) patch(bytes, size, n_at + 48 + 5 * 8, &v, 8);
    break;
  }
  case BOND_AREA:
    b->area = c->value;
    if (bytes) patch(bytes, size, b_at + 8, &c->value, 8);
    break;
  case BOND_CENTROID: {
    // value 0: just outside leaf_a's bounds (a tenth of its diagonal past them); else that x.
    bk_aabb box = bk_mesh_tree_leaf(t, b->leaf_a)->bounds;
    double x = c->value != 0.0 ? c->value : box.max.x + 0.1 * bk_v3_length(bk_v3_sub(box.max, box.min));
    b->centroid.x = x;
    if (bytes) patch(bytes, size, b_at + 16, &x, 8);
    break;
  }
  case BOND_NORMAL: {
    bk_vec3 n = bk_v3_scale(b->normal, c->value);
    b->normal = n;
    if (bytes) patch(bytes, size, b_at + 40, &n, 24);
    break;
  }
  case NODE_PARENT: {
    // Node 1 (a child of the root) names another node as its parent.
    uint32_t v = (uint32_t)c->value;
    t->nodes[1].parent = v;
    if (bytes) patch(bytes, size, node_offset(t, 1) + 6 * 8 + 10 * 8 + 4 * 8, &v, 4);
    break;
  }
  }
}

static uint8_t* read_file(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "cannot open %s", path);
  fseek(f, 0, SEEK_END);
  long length = ftell(f);
  fseek(f, 0, SEEK_SET);
  uint8_t* data = malloc((size_t)length + 1);
  ENSURE(fread(data, 1, (size_t)length, f) == (size_t)length);
  fclose(f);
  *size = (size_t)length;
  return data;
}

static void write_bytes(const char* path, const uint8_t* data, size_t size) {
  FILE* f = fopen(path, "wb");
  ENSURE(f != NULL);
  ENSURE(fwrite(data, 1, size, f) == size);
  fclose(f);
}

static bool exists(const char* path) {
  struct stat st;
  return stat(path, &st) == 0;
}

// The runtime asks where clusters are; none is ever made here.
static bk_body_state body_at_rest(bk_cluster_id cluster, void* context) {
  (void)cluster, (void)context;
  return (bk_body_state){0};
}

#ifdef BK_BREAKABLES_EXE
#define RUN_STDERR_PATH BK_TEST_TMP "/test_tree_validate.stderr"
#include "run_exe.h"

// `sim` with a refused file: one line, naming the file once and the problem.
static void expect_sim_refuses(const char* path, const char* index, const char* expect) {
  char args[1024];
  snprintf(args, sizeof args, "sim --mesh '%s' --steps 2 --shots 0", path);
  run_result* r = run(args);
  ENSURE_MSG(r->status != 0, "'%s' exited 0", args);
  ENSURE_MSG(count_lines(r->err) == 1 && r->err[strlen(r->err) - 1] == '\n', "'%s': not one line: %s", args,
             r->err);
  // Once by any name: the path as given, or its last part.
  const char* base = strrchr(path, '/') ? strrchr(path, '/') + 1 : path;
  const char* first = strstr(r->err, base);
  ENSURE_MSG(strstr(r->err, path) && !strstr(first + 1, base), "'%s' must name the file once: %s", args,
             r->err);
  ENSURE_MSG(strstr(r->err, index) && strstr(r->err, expect), "'%s': expected '%s' and '%s' in: %s", args,
             index, expect, r->err);
}
#endif

static void test_corruptions_refused(void) {
  bk_mesh_tree valid = build("cube", def_of(BK_PATTERN_PLANES, 8));
  ENSURE(valid.bond_count > 0 && valid.node_count > 2);
  uint8_t* valid_bytes = NULL;
  size_t valid_size = 0;
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_save_memory(&valid, "valid", &valid_bytes, &valid_size, &err), "%s", err.message);
  char glb_path[512];
  snprintf(glb_path, sizeof glb_path, "%s/tree_validate_valid.glb", BK_TEST_TMP);
  ENSURE_MSG(bk_mesh_tree_save_gltf(&valid, glb_path, NULL, &err), "%s", err.message);
  size_t glb_size = 0;
  uint8_t* glb = read_file(glb_path, &glb_size);
  // The .glb carries the .mtree bytes: found by its magic, patched in place.
  size_t embedded = 0;
  while (embedded + 8 <= glb_size && memcmp(glb + embedded, "BKMTREE", 8) != 0)
    ++embedded;
  ENSURE(embedded + valid_size <= glb_size && memcmp(glb + embedded, valid_bytes, valid_size) == 0);

  const uint32_t leaf = 3, bond = 2;
  const uint32_t node = valid.leaf_nodes[leaf];
  const bk_bond* vb = &valid.bonds[bond];
  char leaf_name[64], bond_name[64], node_name[64];
  snprintf(leaf_name, sizeof leaf_name, "leaf %u (node %u): ", leaf, node);
  snprintf(node_name, sizeof node_name, "node %u: ", node);
  snprintf(bond_name, sizeof bond_name, "bond %u (leaves %u and %u): ", bond, vb->leaf_a, vb->leaf_b);
  const corruption cases[] = {
      {"bond leaf out of range", BOND_LEAF, 8.0, "joins leaves"},
      {"bond leaf far out of range", BOND_LEAF, 4000000000.0, "joins leaves"},
      {"negative leaf volume", LEAF_VOLUME, -0.003, "volume -0.003 is not positive"},
      {"zero leaf volume", LEAF_VOLUME, 0.0, "volume 0 is not positive"},
      {"huge leaf volume", LEAF_VOLUME, 1e300, "volume 1e+300 is not its mesh's volume"},
      {"NaN leaf volume", LEAF_VOLUME, NAN, "moment v is nan"},
      {"negative inertia", LEAF_MOMENT_YY, -4.0, "principal moment of inertia"},
      {"zero bond area", BOND_AREA, 0.0, "area 0 is not positive"},
      {"negative bond area", BOND_AREA, -1.0, "area -1 is not positive"},
      {"far bond centroid", BOND_CENTROID, 1e300, "centroid (1e+300"},
      {"bond centroid outside its leaves", BOND_CENTROID, 0.0, "lies outside leaf"},
      {"bond normal not unit", BOND_NORMAL, 1.5, "normal has length 1.5, not 1"},
      {"broken parent link", NODE_PARENT, 2.0, "lists child 1, whose parent is 2"},
  };
  for (size_t k = 0; k < sizeof cases / sizeof *cases; ++k) {
    const corruption* c = &cases[k];
    const char* index = c->field == BOND_LEAF     ? "bond 2 "
                        : c->field == NODE_PARENT ? "node 0 "
                        : isnan(c->value)         ? node_name // not a number: refused before the physics
                        : c->field == LEAF_VOLUME || c->field == LEAF_MOMENT_YY ? leaf_name
                                                                                : bond_name;
    fprintf(stderr, "    %s\n", c->what);
    // The tree in memory.
    bk_mesh_tree t = {0};
    ENSURE(bk_mesh_tree_load_memory(valid_bytes, valid_size, "copy", &t, &err));
    uint8_t* bytes = malloc(valid_size);
    memcpy(bytes, valid_bytes, valid_size);
    corrupt_tree(&t, c, leaf, bond, bytes, valid_size);
    bk_error why = {0};
    ENSURE_MSG(!bk_mesh_tree_validate(&t, &why), "%s: accepted", c->what);
    ENSURE_MSG(strstr(why.message, index) && strstr(why.message, c->expect),
               "%s: expected '%s' and '%s' in: %s", c->what, index, c->expect, why.message);
    ENSURE_MSG(!strchr(why.message, '\n'), "%s: not one line", c->what);

    // The runtime refuses it before it allocates anything from it.
    bk_runtime_def rd = bk_default_runtime_def();
    rd.body_state = body_at_rest;
    bk_runtime* rt = bk_runtime_create(&rd, &err);
    ENSURE_MSG(rt != NULL, "%s", err.message);
    bk_breakable_def bd = bk_default_breakable_def();
    bd.tree = &t;
    bk_error rt_err = {0};
    bk_breakable_id id = bk_runtime_add_breakable(rt, &bd, &rt_err);
    ENSURE_MSG(bk_breakable_is_null(id), "%s: the runtime took it", c->what);
    char expected[600];
    snprintf(expected, sizeof expected, "breakable: tree: %s", why.message);
    ENSURE_MSG(strcmp(rt_err.message, expected) == 0, "%s: runtime said '%s', expected '%s'", c->what,
               rt_err.message, expected);
    bk_runtime_destroy(rt);

    // Saving it is refused, as .mtree and as .glb, and nothing is written.
    char path[512];
    snprintf(path, sizeof path, "%s/tree_validate_bad_%zu.mtree", BK_TEST_TMP, k);
    remove(path);
    ENSURE_MSG(!bk_mesh_tree_save(&t, path, &err), "%s: saved", c->what);
    ENSURE_MSG(strstr(err.message, "cannot save an invalid mesh tree") && strstr(err.message, why.message),
               "%s: %s", c->what, err.message);
    ENSURE(!exists(path));
    char gltf_path[512];
    snprintf(gltf_path, sizeof gltf_path, "%s/tree_validate_bad_%zu.glb", BK_TEST_TMP, k);
    remove(gltf_path);
    ENSURE_MSG(!bk_mesh_tree_save_gltf(&t, gltf_path, NULL, &err), "%s: exported", c->what);
    ENSURE_MSG(strstr(err.message, why.message), "%s: %s", c->what, err.message);
    ENSURE(!exists(gltf_path));

    // Loading it is refused: the .mtree file and the .glb carrying it.
    write_bytes(path, bytes, valid_size);
    bk_mesh_tree loaded = {0};
    ENSURE_MSG(!bk_mesh_tree_load(path, &loaded, &err), "%s: loaded", c->what);
    ENSURE_MSG(strstr(err.message, path) && strstr(err.message, why.message), "%s: %s", c->what, err.message);
    ENSURE(loaded.node_count == 0 && loaded.nodes == NULL);
    uint8_t* bad_glb = malloc(glb_size);
    memcpy(bad_glb, glb, glb_size);
    memcpy(bad_glb + embedded, bytes, valid_size);
    write_bytes(gltf_path, bad_glb, glb_size);
    ENSURE_MSG(!bk_mesh_tree_load_gltf(gltf_path, &loaded, &err), "%s: loaded the .glb", c->what);
    ENSURE_MSG(strstr(err.message, gltf_path) && strstr(err.message, why.message), "%s: %s", c->what,
               err.message);
#ifdef BK_BREAKABLES_EXE
    if (k % 4 == 0 || c->field == BOND_LEAF) { // a few through the command line: each run fractures nothing
      expect_sim_refuses(path, index, c->expect);
      expect_sim_refuses(gltf_path, index, c->expect);
    }
#endif
    remove(path);
    remove(gltf_path);
    free(bad_glb);
    free(bytes);
    bk_mesh_tree_free(&t);
  }
  free(glb);
  free(valid_bytes);
  remove(glb_path);
  bk_mesh_tree_free(&valid);
}

// A NULL tree and arrays missing behind their counts are refused, not read.
static void test_missing_arrays_refused(void) {
  bk_error err = {0};
  ENSURE(!bk_mesh_tree_validate(NULL, &err) && strstr(err.message, "NULL"));
  bk_mesh_tree t = build("cube", def_of(BK_PATTERN_PLANES, 4));
  bk_bond* bonds = t.bonds;
  t.bonds = NULL;
  ENSURE(!bk_mesh_tree_validate(&t, &err) && strstr(err.message, "bonds is NULL"));
  t.bonds = bonds;
  uint8_t* materials = t.nodes[2].mesh.materials;
  t.nodes[2].mesh.materials = NULL;
  ENSURE(!bk_mesh_tree_validate(&t, &err) &&
         strstr(err.message, "node 2: its mesh has counts but no arrays"));
  t.nodes[2].mesh.materials = materials;
  ENSURE_MSG(bk_mesh_tree_validate(&t, &err), "%s", err.message);
  bk_mesh_tree_free(&t);
}

int main(void) {
  RUN(test_every_pattern_passes);
  RUN(test_cutout_bonds_inside_their_leaves);
  RUN(test_corruptions_refused);
  RUN(test_missing_arrays_refused);
  return 0;
}
