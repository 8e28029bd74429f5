// Internal to render/: shader and texture loading shared by the renderer.
#pragma once

#include <glad/gl.h>

#include "bk_render.h"

/// Compiles and links `<dir>/<name>.vert` + `.frag`, each preceded by
/// `<dir>/common.glsl` and, if non-NULL, `variant` defined as a macro (to 1). 0 with err holding the file
/// name, the variant and the GL info log on failure.
GLuint bk_shader_load(const char* dir, const char* name, const char* variant, bk_error* err);
/// Loads a PNG into a mipmapped, repeating texture; colour maps (`srgb`) keep
/// their sRGB bytes for the shader to decode, with levels averaged in linear light;
/// `mean_rgb` (may be NULL) gets its mean colour, linear for colour maps.
GLuint bk_texture_load(const char* path, bool srgb, float mean_rgb[3], bk_error* err);
/// The next mipmap level of an RGB image: each texel the mean of a 2x2 box
/// (an odd size leaves its last row or column out; a size of 1 takes its one
/// row or column twice), in linear light for `srgb` images (rounded to the
/// nearest sRGB byte). `out` holds max(w/2,1) x max(h/2,1) texels and may be `rgb`.
void bk_texture_halve(const unsigned char* rgb, int width, int height, bool srgb, unsigned char* out);
/// A 1x1 texture of one colour (stands in for an optional map).
GLuint bk_texture_solid(const unsigned char rgb[3]);
