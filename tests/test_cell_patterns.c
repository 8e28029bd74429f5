// The cell patterns (Voronoi, clustered, radial) give the same kind of mesh
// tree as the planes pattern: exactly the pieces asked for, every node
// closed, leaf volumes adding up to the source's, bonds only between leaves
// that share cut-face triangles (measured on them), cut faces tagged
// interior with unit normals and tangents, deterministic for a seed; and
// each pattern's own parameter changes what it makes.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bk_fracture.h"
#include "ensure.h"
#include "load_shape.h"
#include "tree_bytes.h"

static bk_mesh_tree build(const bk_mesh* m, bk_fracture_def d) {
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(m, &d, &tree, &err), "%s %u: %s", bk_fracture_pattern_name(d.pattern),
             d.pieces, err.message);
  return tree;
}

static bk_fracture_def def_of(bk_fracture_pattern pattern, uint32_t pieces) {
  bk_fracture_def d = bk_default_fracture_def();
  d.pattern = pattern;
  d.pieces = pieces;
  return d;
}

// The area of the cut-face triangles of leaf a whose face (tag) leaf b has too.
// True when triangle i of a and triangle j of b have the same three positions.
static bool same_triangle(const bk_mesh* a, uint32_t i, const bk_mesh* b, uint32_t j) {
  for (uint32_t k = 0; k < 3; ++k) {
    bk_vec3 p = a->positions[bk_mesh_tri_position(a, i, k)];
    bool found = false;
    for (uint32_t m = 0; m < 3 && !found; ++m) {
      bk_vec3 q = b->positions[bk_mesh_tri_position(b, j, m)];
      found = p.x == q.x && p.y == q.y && p.z == q.z;
    }
    if (!found) return false;
  }
  return true;
}

// The area of the cut-face triangles both leaves carry (the same face, the
// same positions: a face that crosses the source twice may separate other
// leaves at its other crossing).
static double shared_area(const bk_mesh* a, const bk_mesh* b) {
  double area = 0.0;
  for (uint32_t i = 0; i < a->triangle_count; ++i) {
    if (!a->tags[i]) continue;
    bool shared = false;
    for (uint32_t j = 0; j < b->triangle_count && !shared; ++j)
      shared = b->tags[j] == a->tags[i] && same_triangle(a, i, b, j);
    if (!shared) continue;
    bk_vec3 p0 = a->positions[bk_mesh_tri_position(a, i, 0)];
    area += 0.5 * bk_v3_length(bk_v3_cross(bk_v3_sub(a->positions[bk_mesh_tri_position(a, i, 1)], p0),
                                           bk_v3_sub(a->positions[bk_mesh_tri_position(a, i, 2)], p0)));
  }
  return area;
}

static void ensure_tree(const bk_mesh_tree* t, const char* name, uint32_t pieces) {
  ENSURE_MSG(t->leaf_count == pieces, "%s: %u leaves for %u pieces", name, t->leaf_count, pieces);
  bk_mesh_tree_stats st = bk_mesh_tree_measure(t);
  ENSURE_MSG(st.open_nodes == 0, "%s: %u open nodes", name, st.open_nodes);
  ENSURE_MSG(fabs(st.leaf_volume_sum - st.source_volume) <= 1e-9 * st.source_volume,
             "%s: leaves %.17g, source %.17g", name, st.leaf_volume_sum, st.source_volume);
  ENSURE_MSG(st.max_child_rel_error <= 1e-9, "%s: children miss their parent by %g", name,
             st.max_child_rel_error);
  // Every inner node's leaf range is the union of its children's.
  for (uint32_t i = 0; i < t->node_count; ++i) {
    const bk_mesh_tree_node* n = &t->nodes[i];
    if (!n->child_count) continue;
    ENSURE(t->nodes[n->first_child].leaf_begin == n->leaf_begin);
    ENSURE(t->nodes[n->first_child + n->child_count - 1].leaf_end == n->leaf_end);
    for (uint32_t c = 0; c < n->child_count; ++c)
      ENSURE(t->nodes[n->first_child + c].parent == i);
  }
  // Cut faces: interior material, unit normal and tangent, finite uv.
  for (uint32_t l = 0; l < t->leaf_count; ++l) {
    const bk_mesh* m = &bk_mesh_tree_leaf(t, l)->mesh;
    for (uint32_t tri = 0; tri < m->triangle_count; ++tri) {
      if (!m->tags[tri]) {
        ENSURE(!bk_material_is_interior(m->materials[tri]));
        continue;
      }
      ENSURE_MSG(bk_material_is_interior(m->materials[tri]), "%s: a cut face triangle is not interior", name);
      const bk_corner* c = &m->corners[m->indices[3 * tri]];
      double nl =
          sqrt(c->normal[0] * c->normal[0] + c->normal[1] * c->normal[1] + c->normal[2] * c->normal[2]);
      double tl =
          sqrt(c->tangent[0] * c->tangent[0] + c->tangent[1] * c->tangent[1] + c->tangent[2] * c->tangent[2]);
      ENSURE(fabs(nl - 1.0) < 1e-5 && fabs(tl - 1.0) < 1e-5 && isfinite(c->uv[0]) && isfinite(c->uv[1]));
    }
  }
  // One solid: the bonds connect every leaf, so there are at least leaves - 1.
  ENSURE_MSG(t->bond_count + 1 >= t->leaf_count, "%s: %u bonds for %u leaves", name, t->bond_count,
             t->leaf_count);
  // Bonds: distinct leaves that share a cut face, unit normals, and the
  // area is the shared triangles' area; leaves that share none are not bonded.
  for (uint32_t b = 0; b < t->bond_count; ++b) {
    const bk_bond* bond = &t->bonds[b];
    ENSURE(bond->leaf_a < bond->leaf_b && bond->leaf_b < t->leaf_count);
    ENSURE(bond->area > 0.0 && fabs(bk_v3_length(bond->normal) - 1.0) < 1e-9);
    if (b % 7 == 0) { // a sample: the quadratic check is slow on big trees
      double area =
          shared_area(&bk_mesh_tree_leaf(t, bond->leaf_a)->mesh, &bk_mesh_tree_leaf(t, bond->leaf_b)->mesh);
      ENSURE_MSG(fabs(area - bond->area) <= 1e-9 * area, "%s: bond %u has area %.17g, its leaves share %.17g",
                 name, b, bond->area, area);
    }
  }
}

static void test_every_pattern_and_shape(void) {
  const char* shapes[] = {"cube", "torus", "eggshell", "wall", "bunny"};
  const bk_fracture_pattern patterns[] = {BK_PATTERN_VORONOI, BK_PATTERN_CLUSTERED, BK_PATTERN_RADIAL};
  const uint32_t counts[] = {64, 1024};
  for (size_t s = 0; s < sizeof shapes / sizeof *shapes; ++s) {
    bk_mesh m = load_shape(shapes[s]);
    for (size_t p = 0; p < 3; ++p)
      for (size_t c = 0; c < 2; ++c) {
        bk_fracture_def d = def_of(patterns[p], counts[c]);
        if (patterns[p] == BK_PATTERN_RADIAL) { // on the surface, where a shot lands
          bk_aabb box = bk_mesh_bounds(&m);
          d.impact = bk_v3(0.5 * (box.min.x + box.max.x), 0.5 * (box.min.y + box.max.y), box.max.z);
        }
        bk_mesh_tree t = build(&m, d);
        char name[128];
        snprintf(name, sizeof name, "%s %s %u", shapes[s], bk_fracture_pattern_name(patterns[p]), counts[c]);
        ensure_tree(&t, name, counts[c]);
        bk_mesh_tree_free(&t);
      }
    bk_mesh_free(&m);
  }
}

static void test_determinism_and_cache(void) {
  bk_mesh m = load_shape("torus");
  // One thread and three (more than this machine may have): the same bytes.
  bk_fracture_def d = def_of(BK_PATTERN_VORONOI, 200);
  d.threads = 1;
  bk_mesh_tree a = build(&m, d);
  d.threads = 3;
  bk_mesh_tree b = build(&m, d);
  d.threads = 0;
  ENSURE(trees_same_bytes(&a, &b));
  // Loaded back, its bonds recompute to the same bonds (from the cut-face tags).
  uint8_t* da = NULL;
  size_t sa = 0;
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_save_memory(&a, "tree", &da, &sa, &err), "%s", err.message);
  bk_mesh_tree loaded = {0};
  ENSURE_MSG(bk_mesh_tree_load_memory(da, sa, "tree", &loaded, &err), "%s", err.message);
  ENSURE(loaded.desc.pattern == BK_PATTERN_VORONOI);
  bk_mesh_tree_compute_bonds(&loaded);
  ENSURE(loaded.bond_count == a.bond_count);
  ENSURE(memcmp(loaded.bonds, a.bonds, sizeof(bk_bond) * a.bond_count) == 0);
  // Another seed, another tree.
  d.seed = 4;
  bk_mesh_tree c = build(&m, d);
  ENSURE(!trees_same_bytes(&a, &c));
  free(da);
  bk_mesh_tree_free(&a);
  bk_mesh_tree_free(&b);
  bk_mesh_tree_free(&c);
  bk_mesh_tree_free(&loaded);
  bk_mesh_free(&m);
}

// Radial: pieces near the impact are much smaller than far from it; with
// the falloff 0 they are not.
static double near_far_ratio(const bk_mesh* m, double falloff) {
  bk_fracture_def d = def_of(BK_PATTERN_RADIAL, 300);
  d.impact = bk_v3(0.0, 0.6, 0.1); // the wall's face, half-way up
  d.radial_falloff = falloff;
  bk_mesh_tree t = build(m, d);
  double near = 0.0, far = 0.0;
  uint32_t near_count = 0, far_count = 0;
  for (uint32_t l = 0; l < t.leaf_count; ++l) {
    const bk_mesh_tree_node* n = bk_mesh_tree_leaf(&t, l);
    bk_mass_properties mass = bk_mesh_tree_mass(&t, n->moments);
    double dist = bk_v3_length(bk_v3_sub(mass.centroid, d.impact));
    if (dist < 0.3) near += n->moments.v, near_count++;
    if (dist > 0.7) far += n->moments.v, far_count++;
  }
  bk_mesh_tree_free(&t);
  ENSURE(near_count && far_count);
  return (near / near_count) / (far / far_count);
}

static void test_radial_density(void) {
  bk_mesh wall = load_shape("wall");
  double focused = near_far_ratio(&wall, 1.0), uniform = near_far_ratio(&wall, 0.0);
  ENSURE_MSG(focused < 0.25, "near pieces are %.3g of far ones' size", focused);
  ENSURE_MSG(uniform > 0.4, "with falloff 0, near pieces are %.3g of far ones' size", uniform);
  bk_mesh_free(&wall);
}

// Clustered: the root's children are the chunks (each connected), so their
// count follows `clusters`; chunk leaves near the chunks' borders are small.
static void test_clusters(void) {
  bk_mesh cube = load_shape("cube");
  for (uint32_t clusters = 3; clusters <= 6; clusters += 3) {
    bk_fracture_def d = def_of(BK_PATTERN_CLUSTERED, 256);
    d.clusters = clusters;
    bk_mesh_tree t = build(&cube, d);
    ENSURE_MSG(t.nodes[0].child_count >= clusters, "%u clusters, %u root children", clusters,
               t.nodes[0].child_count);
    ENSURE_MSG(t.nodes[0].child_count <= clusters + 2, "%u clusters, %u root children", clusters,
               t.nodes[0].child_count);
    // The largest leaves are the chunk cores: far larger than the median.
    double largest = 0.0;
    double* v = bk_alloc(sizeof(double) * t.leaf_count);
    for (uint32_t l = 0; l < t.leaf_count; ++l)
      v[l] = bk_mesh_tree_leaf(&t, l)->moments.v, largest = fmax(largest, v[l]);
    uint32_t below = 0;
    for (uint32_t l = 0; l < t.leaf_count; ++l)
      below += v[l] < largest / 20.0;
    ENSURE_MSG(below > t.leaf_count / 2, "only %u of %u leaves are under 1/20 of the largest", below,
               t.leaf_count);
    free(v);
    bk_mesh_tree_free(&t);
  }
  bk_mesh_free(&cube);
}

// The caller's seeds: one cell per seed inside (outside ones ignored).
static void test_user_seeds(void) {
  bk_mesh cube = load_shape("cube");
  bk_aabb box = bk_mesh_bounds(&cube);
  bk_vec3 c = bk_v3_scale(bk_v3_add(box.min, box.max), 0.5),
          h = bk_v3_scale(bk_v3_sub(box.max, box.min), 0.25);
  bk_vec3 seeds[5] = {bk_v3_sub(c, h), bk_v3_add(c, h), bk_v3(c.x + h.x, c.y - h.y, c.z + 0.3 * h.z),
                      bk_v3(c.x - h.x, c.y + h.y, c.z - 0.2 * h.z), bk_v3(c.x + 100.0, c.y, c.z)};
  bk_fracture_def d = def_of(BK_PATTERN_VORONOI, 7);
  d.seed_points = seeds;
  d.seed_point_count = 5;
  bk_mesh_tree t = build(&cube, d);
  ensure_tree(&t, "cube with 4 seeds inside", 4);
  ENSURE(t.desc.seed_points == NULL && t.desc.seed_point_count == 5 && t.desc.pieces == 4);
  // Each seed lies in its own leaf's bounds.
  for (int s = 0; s < 4; ++s) {
    uint32_t holders = 0;
    for (uint32_t l = 0; l < t.leaf_count; ++l) {
      bk_aabb b = bk_mesh_tree_leaf(&t, l)->bounds;
      holders += seeds[s].x >= b.min.x && seeds[s].x <= b.max.x && seeds[s].y >= b.min.y &&
                 seeds[s].y <= b.max.y && seeds[s].z >= b.min.z && seeds[s].z <= b.max.z;
    }
    ENSURE(holders >= 1);
  }
  bk_mesh_tree_free(&t);
  // Every seed outside: a clear error.
  d.seed_points = &seeds[4];
  d.seed_point_count = 1;
  bk_mesh_tree none = {0};
  bk_error err = {0};
  ENSURE(!bk_mesh_tree_build(&cube, &d, &none, &err));
  ENSURE_MSG(strstr(err.message, "none of the 1 seed points lies inside"), "%s", err.message);
  bk_mesh_free(&cube);
}

static void test_refusals(void) {
  bk_error err = {0};
  bk_fracture_def d = def_of(BK_PATTERN_RADIAL, 10);
  d.radial_falloff = 2.0;
  ENSURE(!bk_fracture_def_validate(&d, &err) && strstr(err.message, "radial_falloff"));
  d = def_of(BK_PATTERN_VORONOI, 10);
  d.noise_frequency = 0.0;
  ENSURE(!bk_fracture_def_validate(&d, &err) && strstr(err.message, "noise_frequency"));
  d = def_of((bk_fracture_pattern)17, 10);
  ENSURE(!bk_fracture_def_validate(&d, &err) && strstr(err.message, "pattern"));
  // Far from the source, a radial impact still fractures it (seeds are
  // drawn inside only); NaN is refused.
  bk_mesh cube = load_shape("cube");
  d = def_of(BK_PATTERN_RADIAL, 16);
  d.impact = bk_v3(NAN, 0, 0);
  bk_mesh_tree t = {0};
  ENSURE(!bk_mesh_tree_build(&cube, &d, &t, &err) && strstr(err.message, "impact"));
  bk_mesh_free(&cube);
}

// Cut-out: a map with a cross makes four quarters of the wall, each
// within its quarter (to about one sample of the map), bonded to the two
// quarters beside it.
static void test_cutout(void) {
  enum { W = 64, H = 48 };
  static uint8_t map[W * H];
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x)
      map[y * W + x] = (x == W / 2 || y == H / 2) ? 255 : 0;
  bk_mesh wall = load_shape("wall");
  bk_fracture_def d = def_of(BK_PATTERN_CUTOUT, 1);
  d.cutout_pixels = map;
  d.cutout_width = W;
  d.cutout_height = H;
  d.cutout_axis = 2;
  bk_mesh_tree t = build(&wall, d);
  ensure_tree(&t, "cutout cross", 4);
  ENSURE(t.desc.cutout_pixels == NULL && t.desc.cutout_width == W && t.desc.pieces == 4);
  bk_aabb box = bk_mesh_bounds(&wall);
  double cx = 0.5 * (box.min.x + box.max.x), cy = 0.5 * (box.min.y + box.max.y);
  double slack = 0.08 * (box.max.x - box.min.x); // a couple of map samples
  for (uint32_t l = 0; l < t.leaf_count; ++l) {
    bk_aabb b = bk_mesh_tree_leaf(&t, l)->bounds;
    bool left = b.max.x<cx + slack, right = b.min.x> cx - slack;
    bool low = b.max.y<cy + slack, high = b.min.y> cy - slack;
    ENSURE_MSG((left || right) && (low || high), "leaf %u spans [%g, %g] x [%g, %g]", l, b.min.x, b.max.x,
               b.min.y, b.max.y);
    ENSURE(fabs((b.max.z - b.min.z) - (box.max.z - box.min.z)) < 1e-12); // through the whole depth
  }
  ENSURE_MSG(t.bond_count == 4 || t.bond_count == 5 || t.bond_count == 6, "%u bonds", t.bond_count);
  bk_mesh_tree_free(&t);
  // Along x, the wall's thin side sees the cross: again four pieces, now
  // split across its depth.
  d.cutout_axis = 0;
  t = build(&wall, d);
  ensure_tree(&t, "cutout cross along x", 4);
  double thinnest = INFINITY;
  for (uint32_t l = 0; l < t.leaf_count; ++l) {
    bk_aabb b = bk_mesh_tree_leaf(&t, l)->bounds;
    thinnest = fmin(thinnest, b.max.z - b.min.z);
  }
  ENSURE(thinnest < 0.75 * (box.max.z - box.min.z));
  bk_mesh_tree_free(&t);
  // All lines: no region.
  memset(map, 255, sizeof map);
  bk_error err = {0};
  ENSURE(!bk_mesh_tree_build(&wall, &d, &t, &err) && strstr(err.message, "encloses no region"));
  bk_mesh_free(&wall);
}

// How far the cut faces a bond's two leaves share stray from flat: for each
// face (tag) they share, the largest distance of its corners from the plane
// of its first triangle.
static double bond_bend(const bk_mesh_tree* t, const bk_bond* b) {
  const bk_mesh* ma = &bk_mesh_tree_leaf(t, b->leaf_a)->mesh;
  const bk_mesh* mb = &bk_mesh_tree_leaf(t, b->leaf_b)->mesh;
  double worst = 0.0;
  for (uint32_t i = 0; i < ma->triangle_count; ++i) {
    uint32_t tag = ma->tags[i];
    bool shared = false;
    for (uint32_t j = 0; j < mb->triangle_count && tag && !shared; ++j)
      shared = mb->tags[j] == tag;
    if (!shared) continue;
    // The face's first triangle in leaf a gives the plane.
    uint32_t first = i;
    while (first > 0 && ma->tags[first - 1] == tag)
      first--;
    bk_vec3 p0 = ma->positions[bk_mesh_tri_position(ma, first, 0)];
    bk_vec3 n =
        bk_v3_normalize(bk_v3_cross(bk_v3_sub(ma->positions[bk_mesh_tri_position(ma, first, 1)], p0),
                                    bk_v3_sub(ma->positions[bk_mesh_tri_position(ma, first, 2)], p0)));
    for (int k = 0; k < 3; ++k)
      worst = fmax(worst, fabs(bk_v3_dot(bk_v3_sub(ma->positions[bk_mesh_tri_position(ma, i, k)], p0), n)));
  }
  return worst;
}

// Noise: the same cells, still closed and adding up, but the cut faces are
// no longer flat; their bonds still join touching leaves.
static void test_noise(void) {
  bk_mesh cube = load_shape("cube");
  bk_fracture_def d = def_of(BK_PATTERN_VORONOI, 40);
  bk_mesh_tree flat = build(&cube, d);
  d.noise_amplitude = 0.03;
  d.noise_frequency = 6.0;
  bk_mesh_tree noisy = build(&cube, d);
  ensure_tree(&noisy, "noisy voronoi", 40);
  ENSURE(noisy.bond_count == flat.bond_count);
  double flat_bend = 0.0, noisy_bend = 0.0, flat_area = 0.0, noisy_area = 0.0;
  for (uint32_t b = 0; b < flat.bond_count; ++b) {
    ENSURE(flat.bonds[b].leaf_a == noisy.bonds[b].leaf_a && flat.bonds[b].leaf_b == noisy.bonds[b].leaf_b);
    flat_bend = fmax(flat_bend, bond_bend(&flat, &flat.bonds[b]));
    noisy_bend = fmax(noisy_bend, bond_bend(&noisy, &noisy.bonds[b]));
    flat_area += flat.bonds[b].area;
    noisy_area += noisy.bonds[b].area;
  }
  ENSURE_MSG(flat_bend < 1e-9, "flat faces bend by %g", flat_bend);
  ENSURE_MSG(noisy_bend > 0.003, "noisy faces bend by only %g", noisy_bend);
  ENSURE(noisy_area > flat_area); // a rough surface is larger than its plane
  ENSURE(noisy.nodes[noisy.leaf_nodes[0]].mesh.triangle_count >
         flat.nodes[flat.leaf_nodes[0]].mesh.triangle_count);
  // Brick cuts flat along its mortar: noise is refused, naming the field
  // (noisy planes: test_noisy_planes).
  bk_error err = {0};
  d.pattern = BK_PATTERN_BRICK;
  ENSURE(!bk_fracture_def_validate(&d, &err) && strstr(err.message, "noise_amplitude"));
  bk_mesh_tree_free(&flat);
  bk_mesh_tree_free(&noisy);
  bk_mesh_free(&cube);
}

int main(void) {
  test_cutout();
  test_noise();
  test_refusals();
  test_user_seeds();
  test_determinism_and_cache();
  test_radial_density();
  test_clusters();
  test_every_pattern_and_shape();
  printf("test_cell_patterns: ok\n");
  return 0;
}
