// Repair of meshes from art tools before fracture: shells touching at a
// vertex or an edge are split apart (bk_mesh_split_nonmanifold), simple
// holes are filled (bk_mesh_fill_holes), and what still is not closed is
// refused with the count of bad edges and where the first one is.
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

static uint32_t find_root(uint32_t* parent, uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

// Connected components by shared positions.
static uint32_t count_shells(const bk_mesh* m) {
  uint32_t* parent = bk_alloc(sizeof(uint32_t) * (m->position_count + 1u));
  for (uint32_t i = 0; i < m->position_count; ++i)
    parent[i] = i;
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 1; k < 3; ++k) {
      uint32_t a = find_root(parent, bk_mesh_tri_position(m, t, 0)),
               b = find_root(parent, bk_mesh_tri_position(m, t, k));
      if (a != b) parent[a > b ? a : b] = a < b ? a : b;
    }
  uint8_t* used = bk_calloc(m->position_count + 1u, 1);
  uint32_t shells = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    uint32_t r = find_root(parent, bk_mesh_tri_position(m, t, 0));
    if (!used[r]) used[r] = 1, shells++;
  }
  bk_free(used);
  bk_free(parent);
  return shells;
}

// How many triangles use each directed edge (keyed by bk_directed_edge_key).
static void count_directed_edges(const bk_mesh* m, bk_index_map* edges) {
  bk_index_map_init(edges, 3u * m->triangle_count);
  for (uint32_t t = 0; t < m->triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      bool inserted = false;
      uint32_t* uses = bk_index_map_insert(
          edges, bk_directed_edge_key(bk_mesh_tri_position(m, t, k), bk_mesh_tri_position(m, t, (k + 1) % 3)),
          0, &inserted);
      ++*uses;
    }
}

// Midpoint of the first directed edge (in triangle order) that has no
// opposite (open) or shares its direction with another (overused).
static bk_vec3 first_bad_edge(const bk_mesh* m, bool overused) {
  bk_index_map edges = {0};
  count_directed_edges(m, &edges);
  bk_vec3 where = bk_v3(NAN, NAN, NAN);
  for (uint32_t t = 0; t < m->triangle_count && isnan(where.x); ++t)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      bool bad = overused ? (a == b || *bk_index_map_find(&edges, bk_directed_edge_key(a, b)) > 1)
                          : !bk_index_map_find(&edges, bk_directed_edge_key(b, a));
      if (bad) {
        where = bk_v3_scale(bk_v3_add(m->positions[a], m->positions[b]), 0.5);
        break;
      }
    }
  bk_index_map_free(&edges);
  return where;
}

// Turns every triangle wound against all its neighbours: one of its
// directed edges is used the same way by another triangle, and none of them
// reversed is, so turned it closes its shell where before the shell split
// off a zero-volume pair of it and its own back. (Coincident faces of shells
// that touch use their edges both ways and are left to the split.) Returns
// how many were turned.
static uint32_t turn_flipped_faces(bk_mesh* m) {
  bk_index_map edges = {0};
  count_directed_edges(m, &edges);
  // Decided on the counts before any turn, so the result does not depend on
  // the triangles' order.
  uint8_t* turn = bk_calloc(m->triangle_count + 1u, 1);
  uint32_t turned = 0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    uint32_t same = 0, reversed = 0, degenerate = 0;
    for (int k = 0; k < 3; ++k) {
      uint32_t a = bk_mesh_tri_position(m, t, k), b = bk_mesh_tri_position(m, t, (k + 1) % 3);
      degenerate += a == b; // left to the closure check
      same += *bk_index_map_find(&edges, bk_directed_edge_key(a, b)) > 1;
      reversed += bk_index_map_find(&edges, bk_directed_edge_key(b, a)) != NULL;
    }
    if (same > 0 && reversed == 0 && degenerate == 0) turn[t] = 1, turned++;
  }
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    if (!turn[t]) continue;
    uint32_t swap = m->indices[3 * t + 1];
    m->indices[3 * t + 1] = m->indices[3 * t + 2];
    m->indices[3 * t + 2] = swap;
  }
  bk_free(turn);
  bk_index_map_free(&edges);
  return turned;
}

bool bk_mesh_repair(bk_mesh* m, bk_repair_info* info_out, bk_error* err) {
  bk_repair_info scratch;
  bk_repair_info* info = info_out ? info_out : &scratch;
  memset(info, 0, sizeof *info);
  if (m->triangle_count == 0) return bk_error_set(err, "mesh has no triangles");
  info->duplicates_removed = bk_mesh_remove_duplicate_triangles(m);
  info->faces_turned = turn_flipped_faces(m);
  info->faces_turned += bk_mesh_turn_flipped_patches(m);
  info->positions_split = bk_mesh_split_nonmanifold(m);
  bk_closure closure = bk_mesh_check_closure(m);
  info->open_edges = closure.open_edges;
  if (closure.overused_edges || closure.degenerate_edges) {
    bk_vec3 p = first_bad_edge(m, true);
    return bk_error_set(err,
                        "mesh is not watertight: %u edges used twice in one direction (overlapping or "
                        "inconsistently wound surfaces), the first near (%g, %g, %g)",
                        closure.overused_edges + closure.degenerate_edges, p.x, p.y, p.z);
  }
  if (closure.open_edges) {
    bk_vec3 p = first_bad_edge(m, false);
    bk_error fill_err = {0};
    int filled = bk_mesh_fill_holes(m, &fill_err);
    if (filled < 0)
      return bk_error_set(
          err,
          "mesh is not watertight (%u open edges, the first near (%g, %g, %g)) and cannot be repaired: %s",
          closure.open_edges, p.x, p.y, p.z, fill_err.message);
    info->holes_closed = (uint32_t)filled;
    // A sheet (a plane, a single-sided surface) closes against its own back.
    bk_aabb box = bk_mesh_bounds(m);
    double size = bk_v3_length(bk_v3_sub(box.max, box.min));
    if (fabs(bk_mesh_volume(m)) <= BK_FRACTURE_MIN_THICKNESS * bk_mesh_area(m) * size)
      return bk_error_set(
          err,
          "mesh is an open surface enclosing no volume (a sheet: %u open edges, the first near (%g, "
          "%g, %g)); it needs thickness to be fractured",
          closure.open_edges, p.x, p.y, p.z);
  }
  // What a repair closed against its own back (a face given twice the
  // other way round, a stray sheet) encloses nothing: never a fragment.
  info->sheets_removed = bk_mesh_remove_sheets(m, &info->sheet_near);
  info->shells = count_shells(m);
  return true;
}
