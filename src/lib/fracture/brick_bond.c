// The brick bond as cutting planes (see brick_bond.h).
#include "brick_bond.h"

/// One family of parallel bond planes: world coordinate
/// origin + (k + shift) * spacing along `axis`, for every integer k.
typedef struct bond_axis {
  int axis; ///< 0 = x, 1 = y, 2 = z
  double origin, spacing, shift;
} bond_axis;

static double component(bk_vec3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

bk_brick_bond bk_brick_bond_of(const bk_fracture_def* def, bk_tree_frame frame) {
  return (bk_brick_bond){
      .frame = frame, .size = def->brick_size, .origin = def->brick_origin, .offset = def->brick_offset};
}

// Plane k's local coordinate, moved from the world exactly as the tree frame
// moves positions: a plane through source vertices (a wall's base on a
// mortar line) passes through their local copies too.
static double plane_local(const bk_brick_bond* b, bond_axis g, double k) {
  double world = g.origin + (k + g.shift) * g.spacing;
  return ldexp(world - component(b->frame.origin, g.axis), -b->frame.exponent);
}

// The real-valued plane index at a local coordinate (k where it lies on plane k).
static double plane_index(const bk_brick_bond* b, bond_axis g, double local) {
  double world = ldexp(local, b->frame.exponent) + component(b->frame.origin, g.axis);
  return (world - g.origin) / g.spacing - g.shift;
}

// How many one-plane steps the search for the first and last plane inside
// may take: the index estimates are off by at most one, so a few suffice,
// and a bond so fine that planes fall within rounding of each other stops
// here (the piece is then cut as one brick) instead of stepping for ever.
enum { MAX_INDEX_STEPS = 4 };

// The plane of family g nearest `centre` among those inside (lo, hi) by more
// than a margin, in local units: far above the cut tolerance (1e-9 of the
// piece's size), so the plane always splits the piece, and far above rounding
// in cut points, so the pieces of an earlier cut by a neighbouring plane are
// never taken to span it; far below a brick. False when none is inside.
static bool nearest_inside(const bk_brick_bond* b, bond_axis g, double lo, double hi, double centre,
                           double piece_size, double* at) {
  double margin = fmax(1e-6 * ldexp(g.spacing, -b->frame.exponent), 1e-7 * piece_size);
  if (!(hi - lo > 2.0 * margin)) return false;
  // One below the estimate (and one above at the top), then inwards to the
  // first plane that is inside: rounding in the estimate never skips one.
  double first = floor(plane_index(b, g, lo + margin)) - 1.0;
  for (int step = 0; step < MAX_INDEX_STEPS && plane_local(b, g, first) <= lo + margin; ++step)
    first += 1.0;
  double last = ceil(plane_index(b, g, hi - margin)) + 1.0;
  for (int step = 0; step < MAX_INDEX_STEPS && plane_local(b, g, last) >= hi - margin; ++step)
    last -= 1.0;
  if (plane_local(b, g, first) <= lo + margin || plane_local(b, g, last) >= hi - margin || first > last)
    return false;
  // Planes are evenly spaced, so the nearest to the centre, clamped to the
  // planes inside, is the nearest inside.
  double k = fmin(fmax(nearbyint(plane_index(b, g, centre)), first), last);
  *at = plane_local(b, g, k);
  return true;
}

static bool axis_plane(int axis, double at, bk_plane* plane) {
  *plane = (bk_plane){{axis == 0, axis == 1, axis == 2}, at};
  return true;
}

bool bk_brick_bond_plane(const bk_brick_bond* b, bk_aabb box, bk_vec3 centroid, bk_plane* plane) {
  double piece_size = bk_v3_length(bk_v3_sub(box.max, box.min));
  double at = 0.0;
  // Mortar before head joints: courses part first, as a wall breaks.
  bond_axis mortar = {1, b->origin.y, b->size.y, 0.0};
  if (nearest_inside(b, mortar, box.min.y, box.max.y, centroid.y, piece_size, &at))
    return axis_plane(1, at, plane);
  // Within one course (its middle names it), whose head joints are shifted
  // by the course's own fraction of a brick.
  double course = floor(plane_index(b, mortar, 0.5 * (box.min.y + box.max.y)));
  double shift = course * b->offset - floor(course * b->offset);
  bond_axis head = {0, b->origin.x, b->size.x, shift};
  bond_axis depth = {2, b->origin.z, b->size.z, 0.0};
  // Along the side that spans more bricks first, so the groups stay compact;
  // a depth of 0 has no planes (bricks go through the whole source).
  bool has_depth = b->size.z > 0.0;
  bool depth_first = has_depth && (box.max.z - box.min.z) / b->size.z > (box.max.x - box.min.x) / b->size.x;
  bond_axis order[2] = {depth_first ? depth : head, depth_first ? head : depth};
  for (int i = 0; i < 1 + has_depth; ++i) {
    bond_axis g = order[i];
    if (nearest_inside(b, g, component(box.min, g.axis), component(box.max, g.axis),
                       component(centroid, g.axis), piece_size, &at))
      return axis_plane(g.axis, at, plane);
  }
  return false;
}
