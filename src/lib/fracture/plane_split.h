// Internal: one split of the planes and brick patterns' mesh tree. A split
// is a pure function of the node, its index and how many pieces the tree may
// still take: its random planes come from a generator seeded by the def's
// seed and the node's index, so splits can run on any thread, in any order,
// and give the same pieces.
#pragma once

#include "brick_bond.h"
#include "cap.h"

/// Why a split made no pieces (the last attempt's reason).
typedef enum bk_split_failure {
  BK_SPLIT_MISSED,
  BK_SPLIT_CAP_FAILED,
  BK_SPLIT_NOT_CLOSED,
  BK_SPLIT_VOLUME_CHANGED,
  BK_SPLIT_NO_VOLUME, ///< a piece encloses no volume (a face of the source closed against its own back)
  BK_SPLIT_NOT_SOLID, ///< a piece's mass is not a solid's (bk_solid_mass_check: the surface crosses itself)
} bk_split_failure;

/// What every split of one build shares (read only).
typedef struct bk_plane_split_context {
  const bk_fracture_def* def;
  const bk_tree_frame* frame;
  const bk_brick_bond* bond; ///< NULL: the planes pattern
} bk_plane_split_context;

/// The outcome of a split: `count` closed pieces (0: none held, `why` says
/// why), the plane that made them (local frame) and their moments.
typedef struct bk_plane_split {
  bk_mesh* pieces;
  bk_moments* moments;
  uint32_t count;
  bk_plane plane;
  bk_split_failure why;
  uint32_t bond_fallbacks; ///< 1 when a brick bond's cut failed and random planes cut instead
  uint32_t sheets_merged;  ///< pieces enclosing no volume that joined a neighbour (never fragments)
} bk_plane_split;

/// A thread's cutting tools (slicer with its tessellator, face simplifier).
typedef struct bk_plane_splitter bk_plane_splitter;

/// NULL when the cap tessellator cannot be created.
bk_plane_splitter* bk_plane_splitter_create(void);
void bk_plane_splitter_destroy(bk_plane_splitter* splitter);

/// Splits `node` (index `node_index`, local frame) into at most `allowed`
/// pieces (merged down when the cut that held made more).
void bk_plane_split_node(bk_plane_splitter* splitter, const bk_plane_split_context* ctx,
                         const bk_mesh_tree_node* node, uint32_t node_index, uint32_t allowed,
                         bk_plane_split* out);
/// Releases the pieces a split made (when they are not taken into the tree).
void bk_plane_split_free(bk_plane_split* split);

/// True when `count` pieces of `node` are closed, each encloses volume
/// (bk_mesh_encloses_no_volume) and they keep the node's volume within
/// BK_FRACTURE_SPLIT_VOLUME_TOLERANCE; fills their moments, else sets *why.
/// `scratch` is storage for the closure test, reused between calls.
bool bk_plane_pieces_hold(const bk_mesh_tree_node* node, const bk_mesh* pieces, uint32_t count,
                          bk_moments* moments, bk_split_failure* why, bk_topology_scratch* scratch);
