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
#define MANY (UINT32_MAX - 1)

// Topology is looked up through half-edges grouped by the position they
// start at (h = 3t + k runs from corner k of triangle t to corner k + 1),
// listed in increasing h: a vertex has a handful of them, so a lookup scans
// a few entries instead of hashing, and "the first half-edge that matches"
// is the one a first-wins map keyed in triangle order would hold.
struct bk_face_simplifier {
  // Per triangle (faces are numbered below the triangle count).
  uint32_t* group; // face id (union-find, then compacted)
  bk_vec3* normal; // cross product of its edges
  uint8_t* face_redo;
  uint32_t* face_first_tri; // per face: one triangle (material and tag)
  bk_vec3* face_normal;     // per face: unit area-weighted normal
  uint32_t* face_outline_start;
  uint32_t tri_capacity;
  // Per half-edge.
  uint32_t* from;    // the position it starts at
  uint32_t* to;      // the position it ends at
  uint32_t* face;    // its triangle's face
  uint32_t* twin;    // the first half-edge running the other way, or NONE
  uint32_t* around;  // half-edges by start position
  uint32_t* outline; // outline half-edges, then bucketed by face
  uint32_t* outline_sorted;
  uint32_t half_capacity;
  // Per position.
  uint32_t* around_start;    // + 1: start of its half-edges in `around`
  uint32_t* face_a;          // first face touching it
  uint32_t* face_b;          // second face, NONE, or MANY
  uint32_t* position_face;   // 3 per position: its first faces (NONE past the last)
  uint32_t* position_corner; // 3 per position: those faces' first corners there
  uint8_t* more_faces;       // per position: more than three faces
  uint8_t* removable;
  uint32_t* new_index;
  uint32_t* local_of; // local id in the face being redone, or NONE
  uint32_t* stamp;    // scratch marks (which position or face set `slot`)
  uint32_t* slot;
  uint32_t position_capacity;
  uint32_t* corner_new;
  uint32_t corner_capacity;
  // One face being redone.
  uint32_t* face_edges;  // boundary edges (local ids)
  uint32_t* face_global; // local id -> position
  uint32_t* face_corner; // local id -> the face's corner there
  double* xy;
  uint32_t edge_capacity;
  bk_mesh out; // the simplified mesh, copied out at its exact size
  bk_cap* cap;
  bool keep_cuts;
};

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
  return fs;
}

void bk_face_simplifier_destroy(bk_face_simplifier* fs) {
  if (!fs) return;
  bk_free(fs->group);
  bk_free(fs->normal);
  bk_free(fs->face_redo);
  bk_free(fs->face_first_tri);
  bk_free(fs->face_normal);
  bk_free(fs->face_outline_start);
  bk_free(fs->from);
  bk_free(fs->to);
  bk_free(fs->face);
  bk_free(fs->twin);
  bk_free(fs->around);
  bk_free(fs->outline);
  bk_free(fs->outline_sorted);
  bk_free(fs->around_start);
  bk_free(fs->face_a);
  bk_free(fs->face_b);
  bk_free(fs->position_face);
  bk_free(fs->position_corner);
  bk_free(fs->more_faces);
  bk_free(fs->removable);
  bk_free(fs->new_index);
  bk_free(fs->local_of);
  bk_free(fs->stamp);
  bk_free(fs->slot);
  bk_free(fs->corner_new);
  bk_free(fs->face_edges);
  bk_free(fs->face_global);
  bk_free(fs->face_corner);
  bk_free(fs->xy);
  bk_mesh_free(&fs->out);
  bk_cap_destroy(fs->cap);
  bk_free(fs);
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
  if (3u * m->triangle_count > fs->half_capacity) {
    fs->half_capacity = bk_grow_capacity(fs->half_capacity, 3u * m->triangle_count);
    fs->from = bk_realloc(fs->from, sizeof(uint32_t) * fs->half_capacity);
    fs->to = bk_realloc(fs->to, sizeof(uint32_t) * fs->half_capacity);
    fs->face = bk_realloc(fs->face, sizeof(uint32_t) * fs->half_capacity);
    fs->twin = bk_realloc(fs->twin, sizeof(uint32_t) * fs->half_capacity);
    fs->around = bk_realloc(fs->around, sizeof(uint32_t) * fs->half_capacity);
    fs->outline = bk_realloc(fs->outline, sizeof(uint32_t) * fs->half_capacity);
    fs->outline_sorted = bk_realloc(fs->outline_sorted, sizeof(uint32_t) * fs->half_capacity);
  }
  if (m->position_count > fs->position_capacity) {
    fs->position_capacity = bk_grow_capacity(fs->position_capacity, m->position_count);
    fs->around_start = bk_realloc(fs->around_start, sizeof(uint32_t) * (fs->position_capacity + 1u));
    fs->face_a = bk_realloc(fs->face_a, sizeof(uint32_t) * fs->position_capacity);
    fs->face_b = bk_realloc(fs->face_b, sizeof(uint32_t) * fs->position_capacity);
    fs->position_face = bk_realloc(fs->position_face, sizeof(uint32_t) * 3u * fs->position_capacity);
    fs->position_corner = bk_realloc(fs->position_corner, sizeof(uint32_t) * 3u * fs->position_capacity);
    fs->more_faces = bk_realloc(fs->more_faces, fs->position_capacity);
    fs->removable = bk_realloc(fs->removable, fs->position_capacity);
    fs->new_index = bk_realloc(fs->new_index, sizeof(uint32_t) * fs->position_capacity);
    fs->local_of = bk_realloc(fs->local_of, sizeof(uint32_t) * fs->position_capacity);
    fs->stamp = bk_realloc(fs->stamp, sizeof(uint32_t) * fs->position_capacity);
    fs->slot = bk_realloc(fs->slot, sizeof(uint32_t) * fs->position_capacity);
  }
  if (m->corner_count > fs->corner_capacity) {
    fs->corner_capacity = bk_grow_capacity(fs->corner_capacity, m->corner_count);
    fs->corner_new = bk_realloc(fs->corner_new, sizeof(uint32_t) * fs->corner_capacity);
  }
  bk_mesh_reserve(&fs->out, m->position_count, m->corner_count, m->triangle_count);
  fs->out.position_count = fs->out.corner_count = fs->out.triangle_count = 0;
}

static void reserve_face_edges(bk_face_simplifier* fs, uint32_t edges) {
  if (edges <= fs->edge_capacity) return;
  fs->edge_capacity = bk_grow_capacity(fs->edge_capacity, edges);
  fs->face_edges = bk_realloc(fs->face_edges, sizeof(uint32_t) * 2u * fs->edge_capacity);
  fs->face_global = bk_realloc(fs->face_global, sizeof(uint32_t) * 2u * fs->edge_capacity);
  fs->face_corner = bk_realloc(fs->face_corner, sizeof(uint32_t) * 2u * fs->edge_capacity);
  fs->xy = bk_realloc(fs->xy, sizeof(double) * 4u * fs->edge_capacity);
}

// Half-edges grouped by start position, each group in increasing h, and
// each one's twin. Returns false when a directed edge is used twice (an
// open or folded mesh; the twins are then only the first of several).
static bool group_half_edges(bk_face_simplifier* fs, const bk_mesh* m, uint32_t half_count) {
  uint32_t* start = fs->around_start;
  memset(start, 0, sizeof(uint32_t) * (m->position_count + 1u));
  for (uint32_t h = 0; h < half_count; ++h) {
    fs->from[h] = m->corners[m->indices[h]].position;
    start[fs->from[h] + 1]++;
  }
  for (uint32_t h = 0; h < half_count; h += 3) {
    fs->to[h] = fs->from[h + 1];
    fs->to[h + 1] = fs->from[h + 2];
    fs->to[h + 2] = fs->from[h];
  }
  for (uint32_t p = 0; p < m->position_count; ++p)
    start[p + 1] += start[p];
  for (uint32_t h = 0; h < half_count; ++h)
    fs->around[start[fs->from[h]]++] = h;
  for (uint32_t p = m->position_count; p > 0; --p)
    start[p] = start[p - 1];
  start[0] = 0;
  // The half-edges ending at b are the predecessors of those leaving it: mark
  // where b's half-edges go (last to first, so the first wins), then look
  // each incoming one's start up.
  bool single = true;
  memset(fs->stamp, 0xff, sizeof(uint32_t) * m->position_count);
  for (uint32_t b = 0; b < m->position_count; ++b) {
    for (uint32_t i = start[b + 1]; i > start[b]; --i) {
      uint32_t h = fs->around[i - 1], x = fs->to[h];
      single &= fs->stamp[x] != b;
      fs->stamp[x] = b;
      fs->slot[x] = h;
    }
    for (uint32_t i = start[b]; i < start[b + 1]; ++i) {
      uint32_t h = bk_half_prev(fs->around[i]), a = fs->from[h];
      fs->twin[h] = fs->stamp[a] == b ? fs->slot[a] : NONE;
    }
  }
  return single;
}

// The corner of face f at position p: that of its first half-edge from p.
static uint32_t corner_of_face(const bk_face_simplifier* fs, const bk_mesh* m, uint32_t f, uint32_t p) {
  for (uint32_t k = 0; k < 3; ++k)
    if (fs->position_face[3 * p + k] == f) return fs->position_corner[3 * p + k];
  if (!fs->more_faces[p]) return NONE;
  for (uint32_t i = fs->around_start[p]; i < fs->around_start[p + 1]; ++i) {
    uint32_t h = fs->around[i];
    if (fs->face[h] == f) return m->indices[h];
  }
  return NONE;
}

// Appends a copy of input corner `corner` (and its position) once.
static uint32_t keep_corner(bk_face_simplifier* fs, const bk_mesh* m, uint32_t corner) {
  if (fs->corner_new[corner] != NONE) return fs->corner_new[corner];
  bk_mesh* out = &fs->out;
  bk_corner copy = m->corners[corner];
  uint32_t p = copy.position;
  if (fs->new_index[p] == NONE) {
    fs->new_index[p] = out->position_count;
    out->positions[out->position_count++] = m->positions[p];
  }
  copy.position = fs->new_index[p];
  fs->corner_new[corner] = out->corner_count;
  out->corners[out->corner_count++] = copy;
  return fs->corner_new[corner];
}

void bk_face_simplifier_keep_cuts(bk_face_simplifier* fs, bool keep) { fs->keep_cuts = keep; }

// 1. Faces: union triangles across edges whose corners are shared (no
//    attribute seam) with the same material and tag. The tag names the
//    planar face a triangle came from (a cut, or a planar region of the
//    source), so such triangles are coplanar by construction; comparing
//    normals instead would fail on slivers, whose normals are noise.
//    Returns the face count.
static uint32_t find_faces(bk_face_simplifier* fs, const bk_mesh* m, bool single) {
  uint32_t tri_count = m->triangle_count;
  for (uint32_t t = 0; t < tri_count; ++t) {
    bk_vec3 a = m->positions[fs->from[3 * t]];
    bk_vec3 e = bk_v3_cross(bk_v3_sub(m->positions[fs->from[3 * t + 1]], a),
                            bk_v3_sub(m->positions[fs->from[3 * t + 2]], a));
    fs->normal[t] = e; // twice the area times the unit normal
    fs->group[t] = t;
  }
  static const uint32_t next_k[3] = {1, 2, 0};
  for (uint32_t t = 0; t < tri_count; ++t) {
    if (fs->normal[t].x == 0.0 && fs->normal[t].y == 0.0 && fs->normal[t].z == 0.0) continue;
    if (m->tags[t] == 0 || (fs->keep_cuts && m->tags[t] < BK_SOURCE_FACE_TAG)) continue;
    for (uint32_t k = 0; k < 3; ++k) {
      // The first half-edge running corner c1 -> c0 against this one's c0 -> c1:
      // the twin when no directed edge repeats, else searched for.
      uint32_t h = 3u * t + k, c0 = m->indices[h], c1 = m->indices[3u * t + next_k[k]], o = NONE;
      if (single) {
        uint32_t r = fs->twin[h];
        if (r != NONE && m->indices[r] == c1 && m->indices[bk_half_next(r)] == c0) o = r / 3u;
      } else {
        uint32_t p1 = fs->to[h];
        for (uint32_t i = fs->around_start[p1]; i < fs->around_start[p1 + 1] && o == NONE; ++i) {
          uint32_t r = fs->around[i];
          if (m->indices[r] == c1 && m->indices[bk_half_next(r)] == c0) o = r / 3u;
        }
      }
      if (o == NONE || o <= t) continue;
      if (m->materials[o] != m->materials[t] || m->tags[o] != m->tags[t]) continue;
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
    fs->face[3 * t] = fs->face[3 * t + 1] = fs->face[3 * t + 2] = fs->group[t];
  }
  return face_count;
}

// 2. Faces around each position, and which positions can go: one inside a
//    single face, or on the edge between two faces that are not parallel
//    (then it is on their line of intersection, between its neighbours on
//    that line).
static void find_removable(bk_face_simplifier* fs, const bk_mesh* m, uint32_t face_count) {
  memset(fs->face_normal, 0, sizeof(bk_vec3) * face_count);
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    fs->face_normal[fs->group[t]] = bk_v3_add(fs->face_normal[fs->group[t]], fs->normal[t]);
  for (uint32_t f = 0; f < face_count; ++f)
    fs->face_normal[f] = bk_v3_normalize(fs->face_normal[f]);
  // A position's half-edges in h order are its triangle corners in order:
  // its first three faces, each with the corner it has there first.
  for (uint32_t p = 0; p < m->position_count; ++p) {
    uint32_t* faces = &fs->position_face[3 * p];
    uint32_t* corners = &fs->position_corner[3 * p];
    uint32_t distinct = 0;
    faces[0] = faces[1] = faces[2] = NONE;
    for (uint32_t i = fs->around_start[p]; i < fs->around_start[p + 1]; ++i) {
      uint32_t h = fs->around[i], f = fs->face[h];
      if (f == faces[0] || f == faces[1] || f == faces[2]) continue;
      if (distinct < 3) faces[distinct] = f, corners[distinct] = m->indices[h];
      distinct++;
    }
    fs->face_a[p] = faces[0];
    fs->face_b[p] = distinct >= 3 ? MANY : faces[1];
    fs->more_faces[p] = distinct > 3;
  }
  for (uint32_t p = 0; p < m->position_count; ++p) {
    uint32_t a = fs->face_a[p], b = fs->face_b[p];
    fs->removable[p] =
        b == MANY ? 0 : (b == NONE || fabs(bk_v3_dot(fs->face_normal[a], fs->face_normal[b])) < 1.0 - 1e-6);
  }
}

// 3. Outline half-edges of each face, bucketed by face (in h order), and
//    which faces change: a face changes when it loses a vertex or has more
//    triangles than its outline needs. False when a face touches itself at
//    a vertex (the mesh is then left as it is).
static bool find_outlines(bk_face_simplifier* fs, const bk_mesh* m, uint32_t face_count) {
  uint32_t half_count = 3u * m->triangle_count, outline_count = 0;
  memset(fs->face_redo, 0, face_count);
  for (uint32_t h = 0; h < half_count; ++h) {
    // Interior when the first half-edge back belongs to the same face.
    uint32_t f = fs->face[h], across = fs->twin[h];
    bool outer = across == NONE || fs->face[across == NONE ? h : across] != f;
    fs->face_redo[f] |= (uint8_t)(outer & fs->removable[fs->from[h]]);
    fs->outline[outline_count] = h;
    outline_count += outer;
  }
  // Faces with interior vertices or extra triangles: count outline vertices.
  for (uint32_t p = 0; p < m->position_count; ++p)
    if (fs->face_a[p] != NONE && fs->face_b[p] == NONE) fs->face_redo[fs->face_a[p]] = 1;
  // Bucket the outline edges by face (counting sort keeps their order).
  uint32_t* start = fs->face_outline_start;
  memset(start, 0, sizeof(uint32_t) * (face_count + 1u));
  for (uint32_t i = 0; i < outline_count; ++i)
    start[fs->face[fs->outline[i]] + 1]++;
  for (uint32_t f = 0; f < face_count; ++f)
    start[f + 1] += start[f];
  for (uint32_t i = 0; i < outline_count; ++i)
    fs->outline_sorted[start[fs->face[fs->outline[i]]]++] = fs->outline[i];
  for (uint32_t f = face_count; f > 0; --f)
    start[f] = start[f - 1];
  start[0] = 0;
  // Two outline edges of one face leaving one position: the face touches itself.
  memset(fs->stamp, 0xff, sizeof(uint32_t) * m->position_count);
  for (uint32_t f = 0; f < face_count; ++f)
    for (uint32_t i = start[f]; i < start[f + 1]; ++i) {
      uint32_t a = fs->from[fs->outline_sorted[i]];
      if (fs->stamp[a] == f) return false;
      fs->stamp[a] = f;
    }
  return true;
}

// 4. Re-triangulates face f over its kept outline vertices into fs->out.
static bool redo_face(bk_face_simplifier* fs, const bk_mesh* m, uint32_t f) {
  uint32_t t0 = fs->face_first_tri[f];
  // Gather the face's boundary edges by walking from each kept vertex over
  // dropped ones. Every outline edge starts at a position with this face.
  uint32_t edge_count = 0, local_count = 0, first = fs->face_outline_start[f],
           last = fs->face_outline_start[f + 1];
  // Where the outline goes on from each of its positions (stamp: this face).
  for (uint32_t i = first; i < last; ++i) {
    uint32_t h = fs->outline_sorted[i];
    fs->stamp[fs->from[h]] = f;
    fs->slot[fs->from[h]] = fs->to[h];
  }
  bool ok = true;
  for (uint32_t i = first; i < last && ok; ++i) {
    uint32_t h = fs->outline_sorted[i], a = fs->from[h];
    if (fs->removable[a]) continue;
    uint32_t b = fs->to[h], steps = 0;
    while (fs->removable[b] && steps++ < m->position_count) {
      if (fs->stamp[b] != f) break;
      b = fs->slot[b];
    }
    if (fs->removable[b]) {
      ok = false; // a loop with no corner: cannot happen for planar faces; give up safely
      break;
    }
    reserve_face_edges(fs, edge_count + 1);
    uint32_t ends[2] = {a, b};
    for (int e = 0; e < 2; ++e) {
      if (fs->local_of[ends[e]] == NONE) {
        fs->local_of[ends[e]] = local_count;
        fs->face_global[local_count++] = ends[e];
      }
      fs->face_edges[2 * edge_count + e] = fs->local_of[ends[e]];
    }
    edge_count++;
  }
  for (uint32_t i = 0; i < local_count; ++i) {
    fs->local_of[fs->face_global[i]] = NONE;
    // The face's corner there: that of its first half-edge from the position.
    fs->face_corner[i] = corner_of_face(fs, m, f, fs->face_global[i]);
  }
  if (!ok) return false;
  bk_vec3 n = fs->face_normal[f], u = {0}, v = {0};
  bk_plane_basis(n, &u, &v);
  for (uint32_t i = 0; i < local_count; ++i) {
    fs->xy[2 * i] = bk_v3_dot(m->positions[fs->face_global[i]], u);
    fs->xy[2 * i + 1] = bk_v3_dot(m->positions[fs->face_global[i]], v);
  }
  const uint32_t* tris = NULL;
  uint32_t count = 0;
  if (!bk_cap_triangulate(fs->cap, fs->face_edges, edge_count, fs->xy, local_count, &tris, &count, NULL))
    return false;
  bk_mesh* out = &fs->out;
  bk_mesh_reserve(out, 0, 0, out->triangle_count + count);
  for (uint32_t t = 0; t < count; ++t) {
    uint32_t* c = &out->indices[3u * out->triangle_count];
    for (int k = 0; k < 3; ++k)
      c[k] = keep_corner(fs, m, fs->face_corner[tris[3 * t + k]]);
    out->materials[out->triangle_count] = m->materials[t0];
    out->tags[out->triangle_count++] = m->tags[t0];
  }
  return true;
}

// Points *simplified at the simplified mesh (fs->out), or at the input when
// nothing changes or (returning false) a face cannot be re-triangulated.
static bool simplify(bk_face_simplifier* fs, const bk_mesh* m, const bk_mesh** simplified) {
  *simplified = m;
  uint32_t tri_count = m->triangle_count;
  if (tri_count < 4) return true;
  reserve(fs, m);
  bool single = group_half_edges(fs, m, 3u * tri_count);
  uint32_t face_count = find_faces(fs, m, single);
  if (face_count == tri_count) return true; // nothing to merge
  find_removable(fs, m, face_count);
  if (!find_outlines(fs, m, face_count)) return true; // a face touches itself: leave the mesh as it is

  // Unchanged faces keep their triangles; the others are re-triangulated.
  bk_mesh* out = &fs->out;
  memset(fs->new_index, 0xff, sizeof(uint32_t) * m->position_count);
  memset(fs->local_of, 0xff, sizeof(uint32_t) * m->position_count);
  memset(fs->corner_new, 0xff, sizeof(uint32_t) * m->corner_count);
  for (uint32_t t = 0; t < tri_count; ++t) {
    if (fs->face_redo[fs->group[t]]) continue;
    uint32_t* c = &out->indices[3u * out->triangle_count];
    for (int k = 0; k < 3; ++k)
      c[k] = keep_corner(fs, m, m->indices[3 * t + k]);
    out->materials[out->triangle_count] = m->materials[t];
    out->tags[out->triangle_count++] = m->tags[t];
  }
  for (uint32_t f = 0; f < face_count; ++f)
    if (fs->face_redo[f] && !redo_face(fs, m, f)) return false;
  *simplified = out;
  return true;
}

bool bk_face_simplifier_run(bk_face_simplifier* fs, const bk_mesh* m, bk_mesh* result) {
  const bk_mesh* simplified = m;
  bool ok = simplify(fs, m, &simplified);
  bk_mesh_copy_exact(result, simplified);
  return ok;
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
  bk_free(parent);
  bk_free(normal);
}
