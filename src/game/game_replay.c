// play's recordings: the same file and events as sim's (recording.h), with
// the game's own sources of change. Shots and weights are recorded as they
// are made; what the panel changes (materials, stress, the budget) and where
// the camera is (the physics budget's focus) are compared each frame with
// the last frame's and recorded when they differ; every scene load is a
// scene event with all its options. The step is the count of steps since the
// start: inputs reach the world between the worker's jobs, so an event
// applies before the step the next job runs first, and a replay cuts the
// jobs short so that each event lands before its own step.
#include "game_replay.h"

#include <stdio.h>
#include <string.h>

#include "app.h"
#include "scene_args.h"
#include "scene_replay.h"
#include "scenes.h"

const char* const game_replay_help =
    "  --record-input F.bkrec  record what changes the run (shots, weights, the panel's changes,\n"
    "                        scene switches and resets, the camera's place for the physics budget)\n"
    "                        by the physics step, with every step's hashes; prints the final\n"
    "                        state_hash and world_hash on exit\n"
    "  --replay F.bkrec      play a recording (play's or sim's) back at the same steps: its scenes,\n"
    "                        options and events; your shots, weights, panel and reloads are\n"
    "                        ignored (the camera still flies); each step's hashes compared, exit 1\n"
    "                        at the first that differs; ends with the recording; prints the final\n"
    "                        hashes on exit\n";

int game_replay_parse(int argc, char** argv, int* i, game_replay* r) {
  static const char* const names[] = {"--record-input", "--replay"};
  const char* value = NULL;
  int which = take_option("play", argc, argv, i, names, 2, &value);
  if (which < 0) return which == -1 ? 1 : 2;
  if (which == 0)
    r->record_path = value;
  else
    r->replay_path = value;
  return 0;
}

int game_replay_setup(game_replay* r, int argc, char** argv, const char* mesh, uint32_t* scene_index,
                      scene_options* options) {
  bk_error err = {0};
  if (r->record_path && r->replay_path) {
    fprintf(stderr, "breakables play: --record-input and --replay cannot be used together\n");
    return 2;
  }
  const app_file inputs[] = {{"--mesh", mesh, NULL, false}, {"--replay", r->replay_path, NULL, false}};
  const app_file outputs[] = {{"--record-input", r->record_path, ".bkrec", false}};
  if (!app_check_files(inputs, 2, outputs, 1, &err)) {
    fprintf(stderr, "breakables play: %s\n", err.message);
    return 1;
  }
  if (!r->replay_path) return 0;
  // What shapes the run comes from the recording alone.
  uint32_t count = 0;
  const scene_arg* table = scene_arg_table(&count);
  for (int i = 1; i < argc; ++i) {
    bool shaping = strcmp(argv[i], "--autofire") == 0 || strcmp(argv[i], "--benchmark") == 0;
    for (uint32_t k = 0; k < count && !shaping; ++k)
      shaping = strcmp(argv[i], table[k].name) == 0 && strcmp(argv[i], "--max-memory") != 0;
    if (shaping) {
      fprintf(stderr,
              "breakables play: --replay plays the recording's scenes, options and events: '%s' cannot be "
              "given with it\n",
              argv[i]);
      return 2;
    }
  }
  if (!recording_read(r->replay_path, &r->rec, &err)) {
    fprintf(stderr, "breakables play: %s\n", err.message);
    return 1;
  }
  const recording_scene* scene = &r->rec.scenes[r->rec.events[0].scene];
  *scene_index = replay_scene_index(scene, &err);
  if (*scene_index == UINT32_MAX) {
    fprintf(stderr, "breakables play: %s: %s\n", r->replay_path, err.message);
    recording_free(&r->rec);
    return 1;
  }
  *options = recording_scene_options(scene);
  r->next = 1; // the first scene: loaded by the game as it starts
  return 0;
}

bool game_replay_playing(const game_replay* r) { return r->replay_path != NULL; }

// What the world has now, as the next frame compares it.
static void keep_state(game_replay* r, bk_world* world) {
  r->focus_set = bk_world_focus(world, &r->focus);
  r->stress = bk_world_stress(world);
  r->budget_ms = bk_world_physics_budget(world);
  uint32_t count = bk_world_breakable_count(world);
  r->material_count = count < RECORDING_BREAKABLES_MAX ? count : RECORDING_BREAKABLES_MAX;
  for (uint32_t i = 0; i < r->material_count; ++i) {
    r->materials[i] = bk_world_material(world, bk_world_breakable_at(world, i));
    snprintf(r->names[i], sizeof r->names[i], "%s", r->materials[i].name ? r->materials[i].name : "");
    r->materials[i].name = r->names[i];
  }
}

void game_replay_loaded(game_replay* r, const loaded_scene* loaded, uint32_t index,
                        const scene_options* options) {
  if (r->record_path) {
    const app_scene* scene = scene_at(index);
    const char* mesh = scene->fit_to_mesh ? scene->objects[0].mesh : NULL;
    recording_scene s = replay_scene_of(scene, mesh, options);
    recording_add_scene(&r->rec, r->step, &s);
  }
  keep_state(r, loaded->world);
}

void game_replay_fired(game_replay* r, const bk_projectile_def* shot) {
  if (!r->record_path) return;
  recording_event e = {.step = r->step, .kind = RECORDING_FIRE, .fire = *shot};
  recording_add(&r->rec, &e);
}

void game_replay_weight(game_replay* r, bk_vec3 surface, double kg, double radius) {
  if (!r->record_path) return;
  recording_event e = {.step = r->step, .kind = RECORDING_WEIGHT};
  e.weight.surface = surface, e.weight.kg = kg, e.weight.radius = radius;
  recording_add(&r->rec, &e);
}

// Recording: what changed since the last frame.
static void record_changes(game_replay* r, bk_world* world) {
  uint64_t step = r->step;
  bk_vec3 focus = {0.0, 0.0, 0.0};
  if (bk_world_focus(world, &focus) &&
      (!r->focus_set || memcmp(&focus, &r->focus, sizeof focus) != 0)) { // bit for bit
    recording_event e = {.step = step, .kind = RECORDING_FOCUS, .focus = focus};
    recording_add(&r->rec, &e);
  }
  if (bk_world_stress(world) != r->stress) {
    recording_event e = {.step = step, .kind = RECORDING_STRESS, .stress = bk_world_stress(world)};
    recording_add(&r->rec, &e);
  }
  double budget = bk_world_physics_budget(world);
  if (memcmp(&budget, &r->budget_ms, sizeof budget) != 0) {
    recording_event e = {.step = step, .kind = RECORDING_BUDGET, .budget_ms = budget};
    recording_add(&r->rec, &e);
  }
  for (uint32_t i = 0; i < r->material_count; ++i) {
    bk_material now = bk_world_material(world, bk_world_breakable_at(world, i));
    recording_setter setter = RECORDING_SET_MATERIAL;
    if (replay_material_change(&r->materials[i], &now, &setter))
      recording_add_material(&r->rec, step, i, setter, &now);
  }
  keep_state(r, world);
}

// Replay: the events due before this step, then as many steps as reach the
// next. A scene event stops it: the game loads the scene and calls again.
static void apply_events(game_replay* r, loaded_scene* scene, game_replay_frame_io* io) {
  while (r->next < r->rec.event_count && r->rec.events[r->next].step == r->step && !r->failed) {
    const recording_event* e = &r->rec.events[r->next++];
    bk_error err = {0};
    if (e->kind == RECORDING_SCENE) {
      const recording_scene* s = &r->rec.scenes[e->scene];
      io->index = replay_scene_index(s, &err);
      io->options = recording_scene_options(s);
      io->load = io->index != UINT32_MAX;
      if (io->load) return;
    } else {
      bool applied = false;
      io->shots += replay_apply(scene, e, &applied, &err);
      io->weights += e->kind == RECORDING_WEIGHT && applied;
      if (applied) continue;
    }
    fprintf(stderr, "breakables play: replay: step %llu: %s\n", (unsigned long long)r->step, err.message);
    r->failed = true;
  }
  uint64_t until = r->next < r->rec.event_count ? r->rec.events[r->next].step : r->rec.steps;
  if (r->failed) until = r->step;
  if ((uint64_t)io->pending_steps > until - r->step) io->pending_steps = (int)(until - r->step);
  if (r->step + (uint64_t)io->pending_steps >= r->rec.steps || r->failed) io->ended = true;
}

void game_replay_frame(game_replay* r, loaded_scene* scene, bk_vec3 eye, game_replay_frame_io* io) {
  io->load = false;
  if (r->replay_path) {
    apply_events(r, scene, io);
    return;
  }
  bk_world_set_focus(scene->world, eye); // the physics budget spares what is near the camera
  if (r->record_path) record_changes(r, scene->world);
}

void game_replay_step(game_replay* r, loaded_scene* scene) {
  uint64_t step = r->step++;
  if (!r->record_path && !(r->replay_path && r->rec.has_hashes)) return;
  uint64_t state = 0, world = 0;
  replay_hashes(scene, &state, &world);
  if (r->record_path) {
    recording_add_hashes(&r->rec, step, state, world);
    return;
  }
  if (step >= r->rec.steps) return;
  r->checked++;
  // Printed at once, as sim does: the steps go on, and the first is the one to look at.
  if (!r->diverged && !replay_check(&r->rec, step, state, world, "play")) r->diverged = true;
}

bool game_replay_finish(game_replay* r, loaded_scene* scene) {
  bool ok = !r->diverged && !r->failed;
  if ((r->record_path || r->replay_path) && scene->world) {
    uint64_t state = 0, world = 0;
    replay_hashes(scene, &state, &world);
    printf("state_hash %016llx world_hash %016llx steps %llu%s\n", (unsigned long long)state,
           (unsigned long long)world, (unsigned long long)r->step, r->replay_path ? "" : " recorded");
  }
  if (r->replay_path && r->step < r->rec.steps && ok) // closed early: what was compared held
    fprintf(stderr, "breakables play: note: the replay stopped at step %llu of the recording's %llu\n",
            (unsigned long long)r->step, (unsigned long long)r->rec.steps);
  if (r->record_path) {
    bk_error err = {0};
    r->rec.steps = r->step;
    // What the last frame changed after the last step never came into play.
    while (r->rec.event_count > 1 && r->rec.events[r->rec.event_count - 1].step >= r->step)
      r->rec.event_count--;
    snprintf(r->rec.program, sizeof r->rec.program, "breakables play");
    if (r->step == 0) {
      fprintf(stderr, "breakables play: --record-input: no step was run, nothing to record\n");
      ok = false;
    } else if (!recording_write(&r->rec, r->record_path, &err)) {
      fprintf(stderr, "breakables play: %s\n", err.message);
      ok = false;
    }
  }
  recording_free(&r->rec);
  return ok;
}
