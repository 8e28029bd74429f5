// The panel's Physics budget section. The world owns the budget: the slider
// shows what bk_world_physics_budget says every frame and writes a change
// straight back; the options only record it for the next reset, as the
// panel's other live settings do.
#include "panel_budget.h"
#include "ui.h"

void game_budget_section(app_game* g) {
  bk_world* world = g->scene.world;
  double ms = bk_world_physics_budget(world);
  if (ui_slider_double("budget ms", &ms, 0.0, 33.0, ms > 0.0 ? "%.1f ms" : "off", false) &&
      bk_world_set_physics_budget(world, ms))
    g->options.physics_budget_ms = ms;
  ui_tooltip("what the physics of a step may cost (0 = off; Ctrl+click to type a value). Over it, the "
             "least important loose pieces (small, far from the camera, slow, long at rest) get "
             "cheaper, tier by tier: debris stops colliding with other debris (only with large pieces "
             "and the world), then is simplified to a fitted sphere or box, then frozen where it lies, "
             "then retired: removed, and drawn fading out for a second. Large pieces and those near the "
             "camera stay fully simulated; under half the budget, pieces get their fidelity back");
  bk_world_stats s = bk_world_get_stats(world);
  char level[48];
  snprintf(level, sizeof level, "level %.2f of 4", s.budget_level);
  ui_progress((float)(s.budget_level / 4.0), level);
  ui_tooltip("how far the budget reaches: 0 nothing made cheaper, 1 debris, 2 simplified, 3 frozen, "
             "4 retiring");
  ui_text("step cost %.2f ms (as the budget sees it)", s.budget_cost_ms);
  ui_text("now: debris %u   simplified %u   frozen %u", s.budget_debris, s.budget_simplified,
          s.budget_frozen);
  ui_text("retired %u (%.3g kg)", s.budget_retired, s.retired_mass);
  ui_text("fading %u of %d (%u cut short)", g->retired.count, BK_RETIRED_PIECES_MAX, g->retired.pushed_out);
  ui_tooltip("retired pieces drawn fading out for a second; when more retire at once than fit, the oldest "
             "go first");
  ui_text("demotions %u   restorations %u", s.budget_demotions, s.budget_restorations);
  ui_checkbox("colour bodies by tier (L)", &g->show_budget);
  ui_tooltip("blue: debris, yellow: simplified, purple: frozen, red: retired and fading; full "
             "fidelity keeps its own colours");
}
