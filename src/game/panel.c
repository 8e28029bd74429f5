// The live tuning panel. Frailty and density change the objects in the world
// at once; pattern, pieces, seed and texture scale re-fracture on a worker
// thread (the game keeps running, a progress bar shows how far it got) and the
// result is cached so the next start is instant.
#include <pthread.h>
#include <stdatomic.h>
#include <string.h>

#include "panel.h"
#include "panel_budget.h"
#include "panel_refine.h"
#include "ui.h"

typedef struct refracture_job {
  pthread_t thread;
  bool running;
  atomic_bool done;
  atomic_uint leaves, target;
  scene_options options;
  const app_scene* scene;
  loaded_scene result;
  bool ok;
  bk_error err;
} refracture_job;

static refracture_job job;

// The runtime sweep of `breakables bench`, on the current scene, in the panel.
enum { SWEEP_POINTS = 6 };
typedef struct sweep_job {
  pthread_t thread;
  bool running, finished, ok, show;
  atomic_bool done;
  atomic_uint progress; // points measured
  const app_scene* scene;
  uint64_t seed;
  uint32_t pieces[SWEEP_POINTS], colliders[2][SWEEP_POINTS];
  float worst_ms[2][SWEEP_POINTS]; // [mesh tree, plain BCRB]
  bk_error err;
} sweep_job;

static sweep_job sweep;

static void* run_sweep(void* unused) {
  (void)unused;
  sweep.ok = true;
  for (uint32_t i = 0; i < SWEEP_POINTS && sweep.ok; ++i) {
    sweep.pieces[i] = 16u << i;
    bk_mesh_tree tree = {0};
    sweep.ok = app_load_scene_tree(sweep.seed, sweep.scene, sweep.pieces[i], &tree, &sweep.err);
    for (int naive = 0; naive < 2 && sweep.ok; ++naive) {
      app_impact setup = {
          .scene = sweep.scene, .tree = &tree, .copies = 1, .naive = naive == 1, .steps_after = 120};
      impact_result result = {0};
      sweep.ok = impact_run(&setup, &result, &sweep.err);
      sweep.worst_ms[naive][i] = (float)result.hit_step_ms;
      sweep.colliders[naive][i] = result.colliders;
    }
    bk_mesh_tree_free(&tree);
    atomic_store(&sweep.progress, i + 1);
  }
  atomic_store(&sweep.done, true);
  return NULL;
}

// Joins a finished sweep; true while it still runs.
static bool sweep_running(void) {
  if (sweep.running && atomic_load(&sweep.done)) {
    pthread_join(sweep.thread, NULL);
    sweep.running = false;
    sweep.finished = true;
  }
  return sweep.running;
}

static void start_sweep(app_game* g) {
  if (sweep.running) return;
  memset(&sweep, 0, sizeof sweep);
  sweep.scene = g->scene.scene;
  sweep.seed = g->options.seed;
  sweep.running = pthread_create(&sweep.thread, NULL, run_sweep, NULL) == 0;
  sweep.show = true;
}

// The sweep's own window: progress while it runs, then plots and a table.
static void sweep_window(void) {
  bool running = sweep_running();
  if (!sweep.show || !ui_begin_window("Runtime sweep", 380.0f, 10.0f, 470.0f, 340.0f, &sweep.show)) return;
  ui_text("%s: one shot at 16..512 fragments,", sweep.scene->name);
  ui_text("mesh tree against plain BCRB (one collider per fragment)");
  if (running) {
    char overlay[64];
    snprintf(overlay, sizeof overlay, "%u / %d fragment counts", atomic_load(&sweep.progress), SWEEP_POINTS);
    ui_progress((float)atomic_load(&sweep.progress) / SWEEP_POINTS, overlay);
  } else if (!sweep.ok) {
    ui_text("sweep failed: %s", sweep.err.message);
  } else {
    float top = 1.0f;
    for (int m = 0; m < 2; ++m)
      for (int i = 0; i < SWEEP_POINTS; ++i)
        top = fmaxf(top, sweep.worst_ms[m][i]);
    ui_plot("mesh tree", sweep.worst_ms[0], SWEEP_POINTS, 0, 0.0f, top, 60.0f, "worst step ms");
    ui_plot("plain BCRB", sweep.worst_ms[1], SWEEP_POINTS, 0, 0.0f, top, 60.0f, "worst step ms");
    ui_text("fragments  worst step  colliders | plain BCRB");
    for (int i = 0; i < SWEEP_POINTS; ++i)
      ui_text("%9u  %7.2f ms  %9u | %7.2f ms  %u", sweep.pieces[i], sweep.worst_ms[0][i],
              sweep.colliders[0][i], sweep.worst_ms[1][i], sweep.colliders[1][i]);
  }
  ui_end_window();
}
static int pieces_setting = 0, seed_setting = 3000;
static double texture_scale_setting = 0.1;
// The pattern selector's entry: 0 = each object's own, 1 + a bk_fracture_pattern
// otherwise; -1 until it is read from the game's options. The parameters of
// the clustered and radial patterns start at the library's defaults.
static int pattern_setting = -1, clusters_setting = 0;
static double cluster_border_setting = 0.0, radial_falloff_setting = -1.0, noise_setting = 0.0;
static char status_line[600];

static bool report_progress(void* user, uint32_t leaves, uint32_t target) {
  (void)user;
  atomic_store(&job.leaves, leaves);
  atomic_store(&job.target, target);
  return true;
}

static void* refracture(void* unused) {
  (void)unused;
  // Trees only: a Bullet world is created and stepped on the game's thread
  // alone (bullet.h), so the world is made when the game takes the result.
  job.ok = loaded_scene_load_trees(job.scene, &job.options, &job.result, &job.err);
  atomic_store(&job.done, true);
  return NULL;
}

static void start_refracture(app_game* g) {
  if (job.running) return;
  memset(&job.result, 0, sizeof job.result);
  job.options = g->options;
  job.options.pieces = (uint32_t)pieces_setting;
  job.options.seed = (uint64_t)seed_setting;
  job.options.texture_scale = texture_scale_setting;
  job.options.pattern = pattern_setting - 1;
  job.options.clusters = (uint32_t)clusters_setting;
  job.options.cluster_border = cluster_border_setting;
  job.options.radial_falloff = radial_falloff_setting;
  job.options.noise = noise_setting;
  job.options.progress = report_progress;
  job.scene = g->scene.scene;
  atomic_store(&job.done, false);
  atomic_store(&job.leaves, 0);
  atomic_store(&job.target, job.options.pieces ? job.options.pieces : job.scene->pieces);
  job.running = pthread_create(&job.thread, NULL, refracture, NULL) == 0;
  if (!job.running) snprintf(status_line, sizeof status_line, "cannot start the fracture thread");
}

// Swaps in a finished re-fracture: the new trees and world replace the old.
static void finish_refracture(app_game* g) {
  if (!job.running || !atomic_load(&job.done)) return;
  pthread_join(job.thread, NULL);
  job.running = false;
  if (!job.ok) {
    snprintf(status_line, sizeof status_line, "re-fracture failed: %s", job.err.message);
    return;
  }
  uint32_t index = g->scene_index;
  g->options.pieces = job.options.pieces;
  g->options.seed = job.options.seed;
  g->options.texture_scale = job.options.texture_scale;
  g->options.pattern = job.options.pattern;
  g->options.clusters = job.options.clusters;
  g->options.cluster_border = job.options.cluster_border;
  g->options.radial_falloff = job.options.radial_falloff;
  g->options.noise = job.options.noise;
  // The trees are cached now, so the game's reload (next frame, on its own
  // thread, where worlds are made) finds them at once and keeps the camera.
  uint32_t leaves = job.result.trees[0].leaf_count;
  loaded_scene_destroy(&job.result);
  g->next_scene = (int)index;
  g->reload = true;
  g->reload_keeps_camera = true;
  snprintf(status_line, sizeof status_line, "re-fractured into %u pieces (%s)", leaves,
           pattern_setting > 0 ? bk_fracture_pattern_name((bk_fracture_pattern)(pattern_setting - 1))
                               : "each object's own pattern");
}

// The world's runtime owns the live values: the panel reads them back every
// frame and writes changes to every object; the options only record what the
// next reset builds.
static void material_section(app_game* g) {
  const char* names[16];
  int count = (int)bk_material_count();
  for (int i = 0; i < count && i < 16; ++i)
    names[i] = bk_material_at((uint32_t)i)->name;
  bk_world* world = g->scene.world;
  bk_breakable_id first = g->scene.ids[0];
  bk_material live = bk_world_material(world, first);
  int preset = -1;
  for (int i = 0; i < count && live.name; ++i)
    if (strcmp(names[i], live.name) == 0) preset = i;
  if (ui_combo("preset", &preset, names, count) && preset >= 0)
    loaded_scene_apply_material(&g->scene, &g->options, bk_material_at((uint32_t)preset));
  live = bk_world_material(world, first);
  double frailty = live.frailty, density = live.density, strength = live.bond_strength;
  if (ui_slider_double("frailty", &frailty, 0.01, 50.0, "%.2f", true)) {
    g->options.frailty = frailty;
    for (uint32_t i = 0; i < g->scene.tree_count; ++i)
      bk_world_set_frailty(world, g->scene.ids[i], frailty);
  }
  ui_tooltip("damage = frailty x impulse / distance^3 (applies now)");
  if (ui_slider_double("density kg/m3", &density, 50.0, 20000.0, "%.0f", true)) {
    g->options.density = density;
    for (uint32_t i = 0; i < g->scene.tree_count; ++i)
      bk_world_set_density(world, g->scene.ids[i], density);
  }
  ui_tooltip("masses and inertia are recomputed now");
  if (ui_slider_double("bond strength", &strength, 1e4, 1e8, "%.3g", true)) {
    g->options.bond_strength = strength;
    for (uint32_t i = 0; i < g->scene.tree_count; ++i)
      bk_world_set_bond_strength(world, g->scene.ids[i], strength);
    game_refine_follow(g); // how hard a hit must be to refine goes with it
  }
  ui_tooltip("hit points per m^2 of contact (intact bonds keep the fraction they have left)");
  int kind = live.accumulate ? 1 : 0;
  bool kind_changed = ui_radio("discrete", &kind, 0);
  ui_same_line();
  kind_changed |= ui_radio("accumulating", &kind, 1);
  if (kind_changed) {
    g->options.accumulate = kind;
    for (uint32_t i = 0; i < g->scene.tree_count; ++i) {
      bk_material m = bk_world_material(world, g->scene.ids[i]);
      m.accumulate = kind == 1;
      bk_world_set_material(world, g->scene.ids[i], &m);
    }
  }
  bool convex = g->options.convex_colliders, naive = g->options.naive;
  if (ui_checkbox("convex colliders", &convex)) g->options.convex_colliders = convex;
  ui_same_line();
  if (ui_checkbox("plain BCRB", &naive)) g->options.naive = naive;
  ui_tooltip("colliders are chosen when bodies are made (applies on reset)");
  if (ui_button("reset with these settings (R)")) g->reload = true;
}

// Structural stress: the switch is the world's and the limits are the
// runtime's (the first object's shown, a change written to every object, as
// the material's other values); the options only record them for the next
// reset. A new limit makes the runtime solve every cluster again.
static void stress_section(app_game* g) {
  bk_world* world = g->scene.world;
  bool on = bk_world_stress(world);
  if (ui_checkbox("structural stress", &on)) {
    g->options.stress = on;
    bk_world_set_stress(world, on);
  }
  ui_tooltip("each step the weight of what stands is carried through its bonds down to the ground; a "
             "bond past a limit breaks and what it held falls (off: whatever is bonded to an anchor "
             "stays up however little holds it)");
  static const char* const labels[3] = {"compression", "tension", "shear"};
  static const char* const tips[3] = {
      "the push a bond takes per m^2 before it crushes (stone 10 MPa, concrete 20)",
      "the pull a bond takes per m^2 before it cracks open: what a tower bent over its notch or a "
      "deck sagging between its legs fails by (stone 0.4 MPa, concrete 1.5)",
      "the sliding a bond takes per m^2 before it shears off: what gives where a balcony leaves its "
      "wall (stone 0.8 MPa, concrete 2.5)"};
  bk_material live = bk_world_material(world, g->scene.ids[0]);
  double* limits[3] = {&live.compression_limit, &live.tension_limit, &live.shear_limit};
  double* recorded[3] = {&g->options.compression_limit, &g->options.tension_limit, &g->options.shear_limit};
  for (int k = 0; k < 3; ++k) {
    double mpa = *limits[k] * 1e-6;
    bool changed = ui_slider_double(labels[k], &mpa, 0.001, 100.0, "%.3g MPa", true);
    ui_tooltip(tips[k]);
    if (!changed || !(mpa > 0.0)) continue;
    *recorded[k] = mpa * 1e6;
    for (uint32_t i = 0; i < g->scene.tree_count; ++i) {
      bk_material m = bk_world_material(world, g->scene.ids[i]);
      double* limit = k == 0 ? &m.compression_limit : k == 1 ? &m.tension_limit : &m.shear_limit;
      *limit = mpa * 1e6;
      bk_world_set_material(world, g->scene.ids[i], &m);
    }
  }
  if (ui_button("the material's limits")) {
    g->options.stress_scale = 1.0;
    g->options.compression_limit = g->options.tension_limit = g->options.shear_limit = 0.0;
    for (uint32_t i = 0; i < g->scene.tree_count; ++i) {
      bk_material m = bk_world_material(world, g->scene.ids[i]);
      const bk_material* preset = m.name ? bk_material_find(m.name) : NULL;
      if (!preset) continue;
      // As the scene made it: an old concrete's limits are its own, but a
      // preset chosen for every object is that preset as it is.
      double own = g->scene.scene->objects[i].stress_scale;
      if (g->options.material || !(own > 0.0)) own = 1.0;
      m.compression_limit = preset->compression_limit * own;
      m.tension_limit = preset->tension_limit * own;
      m.shear_limit = preset->shear_limit * own;
      bk_world_set_material(world, g->scene.ids[i], &m);
    }
  }
  ui_tooltip("each object's limits back to its own: its preset's (the bridge's and the balcony's old "
             "concrete: 22% and 40% of them)");
  // The weight X sets down: a load to carry, where a shot is a hit.
  ui_slider_double("weight kg", &g->weight_kg, 100.0, 1e5, "%.0f", true);
  ui_tooltip("the mass of the ball X sets down at rest on what you look at (the bridge's old "
             "concrete carries 500 kg in the middle of its deck and breaks under 1,000)");
  ui_slider_double("radius m", &g->weight_radius, BK_DROP_RADIUS_MIN, BK_DROP_RADIUS_MAX, "%.2f", true);
  ui_tooltip("the weight's radius: the smaller, the more its load bears on one place");
  bk_vec3 surface = {0.0, 0.0, 0.0};
  if (ui_button("set one on the target") && scene_drop_point(&g->scene, &surface) &&
      app_drop_weight(world, surface, g->weight_kg, g->weight_radius, NULL))
    g->weights++;
  ui_tooltip("on the top surface over the scene's aim point (X: over what you look at); it stays "
             "until the scene is reset");
  bk_world_stats s = bk_world_get_stats(world);
  ui_text("bonds broken by stress %u   solve %.2f ms", s.stress_bonds_broken, s.stress_ms);
  ui_text("clusters still to solve %u", s.stress_clusters_pending);
}

// True when the selector's choice breaks some object of the scene by `pattern`.
static bool pattern_used(const app_scene* scene, bk_fracture_pattern pattern) {
  if (pattern_setting > 0) return pattern_setting == 1 + (int)pattern;
  for (uint32_t i = 0; i < scene->object_count; ++i)
    if (scene->objects[i].pattern == pattern) return true;
  return false;
}

// The pattern selector: the scene's own choice first (named when all its
// objects share one), then every pattern, with the parameters of the chosen
// one worth tuning by eye.
static void pattern_selector(app_game* g) {
  const app_scene* scene = g->scene.scene;
  if (pattern_setting < 0) pattern_setting = g->options.pattern + 1;
  bk_fracture_pattern own = scene->objects[0].pattern;
  for (uint32_t i = 1; i < scene->object_count; ++i)
    if (scene->objects[i].pattern != own) own = BK_PATTERN_COUNT;
  char scene_default[64];
  snprintf(scene_default, sizeof scene_default, "scene default (%s)",
           own == BK_PATTERN_COUNT ? "per object" : bk_fracture_pattern_name(own));
  const char* names[1 + BK_PATTERN_COUNT] = {scene_default};
  for (int p = 0; p < BK_PATTERN_COUNT; ++p)
    names[1 + p] = bk_fracture_pattern_name((bk_fracture_pattern)p);
  ui_combo("pattern", &pattern_setting, names, 1 + BK_PATTERN_COUNT);
  ui_tooltip(
      "how the objects break: the scene's choice (walls brick, pillar clustered, bunny, torus, tower, bridge "
      "and balcony radial round their aim points, eggshell voronoi, the rest planes) or one pattern "
      "for all (applies on re-fracture)");
  bk_fracture_def defaults = bk_default_fracture_def();
  if (pattern_used(scene, BK_PATTERN_CLUSTERED)) {
    if (clusters_setting == 0) clusters_setting = (int)defaults.clusters;
    if (!(cluster_border_setting > 0.0)) cluster_border_setting = defaults.cluster_border;
    ui_slider_int("clusters", &clusters_setting, 1, 64);
    ui_slider_double("cluster border", &cluster_border_setting, 0.01, 0.5, "%.2f", true);
    ui_tooltip("width of a chunk's finely broken border, a fraction of the object's size");
  }
  if (pattern_used(scene, BK_PATTERN_RADIAL)) {
    if (radial_falloff_setting < 0.0) radial_falloff_setting = defaults.radial_falloff;
    ui_slider_double("radial falloff", &radial_falloff_setting, 0.0, 1.4, "%.2f", false);
    ui_tooltip("how fast pieces grow away from the aim point (0 = evenly)");
  }
  ui_slider_double("noise", &noise_setting, 0.0, 0.05, "%.3f", false);
  ui_tooltip("rough cut faces: how far they bend, a fraction of each object's size (0 = flat; brick "
             "stays flat along its mortar; applies on re-fracture)");
}

static void fracture_section(app_game* g) {
  if (pieces_setting == 0)
    pieces_setting = (int)(g->options.pieces ? g->options.pieces : g->scene.scene->pieces);
  pattern_selector(g);
  ui_slider_int("pieces", &pieces_setting, 2, 4096);
  ui_slider_int("seed", &seed_setting, 0, 100000);
  ui_slider_double("texture scale", &texture_scale_setting, 0.01, 2.0, "%.2f", true);
  if (job.running) {
    uint32_t leaves = atomic_load(&job.leaves), target = atomic_load(&job.target);
    char overlay[64];
    snprintf(overlay, sizeof overlay, "%u / %u pieces", leaves, target);
    ui_progress(target ? (float)leaves / (float)target : 0.0f, overlay);
  } else if (ui_button("re-fracture")) {
    start_refracture(g);
  }
  if (status_line[0]) ui_text("%s", status_line);
}

static void stats_section(app_game* g) {
  bk_world_stats s = bk_world_get_stats(g->scene.world);
  int latest = (g->history_at + BK_HISTORY - 1) % BK_HISTORY;
  float frame_ms = g->frame_history[latest];
  ui_text("%.0f fps   frame %.2f ms", frame_ms > 0.0f ? 1000.0f / frame_ms : 0.0f, frame_ms);
  ui_text("physics %.2f ms   breaking %.2f ms", g->physics_ms, g->break_ms);
  ui_text("bodies %u (%u moving)   fragments free %u", s.bodies, s.dynamic_bodies, s.fragments_free);
  ui_text("colliders %u   plain BCRB would use %u", s.colliders, s.colliders_naive);
  ui_text("bonds broken %u   splits %u   projectiles %u", s.bonds_broken, s.break_events, s.projectiles);
  ui_text("small fragments retired %u", s.fragments_retired);
  int offset = g->history_at % BK_HISTORY;
  ui_plot("frame ms", g->frame_history, BK_HISTORY, offset, 0.0f, 40.0f, 40.0f, NULL);
  ui_plot("physics ms", g->physics_history, BK_HISTORY, offset, 0.0f, 20.0f, 40.0f, NULL);
  ui_plot("break ms", g->break_history, BK_HISTORY, offset, 0.0f, 5.0f, 40.0f, NULL);
}

void game_panel(app_game* g) {
  finish_refracture(g);
  if (g->start_benchmark) {
    g->start_benchmark = false;
    start_sweep(g);
  }
  sweep_window();
  if (!ui_begin_window("Breakables", 10.0f, 10.0f, 360.0f, 0.0f, &g->show_panel)) {
    ui_end_window();
    return;
  }
  const char* scenes[16];
  int count = (int)scene_count(), current = (int)g->scene_index;
  for (int i = 0; i < count && i < 16; ++i)
    scenes[i] = scene_at((uint32_t)i)->name;
  if (ui_combo("scene", &current, scenes, count) && current != (int)g->scene_index) {
    g->next_scene = current;
    g->reload = true;
    pieces_setting = 0;
  }
  if (ui_collapsing_header("Material", true)) material_section(g);
  if (ui_collapsing_header("Structural stress", false)) stress_section(g);
  if (ui_collapsing_header("Fracture", false)) fracture_section(g);
  // Open from the start when the game was started with refinement.
  if (ui_collapsing_header("Refinement", g->options.refine)) game_refine_section(g);
  if (ui_collapsing_header("Projectile", false)) {
    // A user's model's shots are sized to it, maybe beyond these ranges:
    // they reach its own, so that touching a slider does not clamp it.
    const app_scene* scene = g->scene.scene;
    ui_slider_double("speed m/s", &g->projectile_speed, fmin(1.0, scene->projectile_speed),
                     fmax(200.0, scene->projectile_speed), "%.0f", false);
    ui_slider_double("radius m", &g->projectile_radius, fmin(0.01, scene->projectile_radius),
                     fmax(0.5, scene->projectile_radius), "%.2f", false);
    ui_slider_double("mass kg", &g->projectile_mass, fmin(0.05, scene->projectile_mass),
                     fmax(200.0, scene->projectile_mass), "%.2f", true);
  }
  if (ui_collapsing_header("World", false)) {
    bk_physics* physics = bk_world_physics(g->scene.world);
    double gravity = -bk_physics_gravity(physics).y;
    if (ui_slider_double("gravity m/s2", &gravity, 0.0, 30.0, "%.2f", false))
      bk_physics_set_gravity(physics, bk_v3(0, -gravity, 0));
    ui_slider_double("time scale", &g->time_scale, 0.05, 2.0, "%.2f", true);
    ui_checkbox("paused (P)", &g->paused);
    ui_same_line();
    if (ui_button("step (N)")) g->step_once = true;
  }
  // Open from the start when the game was started with a budget.
  if (ui_collapsing_header("Physics budget", g->options.physics_budget_ms > 0.0)) game_budget_section(g);
  if (ui_collapsing_header("Overlays", false)) {
    ui_checkbox("bonds by hit points (B)", &g->show_bonds);
    ui_checkbox("bonds by stress (V)", &g->show_stress);
    ui_tooltip("each intact bond coloured by its stress over its limit: green up to 1%, yellow at "
               "10%, red at the limit (it breaks); grey bonds are not solved (moving, or stress is off)");
    ui_checkbox("mesh-tree nodes per body (G)", &g->show_nodes);
    ui_checkbox("collider hulls (H)", &g->show_hulls);
    ui_checkbox("physics budget tiers (L)", &g->show_budget);
    ui_tooltip("blue: debris, yellow: simplified, purple: frozen, red: retired and fading");
  }
  if (ui_collapsing_header("Statistics", true)) stats_section(g);
  if (ui_collapsing_header("Benchmark", false)) {
    if (ui_button("run the runtime sweep on this scene")) start_sweep(g);
    ui_tooltip("16 to 512 fragments, one shot each, mesh tree against plain BCRB (as breakables bench)");
  }
  ui_end_window();
}

bool game_panel_busy(void) { return sweep_running(); }

void game_panel_shutdown(void) {
  if (sweep.running) {
    pthread_join(sweep.thread, NULL);
    sweep.running = false;
  }
  if (!job.running) return;
  pthread_join(job.thread, NULL);
  job.running = false;
  if (job.ok) loaded_scene_destroy(&job.result);
}
