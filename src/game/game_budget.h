// What the game shows of the physics budget: tiers and retired pieces.
#pragma once

#include "game_state.h"

/// Empties the retired pieces (a scene is loaded: their trees are gone).
void game_retired_reset(app_game* game);
/// After a world step (on the worker): ages the retired pieces by a step and
/// adds those the step retired.
void game_collect_retired(app_game* game);
/// Draws the retired pieces fading out, `alpha` of the way through the last step as the world is.
void game_draw_retired(app_game* game, double alpha);
/// The budget overlay's colour (rgb, strength) of a body at `tier`: none for full fidelity.
void game_tier_color(bk_budget_tier tier, float out[4]);
/// Turns on the overlay --overlay names; false (and one line on stderr) for an unknown name.
bool game_set_overlay(app_game* game, const char* name);
