// One split of the planes and brick patterns: random planes through the
// piece's centroid (tilted towards its longest axis, shifted by the jitter)
// until the pieces hold, or the brick bond's plane for a piece spanning
// several bricks. Each node draws from its own generator, so the result
// does not depend on which thread splits it or when.
#include <stdlib.h>
#include <string.h>

#include "plane_split.h"

struct bk_plane_splitter {
  bk_slicer* slicer;
  bk_face_simplifier* simplifier;
  bk_topology_scratch topology; // hull and closure tests
  bk_mesh sides[2];             // what the slicer makes, kept between cuts
};

bk_plane_splitter* bk_plane_splitter_create(void) {
  bk_slicer* slicer = bk_slicer_create();
  if (!slicer) return NULL;
  bk_plane_splitter* s = bk_calloc(1, sizeof *s);
  s->slicer = slicer;
  s->simplifier = bk_face_simplifier_create();
  return s;
}

void bk_plane_splitter_destroy(bk_plane_splitter* s) {
  if (!s) return;
  bk_slicer_destroy(s->slicer);
  bk_face_simplifier_destroy(s->simplifier);
  bk_topology_scratch_free(&s->topology);
  bk_mesh_free(&s->sides[0]);
  bk_mesh_free(&s->sides[1]);
  bk_free(s);
}

static void free_pieces(bk_mesh* pieces, uint32_t count) {
  for (uint32_t i = 0; i < count; ++i)
    bk_mesh_free(&pieces[i]);
  bk_free(pieces);
}

void bk_plane_split_free(bk_plane_split* split) {
  free_pieces(split->pieces, split->count);
  bk_free(split->moments);
  split->pieces = NULL;
  split->moments = NULL;
  split->count = 0;
}

// A cut holds when every piece is a closed solid and the pieces' volumes add
// up to the whole's within 1e-11 of it. Rounding in cut points and
// re-triangulated faces stays far below that (about 1e-15 on ordinary
// pieces), while a cap that overlaps itself or a sliver whose sides crossed
// after snapping to the plane is far above it. A tree is at most a few dozen
// levels deep, so its leaves add up to the source within 1e-9.
bool bk_plane_pieces_hold(const bk_mesh_tree_node* node, const bk_mesh* pieces, uint32_t count,
                          bk_moments* moments, bk_split_failure* why, bk_topology_scratch* scratch) {
  double sum = 0.0;
  for (uint32_t i = 0; i < count; ++i) {
    if (!bk_mesh_is_closed_with(&pieces[i], scratch)) {
      *why = BK_SPLIT_NOT_CLOSED;
      return false;
    }
    moments[i] = bk_mesh_moments(&pieces[i]);
    double v = moments[i].v;
    if (!(v > 0.0)) {
      *why = BK_SPLIT_VOLUME_CHANGED;
      return false;
    }
    // A piece that encloses no volume (a face closed against its own back,
    // 1e-18 m^3 for half a metre across) is never a fragment.
    if (bk_mesh_encloses_no_volume(&pieces[i], v)) {
      *why = BK_SPLIT_NO_VOLUME;
      return false;
    }
    // A piece of a surface that crosses itself can enclose volume and still
    // not be a solid (its centre of mass outside it, a negative principal
    // moment): no body can be made of it, so another plane is tried.
    if (!bk_solid_mass_check(&moments[i], bk_v3(0, 0, 0), bk_mesh_bounds(&pieces[i]), false, "piece", NULL)) {
      *why = BK_SPLIT_NOT_SOLID;
      return false;
    }
    sum += v;
  }
  if (!(fabs(sum - node->moments.v) <= BK_FRACTURE_SPLIT_VOLUME_TOLERANCE * node->moments.v)) {
    *why = BK_SPLIT_VOLUME_CHANGED;
    return false;
  }
  return true;
}

// The solid shells of one side of a cut, their faces re-triangulated, after
// the `*count` pieces of `*pieces` (room for `*capacity`). Nearly every side
// is one piece, simplified straight from the slicer's storage.
static void add_side(bk_plane_splitter* s, const bk_mesh* side, bk_mesh** pieces, uint32_t* count,
                     uint32_t* capacity) {
  bk_mesh* hulls = NULL;
  uint32_t hull_count = 0;
  if (!bk_mesh_is_connected_with(side, &s->topology)) {
    bk_mesh copy = {0}; // taken by bk_mesh_split_hulls
    bk_mesh_copy(&copy, side);
    hull_count = bk_mesh_split_hulls(&copy, &hulls);
  }
  uint32_t add = hull_count ? hull_count : 1;
  if (*count + add > *capacity) {
    *capacity = bk_grow_capacity(*capacity, *count + add);
    *pieces = bk_realloc(*pieces, sizeof(bk_mesh) * *capacity);
  }
  for (uint32_t i = 0; i < add; ++i)
    bk_face_simplifier_run(s->simplifier, hull_count ? &hulls[i] : side, &(*pieces)[(*count)++]);
  for (uint32_t i = 0; i < hull_count; ++i)
    bk_mesh_free(&hulls[i]);
  bk_free(hulls);
}

// Pieces that enclose no volume (a sheet of the source cut with the rest)
// join the nearest piece that does (by the centres of their bounds), on
// their own side of the cut when it has one, so they are never fragments
// of their own. Updates *count and *below_count; returns how many joined
// (0, nothing changed, when no piece encloses volume).
static uint32_t merge_sheets(bk_mesh* pieces, uint32_t* count, uint32_t* below_count) {
  uint32_t n = *count, merged = 0, kept = 0, kept_below = 0;
  uint8_t* sheet = bk_calloc(n + 1u, 1);
  bk_vec3* centre = bk_alloc(sizeof(bk_vec3) * (n + 1u));
  bool solid = false;
  for (uint32_t i = 0; i < n; ++i) {
    bk_aabb box = bk_mesh_bounds(&pieces[i]);
    centre[i] = bk_v3_scale(bk_v3_add(box.min, box.max), 0.5);
    sheet[i] = bk_mesh_encloses_no_volume(&pieces[i], bk_mesh_volume(&pieces[i]));
    solid = solid || !sheet[i];
  }
  for (uint32_t i = 0; i < n && solid; ++i) {
    if (!sheet[i]) continue;
    uint32_t best = UINT32_MAX;
    double best_distance = INFINITY;
    for (int pass = 0; pass < 2 && best == UINT32_MAX; ++pass) // own side first
      for (uint32_t j = 0; j < n; ++j) {
        if (sheet[j] || (pass == 0 && (j < *below_count) != (i < *below_count))) continue;
        double d = bk_v3_length(bk_v3_sub(centre[j], centre[i]));
        if (d < best_distance) best_distance = d, best = j;
      }
    bk_mesh_append(&pieces[best], &pieces[i]);
    bk_mesh_free(&pieces[i]);
    merged++;
  }
  for (uint32_t i = 0; i < n && merged; ++i) {
    if (sheet[i]) continue;
    kept_below += i < *below_count;
    pieces[kept++] = pieces[i];
  }
  if (merged) *count = kept, *below_count = kept_below;
  bk_free(sheet);
  bk_free(centre);
  return merged;
}

// Cuts a node by one plane (local frame) into the solid shells on each side,
// their faces re-triangulated; returns how many, *below_count of them below
// the plane, or 0 (nothing allocated) with *why set when the plane misses
// the node or the pieces do not hold.
static uint32_t cut_node(bk_plane_splitter* s, const bk_plane_split_context* ctx,
                         const bk_mesh_tree_node* node, uint32_t node_index, bk_plane plane, bk_mesh** pieces,
                         bk_moments** moments, uint32_t* below_count, bk_split_failure* why,
                         uint32_t* sheets_merged) {
  const bk_fracture_def* d = ctx->def;
  const bk_tree_frame* frame = ctx->frame;
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
                        .cap_tag = node_index + 1,
                        .noise_amplitude = ldexp(d->noise_amplitude, -frame->exponent),
                        .noise_frequency = ldexp(d->noise_frequency, frame->exponent),
                        .noise_seed = d->seed * 0x9e3779b97f4a7c15ull + node_index};
  bk_mesh *below = &s->sides[0], *above = &s->sides[1];
  if (!bk_slicer_slice_reuse(s->slicer, &node->mesh, &slice, below, above, NULL)) {
    *why = BK_SPLIT_CAP_FAILED;
    return 0;
  }
  if (below->triangle_count == 0 || above->triangle_count == 0) {
    *why = BK_SPLIT_MISSED;
    return 0;
  }
  // Noisy cut faces are not planar: only the source's planar faces are redone.
  bk_face_simplifier_keep_cuts(s->simplifier, d->noise_amplitude > 0.0);
  uint32_t count = 0, capacity = 2;
  *pieces = bk_alloc(sizeof(bk_mesh) * capacity);
  add_side(s, below, pieces, &count, &capacity);
  *below_count = count;
  add_side(s, above, pieces, &count, &capacity);
  *moments = bk_realloc(*moments, sizeof(bk_moments) * count);
  if (bk_plane_pieces_hold(node, *pieces, count, *moments, why, &s->topology)) return count;
  if (*why == BK_SPLIT_NO_VOLUME) {
    uint32_t merged = merge_sheets(*pieces, &count, below_count);
    // A sheet alone on its side of the cut joined the other side: the
    // plane cut nothing else there.
    bool both_sides = *below_count > 0 && *below_count < count;
    if (merged && both_sides && bk_plane_pieces_hold(node, *pieces, count, *moments, why, &s->topology)) {
      *sheets_merged = merged;
      return count;
    }
    if (merged && !both_sides) *why = BK_SPLIT_MISSED;
  }
  free_pieces(*pieces, count);
  *pieces = NULL;
  return 0;
}

// Random planes through the centroid until one splits the node into pieces
// that hold and are at most `allowed` (what the tree may still take without
// passing the pieces asked for). When every cut that holds makes more (a
// concave piece, or one of separate shells), the one with fewest is taken and
// merged down to `allowed`. The first cut that holds and fits is taken at
// once, so a result computed with a larger `allowed` is the same whenever it
// fits the smaller one (the build relies on this to split ahead).
static void split_random(bk_plane_splitter* s, const bk_plane_split_context* ctx,
                         const bk_mesh_tree_node* node, uint32_t node_index, uint32_t allowed,
                         bk_plane_split* out) {
  const bk_fracture_def* d = ctx->def;
  bk_rng rng = bk_rng_seed(d->seed, ((uint64_t)0x62726b62u << 32) | node_index);
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
  bk_plane_split fewest = {0};
  uint32_t fewest_below = 0;
  out->why = BK_SPLIT_MISSED;
  for (int attempt = 0; attempt < BK_FRACTURE_SPLIT_ATTEMPTS; ++attempt) {
    bk_vec3 n = bk_rng_direction(&rng);
    if (d->aspect_bias > 0.0) {
      bk_vec3 tilt = bk_v3_scale(longest, bk_v3_dot(n, longest) < 0.0 ? -d->aspect_bias : d->aspect_bias);
      n = bk_v3_normalize(bk_v3_add(n, tilt));
    }
    // Extent of the piece along n, for the jitter.
    double extent = fabs(n.x) * size.x + fabs(n.y) * size.y + fabs(n.z) * size.z;
    double shift = d->jitter * extent * (bk_rng_unit(&rng) - 0.5);
    bk_plane plane = {n, bk_v3_dot(n, mass.centroid) + shift};
    bk_mesh* pieces = NULL;
    bk_moments* moments = NULL;
    uint32_t below_count = 0, sheets = 0;
    uint32_t count =
        cut_node(s, ctx, node, node_index, plane, &pieces, &moments, &below_count, &out->why, &sheets);
    if (count == 0) {
      bk_free(moments);
      continue;
    }
    if (count <= allowed) {
      bk_plane_split_free(&fewest);
      *out = (bk_plane_split){pieces, moments, count, plane, out->why, out->bond_fallbacks, sheets};
      return;
    }
    if (fewest.count == 0 || count < fewest.count) {
      bk_plane_split_free(&fewest);
      fewest = (bk_plane_split){pieces, moments, count, plane, BK_SPLIT_MISSED, 0, sheets};
      fewest_below = below_count;
    } else {
      free_pieces(pieces, count);
      bk_free(moments);
    }
  }
  if (fewest.count == 0) return;
  out->pieces = fewest.pieces;
  out->moments = fewest.moments;
  out->plane = fewest.plane;
  out->sheets_merged = fewest.sheets_merged;
  out->count =
      bk_merge_pieces(fewest.pieces, fewest.moments, fewest.count, fewest_below, node_index + 1, allowed);
}

void bk_plane_split_node(bk_plane_splitter* s, const bk_plane_split_context* ctx,
                         const bk_mesh_tree_node* node, uint32_t node_index, uint32_t allowed,
                         bk_plane_split* out) {
  *out = (bk_plane_split){.why = BK_SPLIT_MISSED};
  // A piece spanning several bricks is cut along the bond (an exact plane,
  // no random draw), its pieces merged down to `allowed` when there are
  // more (a concave source; merged pieces are still whole bricks). When the
  // bond's cut does not hold (a tolerance failing on some odd source), the
  // piece is cut by random planes like a single brick, so the build never
  // sticks, and the fallback is counted.
  if (ctx->bond &&
      bk_brick_bond_plane(ctx->bond, node->bounds, bk_moments_to_mass(node->moments).centroid, &out->plane)) {
    uint32_t below_count = 0;
    uint32_t count = cut_node(s, ctx, node, node_index, out->plane, &out->pieces, &out->moments, &below_count,
                              &out->why, &out->sheets_merged);
    if (count) {
      out->count = count <= allowed ? count
                                    : bk_merge_pieces(out->pieces, out->moments, count, below_count,
                                                      node_index + 1, allowed);
      return;
    }
    bk_free(out->moments);
    out->moments = NULL;
    out->bond_fallbacks = 1;
  }
  split_random(s, ctx, node, node_index, allowed, out);
}
