// Cut-out seeds: the fracture map's regions (4-connected pixels below 128,
// the lines between them handed to the nearest region) are sampled on a
// jittered grid in the plane through the source's middle across the map's
// axis. Seeds in one plane make Voronoi cells that are prisms along the
// axis, so every region becomes the map's shape extruded through the
// source; cells of one region share its label and become one piece.
#include <stdlib.h>
#include <string.h>

#include "cell_stages.h"

/// About this many seeds sample the map (the pieces' outlines follow the
/// map to about one sample spacing), whatever its shape.
#define CUTOUT_SAMPLES 3000.0

/// Below this many samples across, a map is thin: its long side takes the
/// rest of the samples, so that a thin map draws as many as a square one.
#define CUTOUT_THIN_SAMPLES 8u

uint32_t bk_cutout_grid(uint32_t w, uint32_t h, uint32_t* columns, uint32_t* rows) {
  // Square samples of the map's pixels, one pixel at the finest.
  double step = fmax(sqrt((double)w * h / CUTOUT_SAMPLES), 1.0);
  double across = floor(w / step), down = floor(h / step);
  // A side thinner than a few steps would leave the other side step-spaced
  // too: 2 x 8,388,608 pixels would draw 112,173 samples, not 3,000.
  // There the long side takes whatever the thin side leaves of the budget.
  // (Rounded there: 3 x 1,100 pixels take 3 x 1,000 samples, not 2 x 1,100.)
  if (across < CUTOUT_THIN_SAMPLES && across <= down) {
    across = fmax(floor(w / step + 0.5), 1.0);
    down = fmin(floor(CUTOUT_SAMPLES / across), h);
  } else if (down < CUTOUT_THIN_SAMPLES) {
    down = fmax(floor(h / step + 0.5), 1.0);
    across = fmin(floor(CUTOUT_SAMPLES / down), w);
  }
  *columns = (uint32_t)across;
  *rows = (uint32_t)down;
  return *columns * *rows;
}

// Breadth first from the queued pixels: each gives its label to its
// unlabelled 4-neighbours (only to pixels below 128 when `open_only`).
static void grow(const uint8_t* px, uint32_t w, uint32_t h, bool open_only, uint32_t* label, uint32_t* queue,
                 size_t tail) {
  static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
  for (size_t head = 0; head < tail;) {
    uint32_t at = queue[head++], x = at % w, y = at / w;
    for (int k = 0; k < 4; ++k) {
      int nx = (int)x + dx[k], ny = (int)y + dy[k];
      if (nx < 0 || ny < 0 || nx >= (int)w || ny >= (int)h) continue;
      uint32_t o = (uint32_t)ny * w + (uint32_t)nx;
      if (label[o] != UINT32_MAX || (open_only && px[o] >= 128)) continue;
      label[o] = label[at];
      queue[tail++] = o;
    }
  }
}

// Labels every pixel with its region: flood fill of the non-line pixels,
// then the line pixels from their nearest labelled neighbour (breadth
// first from every region at once, so each takes the region it is closest
// to). Returns the count.
static uint32_t label_regions(const uint8_t* px, uint32_t w, uint32_t h, uint32_t* label) {
  size_t n = (size_t)w * h;
  uint32_t* queue = bk_alloc(sizeof(uint32_t) * n);
  for (size_t i = 0; i < n; ++i)
    label[i] = UINT32_MAX;
  uint32_t regions = 0;
  for (size_t start = 0; start < n; ++start) {
    if (px[start] >= 128 || label[start] != UINT32_MAX) continue;
    label[start] = regions++;
    queue[0] = (uint32_t)start;
    grow(px, w, h, true, label, queue, 1);
  }
  size_t tail = 0;
  for (size_t i = 0; i < n; ++i)
    if (label[i] != UINT32_MAX) queue[tail++] = (uint32_t)i;
  grow(px, w, h, false, label, queue, tail);
  bk_free(queue);
  return regions;
}

uint32_t bk_cutout_regions(const uint8_t* pixels, uint32_t w, uint32_t h) {
  uint32_t* label = bk_alloc(sizeof(uint32_t) * (size_t)w * h);
  uint32_t regions = label_regions(pixels, w, h, label);
  bk_free(label);
  return regions;
}

uint32_t bk_cutout_seeds(const bk_mesh* m, const bk_fracture_def* d, bk_vec3** seeds, uint32_t** labels,
                         bk_error* err) {
  *seeds = NULL;
  *labels = NULL;
  uint32_t w = d->cutout_width, h = d->cutout_height;
  uint32_t* label = bk_alloc(sizeof(uint32_t) * (size_t)w * h);
  uint32_t regions = label_regions(d->cutout_pixels, w, h, label);
  if (regions == 0) {
    bk_free(label);
    return bk_error_set(err, "fracture: the cutout map (%u x %u) is all lines: it encloses no region", w, h),
           0;
  }
  // The map's right and up directions in the source, by axis (see
  // bk_fracture_def.cutout_axis), and the plane the seeds lie in.
  bk_aabb box = bk_mesh_bounds(m);
  const double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
  uint32_t axis = d->cutout_axis;
  int right = axis == 0 ? 2 : 0, up = axis == 1 ? 2 : 1;
  bool right_flipped = axis == 0, up_flipped = axis == 1;
  uint32_t columns = 0, rows = 0;
  bk_cutout_grid(w, h, &columns, &rows);
  bk_rng rng = bk_rng_seed(d->seed, 0x63757470u);
  bk_vec3* out = bk_alloc(sizeof(bk_vec3) * columns * rows);
  uint32_t* out_label = bk_alloc(sizeof(uint32_t) * columns * rows);
  uint32_t count = 0;
  for (uint32_t r = 0; r < rows; ++r)
    for (uint32_t c = 0; c < columns; ++c) {
      // A jittered sample: a regular grid would put four seeds on one
      // circle everywhere, which no Voronoi diagram survives in rounding.
      double u = (c + 0.1 + 0.8 * bk_rng_unit(&rng)) / columns,
             v = (r + 0.1 + 0.8 * bk_rng_unit(&rng)) / rows;
      uint32_t px = (uint32_t)fmin(u * w, w - 1), py = (uint32_t)fmin(v * h, h - 1);
      double p[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
      p[right] =
          right_flipped ? hi[right] - u * (hi[right] - lo[right]) : lo[right] + u * (hi[right] - lo[right]);
      // Row 0 is the map's top.
      p[up] = up_flipped ? lo[up] + v * (hi[up] - lo[up]) : hi[up] - v * (hi[up] - lo[up]);
      out[count] = bk_v3(p[0], p[1], p[2]);
      out_label[count++] = label[(size_t)py * w + px];
    }
  bk_free(label);
  *seeds = out;
  *labels = out_label;
  return count;
}
