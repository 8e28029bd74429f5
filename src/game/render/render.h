// render: OpenGL 3.3 core renderer for breakables. Mesh trees are uploaded
// once (one vertex and index buffer per tree; each node a range in them; a
// tree grown at run time adds its new nodes' ranges), and
// a body draws its minimal node set with its model matrix. Frames are
// recorded as a draw list and played at renderer_end_frame: a sun shadow
// pass, the lit pass with textured materials, the sky, transparent glass
// (sorted, blended), particles and debug lines. Needs a current GL context;
// knows nothing of physics or windows.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include <breakables/authoring.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct app_renderer app_renderer;

/// Zero fields mean the default.
typedef struct renderer_def {
  /// GL function loader of the window system (e.g. glfwGetProcAddress); required.
  void (*(*get_proc_address)(const char* name))(void);
  const char* shader_dir;  ///< directory with the .vert/.frag files (required)
  const char* texture_dir; ///< directory with the material PNGs (required)
  int shadow_size;         ///< shadow map resolution; default 1024
  uint32_t max_particles;  ///< most particles and most chips drawn a frame (each); default 16384
} renderer_def;

/// Loads GL entry points, shaders and textures. Fails with a message naming
/// the file (and the GL info log for a broken shader).
app_renderer* renderer_create(const renderer_def* desc, bk_error* err);
void renderer_destroy(app_renderer* renderer);

/// Uploaded mesh tree, id with a generation (zero = null).
typedef struct app_render_tree {
  uint32_t index, generation;
} app_render_tree;

/// Uploads every node of a tree once. The tree may be freed afterwards.
app_render_tree renderer_upload_tree(app_renderer* renderer, const bk_mesh_tree* tree);
/// Uploads the nodes a tree gained since it was uploaded: nodes
/// [renderer_tree_node_count, tree->node_count) of `tree`, which must be
/// the uploaded tree grown by appending (as bk_runtime_refine grows a
/// breakable's: node indices and the meshes of the nodes it had never
/// change). Returns how many nodes it added (0 for a stale id, or when the
/// tree has no more nodes than were uploaded); the id stays the same.
/// renderer_build_nodes + renderer_append_nodes in one call.
uint32_t renderer_grow_tree(app_renderer* renderer, app_render_tree id, const bk_mesh_tree* tree);
/// The nodes uploaded of a tree (0 for a null, released or stale id).
uint32_t renderer_tree_node_count(const app_renderer* renderer, app_render_tree id);
/// Nodes of a tree made ready for the GPU (their vertices, indices, coarse
/// copies and bounds: the costly part of an upload, decimating the coarse
/// copies), without GL and without a renderer, so on any thread.
typedef struct render_nodes render_nodes;
/// Builds nodes [first, end) of `tree` (NULL when they are not its nodes).
render_nodes* renderer_build_nodes(const bk_mesh_tree* tree, uint32_t first, uint32_t end);
/// Appends built nodes to an uploaded tree, when they are the nodes that
/// follow what it has (first == renderer_tree_node_count); frees `nodes`
/// either way. Returns how many it appended.
uint32_t renderer_append_nodes(app_renderer* renderer, app_render_tree id, render_nodes* nodes);
/// Frees built nodes not appended (NULL is ignored).
void renderer_free_nodes(render_nodes* nodes);
void renderer_release_tree(app_renderer* renderer, app_render_tree tree);

/// Material looks, by name: stone, brick, concrete, porcelain, glass,
/// eggshell, wood (unknown names fall back to stone).
int app_renderer_material(const app_renderer* renderer, const char* name);
/// A look for a model with its own surface: the outer surface coloured by
/// `image` (an image file's bytes: PNG, JPEG, TGA, BMP, ...; NULL = white)
/// times `color` (linear RGB; NULL = white) at the model's UVs, without
/// relief; cut faces, gloss and transparency those of look `base`. One such
/// look at a time: each call replaces the last. Returns its index (`base`
/// when there is no room).
int renderer_model_look(app_renderer* renderer, int base, const void* image, size_t image_size,
                        const float color[3]);

typedef struct app_camera {
  bk_vec3 eye, target;
  double fov_y;                 ///< radians; default 60 degrees
  double near_plane, far_plane; ///< defaults 0.05, 200
} app_camera;

/// Starts recording a frame of the given framebuffer size.
void renderer_begin_frame(app_renderer* renderer, const app_camera* camera, int width, int height);

/// How to draw a set of nodes.
typedef struct node_draw {
  app_render_tree tree;
  const uint32_t* nodes;
  uint32_t node_count;
  bk_transform model;
  int material;
  double interior_scale;    ///< multiplies interior uvs (1 = as fractured)
  const float* node_colors; ///< optional rgba per node: overlay colour and strength (debug views)
  /// How far the nodes have faded out: 0 = drawn as usual, 1 = not drawn at all (nor their shadow).
  /// Between, that share of their pixels is left out in a fixed 4x4 ordered-dither pattern, in the lit
  /// and the shadow pass alike, so fading pieces need no sorting or blending. Clamped to 0..1; NaN = 0.
  double fade;
} node_draw;

void renderer_draw_nodes(app_renderer* renderer, const node_draw* draw);
/// A projectile or marker.
void renderer_draw_sphere(app_renderer* renderer, bk_vec3 center, double radius, const float rgb[3]);
/// A debug line, drawn on top of the scene (overlays show what is inside solids).
void renderer_draw_line(app_renderer* renderer, bk_vec3 a, bk_vec3 b, const float rgba[4]);

/// One blended particle, a camera-facing quad: a dust puff (kind 0) or a glint (kind 1). Zero fields
/// draw nothing (size and alpha 0).
typedef struct particle_instance {
  float position[3]; ///< centre, world space
  float size;        ///< radius in metres
  /// Linear rgb and opacity. A puff's colour is its albedo, lit by the sun and the sky in the shader
  /// (so dust is not a glowing disc); a glint's is emitted as is (a sparkle of glass in the sun).
  float color[4];
  /// 0: a soft puff of dust, its shape a tileable noise texture under a soft round falloff, faded
  /// where it meets the scene (the depth buffer) and near the eye. 1: a glint, a small hard sparkle.
  float kind;
  /// Picks the puff's shape: a rotation and an offset into the noise (any value; each differs).
  float seed;
} particle_instance;

/// Particles for this frame (drawn instanced, blended, after the opaque pass and the chips). The
/// array must stay valid until renderer_end_frame.
void renderer_draw_particles(app_renderer* renderer, const particle_instance* particles, uint32_t count);

/// One debris chip: a tiny lit mesh (one of a few irregular convex shapes built at renderer_create)
/// textured with its material's interior. Chips are opaque and cast no shadow. Zero fields: an
/// unrotated, white-tinted stone chip of shape 0 and size 0 (not drawn).
typedef struct chip_instance {
  float position[3]; ///< centre, world space
  float size;        ///< radius in metres; 0 or less: not drawn
  float rotation[4]; ///< quaternion (x, y, z, w), normalised in the shader; all zero = unrotated
  float tint[3];     ///< multiplies the interior texture (linear); all zero = white
  /// 0 = drawn, 1 = not drawn; between, that share of its pixels is left out in the ordered-dither
  /// pattern of node_draw.fade. Clamped to 0..1; NaN = 0.
  float fade;
  int material;   ///< app_renderer_material's index; out of range = stone
  uint32_t shape; ///< which prebuilt chip, modulo their number (renderer_chip_shapes)
} chip_instance;

/// Chips for this frame (instanced, one call per material and shape). The array must stay valid
/// until renderer_end_frame; a frame that does not call this draws none.
void renderer_draw_chips(app_renderer* renderer, const chip_instance* chips, uint32_t count);
/// How many chip shapes there are.
uint32_t renderer_chip_shapes(void);

/// Renders everything recorded. Returns the first GL error code seen this
/// frame (GL_NO_ERROR = 0 when all went well).
unsigned renderer_end_frame(app_renderer* renderer);

/// Reads the current framebuffer and writes a PNG.
bool renderer_screenshot(app_renderer* renderer, int width, int height, const char* path, bk_error* err);

/// Counters of the last frame.
typedef struct render_stats {
  uint32_t draw_calls, triangles, particles, lines;
  uint32_t chips; ///< debris chips drawn
} render_stats;

render_stats renderer_stats(const app_renderer* renderer);

#ifdef __cplusplus
}
#endif
