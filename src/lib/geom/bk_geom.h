// geom (private): the utilities authoring's files share (random numbers,
// index maps, hashing, heaps, checked allocation, whole-file reads and atomic
// writes). Not installed: the public API is <breakables/authoring.h>.
#pragma once

#include <locale.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include <breakables/authoring.h>

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- utilities

/// PCG32 random generator: deterministic across platforms for a given seed.
typedef struct bk_rng {
  uint64_t state, inc;
} bk_rng;

/// Seeds a generator.
bk_rng bk_rng_seed(uint64_t seed, uint64_t stream);
/// Next 32 random bits.
uint32_t bk_rng_next(bk_rng* rng);
/// Uniform double in [0, 1).
double bk_rng_unit(bk_rng* rng);
/// Uniformly distributed unit vector.
bk_vec3 bk_rng_direction(bk_rng* rng);

/// Open-addressing map from 64-bit keys to 32-bit values, for index-based
/// topology lookups (edge -> new vertex, directed edge -> triangle).
/// UINT64_MAX marks empty slots and is not a valid key.
typedef struct bk_index_map {
  uint64_t* keys;
  uint32_t* values;
  uint32_t count, capacity; ///< capacity is a power of two
} bk_index_map;

/// Prepares a map for about `expected` keys (may be 0).
void bk_index_map_init(bk_index_map* map, uint32_t expected);
/// Releases the map.
void bk_index_map_free(bk_index_map* map);
/// Removes every key (shrinking storage that the last use left mostly empty).
void bk_index_map_clear(bk_index_map* map);
/// Returns a pointer to the value of key, inserting `value` first if absent;
/// *inserted tells which happened. The pointer is valid until the next insert.
uint32_t* bk_index_map_insert(bk_index_map* map, uint64_t key, uint32_t value, bool* inserted);
/// Returns the value of key or NULL.
uint32_t* bk_index_map_find(const bk_index_map* map, uint64_t key);

/// Key of the undirected edge {a, b}.
static inline uint64_t bk_edge_key(uint32_t a, uint32_t b) {
  return a < b ? ((uint64_t)a << 32) | b : ((uint64_t)b << 32) | a;
}
/// Key of the directed edge a -> b.
static inline uint64_t bk_directed_edge_key(uint32_t a, uint32_t b) { return ((uint64_t)a << 32) | b; }

/// fmin and fmax as glibc computes them (a NaN loses; of equal values, such
/// as 0 and -0, the first), without the call.
static inline double bk_min(double x, double y) { return (y < x || x != x) ? y : x; }
static inline double bk_max(double x, double y) { return (y > x || x != x) ? y : x; }

/// A copy of `src` into `dst` (overwritten, not freed) whose arrays hold
/// exactly its contents: for meshes that are kept (a tree's nodes) but
/// built in storage that is reused.
void bk_mesh_copy_exact(bk_mesh* dst, const bk_mesh* src);

/// Half-edges: h = 3t + k runs from corner k of triangle t to corner k + 1.
static inline uint32_t bk_half_next(uint32_t h) { return h % 3u == 2u ? h - 2u : h + 1u; }
static inline uint32_t bk_half_prev(uint32_t h) { return h % 3u == 0u ? h + 2u : h - 1u; }

/// A mesh's half-edges grouped by the position they start at, for topology
/// tests that scan a vertex's few neighbours instead of hashing edges.
/// Reused between meshes; zero-initialised is empty.
typedef struct bk_topology_scratch {
  uint32_t* start;  ///< per position + 1: first entry of its group in `around`
  uint32_t* mark;   ///< per position, free for the caller between groupings
  uint32_t* from;   ///< per half-edge: its start position
  uint32_t* around; ///< half-edges by start position, each group in increasing h
  uint32_t position_capacity, half_capacity;
} bk_topology_scratch;

/// Fills `from`, `start` and `around` for `mesh`.
void bk_topology_group(bk_topology_scratch* scratch, const bk_mesh* mesh);
/// bk_mesh_is_closed with reused storage.
bool bk_mesh_is_closed_with(const bk_mesh* mesh, bk_topology_scratch* scratch);
void bk_topology_scratch_free(bk_topology_scratch* scratch);

/// 64-bit FNV-1a over bytes, continuing from `hash` (start with BK_FNV_OFFSET).
uint64_t bk_hash_bytes(uint64_t hash, const void* data, size_t size);
#define BK_FNV_OFFSET 0xcbf29ce484222325ull

/// One entry of a bk_heap.
typedef struct bk_heap_item {
  double key;
  uint32_t value;
} bk_heap_item;

/// Binary min-heap: smallest key first, equal keys by smallest value (so the
/// order is deterministic). Zero-initialised is empty.
typedef struct bk_heap {
  bk_heap_item* items;
  uint32_t count, capacity;
} bk_heap;

/// Adds a pair.
void bk_heap_push(bk_heap* heap, double key, uint32_t value);
/// Removes and returns the first pair; the heap must not be empty.
bk_heap_item bk_heap_pop(bk_heap* heap);
/// Releases the heap's storage and empties it.
void bk_heap_free(bk_heap* heap);

/// This thread in the C locale's number format, for reading and writing text
/// files whatever locale the host application chose ("0.5", never "0,5").
typedef struct bk_c_locale {
  locale_t c, previous;
} bk_c_locale;

/// Switches; does nothing if the C locale cannot be made.
bk_c_locale bk_c_locale_begin(void);
/// Restores what the thread had.
void bk_c_locale_end(bk_c_locale* locale);

/// Growth helper: returns a capacity >= need (doubling), aborting on overflow.
uint32_t bk_grow_capacity(uint32_t current, uint32_t need);
/// malloc/realloc that abort with a message on exhaustion (geometry code has no partial states to recover).
void* bk_alloc(size_t size);
void* bk_realloc(void* ptr, size_t size);
void* bk_calloc(size_t count, size_t size);

/// Longest material name an OBJ file's `usemtl` keeps (with the NUL).
#define BK_OBJ_MATERIAL_NAME 64
/// The materials an OBJ file names.
typedef struct bk_obj_materials {
  char names[BK_MATERIAL_SOURCES_MAX][BK_OBJ_MATERIAL_NAME]; ///< by source id ("" = faces before any usemtl)
  uint32_t count;                                            ///< 0 when the file has no usemtl
  uint32_t merged;                                           ///< usemtl names past the limit, given id 0
  char library[512];                                         ///< the first `mtllib` file, as written
} bk_obj_materials;
/// bk_obj_parse that also reports the `usemtl` names (their ids are the
/// triangles' source materials) and the `mtllib` file.
bool bk_obj_parse_materials(const char* text, size_t length, const char* name, bk_mesh* out,
                            bk_obj_materials* materials, bk_error* err);
/// Reads an MTL file's text into `list` (one entry per name in `materials`,
/// zeroed or filled before): each named material's `Kd` (and `d` or `Tr`)
/// colour and `map_Kd` file name, as written. Unknown statements and values
/// that are not finite numbers in [0, 1] are skipped, as a renderer would.
void bk_mtl_parse(const char* text, size_t length, const bk_obj_materials* materials,
                  bk_import_material* list);

/// The format of an image file's bytes, told by its signature: "png",
/// "jpeg" (glTF 2.0's core image formats) or NULL for anything else.
const char* bk_image_format(const void* data, size_t size);
/// Encodes `width` x `height` RGBA pixels as a PNG file's bytes (*png,
/// released with free); false if they cannot be.
bool bk_png_encode_rgba(const uint8_t* rgba, uint32_t width, uint32_t height, uint8_t** png, size_t* size);
/// The most pixels an image converted or drawn may have (256 MiB as RGBA).
#define BK_IMAGE_MAX_PIXELS ((uint64_t)1 << 26)
/// Converts a TGA, BMP or GIF image (read by stb_image; no more than 16384
/// pixels a side nor BK_IMAGE_MAX_PIXELS in all) to a PNG file's bytes (*png, released with free), for a
/// glTF export, whose images must be PNG or JPEG. False (nothing allocated)
/// for bytes that are none of these or cannot be decoded.
bool bk_image_convert_to_png(const void* data, size_t size, uint8_t** png, size_t* png_size);

/// Opens a file for reading only when it is a regular file: anything else is
/// refused without blocking ("<path>: is a directory", "<path>: is not a
/// regular file"; a FIFO or a device is never opened). `size` (may be NULL)
/// gets its size. NULL with the reason in `err` otherwise.
FILE* bk_file_open_read(const char* path, uint64_t* size, bk_error* err);
/// bk_file_open_read's checks for a reader that opens the file itself (assimp).
bool bk_file_check_read(const char* path, bk_error* err);
/// Checks, before any work, that bk_file_begin_atomic may replace `path`: its
/// directory exists and takes new files, and the target, if there, is a
/// regular file whose mode bits let this process write it (for root: any
/// write bit), so a read-only file is never replaced. One-line reason otherwise.
bool bk_file_check_write(const char* path, bk_error* err);
/// The part of bk_file_check_write about the target itself (bk_file_begin_atomic applies it).
bool bk_file_check_target(const char* path, bk_error* err);
/// Whether two paths name the same file: by device and inode when both
/// exist (symlinks and hard links included), else by their normalised
/// absolute names ("./x" and "x" are the same).
bool bk_file_same(const char* a, const char* b);
/// Copies `length` bytes of text to `out` (NUL-terminated, at most size - 1
/// bytes) with every byte a terminal could act on (controls, invalid UTF-8,
/// C1 controls) written as \xNN. Returns how many bytes of text it took.
/// bk_error_set applies it to every message, so text quoted from a file
/// never reaches a terminal raw.
size_t bk_escape_text(const char* text, size_t length, char* out, size_t size);

/// Reads a whole regular file (bk_file_open_read) into a fresh buffer (free
/// it with free()). Files over max_bytes are refused, before anything is
/// allocated, with "<path>: file larger than <limit_text>, refusing to load";
/// limit_text lets each caller name its limit ("1 GiB").
bool bk_file_read(const char* path, uint64_t max_bytes, const char* limit_text, void** data, size_t* size,
                  bk_error* err);

/// Wording of atomic-write failures; each message reads "<path>: <text>: <reason>".
typedef struct bk_atomic_messages {
  const char* open_failed;   ///< the temporary file could not be created
  const char* write_failed;  ///< writing, flushing, syncing or closing failed
  const char* rename_failed; ///< the temporary could not replace the target
} bk_atomic_messages;

/// A file being written beside its target, to replace the target atomically.
typedef struct bk_atomic_file {
  FILE* stream;   ///< write the new contents here
  char* tmp_path; ///< the temporary's name (owned; released by bk_file_commit_atomic)
} bk_atomic_file;

/// Starts replacing `path` atomically: creates a temporary file with a new,
/// unique name in the same directory, exclusively (a file or symlink already
/// there is never opened or followed), with the permissions a new file gets
/// (0666 less the umask). Readers see either the old file or the complete new
/// one, never a partial write, and concurrent writers never share a
/// temporary. A target bk_file_check_write refuses (read-only, a directory,
/// not a regular file) is never replaced. Returns false (err filled, nothing
/// created) on failure. Every file the project writes goes through here.
bool bk_file_begin_atomic(const char* path, const bk_atomic_messages* messages, bk_atomic_file* out,
                          bk_error* err);
/// Finishes a write begun by bk_file_begin_atomic: checks the stream, flushes,
/// syncs, closes and renames over `path`. Always consumes the file; on any
/// failure the temporary is removed and the target left as it was.
bool bk_file_commit_atomic(bk_atomic_file* file, const char* path, const bk_atomic_messages* messages,
                           bk_error* err);
/// Abandons a write begun by bk_file_begin_atomic: the temporary is removed
/// and the target left as it was.
void bk_file_abort_atomic(bk_atomic_file* file);

// ---------------------------------------------------------------- shapes

/// Most corners an extruded polygon may have (the caps' ears are kept on the stack).
#define BK_EXTRUSION_MAX_CORNERS 64

/// A prism: a simple polygon in the plane of x_axis and y_axis, extruded
/// along depth = x_axis x y_axis from depth_from to depth_to.
typedef struct bk_extrusion {
  const double (*profile)[2];  ///< the polygon's corners (x, y), counter-clockwise, edges not crossing
  uint32_t corner_count;       ///< 3 to BK_EXTRUSION_MAX_CORNERS
  bk_vec3 x_axis, y_axis;      ///< orthonormal world directions of the profile's coordinates
  double depth_from, depth_to; ///< the prism's extent along depth; depth_to > depth_from
} bk_extrusion;

/// Appends the prism to `m`: 2n positions, a flat quad (4 corners) per edge
/// and two caps of n - 2 ear triangles on the polygon's own corners, so
/// 6n corners and 4n - 4 triangles, closed by topology and facing out. uvs
/// are in metres like the boxes' (world coordinates along each face, v up
/// on vertical faces); tangents are left for bk_mesh_compute_tangents.
/// False (nothing added) when the polygon has too few or too many corners,
/// the depth is empty, or ear clipping finds no ear (a clockwise polygon,
/// most that cross themselves: a simple counter-clockwise one always has one).
bool bk_shape_extrude(bk_mesh* m, const bk_extrusion* def);

#ifdef __cplusplus
}
#endif
