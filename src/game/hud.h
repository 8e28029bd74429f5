// Internal to the executable: the game's heads-up display, drawn over the
// picture through the UI layer (a crosshair where shots go, a controls hint).
#pragma once

#include <stdbool.h>

/// The hint's opacity `seconds` after the game started: 1 for the first
/// seconds, then fading to 0, and 0 from then on.
float hud_hint_alpha(double seconds);
/// The one-line controls hint, or its short form for a window too narrow for it.
const char* hud_hint(bool narrow);
/// Draws the crosshair at the window's centre and, while it has not faded,
/// the hint along the bottom (between ui_begin_frame and ui_end_frame).
void hud_draw(double seconds);
