// breakables sim: run a scene headless, fire projectiles, report.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "commands.h"
#include "fracture_patterns.h"
#include "scene_args.h"
#include "sim_measure.h"
#include "sim_record.h"
#include "sim_state.h"
#include "sim_stream.h"

static const char* const sim_usage =
    "usage: breakables sim [--scene NAME | --mesh PATH] [--material NAME] [--pattern NAME] [--pieces N]\n"
    "                      [--scale S] [--units mm|cm|m|in]\n"
    "                      [--seed S] [--shots K] [--steps F] [--volley V]\n"
    "                      [--speed M/S] [--frailty X] [--density X] [--discrete|--accumulate] [--naive]\n"
    "                      [--no-stress] [--stress-scale X] [--drop KG] [--drop-radius M] [--drop-at STEP]\n"
    "                      [--budget-ms X] [--budget-fidelity S] [--budget-fidelity-factor F]\n"
    "                      [--copies N] [--max-memory MIB] [--refine] [--refine-pieces N]\n"
    "                      [--record F.bkrec [--record-no-hashes] | --replay F.bkrec]\n"
    "                      [--save-state F.bkstate [--at STEP]] [--load-state F.bkstate]\n"
    "                      [--serve ADDR:PORT [--watchers N] [--realtime] [--send-every K]\n"
    "                      | --watch ADDR:PORT] [--stream-wait MS]\n"
    "                      [--export-obj FILE.obj] [--export-gltf FILE.glb|FILE.gltf] [--hash-every N] "
    "[--json]\n"
    "\n"
    "Runs a scene headless at a fixed 60 Hz: builds (or loads from the cache) the\n"
    "scene's mesh tree, fires K projectiles at the object at regular intervals\n"
    "during F steps, and reports what broke and what it cost.\n"
    "\n"
    "options:\n";

// The options only sim takes (scene_args_help prints the shared ones first).
static const char* const sim_options =
    "  --shots K        projectiles to fire, 0..1000 (default: 3, or 0 with --drop)\n"
    "  --steps F        60 Hz steps to run, 1..1000000 (default: 300)\n"
    "  --speed M/S      projectile speed, 0.1..2000 (default: the scene's)\n"
    "  --frailty X      damage multiplier, 1e-6..1e6 (default: the material's)\n"
    "  --density X      kg/m^3, 1..1e5 (default: the material's)\n"
    "  --discrete       a bond breaks only if one hit exceeds its hit points\n"
    "  --accumulate     bonds lose hit points over hits (default: the material's choice)\n"
    "  --naive          plain BCRB: one collider per fragment, for comparison\n"
    "  --budget-fidelity S  for S seconds after it comes loose, 0..60 (default 1), a piece\n"
    "                   keeps what the player sees of it: no contacts dropped while it lies\n"
    "                   on others, its own shape, never retired; 0 makes every piece fair\n"
    "                   game at once (faster, but piles fall through themselves)\n"
    "  --budget-fidelity-factor F  while new pieces keep that, a step may cost up to F\n"
    "                   times the budget, 0 or 1..1000 (default 2); past it the least\n"
    "                   important of them give it up; 0 keeps it whatever it costs\n"
    "  --copies N       N copies of the scene side by side along x, 1..64 (default 1), a gap\n"
    "                   between them; each shot hits every copy in the same step\n"
    "  --export-obj FILE.obj  write the first object's mesh tree as it stands at the end of\n"
    "                   the run (refined where it was hit, with --refine): its fragments as OBJ,\n"
    "                   one 'o fragment_<i>' each, in the object's own frame (as fracture\n"
    "                   --export-obj writes them)\n"
    "  --export-gltf FILE.glb|FILE.gltf  the same tree as glTF 2.0, as fracture --export-gltf\n"
    "                   writes it (the fragments, their hierarchy and the exact tree); it\n"
    "                   loads back, in sim --mesh too\n"
    "  --json           print one JSON object: scene, pieces, bodies_initial, bodies_final,\n"
    "                   break_events, bonds_broken, colliders_initial, colliders_final,\n"
    "                   colliders_naive_final, step_ms_median, step_ms_max, break_ms_median,\n"
    "                   break_ms_max, step_ms_last_second, awake_final, pairs_final,\n"
    "                   manifolds_final, mass_rel_error, nan, fragments_free, from_cache,\n"
    "                   stress_bonds_broken (bonds the load they carried broke),\n"
    "                   fragments_fallen (fragments whose centroid ends more than 0.5 m\n"
    "                   below where it started), stress_ms_median and stress_ms_max (over\n"
    "                   the steps the stress solve worked), pattern (the objects' pattern,\n"
    "                   or \"mixed\"), patterns (one per object), drop_kg (0: no weight) and\n"
    "                   drop_point (where the weight was set down, or null); step_ms_p95,\n"
    "                   physics_ms_median, physics_ms_p95, physics_ms_max; budget_ms and\n"
    "                   budget_fidelity_s, budget_fidelity_factor (the options), the budget's tiers now\n"
    "                   (budget_debris, budget_simplified, budget_frozen)\n"
    "                   and since the start (budget_retired, budget_demotions,\n"
    "                   budget_restorations), mass_retired (kg; mass_rel_error counts it as\n"
    "                   kept); copies; and what the player sees of the debris (every dynamic\n"
    "                   piece still simulated), averaged over the first second after each\n"
    "                   shot: debris_mass_1s (kg), debris_momentum_1s (the sum of |m v| over\n"
    "                   the pieces: how much moves) and debris_net_momentum_1s (|sum of m v|),\n"
    "                   and the same of the pieces within budget_fidelity_radius (8 m) of\n"
    "                   the scene's eye that look large enough from it to see\n"
    "                   (budget_visible_angle, 0.006 rad: about four pixels)\n"
    "                   (debris_near_mass_1s, debris_near_momentum_1s,\n"
    "                   debris_near_net_momentum_1s), to compare a run with a budget against\n"
    "                   one without; break handling plus body creation (damage from\n"
    "                   contacts, splits, the bodies they remove and make: CPU time of the\n"
    "                   thread, not the stress solve) over the steps that had any (bonds\n"
    "                   broke, a body split, or hits or splits waited for the world's budgets):\n"
    "                   break_ms_median (= break_ms_p50), break_ms_p99, break_ms_max;\n"
    "                   break_wait_steps_max (the most steps a shot's last piece waited\n"
    "                   for its body: from the step it was hit until no hit or split waits);\n"
    "                   settled_physics_ms (the physics engine's CPU time per step, mean\n"
    "                   over the last 60 steps, when the debris has come to rest);\n"
    "                   refined_leaves (fragments refined over the run, 0 without --refine),\n"
    "                   leaves_final (the fragments of every object's tree at the end: the\n"
    "                   pieces plus what refinement added), refine_ms_p99 and refine_ms_max\n"
    "                   (each step's refinement, CPU time of the thread: starting and landing\n"
    "                   the pieces; the fracture, the bond division and the pieces' hulls run\n"
    "                   on a worker), state_hash and world_hash (bk_runtime_state_hash and\n"
    "                   bk_world_state_hash at the end, 16 hex digits)\n"
    "  --hash-every N   print 'step S state_hash H world_hash W' every N steps, 1..1000000\n"
    "                   (on stderr with --json)\n"
    "  -h, --help       show this help\n"
    "\n"
    "Mesh trees are cached in $BREAKABLES_CACHE_DIR (else $XDG_CACHE_HOME/breakables,\n"
    "else ~/.cache/breakables).\n";

int cmd_sim(int argc, char** argv) {
  uint64_t shots = 3, steps = 300, hash_every = 0;
  double speed = 0.0;
  bool json = false, shots_given = false;
  const char* obj_path = NULL;
  const char* gltf_path = NULL;
  scene_args args = default_scene_args("wall");
  sim_record record = sim_record_default();
  sim_stream stream = default_sim_stream();
  sim_state state = sim_state_default();
  for (int i = 1; i < argc; ++i) {
    const char* arg = argv[i];
    int streamed = sim_stream_parse(argc, argv, &i, &stream);
    if (streamed != 1) {
      if (streamed == 2) return 2;
      continue;
    }
    int saved = sim_state_parse(argc, argv, &i, &state);
    if (saved != 1) {
      if (saved == 2) return 2;
      continue;
    }
    int recorded = sim_record_parse(argc, argv, &i, &record);
    if (recorded != 1) {
      if (recorded == 2) return 2;
      continue;
    }
    int shared = scene_args_parse("sim", argc, argv, &i, &args);
    if (shared == 0) continue;
    if (shared == 2) return 2;
    bool flag = true;
    uint64_t number = 0;
    if (strcmp(arg, "-h") == 0 || strcmp(arg, "--help") == 0) {
      fputs(sim_usage, stdout);
      scene_args_help("sim", 19, 88, stdout);
      fputs(sim_record_help, stdout);
      fputs(sim_state_help, stdout);
      sim_stream_help(stdout);
      fputs(sim_options, stdout);
      return 0;
    } else if (strcmp(arg, "--json") == 0) {
      json = true;
    } else if (strcmp(arg, "--naive") == 0) {
      args.options.naive = true;
    } else if (strcmp(arg, "--discrete") == 0) {
      args.options.accumulate = 0;
    } else if (strcmp(arg, "--accumulate") == 0) {
      args.options.accumulate = 1;
    } else {
      flag = false;
    }
    if (flag) continue;
    static const char* const names[] = {"--shots",       "--frailty",         "--density",
                                        "--steps",       "--speed",           "--budget-fidelity-factor",
                                        "--copies",      "--budget-fidelity", "--export-obj",
                                        "--export-gltf", "--hash-every"};
    const char* value = NULL;
    int which = take_option("sim", argc, argv, &i, names, (int)(sizeof names / sizeof *names), &value);
    if (which == -2) return 2;
    if (which == -1) {
      fprintf(stderr, "breakables sim: unknown option '%s' (see 'breakables sim --help')\n", arg);
      return 2;
    }
    scene_options* o = &args.options;
    if (strcmp(arg, "--hash-every") == 0) {
      if (!option_u64("sim", arg, value, 1, 1000000, &hash_every)) return 2;
    } else if (strcmp(arg, "--export-obj") == 0) {
      obj_path = value;
    } else if (strcmp(arg, "--export-gltf") == 0) {
      gltf_path = value;
    } else if (strcmp(arg, "--shots") == 0) {
      if (!option_u64("sim", arg, value, 0, 1000, &shots)) return 2;
      shots_given = true;
    } else if (strcmp(arg, "--steps") == 0) {
      // A million steps is 4.6 simulated hours, two timings of 8 bytes each.
      if (!option_u64("sim", arg, value, 0, 1000000, &steps)) return 2; // 0: only with --load-state
    } else if (strcmp(arg, "--speed") == 0) {
      // From a lob to twice a rifle bullet; continuous collision detection
      // keeps even the fastest from passing through a thin wall.
      if (!option_double("sim", arg, value, 0.1, 2000.0, &speed)) return 2;
    } else if (strcmp(arg, "--budget-fidelity-factor") == 0) {
      if (!option_double("sim", arg, value, 0.0, BK_BUDGET_FIDELITY_FACTOR_MAX, &o->budget_fidelity_factor))
        return 2;
      if (o->budget_fidelity_factor > 0.0 && o->budget_fidelity_factor < 1.0) {
        fprintf(stderr, "breakables sim: %s '%s' is out of range (0, or 1..%g)\n", arg, value,
                BK_BUDGET_FIDELITY_FACTOR_MAX);
        return 2;
      }
    } else if (strcmp(arg, "--budget-fidelity") == 0) {
      if (!option_double("sim", arg, value, 0.0, BK_BUDGET_FIDELITY_MAX, &o->budget_fidelity_time)) return 2;
    } else if (strcmp(arg, "--copies") == 0) {
      if (!option_u64("sim", arg, value, 1, BK_COPIES_MAX, &number)) return 2;
      o->copies = (uint32_t)number;
    } else if (strcmp(arg, "--frailty") == 0) {
      // Materials use 0.5..8. At 1e-6 no shot breaks a bond and at 1e6 every
      // bond breaks at the first touch: beyond these nothing changes.
      if (!option_double("sim", arg, value, 1e-6, 1e6, &o->frailty)) return 2;
    } else if (strcmp(arg, "--density") == 0) {
      // Aerogel to four times osmium covers any real solid. Far outside it,
      // Bullet's float masses stop meaning anything: 1e-300 rounds to a mass
      // of 0, which Bullet treats as static.
      if (!option_double("sim", arg, value, 1.0, 1e5, &o->density)) return 2;
    }
  }
  // A replay takes the scene, its options and the steps from its file.
  int setup = sim_record_setup(&record, argc, argv, &args, &steps, &shots);
  if (setup) return setup;
  int state_code = sim_state_check(&state, steps);
  if (state_code) return state_code;
  if (state.load_path && !shots_given) shots = 0; // the state has its shots
  const char* scene_name = args.scene_name;
  const char* mesh = args.mesh;
  const char* material = args.material;
  bool scene_given = args.scene_given;
  uint64_t volley = args.volley;
  scene_options options = args.options;
  app_drop drop = args.drop;
  if (!check_drop("sim", &drop, steps, "--steps")) return 2;
  // A weight is the load under test: shots on top of it would break the
  // structure themselves and hide what the weight alone does.
  if (drop.kg > 0.0 && !shots_given) shots = 0;
  bk_error err = {0};
  uint32_t scene_index = scene_resolve(scene_name, scene_given, mesh, material, &err);
  if (scene_index == UINT32_MAX) {
    fprintf(stderr, "breakables sim: %s\n", err.message);
    return 2;
  }
  const app_scene* scene = scene_at(scene_index);
  options.material = material;
  // The files to write, checked before the run, as fracture checks its own:
  // names the writers take, places to write them, and no file lost (the
  // model read, or the other export).
  const app_file inputs[] = {{"--mesh", mesh, NULL, false},
                             {"--replay", record.replay_path, NULL, false},
                             {"--load-state", state.load_path, NULL, false}};
  const app_file outputs[] = {{"--record", record.record_path, ".bkrec", false},
                              {"--export-obj", obj_path, ".obj", true},
                              {"--export-gltf", gltf_path, ".glb .gltf", true},
                              {"--save-state", state.save_path, ".bkstate", false}};
  if (!app_check_files(inputs, 3, outputs, 4, &err)) {
    sim_record_free(&record);
    fprintf(stderr, "breakables sim: %s\n", err.message);
    return 1;
  }

  loaded_scene loaded = {0};
  if (!loaded_scene_create(scene, &options, &loaded, &err)) {
    // A user's model: what failed to read or load it names its file already
    // (once is enough); a built-in scene's name says which scene failed.
    if (scene->fit_to_mesh && strstr(err.message, scene->objects[0].mesh))
      fprintf(stderr, "breakables sim: %s\n", err.message);
    else
      fprintf(stderr, "breakables sim: %s: %s\n", scene->name, err.message);
    sim_record_free(&record);
    return 1;
  }
  // The budget keeps what is near the eye fully simulated (with copies,
  // the one in the middle, or the two either side of it).
  bk_world_set_focus(loaded.world, loaded.scene->eye);
  if (!sim_state_load(&state, loaded.world) || !sim_state_after(&state, loaded.world, 0)) {
    loaded_scene_destroy(&loaded), sim_record_free(&record);
    return 1;
  }
  sim_record_start(&record, &loaded, mesh, &options);
  // A watcher follows the server's run instead of making its own.
  if (stream.watch) {
    int code = sim_watch_run(&stream, &loaded, json);
    loaded_scene_destroy(&loaded), sim_record_free(&record);
    return code;
  }
  if (stream.serve && !sim_serve_start(&stream, &loaded)) {
    loaded_scene_destroy(&loaded), sim_record_free(&record);
    return 1;
  }
  bk_world_stats initial = bk_world_get_stats(loaded.world);
  double* rest_heights = sim_heights_of(&loaded);
  double* step_ms = bk_alloc(sizeof(double) * steps);
  double* physics_ms = bk_alloc(sizeof(double) * steps);
  app_fidelity fidelity = {0};
  double* break_ms = bk_alloc(sizeof(double) * steps);
  double* stress_ms = bk_alloc(sizeof(double) * steps);
  double* refine_ms = bk_alloc(sizeof(double) * steps);
  bk_quat* rotations = sim_start_rotations(&loaded);
  uint32_t break_steps = 0, stress_steps = 0, fired = 0;
  // Clusters waiting for the split budget: since which step, and the
  // longest wait of a shot's last piece for its body.
  uint64_t waiting_since = 0, wait_max = 0;
  bool waiting = false;
  // The last second's physics, when what the shots broke has come to rest.
  uint32_t settled_from = steps < 60 ? 0u : (uint32_t)steps - 60u;
  double settled_sum = 0.0;
  bk_vec3 drop_point = {0.0, 0.0, 0.0};
  bool drop_set = false;
  for (uint64_t step = 0; step < steps; ++step) {
    if (drop.kg > 0.0 && step == drop.at) {
      bk_error drop_err = {0};
      if (!scene_drop_point(&loaded, &drop_point) ||
          !app_drop_weight(loaded.world, drop_point, drop.kg, drop.radius, &drop_err)) {
        fprintf(stderr, "breakables sim: --drop: %s\n",
                drop_err.message[0] ? drop_err.message
                                    : "no surface of the first object to set the weight on");
        free(step_ms), free(physics_ms), free(break_ms), free(stress_ms), free(rest_heights);
        bk_free(refine_ms), bk_free(rotations);
        loaded_scene_destroy(&loaded), sim_record_free(&record);
        return 1;
      }
      drop_set = true;
      sim_record_weight(&record, step, drop_point, drop.kg, drop.radius);
    }
    // Shots at regular intervals, leaving time after the last one.
    uint64_t span = volley && volley < steps ? volley : steps;
    uint32_t hits = 0;
    while (fired < shots && step >= (fired + 1) * span / (shots + 1))
      hits += sim_record_fire(&record, &loaded, step, fired++, speed); // at every copy, recorded
    // A replay's shots and weights.
    uint32_t replayed = sim_record_step(&record, &loaded, step);
    hits += replayed, fired += replayed / (loaded.copies ? loaded.copies : 1);
    bk_world_stats before = bk_world_get_stats(loaded.world);
    bk_world_step(loaded.world);
    sim_state_after(&state, loaded.world, step + 1);
    fidelity_step(&fidelity, loaded.world, step, hits);
    sim_record_after(&record, &loaded, step);
    if (stream.serve) sim_serve_step(&stream, &loaded, step + 1, step + 1 == steps);
    bk_world_stats now = bk_world_get_stats(loaded.world);
    step_ms[step] = now.step_ms;
    physics_ms[step] = now.physics_ms;
    refine_ms[step] = now.refine_ms;
    // Steps with break work: bonds broke, a body split, or splits waited.
    if (break_step(&before, &now)) break_ms[break_steps++] = now.fracture_ms;
    bool pending = now.pending_splits > 0 || now.pending_hits > 0;
    if (pending && !waiting) waiting = true, waiting_since = step;
    if (waiting && (!pending || step + 1 == steps)) {
      // The run may end first: then the wait so far.
      wait_max = step - waiting_since > wait_max ? step - waiting_since : wait_max;
      waiting = pending;
    }
    if (step >= settled_from) settled_sum += now.physics_cpu_ms;
    if (now.stress_iterations) stress_ms[stress_steps++] = now.stress_ms;
    // The state every N steps: stderr with --json, whose stdout is one object.
    if (hash_every && (step + 1) % hash_every == 0)
      fprintf(json ? stderr : stdout, "step %llu state_hash %016llx world_hash %016llx\n",
              (unsigned long long)(step + 1),
              (unsigned long long)bk_runtime_state_hash(bk_world_runtime(loaded.world)),
              (unsigned long long)bk_world_state_hash(loaded.world));
  }
  uint64_t state_hash = bk_runtime_state_hash(bk_world_runtime(loaded.world));
  uint64_t world_hash = bk_world_state_hash(loaded.world);
  if (stream.serve) sim_serve_finish(&stream, steps, state_hash, world_hash);
  bk_world_stats final = bk_world_get_stats(loaded.world);
  // Walks every manifold: read once here, not in the per-step world stats.
  bk_physics_stats physics = bk_physics_get_stats(bk_world_physics(loaded.world));
  // What the budget retired has left the world, not the simulation's books.
  double mass_error = fabs(final.total_mass + final.retired_mass - initial.total_mass) / initial.total_mass;
  double step_max = app_maximum(step_ms, (uint32_t)steps), break_max = app_maximum(break_ms, break_steps);
  double physics_max = app_maximum(physics_ms, (uint32_t)steps);
  double physics_median = app_median(physics_ms, (uint32_t)steps);
  double physics_p95 = app_percentile(physics_ms, (uint32_t)steps, 95.0);
  debris_sample debris = fidelity_mean(&fidelity);
  debris_sample near = fidelity_near_mean(&fidelity);
  // The last second alone: the steady cost of what the shots left behind.
  uint32_t tail = steps < 60 ? (uint32_t)steps : 60;
  double last_median = app_median(step_ms + (steps - tail), tail);
  double step_median = app_median(step_ms, (uint32_t)steps), break_median = app_median(break_ms, break_steps);
  double break_p99 = app_percentile(break_ms, break_steps, 99.0);
  double settled_ms = settled_sum / (double)(steps - settled_from);
  double step_p95 = app_percentile(step_ms, (uint32_t)steps, 95.0);
  uint32_t pieces = sim_fragments_of(&loaded) * loaded.copies;
  uint32_t fallen = sim_fragments_fallen(&loaded, rest_heights, rotations);
  uint32_t leaves_final = sim_leaves_now(&loaded);
  double refine_p99 = app_percentile(refine_ms, (uint32_t)steps, 99.0);
  double refine_max = app_maximum(refine_ms, (uint32_t)steps);
  bool exported = (!obj_path && !gltf_path) || sim_export_first_tree(&loaded, obj_path, gltf_path);
  double stress_median = app_median(stress_ms, stress_steps),
         stress_max = app_maximum(stress_ms, stress_steps);
  if (json) {
    // Every number through BK_APP_JSON_NUMBER: a non-finite one is null, never inf or nan.
    fputs("{\"scene\": ", stdout);
    app_json_string(stdout, scene->name);
    printf(", \"pieces\": %u, \"shots\": %u, \"steps\": %llu, \"bodies_initial\": %u, "
           "\"bodies_final\": %u, \"break_events\": %u, \"bonds_broken\": %u, \"colliders_initial\": %u, "
           "\"colliders_final\": %u, \"colliders_naive_final\": %u, \"fragments_free\": %u, "
           "\"step_ms_median\": %s, \"step_ms_max\": %s, \"break_ms_median\": %s, \"break_ms_max\": %s, "
           "\"step_ms_last_second\": %s, \"awake_final\": %u, \"pairs_final\": %u, \"manifolds_final\": %u, "
           "\"mass_rel_error\": %s, \"nan\": %s, \"from_cache\": %s, \"stress_bonds_broken\": %u, "
           "\"fragments_fallen\": %u, \"stress_ms_median\": %s, \"stress_ms_max\": %s, ",
           pieces, fired, (unsigned long long)steps, initial.bodies, final.bodies, final.break_events,
           final.bonds_broken, initial.colliders, final.colliders, final.colliders_naive,
           final.fragments_free, BK_APP_JSON_NUMBER("%.4f", step_median),
           BK_APP_JSON_NUMBER("%.4f", step_max), BK_APP_JSON_NUMBER("%.4f", break_median),
           BK_APP_JSON_NUMBER("%.4f", break_max), BK_APP_JSON_NUMBER("%.4f", last_median),
           physics.awake_bodies, physics.pairs, physics.manifolds, BK_APP_JSON_NUMBER("%.3e", mass_error),
           final.nan ? "true" : "false", loaded.from_cache ? "true" : "false", final.stress_bonds_broken,
           fallen, BK_APP_JSON_NUMBER("%.4f", stress_median), BK_APP_JSON_NUMBER("%.4f", stress_max));
    sim_print_patterns(&loaded, true);
    printf(", \"drop_kg\": %s, \"drop_point\": ", BK_APP_JSON_NUMBER("%g", drop_set ? drop.kg : 0.0));
    if (drop_set)
      printf("[%s, %s, %s], ", BK_APP_JSON_NUMBER("%.4f", drop_point.x),
             BK_APP_JSON_NUMBER("%.4f", drop_point.y), BK_APP_JSON_NUMBER("%.4f", drop_point.z));
    else
      printf("null, ");
    printf("\"copies\": %u, \"step_ms_p95\": %s, \"physics_ms_median\": %s, \"physics_ms_p95\": %s, "
           "\"physics_ms_max\": %s, \"budget_ms\": %s, \"budget_fidelity_s\": %s, "
           "\"budget_fidelity_factor\": %s, \"budget_debris\": %u, "
           "\"budget_simplified\": %u, "
           "\"budget_frozen\": %u, \"budget_retired\": %u, \"budget_demotions\": %u, "
           "\"budget_restorations\": %u, \"mass_retired\": %s, \"debris_mass_1s\": %s, "
           "\"debris_momentum_1s\": %s, \"debris_net_momentum_1s\": %s, \"debris_near_mass_1s\": %s, "
           "\"debris_near_momentum_1s\": %s, \"debris_near_net_momentum_1s\": %s, ",
           loaded.copies, BK_APP_JSON_NUMBER("%.4f", step_p95), BK_APP_JSON_NUMBER("%.4f", physics_median),
           BK_APP_JSON_NUMBER("%.4f", physics_p95), BK_APP_JSON_NUMBER("%.4f", physics_max),
           BK_APP_JSON_NUMBER("%g", options.physics_budget_ms),
           BK_APP_JSON_NUMBER("%g", options.budget_fidelity_time),
           BK_APP_JSON_NUMBER("%g", options.budget_fidelity_factor), final.budget_debris,
           final.budget_simplified, final.budget_frozen, final.budget_retired, final.budget_demotions,
           final.budget_restorations, BK_APP_JSON_NUMBER("%.6g", final.retired_mass),
           BK_APP_JSON_NUMBER("%.6g", debris.mass), BK_APP_JSON_NUMBER("%.6g", debris.momentum),
           BK_APP_JSON_NUMBER("%.6g", debris.net_momentum), BK_APP_JSON_NUMBER("%.6g", near.mass),
           BK_APP_JSON_NUMBER("%.6g", near.momentum), BK_APP_JSON_NUMBER("%.6g", near.net_momentum));
    sim_record_json(&record, stdout);
    sim_state_json(&state, stdout);
    if (stream.serve) sim_serve_json(&stream, stdout, final.bonds_broken, steps);
    printf("\"break_ms_p50\": %s, \"break_ms_p99\": %s, \"break_wait_steps_max\": %llu, "
           "\"settled_physics_ms\": %s, \"refined_leaves\": %u, \"leaves_final\": %u, "
           "\"refine_ms_p99\": %s, \"refine_ms_max\": %s, \"state_hash\": \"%016llx\", \"world_hash\": "
           "\"%016llx\"}\n",
           BK_APP_JSON_NUMBER("%.4f", break_median), BK_APP_JSON_NUMBER("%.4f", break_p99),
           (unsigned long long)wait_max, BK_APP_JSON_NUMBER("%.4f", settled_ms), final.refined_leaves,
           leaves_final, BK_APP_JSON_NUMBER("%.4f", refine_p99), BK_APP_JSON_NUMBER("%.4f", refine_max),
           (unsigned long long)state_hash, (unsigned long long)world_hash);
  } else {
    if (loaded.copies > 1) printf("%u copies %.3g m apart, ", loaded.copies, loaded.copy_spacing);
    printf("%s: %u fragments, %u shots over %llu steps (%.1f s)\n", scene->name, pieces, fired,
           (unsigned long long)steps, (double)steps / 60.0);
    printf("  bodies %u -> %u (%u splits, %u bonds broken, %u fragments free)\n", initial.bodies,
           final.bodies, final.break_events, final.bonds_broken, final.fragments_free);
    printf("  colliders %u -> %u (plain BCRB would use %u)\n", initial.colliders, final.colliders,
           final.colliders_naive);
    printf(
        "  step ms median %.3f max %.3f; break handling ms median %.3f p99 %.3f max %.3f (CPU), last piece "
        "waited %llu steps\n",
        step_median, step_max, break_median, break_p99, break_max, (unsigned long long)wait_max);
    printf("  last second: step ms median %.3f, %u bodies awake, %u pairs, %u manifolds, %u contact points\n",
           last_median, physics.awake_bodies, physics.pairs, physics.manifolds, physics.contact_points);
    printf("  stress: %u bonds broken, %u fragments fell; ms median %.3f max %.3f over %u steps\n",
           final.stress_bonds_broken, fallen, stress_median, stress_max, stress_steps);
    if (drop_set)
      printf("  weight: %g kg (radius %g m) set on (%.2f, %.2f, %.2f) at step %llu\n", drop.kg, drop.radius,
             drop_point.x, drop_point.y, drop_point.z, (unsigned long long)drop.at);
    printf("  physics ms median %.3f p95 %.3f max %.3f; step ms p95 %.3f\n", physics_median, physics_p95,
           physics_max, step_p95);
    if (options.physics_budget_ms > 0.0)
      printf("  budget %g ms: now %u debris, %u simplified, %u frozen; %u retired (%.3g kg), %u demotions, "
             "%u restorations\n",
             options.physics_budget_ms, final.budget_debris, final.budget_simplified, final.budget_frozen,
             final.budget_retired, final.retired_mass, final.budget_demotions, final.budget_restorations);
    if (fidelity.weight > 0.0)
      printf("  debris over the first second after each shot: %.4g kg, momentum %.4g kg m/s (net %.4g)\n",
             debris.mass, debris.momentum, debris.net_momentum);
    if (options.refine)
      printf("  refined %u fragments: %u -> %u; refinement ms p99 %.3f max %.3f (CPU)\n",
             final.refined_leaves, pieces, leaves_final, refine_p99, refine_max);
    printf("  mass error %.2e%s\n", mass_error, final.nan ? ", NaN detected" : "");
    printf("  state hash %016llx, world hash %016llx\n", (unsigned long long)state_hash,
           (unsigned long long)world_hash);
    sim_print_patterns(&loaded, false);
    if (obj_path && exported) printf("  exported %s\n", obj_path);
    if (gltf_path && exported) printf("  exported %s\n", gltf_path);
  }
  free(step_ms);
  free(physics_ms);
  free(break_ms);
  free(stress_ms);
  free(rest_heights);
  bk_free(refine_ms);
  bk_free(rotations);
  bool recorded_ok = sim_record_finish(&record, steps);
  loaded_scene_destroy(&loaded);
  return final.nan || !exported || !recorded_ok || state.failed ? 1 : 0;
}
