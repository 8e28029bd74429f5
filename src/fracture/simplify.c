// Planar face re-triangulation. Cutting a triangle leaves three, and every
// later cut through the slivers leaves more, so without this a cube's
// fragments carry ~190 triangles each after 12 levels of cuts. Here the
// triangles of each planar face (coplanar, sharing corners, same material and
// cut) are replaced by a triangulation of the face's outline over its true
// corners only: vertices inside a face, or on the straight edge between
// exactly two faces, are dropped from both faces at once, so the mesh stays
// closed. Corner attributes of kept vertices are unchanged (they are linear
// over a planar face, so nothing visible moves).
#include <stdlib.h>
#include <string.h>

#include "cap.h"

#define NONE UINT32_MAX

struct bk_face_simplifier {
  uint32_t* group;     // per triangle: face id (union-find, then compacted)
  bk_vec3* normal;     // per triangle: cross product of its edges
  uint32_t* face_a;    // per position: first face touching it
  uint32_t* face_b;    // per position: second face, NONE, or MANY
  uint32_t* new_index; // per position / corner remap
  uint32_t* corner_new;
  uint32_t tri_capacity, position_capacity, corner_capacity;
  bk_index_map tri_of_edge;    // directed position edge -> triangle
  bk_index_map corner_of_face; // (face, position) -> corner
  bk_index_map next_on_face;   // (face, position) -> next boundary position
  uint32_t* face_edges;        // boundary edges of one face (local ids)
  uint32_t* face_global;       // local id -> position
  double* xy;
  uint32_t edge_capacity;
  bk_index_map local_of_position;
  uint8_t* face_redo; // per face: re-triangulate
  uint32_t face_capacity;
  uint32_t* face_first_tri; // per face: one triangle (material and tag)
  bk_vec3* face_normal;     // per face: unit area-weighted normal
  uint32_t* outline;        // outline edges (face, a, b), bucketed by face
  uint32_t* outline_sorted;
  uint32_t* face_outline_start; // per face + 1: start in outline_sorted
  uint32_t outline_capacity;
  bk_cap* cap;
  bool keep_cuts;
};

#define MANY (UINT32_MAX - 1)

static uint32_t find(uint32_t* parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

bk_face_simplifier* bk_face_simplifier_create(void) {
  bk_face_simplifier* fs = bk_calloc(1, sizeof *fs);
  fs->cap = bk_cap_create();
  bk_index_map_init(&fs->tri_of_edge, 64);
  bk_index_map_init(&fs->corner_of_face, 64);
  bk_index_map_init(&fs->next_on_face, 64);
  bk_index_map_init(&fs->local_of_position, 64);
  return fs;
}

void bk_face_simplifier_destroy(bk_face_simplifier* fs) {
  if (!fs) return;
  free(fs->group);
  free(fs->normal);
  free(fs->face_a);
  free(fs->face_b);
  free(fs->new_index);
  free(fs->corner_new);
  free(fs->face_edges);
  free(fs->face_global);
  free(fs->xy);
  free(fs->face_redo);
  free(fs->face_first_tri);
  free(fs->face_normal);
  free(fs->outline);
  free(fs->outline_sorted);
  free(fs->face_outline_start);
  bk_cap_destroy(fs->cap);
  bk_index_map_free(&fs->tri_of_edge);
  bk_index_map_free(&fs->corner_of_face);
  bk_index_map_free(&fs->next_on_face);
  bk_index_map_free(&fs->local_of_position);
  free(fs);
}

static void reserve(bk_face_simplifier* fs, const bk_mesh* m) {
  if (m->triangle_count > fs->tri_capacity) {
    fs->tri_capacity = bk_grow_capacity(fs->tri_capacity, m->triangle_count);
    fs->group = bk_realloc(fs->group, sizeof(uint32_t) * fs->tri_capacity);
    fs->normal = bk_realloc(fs->normal, sizeof(bk_vec3) * fs->tri_capacity);
    fs->face_redo = bk_realloc(fs->face_redo, fs->tri_capacity);
    fs->face_first_tri = bk_realloc(fs->face_first_tri, sizeof(uint32_t) * fs->tri_capacity);
    fs->face_normal = bk_realloc(fs->face_normal, sizeof(bk_vec3) * fs->tri_capacity);
    fs->face_outline_start = bk_realloc(fs->face_outline_start, sizeof(uint32_t) * (fs->tri_capacity + 1u));
  }
  if (3u * m->triangle_count > fs->outline_capacity) {
    fs->outline_capacity = bk_grow_capacity(fs->outline_capacity, 3u * m->triangle_count);
    fs->outline = bk_realloc(fs->outline, sizeof(uint32_t) * 3u * fs->outline_capacity);
    fs->outline_sorted = bk_realloc(fs->outline_sorted, sizeof(uint32_t) * 3u * fs->outline_capacity);
  }
  if (m->position_count > fs->position_capacity) {
    fs->position_capacity = bk_grow_capacity(fs->position_capacity, m->position_count);
    fs->face_a = bk_realloc(fs->face_a, sizeof(uint32_t) * fs->position_capacity);
    fs->face_b = bk_realloc(fs->face_b, sizeof(uint32_t) * fs->position_capacity);
    fs->new_index = bk_realloc(fs->new_index, sizeof(uint32_t) * fs->position_capacity);
  }
  if (m->corner_count > fs->corner_capacity) {
    fs->corner_capacity = bk_grow_capacity(fs->corner_capacity, m->corner_count);
    fs->corner_new = bk_realloc(fs->corner_new, sizeof(uint32_t) * fs->corner_capacity);
  }
}

static void reserve_face_edges(bk_face_simplifier* fs, uint32_t edges) {
  if (edges <= fs->edge_capacity) return;
  fs->edge_capacity = bk_grow_capacity(fs->edge_capacity, edges);
  fs->face_edges = bk_realloc(fs->face_edges, sizeof(uint32_t) * 2u * fs->edge_capacity);
  fs->face_global = bk_realloc(fs->face_global, sizeof(uint32_t) * 2u * fs->edge_capacity);
  fs->xy = bk_realloc(fs->xy, sizeof(double) * 4u * fs->edge_capacity);
}

static inline uint64_t face_key(uint32_t face, uint32_t position) {
  return ((uint64_t)face << 32) | position;
}

// A position can go when it lies inside one face, or on the edge between two
// faces that are not parallel (then it is on their line of intersection,
// between its neighbours on that line).
static bool removable(const bk_face_simplifier* fs, const bk_mesh* m, uint32_t p) {
  (void)m;
  uint32_t a = fs->face_a[p], b = fs->face_b[p];
  if (b == MANY) return false;
  if (b == NONE) return true;
  return fabs(bk_v3_dot(fs->face_normal[a], fs->face_normal[b])) < 1.0 - 1e-6;
}

void bk_face_simplifier_keep_cuts(bk_face_simplifier* fs, bool keep) { fs->keep_cuts = keep; }

bool bk_face_simplifier_run(bk_face_simplifier* fs, bk_mesh* m) {
  uint32_t tri_count = m->triangle_count;
  if (tri_count < 4) return true;
  reserve(fs, m);

  // 1. Faces: union triangles across edges whose corners are shared (no
  //    attribute seam) with the same material and tag. The tag names the
  //    planar face a triangle came from (a cut, or a planar region of the
  //    source), so such triangles are coplanar by construction; comparing
  //    normals instead would fail on slivers, whose normals are noise.
  for (uint32_t t = 0; t < tri_count; ++t) {
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
    bk_vec3 e = bk_v3_cross(bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], a),
                            bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], a));
    fs->normal[t] = e; // twice the area times the unit normal
    fs->group[t] = t;
  }
  bk_index_map_clear(&fs->tri_of_edge);
  bool inserted = false;
  for (uint32_t t = 0; t < tri_count; ++t)
    for (int k = 0; k < 3; ++k)
      bk_index_map_insert(&fs->tri_of_edge,
                          bk_directed_edge_key(m->indices[3 * t + k], m->indices[3 * t + (k + 1) % 3]), t,
                          &inserted);
  for (uint32_t t = 0; t < tri_count; ++t) {
    if (fs->normal[t].x == 0.0 && fs->normal[t].y == 0.0 && fs->normal[t].z == 0.0) continue;
    for (int k = 0; k < 3; ++k) {
      uint32_t* other = bk_index_map_find(
          &fs->tri_of_edge, bk_directed_edge_key(m->indices[3 * t + (k + 1) % 3], m->indices[3 * t + k]));
      if (!other || *other <= t) continue;
      uint32_t o = *other;
      if (m->materials[o] != m->materials[t] || m->tags[o] != m->tags[t] || m->tags[t] == 0) continue;
      if (fs->keep_cuts && m->tags[t] < BK_SOURCE_FACE_TAG) continue;
      uint32_t ra = find(fs->group, t), rb = find(fs->group, o);
      if (ra != rb) fs->group[ra > rb ? ra : rb] = ra < rb ? ra : rb;
    }
  }
  // Flatten to roots first: numbering overwrites entries that later finds would walk.
  for (uint32_t t = 0; t < tri_count; ++t)
    fs->group[t] = find(fs->group, t);
  uint32_t face_count = 0;
  for (uint32_t t = 0; t < tri_count; ++t) {
    uint32_t r = fs->group[t];
    if (r == t) {
      fs->face_first_tri[face_count] = t;
      fs->group[t] = face_count++;
    } else {
      fs->group[t] = fs->group[r]; // r < t was numbered already
    }
  }
  if (face_count == tri_count) return true; // nothing to merge
  memset(fs->face_normal, 0, sizeof(bk_vec3) * face_count);
  for (uint32_t t = 0; t < tri_count; ++t)
    fs->face_normal[fs->group[t]] = bk_v3_add(fs->face_normal[fs->group[t]], fs->normal[t]);
  for (uint32_t f = 0; f < face_count; ++f)
    fs->face_normal[f] = bk_v3_normalize(fs->face_normal[f]);

  // 2. Faces around each position.
  memset(fs->face_a, 0xff, sizeof(uint32_t) * m->position_count);
  memset(fs->face_b, 0xff, sizeof(uint32_t) * m->position_count);
  for (uint32_t t = 0; t < tri_count; ++t) {
    uint32_t f = fs->group[t];
    for (int k = 0; k < 3; ++k) {
      uint32_t p = bk_mesh_tri_position(m, t, k);
      if (fs->face_a[p] == NONE || fs->face_a[p] == f)
        fs->face_a[p] = f;
      else if (fs->face_b[p] == NONE || fs->face_b[p] == f)
        fs->face_b[p] = f;
      else
        fs->face_b[p] = MANY;
    }
  }

  // 3. Boundary edges of each face (by position), and which faces change: a
  //    face changes when it loses a vertex or has more triangles than its
  //    outline needs.
  bk_index_map_clear(&fs->tri_of_edge); // now: directed position edge -> triangle
  for (uint32_t t = 0; t < tri_count; ++t)
    for (int k = 0; k < 3; ++k)
      bk_index_map_insert(
          &fs->tri_of_edge,
          bk_directed_edge_key(bk_mesh_tri_position(m, t, k), bk_mesh_tri_position(m, t, (k + 1) % 3)), t,
          &inserted);
  bk_index_map_clear(&fs->next_on_face);
  bk_index_map_clear(&fs->corner_of_face);
  memset(fs->face_redo, 0, face_count);
  uint32_t outline_count = 0;
  for (uint32_t t = 0; t < tri_count; ++t) {
    uint32_t f = fs->group[t];
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      bk_index_map_insert(&fs->corner_of_face, face_key(f, a), m->indices[3 * t + k], &inserted);
      uint32_t* across = bk_index_map_find(&fs->tri_of_edge, bk_directed_edge_key(b, a));
      if (across && fs->group[*across] == f) continue; // interior edge of the face
      bk_index_map_insert(&fs->next_on_face, face_key(f, a), b, &inserted);
      if (!inserted) return true; // the face touches itself at a vertex: leave the mesh as it is
      if (removable(fs, m, a)) fs->face_redo[f] = 1;
      uint32_t* e = &fs->outline[3 * outline_count++];
      e[0] = f, e[1] = a, e[2] = b;
    }
  }
  // Faces with interior vertices or extra triangles: count outline vertices.
  for (uint32_t p = 0; p < m->position_count; ++p)
    if (fs->face_a[p] != NONE && fs->face_b[p] == NONE) fs->face_redo[fs->face_a[p]] = 1;

  // Bucket the outline edges by face (counting sort keeps their order).
  memset(fs->face_outline_start, 0, sizeof(uint32_t) * (face_count + 1u));
  for (uint32_t i = 0; i < outline_count; ++i)
    fs->face_outline_start[fs->outline[3 * i] + 1]++;
  for (uint32_t f = 0; f < face_count; ++f)
    fs->face_outline_start[f + 1] += fs->face_outline_start[f];
  for (uint32_t i = 0; i < outline_count; ++i) {
    uint32_t slot = fs->face_outline_start[fs->outline[3 * i]]++;
    memcpy(&fs->outline_sorted[3 * slot], &fs->outline[3 * i], sizeof(uint32_t) * 3);
  }
  for (uint32_t f = face_count; f > 0; --f)
    fs->face_outline_start[f] = fs->face_outline_start[f - 1];
  fs->face_outline_start[0] = 0;

  // 4. Re-triangulate each changing face over its kept outline vertices.
  bk_mesh out = {0};
  bk_mesh_reserve(&out, m->position_count, m->corner_count, tri_count);
  memset(fs->new_index, 0xff, sizeof(uint32_t) * m->position_count);
  memset(fs->corner_new, 0xff, sizeof(uint32_t) * m->corner_count);
  bool ok = true;
  // Unchanged faces keep their triangles.
  for (uint32_t t = 0; t < tri_count && ok; ++t) {
    if (fs->face_redo[fs->group[t]]) continue;
    uint32_t c[3];
    for (int k = 0; k < 3; ++k) {
      uint32_t corner = m->indices[3 * t + k];
      if (fs->corner_new[corner] == NONE) {
        bk_corner copy = m->corners[corner];
        if (fs->new_index[copy.position] == NONE)
          fs->new_index[copy.position] = bk_mesh_add_position(&out, m->positions[copy.position]);
        copy.position = fs->new_index[copy.position];
        fs->corner_new[corner] = bk_mesh_add_corner(&out, &copy);
      }
      c[k] = fs->corner_new[corner];
    }
    bk_mesh_add_triangle(&out, c[0], c[1], c[2], m->materials[t], m->tags[t]);
  }
  for (uint32_t f = 0; f < face_count && ok; ++f) {
    if (!fs->face_redo[f]) continue;
    uint32_t t0 = fs->face_first_tri[f];
    // Gather the face's boundary edges by walking from each kept vertex over
    // dropped ones. Every outline edge starts at a position with this face.
    uint32_t edge_count = 0, local_count = 0;
    bk_index_map_clear(&fs->local_of_position);
    for (uint32_t i = fs->face_outline_start[f]; i < fs->face_outline_start[f + 1]; ++i) {
      uint32_t a = fs->outline_sorted[3 * i + 1];
      if (removable(fs, m, a)) continue;
      uint32_t b = fs->outline_sorted[3 * i + 2], steps = 0;
      while (removable(fs, m, b) && steps++ < m->position_count) {
        uint32_t* next = bk_index_map_find(&fs->next_on_face, face_key(f, b));
        if (!next) break;
        b = *next;
      }
      if (removable(fs, m, b)) {
        ok = false; // a loop with no corner: cannot happen for planar faces; give up safely
        break;
      }
      reserve_face_edges(fs, edge_count + 1);
      uint32_t ends[2] = {a, b};
      for (int e = 0; e < 2; ++e) {
        uint32_t* local = bk_index_map_insert(&fs->local_of_position, ends[e], local_count, &inserted);
        if (inserted) fs->face_global[local_count++] = ends[e];
        fs->face_edges[2 * edge_count + e] = *local;
      }
      edge_count++;
    }
    if (!ok) break;
    bk_vec3 n = fs->face_normal[f], u, v;
    bk_plane_basis(n, &u, &v);
    for (uint32_t i = 0; i < local_count; ++i) {
      fs->xy[2 * i] = bk_v3_dot(m->positions[fs->face_global[i]], u);
      fs->xy[2 * i + 1] = bk_v3_dot(m->positions[fs->face_global[i]], v);
    }
    const uint32_t* tris = NULL;
    uint32_t count = 0;
    if (!bk_cap_triangulate(fs->cap, fs->face_edges, edge_count, fs->xy, local_count, &tris, &count, NULL)) {
      ok = false;
      break;
    }
    for (uint32_t t = 0; t < count; ++t) {
      uint32_t c[3];
      for (int k = 0; k < 3; ++k) {
        uint32_t p = fs->face_global[tris[3 * t + k]];
        uint32_t corner = *bk_index_map_find(&fs->corner_of_face, face_key(f, p));
        if (fs->corner_new[corner] == NONE) {
          bk_corner copy = m->corners[corner];
          if (fs->new_index[p] == NONE) fs->new_index[p] = bk_mesh_add_position(&out, m->positions[p]);
          copy.position = fs->new_index[p];
          fs->corner_new[corner] = bk_mesh_add_corner(&out, &copy);
        }
        c[k] = fs->corner_new[corner];
      }
      bk_mesh_add_triangle(&out, c[0], c[1], c[2], m->materials[t0], m->tags[t0]);
    }
  }
  if (!ok) {
    bk_mesh_free(&out);
    return false;
  }
  bk_mesh_free(m);
  *m = out;
  return true;
}

// Nearly equal normals are not enough: a quad bent by 1e-6 (exporters round
// coordinates) has normals equal to 1e-13, yet re-triangulating it as one
// face would change the volume by about 1e-7 of it, and every cut of it would
// fail its volume check. The far corner of `other` must lie on t's plane to
// within 1e-14 of its distance from it.
static bool other_corner_on_plane(const bk_mesh* m, uint32_t t, uint32_t other) {
  bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_vec3 n = bk_v3_cross(bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], a),
                          bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], a));
  for (int k = 0; k < 3; ++k) {
    uint32_t p = bk_mesh_tri_position(m, other, k);
    if (p == bk_mesh_tri_position(m, t, 0) || p == bk_mesh_tri_position(m, t, 1) ||
        p == bk_mesh_tri_position(m, t, 2))
      continue;
    bk_vec3 d = bk_v3_sub(m->positions[p], a);
    return fabs(bk_v3_dot(n, d)) <= 1e-14 * bk_v3_length(n) * bk_v3_length(d);
  }
  return true;
}

void bk_label_planar_faces(bk_mesh* m) {
  // Adjacent source triangles that share corners, material and an exact
  // plane (unit normals equal to 1e-12: source triangles are not slivers of
  // cuts, so their normals are accurate) get one label.
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (m->triangle_count + 1u));
  bk_vec3* normal = bk_alloc(sizeof(bk_vec3) * (m->triangle_count + 1u));
  bk_index_map tri_of_edge = {0};
  bk_index_map_init(&tri_of_edge, 3u * m->triangle_count);
  bool inserted = false;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 a = m->positions[bk_mesh_tri_position(m, t, 0)];
    normal[t] = bk_v3_normalize(bk_v3_cross(bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], a),
                                            bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], a)));
    parent[t] = t;
    for (int k = 0; k < 3; ++k)
      bk_index_map_insert(&tri_of_edge,
                          bk_directed_edge_key(m->indices[3 * t + k], m->indices[3 * t + (k + 1) % 3]), t,
                          &inserted);
  }
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t* other = bk_index_map_find(
          &tri_of_edge, bk_directed_edge_key(m->indices[3 * t + (k + 1) % 3], m->indices[3 * t + k]));
      if (!other || m->materials[*other] != m->materials[t]) continue;
      if (bk_v3_dot(normal[t], normal[*other]) < 1.0 - 1e-12) continue;
      if (!other_corner_on_plane(m, t, *other)) continue;
      uint32_t ra = find(parent, t), rb = find(parent, *other);
      if (ra != rb) parent[ra > rb ? ra : rb] = ra < rb ? ra : rb;
    }
  uint32_t labels = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    uint32_t r = find(parent, t);
    m->tags[t] = r == t ? BK_SOURCE_FACE_TAG + labels++ : m->tags[r];
  }
  bk_index_map_free(&tri_of_edge);
  free(parent);
  free(normal);
}
