// A model file's own surface, for drawing it as it is in `play`.
#pragma once

#include <stdbool.h>
#include <stddef.h>

/// A model file's own surface (model_surface.c): the base-colour texture
/// (the image file's bytes, or NULL) and colour (linear RGB) of the
/// material most of its triangles use.
typedef struct app_model_surface {
  void* image;
  size_t image_size;
  float color[3];
} app_model_surface;
/// Reads `path`'s surface; false (nothing held) when it is not a model file
/// or has no texture or colour of its own (untextured and white or a
/// neutral grey, as a format's default material).
bool app_read_model_surface(const char* path, app_model_surface* out);
void app_model_surface_free(app_model_surface* surface);
