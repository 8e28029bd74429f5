// Structural stress in the runtime alone (no physics engine): the solver
// against statics worked by hand (a stacked column, a cantilever), its
// multigrid against plain iteration, and the runtime's use of it: a sound
// structure stands and costs nothing once solved, a pillar cut through its
// middle drops its top, a fragment hanging by one small bond falls, limits
// and gravity change the outcome, the same calls give the same breaks.
#include <stdlib.h>
#include <string.h>

#include <breakables/runtime.h>

#include "ensure.h"
#include "runtime_caller.h"
#include "runtime_internal.h"
#include "stress_leaves.h"
#include "stress_system.h"

enum { DOF = 6 };

static const bk_vec3 gravity = {0.0, -9.81, 0.0};

// ---------------------------------------------------------------- the system, by hand

// A column of n unit cubes of mass m stacked along y, the lowest held: the
// bond under cube k carries the weight of the cubes above it, in pure
// compression, whatever the stiffness (the column is statically determinate).
static void test_column(void) {
  enum { N = 12 };
  rt_stress_node nodes[N];
  rt_stress_bond bonds[N - 1];
  for (uint32_t i = 0; i < N; ++i)
    nodes[i] = (rt_stress_node){.centroid = {0.0, i + 0.5, 0.0}, .mass = 100.0, .fixed = i == 0};
  for (uint32_t i = 0; i + 1 < N; ++i)
    bonds[i] = (rt_stress_bond){.a = i,
                                .b = i + 1,
                                .centroid = {0.0, i + 1.0, 0.0},
                                .normal = {0, 1, 0},
                                .area = 1.0,
                                .tree_bond = i};
  rt_stress* s = rt_stress_create(nodes, N, bonds, N - 1, NULL, 0);
  rt_stress_load(s, gravity, NULL);
  rt_stress_iterate(s, 500, 1e-12);
  ENSURE(rt_stress_converged(s, 1e-10));
  for (uint32_t k = 0; k + 1 < N; ++k) {
    double stress[3] = {0};
    rt_stress_bond_stress(s, k, stress);
    double above = (double)(N - 1 - k) * 100.0 * 9.81; // N over 1 m^2
    ENSURE_REL(stress[0], above, 1e-8);
    ENSURE_SMALL(stress[1], 0.0, 1e-6 * above);
    ENSURE_SMALL(stress[2], 0.0, 1e-6 * above);
  }
  rt_stress_destroy(s);
}

// A horizontal beam of n cubes sticking out of a held one: the bond at the
// root shears by the weight outboard and bends by its moment, tension on
// top: 6 M / A^1.5 over a square section.
static void test_cantilever(void) {
  enum { N = 6 };
  rt_stress_node nodes[N];
  rt_stress_bond bonds[N - 1];
  double side = 0.5, area = side * side, mass = 50.0;
  for (uint32_t i = 0; i < N; ++i)
    nodes[i] = (rt_stress_node){.centroid = {(i + 0.5) * side, 2.0, 0.0}, .mass = mass, .fixed = i == 0};
  for (uint32_t i = 0; i + 1 < N; ++i)
    bonds[i] = (rt_stress_bond){.a = i,
                                .b = i + 1,
                                .centroid = {(i + 1.0) * side, 2.0, 0.0},
                                .normal = {1, 0, 0},
                                .area = area,
                                .tree_bond = i};
  rt_stress* s = rt_stress_create(nodes, N, bonds, N - 1, NULL, 0);
  rt_stress_load(s, gravity, NULL);
  rt_stress_iterate(s, 1000, 1e-13);
  for (uint32_t k = 0; k + 1 < N; ++k) {
    double stress[3] = {0};
    rt_stress_bond_stress(s, k, stress);
    double weight = 0.0, moment = 0.0, root = (k + 1.0) * side;
    for (uint32_t j = k + 1; j < N; ++j) {
      weight += mass * 9.81;
      moment += mass * 9.81 * ((j + 0.5) * side - root);
    }
    double bending = 6.0 * moment / (area * sqrt(area));
    ENSURE_REL(stress[2], weight / area, 1e-7);
    ENSURE_REL(stress[1], bending, 1e-7); // no axial force: bending alone
    ENSURE_REL(stress[0], bending, 1e-7);
  }
  rt_stress_destroy(s);
}

// A block lattice of nx x ny x nz unit cubes (bottom layer held), its
// bonds between face neighbours, grouped 2 x 2 x 2 and 4 x 4 x 4 for the
// multigrid when `grouped`.
enum { LX = 8, LY = 8, LZ = 3, LATTICE = LX * LY * LZ };

static rt_stress* make_lattice(bool grouped) {
  rt_stress_node nodes[LATTICE];
  rt_stress_bond bonds[3 * LATTICE];
  uint32_t keys[2][LATTICE];
  uint32_t bond_count = 0;
  for (uint32_t x = 0; x < LX; ++x)
    for (uint32_t y = 0; y < LY; ++y)
      for (uint32_t z = 0; z < LZ; ++z) {
        uint32_t i = (x * LY + y) * LZ + z;
        // Masses vary so no symmetry helps the solve.
        nodes[i] = (rt_stress_node){.centroid = {x + 0.5, y + 0.5, z + 0.5},
                                    .mass = 100.0 + 37.0 * ((x * 7 + y * 3 + z) % 5),
                                    .fixed = y == 0};
        keys[0][i] = ((x / 2) * LY + y / 2) * LZ + z / 2;
        keys[1][i] = ((x / 4) * LY + y / 4) * LZ + z / 4;
        const uint32_t step[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
        for (int d = 0; d < 3; ++d) {
          uint32_t u = x + step[d][0], v = y + step[d][1], w = z + step[d][2];
          if (u >= LX || v >= LY || w >= LZ) continue;
          bonds[bond_count] =
              (rt_stress_bond){.a = i,
                               .b = (u * LY + v) * LZ + w,
                               .centroid = {x + 0.5 + 0.5 * step[d][0], y + 0.5 + 0.5 * step[d][1],
                                            z + 0.5 + 0.5 * step[d][2]},
                               .normal = {step[d][0], step[d][1], step[d][2]},
                               .area = 0.5 + 0.1 * (bond_count % 3),
                               .tree_bond = bond_count};
          bond_count++;
        }
      }
  const uint32_t* groups[2] = {keys[0], keys[1]};
  return rt_stress_create(nodes, LATTICE, bonds, bond_count, grouped ? groups : NULL, grouped ? 2u : 0u);
}

// The multigrid (coarse levels assembled from the groups, the finest
// additive) converges to the direct solution of the whole system; its
// setup comes in steps (a level each), and made step by step or all at
// once, it gives the same answer.
static void test_multigrid_matches_direct(void) {
  rt_stress* direct = make_lattice(false);
  rt_stress_load(direct, gravity, NULL);
  ENSURE(direct->level_count == 1); // no groups: one dense solve
  rt_stress_iterate(direct, 10, 1e-12);
  ENSURE(rt_stress_converged(direct, 1e-10));

  rt_stress* stepped = make_lattice(true);
  ENSURE(!stepped->ready && !rt_stress_converged(stepped, 1.0)); // not loaded: never converged
  uint32_t steps = 0;
  while (!stepped->ready) {
    ENSURE(rt_stress_setup_step(stepped) > 0);
    steps++;
  }
  ENSURE_MSG(steps == 3 && stepped->level_count == 3, "%u steps, %u levels", steps, stepped->level_count);
  ENSURE(stepped->levels[1].pair_count > 0 && stepped->levels[1].pair_count < stepped->levels[1].bond_count);
  rt_stress_load(stepped, gravity, NULL);
  uint32_t iterations = rt_stress_iterate(stepped, 200, 1e-10);
  ENSURE(rt_stress_converged(stepped, 1e-10));
  printf("  lattice of %u: multigrid in %u iterations\n", LATTICE, iterations);
  ENSURE(iterations < 60);

  rt_stress* at_once = make_lattice(true);
  rt_stress_load(at_once, gravity, NULL); // the setup made here
  ENSURE(at_once->ready);
  ENSURE(rt_stress_iterate(at_once, 200, 1e-10) == iterations);
  double worst = 0.0, largest = 0.0;
  for (uint32_t k = 0; k < direct->bond_count; ++k) {
    double a[3] = {0}, b[3] = {0}, c[3] = {0};
    rt_stress_bond_stress(direct, k, a);
    rt_stress_bond_stress(stepped, k, b);
    rt_stress_bond_stress(at_once, k, c);
    for (int i = 0; i < 3; ++i) {
      worst = fmax(worst, fabs(a[i] - b[i]));
      largest = fmax(largest, fabs(a[i]));
      ENSURE(b[i] == c[i]);
    }
  }
  ENSURE_MSG(worst <= 1e-6 * largest, "multigrid off the direct solve by %g of %g", worst, largest);
  rt_stress_destroy(direct);
  rt_stress_destroy(stepped);
  rt_stress_destroy(at_once);
}

// The cantilever again, with a weight hung at its tip: node loads add to
// its own; the root shears by both.
static void test_cantilever_tip_load(void) {
  enum { N = 6 };
  rt_stress_node nodes[N];
  rt_stress_bond bonds[N - 1];
  double side = 0.5, area = side * side, mass = 50.0, hung = 300.0 * 9.81;
  for (uint32_t i = 0; i < N; ++i)
    nodes[i] = (rt_stress_node){.centroid = {(i + 0.5) * side, 2.0, 0.0}, .mass = mass, .fixed = i == 0};
  for (uint32_t i = 0; i + 1 < N; ++i)
    bonds[i] = (rt_stress_bond){
        .a = i, .b = i + 1, .centroid = {(i + 1.0) * side, 2.0, 0.0}, .normal = {1, 0, 0}, .area = area};
  double loads[DOF * N] = {0};
  loads[DOF * (N - 1) + 1] = -hung;
  rt_stress* s = rt_stress_create(nodes, N, bonds, N - 1, NULL, 0);
  rt_stress_load(s, gravity, loads);
  rt_stress_iterate(s, 1000, 1e-13);
  double stress[3] = {0};
  rt_stress_bond_stress(s, 0, stress);
  ENSURE_REL(stress[2], ((N - 1) * mass * 9.81 + hung) / area, 1e-7);
  rt_stress_destroy(s);
}

// ---------------------------------------------------------------- through the runtime

static bk_mesh_tree make_tree(bk_shape shape, uint32_t pieces, bk_fracture_pattern pattern) {
  bk_mesh mesh = {0};
  bk_shape_build(shape, &mesh);
  bk_fracture_def def = bk_default_fracture_def();
  def.pieces = pieces;
  def.pattern = pattern;
  def.seed = 7;
  bk_mesh_tree tree = {0};
  bk_error err = {0};
  ENSURE_MSG(bk_mesh_tree_build(&mesh, &def, &tree, &err), "%s", err.message);
  bk_mesh_free(&mesh);
  return tree;
}

typedef struct scene {
  bodies* bodies;
  bk_runtime* rt;
  bk_breakable_id id;
  uint32_t broken_by_stress; // over every call
} scene;

static scene make_scene(const bk_mesh_tree* tree, const char* material, double scale) {
  scene s = {.bodies = calloc(1, sizeof(bodies))};
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.context = s.bodies;
  // Hits here stand for shots that break exactly the bonds a test picks:
  // the damage at a bond's own centroid falls a millionth within a cm.
  def.damage_min_distance = 1e-4;
  bk_error err = {0};
  s.rt = bk_runtime_create(&def, &err);
  ENSURE_MSG(s.rt, "%s", err.message);
  bk_breakable_def bd = bk_default_breakable_def();
  bd.tree = tree;
  bd.anchored = true;
  bd.material = *bk_material_find(material);
  bd.material.compression_limit *= scale;
  bd.material.tension_limit *= scale;
  bd.material.shear_limit *= scale;
  s.id = bk_runtime_add_breakable(s.rt, &bd, &err);
  ENSURE_MSG(!bk_breakable_is_null(s.id), "%s", err.message);
  take_created(s.rt, s.bodies);
  return s;
}

static void free_scene(scene* s) {
  bk_runtime_destroy(s->rt);
  free(s->bodies);
}

// Solves and splits until nothing is left to do (at most `calls` calls).
static uint32_t settle(scene* s, uint32_t calls) {
  for (uint32_t i = 0; i < calls; ++i) {
    bk_runtime_solve_stress(s->rt, gravity, NULL, 0, NULL, 0);
    uint32_t n = bk_runtime_broken_bonds(s->rt, NULL, 0);
    bk_bond_break* broken = calloc(n + 1u, sizeof *broken);
    bk_runtime_broken_bonds(s->rt, broken, n);
    for (uint32_t k = 0; k < n; ++k)
      ENSURE(broken[k].cause == BK_BREAK_STRESS);
    free(broken);
    s->broken_by_stress += n;
    bk_runtime_split(s->rt);
    take_created(s->rt, s->bodies);
    bk_runtime_stats st = bk_runtime_get_stats(s->rt);
    if (st.stress_clusters_pending == 0 && st.pending_splits == 0 && n == 0) return i + 1;
  }
  return calls;
}

static bool leaf_static(const scene* s, uint32_t leaf) {
  bk_cluster_info info = {0};
  bk_cluster_id c = bk_runtime_leaf_cluster(s->rt, s->id, leaf);
  return bk_runtime_cluster(s->rt, c, &info) && info.is_static;
}

// Breaks a bond as a hit would (through the public API: damage at its
// centroid, strong enough for it and its near neighbours alone).
static void cut_bonds(scene* s, const bk_mesh_tree* tree, bool (*cut)(const bk_bond*, void*), void* user) {
  for (uint32_t k = 0; k < tree->bond_count; ++k) {
    if (!cut(&tree->bonds[k], user)) continue;
    double initial = 0.0;
    if (bk_runtime_bond_health(s->rt, s->id, k, &initial) <= 0.0) continue;
    // damage = frailty x J / s_min^3 at the centroid; just past its hit points.
    double s_min = 1e-4;
    bk_runtime_damage_at(s->rt, tree->bonds[k].centroid, 1.01 * initial * s_min * s_min * s_min);
  }
  bk_runtime_split(s->rt);
  take_created(s->rt, s->bodies);
}

// A sound structure stands: nothing breaks over 3,600 calls, and once
// solved it costs nothing.
static void test_sound_structures_stand(void) {
  struct {
    bk_shape shape;
    bk_fracture_pattern pattern;
    const char* material;
  } cases[] = {
      {BK_SHAPE_WALL, BK_PATTERN_VORONOI, "stone"},      {BK_SHAPE_PILLAR, BK_PATTERN_CLUSTERED, "stone"},
      {BK_SHAPE_WALL, BK_PATTERN_BRICK, "stone"},        {BK_SHAPE_TOWER, BK_PATTERN_VORONOI, "stone"},
      {BK_SHAPE_BRIDGE, BK_PATTERN_VORONOI, "concrete"}, {BK_SHAPE_BALCONY, BK_PATTERN_VORONOI, "concrete"}};
  for (size_t c = 0; c < sizeof cases / sizeof *cases; ++c) {
    bk_mesh_tree tree = make_tree(cases[c].shape, 256, cases[c].pattern);
    scene s = make_scene(&tree, cases[c].material, 1.0);
    uint32_t calls = settle(&s, 3600);
    ENSURE_MSG(calls < 200, "%s took %u calls", bk_shape_name(cases[c].shape), calls);
    double worst = 0.0;
    for (uint32_t k = 0; k < tree.bond_count; ++k) {
      bk_bond_stress bs = {0};
      ENSURE(bk_runtime_bond_stress(s.rt, s.id, k, &bs));
      worst = fmax(worst, bs.ratio);
    }
    printf("  %s (%s, %s): solved in %u calls, worst bond at %.3f of its limit\n",
           bk_shape_name(cases[c].shape), bk_fracture_pattern_name(cases[c].pattern), cases[c].material,
           calls, worst);
    ENSURE(worst > 0.0 && worst < 1.0);
    for (uint32_t i = calls; i < 3600; ++i) {
      bk_runtime_solve_stress(s.rt, gravity, NULL, 0, NULL, 0);
      bk_runtime_stats st = bk_runtime_get_stats(s.rt);
      ENSURE(st.stress_iterations == 0 && st.stress_clusters_solved == 0); // asleep: nothing to do
    }
    ENSURE(bk_runtime_get_stats(s.rt).bonds_broken == 0);
    // Turned upside down, the same structure has other loads: solved again.
    bk_runtime_solve_stress(s.rt, bk_v3(0, 9.81, 0), NULL, 0, NULL, 0);
    ENSURE(bk_runtime_get_stats(s.rt).stress_iterations > 0);
    free_scene(&s);
    bk_mesh_tree_free(&tree);
  }
}

typedef struct band {
  double low, high, keep_x; // bonds in [low, high] of y with x past keep_x
} band;

static bool in_band(const bk_bond* bond, void* user) {
  const band* b = user;
  return bond->centroid.y >= b->low && bond->centroid.y <= b->high && bond->centroid.x >= b->keep_x;
}

// The pillar shot through its middle from one side: a strip of its far side
// is left, and the stone above, its weight off to the side of that strip,
// bends it past what stone holds in tension and drops; without the stress
// solve it stays up.
static void test_pillar_drops_top(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_PILLAR, 128, BK_PATTERN_VORONOI);
  bk_aabb box = tree.nodes[0].bounds;
  double middle = 0.5 * (box.min.y + box.max.y), width = box.max.x - box.min.x;
  band cut = {middle - 0.15, middle + 0.15, box.min.x + 0.2 * width};
  for (int solve = 0; solve < 2; ++solve) {
    scene s = make_scene(&tree, "stone", 1.0);
    settle(&s, 200);
    ENSURE(bk_runtime_get_stats(s.rt).bonds_broken == 0);
    cut_bonds(&s, &tree, in_band, &cut);
    uint32_t by_hits = bk_runtime_get_stats(s.rt).bonds_broken;
    if (solve) settle(&s, 400);
    uint32_t above = 0, static_above = 0;
    for (uint32_t l = 0; l < tree.leaf_count; ++l) {
      bk_aabb leaf = bk_mesh_tree_leaf(&tree, l)->bounds;
      if (leaf.min.y < middle + 0.2) continue;
      above++;
      static_above += leaf_static(&s, l);
    }
    printf("  pillar cut (%u bonds by hits)%s: %u of %u fragments above still anchored, %u bonds broken by "
           "stress\n",
           by_hits, solve ? ", stress solved" : "", static_above, above, s.broken_by_stress);
    ENSURE(above > 10);
    if (solve)
      ENSURE(static_above == 0 && s.broken_by_stress > 0);
    else
      ENSURE(static_above == above); // the thin core holds it all, statically
    free_scene(&s);
  }
  bk_mesh_tree_free(&tree);
}

// A fragment high in a wall left hanging by its smallest bond falls (and
// only with the stress solve).
static void test_hanging_chip_falls(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 256, BK_PATTERN_VORONOI);
  // The highest fragment with at least three bonds; keep its smallest.
  uint32_t best = 0;
  double best_y = -INFINITY;
  for (uint32_t l = 0; l < tree.leaf_count; ++l) {
    uint32_t bonds = 0;
    for (uint32_t k = 0; k < tree.bond_count; ++k)
      bonds += tree.bonds[k].leaf_a == l || tree.bonds[k].leaf_b == l;
    double y = bk_mesh_tree_leaf(&tree, l)->bounds.min.y;
    if (bonds >= 3 && y > best_y) best = l, best_y = y;
  }
  uint32_t keep = UINT32_MAX;
  for (uint32_t k = 0; k < tree.bond_count; ++k)
    if ((tree.bonds[k].leaf_a == best || tree.bonds[k].leaf_b == best) &&
        (keep == UINT32_MAX || tree.bonds[k].area < tree.bonds[keep].area))
      keep = k;
  for (int solve = 0; solve < 2; ++solve) {
    scene s = make_scene(&tree, "stone", 1.0);
    settle(&s, 200);
    // Free the chip's other bonds one by one, at their centroids.
    for (uint32_t k = 0; k < tree.bond_count; ++k) {
      if (k == keep || (tree.bonds[k].leaf_a != best && tree.bonds[k].leaf_b != best)) continue;
      double initial = 0.0;
      bk_runtime_bond_health(s.rt, s.id, k, &initial);
      if (!bk_runtime_bond_health(s.rt, s.id, k, NULL)) continue;
      (void)initial;
      // A tiny hit just at that bond (damage falls off with distance cubed).
      bk_vec3 at = tree.bonds[k].centroid;
      double s_min = 1e-4;
      bk_runtime_damage_at(s.rt, at, 1.01 * initial * s_min * s_min * s_min);
      bk_runtime_split(s.rt);
      take_created(s.rt, s.bodies);
    }
    ENSURE(bk_runtime_bond_health(s.rt, s.id, keep, NULL) > 0.0); // still hanging by it
    if (solve) settle(&s, 400);
    bool hangs = leaf_static(&s, best);
    printf("  chip of %.2g m^3 by a bond of %.2g m^2%s: %s\n", bk_mesh_tree_leaf(&tree, best)->moments.v,
           tree.bonds[keep].area, solve ? ", stress solved" : "", hangs ? "hangs" : "falls");
    ENSURE(hangs == !solve);
    free_scene(&s);
  }
  bk_mesh_tree_free(&tree);
}

// Limits scaled down 10x bring the bridge down under its own weight; the
// same calls give the same breaks.
static void test_limits_and_determinism(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_BRIDGE, 256, BK_PATTERN_VORONOI);
  uint32_t broken[2] = {0};
  for (int run = 0; run < 2; ++run) {
    scene s = make_scene(&tree, "concrete", 0.1);
    settle(&s, 2000);
    broken[run] = s.broken_by_stress;
    uint32_t loose = 0;
    for (uint32_t l = 0; l < tree.leaf_count; ++l)
      loose += !leaf_static(&s, l);
    if (run == 0)
      printf("  bridge, limits / 10: %u bonds broken by stress, %u fragments loose\n", broken[run], loose);
    ENSURE(loose > tree.leaf_count / 10);
    free_scene(&s);
  }
  ENSURE(broken[0] > 0 && broken[0] == broken[1]);
  bk_mesh_tree_free(&tree);
}

// A weight on the bridge's deck (a load at a point of its span): small and
// changing, it wakes nothing; forty times the span's weight breaks it, even
// when it comes every other call.
static void test_loads(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_BRIDGE, 256, BK_PATTERN_VORONOI);
  scene s = make_scene(&tree, "concrete", 1.0);
  settle(&s, 400);
  bk_cluster_id bridge = {0, 0};
  ENSURE(bk_runtime_clusters(s.rt, &bridge, 1) == 1);
  bk_cluster_info info = {0};
  ENSURE(bk_runtime_cluster(s.rt, bridge, &info));
  bk_aabb box = tree.nodes[0].bounds;
  bk_vec3 middle = {0.5 * (box.min.x + box.max.x), box.max.y, 0.5 * (box.min.z + box.max.z)};
  double weight = info.mass * 9.81;
  // A few percent of its weight, changing every call: below what a solve is
  // worth (a tenth).
  for (uint32_t i = 0; i < 60; ++i) {
    bk_stress_load load = {bridge, middle, {0.0, -weight * (0.02 + 0.01 * (i % 3)), 0.0}};
    bk_runtime_solve_stress(s.rt, gravity, NULL, 0, &load, 1);
    ENSURE(bk_runtime_get_stats(s.rt).stress_clusters_solved == 0);
  }
  // A bad load is ignored, not a crash.
  bk_stress_load bad = {bridge, {NAN, 0, 0}, {0, -weight, 0}};
  bk_runtime_solve_stress(s.rt, gravity, NULL, 0, &bad, 1);
  ENSURE(bk_runtime_get_stats(s.rt).stress_clusters_solved == 0);
  // Forty times its weight on the middle of the span, as a resting
  // contact reports it: there one step, gone the next (averaged over calls).
  uint32_t broken = 0;
  for (uint32_t i = 0; i < 200 && !broken; ++i) {
    bk_stress_load load = {bridge, middle, {0.0, -80.0 * weight, 0.0}};
    bk_runtime_solve_stress(s.rt, gravity, NULL, 0, &load, i % 2);
    broken = bk_runtime_broken_bonds(s.rt, NULL, 0);
  }
  printf("  bridge under 40x its weight: %u bonds broken by stress\n", broken);
  ENSURE(broken > 0);
  free_scene(&s);
  bk_mesh_tree_free(&tree);
}

// The leaf under a point, found down the mesh tree, is the one trying every
// leaf of the cluster finds (nearest bounds, then nearest centroid), for
// points inside, on and around a wall, on the whole wall and on a piece of it.
static void test_leaf_at_matches_scan(void) {
  bk_mesh_tree tree = make_tree(BK_SHAPE_WALL, 512, BK_PATTERN_VORONOI);
  scene s = make_scene(&tree, "stone", 1.0);
  bk_runtime_damage_at(s.rt, bk_v3(0.0, 0.6, 0.1), 320.0); // holes it: clusters of all sizes
  bk_runtime_split(s.rt);
  take_created(s.rt, s.bodies);
  rt_breakable* b = &s.rt->breakables[0];
  rt_stress_prepare_breakable(b);
  bk_aabb box = tree.nodes[0].bounds;
  uint64_t random = 12345;
  uint32_t checked = 0;
  for (uint32_t slot = 0; slot < s.rt->cluster_count; ++slot) {
    const rt_cluster* c = &s.rt->clusters[slot];
    if (!c->alive || c->leaf_count < 2) continue;
    for (int i = 0; i < 200; ++i) {
      double u[3] = {0};
      for (int d = 0; d < 3; ++d) {
        random = random * 6364136223846793005u + 1442695040888963407u;
        u[d] = (double)(random >> 11) / 9007199254740992.0 * 1.4 - 0.2; // a margin around the bounds
      }
      bk_vec3 p = {box.min.x + u[0] * (box.max.x - box.min.x), box.min.y + u[1] * (box.max.y - box.min.y),
                   box.min.z + u[2] * (box.max.z - box.min.z)};
      uint32_t best = c->leaves[0];
      double best_box = INFINITY, best_centre = INFINITY;
      for (uint32_t k = 0; k < c->leaf_count; ++k) {
        bk_aabb lb = bk_mesh_tree_leaf(&tree, c->leaves[k])->bounds;
        double dx = fmax(fmax(lb.min.x - p.x, p.x - lb.max.x), 0.0);
        double dy = fmax(fmax(lb.min.y - p.y, p.y - lb.max.y), 0.0);
        double dz = fmax(fmax(lb.min.z - p.z, p.z - lb.max.z), 0.0);
        double d2 = dx * dx + dy * dy + dz * dz;
        double centre = bk_v3_length(bk_v3_sub(b->leaf_centroid[c->leaves[k]], p));
        if (d2 < best_box || (d2 == best_box && centre < best_centre))
          best = c->leaves[k], best_box = d2, best_centre = centre;
      }
      ENSURE(rt_stress_leaf_at(b, c, p) == best);
      checked++;
    }
  }
  printf("  leaf under a point: %u points, down the tree as by trying every leaf\n", checked);
  ENSURE(checked >= 400);
  free_scene(&s);
  bk_mesh_tree_free(&tree);
}

static void test_validation(void) {
  bk_material m = *bk_material_find("stone");
  bk_error err = {0};
  m.tension_limit = 0.0;
  ENSURE(!bk_material_validate(&m, &err));
  ENSURE_MSG(strstr(err.message, "material.tension_limit"), "%s", err.message);
  m.tension_limit = NAN;
  ENSURE(!bk_material_validate(&m, &err));
  m.tension_limit = INFINITY; // never fails in tension
  ENSURE(bk_material_validate(&m, &err));
  bk_runtime_def def = bk_default_runtime_def();
  def.body_state = body_state;
  def.stress_budget = 0;
  ENSURE(!bk_runtime_create(&def, &err));
  ENSURE_MSG(strstr(err.message, "stress_budget"), "%s", err.message);
  def = bk_default_runtime_def();
  def.body_state = body_state;
  def.stress_tolerance = 0.5;
  ENSURE(!bk_runtime_create(&def, &err));
  ENSURE_MSG(strstr(err.message, "stress_tolerance"), "%s", err.message);
  for (uint32_t i = 0; i < bk_material_count(); ++i)
    ENSURE(bk_material_validate(bk_material_at(i), &err));
}

int main(void) {
  test_column();
  test_cantilever();
  test_cantilever_tip_load();
  test_multigrid_matches_direct();
  test_validation();
  test_sound_structures_stand();
  test_pillar_drops_top();
  test_hanging_chip_falls();
  test_limits_and_determinism();
  test_loads();
  test_leaf_at_matches_scan();
  printf("test_stress: ok\n");
  return 0;
}
