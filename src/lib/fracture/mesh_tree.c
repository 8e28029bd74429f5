// The mesh tree: building it (the pattern's builder: plane_tree.c or the
// cell patterns' cell_tree.c), numbering its leaves, measuring it.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tree_frame.h"

void bk_mesh_tree_number_leaves(bk_mesh_tree* tree) {
  tree->leaf_nodes = bk_alloc(sizeof(uint32_t) * tree->node_count);
  uint32_t* stack = bk_alloc(sizeof(uint32_t) * tree->node_count);
  uint8_t* visited = bk_calloc(tree->node_count, 1);
  uint32_t top = 0, leaves = 0;
  stack[top++] = 0;
  while (top) {
    uint32_t i = stack[top - 1];
    bk_mesh_tree_node* node = &tree->nodes[i];
    if (!visited[i]) {
      visited[i] = 1;
      node->leaf_begin = leaves;
      if (node->child_count == 0) {
        tree->leaf_nodes[leaves++] = i;
      } else {
        // Push children in reverse so the first child is numbered first.
        for (uint32_t c = node->child_count; c > 0; --c)
          stack[top++] = node->first_child + c - 1;
        continue;
      }
    }
    node->leaf_end = leaves;
    top--;
  }
  tree->leaf_count = leaves;
  free(stack);
  free(visited);
}

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
  free(local.positions);
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

bk_vec3 bk_mesh_tree_origin(const bk_mesh_tree* tree) {
  return tree->node_count ? bk_tree_frame_of(tree->nodes[0].bounds).origin : bk_v3(0, 0, 0);
}

bk_mass_properties bk_mesh_tree_mass(const bk_mesh_tree* tree, bk_moments moments) {
  bk_mass_properties mass = bk_moments_to_mass(moments);
  mass.centroid = bk_v3_add(mass.centroid, bk_mesh_tree_origin(tree));
  return mass;
}

bool bk_mesh_tree_shortfall_text(const bk_mesh_tree* tree, char* text, size_t size) {
  if (size) text[0] = 0;
  const bk_fracture_shortfall* s = &tree->shortfall;
  if (s->cells_joined) {
    int n = 0;
    if (tree->leaf_count < tree->desc.pieces)
      n = snprintf(text, size, "made %u of the %u pieces asked for: ", tree->leaf_count, tree->desc.pieces);
    if (n < 0 || (size_t)n > size) n = (int)size;
    snprintf(text + n, size > (size_t)n ? size - (size_t)n : 0,
             "%u cut face%s between cells could not be made (the source's surface crosses itself there), "
             "so the cells on either side were kept as one piece",
             s->cells_joined, s->cells_joined == 1 ? "" : "s");
    return true;
  }
  if (s->sheets_merged && tree->leaf_count >= tree->desc.pieces) {
    snprintf(
        text, size,
        "%u cut piece%s enclosed no volume (a face of the source closed against its own back) and joined "
        "the nearest piece",
        s->sheets_merged, s->sheets_merged == 1 ? "" : "s");
    return true;
  }
  if (tree->leaf_count >= tree->desc.pieces) return false;
  int n = snprintf(text, size, "made %u of the %u pieces asked for", tree->leaf_count, tree->desc.pieces);
  if (s->uncut == 0) {
    snprintf(text + n, size > (size_t)n ? size - (size_t)n : 0,
             ": the tree was loaded from a cache file that does not record why");
    return true;
  }
  const char* most = "no plane cut through them (thinner than the cut tolerance)";
  uint32_t top = s->missed;
  if (s->cap_failed > top)
    top = s->cap_failed,
    most = "their cross-sections could not be closed (overlapping or self-intersecting shells?)";
  if (s->not_closed > top) top = s->not_closed, most = "cutting them left open pieces";
  if (s->volume_changed > top)
    top = s->volume_changed, most = "their cut pieces did not keep the volume (slivers too thin to cut?)";
  if (s->not_solid > top)
    top = s->not_solid, most = "their cut pieces were not solids (the source's surface crosses itself there)";
  snprintf(text + n, size > (size_t)n ? size - (size_t)n : 0,
           ": %u piece%s could not be cut in %d tries each (%u of them because %s)", s->uncut,
           s->uncut == 1 ? "" : "s", BK_FRACTURE_SPLIT_ATTEMPTS, top, most);
  return true;
}

bool bk_mesh_tree_overlap_text(const bk_mesh_tree* tree, char* text, size_t size) {
  if (size) text[0] = 0;
  const bk_fracture_overlap* o = &tree->overlap;
  if (o->pairs == 0) return false;
  int n = snprintf(text, size, "shells %u and %u %s (volumes %.6g and %.6g m^3 near (%.6g, %.6g, %.6g))",
                   o->shell_a, o->shell_b, o->touching ? "touch" : "overlap", o->volume_a, o->volume_b,
                   o->point.x, o->point.y, o->point.z);
  if (n < 0 || (size_t)n > size) n = (int)size;
  if (o->pairs > 1)
    n += snprintf(text + n, size > (size_t)n ? size - (size_t)n : 0,
                  ", and %u more pair%s overlapping or touching (%u shells in all)", o->pairs - 1,
                  o->pairs == 2 ? "" : "s", o->shells);
  if (n < 0 || (size_t)n > size) n = (int)size;
  if (tree->leaf_count < o->shells)
    snprintf(text + n, size > (size_t)n ? size - (size_t)n : 0,
             "; with more shells than pieces, the nearest shared a piece (no bonds between them)");
  else
    snprintf(text + n, size > (size_t)n ? size - (size_t)n : 0,
             "; each was fractured on its own (no bonds between them)");
  return true;
}

void bk_mesh_tree_free(bk_mesh_tree* tree) {
  for (uint32_t i = 0; i < tree->node_count; ++i)
    bk_mesh_free(&tree->nodes[i].mesh);
  free(tree->nodes);
  free(tree->leaf_nodes);
  free(tree->bonds);
  memset(tree, 0, sizeof *tree);
}

bk_mesh_tree_stats bk_mesh_tree_measure(const bk_mesh_tree* tree) {
  bk_mesh_tree_stats st = {0};
  if (tree->node_count == 0) return st;
  st.source_volume = tree->nodes[0].moments.v;
  st.min_leaf_volume = INFINITY;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[i];
    if (!bk_mesh_is_closed(&node->mesh)) st.open_nodes++;
    if (node->child_count == 0) {
      st.leaf_triangles += node->mesh.triangle_count;
      st.leaf_volume_sum += node->moments.v;
      st.min_leaf_volume = fmin(st.min_leaf_volume, node->moments.v);
      st.max_leaf_volume = fmax(st.max_leaf_volume, node->moments.v);
    } else {
      double sum = 0.0;
      for (uint32_t c = 0; c < node->child_count; ++c)
        sum += tree->nodes[node->first_child + c].moments.v;
      st.max_child_rel_error =
          fmax(st.max_child_rel_error, fabs(sum - node->moments.v) / fabs(node->moments.v));
    }
  }
  return st;
}
