// Section 10 of 'breakables bench': refinement at the impact (issue 34),
// first its speed. A fine torus (the asset section's 100,000 triangles) is
// cut into ten arcs of about 10,000 triangles each (Voronoi cells round
// seeds on its ring); four of them rest on the ground, and each of their 40
// arcs is hit once, a hit every few steps, hard enough to refine it into 32
// pieces round the hit (the --refine rule: refine_strength an eighth of the
// bond strength) and to knock the nearest pieces loose. Measured: what the
// calling thread pays in the step that lands a refinement, through the
// Bullet world (bk_world_stats.refine_ms: bk_runtime_refine and the new
// nodes' hulls) and in the runtime alone (the bk_runtime_refine call), with
// the fracture on a worker (latency 1) and on the calling thread (latency
// 0); the worker's own time (bk_mesh_fracture_leaf alone); and the steps
// from the hit to the pieces' bodies. All in CPU time of the thread: the
// landing call waits for the worker, which the clock would count.
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "app.h"
#include "bench_report.h"
#include "scene_run.h"

enum {
  SPEED_SEEDS = 10,  ///< arcs of the torus (one Voronoi seed each, round its ring)
  SPEED_COPIES = 4,  ///< tori side by side: 40 arcs, 40 hits
  SPEED_HIT_GAP = 6, ///< steps between hits: each refinement lands in a step of its own
  SPEED_TAIL = 30,   ///< steps after the last hit
  SPEED_PIECES = 32, ///< pieces per refinement (--refine's default)
  TORUS_RING = 250,  ///< the asset section's torus: 2 x 250 x 200 = 100,000 triangles
  TORUS_TUBE = 200,  //
  QUICK_RING = 80,   ///< --quick: 2 x 80 x 60 = 9,600 triangles ...
  QUICK_TUBE = 60,   //
  QUICK_SEEDS = 4,   ///< ... into 4 arcs of about 2,400,
  QUICK_COPIES = 1,  ///< one torus, 4 hits
  MAX_HITS = SPEED_SEEDS * SPEED_COPIES,
};

static const double torus_major = 1.0, torus_minor = 0.35; // bench_fine_torus's radii
static const double copy_spacing = 3.0;                    // m between the tori's centres
static const double hit_impulse = 100.0;                   // N s: refines the arc hit, and no other
static const double step_target_ms = 2.0;                  // issue 34: work a step at p99
static const uint32_t steps_target = 2;                    // and pieces in the simulation within two steps

static double thread_ms(void) {
  struct timespec t = {0};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return (double)t.tv_sec * 1e3 + (double)t.tv_nsec * 1e-6;
}

/// The torus of the speed test and its hits.
typedef struct speed_load {
  bk_mesh_tree tree;
  uint32_t copies, hits;
  bk_vec3 points[MAX_HITS];  ///< world points of the hits, in the order they are made
  uint32_t leaves[MAX_HITS]; ///< the arc (leaf of the tree as built) each hits
  double leaf_triangles;     ///< mean triangles of an arc
  uint32_t source_triangles;
} speed_load;

static bk_vec3 copy_position(uint32_t copy) {
  // Resting on the ground (its tube's bottom at y = 0), a millimetre up.
  return (bk_vec3){copy * copy_spacing, torus_minor + 0.001, 0.0};
}

static bool speed_load_make(const bench* b, speed_load* load, bk_error* err) {
  memset(load, 0, sizeof *load);
  uint32_t seeds = b->quick ? QUICK_SEEDS : SPEED_SEEDS;
  load->copies = b->quick ? QUICK_COPIES : SPEED_COPIES;
  load->hits = seeds * load->copies;
  bk_mesh torus = {0};
  bench_fine_torus(b->quick ? QUICK_RING : TORUS_RING, b->quick ? QUICK_TUBE : TORUS_TUBE, &torus);
  load->source_triangles = torus.triangle_count;
  bk_vec3 points[SPEED_SEEDS];
  for (uint32_t k = 0; k < seeds; ++k) {
    double phi = 2.0 * 3.14159265358979323846 * (k + 0.5) / seeds;
    points[k] = (bk_vec3){torus_major * cos(phi), 0.0, -torus_major * sin(phi)};
  }
  bk_fracture_def def = bk_default_fracture_def();
  def.pattern = BK_PATTERN_VORONOI;
  def.seed_points = points;
  def.seed_point_count = seeds;
  def.seed = b->seed;
  bool ok = bk_mesh_tree_build(&torus, &def, &load->tree, err);
  bk_mesh_free(&torus);
  if (!ok) return false;
  double triangles = 0.0;
  for (uint32_t l = 0; l < load->tree.leaf_count; ++l)
    triangles += bk_mesh_tree_leaf(&load->tree, l)->mesh.triangle_count;
  load->leaf_triangles = triangles / load->tree.leaf_count;
  // Each arc once, the tori in turn: on the outer equator, above the arc's centroid.
  for (uint32_t h = 0; h < load->hits; ++h) {
    uint32_t copy = h % load->copies, leaf = (h / load->copies) % load->tree.leaf_count;
    const bk_mesh_tree_node* n = bk_mesh_tree_leaf(&load->tree, leaf);
    bk_vec3 c = bk_mesh_tree_mass(&load->tree, n->moments).centroid;
    double phi = atan2(-c.z, c.x), r = torus_major + torus_minor;
    load->points[h] = bk_v3_add(copy_position(copy), (bk_vec3){r * cos(phi), 0.0, -r * sin(phi)});
    load->leaves[h] = leaf;
  }
  return true;
}

/// The --refine settings (scene_refine) at SPEED_PIECES pieces, but for the
/// smallest size: a hit refines an arc once, not its pieces again (the
/// pieces' bonds take its waiting damage, and that damage would pass their
/// smaller threshold), so that each landing is one fragment's.
static void refine_settings(bk_breakable_def* def, const bk_mesh_tree* tree, uint32_t copy) {
  def->tree = tree;
  def->material = *bk_material_find("stone");
  def->material.refine_strength = def->material.bond_strength / 8.0;
  double arc = bk_mesh_tree_leaf(tree, 0)->moments.v / SPEED_PIECES;
  def->refine = (bk_refine_def){.pattern = BK_PATTERN_RADIAL,
                                .pieces = SPEED_PIECES,
                                .min_size = 0.75 * cbrt(arc),
                                .radial_falloff = 1.0};
  def->transform.position = copy_position(copy);
}

/// One setup's measurements over the hits.
typedef struct speed_result {
  double land_ms[MAX_HITS];  ///< the calling thread's time in the step (call) that landed each hit's pieces
  double start_ms[MAX_HITS]; ///< and in the step that started it (latency 1)
  uint32_t steps[MAX_HITS];  ///< steps from the hit (1: its own) to the one that landed its pieces; 0: never
  bool hit_landed[MAX_HITS]; ///< the hit refined a fragment (a hit below the threshold refines none)
  uint32_t landed, refined;  ///< hits whose refinement landed; fragments refined in all
  /// In the step that made the pieces' bodies: the world's break handling
  /// and body creation (fracture_ms: the split, and the hulls of the nodes
  /// the new bodies use), or the runtime's bk_runtime_split call
  double bodies_ms[MAX_HITS];
  double step_ms[MAX_HITS]; ///< refinement and body creation in that step together (the world)
} speed_result;

static uint32_t steps_total(const speed_load* load) { return load->hits * SPEED_HIT_GAP + SPEED_TAIL; }

// Through the Bullet world: bk_world_impact at each point, a step at a time.
static bool speed_world(const speed_load* load, uint32_t latency, speed_result* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  bk_world_def wd = bk_default_world_def();
  wd.runtime.refine_latency = latency;
  bk_world* world = bk_world_create(&wd, err);
  if (!world) return false;
  bool ok = true;
  for (uint32_t c = 0; ok && c < load->copies; ++c) {
    bk_world_breakable_def def = bk_default_world_breakable_def();
    refine_settings(&def.breakable, &load->tree, c);
    ok = !bk_breakable_is_null(bk_world_add_breakable(world, &def, err));
  }
  for (uint32_t i = 0; i < 30 && ok; ++i)
    bk_world_step(world); // settled on the ground
  uint32_t hit = 0, steps = steps_total(load);
  bk_world_stats at_hit[MAX_HITS];
  uint32_t hit_step[MAX_HITS] = {0};
  bool landed[MAX_HITS] = {false};
  for (uint32_t step = 0; ok && step < steps; ++step) {
    if (hit < load->hits && step == hit * SPEED_HIT_GAP) {
      at_hit[hit] = bk_world_get_stats(world);
      hit_step[hit] = step;
      bk_world_impact(world, load->points[hit++], hit_impulse);
    }
    bk_world_step(world);
    bk_world_stats st = bk_world_get_stats(world);
    for (uint32_t h = 0; h < hit; ++h) {
      if (step == hit_step[h]) out->start_ms[h] = st.refine_ms;
      // Its pieces are in the simulation from the step that lands them: the
      // fragment's body covers them, and the split that follows in that
      // step makes bodies of those the hit knocked loose.
      // (Before the next hit: a hit below the threshold refines nothing, and
      // the next one's landing is not its.)
      if (!landed[h] && step < hit_step[h] + SPEED_HIT_GAP && st.refined_leaves > at_hit[h].refined_leaves) {
        landed[h] = out->hit_landed[h] = true;
        out->land_ms[out->landed++] = st.refine_ms;
        out->steps[h] = step - hit_step[h] + 1;
        out->bodies_ms[h] = st.fracture_ms;
        out->step_ms[h] = st.fracture_ms + st.refine_ms;
      }
    }
  }
  out->refined = bk_world_get_stats(world).refined_leaves;
  bk_world_destroy(world);
  return ok;
}

// ---------------------------------------------------------------- the runtime alone

static bk_body_state body_states[8192];

static bk_body_state body_state(bk_cluster_id cluster, void* context) {
  (void)context;
  return body_states[cluster.index % 8192u];
}

static uint32_t take_created(bk_runtime* rt) {
  uint32_t n = bk_runtime_created_clusters(rt, NULL, 0);
  bk_cluster_created* created = bk_alloc(sizeof *created * (n ? n : 1u));
  bk_runtime_created_clusters(rt, created, n);
  for (uint32_t i = 0; i < n; ++i)
    body_states[created[i].cluster.id.index % 8192u] = created[i].body;
  free(created);
  bk_runtime_clear_events(rt);
  return n;
}

// The same hits on the runtime alone: the time of each bk_runtime_refine call.
static bool speed_runtime(const speed_load* load, uint32_t latency, speed_result* out, bk_error* err) {
  memset(out, 0, sizeof *out);
  bk_runtime_def rd = bk_default_runtime_def();
  rd.refine_latency = latency;
  rd.body_state = body_state;
  bk_runtime* rt = bk_runtime_create(&rd, err);
  if (!rt) return false;
  bool ok = true;
  for (uint32_t c = 0; ok && c < load->copies; ++c) {
    bk_breakable_def def = bk_default_breakable_def();
    refine_settings(&def, &load->tree, c);
    ok = !bk_breakable_is_null(bk_runtime_add_breakable(rt, &def, err));
  }
  take_created(rt);
  uint32_t hit = 0, steps = steps_total(load), started = 0;
  uint32_t hit_step[MAX_HITS] = {0};
  for (uint32_t step = 0; ok && step < steps; ++step) {
    if (hit < load->hits && step == hit * SPEED_HIT_GAP) {
      hit_step[hit] = step;
      bk_runtime_damage_at(rt, load->points[hit++], hit_impulse);
    }
    double start = thread_ms();
    uint32_t refined = bk_runtime_refine(rt);
    double spent = thread_ms() - start;
    start = thread_ms();
    bk_runtime_split(rt);
    double split_ms = thread_ms() - start;
    uint32_t created = take_created(rt);
    if (started < hit && step == hit_step[started]) out->start_ms[started++] = spent;
    if (refined) {
      // One hit refines one arc; its pieces are clusters when the split made some.
      uint32_t h = out->landed;
      out->land_ms[out->landed++] = spent;
      if (h < hit) out->hit_landed[h] = true;
      if (h < hit && created) {
        out->steps[h] = step - hit_step[h] + 1;
        out->bodies_ms[h] = split_ms;
        out->step_ms[h] = spent + split_ms;
      }
    }
  }
  out->refined = bk_runtime_get_stats(rt).refined_leaves;
  bk_runtime_destroy(rt);
  return ok;
}

// The worker's part alone: each hit arc fractured as the runtime does
// (refine_jobs.c: the leaf's mesh, the tree's bounds, a radial pattern at
// the hit in the tree frame, one thread).
static bool speed_worker(const speed_load* load, speed_result* out, double* pieces_mean, bk_error* err) {
  memset(out, 0, sizeof *out);
  double pieces = 0.0;
  for (uint32_t h = 0; h < load->hits; ++h) {
    const bk_mesh_tree_node* n = bk_mesh_tree_leaf(&load->tree, load->leaves[h]);
    bk_fracture_def def = bk_default_fracture_def();
    def.pattern = BK_PATTERN_RADIAL;
    def.pieces = SPEED_PIECES;
    def.seed = load->tree.desc.seed + h;
    def.impact = bk_v3_sub(load->points[h], copy_position(h % load->copies));
    def.radial_falloff = 1.0;
    def.texture_scale = load->tree.desc.texture_scale;
    def.aspect_bias = load->tree.desc.aspect_bias;
    def.threads = 1;
    bk_mesh_tree made = {0};
    double start = thread_ms();
    bool ok = bk_mesh_fracture_leaf(&n->mesh, load->tree.nodes[0].bounds, &def, &made, err);
    out->land_ms[out->landed++] = thread_ms() - start;
    pieces += made.leaf_count;
    bk_mesh_tree_free(&made);
    if (!ok) return false;
  }
  *pieces_mean = pieces / load->hits;
  return true;
}

// ---------------------------------------------------------------- the table

static const bench_column speed_columns[] = {{"setup", "setup"},
                                             {"latency", "latency"},
                                             {"hits", "hits"},
                                             {"refined", "fragments refined"},
                                             {"leaf_triangles", "triangles a fragment"},
                                             {"refine_ms_p50", "refine ms p50"},
                                             {"refine_ms_p99", "refine ms p99"},
                                             {"refine_ms_max", "refine ms max"},
                                             {"start_ms_max", "starting step ms max"},
                                             {"bodies_ms_p50", "bodies ms p50"},
                                             {"bodies_ms_p99", "bodies ms p99"},
                                             {"bodies_ms_max", "bodies ms max"},
                                             {"step_ms_p99", "step work ms p99"},
                                             {"steps_to_bodies_max", "steps to bodies (max)"},
                                             {"target_met", "target met"}};

typedef struct speed_summary {
  double refine[3], bodies[3], step_p99, start_max; ///< p50, p99, max
  uint32_t steps_max, never;
} speed_summary;

static void percentiles(const double* values, uint32_t count, double out[3]) {
  double sorted[MAX_HITS];
  memcpy(sorted, values, sizeof(double) * count);
  out[0] = app_percentile(sorted, count, 50.0);
  out[1] = app_percentile(sorted, count, 99.0);
  out[2] = app_maximum(sorted, count);
}

static speed_summary summarize(const speed_result* r, uint32_t hits) {
  speed_summary s = {0};
  double step[3] = {0};
  percentiles(r->land_ms, r->landed, s.refine);
  s.start_max = app_maximum(r->start_ms, hits);
  // Over the hits whose pieces got bodies.
  double bodies[MAX_HITS] = {0}, work[MAX_HITS] = {0};
  uint32_t made = 0;
  for (uint32_t h = 0; h < hits; ++h) {
    s.steps_max = r->steps[h] > s.steps_max ? r->steps[h] : s.steps_max;
    s.never += r->hit_landed[h] && r->steps[h] == 0; // refined, and its pieces never had bodies
    if (r->steps[h]) bodies[made] = r->bodies_ms[h], work[made++] = r->step_ms[h];
  }
  percentiles(bodies, made, s.bodies);
  percentiles(work, made, step);
  s.step_p99 = step[1];
  return s;
}

static bool speed_met(speed_summary s) {
  return s.step_p99 <= step_target_ms && s.never == 0 && s.steps_max <= steps_target;
}

static void speed_cells(bench_table* t, const char* setup, int latency, const speed_load* load,
                        const speed_result* r, speed_summary s) {
  bench_table_cell(t, "%s", setup);
  if (latency >= 0)
    bench_table_cell(t, "%d", latency);
  else
    bench_table_cell(t, "-");
  bench_table_cell(t, "%u", load->hits);
  bench_table_cell(t, "%u", r->refined);
  bench_table_cell(t, "%.0f", load->leaf_triangles);
  for (int i = 0; i < 3; ++i)
    bench_table_cell(t, "%.3f", s.refine[i]);
  if (latency < 0) { // the worker: its fracture alone
    for (int i = 0; i < 7; ++i)
      bench_table_cell(t, "-");
    return;
  }
  bench_table_cell(t, "%.3f", s.start_max);
  for (int i = 0; i < 3; ++i)
    bench_table_cell(t, "%.3f", s.bodies[i]);
  bench_table_cell(t, "%.3f", s.step_p99);
  if (s.never)
    bench_table_cell(t, "never (%u)", s.never);
  else
    bench_table_cell(t, "%u", s.steps_max);
  bench_table_cell(t, "%s", speed_met(s) ? "yes" : "no");
}

static bool speed_plot(const bench* b) {
  bench_script s = {0};
  bench_script_add(
      &s,
      "unset logscale x\nset title 'Refining a fragment: the calling thread''s CPU time in the "
      "landing step'\n"
      "set ylabel 'ms'\nset style data histograms\nset style histogram clustered gap 1\n"
      "set style fill solid 0.7 border -1\nset xtics rotate by -12 nomirror\n"
      "plot 'refine_speed.csv' using 'refine_ms_p50':xtic(strcol('setup')) title 'refinement p50', \\\n"
      "     '' using 'refine_ms_p99' title 'refinement p99', \\\n"
      "     '' using 'bodies_ms_p99' title 'body creation p99', \\\n"
      "     '' using 'step_ms_p99' title 'both, p99', \\\n"
      "     %g with lines dt 3 lc rgb 'gray30' title 'target (2 ms a step at p99)'",
      step_target_ms);
  return bench_plot(b, "refine_speed", "Main-thread cost of a refinement, and the worker's (log scale)", 1000,
                    540, &s);
}

static bool section_speed(const bench* b) {
  speed_load load = {0};
  bk_error err = {0};
  speed_result world1 = {0}, world0 = {0}, rt1 = {0}, rt0 = {0}, worker = {0};
  double pieces_mean = 0.0;
  bool ok = speed_load_make(b, &load, &err) && speed_world(&load, 1, &world1, &err) &&
            speed_world(&load, 0, &world0, &err) && speed_runtime(&load, 1, &rt1, &err) &&
            speed_runtime(&load, 0, &rt0, &err) && speed_worker(&load, &worker, &pieces_mean, &err);
  if (!ok) {
    fprintf(stderr, "breakables bench: refinement of the torus: %s\n", err.message);
    bk_mesh_tree_free(&load.tree);
    return false;
  }
  bench_table t =
      bench_table_make("refine_speed", speed_columns, sizeof speed_columns / sizeof *speed_columns);
  speed_summary s_world1 = summarize(&world1, load.hits), s_world0 = summarize(&world0, load.hits);
  speed_summary s_rt1 = summarize(&rt1, load.hits), s_rt0 = summarize(&rt0, load.hits);
  speed_summary s_worker = summarize(&worker, load.hits);
  worker.refined = load.hits;
  speed_cells(&t, "world: on a worker", 1, &load, &world1, s_world1);
  speed_cells(&t, "world: synchronous", 0, &load, &world0, s_world0);
  speed_cells(&t, "runtime: on a worker", 1, &load, &rt1, s_rt1);
  speed_cells(&t, "runtime: synchronous", 0, &load, &rt0, s_rt0);
  speed_cells(&t, "worker: the fracture alone", -1, &load, &worker, s_worker);
  ok = bench_table_write(b, &t) && speed_plot(b);
  bench_table_free(&t);
  if (ok)
    bench_say(
        b,
        "**Does refining a fragment of about 10,000 triangles into 32 pieces keep to 2 ms of work a "
        "step at p99, with its pieces in the simulation within two steps?** %s. Over %u hits (each "
        "refined %.2f fragments of %.0f triangles on average, into %.1f pieces), the step that lands a "
        "refinement spends %.3f ms of the calling thread's time on it at the median, %.3f at p99 and %.3f "
        "at worst (`bk_runtime_refine`; in the runtime alone %.3f, %.3f and %.3f), and making the pieces' "
        "bodies (the split and the hulls of the nodes the new bodies use) %.3f, %.3f and %.3f: %.3f ms "
        "of work in that step at p99 (target 2). The step that starts it spends %.3f at worst; the "
        "pieces had their bodies %u steps after the hit at most (the hit's step counted as the first). "
        "The worker's fracture of a fragment takes %.2f ms at the median and %.2f at worst, %s one 60 Hz "
        "frame (16.7 ms), the time it has before the landing step joins it%s. Without the worker (latency "
        "0) the hit's step pays for the fracture: %.2f ms at the median, %.2f at p99, %.2f at worst, and "
        "the pieces arrive in %u step%s.%s\n\n",
        speed_met(s_world1) ? "Yes" : "No", load.hits, (double)world1.refined / load.hits,
        load.leaf_triangles, pieces_mean, s_world1.refine[0], s_world1.refine[1], s_world1.refine[2],
        s_rt1.refine[0], s_rt1.refine[1], s_rt1.refine[2], s_world1.bodies[0], s_world1.bodies[1],
        s_world1.bodies[2], s_world1.step_p99, s_world1.start_max, s_world1.steps_max, s_worker.refine[0],
        s_worker.refine[2], s_worker.refine[2] < 1000.0 / 60.0 ? "within" : "more than",
        s_worker.refine[2] < 1000.0 / 60.0
            ? ""
            : " (in a game the landing step would wait for the rest, which CPU time does not count)",
        s_world0.refine[0], s_world0.refine[1], s_world0.refine[2], s_world0.steps_max,
        s_world0.steps_max == 1 ? "" : "s",
        b->quick ? " These are `--quick`'s smaller fragments; run without it for 10,000 triangles." : "");
  bk_mesh_tree_free(&load.tree);
  return ok;
}

bool bench_section_refine(const bench* b) {
  bench_section(
      b, "10. Refinement at the impact",
      "*Speed.* A ring torus of 100,000 triangles (the asset section's) cut into ten arcs of about 10,000 "
      "triangles each (Voronoi cells round ten seeds on its ring); four of them rest on the ground in a "
      "Bullet world, and each of their 40 arcs is hit once (`bk_world_impact`, 100 N s on its outer "
      "equator), a hit every 6 steps. Stone, refined as `--refine` refines (refine_strength an eighth of "
      "the bond strength; 32 pieces, radial round the hit) but for its smallest size (three quarters of "
      "an arc's (volume / 32)^(1/3)), so that each hit refines the arc it strikes and not its pieces "
      "again; the hit knocks the pieces nearest it loose. The same hits on the runtime alone "
      "(`bk_runtime_damage_at`, then `bk_runtime_refine` and `bk_runtime_split` a step). With the "
      "fracture on a worker (`refine_latency` 1, the default: the hit's step starts it, the next lands "
      "it) or synchronous (latency 0: the hit's step fractures and lands it). *Refine ms*: the calling "
      "thread's CPU time in the step that landed a refinement (the world's `bk_world_stats.refine_ms`, "
      "or the `bk_runtime_refine` call), p50, p99 and max over the hits; *starting step*: the same in "
      "the hit's step; *bodies ms*: in the step that made the pieces' bodies, the world's break handling "
      "and body creation (`fracture_ms`: the split, and the hulls of the nodes the new bodies use), or "
      "the `bk_runtime_split` call; *step work*: the two together in that step, p99; *steps to bodies*: "
      "from the hit (its own step the first) to the step that landed its pieces (from then they are in "
      "the simulation: the fragment's body covers them, and that step's split makes bodies of those the "
      "hit knocked loose; in the runtime alone, to the step whose split made clusters of them). The last "
      "row is the worker's work alone: `bk_mesh_fracture_leaf` on each hit arc as the runtime calls it "
      "(one thread). CPU time, not the clock: the landing call waits for the worker, which in a game "
      "running at 60 Hz has had a frame. Target (issue 34): at most 2 ms of work a step at p99 (*step "
      "work*), pieces in the simulation within two steps.");
  return section_speed(b) && bench_refine_walls(b);
}
