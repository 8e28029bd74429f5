// The brick pattern: a wall parts along the mortar of its brick bond. With
// fewer pieces than bricks every piece is a group of whole bricks; with as
// many or more, every brick is separate before any is broken, so every
// fragment lies within one brick. Trees stay exact (piece count, closed
// nodes, volume), bonds join touching fragments only, the same def gives the
// same bytes, and the course offset moves the head joints. The grid here is
// computed on its own, in world units, so it checks the builder's.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"
#include "tree_bytes.h"

// World units: a point within this of a bond plane lies on it.
#define ON_PLANE 1e-9

// The bond that lines up with the brick texture on the "wall" shape: the
// texture tile is 1 m square (BOX_UV_METRES, uv_scale 1) with 8 courses of 4
// bricks, odd courses shifted half a brick, course 0 starting at v = 0 (the
// wall's base).
static bk_fracture_def wall_def(uint32_t pieces) {
  bk_fracture_def d = bk_default_fracture_def();
  d.pattern = BK_PATTERN_BRICK;
  d.pieces = pieces;
  d.aspect_bias = 1.5; // as the wall scene cuts
  d.brick_size = bk_v3(0.25, 0.125, 0.0);
  d.brick_origin = bk_v3(0.0, 0.0, 0.0);
  d.brick_offset = 0.5;
  return d;
}

static bk_mesh_tree build(const bk_mesh* source, const bk_fracture_def* d) {
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(source, d, &tree, &err), "%s", err.message);
  return tree;
}

// ---------------------------------------------------------------- the grid

// Course k's head joints are shifted by frac(k * offset) of a brick.
static double course_shift(const bk_fracture_def* d, double course) {
  return course * d->brick_offset - floor(course * d->brick_offset);
}

// The course holding height y.
static double course_of(const bk_fracture_def* d, double y) {
  return floor((y - d->brick_origin.y) / d->brick_size.y);
}

// The brick cell holding point p (unbounded: the source clips it); with no
// depth, bricks go through the whole source (z unbounded).
static bk_aabb brick_at(const bk_fracture_def* d, bk_vec3 p) {
  bk_vec3 o = d->brick_origin, s = d->brick_size;
  double k = course_of(d, p.y), shift = course_shift(d, k);
  double m = floor((p.x - o.x) / s.x - shift);
  bk_aabb box = {{o.x + (m + shift) * s.x, o.y + k * s.y, -INFINITY},
                 {o.x + (m + shift + 1.0) * s.x, o.y + (k + 1.0) * s.y, INFINITY}};
  if (s.z > 0.0) {
    double j = floor((p.z - o.z) / s.z);
    box.min.z = o.z + j * s.z;
    box.max.z = o.z + (j + 1.0) * s.z;
  }
  return box;
}

static bk_vec3 box_centre(bk_aabb b) { return bk_v3_scale(bk_v3_add(b.min, b.max), 0.5); }

static bool box_inside(bk_aabb inner, bk_aabb outer, double tol) {
  return inner.min.x >= outer.min.x - tol && inner.max.x <= outer.max.x + tol &&
         inner.min.y >= outer.min.y - tol && inner.max.y <= outer.max.y + tol &&
         inner.min.z >= outer.min.z - tol && inner.max.z <= outer.max.z + tol;
}

static bk_aabb box_clip(bk_aabb a, bk_aabb b) {
  return (bk_aabb){{fmax(a.min.x, b.min.x), fmax(a.min.y, b.min.y), fmax(a.min.z, b.min.z)},
                   {fmin(a.max.x, b.max.x), fmin(a.max.y, b.max.y), fmin(a.max.z, b.max.z)}};
}

static double box_volume(bk_aabb b) {
  bk_vec3 s = bk_v3_sub(b.max, b.min);
  return s.x > 0.0 && s.y > 0.0 && s.z > 0.0 ? s.x * s.y * s.z : 0.0;
}

/// The bricks of a box-shaped source.
typedef struct brick_tally {
  uint32_t bricks;  ///< cells with a volume
  uint32_t courses; ///< courses with a volume
  uint32_t widest;  ///< most bricks in one course
} brick_tally;

// Every cell met, walked course by course from the bottom, brick by brick,
// layer by layer.
static brick_tally count_bricks(const bk_fracture_def* d, bk_aabb source) {
  brick_tally t = {0};
  for (double y = source.min.y; y < source.max.y;) {
    bk_aabb course = brick_at(d, bk_v3(source.min.x, y + 0.5 * ON_PLANE, source.min.z));
    uint32_t in_course = 0;
    for (double x = source.min.x; x < source.max.x;) {
      bk_aabb row = brick_at(d, bk_v3(x + 0.5 * ON_PLANE, y + 0.5 * ON_PLANE, source.min.z));
      for (double z = source.min.z; z < source.max.z;) {
        bk_aabb cell = brick_at(d, bk_v3(x + 0.5 * ON_PLANE, y + 0.5 * ON_PLANE, z + 0.5 * ON_PLANE));
        if (box_volume(box_clip(cell, source)) > 1e-12) in_course++;
        z = cell.max.z;
      }
      x = row.max.x;
    }
    t.bricks += in_course;
    t.courses += in_course > 0;
    if (in_course > t.widest) t.widest = in_course;
    y = course.max.y;
  }
  return t;
}

static uint32_t ceil_log2(uint32_t n) {
  uint32_t bits = 0;
  while ((1u << bits) < n)
    bits++;
  return bits;
}

// The cell of a piece's bounds when they lie within one brick.
static bool in_one_brick(const bk_fracture_def* d, bk_aabb bounds, bk_aabb* cell) {
  *cell = brick_at(d, box_centre(bounds));
  return box_inside(bounds, *cell, ON_PLANE);
}

static bool on_grid(double x, double origin, double spacing, double shift) {
  double k = nearbyint((x - origin) / spacing - shift);
  return fabs(origin + (k + shift) * spacing - x) <= ON_PLANE;
}

static bool on_mortar(const bk_fracture_def* d, double y) {
  return on_grid(y, d->brick_origin.y, d->brick_size.y, 0.0);
}

// x on a head joint of any course from y_lo to y_hi.
static bool on_head_joint(const bk_fracture_def* d, double x, double y_lo, double y_hi) {
  for (double k = course_of(d, y_lo + ON_PLANE); k <= course_of(d, y_hi - ON_PLANE); k += 1.0)
    if (on_grid(x, d->brick_origin.x, d->brick_size.x, course_shift(d, k))) return true;
  return false;
}

static bool on_depth_plane(const bk_fracture_def* d, double z) {
  return d->brick_size.z > 0.0 && on_grid(z, d->brick_origin.z, d->brick_size.z, 0.0);
}

static bool near(double a, double b) { return fabs(a - b) <= ON_PLANE; }

// ---------------------------------------------------------------- checks

// Exactly `pieces` leaves, none short, no bond cut fell back to random
// planes, every node closed, volumes kept.
static void ensure_sound(const bk_mesh_tree* tree, const bk_mesh* source, uint32_t pieces) {
  ENSURE_MSG(tree->leaf_count == pieces, "%u leaves for %u pieces", tree->leaf_count, pieces);
  ENSURE(tree->shortfall.uncut == 0);
  ENSURE_MSG(tree->shortfall.bond_fallbacks == 0, "%u bond cuts fell back", tree->shortfall.bond_fallbacks);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(tree);
  ENSURE_MSG(st.open_nodes == 0, "%u open nodes", st.open_nodes);
  ENSURE_REL(st.leaf_volume_sum, bk_mesh_volume(source), 1e-9);
  ENSURE(st.max_child_rel_error <= 1e-9);
}

// Every node that spans several bricks is cut by a plane of the bond: a
// mortar plane, a head joint of the one course it lies in, or a depth plane.
static void ensure_bond_cuts(const bk_mesh_tree* tree, const bk_fracture_def* d) {
  uint32_t bond_cuts = 0;
  for (uint32_t i = 0; i < tree->node_count; ++i) {
    const bk_mesh_tree_node* node = &tree->nodes[i];
    bk_aabb cell = {0};
    if (node->child_count == 0 || in_one_brick(d, node->bounds, &cell)) continue;
    bk_vec3 n = node->plane.normal;
    double at = node->plane.offset;
    bool ok = false;
    if (n.y == 1.0) {
      ok = on_mortar(d, at);
    } else if (n.x == 1.0) {
      double k = course_of(d, 0.5 * (node->bounds.min.y + node->bounds.max.y));
      ok = course_of(d, node->bounds.min.y + ON_PLANE) == k &&
           course_of(d, node->bounds.max.y - ON_PLANE) == k &&
           on_grid(at, d->brick_origin.x, d->brick_size.x, course_shift(d, k));
    } else if (n.z == 1.0) {
      ok = on_depth_plane(d, at);
    }
    ENSURE_MSG(ok, "node %u (spanning bricks) cut by (%g, %g, %g) at %.17g", i, n.x, n.y, n.z, at);
    bond_cuts++;
  }
  ENSURE(bond_cuts > 0);
}

// With at least as many pieces as bricks: every leaf within one brick.
static void ensure_leaves_in_bricks(const bk_mesh_tree* tree, const bk_fracture_def* d) {
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_aabb b = bk_mesh_tree_leaf(tree, l)->bounds, cell = {0};
    ENSURE_MSG(in_one_brick(d, b, &cell), "leaf %u (%g..%g, %g..%g, %g..%g) crosses a brick", l, b.min.x,
               b.max.x, b.min.y, b.max.y, b.min.z, b.max.z);
  }
}

// With as many pieces as bricks: every leaf is one whole brick.
static void ensure_one_brick_each(const bk_mesh_tree* tree, const bk_fracture_def* d, bk_aabb source) {
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    const bk_mesh_tree_node* leaf = bk_mesh_tree_leaf(tree, l);
    bk_aabb cell = {0};
    ENSURE(in_one_brick(d, leaf->bounds, &cell));
    ENSURE_REL(leaf->moments.v, box_volume(box_clip(cell, source)), 1e-9);
  }
}

// With fewer pieces than bricks: every leaf is a group of whole bricks, so
// each side of its bounds is a bond plane or the source's own side.
static void ensure_whole_bricks(const bk_mesh_tree* tree, const bk_fracture_def* d, bk_aabb source) {
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_aabb b = bk_mesh_tree_leaf(tree, l)->bounds;
    double ys[2] = {b.min.y, b.max.y}, xs[2] = {b.min.x, b.max.x}, zs[2] = {b.min.z, b.max.z};
    for (int s = 0; s < 2; ++s) {
      ENSURE_MSG(on_mortar(d, ys[s]) || near(ys[s], s ? source.max.y : source.min.y),
                 "leaf %u: y = %.17g is not on the mortar", l, ys[s]);
      ENSURE_MSG(on_head_joint(d, xs[s], b.min.y, b.max.y) || near(xs[s], s ? source.max.x : source.min.x),
                 "leaf %u: x = %.17g is not a head joint of its courses", l, xs[s]);
      ENSURE_MSG(on_depth_plane(d, zs[s]) || near(zs[s], s ? source.max.z : source.min.z),
                 "leaf %u: z = %.17g is not a depth plane", l, zs[s]);
    }
  }
}

// Bonds join leaves whose bounds touch.
static void ensure_bonds_touch(const bk_mesh_tree* tree) {
  ENSURE(tree->bond_count > 0);
  for (uint32_t i = 0; i < tree->bond_count; ++i) {
    const bk_bond* bond = &tree->bonds[i];
    bk_aabb a = bk_mesh_tree_leaf(tree, bond->leaf_a)->bounds,
            b = bk_mesh_tree_leaf(tree, bond->leaf_b)->bounds;
    bk_aabb meet = box_clip(a, b);
    ENSURE_MSG(meet.min.x <= meet.max.x + ON_PLANE && meet.min.y <= meet.max.y + ON_PLANE &&
                   meet.min.z <= meet.max.z + ON_PLANE,
               "bond %u joins leaves %u and %u, which do not touch", i, bond->leaf_a, bond->leaf_b);
  }
}

static void ensure_same_bytes(const bk_mesh_tree* a, const bk_mesh_tree* b) {
  ENSURE(trees_same_bytes(a, b));
}

// One build of the wall checked whole: sound, cut along the bond, and its
// leaves whole bricks or within bricks as the piece count has it.
static void check_wall(const bk_mesh* wall, const bk_fracture_def* d) {
  bk_aabb source = bk_mesh_bounds(wall);
  brick_tally tally = count_bricks(d, source);
  uint32_t bricks = tally.bricks;
  bk_mesh_tree tree = build(wall, d);
  // Each bond cut takes the plane nearest the piece's centroid, so courses
  // and then bricks are halved: every brick is separate this deep.
  if (d->pieces == bricks)
    ENSURE_MSG(tree.max_depth <= ceil_log2(tally.courses) + ceil_log2(tally.widest),
               "depth %u for %u courses of at most %u bricks", tree.max_depth, tally.courses, tally.widest);
  ensure_sound(&tree, wall, d->pieces);
  ensure_bond_cuts(&tree, d);
  if (d->pieces >= bricks) ensure_leaves_in_bricks(&tree, d);
  if (d->pieces == bricks) ensure_one_brick_each(&tree, d, source);
  if (d->pieces <= bricks) ensure_whole_bricks(&tree, d, source);
  ensure_bonds_touch(&tree);
  bk_mesh_tree_free(&tree);
}

// ---------------------------------------------------------------- tests

static bk_mesh wall_mesh(void) {
  bk_mesh wall = {0};
  bk_shape_build(BK_SHAPE_WALL, &wall);
  return wall;
}

// The texture-aligned bond on the wall: 10 courses (the top one 0.075 high),
// 8 bricks in even courses and 7 and two halves in odd ones.
static void test_texture_bond(void) {
  bk_mesh wall = wall_mesh();
  bk_fracture_def d = wall_def(0);
  uint32_t bricks = count_bricks(&d, bk_mesh_bounds(&wall)).bricks;
  ENSURE_MSG(bricks == 85, "%u bricks", bricks);
  static const uint32_t pieces[] = {64, 85, 300, 1024};
  for (size_t i = 0; i < sizeof pieces / sizeof pieces[0]; ++i) {
    d.pieces = pieces[i];
    check_wall(&wall, &d);
  }
  bk_mesh_free(&wall);
}

// Other bonds: no offset, a quarter offset with a brick origin off the
// wall's corner, bricks half the wall deep (planes along z too), pieces
// below, at and above the brick count.
static void test_other_bonds(void) {
  bk_mesh wall = wall_mesh();
  bk_aabb source = bk_mesh_bounds(&wall);
  bk_fracture_def d = wall_def(0);
  d.brick_offset = 0.0;
  uint32_t bricks = count_bricks(&d, source).bricks;
  ENSURE(bricks == 80);
  d.pieces = 300;
  check_wall(&wall, &d);
  d.brick_offset = 0.25;
  d.brick_origin = bk_v3(0.1, 0.03, 0.0);
  d.brick_size = bk_v3(0.3, 0.1, 0.1);
  d.aspect_bias = 0.0;
  bricks = count_bricks(&d, source).bricks;
  ENSURE(bricks > 100);
  uint32_t counts[3] = {bricks / 3, bricks, 3 * bricks};
  for (int i = 0; i < 3; ++i) {
    d.pieces = counts[i];
    check_wall(&wall, &d);
  }
  bk_mesh_free(&wall);
}

// The same def twice: the same bytes.
static void test_determinism(void) {
  bk_mesh wall = wall_mesh();
  bk_fracture_def d = wall_def(300);
  bk_mesh_tree a = build(&wall, &d), b = build(&wall, &d);
  ensure_same_bytes(&a, &b);
  bk_mesh_tree_free(&a);
  bk_mesh_tree_free(&b);
  bk_mesh_free(&wall);
}

// Leaves of a tree that cross a brick of another bond.
static uint32_t leaves_crossing(const bk_mesh_tree* tree, const bk_fracture_def* other) {
  uint32_t crossing = 0;
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_aabb cell = {0};
    crossing += !in_one_brick(other, bk_mesh_tree_leaf(tree, l)->bounds, &cell);
  }
  return crossing;
}

// Offsets 0 and 0.5 give different leaves: in every other course the head
// joints of one lie half a brick from the other's, so many leaves of each
// cross the other's bricks.
static void test_offset_matters(void) {
  bk_mesh wall = wall_mesh();
  bk_fracture_def running = wall_def(300), stack = running;
  stack.brick_offset = 0.0;
  bk_mesh_tree a = build(&wall, &running), b = build(&wall, &stack);
  uint32_t a_crossing = leaves_crossing(&a, &stack), b_crossing = leaves_crossing(&b, &running);
  ENSURE_MSG(a_crossing >= a.leaf_count / 4 && b_crossing >= b.leaf_count / 4,
             "%u and %u of %u leaves cross the other bond's bricks", a_crossing, b_crossing, a.leaf_count);
  bk_mesh_tree_free(&a);
  bk_mesh_tree_free(&b);
  bk_mesh_free(&wall);
}

int main(void) {
  RUN(test_texture_bond);
  RUN(test_other_bonds);
  RUN(test_determinism);
  RUN(test_offset_matters);
  return 0;
}
