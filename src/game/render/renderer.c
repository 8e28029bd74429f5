// The renderer's life and frame: create (programs, uniforms, materials,
// shadow map, fixed buffers) and destroy, material lookup, begin_frame,
// screenshots and stats. The draw list is in render_batches.c, the passes
// that play it at renderer_end_frame in render_passes.c.
#include <stb_image_write.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "render_internal.h"

// Glazed porcelains keep a matte body under their coat (gloss), which their
// cut faces show bare (interior_gloss); their tint keeps the body below
// white, so that a lit side still has shading and the glaze's highlight
// shows over it. Glass lets a greenish share of the light through each
// surface it crosses, and casts no shadow: most of the sun goes through it,
// and a lighter shadow left out a dithered share of the shadow map's texels,
// which the lit passes' one filtered lookup showed as a checkerboard on the
// ground (two lookups a pixel would smooth it, on every lit pixel).
static const material material_table[] = {
    {.name = "stone",
     .texture = "stone",
     .tint = {1, 1, 1},
     .gloss = 0.1f,
     .interior_gloss = 0.05f,
     .uv_scale = 1.0f,
     .shadow = 1.0f},
    {.name = "brick",
     .texture = "brick",
     .tint = {1, 1, 1},
     .gloss = 0.05f,
     .interior_gloss = 0.03f,
     .uv_scale = 1.0f,
     .shadow = 1.0f},
    {.name = "concrete",
     .texture = "concrete",
     .tint = {1, 1, 1},
     .gloss = 0.05f,
     .interior_gloss = 0.03f,
     .uv_scale = 1.0f,
     .shadow = 1.0f},
    {.name = "porcelain",
     .texture = "porcelain",
     .tint = {0.5f, 0.5f, 0.5f},
     .gloss = 0.3f,
     .interior_gloss = 0.05f,
     .uv_scale = 1.0f,
     .glaze = 1.0f,
     .shadow = 1.0f},
    {.name = "glass",
     .texture = "glass",
     .tint = {1, 1, 1},
     .gloss = 1.0f,
     .interior_gloss = 1.0f,
     .uv_scale = 1.0f,
     .transmit = {0.80f, 0.93f, 0.87f},
     .shadow = 0.0f},
    {.name = "eggshell",
     .texture = "eggshell",
     .tint = {0.6f, 0.6f, 0.6f},
     .gloss = 0.2f,
     .interior_gloss = 0.05f,
     .uv_scale = 1.0f,
     .glaze = 0.6f,
     .shadow = 1.0f},
    {.name = "wood",
     .texture = "wood",
     .tint = {1, 1, 1},
     .gloss = 0.15f,
     .interior_gloss = 0.05f,
     .uv_scale = 1.0f,
     .shadow = 1.0f},
};

// The programs that draw a material, from its numbers.
static void choose_programs(material* m) {
  bool transparent = m->transmit[0] > 0.0f || m->transmit[1] > 0.0f || m->transmit[2] > 0.0f;
  m->programs[SURFACE] = transparent ? GLASS_SURFACE : m->glaze > 0.0f ? GLAZED : SURFACE;
  m->programs[INTERIOR] = transparent ? GLASS_INTERIOR : INTERIOR;
  m->programs[SIMPLE] = transparent ? GLASS_SIMPLE : SIMPLE;
}

// The cut faces' relief and occlusion: optional, so a material without the
// file is drawn with a flat, open face (the renderer's flat_normal).
static bool load_interior_normal(const char* path, GLuint flat, GLuint* out, bk_error* err) {
  struct stat st = {0};
  if (stat(path, &st) != 0) {
    *out = flat;
    return true;
  }
  return (*out = texture_load_rgba(path, err)) != 0;
}

static bool load_material(const char* dir, material* m, bool has_interior, GLuint flat, bk_error* err) {
  char path[1024];
  choose_programs(m);
  m->interior_normal = flat;
  snprintf(path, sizeof path, "%s/%s_albedo.png", dir, m->texture);
  if (!(m->albedo = texture_load(path, true, m->albedo_mean, err))) return false;
  snprintf(path, sizeof path, "%s/%s_normal.png", dir, m->texture);
  if (!(m->normal = texture_load(path, false, NULL, err))) return false;
  if (has_interior) {
    snprintf(path, sizeof path, "%s/%s_interior.png", dir, m->texture);
    if (!(m->interior = texture_load(path, true, m->interior_mean, err))) return false;
    snprintf(path, sizeof path, "%s/%s_interior_normal.png", dir, m->texture);
    if (!load_interior_normal(path, flat, &m->interior_normal, err)) return false;
  } else {
    m->interior = m->albedo;
    memcpy(m->interior_mean, m->albedo_mean, sizeof m->interior_mean);
  }
  return true;
}

static bool make_shadow_map(app_renderer* r, bk_error* err) {
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

app_renderer* renderer_create(const renderer_def* desc, bk_error* err) {
  if (!desc->shader_dir || !desc->texture_dir)
    return bk_error_set(err, "renderer: shader_dir and texture_dir are required"), NULL;
  if (!desc->get_proc_address || !gladLoadGL((GLADloadfunc)desc->get_proc_address))
    return bk_error_set(err, "renderer: cannot load OpenGL 3.3 core functions"), NULL;
  app_renderer* r = bk_calloc(1, sizeof *r);
  r->shadow_size = desc->shadow_size > 0 ? desc->shadow_size : 1024;
  r->max_particles = desc->max_particles ? desc->max_particles : 16384;
  enum { OTHERS = 6, PROGRAMS = MESH_PROGRAMS + OTHERS };
  static const char* const mesh_variants[MESH_PROGRAMS] = {
      [SURFACE] = "SURFACE",
      [INTERIOR] = "INTERIOR",
      [SIMPLE] = "SIMPLE",
      [GROUND] = "GROUND",
      [GLAZED] = "SURFACE GLAZE",
      [GLASS_SURFACE] = "SURFACE GLASS",
      [GLASS_INTERIOR] = "INTERIOR GLASS",
      [GLASS_SIMPLE] = "SIMPLE GLASS",
  };
  const char* programs[PROGRAMS] = {"shadow", "shadow", "sky", "sky", "particle", "line"};
  const char* variants[PROGRAMS] = {NULL, "DITHERED", "DOME", "SUN"};
  GLuint* slots[PROGRAMS] = {&r->shadow_programs[SHADOW_SOLID],
                             &r->shadow_programs[SHADOW_DITHERED],
                             &r->sky_programs[SKY_DOME],
                             &r->sky_programs[SKY_SUN],
                             &r->particle_program,
                             &r->line_program};
  for (int i = 0; i < MESH_PROGRAMS; ++i) {
    programs[OTHERS + i] = "mesh";
    variants[OTHERS + i] = mesh_variants[i];
    slots[OTHERS + i] = &r->mesh_programs[i];
  }
  for (int i = 0; i < PROGRAMS; ++i)
    if (!(*slots[i] = shader_load(desc->shader_dir, programs[i], variants[i], err))) {
      renderer_destroy(r);
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
                                   .mean_color = uniform(p, "u_mean_color"),
                                   .horizon_color = uniform(p, "u_horizon_color"),
                                   .glaze = uniform(p, "u_glaze"),
                                   .transmit = uniform(p, "u_transmit")};
    // Texture units never change: set once, the program keeps them.
    glUseProgram(p);
    glUniform1i(uniform(p, "u_albedo"), 0);
    glUniform1i(uniform(p, "u_normal_map"), 1);
    glUniform1i(uniform(p, "u_shadow_map"), 3);
    glUniform1i(uniform(p, "u_nodes"), TABLE_UNIT);
  }
  for (int i = 0; i < SHADOW_PROGRAMS; ++i) {
    p = r->shadow_programs[i];
    glUseProgram(p);
    glUniform1i(uniform(p, "u_nodes"), TABLE_UNIT);
    r->shadow_light_view_projection[i] = uniform(p, "u_light_view_projection");
  }
  glUseProgram(0);
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
  r->flat_normal = texture_solid((const unsigned char[4]){128, 128, 255, 255});
  r->material_count = (int)(sizeof material_table / sizeof *material_table);
  for (int i = 0; i < r->material_count; ++i) {
    r->materials[i] = material_table[i];
    if (!load_material(desc->texture_dir, &r->materials[i], true, r->flat_normal, err)) {
      renderer_destroy(r);
      return NULL;
    }
  }
  r->ground = (material){.name = "ground",
                         .texture = "ground",
                         .tint = {1, 1, 1},
                         .gloss = 0.05f,
                         .uv_scale = 0.5f,
                         .shadow = 1.0f};
  if (!load_material(desc->texture_dir, &r->ground, false, r->flat_normal, err) || !make_shadow_map(r, err)) {
    renderer_destroy(r);
    return NULL;
  }
  render_make_ground(r);
  render_vertex_layout();
  render_make_sphere(r);
  if (!render_make_particles(r, desc->shader_dir, err)) {
    renderer_destroy(r);
    return NULL;
  }
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
  render_make_table(&r->loose_buffer, &r->loose_texture, 0);
  r->loose_gpu_capacity = 1;
  return r;
}

void renderer_destroy(app_renderer* r) {
  if (!r) return;
  for (uint32_t i = 0; i < r->tree_count; ++i)
    if (r->trees[i].used) renderer_release_tree(r, (app_render_tree){i, r->trees[i].generation});
  free(r->trees);
  render_free_particles(r);
  GLuint programs[6] = {r->shadow_programs[SHADOW_SOLID],
                        r->shadow_programs[SHADOW_DITHERED],
                        r->sky_programs[SKY_DOME],
                        r->sky_programs[SKY_SUN],
                        r->particle_program,
                        r->line_program};
  for (int i = 0; i < 6; ++i)
    if (programs[i]) glDeleteProgram(programs[i]);
  for (int i = 0; i < MESH_PROGRAMS; ++i)
    if (r->mesh_programs[i]) glDeleteProgram(r->mesh_programs[i]);
  for (int i = 0; i < r->material_count; ++i) {
    material* m = &r->materials[i];
    GLuint textures[4] = {m->albedo, m->normal, m->interior,
                          m->interior_normal != r->flat_normal ? m->interior_normal : 0};
    glDeleteTextures(m->model_look ? 1 : 4, textures);
  }
  GLuint ground_textures[3] = {r->ground.albedo, r->ground.normal, r->flat_normal};
  glDeleteTextures(3, ground_textures);
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
  free(r->glass_batches);
  free(r->glass_nodes);
  free(r->drawn_trees);
  free(r->spills);
  free(r->loose);
  free(r->spheres);
  free(r->sphere_levels);
  free(r->lines);
  free(r);
}

int renderer_model_look(app_renderer* r, int base, const void* image, size_t image_size,
                        const float color[3]) {
  const int builtin = (int)(sizeof material_table / sizeof *material_table);
  if (base < 0 || base >= builtin || builtin >= (int)(sizeof r->materials / sizeof *r->materials))
    return base;
  // The base's cut faces, numbers and programs; the model's colours on a
  // surface without relief, at its own UVs. The base's tint, which colours
  // its cut faces too, is divided out of the model's colour.
  material m = r->materials[base];
  float own[3] = {1.0f, 1.0f, 1.0f};
  for (int k = 0; k < 3; ++k)
    own[k] = (color ? color[k] : 1.0f) / (m.tint[k] > 0.0f ? m.tint[k] : 1.0f);
  bk_error err = {0};
  GLuint albedo = texture_load_memory_flipped(image, image_size, own, m.albedo_mean, &err);
  if (!albedo) {
    fprintf(stderr, "breakables: warning: the model is drawn without its texture: %s\n", err.message);
    albedo = texture_load_memory_flipped(NULL, 0, own, m.albedo_mean, &err);
  }
  if (r->material_count > builtin) glDeleteTextures(1, &r->materials[builtin].albedo);
  m.name = "model";
  m.model_look = true;
  m.albedo = albedo;
  m.normal = r->flat_normal;
  m.uv_scale = 1.0f;
  m.glaze = 0.0f;
  choose_programs(&m);
  r->materials[builtin] = m;
  r->material_count = builtin + 1;
  return builtin;
}

int app_renderer_material(const app_renderer* r, const char* name) {
  for (int i = 0; i < r->material_count; ++i)
    if (name && strcmp(r->materials[i].name, name) == 0) return i;
  return 0;
}

void renderer_begin_frame(app_renderer* r, const app_camera* camera, int width, int height) {
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

static void write_to_stream(void* context, void* data, int size) {
  fwrite(data, 1, (size_t)size, context); // a short write leaves the stream in error, which commit reports
}

bool renderer_screenshot(app_renderer* r, int width, int height, const char* path, bk_error* err) {
  (void)r;
  // Written beside the target and renamed over it, like every file the project writes.
  static const bk_atomic_messages messages = {"cannot write the screenshot", "cannot write the screenshot",
                                              "cannot write the screenshot"};
  bk_atomic_file file = {0};
  if (!bk_file_begin_atomic(path, &messages, &file, err)) return false;
  unsigned char* pixels = bk_alloc((size_t)width * (size_t)height * 3);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, pixels);
  stbi_flip_vertically_on_write(1); // GL rows start at the bottom
  int ok = stbi_write_png_to_func(write_to_stream, file.stream, width, height, 3, pixels, width * 3);
  free(pixels);
  if (!ok) {
    bk_file_abort_atomic(&file);
    return bk_error_set(err, "%s: cannot write the screenshot", path);
  }
  return bk_file_commit_atomic(&file, path, &messages, err);
}

render_stats renderer_stats(const app_renderer* r) { return r->stats; }
