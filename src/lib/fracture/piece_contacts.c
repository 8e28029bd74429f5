// How a refined leaf's pieces touch the faces of its bonds with its
// neighbours (the measure bk_mesh_tree_splice divides each bond by), on the
// thread that made the pieces (bk_mesh_measure_piece_contacts) or at the
// splice. Three ways, the cheapest that is exact: when the leaf's side of
// the face is all in contact (its area is the bond's: cell patterns share
// faces exactly), a piece's contact is its triangles that are pieces of that
// side's (those in its plane when it is flat and no other triangle of the
// leaf is there, else those inside its triangles); when the neighbour's side
// is one flat convex polygon (a cell's face, a neighbour refined before
// covering part of it), the pieces' triangles in its plane are clipped
// against it; else every pair of facing triangles is clipped.
#include <string.h>

#include "mesh_contact.h"

void bk_piece_faces_make(const bk_mesh* leaf_mesh, bk_aabb tree_bounds, const bk_mesh_tree* pieces,
                         bk_piece_faces* out) {
  memset(out, 0, sizeof *out);
  out->tolerance = 1e-9 * bk_v3_length(bk_v3_sub(tree_bounds.max, tree_bounds.min)) + 1e-300;
  out->leaf_bounds = bk_mesh_bounds(leaf_mesh);
  out->piece_count = pieces->leaf_count;
  out->sides = bk_calloc(pieces->leaf_count + 1u, sizeof(bk_contact_side));
  for (uint32_t p = 0; p < pieces->leaf_count; ++p)
    bk_contact_side_gather(&bk_mesh_tree_leaf(pieces, p)->mesh, out->leaf_bounds, out->tolerance,
                           &out->sides[p]);
  bk_contact_side_gather(leaf_mesh, out->leaf_bounds, out->tolerance, &out->own);
}

void bk_piece_faces_measure(bk_piece_faces* f, const bk_mesh* neighbour, double bond_area,
                            bk_contact_measure* parts) {
  double tolerance = f->tolerance;
  // The neighbour's triangles on this face: those facing the leaf's own
  // (both sides taken where the two leaves' boxes meet).
  bk_contact_side other = {0}, near = {0};
  bk_contact_side_gather(neighbour, f->leaf_bounds, tolerance, &other);
  bk_contact_side_subset(&f->own, bk_mesh_bounds(neighbour), tolerance, &near);
  bk_contact_side_keep_facing(&other, &near, tolerance);
  bk_contact_side_keep_facing(&near, &other, tolerance);
  double own_area = bk_contact_side_area(&near);
  bool covered = fabs(own_area - bond_area) <= 1e-9 * bond_area;
  bk_plane plane = {{0, 0, 0}, 0};
  bool near_flat = bk_contact_side_plane(&near, tolerance, &plane);
  bool flat = covered && near_flat &&
              fabs(bk_contact_side_on_plane(&f->own, plane, tolerance).area - own_area) <= 1e-9 * own_area;
  bk_contact_outline outline = {0};
  bool outlined = !flat && near_flat && bk_contact_outline_make(&other, plane, tolerance, &outline);
  double total = 0.0;
  for (uint32_t p = 0; p < f->piece_count; ++p) {
    parts[p] = flat       ? bk_contact_side_on_plane(&f->sides[p], plane, tolerance)
               : outlined ? bk_contact_outline_clip(&f->sides[p], &outline, plane, tolerance)
               : covered  ? bk_contact_side_parts_of(&f->sides[p], &near, tolerance)
                          : bk_contact_sides_measure(&f->sides[p], &other, tolerance);
    total += parts[p].area;
  }
  bk_contact_outline_free(&outline);
  bk_contact_sides_free(&near);
  bk_contact_sides_free(&other);
  // Slivers of area from rounding at a face's rim are no contact.
  for (uint32_t p = 0; p < f->piece_count; ++p)
    if (!(parts[p].area > 1e-9 * total)) parts[p] = (bk_contact_measure){0};
}

void bk_piece_faces_free(bk_piece_faces* f) {
  for (uint32_t p = 0; f->sides && p < f->piece_count; ++p)
    bk_contact_sides_free(&f->sides[p]);
  bk_free(f->sides);
  bk_contact_sides_free(&f->own);
  memset(f, 0, sizeof *f);
}

void bk_mesh_measure_piece_contacts(const bk_mesh* leaf_mesh, bk_aabb tree_bounds, const bk_mesh_tree* pieces,
                                    const bk_piece_neighbour* neighbours, uint32_t count,
                                    bk_piece_contacts* out) {
  memset(out, 0, sizeof *out);
  if (!leaf_mesh || !pieces || !pieces->leaf_count || (count && !neighbours)) return;
  out->neighbour_count = count;
  out->piece_count = pieces->leaf_count;
  out->nodes = bk_alloc(sizeof(uint32_t) * (count + 1u));
  out->bond_areas = bk_alloc(sizeof(double) * (count + 1u));
  out->parts = bk_calloc((size_t)count * pieces->leaf_count + 1u, sizeof(bk_contact_measure));
  bk_piece_faces faces = {0};
  bk_piece_faces_make(leaf_mesh, tree_bounds, pieces, &faces);
  for (uint32_t i = 0; i < count; ++i) {
    out->nodes[i] = neighbours[i].node;
    out->bond_areas[i] = neighbours[i].bond_area;
    bk_piece_faces_measure(&faces, &neighbours[i].mesh, neighbours[i].bond_area,
                           &out->parts[(size_t)i * pieces->leaf_count]);
  }
  bk_piece_faces_free(&faces);
}

void bk_piece_contacts_free(bk_piece_contacts* contacts) {
  if (!contacts) return;
  bk_free(contacts->nodes);
  bk_free(contacts->bond_areas);
  bk_free(contacts->parts);
  memset(contacts, 0, sizeof *contacts);
}
