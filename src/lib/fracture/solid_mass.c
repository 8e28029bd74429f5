// Whether volume moments are those of a solid: what a rigid body made of
// them gets (centre of mass, principal moments and axes) is physical. A
// closed surface that crosses itself, or is turned inside out in part,
// still has a positive signed volume, but the regions it counts twice or
// negatively move its centre of mass out of its bounds and make a
// principal moment negative or larger than the other two together. The
// mesh tree's check and the planes pattern's cuts share this test, so a
// fracture never hands out a piece the runtime would refuse.
#include <float.h>

#include "bk_fracture.h"

// Principal moments and frames are computed in doubles from values of about
// unit scale: rounding stays near 1e-15.
#define FRAME_TOLERANCE 1e-9
// A centre of mass lies inside its bounds up to this fraction of their
// diagonal, plus a few ulps of the coordinates (a piece far from the origin).
#define INSIDE_TOLERANCE 1e-6
#define INSIDE_ROUNDING_ULPS 64.0

double bk_aabb_diagonal(bk_aabb b) { return bk_v3_length(bk_v3_sub(b.max, b.min)); }

double bk_aabb_largest_coordinate(bk_aabb b) {
  return fmax(fmax(fmax(fabs(b.min.x), fabs(b.min.y)), fmax(fabs(b.min.z), fabs(b.max.x))),
              fmax(fabs(b.max.y), fabs(b.max.z)));
}

double bk_inside_slack(bk_aabb b) {
  return INSIDE_TOLERANCE * bk_aabb_diagonal(b) +
         INSIDE_ROUNDING_ULPS * DBL_EPSILON * bk_aabb_largest_coordinate(b);
}

bool bk_point_inside(bk_aabb b, bk_vec3 p, double slack) {
  return p.x >= b.min.x - slack && p.x <= b.max.x + slack && p.y >= b.min.y - slack &&
         p.y <= b.max.y + slack && p.z >= b.min.z - slack && p.z <= b.max.z + slack;
}

static bool matrix_finite(const double m[3][3]) {
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (!isfinite(m[i][j])) return false;
  return true;
}

// The quick test: the second moment Σ = tr(I)/2 x 1 - I (the spread of the
// volume about its centre) is positive definite (Sylvester's leading
// minors) and its trace, which bounds every principal moment, is within
// volume x diagonal^2. When it holds the principal moments are positive and
// satisfy the triangle inequality (I_k = tr Σ - σ_k); only when it fails, or
// the principal frame is asked for, are they computed.
static bool spread_is_solid(const double inertia[3][3], double limit) {
  double half = 0.5 * (inertia[0][0] + inertia[1][1] + inertia[2][2]);
  double s[3][3] = {{0}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      s[i][j] = (i == j ? half : 0.0) - inertia[i][j];
  double minor2 = s[0][0] * s[1][1] - s[0][1] * s[1][0];
  double det = s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1]) -
               s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0]) +
               s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0]);
  return s[0][0] > 0.0 && minor2 > 0.0 && det > 0.0 && half <= limit;
}

bool bk_solid_mass_check(const bk_moments* moments, bk_vec3 offset, bk_aabb bounds, bool frame,
                         const char* name, bk_error* why) {
  double v = moments->v;
  if (!(v > 0.0) || !isfinite(v)) return bk_error_set(why, "%s: volume %g is not positive", name, v);
  bk_mass_properties mass = bk_moments_to_mass(*moments);
  mass.centroid = bk_v3_add(mass.centroid, offset);
  if (!bk_v3_is_finite(mass.centroid))
    return bk_error_set(why, "%s: centroid (%g, %g, %g) is not finite", name, mass.centroid.x,
                        mass.centroid.y, mass.centroid.z);
  // A centre of mass lies within the solid's convex hull, so in its bounds.
  if (!bk_point_inside(bounds, mass.centroid, bk_inside_slack(bounds)))
    return bk_error_set(why, "%s: centroid (%g, %g, %g) lies outside its bounds", name, mass.centroid.x,
                        mass.centroid.y, mass.centroid.z);
  if (!matrix_finite(mass.inertia)) return bk_error_set(why, "%s: inertia is not finite", name);
  double d = bk_aabb_diagonal(bounds), limit = v * d * d * (1.0 + FRAME_TOLERANCE);
  if (!frame && spread_is_solid(mass.inertia, limit)) return true;
  double principal[3] = {0}, axes[3][3] = {{0}};
  bk_sym3_eigen(mass.inertia, principal, axes);
  // No point of the solid is further than the bounds' diagonal from its
  // centre of mass, so no principal moment exceeds volume x diagonal^2; a
  // real body's three also satisfy the triangle inequality.
  double sum = principal[0] + principal[1] + principal[2];
  for (int k = 0; k < 3; ++k) {
    if (!(principal[k] > 0.0))
      return bk_error_set(why, "%s: principal moment of inertia %d is %g, not positive", name, k,
                          principal[k]);
    if (!(principal[k] <= limit))
      return bk_error_set(why, "%s: principal moment of inertia %d is %g, more than volume x diagonal^2 (%g)",
                          name, k, principal[k], limit);
    if (!(sum - principal[k] >= principal[k] - FRAME_TOLERANCE * sum))
      return bk_error_set(
          why, "%s: principal moments of inertia %g, %g, %g: %g is more than the other two together", name,
          principal[0], principal[1], principal[2], principal[k]);
  }
  // The principal axes are the body's frame: they must be a rotation.
  for (int a = 0; a < 3; ++a)
    for (int b = a; b < 3; ++b) {
      double dot = axes[0][a] * axes[0][b] + axes[1][a] * axes[1][b] + axes[2][a] * axes[2][b];
      if (!(fabs(dot - (a == b ? 1.0 : 0.0)) <= FRAME_TOLERANCE))
        return bk_error_set(why, "%s: principal axes %d and %d are not orthonormal (dot product %g)", name, a,
                            b, dot);
    }
  return true;
}
