// The mesh tree: the source mesh at the root, every intermediate piece kept,
// fragments at the leaves. The largest leaf is split next, so pieces stay
// even-sized instead of clustering (the thesis saw clusters of tiny pieces
// from depth-first splitting).
#include <stdlib.h>
#include <string.h>

#include "cap.h"

enum { MAX_SPLIT_ATTEMPTS = 8 };

bk_fracture_desc bk_default_fracture_desc(void) {
  return (bk_fracture_desc){.pieces = 256, .seed = 3000, .texture_scale = 0.1, .jitter = 0.05};
}

bool bk_fracture_desc_validate(const bk_fracture_desc* d, bk_error* err) {
  if (d->pieces > (1u << 20))
    return bk_error_set(err, "fracture: pieces = %u is too many (at most %u)", d->pieces, 1u << 20);
  if (!isfinite(d->texture_scale) || d->texture_scale < 0.0)
    return bk_error_set(err, "fracture: texture_scale must be a positive finite number (got %g)",
                        d->texture_scale);
  if (!isfinite(d->jitter) || d->jitter < 0.0 || d->jitter > 0.5)
    return bk_error_set(err, "fracture: jitter must be between 0 and 0.5 (got %g)", d->jitter);
  if (!isfinite(d->aspect_bias) || d->aspect_bias < 0.0 || d->aspect_bias > 100.0)
    return bk_error_set(err, "fracture: aspect_bias must be between 0 and 100 (got %g)", d->aspect_bias);
  return true;
}

static bk_fracture_desc resolve_defaults(const bk_fracture_desc* in) {
  bk_fracture_desc d = *in;
  if (d.pieces == 0) d.pieces = 256;
  if (d.texture_scale == 0.0) d.texture_scale = 0.1;
  return d;
}

// ---------------------------------------------------------------- building

static uint32_t add_node(bk_mesh_tree* tree, uint32_t* capacity, bk_mesh* mesh, uint32_t parent) {
  if (tree->node_count == *capacity) {
    *capacity = bk_grow_capacity(*capacity, tree->node_count + 1);
    tree->nodes = bk_realloc(tree->nodes, sizeof(bk_mesh_tree_node) * *capacity);
  }
  uint32_t index = tree->node_count++;
  bk_mesh_tree_node* node = &tree->nodes[index];
  memset(node, 0, sizeof *node);
  node->mesh = *mesh; // takes ownership
  node->bounds = bk_mesh_bounds(mesh);
  node->moments = bk_mesh_moments(mesh);
  node->parent = parent;
  node->first_child = BK_NULL_INDEX;
  node->depth = parent == BK_NULL_INDEX ? 0 : tree->nodes[parent].depth + 1;
  if (node->depth > tree->max_depth) tree->max_depth = node->depth;
  return index;
}

// Tries random planes through the centroid until one splits the node into
// two non-empty sides with closed caps; returns the hulls of both sides.
static uint32_t split_node(bk_slicer* slicer, bk_face_simplifier* simplifier, const bk_mesh_tree_node* node,
                           uint32_t node_index, const bk_fracture_desc* d, bk_rng* rng, bk_plane* plane,
                           bk_mesh** pieces) {
  bk_mass_properties mass = bk_moments_to_mass(node->moments);
  bk_vec3 size = bk_v3_sub(node->bounds.max, node->bounds.min);
  bk_vec3 longest = {0};
  if (d->aspect_bias > 0.0) {
    // The longest direction of the piece has the smallest moment of inertia.
    double values[3], axes[3][3];
    bk_sym3_eigen(mass.inertia, values, axes);
    int k = values[0] <= values[1] && values[0] <= values[2] ? 0 : (values[1] <= values[2] ? 1 : 2);
    longest = bk_v3(axes[0][k], axes[1][k], axes[2][k]);
  }
  for (int attempt = 0; attempt < MAX_SPLIT_ATTEMPTS; ++attempt) {
    bk_vec3 n = bk_rng_direction(rng);
    if (d->aspect_bias > 0.0) {
      bk_vec3 tilt = bk_v3_scale(longest, bk_v3_dot(n, longest) < 0.0 ? -d->aspect_bias : d->aspect_bias);
      n = bk_v3_normalize(bk_v3_add(n, tilt));
    }
    // Extent of the piece along n, for the jitter and the snapping tolerance.
    double extent = fabs(n.x) * size.x + fabs(n.y) * size.y + fabs(n.z) * size.z;
    double shift = d->jitter * extent * (bk_rng_unit(rng) - 0.5);
    *plane = (bk_plane){n, bk_v3_dot(n, mass.centroid) + shift};
    bk_slice_desc slice = {.plane = *plane,
                           .tolerance = 1e-9 * bk_v3_length(size),
                           .texture_scale = d->texture_scale,
                           .cap_tag = node_index + 1};
    bk_mesh below = {0}, above = {0};
    if (!bk_slicer_slice(slicer, &node->mesh, &slice, &below, &above, NULL)) continue;
    if (below.triangle_count == 0 || above.triangle_count == 0) {
      bk_mesh_free(&below);
      bk_mesh_free(&above);
      continue;
    }
    bk_mesh *below_hulls = NULL, *above_hulls = NULL;
    uint32_t below_count = bk_mesh_split_hulls(&below, &below_hulls);
    uint32_t above_count = bk_mesh_split_hulls(&above, &above_hulls);
    *pieces = bk_realloc(below_hulls, sizeof(bk_mesh) * (below_count + above_count));
    memcpy(*pieces + below_count, above_hulls, sizeof(bk_mesh) * above_count);
    free(above_hulls);
    for (uint32_t i = 0; i < below_count + above_count; ++i)
      bk_face_simplifier_run(simplifier, &(*pieces)[i]);
    return below_count + above_count;
  }
  return 0;
}

// Leaves are numbered in depth-first order so each subtree is a contiguous range.
static void number_leaves(bk_mesh_tree* tree) {
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

bool bk_mesh_tree_build(const bk_mesh* source, const bk_fracture_desc* desc_in, bk_mesh_tree* tree,
                        bk_error* err) {
  memset(tree, 0, sizeof *tree);
  if (!bk_fracture_desc_validate(desc_in, err)) return false;
  if (!bk_mesh_validate(source, err)) return false;
  bk_closure closure = bk_mesh_check_closure(source);
  if (closure.open_edges || closure.overused_edges || closure.degenerate_edges)
    return bk_error_set(err,
                        "mesh is not watertight: %u open edges, %u edges used twice in one direction, %u "
                        "degenerate triangle edges",
                        closure.open_edges, closure.overused_edges, closure.degenerate_edges);
  double volume = bk_mesh_volume(source);
  if (!(volume > 0.0))
    return bk_error_set(err, "mesh encloses no volume (signed volume %g): are its triangles wound inward?",
                        volume);

  bk_fracture_desc d = resolve_defaults(desc_in);
  bk_slicer* slicer = bk_slicer_create();
  if (!slicer) return bk_error_set(err, "fracture: cannot create the cap tessellator");
  bk_face_simplifier* simplifier = bk_face_simplifier_create();
  bk_rng rng = bk_rng_seed(d.seed, 0x62726b62u);
  uint32_t capacity = 0;
  bk_mesh root = {0};
  bk_mesh_copy(&root, source);
  // Tags identify cuts of this tree and planar faces of the source, which
  // lets each piece's faces be re-triangulated over their true corners.
  bk_label_planar_faces(&root);
  add_node(tree, &capacity, &root, BK_NULL_INDEX);

  // Largest volume first (keys negated), ties by lower node index.
  bk_heap heap = {0};
  bk_heap_push(&heap, -tree->nodes[0].moments.v, 0);
  uint32_t leaves = 1;
  bool cancelled = false;
  while (leaves < d.pieces && heap.count) {
    uint32_t split = bk_heap_pop(&heap).value;
    bk_plane plane = {0};
    bk_mesh* pieces = NULL;
    uint32_t count = split_node(slicer, simplifier, &tree->nodes[split], split, &d, &rng, &plane, &pieces);
    if (count == 0) continue; // unsplittable (degenerate sliver): stays a leaf
    uint32_t first = tree->node_count;
    for (uint32_t i = 0; i < count; ++i)
      add_node(tree, &capacity, &pieces[i], split);
    free(pieces);
    bk_mesh_tree_node* node = &tree->nodes[split];
    node->plane = plane;
    node->first_child = first;
    node->child_count = count;
    leaves += count - 1;
    for (uint32_t i = 0; i < count; ++i)
      bk_heap_push(&heap, -tree->nodes[first + i].moments.v, first + i);
    if (d.progress && !d.progress(d.progress_user, leaves, d.pieces)) {
      cancelled = true;
      break;
    }
  }
  bk_heap_free(&heap);
  bk_slicer_destroy(slicer);
  bk_face_simplifier_destroy(simplifier);
  if (cancelled) {
    bk_mesh_tree_free(tree);
    return bk_error_set(err, "fracture cancelled");
  }
  number_leaves(tree);
  tree->source_hash = bk_mesh_hash(source);
  d.progress = NULL;
  d.progress_user = NULL;
  tree->desc = d;
  bk_mesh_tree_compute_bonds(tree);
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
