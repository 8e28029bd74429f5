// What the game shows of the physics budget: bodies coloured by the tier
// the budget gave them (L, --overlay budget), and the pieces it retired,
// kept from the world's list after each step and drawn fading out along the
// path they were on. Also the overlay names --overlay takes.
#include <string.h>

#include "game_budget.h"

static const double fade_seconds = 1.0;

// One world step: the game's worlds keep the default.
static double step_seconds(void) { return bk_default_world_def().fixed_dt; }

void game_retired_reset(app_game* g) {
  retired_pieces_init(&g->retired, fade_seconds, bk_v3(0.0, -9.81, 0.0));
}

void game_collect_retired(app_game* g) {
  bk_world* world = g->scene.world;
  g->retired.gravity = bk_physics_gravity(bk_world_physics(world)); // the panel may have changed it
  retired_pieces_update(&g->retired, step_seconds());               // a step's time: paused, they wait too
  bk_retired_body bodies[256];
  uint32_t total = bk_world_retired_bodies(world, bodies, 256);
  // More than fit here in one step: the rest go unseen, as the ring would
  // push them out anyway (and are counted with those it does).
  if (total > 256) g->retired.pushed_out += total - 256;
  for (uint32_t i = 0; i < total && i < 256; ++i) {
    uint32_t tree_index = bodies[i].breakable.index;
    if (tree_index >= g->scene.tree_count) continue;
    // The tree as it is now: a refined one names its new nodes, which the
    // tree the scene was made from does not have.
    const bk_mesh_tree* tree = bk_runtime_breakable_tree(bk_world_runtime(world), bodies[i].breakable);
    if (!tree || bodies[i].node >= tree->node_count) continue;
    const bk_mesh* mesh = &tree->nodes[bodies[i].node].mesh;
    retired_pieces_add(&g->retired, &bodies[i], tree_index, g->looks[tree_index], mesh->positions,
                       mesh->position_count);
  }
}

void game_tier_color(bk_budget_tier tier, float out[4]) {
  // Full bodies keep their own colours; the cheaper the tier, the warmer.
  static const float colors[5][4] = {{0.0f, 0.0f, 0.0f, 0.0f},
                                     {0.15f, 0.45f, 1.0f, 0.65f},
                                     {1.0f, 0.8f, 0.1f, 0.7f},
                                     {0.75f, 0.25f, 1.0f, 0.7f},
                                     {1.0f, 0.15f, 0.1f, 0.8f}};
  memcpy(out, colors[tier <= BK_TIER_RETIRED ? tier : BK_TIER_FULL], sizeof colors[0]);
}

void game_draw_retired(app_game* g, double alpha) {
  // The world is drawn alpha of the way through its last step: so are they.
  double behind = (1.0 - alpha) * step_seconds();
  float red[4] = {0.0f};
  game_tier_color(BK_TIER_RETIRED, red);
  for (uint32_t i = 0; i < g->retired.count; ++i) {
    const retired_piece* p = retired_pieces_at(&g->retired, i);
    if (p->tree >= g->scene.tree_count) continue;
    double age = fmax(0.0, p->age - behind);
    node_draw draw = {.tree = g->render_trees[p->tree],
                      .nodes = &p->node,
                      .node_count = 1,
                      .model = retired_piece_pose(&g->retired, p, age),
                      .material = p->material,
                      .node_colors = g->show_budget ? red : NULL,
                      .fade = retired_piece_fade(&g->retired, age)};
    renderer_draw_nodes(g->renderer, &draw);
  }
}

bool game_set_overlay(app_game* g, const char* name) {
  bool* flags[] = {&g->show_bonds, &g->show_stress, &g->show_nodes, &g->show_hulls, &g->show_budget};
  const char* const names[] = {"bonds", "stress", "nodes", "hulls", "budget"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
    if (strcmp(name, names[i]) == 0) return *flags[i] = true;
  fprintf(stderr, "breakables play: --overlay must be bonds, stress, nodes, hulls or budget (got '%s')\n",
          name);
  return false;
}
