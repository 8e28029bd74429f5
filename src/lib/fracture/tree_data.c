// The helpers over a mesh tree's data that its builders and its users
// share: numbering its leaves, its frame's origin and masses, what it says
// of pieces it could not make, measuring and freeing it.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tree_data.h"
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
  bk_free(stack);
  bk_free(visited);
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
  bk_free(tree->nodes);
  bk_free(tree->leaf_nodes);
  bk_free(tree->bonds);
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
