// The .mtree cache file: bit-exact round trips, deterministic bytes, atomic
// replacement, and a distinct, clean failure (zeroed output, no leaks) for
// every kind of damaged file.
#include <dirent.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "bk_geom.h"
#include "ensure.h"

#define TREE_PATH BK_TEST_TMP "/t.mtree"
#define OTHER_PATH BK_TEST_TMP "/t2.mtree"
#define DAMAGED_PATH BK_TEST_TMP "/damaged.mtree"

// The offsets below are version 4's layout: a new version must revisit them.
_Static_assert(BK_MTREE_VERSION == 4, "test_tree_cache.c knows the layout of .mtree version 4");

// Header layout (see tree_cache.c): magic 8, version 4, endian 4, payload size 8, checksum 8.
enum { HEADER_BYTES = 32, VERSION_OFFSET = 8, ENDIAN_OFFSET = 12, CHECKSUM_OFFSET = 24 };
// Payload: source_hash 8, pieces 4, seed 8, texture_scale 8, jitter 8, aspect_bias 8, then the pattern
// fields (version 4), max_depth 4, then node_count.
enum { PATTERN_OFFSET = HEADER_BYTES + 8 + 4 + 8 + 8 + 8 + 8 };
// The pattern fields: pattern, seed_point_count, clusters (u32); cluster_border, impact[3],
// radial_falloff, brick_size[3], brick_origin[3], brick_offset (f64); cutout_width, cutout_height,
// cutout_axis (u32); noise_amplitude, noise_frequency (f64). Offsets from PATTERN_OFFSET.
enum {
  SEED_POINT_COUNT_AT = 4,
  CLUSTERS_AT = 8,
  CUTOUT_AXIS_AT = 3 * 4 + 12 * 8 + 2 * 4,
  NOISE_FREQUENCY_AT = 3 * 4 + 12 * 8 + 3 * 4 + 8,
  PATTERN_FIELDS_BYTES = 3 * 4 + 12 * 8 + 3 * 4 + 2 * 8,
};
enum { NODE_COUNT_OFFSET = PATTERN_OFFSET + PATTERN_FIELDS_BYTES + 4 };
// The root's parent follows the counts (node, leaf, bond: 12 bytes) and its
// bounds, moments and plane (20 doubles).
enum { ROOT_PARENT_OFFSET = NODE_COUNT_OFFSET + 12 + 20 * 8 };
// Bonds close the file, 64 bytes each: leaf_a, leaf_b, then 7 doubles.
enum { BOND_BYTES = 2 * 4 + 7 * 8 };

static void build_tree(uint32_t pieces, uint64_t seed, bk_mesh_tree* tree) {
  bk_mesh cube = {0};
  bk_shape_build(BK_SHAPE_CUBE, &cube);
  bk_fracture_def desc = bk_default_fracture_def();
  desc.pieces = pieces;
  desc.seed = seed;
  desc.jitter = 0.0;
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_build(&cube, &desc, tree, &err), "%s", err.message);
  bk_mesh_free(&cube);
  ENSURE(tree->leaf_count >= pieces);
  ENSURE(tree->bond_count > 0);
}

static uint8_t* read_bytes(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  ENSURE_MSG(f != NULL, "cannot open %s", path);
  ENSURE(fseek(f, 0, SEEK_END) == 0);
  long length = ftell(f);
  ENSURE(length >= 0);
  ENSURE(fseek(f, 0, SEEK_SET) == 0);
  uint8_t* data = malloc((size_t)length + 1);
  ENSURE(data != NULL);
  ENSURE(fread(data, 1, (size_t)length, f) == (size_t)length);
  fclose(f);
  *size = (size_t)length;
  return data;
}

static void write_bytes(const char* path, const uint8_t* data, size_t size) {
  FILE* f = fopen(path, "wb");
  ENSURE_MSG(f != NULL, "cannot create %s", path);
  ENSURE(fwrite(data, 1, size, f) == size);
  ENSURE(fclose(f) == 0);
}

static void store_u32(uint8_t* p, uint32_t v) {
  for (int i = 0; i < 4; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static void store_u64(uint8_t* p, uint64_t v) {
  for (int i = 0; i < 8; ++i)
    p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t load_u32(const uint8_t* p) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i)
    v |= (uint32_t)p[i] << (8 * i);
  return v;
}

static double load_f64(const uint8_t* p) {
  uint64_t bits = 0;
  for (int i = 0; i < 8; ++i)
    bits |= (uint64_t)p[i] << (8 * i);
  double v = 0.0;
  memcpy(&v, &bits, sizeof v);
  return v;
}

// Stores a new checksum so the damage gets past the header checks and the
// structural checks are what must catch it.
static void rehash(uint8_t* data, size_t size) {
  uint64_t hash = bk_hash_bytes(BK_FNV_OFFSET, data + HEADER_BYTES, size - HEADER_BYTES);
  for (int i = 0; i < 8; ++i)
    data[CHECKSUM_OFFSET + i] = (uint8_t)(hash >> (8 * i));
}

static bool all_zero(const void* p, size_t size) {
  const uint8_t* b = p;
  for (size_t i = 0; i < size; ++i)
    if (b[i]) return false;
  return true;
}

static void compare_meshes(const bk_mesh* a, const bk_mesh* b) {
  ENSURE(a->position_count == b->position_count);
  ENSURE(a->corner_count == b->corner_count);
  ENSURE(a->triangle_count == b->triangle_count);
  ENSURE(memcmp(a->positions, b->positions, sizeof(bk_vec3) * a->position_count) == 0);
  ENSURE(memcmp(a->corners, b->corners, sizeof(bk_corner) * a->corner_count) == 0);
  ENSURE(memcmp(a->indices, b->indices, sizeof(uint32_t) * 3 * a->triangle_count) == 0);
  ENSURE(memcmp(a->materials, b->materials, a->triangle_count) == 0);
  ENSURE(memcmp(a->tags, b->tags, sizeof(uint32_t) * a->triangle_count) == 0);
}

#define SAME_BITS(a, b) (sizeof(a) == sizeof(b) && memcmp(&(a), &(b), sizeof(a)) == 0)

// Every stored field of the fracture def, bit for bit; the borrowed arrays
// and the callback are not kept.
static void compare_descs(const bk_fracture_def* built, const bk_fracture_def* loaded) {
  ENSURE(built->pieces == loaded->pieces);
  ENSURE(built->seed == loaded->seed);
  ENSURE(SAME_BITS(built->texture_scale, loaded->texture_scale));
  ENSURE(SAME_BITS(built->jitter, loaded->jitter));
  ENSURE(SAME_BITS(built->aspect_bias, loaded->aspect_bias));
  ENSURE(built->pattern == loaded->pattern);
  ENSURE(built->seed_point_count == loaded->seed_point_count);
  ENSURE(built->clusters == loaded->clusters);
  ENSURE(SAME_BITS(built->cluster_border, loaded->cluster_border));
  ENSURE(SAME_BITS(built->impact, loaded->impact));
  ENSURE(SAME_BITS(built->radial_falloff, loaded->radial_falloff));
  ENSURE(SAME_BITS(built->brick_size, loaded->brick_size));
  ENSURE(SAME_BITS(built->brick_origin, loaded->brick_origin));
  ENSURE(SAME_BITS(built->brick_offset, loaded->brick_offset));
  ENSURE(built->cutout_width == loaded->cutout_width);
  ENSURE(built->cutout_height == loaded->cutout_height);
  ENSURE(built->cutout_axis == loaded->cutout_axis);
  ENSURE(SAME_BITS(built->noise_amplitude, loaded->noise_amplitude));
  ENSURE(SAME_BITS(built->noise_frequency, loaded->noise_frequency));
  ENSURE(loaded->progress == NULL && loaded->progress_user == NULL);
  ENSURE(loaded->seed_points == NULL && loaded->cutout_pixels == NULL);
}

// Bit-exact comparison; `loaded` must also have capacities equal to counts.
static void compare_trees(const bk_mesh_tree* built, const bk_mesh_tree* loaded) {
  ENSURE(built->node_count == loaded->node_count);
  ENSURE(built->leaf_count == loaded->leaf_count);
  ENSURE(built->bond_count == loaded->bond_count);
  ENSURE(built->max_depth == loaded->max_depth);
  ENSURE(built->source_hash == loaded->source_hash);
  compare_descs(&built->desc, &loaded->desc);
  for (uint32_t i = 0; i < built->node_count; ++i) {
    const bk_mesh_tree_node *a = &built->nodes[i], *b = &loaded->nodes[i];
    ENSURE(memcmp(&a->bounds, &b->bounds, sizeof a->bounds) == 0);
    ENSURE(memcmp(&a->moments, &b->moments, sizeof a->moments) == 0);
    ENSURE(memcmp(&a->plane, &b->plane, sizeof a->plane) == 0);
    ENSURE(a->parent == b->parent);
    ENSURE(a->first_child == b->first_child);
    ENSURE(a->child_count == b->child_count);
    ENSURE(a->leaf_begin == b->leaf_begin);
    ENSURE(a->leaf_end == b->leaf_end);
    ENSURE(a->depth == b->depth);
    compare_meshes(&a->mesh, &b->mesh);
    ENSURE(b->mesh.position_capacity == b->mesh.position_count);
    ENSURE(b->mesh.corner_capacity == b->mesh.corner_count);
    ENSURE(b->mesh.triangle_capacity == b->mesh.triangle_count);
  }
  ENSURE(memcmp(built->leaf_nodes, loaded->leaf_nodes, sizeof(uint32_t) * built->leaf_count) == 0);
  ENSURE(memcmp(built->bonds, loaded->bonds, sizeof(bk_bond) * built->bond_count) == 0);
}

// Saves and checks that no temporary file (<name>.<random>.tmp beside the
// target) is left behind.
static void save_ok(const bk_mesh_tree* tree, const char* path) {
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_save(tree, path, &err), "%s", err.message);
  const char* slash = strrchr(path, '/');
  ENSURE(slash != NULL);
  char dir[512] = {0};
  snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
  DIR* d = opendir(dir);
  ENSURE(d != NULL);
  size_t base = strlen(slash + 1);
  for (struct dirent* e = readdir(d); e; e = readdir(d)) {
    size_t len = strlen(e->d_name);
    bool temp = strncmp(e->d_name, slash + 1, base) == 0 && len > base + 4 &&
                strcmp(e->d_name + len - 4, ".tmp") == 0;
    ENSURE_MSG(!temp, "%s/%s left behind", dir, e->d_name);
  }
  closedir(d);
}

// Loads a damaged file and checks the failure: message, zeroed output. The
// output starts as garbage so "zeroed" is really the loader's doing.
static void expect_load_failure(const char* path, const char* expected) {
  bk_mesh_tree out;
  memset(&out, 0x5a, sizeof out);
  bk_error err = {{0}};
  ENSURE(!bk_mesh_tree_load(path, &out, &err));
  ENSURE_MSG(strstr(err.message, expected) != NULL, "expected \"%s\", got \"%s\"", expected, err.message);
  ENSURE_MSG(strstr(err.message, path) != NULL, "message does not name the file: %s", err.message);
  ENSURE_MSG(strchr(err.message, '\n') == NULL, "message is not one line: %s", err.message);
  ENSURE(all_zero(&out, sizeof out));
}

static void expect_damaged(const uint8_t* data, size_t size, const char* expected) {
  write_bytes(DAMAGED_PATH, data, size);
  expect_load_failure(DAMAGED_PATH, expected);
}

static void test_round_trip(void) {
  bk_mesh_tree built = {0};
  build_tree(64, 7, &built);
  save_ok(&built, TREE_PATH);
  bk_mesh_tree loaded = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_load(TREE_PATH, &loaded, &err), "%s", err.message);
  compare_trees(&built, &loaded);
  // The loaded tree is a fully working tree, not just equal bytes.
  bk_mesh_tree_stats stats = bk_mesh_tree_measure(&loaded);
  ENSURE(stats.open_nodes == 0);
  ENSURE_REL(stats.leaf_volume_sum, stats.source_volume, 1e-9);
  bk_mesh_tree_free(&loaded);
  ENSURE(all_zero(&loaded, sizeof loaded));
  bk_mesh_tree_free(&built);
}

static void test_deterministic(void) {
  bk_mesh_tree built = {0};
  build_tree(64, 7, &built);
  save_ok(&built, TREE_PATH);
  save_ok(&built, OTHER_PATH);
  size_t size_a = 0, size_b = 0;
  uint8_t* a = read_bytes(TREE_PATH, &size_a);
  uint8_t* b = read_bytes(OTHER_PATH, &size_b);
  ENSURE(size_a == size_b);
  ENSURE(memcmp(a, b, size_a) == 0);
  free(b);

  // Saving a loaded tree reproduces the file: nothing is lost or reordered.
  bk_mesh_tree loaded = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_load(TREE_PATH, &loaded, &err), "%s", err.message);
  save_ok(&loaded, OTHER_PATH);
  b = read_bytes(OTHER_PATH, &size_b);
  ENSURE(size_a == size_b);
  ENSURE(memcmp(a, b, size_a) == 0);
  free(a);
  free(b);
  bk_mesh_tree_free(&loaded);
  bk_mesh_tree_free(&built);
}

static void test_corruption(void) {
  bk_mesh_tree built = {0};
  build_tree(64, 7, &built);
  save_ok(&built, TREE_PATH);
  bk_mesh_tree_free(&built);
  size_t size = 0;
  uint8_t* good = read_bytes(TREE_PATH, &size);
  uint8_t* data = malloc(size + 1);
  ENSURE(data != NULL);
  ENSURE(load_u32(good + NODE_COUNT_OFFSET) > 1);

  // (a) shorter than a header
  expect_damaged(good, 10, "truncated header (10 bytes)");
  expect_damaged(good, 0, "truncated header (0 bytes)");

  // (b) magic
  memcpy(data, good, size);
  data[0] ^= 0xff;
  expect_damaged(data, size, "not a mesh tree file (bad magic)");

  // (c) version
  memcpy(data, good, size);
  store_u32(data + VERSION_OFFSET, 99);
  char expected_version[128] = {0};
  snprintf(expected_version, sizeof expected_version, "mesh tree version 99 is not supported (expected %u)",
           BK_MTREE_VERSION);
  expect_damaged(data, size, expected_version);

  // byte order: the marker as a big-endian writer would store it
  memcpy(data, good, size);
  for (int i = 0; i < 4; ++i)
    data[ENDIAN_OFFSET + i] = (uint8_t)(i + 1);
  expect_damaged(data, size, "wrong byte order");

  // (d) payload one byte short, and one byte too long
  char expected[128] = {0};
  snprintf(expected, sizeof expected, "truncated: payload is %zu bytes, header says %zu",
           size - HEADER_BYTES - 1, size - HEADER_BYTES);
  expect_damaged(good, size - 1, expected);
  memcpy(data, good, size);
  data[size] = 0;
  expect_damaged(data, size + 1, "corrupt: payload is");

  // (e) one payload bit flipped
  memcpy(data, good, size);
  data[HEADER_BYTES + (size - HEADER_BYTES) / 2] ^= 0x10;
  expect_damaged(data, size, "checksum mismatch (file is corrupt)");

  // (f) an absurd node count behind a valid checksum must be refused by the
  // size guard (the message names the remaining bytes), not by a failed
  // terabyte allocation.
  memcpy(data, good, size);
  store_u32(data + NODE_COUNT_OFFSET, 0xFFFFFFF0u);
  rehash(data, size);
  expect_damaged(data, size, "corrupt: 4294967280 nodes");
  expect_damaged(data, size, "remain");

  // Structural damage behind a valid checksum: the root claims a parent.
  memcpy(data, good, size);
  ENSURE(load_u32(data + ROOT_PARENT_OFFSET) == BK_NULL_INDEX);
  store_u32(data + ROOT_PARENT_OFFSET, 0);
  rehash(data, size);
  expect_damaged(data, size, "corrupt: the root has parent 0");

  // ... the last bond joins a leaf to itself (leaf_a = leaf_b).
  memcpy(data, good, size);
  uint8_t* bond = data + size - BOND_BYTES;
  store_u32(bond, load_u32(bond + 4));
  rehash(data, size);
  expect_damaged(data, size, "corrupt: bond");

  // ... one fewer node than the data holds: bytes are left over.
  memcpy(data, good, size);
  store_u32(data + NODE_COUNT_OFFSET, load_u32(good + NODE_COUNT_OFFSET) - 1);
  rehash(data, size);
  expect_damaged(data, size, "corrupt");

  // Truncations at many points of the payload fail cleanly (no overrun, no leak).
  // 101 cuts from an empty payload to one byte short, spread evenly: quick under ASan.
  for (size_t k = 0; k <= 100; ++k) {
    size_t cut = HEADER_BYTES + (size - 1 - HEADER_BYTES) * k / 100;
    memcpy(data, good, cut);
    // Keep the header consistent with the shortened payload so the parser itself is exercised.
    uint64_t payload = cut - HEADER_BYTES;
    for (int i = 0; i < 8; ++i)
      data[16 + i] = (uint8_t)(payload >> (8 * i));
    rehash(data, cut);
    expect_damaged(data, cut, "corrupt");
  }

  free(data);
  free(good);
}

// Non-default values in every pattern field: awkward doubles (not short
// decimals, a subnormal, -0.0), so only a bit-exact round trip compares equal.
static void set_pattern_fields(bk_fracture_def* d, bk_fracture_pattern pattern) {
  d->pattern = pattern;
  // A loaded desc keeps a seed point count only for Voronoi (the points are not kept).
  d->seed_point_count = pattern == BK_PATTERN_VORONOI ? 37 : 0;
  d->clusters = 11;
  d->cluster_border = 0.1 + 0.2;
  d->impact = bk_v3(0.1, -2.0 / 3.0, 4.9e-320);
  d->radial_falloff = 1.0 / 3.0;
  d->brick_size = bk_v3(0.21, 0.0625 + 1e-17, 0.1);
  d->brick_origin = bk_v3(-0.0, 0.125, -3.75e-3);
  d->brick_offset = 1.0 / 7.0;
  d->cutout_width = 640;
  d->cutout_height = 480;
  d->cutout_axis = 1;
  // Noisy faces exist for every pattern but brick (it cuts along its mortar).
  d->noise_amplitude = pattern != BK_PATTERN_BRICK ? 0.015 : 0.0;
  d->noise_frequency = 4.0 / 3.0;
  d->jitter = 0.05 / 3.0;
  d->aspect_bias = 2.0 / 3.0;
}

// Every pattern field survives save and load bit for bit, for every pattern,
// sits where the layout comment says, and a loaded tree saves back to the
// same bytes. The tree is built by planes; only its desc is changed.
static void test_pattern_round_trip(void) {
  bk_mesh_tree built = {0};
  build_tree(8, 5, &built);
  for (int p = 0; p < BK_PATTERN_COUNT; ++p) {
    set_pattern_fields(&built.desc, (bk_fracture_pattern)p);
    // The values really differ from the defaults, so a field that is not stored cannot pass.
    bk_fracture_def def = bk_default_fracture_def();
    ENSURE(built.desc.clusters != def.clusters && built.desc.cutout_axis != def.cutout_axis);
    ENSURE(!SAME_BITS(built.desc.brick_origin, def.brick_origin) &&
           !SAME_BITS(built.desc.impact, def.impact));
    save_ok(&built, TREE_PATH);
    bk_mesh_tree loaded = {0};
    bk_error err = {{0}};
    ENSURE_MSG(bk_mesh_tree_load(TREE_PATH, &loaded, &err), "%s", err.message);
    compare_trees(&built, &loaded);

    size_t size = 0;
    uint8_t* bytes = read_bytes(TREE_PATH, &size);
    ENSURE(load_u32(bytes + VERSION_OFFSET) == BK_MTREE_VERSION);
    ENSURE(load_u32(bytes + PATTERN_OFFSET) == (uint32_t)p);
    ENSURE(load_u32(bytes + PATTERN_OFFSET + SEED_POINT_COUNT_AT) == built.desc.seed_point_count);
    ENSURE(load_u32(bytes + PATTERN_OFFSET + CUTOUT_AXIS_AT) == built.desc.cutout_axis);
    double frequency = load_f64(bytes + PATTERN_OFFSET + NOISE_FREQUENCY_AT);
    ENSURE(SAME_BITS(frequency, built.desc.noise_frequency));
    ENSURE(load_u32(bytes + NODE_COUNT_OFFSET) == built.node_count);

    save_ok(&loaded, OTHER_PATH);
    size_t again_size = 0;
    uint8_t* again = read_bytes(OTHER_PATH, &again_size);
    ENSURE(again_size == size && memcmp(again, bytes, size) == 0);
    free(again);
    free(bytes);
    bk_mesh_tree_free(&loaded);
  }
  bk_mesh_tree_free(&built);
}

// A real version-3 file (no pattern fields, consistent size and checksum) is
// refused by its version, in one line naming it; the same bytes claiming
// version 4 are refused as corrupt rather than misread.
static void test_version_3_refused(void) {
  bk_mesh_tree built = {0};
  build_tree(8, 5, &built);
  save_ok(&built, TREE_PATH);
  bk_mesh_tree_free(&built);
  size_t size = 0;
  uint8_t* v4 = read_bytes(TREE_PATH, &size);
  size_t v3_size = size - PATTERN_FIELDS_BYTES;
  uint8_t* v3 = malloc(v3_size);
  ENSURE(v3 != NULL);
  memcpy(v3, v4, PATTERN_OFFSET);
  memcpy(v3 + PATTERN_OFFSET, v4 + PATTERN_OFFSET + PATTERN_FIELDS_BYTES,
         size - PATTERN_OFFSET - PATTERN_FIELDS_BYTES);
  store_u32(v3 + VERSION_OFFSET, 3);
  store_u64(v3 + 16, v3_size - HEADER_BYTES);
  rehash(v3, v3_size);
  char expected[160] = {0};
  snprintf(expected, sizeof expected, "%s: mesh tree version 3 is not supported (expected %u)", DAMAGED_PATH,
           BK_MTREE_VERSION);
  write_bytes(DAMAGED_PATH, v3, v3_size);
  bk_mesh_tree out = {0};
  bk_error err = {{0}};
  ENSURE(!bk_mesh_tree_load(DAMAGED_PATH, &out, &err));
  ENSURE_MSG(strcmp(err.message, expected) == 0, "expected \"%s\", got \"%s\"", expected, err.message);
  expect_damaged(v3, v3_size, expected);

  store_u32(v3 + VERSION_OFFSET, BK_MTREE_VERSION);
  expect_damaged(v3, v3_size, "corrupt");
  free(v3);
  free(v4);
}

// A stored pattern field out of range, behind a valid checksum, is refused in
// one line naming the field and the stored value.
static void test_bad_pattern_fields(void) {
  bk_mesh_tree built = {0};
  build_tree(8, 5, &built);
  save_ok(&built, TREE_PATH);
  bk_mesh_tree_free(&built);
  size_t size = 0;
  uint8_t* good = read_bytes(TREE_PATH, &size);
  uint8_t* data = malloc(size);
  ENSURE(data != NULL);
  ENSURE(load_u32(good + PATTERN_OFFSET) == BK_PATTERN_PLANES);

  memcpy(data, good, size);
  store_u32(data + PATTERN_OFFSET, 9);
  rehash(data, size);
  char expected[128] = {0};
  snprintf(expected, sizeof expected, "corrupt: fracture: pattern = 9 is not a pattern (0 to %d)",
           BK_PATTERN_COUNT - 1);
  expect_damaged(data, size, expected);

  store_u32(data + PATTERN_OFFSET, BK_PATTERN_COUNT);
  rehash(data, size);
  snprintf(expected, sizeof expected, "fracture: pattern = %d is not a pattern", BK_PATTERN_COUNT);
  expect_damaged(data, size, expected);

  store_u32(data + PATTERN_OFFSET, 0xFFFFFFFFu);
  rehash(data, size);
  expect_damaged(data, size, "fracture: pattern = 4294967295 is not a pattern");

  // The other fields are refused by the def's own validation, which names them.
  memcpy(data, good, size);
  store_u32(data + PATTERN_OFFSET + CUTOUT_AXIS_AT, 3);
  rehash(data, size);
  expect_damaged(data, size, "corrupt: fracture: cutout_axis must be 0, 1 or 2 (got 3)");

  memcpy(data, good, size);
  store_u32(data + PATTERN_OFFSET + CLUSTERS_AT, 0);
  rehash(data, size);
  expect_damaged(data, size, "corrupt: fracture: clusters");

  memcpy(data, good, size);
  store_u64(data + PATTERN_OFFSET + NOISE_FREQUENCY_AT, 0);
  rehash(data, size);
  expect_damaged(data, size, "corrupt: fracture: noise_frequency");

  // Seed points are kept only as a Voronoi tree's count.
  memcpy(data, good, size);
  store_u32(data + PATTERN_OFFSET + SEED_POINT_COUNT_AT, 5);
  rehash(data, size);
  expect_damaged(data, size, "seed_point_count");
  // ... and a Voronoi tree's count within the build's limit (the points themselves are not read).
  store_u32(data + PATTERN_OFFSET, BK_PATTERN_VORONOI);
  store_u32(data + PATTERN_OFFSET + SEED_POINT_COUNT_AT, (1u << 20) + 1);
  rehash(data, size);
  expect_damaged(data, size, "corrupt: fracture: seed_point_count = 1048577 is too many");
  free(data);
  free(good);
}

static void test_missing_file(void) { expect_load_failure(BK_TEST_TMP "/no_such_file.mtree", "cannot open"); }

static void test_save_errors(void) {
  bk_mesh_tree built = {0};
  build_tree(8, 1, &built);
  bk_error err = {{0}};
  const char* path = BK_TEST_TMP "/no_such_dir/t.mtree";
  ENSURE(!bk_mesh_tree_save(&built, path, &err));
  ENSURE_MSG(strstr(err.message, path) && strstr(err.message, "cannot write"), "%s", err.message);
  bk_mesh_tree_free(&built);

  // An empty tree is refused rather than written as a file nothing can load.
  bk_mesh_tree empty = {0};
  ENSURE(!bk_mesh_tree_save(&empty, OTHER_PATH, &err));
  ENSURE_MSG(strstr(err.message, "invalid mesh tree"), "%s", err.message);
}

static void test_replace_existing(void) {
  bk_mesh_tree a = {0}, b = {0};
  build_tree(64, 7, &a);
  build_tree(16, 3, &b);
  save_ok(&a, TREE_PATH);
  save_ok(&b, TREE_PATH);
  bk_mesh_tree loaded = {0};
  bk_error err = {{0}};
  ENSURE_MSG(bk_mesh_tree_load(TREE_PATH, &loaded, &err), "%s", err.message);
  compare_trees(&b, &loaded);
  bk_mesh_tree_free(&loaded);
  bk_mesh_tree_free(&a);
  bk_mesh_tree_free(&b);
}

int main(void) {
  RUN(test_round_trip);
  RUN(test_deterministic);
  RUN(test_corruption);
  RUN(test_pattern_round_trip);
  RUN(test_version_3_refused);
  RUN(test_bad_pattern_fields);
  RUN(test_missing_file);
  RUN(test_save_errors);
  RUN(test_replace_existing);
  return 0;
}
