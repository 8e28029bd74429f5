// The panel's Refinement section.
#pragma once

#include "game_state.h"

/// The panel's Refinement section (panel_refine.c).
void game_refine_section(app_game* game);
/// Refinement on or off for every object of the scene now (their
/// materials' refine_strength, scene_refine's rule), and for the next reload.
void game_set_refine(app_game* game, bool on);
/// Whether the scene's objects refine now (their material's refine_strength).
bool game_refine_live(const app_game* game);
/// After a change of bond strength: the refine_strength that follows it
/// (scene_refine), when refinement is on.
void game_refine_follow(app_game* game);
