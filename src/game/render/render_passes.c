// The passes that play a frame at renderer_end_frame: the sun's shadow
// map, the sky, the ground and the opaque programs of mesh.frag (with the
// material each binds), glass blended over them, then debug lines and
// particles.
#include <math.h>

#include "render_internal.h"

// The dome's cells (sky.vert: 48 segments, 19 bands), two triangles each.
static const GLsizei sky_dome_vertices = 48 * 19 * 6;

// Sun and sky: one place, used by every pass.
static const float sun_direction[3] = {-0.45f, 0.78f, 0.43f};
static const float sun_color[3] = {2.6f, 2.4f, 2.1f};
static const float sky_color[3] = {0.32f, 0.52f, 0.82f};
static const float horizon_color[3] = {0.78f, 0.84f, 0.9f};
static const float ground_bounce[3] = {0.35f, 0.3f, 0.25f};

static void bind_table(GLuint texture) {
  glActiveTexture(GL_TEXTURE0 + TABLE_UNIT);
  glBindTexture(GL_TEXTURE_BUFFER, texture);
}

// Binds what `program` samples of a material and sets its uniforms: the
// outer programs its albedo and normal map, the cut faces' its interior
// colour and relief (with occlusion in alpha); the SIMPLE ones no texture.
static void use_material(app_renderer* r, int program, const material* m, float interior_scale) {
  const mesh_uniforms* u = &r->mesh_u[program];
  bool interior = program == INTERIOR || program == GLASS_INTERIOR;
  if (program != SIMPLE && program != GLASS_SIMPLE) {
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, interior ? m->interior : m->albedo);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, interior ? m->interior_normal : m->normal);
  }
  glUniform3fv(u->tint, 1, m->tint);
  glUniform1f(u->gloss, interior ? m->interior_gloss : m->gloss);
  glUniform1f(u->uv_scale, m->uv_scale);
  glUniform1f(u->interior_scale, interior_scale);
  glUniform1f(u->glaze, m->glaze);
  glUniform3fv(u->transmit, 1, m->transmit);
}

// A batch's section drawn with `program`, from its ranges (in the order they were made).
static void draw_ranges(app_renderer* r, const draw_batch* batch, int section, int program) {
  const material* m = &r->materials[batch->material];
  if (batch->range_count[section] == 0) return;
  use_material(r, program, m, batch->interior_scale);
  if (batch->simple)
    glUniform3fv(r->mesh_u[program].mean_color, 1, section == INTERIOR ? m->interior_mean : m->albedo_mean);
  glMultiDrawElements(GL_TRIANGLES, &r->multi_counts[batch->first_range[section]], GL_UNSIGNED_INT,
                      &r->multi_offsets[batch->first_range[section]], (GLsizei)batch->range_count[section]);
  r->stats.draw_calls++;
}

static void use_tree(const tree_buffers* t) {
  glBindVertexArray(t->vao);
  bind_table(t->table_texture);
}

// The spilled nodes of opaque (or, with `transparent`, transparent)
// materials whose section draws with `program`; -1 draws every
// section for the shadow map.
static void draw_spills(app_renderer* r, int program, bool transparent) {
  bind_table(r->loose_texture);
  for (uint32_t i = 0; i < r->spill_count; ++i) {
    const spill_draw* s = &r->spills[i];
    const tree_buffers* t = &r->trees[s->tree];
    const material* m = &r->materials[s->material];
    if (program >= 0 && material_transparent(m) != transparent) continue;
    // With the attribute off, every vertex reads the constant: the spill's row.
    glBindVertexArray(t->vao);
    glDisableVertexAttribArray(NODE_ATTRIBUTE);
    glVertexAttribI4ui(NODE_ATTRIBUTE, s->entry, 0, 0, 0);
    for (int k = 0; k < SECTIONS; ++k) {
      uint32_t count = t->index_count[k][s->node];
      if ((program >= 0 && m->programs[k] != program) || count == 0) continue;
      if (program >= 0) use_material(r, program, m, s->interior_scale);
      glDrawElements(GL_TRIANGLES, (GLsizei)count, GL_UNSIGNED_INT,
                     (void*)(uintptr_t)(sizeof(uint32_t) * t->first_index[k][s->node]));
      r->stats.draw_calls++;
    }
    glEnableVertexAttribArray(NODE_ATTRIBUTE);
  }
}

// The projectiles: polished steel, each its own tint; `level` 0 for the lit pass, 1 for the shadow's.
static void draw_spheres(app_renderer* r, int level_pass) {
  if (r->sphere_count == 0) return;
  bool shadow = level_pass == 1;
  glBindVertexArray(r->sphere_vao);
  if (!shadow) {
    use_material(r, SURFACE, &r->materials[0], 1.0f);
    glUniform1f(r->mesh_u[SURFACE].gloss, 0.8f);
  }
  for (uint32_t i = 0; i < r->sphere_count; ++i) {
    const float* s = r->spheres[i];
    int level = r->sphere_levels[i][level_pass];
    if (level < 0) continue;
    glVertexAttribI4ui(NODE_ATTRIBUTE, 1 + i, 0, 0, 0); // rows 1.. of the loose table
    if (!shadow) glUniform3f(r->mesh_u[SURFACE].tint, s[4], s[5], s[6]);
    glDrawElements(GL_TRIANGLES, (GLsizei)r->sphere_index_count[level], GL_UNSIGNED_INT,
                   (void*)(uintptr_t)(sizeof(uint32_t) * r->sphere_first[level]));
    r->stats.draw_calls++;
    r->stats.triangles += r->sphere_index_count[level] / 3;
  }
}

// The shadow map: every tree in one call whatever its batches (the node
// table thins the shadows of fading and glass nodes), spills and spheres.
static void draw_shadow_casters(app_renderer* r, const float* light_view_projection) {
  for (int i = 0; i < SHADOW_PROGRAMS; ++i) {
    glUseProgram(r->shadow_programs[i]);
    glUniformMatrix4fv(r->shadow_light_view_projection[i], 1, GL_FALSE, light_view_projection);
  }
  int current = SHADOW_DITHERED;
  for (uint32_t i = 0; i < r->drawn_tree_count; ++i) {
    const tree_buffers* t = &r->trees[r->drawn_trees[i]];
    if (t->shadow_range_count == 0) continue;
    // Discard costs a software renderer on every texel: only trees that thin a shadow pay it.
    int program = t->shadow_dithered ? SHADOW_DITHERED : SHADOW_SOLID;
    if (program != current) glUseProgram(r->shadow_programs[current = program]);
    use_tree(t);
    glMultiDrawElements(GL_TRIANGLES, &r->multi_counts[t->first_shadow_range], GL_UNSIGNED_INT,
                        &r->multi_offsets[t->first_shadow_range], (GLsizei)t->shadow_range_count);
    r->stats.draw_calls++;
  }
  glUseProgram(r->shadow_programs[SHADOW_DITHERED]); // spills are rare: no need to sort them out
  draw_spills(r, -1, false);
  glUseProgram(r->shadow_programs[SHADOW_SOLID]); // the projectiles are opaque and never fade
  draw_spheres(r, 1);
}

// The opaque batches whose sections `program` draws (the current program):
// an outer program the outer surfaces of detailed batches whose material
// picks it (SURFACE also the spheres), INTERIOR their cut faces, SIMPLE both
// sections of the batches of small nodes, each in its mean colour.
static void draw_opaque(app_renderer* r, int program) {
  for (uint32_t b = 0; b < r->batch_count; ++b) {
    const draw_batch* batch = &r->batches[b];
    if (batch->transparent || batch->simple != (program == SIMPLE)) continue;
    const material* m = &r->materials[batch->material];
    bool any = false;
    for (int section = 0; section < SECTIONS; ++section)
      any |= batch->range_count[section] > 0 && m->programs[batch->simple ? SIMPLE : section] == program;
    if (!any) continue;
    use_tree(&r->trees[batch->tree]);
    for (int section = 0; section < SECTIONS; ++section)
      if (m->programs[batch->simple ? SIMPLE : section] == program) draw_ranges(r, batch, section, program);
  }
  draw_spills(r, program, false);
  if (program == SURFACE) draw_spheres(r, 0);
}

// Glass, after everything opaque: blended (colour plus the background
// times the colour the glass lets through: dual-source blending), depth
// tested but not written, batches farthest first and each batch's nodes back
// to front. Detailed pieces draw their back faces first, then their front
// faces, so that the far side of a piece shows through its near side.
static void draw_transparent(app_renderer* r) {
  bool spills = false;
  for (uint32_t i = 0; i < r->spill_count; ++i)
    spills |= material_transparent(&r->materials[r->spills[i].material]);
  if (r->glass_batch_count == 0 && !spills) return;
  glEnable(GL_BLEND);
  glBlendFunc(GL_ONE, GL_SRC1_COLOR);
  glDepthMask(GL_FALSE);
  for (uint32_t i = 0; i < r->glass_batch_count; ++i) {
    const draw_batch* batch = &r->batches[r->glass_batches[i]];
    const material* m = &r->materials[batch->material];
    use_tree(&r->trees[batch->tree]);
    if (batch->simple) {
      glUseProgram(r->mesh_programs[m->programs[SIMPLE]]);
      for (int section = 0; section < SECTIONS; ++section)
        draw_ranges(r, batch, section, m->programs[SIMPLE]);
      continue;
    }
    for (int side = 0; side < 2; ++side) {
      glCullFace(side == 0 ? GL_FRONT : GL_BACK);
      for (int section = 0; section < SECTIONS; ++section) {
        if (batch->range_count[section] == 0) continue;
        glUseProgram(r->mesh_programs[m->programs[section]]);
        draw_ranges(r, batch, section, m->programs[section]);
      }
    }
  }
  glCullFace(GL_BACK);
  for (int section = 0; spills && section < SECTIONS; ++section) {
    glUseProgram(r->mesh_programs[section == SURFACE ? GLASS_SURFACE : GLASS_INTERIOR]);
    draw_spills(r, section == SURFACE ? GLASS_SURFACE : GLASS_INTERIOR, true);
  }
  glDepthMask(GL_TRUE);
  glDisable(GL_BLEND);
}

// The sky where the ground is not: drawn first, on the far plane, without
// depth writes, so that everything after covers it. Nothing is drawn before
// it since the clear, so it needs no depth test either (a software renderer
// reads the depth of every pixel it tests).
static void draw_sky(app_renderer* r, mat4 view_projection, const vec3 sun) {
  const app_camera* c = &r->camera;
  glDisable(GL_DEPTH_TEST);
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
  glEnable(GL_DEPTH_TEST);
}

unsigned renderer_end_frame(app_renderer* r) {
  while (glGetError() != GL_NO_ERROR) {
  } // errors from before this frame are not ours
  app_camera* c = &r->camera;
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

  render_prepare_batches(r);

  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glEnable(GL_CULL_FACE);
  glDisable(GL_BLEND);
  glDisable(GL_FRAMEBUFFER_SRGB); // shaders encode sRGB themselves (common.glsl)

  // Shadow pass.
  glBindFramebuffer(GL_FRAMEBUFFER, r->shadow_fbo);
  glViewport(0, 0, r->shadow_size, r->shadow_size);
  glClear(GL_DEPTH_BUFFER_BIT);
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.5f, 2.0f);
  draw_shadow_casters(r, (const float*)light_view_projection);
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
  for (int program = 0; program < MESH_PROGRAMS; ++program) {
    // Every program's frame uniforms first: glass switches programs per batch.
    const mesh_uniforms* u = &r->mesh_u[program];
    glUseProgram(r->mesh_programs[program]);
    glUniformMatrix4fv(u->view_projection, 1, GL_FALSE, (const float*)view_projection);
    glUniformMatrix4fv(u->light_view_projection, 1, GL_FALSE, (const float*)light_view_projection);
    glUniform3fv(u->sun_direction, 1, sun);
    glUniform3fv(u->sun_color, 1, sun_color);
    glUniform3fv(u->sky_color, 1, sky_color);
    glUniform3fv(u->horizon_color, 1, horizon_color);
    glUniform3fv(u->ground_color, 1, ground_bounce);
    glUniform3f(u->eye, (float)c->eye.x, (float)c->eye.y, (float)c->eye.z);
  }
  // The ground: row 0 of the loose table.
  glUseProgram(r->mesh_programs[GROUND]);
  bind_table(r->loose_texture);
  glVertexAttribI4ui(NODE_ATTRIBUTE, 0, 0, 0, 0);
  use_material(r, GROUND, &r->ground, 1.0f);
  glBindVertexArray(r->ground_vao);
  glDrawArrays(GL_TRIANGLES, 0, 6);
  glFlush();
  const int opaque[] = {SURFACE, GLAZED, INTERIOR, SIMPLE};
  for (size_t i = 0; i < sizeof opaque / sizeof *opaque; ++i) {
    glUseProgram(r->mesh_programs[opaque[i]]);
    draw_opaque(r, opaque[i]);
  }
  draw_transparent(r);

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
  render_draw_particle_pass(
      r, view_projection, view,
      &(render_light){.sun = sun, .sun_color = sun_color, .sky = sky_color, .ground = ground_bounce});
  glDisable(GL_BLEND);
  glBindVertexArray(0);
  glUseProgram(0);
  return glGetError();
}
