// Internal: the brick bond of BK_PATTERN_BRICK as cutting planes in a mesh
// tree's local frame. The bond's planes are horizontal mortar planes
// y = origin.y + k * height (course k), in course k the vertical head joints
// x = origin.x + (m + frac(k * offset)) * length, and with a depth, planes
// z = origin.z + j * depth. A piece spanning several bricks is cut by one of
// them, so pieces are unions of whole bricks until every brick is separate.
#pragma once

#include "tree_frame.h"

/// A def's brick bond seen from one tree's frame.
typedef struct bk_brick_bond {
  bk_tree_frame frame;
  bk_vec3 size;   ///< brick length, height, depth (0: through the whole source), source units
  bk_vec3 origin; ///< a corner of one brick, source units
  double offset;  ///< course shift, a fraction of the length in [0, 1)
} bk_brick_bond;

/// The bond of `def` (brick_size, brick_origin, brick_offset) in `frame`.
bk_brick_bond bk_brick_bond_of(const bk_fracture_def* def, bk_tree_frame frame);

/// The bond plane that cuts a piece (local bounds and centroid) into groups
/// of whole bricks: a mortar plane when the piece spans several courses,
/// else a head joint of its course or a depth plane; of those, the one
/// nearest the centroid that lies inside the bounds by more than a margin
/// (so the cut halves the piece as evenly as the bond allows and rounding
/// never makes a sliver). False when the piece lies within one brick. The
/// plane is local, with a unit axis normal.
bool bk_brick_bond_plane(const bk_brick_bond* bond, bk_aabb bounds, bk_vec3 centroid, bk_plane* plane);
