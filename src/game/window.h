// The window and its GL context, and the options the windowed commands share.
#pragma once

#include <stdbool.h>
#include <stdint.h>

#include "app.h"
#include "render.h"

/// Options shared by `play` and `editor`.
typedef struct window_options {
  int width, height;
  uint32_t frames;        ///< 0 = run until closed
  uint32_t autofire;      ///< projectiles fired at the target over the run
  const char* screenshot; ///< PNG of the last frame
} window_options;

/// Parses the options both windowed commands share; returns 0 if `arg` was
/// one of them (consuming its value), 1 if not ours, or 2 on a bad value.
int parse_window_option(const char* command, int argc, char** argv, int* i, window_options* options);

/// Fits a camera's near and far planes to what it looks at from `distance`
/// metres: the renderer's defaults (0.05, 200) for the scenes, the far plane
/// pushed out for a model hundreds of metres across and the near plane
/// brought in for one of a few centimetres, so that either is seen whole.
void camera_fit_planes(app_camera* camera, double distance);

/// Opens a window with a GL 3.3 core context and the renderer.
bool window_open(const char* title, const window_options* options, void** window, app_renderer** renderer,
                 bk_error* err);
void window_close(void* window, app_renderer* renderer);
/// Shader directory next to the executable (or in the source tree).
const char* app_shader_dir(void);
