// The pose a body is drawn at between two physics steps: drawing runs at
// the display's rate, physics at a fixed 60 Hz, so each frame blends the
// last two steps' transforms by how far the frame is between them.
#pragma once

#include <breakables/types.h>

/// a at t = 0, b at t = 1: positions blended linearly, rotations by a
/// normalised blend of the quaternions taken on the same hemisphere (the
/// short way round; close enough to a slerp for one step's turn).
static inline bk_transform lerp_transform(bk_transform a, bk_transform b, double t) {
  bk_quat qa = a.rotation, qb = b.rotation;
  if (qa.x * qb.x + qa.y * qb.y + qa.z * qb.z + qa.w * qb.w < 0.0) qb = (bk_quat){-qb.x, -qb.y, -qb.z, -qb.w};
  bk_quat q = bk_quat_normalize((bk_quat){qa.x + (qb.x - qa.x) * t, qa.y + (qb.y - qa.y) * t,
                                          qa.z + (qb.z - qa.z) * t, qa.w + (qb.w - qa.w) * t});
  return (bk_transform){bk_v3_lerp(a.position, b.position, t), q};
}
