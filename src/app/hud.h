// Internal to the executable: the game's heads-up display, drawn over the
// picture through the UI layer (a crosshair where shots go, a controls hint).
#pragma once

#include <stdbool.h>

/// The hint's opacity `seconds` after the game started: 1 for the first
/// seconds, then fading to 0, and 0 from then on.
float bk_hud_hint_alpha(double seconds);
/// The one-line controls hint, or its short form for a window too narrow for it.
const char* bk_hud_hint(bool narrow);
/// Draws the crosshair at the window's centre and, while it has not faded,
/// the hint along the bottom (between bk_ui_begin_frame and bk_ui_end_frame).
void bk_hud_draw(double seconds);
