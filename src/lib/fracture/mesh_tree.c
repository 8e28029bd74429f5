// Building a mesh tree: the source checked, the pattern's builder
// (plane_tree.c, or the cell patterns' cell_tree.c) run, and what it made
// checked before it is handed out. The helpers over a tree's data that the
// builders share are tree_data.c's: this file calls the builders, the
// builders call the helpers, and nothing calls back.
#include <string.h>

#include "tree_data.h"

// A closed surface that crosses itself, or is partly inside out, can still
// enclose a positive signed volume; when its mass is not a solid's no body
// can be made of it or of its pieces. Measured about the centre of its
// bounds, so a source far from the origin keeps its precision.
static bool source_is_solid(const bk_mesh* source, bk_aabb box, bk_error* err) {
  bk_vec3 centre = bk_v3_scale(bk_v3_add(box.min, box.max), 0.5);
  bk_mesh local = *source;
  local.positions = bk_alloc(sizeof(bk_vec3) * (source->position_count + 1u));
  for (uint32_t i = 0; i < source->position_count; ++i)
    local.positions[i] = bk_v3_sub(source->positions[i], centre);
  bk_moments moments = bk_mesh_moments(&local);
  bk_free(local.positions);
  if (!(moments.v > 0.0)) return true; // a source of no volume is refused with its own message
  bk_error why = {{0}};
  if (bk_solid_mass_check(&moments, centre, box, false, "its mass", &why)) return true;
  return bk_error_set(err, "mesh is not a solid: its surface crosses itself or is partly inside out (%s)",
                      why.message);
}

// The source must have a size whose moments fit doubles, a volume, and cut
// faces whose uvs floats can hold.
static bool check_source(const bk_mesh* source, const bk_fracture_def* d, bk_error* err) {
  if (!bk_mesh_validate(source, err)) return false;
  bk_closure closure = bk_mesh_check_closure(source);
  if (closure.open_edges || closure.overused_edges || closure.degenerate_edges)
    return bk_error_set(err,
                        "mesh is not watertight: %u open edges, %u edges used twice in one direction, %u "
                        "degenerate triangle edges",
                        closure.open_edges, closure.overused_edges, closure.degenerate_edges);
  bk_aabb box = bk_mesh_bounds(source);
  bk_vec3 size = bk_v3_sub(box.max, box.min);
  double largest = fmax(size.x, fmax(size.y, size.z));
  if (!(largest >= BK_FRACTURE_MIN_SIZE && largest <= BK_FRACTURE_MAX_SIZE))
    return bk_error_set(err,
                        "mesh is %g across; fracture takes meshes %g to %g across (volume moments grow "
                        "with size^5 and must fit double precision): scale it",
                        largest, BK_FRACTURE_MIN_SIZE, BK_FRACTURE_MAX_SIZE);
  if (!source_is_solid(source, box, err)) return false;
  if (largest / d->texture_scale > BK_FRACTURE_MAX_UV_TILES)
    return bk_error_set(err,
                        "texture_scale %g is too small for a mesh %g across: cut faces would span %.3g "
                        "texture tiles (at most %g)",
                        d->texture_scale, largest, largest / d->texture_scale, BK_FRACTURE_MAX_UV_TILES);
  return true;
}

// A piece that encloses no volume is never a fragment, whatever made it: the
// builders refuse such cuts and such sources, and a tree that has one
// anyway is not handed out (freed, with the leaf named).
static bool leaves_enclose_volume(bk_mesh_tree* tree, bk_error* err) {
  for (uint32_t i = 0; i < tree->leaf_count; ++i) {
    const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(tree, i);
    if (!bk_mesh_encloses_no_volume(&leaf->mesh, leaf->moments.v)) continue;
    double volume = leaf->moments.v, area = bk_mesh_area(&leaf->mesh);
    bk_mesh_tree_free(tree);
    return bk_error_set(err,
                        "fracture: piece %u encloses no volume (%g for a surface of area %g): a sheet of the "
                        "source or a cut along one of its faces; nothing was made",
                        i, volume, area);
  }
  return true;
}

// What the builders made is what every consumer will check
// (bk_mesh_tree_validate): a tree that fails it is not handed out. The
// planes and brick patterns try another plane where a piece is no solid,
// so for them this is a defect of the builder; a cell keeps its place, so
// where the source's surface crosses itself a cell's piece can be no solid
// (a negative volume) and the source is refused, pointing to planes.
static bool finish(bk_mesh_tree* tree, bk_fracture_pattern pattern, bk_error* err) {
  if (!leaves_enclose_volume(tree, err)) return false;
  bk_error why = {{0}};
  if (bk_mesh_tree_check_built(tree, &why)) return true;
  bk_mesh_tree_free(tree);
  if (bk_fracture_pattern_is_cellular(pattern))
    return bk_error_set(err,
                        "fracture: the %s pattern's pieces are not solids (%s): the source's surface crosses "
                        "itself there; the planes pattern cuts around such places",
                        bk_fracture_pattern_name(pattern), why.message);
  return bk_error_set(err, "fracture: the pieces made are not valid (%s); nothing was made", why.message);
}

bool bk_mesh_tree_build(const bk_mesh* source, const bk_fracture_def* desc_in, bk_mesh_tree* tree,
                        bk_error* err) {
  memset(tree, 0, sizeof *tree);
  if (!bk_fracture_def_validate(desc_in, err)) return false;
  bk_fracture_def d = *desc_in;
  if (!check_source(source, &d, err)) return false;
  if (bk_fracture_pattern_is_cellular(d.pattern))
    return bk_cell_tree_build(source, &d, tree, err) && finish(tree, d.pattern, err);
  if (!bk_plane_tree_build(source, &d, tree, err)) return false;
  bk_mesh_tree_number_leaves(tree);
  tree->source_hash = bk_mesh_hash(source);
  bk_fracture_def_clear_borrowed(&d);
  tree->desc = d;
  bk_mesh_tree_compute_bonds(tree);
  return finish(tree, d.pattern, err);
}
