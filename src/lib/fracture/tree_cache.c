// The .mtree cache file: a mesh tree written so that a later run can skip the
// (slow) fracture. Everything is serialised field by field in little-endian
// order with explicit helpers, so the file does not depend on struct padding,
// the compiler or the host's byte order, and saving the same tree twice gives
// identical bytes.
//
// Layout: a fixed 32-byte header followed by the payload.
//   header:  "BKMTREE\0" | u32 version | u32 0x01020304 | u64 payload size | u64 FNV-1a-64 of the payload
//   payload: u64 source_hash | u32 pieces | u64 seed | f64 texture_scale | f64 jitter | f64 aspect_bias
//            u32 pattern | u32 seed_point_count | u32 clusters | f64 cluster_border | f64 impact[3]
//            f64 radial_falloff | f64 brick_size[3] | f64 brick_origin[3] | f64 brick_offset
//            u32 cutout_width, cutout_height, cutout_axis | f64 noise_amplitude, noise_frequency
//            u32 max_depth | u32 node_count | u32 leaf_count | u32 bond_count
//            node_count x { f64 bounds[6] | f64 moments[10] | f64 plane[4]
//                           u32 parent, first_child, child_count, leaf_begin, leaf_end, depth
//                           u32 position_count, corner_count, triangle_count
//                           positions (3 f64) | corners (u32 + 9 f32) | indices (3 u32)
//                           materials (u8) | tags (u32) }
//            leaf_count x u32 leaf_nodes
//            bond_count x { u32 leaf_a, leaf_b | f64 area | f64 centroid[3] | f64 normal[3] }
// Floats are stored as their IEEE-754 bits, so a round trip is bit-exact.
// Version 3: node moments are taken about bk_mesh_tree_origin (version 2 took
// them about the world origin, which loses all precision far from it).
// Version 4: the fracture pattern and its parameters (the caller's seed
// points and cut-out map are not kept, only their counts and size).
#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_bytes.h"
#include "bk_fracture.h"

static const uint8_t mtree_magic[8] = {'B', 'K', 'M', 'T', 'R', 'E', 'E', '\0'};

enum {
  MTREE_HEADER_BYTES = 32,
  MTREE_ENDIAN_MARKER = 0x01020304,
  // Smallest possible encoding of each record: used to reject a corrupt count
  // before it turns into a huge allocation.
  MTREE_NODE_MIN_BYTES = 20 * 8 + 6 * 4 + 3 * 4,
  MTREE_POSITION_BYTES = 3 * 8,
  MTREE_CORNER_BYTES = 4 + 9 * 4,
  MTREE_TRIANGLE_BYTES = 3 * 4 + 1 + 4,
  MTREE_BOND_BYTES = 2 * 4 + 7 * 8,
};

// A cache file is a convenience; anything this large is far more likely to be
// the wrong file than a real tree.
#define MTREE_MAX_FILE_BYTES ((uint64_t)4 << 30)

// ---------------------------------------------------------------- writing

static void put_mesh(bk_byte_writer* w, const bk_mesh* m) {
  bk_put_u32(w, m->position_count);
  bk_put_u32(w, m->corner_count);
  bk_put_u32(w, m->triangle_count);
  for (uint32_t i = 0; i < m->position_count; ++i)
    bk_put_vec3(w, m->positions[i]);
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const bk_corner* c = &m->corners[i];
    bk_put_u32(w, c->position);
    for (int k = 0; k < 3; ++k)
      bk_put_f32(w, c->normal[k]);
    for (int k = 0; k < 2; ++k)
      bk_put_f32(w, c->uv[k]);
    for (int k = 0; k < 4; ++k)
      bk_put_f32(w, c->tangent[k]);
  }
  for (uint32_t i = 0; i < 3 * m->triangle_count; ++i)
    bk_put_u32(w, m->indices[i]);
  for (uint32_t i = 0; i < m->triangle_count; ++i)
    bk_put_u8(w, m->materials[i]);
  for (uint32_t i = 0; i < m->triangle_count; ++i)
    bk_put_u32(w, m->tags[i]);
}

static void put_node(bk_byte_writer* w, const bk_mesh_tree_node* n) {
  bk_put_vec3(w, n->bounds.min);
  bk_put_vec3(w, n->bounds.max);
  const bk_moments* mo = &n->moments;
  const double moments[10] = {mo->v, mo->x, mo->y, mo->z, mo->xx, mo->yy, mo->zz, mo->xy, mo->yz, mo->zx};
  for (int k = 0; k < 10; ++k)
    bk_put_f64(w, moments[k]);
  bk_put_vec3(w, n->plane.normal);
  bk_put_f64(w, n->plane.offset);
  bk_put_u32(w, n->parent);
  bk_put_u32(w, n->first_child);
  bk_put_u32(w, n->child_count);
  bk_put_u32(w, n->leaf_begin);
  bk_put_u32(w, n->leaf_end);
  bk_put_u32(w, n->depth);
  put_mesh(w, &n->mesh);
}

static void put_payload(bk_byte_writer* w, const bk_mesh_tree* tree) {
  bk_put_u64(w, tree->source_hash);
  bk_put_u32(w, tree->desc.pieces);
  bk_put_u64(w, tree->desc.seed);
  bk_put_f64(w, tree->desc.texture_scale);
  bk_put_f64(w, tree->desc.jitter);
  bk_put_f64(w, tree->desc.aspect_bias);
  const bk_fracture_def* d = &tree->desc;
  bk_put_u32(w, (uint32_t)d->pattern);
  bk_put_u32(w, d->seed_point_count);
  bk_put_u32(w, d->clusters);
  bk_put_f64(w, d->cluster_border);
  bk_put_vec3(w, d->impact);
  bk_put_f64(w, d->radial_falloff);
  bk_put_vec3(w, d->brick_size);
  bk_put_vec3(w, d->brick_origin);
  bk_put_f64(w, d->brick_offset);
  bk_put_u32(w, d->cutout_width);
  bk_put_u32(w, d->cutout_height);
  bk_put_u32(w, d->cutout_axis);
  bk_put_f64(w, d->noise_amplitude);
  bk_put_f64(w, d->noise_frequency);
  bk_put_u32(w, tree->max_depth);
  bk_put_u32(w, tree->node_count);
  bk_put_u32(w, tree->leaf_count);
  bk_put_u32(w, tree->bond_count);
  for (uint32_t i = 0; i < tree->node_count; ++i)
    put_node(w, &tree->nodes[i]);
  for (uint32_t i = 0; i < tree->leaf_count; ++i)
    bk_put_u32(w, tree->leaf_nodes[i]);
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* b = &tree->bonds[i];
    bk_put_u32(w, b->leaf_a);
    bk_put_u32(w, b->leaf_b);
    bk_put_f64(w, b->area);
    bk_put_vec3(w, b->centroid);
    bk_put_vec3(w, b->normal);
  }
}

// ---------------------------------------------------------------- save

// The tree cache reports every write failure the same way.
static const bk_atomic_messages mtree_write_messages = {"cannot write", "cannot write", "cannot write"};

static bool write_file(const char* path, const uint8_t* data, size_t size, bk_error* err) {
  // Write beside the target and rename over it, so an existing file is never half-overwritten.
  bk_atomic_file file = {0};
  if (!bk_file_begin_atomic(path, &mtree_write_messages, &file, err)) return false;
  fwrite(data, 1, size, file.stream); // a short write leaves the stream in error, which commit reports
  return bk_file_commit_atomic(&file, path, &mtree_write_messages, err);
}

bool bk_mesh_tree_save(const bk_mesh_tree* tree, const char* path, bk_error* err) {
  uint8_t* data = NULL;
  size_t size = 0;
  if (!bk_mesh_tree_save_memory(tree, path, &data, &size, err)) return false;
  bool ok = write_file(path, data, size, err);
  bk_free(data);
  return ok;
}

bool bk_mesh_tree_save_memory(const bk_mesh_tree* tree, const char* name, uint8_t** data, size_t* size,
                              bk_error* err) {
  *data = NULL;
  *size = 0;
  const char* path = name;
  // Save never writes a file that load would refuse.
  bk_error why = {{0}};
  if (!bk_mesh_tree_validate(tree, &why))
    return bk_error_set(err, "%s: cannot save an invalid mesh tree: %s", path, why.message);

  bk_byte_writer w = {.grows = true};
  bk_bytes_room(&w, MTREE_HEADER_BYTES); // filled once the payload's size and checksum are known
  put_payload(&w, tree);
  uint64_t payload_size = (uint64_t)(w.size - MTREE_HEADER_BYTES);
  if ((uint64_t)w.size > MTREE_MAX_FILE_BYTES) {
    bk_free(w.out);
    return bk_error_set(err, "%s: mesh tree is too large to cache (%" PRIu64 " bytes, limit %" PRIu64 ")",
                        path, (uint64_t)w.size, MTREE_MAX_FILE_BYTES);
  }
  memcpy(w.out, mtree_magic, sizeof mtree_magic);
  bk_store_u32(w.out + 8, BK_MTREE_VERSION);
  bk_store_u32(w.out + 12, MTREE_ENDIAN_MARKER);
  bk_store_u64(w.out + 16, payload_size);
  bk_store_u64(w.out + 24, bk_hash_bytes(BK_FNV_OFFSET, w.out + MTREE_HEADER_BYTES, (size_t)payload_size));
  *data = w.out;
  *size = w.size;
  return true;
}

// ---------------------------------------------------------------- load

// Bounds-checked cursor over the payload. Reading past the end returns zeros
// and sets `overrun`; callers check it after each record, and every count is
// checked against remaining() before anything is allocated from it.
typedef struct byte_reader {
  const uint8_t* data;
  size_t size, pos;
  bool overrun;
} byte_reader;

static size_t remaining(const byte_reader* r) { return r->size - r->pos; }

static const uint8_t* take(byte_reader* r, size_t n) {
  if (r->overrun || n > remaining(r)) {
    r->overrun = true;
    return NULL;
  }
  const uint8_t* p = r->data + r->pos;
  r->pos += n;
  return p;
}

static uint8_t get_u8(byte_reader* r) {
  const uint8_t* p = take(r, 1);
  return p ? p[0] : 0;
}

static uint32_t get_u32(byte_reader* r) {
  const uint8_t* p = take(r, 4);
  return p ? bk_load_u32(p) : 0;
}

static uint64_t get_u64(byte_reader* r) {
  const uint8_t* p = take(r, 8);
  return p ? bk_load_u64(p) : 0;
}

static float get_f32(byte_reader* r) {
  uint32_t bits = get_u32(r);
  float v = 0.0f;
  memcpy(&v, &bits, sizeof v);
  return v;
}

static double get_f64(byte_reader* r) {
  uint64_t bits = get_u64(r);
  double v = 0.0;
  memcpy(&v, &bits, sizeof v);
  return v;
}

static bk_vec3 get_vec3(byte_reader* r) {
  bk_vec3 v = {0};
  v.x = get_f64(r);
  v.y = get_f64(r);
  v.z = get_f64(r);
  return v;
}

__attribute__((format(printf, 3, 4))) static bool corrupt(bk_error* err, const char* path, const char* fmt,
                                                          ...) {
  char what[400] = {0};
  va_list args;
  va_start(args, fmt);
  vsnprintf(what, sizeof what, fmt, args);
  va_end(args);
  return bk_error_set(err, "%s: corrupt: %s", path, what);
}

static bool get_mesh(byte_reader* r, bk_mesh* m, uint32_t node, const char* path, bk_error* err) {
  uint32_t positions = get_u32(r), corners = get_u32(r), triangles = get_u32(r);
  if (r->overrun) return corrupt(err, path, "payload ends inside node %u", node);
  uint64_t need = (uint64_t)positions * MTREE_POSITION_BYTES + (uint64_t)corners * MTREE_CORNER_BYTES +
                  (uint64_t)triangles * MTREE_TRIANGLE_BYTES;
  if (need > remaining(r))
    return corrupt(err, path,
                   "node %u mesh (%u positions, %u corners, %u triangles) needs %" PRIu64
                   " bytes but %zu remain",
                   node, positions, corners, triangles, need, remaining(r));
  // Exact sizes: a loaded mesh is not grown in place, so capacities equal counts.
  if (positions) m->positions = bk_alloc(sizeof(bk_vec3) * positions);
  if (corners) m->corners = bk_alloc(sizeof(bk_corner) * corners);
  if (triangles) {
    m->indices = bk_alloc(sizeof(uint32_t) * 3u * (size_t)triangles);
    m->materials = bk_alloc(triangles);
    m->tags = bk_alloc(sizeof(uint32_t) * triangles);
  }
  m->position_count = m->position_capacity = positions;
  m->corner_count = m->corner_capacity = corners;
  m->triangle_count = m->triangle_capacity = triangles;
  for (uint32_t i = 0; i < positions; ++i)
    m->positions[i] = get_vec3(r);
  for (uint32_t i = 0; i < corners; ++i) {
    bk_corner* c = &m->corners[i];
    c->position = get_u32(r);
    for (int k = 0; k < 3; ++k)
      c->normal[k] = get_f32(r);
    for (int k = 0; k < 2; ++k)
      c->uv[k] = get_f32(r);
    for (int k = 0; k < 4; ++k)
      c->tangent[k] = get_f32(r);
  }
  for (size_t i = 0; i < 3u * (size_t)triangles; ++i)
    m->indices[i] = get_u32(r);
  for (uint32_t i = 0; i < triangles; ++i)
    m->materials[i] = get_u8(r);
  for (uint32_t i = 0; i < triangles; ++i)
    m->tags[i] = get_u32(r);
  // Cannot overrun after the size check above; kept so a layout change cannot silently read zeros.
  if (r->overrun) return corrupt(err, path, "payload ends inside the mesh of node %u", node);
  return true;
}

static bool get_node(byte_reader* r, bk_mesh_tree_node* n, uint32_t index, const char* path, bk_error* err) {
  n->bounds.min = get_vec3(r);
  n->bounds.max = get_vec3(r);
  bk_moments* mo = &n->moments;
  double* const moments[10] = {&mo->v,  &mo->x,  &mo->y,  &mo->z,  &mo->xx,
                               &mo->yy, &mo->zz, &mo->xy, &mo->yz, &mo->zx};
  for (int k = 0; k < 10; ++k)
    *moments[k] = get_f64(r);
  n->plane.normal = get_vec3(r);
  n->plane.offset = get_f64(r);
  n->parent = get_u32(r);
  n->first_child = get_u32(r);
  n->child_count = get_u32(r);
  n->leaf_begin = get_u32(r);
  n->leaf_end = get_u32(r);
  n->depth = get_u32(r);
  if (r->overrun) return corrupt(err, path, "payload ends inside node %u", index);
  return get_mesh(r, &n->mesh, index, path, err);
}

// Parses the payload into *t (zeroed by the caller). On failure *t may hold
// partial allocations; node_count always covers every allocated node, so
// bk_mesh_tree_free releases them.
static bool parse_payload(byte_reader* r, bk_mesh_tree* t, const char* path, bk_error* err) {
  t->source_hash = get_u64(r);
  t->desc.pieces = get_u32(r);
  t->desc.seed = get_u64(r);
  t->desc.texture_scale = get_f64(r);
  t->desc.jitter = get_f64(r);
  t->desc.aspect_bias = get_f64(r);
  bk_fracture_def* d = &t->desc;
  uint32_t pattern = get_u32(r); // checked below, before it is stored as an enum
  d->seed_point_count = get_u32(r);
  d->clusters = get_u32(r);
  d->cluster_border = get_f64(r);
  d->impact = get_vec3(r);
  d->radial_falloff = get_f64(r);
  d->brick_size = get_vec3(r);
  d->brick_origin = get_vec3(r);
  d->brick_offset = get_f64(r);
  d->cutout_width = get_u32(r);
  d->cutout_height = get_u32(r);
  d->cutout_axis = get_u32(r);
  d->noise_amplitude = get_f64(r);
  d->noise_frequency = get_f64(r);
  t->max_depth = get_u32(r);
  uint32_t nodes = get_u32(r), leaves = get_u32(r), bonds = get_u32(r);
  if (r->overrun) return corrupt(err, path, "payload ends inside the tree header");
  // Checked here so the message names the stored value; an out-of-range value never becomes the enum.
  if (pattern >= BK_PATTERN_COUNT)
    return corrupt(err, path, "fracture: pattern = %" PRIu32 " is not a pattern (0 to %d)", pattern,
                   BK_PATTERN_COUNT - 1);
  d->pattern = (bk_fracture_pattern)pattern;
  uint64_t need =
      (uint64_t)nodes * MTREE_NODE_MIN_BYTES + (uint64_t)leaves * 4u + (uint64_t)bonds * MTREE_BOND_BYTES;
  if (need > remaining(r))
    return corrupt(err, path,
                   "%u nodes, %u leaves and %u bonds need at least %" PRIu64 " bytes but %zu remain", nodes,
                   leaves, bonds, need, remaining(r));
  if (nodes == 0) return corrupt(err, path, "the tree has no nodes");
  if (leaves == 0 || leaves > nodes) return corrupt(err, path, "%u leaves for %u nodes", leaves, nodes);

  // Zeroed nodes have empty meshes, so freeing after a failure part-way is safe.
  t->nodes = bk_calloc(nodes, sizeof(bk_mesh_tree_node));
  t->node_count = nodes;
  for (uint32_t i = 0; i < nodes; ++i)
    if (!get_node(r, &t->nodes[i], i, path, err)) return false;

  // Recheck: the meshes consumed bytes the first estimate did not know about.
  if ((uint64_t)leaves * 4u + (uint64_t)bonds * MTREE_BOND_BYTES > remaining(r))
    return corrupt(err, path, "payload ends before the %u leaves and %u bonds", leaves, bonds);
  t->leaf_nodes = bk_alloc(sizeof(uint32_t) * leaves);
  t->leaf_count = leaves;
  for (uint32_t i = 0; i < leaves; ++i)
    t->leaf_nodes[i] = get_u32(r);
  if (bonds) t->bonds = bk_alloc(sizeof(bk_bond) * bonds);
  t->bond_count = bonds;
  for (uint32_t i = 0; i < bonds; ++i) {
    bk_bond* b = &t->bonds[i];
    b->leaf_a = get_u32(r);
    b->leaf_b = get_u32(r);
    b->area = get_f64(r);
    b->centroid = get_vec3(r);
    b->normal = get_vec3(r);
  }
  if (r->overrun) return corrupt(err, path, "payload ends inside the leaves or bonds");
  if (remaining(r) != 0) return corrupt(err, path, "%zu unexpected bytes after the bonds", remaining(r));

  bk_error why = {{0}};
  if (!bk_mesh_tree_validate(t, &why)) return corrupt(err, path, "%s", why.message);
  return true;
}

// Checks the header in a fixed order so each kind of damage gets its own message.
static bool check_header(const uint8_t* data, size_t size, const char* path, bk_error* err) {
  if (size < MTREE_HEADER_BYTES) return bk_error_set(err, "%s: truncated header (%zu bytes)", path, size);
  if (memcmp(data, mtree_magic, sizeof mtree_magic) != 0)
    return bk_error_set(err, "%s: not a mesh tree file (bad magic)", path);
  uint32_t version = bk_load_u32(data + 8), marker = bk_load_u32(data + 12);
  // A file from a big-endian writer would misread its version as well; name the real cause.
  bool swapped = marker == 0x04030201u;
  if (version != BK_MTREE_VERSION && !swapped)
    return bk_error_set(err, "%s: mesh tree version %" PRIu32 " is not supported (expected %u)", path,
                        version, BK_MTREE_VERSION);
  if (marker != MTREE_ENDIAN_MARKER)
    return bk_error_set(
        err, "%s: wrong byte order (marker 0x%08" PRIx32 ", expected 0x%08x): written by a %s", path, marker,
        (unsigned)MTREE_ENDIAN_MARKER, swapped ? "big-endian writer" : "different or damaged writer");
  uint64_t declared = bk_load_u64(data + 16), actual = (uint64_t)(size - MTREE_HEADER_BYTES);
  if (actual < declared)
    return bk_error_set(err, "%s: truncated: payload is %" PRIu64 " bytes, header says %" PRIu64, path,
                        actual, declared);
  if (actual > declared)
    return bk_error_set(err, "%s: corrupt: payload is %" PRIu64 " bytes, header says %" PRIu64, path, actual,
                        declared);
  if (bk_hash_bytes(BK_FNV_OFFSET, data + MTREE_HEADER_BYTES, (size_t)actual) != bk_load_u64(data + 24))
    return bk_error_set(err, "%s: checksum mismatch (file is corrupt)", path);
  return true;
}

bool bk_mesh_tree_load(const char* path, bk_mesh_tree* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  void* contents = NULL;
  size_t size = 0;
  if (!bk_file_read(path, MTREE_MAX_FILE_BYTES, "4 GiB", &contents, &size, err)) return false;
  bool ok = bk_mesh_tree_load_memory(contents, size, path, out, err);
  bk_free(contents);
  return ok;
}

bool bk_mesh_tree_load_memory(const void* contents, size_t size, const char* name, bk_mesh_tree* out,
                              bk_error* err) {
  memset(out, 0, sizeof *out);
  const char* path = name;
  const uint8_t* data = contents;
  bool ok = check_header(data, size, path, err);
  bk_mesh_tree tree = {0};
  if (ok) {
    byte_reader r = {.data = data + MTREE_HEADER_BYTES, .size = size - MTREE_HEADER_BYTES, .pos = 0};
    ok = parse_payload(&r, &tree, path, err);
  }
  if (!ok) {
    bk_mesh_tree_free(&tree); // never hand out a half-loaded tree
    return false;
  }
  *out = tree;
  return true;
}
