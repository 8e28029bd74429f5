// The panel's Physics budget section.
#pragma once

#include "game_state.h"

/// The panel's Physics budget section (panel_budget.c).
void game_budget_section(app_game* game);
