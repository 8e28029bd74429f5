// Internal to render/: the renderer's state and the helpers its files share
// (renderer.c, render_trees.c, render_batches.c, render_passes.c,
// render_shapes.c, render_particles.c), and shader and texture loading.
//
// Draw calls cost far more than triangles on a software GL, and a break can
// leave a thousand bodies. So a body is not a draw call: every vertex carries
// the index of its mesh-tree node, and a per-tree node table (a texture
// buffer) holds each drawn node's model matrix, overlay colour and fade. The items
// of a frame are grouped by (tree, material, interior scale) and each group
// is one glMultiDrawElements per pass, whatever the number of bodies in it.
//
// A software renderer also runs both sides of a shader's branches, so outer
// surfaces, cut faces and the ground are separate programs (variants of
// mesh.frag), and nodes only a few pixels wide a fourth, lit per vertex in
// their material's mean colours. Each tree's index buffer holds every node's
// outer triangles first, then every node's cut faces, so a batch is one call
// per program and section.
#pragma once

#include <cglm/cglm.h>
#include <glad/gl.h>

#include "render.h"

typedef struct vertex {
  float position[3];
  float normal[3];
  float uv[2];
  float tangent[4];
  uint32_t node; // row in the node table (spheres and the ground read a constant instead)
} vertex;

enum {
  NODE_ATTRIBUTE = 5, // vertex attribute holding the node index
  TABLE_UNIT = 4,     // texture unit of the node table
  // Per node: the three rows of its model matrix, then its overlay colour
  // (rgb, strength) as a fourth texel, and as a fifth its fade, the share of
  // its shadow's texels left out (as it fades, and for glass), two zeros.
  TABLE_TEXELS = 5,
  TABLE_FLOATS = 4 * TABLE_TEXELS,
};

// The programs of mesh.frag, and the two sections of a tree's index buffer
// (outer surface, cut faces) that the first two draw. SURFACE, INTERIOR and
// SIMPLE are also the kinds of draw a material picks its program for
// (material.programs): GLAZED is SURFACE with a clear coat, the GLASS_ ones
// are drawn blended after the opaque pass.
enum {
  SURFACE,
  INTERIOR,
  SIMPLE,
  GROUND,
  GLAZED,
  GLASS_SURFACE,
  GLASS_INTERIOR,
  GLASS_SIMPLE,
  MESH_PROGRAMS,
  SECTIONS = 2,
  DRAW_KINDS = 3,
  COARSE_LEVELS = 2
};

enum { SPHERE_LEVELS = 3 };

typedef struct tree_buffers {
  uint32_t generation; // last generation handed out for this slot
  bool used;
  GLuint vao, vbo, ibo;
  // What the buffers hold and have room for (vertices, indices): a tree grown
  // at run time (renderer_grow_tree) appends its new nodes after them.
  uint32_t vertex_count, vertex_capacity, index_total, index_capacity;
  uint32_t* first_index[SECTIONS]; // per section, per node
  uint32_t* index_count[SECTIONS];
  uint32_t* coarse_first[COARSE_LEVELS][SECTIONS]; // the same, decimated: what SIMPLE draws
  uint32_t* coarse_count[COARSE_LEVELS][SECTIONS];
  float (*spheres)[4]; // per node: bounding sphere in tree space (centre, radius)
  uint32_t node_count;
  GLuint table_buffer, table_texture;              // the node table on the GPU
  float* table;                                    // its CPU side: rows of nodes drawn this frame are current
  uint32_t* node_frame;                            // frame that last drew each node
  uint32_t* node_batch;                            // the batch that drew it then
  uint8_t* node_level;                             // and, if SIMPLE, which coarse copy
  uint32_t frame;                                  // last frame that drew from this tree
  uint32_t lowest, highest;                        // span of nodes drawn that frame: what gets uploaded
  uint32_t first_shadow_range, shadow_range_count; // the shadow pass draws the whole tree at once
  bool shadow_dithered;                            // a node drawn this frame thins its shadow
  float* node_distance;                            // from the eye, this frame: glass sorts by it
} tree_buffers;

// A look: textures and numbers. What differs between materials is here, as
// data: the passes ask a material for its programs and never for its name.
typedef struct material {
  const char* name;
  const char* texture;                              // file prefix
  GLuint albedo, normal, interior, interior_normal; // interior_normal: rgb normal, a occlusion (linear)
  float albedo_mean[3], interior_mean[3];           // linear mean colours: small debris is drawn with these
  float tint[3];
  float gloss, interior_gloss; // cut faces are the unglazed, unpolished body
  float uv_scale;
  float glaze; // clear coat over the outer surface (0 = none): a sharp highlight and the sky's reflection
  // Transparent materials (glass): light let through per crossing of an outer
  // surface at normal incidence (rgb, 0 = opaque material); cut faces let
  // through their interior colour instead, a thick green edge.
  float transmit[3];
  float shadow;             // share of the sun's light its pieces stop (1 = a full shadow)
  int programs[DRAW_KINDS]; // by kind (SURFACE, INTERIOR, SIMPLE): the program that draws it
  bool model_look;          // renderer_model_look's: only its albedo is its own
} material;

// Whether a material's pieces are drawn blended after the opaque pass.
static inline bool material_transparent(const material* m) { return m->programs[SURFACE] == GLASS_SURFACE; }

typedef struct draw_item {
  app_render_tree tree;
  uint32_t first_node, node_count; // range in the frame's node array
  float rows[12];                  // model matrix rows, as the node table holds them
  int material;
  float interior_scale;
  float fade;   // node_draw.fade, in 0..1 (1 never reaches the list)
  bool colored; // node colours follow the nodes in the frame's colour array
} draw_item;

// Items that share everything but their matrices: one call per pass.
typedef struct draw_batch {
  uint32_t tree; // slot
  int material;
  float interior_scale;
  bool simple;                                           // drawn with SIMPLE (its nodes are small on screen)
  bool transparent;                                      // its material's (then sorted back to front)
  float distance;                                        // transparent: of its farthest node from the eye
  uint32_t node_count;                                   // nodes it draws (bounds its ranges in each section)
  uint32_t first_range[SECTIONS], range_count[SECTIONS]; // in the frame's range arrays
} draw_batch;

// A node drawn a second time in a frame (its table row is taken by the first
// body): drawn alone, with a row of the loose table.
typedef struct spill_draw {
  uint32_t tree, node, entry;
  int material;
  float interior_scale;
} spill_draw;

// Uniform locations, looked up once: a lookup is a string search in the driver.
typedef struct mesh_uniforms {
  GLint view_projection, light_view_projection, sun_direction, sun_color, sky_color, ground_color, eye;
  GLint tint, gloss, uv_scale, interior_scale, mean_color, horizon_color, glaze, transmit;
} mesh_uniforms;

typedef struct sky_uniforms {
  GLint view_projection, sun_direction, sky_color, horizon_color, heading, below_horizon;
} sky_uniforms;

enum { SKY_DOME, SKY_SUN, SKY_PROGRAMS }; // sky.vert's variants
// shadow.vert's: without discard, and leaving out a dithered share of texels.
enum { SHADOW_SOLID, SHADOW_DITHERED, SHADOW_PROGRAMS };
// The sun and the sky as the lit passes use them (render_passes.c), for the
// chips and the dust (render_particles.c).
typedef struct render_light {
  const float *sun, *sun_color, *sky, *ground; // 3 floats each, linear; sun normalised
} render_light;

typedef struct debris_gpu debris_gpu; // render_particles.c: chips, the puffs' noise and depth copy

typedef struct particle_uniforms {
  GLint view_projection, camera_right, camera_up;
} particle_uniforms;

typedef struct line_vertex {
  float position[3];
  float color[4];
} line_vertex;

struct app_renderer {
  GLuint mesh_programs[MESH_PROGRAMS], shadow_programs[SHADOW_PROGRAMS], sky_programs[SKY_PROGRAMS],
      particle_program, line_program;
  mesh_uniforms mesh_u[MESH_PROGRAMS];
  GLint shadow_light_view_projection[SHADOW_PROGRAMS], line_view_projection;
  sky_uniforms sky_u[SKY_PROGRAMS];
  particle_uniforms particle_u;
  GLuint shadow_fbo, shadow_texture;
  int shadow_size;
  tree_buffers* trees;
  uint32_t tree_count, tree_capacity;
  material materials[8];
  int material_count;
  material ground;
  GLuint flat_normal; // a material's interior_normal when it has no map: facing out, unoccluded
  GLuint ground_vao, ground_vbo;
  GLuint sphere_vao, sphere_vbo, sphere_ibo;
  uint32_t sphere_first[SPHERE_LEVELS], sphere_index_count[SPHERE_LEVELS];
  GLuint particle_vao, particle_quad_vbo, particle_instance_vbo;
  uint32_t max_particles;
  GLuint line_vao, line_vbo;
  uint32_t line_capacity;
  GLuint empty_vao; // the sky draws from gl_VertexID only
  // Node table of what is not a tree node: the ground (row 0), the spheres,
  // then spilled nodes. Their VAOs leave the node attribute off, so a draw
  // picks its row by setting the attribute's constant value.
  GLuint loose_buffer, loose_texture;
  float* loose;
  uint32_t loose_count, loose_capacity, loose_gpu_capacity;
  // This frame.
  app_camera camera;
  vec4 view_planes[6], light_planes[6]; // the camera's frustum and the shadow map's box, facing in
  int width, height;
  draw_item* items;
  uint32_t item_count, item_capacity;
  uint32_t* nodes;
  float* node_colors;
  uint32_t node_count, node_capacity;
  // Index ranges for glMultiDrawElements: the lit passes' per batch and
  // section, then the shadow pass's per tree; each at most one per drawn
  // node and section.
  GLsizei* multi_counts;
  const void** multi_offsets;
  uint32_t frame; // stamps the node tables' rows (never 0 once drawing)
  draw_batch* batches;
  uint32_t batch_count, batch_capacity;
  uint32_t* glass_batches; // transparent batches, farthest first
  uint32_t glass_batch_count, glass_batch_capacity;
  // Transparent nodes drawn this frame (batch, node, coarse level, distance):
  // their ranges go in back to front.
  struct glass_node {
    uint32_t batch, node;
    uint8_t level;
    float distance;
  } * glass_nodes;
  uint32_t glass_node_count, glass_node_capacity;
  uint32_t* drawn_trees; // slots of trees with nodes this frame, in first-drawn order
  uint32_t drawn_tree_capacity, drawn_tree_count;
  spill_draw* spills;
  uint32_t spill_count, spill_capacity;
  float (*spheres)[7]; // center, radius, rgb
  // Per sphere this frame: level of detail in the lit and the shadow pass (-1: not drawn).
  int8_t (*sphere_levels)[2];
  uint32_t sphere_count, sphere_capacity;
  line_vertex* lines;
  uint32_t line_count, line_vertex_capacity;
  const particle_instance* particles;
  uint32_t particle_count;
  debris_gpu* debris;
  render_stats stats;
};

static const float ground_half_size = 60.0f; // metres

/// Compiles and links `<dir>/<name>.vert` + `.frag`, each preceded by
/// `<dir>/common.glsl` and, if non-NULL, each space-separated word of `variant` defined as a macro (to 1). 0
/// with err holding the file name, the variant and the GL info log on failure.
GLuint shader_load(const char* dir, const char* name, const char* variant, bk_error* err);
/// Loads a PNG into a mipmapped, repeating texture; colour maps (`srgb`) keep
/// their sRGB bytes for the shader to decode, with levels averaged in linear light;
/// `mean_rgb` (may be NULL) gets its mean colour, linear for colour maps.
GLuint texture_load(const char* path, bool srgb, float mean_rgb[3], bk_error* err);
/// Loads a PNG of linear data into a mipmapped, repeating RGBA texture (a
/// normal map with occlusion in alpha): 4 channels whatever the file has.
GLuint texture_load_rgba(const char* path, bk_error* err);
/// texture_load (sRGB) from an image file's bytes (PNG, JPEG, TGA, BMP,
/// ...; no more than 16384 pixels a side; NULL: one white texel), times
/// `color` (linear, clamped to 0..1; NULL = white), its rows reversed: a
/// model's UVs have v = 0 at the image's bottom.
GLuint texture_load_memory_flipped(const void* data, size_t size, const float color[3], float mean_rgb[3],
                                   bk_error* err);
/// The next mipmap level of an RGB image: each texel the mean of a 2x2 box
/// (an odd size leaves its last row or column out; a size of 1 takes its one
/// row or column twice), in linear light for `srgb` images (rounded to the
/// nearest sRGB byte). `out` holds max(w/2,1) x max(h/2,1) texels and may be `rgb`.
void texture_halve(const unsigned char* rgb, int width, int height, bool srgb, unsigned char* out);
/// The same for linear RGBA bytes (every channel a plain mean, rounded).
void texture_halve_rgba(const unsigned char* rgba, int width, int height, unsigned char* out);
/// A 1x1 RGBA texture of one value (stands in for an optional map).
GLuint texture_solid(const unsigned char rgba[4]);

/// Vertex attributes 0-3 of `vertex` on the bound VAO and array buffer (the node attribute stays off).
void render_vertex_layout(void);
/// A node table of `rows` rows: a float buffer read in the vertex shaders through a texture.
void render_make_table(GLuint* buffer, GLuint* texture, uint32_t rows);
/// The uploaded tree `id` names, or NULL when it is null, released or stale.
tree_buffers* render_find_tree(app_renderer* renderer, app_render_tree id);
/// The ground quad's VAO and buffer (render_shapes.c).
void render_make_ground(app_renderer* renderer);
/// The projectile sphere's levels of detail in one VAO (render_shapes.c).
void render_make_sphere(app_renderer* renderer);
/// The particle quad and instance buffers, the puffs' noise, the chips' shapes and program
/// (render_particles.c). False with err set when chip.vert/.frag do not build.
bool render_make_particles(app_renderer* renderer, const char* shader_dir, bk_error* err);
/// Frees what render_make_particles made beyond the renderer's own fields.
void render_free_particles(app_renderer* renderer);
/// Turns the frame's draw list into node table rows, batches and index ranges, and uploads the tables.
void render_prepare_batches(app_renderer* renderer);
/// Draws this frame's chips (opaque, lit), then its particles blended over the scene (`view` gives
/// the camera's axes), both lit by `light`.
void render_draw_particle_pass(app_renderer* renderer, mat4 view_projection, mat4 view,
                               const render_light* light);
