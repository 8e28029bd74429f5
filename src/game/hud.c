// The game's heads-up display: a crosshair at the centre of the picture,
// where the camera looks and so where a shot goes, and a one-line hint of
// the controls that fades once a new player has had time to read it.
#include <stdbool.h>

#include "hud.h"
#include "ui.h"

// Long enough to read the line twice, short enough not to sit over the
// first breaks of a session.
static const double hint_shown = 6.0, hint_fade = 1.5;

float hud_hint_alpha(double seconds) {
  if (!(seconds > hint_shown)) return 1.0f; // NaN too: better shown than lost
  double t = (seconds - hint_shown) / hint_fade;
  if (t >= 1.0) return 0.0f;
  return (float)(1.0 - t * t * (3.0 - 2.0 * t)); // smoothstep: no jump at either end
}

const char* hud_hint(bool narrow) {
  return narrow ? "Right drag: look   WASD: move   Click: fire   F1: panel"
                : "Right drag: look   W A S D Q E: move   Click / Space: fire   X: weight   1-9, 0: scenes   "
                  "R: reset   P: pause   F1: panel   Esc: quit";
}

// Arms with a gap at the middle, light over a dark outline, so that the
// cross reads against the sky, stone and glass alike without hiding the
// point it marks.
static void draw_crosshair(float cx, float cy, float unit) {
  const float dark[4] = {0.0f, 0.0f, 0.0f, 0.55f}, light[4] = {1.0f, 1.0f, 1.0f, 0.9f};
  float gap = 5.0f * unit, arm = 15.0f * unit;
  const float dirs[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
  for (int pass = 0; pass < 2; ++pass)
    for (int i = 0; i < 4; ++i) {
      float dx = dirs[i][0], dy = dirs[i][1], pad = pass == 0 ? unit : 0.0f;
      ui_overlay_line(cx + dx * (gap - pad), cy + dy * (gap - pad), cx + dx * (arm + pad),
                      cy + dy * (arm + pad), pass == 0 ? dark : light, pass == 0 ? 4.0f * unit : 2.0f * unit);
    }
  ui_overlay_rect(cx - unit, cy - unit, cx + unit, cy + unit, light, 0.0f);
}

static void draw_hint(float width, float height, float alpha) {
  float text_w = 0.0f, text_h = 0.0f, pad = 0.0f;
  const char* hint = hud_hint(false);
  ui_text_size(hint, &text_w, &text_h);
  pad = 0.6f * text_h;
  if (text_w + 4.0f * pad > width) {
    hint = hud_hint(true);
    ui_text_size(hint, &text_w, &text_h);
  }
  float x = 0.5f * (width - text_w), y = height - text_h - 3.0f * pad;
  const float box[4] = {0.05f, 0.06f, 0.08f, 0.6f * alpha}, ink[4] = {0.95f, 0.95f, 0.92f, alpha};
  ui_overlay_rect(x - pad, y - 0.5f * pad, x + text_w + pad, y + text_h + 0.5f * pad, box, 0.5f * pad);
  ui_overlay_text(x, y, ink, hint);
}

void hud_draw(double seconds) {
  float width = 0.0f, height = 0.0f, text_h = 0.0f;
  ui_display_size(&width, &height);
  if (!(width > 0.0f && height > 0.0f)) return; // outside a frame, or a minimised window
  ui_text_size("X", NULL, &text_h);
  float unit = text_h > 0.0f ? text_h / 13.0f : 1.0f; // follows the UI's scale (13 px at 1)
  draw_crosshair(0.5f * width, 0.5f * height, unit);
  float alpha = hud_hint_alpha(seconds);
  if (alpha > 0.0f) draw_hint(width, height, alpha);
}
