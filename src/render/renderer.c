// The renderer: uploaded trees, materials, the per-frame draw list, and the
// passes that play it (shadow, lit, sky, particles, lines).
#include <cglm/cglm.h>
#include <stb_image_write.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

typedef struct vertex {
  float position[3];
  float normal[3];
  float uv[2];
  float tangent[4];
  float interior;
} vertex;

typedef struct tree_buffers {
  uint32_t generation; // last generation handed out for this slot
  bool used;
  GLuint vao, vbo, ibo;
  uint32_t* first_index; // per node
  uint32_t* index_count; // per node
  uint32_t node_count;
} tree_buffers;

typedef struct material {
  const char* name;
  const char* texture; // file prefix
  GLuint albedo, normal, interior;
  float tint[3];
  float gloss;
  float uv_scale;
} material;

typedef struct draw_item {
  bk_render_tree tree;
  uint32_t first_node, node_count; // range in the frame's node array
  mat4 model;
  int material;
  float interior_scale;
  bool colored; // node colours follow the nodes in the frame's colour array
} draw_item;

typedef struct line_vertex {
  float position[3];
  float color[4];
} line_vertex;

struct bk_renderer {
  GLuint mesh_program, shadow_program, sky_program, particle_program, line_program;
  GLuint shadow_fbo, shadow_texture;
  int shadow_size;
  tree_buffers* trees;
  uint32_t tree_count, tree_capacity;
  material materials[8];
  int material_count;
  material ground;
  GLuint ground_vao, ground_vbo;
  GLuint sphere_vao, sphere_vbo, sphere_ibo;
  uint32_t sphere_index_count;
  GLuint particle_vao, particle_quad_vbo, particle_instance_vbo;
  uint32_t max_particles;
  GLuint line_vao, line_vbo;
  uint32_t line_capacity;
  GLuint empty_vao; // the sky draws from gl_VertexID only
  // This frame.
  bk_camera camera;
  int width, height;
  draw_item* items;
  uint32_t item_count, item_capacity;
  uint32_t* nodes;
  float* node_colors;
  uint32_t node_count, node_capacity;
  GLsizei* multi_counts; // per node of one item, for glMultiDrawElements
  const void** multi_offsets;
  float (*spheres)[7]; // center, radius, rgb
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
  if (!(m->albedo = bk_texture_load(path, true, err))) return false;
  snprintf(path, sizeof path, "%s/%s_normal.png", dir, m->texture);
  if (!(m->normal = bk_texture_load(path, false, err))) return false;
  if (has_interior) {
    snprintf(path, sizeof path, "%s/%s_interior.png", dir, m->texture);
    if (!(m->interior = bk_texture_load(path, true, err))) return false;
  } else {
    m->interior = m->albedo;
  }
  return true;
}

static void make_ground(bk_renderer* r) {
  // A large quad; uvs in metres so the paving keeps its size.
  const float s = 60.0f;
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
  glEnableVertexAttribArray(4);
  glVertexAttribPointer(4, 1, GL_FLOAT, GL_FALSE, sizeof(vertex), (void*)offsetof(vertex, interior));
}

static void make_sphere(bk_renderer* r) {
  enum { RINGS = 12, SEGMENTS = 20 };
  vertex vertices[(RINGS + 1) * (SEGMENTS + 1)];
  uint32_t indices[RINGS * SEGMENTS * 6];
  uint32_t v = 0, i = 0;
  for (int ring = 0; ring <= RINGS; ++ring)
    for (int seg = 0; seg <= SEGMENTS; ++seg) {
      float theta = (float)ring / RINGS * 3.14159265f, phi = (float)seg / SEGMENTS * 6.2831853f;
      float n[3] = {sinf(theta) * cosf(phi), cosf(theta), sinf(theta) * sinf(phi)};
      vertices[v++] = (vertex){{n[0], n[1], n[2]},
                               {n[0], n[1], n[2]},
                               {(float)seg / SEGMENTS * 2, (float)ring / RINGS},
                               {-sinf(phi), 0, cosf(phi), 1},
                               0};
    }
  for (int ring = 0; ring < RINGS; ++ring)
    for (int seg = 0; seg < SEGMENTS; ++seg) {
      uint32_t a = (uint32_t)(ring * (SEGMENTS + 1) + seg), b = a + SEGMENTS + 1;
      uint32_t quad[6] = {a, a + 1, b, a + 1, b + 1, b};
      memcpy(&indices[i], quad, sizeof quad);
      i += 6;
    }
  r->sphere_index_count = i;
  glGenVertexArrays(1, &r->sphere_vao);
  glGenBuffers(1, &r->sphere_vbo);
  glGenBuffers(1, &r->sphere_ibo);
  glBindVertexArray(r->sphere_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->sphere_vbo);
  glBufferData(GL_ARRAY_BUFFER, sizeof vertices, vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->sphere_ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, sizeof indices, indices, GL_STATIC_DRAW);
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

bk_renderer* bk_renderer_create(const bk_renderer_desc* desc, bk_error* err) {
  if (!desc->shader_dir || !desc->texture_dir)
    return bk_error_set(err, "renderer: shader_dir and texture_dir are required"), NULL;
  if (!desc->get_proc_address || !gladLoadGL((GLADloadfunc)desc->get_proc_address))
    return bk_error_set(err, "renderer: cannot load OpenGL 3.3 core functions"), NULL;
  bk_renderer* r = bk_calloc(1, sizeof *r);
  r->shadow_size = desc->shadow_size > 0 ? desc->shadow_size : 1024;
  r->max_particles = desc->max_particles ? desc->max_particles : 16384;
  const char* programs[5] = {"mesh", "shadow", "sky", "particle", "line"};
  GLuint* slots[5] = {&r->mesh_program, &r->shadow_program, &r->sky_program, &r->particle_program,
                      &r->line_program};
  for (int i = 0; i < 5; ++i)
    if (!(*slots[i] = bk_shader_load(desc->shader_dir, programs[i], err))) {
      bk_renderer_destroy(r);
      return NULL;
    }
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
  return r;
}

void bk_renderer_destroy(bk_renderer* r) {
  if (!r) return;
  for (uint32_t i = 0; i < r->tree_count; ++i)
    if (r->trees[i].used) bk_renderer_release_tree(r, (bk_render_tree){i, r->trees[i].generation});
  free(r->trees);
  GLuint programs[5] = {r->mesh_program, r->shadow_program, r->sky_program, r->particle_program,
                        r->line_program};
  for (int i = 0; i < 5; ++i)
    if (programs[i]) glDeleteProgram(programs[i]);
  for (int i = 0; i < r->material_count; ++i) {
    material* m = &r->materials[i];
    GLuint textures[3] = {m->albedo, m->normal, m->interior};
    glDeleteTextures(3, textures);
  }
  GLuint ground_textures[2] = {r->ground.albedo, r->ground.normal};
  glDeleteTextures(2, ground_textures);
  glDeleteTextures(1, &r->shadow_texture);
  glDeleteFramebuffers(1, &r->shadow_fbo);
  GLuint vaos[5] = {r->ground_vao, r->sphere_vao, r->particle_vao, r->line_vao, r->empty_vao};
  glDeleteVertexArrays(5, vaos);
  GLuint buffers[6] = {
      r->ground_vbo, r->sphere_vbo, r->sphere_ibo, r->particle_quad_vbo, r->particle_instance_vbo,
      r->line_vbo};
  glDeleteBuffers(6, buffers);
  free(r->items);
  free(r->nodes);
  free(r->node_colors);
  free(r->multi_counts);
  free(r->multi_offsets);
  free(r->spheres);
  free(r->lines);
  free(r);
}

static tree_buffers* find_tree(bk_renderer* r, bk_render_tree id) {
  if (id.generation == 0 || id.index >= r->tree_count) return NULL;
  tree_buffers* t = &r->trees[id.index];
  return t->used && t->generation == id.generation ? t : NULL;
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
  // One vertex per corner and one index per triangle corner, node after node.
  uint64_t corners = 0, indices = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    corners += tree->nodes[i].mesh.corner_count;
    indices += 3ull * tree->nodes[i].mesh.triangle_count;
  }
  vertex* vertices = bk_alloc(sizeof(vertex) * (corners + 1));
  uint32_t* index_data = bk_alloc(sizeof(uint32_t) * (indices + 1));
  t->node_count = tree->node_count;
  t->first_index = bk_alloc(sizeof(uint32_t) * tree->node_count);
  t->index_count = bk_alloc(sizeof(uint32_t) * tree->node_count);
  uint32_t v = 0, k = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const bk_mesh* m = &tree->nodes[i].mesh;
    uint32_t base = v;
    for (uint32_t c = 0; c < m->corner_count; ++c) {
      const bk_corner* corner = &m->corners[c];
      bk_vec3 p = m->positions[corner->position];
      vertex* out = &vertices[v++];
      *out = (vertex){{(float)p.x, (float)p.y, (float)p.z},
                      {corner->normal[0], corner->normal[1], corner->normal[2]},
                      {corner->uv[0], corner->uv[1]},
                      {corner->tangent[0], corner->tangent[1], corner->tangent[2], corner->tangent[3]},
                      0.0f};
    }
    t->first_index[i] = k;
    for (uint32_t tri = 0; tri < m->triangle_count; ++tri) {
      float interior = m->materials[tri] == BK_MATERIAL_INTERIOR ? 1.0f : 0.0f;
      for (int j = 0; j < 3; ++j) {
        uint32_t corner = m->indices[3 * tri + j];
        index_data[k++] = base + corner;
        // A corner belongs to faces of one material (cuts make their own corners).
        vertices[base + corner].interior = interior;
      }
    }
    t->index_count[i] = k - t->first_index[i];
  }
  glGenVertexArrays(1, &t->vao);
  glGenBuffers(1, &t->vbo);
  glGenBuffers(1, &t->ibo);
  glBindVertexArray(t->vao);
  glBindBuffer(GL_ARRAY_BUFFER, t->vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(vertex) * v), vertices, GL_STATIC_DRAW);
  glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, t->ibo);
  glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * k), index_data, GL_STATIC_DRAW);
  vertex_layout();
  glBindVertexArray(0);
  free(vertices);
  free(index_data);
  return (bk_render_tree){slot, t->generation};
}

void bk_renderer_release_tree(bk_renderer* r, bk_render_tree id) {
  tree_buffers* t = find_tree(r, id);
  if (!t) return;
  glDeleteVertexArrays(1, &t->vao);
  GLuint buffers[2] = {t->vbo, t->ibo};
  glDeleteBuffers(2, buffers);
  free(t->first_index);
  free(t->index_count);
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

static void model_matrix(bk_transform t, mat4 out) {
  versor q = {(float)t.rotation.x, (float)t.rotation.y, (float)t.rotation.z, (float)t.rotation.w};
  glm_quat_mat4(q, out);
  out[3][0] = (float)t.position.x;
  out[3][1] = (float)t.position.y;
  out[3][2] = (float)t.position.z;
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
    r->multi_counts = bk_realloc(r->multi_counts, sizeof(GLsizei) * r->node_capacity);
    r->multi_offsets = bk_realloc(r->multi_offsets, sizeof(void*) * r->node_capacity);
  }
  draw_item* item = &r->items[r->item_count++];
  item->tree = d->tree;
  item->first_node = r->node_count;
  item->node_count = d->node_count;
  model_matrix(d->model, item->model);
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

static GLint uniform(GLuint program, const char* name) { return glGetUniformLocation(program, name); }

// Everything that casts a shadow or is lit: trees, spheres (and the ground,
// which only receives). `shadow` selects the depth-only program.
static void draw_scene(bk_renderer* r, GLuint program, bool shadow) {
  GLint model_location = uniform(program, "u_model");
  GLint highlight = shadow ? -1 : uniform(program, "u_highlight");
  for (uint32_t i = 0; i < r->item_count; ++i) {
    const draw_item* item = &r->items[i];
    tree_buffers* t = find_tree(r, item->tree);
    if (!t) continue;
    glUniformMatrix4fv(model_location, 1, GL_FALSE, (const float*)item->model);
    if (!shadow) {
      const material* m = &r->materials[item->material];
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, m->albedo);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, m->normal);
      glActiveTexture(GL_TEXTURE2);
      glBindTexture(GL_TEXTURE_2D, m->interior);
      glUniform3fv(uniform(program, "u_tint"), 1, m->tint);
      glUniform1f(uniform(program, "u_gloss"), m->gloss);
      glUniform1f(uniform(program, "u_uv_scale"), m->uv_scale);
      glUniform1f(uniform(program, "u_interior_scale"), item->interior_scale);
      glUniform4f(highlight, 0, 0, 0, 0);
    }
    glBindVertexArray(t->vao);
    if (!shadow && item->colored) {
      // Overlay colours differ per node: one call each.
      for (uint32_t n = 0; n < item->node_count; ++n) {
        uint32_t node = r->nodes[item->first_node + n];
        if (node >= t->node_count) continue;
        glUniform4fv(highlight, 1, &r->node_colors[4 * (item->first_node + n)]);
        glDrawElements(GL_TRIANGLES, (GLsizei)t->index_count[node], GL_UNSIGNED_INT,
                       (void*)(uintptr_t)(sizeof(uint32_t) * t->first_index[node]));
        r->stats.draw_calls++;
        r->stats.triangles += t->index_count[node] / 3;
      }
      continue;
    }
    // All of a body's nodes share its matrix and material: one call.
    GLsizei n = 0;
    for (uint32_t k = 0; k < item->node_count; ++k) {
      uint32_t node = r->nodes[item->first_node + k];
      if (node >= t->node_count) continue;
      r->multi_counts[n] = (GLsizei)t->index_count[node];
      r->multi_offsets[n] = (const void*)(uintptr_t)(sizeof(uint32_t) * t->first_index[node]);
      r->stats.triangles += t->index_count[node] / 3;
      n++;
    }
    glMultiDrawElements(GL_TRIANGLES, r->multi_counts, GL_UNSIGNED_INT, r->multi_offsets, n);
    r->stats.draw_calls++;
  }
  glBindVertexArray(r->sphere_vao);
  for (uint32_t i = 0; i < r->sphere_count; ++i) {
    const float* s = r->spheres[i];
    mat4 model = GLM_MAT4_IDENTITY_INIT;
    glm_translate(model, (vec3){s[0], s[1], s[2]});
    glm_scale_uni(model, s[3]);
    glUniformMatrix4fv(model_location, 1, GL_FALSE, (const float*)model);
    if (!shadow) {
      const material* m = &r->materials[0];
      glActiveTexture(GL_TEXTURE0);
      glBindTexture(GL_TEXTURE_2D, m->albedo);
      glActiveTexture(GL_TEXTURE1);
      glBindTexture(GL_TEXTURE_2D, m->normal);
      glUniform3f(uniform(program, "u_tint"), s[4], s[5], s[6]);
      glUniform1f(uniform(program, "u_gloss"), 0.8f);
      glUniform1f(uniform(program, "u_uv_scale"), 1.0f);
      glUniform4f(highlight, 0, 0, 0, 0);
    }
    glDrawElements(GL_TRIANGLES, (GLsizei)r->sphere_index_count, GL_UNSIGNED_INT, NULL);
    r->stats.draw_calls++;
  }
}

unsigned bk_renderer_end_frame(bk_renderer* r) {
  while (glGetError() != GL_NO_ERROR) {
  } // errors from before this frame are not ours
  bk_camera* c = &r->camera;
  mat4 view, projection, view_projection, inverse_view_projection;
  glm_lookat((vec3){(float)c->eye.x, (float)c->eye.y, (float)c->eye.z},
             (vec3){(float)c->target.x, (float)c->target.y, (float)c->target.z}, (vec3){0, 1, 0}, view);
  glm_perspective((float)c->fov_y, (float)r->width / (float)r->height, (float)c->near_plane,
                  (float)c->far_plane, projection);
  glm_mat4_mul(projection, view, view_projection);
  glm_mat4_inv(view_projection, inverse_view_projection);
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

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_FRAMEBUFFER_SRGB);

  // Shadow pass.
  glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo);
  glViewport(0, 0, r->shadow_size, r->shadow_size);
  glClear(GL_DEPTH_BUFFER_BIT);
  glUseProgram(r->shadow_program);
  glUniformMatrix4fv(uniform(r->shadow_program, "u_light_view_projection"), 1, GL_FALSE,
                     (const float*)light_view_projection);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  draw_scene(r, r->shadow_program, true);
  glDisable(GL_POLYGON_OFFSET_FILL);
  glBindFramebuffer(GL_FRAMEBUFFER, 0);

  glViewport(0, 0, r->width, r->height);
  glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  glEnable(GL_FRAMEBUFFER_SRGB); // shaders write linear colour

  // Lit pass.
  GLuint p = r->mesh_program;
  glUseProgram(p);
  glUniformMatrix4fv(uniform(p, "u_view_projection"), 1, GL_FALSE, (const float*)view_projection);
  glUniformMatrix4fv(uniform(p, "u_light_view_projection"), 1, GL_FALSE, (const float*)light_view_projection);
  glUniform3fv(uniform(p, "u_sun_direction"), 1, sun);
  glUniform3fv(uniform(p, "u_sun_color"), 1, sun_color);
  glUniform3fv(uniform(p, "u_sky_color"), 1, sky_color);
  glUniform3fv(uniform(p, "u_ground_color"), 1, ground_bounce);
  glUniform3f(uniform(p, "u_eye"), (float)c->eye.x, (float)c->eye.y, (float)c->eye.z);
  glUniform1i(uniform(p, "u_albedo"), 0);
  glUniform1i(uniform(p, "u_normal_map"), 1);
  glUniform1i(uniform(p, "u_interior"), 2);
  glUniform1i(uniform(p, "u_shadow_map"), 3);
  glUniform1i(uniform(p, "u_detail"), 1);
  glActiveTexture(GL_TEXTURE3);
  glBindTexture(GL_TEXTURE_2D, r->shadow_texture);
  // Objects before the ground and the sky: on a software renderer every
  // shaded pixel counts, and early depth tests skip what they hide.
  draw_scene(r, p, false);
  // Ground.
  mat4 identity = GLM_MAT4_IDENTITY_INIT;
  glUniformMatrix4fv(uniform(p, "u_model"), 1, GL_FALSE, (const float*)identity);
  glActiveTexture(GL_TEXTURE0);
  glBindTexture(GL_TEXTURE_2D, r->ground.albedo);
  glActiveTexture(GL_TEXTURE1);
  glBindTexture(GL_TEXTURE_2D, r->ground.normal);
  glActiveTexture(GL_TEXTURE2);
  glBindTexture(GL_TEXTURE_2D, r->ground.albedo);
  glUniform3fv(uniform(p, "u_tint"), 1, r->ground.tint);
  glUniform1f(uniform(p, "u_gloss"), r->ground.gloss);
  glUniform1f(uniform(p, "u_uv_scale"), r->ground.uv_scale);
  glUniform1f(uniform(p, "u_interior_scale"), 1.0f);
  glUniform4f(uniform(p, "u_highlight"), 0, 0, 0, 0);
  glUniform1i(uniform(p, "u_detail"), 0);
  glBindVertexArray(r->ground_vao);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glUniform1i(uniform(p, "u_detail"), 1);

  // Sky last, only where nothing was drawn (depth still at the far plane).
  glDepthMask(GL_FALSE);
  glDepthFunc(GL_LEQUAL);
  glUseProgram(r->sky_program);
  glUniformMatrix4fv(uniform(r->sky_program, "u_inverse_view_projection"), 1, GL_FALSE,
                     (const float*)inverse_view_projection);
  glUniform3fv(uniform(r->sky_program, "u_sun_direction"), 1, sun);
  glUniform3fv(uniform(r->sky_program, "u_sky_color"), 1, sky_color);
  glUniform3fv(uniform(r->sky_program, "u_horizon_color"), 1, horizon_color);
  glBindVertexArray(r->empty_vao);
  glDrawArrays(GL_TRIANGLES, 0, 3);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);

  // Debug lines, then blended particles (no depth writes, so puffs overlap softly).
  if (r->line_count) {
    glUseProgram(r->line_program);
    glUniformMatrix4fv(uniform(r->line_program, "u_view_projection"), 1, GL_FALSE,
                       (const float*)view_projection);
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
    glUniformMatrix4fv(uniform(r->particle_program, "u_view_projection"), 1, GL_FALSE,
                       (const float*)view_projection);
    glUniform3f(uniform(r->particle_program, "u_camera_right"), view[0][0], view[1][0], view[2][0]);
    glUniform3f(uniform(r->particle_program, "u_camera_up"), view[0][1], view[1][1], view[2][1]);
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
  glDisable(GL_FRAMEBUFFER_SRGB); // the UI draws in sRGB already
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
