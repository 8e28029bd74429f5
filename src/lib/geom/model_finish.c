// Finishing an imported mesh: welding (so UV and normal seams share
// positions), dropping what welding made degenerate, turning a mesh that is
// inside out, and filling in normals, UVs and tangents the file lacked.
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"
#include "model_import.h"

// ---------------------------------------------------------------- the mesh

// Welds positions (so UV and normal seams share them), drops triangles that
// weld made degenerate and everything no triangle uses, turns an inside-out
// mesh right and fills in normals, UVs and tangents.
bool bk_import_finish_mesh(import_state* s) {
  bk_mesh* m = &s->mesh;
  bk_import_info* info = s->info;
  if (m->triangle_count == 0) return bk_error_set(s->err, "%s: no triangles", s->name);
  info->welded_positions = bk_mesh_weld(m);
  uint32_t kept = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    uint32_t a = bk_mesh_tri_position(m, t, 0), b = bk_mesh_tri_position(m, t, 1),
             c = bk_mesh_tri_position(m, t, 2);
    if (a == b || b == c || c == a) {
      info->degenerate_triangles++;
      continue;
    }
    memmove(&m->indices[3 * kept], &m->indices[3 * t], 3 * sizeof(uint32_t));
    m->materials[kept] = m->materials[t];
    m->tags[kept++] = m->tags[t];
  }
  m->triangle_count = kept;
  if (kept == 0)
    return bk_error_set(s->err, "%s: no triangles (%u degenerate dropped)", s->name,
                        info->degenerate_triangles);
  // Keep only the corners and positions the triangles use.
  uint32_t* corner_map = bk_alloc(sizeof(uint32_t) * (m->corner_count + 1u));
  uint32_t* position_map = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  memset(corner_map, 0xff, sizeof(uint32_t) * m->corner_count);
  memset(position_map, 0xff, sizeof(uint32_t) * m->position_count);
  // Copies in order of first use (into fresh arrays: in place would overwrite unread entries).
  bk_vec3* old_positions = m->positions;
  bk_corner* old_corners = m->corners;
  bool* old_normal = s->corner_has_normal;
  bool* old_uv = s->corner_has_uv;
  m->positions = bk_alloc(sizeof(bk_vec3) * m->position_capacity);
  m->corners = bk_alloc(sizeof(bk_corner) * m->corner_capacity);
  s->corner_has_normal = bk_alloc(s->corner_flag_capacity + 1u);
  s->corner_has_uv = bk_alloc(s->corner_flag_capacity + 1u);
  uint32_t corners = 0, positions = 0;
  for (uint32_t i = 0; i < 3 * m->triangle_count; ++i) {
    uint32_t c = m->indices[i];
    if (corner_map[c] == UINT32_MAX) {
      uint32_t p = old_corners[c].position;
      if (position_map[p] == UINT32_MAX) {
        position_map[p] = positions;
        m->positions[positions++] = old_positions[p];
      }
      corner_map[c] = corners;
      m->corners[corners] = old_corners[c];
      m->corners[corners].position = position_map[p];
      s->corner_has_normal[corners] = old_normal[c];
      s->corner_has_uv[corners++] = old_uv[c];
    }
    m->indices[i] = corner_map[c];
  }
  m->corner_count = corners;
  m->position_count = positions;
  bk_free(old_positions);
  bk_free(old_corners);
  bk_free(old_normal);
  bk_free(old_uv);
  bk_free(corner_map);
  bk_free(position_map);

  // Inside out as a whole (every triangle wound clockwise seen from outside): turn it.
  if (bk_mesh_volume(m) < 0.0) {
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      uint32_t swap = m->indices[3 * t + 1];
      m->indices[3 * t + 1] = m->indices[3 * t + 2];
      m->indices[3 * t + 2] = swap;
    }
    info->flipped = true;
  }
  // Smooth normals everywhere; the file's own come back, turned to agree with
  // the winding if most of them disagree.
  float* given = bk_alloc(sizeof(float) * 3u * (m->corner_count + 1u));
  for (uint32_t i = 0; i < m->corner_count; ++i)
    memcpy(&given[3 * i], m->corners[i].normal, 3 * sizeof(float));
  bk_mesh_compute_normals(m);
  double agreement = 0.0;
  for (uint32_t i = 0; i < m->corner_count; ++i)
    if (s->corner_has_normal[i])
      for (int k = 0; k < 3; ++k)
        agreement += (double)given[3 * i + k] * m->corners[i].normal[k];
  float sign = agreement < 0.0 ? -1.0f : 1.0f;
  for (uint32_t i = 0; i < m->corner_count; ++i)
    if (s->corner_has_normal[i])
      for (int k = 0; k < 3; ++k)
        m->corners[i].normal[k] = sign * given[3 * i + k];
  bk_free(given);
  // Box projection where there are no UVs: drop the normal's dominant axis.
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    if (s->corner_has_uv[i]) continue;
    bk_corner* c = &m->corners[i];
    bk_vec3 q = m->positions[c->position];
    float ax = fabsf(c->normal[0]), ay = fabsf(c->normal[1]), az = fabsf(c->normal[2]);
    c->uv[0] = (float)(ax >= ay && ax >= az ? q.y : q.x);
    c->uv[1] = (float)(ax >= ay && ax >= az ? q.z : ay >= az ? q.z : q.y);
  }
  bk_mesh_compute_tangents(m);
  bk_error invalid = {0};
  return bk_mesh_validate(m, &invalid) || bk_error_set(s->err, "%s: %s", s->name, invalid.message);
}

// ---------------------------------------------------------------- PLY

// PLY read by our own reader: the counts, and a mesh inside out as a whole
// turned, as for assimp's formats.
bool bk_import_finish_ply(bool ok, const char* name, const bk_import_def* def, bk_mesh* out,
                          bk_import_info* info, bk_error* err) {
  if (!ok) return false;
  if (out->triangle_count > def->max_triangles) {
    bk_mesh_free(out);
    return bk_error_set(err, "%s: too many triangles (more than %u)", name, def->max_triangles);
  }
  snprintf(info->format, sizeof info->format, "ply");
  info->triangles_in = out->triangle_count;
  info->meshes = 1;
  if (bk_mesh_volume(out) < 0.0) {
    for (uint32_t t = 0; t < out->triangle_count; ++t) {
      uint32_t swap = out->indices[3 * t + 1];
      out->indices[3 * t + 1] = out->indices[3 * t + 2];
      out->indices[3 * t + 2] = swap;
    }
    for (uint32_t c = 0; c < out->corner_count; ++c)
      for (int k = 0; k < 3; ++k)
        out->corners[c].normal[k] = -out->corners[c].normal[k];
    bk_mesh_compute_tangents(out);
    info->flipped = true;
  }
  bk_import_single_material(info, out);
  return true;
}
