// The fracture parameters: defaults, the patterns' names, and validation
// that names the wrong field.
#include <string.h>

#include "bk_fracture.h"

bk_fracture_def bk_default_fracture_def(void) {
  return (bk_fracture_def){.pieces = 256,
                           .seed = 3000,
                           .texture_scale = 0.1,
                           .jitter = 0.05,
                           .pattern = BK_PATTERN_PLANES,
                           .clusters = 6,
                           .cluster_border = 0.05,
                           .radial_falloff = 1.0,
                           .brick_size = {0.25, 0.125, 0.0},
                           .brick_offset = 0.5,
                           .cutout_axis = 2,
                           .noise_frequency = 8.0};
}

static const char* const pattern_names[BK_PATTERN_COUNT] = {"planes", "voronoi", "clustered",
                                                            "radial", "brick",   "cutout"};

const char* bk_fracture_pattern_name(bk_fracture_pattern pattern) {
  return (unsigned)pattern < BK_PATTERN_COUNT ? pattern_names[pattern] : "unknown";
}

bool bk_fracture_pattern_from_name(const char* name, bk_fracture_pattern* pattern) {
  for (int i = 0; i < BK_PATTERN_COUNT; ++i)
    if (name && strcmp(name, pattern_names[i]) == 0) {
      *pattern = (bk_fracture_pattern)i;
      return true;
    }
  return false;
}

// The fields of the patterns; each is checked whatever the pattern, so a def
// is valid or not on its own.
static bool validate_pattern(const bk_fracture_def* d, bk_error* err) {
  if ((unsigned)d->pattern >= BK_PATTERN_COUNT)
    return bk_error_set(err, "fracture: pattern = %d is not a pattern (0 to %d)", (int)d->pattern,
                        BK_PATTERN_COUNT - 1);
  // A loaded tree's desc keeps the counts of borrowed arrays, not the arrays.
  if (d->seed_point_count && !d->seed_points && d->pattern != BK_PATTERN_VORONOI)
    return bk_error_set(err, "fracture: seed_points is NULL but seed_point_count is %u", d->seed_point_count);
  if (d->seed_point_count > (1u << 20))
    return bk_error_set(err, "fracture: seed_point_count = %u is too many (at most %u)", d->seed_point_count,
                        1u << 20);
  for (uint32_t i = 0; d->seed_points && i < d->seed_point_count; ++i)
    if (!bk_v3_is_finite(d->seed_points[i]))
      return bk_error_set(err, "fracture: seed_points[%u] is not finite", i);
  if (d->clusters == 0 || d->clusters > (1u << 20))
    return bk_error_set(err, "fracture: clusters must be between 1 and %u (got %u)", 1u << 20, d->clusters);
  if (!isfinite(d->cluster_border) || !(d->cluster_border > 0.0) || d->cluster_border > 1.0)
    return bk_error_set(err, "fracture: cluster_border must be in (0, 1] (got %g)", d->cluster_border);
  if (!bk_v3_is_finite(d->impact)) return bk_error_set(err, "fracture: impact is not finite");
  if (!isfinite(d->radial_falloff) || d->radial_falloff < 0.0 || d->radial_falloff > 1.4)
    return bk_error_set(err, "fracture: radial_falloff must be between 0 and 1.4 (got %g)",
                        d->radial_falloff);
  if (!bk_v3_is_finite(d->brick_size) || !(d->brick_size.x > 0.0) || !(d->brick_size.y > 0.0) ||
      d->brick_size.z < 0.0)
    return bk_error_set(err,
                        "fracture: brick_size must have a positive length and height and a depth >= 0 "
                        "(got %g, %g, %g)",
                        d->brick_size.x, d->brick_size.y, d->brick_size.z);
  if (!bk_v3_is_finite(d->brick_origin)) return bk_error_set(err, "fracture: brick_origin is not finite");
  if (!isfinite(d->brick_offset) || d->brick_offset < 0.0 || d->brick_offset >= 1.0)
    return bk_error_set(err, "fracture: brick_offset must be in [0, 1) (got %g)", d->brick_offset);
  if (d->cutout_axis > 2)
    return bk_error_set(err, "fracture: cutout_axis must be 0, 1 or 2 (got %u)", d->cutout_axis);
  if (d->cutout_pixels) {
    if (d->cutout_width < 2 || d->cutout_height < 2)
      return bk_error_set(err, "fracture: cutout_pixels must be at least 2 x 2 (got %u x %u)",
                          d->cutout_width, d->cutout_height);
    if ((uint64_t)d->cutout_width * d->cutout_height > (1u << 24))
      return bk_error_set(err, "fracture: cutout map %u x %u is too large (at most %u pixels)",
                          d->cutout_width, d->cutout_height, 1u << 24);
  }
  if (!isfinite(d->noise_amplitude) || d->noise_amplitude < 0.0)
    return bk_error_set(err, "fracture: noise_amplitude must be a finite number >= 0 (got %g)",
                        d->noise_amplitude);
  if (d->noise_amplitude > 0.0 && d->pattern == BK_PATTERN_BRICK)
    return bk_error_set(err,
                        "fracture: noise_amplitude needs the planes, voronoi, clustered, radial or cutout "
                        "pattern (the brick pattern cuts flat along its mortar)");
  if (!isfinite(d->noise_frequency) || !(d->noise_frequency > 0.0))
    return bk_error_set(err, "fracture: noise_frequency must be a positive finite number (got %g)",
                        d->noise_frequency);
  if (d->threads > 1024)
    return bk_error_set(err, "fracture: threads = %u is too many (at most 1024)", d->threads);
  return true;
}

bool bk_fracture_def_validate(const bk_fracture_def* d, bk_error* err) {
  if (d->pieces == 0) return bk_error_set(err, "fracture: pieces must be at least 1 (got 0)");
  if (d->pieces > (1u << 20))
    return bk_error_set(err, "fracture: pieces = %u is too many (at most %u)", d->pieces, 1u << 20);
  if (!isfinite(d->texture_scale) || !(d->texture_scale > 0.0))
    return bk_error_set(err, "fracture: texture_scale must be a positive finite number (got %g)",
                        d->texture_scale);
  if (!isfinite(d->jitter) || d->jitter < 0.0 || d->jitter > 0.5)
    return bk_error_set(err, "fracture: jitter must be between 0 and 0.5 (got %g)", d->jitter);
  if (!isfinite(d->aspect_bias) || d->aspect_bias < 0.0 || d->aspect_bias > 100.0)
    return bk_error_set(err, "fracture: aspect_bias must be between 0 and 100 (got %g)", d->aspect_bias);
  return validate_pattern(d, err);
}
