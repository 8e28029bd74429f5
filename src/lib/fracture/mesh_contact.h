// Internal: contacts between closed meshes measured triangle pair by pair
// (mesh_contact.c), the parts bk_mesh_contact is made of, so a refinement can
// gather one neighbour's triangles once and measure every piece against them.
#pragma once

#include "bk_fracture.h"

/// A triangle's plane and box, measured once.
typedef struct tri_info {
  bk_vec3 p[3];
  bk_vec3 normal; // unit
  double offset;  // normal . p = offset
  bk_aabb box;
} tri_info;

/// A polygon's area (> 0 when counter-clockwise) and centroid in the plane
/// frame (origin, u, v), lifted back into space; false when it has none.
bool bk_polygon_lift(const double (*points)[2], uint32_t n, bk_vec3 origin, bk_vec3 u, bk_vec3 v,
                     double* area, bk_vec3* centroid);

/// Whether a triangle lies in a plane (its corners within tolerance of it),
/// facing the plane's normal side.
static inline bool bk_tri_on_plane(const tri_info* t, bk_plane plane, double tolerance) {
  bool on = bk_v3_dot(t->normal, plane.normal) > 0.0;
  for (int k = 0; k < 3 && on; ++k)
    on = fabs(bk_plane_distance(plane, t->p[k])) <= tolerance;
  return on;
}

/// A contact from its sums: area, area-weighted centroid and normal (zero
/// when there is no area).
bk_contact_measure bk_contact_finish(double area, bk_vec3 moment, bk_vec3 normal);

/// One mesh's interior triangles near a region, with their planes and boxes.
typedef struct bk_contact_side {
  void* tris; // tri_info (mesh_contact.c)
  uint32_t count;
  bk_aabb box; // of the triangles kept
} bk_contact_side;

/// The interior triangles of `mesh` whose boxes touch `within`.
void bk_contact_side_gather(const bk_mesh* mesh, bk_aabb within, double tolerance, bk_contact_side* out);
/// The triangles of `from` whose boxes touch `within`.
void bk_contact_side_subset(const bk_contact_side* from, bk_aabb within, double tolerance,
                            bk_contact_side* out);
/// Keeps only the triangles of `side` that face one of `other`'s (a smaller
/// set to measure many meshes against).
void bk_contact_side_keep_facing(bk_contact_side* side, const bk_contact_side* other, double tolerance);
/// The contact of the two sides' triangles (area 0: none); normal from a to b.
bk_contact_measure bk_contact_sides_measure(const bk_contact_side* a, const bk_contact_side* b,
                                            double tolerance);
/// The total area of a side's triangles.
double bk_contact_side_area(const bk_contact_side* side);
/// The part of `a` made of pieces of `on`'s triangles: each triangle of `a`
/// whose centroid lies inside a triangle of `on` facing the same way counts
/// whole (a refined leaf's pieces' triangles on a face are pieces of the
/// leaf's own triangles there); normal a's.
bk_contact_measure bk_contact_side_parts_of(const bk_contact_side* a, const bk_contact_side* on,
                                            double tolerance);
/// Whether all of a side's triangles lie in one plane (within tolerance),
/// facing one way: that plane, its normal theirs.
bool bk_contact_side_plane(const bk_contact_side* side, double tolerance, bk_plane* plane);
/// The part of `a` in a plane: its triangles whose corners lie on it
/// (within tolerance), facing its normal.
bk_contact_measure bk_contact_side_on_plane(const bk_contact_side* a, bk_plane plane, double tolerance);
void bk_contact_sides_free(bk_contact_side* side);

/// A flat side's outline, when its triangles make one convex polygon
/// (contact_outline.c): counter-clockwise seen from `plane`'s normal side.
typedef struct bk_contact_outline {
  bk_vec3 origin, u, v; // the plane's frame
  double (*points)[2];
  uint32_t count;
  double lo[2], hi[2]; // its box
} bk_contact_outline;
/// False when the triangles' boundary is not one convex loop.
bool bk_contact_outline_make(const bk_contact_side* side, bk_plane plane, double tolerance,
                             bk_contact_outline* out);
/// The part of `a`'s triangles in the plane (facing its normal) inside the outline.
bk_contact_measure bk_contact_outline_clip(const bk_contact_side* a, const bk_contact_outline* outline,
                                           bk_plane plane, double tolerance);
void bk_contact_outline_free(bk_contact_outline* outline);

/// A refined leaf's pieces' sides and its own, gathered once to measure
/// each of its bonds' faces (piece_contacts.c).
typedef struct bk_piece_faces {
  bk_contact_side* sides; // per piece
  uint32_t piece_count;
  bk_contact_side own;
  bk_aabb leaf_bounds;
  double tolerance;
} bk_piece_faces;
void bk_piece_faces_make(const bk_mesh* leaf_mesh, bk_aabb tree_bounds, const bk_mesh_tree* pieces,
                         bk_piece_faces* out);
/// Each piece's contact with the face of the leaf's bond of `bond_area`
/// with `neighbour` (slivers of area from rounding dropped) into parts.
void bk_piece_faces_measure(bk_piece_faces* faces, const bk_mesh* neighbour, double bond_area,
                            bk_contact_measure* parts);
void bk_piece_faces_free(bk_piece_faces* faces);
