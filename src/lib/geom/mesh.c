// The indexed mesh: storage, growth, copies, bounds, validation, welding,
// normals and tangents.
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"

void bk_mesh_free(bk_mesh* mesh) {
  bk_free(mesh->positions);
  bk_free(mesh->corners);
  bk_free(mesh->indices);
  bk_free(mesh->materials);
  bk_free(mesh->tags);
  memset(mesh, 0, sizeof *mesh);
}

void bk_mesh_reserve(bk_mesh* m, uint32_t positions, uint32_t corners, uint32_t triangles) {
  if (positions > m->position_capacity) {
    m->position_capacity = bk_grow_capacity(m->position_capacity, positions);
    m->positions = bk_realloc(m->positions, sizeof(bk_vec3) * m->position_capacity);
  }
  if (corners > m->corner_capacity) {
    m->corner_capacity = bk_grow_capacity(m->corner_capacity, corners);
    m->corners = bk_realloc(m->corners, sizeof(bk_corner) * m->corner_capacity);
  }
  if (triangles > m->triangle_capacity) {
    m->triangle_capacity = bk_grow_capacity(m->triangle_capacity, triangles);
    m->indices = bk_realloc(m->indices, sizeof(uint32_t) * 3u * m->triangle_capacity);
    m->materials = bk_realloc(m->materials, m->triangle_capacity);
    m->tags = bk_realloc(m->tags, sizeof(uint32_t) * m->triangle_capacity);
  }
}

uint32_t bk_mesh_add_position(bk_mesh* m, bk_vec3 p) {
  if (m->position_count == m->position_capacity) bk_mesh_reserve(m, m->position_count + 1, 0, 0);
  m->positions[m->position_count] = p;
  return m->position_count++;
}

uint32_t bk_mesh_add_corner(bk_mesh* m, const bk_corner* c) {
  if (m->corner_count == m->corner_capacity) bk_mesh_reserve(m, 0, m->corner_count + 1, 0);
  m->corners[m->corner_count] = *c;
  return m->corner_count++;
}

void bk_mesh_add_triangle(bk_mesh* m, uint32_t a, uint32_t b, uint32_t c, uint8_t material, uint32_t tag) {
  if (m->triangle_count == m->triangle_capacity) bk_mesh_reserve(m, 0, 0, m->triangle_count + 1);
  uint32_t t = m->triangle_count++;
  m->indices[3 * t + 0] = a;
  m->indices[3 * t + 1] = b;
  m->indices[3 * t + 2] = c;
  m->materials[t] = material;
  m->tags[t] = tag;
}

void bk_mesh_copy(bk_mesh* dst, const bk_mesh* src) {
  memset(dst, 0, sizeof *dst);
  bk_mesh_append(dst, src);
}

void bk_mesh_copy_exact(bk_mesh* dst, const bk_mesh* src) {
  dst->position_count = dst->position_capacity = src->position_count;
  dst->corner_count = dst->corner_capacity = src->corner_count;
  dst->triangle_count = dst->triangle_capacity = src->triangle_count;
  dst->positions = bk_alloc(sizeof(bk_vec3) * src->position_count);
  dst->corners = bk_alloc(sizeof(bk_corner) * src->corner_count);
  dst->indices = bk_alloc(sizeof(uint32_t) * 3u * src->triangle_count);
  dst->materials = bk_alloc(src->triangle_count);
  dst->tags = bk_alloc(sizeof(uint32_t) * src->triangle_count);
  if (src->position_count) memcpy(dst->positions, src->positions, sizeof(bk_vec3) * src->position_count);
  if (src->corner_count) memcpy(dst->corners, src->corners, sizeof(bk_corner) * src->corner_count);
  if (src->triangle_count) {
    memcpy(dst->indices, src->indices, sizeof(uint32_t) * 3u * src->triangle_count);
    memcpy(dst->materials, src->materials, src->triangle_count);
    memcpy(dst->tags, src->tags, sizeof(uint32_t) * src->triangle_count);
  }
}

void bk_mesh_append(bk_mesh* dst, const bk_mesh* src) {
  uint32_t p0 = dst->position_count, c0 = dst->corner_count, t0 = dst->triangle_count;
  bk_mesh_reserve(dst, p0 + src->position_count, c0 + src->corner_count, t0 + src->triangle_count);
  if (src->position_count) memcpy(dst->positions + p0, src->positions, sizeof(bk_vec3) * src->position_count);
  for (uint32_t i = 0; i < src->corner_count; ++i) {
    dst->corners[c0 + i] = src->corners[i];
    dst->corners[c0 + i].position += p0;
  }
  for (uint32_t i = 0; i < 3 * src->triangle_count; ++i)
    dst->indices[3 * t0 + i] = src->indices[i] + c0;
  if (src->triangle_count) {
    memcpy(dst->materials + t0, src->materials, src->triangle_count);
    memcpy(dst->tags + t0, src->tags, sizeof(uint32_t) * src->triangle_count);
  }
  dst->position_count += src->position_count;
  dst->corner_count += src->corner_count;
  dst->triangle_count += src->triangle_count;
}

bk_aabb bk_mesh_bounds(const bk_mesh* m) {
  bk_aabb box = {bk_v3(INFINITY, INFINITY, INFINITY), bk_v3(-INFINITY, -INFINITY, -INFINITY)};
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 p = m->positions[i]; // bk_v3_min and bk_v3_max, inline
    box.min = bk_v3(bk_min(box.min.x, p.x), bk_min(box.min.y, p.y), bk_min(box.min.z, p.z));
    box.max = bk_v3(bk_max(box.max.x, p.x), bk_max(box.max.y, p.y), bk_max(box.max.z, p.z));
  }
  return box;
}

void bk_mesh_fit_unit_height(bk_mesh* m) {
  bk_aabb box = bk_mesh_bounds(m);
  double height = box.max.y - box.min.y;
  if (!(height > 0.0)) return;
  double s = 1.0 / height;
  bk_vec3 centre = bk_v3(0.5 * (box.min.x + box.max.x), box.min.y, 0.5 * (box.min.z + box.max.z));
  for (uint32_t i = 0; i < m->position_count; ++i)
    m->positions[i] = bk_v3_scale(bk_v3_sub(m->positions[i], centre), s);
}

static bk_vec3 triangle_cross(const bk_mesh* m, uint32_t t) {
  bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_vec3 b = m->positions[bk_mesh_tri_position(m, t, 1)];
  bk_vec3 c = m->positions[bk_mesh_tri_position(m, t, 2)];
  return bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
}

double bk_mesh_area(const bk_mesh* m) {
  double area = 0.0;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    area += 0.5 * bk_v3_length(triangle_cross(m, t));
  return area;
}

static bool floats_finite(const float* f, int n) {
  for (int i = 0; i < n; ++i)
    if (!isfinite(f[i])) return false;
  return true;
}

bool bk_mesh_validate(const bk_mesh* m, bk_error* err) {
  if (m->triangle_count == 0) return bk_error_set(err, "mesh has no triangles");
  for (uint32_t i = 0; i < m->position_count; ++i)
    if (!bk_v3_is_finite(m->positions[i])) return bk_error_set(err, "position %u is not finite", i);
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    const bk_corner* c = &m->corners[i];
    if (c->position >= m->position_count)
      return bk_error_set(err, "corner %u uses position %u of %u", i, c->position, m->position_count);
    if (!floats_finite(c->normal, 3) || !floats_finite(c->uv, 2) || !floats_finite(c->tangent, 4))
      return bk_error_set(err, "corner %u has a non-finite attribute", i);
  }
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    for (int k = 0; k < 3; ++k)
      if (m->indices[3 * t + k] >= m->corner_count)
        return bk_error_set(err, "triangle %u uses corner %u of %u", t, m->indices[3 * t + k],
                            m->corner_count);
    // Every material byte is a valid id (bk_material_id): nothing to check.
  }
  return true;
}

uint32_t bk_mesh_weld(bk_mesh* m) {
  // Exact coordinate match: OBJ exporters repeat a shared vertex with the same
  // text, so exact bits are what "coincident" means on load. Never used on
  // sliced geometry, where topology comes from indices.
  bk_index_map map = {0};
  bk_index_map_init(&map, m->position_count);
  uint32_t* remap = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  uint32_t* first = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  uint32_t kept = 0;
  for (uint32_t i = 0; i < m->position_count; ++i) {
    bk_vec3 p = m->positions[i];
    p.x += 0.0, p.y += 0.0, p.z += 0.0; // -0 becomes +0
    uint64_t h = bk_hash_bytes(BK_FNV_OFFSET, &p, sizeof p);
    // Chain on hash collisions by probing successive keys.
    for (;;) {
      bool inserted = false;
      uint32_t* slot = bk_index_map_insert(&map, h, kept, &inserted);
      if (inserted) {
        first[kept] = i;
        remap[i] = kept++;
        break;
      }
      bk_vec3 q = m->positions[first[*slot]];
      if (q.x == p.x && q.y == p.y && q.z == p.z) {
        remap[i] = *slot;
        break;
      }
      h = h * 0x100000001b3ull + 1;
    }
  }
  for (uint32_t k = 0; k < kept; ++k)
    m->positions[k] = m->positions[first[k]];
  for (uint32_t i = 0; i < m->corner_count; ++i)
    m->corners[i].position = remap[m->corners[i].position];
  uint32_t merged = m->position_count - kept;
  m->position_count = kept;
  bk_free(remap);
  bk_free(first);
  bk_index_map_free(&map);
  return merged;
}

void bk_mesh_compute_normals(bk_mesh* m) {
  bk_vec3* acc = bk_calloc(m->position_count, sizeof(bk_vec3));
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 n = triangle_cross(m, t); // length = 2 * area: area weighting for free
    for (int k = 0; k < 3; ++k) {
      uint32_t p = bk_mesh_tri_position(m, t, k);
      acc[p] = bk_v3_add(acc[p], n);
    }
  }
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    bk_vec3 n = bk_v3_normalize(acc[m->corners[i].position]);
    m->corners[i].normal[0] = (float)n.x;
    m->corners[i].normal[1] = (float)n.y;
    m->corners[i].normal[2] = (float)n.z;
  }
  bk_free(acc);
}

void bk_mesh_compute_tangents(bk_mesh* m) {
  // Per-corner accumulation of the uv-derivative directions (Lengyel's method).
  bk_vec3* tan = bk_calloc(m->corner_count, sizeof(bk_vec3));
  bk_vec3* bit = bk_calloc(m->corner_count, sizeof(bk_vec3));
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    const uint32_t* idx = &m->indices[3 * t];
    const bk_corner *c0 = &m->corners[idx[0]], *c1 = &m->corners[idx[1]], *c2 = &m->corners[idx[2]];
    bk_vec3 e1 = bk_v3_sub(m->positions[c1->position], m->positions[c0->position]);
    bk_vec3 e2 = bk_v3_sub(m->positions[c2->position], m->positions[c0->position]);
    double du1 = c1->uv[0] - c0->uv[0], dv1 = c1->uv[1] - c0->uv[1];
    double du2 = c2->uv[0] - c0->uv[0], dv2 = c2->uv[1] - c0->uv[1];
    double det = du1 * dv2 - du2 * dv1;
    if (fabs(det) < 1e-20) continue;
    double r = 1.0 / det;
    bk_vec3 sdir = bk_v3_scale(bk_v3_sub(bk_v3_scale(e1, dv2), bk_v3_scale(e2, dv1)), r);
    bk_vec3 tdir = bk_v3_scale(bk_v3_sub(bk_v3_scale(e2, du1), bk_v3_scale(e1, du2)), r);
    for (int k = 0; k < 3; ++k) {
      tan[idx[k]] = bk_v3_add(tan[idx[k]], sdir);
      bit[idx[k]] = bk_v3_add(bit[idx[k]], tdir);
    }
  }
  for (uint32_t i = 0; i < m->corner_count; ++i) {
    bk_corner* c = &m->corners[i];
    bk_vec3 n = bk_v3(c->normal[0], c->normal[1], c->normal[2]);
    // Gram-Schmidt against the normal; fall back to any orthogonal direction.
    bk_vec3 t = bk_v3_sub(tan[i], bk_v3_scale(n, bk_v3_dot(n, tan[i])));
    double len = bk_v3_length(t);
    double w = 1.0;
    if (len < 1e-12) {
      bk_vec3 v;
      bk_plane_basis(bk_v3_length(n) > 0 ? n : bk_v3(0, 0, 1), &t, &v);
    } else {
      t = bk_v3_scale(t, 1.0 / len);
      w = bk_v3_dot(bk_v3_cross(n, t), bit[i]) < 0.0 ? -1.0 : 1.0;
    }
    c->tangent[0] = (float)t.x;
    c->tangent[1] = (float)t.y;
    c->tangent[2] = (float)t.z;
    c->tangent[3] = (float)w;
  }
  bk_free(tan);
  bk_free(bit);
}

uint64_t bk_mesh_hash(const bk_mesh* m) {
  uint64_t h = BK_FNV_OFFSET;
  uint32_t counts[3] = {m->position_count, m->corner_count, m->triangle_count};
  h = bk_hash_bytes(h, counts, sizeof counts);
  h = bk_hash_bytes(h, m->positions, sizeof(bk_vec3) * m->position_count);
  h = bk_hash_bytes(h, m->corners, sizeof(bk_corner) * m->corner_count);
  h = bk_hash_bytes(h, m->indices, sizeof(uint32_t) * 3u * m->triangle_count);
  h = bk_hash_bytes(h, m->materials, m->triangle_count);
  return h;
}
