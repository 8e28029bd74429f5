// A recording's events applied to a loaded scene: the same world calls the
// recording run made, in the same order, before the same steps.
#include "scene_replay.h"

#include <stdio.h>
#include <string.h>

#include "app.h"
#include "scenes.h"

recording_scene replay_scene_of(const app_scene* scene, const char* mesh, const scene_options* options) {
  recording_scene s = {.options = *options};
  snprintf(s.name, sizeof s.name, "%s", scene->name);
  snprintf(s.mesh, sizeof s.mesh, "%s", mesh ? mesh : "");
  snprintf(s.material, sizeof s.material, "%s", options->material ? options->material : "");
  const char* units = NULL;
  app_model_units(&s.model_scale, &units);
  snprintf(s.units, sizeof s.units, "%s", units ? units : "");
  s.options.material = NULL, s.options.progress = NULL, s.options.progress_user = NULL;
  return s;
}

uint32_t replay_scene_index(const recording_scene* scene, bk_error* err) {
  // The units through their own parser, as the command line gave them.
  char scale[32] = "";
  snprintf(scale, sizeof scale, "%.17g", scene->model_scale);
  char* args[] = {"replay", "--scale", scale, "--units", (char*)scene->units};
  int at = 1;
  app_reset_model_units();
  if (parse_model_units_option("replay", 3, args, &at) != 0)
    return bk_error_set(err, "the recording's model scale %g is refused", scene->model_scale), UINT32_MAX;
  at = 3;
  if (scene->units[0] && parse_model_units_option("replay", 5, args, &at) != 0)
    return bk_error_set(err, "the recording's model units '%s' are refused", scene->units), UINT32_MAX;
  const char* material = scene->material[0] ? scene->material : NULL;
  if (scene->mesh[0]) return scene_resolve(NULL, false, scene->mesh, material, err);
  return scene_resolve(scene->name, true, NULL, material, err);
}

uint32_t replay_apply(loaded_scene* s, const recording_event* e, bool* applied, bk_error* err) {
  bk_world* world = s->world;
  *applied = true;
  switch (e->kind) {
  case RECORDING_FIRE:
    if (bk_body_is_null(bk_world_fire(world, &e->fire, err))) *applied = false;
    return *applied ? 1 : 0;
  case RECORDING_WEIGHT:
    *applied = app_drop_weight(world, e->weight.surface, e->weight.kg, e->weight.radius, err);
    return 0;
  case RECORDING_FOCUS:
    bk_world_set_focus(world, e->focus);
    return 0;
  case RECORDING_MATERIAL: {
    bk_breakable_id id = bk_world_breakable_at(world, e->material.breakable);
    bk_material m = recording_material(e);
    bk_result result = BK_ERROR_STALE_ID;
    if (e->material.setter == RECORDING_SET_FRAILTY)
      result = bk_world_set_frailty(world, id, m.frailty);
    else if (e->material.setter == RECORDING_SET_DENSITY)
      result = bk_world_set_density(world, id, m.density);
    else if (e->material.setter == RECORDING_SET_BOND_STRENGTH)
      result = bk_world_set_bond_strength(world, id, m.bond_strength);
    else
      result = bk_world_set_material(world, id, &m);
    if (result != BK_OK) {
      *applied = false;
      bk_error_set(err, "breakable %u refused its recorded material (%s)", e->material.breakable,
                   result == BK_ERROR_STALE_ID ? "no such breakable" : "invalid for it");
    }
    return 0;
  }
  case RECORDING_STRESS:
    bk_world_set_stress(world, e->stress);
    return 0;
  case RECORDING_BUDGET:
    if (!bk_world_set_physics_budget(world, e->budget_ms)) {
      *applied = false;
      bk_error_set(err, "the world refused the recorded physics budget %g ms", e->budget_ms);
    }
    return 0;
  default:
    *applied = false;
    bk_error_set(err, "a scene event cannot be applied to a loaded scene");
    return 0;
  }
}

static bool same(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

bool replay_material_change(const bk_material* a, const bk_material* b, recording_setter* setter) {
  bool name = strcmp(a->name ? a->name : "", b->name ? b->name : "") != 0;
  bool frailty = !same(a->frailty, b->frailty), density = !same(a->density, b->density);
  bool strength = !same(a->bond_strength, b->bond_strength);
  bool others = name || a->accumulate != b->accumulate || !same(a->friction, b->friction) ||
                !same(a->restitution, b->restitution) || !same(a->compression_limit, b->compression_limit) ||
                !same(a->tension_limit, b->tension_limit) || !same(a->shear_limit, b->shear_limit) ||
                !same(a->refine_strength, b->refine_strength);
  int changed = frailty + density + strength;
  *setter = RECORDING_SET_MATERIAL;
  if (!others && changed == 1)
    *setter = frailty ? RECORDING_SET_FRAILTY : density ? RECORDING_SET_DENSITY : RECORDING_SET_BOND_STRENGTH;
  return others || changed > 0;
}

void replay_hashes(loaded_scene* s, uint64_t* state_hash, uint64_t* world_hash) {
  *state_hash = bk_runtime_state_hash(bk_world_runtime(s->world));
  *world_hash = bk_world_state_hash(s->world);
}

bool replay_check(const recording* rec, uint64_t step, uint64_t state, uint64_t world, const char* command) {
  uint64_t want_state = rec->hashes[2 * step], want_world = rec->hashes[2 * step + 1];
  if (state == want_state && world == want_world) return true;
  if (state != want_state)
    fprintf(stderr, "breakables %s: replay: step %llu differs: state_hash %016llx, recorded %016llx\n",
            command, (unsigned long long)step + 1, (unsigned long long)state, (unsigned long long)want_state);
  else
    fprintf(stderr, "breakables %s: replay: step %llu differs: world_hash %016llx, recorded %016llx\n",
            command, (unsigned long long)step + 1, (unsigned long long)world, (unsigned long long)want_world);
  return false;
}
