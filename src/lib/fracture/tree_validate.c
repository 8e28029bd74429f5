// bk_mesh_tree_validate: whether a mesh tree is one the runtime, the cache
// file and the glTF export can use as it is. A tree is a public struct that
// a game may build, load or edit itself, so nothing downstream trusts it:
// the structure (indices, ranges, the tree's shape, leaf ranges, bond
// leaves) is checked first, since every later check indexes through it,
// then the physics (volumes, mass moments, inertia, bonds), since a wrong
// value there does not crash but silently changes the simulation: a
// negative volume removes a leaf's mass, a zero bond area breaks the bond
// at once, a bond far outside its leaves is never reached by damage.
#include <float.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"

// How far a leaf's stored volume may be from its mesh's volume, relative to
// the larger of the two; and how far an inner node's may be from the sum of
// its children's. Built trees of every pattern stay below 1e-10 and 1e-13;
// a file or a caller that changed a volume by more than rounding is caught.
#define VOLUME_TOLERANCE 1e-9
// Rounding in a volume summed from a mesh's triangles is a few ulps of the
// sum of their terms' sizes (see mesh_volume), which for a small piece far
// from the tree's centre or from the world origin can exceed a relative
// 1e-9 of the volume itself: this many ulps of it are allowed on top.
#define VOLUME_ROUNDING_ULPS 256.0
// A bond's normal is computed in doubles from values of about unit scale.
#define NORMAL_TOLERANCE 1e-6
// Where a centre of mass or a bond's centroid may lie: bk_inside_slack.

// ---------------------------------------------------------------- structure

static bool aabb_finite(bk_aabb b) { return bk_v3_is_finite(b.min) && bk_v3_is_finite(b.max); }

static bool moments_finite(const bk_moments* m) {
  const double v[10] = {m->v, m->x, m->y, m->z, m->xx, m->yy, m->zz, m->xy, m->yz, m->zx};
  for (int k = 0; k < 10; ++k)
    if (!isfinite(v[k])) return false;
  return true;
}

// Names the first moment of node i that is not finite.
static bool moments_error(const bk_mesh_tree_node* n, uint32_t i, bk_error* why) {
  const bk_moments* m = &n->moments;
  const double v[10] = {m->v, m->x, m->y, m->z, m->xx, m->yy, m->zz, m->xy, m->yz, m->zx};
  static const char* const names[10] = {"v", "x", "y", "z", "xx", "yy", "zz", "xy", "yz", "zx"};
  int k = 0;
  while (k < 9 && isfinite(v[k]))
    ++k;
  return bk_error_set(why, "node %u: moment %s is %g, not finite", i, names[k], v[k]);
}

// Arrays a count says are there must be: the checks below read them.
static bool check_arrays(const bk_mesh_tree* t, bk_error* why) {
  if (t->node_count && !t->nodes) return bk_error_set(why, "nodes is NULL for %u nodes", t->node_count);
  if (t->leaf_count && !t->leaf_nodes)
    return bk_error_set(why, "leaf_nodes is NULL for %u leaves", t->leaf_count);
  if (t->bond_count && !t->bonds) return bk_error_set(why, "bonds is NULL for %u bonds", t->bond_count);
  for (uint32_t i = 0; i < t->node_count; ++i) {
    const bk_mesh* m = &t->nodes[i].mesh;
    if ((m->position_count && !m->positions) || (m->corner_count && !m->corners) ||
        (m->triangle_count && (!m->indices || !m->materials || !m->tags)))
      return bk_error_set(why, "node %u: its mesh has counts but no arrays", i);
  }
  return true;
}

// The invariants every consumer of a tree indexes by (indices in range, a
// real tree shape, contiguous leaf ranges, bonds between existing leaves),
// and every value finite.
static bool check_structure(const bk_mesh_tree* t, bk_error* why) {
  bk_error inner = {{0}};
  // A Voronoi tree's desc keeps the count of the caller's seed points but not
  // the points (bk_fracture_def_clear_borrowed). bk_fracture_def_validate
  // would read count points from NULL, so the count is checked here (same
  // limit) and the def validated without it.
  bk_fracture_def desc = t->desc;
  if (desc.pattern == BK_PATTERN_VORONOI && !desc.seed_points && desc.seed_point_count) {
    if (desc.seed_point_count > (1u << 20))
      return bk_error_set(why, "fracture: seed_point_count = %u is too many (at most %u)",
                          desc.seed_point_count, 1u << 20);
    desc.seed_point_count = 0;
  }
  if (!bk_fracture_def_validate(&desc, &inner)) return bk_error_set(why, "%s", inner.message);
  if (t->node_count == 0) return bk_error_set(why, "the tree has no nodes");
  if (t->leaf_count == 0 || t->leaf_count > t->node_count)
    return bk_error_set(why, "%u leaves for %u nodes", t->leaf_count, t->node_count);
  if (!check_arrays(t, why)) return false;
  uint32_t deepest = 0;
  for (uint32_t i = 0; i < t->node_count; ++i) {
    const bk_mesh_tree_node* n = &t->nodes[i];
    if (!bk_mesh_validate(&n->mesh, &inner)) return bk_error_set(why, "node %u: %s", i, inner.message);
    if (!aabb_finite(n->bounds)) return bk_error_set(why, "node %u: bounds are not finite", i);
    if (!moments_finite(&n->moments)) return moments_error(n, i, why);
    if (!bk_v3_is_finite(n->plane.normal) || !isfinite(n->plane.offset))
      return bk_error_set(why, "node %u: split plane is not finite", i);
    // Bounds are derived from the mesh (the tree's origin from the root's),
    // and a split plane's normal is a unit vector (bonds take it as theirs).
    bk_aabb box = bk_mesh_bounds(&n->mesh);
    if (memcmp(&box, &n->bounds, sizeof box) != 0)
      return bk_error_set(why, "node %u: its stored bounds are not its mesh's", i);
    if (n->child_count && !(fabs(bk_v3_length(n->plane.normal) - 1.0) <= 1e-9))
      return bk_error_set(why, "node %u: its split plane's normal has length %.17g, not 1", i,
                          bk_v3_length(n->plane.normal));
    if (i == 0) {
      bk_vec3 size = bk_v3_sub(box.max, box.min);
      double largest = fmax(size.x, fmax(size.y, size.z));
      if (!(largest >= BK_FRACTURE_MIN_SIZE && largest <= BK_FRACTURE_MAX_SIZE))
        return bk_error_set(why, "the source is %g across (%g to %g allowed)", largest, BK_FRACTURE_MIN_SIZE,
                            BK_FRACTURE_MAX_SIZE);
      if (n->parent != BK_NULL_INDEX || n->depth != 0)
        return bk_error_set(why, "the root has parent %u and depth %u", n->parent, n->depth);
      if (n->leaf_begin != 0 || n->leaf_end != t->leaf_count)
        return bk_error_set(why, "the root covers leaves [%u, %u), not [0, %u)", n->leaf_begin, n->leaf_end,
                            t->leaf_count);
    } else {
      if (n->parent >= t->node_count)
        return bk_error_set(why, "node %u has parent %u of %u", i, n->parent, t->node_count);
      const bk_mesh_tree_node* p = &t->nodes[n->parent];
      // Children come after their parent (checked below), so this also rules out cycles.
      if (p->child_count == 0 || i < p->first_child ||
          (uint64_t)i >= (uint64_t)p->first_child + p->child_count)
        return bk_error_set(why, "node %u names parent %u, which does not list it as a child", i, n->parent);
      if ((uint64_t)n->depth != (uint64_t)p->depth + 1)
        return bk_error_set(why, "node %u has depth %u under a parent of depth %u", i, n->depth, p->depth);
    }
    if (n->depth > deepest) deepest = n->depth;
    if (n->leaf_begin > n->leaf_end || n->leaf_end > t->leaf_count)
      return bk_error_set(why, "node %u has leaf range [%u, %u) of %u leaves", i, n->leaf_begin, n->leaf_end,
                          t->leaf_count);
    if (n->child_count == 0) {
      if (n->first_child != BK_NULL_INDEX)
        return bk_error_set(why, "leaf node %u has first child %u", i, n->first_child);
      if (n->leaf_end != n->leaf_begin + 1 || t->leaf_nodes[n->leaf_begin] != i)
        return bk_error_set(why, "leaf node %u has leaf range [%u, %u) that does not name it", i,
                            n->leaf_begin, n->leaf_end);
      continue;
    }
    if (n->first_child <= i || (uint64_t)n->first_child + n->child_count > t->node_count)
      return bk_error_set(why, "node %u has children [%u, +%u) of %u nodes", i, n->first_child,
                          n->child_count, t->node_count);
    // The children's leaf ranges must tile the parent's, in order.
    uint32_t next_leaf = n->leaf_begin;
    for (uint32_t c = n->first_child; c < n->first_child + n->child_count; ++c) {
      if (t->nodes[c].parent != i)
        return bk_error_set(why, "node %u lists child %u, whose parent is %u", i, c, t->nodes[c].parent);
      if (t->nodes[c].leaf_begin != next_leaf)
        return bk_error_set(why, "child %u of node %u starts at leaf %u, expected %u", c, i,
                            t->nodes[c].leaf_begin, next_leaf);
      next_leaf = t->nodes[c].leaf_end;
    }
    if (next_leaf != n->leaf_end)
      return bk_error_set(why, "the children of node %u end at leaf %u, expected %u", i, next_leaf,
                          n->leaf_end);
  }
  if (deepest != t->max_depth)
    return bk_error_set(why, "max_depth is %u but the deepest node has depth %u", t->max_depth, deepest);
  for (uint32_t l = 0; l < t->leaf_count; ++l) {
    uint32_t node = t->leaf_nodes[l];
    if (node >= t->node_count || t->nodes[node].child_count != 0 || t->nodes[node].leaf_begin != l)
      return bk_error_set(why, "leaf %u names node %u, which is not that leaf", l, node);
  }
  for (uint32_t b = 0; b < t->bond_count; ++b) {
    const bk_bond* bond = &t->bonds[b];
    if (bond->leaf_a >= bond->leaf_b || bond->leaf_b >= t->leaf_count)
      return bk_error_set(why, "bond %u joins leaves %u and %u of %u", b, bond->leaf_a, bond->leaf_b,
                          t->leaf_count);
    const char* field = !isfinite(bond->area)              ? "area"
                        : !bk_v3_is_finite(bond->centroid) ? "centroid"
                        : !bk_v3_is_finite(bond->normal)   ? "normal"
                                                           : NULL;
    if (field)
      return bk_error_set(why, "bond %u (leaves %u and %u): %s is not finite", b, bond->leaf_a, bond->leaf_b,
                          field);
  }
  return true;
}

// ---------------------------------------------------------------- physics

// "leaf 12 (node 40)" or "node 3": how a message names node i.
static const char* node_name(const bk_mesh_tree_node* n, uint32_t i, char* out, size_t size) {
  if (n->child_count == 0)
    snprintf(out, size, "leaf %u (node %u)", n->leaf_begin, i);
  else
    snprintf(out, size, "node %u", i);
  return out;
}

// Volume of a closed mesh, summed about the centre of its bounds (its own
// coordinates stay small there, so this sum barely rounds), and in *scale
// the size of the rounding in the volume stored with it: that was summed
// about `origin` (the tree's) from positions that were then moved to the
// source's coordinates, rounding each by an ulp of its distance from the
// world origin. Either way each triangle's term is its doubled area vector
// times a position, so the rounding is a few ulps of the triangles' areas
// times the larger of those distances (plus the piece's own size).
static double mesh_volume(const bk_mesh* m, bk_aabb bounds, bk_vec3 origin, double* scale, double* area) {
  bk_vec3 centre = bk_v3_scale(bk_v3_add(bounds.min, bounds.max), 0.5);
  double sum = 0.0, area2 = 0.0;
  for (uint32_t t = 0; t < m->triangle_count; ++t) {
    bk_vec3 a = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 0)], centre);
    bk_vec3 b = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 1)], centre);
    bk_vec3 c = bk_v3_sub(m->positions[bk_mesh_tri_position(m, t, 2)], centre);
    bk_vec3 d = bk_v3_cross(bk_v3_sub(b, a), bk_v3_sub(c, a));
    sum += bk_v3_dot(a, d);
    area2 += bk_v3_length(d);
  }
  bk_aabb about = {bk_v3_sub(bounds.min, origin), bk_v3_sub(bounds.max, origin)};
  double reach =
      fmax(bk_aabb_largest_coordinate(about), bk_aabb_largest_coordinate(bounds)) + bk_aabb_diagonal(bounds);
  *scale = area2 * reach / 6.0;
  *area = area2 / 2.0;
  return sum / 6.0;
}

// Volume, centre of mass and inertia of node i: what a body made of it gets.
static bool check_mass(const bk_mesh_tree* t, uint32_t i, bk_error* why) {
  const bk_mesh_tree_node* n = &t->nodes[i];
  char name[64] = "";
  node_name(n, i, name, sizeof name);
  return bk_solid_mass_check(&n->moments, bk_mesh_tree_origin(t), n->bounds, true, name, why);
}

// A leaf's volume is its mesh's; an inner node's is the sum of its
// children's (so, down the tree, of its leaves' meshes). A leaf's surface
// area goes to leaf_area[leaf], for its bonds.
static bool check_volume(const bk_mesh_tree* t, uint32_t i, bk_vec3 origin, double* leaf_area,
                         bk_error* why) {
  const bk_mesh_tree_node* n = &t->nodes[i];
  char name[64] = "";
  node_name(n, i, name, sizeof name);
  double stored = n->moments.v;
  if (!(stored > 0.0)) return bk_error_set(why, "%s: volume %g is not positive", name, stored);
  if (n->child_count == 0) {
    double scale = 0.0,
           measured = mesh_volume(&n->mesh, n->bounds, origin, &scale, &leaf_area[n->leaf_begin]);
    double slack =
        VOLUME_TOLERANCE * fmax(fabs(stored), fabs(measured)) + VOLUME_ROUNDING_ULPS * DBL_EPSILON * scale;
    if (!(fabs(stored - measured) <= slack))
      return bk_error_set(why, "%s: volume %.9g is not its mesh's volume %.9g", name, stored, measured);
    return true;
  }
  double children = 0.0;
  for (uint32_t c = n->first_child; c < n->first_child + n->child_count; ++c)
    children += t->nodes[c].moments.v;
  if (!(fabs(stored - children) <= VOLUME_TOLERANCE * fmax(fabs(stored), fabs(children))))
    return bk_error_set(why, "%s: volume %.9g is not the sum of its children's volumes %.9g", name, stored,
                        children);
  return true;
}

static bool check_bond(const bk_mesh_tree* t, uint32_t b, const double* leaf_area, bk_error* why) {
  const bk_bond* bond = &t->bonds[b];
  const bk_mesh_tree_node* a = bk_mesh_tree_leaf(t, bond->leaf_a);
  const bk_mesh_tree_node* c = bk_mesh_tree_leaf(t, bond->leaf_b);
  // The contact is part of both leaves' surfaces (rough where the cut faces
  // are noisy), so it lies inside both bounds and is no larger than either
  // surface.
  double surface = leaf_area ? fmin(leaf_area[bond->leaf_a], leaf_area[bond->leaf_b]) : INFINITY;
  if (!(bond->area > 0.0) || !isfinite(bond->area))
    return bk_error_set(why, "bond %u (leaves %u and %u): area %g is not positive", b, bond->leaf_a,
                        bond->leaf_b, bond->area);
  if (!(bond->area <= surface * (1.0 + NORMAL_TOLERANCE)))
    return bk_error_set(why,
                        "bond %u (leaves %u and %u): area %g is more than the smaller leaf's surface (%g)", b,
                        bond->leaf_a, bond->leaf_b, bond->area, surface);
  bk_vec3 p = bond->centroid;
  if (!bk_point_inside(a->bounds, p, bk_inside_slack(a->bounds)) ||
      !bk_point_inside(c->bounds, p, bk_inside_slack(c->bounds)))
    return bk_error_set(
        why, "bond %u (leaves %u and %u): centroid (%g, %g, %g) lies outside leaf %u's bounds", b,
        bond->leaf_a, bond->leaf_b, p.x, p.y, p.z,
        bk_point_inside(a->bounds, p, bk_inside_slack(a->bounds)) ? bond->leaf_b : bond->leaf_a);
  double length = bk_v3_length(bond->normal);
  if (!(fabs(length - 1.0) <= NORMAL_TOLERANCE))
    return bk_error_set(why, "bond %u (leaves %u and %u): normal has length %.9g, not 1", b, bond->leaf_a,
                        bond->leaf_b, length);
  return true;
}

bool bk_mesh_tree_validate(const bk_mesh_tree* tree, bk_error* err) {
  if (!tree) return bk_error_set(err, "the tree is NULL");
  if (!check_structure(tree, err)) return false;
  bk_vec3 origin = bk_mesh_tree_origin(tree);
  double* leaf_area = bk_alloc(sizeof(double) * tree->leaf_count);
  bool ok = true;
  // Children before their parents (they come after them), so a wrong leaf
  // is named itself, not as the parent whose children no longer add up.
  for (uint32_t i = tree->node_count; ok && i-- > 0;)
    ok = check_volume(tree, i, origin, leaf_area, err) && check_mass(tree, i, err);
  for (uint32_t b = 0; ok && b < tree->bond_count; ++b)
    ok = check_bond(tree, b, leaf_area, err);
  bk_free(leaf_area);
  return ok;
}

// A tree the builders made has its structure and its volumes by
// construction; what a surface that crosses itself can still spoil is a
// leaf's mass (an inner node's is a sum of its leaves', a solid's when
// theirs are) and the bonds measured on its cut faces. O(leaves + bonds).
bool bk_mesh_tree_check_built(const bk_mesh_tree* tree, bk_error* err) {
  bk_vec3 origin = bk_mesh_tree_origin(tree);
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    const bk_mesh_tree_node* n = bk_mesh_tree_leaf(tree, l);
    char name[64] = "";
    node_name(n, tree->leaf_nodes[l], name, sizeof name);
    if (!bk_solid_mass_check(&n->moments, origin, n->bounds, false, name, err)) return false;
  }
  for (uint32_t b = 0; b < tree->bond_count; ++b)
    if (!check_bond(tree, b, NULL, err)) return false;
  return true;
}
