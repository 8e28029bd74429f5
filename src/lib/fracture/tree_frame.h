// Internal: the frame a mesh tree is cut in. Slicing, capping and volume
// checks work in coordinates relative to the source's centre and scaled by a
// power of two to about unit size, so a mesh far from the world origin or
// much smaller or larger than a metre cuts exactly as the same mesh at unit
// size at the origin (no absolute tolerance ever meets coordinates of 1e9).
#pragma once

#include "bk_fracture.h"

/// local = (world - origin) * 2^-exponent. The scale is a power of two, so
/// scaling is exact; the origin lies on a grid of 2^(exponent - 1), so far
/// from the world origin the shift is exact too.
typedef struct bk_tree_frame {
  bk_vec3 origin;
  int exponent;
} bk_tree_frame;

/// The frame of a source with these bounds (non-empty, finite, size > 0).
bk_tree_frame bk_tree_frame_of(bk_aabb bounds);
/// World positions to local ones, in place.
void bk_tree_frame_to_local(bk_tree_frame frame, bk_mesh* mesh);
/// Local positions to world ones, in place.
void bk_tree_frame_to_world(bk_tree_frame frame, bk_mesh* mesh);
/// Moments of a local mesh (about the local origin) as world-unit moments
/// about the frame's origin (exact: powers of two).
bk_moments bk_tree_frame_moments_to_world(bk_tree_frame frame, bk_moments local);
/// A local plane as the world plane.
bk_plane bk_tree_frame_plane_to_world(bk_tree_frame frame, bk_plane local);
/// The frame of a source and a copy of it in that frame (`root`,
/// overwritten); false (nothing allocated) when it encloses no volume.
bool bk_tree_frame_local_source(const bk_mesh* source, bk_tree_frame* frame, bk_mesh* root, bk_error* err);
