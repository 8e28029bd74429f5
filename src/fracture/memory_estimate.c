// How much memory a fracture will need, known before it starts, so that a
// request that cannot fit is refused up front instead of exhausting the
// machine half-way (a cube into 1,048,576 pieces peaks at 8.3 GB).
//
// The model was fitted (least squares on relative error) to the peak resident
// memory of `breakables fracture --json` (Release build, x86-64, glibc) over 7
// built-in meshes (12 to 3,674 triangles) and icospheres of 5,120 to 327,680
// triangles, from 1 to 262,144 pieces (133 runs). With T source triangles,
// N pieces and L = log2 N, the peak is the larger of
//   - the first cut's working set (N > 1): slicing, capping and checking a
//     copy of the whole source, 660 bytes per source triangle;
//   - the finished tree, the sum of
//       a fixed part: the process itself;
//       T: the source mesh and its loading;
//       T L: every level of the tree holds the whole source surface again;
//       N: each fragment and its parent node (about 14 triangles each, with
//          their caps, bounds, moments and bonds), 8.4 KB per piece;
//       sqrt(T) N^(1/3): curved surfaces are cut into more triangles as the
//          pieces along them grow in number.
// The fit is within -10%..+13% of every measurement. The estimate is the fit
// times 1.25, so it exceeds every measured peak (by 12% to 41%) and leaves
// room for changes to the fracture core.
#include <math.h>

#include "bk_fracture.h"

// Margins over the fits, so that the estimates err on the high side.
#define BUILD_MARGIN 1.25
#define FILE_MARGIN 1.1

static double pieces_of(const bk_fracture_def* desc) {
  return desc && desc->pieces ? (double)desc->pieces : (double)bk_default_fracture_def().pieces;
}

static uint64_t to_bytes(double bytes) {
  return bytes >= 18446744073709551615.0 ? UINT64_MAX : (uint64_t)ceil(bytes);
}

uint64_t bk_mesh_tree_estimate_bytes(const bk_mesh* source, const bk_fracture_def* desc) {
  double t = source ? (double)source->triangle_count : 0.0, n = pieces_of(desc);
  double levels = log2(n);
  double first_cut = n > 1.0 ? 5.75e6 + 660.0 * t : 0.0;
  double tree = 5.75e6 + 190.0 * t + 72.0 * t * levels + 8420.0 * n + 16100.0 * sqrt(t) * cbrt(n);
  return to_bytes(BUILD_MARGIN * fmax(first_cut, tree));
}

// Fitted the same way to the sizes of 13 saved trees (4.3 KB per piece); the
// rounded fit is 4% to 15% above each. Saving holds the whole file in memory
// before writing it.
uint64_t bk_mesh_tree_estimate_file_bytes(const bk_mesh* source, const bk_fracture_def* desc) {
  double t = source ? (double)source->triangle_count : 0.0, n = pieces_of(desc);
  double levels = log2(n);
  double fit = 40.0 * t + 48.0 * t * levels + 4300.0 * n + 9000.0 * sqrt(t) * cbrt(n);
  return to_bytes(FILE_MARGIN * fit);
}
