// The live tuning panel and its worker threads.
#pragma once

#include "game_state.h"

/// Draws the tuning panel (between ui_begin_frame and ui_end_frame).
void game_panel(app_game* game);
/// True while the panel's benchmark sweep runs.
bool game_panel_busy(void);
/// Waits for a running re-fracture and frees what it made.
void game_panel_shutdown(void);
