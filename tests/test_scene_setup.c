// Scenes in a world, as the game's panel drives them: a material preset
// chosen in the panel applies at once and survives the reload that follows
// (the world's runtime owns the live values; the options say what the next
// load builds), and a slider's override survives a reset until a preset
// replaces it.
#include <stdlib.h>
#include <string.h>

#include "app.h"
#include "ensure.h"
#include "scene_run.h"

// In place: the world borrows the trees inside the loaded scene.
static void load(loaded_scene* scene, const scene_options* options) {
  bk_error err = {0};
  ENSURE_MSG(loaded_scene_create(scene_find("showcase"), options, scene, &err), "%s", err.message);
}

int main(void) {
  setenv("BREAKABLES_CACHE_DIR", BK_TEST_TMP "/scene_setup_cache", 1);
  scene_options options = default_scene_options();
  options.pieces = 16;
  loaded_scene scene = {0};
  load(&scene, &options);
  ENSURE(scene.tree_count == 6);
  // The showcase's objects start with their own presets.
  ENSURE(strcmp(bk_world_material(scene.world, scene.ids[0]).name, "stone") == 0);
  ENSURE(strcmp(bk_world_material(scene.world, scene.ids[3]).name, "glass") == 0);
  ENSURE(strcmp(bk_world_material(scene.world, scene.ids[5]).name, "stone") == 0); // the tower

  // The panel's preset: every object, now.
  const bk_material* wood = bk_material_find("wood");
  loaded_scene_apply_material(&scene, &options, wood);
  for (uint32_t i = 0; i < scene.tree_count; ++i) {
    bk_material m = bk_world_material(scene.world, scene.ids[i]);
    ENSURE(strcmp(m.name, "wood") == 0 && m.frailty == wood->frailty && m.density == wood->density);
    ENSURE(m.bond_strength == wood->bond_strength && m.accumulate == wood->accumulate);
  }
  // ...and after the reload (what R and the panel's reset do).
  loaded_scene_destroy(&scene);
  load(&scene, &options);
  for (uint32_t i = 0; i < scene.tree_count; ++i) {
    bk_material m = bk_world_material(scene.world, scene.ids[i]);
    ENSURE_MSG(strcmp(m.name, "wood") == 0 && m.frailty == wood->frailty && m.density == wood->density,
               "object %u is %s (frailty %g, density %g) after the reload", i, m.name, m.frailty, m.density);
  }

  // A slider's value is an override the reload keeps.
  options.frailty = 7.5;
  loaded_scene_destroy(&scene);
  load(&scene, &options);
  ENSURE(bk_world_frailty(scene.world, scene.ids[2]) == 7.5);
  ENSURE(bk_world_density(scene.world, scene.ids[2]) == wood->density);
  // A new preset replaces it.
  const bk_material* glass = bk_material_find("glass");
  loaded_scene_apply_material(&scene, &options, glass);
  loaded_scene_destroy(&scene);
  load(&scene, &options);
  ENSURE(bk_world_frailty(scene.world, scene.ids[2]) == glass->frailty);
  loaded_scene_destroy(&scene);
  return 0;
}
