// The mesh tree of the cell patterns. Seeds -> Voronoi cells -> the source's
// surface clipped per cell and the cut faces between cells, all over one set
// of named vertices (cell_complex.h). A cell's triangles may form several
// separate solids (a cell across a notch of a concave source): each is an
// atom. Atoms are merged, smallest first into the neighbour they share most
// face with, down to the pieces asked for; the leaves are the merged groups.
// Inner nodes group adjacent leaves by halving along their longest extent
// (clustered: the chunks first), each node's mesh being its leaves' triangles
// without the faces they share, so every node is closed by topology.
//
// This file runs the stages (cell_stages.h) for bk_cell_tree_build: the
// complex (cell_build.c, which groups its cells' solids with cell_group.c),
// the tree's nodes (cell_assemble.c), and the bonds (cell_bonds.c).
#include <string.h>

#include "cell_stages.h"
#include "tree_data.h"
#include "tree_frame.h"

bool bk_cell_tree_build(const bk_mesh* source, const bk_fracture_def* d, bk_mesh_tree* tree, bk_error* err) {
  memset(tree, 0, sizeof *tree);
  if (d->pattern == BK_PATTERN_CUTOUT && (!d->cutout_pixels || d->cutout_width < 2 || d->cutout_height < 2))
    return bk_error_set(err, "fracture: the cutout pattern needs cutout_pixels (a map of at least 2 x 2)");
  bk_tree_frame frame = {0};
  bk_mesh root = {0};
  if (!bk_tree_frame_local_source(source, &frame, &root, err)) return false;
  bk_mesh* shells = NULL;
  bk_fracture_overlap overlap = {0};
  uint32_t shell_count = bk_mesh_split_overlapping_shells(&root, &shells, &overlap);
  for (uint32_t i = 0; i < shell_count; ++i)
    bk_mesh_free(&shells[i]);
  bk_free(shells);
  if (shell_count) {
    bk_mesh_free(&root);
    return bk_error_set(
        err,
        "fracture: the %s pattern needs shells that neither overlap nor touch (shells %u and %u "
        "%s); the planes pattern cuts such sources",
        bk_fracture_pattern_name(d->pattern), overlap.shell_a, overlap.shell_b,
        overlap.touching ? "touch" : "overlap");
  }
  // Rounding can make a near-degenerate layout (five seeds almost on one
  // sphere) inconsistent; then the seeds are moved by a hair and it is
  // built again. Deterministic: the same def always takes the same tries.
  bool ok = false;
  for (uint32_t attempt = 0; attempt < BK_CELL_ATTEMPTS && !ok; ++attempt) {
    bk_cell_build build = {0};
    bk_error inner = {0};
    ok = bk_cell_complex_run(&root, d, frame, attempt, &build, &inner);
    if (ok) ok = bk_cell_tree_assemble(&root, d, frame, &build, tree, &inner);
    if (ok) tree->shortfall.cells_joined = build.faces.joined_count;
    bk_cell_build_free(&build);
    if (!ok) {
      bk_mesh_tree_free(tree);
      if (err) *err = inner;
      if (strstr(inner.message, "cancelled") || strstr(inner.message, "seed point") ||
          strstr(inner.message, "cutout"))
        break; // not a matter of rounding
    }
  }
  bk_mesh_free(&root);
  if (!ok) return false;
  // Cells are grouped into exactly the pieces asked for (unless the map's
  // regions or the user's seeds set the count), through the faces they
  // share; a part of the source that touches no other (a shell that
  // encloses no volume, left flat by a repair) cannot join a group and
  // would be one piece too many: refused, never a silently wrong count.
  // Cells joined for a face that could not be made give fewer pieces, as
  // the shortfall records.
  bool counted = d->pattern != BK_PATTERN_CUTOUT && !d->seed_points;
  bool joined_fewer = tree->leaf_count < d->pieces && tree->shortfall.cells_joined > 0;
  if (counted && tree->leaf_count != d->pieces && !joined_fewer) {
    uint32_t made = tree->leaf_count;
    bk_mesh_tree_free(tree);
    return bk_error_set(err,
                        "fracture: the %s pattern made %u pieces of the %u asked for (a part of the source "
                        "touches no other, such as a flat shell); the planes pattern cuts such sources",
                        bk_fracture_pattern_name(d->pattern), made, d->pieces);
  }
  // The root gets the source's own positions back; the other nodes' bounds
  // were taken as their meshes were made.
  memcpy(tree->nodes[0].mesh.positions, source->positions, sizeof(bk_vec3) * source->position_count);
  tree->nodes[0].bounds = bk_mesh_bounds(&tree->nodes[0].mesh);
  for (uint32_t i = 0; i < tree->node_count; ++i)
    tree->nodes[i].moments = bk_tree_frame_moments_to_world(frame, tree->nodes[i].moments);
  tree->source_hash = bk_mesh_hash(source);
  bk_cell_tree_compute_bonds(tree);
  return true;
}
