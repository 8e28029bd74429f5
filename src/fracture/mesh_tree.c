// The mesh tree of the planes and brick patterns: the source mesh at the
// root, every intermediate piece kept, fragments at the leaves. The largest
// leaf is split next, so pieces stay even-sized instead of clustering (the
// thesis saw clusters of tiny pieces from depth-first splitting); with a
// brick bond, pieces spanning several bricks go first, cut along the mortar.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brick_bond.h"
#include "cap.h"
#include "tree_frame.h"

// ---------------------------------------------------------------- building

static uint32_t add_node(bk_mesh_tree* tree, uint32_t* capacity, bk_mesh* mesh, bk_moments moments,
                         uint32_t parent) {
  if (tree->node_count == *capacity) {
    *capacity = bk_grow_capacity(*capacity, tree->node_count + 1);
    tree->nodes = bk_realloc(tree->nodes, sizeof(bk_mesh_tree_node) * *capacity);
  }
  uint32_t index = tree->node_count++;
  bk_mesh_tree_node* node = &tree->nodes[index];
  memset(node, 0, sizeof *node);
  node->mesh = *mesh; // takes ownership
  node->bounds = bk_mesh_bounds(mesh);
  node->moments = moments;
  node->parent = parent;
  node->first_child = BK_NULL_INDEX;
  node->depth = parent == BK_NULL_INDEX ? 0 : tree->nodes[parent].depth + 1;
  if (node->depth > tree->max_depth) tree->max_depth = node->depth;
  return index;
}

typedef enum split_failure {
  SPLIT_MISSED,
  SPLIT_CAP_FAILED,
  SPLIT_NOT_CLOSED,
  SPLIT_VOLUME_CHANGED,
} split_failure;

static void free_pieces(bk_mesh* pieces, uint32_t count) {
  for (uint32_t i = 0; i < count; ++i)
    bk_mesh_free(&pieces[i]);
  free(pieces);
}

// A cut holds when every piece is a closed solid and the pieces' volumes add
// up to the whole's within 1e-11 of it. Rounding in cut points and
// re-triangulated faces stays far below that (about 1e-15 on ordinary
// pieces), while a cap that overlaps itself or a sliver whose sides crossed
// after snapping to the plane is far above it. A tree is at most a few dozen
// levels deep, so its leaves add up to the source within 1e-9.
// Fills each piece's moments on the way (the node keeps them).
static bool pieces_hold(const bk_mesh_tree_node* node, const bk_mesh* pieces, uint32_t count,
                        bk_moments* moments, split_failure* why) {
  double sum = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    if (!bk_mesh_is_closed(&pieces[i])) {
      *why = SPLIT_NOT_CLOSED;
      return false;
    }
    moments[i] = bk_mesh_moments(&pieces[i]);
    double v = moments[i].v;
    if (!(v > 0.0)) {
      *why = SPLIT_VOLUME_CHANGED;
      return false;
    }
    sum += v;
  }
  if (!(fabs(sum - node->moments.v) <= BK_FRACTURE_SPLIT_VOLUME_TOLERANCE * node->moments.v)) {
    *why = SPLIT_VOLUME_CHANGED;
    return false;
  }
  return true;
}

// Cuts a node by one plane (local frame) into the solid shells on each side,
// their faces re-triangulated; returns how many, *below_count of them below
// the plane, or 0 (nothing allocated) with *why set when the plane misses
// the node or the pieces do not hold.
static uint32_t cut_node(bk_slicer* slicer, bk_face_simplifier* simplifier, const bk_mesh_tree_node* node,
                         uint32_t node_index, const bk_fracture_def* d, const bk_tree_frame* frame,
                         bk_plane plane, bk_mesh** pieces, bk_moments** moments, uint32_t* below_count,
                         split_failure* why) {
  bk_vec3 size = bk_v3_sub(node->bounds.max, node->bounds.min);
  // Cap uvs are world plane coordinates over the tile size; the local
  // origin's own uv (whole tiles dropped) keeps them so.
  bk_vec3 u = {0}, v = {0};
  bk_plane_basis(plane.normal, &u, &v);
  double origin_u = bk_v3_dot(frame->origin, u) / d->texture_scale;
  double origin_v = bk_v3_dot(frame->origin, v) / d->texture_scale;
  bk_slice_def slice = {.plane = plane,
                        .tolerance = 1e-9 * bk_v3_length(size),
                        .texture_scale = ldexp(d->texture_scale, -frame->exponent),
                        .uv_origin = {origin_u - floor(origin_u), origin_v - floor(origin_v)},
                        .cap_tag = node_index + 1};
  bk_mesh below = {0}, above = {0};
  if (!bk_slicer_slice(slicer, &node->mesh, &slice, &below, &above, NULL)) {
    *why = SPLIT_CAP_FAILED;
    return 0;
  }
  if (below.triangle_count == 0 || above.triangle_count == 0) {
    bk_mesh_free(&below);
    bk_mesh_free(&above);
    *why = SPLIT_MISSED;
    return 0;
  }
  bk_mesh *below_hulls = NULL, *above_hulls = NULL;
  *below_count = bk_mesh_split_hulls(&below, &below_hulls);
  uint32_t above_count = bk_mesh_split_hulls(&above, &above_hulls);
  uint32_t count = *below_count + above_count;
  *pieces = bk_realloc(below_hulls, sizeof(bk_mesh) * count);
  memcpy(*pieces + *below_count, above_hulls, sizeof(bk_mesh) * above_count);
  free(above_hulls);
  for (uint32_t i = 0; i < count; ++i)
    bk_face_simplifier_run(simplifier, &(*pieces)[i]);
  *moments = bk_realloc(*moments, sizeof(bk_moments) * count);
  if (pieces_hold(node, *pieces, count, *moments, why)) return count;
  free_pieces(*pieces, count);
  *pieces = NULL;
  return 0;
}

// Tries random planes through the centroid until one splits the node into
// pieces that hold (closed, volume kept) and are at most `allowed` (what the
// tree may still take without passing the pieces asked for); returns them,
// or 0 with *why set to how the last attempt failed. When every cut that
// holds makes more pieces than allowed (a concave piece, or one of separate
// shells), the one with fewest is taken and merged down to `allowed`. The
// first cut that holds and fits is taken at once, so a split that never
// made too many draws the same random numbers as it always did. Works in
// the tree's local frame.
static uint32_t split_node(bk_slicer* slicer, bk_face_simplifier* simplifier, const bk_mesh_tree_node* node,
                           uint32_t node_index, const bk_fracture_def* d, const bk_tree_frame* frame,
                           uint32_t allowed, bk_rng* rng, bk_plane* plane, bk_mesh** pieces,
                           bk_moments** moments, split_failure* why) {
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
  // The cut that held with the fewest pieces, all more than allowed.
  bk_mesh* fewest = NULL;
  bk_moments* fewest_moments = NULL;
  uint32_t fewest_count = 0, fewest_below = 0;
  bk_plane fewest_plane = {0};
  *why = SPLIT_MISSED;
  for (int attempt = 0; attempt < BK_FRACTURE_SPLIT_ATTEMPTS; ++attempt) {
    bk_vec3 n = bk_rng_direction(rng);
    if (d->aspect_bias > 0.0) {
      bk_vec3 tilt = bk_v3_scale(longest, bk_v3_dot(n, longest) < 0.0 ? -d->aspect_bias : d->aspect_bias);
      n = bk_v3_normalize(bk_v3_add(n, tilt));
    }
    // Extent of the piece along n, for the jitter.
    double extent = fabs(n.x) * size.x + fabs(n.y) * size.y + fabs(n.z) * size.z;
    double shift = d->jitter * extent * (bk_rng_unit(rng) - 0.5);
    *plane = (bk_plane){n, bk_v3_dot(n, mass.centroid) + shift};
    uint32_t below_count = 0;
    uint32_t count =
        cut_node(slicer, simplifier, node, node_index, d, frame, *plane, pieces, moments, &below_count, why);
    if (count == 0) continue;
    if (count <= allowed) {
      free_pieces(fewest, fewest_count);
      free(fewest_moments);
      return count;
    }
    if (fewest_count == 0 || count < fewest_count) {
      free_pieces(fewest, fewest_count);
      fewest = *pieces;
      fewest_moments = bk_realloc(fewest_moments, sizeof(bk_moments) * count);
      memcpy(fewest_moments, *moments, sizeof(bk_moments) * count);
      fewest_count = count;
      fewest_below = below_count;
      fewest_plane = *plane;
    } else {
      free_pieces(*pieces, count);
    }
    *pieces = NULL;
  }
  if (fewest_count == 0) return 0;
  *pieces = fewest;
  *plane = fewest_plane;
  *moments = bk_realloc(*moments, sizeof(bk_moments) * fewest_count);
  memcpy(*moments, fewest_moments, sizeof(bk_moments) * fewest_count);
  free(fewest_moments);
  return bk_merge_pieces(*pieces, *moments, fewest_count, fewest_below, node_index + 1, allowed);
}

// The brick pattern's split: a piece spanning several bricks is cut along
// the bond (an exact plane, no random draw), its pieces merged down to
// `allowed` when there are more (a concave source; merged pieces are still
// whole bricks). When the bond's cut does not hold (a tolerance failing on
// some odd source), the piece is cut by random planes like a single brick,
// so the build never sticks, and the fallback is counted. A piece within one
// brick is cut by random planes, as the planes pattern cuts.
static uint32_t split_bond(bk_slicer* slicer, bk_face_simplifier* simplifier, const bk_mesh_tree_node* node,
                           uint32_t node_index, const bk_fracture_def* d, const bk_tree_frame* frame,
                           const bk_brick_bond* bond, uint32_t allowed, bk_rng* rng, bk_plane* plane,
                           bk_mesh** pieces, bk_moments** moments, split_failure* why,
                           bk_fracture_shortfall* shortfall) {
  bk_vec3 centroid = bk_moments_to_mass(node->moments).centroid;
  if (bk_brick_bond_plane(bond, node->bounds, centroid, plane)) {
    uint32_t below_count = 0;
    uint32_t count =
        cut_node(slicer, simplifier, node, node_index, d, frame, *plane, pieces, moments, &below_count, why);
    if (count)
      return count <= allowed
                 ? count
                 : bk_merge_pieces(*pieces, *moments, count, below_count, node_index + 1, allowed);
    shortfall->bond_fallbacks++;
  }
  return split_node(slicer, simplifier, node, node_index, d, frame, allowed, rng, plane, pieces, moments,
                    why);
}

// Leaves waiting to be split, largest volume first (keys negated), ties by
// lower node index. With a brick bond, pieces that span several bricks wait
// in a heap of their own that is emptied first: the source parts along its
// mortar into whole bricks (or groups of them, with fewer pieces than
// bricks) before any brick is broken.
typedef struct leaf_queue {
  bk_heap within;            // pieces within one brick (every piece, without a bond)
  bk_heap across;            // pieces spanning several bricks
  const bk_brick_bond* bond; // NULL: the planes pattern
} leaf_queue;

static void queue_push(leaf_queue* q, const bk_mesh_tree_node* node, uint32_t index) {
  bk_plane plane = {0};
  bool across = q->bond && bk_brick_bond_plane(q->bond, node->bounds,
                                               bk_moments_to_mass(node->moments).centroid, &plane);
  bk_heap_push(across ? &q->across : &q->within, -node->moments.v, index);
}

static uint32_t queue_pop(leaf_queue* q) {
  return bk_heap_pop(q->across.count ? &q->across : &q->within).value;
}

static void count_shortfall(bk_fracture_shortfall* s, split_failure why) {
  s->uncut++;
  switch (why) {
  case SPLIT_MISSED:
    s->missed++;
    break;
  case SPLIT_CAP_FAILED:
    s->cap_failed++;
    break;
  case SPLIT_NOT_CLOSED:
    s->not_closed++;
    break;
  case SPLIT_VOLUME_CHANGED:
    s->volume_changed++;
    break;
  }
}

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
  if (largest / d->texture_scale > BK_FRACTURE_MAX_UV_TILES)
    return bk_error_set(err,
                        "texture_scale %g is too small for a mesh %g across: cut faces would span %.3g "
                        "texture tiles (at most %g)",
                        d->texture_scale, largest, largest / d->texture_scale, BK_FRACTURE_MAX_UV_TILES);
  return true;
}

bool bk_mesh_tree_build(const bk_mesh* source, const bk_fracture_def* desc_in, bk_mesh_tree* tree,
                        bk_error* err) {
  memset(tree, 0, sizeof *tree);
  if (!bk_fracture_def_validate(desc_in, err)) return false;
  bk_fracture_def d = *desc_in;
  if (!check_source(source, &d, err)) return false;
  if (d.pattern != BK_PATTERN_PLANES && d.pattern != BK_PATTERN_BRICK)
    return bk_cell_tree_build(source, &d, tree, err);

  // Everything is cut in the local frame (centred, about unit size) and moved
  // back to the source's coordinates at the end.
  bk_tree_frame frame = {0};
  bk_mesh root = {0};
  if (!bk_tree_frame_local_source(source, &frame, &root, err)) return false;
  double volume = bk_mesh_volume(&root);
  bk_aabb local_box = bk_mesh_bounds(&root);
  double area = bk_mesh_area(&root), size = bk_v3_length(bk_v3_sub(local_box.max, local_box.min));
  if (volume < BK_FRACTURE_MIN_THICKNESS * area * size) {
    bk_mesh_free(&root);
    return bk_error_set(err,
                        "mesh encloses almost no volume (%g for a surface of area %g): is it flat, or a "
                        "surface closed against its own back?",
                        ldexp(volume, 3 * frame.exponent), ldexp(area, 2 * frame.exponent));
  }
  bk_slicer* slicer = bk_slicer_create();
  if (!slicer) {
    bk_mesh_free(&root);
    return bk_error_set(err, "fracture: cannot create the cap tessellator");
  }
  bk_face_simplifier* simplifier = bk_face_simplifier_create();
  bk_rng rng = bk_rng_seed(d.seed, 0x62726b62u);
  uint32_t capacity = 0;
  // Tags identify cuts of this tree and planar faces of the source, which
  // lets each piece's faces be re-triangulated over their true corners.
  bk_label_planar_faces(&root);
  // Overlapping shells cannot be cut together: the root is split into them
  // first (see bk_fracture_overlap), and each is cut on its own below.
  bk_mesh* shell_parts = NULL;
  bk_fracture_overlap overlap = {0};
  uint32_t shell_part_count =
      d.pieces >= 2 ? bk_mesh_split_overlapping_shells(&root, &shell_parts, &overlap) : 0;
  add_node(tree, &capacity, &root, bk_mesh_moments(&root), BK_NULL_INDEX);

  bk_brick_bond bond = bk_brick_bond_of(&d, frame);
  leaf_queue queue = {.bond = d.pattern == BK_PATTERN_BRICK ? &bond : NULL};
  queue_push(&queue, &tree->nodes[0], 0);
  uint32_t leaves = 1;
  bool cancelled = false;
  bk_moments* moments = NULL; // of the pieces of the last cut, grown as needed
  while (leaves < d.pieces && (queue.within.count || queue.across.count)) {
    uint32_t split = queue_pop(&queue);
    bk_plane plane = {0};
    bk_mesh* pieces = NULL;
    split_failure why = SPLIT_MISSED;
    uint32_t count = 0;
    if (split == 0 && shell_part_count) {
      // The root's children are its overlapping shells (and the rest); no
      // cap carries the root's tag, so its plane is only a unit placeholder.
      moments = bk_realloc(moments, sizeof(bk_moments) * shell_part_count);
      if (pieces_hold(&tree->nodes[0], shell_parts, shell_part_count, moments, &why)) {
        pieces = shell_parts;
        // More shells than pieces asked for: the nearest are merged (no cut
        // made them, so all count as one side).
        count = bk_merge_pieces(shell_parts, moments, shell_part_count, shell_part_count, 0, d.pieces);
        plane = (bk_plane){{0, 0, 1}, 0};
        tree->overlap = overlap;
      } else {
        free_pieces(shell_parts, shell_part_count);
      }
      shell_parts = NULL;
      shell_part_count = 0;
    }
    if (count == 0 && queue.bond)
      count = split_bond(slicer, simplifier, &tree->nodes[split], split, &d, &frame, queue.bond,
                         d.pieces - leaves + 1, &rng, &plane, &pieces, &moments, &why, &tree->shortfall);
    else if (count == 0)
      count = split_node(slicer, simplifier, &tree->nodes[split], split, &d, &frame, d.pieces - leaves + 1,
                         &rng, &plane, &pieces, &moments, &why);
    if (count == 0) { // no cut held: stays a leaf
      count_shortfall(&tree->shortfall, why);
      continue;
    }
    uint32_t first = tree->node_count;
    for (uint32_t i = 0; i < count; ++i)
      add_node(tree, &capacity, &pieces[i], moments[i], split);
    free(pieces);
    bk_mesh_tree_node* node = &tree->nodes[split];
    node->plane = plane;
    node->first_child = first;
    node->child_count = count;
    leaves += count - 1;
    for (uint32_t i = 0; i < count; ++i)
      queue_push(&queue, &tree->nodes[first + i], first + i);
    if (d.progress && !d.progress(d.progress_user, leaves, d.pieces)) {
      cancelled = true;
      break;
    }
  }
  free_pieces(shell_parts, shell_part_count);
  free(moments);
  bk_heap_free(&queue.within);
  bk_heap_free(&queue.across);
  bk_slicer_destroy(slicer);
  bk_face_simplifier_destroy(simplifier);
  if (cancelled) {
    bk_mesh_tree_free(tree);
    return bk_error_set(err, "fracture cancelled");
  }
  // Back to the source's coordinates; the root keeps the source's own.
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    bk_mesh_tree_node* node = &tree->nodes[i];
    if (i == 0)
      memcpy(node->mesh.positions, source->positions, sizeof(bk_vec3) * source->position_count);
    else
      bk_tree_frame_to_world(frame, &node->mesh);
    node->bounds = bk_mesh_bounds(&node->mesh);
    node->moments = bk_tree_frame_moments_to_world(frame, node->moments);
    if (node->child_count) node->plane = bk_tree_frame_plane_to_world(frame, node->plane);
  }
  if (tree->overlap.pairs) { // named in the source's coordinates
    bk_fracture_overlap* o = &tree->overlap;
    o->volume_a = ldexp(o->volume_a, 3 * frame.exponent);
    o->volume_b = ldexp(o->volume_b, 3 * frame.exponent);
    o->point = bk_v3_add(bk_v3(ldexp(o->point.x, frame.exponent), ldexp(o->point.y, frame.exponent),
                               ldexp(o->point.z, frame.exponent)),
                         frame.origin);
  }
  bk_mesh_tree_number_leaves(tree);
  tree->source_hash = bk_mesh_hash(source);
  bk_fracture_def_clear_borrowed(&d);
  tree->desc = d;
  bk_mesh_tree_compute_bonds(tree);
  return true;
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
  if (tree->leaf_count >= tree->desc.pieces) return false;
  const bk_fracture_shortfall* s = &tree->shortfall;
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
