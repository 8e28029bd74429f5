// render: OpenGL 3.3 core renderer for breakables. Mesh trees are uploaded
// once (one vertex and index buffer per tree; each node a range in them), and
// a body draws its minimal node set with its model matrix. Frames are
// recorded as a draw list and played at bk_renderer_end_frame: a sun shadow
// pass, the lit pass with textured materials, the sky, particles and debug
// lines. Needs a current GL context; knows nothing of physics or windows.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "bk_fracture.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct bk_renderer bk_renderer;

/// Zero fields mean the default.
typedef struct bk_renderer_def {
  /// GL function loader of the window system (e.g. glfwGetProcAddress); required.
  void (*(*get_proc_address)(const char* name))(void);
  const char* shader_dir;  ///< directory with the .vert/.frag files (required)
  const char* texture_dir; ///< directory with the material PNGs (required)
  int shadow_size;         ///< shadow map resolution; default 1024
  uint32_t max_particles;  ///< default 16384
} bk_renderer_def;

/// Loads GL entry points, shaders and textures. Fails with a message naming
/// the file (and the GL info log for a broken shader).
bk_renderer* bk_renderer_create(const bk_renderer_def* desc, bk_error* err);
void bk_renderer_destroy(bk_renderer* renderer);

/// Uploaded mesh tree, id with a generation (zero = null).
typedef struct bk_render_tree {
  uint32_t index, generation;
} bk_render_tree;

/// Uploads every node of a tree once. The tree may be freed afterwards.
bk_render_tree bk_renderer_upload_tree(bk_renderer* renderer, const bk_mesh_tree* tree);
void bk_renderer_release_tree(bk_renderer* renderer, bk_render_tree tree);

/// Material looks, by name: stone, brick, concrete, porcelain, glass,
/// eggshell, wood (unknown names fall back to stone).
int bk_renderer_material(const bk_renderer* renderer, const char* name);

typedef struct bk_camera {
  bk_vec3 eye, target;
  double fov_y;                 ///< radians; default 60 degrees
  double near_plane, far_plane; ///< defaults 0.05, 200
} bk_camera;

/// Starts recording a frame of the given framebuffer size.
void bk_renderer_begin_frame(bk_renderer* renderer, const bk_camera* camera, int width, int height);

/// How to draw a set of nodes.
typedef struct bk_node_draw {
  bk_render_tree tree;
  const uint32_t* nodes;
  uint32_t node_count;
  bk_transform model;
  int material;
  double interior_scale;    ///< multiplies interior uvs (1 = as fractured)
  const float* node_colors; ///< optional rgba per node: overlay colour and strength (debug views)
} bk_node_draw;

void bk_renderer_draw_nodes(bk_renderer* renderer, const bk_node_draw* draw);
/// A projectile or marker.
void bk_renderer_draw_sphere(bk_renderer* renderer, bk_vec3 center, double radius, const float rgb[3]);
/// A debug line, drawn on top of the scene (overlays show what is inside solids).
void bk_renderer_draw_line(bk_renderer* renderer, bk_vec3 a, bk_vec3 b, const float rgba[4]);

/// One particle: a dust puff (kind 0, soft) or a debris chip (kind 1).
typedef struct bk_particle_instance {
  float position[3];
  float size;
  float color[4];
  float kind;
} bk_particle_instance;

/// Particles for this frame (drawn instanced, blended, after the opaque pass).
void bk_renderer_draw_particles(bk_renderer* renderer, const bk_particle_instance* particles, uint32_t count);

/// Renders everything recorded. Returns the first GL error code seen this
/// frame (GL_NO_ERROR = 0 when all went well).
unsigned bk_renderer_end_frame(bk_renderer* renderer);

/// Reads the current framebuffer and writes a PNG.
bool bk_renderer_screenshot(bk_renderer* renderer, int width, int height, const char* path, bk_error* err);

/// Counters of the last frame.
typedef struct bk_render_stats {
  uint32_t draw_calls, triangles, particles, lines;
} bk_render_stats;

bk_render_stats bk_renderer_stats(const bk_renderer* renderer);

#ifdef __cplusplus
}
#endif
