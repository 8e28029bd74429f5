// Internal: the stages of the cell patterns' mesh tree, which cell_tree.c
// runs: cell_build.c makes the complex, cell_group.c groups the cells'
// solids into leaves, cell_assemble.c makes the tree's nodes.
#pragma once

#include "cell_complex.h"
#include "tree_frame.h"

/// One triangle of one cell: a fan piece of a clipped source triangle, or
/// one side of a cut face's triangle.
typedef struct bk_cell_tri {
  uint32_t v[3]; ///< complex vertices, counter-clockwise seen from outside the cell
  uint32_t cell;
  uint32_t origin; ///< source triangle, or cut face index
  uint8_t is_face;
  uint8_t reversed; ///< the face's b side
} bk_cell_tri;

/// One separate solid of one cell.
typedef struct bk_cell_atom {
  uint32_t cell;
  double moments[4]; ///< volume and first moments (local frame)
} bk_cell_atom;

typedef struct bk_cell_parts {
  bk_cell_tri* tris; ///< grouped by cell
  uint32_t tri_count;
  uint32_t* cell_start; ///< cells + 1
  uint32_t* tri_atom;
  uint32_t* twin; ///< per triangle: the other side of a face triangle, else UINT32_MAX
  bk_cell_atom* atoms;
  uint32_t atom_count, atom_capacity;
  uint32_t *contacts_a, *contacts_b; ///< atom pairs sharing face area
  double* contact_area;
  uint32_t contact_count;
  uint32_t* atom_leaf;
  uint32_t leaf_count;
} bk_cell_parts;

/// Everything one build makes.
typedef struct bk_cell_build {
  bk_vec3* seeds;
  uint32_t* cluster_of; ///< clustered: each seed's chunk
  uint32_t* cell_label; ///< cut-out: each seed's region; clustered: each seed's piece
  uint32_t cells;
  bk_cell_complex cx;
  bk_cell_polytope* polytopes; ///< NULL once the cells are grouped
  bk_cell_surface* surfaces;   ///< NULL once the cells are grouped
  bk_cell_faces faces;
  bk_cell_parts parts;
} bk_cell_build;

/// How often a build is tried with the seeds moved by a hair. The last try
/// joins the two cells of a cut face that cannot be made into one piece.
#define BK_CELL_ATTEMPTS 4

/// Seeds, polytopes, surfaces, faces and the grouping into leaves, for a
/// source already in the local frame (the polytopes and surfaces are freed
/// once their triangles are grouped).
/// A retry (`attempt` > 0) moves every seed by a tiny deterministic amount,
/// which takes a near-degenerate layout apart.
bool bk_cell_complex_run(const bk_mesh* local_source, const bk_fracture_def* d, bk_tree_frame frame,
                         uint32_t attempt, bk_cell_build* b, bk_error* err);
/// Triangles, atoms, contacts and leaves: with labels, atoms of one label
/// that touch become one leaf first; then the smallest are merged into
/// their neighbours while there are more than `target`.
bool bk_cell_group(bk_cell_build* b, uint32_t target, const uint32_t* cell_label);
/// The tree's nodes from the grouped build, their meshes made on every core:
/// the root a copy of `root` (still in the local frame), every other node
/// in the source's coordinates with its bounds; moments local.
bool bk_cell_tree_assemble(const bk_mesh* root, const bk_fracture_def* d, bk_tree_frame frame,
                           bk_cell_build* b, bk_mesh_tree* tree, bk_error* err);
void bk_cell_build_free(bk_cell_build* b);

/// Cut-out seeds: one per map pixel sample inside the source, labelled with
/// its region (regions enclosed by the map's lines). Returns the count.
uint32_t bk_cutout_seeds(const bk_mesh* local_source, const bk_fracture_def* d, bk_vec3** seeds,
                         uint32_t** labels, bk_error* err);
