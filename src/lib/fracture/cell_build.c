// Makes the cell complex of one build: seeds, each cell's polytope (clipped
// by the bisectors of the seeds near it, nearest first, until no farther
// seed can reach it), the source's surface inside each cell, and the cut
// faces between cells.
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "cell_stages.h"

// Source triangles binned by their bounds, to find those near a cell.
typedef struct tri_grid {
  bk_aabb box;
  int n[3];
  bk_vec3 cell;
  uint32_t *start, *items;
} tri_grid;

static void bin_range(const tri_grid* g, bk_aabb b, int lo[3], int hi[3]) {
  const double bmin[3] = {b.min.x, b.min.y, b.min.z}, bmax[3] = {b.max.x, b.max.y, b.max.z};
  const double gmin[3] = {g->box.min.x, g->box.min.y, g->box.min.z},
               size[3] = {g->cell.x, g->cell.y, g->cell.z};
  for (int a = 0; a < 3; ++a) {
    double l = floor((bmin[a] - gmin[a]) / size[a]), h = floor((bmax[a] - gmin[a]) / size[a]);
    lo[a] = (int)fmax(fmin(l, g->n[a] - 1), 0);
    hi[a] = (int)fmax(fmin(h, g->n[a] - 1), 0);
  }
}

static bk_aabb tri_bounds(const bk_mesh* m, uint32_t t) {
  bk_vec3 p = m->positions[bk_mesh_tri_position(m, t, 0)];
  bk_aabb b = {p, p};
  for (int k = 1; k < 3; ++k) {
    p = m->positions[bk_mesh_tri_position(m, t, k)];
    b.min = bk_v3_min(b.min, p);
    b.max = bk_v3_max(b.max, p);
  }
  return b;
}

static void tri_grid_build(tri_grid* g, const bk_mesh* m) {
  g->box = bk_mesh_bounds(m);
  bk_vec3 size = bk_v3_sub(g->box.max, g->box.min);
  double per =
      bk_cbrt(fmax(size.x * size.y * size.z, 1e-300) * 4.0 / (m->triangle_count ? m->triangle_count : 1));
  g->n[0] = (int)fmin(fmax(ceil(size.x / per), 1), 256);
  g->n[1] = (int)fmin(fmax(ceil(size.y / per), 1), 256);
  g->n[2] = (int)fmin(fmax(ceil(size.z / per), 1), 256);
  g->cell =
      bk_v3(fmax(size.x / g->n[0], 1e-300), fmax(size.y / g->n[1], 1e-300), fmax(size.z / g->n[2], 1e-300));
  size_t bins = (size_t)g->n[0] * g->n[1] * g->n[2];
  g->start = bk_calloc(bins + 1, sizeof(uint32_t));
  for (int pass = 0; pass < 2; ++pass) {
    uint32_t* fill = NULL;
    if (pass == 1) {
      for (size_t b = 0; b < bins; ++b)
        g->start[b + 1] += g->start[b];
      g->items = bk_alloc(sizeof(uint32_t) * (g->start[bins] ? g->start[bins] : 1));
      fill = bk_alloc(sizeof(uint32_t) * bins);
      memcpy(fill, g->start, sizeof(uint32_t) * bins);
    }
    for (uint32_t t = 0; t < m->triangle_count; ++t) {
      int lo[3], hi[3];
      bin_range(g, tri_bounds(m, t), lo, hi);
      for (int z = lo[2]; z <= hi[2]; ++z)
        for (int y = lo[1]; y <= hi[1]; ++y)
          for (int x = lo[0]; x <= hi[0]; ++x) {
            size_t b = ((size_t)z * g->n[1] + y) * g->n[0] + x;
            if (pass == 0)
              g->start[b + 1]++;
            else
              g->items[fill[b]++] = t;
          }
    }
    bk_free(fill);
  }
}

// Triangles whose bins meet `box`, each once, in increasing order.
static uint32_t tri_grid_query(const tri_grid* g, bk_aabb box, uint32_t* stamp, uint32_t mark, uint32_t** out,
                               uint32_t* capacity) {
  int lo[3], hi[3];
  bin_range(g, box, lo, hi);
  uint32_t count = 0;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        size_t b = ((size_t)z * g->n[1] + y) * g->n[0] + x;
        for (uint32_t k = g->start[b]; k < g->start[b + 1]; ++k) {
          uint32_t t = g->items[k];
          if (stamp[t] == mark) continue;
          stamp[t] = mark;
          if (count == *capacity) {
            *capacity = bk_grow_capacity(*capacity, count + 1);
            *out = bk_realloc(*out, sizeof(uint32_t) * *capacity);
          }
          (*out)[count++] = t;
        }
      }
  return count;
}

static int compare_u32(const void* pa, const void* pb) {
  uint32_t a = *(const uint32_t*)pa, b = *(const uint32_t*)pb;
  return a < b ? -1 : (a > b);
}

static bk_aabb polytope_bounds(const bk_cell_complex* cx, const bk_cell_polytope* p) {
  bk_aabb b = {cx->points[p->loop[0]], cx->points[p->loop[0]]};
  for (uint32_t i = 1; i < p->loop_count; ++i) {
    b.min = bk_v3_min(b.min, cx->points[p->loop[i]]);
    b.max = bk_v3_max(b.max, cx->points[p->loop[i]]);
  }
  return b;
}

// ---------------------------------------------------------------- cells on every core

// Cells are independent once the seeds are known: each worker builds the
// polytopes and surfaces of the cells it takes into a vertex table of its
// own (a vertex's coordinates follow from its name, so every table agrees
// on them). The tables are then merged in cell order, so the vertex numbers
// and everything after them are the same for any number of threads.
typedef struct cell_worker {
  const bk_mesh* m;
  const bk_fracture_def* d;
  bk_cell_build* b;
  const bk_seed_grid* grid;
  const tri_grid* tg;
  double spacing, whole;
  uint32_t index;
  uint32_t* owner;
  atomic_uint* next;
  atomic_bool* cancelled;
  bk_cell_complex cx;
  uint32_t failed_cell; // the lowest cell that degenerated, or UINT32_MAX
} cell_worker;

static void* cell_work(void* arg) {
  cell_worker* w = arg;
  bk_cell_build* b = w->b;
  bk_cell_builder* builder = bk_cell_builder_create();
  bk_seed_near near = {0};
  uint32_t *tris = NULL, tri_capacity = 0;
  uint32_t* stamp = bk_alloc(sizeof(uint32_t) * (w->m->triangle_count ? w->m->triangle_count : 1));
  memset(stamp, 0xff, sizeof(uint32_t) * w->m->triangle_count);
  uint32_t done = 0;
  for (;;) {
    uint32_t c = atomic_fetch_add(w->next, 1u);
    if (c >= b->cells || atomic_load(w->cancelled)) break;
    w->owner[c] = w->index;
    bool ok = true;
    // Start from the local spacing: seeds of the radial and clustered
    // patterns are far denser in places than on average.
    double local = bk_seed_grid_spacing(w->grid, c);
    bk_cell_polytope_begin(builder, &w->cx, c);
    // A wider list would start with the seeds of the narrower one: only the
    // seeds beyond it are listed, and the clipping goes on with them.
    double inner = -1.0;
    for (double radius = 2.5 * (local < w->spacing ? local : w->spacing);;) {
      uint32_t count = bk_seed_grid_near(w->grid, c, inner, radius, &near);
      if (!bk_cell_polytope_clip(builder, &w->cx, near.seeds, count)) {
        ok = false;
        break;
      }
      // Every seed that could still cut the cell must have been in the list.
      double reach = bk_cell_builder_reach(builder, &w->cx);
      if (2.0 * reach <= radius || radius > 2.0 * w->whole) break;
      inner = radius;
      radius = 2.0 * reach * 1.0001;
    }
    if (!ok) {
      if (c < w->failed_cell) w->failed_cell = c;
      bk_cell_polytope_free(&b->polytopes[c]);
      continue;
    }
    bk_cell_polytope_store(builder, &w->cx, &b->polytopes[c]);
    uint32_t count =
        tri_grid_query(w->tg, polytope_bounds(&w->cx, &b->polytopes[c]), stamp, c, &tris, &tri_capacity);
    if (count) bk_sort(tris, count, sizeof(uint32_t), compare_u32);
    bk_cell_clip_surface(&w->cx, c, &b->polytopes[c], tris, count, &b->surfaces[c]);
    // Only the calling thread reports, as bk_fracture_def.progress promises.
    if (w->index == 0 && w->d->progress && (++done & 31) == 0 &&
        !w->d->progress(w->d->progress_user, c / 2, b->cells))
      atomic_store(w->cancelled, true);
  }
  bk_seed_near_free(&near);
  bk_free(tris);
  bk_free(stamp);
  bk_cell_builder_destroy(builder);
  return NULL;
}

// Renumbers one worker's vertex into the shared table.
static uint32_t merged(bk_cell_complex* cx, cell_worker* w, uint32_t* remap, uint32_t v) {
  if (remap[v] == UINT32_MAX) remap[v] = bk_cell_vertex_at(cx, &w->cx.keys[v], w->cx.points[v]);
  return remap[v];
}

static bool run_cells(const bk_mesh* m, const bk_fracture_def* d, bk_cell_build* b, bk_error* err) {
  bk_seed_grid* grid = bk_seed_grid_create(b->seeds, b->cells, b->cx.box);
  tri_grid tg = {0};
  tri_grid_build(&tg, m);
  bk_vec3 size = bk_v3_sub(b->cx.box.max, b->cx.box.min);
  b->polytopes = bk_calloc(b->cells, sizeof(bk_cell_polytope));
  b->surfaces = bk_calloc(b->cells, sizeof(bk_cell_surface));
  uint32_t threads = bk_fracture_thread_count(d, b->cells, 16);
  cell_worker* workers = bk_calloc(threads, sizeof(cell_worker));
  uint32_t* owner = bk_alloc(sizeof(uint32_t) * b->cells);
  atomic_uint next = 0;
  atomic_bool cancelled = false;
  for (uint32_t t = 0; t < threads; ++t) {
    cell_worker* w = &workers[t];
    *w = (cell_worker){.m = m,
                       .d = d,
                       .b = b,
                       .grid = grid,
                       .tg = &tg,
                       .spacing = bk_cbrt(size.x * size.y * size.z / b->cells),
                       .whole = bk_v3_length(size),
                       .index = t,
                       .owner = owner,
                       .next = &next,
                       .cancelled = &cancelled,
                       .failed_cell = UINT32_MAX};
    bk_cell_complex_init(&w->cx, m, b->seeds, b->cells);
    w->cx.planar_axis = b->cx.planar_axis;
  }
  bk_fracture_run_jobs(cell_work, workers, sizeof *workers, threads);
  uint32_t failed = UINT32_MAX;
  for (uint32_t t = 0; t < threads; ++t)
    failed = workers[t].failed_cell < failed ? workers[t].failed_cell : failed;
  bool ok = true;
  if (atomic_load(&cancelled))
    ok = bk_error_set(err, "fracture cancelled");
  else if (failed != UINT32_MAX)
    ok = bk_error_set(err, "fracture: the cell of seed %u degenerated (seeds too close together?)", failed);
  // Merge the workers' tables in cell order.
  uint32_t** remap = bk_calloc(threads, sizeof(uint32_t*));
  for (uint32_t t = 0; t < threads && ok; ++t) {
    remap[t] = bk_alloc(sizeof(uint32_t) * (workers[t].cx.count ? workers[t].cx.count : 1));
    memset(remap[t], 0xff, sizeof(uint32_t) * workers[t].cx.count);
  }
  for (uint32_t c = 0; c < b->cells && ok; ++c) {
    cell_worker* w = &workers[owner[c]];
    bk_cell_polytope* p = &b->polytopes[c];
    for (uint32_t i = 0; i < p->loop_count; ++i)
      p->loop[i] = merged(&b->cx, w, remap[owner[c]], p->loop[i]);
    bk_cell_surface* s = &b->surfaces[c];
    for (uint32_t i = 0; i < s->vertex_count; ++i)
      s->vertices[i] = merged(&b->cx, w, remap[owner[c]], s->vertices[i]);
  }
  for (uint32_t t = 0; t < threads; ++t) {
    bk_free(remap[t]);
    bk_cell_complex_free(&workers[t].cx);
  }
  bk_free(remap);
  bk_free(workers);
  bk_free(owner);
  bk_free(tg.start);
  bk_free(tg.items);
  bk_seed_grid_destroy(grid);
  return ok;
}

static void free_cells(bk_cell_build* b) {
  for (uint32_t c = 0; b->polytopes && c < b->cells; ++c)
    bk_cell_polytope_free(&b->polytopes[c]);
  for (uint32_t c = 0; b->surfaces && c < b->cells; ++c)
    bk_cell_surface_free(&b->surfaces[c]);
  bk_free(b->polytopes);
  bk_free(b->surfaces);
  b->polytopes = NULL;
  b->surfaces = NULL;
}

bool bk_cell_complex_run(const bk_mesh* m, const bk_fracture_def* d, bk_tree_frame frame, uint32_t attempt,
                         bk_cell_build* b, bk_error* err) {
  memset(b, 0, sizeof *b);
  if (d->pattern == BK_PATTERN_CUTOUT)
    b->cells = bk_cutout_seeds(m, d, &b->seeds, &b->cell_label, err);
  else
    b->cells =
        bk_cell_seeds(m, d, frame.origin, frame.exponent, &b->seeds, &b->cluster_of, &b->cell_label, err);
  if (b->cells == 0) return false;
  if (attempt) {
    bk_aabb box = bk_mesh_bounds(m);
    bk_vec3 size = bk_v3_sub(box.max, box.min);
    double step = 1e-5 * bk_cbrt(fmax(size.x * size.y * size.z, 1e-300) / b->cells);
    bk_rng rng = bk_rng_seed(d->seed, 0x6a697474u + attempt);
    for (uint32_t i = 0; i < b->cells; ++i)
      b->seeds[i] = bk_v3_add(b->seeds[i], bk_v3_scale(bk_rng_direction(&rng), step));
  }
  bk_cell_complex_init(&b->cx, m, b->seeds, b->cells);
  // Cut-out seeds lie in one plane across the map's axis: only distances
  // within that plane decide which seeds can cut a cell (its prism may be
  // far longer than wide).
  if (d->pattern == BK_PATTERN_CUTOUT) b->cx.planar_axis = (int)d->cutout_axis;
  if (!run_cells(m, d, b, err)) return false;
  // Only the last try joins the cells of a face that cannot be made: the
  // earlier ones fail and move the seeds, which takes a rounding failure
  // apart and keeps every piece.
  if (!bk_cell_build_faces(&b->cx, b->polytopes, b->surfaces, b->cells,
                           bk_fracture_thread_count(d, b->cells, 64), attempt + 1 >= BK_CELL_ATTEMPTS,
                           &b->faces, err))
    return false;
  if (d->noise_amplitude > 0.0)
    bk_cell_faces_add_noise(&b->cx, &b->faces, ldexp(d->noise_amplitude, -frame.exponent),
                            ldexp(d->noise_frequency, frame.exponent), d->seed);
  // The map's regions or the caller's points set the count, never above one
  // piece per cell: a cell that a concave source cuts into several solids
  // beyond that joins a neighbour, so a map or a point file can never ask
  // for more pieces than its samples or points.
  uint32_t target = d->pattern == BK_PATTERN_CUTOUT || d->seed_points ? b->cells : d->pieces;
  if (!bk_cell_group(b, target, b->cell_label)) return false;
  // The triangles are in b->parts now: the cells' polytopes and surfaces go
  // before the nodes' meshes are made, which lowers the peak.
  free_cells(b);
  return true;
}

void bk_cell_build_free(bk_cell_build* b) {
  free_cells(b);
  bk_cell_faces_free(&b->faces);
  bk_cell_parts* p = &b->parts;
  bk_free(p->tris);
  bk_free(p->cell_start);
  bk_free(p->tri_atom);
  bk_free(p->twin);
  bk_free(p->atoms);
  bk_free(p->contacts_a);
  bk_free(p->contacts_b);
  bk_free(p->contact_area);
  bk_free(p->atom_leaf);
  bk_cell_complex_free(&b->cx);
  bk_free(b->seeds);
  bk_free(b->cluster_of);
  bk_free(b->cell_label);
  memset(b, 0, sizeof *b);
}
