// Breakables authoring (breakables::authoring): indexed triangle meshes,
// procedural shapes, OBJ input and output, exact mass properties, plane
// slicing with triangulated caps, the mesh tree (root = source mesh, leaves =
// fragments), bonds between touching fragments and the .mtree cache file.
// Pure C: no GL context, no window, no physics engine.
#pragma once

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "base.h"
#include "types.h"

#ifdef __cplusplus
extern "C" {
#endif

// ---------------------------------------------------------------- meshes

/// Material ids stored per triangle: bit 0 tells the faces created by cuts
/// (caps) from the source's own surface, the bits above it which source
/// material the triangle belongs to (an index into the import's
/// bk_import_info.material_list; 0 for a one-material mesh). A cap takes the
/// source material of the surface it cuts through, so each source material
/// has two ids: its surface and its interior.
enum {
  BK_MATERIAL_OUTER = 0,         ///< source material 0's surface
  BK_MATERIAL_INTERIOR = 1,      ///< source material 0's cut faces
  BK_MATERIAL_SOURCES_MAX = 128, ///< source materials a mesh can tell apart
};

/// The material id of source material `source` (< BK_MATERIAL_SOURCES_MAX):
/// its cut faces when `interior`, else its surface.
static inline uint8_t bk_material_id(uint32_t source, bool interior) {
  return (uint8_t)((source & (BK_MATERIAL_SOURCES_MAX - 1)) << 1 | (interior ? 1u : 0u));
}
/// True for the id of a cut face.
static inline bool bk_material_is_interior(uint8_t id) { return (id & 1u) != 0; }
/// The source material an id belongs to.
static inline uint32_t bk_material_source(uint8_t id) { return (uint32_t)id >> 1; }

/// One triangle corner's attributes. Corners index welded positions, so two
/// corners at a UV or normal seam share the position and topology stays closed.
typedef struct bk_corner {
  uint32_t position; ///< index into bk_mesh.positions: this carries topology
  float normal[3];
  float uv[2];
  float tangent[4]; ///< xyz along +u, w = handedness of the bitangent (+1/-1)
} bk_corner;

/// Indexed triangle mesh. Triangles index corners; corners index positions.
/// Everything is owned; capacities let builders grow arrays in place.
typedef struct bk_mesh {
  bk_vec3* positions;
  bk_corner* corners;
  uint32_t* indices;  ///< 3 corner indices per triangle, counter-clockwise seen from outside
  uint8_t* materials; ///< per triangle: a material id (bk_material_id)
  uint32_t* tags;     ///< per triangle, copied through slicing (fracture: which cut made a cap; 0 = none)
  uint32_t position_count, position_capacity;
  uint32_t corner_count, corner_capacity;
  uint32_t triangle_count, triangle_capacity;
} bk_mesh;

/// Releases every array and zeroes the mesh; safe on a zeroed mesh.
void bk_mesh_free(bk_mesh* mesh);
/// Ensures room for at least the given counts (existing data kept).
void bk_mesh_reserve(bk_mesh* mesh, uint32_t positions, uint32_t corners, uint32_t triangles);
/// Appends a position and returns its index.
uint32_t bk_mesh_add_position(bk_mesh* mesh, bk_vec3 p);
/// Appends a corner and returns its index.
uint32_t bk_mesh_add_corner(bk_mesh* mesh, const bk_corner* c);
/// Appends a triangle of three corner indices.
void bk_mesh_add_triangle(bk_mesh* mesh, uint32_t a, uint32_t b, uint32_t c, uint8_t material, uint32_t tag);
/// Deep copy (dst is overwritten, not freed first).
void bk_mesh_copy(bk_mesh* dst, const bk_mesh* src);
/// Appends src to dst as separate geometry (indices offset). Used to export many fragments as one.
void bk_mesh_append(bk_mesh* dst, const bk_mesh* src);
/// Position index of corner k (0..2) of triangle t.
static inline uint32_t bk_mesh_tri_position(const bk_mesh* m, uint32_t t, uint32_t k) {
  return m->corners[m->indices[3 * t + k]].position;
}
/// Bounds of the positions; an empty mesh gives min > max.
bk_aabb bk_mesh_bounds(const bk_mesh* mesh);
/// Scales and moves the positions to a height of 1 (along y), standing on
/// y = 0 and centred in x and z: how the command line, the game and the web
/// page take the bundled bunny. A mesh of no height is left as it is.
void bk_mesh_fit_unit_height(bk_mesh* mesh);
/// Total surface area.
double bk_mesh_area(const bk_mesh* mesh);
/// Checks internal consistency: indices in range, finite positions and
/// attributes. Fills err naming the first problem.
bool bk_mesh_validate(const bk_mesh* mesh, bk_error* err);
/// Merges positions with bit-identical coordinates (after -0 == +0). Returns
/// how many positions were merged away.
uint32_t bk_mesh_weld(bk_mesh* mesh);
/// Computes smooth corner normals (area-weighted per position) for every corner.
void bk_mesh_compute_normals(bk_mesh* mesh);
/// Computes corner tangents from uvs and normals (falls back to any
/// direction orthogonal to the normal where the uv mapping is degenerate).
void bk_mesh_compute_tangents(bk_mesh* mesh);
/// A lighter copy of a closed mesh for drawing it small: edges collapse while
/// each survivor stays within `tolerance` of every original triangle plane it
/// stands for, never pinching the surface or turning a triangle over, and the
/// border between materials stays put. Corners keep their
/// attributes. Positions where the mesh is open or non-manifold never move.
/// `out` is overwritten (not freed first); returns its triangle count.
uint32_t bk_mesh_decimate(const bk_mesh* mesh, double tolerance, bk_mesh* out);
/// Stable 64-bit hash of the mesh's geometry and attributes (identifies cache files).
uint64_t bk_mesh_hash(const bk_mesh* mesh);

// ---------------------------------------------------------------- closure

/// Result of checking that every directed edge has exactly one opposite.
typedef struct bk_closure {
  uint32_t open_edges;     ///< directed edges with no opposite edge
  uint32_t overused_edges; ///< directed edges used by more than one triangle (bad orientation / non-manifold)
  uint32_t degenerate_edges; ///< triangles using one position twice
} bk_closure;

/// Counts the edges that break closure; all zero means watertight and consistently oriented.
bk_closure bk_mesh_check_closure(const bk_mesh* mesh);
/// True when bk_mesh_check_closure finds nothing wrong.
bool bk_mesh_is_closed(const bk_mesh* mesh);

// ---------------------------------------------------------------- mass properties

/// Raw volume moments of a closed mesh: integrals over the solid of
/// 1, x, y, z, x^2, y^2, z^2, xy, yz, zx. They add up across pieces, so any
/// set of mesh-tree nodes combines in O(nodes).
typedef struct bk_moments {
  double v;
  double x, y, z;
  double xx, yy, zz, xy, yz, zx;
} bk_moments;

/// Mass properties per unit density.
typedef struct bk_mass_properties {
  double volume;
  bk_vec3 centroid;
  double inertia[3][3]; ///< inertia tensor about the centroid (per unit density)
} bk_mass_properties;

/// Exact moments by the divergence theorem (double precision).
bk_moments bk_mesh_moments(const bk_mesh* mesh);
/// Sum of two sets of moments.
bk_moments bk_moments_add(bk_moments a, bk_moments b);
/// Volume, centroid and central inertia tensor from moments.
bk_mass_properties bk_moments_to_mass(bk_moments m);
/// Convenience: volume of a closed mesh.
double bk_mesh_volume(const bk_mesh* mesh);
/// Eigenvalues and eigenvectors (columns of `vectors`, a right-handed
/// rotation) of a symmetric 3x3 matrix: principal moments and axes of inertia.
void bk_sym3_eigen(const double m[3][3], double values[3], double vectors[3][3]);
/// Quaternion of a rotation matrix.
bk_quat bk_quat_from_matrix(const double r[3][3]);

// ---------------------------------------------------------------- shapes

/// Procedural test meshes, named as on the command line. All are closed.
typedef enum bk_shape {
  BK_SHAPE_CUBE,     ///< unit cube centred at the origin: 8 positions, 24 corners, 12 triangles
  BK_SHAPE_TORUS,    ///< ring torus: 20x20 segments, 441 corners, 800 triangles
  BK_SHAPE_EGGSHELL, ///< hollow egg: outer surface + inward-facing inner surface
  BK_SHAPE_WALL,     ///< thin brick-proportioned wall standing on y = 0
  BK_SHAPE_SLAB,     ///< flat stone slab lying on y = 0
  BK_SHAPE_PILLAR,   ///< tall octagonal pillar standing on y = 0
  BK_SHAPE_TOWER,    ///< square stone column 0.8 x 4 x 0.8 m standing on y = 0: 8 positions, 12 triangles
  /// Pi-shaped bridge standing on y = 0: a deck 5 m long (x), 1.2 m wide (z) and 0.3 m thick, its
  /// underside 1.5 m up, on two legs 0.5 m thick set 0.2 m in from its ends; 44 triangles
  BK_SHAPE_BRIDGE,
  /// balcony standing on y = 0: a wall 2.4 m wide (x), 3 m high and 0.3 m thick (z), with a slab
  /// 0.2 m thick, its top 2 m up, reaching 1.2 m out along +z; only the wall touches the ground; 28 triangles
  BK_SHAPE_BALCONY,
  BK_SHAPE_COUNT
} bk_shape;

/// Name used on the command line ("cube", "torus", ...).
const char* bk_shape_name(bk_shape shape);
/// Looks a shape up by name; false if unknown.
bool bk_shape_from_name(const char* name, bk_shape* out);
/// Builds a shape (out is overwritten).
void bk_shape_build(bk_shape shape, bk_mesh* out);

// ---------------------------------------------------------------- OBJ files

/// Parses OBJ text (v, vt, vn, f with negative indices; polygons fanned; o/g/s/usemtl
/// ignored). Positions are welded. Missing normals are computed, missing uvs
/// get a box projection, tangents are derived. `name` prefixes error messages.
bool bk_obj_parse(const char* text, size_t length, const char* name, bk_mesh* out, bk_error* err);
/// Reads and parses an OBJ file.
bool bk_obj_load(const char* path, bk_mesh* out, bk_error* err);
/// Writes meshes as one OBJ file with one `o fragment_<i>` object per mesh.
bool bk_obj_save(const char* path, const bk_mesh* meshes, uint32_t mesh_count, bk_error* err);

// ---------------------------------------------------------------- model import

/// The file extensions bk_model_import reads, space-separated, lower case
/// ("obj gltf glb fbx ..."). `.obj` is read by bk_obj_load (this library's own
/// reader); every other one by assimp (Open Asset Import Library, C API).
#define BK_IMPORT_EXTENSIONS "obj gltf glb fbx dae ply stl 3ds off 3mf blend x ac ase"
/// Files larger than this are refused before they are parsed.
#define BK_IMPORT_MAX_FILE_BYTES ((uint64_t)1 << 30)

/// How to import a model: bk_default_import_def() fills every field.
typedef struct bk_import_def {
  /// Name of the scene node to import, with its subtree, in that node's
  /// world placement; NULL (the default) = every node's meshes, combined with
  /// their node transforms. An unknown name is an error listing node names.
  const char* node;
  /// The most triangles (after triangulation) the model may have; default 2^24.
  uint32_t max_triangles;
  /// The most vertices, summed over every mesh placed; default 2^25.
  uint32_t max_vertices;
  /// Files larger than this many bytes are refused; default BK_IMPORT_MAX_FILE_BYTES.
  uint64_t max_file_bytes;
} bk_import_def;

/// Default import parameters: every node, 2^24 triangles, 2^25 vertices, 1 GiB.
bk_import_def bk_default_import_def(void);

/// Longest text kept in bk_import_info's strings (longer ones are cut).
#define BK_IMPORT_TEXT_MAX 512

/// One material of an imported model, as the file gives it.
typedef struct bk_import_material {
  char name[64];       ///< the file's name for it, cut to 63 bytes ("" when it has none)
  float base_color[4]; ///< base colour factor, RGBA (1, 1, 1, 1 when the file gives none)
  /// Base-colour texture file: a path resolved relative to the model file's
  /// directory, or "" when there is none or it is embedded.
  char texture[BK_IMPORT_TEXT_MAX];
  /// An embedded base-colour image (owned by the bk_import_info): PNG or
  /// JPEG bytes as the file holds them, or a TGA, BMP or GIF file or
  /// uncompressed texels the import encoded as PNG; NULL when there is none
  /// (or it is in another format: then image_unsupported).
  uint8_t* image;
  size_t image_size;
  char image_format[8];   ///< "png" or "jpeg" when image is set
  bool image_unsupported; ///< an embedded image in a format glTF cannot hold (e.g. "dds")
  uint32_t triangles;     ///< triangles of the mesh with this material
} bk_import_material;

/// What an import found (zeroed, then filled as far as the import got).
/// Release with bk_import_info_free when done (it owns material_list).
typedef struct bk_import_info {
  char format[32]; ///< the reader: "obj" (ours) or "assimp:<extension>"
  /// The materials the mesh's triangles use, in the order of their ids:
  /// triangles of material_list[k] have bk_material_source k. Files with
  /// more than BK_MATERIAL_SOURCES_MAX materials have the extra ones'
  /// triangles given the first material (counted in materials_merged).
  bk_import_material* material_list;
  uint32_t materials;            ///< entries in material_list (at least 1 after a successful import)
  uint32_t materials_merged;     ///< materials beyond BK_MATERIAL_SOURCES_MAX, merged into the first
  uint32_t dominant_material;    ///< the index of the material with the most triangles
  uint32_t meshes;               ///< mesh instances placed (a mesh used by two nodes counts twice)
  uint32_t nodes;                ///< nodes in the scene
  uint32_t nodes_used;           ///< nodes whose meshes were placed
  uint32_t triangles_in;         ///< triangles read (after triangulation)
  uint32_t dropped_primitives;   ///< point and line primitives dropped
  uint32_t degenerate_triangles; ///< triangles dropped because two corners share a welded position
  uint32_t mirrored_meshes;      ///< mesh instances under a mirroring transform (their winding reversed)
  uint32_t welded_positions;     ///< positions merged by welding (UV and normal seams)
  bool normals_computed;         ///< some corners had no normal in the file
  bool uvs_projected;            ///< some corners had no UV in the file (box projection)
  bool flipped;                  ///< the whole mesh was inside out (negative volume): winding reversed
  /// The file states its unit of length (FBX, glTF, Collada): the mesh is in
  /// metres, `metres_per_unit` applied. Else the file's numbers are kept.
  bool units_given;
  double metres_per_unit; ///< the scale the import applied (1 unless the file's unit is not the metre)
  /// How the file was read when that needs saying ("" if nothing): a PLY
  /// header line taken as a comment, a PLY header read by assimp.
  char note[200];
} bk_import_info;

/// Imports a model file as one welded bk_mesh: positions (double), normals
/// (computed where missing), UVs of the first channel (box projection where
/// missing) and tangents. A scene's meshes are combined with their node
/// transforms (or only def->node's subtree); points and lines are dropped,
/// polygons triangulated; a mesh under a mirroring transform keeps facing
/// out; a whole mesh that is inside out is turned right. The mesh is not
/// repaired: see bk_mesh_repair. Refuses with a one-line error naming the
/// file and the problem (missing, too large, unreadable or corrupt, an
/// index out of range, a non-finite or out-of-range coordinate, too many
/// triangles or vertices, no triangles, an unknown node). `def` NULL = the
/// defaults, `info` may be NULL. On failure *out is zeroed.
bool bk_model_import(const char* path, const bk_import_def* def, bk_mesh* out, bk_import_info* info,
                     bk_error* err);
/// bk_model_import from bytes in memory; `format` is the file extension to
/// read them as ("glb", "ply", ...; one of BK_IMPORT_EXTENSIONS) and `name`
/// prefixes error messages. External files (a .gltf's buffers, textures) are
/// not available this way.
bool bk_model_import_memory(const void* data, size_t size, const char* format, const char* name,
                            const bk_import_def* def, bk_mesh* out, bk_import_info* info, bk_error* err);
/// Releases what an import left in `info` (its material list) and zeroes
/// it; safe on a zeroed info.
void bk_import_info_free(bk_import_info* info);
/// True when `path`'s extension (any case) is one of BK_IMPORT_EXTENSIONS.
bool bk_model_import_supports(const char* path);

// ---------------------------------------------------------------- slicing

/// Reusable scratch state for slicing (buffers and the cap tessellator).
/// One per thread; create once and slice many meshes with it.
typedef struct bk_slicer bk_slicer;

/// Creates a slicer.
bk_slicer* bk_slicer_create(void);
/// Destroys a slicer; NULL is allowed.
void bk_slicer_destroy(bk_slicer* slicer);

/// How to slice one mesh.
typedef struct bk_slice_def {
  bk_plane plane;       ///< unit normal points from `below` to `above`
  double tolerance;     ///< vertices closer than this count as on the plane; 0 = 1e-9 x mesh size
  double texture_scale; ///< cap uv = plane coordinates / texture_scale (world size of one tile); 0 = 0.1
  double uv_origin[2];  ///< added to every cap uv (the uv of the plane basis's origin when slicing a shifted
                        ///< mesh)
  uint32_t cap_tag;     ///< tag written on the cap triangles (identifies the cut)
  /// > 0: the cap gets points inside it, about a third of a noise wave
  /// apart, pushed along the normal by coherent noise of this amplitude
  /// (mesh units), tapered to zero at its border and never more than a
  /// quarter of the thinner side's depth, so both sides stay closed and fit
  /// each other. 0 (the default): a flat cap.
  double noise_amplitude;
  double noise_frequency; ///< noise waves per mesh unit (> 0 when noise_amplitude is)
  uint64_t noise_seed;    ///< picks the noise pattern
} bk_slice_def;

/// Splits a closed mesh by a plane into the part below (signed distance < 0)
/// and above, each closed with a triangulated cap (ODD winding: holes and
/// islands in holes are handled). Topology is carried by indices: every cut
/// edge gets one new vertex shared by both sides. `below`/`above` are
/// overwritten; a side the plane misses comes back empty. Fails (with the
/// meshes freed) only if a cap cannot be closed.
bool bk_slicer_slice(bk_slicer* slicer, const bk_mesh* mesh, const bk_slice_def* def, bk_mesh* below,
                     bk_mesh* above, bk_error* err);

/// Triangulates simple boundary loops of an open mesh (a repair for
/// almost-closed inputs). Returns the number of loops filled, or -1 with err
/// set if the mesh cannot be closed this way (non-manifold edges, failed loop).
int bk_mesh_fill_holes(bk_mesh* mesh, bk_error* err);

/// Separates shells that touch at a vertex, along an edge or over a face
/// (whose two opposite copies use the same positions, as welding leaves
/// them): around every edge used by more than two triangles, the triangles
/// are paired with their angular neighbour that closes the solid (the
/// pairing of two closed shells touching there; of two coincident triangles
/// facing opposite ways, each pairs with its own shell's triangle), and
/// every position whose triangles then form several separate fans gets one
/// copy per fan. Afterwards each shell is closed (or open) on its own, and
/// bk_mesh_split_hulls tells them apart. Returns the number of positions
/// added.
uint32_t bk_mesh_split_nonmanifold(bk_mesh* mesh);

/// What bk_mesh_repair found and did.
typedef struct bk_repair_info {
  uint32_t open_edges;         ///< open edges before repair (after splitting)
  uint32_t positions_split;    ///< positions added by bk_mesh_split_nonmanifold
  uint32_t holes_closed;       ///< boundary loops filled by bk_mesh_fill_holes
  uint32_t shells;             ///< connected shells after repair
  uint32_t faces_turned;       ///< triangles wound against all their neighbours, turned
  uint32_t duplicates_removed; ///< triangles given twice (same positions, same turn), removed
  uint32_t sheets_removed;     ///< shells enclosing no volume (a face and its own back), removed
  bk_vec3 sheet_near;          ///< the middle of the first shell removed
} bk_repair_info;

/// Makes a mesh from an art tool fit for bk_mesh_tree_build when that is
/// possible: removes triangles given twice, turns single triangles and
/// patches of them wound against their neighbours, splits
/// shells touching at vertices, edges or faces, then fills
/// simple holes, and removes shells that then enclose no volume (unless all
/// do). What still is not closed is refused with the count and
/// location of the problem ("12 open edges, the first near (x, y, z)"); the
/// mesh is then left split but unfilled. `info` may be NULL.
bool bk_mesh_repair(bk_mesh* mesh, bk_repair_info* info, bk_error* err);

// ---------------------------------------------------------------- hulls

/// Separates a closed mesh into its connected solids. Cavities (inward-facing
/// closed components, e.g. the inside of an eggshell) stay with the solid that
/// contains them. Takes ownership of `mesh` (it is zeroed on return; a mesh
/// that is one hull is moved, not copied). Returns the number of meshes
/// written to *out (allocated; free each mesh and the array).
uint32_t bk_mesh_split_hulls(bk_mesh* mesh, bk_mesh** out);

// ---------------------------------------------------------------- mesh tree

/// How a source is cut into its pieces. Every pattern gives the same kind of
/// mesh tree: inner nodes are closed pieces (groups of adjacent leaves), every
/// node is watertight, leaf volumes add up to the source's and bonds are
/// measured on the leaves' shared cut faces.
typedef enum bk_fracture_pattern {
  BK_PATTERN_PLANES,    ///< random planes through the largest piece (the thesis's method)
  BK_PATTERN_VORONOI,   ///< Voronoi cells of seed points spread through the volume (or the caller's)
  BK_PATTERN_CLUSTERED, ///< a few large chunks whose borders are finely fractured
  BK_PATTERN_RADIAL,    ///< dense small pieces around an impact point, coarser with distance
  BK_PATTERN_BRICK,     ///< along the mortar of a brick bond, each brick then cut into a few pieces
  BK_PATTERN_CUTOUT,    ///< the regions of a fracture map (lines on an image) projected along an axis
  BK_PATTERN_COUNT
} bk_fracture_pattern;

/// The pattern's name as the command line spells it ("planes", "voronoi", ...);
/// "unknown" for a value out of range.
const char* bk_fracture_pattern_name(bk_fracture_pattern pattern);
/// The pattern named `name`; false when there is none.
bool bk_fracture_pattern_from_name(const char* name, bk_fracture_pattern* pattern);

/// Parameters of a fracture: bk_default_fracture_def() fills every field;
/// bk_fracture_def_validate (and the build) take them as given.
typedef struct bk_fracture_def {
  /// Leaf count, >= 1; default 256. Exactly this many come out, unless a
  /// piece cannot be cut (then fewer, see bk_fracture_shortfall). A cut
  /// through a concave piece, or one of separate shells (or a source with
  /// more overlapping shells than pieces), can make more pieces than the
  /// tree may still take: the nearest of them are then merged, so a leaf may
  /// be made of several closed shells.
  uint32_t pieces;
  uint64_t seed;        ///< random seed; the same seed gives the same tree; default 3000
  double texture_scale; ///< world size of one interior texture tile, > 0; default 0.1
  /// Plane offset jitter, fraction of the piece's extent, in [0, 0.5]
  /// (0 = exactly through the centroid); default 0.05
  double jitter;
  /// Tilts each cut's normal towards the piece's longest principal axis:
  /// normal = normalize(uniform direction + aspect_bias x axis). 0 (the
  /// default) gives uniformly distributed directions, as in the thesis; about
  /// 1.5 gives chunky fragments instead of plates and shards on thin or long
  /// shapes (walls, slabs, pillars), which also stack and collide far better.
  double aspect_bias;
  /// Optional progress report, called from the building thread with the leaf
  /// count so far; returning false cancels the build.
  bool (*progress)(void* user, uint32_t leaves, uint32_t target);
  void* progress_user;

  bk_fracture_pattern pattern; ///< default BK_PATTERN_PLANES
  /// Voronoi: the caller's seed points (source coordinates; borrowed for the
  /// build only, cleared in bk_mesh_tree.desc). NULL (the default) spreads
  /// `pieces` seeds uniformly through the volume. With points, every point
  /// inside the source makes one cell and `pieces` is ignored; never more
  /// pieces than points (a cell a concave source cuts in two joins a
  /// neighbour).
  const bk_vec3* seed_points;
  uint32_t seed_point_count;
  /// Clustered: how many large chunks, >= 1 (at most `pieces` are made); default 6.
  uint32_t clusters;
  /// Clustered: width of a chunk's finely fractured border, as a fraction of
  /// the source's size, in (0, 1]; default 0.05.
  double cluster_border;
  /// Radial: the impact point (source coordinates); default the origin.
  bk_vec3 impact;
  /// Radial: how fast pieces grow with distance from the impact, in [0, 1.4]:
  /// seed density falls as 1 / distance^(2 x radial_falloff) (0 = uniform);
  /// default 1.
  double radial_falloff;
  /// Brick: the size of one brick with its mortar: length along x, height
  /// along y, depth along z (0 = through the whole source); default
  /// (0.25, 0.125, 0), the game's brick texture at 1 m per tile. Courses
  /// are horizontal (y up).
  bk_vec3 brick_size;
  /// Brick: a corner of one brick (where the brick texture's tile starts);
  /// default the origin.
  bk_vec3 brick_origin;
  /// Brick: how far each course is shifted against the one below, as a
  /// fraction of the brick length, in [0, 1); default 0.5 (running bond).
  double brick_offset;
  /// Cut-out: the fracture map, width x height grey pixels (row 0 at the
  /// top; borrowed for the build only, cleared in bk_mesh_tree.desc): pixels
  /// of 128 and above are lines, each region enclosed by them becomes a
  /// piece. It is stretched over the source's bounds seen along cutout_axis
  /// and sampled by about 3,000 seeds whatever its shape (the memory
  /// estimate counts them and the pixels); never more pieces than samples.
  /// `pieces` is ignored.
  const uint8_t* cutout_pixels;
  uint32_t cutout_width, cutout_height;
  /// Cut-out: the axis the map is projected along: 0 = x (the map's right is
  /// -z, its top +y), 1 = y (right +x, top -z), 2 = z (right +x, top +y);
  /// default 2.
  uint32_t cutout_axis;
  /// Planes, voronoi, clustered, radial and cut-out: cut faces are displaced
  /// along their normal by coherent noise of this amplitude (source units,
  /// >= 0; 0, the default, keeps them flat), tapered to zero at their borders
  /// so every node stays closed. Brick cuts flat (along its mortar) and
  /// refuses it.
  double noise_amplitude;
  /// Noise frequency, in waves per source unit, > 0; default 8.
  double noise_frequency;
  /// Threads the build may use; 0 (the default) = every core. The tree is
  /// byte-identical for any count. Planes and brick split the largest
  /// pieces ahead on them (each piece's random planes come from its own
  /// stream); the cell patterns build their cells on them; bonds are found
  /// on them. Progress is reported from the calling thread only.
  uint32_t threads;
} bk_fracture_def;

/// Default fracture parameters (the thesis's: 256 pieces, seed 3000, texture
/// scale 0.1, the planes pattern; the other patterns' defaults as documented).
bk_fracture_def bk_default_fracture_def(void);
/// Checks a fracture def; err names the wrong field.
bool bk_fracture_def_validate(const bk_fracture_def* def, bk_error* err);
/// The cut-out's jittered grid on a w x h fracture map: *columns x *rows
/// samples, returned; about 3,000 (2,600 to 3,000) whatever the map's
/// shape, fewer only on a map of fewer pixels. A region no sample falls in
/// becomes no piece.
uint32_t bk_cutout_grid(uint32_t w, uint32_t h, uint32_t* columns, uint32_t* rows);
/// The regions of a w x h fracture map (4-connected pixels below 128), as
/// the cut-out labels them (8 bytes a pixel while counting): more regions
/// than bk_cutout_grid's samples means some become no piece.
uint32_t bk_cutout_regions(const uint8_t* pixels, uint32_t w, uint32_t h);

#define BK_NULL_INDEX UINT32_MAX

/// One node: the mesh of one intermediate piece. Children are contiguous in
/// the node array; leaves are numbered so every subtree covers the contiguous
/// leaf range [leaf_begin, leaf_end).
typedef struct bk_mesh_tree_node {
  bk_mesh mesh;
  bk_aabb bounds;
  bk_moments moments; ///< volume moments about bk_mesh_tree_origin (additive across nodes)
  bk_plane plane;     ///< the plane that split this node (meaningless for leaves)
  uint32_t parent;    ///< BK_NULL_INDEX for the root
  uint32_t first_child, child_count;
  uint32_t leaf_begin, leaf_end;
  uint32_t depth;
} bk_mesh_tree_node;

/// A bond between two truly touching leaves, measured on their shared cut.
typedef struct bk_bond {
  uint32_t leaf_a, leaf_b; ///< leaf indices, leaf_a < leaf_b
  double area;             ///< contact area
  bk_vec3 centroid;        ///< centroid of the contact region
  bk_vec3 normal;          ///< unit normal of the contact, pointing from leaf_a to leaf_b
} bk_bond;

/// Why a tree has fewer leaves than asked for: pieces that every cut attempt
/// failed on, counted by how their last attempt failed. A cut is kept only
/// when every piece it makes is closed and the pieces' volumes add up to the
/// whole's within BK_FRACTURE_SPLIT_VOLUME_TOLERANCE of it; otherwise another
/// plane is tried, and after BK_FRACTURE_SPLIT_ATTEMPTS the piece stays whole.
typedef struct bk_fracture_shortfall {
  uint32_t uncut;      ///< pieces left whole because no cut of them held
  uint32_t cap_failed; ///< ... their cut's cross-section could not be closed (overlapping or crossing shells)
  uint32_t not_closed; ///< ... a cut left a piece open
  uint32_t volume_changed; ///< ... the cut pieces' volumes did not add up to the whole's
  /// ... a cut piece's mass was not a solid's (its centre of mass outside
  /// it, or a principal moment of inertia not positive: the source's
  /// surface crosses itself there)
  uint32_t not_solid;
  uint32_t missed; ///< ... the plane left everything on one side (thinner than the cut tolerance)
  /// Brick pattern: pieces spanning several bricks whose mortar or head-joint
  /// cut did not hold, cut by random planes instead (their bricks broken
  /// across); such a piece is not short of anything, so `uncut` leaves it out.
  uint32_t bond_fallbacks;
  /// Planes and brick: pieces of a cut that enclosed no volume (a face of
  /// the source closed against its own back), each joined to the nearest
  /// piece that does instead of becoming a fragment; the tree is not short
  /// of anything for them.
  uint32_t sheets_merged;
  /// Cell patterns: cut faces between two cells that could not be made (the
  /// face's outline crosses itself where the source's surface crosses
  /// itself), each pair of cells kept together in one piece instead, as the
  /// planes pattern leaves a piece uncut whose every cut fails; the tree may
  /// then have fewer leaves than asked for.
  uint32_t cells_joined;
} bk_fracture_shortfall;

/// Closed solid shells of a source that overlap or touch another
/// (interpenetrating or nested solids, or solids whose surfaces meet along a
/// line or over an area, such as a box standing on a plinth; a cavity, such
/// as the inside of an eggshell, is part of its solid and overlaps nothing;
/// shells meeting at single points do not count). A plane through such
/// shells cuts cross-sections that overlap or share edges, which no cap can
/// close, so bk_mesh_tree_build makes each such shell a child of the root of
/// its own, and all the other shells together one more child, each
/// fractured as a whole source would be (the pieces are shared by volume:
/// the largest leaf of the whole tree is cut next). Such children share no
/// cut, so no bond joins them, and the root's volume is the sum of the
/// shells' volumes (an overlap counted twice).
typedef struct bk_fracture_overlap {
  uint32_t shells;           ///< solid shells that overlap or touch at least one other (0: none)
  uint32_t pairs;            ///< pairs of shells that overlap or touch
  uint32_t touching_pairs;   ///< of those, the pairs that only touch (their solids share no volume)
  uint32_t shell_a, shell_b; ///< the first pair, numbered from 1 in the source's order (of first triangle)
  bool touching;             ///< the first pair only touches
  double volume_a, volume_b; ///< their volumes
  bk_vec3 point; ///< a point where they overlap (a contained vertex or a crossing of their surfaces) or touch
} bk_fracture_overlap;

/// How many planes are tried on a piece before it stays whole.
#define BK_FRACTURE_SPLIT_ATTEMPTS 16
/// The fracture's generation: raised whenever the same source and def make
/// a different tree (2: the planes and brick patterns draw a random stream
/// per piece; 3: the library's own sin, cos, cbrt, pow, log2, atan2 and
/// hypot and a stable sort, so a tree is the same bytes on every machine and
/// in WebAssembly). A cache of built trees keys on it, so it rebuilds them.
#define BK_FRACTURE_GENERATION 3
/// How far the pieces of one cut may miss their whole's volume, relative to
/// it (trees are at most a few dozen levels deep, so the leaves of a tree add
/// up to the source within 1e-9).
#define BK_FRACTURE_SPLIT_VOLUME_TOLERANCE 1e-11
/// A source's volume must be at least this fraction of its surface area x its
/// size: below it, rounding in the volume itself (about 1e-16 of that
/// product) is more than 0.1% of it, as for a flat or two-sided surface.
#define BK_FRACTURE_MIN_THICKNESS 1e-13

/// The sizes a source may have (its bounding box's largest side): the
/// volume moments grow with size^5 and must stay well inside double range.
#define BK_FRACTURE_MIN_SIZE 1e-30
#define BK_FRACTURE_MAX_SIZE 1e30
/// Cut faces may span at most this many interior texture tiles (float uvs
/// keep sub-texel precision up to about here).
#define BK_FRACTURE_MAX_UV_TILES 1e6

/// The whole fracture result.
typedef struct bk_mesh_tree {
  bk_mesh_tree_node* nodes; ///< nodes[0] is the root (the source mesh)
  uint32_t node_count;
  uint32_t* leaf_nodes; ///< node index of each leaf
  uint32_t leaf_count;
  bk_bond* bonds;
  uint32_t bond_count;
  uint32_t max_depth;
  uint64_t source_hash; ///< bk_mesh_hash of the source
  bk_fracture_def desc; ///< the parameters that made it (callbacks cleared)
  /// Pieces that could not be cut while building (not stored in cache files:
  /// a loaded tree has it zeroed).
  bk_fracture_shortfall shortfall;
  /// Shells that overlapped and were fractured each on its own (not stored
  /// in cache files: a loaded tree has it zeroed).
  bk_fracture_overlap overlap;
} bk_mesh_tree;

/// Builds the mesh tree of a closed mesh by def->pattern. Planes: repeatedly
/// splits the largest-volume leaf by a random plane through its centroid;
/// brick: the same, but pieces spanning several bricks go first and are cut
/// along the bond's mortar. The cell patterns (voronoi, clustered, radial,
/// cutout) divide the source into Voronoi cells that share every vertex, so
/// the leaves are the cells' solids and inner nodes groups of adjacent ones
/// (halved along their longest extent; clustered: the chunks first). Every
/// piece is kept and bonds are computed. Fails with a clear message on an
/// open mesh or a bad def. A source whose solid shells overlap is first split
/// into shells by planes and brick (see bk_fracture_overlap; only when
/// pieces >= 2; when there are more such shells than pieces, the nearest
/// share a piece); the cell patterns refuse such a source.
bool bk_mesh_tree_build(const bk_mesh* source, const bk_fracture_def* def, bk_mesh_tree* out, bk_error* err);
/// Releases everything; safe on a zeroed tree.
void bk_mesh_tree_free(bk_mesh_tree* tree);
/// Checks that a tree (built, loaded, or made or edited by the caller) is
/// one the runtime, the cache file and the glTF export can use: its
/// structure (desc, arrays present, every index and leaf range in range, a
/// real tree shape, bounds that are its meshes', every value finite) and its
/// physics: every node's volume positive, a leaf's that of its mesh and an
/// inner node's the sum of its children's (within 1e-9 relative, plus
/// rounding); every centre of mass inside its node's bounds; every inertia
/// finite, with principal moments that are positive, at most volume x
/// diagonal^2 and each at most the other two together, in an orthonormal
/// frame; every bond's area positive and no more than the smaller of its
/// leaves' surface areas, its centroid inside both leaves' bounds (within
/// 1e-6 of their diagonal) and its normal of unit length. False with one line
/// naming the first problem's node, leaf or bond and field ("leaf 12 (node
/// 40): volume -0.003 is not positive"). O(total triangles of all nodes):
/// bk_runtime_add_breakable, bk_mesh_tree_save and the loaders call it.
bool bk_mesh_tree_validate(const bk_mesh_tree* tree, bk_error* err);
/// The point the nodes' moments are taken about: the centre of the source's
/// bounds (on a grid of half its size, so moments stay exact for a mesh far
/// from the world origin). Derived from the root's bounds.
bk_vec3 bk_mesh_tree_origin(const bk_mesh_tree* tree);
/// Mass properties (unit density) of a sum of this tree's node moments, with
/// the centroid in the tree's frame (the source mesh's coordinates).
bk_mass_properties bk_mesh_tree_mass(const bk_mesh_tree* tree, bk_moments moments);
/// One line saying why the tree has fewer leaves than desc.pieces, or that
/// cells were joined (shortfall.cells_joined), written to `text`; false (and
/// an empty text) when it has them all and none were.
bool bk_mesh_tree_shortfall_text(const bk_mesh_tree* tree, char* text, size_t size);
/// One line naming the shells that overlapped and were fractured each on its
/// own ("shells 1 and 2 overlap (volumes 1 and 0.125 near (x, y, z)); each was
/// fractured on its own"), written to `text`; false (and an empty text) when
/// none did.
bool bk_mesh_tree_overlap_text(const bk_mesh_tree* tree, char* text, size_t size);
/// Node index of leaf i.
static inline const bk_mesh_tree_node* bk_mesh_tree_leaf(const bk_mesh_tree* tree, uint32_t leaf) {
  return &tree->nodes[tree->leaf_nodes[leaf]];
}

/// Computes the bonds of a tree's leaves from their coplanar, opposite-facing
/// cap triangles (replaces tree->bonds). Called by bk_mesh_tree_build.
void bk_mesh_tree_compute_bonds(bk_mesh_tree* tree);

// ---------------------------------------------------------------- refinement

/// A contact between two meshes, or between a piece and a neighbour: its
/// area, centroid and normal (see bk_mesh_contact).
typedef struct bk_contact_measure {
  double area;
  bk_vec3 centroid;
  bk_vec3 normal; ///< unit, from a to b (area-weighted)
} bk_contact_measure;

/// Fractures one leaf's mesh again, for bk_mesh_tree_splice: as
/// bk_mesh_tree_build does a source, but with every node's moments about the
/// origin of the tree the leaf is in (bk_mesh_tree_origin, derived from that
/// tree's root bounds `tree_bounds`) and cut faces textured at
/// def->texture_scale as the tree's are. Reads nothing but its arguments
/// (the mesh's arrays are never changed by a splice), so it may run on a
/// worker thread while the tree is used and grown. The same mesh, bounds and
/// def give the same bytes.
bool bk_mesh_fracture_leaf(const bk_mesh* mesh, bk_aabb tree_bounds, const bk_fracture_def* def,
                           bk_mesh_tree* out, bk_error* err);

/// What bk_mesh_tree_splice did to a tree.
typedef struct bk_splice_info {
  /// The refined leaf's index before the splice, now its first piece's: its
  /// pieces are leaves [leaf, leaf + leaf_count), and every leaf after it
  /// moved up by leaf_count - 1 (so every subtree still covers a
  /// contiguous leaf range)
  uint32_t leaf;
  uint32_t leaf_count;
  uint32_t node;                   ///< the refined leaf's node, now an inner node (node indices never change)
  uint32_t first_node, node_count; ///< the pieces' nodes, appended (children of `node` and below)
  /// Bonds appended: the pieces' own bonds, and each divided bond's parts
  /// but its first (which keeps the old bond's index). An appended bond
  /// between a piece and a leaf outside came from the old bond of the
  /// refined leaf with that leaf (a pair of leaves has at most one bond).
  uint32_t first_bond, bond_count;
  uint32_t bonds_divided; ///< bonds of the refined leaf with its neighbours, divided among its pieces
} bk_splice_info;

/// A neighbour of a leaf being refined, as it was when its pieces were made.
typedef struct bk_piece_neighbour {
  uint32_t node;    ///< its node in the tree
  bk_mesh mesh;     ///< its mesh (borrowed: a node's mesh never changes)
  double bond_area; ///< the area of its bond with the leaf
} bk_piece_neighbour;

/// How a leaf's pieces touch its neighbours, measured ahead of the splice.
typedef struct bk_piece_contacts {
  uint32_t neighbour_count, piece_count;
  uint32_t* nodes;           ///< per neighbour, its node
  double* bond_areas;        ///< per neighbour, its bond's area then
  bk_contact_measure* parts; ///< neighbour_count x piece_count
} bk_piece_contacts;

/// Measures how the pieces of a leaf (bk_mesh_fracture_leaf of its mesh)
/// touch each neighbour's face, as bk_mesh_tree_splice would: where the
/// pieces are made (on a worker: it reads only its arguments), so the splice
/// need not. Free with bk_piece_contacts_free.
void bk_mesh_measure_piece_contacts(const bk_mesh* leaf_mesh, bk_aabb tree_bounds, const bk_mesh_tree* pieces,
                                    const bk_piece_neighbour* neighbours, uint32_t count,
                                    bk_piece_contacts* out);
void bk_piece_contacts_free(bk_piece_contacts* contacts);

/// Grows a tree where it broke: leaf `leaf` becomes an inner node whose
/// subtree is `pieces` (made by bk_mesh_fracture_leaf from that leaf's
/// mesh and the tree's root bounds; its root stands for the leaf, its other
/// nodes are appended with their meshes, moved out: `pieces` is freed).
/// Every bond of the leaf with a neighbour is divided among the pieces that
/// touch its face (measured as the bonds are: the overlap of their cap
/// triangles), its area shared out in proportion to those overlaps, so the
/// parts add up to the old bond's area; the first part keeps the bond's
/// index. Existing nodes' meshes are neither moved nor freed, so a tree
/// whose meshes are shared with another can be grown. False (the tree and
/// `pieces` untouched) when `pieces` does not fit that leaf (its volume off
/// the leaf's by more than 1e-9 relative, fewer than two leaves) or a bond
/// of the leaf touches no piece.
bool bk_mesh_tree_splice(bk_mesh_tree* tree, uint32_t leaf, bk_mesh_tree* pieces, bk_splice_info* info,
                         bk_error* err);
/// bk_mesh_tree_splice with the pieces' contacts measured ahead: a bond
/// whose neighbour's node and area are still those measured takes its
/// parts from `contacts` (may be NULL); the others are measured here.
bool bk_mesh_tree_splice_measured(bk_mesh_tree* tree, uint32_t leaf, bk_mesh_tree* pieces,
                                  const bk_piece_contacts* contacts, bk_splice_info* info, bk_error* err);

/// The contact of two closed meshes, measured as the bonds are, pair by
/// pair of triangles: interior (cap) triangles of `a` and `b` in one plane
/// (within `tolerance`), facing opposite ways, clipped against each other.
/// Area 0 when they do not touch. O(triangles of a x triangles of b) within
/// their bounds' overlap: a brute-force check of a tree's bonds.
bk_contact_measure bk_mesh_contact(const bk_mesh* a, const bk_mesh* b, double tolerance);

/// Statistics for reports and tests.
typedef struct bk_mesh_tree_stats {
  uint32_t leaf_triangles;    ///< triangles over all leaves
  uint32_t open_nodes;        ///< nodes whose mesh is not closed (0 when all is well)
  double source_volume;       ///< root volume
  double leaf_volume_sum;     ///< sum of leaf volumes
  double max_child_rel_error; ///< worst |sum(children) - parent| / parent over inner nodes
  double min_leaf_volume, max_leaf_volume;
} bk_mesh_tree_stats;

/// Checks every node (closure, volumes). O(total triangles).
bk_mesh_tree_stats bk_mesh_tree_measure(const bk_mesh_tree* tree);

/// A leaf whose aspect is below this is a sliver (see bk_mesh_tree_quality).
#define BK_SLIVER_ASPECT 0.15

/// How usable a tree's fragments are: thin plates and needles (slivers)
/// collide and stack badly, and a wide spread of sizes looks uneven.
///
/// A leaf's principal axes are the eigenvectors of its central inertia
/// tensor (from its volume moments); its principal extents are the extents
/// of its mesh positions projected on those axes, and its aspect is its
/// thinnest principal extent over its longest (1 for a cube, 0.1 for a
/// 1 x 1 x 0.1 box; 0 for a leaf without positions or of zero size). Where
/// principal moments are equal the shape does not fix those axes and
/// rounding picks them: a cube measures between 1 / sqrt(3) and 1 (1 when
/// aligned with x, y and z), a square 1 x 1 x t plate between t / sqrt(2)
/// and t; the axis that stands apart (a plate's thickness, a needle's
/// length) is always found.
typedef struct bk_mesh_tree_quality {
  uint32_t leaves;        ///< the tree's leaf count
  uint32_t slivers;       ///< leaves with aspect < BK_SLIVER_ASPECT
  double sliver_fraction; ///< slivers / leaves (0 for no leaves)
  /// Leaf volumes at the 5th and 95th percentiles, nearest rank: the k-th
  /// smallest volume with k = ceil(p / 100 x leaves) (for one leaf both are
  /// its volume).
  double volume_p5, volume_p95;
  /// volume_p95 / volume_p5, >= 1: 1 for one leaf or equal leaves; 0 for no
  /// leaves, +infinity when volume_p5 <= 0 (never in a tree that was built).
  double volume_ratio_p95_p5;
  double min_aspect;    ///< the smallest leaf aspect (0 for no leaves)
  double median_aspect; ///< the median leaf aspect (the mean of the middle two for an even count)
} bk_mesh_tree_quality;

/// Measures the tree's fragments as bk_mesh_tree_quality defines.
/// O(total leaf positions + leaves log leaves).
bk_mesh_tree_quality bk_mesh_tree_measure_quality(const bk_mesh_tree* tree);

/// Estimated peak memory, in bytes, of bk_mesh_tree_build(source, def)
/// (including 10 MB for the process, as the command line tool measures it),
/// known before building: a model of the source's triangle count, the
/// pieces asked for (the seed points for voronoi with seed_points; for
/// cut-out the map's samples, regions and pixels, 9 bytes each), the
/// pattern and, with noise, the triangles the noisy cut faces get (from the
/// noise frequency times the source's size, as the meshers place them),
/// fitted to measured peaks: 0.9 to 1.5 times each for planes and brick,
/// 1.15 to 1.4 times for the cell patterns flat and 0.7 to 2.1 times with
/// noise (the cell patterns' refinement budget makes their peak jump by up
/// to 2x between nearby requests). A def of NULL or pieces 0 means the
/// default piece count.
uint64_t bk_mesh_tree_estimate_bytes(const bk_mesh* source, const bk_fracture_def* def);
/// Estimated size, in bytes, of the .mtree file of that tree (0.64 to 1.83
/// times it on the trees measured); bk_mesh_tree_save holds this much in
/// memory while saving.
uint64_t bk_mesh_tree_estimate_file_bytes(const bk_mesh* source, const bk_fracture_def* def);

// ---------------------------------------------------------------- cache file

/// Current .mtree format version.
#define BK_MTREE_VERSION 4u

/// Writes the tree to a versioned, checksummed binary file (via a temporary
/// file and rename, so an existing file is never half-written); a tree
/// bk_mesh_tree_validate refuses is not written.
bool bk_mesh_tree_save(const bk_mesh_tree* tree, const char* path, bk_error* err);
/// Loads a tree; verifies magic, version, sizes, checksum, and the tree as
/// bk_mesh_tree_validate does ("tree.mtree: corrupt: bond 3 (leaves 1 and
/// 4): area 0 is not positive"). On failure *out stays zeroed and err says what is wrong.
bool bk_mesh_tree_load(const char* path, bk_mesh_tree* out, bk_error* err);
/// The .mtree file's bytes in memory (what bk_mesh_tree_save writes): *data
/// is allocated with the library's allocator (bk_free it). `name` prefixes
/// error messages.
bool bk_mesh_tree_save_memory(const bk_mesh_tree* tree, const char* name, uint8_t** data, size_t* size,
                              bk_error* err);
/// Loads a tree from .mtree bytes in memory, with every check of
/// bk_mesh_tree_load; `name` prefixes error messages. On failure *out stays
/// zeroed.
bool bk_mesh_tree_load_memory(const void* data, size_t size, const char* name, bk_mesh_tree* out,
                              bk_error* err);

// ---------------------------------------------------------------- glTF export

/// Which mesh-tree nodes a glTF export holds, and which of them have a mesh.
/// Importers (three.js, Godot, Blender) draw every node that has a mesh, so
/// only BK_GLTF_LEVELS_ALL draws the object more than once.
typedef enum bk_gltf_levels {
  /// Every node as the node hierarchy (root = source, children = split
  /// pieces), meshes on the fragments only: the object is drawn once, and
  /// moving an inner node moves its fragments. The default.
  BK_GLTF_LEVELS_HIERARCHY = 0,
  BK_GLTF_LEVELS_LEAVES, ///< the fragments only, each a root node of the scene
  /// Every node with its own mesh: each level of the tree draws the whole
  /// object, so an engine shows one level at a time (coarse levels have fewer
  /// triangles, for swapping in finer ones as it breaks).
  BK_GLTF_LEVELS_ALL,
} bk_gltf_levels;

/// A texture of a glTF export: image bytes written into the file, or a URI
/// written as it is; both NULL for none.
typedef struct bk_gltf_image {
  /// PNG or JPEG bytes (glTF 2.0's core image formats), copied into the
  /// file's binary buffer, so the export stands alone; NULL for none.
  const void* data;
  size_t size; ///< bytes at data
  /// When data is NULL: the image's URI as written in the file (a path
  /// relative to the exported file, as glTF resolves it; not copied).
  const char* uri;
} bk_gltf_image;

/// One source material of a glTF export. Triangles of source material k
/// (bk_material_source) use the export's materials 2k (surface) and 2k + 1
/// (cut faces, named `<name>_interior`).
typedef struct bk_gltf_material {
  const char* name;      ///< 1..63 bytes
  float base_color[4];   ///< baseColorFactor of the surface, RGBA, each in [0, 1]
  bk_gltf_image texture; ///< base-colour texture of the surface
  /// Base-colour texture of the cut faces (their UVs are already divided by
  /// the fracture's texture scale, so one tile is texture_scale wide).
  bk_gltf_image interior_texture;
} bk_gltf_material;

/// A material named "surface", white, without textures.
bk_gltf_material bk_default_gltf_material(void);

/// Parameters of a glTF export: bk_default_gltf_def() fills every field;
/// bk_mesh_tree_save_gltf takes them as given (and refuses bad ones, naming the field).
typedef struct bk_gltf_def {
  bk_gltf_levels levels; ///< default BK_GLTF_LEVELS_HIERARCHY
  /// Embed the tree's exact .mtree bytes (default true), what
  /// bk_mesh_tree_load_gltf reads back. Most of a file's size: a shipped game
  /// that draws the meshes and reads the extras (bonds, node moments) can
  /// leave it out; such a file does not load back.
  bool embed_tree;
  /// Compress the vertices with meshoptimizer (the EXT_meshopt_compression
  /// extension, which the file then requires; three.js decodes it with its
  /// MeshoptDecoder, Blender 3.4 and Godot 4.2 do not). Default false.
  bool meshopt_compression;
  /// The source materials, indexed by bk_material_source of the triangles
  /// (at most BK_MATERIAL_SOURCES_MAX); NULL with material_count 0 (the
  /// default) = one bk_default_gltf_material(). Triangles of a source
  /// material beyond the list use the list's first.
  const bk_gltf_material* materials;
  uint32_t material_count;
  /// Material parameters recorded in asset.extras.breakables.material for
  /// the game (see gltf.md in the installed documentation,
  /// share/doc/breakables): density in kg/m^3 (> 0, default 2400),
  /// frailty (>= 0, default 1), bond strength in hit points per m^2 of bond
  /// area (> 0, default 2e5): the runtime's defaults.
  double density, frailty, bond_strength;
} bk_gltf_def;

/// Default glTF export parameters.
bk_gltf_def bk_default_gltf_def(void);
/// Writes the tree as glTF 2.0: binary (`.glb`) or JSON (`.gltf`, with the
/// binary buffer inside as a base64 data URI, so the file stands alone), by
/// the path's extension (any other is refused). Nodes are the tree's nodes
/// (or leaves, by def->levels), named `node_<index>` and `fragment_<leaf>`;
/// each node's translation is its centre of mass and its mesh's vertices
/// are relative to it, with one primitive per material id present (a source
/// material's surface or its cut faces).
/// The extras (volumes, moments, bounds, leaf ranges, bonds, fracture and
/// material parameters) and the embedded .mtree that makes the file load back
/// exactly are described in gltf.md (share/doc/breakables). Written
/// atomically, in the C locale.
/// def may be NULL for the defaults.
bool bk_mesh_tree_save_gltf(const bk_mesh_tree* tree, const char* path, const bk_gltf_def* def,
                            bk_error* err);
/// Loads the tree stored in a glTF file written by bk_mesh_tree_save_gltf
/// (`.glb` or `.gltf`, told apart by content), bit-exactly, through the .mtree
/// loader and its checks. A glTF without that tree, a corrupt or truncated file
/// is refused with a one-line message; *out then stays zeroed.
bool bk_mesh_tree_load_gltf(const char* path, bk_mesh_tree* out, bk_error* err);
/// bk_mesh_tree_load_gltf on bytes in memory; `name` prefixes error messages.
bool bk_mesh_tree_load_gltf_memory(const void* data, size_t size, const char* name, bk_mesh_tree* out,
                                   bk_error* err);
/// The format of an image file's bytes, told by its signature: "png",
/// "jpeg" (glTF 2.0's core image formats, what a bk_gltf_image may hold) or
/// NULL for anything else.
const char* bk_image_format(const void* data, size_t size);
/// Converts a TGA, BMP or GIF image (no more than 16384 pixels a side nor
/// 2^26 pixels in all) to a PNG file's bytes (*png, released with bk_free),
/// for a glTF export, whose images must be PNG or JPEG. False (nothing
/// allocated) for bytes that are none of these or cannot be decoded.
bool bk_image_convert_to_png(const void* data, size_t size, uint8_t** png, size_t* png_size);

#ifdef __cplusplus
}
#endif
