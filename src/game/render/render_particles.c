// Dust and debris. Chips are a few irregular low-poly shapes built here
// once, drawn instanced (one call per material and shape) with the
// material's interior texture, lit, without shadows. Dust puffs and glints
// are instanced camera-facing quads, blended after everything opaque
// without depth writes: a puff's shape is a tileable noise texture made
// here under a soft round falloff, lit per corner by the sun and the sky,
// faded where it meets the ground and near the eye. (Fading it against
// everything through a copy of the depth buffer cost 9 ms a frame in a
// showcase volley under llvmpipe, whose copy waits for the whole scene to
// be drawn: 20% of the frame, for edges the quads' lift towards the eye
// mostly avoids.)
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "render_internal.h"

enum {
  CHIP_SHAPES = 4,
  NOISE_SIZE = 64,
  NOISE_UNIT = 6, // texture units the mesh programs leave alone
  INTERIOR_UNIT = 0,
};

typedef struct chip_vertex {
  float position[3];
  float normal[3];
  float uv[2];
} chip_vertex;

struct debris_gpu {
  GLuint noise_texture;
  GLint puff_noise, puff_sun, puff_sun_color, puff_sky, puff_ground, puff_camera_back, puff_near, puff_eye;
  GLuint chip_program;
  GLint chip_view_projection, chip_sun, chip_sun_color, chip_sky, chip_ground, chip_eye, chip_gloss;
  GLuint chip_vao, chip_mesh_vbo, chip_instance_vbo;
  GLint shape_first[CHIP_SHAPES], shape_count[CHIP_SHAPES];
  const chip_instance* chips;
  uint32_t chip_count;
  chip_instance* sorted; // this frame's chips grouped by material and shape
  uint32_t* group_of;    // each chip's group (UINT32_MAX: not drawn)
  uint32_t sorted_capacity;
};

static uint32_t hash(uint32_t x) {
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

static float hash_unit(uint32_t x) { return (float)(hash(x) & 0xffffff) / (float)0x1000000; }

// Value noise of `period` cells across the texture, smoothly interpolated, so
// that it tiles; three octaves summed, stretched to the full byte range.
static void make_noise(unsigned char* out) {
  static float sum[NOISE_SIZE * NOISE_SIZE];
  float low = 1e9f, high = -1e9f;
  for (int y = 0; y < NOISE_SIZE; ++y)
    for (int x = 0; x < NOISE_SIZE; ++x) {
      float v = 0.0f;
      const int periods[3] = {4, 8, 16};
      const float weights[3] = {0.55f, 0.3f, 0.15f};
      for (int o = 0; o < 3; ++o) {
        int n = periods[o], cell = NOISE_SIZE / n;
        int cx = x / cell, cy = y / cell;
        float fx = (float)(x % cell) / (float)cell, fy = (float)(y % cell) / (float)cell;
        fx = fx * fx * (3.0f - 2.0f * fx), fy = fy * fy * (3.0f - 2.0f * fy);
        uint32_t base = 1000u * (uint32_t)o;
        float a = hash_unit(base + (uint32_t)(cy % n * n + cx % n));
        float b = hash_unit(base + (uint32_t)(cy % n * n + (cx + 1) % n));
        float c = hash_unit(base + (uint32_t)((cy + 1) % n * n + cx % n));
        float d = hash_unit(base + (uint32_t)((cy + 1) % n * n + (cx + 1) % n));
        v += weights[o] * ((a + (b - a) * fx) * (1.0f - fy) + (c + (d - c) * fx) * fy);
      }
      sum[y * NOISE_SIZE + x] = v;
      low = fminf(low, v), high = fmaxf(high, v);
    }
  for (int i = 0; i < NOISE_SIZE * NOISE_SIZE; ++i)
    out[i] = (unsigned char)(255.0f * (sum[i] - low) / (high - low) + 0.5f);
}

// A chip: a convex base shape (octahedron, wedge, box, bipyramid), squashed
// along its axes and its corners pulled in at random, so that each looks
// broken off. Faces are flat (own normals), wound outwards.
static uint32_t make_chip(int shape, chip_vertex* out) {
  static const float octahedron[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const int octahedron_faces[8][3] = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4},
                                             {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  static const float wedge[6][3] = {{-1, -0.6f, -0.8f}, {1, -0.6f, -0.8f}, {0, -0.6f, 1},
                                    {-1, 0.6f, -0.8f},  {1, 0.6f, -0.8f},  {0, 0.6f, 1}};
  static const int wedge_faces[8][3] = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3},
                                        {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
  static const float box[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  static const int box_faces[12][3] = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                                       {3, 7, 6}, {3, 6, 2}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  static const float bipyramid[5][3] = {
      {1, 0, 0}, {-0.5f, 0, 0.87f}, {-0.5f, 0, -0.87f}, {0, 1, 0}, {0, -1, 0}};
  static const int bipyramid_faces[6][3] = {{0, 3, 1}, {1, 3, 2}, {2, 3, 0}, {0, 1, 4}, {1, 2, 4}, {2, 0, 4}};
  const float(*corners)[3] = octahedron;
  const int(*faces)[3] = octahedron_faces;
  int corner_count = 6, face_count = 8;
  if (shape == 1) corners = wedge, faces = wedge_faces, corner_count = 6, face_count = 8;
  if (shape == 2) corners = box, faces = box_faces, corner_count = 8, face_count = 12;
  if (shape == 3) corners = bipyramid, faces = bipyramid_faces, corner_count = 5, face_count = 6;
  const float axes[CHIP_SHAPES][3] = {
      {1.0f, 0.45f, 0.8f}, {0.9f, 0.5f, 0.7f}, {0.8f, 0.35f, 0.6f}, {1.0f, 0.6f, 0.75f}};
  float p[8][3];
  float length = 0.0f;
  for (int i = 0; i < corner_count; ++i) {
    float pull = 0.65f + 0.35f * hash_unit(100u * (uint32_t)shape + (uint32_t)i);
    for (int k = 0; k < 3; ++k) {
      float shift = 0.2f * (hash_unit(500u + 100u * (uint32_t)shape + 3u * (uint32_t)i + (uint32_t)k) - 0.5f);
      p[i][k] = (corners[i][k] * pull + shift) * axes[shape][k];
    }
    length = fmaxf(length, sqrtf(p[i][0] * p[i][0] + p[i][1] * p[i][1] + p[i][2] * p[i][2]));
  }
  for (int i = 0; i < corner_count; ++i) // radius 1: chip_instance.size is the chip's radius
    for (int k = 0; k < 3; ++k)
      p[i][k] /= length;
  uint32_t n = 0;
  for (int f = 0; f < face_count; ++f) {
    const float *a = p[faces[f][0]], *b = p[faces[f][1]], *c = p[faces[f][2]];
    vec3 ab = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, normal;
    glm_vec3_cross(ab, ac, normal);
    glm_vec3_normalize(normal);
    vec3 centre = {(a[0] + b[0] + c[0]) / 3.0f, (a[1] + b[1] + c[1]) / 3.0f, (a[2] + b[2] + c[2]) / 3.0f};
    bool flip = glm_vec3_dot(normal, centre) < 0.0f; // the pulled corners may turn a face: keep it outward
    if (flip) glm_vec3_negate(normal);
    // Uvs in the face's plane: the interior texture lies flat on every face.
    vec3 tangent = {1, 0, 0}, bitangent;
    if (fabsf(normal[0]) > 0.8f) tangent[0] = 0.0f, tangent[1] = 1.0f;
    glm_vec3_cross(normal, tangent, bitangent);
    glm_vec3_normalize(bitangent);
    glm_vec3_cross(bitangent, normal, tangent);
    const float* order[3] = {a, flip ? c : b, flip ? b : c};
    for (int k = 0; k < 3; ++k, ++n) {
      memcpy(out[n].position, order[k], sizeof out[n].position);
      memcpy(out[n].normal, normal, sizeof out[n].normal);
      out[n].uv[0] = glm_vec3_dot((float*)order[k], tangent);
      out[n].uv[1] = glm_vec3_dot((float*)order[k], bitangent);
    }
  }
  return n;
}

static void instance_attribute(GLuint index, GLint size, size_t offset) {
  glEnableVertexAttribArray(index);
  glVertexAttribPointer(index, size, GL_FLOAT, GL_FALSE, sizeof(chip_instance), (void*)offset);
  glVertexAttribDivisor(index, 1);
}

// The chips' instance attributes, starting at instance `first` of the buffer
// (GL 3.3 has no base instance: each group points them at its own range).
static void chip_instances_at(uint32_t first) {
  size_t base = sizeof(chip_instance) * first;
  instance_attribute(3, 4, base + offsetof(chip_instance, position));
  instance_attribute(4, 4, base + offsetof(chip_instance, rotation));
  instance_attribute(5, 4, base + offsetof(chip_instance, tint));
}

static void make_chips(app_renderer* r, debris_gpu* d) {
  chip_vertex vertices[CHIP_SHAPES * 36];
  GLint used = 0;
  for (int s = 0; s < CHIP_SHAPES; ++s) {
    d->shape_first[s] = used;
    d->shape_count[s] = (GLint)make_chip(s, vertices + used);
    used += d->shape_count[s];
  }
  glGenVertexArrays(1, &d->chip_vao);
  glGenBuffers(1, &d->chip_mesh_vbo);
  glGenBuffers(1, &d->chip_instance_vbo);
  glBindVertexArray(d->chip_vao);
  glBindBuffer(GL_ARRAY_BUFFER, d->chip_mesh_vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(chip_vertex) * (size_t)used), vertices, GL_STATIC_DRAW);
  glEnableVertexAttribArray(0);
  glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(chip_vertex),
                        (void*)offsetof(chip_vertex, position));
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(chip_vertex), (void*)offsetof(chip_vertex, normal));
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, sizeof(chip_vertex), (void*)offsetof(chip_vertex, uv));
  glBindBuffer(GL_ARRAY_BUFFER, d->chip_instance_vbo);
  glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(chip_instance) * r->max_particles), NULL, GL_STREAM_DRAW);
  chip_instances_at(0);
  glBindVertexArray(0);
}

bool render_make_particles(app_renderer* r, const char* shader_dir, bk_error* err) {
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
  glBufferData(GL_ARRAY_BUFFER, sizeof(particle_instance) * r->max_particles, NULL, GL_STREAM_DRAW);
  const GLsizei stride = sizeof(particle_instance);
  glEnableVertexAttribArray(1);
  glVertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(particle_instance, position));
  glVertexAttribDivisor(1, 1);
  glEnableVertexAttribArray(2);
  glVertexAttribPointer(2, 4, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(particle_instance, color));
  glVertexAttribDivisor(2, 1);
  glEnableVertexAttribArray(3);
  glVertexAttribPointer(3, 2, GL_FLOAT, GL_FALSE, stride, (void*)offsetof(particle_instance, kind));
  glVertexAttribDivisor(3, 1);
  glBindVertexArray(0);

  debris_gpu* d = r->debris = bk_calloc(1, sizeof *d);
  unsigned char noise[NOISE_SIZE * NOISE_SIZE];
  make_noise(noise);
  glGenTextures(1, &d->noise_texture);
  glBindTexture(GL_TEXTURE_2D, d->noise_texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, NOISE_SIZE, NOISE_SIZE, 0, GL_RED, GL_UNSIGNED_BYTE, noise);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);

  GLuint p = r->particle_program;
  d->puff_noise = glGetUniformLocation(p, "u_noise");
  d->puff_sun = glGetUniformLocation(p, "u_sun_direction");
  d->puff_sun_color = glGetUniformLocation(p, "u_sun_color");
  d->puff_sky = glGetUniformLocation(p, "u_sky_color");
  d->puff_ground = glGetUniformLocation(p, "u_ground_color");
  d->puff_camera_back = glGetUniformLocation(p, "u_camera_back");
  d->puff_near = glGetUniformLocation(p, "u_near");
  d->puff_eye = glGetUniformLocation(p, "u_eye");
  glUseProgram(p);
  glUniform1i(d->puff_noise, NOISE_UNIT);

  if (!(d->chip_program = shader_load(shader_dir, "chip", NULL, err))) return false;
  p = d->chip_program;
  d->chip_view_projection = glGetUniformLocation(p, "u_view_projection");
  d->chip_sun = glGetUniformLocation(p, "u_sun_direction");
  d->chip_sun_color = glGetUniformLocation(p, "u_sun_color");
  d->chip_sky = glGetUniformLocation(p, "u_sky_color");
  d->chip_ground = glGetUniformLocation(p, "u_ground_color");
  d->chip_eye = glGetUniformLocation(p, "u_eye");
  d->chip_gloss = glGetUniformLocation(p, "u_gloss");
  glUseProgram(p);
  glUniform1i(glGetUniformLocation(p, "u_interior"), INTERIOR_UNIT);
  glUseProgram(0);
  make_chips(r, d);
  return true;
}

void render_free_particles(app_renderer* r) {
  debris_gpu* d = r->debris;
  if (!d) return;
  glDeleteTextures(1, &d->noise_texture);
  if (d->chip_program) glDeleteProgram(d->chip_program);
  glDeleteVertexArrays(1, &d->chip_vao);
  GLuint buffers[2] = {d->chip_mesh_vbo, d->chip_instance_vbo};
  glDeleteBuffers(2, buffers);
  free(d->sorted);
  free(d->group_of);
  free(d);
  r->debris = NULL;
}

void renderer_draw_particles(app_renderer* r, const particle_instance* particles, uint32_t count) {
  r->particles = particles;
  r->particle_count = count < r->max_particles ? count : r->max_particles;
}

void renderer_draw_chips(app_renderer* r, const chip_instance* chips, uint32_t count) {
  r->debris->chips = chips;
  r->debris->chip_count = count < r->max_particles ? count : r->max_particles;
}

uint32_t renderer_chip_shapes(void) { return CHIP_SHAPES; }

_Static_assert(sizeof(((app_renderer*)0)->materials) / sizeof(material) <= 8, "draw_chips' group arrays");

// Opaque, depth-tested and written like any mesh: sorted by material and
// shape (a counting sort), then one instanced call per group.
static void draw_chips(app_renderer* r, mat4 view_projection, const render_light* light) {
  debris_gpu* d = r->debris;
  uint32_t groups = (uint32_t)r->material_count * CHIP_SHAPES, start[8 * CHIP_SHAPES + 1] = {0};
  if (d->sorted_capacity < d->chip_count) {
    free(d->sorted);
    free(d->group_of);
    d->sorted_capacity = d->chip_count;
    d->sorted = bk_alloc(sizeof(chip_instance) * d->sorted_capacity);
    d->group_of = bk_alloc(sizeof(uint32_t) * d->sorted_capacity);
  }
  uint32_t* group_of = d->group_of;
  uint32_t drawn = 0;
  for (uint32_t i = 0; i < d->chip_count; ++i) {
    const chip_instance* c = &d->chips[i];
    group_of[i] = UINT32_MAX;
    if (!(c->size > 0.0f) || c->fade >= 1.0f) continue; // a NaN fade draws, as node_draw's
    int row = c->material >= 0 && c->material < r->material_count ? c->material : 0;
    group_of[i] = (uint32_t)row * CHIP_SHAPES + c->shape % CHIP_SHAPES;
    start[group_of[i] + 1]++;
    drawn++;
  }
  for (uint32_t g = 0; g < groups; ++g)
    start[g + 1] += start[g];
  uint32_t fill[8 * CHIP_SHAPES];
  memcpy(fill, start, sizeof fill);
  for (uint32_t i = 0; i < d->chip_count; ++i)
    if (group_of[i] != UINT32_MAX) d->sorted[fill[group_of[i]]++] = d->chips[i];
  if (drawn == 0) return;

  glUseProgram(d->chip_program);
  glUniformMatrix4fv(d->chip_view_projection, 1, GL_FALSE, (const float*)view_projection);
  glUniform3fv(d->chip_sun, 1, light->sun);
  glUniform3fv(d->chip_sun_color, 1, light->sun_color);
  glUniform3fv(d->chip_sky, 1, light->sky);
  glUniform3fv(d->chip_ground, 1, light->ground);
  glUniform3f(d->chip_eye, (float)r->camera.eye.x, (float)r->camera.eye.y, (float)r->camera.eye.z);
  glBindVertexArray(d->chip_vao);
  glBindBuffer(GL_ARRAY_BUFFER, d->chip_instance_vbo);
  glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(chip_instance) * drawn), d->sorted);
  glDisable(GL_BLEND);
  glDepthMask(GL_TRUE);
  glActiveTexture(GL_TEXTURE0 + INTERIOR_UNIT);
  for (uint32_t g = 0; g < groups; ++g) {
    if (start[g + 1] == start[g]) continue;
    const material* m = &r->materials[g / CHIP_SHAPES];
    glBindTexture(GL_TEXTURE_2D, m->interior);
    glUniform1f(d->chip_gloss, m->interior_gloss); // a chip is all broken surface
    chip_instances_at(start[g]);
    int shape = (int)(g % CHIP_SHAPES);
    glDrawArraysInstanced(GL_TRIANGLES, d->shape_first[shape], d->shape_count[shape],
                          (GLsizei)(start[g + 1] - start[g]));
    r->stats.draw_calls++;
    r->stats.triangles += (uint32_t)d->shape_count[shape] / 3 * (start[g + 1] - start[g]);
  }
  r->stats.chips = drawn;
}

void render_draw_particle_pass(app_renderer* r, mat4 view_projection, mat4 view, const render_light* light) {
  debris_gpu* d = r->debris;
  if (d->chip_count) draw_chips(r, view_projection, light);
  d->chip_count = 0; // chips are given per frame, as everything else
  d->chips = NULL;
  if (r->particle_count == 0) return;
  glUseProgram(r->particle_program);
  glUniformMatrix4fv(r->particle_u.view_projection, 1, GL_FALSE, (const float*)view_projection);
  glUniform3f(r->particle_u.camera_right, view[0][0], view[1][0], view[2][0]);
  glUniform3f(r->particle_u.camera_up, view[0][1], view[1][1], view[2][1]);
  glUniform3f(d->puff_camera_back, view[0][2], view[1][2], view[2][2]);
  glUniform3fv(d->puff_sun, 1, light->sun);
  glUniform3fv(d->puff_sun_color, 1, light->sun_color);
  glUniform3fv(d->puff_sky, 1, light->sky);
  glUniform3fv(d->puff_ground, 1, light->ground);
  glUniform1f(d->puff_near, (float)r->camera.near_plane);
  glUniform3f(d->puff_eye, (float)r->camera.eye.x, (float)r->camera.eye.y, (float)r->camera.eye.z);
  glActiveTexture(GL_TEXTURE0 + NOISE_UNIT);
  glBindTexture(GL_TEXTURE_2D, d->noise_texture);
  glBindVertexArray(r->particle_vao);
  glBindBuffer(GL_ARRAY_BUFFER, r->particle_instance_vbo);
  glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(particle_instance) * r->particle_count),
                  r->particles);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glDepthMask(GL_FALSE);
  glDrawArraysInstanced(GL_TRIANGLE_FAN, 0, 4, (GLsizei)r->particle_count);
  glDepthMask(GL_TRUE);
  glActiveTexture(GL_TEXTURE0);
  r->stats.particles = r->particle_count;
}
