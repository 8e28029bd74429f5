// A uniform grid over the seeds, for each cell's list of the seeds near it,
// nearest first (the order its polytope is clipped in).
#include <stdlib.h>
#include <string.h>

#include "cell_complex.h"

struct bk_seed_grid {
  const bk_vec3* seeds;
  bk_aabb box;
  int n[3];
  double cell;
  uint32_t* start; // per bin, into order (n0*n1*n2 + 1)
  uint32_t* order;
};

static int bin_coord(const bk_seed_grid* g, double v, double lo, int n) {
  double c = floor((v - lo) / g->cell);
  return c >= 0.0 ? (c < n ? (int)c : n - 1) : 0; // NaN too lands in bin 0
}

bk_seed_grid* bk_seed_grid_create(const bk_vec3* seeds, uint32_t count, bk_aabb box) {
  bk_seed_grid* g = bk_calloc(1, sizeof *g);
  g->seeds = seeds;
  g->box = box;
  bk_vec3 size = bk_v3_sub(box.max, box.min);
  // About two seeds per bin.
  double volume = fmax(size.x * size.y * size.z, 1e-300);
  g->cell = bk_cbrt(volume * 2.0 / (count ? count : 1));
  g->n[0] = (int)fmin(fmax(ceil(size.x / g->cell), 1), 1024);
  g->n[1] = (int)fmin(fmax(ceil(size.y / g->cell), 1), 1024);
  g->n[2] = (int)fmin(fmax(ceil(size.z / g->cell), 1), 1024);
  g->cell = fmax(fmax(size.x / g->n[0], size.y / g->n[1]), size.z / g->n[2]);
  size_t bins = (size_t)g->n[0] * g->n[1] * g->n[2];
  g->start = bk_calloc(bins + 1, sizeof(uint32_t));
  g->order = bk_alloc(sizeof(uint32_t) * (count ? count : 1));
  uint32_t* bin_of = bk_alloc(sizeof(uint32_t) * (count ? count : 1));
  for (uint32_t i = 0; i < count; ++i) {
    int x = bin_coord(g, seeds[i].x, box.min.x, g->n[0]), y = bin_coord(g, seeds[i].y, box.min.y, g->n[1]),
        z = bin_coord(g, seeds[i].z, box.min.z, g->n[2]);
    bin_of[i] = (uint32_t)(((size_t)z * g->n[1] + y) * g->n[0] + x);
    g->start[bin_of[i] + 1]++;
  }
  for (size_t b = 0; b < bins; ++b)
    g->start[b + 1] += g->start[b];
  uint32_t* fill = bk_alloc(sizeof(uint32_t) * bins);
  memcpy(fill, g->start, sizeof(uint32_t) * bins);
  for (uint32_t i = 0; i < count; ++i)
    g->order[fill[bin_of[i]]++] = i;
  bk_free(fill);
  bk_free(bin_of);
  return g;
}

void bk_seed_grid_destroy(bk_seed_grid* g) {
  if (!g) return;
  bk_free(g->start);
  bk_free(g->order);
  bk_free(g);
}

double bk_seed_grid_spacing(const bk_seed_grid* g, uint32_t cell) {
  bk_vec3 p = g->seeds[cell];
  int x = bin_coord(g, p.x, g->box.min.x, g->n[0]), y = bin_coord(g, p.y, g->box.min.y, g->n[1]),
      z = bin_coord(g, p.z, g->box.min.z, g->n[2]);
  // Seeds in the 3 x 3 x 3 bins around: their density gives the spacing here.
  uint32_t count = 0, bins = 0;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        int bx = x + dx, by = y + dy, bz = z + dz;
        if (bx < 0 || by < 0 || bz < 0 || bx >= g->n[0] || by >= g->n[1] || bz >= g->n[2]) continue;
        size_t b = ((size_t)bz * g->n[1] + by) * g->n[0] + bx;
        count += g->start[b + 1] - g->start[b];
        bins++;
      }
  return bk_cbrt(bins * g->cell * g->cell * g->cell / (count ? count : 1));
}

static inline bool near_less(const bk_near_entry* a, const bk_near_entry* b) {
  return a->d < b->d || (a->d == b->d && a->index < b->index);
}

static inline uint64_t distance_bits(double d) {
  uint64_t bits = 0;
  memcpy(&bits, &d, sizeof bits);
  return bits;
}

// Sorts list[0, count) by distance, then id (a total order: one result
// however it is sorted). Long lists (around cells that reach far: the
// cells on the source's surface reach the box) go by radix on the
// distance's bits (a squared distance is never negative, so its bits order
// as integers), then runs of equal distances by id; short ones by merge
// sort over runs of 16 sorted by insertion.
static void sort_near(bk_near_entry* list, bk_near_entry* tmp, uint32_t count) {
  if (count >= 64) {
    uint32_t histogram[8][256] = {{0}};
    for (uint32_t i = 0; i < count; ++i) {
      uint64_t bits = distance_bits(list[i].d);
      for (int digit = 0; digit < 8; ++digit)
        histogram[digit][(bits >> (8 * digit)) & 255]++;
    }
    bk_near_entry *from = list, *to = tmp;
    for (int digit = 0; digit < 8; ++digit) {
      uint32_t* h = histogram[digit];
      if (h[(distance_bits(from[0].d) >> (8 * digit)) & 255] == count) continue; // all share it
      uint32_t sum = 0;
      for (int b = 0; b < 256; ++b) {
        uint32_t n = h[b];
        h[b] = sum;
        sum += n;
      }
      for (uint32_t i = 0; i < count; ++i)
        to[h[(distance_bits(from[i].d) >> (8 * digit)) & 255]++] = from[i];
      bk_near_entry* t = from;
      from = to;
      to = t;
    }
    if (from != list) memcpy(list, from, sizeof(bk_near_entry) * count);
    for (uint32_t i = 1; i < count; ++i) { // equal distances: by id
      bk_near_entry e = list[i];
      uint32_t j = i;
      for (; j > 0 && list[j - 1].d == e.d && list[j - 1].index > e.index; --j)
        list[j] = list[j - 1];
      list[j] = e;
    }
    return;
  }
  const uint32_t run = 16;
  for (uint32_t start = 0; start < count; start += run) {
    uint32_t end = start + run < count ? start + run : count;
    for (uint32_t i = start + 1; i < end; ++i) {
      bk_near_entry e = list[i];
      uint32_t j = i;
      for (; j > start && near_less(&e, &list[j - 1]); --j)
        list[j] = list[j - 1];
      list[j] = e;
    }
  }
  bk_near_entry *from = list, *to = tmp;
  for (uint32_t width = run; width < count; width *= 2) {
    for (uint32_t start = 0; start < count; start += 2 * width) {
      uint32_t mid = start + width < count ? start + width : count;
      uint32_t end = start + 2 * width < count ? start + 2 * width : count;
      uint32_t a = start, b = mid, k = start;
      while (a < mid && b < end)
        to[k++] = near_less(&from[b], &from[a]) ? from[b++] : from[a++];
      while (a < mid)
        to[k++] = from[a++];
      while (b < end)
        to[k++] = from[b++];
    }
    bk_near_entry* t = from;
    from = to;
    to = t;
  }
  if (from != list) memcpy(list, from, sizeof(bk_near_entry) * count);
}

uint32_t bk_seed_grid_near(const bk_seed_grid* g, uint32_t cell, double inner, double radius,
                           bk_seed_near* out) {
  bk_vec3 p = g->seeds[cell];
  int lo[3] = {bin_coord(g, p.x - radius, g->box.min.x, g->n[0]),
               bin_coord(g, p.y - radius, g->box.min.y, g->n[1]),
               bin_coord(g, p.z - radius, g->box.min.z, g->n[2])};
  int hi[3] = {bin_coord(g, p.x + radius, g->box.min.x, g->n[0]),
               bin_coord(g, p.y + radius, g->box.min.y, g->n[1]),
               bin_coord(g, p.z + radius, g->box.min.z, g->n[2])};
  uint32_t count = 0;
  for (int z = lo[2]; z <= hi[2]; ++z)
    for (int y = lo[1]; y <= hi[1]; ++y)
      for (int x = lo[0]; x <= hi[0]; ++x) {
        size_t b = ((size_t)z * g->n[1] + y) * g->n[0] + x;
        for (uint32_t k = g->start[b]; k < g->start[b + 1]; ++k) {
          uint32_t j = g->order[k];
          if (j == cell) continue;
          bk_vec3 e = bk_v3_sub(g->seeds[j], p);
          double d = bk_v3_dot(e, e); // squared: same order
          // The same comparisons for every radius, so a list's seeds are
          // exactly those of the inner list plus those of the shell.
          if (d > radius * radius || (inner >= 0.0 && !(d > inner * inner))) continue;
          if (count == out->capacity) {
            // The scratch lives as long as its thread: it grows, never shrinks.
            out->capacity = bk_grow_capacity(out->capacity, count + 1);
            out->entries = bk_realloc(out->entries, sizeof(bk_near_entry) * 2 * out->capacity);
            out->seeds = bk_realloc(out->seeds, sizeof(uint32_t) * out->capacity);
          }
          out->entries[count++] = (bk_near_entry){d, j};
        }
      }
  if (count > 1) // an empty list may have no buffer yet
    sort_near(out->entries, out->entries + count, count);
  for (uint32_t i = 0; i < count; ++i)
    out->seeds[i] = out->entries[i].index;
  out->count = count;
  return count;
}

void bk_seed_near_free(bk_seed_near* n) {
  bk_free(n->entries);
  bk_free(n->seeds);
  memset(n, 0, sizeof *n);
}
