// How much memory a fracture will need, known before it starts, so that a
// request that cannot fit is refused up front instead of exhausting the
// machine half-way (a cube into 1,048,576 pieces peaks at 6.0 GB).
//
// The models are fitted (least squares on relative error) to the peak
// resident memory of `breakables fracture` (Release build, x86-64, glibc).
// With T source triangles, N pieces and L = log2 N:
//
// Planes and brick, fitted over 7 built-in meshes (12 to 3,674 triangles)
// and spheres of 5,120 to 327,680 triangles, from 2 to 65,536 pieces (75
// runs; a cube into 262,144 and 1,048,576 pieces checked). The peak is the
// larger of
//   - the first cut's working set (N > 1): slicing, capping and checking a
//     copy of the whole source, 414 bytes per source triangle over a fixed
//     11.1 MB;
//   - the finished tree, the sum of
//       a fixed part: the process itself (10.8 MB; 10.3 MB measured for the
//         command line tool with the libraries it links);
//       T: the source mesh and its loading;
//       T L: every level of the tree holds the whole source surface again;
//       N: each fragment and its parent node (about 14 triangles each, held
//          in arrays of exactly their size, with their caps, bounds, moments
//          and bonds), 5.85 KB per piece;
//       sqrt(T) N^(1/3): curved surfaces are cut into more triangles as the
//          pieces along them grow in number.
// The cell patterns (voronoi, clustered, radial, cut-out) hold every cell's
// surface and cut faces and group the cells into a tree whose every level
// holds its cells' triangles again: 4.4 KB per piece and level. Fitted over 6
// built-in meshes and spheres of 20,000 and 80,000 triangles at 2 to 4,096
// pieces (70 runs), within -9%..+13% of each.
//
// Noise (noise_amplitude > 0) adds the triangles its meshers make, counted
// as they make them, so the estimate follows the frequency as they do:
//   - planes: each cap gets the nodes of a grid BK_CAP_NOISE_SPACING waves
//     apart (at most BK_CAP_NOISE_MAX_NODES), and every tree level below the
//     cut holds them again; besides, noisy caps are never re-triangulated,
//     so later cuts leave more triangles on them (26.5 KB per piece);
//   - cell patterns: cut faces are refined by up to BK_CELL_NOISE_MAX_LEVELS
//     levels within the mesher's budget.
// Cut-out builds as many cells as its map's samples (about 3,000 whatever
// the map's shape, bk_cutout_grid), so they stand for N, and its map adds a
// byte a pixel, or 9 while its seeds are drawn (region labels, fill queue).
// The estimate, the fit times 1.25, is 1.19 to 1.32 times the peak for
// planes and brick flat (the runs above, and brick on the wall) and 0.92 to
// 1.50 times with noise (the cube and the bunny at 64, 1,024 and 4,096
// pieces, frequencies 2, 8 and 24). Measured on the cube, bunny, torus,
// eggshell, wall, pillar and the two spheres at 2 to 4,096 pieces, flat and
// with noise at frequencies 2, 8 and 24 (peaks of 11 to 860 MiB), it is
// 1.15 to 1.42 times the peak for the cell patterns flat and 0.70 to 2.04
// times noisy (on the cube and the bunny 0.91 to 1.94): how many levels the
// refinement budget lets through makes their peak jump by up to 2x between
// nearby requests, and the estimate stays between the two outcomes.
#include <math.h>

#include "bk_fracture.h"
#include "cap.h"
#include "cell_complex.h"

// Margins over the fits, so that the estimates err on the high side.
#define BUILD_MARGIN 1.25
#define FILE_MARGIN 1.1

// A cut through the centroid of a piece of volume v has about this times
// v^(2/3) of area (a unit cube's cuts: 1 to 1.4).
#define CAP_AREA_PER_VOLUME 1.2

static bool cutout_map(const bk_fracture_def* desc) {
  return desc && desc->pattern == BK_PATTERN_CUTOUT && desc->cutout_width && desc->cutout_height;
}

// The cells a cut-out builds: the map's samples.
static double cutout_cells(const bk_fracture_def* desc) {
  uint32_t columns = 0, rows = 0;
  return fmax((double)bk_cutout_grid(desc->cutout_width, desc->cutout_height, &columns, &rows), 1.0);
}

// The pieces the build makes, which the tree's memory follows: the pieces
// asked for, one per seed point, or for a map at most one per region and
// one per sample (--pieces does not count; without the pixels, the samples).
static double pieces_of(const bk_fracture_def* desc) {
  if (desc && desc->pattern == BK_PATTERN_VORONOI && desc->seed_points) // one cell per point inside
    return desc->seed_point_count ? (double)desc->seed_point_count : 1.0;
  if (cutout_map(desc)) {
    double cells = cutout_cells(desc);
    if (!desc->cutout_pixels) return cells;
    // A region the source meets in two places (a ring, a hollow shell seen
    // through) is two pieces.
    double regions = bk_cutout_regions(desc->cutout_pixels, desc->cutout_width, desc->cutout_height);
    return fmax(fmin(2.0 * regions, cells), 1.0);
  }
  return desc && desc->pieces ? (double)desc->pieces : (double)bk_default_fracture_def().pieces;
}

// The fracture map's pixels: one byte each (grey, the caller's) through the
// build.
static double map_pixels(const bk_fracture_def* desc) {
  return cutout_map(desc) ? (double)desc->cutout_width * (double)desc->cutout_height : 0.0;
}

static bool cell_pattern(const bk_fracture_def* desc) {
  return desc && desc->pattern != BK_PATTERN_PLANES && desc->pattern != BK_PATTERN_BRICK;
}

// Noise waves per source unit, or 0 when the cut faces stay flat (brick
// refuses noise).
static double noise_frequency_of(const bk_fracture_def* desc) {
  if (!desc || desc->pattern == BK_PATTERN_BRICK || !(desc->noise_amplitude > 0.0)) return 0.0;
  return desc->noise_frequency > 0.0 ? desc->noise_frequency : 0.0;
}

static uint64_t to_bytes(double bytes) {
  return bytes >= 18446744073709551615.0 ? UINT64_MAX : (uint64_t)ceil(bytes);
}

// The points the noisy caps of a planes fracture get, each counted once for
// every tree level below its cut (cap_noise.c). The k-th level's cuts halve
// pieces of volume / 2^k; a cap gets the grid nodes at least half a spacing
// inside its border.
static double planes_noise_point_levels(double volume, double n, double frequency) {
  double levels = bk_log2(n), sum = 0.0;
  double most_across = sqrt(BK_CAP_NOISE_MAX_NODES);
  for (int k = 0; ldexp(1.0, k) < n; ++k) {
    double pieces = ldexp(1.0, k);
    double cuts = fmin(pieces, n - pieces);
    double area = CAP_AREA_PER_VOLUME * bk_pow(volume / pieces, 2.0 / 3.0);
    double across = fmin(sqrt(area) * frequency / BK_CAP_NOISE_SPACING, most_across);
    double inside = fmax(across - 1.0, 0.0);
    sum += cuts * inside * inside * (levels - k);
  }
  return sum;
}

// Bytes noisy caps add to a planes tree: 367 per point and level, and the
// cut faces left whole (26.5 KB per piece).
static double planes_noise_bytes(double volume, double n, double frequency) {
  if (!(n > 1.0) || !(frequency > 0.0) || !(volume > 0.0)) return 0.0;
  return 26500.0 * n + 367.0 * planes_noise_point_levels(volume, n, frequency);
}

// Cut-face triangles of a cell pattern before noise: about 24 per cell, and
// more where the faces meet a finely triangulated surface.
static double cell_face_triangles(double t, double n) { return 24.0 * n + 4.5 * sqrt(t) * bk_cbrt(n); }

// The triangles noise adds to the cut faces of a cell pattern
// (cell_noise.c): a face whose longest edge is e gets
// ceil(bk_log2(2 frequency e)) levels, at most BK_CELL_NOISE_MAX_LEVELS, within
// the budget.
static double cell_noise_triangles(double t, double volume, double n, double frequency) {
  if (!(n > 1.0) || !(frequency > 0.0) || !(volume > 0.0)) return 0.0;
  // Shares of the face triangles whose faces' longest edge is about x times
  // the cells' size (volume / N)^(1/3), as measured on all six meshes.
  static const double shares[][2] = {{0.4, 0.15}, {0.8, 0.30}, {1.2, 0.35}, {1.6, 0.17}, {2.2, 0.03}};
  // Triangles a face triangle becomes at each level: less than 4^levels,
  // since the border edges are never split (measured).
  static const double growth[BK_CELL_NOISE_MAX_LEVELS + 1] = {1.0, 2.5, 9.0, 35.0};
  double faces = cell_face_triangles(t, n), cell = bk_cbrt(volume / n), ratio = 0.0;
  for (size_t i = 0; i < sizeof shares / sizeof *shares; ++i) {
    double wanted = ceil(bk_log2(fmax(2.0 * frequency * shares[i][0] * cell, 1.0)));
    int levels = (int)fmin(wanted, BK_CELL_NOISE_MAX_LEVELS);
    ratio += shares[i][1] * growth[levels];
  }
  // Past the budget the mesher takes fewer levels for every face, which
  // leaves 2.3 to 4.5 times the triangles depending on which side of the
  // budget the faces fall; 3 times is within 2x of either. On few faces the
  // budget allows 100,000 more: 7,000 to 53,000 more were measured at 64
  // pieces.
  double most = fmax((0.38 * BK_CELL_NOISE_BUDGET - 1.0) * faces, 0.25 * BK_CELL_NOISE_EXTRA);
  return fmin(faces * (ratio - 1.0), most);
}

// Each triangle noise adds to a cell pattern's cut faces is held by both
// cells, by the tree's inner nodes up to where the two are grouped, and by
// the build's working copies.
static double cell_noise_bytes_per_triangle(double levels) { return 300.0 + 120.0 * levels; }

uint64_t bk_mesh_tree_estimate_bytes(const bk_mesh* source, const bk_fracture_def* desc) {
  double t = source ? (double)source->triangle_count : 0.0, n = pieces_of(desc);
  double levels = bk_log2(n), frequency = noise_frequency_of(desc);
  double volume = source && frequency > 0.0 ? bk_mesh_volume(source) : 0.0;
  double first_cut = n > 1.0 ? (cell_pattern(desc) ? 5.75e6 + 660.0 * t : 11.1e6 + 414.0 * t) : 0.0;
  double tree = 0.0;
  if (cell_pattern(desc))
    tree = 11.75e6 + 235.0 * t + 4440.0 * n * levels + 24300.0 * sqrt(t) * bk_cbrt(n) + 160.0 * t * levels +
           cell_noise_bytes_per_triangle(levels) * cell_noise_triangles(t, volume, n, frequency);
  else
    tree = 10.8e6 + 270.0 * t + 63.0 * t * levels + 5850.0 * n + 9100.0 * sqrt(t) * bk_cbrt(n) +
           planes_noise_bytes(volume, n, frequency);
  // A map's cells are built all at once whatever the regions they make:
  // prisms through the whole source, each with its faces and the source's
  // surface it holds (8 KB a cell, and more the finer the surface), and
  // the tree of the pieces is made while they are held. The estimate is
  // 1.12 to 2.2 times the peak with assets/maps/cracks.png (2,916 cells, 28
  // to 55 pieces) and a 64 x 64 grid of 256 regions on the cube, eggshell,
  // torus and bunny, and with 2 x 8,388,608 pixels of 4,194,304 regions
  // (3,000 pieces) on the cube, torus and bunny.
  if (cutout_map(desc)) tree += 5.75e6 + 660.0 * t + (8000.0 + 200.0 * sqrt(t)) * cutout_cells(desc);
  // The seeds of a map are drawn from a region label and a fill-queue entry
  // per pixel, freed before the cells are built: the larger of that and the
  // build, with the pixels throughout.
  double pixels = map_pixels(desc), labels = pixels > 0.0 ? 11.75e6 + 8.0 * pixels : 0.0;
  return to_bytes(BUILD_MARGIN * (fmax(fmax(first_cut, tree), labels) + pixels));
}

// Fitted the same way to the sizes of saved trees: planes to 13 (4.3 KB per
// piece; the rounded fit is 4% to 15% above each), the cell patterns to 68
// (3.4 KB per piece and level; -28% to +66% of each, the most above on the
// smallest files). Noise adds to the file what it adds to the tree in
// memory less the build's working copies: 0.67 of it for planes, 0.85 for
// the cell patterns (the estimates are 0.93 to 1.56 and 0.64 to 1.48 times
// 36 noisy files). Saving holds the whole file in memory before writing it.
uint64_t bk_mesh_tree_estimate_file_bytes(const bk_mesh* source, const bk_fracture_def* desc) {
  double t = source ? (double)source->triangle_count : 0.0, n = pieces_of(desc);
  double levels = bk_log2(n), frequency = noise_frequency_of(desc);
  double volume = source && frequency > 0.0 ? bk_mesh_volume(source) : 0.0;
  double fit = 0.0;
  if (cell_pattern(desc))
    fit = 3400.0 * n * levels + 11500.0 * sqrt(t) * bk_cbrt(n) + 125.0 * t * levels +
          0.85 * cell_noise_bytes_per_triangle(levels) * cell_noise_triangles(t, volume, n, frequency);
  else
    fit = 40.0 * t + 48.0 * t * levels + 4300.0 * n + 9000.0 * sqrt(t) * bk_cbrt(n) +
          0.67 * planes_noise_bytes(volume, n, frequency);
  return to_bytes(FILE_MARGIN * fit);
}
