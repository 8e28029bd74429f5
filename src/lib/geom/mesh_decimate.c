// Decimation for drawing far away: edge collapses, cheapest first, in the
// manner of Garland and Heckbert's quadric simplification, but measured by
// the largest distance instead of a sum of squares. Each position keeps the
// planes of every original triangle it stands for; collapsing an edge puts
// the survivor at an end or the middle, wherever the farthest of the two
// ends' planes is nearest, and the collapse is taken while that distance is
// under the tolerance. (An area-weighted sum lets small features such as a
// shard's thin spike or rim go for almost nothing, and they show in the
// silhouette.) Edges between the outer surface and the cut faces add planes
// across them, so the border between the two materials stays where it was.
// Collapses that would pinch the surface (link condition) or turn a triangle
// over are refused, so a closed manifold stays one. Corners keep the
// attributes they had: a cut face's corners keep its flat normal.
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "bk_geom.h"

// Plane of points x with dot(normal, x) + offset == 0.
typedef struct plane {
  bk_vec3 normal;
  double offset;
} plane;

// A growable list of indices.
typedef struct index_list {
  uint32_t* items;
  uint32_t count, capacity;
} index_list;

typedef struct candidate {
  double cost;
  uint32_t keep, drop; // positions: `drop` merges into `keep`
  uint32_t keep_version, drop_version;
  bk_vec3 target;
} candidate;

typedef struct decimator {
  const bk_mesh* in;
  double tolerance;
  bk_vec3* position;
  plane* planes; // of the original triangles, then across material borders
  uint32_t plane_count, plane_capacity;
  index_list* position_planes; // per position: the planes of what it stands for
  uint32_t* plane_mark;        // per plane: scratch stamps
  uint32_t* version;           // per position: bumped when it moves, so queued candidates go stale
  uint8_t* state;              // per position: ALIVE, LOCKED (never moves), DEAD
  uint32_t* tri;               // 3 positions per triangle, updated by collapses
  uint8_t* tri_alive;
  index_list* incident; // per position: triangles using it (dead ones removed after collapses)
  uint32_t* mark;       // per position: scratch stamps for neighbour sets
  uint32_t stamp;
  candidate* candidates; // every collapse queued so far; the heap orders them by cost
  uint32_t candidate_count, candidate_capacity;
  bk_heap heap;
  uint32_t alive_positions, alive_triangles;
} decimator;

enum { ALIVE, LOCKED, DEAD };

static bk_vec3 tri_normal(bk_vec3 a, bk_vec3 b, bk_vec3 c) {
  return bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
}

static void list_push(index_list* list, uint32_t item) {
  if (list->count == list->capacity) {
    list->capacity = bk_grow_capacity(list->capacity, list->count + 1);
    list->items = bk_realloc(list->items, sizeof(uint32_t) * list->capacity);
  }
  list->items[list->count++] = item;
}

static uint32_t add_plane(decimator* d, bk_vec3 normal, bk_vec3 through) {
  if (d->plane_count == d->plane_capacity) {
    d->plane_capacity = bk_grow_capacity(d->plane_capacity, d->plane_count + 1);
    d->planes = bk_realloc(d->planes, sizeof(plane) * d->plane_capacity);
  }
  d->planes[d->plane_count] = (plane){normal, -bk_v3_dot(normal, through)};
  return d->plane_count++;
}

// The distance from x to the farthest of the planes of positions a and b,
// or some distance over `bound` once it is clear the answer exceeds it.
static double farthest_plane(const decimator* d, uint32_t a, uint32_t b, bk_vec3 x, double bound) {
  double worst = 0.0;
  const index_list* lists[2] = {&d->position_planes[a], &d->position_planes[b]};
  for (int l = 0; l < 2; ++l)
    for (uint32_t i = 0; i < lists[l]->count; ++i) {
      const plane* p = &d->planes[lists[l]->items[i]];
      double distance = fabs(bk_v3_dot(p->normal, x) + p->offset);
      if (distance > worst) worst = distance;
      if (worst > bound) return worst;
    }
  return worst;
}

static void push_candidate(decimator* d, candidate c) {
  if (d->candidate_count == d->candidate_capacity) {
    d->candidate_capacity = bk_grow_capacity(d->candidate_capacity, d->candidate_count + 1);
    d->candidates = bk_realloc(d->candidates, sizeof(candidate) * d->candidate_capacity);
  }
  d->candidates[d->candidate_count] = c;
  bk_heap_push(&d->heap, c.cost, d->candidate_count++);
}

// Queues the collapse of edge (a, b) at its best point, if that is within
// the tolerance (the heap's order makes any other useless); a locked end
// stays put.
static void push_edge(decimator* d, uint32_t a, uint32_t b) {
  if (d->state[a] == LOCKED && d->state[b] == LOCKED) return;
  if (d->state[a] == LOCKED) {
    uint32_t t = a;
    a = b;
    b = t;
  }
  // Now `a` may move; `b` is kept when it is locked.
  bk_vec3 options[3] = {d->position[b], d->position[a],
                        bk_v3_scale(bk_v3_add(d->position[a], d->position[b]), 0.5)};
  int count = d->state[b] == LOCKED ? 1 : 3;
  double best = DBL_MAX;
  int chosen = -1;
  for (int i = 0; i < count; ++i) {
    double e = farthest_plane(d, a, b, options[i], fmin(best, d->tolerance));
    if (e < best && e <= d->tolerance) best = e, chosen = i;
  }
  if (chosen >= 0) push_candidate(d, (candidate){best, b, a, d->version[b], d->version[a], options[chosen]});
}

static void drop_dead_incident(decimator* d, uint32_t p) {
  index_list* list = &d->incident[p];
  uint32_t n = 0;
  for (uint32_t i = 0; i < list->count; ++i)
    if (d->tri_alive[list->items[i]]) list->items[n++] = list->items[i];
  list->count = n;
}

// Marks the neighbours of p with the current stamp.
static void mark_neighbours(decimator* d, uint32_t p) {
  for (uint32_t i = 0; i < d->incident[p].count; ++i) {
    const uint32_t* t = &d->tri[3 * d->incident[p].items[i]];
    for (int k = 0; k < 3; ++k)
      if (t[k] != p) d->mark[t[k]] = d->stamp;
  }
}

// Whether moving `keep` and `drop` to `target` keeps the surface a manifold
// with no triangle turned over.
static bool collapse_allowed(decimator* d, uint32_t keep, uint32_t drop, bk_vec3 target) {
  // Link condition: the ends share exactly the two neighbours across the edge.
  d->stamp++;
  mark_neighbours(d, keep);
  uint32_t shared = 0;
  for (uint32_t i = 0; i < d->incident[drop].count; ++i) {
    const uint32_t* t = &d->tri[3 * d->incident[drop].items[i]];
    for (int k = 0; k < 3; ++k)
      if (t[k] != drop && t[k] != keep && d->mark[t[k]] == d->stamp) {
        d->mark[t[k]] = d->stamp - 1; // count each once
        shared++;
      }
  }
  if (shared != 2) return false;
  const uint32_t ends[2] = {keep, drop};
  for (int e = 0; e < 2; ++e)
    for (uint32_t i = 0; i < d->incident[ends[e]].count; ++i) {
      const uint32_t* t = &d->tri[3 * d->incident[ends[e]].items[i]];
      if ((t[0] == keep || t[1] == keep || t[2] == keep) && (t[0] == drop || t[1] == drop || t[2] == drop))
        continue; // collapses away
      bk_vec3 before[3], after[3];
      for (int k = 0; k < 3; ++k) {
        before[k] = d->position[t[k]];
        after[k] = t[k] == keep || t[k] == drop ? target : before[k];
      }
      bk_vec3 n0 = tri_normal(before[0], before[1], before[2]), n1 = tri_normal(after[0], after[1], after[2]);
      double l0 = bk_v3_length(n0), l1 = bk_v3_length(n1);
      // Refuse flips, slivers and turns of more than ~75 degrees.
      if (!(l1 > 1e-6 * l0) || bk_v3_dot(n0, n1) < 0.25 * l0 * l1) return false;
    }
  return true;
}

static void collapse(decimator* d, uint32_t keep, uint32_t drop, bk_vec3 target) {
  d->position[keep] = target;
  // The survivor answers for both ends' planes (each once).
  d->stamp++;
  index_list* planes = &d->position_planes[keep];
  for (uint32_t i = 0; i < planes->count; ++i)
    d->plane_mark[planes->items[i]] = d->stamp;
  const index_list* dropped = &d->position_planes[drop];
  for (uint32_t i = 0; i < dropped->count; ++i)
    if (d->plane_mark[dropped->items[i]] != d->stamp) list_push(planes, dropped->items[i]);
  d->state[drop] = DEAD;
  d->alive_positions--;
  d->version[keep]++;
  for (uint32_t i = 0; i < d->incident[drop].count; ++i) {
    uint32_t t = d->incident[drop].items[i];
    if (!d->tri_alive[t]) continue;
    uint32_t* v = &d->tri[3 * t];
    if (v[0] == keep || v[1] == keep || v[2] == keep) {
      d->tri_alive[t] = 0;
      d->alive_triangles--;
      continue;
    }
    for (int k = 0; k < 3; ++k)
      if (v[k] == drop) v[k] = keep;
    list_push(&d->incident[keep], t);
  }
  d->incident[drop].count = 0;
  drop_dead_incident(d, keep);
  // Every edge around the survivor has a new cost.
  d->stamp++;
  mark_neighbours(d, keep);
  for (uint32_t i = 0; i < d->incident[keep].count; ++i) {
    const uint32_t* t = &d->tri[3 * d->incident[keep].items[i]];
    for (int k = 0; k < 3; ++k)
      if (t[k] != keep && d->mark[t[k]] == d->stamp) {
        d->mark[t[k]] = d->stamp - 1; // each neighbour once; `keep`'s new version made the old costs stale
        push_edge(d, keep, t[k]);
      }
  }
}

static void decimator_free(decimator* d) {
  for (uint32_t p = 0; p < d->in->position_count; ++p) {
    bk_free(d->incident[p].items);
    bk_free(d->position_planes[p].items);
  }
  bk_free(d->position);
  bk_free(d->planes);
  bk_free(d->position_planes);
  bk_free(d->plane_mark);
  bk_free(d->version);
  bk_free(d->state);
  bk_free(d->tri);
  bk_free(d->tri_alive);
  bk_free(d->incident);
  bk_free(d->mark);
  bk_free(d->candidates);
  bk_heap_free(&d->heap);
}

uint32_t bk_mesh_decimate(const bk_mesh* mesh, double tolerance, bk_mesh* out) {
  memset(out, 0, sizeof *out);
  const uint32_t np = mesh->position_count, nt = mesh->triangle_count;
  if (np == 0 || nt == 0) return 0;
  decimator d = {.in = mesh, .tolerance = tolerance};
  d.position = bk_alloc(sizeof(bk_vec3) * np);
  memcpy(d.position, mesh->positions, sizeof(bk_vec3) * np);
  d.position_planes = bk_calloc(np, sizeof(index_list));
  d.version = bk_calloc(np, sizeof(uint32_t));
  d.state = bk_calloc(np, 1);
  d.mark = bk_calloc(np, sizeof(uint32_t));
  d.tri = bk_alloc(sizeof(uint32_t) * 3 * nt);
  d.tri_alive = bk_alloc(nt);
  d.incident = bk_calloc(np, sizeof(index_list));
  d.alive_positions = np;
  d.alive_triangles = nt;
  // Triangles' planes to their corners' positions; edges counted to find
  // where the mesh is not a closed manifold (those positions stay put).
  bk_index_map edges = {0}; // undirected edge -> first triangle * 4 + side, then MANY
  bk_index_map_init(&edges, 3 * nt);
  for (uint32_t t = 0; t < nt; ++t) {
    uint32_t* v = &d.tri[3 * t];
    for (int k = 0; k < 3; ++k)
      v[k] = bk_mesh_tri_position(mesh, t, k);
    d.tri_alive[t] = 1;
    bk_vec3 n = tri_normal(d.position[v[0]], d.position[v[1]], d.position[v[2]]);
    double length = bk_v3_length(n);
    if (length > 0.0) {
      uint32_t id = add_plane(&d, bk_v3_scale(n, 1.0 / length), d.position[v[0]]);
      for (int k = 0; k < 3; ++k)
        list_push(&d.position_planes[v[k]], id);
    }
    for (int k = 0; k < 3; ++k) {
      list_push(&d.incident[v[k]], t);
      uint32_t a = v[k], b = v[(k + 1) % 3];
      if (a == b) {
        d.state[a] = LOCKED;
        continue;
      }
      uint64_t key = bk_edge_key(a, b);
      bool inserted = false;
      uint32_t* slot = bk_index_map_insert(&edges, key, 4 * t + (uint32_t)k, &inserted);
      if (inserted) continue;
      if (*slot == UINT32_MAX) { // a third triangle on one edge
        d.state[a] = d.state[b] = LOCKED;
        continue;
      }
      uint32_t other = *slot / 4;
      *slot = UINT32_MAX;
      if (mesh->materials[other] != mesh->materials[t]) {
        // A border between materials: planes across it, on both sides, keep it in place.
        uint32_t tris[2] = {t, other};
        for (int s = 0; s < 2; ++s) {
          const uint32_t* w = &d.tri[3 * tris[s]];
          bk_vec3 face = bk_v3_normalize(tri_normal(d.position[w[0]], d.position[w[1]], d.position[w[2]]));
          bk_vec3 edge = bk_v3_sub(d.position[b], d.position[a]);
          uint32_t id = add_plane(&d, bk_v3_normalize(bk_v3_cross(edge, face)), d.position[a]);
          list_push(&d.position_planes[a], id);
          list_push(&d.position_planes[b], id);
        }
      }
    }
  }
  // Every edge seen once (open) locks its ends too; then, with every lock
  // known, each edge is queued once.
  for (uint32_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = d.tri[3 * t + k], b = d.tri[3 * t + (k + 1) % 3];
      const uint32_t* slot = a == b ? NULL : bk_index_map_find(&edges, bk_edge_key(a, b));
      if (slot && *slot != UINT32_MAX) d.state[a] = d.state[b] = LOCKED;
    }
  for (uint32_t t = 0; t < nt; ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = d.tri[3 * t + k], b = d.tri[3 * t + (k + 1) % 3];
      const uint32_t* slot = a < b ? bk_index_map_find(&edges, bk_edge_key(a, b)) : NULL;
      if (slot && *slot == UINT32_MAX) push_edge(&d, a, b); // closed edges, each from one side
    }
  bk_index_map_free(&edges);

  d.plane_mark = bk_calloc(d.plane_count + 1, sizeof(uint32_t));
  while (d.heap.count > 0 && d.alive_triangles > 4) {
    candidate c = d.candidates[bk_heap_pop(&d.heap).value];
    if (d.state[c.keep] == DEAD || d.state[c.drop] == DEAD || d.version[c.keep] != c.keep_version ||
        d.version[c.drop] != c.drop_version)
      continue;
    if (!collapse_allowed(&d, c.keep, c.drop, c.target)) continue;
    collapse(&d, c.keep, c.drop, c.target);
  }

  // The survivors, with the corners their triangles still use. Collapses
  // leave a position's triangles with corners from several old positions;
  // those of one material facing within ~25 degrees become one corner (a
  // smooth surface stays one vertex per position, a crease between cut
  // faces stays sharp), so the vertices drop with the triangles.
  uint32_t* new_position = bk_alloc(sizeof(uint32_t) * np);
  bk_mesh_reserve(out, d.alive_positions, 3 * d.alive_triangles, d.alive_triangles);
  for (uint32_t p = 0; p < np; ++p)
    new_position[p] = d.state[p] == DEAD ? UINT32_MAX : bk_mesh_add_position(out, d.position[p]);
  uint32_t* first_corner = bk_alloc(sizeof(uint32_t) * (out->position_count + 1));  // per new position
  uint32_t* next_corner = bk_alloc(sizeof(uint32_t) * (3 * d.alive_triangles + 1)); // per new corner
  uint8_t* corner_material = bk_alloc(3 * d.alive_triangles + 1);
  for (uint32_t p = 0; p < out->position_count; ++p)
    first_corner[p] = UINT32_MAX;
  for (uint32_t t = 0; t < nt; ++t) {
    if (!d.tri_alive[t]) continue;
    uint32_t made[3];
    for (int k = 0; k < 3; ++k) {
      uint32_t p = new_position[d.tri[3 * t + k]];
      const bk_corner* original = &mesh->corners[mesh->indices[3 * t + k]];
      uint32_t c = first_corner[p];
      for (; c != UINT32_MAX; c = next_corner[c]) {
        const float* n = out->corners[c].normal;
        float facing = n[0] * original->normal[0] + n[1] * original->normal[1] + n[2] * original->normal[2];
        if (corner_material[c] == mesh->materials[t] && facing > 0.9f) break;
      }
      if (c == UINT32_MAX) {
        bk_corner copy = *original;
        copy.position = p;
        c = bk_mesh_add_corner(out, &copy);
        corner_material[c] = mesh->materials[t];
        next_corner[c] = first_corner[p];
        first_corner[p] = c;
      }
      made[k] = c;
    }
    bk_mesh_add_triangle(out, made[0], made[1], made[2], mesh->materials[t], mesh->tags ? mesh->tags[t] : 0);
  }
  bk_free(first_corner);
  bk_free(next_corner);
  bk_free(corner_material);
  bk_free(new_position);
  decimator_free(&d);
  return out->triangle_count;
}
