// Section 10 of 'breakables bench', its second part: what refinement buys.
// The wall scene pre-fractured into 64 and refined where it is shot, against
// the same wall pre-fractured into 64 and into 1,024 without refinement, the
// same shots: each run is what `breakables sim --scene wall --pieces N
// [--refine]` runs (its shots, steps and world), so a row can be repeated
// there. Measured: the tree's memory at load and at the end, its fracture
// and cached load time, bodies and colliders, the fragments within each
// shot's damage radius, and the physics and refinement cost of a step.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "bench_report.h"
#include "scene_run.h"

enum {
  WALL_SHOTS = 3,        ///< sim's defaults: 3 shots ...
  WALL_STEPS = 300,      ///< ... over 300 steps
  QUICK_WALL_SHOTS = 2,  ///< --quick: 2 shots ...
  QUICK_WALL_STEPS = 90, ///< ... over 90 steps
  WALL_LOAD_RUNS = 3,    ///< fractures and cached loads timed (the median)
  WALL_SETUPS = 3,
  FINE_PIECES = 1024, ///< the fine wall, whose bonds define the damage radius
};

typedef struct wall_setup {
  uint32_t pieces;
  bool refine;
} wall_setup;

static const wall_setup setups[WALL_SETUPS] = {{64, false}, {64, true}, {FINE_PIECES, false}};

/// A tree's bytes in memory: its node, leaf and bond arrays, and the meshes
/// of nodes [first_mesh, node_count) (positions, corners, indices, materials, tags).
static uint64_t tree_bytes(const bk_mesh_tree* t, uint32_t first_mesh) {
  uint64_t bytes = (uint64_t)t->node_count * sizeof(bk_mesh_tree_node) +
                   (uint64_t)t->leaf_count * sizeof(uint32_t) + (uint64_t)t->bond_count * sizeof(bk_bond);
  for (uint32_t i = first_mesh; i < t->node_count; ++i) {
    const bk_mesh* m = &t->nodes[i].mesh;
    bytes += (uint64_t)m->position_count * sizeof(bk_vec3) + (uint64_t)m->corner_count * sizeof(bk_corner) +
             (uint64_t)m->triangle_count *
                 (3 * sizeof(uint32_t) + sizeof(uint8_t) + (m->tags ? sizeof(uint32_t) : 0));
  }
  return bytes;
}

/// How long the wall's tree takes to make: fractured afresh, and loaded
/// from its .mtree file (as the cache loads it).
typedef struct wall_timing {
  double fracture_ms, load_ms;
  double median_bond_area; ///< of the tree's bonds
} wall_timing;

static int compare_doubles(const void* a, const void* b) {
  double x = *(const double*)a, y = *(const double*)b;
  return (x > y) - (x < y);
}

static bool time_wall_tree(const bench* b, const app_scene* scene, uint32_t pieces, wall_timing* out,
                           bk_error* err) {
  scene_options options = default_scene_options();
  options.seed = b->seed;
  options.pieces = pieces;
  bk_fracture_def fd = scene_fracture_def(scene, 0, &options, NULL);
  bk_mesh source = {0};
  if (!scene_object_source(&scene->objects[0], &source)) {
    return bk_error_set(err, "cannot make the mesh '%s'", scene->objects[0].mesh);
  }
  bk_mesh_tree tree = {0};
  double builds[WALL_LOAD_RUNS] = {0}, start = 0.0;
  bool ok = true;
  for (uint32_t r = 0; ok && r < WALL_LOAD_RUNS; ++r) {
    bk_mesh_tree_free(&tree);
    start = app_now_ms();
    ok = bk_mesh_tree_build(&source, &fd, &tree, err);
    builds[r] = app_now_ms() - start;
  }
  out->fracture_ms = app_median(builds, WALL_LOAD_RUNS);
  bk_mesh_free(&source);
  char path[PATH_MAX];
  snprintf(path, sizeof path, "%s/refine_wall_%u.mtree", b->dir, pieces);
  ok = ok && bk_mesh_tree_save(&tree, path, err);
  double times[WALL_LOAD_RUNS] = {0};
  for (uint32_t r = 0; ok && r < WALL_LOAD_RUNS; ++r) {
    bk_mesh_tree loaded = {0};
    start = app_now_ms();
    ok = bk_mesh_tree_load(path, &loaded, err);
    times[r] = app_now_ms() - start;
    bk_mesh_tree_free(&loaded);
  }
  remove(path);
  out->load_ms = app_median(times, WALL_LOAD_RUNS);
  if (ok && tree.bond_count) {
    double* areas = bk_alloc(sizeof(double) * tree.bond_count);
    for (uint32_t i = 0; i < tree.bond_count; ++i)
      areas[i] = tree.bonds[i].area;
    qsort(areas, tree.bond_count, sizeof(double), compare_doubles);
    out->median_bond_area = areas[tree.bond_count / 2];
    free(areas);
  }
  bk_mesh_tree_free(&tree);
  return ok;
}

/// What one run measured.
typedef struct wall_run {
  uint64_t bytes_load, bytes_end;
  uint32_t leaves_load, leaves_end, refined;
  uint32_t bodies_max, bodies_end, colliders_max, colliders_end;
  double physics_mean, physics_p99; ///< CPU ms a step, from the first shot on
  double refine_p99, refine_max;    ///< CPU ms a step, every step
  double break_p99, break_max;      ///< break handling and body creation, CPU ms a step, every step
  double near_mean;                 ///< fragments within the damage radius of a shot, mean over the shots
  uint32_t near_min, near_max;
  bk_vec3 points[WALL_SHOTS]; ///< where each shot's path meets the wall's box
  double impulse[WALL_SHOTS]; ///< the largest impulse (N s) one contact of each shot's ball applied
  double radius[WALL_SHOTS];  ///< each shot's damage radius (m)
  uint32_t shots;
} wall_run;

/// Where shot `shot` first meets the box `bounds` (world), along its path; false if it misses.
static bool shot_point(const app_scene* scene, uint32_t shot, bk_aabb bounds, bk_vec3* out) {
  bk_projectile_def p = scene_shot(scene, shot, 0.0);
  double speed = bk_v3_length(p.velocity), enter = 0.0, leave = INFINITY;
  if (!(speed > 0.0)) return false;
  bk_vec3 d = bk_v3_scale(p.velocity, 1.0 / speed);
  const double o[3] = {p.position.x, p.position.y, p.position.z}, v[3] = {d.x, d.y, d.z};
  const double lo[3] = {bounds.min.x, bounds.min.y, bounds.min.z},
               hi[3] = {bounds.max.x, bounds.max.y, bounds.max.z};
  for (int k = 0; k < 3; ++k) {
    if (fabs(v[k]) < 1e-12) {
      if (o[k] < lo[k] || o[k] > hi[k]) return false;
      continue;
    }
    double t0 = (lo[k] - o[k]) / v[k], t1 = (hi[k] - o[k]) / v[k];
    enter = fmax(enter, fmin(t0, t1));
    leave = fmin(leave, fmax(t0, t1));
  }
  if (enter > leave) return false;
  *out = bk_v3_add(p.position, bk_v3_scale(d, enter));
  return true;
}

static bk_aabb world_bounds(bk_transform placement, bk_aabb b) {
  bk_aabb out = {{INFINITY, INFINITY, INFINITY}, {-INFINITY, -INFINITY, -INFINITY}};
  for (int corner = 0; corner < 8; ++corner) {
    bk_vec3 p = {corner & 1 ? b.max.x : b.min.x, corner & 2 ? b.max.y : b.min.y,
                 corner & 4 ? b.max.z : b.min.z};
    p = bk_transform_point(placement, p);
    out.min = bk_v3_min(out.min, p);
    out.max = bk_v3_max(out.max, p);
  }
  return out;
}

// Fragments of `tree` whose centroid, where the wall stood, is within `radius` of `point`.
static uint32_t fragments_near(const bk_mesh_tree* tree, bk_transform placement, bk_vec3 point,
                               double radius) {
  uint32_t count = 0;
  for (uint32_t l = 0; l < tree->leaf_count; ++l) {
    bk_vec3 c = bk_mesh_tree_mass(tree, bk_mesh_tree_leaf(tree, l)->moments).centroid;
    count += bk_v3_length(bk_v3_sub(bk_transform_point(placement, c), point)) <= radius;
  }
  return count;
}

/// Runs the wall of `setup` as sim does. Each shot's damage radius is
/// `radii`'s, or with NULL its own: where its largest contact impulse, one
/// hit of frailty x impulse / s^3, breaks a bond of `bond_area`.
static bool run_wall(const bench* b, const app_scene* scene, const wall_setup* setup, const double* radii,
                     double bond_area, wall_run* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  scene_options options = default_scene_options();
  options.seed = b->seed;
  options.pieces = setup->pieces;
  options.refine = setup->refine;
  loaded_scene loaded = {0};
  if (!loaded_scene_create(scene, &options, &loaded, err)) return false;
  bk_world_set_focus(loaded.world, loaded.scene->eye); // as sim does
  const bk_mesh_tree* tree = &loaded.trees[0];
  bk_transform placement = scene_object_def(&scene->objects[0], tree, &options).breakable.transform;
  bk_aabb bounds = world_bounds(placement, tree->nodes[0].bounds);
  out->bytes_load = tree_bytes(tree, 0);
  out->leaves_load = tree->leaf_count;
  uint32_t shots = b->quick ? QUICK_WALL_SHOTS : WALL_SHOTS, steps = b->quick ? QUICK_WALL_STEPS : WALL_STEPS;
  double* physics = bk_alloc(sizeof(double) * 3 * steps);
  double *refine = physics + steps, *breaks = physics + 2 * steps;
  enum { CONTACTS = 8192 };
  bk_contact* contacts = bk_alloc(sizeof(bk_contact) * CONTACTS);
  bk_body_id balls[WALL_SHOTS] = {{0}};
  bk_material stone = bk_world_material(loaded.world, loaded.ids[0]);
  uint32_t timed = 0, fired = 0;
  for (uint32_t step = 0; step < steps; ++step) {
    // sim's shots (loaded_scene_fire, one copy): at regular intervals,
    // leaving time after the last one.
    while (fired < shots && step >= (fired + 1) * steps / (shots + 1)) {
      if (!shot_point(loaded.scene, fired, bounds, &out->points[fired]))
        out->points[fired] = (bk_vec3){NAN, NAN, NAN}; // no fragment is near a miss
      bk_projectile_def p = scene_shot(loaded.scene, fired, 0.0);
      balls[fired++] = bk_world_fire(loaded.world, &p, NULL);
    }
    out->shots = fired;
    bk_world_step(loaded.world);
    uint32_t n = bk_physics_contacts(bk_world_physics(loaded.world), contacts, CONTACTS);
    for (uint32_t i = 0; i < n && i < CONTACTS; ++i)
      for (uint32_t s = 0; s < fired; ++s)
        if (bk_body_equal(contacts[i].a, balls[s]) || bk_body_equal(contacts[i].b, balls[s]))
          out->impulse[s] = fmax(out->impulse[s], contacts[i].impulse);
    bk_world_stats st = bk_world_get_stats(loaded.world);
    refine[step] = st.refine_ms;
    breaks[step] = st.fracture_ms;
    if (fired) physics[timed++] = st.physics_cpu_ms;
    out->bodies_max = st.bodies > out->bodies_max ? st.bodies : out->bodies_max;
    out->colliders_max = st.colliders > out->colliders_max ? st.colliders : out->colliders_max;
  }
  bk_world_stats end = bk_world_get_stats(loaded.world);
  out->bodies_end = end.bodies, out->colliders_end = end.colliders, out->refined = end.refined_leaves;
  double sum = 0.0;
  for (uint32_t i = 0; i < timed; ++i)
    sum += physics[i];
  out->physics_mean = timed ? sum / timed : 0.0;
  out->physics_p99 = app_percentile(physics, timed, 99.0);
  out->refine_p99 = app_percentile(refine, steps, 99.0);
  out->refine_max = app_maximum(refine, steps);
  out->break_p99 = app_percentile(breaks, steps, 99.0);
  out->break_max = app_maximum(breaks, steps);
  free(physics);
  free(contacts);
  for (uint32_t s = 0; s < out->shots; ++s)
    out->radius[s] =
        radii ? radii[s] : cbrt(stone.frailty * out->impulse[s] / (stone.bond_strength * bond_area));
  // The tree as it stands: the one loaded, or the runtime's grown copy of
  // it (its arrays, and the meshes of the nodes refinement added).
  const bk_mesh_tree* now = bk_runtime_breakable_tree(bk_world_runtime(loaded.world), loaded.ids[0]);
  out->leaves_end = now->leaf_count;
  out->bytes_end = out->bytes_load + (now != tree ? tree_bytes(now, tree->node_count) : 0);
  out->near_min = UINT32_MAX;
  for (uint32_t s = 0; s < out->shots; ++s) {
    uint32_t near = fragments_near(now, placement, out->points[s], out->radius[s]);
    out->near_mean += (double)near / out->shots;
    out->near_min = near < out->near_min ? near : out->near_min;
    out->near_max = near > out->near_max ? near : out->near_max;
  }
  if (!out->shots) out->near_min = 0;
  loaded_scene_destroy(&loaded);
  return true;
}

static const bench_column wall_columns[] = {{"wall", "wall"},
                                            {"refine", "refined"},
                                            {"fragments_load", "fragments at load"},
                                            {"fragments_end", "fragments at the end"},
                                            {"refined_leaves", "fragments refined"},
                                            {"tree_kb_load", "tree KB at load"},
                                            {"tree_kb_end", "tree KB at the end"},
                                            {"fracture_ms", "fracture ms"},
                                            {"cached_load_ms", "cached load ms"},
                                            {"bodies_max", "bodies max"},
                                            {"bodies_end", "bodies at the end"},
                                            {"colliders_max", "colliders max"},
                                            {"colliders_end", "colliders at the end"},
                                            {"near_shot_mean", "fragments near a shot (mean)"},
                                            {"near_shot_min", "near (min)"},
                                            {"near_shot_max", "near (max)"},
                                            {"physics_ms_mean", "physics ms mean"},
                                            {"physics_ms_p99", "physics ms p99"},
                                            {"refine_ms_p99", "refine ms p99"},
                                            {"refine_ms_max", "refine ms max"},
                                            {"bodies_ms_p99", "bodies ms p99"},
                                            {"bodies_ms_max", "bodies ms max"}};

static void wall_cells(bench_table* t, const wall_setup* setup, const wall_timing* timing,
                       const wall_run* r) {
  bench_table_cell(t, "%u", setup->pieces);
  bench_table_cell(t, "%s", setup->refine ? "yes" : "no");
  bench_table_cell(t, "%u", r->leaves_load);
  bench_table_cell(t, "%u", r->leaves_end);
  bench_table_cell(t, "%u", r->refined);
  bench_table_cell(t, "%.1f", r->bytes_load / 1024.0);
  bench_table_cell(t, "%.1f", r->bytes_end / 1024.0);
  bench_table_cell(t, "%.2f", timing->fracture_ms);
  bench_table_cell(t, "%.3f", timing->load_ms);
  bench_table_cell(t, "%u", r->bodies_max);
  bench_table_cell(t, "%u", r->bodies_end);
  bench_table_cell(t, "%u", r->colliders_max);
  bench_table_cell(t, "%u", r->colliders_end);
  bench_table_cell(t, "%.1f", r->near_mean);
  bench_table_cell(t, "%u", r->near_min);
  bench_table_cell(t, "%u", r->near_max);
  bench_table_cell(t, "%.3f", r->physics_mean);
  bench_table_cell(t, "%.3f", r->physics_p99);
  bench_table_cell(t, "%.3f", r->refine_p99);
  bench_table_cell(t, "%.3f", r->refine_max);
  bench_table_cell(t, "%.3f", r->break_p99);
  bench_table_cell(t, "%.3f", r->break_max);
}

static bool walls_plot(const bench* b) {
  bench_script s = {0};
  bench_script_add(
      &s, "%s",
      "unset logscale x\nset title 'The wall of 64 refined where it is shot, against 64 and 1024'\n"
      "set style data histograms\nset style histogram clustered gap 1\n"
      "set style fill solid 0.7 border -1\nset key below\n"
      "plot 'refine_walls.csv' using 'fragments_end':xtic(strcol('wall').(strcol('refine') eq "
      "'yes' ? ', refined' : '')) title 'fragments at the end', \\\n"
      "     '' using 'near_shot_mean' title 'fragments near a shot (mean)', \\\n"
      "     '' using 'bodies_max' title 'bodies (max)', '' using 'colliders_max' title "
      "'colliders (max)', \\\n"
      "     '' using 'tree_kb_end' title 'tree KB at the end'");
  return bench_plot(b, "refine_walls", "The refined wall against the coarse and the fine one (log scale)",
                    1000, 540, &s);
}

bool bench_refine_walls(const bench* b) {
  const app_scene* scene = scene_find("wall");
  if (!scene) return false;
  wall_timing timing[2] = {{0}}; // 64, 1024
  bk_error err = {0};
  bool ok = time_wall_tree(b, scene, setups[0].pieces, &timing[0], &err) &&
            time_wall_tree(b, scene, FINE_PIECES, &timing[1], &err);
  // The fine wall first: its shots' contacts give every run's damage radii.
  wall_run runs[WALL_SETUPS];
  memset(runs, 0, sizeof runs);
  ok = ok && run_wall(b, scene, &setups[2], NULL, timing[1].median_bond_area, &runs[2], &err);
  for (uint32_t i = 0; ok && i < 2; ++i)
    ok = run_wall(b, scene, &setups[i], runs[2].radius, timing[1].median_bond_area, &runs[i], &err);
  if (!ok) {
    fprintf(stderr, "breakables bench: the refined wall: %s\n", err.message);
    return false;
  }
  const bk_material* stone = bk_material_find(scene->objects[0].material);
  uint32_t shots = b->quick ? QUICK_WALL_SHOTS : WALL_SHOTS, steps = b->quick ? QUICK_WALL_STEPS : WALL_STEPS;
  bench_say(
      b,
      "*What it buys.* The wall scene (2 x 1.2 x 0.2 m of stone, brick pattern, anchored) pre-fractured "
      "into 64 and refined where it is shot (`--refine`: 32 pieces a refinement), against the same wall "
      "pre-fractured into 64 and into 1024 without refinement, with the same %u shots over %u steps "
      "(each row is `breakables sim --scene wall --pieces N [--refine] --shots %u --steps %u`, the "
      "default physics budget on). *Tree KB*: the tree's node, leaf and bond arrays and its nodes' "
      "meshes, at load and at the end (the loaded tree plus, when refined, the runtime's grown copy of "
      "its arrays and the meshes of its new nodes). *Fracture ms*: the tree built afresh (wall clock, "
      "all cores), *cached load ms*: read back from its `.mtree` file, each the median of %u runs. "
      "*Fragments "
      "near a shot*: the fragments of the tree at the end whose centroid, where the wall stood, is "
      "within the shot's damage radius of where its path meets the wall's box: the distance s at which "
      "the largest impulse J one contact of the shot's ball applied to the 1024 wall, as one hit "
      "(damage = frailty x J / s^3), breaks a bond of the 1024 wall's median area (%.3g m^2, %.0f hit "
      "points), the same radius for every wall; mean, min and max over the shots. Here J was",
      shots, steps, shots, steps, WALL_LOAD_RUNS, timing[1].median_bond_area,
      stone->bond_strength * timing[1].median_bond_area);
  for (uint32_t s = 0; s < runs[2].shots; ++s)
    bench_say(b, "%s %.0f N s (radius %.3f m)",
              s == 0                   ? ""
              : s + 1 == runs[2].shots ? " and"
                                       : ",",
              runs[2].impulse[s], runs[2].radius[s]);
  bench_say(b,
            " (the ball's momentum is %.0f N s). *Physics*: the physics engine's CPU time a step from the "
            "first shot on; *refine*: each step's refinement (`bk_world_stats.refine_ms`: "
            "landing the pieces), *bodies* its break handling and body creation (`fracture_ms`: damage, "
            "splits, and the bodies they make with their hulls), p99 and max over every step.\n\n",
            scene->projectile_mass * scene->projectile_speed);
  bench_table t = bench_table_make("refine_walls", wall_columns, sizeof wall_columns / sizeof *wall_columns);
  for (uint32_t i = 0; i < WALL_SETUPS; ++i)
    wall_cells(&t, &setups[i], &timing[setups[i].pieces == FINE_PIECES], &runs[i]);
  ok = bench_table_write(b, &t) && walls_plot(b);
  bench_table_free(&t);
  if (!ok) return false;
  const wall_run *coarse = &runs[0], *refined = &runs[1], *fine = &runs[2];
  bench_say(
      b,
      "**What does refinement buy against a finer pre-fractured wall?** Near the shots the refined wall "
      "holds %.1f fragments within the damage radius on average (the coarse wall %.1f, the 1024 wall "
      "%.1f), while holding %u fragments in all at the end (%.0f%% of the 1024 wall's %u; %u refined), "
      "a tree of %.0f KB at load and %.0f KB at the end against %.0f KB, fractured in %.1f ms (cached "
      "load %.2f ms) against %.1f ms (%.2f ms). Bodies peaked at %u (1024 wall: %u, coarse: %u), "
      "colliders at %u (%u, %u); physics %.2f ms a step on average and %.2f at p99 (1024 wall: %.2f and "
      "%.2f); a step's refinement %.2f ms at p99 and %.2f at worst, its break handling and body creation "
      "%.2f "
      "and %.2f (1024 wall: %.2f and %.2f).\n",
      refined->near_mean, coarse->near_mean, fine->near_mean, refined->leaves_end,
      100.0 * refined->leaves_end / fine->leaves_end, fine->leaves_end, refined->refined,
      refined->bytes_load / 1024.0, refined->bytes_end / 1024.0, fine->bytes_end / 1024.0,
      timing[0].fracture_ms, timing[0].load_ms, timing[1].fracture_ms, timing[1].load_ms, refined->bodies_max,
      fine->bodies_max, coarse->bodies_max, refined->colliders_max, fine->colliders_max,
      coarse->colliders_max, refined->physics_mean, refined->physics_p99, fine->physics_mean,
      fine->physics_p99, refined->refine_p99, refined->refine_max, refined->break_p99, refined->break_max,
      fine->break_p99, fine->break_max);
  return true;
}
