// The renderer: uploaded trees, materials, the per-frame draw list, and the
// passes that play it (shadow, lit, sky, particles, lines).
//
// Draw calls cost far more than triangles on a software GL, and a break can
// leave a thousand bodies. So a body is not a draw call: every vertex carries
// the index of its mesh-tree node, and a per-tree node table (a texture
// buffer) holds each drawn node's model matrix and overlay colour. The items
// of a frame are grouped by (tree, material, interior scale) and each group
// is one glMultiDrawElements per pass, whatever the number of bodies in it.
//
// A software renderer also runs both sides of a shader's branches, so outer
// surfaces, cut faces and the ground are separate programs (variants of
// mesh.frag), and nodes only a few pixels wide a fourth, lit per vertex in
// their material's mean colours. Each tree's index buffer holds every node's
// outer triangles first, then every node's cut faces, so a batch is one call
// per program and section.
#include <cglm/cglm.h>
#include <math.h>
#include <stb_image_write.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

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
  // (rgb, strength) as a fourth texel.
  TABLE_TEXELS = 4,
  TABLE_FLOATS = 4 * TABLE_TEXELS,
};

// The programs of mesh.frag, and the two sections of a tree's index buffer
// (outer surface, cut faces) that the first two draw.
enum { SURFACE, INTERIOR, SIMPLE, GROUND, MESH_PROGRAMS, SECTIONS = 2, COARSE_LEVELS = 2 };

enum { SPHERE_LEVELS = 3 };
// A sphere's level of detail when its width on screen is at least this many pixels.
static const float sphere_level_pixels[SPHERE_LEVELS] = {48.0f, 16.0f, 0.0f};

// Nodes whose bounding sphere spans fewer pixels than this are drawn with
// SIMPLE: a shard a few pixels wide shows no texture or normal map, and a
// heap of debris is thousands of them.
static const float simple_below_pixels = 24.0f;
// Under this many pixels SIMPLE draws a second, coarser copy (see coarse_tolerance).
static const float tiny_below_pixels = 10.0f;
// A node's batch when it is out of view but casts a shadow into the map.
#define SHADOW_ONLY UINT32_MAX

typedef struct tree_buffers {
  uint32_t generation; // last generation handed out for this slot
  bool used;
  GLuint vao, vbo, ibo;
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
} tree_buffers;

typedef struct material {
  const char* name;
  const char* texture; // file prefix
  GLuint albedo, normal, interior;
  float albedo_mean[3], interior_mean[3]; // linear mean colours: small debris is drawn with these
  float tint[3];
  float gloss;
  float uv_scale;
} material;

typedef struct draw_item {
  bk_render_tree tree;
  uint32_t first_node, node_count; // range in the frame's node array
  float rows[12];                  // model matrix rows, as the node table holds them
  int material;
  float interior_scale;
  bool colored; // node colours follow the nodes in the frame's colour array
} draw_item;

// Items that share everything but their matrices: one call per pass.
typedef struct draw_batch {
  uint32_t tree; // slot
  int material;
  float interior_scale;
  bool simple;                                           // drawn with SIMPLE (its nodes are small on screen)
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
  GLint tint, gloss, uv_scale, interior_scale, mean_color;
} mesh_uniforms;

typedef struct sky_uniforms {
  GLint view_projection, sun_direction, sky_color, horizon_color, heading, below_horizon;
} sky_uniforms;

enum { SKY_DOME, SKY_SUN, SKY_PROGRAMS }; // sky.vert's variants
// The dome's cells (sky.vert: 48 segments, 19 bands), two triangles each.
static const GLsizei sky_dome_vertices = 48 * 19 * 6;

typedef struct particle_uniforms {
  GLint view_projection, camera_right, camera_up;
} particle_uniforms;

typedef struct line_vertex {
  float position[3];
  float color[4];
} line_vertex;

struct bk_renderer {
  GLuint mesh_programs[MESH_PROGRAMS], shadow_program, sky_programs[SKY_PROGRAMS], particle_program,
      line_program;
  mesh_uniforms mesh_u[MESH_PROGRAMS];
  GLint shadow_light_view_projection, line_view_projection;
  sky_uniforms sky_u[SKY_PROGRAMS];
  particle_uniforms particle_u;
  GLuint shadow_fbo, shadow_texture;
  int shadow_size;
  tree_buffers* trees;
  uint32_t tree_count, tree_capacity;
  material materials[8];
  int material_count;
  material ground;
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
  bk_camera camera;
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
  const bk_particle_instance* particles;
  uint32_t particle_count;
  bk_render_stats stats;
};

// Sun and sky: one place, used by every pass.
static const float sun_direction[3] = {-0.45f, 0.78f, 0.43f};
static const float sun_color[3] = {2.6f, 2.4f, 2.1f};
static const float sky_color[3] = {0.32f, 0.52f, 0.82f};
static const float horizon_color[3] = {0.78f, 0.84f, 0.9f};
static const float ground_bounce[3] = {0.35f, 0.3f, 0.25f};

static const material material_table[] = {
    {.name = "stone", .texture = "stone", .tint = {1, 1, 1}, .gloss = 0.1f, .uv_scale = 1.0f},
    {.name = "brick", .texture = "brick", .tint = {1, 1, 1}, .gloss = 0.05f, .uv_scale = 1.0f},
    {.name = "concrete", .texture = "concrete", .tint = {1, 1, 1}, .gloss = 0.05f, .uv_scale = 1.0f},
    {.name = "porcelain", .texture = "porcelain", .tint = {1, 1, 1}, .gloss = 0.9f, .uv_scale = 1.0f},
    {.name = "glass", .texture = "glass", .tint = {0.85f, 0.95f, 1.0f}, .gloss = 1.0f, .uv_scale = 1.0f},
    {.name = "eggshell", .texture = "eggshell", .tint = {1, 1, 1}, .gloss = 0.4f, .uv_scale = 1.0f},
    {.name = "wood", .texture = "wood", .tint = {1, 1, 1}, .gloss = 0.15f, .uv_scale = 1.0f},
};

static bool load_material(const char* dir, material* m, bool has_interior, bk_error* err) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s_albedo.png", dir, m->texture);
  if (!(m->albedo = bk_texture_load(path, true, m->albedo_mean, err))) return false;
  snprintf(path, sizeof path, "%s/%s_normal.png", dir, m->texture);
  if (!(m->normal = bk_texture_load(path, false, NULL, err))) return false;
  if (has_interior) {
    snprintf(path, sizeof path, "%s/%s_interior.png", dir, m->texture);
    if (!(m->interior = bk_texture_load(path, true, m->interior_mean, err))) return false;
  } else {
    m->interior = m->albedo;
    memcpy(m->interior_mean, m->albedo_mean, sizeof m->interior_mean);
  }
  return true;
}

static const float ground_half_size = 60.0f; // metres

static void make_ground(bk_renderer* r) {
  // A large quad; uvs in metres so the paving keeps its size.
  const float s = ground_half_size;
  vertex quad[4] = {{{-s, 0, -s}, {0, 1, 0}, {-s, -s}, {1, 0, 0, 1}, 0},
                    {{-s, 0, s}, {0, 1, 0}, {-s, s}, {1, 0, 0, 1}, 0},
                    {{s, 0, s}, {0, 1, 0}, {s, s}, {1, 0, 0, 1}, 0},
                    {{s, 0, -s}, {0, 1, 0}, {s, -s}, {1, 0, 0, 1}, 0}};
  vertex tris[6] = {quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]};
  glGenVertexArrays(1, &r->ground_vao);
  glGenBuffers(1, &r->ground_vbo);
  glBindVertexArray(r->ground_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->ground_vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof tris, tris, GL_STATIC_DRAW);
}

static void vertex_layout(void) {
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, position));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, normal));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, uv));
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, tangent));
  // The node attribute stays off here: the ground and the spheres read its
  // constant value (glVertexAttribI4ui), which names their row of the loose table.
}

// A node table: a float buffer read in the vertex shaders through a texture.
static void make_table(GLuint* buffer, GLuint* texture, uint32_t rows) {
  glGenBuffers(1, buffer);
  glBindBuffer(GL_TEXTURE_BUFFER, *buffer);
  glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * (rows ? rows : 1)), NULL,
               GL_DYNAMIC_DRAW);
  glGenTextures(1, texture);
  glBindTexture(GL_TEXTURE_BUFFER, *texture);
  glTexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, *buffer);
  glBindTexture(GL_TEXTURE_BUFFER, 0);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
}

// Projectiles in three levels of detail, chosen by their size on screen: a
// volley leaves dozens on the ground, and at full detail they were ~40k
// triangles a frame counting the shadow pass.
enum { SPHERE_RINGS = 12, SPHERE_SEGMENTS = 20 }; // the finest level
static const int sphere_rings[SPHERE_LEVELS] = {SPHERE_RINGS, 8, 5};
static const int sphere_segments[SPHERE_LEVELS] = {SPHERE_SEGMENTS, 12, 8};

static void make_sphere(bk_renderer* r) {
  // Room for every level at the finest one's size.
  enum {
    MAX_VERTICES = SPHERE_LEVELS * (SPHERE_RINGS + 1) * (SPHERE_SEGMENTS + 1),
    MAX_INDICES = SPHERE_LEVELS * 6 * SPHERE_RINGS * SPHERE_SEGMENTS
  };
  vertex vertices[MAX_VERTICES];
  uint32_t indices[MAX_INDICES];
  uint32_t v = 0, i = 0;
  for (int level = 0; level < SPHERE_LEVELS; ++level) {
    int rings = sphere_rings[level], segments = sphere_segments[level];
    uint32_t base = v;
    r->sphere_first[level] = i;
    for (int ring = 0; ring <= rings; ++ring)
      for (int seg = 0; seg <= segments; ++seg) {
        float theta = (float)ring / (float)rings * 3.14159265f,
              phi = (float)seg / (float)segments * 6.2831853f;
        float n[3] = {sinf(theta) * cosf(phi), cosf(theta), sinf(theta) * sinf(phi)};
        vertices[v++] = (vertex){{n[0], n[1], n[2]},
                                 {n[0], n[1], n[2]},
                                 {(float)seg / (float)segments * 2, (float)ring / (float)rings},
                                 {-sinf(phi), 0, cosf(phi), 1},
                                 0};
      }
    for (int ring = 0; ring < rings; ++ring)
      for (int seg = 0; seg < segments; ++seg) {
        uint32_t a = base + (uint32_t)(ring * (segments + 1) + seg), b = a + (uint32_t)segments + 1;
        uint32_t quad[6] = {a, a + 1, b, a + 1, b + 1, b};
        memcpy(&indices[i], quad, sizeof quad);
        i += 6;
      }
    r->sphere_index_count[level] = i - r->sphere_first[level];
  }
  glGenVertexArrays(1, &r->sphere_vao);
  glGenBuffers(1, &r->sphere_vbo);
  glGenBuffers(1, &r->sphere_ibo);
  glBindVertexArray(r->sphere_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->sphere_vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(vertex) * v), vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * i), indices, GL_STATIC_DRAW);
  vertex_layout();
}

static void make_particles(bk_renderer* r) {
  const float corners[8] = {-1, -1, 1, -1, 1, 1, -1, 1};
  glGenVertexArrays(1, &r->particle_vao);
  glGenBuffers(1, &r->particle_quad_vbo);
  glGenBuffers(1, &r->particle_instance_vbo);
  glBindVertexArray(r->particle_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->particle_quad_vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof corners, corners, GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
  glBindBuffer(GL_ARRAY_BUFFER, r->particle_instance_vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof(bk_particle_instance) * r->max_particles, NULL, GL_STREAM_DRAW);
  const GLsizei stride = sizeof(bk_particle_instance);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(bk_particle_instance, position));
  glVertexAttribDivisor(1, 1);
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(bk_particle_instance, color));
  glVertexAttribDivisor(2, 1);
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 1, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(bk_particle_instance, kind));
  glVertexAttribDivisor(3, 1);
}

static bool make_shadow_map(bk_renderer* r, bk_error* err) {
  glGenTextures(1, &r->shadow_texture);
  glBindTexture(GL_TEXTURE_2D, r->shadow_texture);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, r->shadow_size, r->shadow_size, 0, GL_DEPTH_COMPONENT,
               GL_FLOAT, NULL);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
  const float white[4] = {1, 1, 1, 1};
  glTexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, white);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  glGenFramebuffers(1, &r->shadow_fbo);
  glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo);
  glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, r->shadow_texture, 0);
  glDrawBuffer(GL_NONE);
  glReadBuffer(GL_NONE);
  GLenum status = glCheckFramebufferStatus(GL_FRAMEBUFFER);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);
  if (status != GL_FRAMEBUFFER_COMPLETE)
    return bk_error_set(err, "shadow framebuffer incomplete (0x%x)", status);
  return true;
}

static GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

bk_renderer* bk_renderer_create(const bk_renderer_def* desc, bk_error* err) {
  if (!desc->shader_dir || !desc->texture_dir)
    return bk_error_set(err, "renderer: shader_dir and texture_dir are required"), NULL;
  if (!desc->get_proc_address || !gladLoadGL((GLADloadfunc)desc->get_proc_address))
    return bk_error_set(err, "renderer: cannot load OpenGL 3.3 core functions"), NULL;
  bk_renderer* r = bk_calloc(1, sizeof *r);
  r->shadow_size = desc->shadow_size > 0 ? desc->shadow_size : 1024;
  r->max_particles = desc->max_particles ? desc->max_particles : 16384;
  const char* programs[9] = {"mesh", "mesh", "mesh", "mesh", "shadow", "sky", "sky", "particle", "line"};
  const char* variants[9] = {"SURFACE", "INTERIOR", "SIMPLE", "GROUND", NULL, "DOME", "SUN"};
  GLuint* slots[9] = {&r->mesh_programs[SURFACE], &r->mesh_programs[INTERIOR], &r->mesh_programs[SIMPLE],
                      &r->mesh_programs[GROUND],  &r->shadow_program,          &r->sky_programs[SKY_DOME],
                      &r->sky_programs[SKY_SUN],  &r->particle_program,        &r->line_program};
  for (int i = 0; i < 9; ++i)
    if (!(*slots[i] = bk_shader_load(desc->shader_dir, programs[i], variants[i], err))) {
      bk_renderer_destroy(r);
      return NULL;
    }
  GLuint p = 0;
  for (int i = 0; i < MESH_PROGRAMS; ++i) {
    p = r->mesh_programs[i];
    r->mesh_u[i] = (mesh_uniforms){.view_projection = uniform(p, "u_view_projection"),
                                   .light_view_projection = uniform(p, "u_light_view_projection"),
                                   .sun_direction = uniform(p, "u_sun_direction"),
                                   .sun_color = uniform(p, "u_sun_color"),
                                   .sky_color = uniform(p, "u_sky_color"),
                                   .ground_color = uniform(p, "u_ground_color"),
                                   .eye = uniform(p, "u_eye"),
                                   .tint = uniform(p, "u_tint"),
                                   .gloss = uniform(p, "u_gloss"),
                                   .uv_scale = uniform(p, "u_uv_scale"),
                                   .interior_scale = uniform(p, "u_interior_scale"),
                                   .mean_color = uniform(p, "u_mean_color")};
    // Texture units never change: set once, the program keeps them.
    glUseProgram(p);
    glUniform1i(uniform(p, "u_albedo"), 0);
    glUniform1i(uniform(p, "u_normal_map"), 1);
    glUniform1i(uniform(p, "u_shadow_map"), 3);
    glUniform1i(uniform(p, "u_nodes"), TABLE_UNIT);
  }
  glUseProgram(r->shadow_program);
  glUniform1i(uniform(r->shadow_program, "u_nodes"), TABLE_UNIT);
  glUseProgram(0);
  r->shadow_light_view_projection = uniform(r->shadow_program, "u_light_view_projection");
  r->line_view_projection = uniform(r->line_program, "u_view_projection");
  for (int i = 0; i < SKY_PROGRAMS; ++i) {
    p = r->sky_programs[i];
    r->sky_u[i] = (sky_uniforms){.view_projection = uniform(p, "u_view_projection"),
                                 .sun_direction = uniform(p, "u_sun_direction"),
                                 .sky_color = uniform(p, "u_sky_color"),
                                 .horizon_color = uniform(p, "u_horizon_color"),
                                 .heading = uniform(p, "u_heading"),
                                 .below_horizon = uniform(p, "u_below_horizon")};
  }
  p = r->particle_program;
  r->particle_u = (particle_uniforms){.view_projection = uniform(p, "u_view_projection"),
                                      .camera_right = uniform(p, "u_camera_right"),
                                      .camera_up = uniform(p, "u_camera_up")};
  r->material_count = (int)(sizeof material_table / sizeof *material_table);
  for (int i = 0; i < r->material_count; ++i) {
    r->materials[i] = material_table[i];
    if (!load_material(desc->texture_dir, &r->materials[i], true, err)) {
      bk_renderer_destroy(r);
      return NULL;
    }
  }
  r->ground =
      (material){.name = "ground", .texture = "ground", .tint = {1, 1, 1}, .gloss = 0.05f, .uv_scale = 0.5f};
  if (!load_material(desc->texture_dir, &r->ground, false, err) || !make_shadow_map(r, err)) {
    bk_renderer_destroy(r);
    return NULL;
  }
  make_ground(r);
  vertex_layout();
  make_sphere(r);
  make_particles(r);
  glGenVertexArrays(1, &r->line_vao);
  glGenBuffers(1, &r->line_vbo);
  glBindVertexArray(r->line_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->line_vbo);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(line_vertex),
                        (void*)offsetof(line_vertex, position));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, sizeof(line_vertex), (void*)offsetof(line_vertex, color));
  glGenVertexArrays(1, &r->empty_vao);
  glBindVertexArray(0);
  make_table(&r->loose_buffer, &r->loose_texture, 0);
  r->loose_gpu_capacity = 1;
  return r;
}

void bk_renderer_destroy(bk_renderer* r) {
  if (!r) return;
  for (uint32_t i = 0; i < r->tree_count; ++i)
    if (r->trees[i].used) bk_renderer_release_tree(r, (bk_render_tree){i, r->trees[i].generation});
  free(r->trees);
  GLuint programs[5] = {r->shadow_program, r->sky_programs[SKY_DOME], r->sky_programs[SKY_SUN],
                        r->particle_program, r->line_program};
  for (int i = 0; i < 5; ++i)
    if (programs[i]) glDeleteProgram(programs[i]);
  for (int i = 0; i < MESH_PROGRAMS; ++i)
    if (r->mesh_programs[i]) glDeleteProgram(r->mesh_programs[i]);
  for (int i = 0; i < r->material_count; ++i) {
    material* m = &r->materials[i];
    GLuint textures[3] = {m->albedo, m->normal, m->interior};
    glDeleteTextures(3, textures);
  }
  GLuint ground_textures[2] = {r->ground.albedo, r->ground.normal};
  glDeleteTextures(2, ground_textures);
  glDeleteTextures(1, &r->shadow_texture);
  glDeleteFramebuffers(1, &r->shadow_fbo);
  glDeleteTextures(1, &r->loose_texture);
  GLuint vaos[5] = {r->ground_vao, r->sphere_vao, r->particle_vao, r->line_vao, r->empty_vao};
  glDeleteVertexArrays(5, vaos);
  GLuint buffers[7] = {
      r->ground_vbo, r->sphere_vbo,  r->sphere_ibo, r->particle_quad_vbo, r->particle_instance_vbo,
      r->line_vbo,   r->loose_buffer};
  glDeleteBuffers(7, buffers);
  free(r->items);
  free(r->nodes);
  free(r->node_colors);
  free(r->multi_counts);
  free(r->multi_offsets);
  free(r->batches);
  free(r->drawn_trees);
  free(r->spills);
  free(r->loose);
  free(r->spheres);
  free(r->sphere_levels);
  free(r->lines);
  free(r);
}

static tree_buffers* find_tree(bk_renderer* r, bk_render_tree id) {
  if (id.generation == 0 || id.index >= r->tree_count) return NULL;
  tree_buffers* t = &r->trees[id.index];
  return t->used && t->generation == id.generation ? t : NULL;
}

// Copies of the nodes for SIMPLE, which draws nodes under
// simple_below_pixels wide: decimated (bk_mesh_decimate) while no point
// moves by more than 8% of the node's radius, under a pixel at that size;
// under tiny_below_pixels, that copy decimated again at 20% (a pixel at
// most). Vertex and triangle set-up is what a software renderer spends on a
// shard a few pixels wide: at the first level, shards of curved shapes keep
// 55-65% of their triangles and 55-65% of their vertices, flat ones ~85%.
static const double coarse_tolerance[COARSE_LEVELS] = {0.08, 0.2};

// One vertex per corner of `m`, all in `node`'s row of the table.
static uint32_t add_vertices(vertex* out, const bk_mesh* m, uint32_t node) {
  for (uint32_t c = 0; c < m->corner_count; ++c) {
    const bk_corner* corner = &m->corners[c];
    bk_vec3 p = m->positions[corner->position];
    out[c] = (vertex){{(float)p.x, (float)p.y, (float)p.z},
                      {corner->normal[0], corner->normal[1], corner->normal[2]},
                      {corner->uv[0], corner->uv[1]},
                      {corner->tangent[0], corner->tangent[1], corner->tangent[2], corner->tangent[3]},
                      node};
  }
  return m->corner_count;
}

// One section (outer surface or cut faces) of `count` meshes, mesh after
// mesh, appended at index_data[*k], each offset by its first vertex `base`;
// fills (fresh arrays) where each mesh's indices start and how many they are.
static void add_section(uint32_t* index_data, uint32_t* k, const bk_mesh* const* meshes, const uint32_t* base,
                        uint32_t count, bool interior, uint32_t** first, uint32_t** index_count) {
  *first = bk_alloc(sizeof(uint32_t) * count);
  *index_count = bk_alloc(sizeof(uint32_t) * count);
  for (uint32_t i = 0; i < count; ++i) {
    const bk_mesh* m = meshes[i];
    (*first)[i] = *k;
    for (uint32_t tri = 0; tri < m->triangle_count; ++tri)
      if (bk_material_is_interior(m->materials[tri]) == interior)
        for (int j = 0; j < 3; ++j)
          index_data[(*k)++] = base[i] + m->indices[3 * tri + j];
    (*index_count)[i] = *k - (*first)[i];
  }
}

bk_render_tree bk_renderer_upload_tree(bk_renderer* r, const bk_mesh_tree* tree) {
  uint32_t slot = 0;
  while (slot < r->tree_count && r->trees[slot].used)
    slot++;
  if (slot == r->tree_count) {
    if (r->tree_count == r->tree_capacity) {
      r->tree_capacity = bk_grow_capacity(r->tree_capacity, r->tree_count + 1);
      r->trees = bk_realloc(r->trees, sizeof(tree_buffers) * r->tree_capacity);
    }
    memset(&r->trees[r->tree_count], 0, sizeof(tree_buffers));
    r->tree_count++;
  }
  tree_buffers* t = &r->trees[slot];
  t->used = true;
  t->generation++;
  // One vertex per corner and one index per triangle corner, node after
  // node: the full meshes, then the coarse copies.
  const uint32_t nodes = tree->node_count, mesh_count = (COARSE_LEVELS + 1) * nodes;
  bk_mesh* coarse = bk_calloc((size_t)COARSE_LEVELS * nodes + 1, sizeof(bk_mesh)); // level by level
  // Every mesh drawn: the nodes', then each level's copies.
  const bk_mesh** meshes = bk_alloc(sizeof(bk_mesh*) * (mesh_count + 1));
  for (uint32_t i = 0; i < nodes; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[i];
    double radius = 0.5 * bk_v3_length(bk_v3_sub(node->bounds.max, node->bounds.min));
    meshes[i] = &node->mesh;
    for (uint32_t level = 0; level < COARSE_LEVELS; ++level) {
      bk_mesh* m = &coarse[level * nodes + i];
      bk_mesh_decimate(meshes[level * nodes + i], coarse_tolerance[level] * radius, m);
      meshes[(level + 1) * nodes + i] = m;
    }
  }
  uint64_t corners = 0, indices = 0;
  for (uint32_t i = 0; i < mesh_count; ++i) {
    corners += meshes[i]->corner_count;
    indices += 3ull * meshes[i]->triangle_count;
  }
  vertex* vertices = bk_alloc(sizeof(vertex) * (corners + 1));
  uint32_t* index_data = bk_alloc(sizeof(uint32_t) * (indices + 1));
  t->node_count = nodes;
  uint32_t* base = bk_alloc(sizeof(uint32_t) * (mesh_count + 1)); // per mesh: its first vertex
  uint32_t v = 0, k = 0;
  for (uint32_t i = 0; i < mesh_count; ++i) {
    base[i] = v;
    v += add_vertices(&vertices[v], meshes[i], i % nodes);
  }
  t->spheres = bk_alloc(sizeof(float[4]) * (nodes + 1));
  for (uint32_t i = 0; i < nodes; ++i) {
    const bk_mesh* m = &tree->nodes[i].mesh;
    const bk_aabb* box = &tree->nodes[i].bounds;
    bk_vec3 c = bk_v3_scale(bk_v3_add(box->min, box->max), 0.5);
    double radius = 0.0;
    for (uint32_t p = 0; p < m->position_count; ++p)
      radius = fmax(radius, bk_v3_length(bk_v3_sub(m->positions[p], c)));
    t->spheres[i][0] = (float)c.x, t->spheres[i][1] = (float)c.y, t->spheres[i][2] = (float)c.z;
    t->spheres[i][3] = (float)radius;
  }
  // Outer triangles of every node, then cut faces of every node; the same for each level's copies.
  for (int section = 0; section < SECTIONS; ++section)
    add_section(index_data, &k, meshes, base, nodes, section == INTERIOR, &t->first_index[section],
                &t->index_count[section]);
  for (uint32_t level = 0; level < COARSE_LEVELS; ++level)
    for (int section = 0; section < SECTIONS; ++section)
      add_section(index_data, &k, &meshes[(level + 1) * nodes], &base[(level + 1) * nodes], nodes,
                  section == INTERIOR, &t->coarse_first[level][section], &t->coarse_count[level][section]);
  for (uint32_t i = 0; i < COARSE_LEVELS * nodes; ++i)
    bk_mesh_free(&coarse[i]);
  free(coarse);
  free(meshes);
  free(base);
  glGenVertexArrays(1, &t->vao);
  glGenBuffers(1, &t->vbo);
  glGenBuffers(1, &t->ibo);
  glBindVertexArray(t->vao);
  glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(vertex) * v), vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t->ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * k), index_data, GL_STATIC_DRAW);
  vertex_layout();
  glEnableVertexAttribArray(NODE_ATTRIBUTE);
  glVertexAttribIPointer(NODE_ATTRIBUTE, 1, GL_UNSIGNED_INT, sizeof(vertex), (void*)offsetof(vertex, node));
  glBindVertexArray(0);
  free(vertices);
  free(index_data);
  make_table(&t->table_buffer, &t->table_texture, t->node_count);
  t->table = bk_calloc((size_t)t->node_count + 1, sizeof(float) * TABLE_FLOATS);
  t->node_frame = bk_calloc((size_t)t->node_count + 1, sizeof(uint32_t));
  t->node_batch = bk_calloc((size_t)t->node_count + 1, sizeof(uint32_t));
  t->node_level = bk_calloc((size_t)t->node_count + 1, 1);
  return (bk_render_tree){slot, t->generation};
}

void bk_renderer_release_tree(bk_renderer* r, bk_render_tree id) {
  tree_buffers* t = find_tree(r, id);
  if (!t) return;
  glDeleteVertexArrays(1, &t->vao);
  glDeleteTextures(1, &t->table_texture);
  GLuint buffers[3] = {t->vbo, t->ibo, t->table_buffer};
  glDeleteBuffers(3, buffers);
  for (int section = 0; section < SECTIONS; ++section) {
    free(t->first_index[section]);
    free(t->index_count[section]);
    for (int level = 0; level < COARSE_LEVELS; ++level) {
      free(t->coarse_first[level][section]);
      free(t->coarse_count[level][section]);
    }
  }
  free(t->spheres);
  free(t->table);
  free(t->node_frame);
  free(t->node_batch);
  free(t->node_level);
  uint32_t generation = t->generation;
  memset(t, 0, sizeof *t);
  t->generation = generation; // the next upload here gets a new id
}

int bk_renderer_material(const bk_renderer* r, const char* name) {
  for (int i = 0; i < r->material_count; ++i)
    if (name && strcmp(r->materials[i].name, name) == 0) return i;
  return 0;
}

void bk_renderer_begin_frame(bk_renderer* r, const bk_camera* camera, int width, int height) {
  r->camera = *camera;
  if (!(r->camera.fov_y > 0.0)) r->camera.fov_y = 60.0 * 3.14159265358979 / 180.0;
  if (!(r->camera.near_plane > 0.0)) r->camera.near_plane = 0.05;
  if (!(r->camera.far_plane > r->camera.near_plane)) r->camera.far_plane = 200.0;
  r->width = width > 0 ? width : 1;
  r->height = height > 0 ? height : 1;
  r->item_count = r->node_count = r->sphere_count = r->line_count = r->particle_count = 0;
  r->particles = NULL;
  memset(&r->stats, 0, sizeof r->stats);
}

// The node table stores the top three rows of the matrix (the last is 0 0 0 1).
static void model_rows(bk_transform t, float rows[12]) {
  versor q = {(float)t.rotation.x, (float)t.rotation.y, (float)t.rotation.z, (float)t.rotation.w};
  mat4 m = GLM_MAT4_IDENTITY_INIT;
  glm_quat_mat4(q, m);
  m[3][0] = (float)t.position.x;
  m[3][1] = (float)t.position.y;
  m[3][2] = (float)t.position.z;
  for (int row = 0; row < 3; ++row)
    for (int column = 0; column < 4; ++column)
      rows[4 * row + column] = m[column][row];
}

void bk_renderer_draw_nodes(bk_renderer* r, const bk_node_draw* d) {
  if (!find_tree(r, d->tree) || d->node_count == 0) return;
  if (r->item_count == r->item_capacity) {
    r->item_capacity = bk_grow_capacity(r->item_capacity, r->item_count + 1);
    r->items = bk_realloc(r->items, sizeof(draw_item) * r->item_capacity);
  }
  if (r->node_count + d->node_count > r->node_capacity) {
    r->node_capacity = bk_grow_capacity(r->node_capacity, r->node_count + d->node_count);
    r->nodes = bk_realloc(r->nodes, sizeof(uint32_t) * r->node_capacity);
    r->node_colors = bk_realloc(r->node_colors, sizeof(float) * 4u * r->node_capacity);
    r->multi_counts = bk_realloc(r->multi_counts, sizeof(GLsizei) * 2u * SECTIONS * r->node_capacity);
    r->multi_offsets = bk_realloc(r->multi_offsets, sizeof(void*) * 2u * SECTIONS * r->node_capacity);
  }
  draw_item* item = &r->items[r->item_count++];
  item->tree = d->tree;
  item->first_node = r->node_count;
  item->node_count = d->node_count;
  model_rows(d->model, item->rows);
  item->material = d->material >= 0 && d->material < r->material_count ? d->material : 0;
  item->interior_scale = d->interior_scale > 0.0 ? (float)d->interior_scale : 1.0f;
  item->colored = d->node_colors != NULL;
  memcpy(&r->nodes[r->node_count], d->nodes, sizeof(uint32_t) * d->node_count);
  if (d->node_colors)
    memcpy(&r->node_colors[4 * r->node_count], d->node_colors, sizeof(float) * 4 * d->node_count);
  r->node_count += d->node_count;
}

void bk_renderer_draw_sphere(bk_renderer* r, bk_vec3 center, double radius, const float rgb[3]) {
  if (r->sphere_count == r->sphere_capacity) {
    r->sphere_capacity = bk_grow_capacity(r->sphere_capacity, r->sphere_count + 1);
    r->spheres = bk_realloc(r->spheres, sizeof(float[7]) * r->sphere_capacity);
    r->sphere_levels = bk_realloc(r->sphere_levels, sizeof(int8_t[2]) * r->sphere_capacity);
  }
  float* s = r->spheres[r->sphere_count++];
  s[0] = (float)center.x, s[1] = (float)center.y, s[2] = (float)center.z, s[3] = (float)radius;
  s[4] = rgb[0], s[5] = rgb[1], s[6] = rgb[2];
}

void bk_renderer_draw_line(bk_renderer* r, bk_vec3 a, bk_vec3 b, const float rgba[4]) {
  if (r->line_count + 2 > r->line_vertex_capacity) {
    r->line_vertex_capacity = bk_grow_capacity(r->line_vertex_capacity, r->line_count + 2);
    r->lines = bk_realloc(r->lines, sizeof(line_vertex) * r->line_vertex_capacity);
  }
  r->lines[r->line_count++] =
      (line_vertex){{(float)a.x, (float)a.y, (float)a.z}, {rgba[0], rgba[1], rgba[2], rgba[3]}};
  r->lines[r->line_count++] =
      (line_vertex){{(float)b.x, (float)b.y, (float)b.z}, {rgba[0], rgba[1], rgba[2], rgba[3]}};
}

void bk_renderer_draw_particles(bk_renderer* r, const bk_particle_instance* particles, uint32_t count) {
  r->particles = particles;
  r->particle_count = count < r->max_particles ? count : r->max_particles;
}

static uint32_t find_batch(bk_renderer* r, const draw_item* item, bool simple) {
  // Few batches (about two per breakable), and a body's neighbours in the
  // list mostly share its batch: search from the newest.
  for (uint32_t b = r->batch_count; b-- > 0;) {
    const draw_batch* batch = &r->batches[b];
    if (batch->tree == item->tree.index && batch->material == item->material &&
        batch->interior_scale == item->interior_scale && batch->simple == simple)
      return b;
  }
  if (r->batch_count == r->batch_capacity) {
    r->batch_capacity = bk_grow_capacity(r->batch_capacity, r->batch_count + 1);
    r->batches = bk_realloc(r->batches, sizeof(draw_batch) * r->batch_capacity);
  }
  r->batches[r->batch_count] = (draw_batch){.tree = item->tree.index,
                                            .material = item->material,
                                            .interior_scale = item->interior_scale,
                                            .simple = simple};
  return r->batch_count++;
}

static void write_row(float* row, const float model[12], const float color[4]) {
  memcpy(row, model, sizeof(float) * 12);
  memcpy(row + 12, color, sizeof(float) * 4);
}

static float* loose_row(bk_renderer* r) {
  if (r->loose_count == r->loose_capacity) {
    r->loose_capacity = bk_grow_capacity(r->loose_capacity, r->loose_count + 1);
    r->loose = bk_realloc(r->loose, sizeof(float) * TABLE_FLOATS * r->loose_capacity);
  }
  return &r->loose[TABLE_FLOATS * r->loose_count++];
}

// Appends an index range, merged into the previous one when the two are
// adjacent in the index buffer (neighbouring nodes drawn together).
static void append_range(bk_renderer* r, uint32_t first, uint32_t* count, uint32_t indices, uint32_t start) {
  GLsizei* counts = &r->multi_counts[first];
  const void** offsets = &r->multi_offsets[first];
  uintptr_t offset = sizeof(uint32_t) * (uintptr_t)start;
  if (*count > 0 &&
      (uintptr_t)offsets[*count - 1] + sizeof(uint32_t) * (uintptr_t)counts[*count - 1] == offset) {
    counts[*count - 1] += (GLsizei)indices;
    return;
  }
  counts[*count] = (GLsizei)indices;
  offsets[*count] = (const void*)offset;
  (*count)++;
}

// Whether a sphere reaches into a volume given by six planes facing in.
static bool sphere_inside(vec4 planes[6], const float centre[3], float radius) {
  for (int i = 0; i < 6; ++i)
    if (planes[i][0] * centre[0] + planes[i][1] * centre[1] + planes[i][2] * centre[2] + planes[i][3] <
        -radius)
      return false;
  return true;
}

// Turns the frame's items into node table rows and batches, and uploads the
// tables (one buffer update per tree, one for the loose table). Both passes
// then draw from the same index ranges.
static void prepare_batches(bk_renderer* r) {
  if (++r->frame == 0) {
    // Wrapped: stamps from 2^32 frames ago would pass for this frame's.
    for (uint32_t i = 0; i < r->tree_count; ++i)
      if (r->trees[i].used) {
        memset(r->trees[i].node_frame, 0, sizeof(uint32_t) * r->trees[i].node_count);
        r->trees[i].frame = 0;
      }
    r->frame = 1;
  }
  if (r->drawn_tree_capacity < r->tree_count) {
    r->drawn_tree_capacity = r->tree_capacity;
    r->drawn_trees = bk_realloc(r->drawn_trees, sizeof(uint32_t) * r->drawn_tree_capacity);
  }
  r->batch_count = r->drawn_tree_count = r->spill_count = r->loose_count = 0;
  // Screen pixels per world unit at distance 1, and the eye.
  const float pixels_per_unit = 0.5f * (float)r->height / tanf(0.5f * (float)r->camera.fov_y);
  const float eye[3] = {(float)r->camera.eye.x, (float)r->camera.eye.y, (float)r->camera.eye.z};
  static const float no_color[4] = {0, 0, 0, 0};
  // The ground, then the spheres.
  write_row(loose_row(r), (const float[12]){1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}, no_color);
  for (uint32_t i = 0; i < r->sphere_count; ++i) {
    const float* s = r->spheres[i];
    const float rows[12] = {s[3], 0, 0, s[0], 0, s[3], 0, s[1], 0, 0, s[3], s[2]};
    write_row(loose_row(r), rows, no_color);
    float distance = sqrtf((s[0] - eye[0]) * (s[0] - eye[0]) + (s[1] - eye[1]) * (s[1] - eye[1]) +
                           (s[2] - eye[2]) * (s[2] - eye[2]));
    int level = 0;
    while (level + 1 < SPHERE_LEVELS && 2.0f * s[3] * pixels_per_unit < sphere_level_pixels[level] * distance)
      level++;
    // The shadow map has a texel per centimetre or so: a level coarser is enough.
    int shadow = level + 1 < SPHERE_LEVELS ? level + 1 : level;
    r->sphere_levels[i][0] = (int8_t)(sphere_inside(r->view_planes, s, s[3]) ? level : -1);
    r->sphere_levels[i][1] = (int8_t)(sphere_inside(r->light_planes, s, s[3]) ? shadow : -1);
  }
  for (uint32_t i = 0; i < r->item_count; ++i) {
    const draw_item* item = &r->items[i];
    tree_buffers* t = find_tree(r, item->tree);
    if (!t) continue;
    if (t->frame != r->frame) {
      t->frame = r->frame;
      t->lowest = UINT32_MAX;
      t->highest = 0;
      r->drawn_trees[r->drawn_tree_count++] = item->tree.index;
    }
    uint32_t detailed = find_batch(r, item, false), simple = UINT32_MAX;
    const float* m = item->rows;
    for (uint32_t k = 0; k < item->node_count; ++k) {
      uint32_t node = r->nodes[item->first_node + k];
      if (node >= t->node_count) continue;
      // How wide the node's bounding sphere looks: small ones draw simply.
      const float* sphere = t->spheres[node];
      float centre[3];
      for (int row = 0; row < 3; ++row)
        centre[row] = m[4 * row] * sphere[0] + m[4 * row + 1] * sphere[1] + m[4 * row + 2] * sphere[2] +
                      m[4 * row + 3] - eye[row];
      float distance = sqrtf(centre[0] * centre[0] + centre[1] * centre[1] + centre[2] * centre[2]);
      const float world[3] = {centre[0] + eye[0], centre[1] + eye[1], centre[2] + eye[2]};
      float pixels = 2.0f * sphere[3] * pixels_per_unit; // times the distance
      bool small = pixels < simple_below_pixels * distance;
      // Out of view, a node is drawn only into the shadow map, if it casts there.
      bool seen = sphere_inside(r->view_planes, world, sphere[3]);
      if (!seen && (small || !sphere_inside(r->light_planes, world, sphere[3]))) continue;
      if (seen && small && simple == UINT32_MAX) simple = find_batch(r, item, true);
      uint32_t b = !seen ? SHADOW_ONLY : small ? simple : detailed;
      const float* color = item->colored ? &r->node_colors[4 * (item->first_node + k)] : no_color;
      if (t->node_frame[node] == r->frame) {
        // Bodies own disjoint nodes, so this is rare (the API allows it).
        if (r->spill_count == r->spill_capacity) {
          r->spill_capacity = bk_grow_capacity(r->spill_capacity, r->spill_count + 1);
          r->spills = bk_realloc(r->spills, sizeof(spill_draw) * r->spill_capacity);
        }
        r->spills[r->spill_count++] = (spill_draw){.tree = item->tree.index,
                                                   .node = node,
                                                   .entry = r->loose_count,
                                                   .material = item->material,
                                                   .interior_scale = item->interior_scale};
        write_row(loose_row(r), item->rows, color);
        r->stats.triangles += 2 * ((t->index_count[SURFACE][node] + t->index_count[INTERIOR][node]) / 3);
        continue;
      }
      t->node_frame[node] = r->frame;
      t->node_batch[node] = b;
      t->node_level[node] = pixels < tiny_below_pixels * distance;
      write_row(&t->table[TABLE_FLOATS * node], item->rows, color);
      if (node < t->lowest) t->lowest = node;
      if (node > t->highest) t->highest = node;
      if (b != SHADOW_ONLY) r->batches[b].node_count++;
    }
  }
  uint32_t next_range = 0;
  for (uint32_t b = 0; b < r->batch_count; ++b)
    for (int section = 0; section < SECTIONS; ++section) {
      r->batches[b].first_range[section] = next_range;
      next_range += r->batches[b].node_count;
    }
  for (uint32_t i = 0; i < r->drawn_tree_count; ++i) {
    tree_buffers* t = &r->trees[r->drawn_trees[i]];
    t->first_shadow_range = next_range;
    t->shadow_range_count = 0;
    if (t->lowest > t->highest) continue;
    // In node order, so that neighbouring nodes merge into one range.
    for (int section = 0; section < SECTIONS; ++section) {
      for (uint32_t node = t->lowest; node <= t->highest; ++node) {
        if (t->node_frame[node] != r->frame) continue;
        uint32_t count = t->index_count[section][node], first = t->first_index[section][node];
        if (t->node_batch[node] == SHADOW_ONLY) {
          if (count == 0) continue;
          append_range(r, t->first_shadow_range, &t->shadow_range_count, count, first);
          r->stats.triangles += count / 3;
          continue;
        }
        draw_batch* batch = &r->batches[t->node_batch[node]];
        if (batch->simple) {
          // Small nodes draw coarse and cast no shadow: theirs would be a
          // few texels, and the shadow pass paid for every one of their
          // triangles (8 ms a frame with 1500 shards in view).
          int level = t->node_level[node];
          uint32_t coarse = t->coarse_count[level][section][node];
          if (coarse == 0) continue;
          append_range(r, batch->first_range[section], &batch->range_count[section], coarse,
                       t->coarse_first[level][section][node]);
          r->stats.triangles += coarse / 3;
          continue;
        }
        if (count == 0) continue;
        append_range(r, batch->first_range[section], &batch->range_count[section], count, first);
        append_range(r, t->first_shadow_range, &t->shadow_range_count, count, first);
        r->stats.triangles += 2 * (count / 3); // lit and shadow passes
      }
    }
    next_range += t->shadow_range_count;
    glBindBuffer(GL_TEXTURE_BUFFER, t->table_buffer);
    glBufferSubData(GL_TEXTURE_BUFFER, (GLintptr)(sizeof(float) * TABLE_FLOATS * t->lowest),
                    (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * (t->highest - t->lowest + 1)),
                    &t->table[TABLE_FLOATS * t->lowest]);
  }
  glBindBuffer(GL_TEXTURE_BUFFER, r->loose_buffer);
  GLsizeiptr loose_size = (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * r->loose_count);
  if (r->loose_count > r->loose_gpu_capacity) {
    r->loose_gpu_capacity = r->loose_capacity;
    glBufferData(GL_TEXTURE_BUFFER, (GLsizeiptr)(sizeof(float) * TABLE_FLOATS * r->loose_gpu_capacity), NULL,
                 GL_DYNAMIC_DRAW);
  }
  glBufferSubData(GL_TEXTURE_BUFFER, 0, loose_size, r->loose);
  glBindBuffer(GL_TEXTURE_BUFFER, 0);
}

static void bind_table(GLuint texture) {
  glActiveTexture(GL_TEXTURE0 + TABLE_UNIT);
  glBindTexture(GL_TEXTURE_BUFFER, texture);
}

// Binds what `program` samples of a material and sets its uniforms.
static void use_material(bk_renderer* r, int program, const material* m, float interior_scale) {
  const mesh_uniforms* u = &r->mesh_u[program];
  if (program != SIMPLE) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, program == INTERIOR ? m->interior : m->albedo);
  }
  if (program == SURFACE) {
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, m->normal);
  }
  glUniform3fv(u->tint, 1, m->tint);
  glUniform1f(u->gloss, m->gloss);
  glUniform1f(u->uv_scale, m->uv_scale);
  glUniform1f(u->interior_scale, interior_scale);
}

enum { DEPTH_ONLY = -1 }; // draw_scene's pass for the shadow map

// Everything that casts a shadow or is lit: trees and spheres (the ground
// only receives). `pass` is DEPTH_ONLY, which needs no materials (a tree is
// one call whatever its batches), or a program: SURFACE draws the outer
// surfaces of detailed batches and the spheres, INTERIOR their cut faces,
// SIMPLE both sections of the batches of small nodes, each in its mean colour.
static void draw_scene(bk_renderer* r, int pass) {
  bool shadow = pass == DEPTH_ONLY;
  if (pass == SIMPLE) {
    for (uint32_t b = 0; b < r->batch_count; ++b) {
      const draw_batch* batch = &r->batches[b];
      if (!batch->simple) continue;
      const tree_buffers* t = &r->trees[batch->tree];
      const material* m = &r->materials[batch->material];
      glBindVertexArray(t->vao);
      bind_table(t->table_texture);
      use_material(r, SIMPLE, m, batch->interior_scale);
      for (int section = 0; section < SECTIONS; ++section) {
        if (batch->range_count[section] == 0) continue;
        glUniform3fv(r->mesh_u[SIMPLE].mean_color, 1,
                     section == INTERIOR ? m->interior_mean : m->albedo_mean);
        glMultiDrawElements(GL_TRIANGLES, &r->multi_counts[batch->first_range[section]], GL_UNSIGNED_INT,
                            &r->multi_offsets[batch->first_range[section]],
                            (GLsizei)batch->range_count[section]);
        r->stats.draw_calls++;
      }
    }
    return;
  }
  int section = pass == INTERIOR ? INTERIOR : SURFACE;
  if (shadow) {
    for (uint32_t i = 0; i < r->drawn_tree_count; ++i) {
      const tree_buffers* t = &r->trees[r->drawn_trees[i]];
      if (t->shadow_range_count == 0) continue;
      glBindVertexArray(t->vao);
      bind_table(t->table_texture);
      glMultiDrawElements(GL_TRIANGLES, &r->multi_counts[t->first_shadow_range], GL_UNSIGNED_INT,
                          &r->multi_offsets[t->first_shadow_range], (GLsizei)t->shadow_range_count);
      r->stats.draw_calls++;
    }
  } else {
    for (uint32_t b = 0; b < r->batch_count; ++b) {
      const draw_batch* batch = &r->batches[b];
      if (batch->simple || batch->range_count[section] == 0) continue;
      const tree_buffers* t = &r->trees[batch->tree];
      glBindVertexArray(t->vao);
      bind_table(t->table_texture);
      use_material(r, pass, &r->materials[batch->material], batch->interior_scale);
      glMultiDrawElements(GL_TRIANGLES, &r->multi_counts[batch->first_range[section]], GL_UNSIGNED_INT,
                          &r->multi_offsets[batch->first_range[section]],
                          (GLsizei)batch->range_count[section]);
      r->stats.draw_calls++;
    }
  }
  bind_table(r->loose_texture);
  for (uint32_t i = 0; i < r->spill_count; ++i) {
    const spill_draw* s = &r->spills[i];
    const tree_buffers* t = &r->trees[s->tree];
    // With the attribute off, every vertex reads the constant: the spill's row.
    glBindVertexArray(t->vao);
    glDisableVertexAttribArray(NODE_ATTRIBUTE);
    glVertexAttribI4ui(NODE_ATTRIBUTE, s->entry, 0, 0, 0);
    if (!shadow) use_material(r, pass, &r->materials[s->material], s->interior_scale);
    for (int k = 0; k < SECTIONS; ++k) {
      uint32_t count = t->index_count[k][s->node];
      if ((!shadow && k != section) || count == 0) continue;
      glDrawElements(GL_TRIANGLES, (GLsizei)count, GL_UNSIGNED_INT,
                     (void*)(uintptr_t)(sizeof(uint32_t) * t->first_index[k][s->node]));
      r->stats.draw_calls++;
    }
    glEnableVertexAttribArray(NODE_ATTRIBUTE);
  }
  if (r->sphere_count == 0 || pass == INTERIOR) return;
  glBindVertexArray(r->sphere_vao);
  if (!shadow) {
    use_material(r, SURFACE, &r->materials[0], 1.0f);
    glUniform1f(r->mesh_u[SURFACE].gloss, 0.8f); // polished steel; the tint is per sphere
  }
  for (uint32_t i = 0; i < r->sphere_count; ++i) {
    const float* s = r->spheres[i];
    int level = r->sphere_levels[i][shadow ? 1 : 0];
    if (level < 0) continue;
    glVertexAttribI4ui(NODE_ATTRIBUTE, 1 + i, 0, 0, 0); // rows 1.. of the loose table
    if (!shadow) glUniform3f(r->mesh_u[SURFACE].tint, s[4], s[5], s[6]);
    glDrawElements(GL_TRIANGLES, (GLsizei)r->sphere_index_count[level], GL_UNSIGNED_INT,
                   (void*)(uintptr_t)(sizeof(uint32_t) * r->sphere_first[level]));
    r->stats.draw_calls++;
    r->stats.triangles += r->sphere_index_count[level] / 3;
  }
}

// The sky where the ground is not: drawn first, on the far plane, without
// depth writes, so that everything after covers it.
static void draw_sky(bk_renderer* r, mat4 view_projection, const vec3 sun) {
  const bk_camera* c = &r->camera;
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LEQUAL);
  // It stops below the horizon where the ground's far edge is seen:
  // the edge's slope from the eye, doubled because sky.vert measures it
  // along the view's heading (rays at the screen's sides, up to 60 degrees
  // off, see only half of it).
  double reach = fmax(1.0, ground_half_size - fmax(fabs(c->eye.x), fabs(c->eye.z)));
  float below_horizon = (float)fmax(0.05, 2.0 * (fabs(c->eye.y) + 1.0) / reach);
  vec3 heading = {(float)(c->target.x - c->eye.x), 0.0f, (float)(c->target.z - c->eye.z)};
  if (glm_vec3_norm(heading) < 1e-6f) heading[0] = 1.0f; // looking straight up or down
  glm_vec3_normalize(heading);
  glBindVertexArray(r->empty_vao);
  glEnable(GL_CLIP_DISTANCE0);
  for (int program = 0; program < SKY_PROGRAMS; ++program) {
    // The dome, then the sun's square over it (the clipper drops it when
    // the sun is behind the eye).
    const sky_uniforms* u = &r->sky_u[program];
    glUseProgram(r->sky_programs[program]);
    glUniformMatrix4fv(u->view_projection, 1, GL_FALSE, (const float*)view_projection);
    glUniform3fv(u->sun_direction, 1, sun);
    glUniform3fv(u->sky_color, 1, sky_color);
    glUniform3fv(u->horizon_color, 1, horizon_color);
    glUniform3fv(u->heading, 1, heading);
    glUniform1f(u->below_horizon, below_horizon);
    glDrawArrays(GL_TRIANGLES, 0, program == SKY_DOME ? sky_dome_vertices : 6);
  }
  glDisable(GL_CLIP_DISTANCE0);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
}

unsigned bk_renderer_end_frame(bk_renderer* r) {
  while (glGetError() != GL_NO_ERROR) {
  } // errors from before this frame are not ours
  bk_camera* c = &r->camera;
  mat4 view, projection, view_projection;
  glm_lookat((vec3){(float)c->eye.x, (float)c->eye.y, (float)c->eye.z},
             (vec3){(float)c->target.x, (float)c->target.y, (float)c->target.z}, (vec3){0, 1, 0}, view);
  glm_perspective((float)c->fov_y, (float)r->width / (float)r->height, (float)c->near_plane,
                  (float)c->far_plane, projection);
  glm_mat4_mul(projection, view, view_projection);
  // The sun's box follows the point the camera looks at.
  vec3 sun = {sun_direction[0], sun_direction[1], sun_direction[2]};
  glm_vec3_normalize(sun);
  vec3 focus = {(float)c->target.x, 0.0f, (float)c->target.z}, light_eye;
  glm_vec3_scale(sun, 30.0f, light_eye);
  glm_vec3_add(light_eye, focus, light_eye);
  mat4 light_view, light_projection, light_view_projection;
  glm_lookat(light_eye, focus, (vec3){0, 1, 0}, light_view);
  glm_ortho(-9.0f, 9.0f, -9.0f, 9.0f, 1.0f, 70.0f, light_projection);
  glm_mat4_mul(light_projection, light_view, light_view_projection);
  glm_frustum_planes(view_projection, r->view_planes);
  glm_frustum_planes(light_view_projection, r->light_planes);

  prepare_batches(r);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_FRAMEBUFFER_SRGB); // shaders encode sRGB themselves (common.glsl)

  // Shadow pass.
  glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo);
  glViewport(0, 0, r->shadow_size, r->shadow_size);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(r->shadow_program);
  glUniformMatrix4fv(r->shadow_light_view_projection, 1, GL_FALSE, (const float*)light_view_projection);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  draw_scene(r, DEPTH_ONLY);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  glViewport(0, 0, r->width, r->height);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);

  // The sky and the ground first, then a flush: llvmpipe rasterizes what
  // is flushed on its own threads while this one sets up the objects'
  // triangles, instead of one after the other at the swap. The price is the
  // ground and sky pixels that objects cover, shaded for nothing (early
  // depth tests skipped them when objects came first): less than the
  // overlap gains.
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, r->shadow_texture);
  draw_sky(r, view_projection, sun);
  const int order[MESH_PROGRAMS] = {GROUND, SURFACE, INTERIOR, SIMPLE};
  for (int i = 0; i < MESH_PROGRAMS; ++i) {
    int program = order[i];
    const mesh_uniforms* u = &r->mesh_u[program];
    glUseProgram(r->mesh_programs[program]);
    glUniformMatrix4fv(u->view_projection, 1, GL_FALSE, (const float*)view_projection);
    glUniformMatrix4fv(u->light_view_projection, 1, GL_FALSE, (const float*)light_view_projection);
    glUniform3fv(u->sun_direction, 1, sun);
    glUniform3fv(u->sun_color, 1, sun_color);
    glUniform3fv(u->sky_color, 1, sky_color);
    glUniform3fv(u->ground_color, 1, ground_bounce);
    glUniform3f(u->eye, (float)c->eye.x, (float)c->eye.y, (float)c->eye.z);
    if (program != GROUND) {
      draw_scene(r, program);
      continue;
    }
    // The ground: row 0 of the loose table.
    bind_table(r->loose_texture);
    glVertexAttribI4ui(NODE_ATTRIBUTE, 0, 0, 0, 0);
    use_material(r, GROUND, &r->ground, 1.0f);
    glBindVertexArray(r->ground_vao);
    glDrawArrays(GL_TRIANGLES, 0, 6);
    glFlush();
  }

  // Debug lines, then blended particles (no depth writes, so puffs overlap softly).
  if (r->line_count) {
    glUseProgram(r->line_program);
    glUniformMatrix4fv(r->line_view_projection, 1, GL_FALSE, (const float*)view_projection);
    glBindVertexArray(r->line_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->line_vbo);
    if (r->line_count > r->line_capacity) {
      r->line_capacity = r->line_vertex_capacity;
      glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(line_vertex) * r->line_capacity), NULL,
                   GL_STREAM_DRAW);
    }
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(line_vertex) * r->line_count), r->lines);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDisable(GL_DEPTH_TEST); // overlays show what is inside the solids (bonds, hulls)
    glDrawArrays(GL_LINES, 0, (GLsizei)r->line_count);
    glEnable(GL_DEPTH_TEST);
    r->stats.lines = r->line_count / 2;
  }
  if (r->particle_count) {
    glUseProgram(r->particle_program);
    glUniformMatrix4fv(r->particle_u.view_projection, 1, GL_FALSE, (const float*)view_projection);
    glUniform3f(r->particle_u.camera_right, view[0][0], view[1][0], view[2][0]);
    glUniform3f(r->particle_u.camera_up, view[0][1], view[1][1], view[2][1]);
    glBindVertexArray(r->particle_vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->particle_instance_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(bk_particle_instance) * r->particle_count),
                    r->particles);
    glEnable(GL_BLEND);
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    glDepthMask(GL_FALSE);
    glDrawArraysInstanced(GL_TRIANGLE_FAN, 0, 4, (GLsizei)r->particle_count);
    glDepthMask(GL_TRUE);
    r->stats.particles = r->particle_count;
  }
  glDisable(GL_BLEND);
  glBindVertexArray(0);
  glUseProgram(0);
  return glGetError();
}

bool bk_renderer_screenshot(bk_renderer* r, int width, int height, const char* path, bk_error* err) {
  (void)r;
  unsigned char* pixels = bk_alloc((size_t)width * (size_t)height * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels);
  stbi_flip_vertically_on_write(1); // GL rows start at the bottom
  int ok = stbi_write_png(path, width, height, 3, pixels, width * 3);
  free(pixels);
  if (!ok) return bk_error_set(err, "%s: cannot write the screenshot", path);
  return true;
}

bk_render_stats bk_renderer_stats(const bk_renderer* r) { return r->stats; }
