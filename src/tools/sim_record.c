// sim --record and --replay. A recording holds the scene and every option
// that shapes its run (recording.h), each projectile as it was fired and
// each weight, and the state and world hash after every step; its replay
// applies them before the same steps and compares the hashes as it goes,
// so it names the first step that differs.
#include "sim_record.h"

#include <stdio.h>
#include <string.h>

#include "app.h"
#include "scene_replay.h"
#include "scenes.h"

const char* const sim_record_help =
    "  --record F.bkrec record the run: the scene and its options, every projectile as\n"
    "                   fired, the weight, and the state and world hash after every step\n"
    "  --record-no-hashes  no hashes in the recording (smaller; its replay checks none)\n"
    "  --replay F.bkrec run a recording again: its scene, options, steps, shots and weights\n"
    "                   (no other scene options may be given); each step's hashes compared\n"
    "                   with the recorded ones, exit 1 at the first that differs (with\n"
    "                   --json: replay_steps_checked)\n";

sim_record sim_record_default(void) { return (sim_record){.hashes = true}; }

int sim_record_parse(int argc, char** argv, int* i, sim_record* r) {
  const char* arg = argv[*i];
  if (strcmp(arg, "--record-no-hashes") == 0) {
    r->hashes = false;
    return 0;
  }
  static const char* const names[] = {"--record", "--replay"};
  const char* value = NULL;
  int which = take_option("sim", argc, argv, i, names, 2, &value);
  if (which < 0) return which == -1 ? 1 : 2;
  if (which == 0)
    r->record_path = value;
  else
    r->replay_path = value;
  return 0;
}

// The options a replay may take: what it reports and writes, not what it runs.
static int replay_option(const char* arg) {
  static const struct {
    const char* name;
    int values;
  } allowed[] = {{"--replay", 1},     {"--json", 0},        {"--hash-every", 1},
                 {"--export-obj", 1}, {"--export-gltf", 1}, {"--max-memory", 1}};
  for (size_t k = 0; k < sizeof allowed / sizeof *allowed; ++k)
    if (strcmp(arg, allowed[k].name) == 0) return allowed[k].values;
  return -1;
}

int sim_record_setup(sim_record* r, int argc, char** argv, scene_args* args, uint64_t* steps,
                     uint64_t* shots) {
  bk_error err = {0};
  if (r->record_path) { // its file is checked with the others (cmd_sim)
    if (r->replay_path) {
      fprintf(stderr, "breakables sim: --record and --replay cannot be used together\n");
      return 2;
    }
    // A run that starts from a saved state, or follows a server, is not made of its own events.
    for (int i = 1; i < argc; ++i)
      if (strcmp(argv[i], "--load-state") == 0 || strcmp(argv[i], "--watch") == 0) {
        fprintf(stderr, "breakables sim: --record and %s cannot be used together\n", argv[i]);
        return 2;
      }
  }
  if (!r->replay_path) return 0;
  for (int i = 1; i < argc; ++i) {
    int values = replay_option(argv[i]);
    if (values < 0) {
      fprintf(stderr,
              "breakables sim: --replay runs the recording's scene, options, steps and shots: '%s' cannot be "
              "given with it\n",
              argv[i]);
      return 2;
    }
    i += values;
  }
  if (!recording_read(r->replay_path, &r->rec, &err)) {
    fprintf(stderr, "breakables sim: %s\n", err.message);
    return 1;
  }
  for (uint32_t k = 1; k < r->rec.event_count; ++k)
    if (r->rec.events[k].kind == RECORDING_SCENE) {
      fprintf(stderr, "breakables sim: %s: the scene changes at step %llu (only play replays that)\n",
              r->replay_path, (unsigned long long)r->rec.events[k].step);
      sim_record_free(r);
      return 1;
    }
  const recording_scene* scene = &r->rec.scenes[r->rec.events[0].scene];
  uint32_t index = replay_scene_index(scene, &err);
  if (index == UINT32_MAX) {
    fprintf(stderr, "breakables sim: %s: %s\n", r->replay_path, err.message);
    sim_record_free(r);
    return 1;
  }
  args->scene_name = scene_at(index)->name;
  args->scene_given = !scene->mesh[0];
  args->mesh = scene->mesh[0] ? scene->mesh : NULL;
  args->material = scene->material[0] ? scene->material : NULL;
  args->volley = 0;
  args->options = recording_scene_options(scene);
  args->drop = default_drop();
  *steps = r->rec.steps;
  *shots = 0;
  r->next = 1; // the scene: loaded from the arguments above
  return 0;
}

void sim_record_start(sim_record* r, loaded_scene* s, const char* mesh, const scene_options* options) {
  if (!r->record_path) return;
  snprintf(r->rec.program, sizeof r->rec.program, "breakables sim");
  recording_scene scene = replay_scene_of(s->scene, mesh, options);
  recording_add_scene(&r->rec, 0, &scene);
  bk_vec3 focus = {0.0, 0.0, 0.0};
  if (bk_world_focus(s->world, &focus)) {
    recording_event e = {.step = 0, .kind = RECORDING_FOCUS, .focus = focus};
    recording_add(&r->rec, &e);
  }
}

uint32_t sim_record_fire(sim_record* r, loaded_scene* s, uint64_t step, uint32_t shot, double speed) {
  uint32_t copies = s->copies ? s->copies : 1;
  for (uint32_t c = 0; c < copies; ++c) {
    bk_projectile_def p = scene_shot(s->scene, shot, speed);
    p.position.x += copy_offset(c, copies, s->copy_spacing);
    bk_world_fire(s->world, &p, NULL);
    if (r->record_path) {
      recording_event e = {.step = step, .kind = RECORDING_FIRE, .fire = p};
      recording_add(&r->rec, &e);
    }
  }
  return copies;
}

void sim_record_weight(sim_record* r, uint64_t step, bk_vec3 surface, double kg, double radius) {
  if (!r->record_path) return;
  recording_event e = {.step = step, .kind = RECORDING_WEIGHT};
  e.weight.surface = surface, e.weight.kg = kg, e.weight.radius = radius;
  recording_add(&r->rec, &e);
}

uint32_t sim_record_step(sim_record* r, loaded_scene* s, uint64_t step) {
  uint32_t fired = 0;
  while (r->replay_path && r->next < r->rec.event_count && r->rec.events[r->next].step == step) {
    bool applied = false;
    bk_error err = {0};
    fired += replay_apply(s, &r->rec.events[r->next++], &applied, &err);
    if (!applied && !r->failed) {
      fprintf(stderr, "breakables sim: replay: step %llu: %s\n", (unsigned long long)step, err.message);
      r->failed = true;
    }
  }
  return fired;
}

void sim_record_after(sim_record* r, loaded_scene* s, uint64_t step) {
  if (!(r->record_path && r->hashes) && !(r->replay_path && r->rec.has_hashes)) return;
  uint64_t state = 0, world = 0;
  replay_hashes(s, &state, &world);
  if (r->record_path) {
    recording_add_hashes(&r->rec, step, state, world);
    return;
  }
  r->checked++;
  if (!r->diverged && !replay_check(&r->rec, step, state, world, "sim")) r->diverged = true;
}

bool sim_record_finish(sim_record* r, uint64_t steps) {
  bool ok = !r->diverged && !r->failed;
  if (r->record_path) {
    bk_error err = {0};
    r->rec.steps = steps;
    if (!recording_write(&r->rec, r->record_path, &err)) {
      fprintf(stderr, "breakables sim: %s\n", err.message);
      ok = false;
    }
  }
  sim_record_free(r);
  return ok;
}

void sim_record_json(const sim_record* r, FILE* out) {
  if (r->replay_path) fprintf(out, "\"replay_steps_checked\": %llu, ", (unsigned long long)r->checked);
}

void sim_record_free(sim_record* r) { recording_free(&r->rec); }
