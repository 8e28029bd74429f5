// The bond overlays (B, V).
#pragma once

#include "game_state.h"

/// The intact bonds inside each body as lines, coloured by their hit points
/// left or, when `by_stress`, by their stress over its limit (bond_overlay.c).
void game_draw_bonds(app_game* game, double alpha, bool by_stress);
