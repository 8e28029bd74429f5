// The panel's Refinement section: fragments hit hard enough are fractured
// again around the hit (--refine). Whether a hit refines is the material's
// refine_strength, which the world's runtime takes live, so the checkbox
// applies at once; the pieces a refinement makes are fixed when a breakable
// is added, so the slider applies on reset, as the fracture settings do.
#include "panel_refine.h"
#include "ui.h"

// The refine_strength the options give a material (scene_refine's rule:
// it follows the bond strength), or 0 with refinement off.
static double refine_strength(const scene_options* options, const bk_material* material, bool on) {
  scene_options refined = *options;
  refined.refine = on;
  bk_breakable_def def = {.material = *material};
  def.material.refine_strength = 0.0;
  scene_refine(&def, &refined);
  return def.material.refine_strength;
}

void game_set_refine(app_game* g, bool on) {
  g->options.refine = on;
  for (uint32_t i = 0; i < g->scene.tree_count; ++i) {
    bk_material m = bk_world_material(g->scene.world, g->scene.ids[i]);
    m.refine_strength = refine_strength(&g->options, &m, on);
    bk_world_set_material(g->scene.world, g->scene.ids[i], &m);
  }
}

bool game_refine_live(const app_game* g) {
  return g->scene.tree_count > 0 && bk_world_material(g->scene.world, g->scene.ids[0]).refine_strength > 0.0;
}

void game_refine_follow(app_game* g) {
  if (game_refine_live(g)) game_set_refine(g, true);
}

void game_refine_section(app_game* g) {
  bk_world* world = g->scene.world;
  if (g->scene.tree_count == 0) return;
  bool on = game_refine_live(g);
  if (ui_checkbox("Refine where hit", &on)) game_set_refine(g, on);
  ui_tooltip("a fragment struck hard enough is fractured again, radially round the hit, and its pieces "
             "take the hit's damage: fine breaks where it is shot, large pieces elsewhere (applies now)");
  int pieces = (int)g->options.refine_pieces;
  if (ui_slider_int_log("refine pieces", &pieces, BK_REFINE_PIECES_MIN, 256))
    g->options.refine_pieces = (uint32_t)pieces;
  ui_tooltip("pieces per refinement: how many a refined fragment breaks into, radially round the hit "
             "(applies on reset)");
  if (g->refine_pieces_made != g->options.refine_pieces)
    ui_text("now %u pieces a refinement: reset (R) to apply", g->refine_pieces_made);
  const bk_mesh_tree* tree = bk_runtime_breakable_tree(bk_world_runtime(world), g->scene.ids[0]);
  bk_world_stats s = bk_world_get_stats(world);
  ui_text("fragments refined %u   last step %.2f ms", s.refined_leaves, s.refine_ms);
  if (tree) ui_text("fragments %u (fractured into %u)", tree->leaf_count, g->scene.trees[0].leaf_count);
  if (ui_button("reset with these settings")) g->reload = true;
}
