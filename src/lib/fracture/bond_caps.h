// Internal: the cap triangles of a planes-pattern tree's leaves, the input
// of its bonds (bonds.c), gathered on the tree's threads.
#pragma once

#include "bk_fracture.h"

/// One cap triangle of a leaf, with what the bonds read of its geometry
/// (so they never go back to the leaf's mesh for a flat cap).
typedef struct bk_cap_entry {
  uint32_t cut;         ///< node whose split made the cap
  uint32_t side;        ///< 0: the leaf lies below the cut (the cap faces +n), 1: above
  uint32_t leaf;        ///< leaf number
  uint32_t triangle;    ///< in the leaf's mesh
  uint32_t position[3]; ///< the triangle's positions, in corner order
  uint32_t flat;        ///< 1 when all three lie on the cut's plane (within the bonds' tolerance)
  double uv[3][2];      ///< their coordinates in the cut's plane basis, relative to the tree's origin
} bk_cap_entry;

/// How the bonds measure a cut: its plane basis and height above the tree's origin.
typedef struct bk_cut_frame {
  bk_vec3 u, v;
  double height;
} bk_cut_frame;

/// The cap triangles of every leaf, sorted by cut, side, leaf and triangle
/// (the order does not depend on the thread count), into *entries
/// (allocated). `frames` has one entry per node (only those of inner nodes
/// are read); `flat` is the tolerance of a flat cap.
uint32_t bk_gather_cap_entries(const bk_mesh_tree* tree, const bk_cut_frame* frames, double flat,
                               bk_cap_entry** entries);
