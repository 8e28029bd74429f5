// The named vertices of the cell complex and each cell's convex polytope.
// A vertex's coordinates are a function of its name alone (which source
// position, edge or triangle; which seeds or box planes), evaluated in one
// fixed order, so every cell that reaches a vertex gets bit-identical
// coordinates and the same index.
#include <stdlib.h>
#include <string.h>

#include "cell_complex.h"

// ---------------------------------------------------------------- vertex table

// Word by word: cheaper than hashing the key's bytes one at a time, and
// every clipped edge looks a key up. The hash only places keys in slots;
// vertex numbers follow the order of insertion.
static uint64_t key_hash(const bk_cell_key* k) {
  const uint64_t mul = 0x9e3779b97f4a7c15ull;
  uint64_t h = k->kind;
  h = (h ^ k->a) * mul;
  h = (h ^ k->b) * mul;
  for (int i = 0; i < 4; ++i)
    h = (h ^ (uint32_t)k->s[i]) * mul;
  return h ^ (h >> 32);
}

static bool key_equal(const bk_cell_key* a, const bk_cell_key* b) { return memcmp(a, b, sizeof *a) == 0; }

void bk_cell_complex_init(bk_cell_complex* cx, const bk_mesh* source, const bk_vec3* seeds,
                          uint32_t seed_count) {
  memset(cx, 0, sizeof *cx);
  cx->planar_axis = -1;
  cx->source = source;
  cx->seeds = seeds;
  cx->seed_count = seed_count;
  bk_aabb box = bk_mesh_bounds(source);
  for (uint32_t i = 0; i < seed_count; ++i) {
    box.min = bk_v3_min(box.min, seeds[i]);
    box.max = bk_v3_max(box.max, seeds[i]);
  }
  // A margin keeps every box plane clear of the source, so no box face ever
  // meets the solid and the box's corners are known to lie outside it.
  // It is kept small: a cell on the outside reaches to the box, and the
  // farther it reaches, the more seeds may cut it.
  bk_vec3 extent = bk_v3_sub(box.max, box.min);
  double pad = 0.02 * fmax(extent.x, fmax(extent.y, extent.z)) + 1e-3;
  bk_vec3 margin = bk_v3(pad, pad, pad);
  cx->box = (bk_aabb){bk_v3_sub(box.min, margin), bk_v3_add(box.max, margin)};
  cx->slot_mask = 1023;
  cx->slots = bk_calloc(cx->slot_mask + 1, sizeof(uint32_t));
  cx->source_vertex = bk_alloc(sizeof(uint32_t) * (source->position_count ? source->position_count : 1));
  memset(cx->source_vertex, 0xff, sizeof(uint32_t) * source->position_count);
}

void bk_cell_complex_free(bk_cell_complex* cx) {
  bk_free(cx->keys);
  bk_free(cx->points);
  bk_free(cx->slots);
  bk_free(cx->source_vertex);
  memset(cx, 0, sizeof *cx);
}

static bk_vec3 seed_of(const bk_cell_complex* cx, int32_t id) { return cx->seeds[id]; }

// Row of the bisector of seeds a < b: 2 (b - a) . x = (b - a) . (b + a).
static void bisector_row(const bk_cell_complex* cx, int32_t a, int32_t b, double row[4]) {
  bk_vec3 sa = seed_of(cx, a), sb = seed_of(cx, b);
  bk_vec3 d = bk_v3_sub(sb, sa);
  row[0] = 2.0 * d.x, row[1] = 2.0 * d.y, row[2] = 2.0 * d.z;
  row[3] = bk_v3_dot(d, bk_v3_add(sb, sa));
}

static void box_row(const bk_cell_complex* cx, int32_t id, double row[4]) {
  int plane = -id - 1, axis = plane / 2;
  row[0] = axis == 0, row[1] = axis == 1, row[2] = axis == 2;
  bk_vec3 corner = plane & 1 ? cx->box.max : cx->box.min;
  row[3] = axis == 0 ? corner.x : (axis == 1 ? corner.y : corner.z);
}

// Solves three rows [a b c | d] by Cramer's rule (one fixed order of
// operations: the same rows always give the same bits).
static bk_vec3 solve3(const double r[3][4]) {
  double det = r[0][0] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
               r[0][1] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
               r[0][2] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  double x = r[0][3] * (r[1][1] * r[2][2] - r[1][2] * r[2][1]) -
             r[0][1] * (r[1][3] * r[2][2] - r[1][2] * r[2][3]) +
             r[0][2] * (r[1][3] * r[2][1] - r[1][1] * r[2][3]);
  double y = r[0][0] * (r[1][3] * r[2][2] - r[1][2] * r[2][3]) -
             r[0][3] * (r[1][0] * r[2][2] - r[1][2] * r[2][0]) +
             r[0][2] * (r[1][0] * r[2][3] - r[1][3] * r[2][0]);
  double z = r[0][0] * (r[1][1] * r[2][3] - r[1][3] * r[2][1]) -
             r[0][1] * (r[1][0] * r[2][3] - r[1][3] * r[2][0]) +
             r[0][3] * (r[1][0] * r[2][1] - r[1][1] * r[2][0]);
  return bk_v3(x / det, y / det, z / det);
}

static double bisector_value(const bk_cell_complex* cx, int32_t a, int32_t b, bk_vec3 p) {
  bk_cell_side side = {.low = true};
  bisector_row(cx, a, b, side.row);
  return bk_cell_side_value(&side, p);
}

bk_cell_side bk_cell_side_of(const bk_cell_complex* cx, int32_t cell, int32_t other) {
  bk_cell_side side = {.low = cell < other};
  bisector_row(cx, cell < other ? cell : other, cell < other ? other : cell, side.row);
  return side;
}

static bk_vec3 compute_point(const bk_cell_complex* cx, const bk_cell_key* k) {
  const bk_mesh* m = cx->source;
  switch ((bk_cell_vertex_kind)k->kind) {
  case BK_CELL_SOURCE:
    return m->positions[k->a];
  case BK_CELL_CROSSING: {
    bk_vec3 pa = m->positions[k->a], pb = m->positions[k->b];
    double fa = bisector_value(cx, k->s[0], k->s[1], pa), fb = bisector_value(cx, k->s[0], k->s[1], pb);
    double t = fa / (fa - fb);
    t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
    return bk_v3_add(pa, bk_v3_scale(bk_v3_sub(pb, pa), t));
  }
  case BK_CELL_PIERCING: {
    bk_vec3 p0 = m->positions[bk_mesh_tri_position(m, k->a, 0)];
    bk_vec3 p1 = m->positions[bk_mesh_tri_position(m, k->a, 1)];
    bk_vec3 p2 = m->positions[bk_mesh_tri_position(m, k->a, 2)];
    bk_vec3 n = bk_v3_cross(bk_v3_sub(p1, p0), bk_v3_sub(p2, p0));
    double r[3][4];
    bisector_row(cx, k->s[0], k->s[1], r[0]);
    bisector_row(cx, k->s[0], k->s[2], r[1]);
    r[2][0] = n.x, r[2][1] = n.y, r[2][2] = n.z, r[2][3] = bk_v3_dot(n, p0);
    return solve3(r);
  }
  case BK_CELL_NOISE_POINT:
    return bk_v3(0, 0, 0); // placed by bk_cell_vertex_at
  case BK_CELL_CORNER: {
    double r[3][4];
    int rows = 0;
    int32_t first = -1;
    for (int i = 0; i < 4; ++i) {
      if (k->s[i] < 0) {
        box_row(cx, k->s[i], r[rows++]);
      } else if (first < 0) {
        first = k->s[i];
      } else {
        bisector_row(cx, first, k->s[i], r[rows++]);
      }
    }
    return solve3(r);
  }
  }
  return bk_v3(0, 0, 0);
}

static void grow_slots(bk_cell_complex* cx) {
  uint32_t size = (cx->slot_mask + 1) * 2;
  bk_free(cx->slots);
  cx->slots = bk_calloc(size, sizeof(uint32_t));
  cx->slot_mask = size - 1;
  for (uint32_t i = 0; i < cx->count; ++i) {
    uint32_t s = (uint32_t)key_hash(&cx->keys[i]) & cx->slot_mask;
    while (cx->slots[s])
      s = (s + 1) & cx->slot_mask;
    cx->slots[s] = i + 1;
  }
}

uint32_t bk_cell_vertex_find(const bk_cell_complex* cx, const bk_cell_key* key) {
  uint32_t s = (uint32_t)key_hash(key) & cx->slot_mask;
  while (cx->slots[s]) {
    if (key_equal(&cx->keys[cx->slots[s] - 1], key)) return cx->slots[s] - 1;
    s = (s + 1) & cx->slot_mask;
  }
  return UINT32_MAX;
}

static uint32_t insert(bk_cell_complex* cx, const bk_cell_key* key, const bk_vec3* point) {
  uint32_t s = (uint32_t)key_hash(key) & cx->slot_mask;
  while (cx->slots[s]) {
    if (key_equal(&cx->keys[cx->slots[s] - 1], key)) return cx->slots[s] - 1;
    s = (s + 1) & cx->slot_mask;
  }
  if (cx->count == cx->capacity) {
    cx->capacity = bk_grow_capacity(cx->capacity, cx->count + 1);
    cx->keys = bk_realloc(cx->keys, sizeof(bk_cell_key) * cx->capacity);
    cx->points = bk_realloc(cx->points, sizeof(bk_vec3) * cx->capacity);
  }
  uint32_t index = cx->count++;
  cx->keys[index] = *key;
  cx->points[index] = point ? *point : compute_point(cx, key);
  cx->slots[s] = index + 1;
  if (cx->count * 2 > cx->slot_mask) grow_slots(cx);
  return index;
}

uint32_t bk_cell_vertex(bk_cell_complex* cx, const bk_cell_key* key) { return insert(cx, key, NULL); }

uint32_t bk_cell_source_vertex(bk_cell_complex* cx, uint32_t position) {
  if (cx->source_vertex[position] == UINT32_MAX) {
    bk_cell_key key = {.kind = BK_CELL_SOURCE, .a = position};
    cx->source_vertex[position] = insert(cx, &key, NULL);
  }
  return cx->source_vertex[position];
}

uint32_t bk_cell_vertex_at(bk_cell_complex* cx, const bk_cell_key* key, bk_vec3 point) {
  return insert(cx, key, &point);
}

bool bk_cell_belongs(const bk_cell_complex* cx, bk_vec3 p, int32_t a, int32_t b) {
  if (b < 0) { // a box plane: inside the box
    int plane = -b - 1, axis = plane / 2;
    double c = axis == 0 ? p.x : (axis == 1 ? p.y : p.z);
    bk_vec3 corner = plane & 1 ? cx->box.max : cx->box.min;
    double limit = axis == 0 ? corner.x : (axis == 1 ? corner.y : corner.z);
    return plane & 1 ? c <= limit : c >= limit;
  }
  int32_t lo = a < b ? a : b, hi = a < b ? b : a;
  double f = bisector_value(cx, lo, hi, p); // > 0: nearer hi
  return a == lo ? f <= 0.0 : f > 0.0;
}

// ---------------------------------------------------------------- polytopes

struct bk_cell_builder {
  // The cell's vertices while it is clipped: most are cut away again, so
  // they are named in a small table of the cell's own (the same names give
  // the same coordinates) and only the final ones go into the complex.
  bk_cell_complex local;
  uint32_t* remap; // per local vertex: its index in the complex, when stored
  uint32_t remap_capacity;
  bk_cell_polytope work, next;
  uint8_t* keep; // per loop entry of `work`: on the cell's side of the plane being cut
  uint32_t keep_capacity;
  uint32_t (*segments)[2]; // new face's edges: entry -> exit
  uint32_t segment_capacity;
  uint32_t* scratch; // one face's clipped loop, then the new face's loop
  uint32_t scratch_capacity;
  // The points of the distinct vertices of `work` (each sits in three or
  // more of its loops): most bisectors near a cell miss it, and that is seen
  // testing each vertex once.
  bk_vec3* corner_points;
  uint32_t corner_count, corner_capacity;
  uint32_t* seen; // per local vertex: the epoch it was last listed in
  uint32_t seen_capacity, epoch;
  bk_vec3 lo, hi; // the vertices' bounds, relative to the seed
  double scale;   // the largest coordinate in the box, for rounding bounds
  // The clipping in progress (bk_cell_polytope_begin): it goes on where the
  // last list of near seeds ended.
  uint32_t cell;
  double radius; // the cell's reach, or an upper bound when `stale`
  bool stale, done;
};

bk_cell_builder* bk_cell_builder_create(void) { return bk_calloc(1, sizeof(bk_cell_builder)); }

void bk_cell_polytope_free(bk_cell_polytope* p) {
  bk_free(p->planes);
  bk_free(p->face_first);
  bk_free(p->face_count);
  bk_free(p->loop);
  memset(p, 0, sizeof *p);
}

void bk_cell_builder_destroy(bk_cell_builder* b) {
  if (!b) return;
  bk_cell_polytope_free(&b->work);
  bk_cell_polytope_free(&b->next);
  bk_free(b->segments);
  bk_free(b->keep);
  bk_free(b->scratch);
  bk_free(b->corner_points);
  bk_free(b->seen);
  bk_free(b->local.keys);
  bk_free(b->local.points);
  bk_free(b->local.slots);
  bk_free(b->remap);
  bk_free(b);
}

static void sort_ids(int32_t* s, int n) {
  for (int i = 1; i < n; ++i)
    for (int j = i; j > 0 && s[j - 1] > s[j]; --j) {
      int32_t t = s[j];
      s[j] = s[j - 1];
      s[j - 1] = t;
    }
}

static void add_face(bk_cell_polytope* p, int32_t plane, const uint32_t* loop, uint32_t count) {
  // The builder's polytopes keep their arrays from cut to cut: they grow, never shrink.
  if (p->faces == p->face_capacity) {
    p->face_capacity = bk_grow_capacity(p->face_capacity, p->faces + 1);
    p->planes = bk_realloc(p->planes, sizeof(int32_t) * p->face_capacity);
    p->face_first = bk_realloc(p->face_first, sizeof(uint32_t) * p->face_capacity);
    p->face_count = bk_realloc(p->face_count, sizeof(uint32_t) * p->face_capacity);
  }
  if (p->loop_count + count > p->loop_capacity) {
    p->loop_capacity = bk_grow_capacity(p->loop_capacity, p->loop_count + count);
    p->loop = bk_realloc(p->loop, sizeof(uint32_t) * p->loop_capacity);
  }
  p->planes[p->faces] = plane;
  p->face_first[p->faces] = p->loop_count;
  p->face_count[p->faces] = count;
  p->faces++;
  memcpy(p->loop + p->loop_count, loop, sizeof(uint32_t) * count);
  p->loop_count += count;
}

static void reset(bk_cell_polytope* p) { p->faces = p->loop_count = 0; }

static uint32_t* scratch_of(bk_cell_builder* b, uint32_t count) {
  if (b->scratch_capacity < count) {
    b->scratch_capacity = bk_grow_capacity(b->scratch_capacity, count);
    b->scratch = bk_realloc(b->scratch, sizeof(uint32_t) * b->scratch_capacity);
  }
  return b->scratch;
}

// Lists the distinct vertices of `work` (indices into cx, the cell's own
// table) and their bounds.
static void list_corners(bk_cell_builder* b, const bk_cell_complex* cx) {
  if (b->seen_capacity < cx->count) {
    uint32_t old = b->seen_capacity;
    b->seen_capacity = bk_grow_capacity(b->seen_capacity, cx->count);
    b->seen = bk_realloc(b->seen, sizeof(uint32_t) * b->seen_capacity);
    memset(b->seen + old, 0, sizeof(uint32_t) * (b->seen_capacity - old));
  }
  if (++b->epoch == 0) { // wrapped: no stamp may look current
    memset(b->seen, 0, sizeof(uint32_t) * b->seen_capacity);
    b->epoch = 1;
  }
  const bk_cell_polytope* p = &b->work;
  b->corner_count = 0;
  bk_vec3 seed = cx->seeds[b->cell];
  b->lo = bk_v3(INFINITY, INFINITY, INFINITY);
  b->hi = bk_v3(-INFINITY, -INFINITY, -INFINITY);
  for (uint32_t i = 0; i < p->loop_count; ++i) {
    uint32_t v = p->loop[i];
    if (b->seen[v] == b->epoch) continue;
    b->seen[v] = b->epoch;
    if (b->corner_count == b->corner_capacity) {
      b->corner_capacity = bk_grow_capacity(b->corner_capacity, b->corner_count + 1);
      b->corner_points = bk_realloc(b->corner_points, sizeof(bk_vec3) * b->corner_capacity);
    }
    b->corner_points[b->corner_count++] = cx->points[v];
    b->lo = bk_v3_min(b->lo, bk_v3_sub(cx->points[v], seed));
    b->hi = bk_v3_max(b->hi, bk_v3_sub(cx->points[v], seed));
  }
}

static void init_box(bk_cell_complex* cx, uint32_t cell, bk_cell_polytope* p) {
  static const uint8_t loops[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                      {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
  uint32_t corner[8];
  for (int c = 0; c < 8; ++c) {
    bk_cell_key k = {.kind = BK_CELL_CORNER};
    k.s[0] = (int32_t)cell, k.s[1] = c & 1 ? -2 : -1, k.s[2] = c & 2 ? -4 : -3, k.s[3] = c & 4 ? -6 : -5;
    sort_ids(k.s, 4);
    corner[c] = bk_cell_vertex(cx, &k);
  }
  reset(p);
  for (int f = 0; f < 6; ++f) {
    uint32_t loop[4] = {corner[loops[f][0]], corner[loops[f][1]], corner[loops[f][2]], corner[loops[f][3]]};
    add_face(p, -(f + 1), loop, 4);
  }
}

// The vertex where the polytope edge u-v crosses the bisector with m: its
// name is the edge's three ids (the two names' common part) plus m.
static bool crossing_vertex(bk_cell_complex* cx, uint32_t u, uint32_t v, int32_t m, uint32_t* out) {
  const bk_cell_key *ku = &cx->keys[u], *kv = &cx->keys[v];
  bk_cell_key k = {.kind = BK_CELL_CORNER};
  int n = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (ku->s[i] == kv->s[j]) {
        if (n == 3) return false;
        k.s[n++] = ku->s[i];
      }
  if (n != 3) return false;
  k.s[3] = m;
  sort_ids(k.s, 4);
  *out = bk_cell_vertex(cx, &k);
  return true;
}

// Cuts the polytope by the bisector of `cell` and seed m, keeping cell's
// side; *cut tells whether it lost anything.
static bool clip(bk_cell_builder* b, bk_cell_complex* cx, uint32_t cell, int32_t m, bool* cut) {
  bk_cell_polytope* p = &b->work;
  bk_cell_side side = bk_cell_side_of(cx, (int32_t)cell, m);
  *cut = false;
  bool any_out = false, any_in = false;
  for (uint32_t i = 0; i < b->corner_count && !any_out; ++i)
    any_out = !bk_cell_side_keeps(&side, b->corner_points[i]);
  if (!any_out) return true;
  if (b->keep_capacity < p->loop_count) {
    b->keep_capacity = bk_grow_capacity(b->keep_capacity, p->loop_count);
    b->keep = bk_realloc(b->keep, b->keep_capacity);
  }
  any_out = false;
  for (uint32_t i = 0; i < p->loop_count; ++i) {
    bool in = bk_cell_side_keeps(&side, cx->points[p->loop[i]]);
    b->keep[i] = in;
    any_out |= !in;
    any_in |= in;
  }
  if (!any_in) return false; // the seed itself would be cut away: coincident seeds
  bk_cell_polytope* q = &b->next;
  reset(q);
  uint32_t segments = 0;
  for (uint32_t f = 0; f < p->faces; ++f) {
    const uint32_t* loop = p->loop + p->face_first[f];
    uint32_t count = p->face_count[f], out = 0;
    uint32_t* scratch = scratch_of(b, 2 * count + 2);
    uint32_t exit_vertex = UINT32_MAX, entry_vertex = UINT32_MAX;
    const uint8_t* keep = b->keep + p->face_first[f];
    for (uint32_t k = 0; k < count; ++k) {
      uint32_t u = loop[k], v = loop[(k + 1) % count];
      bool iu = keep[k], iv = keep[(k + 1) % count];
      if (iu) scratch[out++] = u;
      if (iu != iv) {
        uint32_t x = 0;
        if (!crossing_vertex(cx, u, v, m, &x)) return false;
        scratch[out++] = x;
        if (iu)
          exit_vertex = x;
        else
          entry_vertex = x;
      }
    }
    if (exit_vertex != UINT32_MAX) {
      if (entry_vertex == UINT32_MAX) return false;
      if (segments == b->segment_capacity) {
        b->segment_capacity = bk_grow_capacity(b->segment_capacity, segments + 1);
        b->segments = bk_realloc(b->segments, sizeof *b->segments * b->segment_capacity);
      }
      // This face runs exit -> entry along the new plane; the new face runs back.
      b->segments[segments][0] = entry_vertex;
      b->segments[segments][1] = exit_vertex;
      segments++;
    }
    if (out >= 3) add_face(q, p->planes[f], scratch, out);
  }
  if (segments < 3) return false;
  // Chain the segments into the new face's loop.
  uint32_t* loop = scratch_of(b, segments);
  uint32_t at = 0, n = 0;
  for (; n < segments; ++n) {
    loop[n] = b->segments[at][0];
    uint32_t next = b->segments[at][1], found = UINT32_MAX;
    for (uint32_t s = 0; s < segments; ++s)
      if (b->segments[s][0] == next) found = s;
    if (found == UINT32_MAX) break;
    at = found;
    if (at == 0) {
      n++;
      break;
    }
  }
  if (n != segments || at != 0) return false;
  add_face(q, m, loop, segments);
  bk_cell_polytope t = b->work;
  b->work = b->next;
  b->next = t;
  list_corners(b, cx);
  *cut = true;
  return true;
}

double bk_cell_distance(const bk_cell_complex* cx, bk_vec3 a, bk_vec3 b) {
  bk_vec3 d = bk_v3_sub(a, b);
  if (cx->planar_axis == 0) d.x = 0.0;
  if (cx->planar_axis == 1) d.y = 0.0;
  if (cx->planar_axis == 2) d.z = 0.0;
  return bk_v3_length(d);
}

double bk_cell_builder_reach(const bk_cell_builder* b, const bk_cell_complex* cx) {
  double r = 0.0;
  for (uint32_t i = 0; i < b->corner_count; ++i)
    r = fmax(r, bk_cell_distance(cx, b->corner_points[i], cx->seeds[b->cell]));
  return r;
}

// True when the bisector with the seed at `e` from the cell's seed surely
// misses the cell: the bisector is where e.(p - seed) = |e|^2 / 2, and over
// the cell's bounds e.(p - seed) stays below that by more than any rounding
// in bk_cell_side_keeps could make up. Most seeds near a cell are ruled out
// so, without testing every vertex.
static bool misses_bounds(const bk_cell_builder* b, bk_vec3 e) {
  double support = fmax(e.x * b->lo.x, e.x * b->hi.x) + fmax(e.y * b->lo.y, e.y * b->hi.y) +
                   fmax(e.z * b->lo.z, e.z * b->hi.z);
  double length = bk_v3_length(e);
  return support < 0.5 * bk_v3_dot(e, e) - length * (1e-9 * length + 1e-12 * b->scale);
}

// Empties the cell's own vertex table, which names vertices as cx does.
static void reset_local(bk_cell_builder* b, const bk_cell_complex* cx) {
  bk_cell_complex* l = &b->local;
  l->source = cx->source;
  l->seeds = cx->seeds;
  l->seed_count = cx->seed_count;
  l->box = cx->box;
  l->planar_axis = cx->planar_axis;
  l->count = 0;
  if (!l->slots) {
    l->slot_mask = 255;
    l->slots = bk_alloc(sizeof(uint32_t) * (l->slot_mask + 1));
  }
  memset(l->slots, 0, sizeof(uint32_t) * (l->slot_mask + 1));
}

void bk_cell_polytope_begin(bk_cell_builder* b, bk_cell_complex* cx, uint32_t cell) {
  reset_local(b, cx);
  init_box(&b->local, cell, &b->work);
  b->cell = cell;
  list_corners(b, &b->local);
  bk_vec3 low = cx->box.min, high = cx->box.max;
  b->scale = fmax(fmax(fmax(fabs(low.x), fabs(low.y)), fmax(fabs(low.z), fabs(high.x))),
                  fmax(fabs(high.y), fabs(high.z)));
  b->radius = bk_cell_builder_reach(b, cx);
  b->stale = b->done = false;
}

bool bk_cell_polytope_clip(bk_cell_builder* b, bk_cell_complex* cx, const uint32_t* near,
                           uint32_t near_count) {
  bk_vec3 seed = cx->seeds[b->cell];
  for (uint32_t i = 0; i < near_count && !b->done; ++i) {
    // Past twice the cell's reach no bisector can cut it any more. Clipping
    // only shrinks the cell, so a stale reach is an upper bound, brought up
    // to date only when it no longer rules a seed out.
    bk_vec3 e = bk_v3_sub(cx->seeds[near[i]], seed);
    double d = bk_v3_length(e);
    if (d > 2.0 * b->radius && b->stale) b->radius = bk_cell_builder_reach(b, cx), b->stale = false;
    if (d > 2.0 * b->radius) {
      b->done = true;
      break;
    }
    if (misses_bounds(b, e)) continue; // clipping would change nothing
    bool cut = false;
    if (!clip(b, &b->local, b->cell, (int32_t)near[i], &cut)) return false;
    b->stale |= cut;
  }
  return true;
}

void bk_cell_polytope_store(bk_cell_builder* b, bk_cell_complex* cx, bk_cell_polytope* out) {
  const bk_cell_polytope* w = &b->work;
  const bk_cell_complex* l = &b->local;
  if (b->remap_capacity < l->count) {
    b->remap_capacity = bk_grow_capacity(b->remap_capacity, l->count);
    b->remap = bk_realloc(b->remap, sizeof(uint32_t) * b->remap_capacity);
  }
  memset(b->remap, 0xff, sizeof(uint32_t) * l->count);
  bk_cell_polytope_free(out);
  out->planes = bk_alloc(sizeof(int32_t) * (w->faces ? w->faces : 1));
  out->face_first = bk_alloc(sizeof(uint32_t) * (w->faces ? w->faces : 1));
  out->face_count = bk_alloc(sizeof(uint32_t) * (w->faces ? w->faces : 1));
  out->loop = bk_alloc(sizeof(uint32_t) * (w->loop_count ? w->loop_count : 1));
  memcpy(out->planes, w->planes, sizeof(int32_t) * w->faces);
  memcpy(out->face_first, w->face_first, sizeof(uint32_t) * w->faces);
  memcpy(out->face_count, w->face_count, sizeof(uint32_t) * w->faces);
  for (uint32_t i = 0; i < w->loop_count; ++i) {
    uint32_t v = w->loop[i];
    if (b->remap[v] == UINT32_MAX) b->remap[v] = bk_cell_vertex_at(cx, &l->keys[v], l->points[v]);
    out->loop[i] = b->remap[v];
  }
  out->faces = out->face_capacity = w->faces;
  out->loop_count = out->loop_capacity = w->loop_count;
}
