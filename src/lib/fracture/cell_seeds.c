// Seed points of the cell patterns, all inside the source (in the tree's
// local frame): uniform for Voronoi, chunk centres plus points along the
// chunks' borders for clustered, and a density falling with distance from
// the impact for radial. Candidates are drawn in batches and kept when the
// ray-parity test puts them inside, so the draws depend only on the seed.
#include <stdlib.h>
#include <string.h>

#include "cell_complex.h"

/// Generated seeds keep at least this fraction of the mean seed spacing
/// (cube root of volume per piece) apart, while the draws allow it.
#define BK_CELL_SEED_GAP 0.3

typedef struct seed_list {
  bk_vec3* points;
  uint32_t count, capacity;
} seed_list;

static void push(seed_list* s, bk_vec3 p) {
  if (s->count == s->capacity) {
    s->capacity = bk_grow_capacity(s->capacity, s->count + 1);
    s->points = bk_realloc(s->points, sizeof(bk_vec3) * s->capacity);
  }
  s->points[s->count++] = p;
}

typedef enum draw_kind { DRAW_UNIFORM, DRAW_BORDER, DRAW_CORE, DRAW_RADIAL } draw_kind;

typedef struct draw_def {
  draw_kind kind;
  const bk_vec3* centres; // border: chunk centres
  uint32_t centre_count;
  double border; // border: largest (second nearest - nearest) distance
  bk_vec3 impact;
  double reach, exponent, min_radius; // radial
  double gap;                         // no two seeds closer (0: any)
} draw_def;

// The seeds drawn so far, hashed on a grid of the gap's size, to keep new
// ones at least `gap` from all of them.
typedef struct gap_grid {
  double cell;
  bk_index_map heads; // grid cell -> first point + 1
  uint32_t* next;     // per point: the next in its grid cell + 1
  uint32_t capacity;
} gap_grid;

// A grid coordinate, wrapped to 21 bits (a far point only shares a bucket,
// its distance is still checked); clamped first so no cast overflows.
static uint64_t gap_coord(double v, double cell, int d) {
  double c = floor(v / cell);
  c = c > 1e15 ? 1e15 : (c < -1e15 ? -1e15 : (c == c ? c : 0.0));
  return (uint64_t)((int64_t)c + d) & 0x1fffff;
}

static uint64_t gap_key(const gap_grid* g, bk_vec3 p, int dx, int dy, int dz) {
  return gap_coord(p.x, g->cell, dx) << 42 | gap_coord(p.y, g->cell, dy) << 21 | gap_coord(p.z, g->cell, dz);
}

static void gap_add(gap_grid* g, const bk_vec3* points, uint32_t i) {
  if (i >= g->capacity) {
    g->capacity = bk_grow_capacity(g->capacity, i + 1);
    g->next = bk_realloc(g->next, sizeof(uint32_t) * g->capacity);
  }
  bool inserted = false;
  uint32_t* head = bk_index_map_insert(&g->heads, gap_key(g, points[i], 0, 0, 0), i + 1, &inserted);
  g->next[i] = inserted ? 0 : *head;
  *head = i + 1;
}

static void gap_reset(gap_grid* g, double gap, const seed_list* out) {
  g->cell = gap;
  bk_index_map_clear(&g->heads);
  for (uint32_t i = 0; gap > 0.0 && i < out->count; ++i)
    gap_add(g, out->points, i);
}

static bool gap_clear(const gap_grid* g, const seed_list* out, bk_vec3 p) {
  if (!(g->cell > 0.0)) return true;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const uint32_t* head = bk_index_map_find(&g->heads, gap_key(g, p, dx, dy, dz));
        for (uint32_t i = head ? *head : 0; i; i = g->next[i - 1]) {
          bk_vec3 e = bk_v3_sub(out->points[i - 1], p);
          if (bk_v3_dot(e, e) < g->cell * g->cell) return false;
        }
      }
  return true;
}

static bk_vec3 candidate(bk_rng* rng, bk_aabb box, const draw_def* dd) {
  if (dd->kind == DRAW_RADIAL) {
    // Points within r of the impact grow as r^exponent: density ~ r^(exponent - 3).
    // Within min_radius nothing is drawn (returned as a point the caller
    // rejects): a crowd of seeds at the impact would make cells too small
    // to cut reliably.
    double r = dd->reach * bk_pow(bk_rng_unit(rng), 1.0 / dd->exponent);
    bk_vec3 dir = bk_rng_direction(rng);
    if (r < dd->min_radius) return bk_v3(INFINITY, INFINITY, INFINITY);
    return bk_v3_add(dd->impact, bk_v3_scale(dir, r));
  }
  double x = bk_rng_unit(rng), y = bk_rng_unit(rng), z = bk_rng_unit(rng);
  return bk_v3(box.min.x + x * (box.max.x - box.min.x), box.min.y + y * (box.max.y - box.min.y),
               box.min.z + z * (box.max.z - box.min.z));
}

static bool accept(const draw_def* dd, bk_vec3 p) {
  if ((dd->kind != DRAW_BORDER && dd->kind != DRAW_CORE) || dd->centre_count < 2) return true;
  double d1 = INFINITY, d2 = INFINITY;
  for (uint32_t c = 0; c < dd->centre_count; ++c) {
    double d = bk_v3_length(bk_v3_sub(p, dd->centres[c]));
    if (d < d1) {
      d2 = d1;
      d1 = d;
    } else if (d < d2) {
      d2 = d;
    }
  }
  return dd->kind == DRAW_BORDER ? d2 - d1 < dd->border : d2 - d1 >= dd->border;
}

// Draws `want` points inside the source into `out`; false when too few of
// the candidates land inside (a source that fills almost none of its box, or
// an impact far away from it).
static bool draw_inside(const bk_mesh* m, const bk_inside_test* test, bk_rng* rng, const draw_def* dd,
                        uint32_t want, seed_list* out) {
  bk_aabb box = bk_mesh_bounds(m);
  uint32_t batch = want < 64 ? 256 : want * 4;
  bk_vec3* pts = bk_alloc(sizeof(bk_vec3) * batch);
  uint8_t* inside = bk_alloc(batch);
  uint64_t drawn = 0, limit = (uint64_t)want * 2000 + 100000, relax = limit / 8;
  uint32_t target = out->count + want;
  gap_grid grid = {0};
  bk_index_map_init(&grid.heads, want * 2 + 64);
  double gap = dd->gap;
  gap_reset(&grid, gap, out);
  while (out->count < target && drawn < limit) {
    // Candidates the pattern refuses (most of them for a thin border band)
    // are dropped before the costlier inside test; the order of the rest
    // is kept, so the same seeds are chosen.
    uint32_t tested = 0;
    for (uint32_t i = 0; i < batch; ++i) {
      bk_vec3 p = candidate(rng, box, dd);
      if (accept(dd, p)) pts[tested++] = p;
    }
    drawn += batch;
    bk_inside_test_run(test, pts, tested, inside);
    for (uint32_t i = 0; i < tested && out->count < target; ++i)
      if (inside[i] && gap_clear(&grid, out, pts[i])) {
        push(out, pts[i]);
        if (gap > 0.0) gap_add(&grid, out->points, out->count - 1);
      }
    // Too crowded for the gap (a thin band, a dense impact): halve it.
    if (gap > 0.0 && drawn >= relax) {
      gap = gap > 0.02 * dd->gap ? 0.5 * gap : 0.0;
      gap_reset(&grid, gap, out);
      relax += limit / 8;
    }
  }
  bk_index_map_free(&grid.heads);
  bk_free(grid.next);
  bk_free(pts);
  bk_free(inside);
  return out->count == target;
}

static uint32_t nearest(const bk_vec3* centres, uint32_t count, bk_vec3 p) {
  uint32_t best = 0;
  double best_d = INFINITY;
  for (uint32_t c = 0; c < count; ++c) {
    double dist = bk_v3_length(bk_v3_sub(p, centres[c]));
    if (dist < best_d) best_d = dist, best = c;
  }
  return best;
}

static int compare_points(const void* pa, const void* pb) {
  const bk_vec3 *a = pa, *b = pb;
  if (a->x != b->x) return a->x < b->x ? -1 : 1;
  if (a->y != b->y) return a->y < b->y ? -1 : 1;
  return a->z < b->z ? -1 : (a->z > b->z);
}

// The caller's points inside the source, in the local frame, without
// duplicates (a repeated point would make an empty cell).
static bool user_seeds(const bk_mesh* m, const bk_fracture_def* d, bk_vec3 origin, int exponent,
                       seed_list* out, bk_error* err) {
  bk_vec3* local = bk_alloc(sizeof(bk_vec3) * d->seed_point_count);
  uint8_t* inside = bk_alloc(d->seed_point_count);
  for (uint32_t i = 0; i < d->seed_point_count; ++i) {
    bk_vec3 p = bk_v3_sub(d->seed_points[i], origin);
    local[i] = bk_v3(ldexp(p.x, -exponent), ldexp(p.y, -exponent), ldexp(p.z, -exponent));
  }
  bk_points_inside(m, local, d->seed_point_count, inside);
  for (uint32_t i = 0; i < d->seed_point_count; ++i)
    if (inside[i]) push(out, local[i]);
  bk_free(local);
  bk_free(inside);
  if (out->count == 0)
    return bk_error_set(err, "fracture: none of the %u seed points lies inside the source",
                        d->seed_point_count);
  bk_sort(out->points, out->count, sizeof(bk_vec3), compare_points);
  uint32_t kept = 1;
  for (uint32_t i = 1; i < out->count; ++i)
    if (compare_points(&out->points[i], &out->points[kept - 1]) != 0) out->points[kept++] = out->points[i];
  out->count = kept;
  return true;
}

uint32_t bk_cell_seeds(const bk_mesh* m, const bk_fracture_def* d, bk_vec3 origin, int exponent,
                       bk_vec3** seeds, uint32_t** cluster_of, uint32_t** labels, bk_error* err) {
  *seeds = NULL;
  *cluster_of = NULL;
  *labels = NULL;
  seed_list list = {0};
  bk_rng rng = bk_rng_seed(d->seed, 0x63656c6cu);
  bk_aabb box = bk_mesh_bounds(m);
  bk_vec3 size = bk_v3_sub(box.max, box.min);
  double largest = fmax(size.x, fmax(size.y, size.z));
  // No two generated seeds closer than this: a crowd of seeds (the impact's
  // neighbourhood, a chunk's border band, chance) makes pieces so small
  // that a physics engine cannot rest them (they jitter awake for ever).
  double gap = BK_CELL_SEED_GAP * bk_cbrt(fmax(bk_mesh_volume(m), 0.0) / d->pieces);
  if (!(gap > 1e-9 * largest)) gap = 0.0; // a sliver of a source: no gap to keep
  // The source is binned for the inside test once, for every batch of candidates.
  bk_inside_test* test = bk_inside_test_create(m);
  bool ok = true;
  switch (d->pattern) {
  case BK_PATTERN_CLUSTERED: {
    // Chunks are the Voronoi regions of a few centres. Each chunk's core
    // is filled with coarse cells that all carry the chunk's label (so
    // they become one piece), the band along the chunks' borders with
    // fine cells of their own.
    uint32_t chunks = d->clusters < d->pieces ? d->clusters : d->pieces;
    draw_def uniform = {.kind = DRAW_UNIFORM};
    // Centres by best candidate (of 16 draws, the farthest from those
    // already placed), so chunks come out of similar size.
    seed_list centres = {0}, candidates = {0};
    for (uint32_t c = 0; c < chunks && ok; ++c) {
      candidates.count = 0;
      ok = draw_inside(m, test, &rng, &uniform, 16, &candidates);
      uint32_t best = 0;
      double best_d = -1.0;
      for (uint32_t i = 0; i < candidates.count && c; ++i) {
        double dist = bk_v3_length(bk_v3_sub(
            candidates.points[i], centres.points[nearest(centres.points, c, candidates.points[i])]));
        if (dist > best_d) best_d = dist, best = i;
      }
      if (ok) push(&centres, candidates.points[best]);
    }
    bk_free(candidates.points);
    double band = d->cluster_border * largest;
    uint32_t cores = 0;
    if (ok && chunks > 1) {
      draw_def core = {.kind = DRAW_CORE, .centres = centres.points, .centre_count = chunks, .border = band};
      ok = draw_inside(m, test, &rng, &core, 8 * chunks, &list);
      cores = list.count;
      // Chunks whose core drew no seed are all border: the pieces left go
      // to the border cells.
      uint32_t cored = 0;
      for (uint32_t c = 0; c < chunks && ok; ++c) {
        bool has = false;
        for (uint32_t i = 0; i < cores && !has; ++i)
          has = nearest(centres.points, chunks, list.points[i]) == c;
        cored += has;
      }
      draw_def border = {
          .gap = gap, .kind = DRAW_BORDER, .centres = centres.points, .centre_count = chunks, .border = band};
      if (ok && d->pieces > cored) ok = draw_inside(m, test, &rng, &border, d->pieces - cored, &list);
    } else if (ok) { // one chunk: no borders, it stays whole
      push(&list, centres.points[0]);
      cores = 1;
    }
    if (ok) {
      *cluster_of = bk_alloc(sizeof(uint32_t) * list.count);
      *labels = bk_alloc(sizeof(uint32_t) * list.count);
      for (uint32_t i = 0; i < list.count; ++i) {
        uint32_t best = nearest(centres.points, chunks, list.points[i]);
        (*cluster_of)[i] = best;
        (*labels)[i] = i < cores ? best : chunks + i;
      }
    }
    bk_free(centres.points);
    break;
  }
  case BK_PATTERN_RADIAL: {
    bk_vec3 p = bk_v3_sub(d->impact, origin);
    bk_vec3 impact = bk_v3(ldexp(p.x, -exponent), ldexp(p.y, -exponent), ldexp(p.z, -exponent));
    double reach = 0.0;
    for (int c = 0; c < 8; ++c) {
      bk_vec3 corner =
          bk_v3(c & 1 ? box.max.x : box.min.x, c & 2 ? box.max.y : box.min.y, c & 4 ? box.max.z : box.min.z);
      reach = fmax(reach, bk_v3_length(bk_v3_sub(corner, impact)));
    }
    draw_def radial = {.kind = DRAW_RADIAL,
                       .gap = gap,
                       .impact = impact,
                       .reach = reach,
                       .exponent = 3.0 - 2.0 * d->radial_falloff,
                       .min_radius = 0.01 * largest};
    ok = draw_inside(m, test, &rng, &radial, d->pieces, &list);
    break;
  }
  default:
    if (d->seed_points) {
      if (!user_seeds(m, d, origin, exponent, &list, err)) {
        bk_free(list.points);
        bk_inside_test_destroy(test);
        return 0;
      }
    } else {
      draw_def uniform = {.kind = DRAW_UNIFORM, .gap = gap};
      ok = draw_inside(m, test, &rng, &uniform, d->pieces, &list);
    }
    break;
  }
  bk_inside_test_destroy(test);
  if (!ok) {
    bk_free(list.points);
    bk_free(*cluster_of);
    bk_free(*labels);
    *cluster_of = NULL;
    *labels = NULL;
    return bk_error_set(
               err,
               d->pattern == BK_PATTERN_RADIAL
                   ? "fracture: could not place %u seed points inside the source around the impact point "
                     "(is the impact far from the source?)"
                   : "fracture: could not place %u seed points inside the source (it fills almost none "
                     "of its bounding box)",
               d->pieces),
           0;
  }
  *seeds = list.points;
  return list.count;
}
