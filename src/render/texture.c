// Textures from PNG files (stb_image), mipmapped and repeating.
#include <math.h>
#include <stb_image.h>

#include "render_internal.h"

// An sRGB-encoded byte in linear light.
static float decode_srgb(unsigned char c) {
  float x = (float)c / 255.0f;
  return x <= 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
}

GLuint bk_texture_load(const char* path, bool srgb, float mean_rgb[3], bk_error* err) {
  int width = 0, height = 0, channels = 0;
  unsigned char* pixels = stbi_load(path, &width, &height, &channels, 3);
  if (!pixels) return bk_error_set(err, "%s: cannot load texture: %s", path, stbi_failure_reason()), 0;
  if (mean_rgb) {
    // In linear light, as the shaders light it: what the texture looks like
    // from far away (its last mipmap level).
    // Counted per byte value first: 768 decodes instead of three a pixel.
    size_t count = (size_t)width * (size_t)height, histogram[3][256] = {{0}};
    for (size_t i = 0; i < count; ++i)
      for (int k = 0; k < 3; ++k)
        histogram[k][pixels[3 * i + k]]++;
    for (int k = 0; k < 3; ++k) {
      double sum = 0.0;
      for (int value = 0; value < 256; ++value)
        sum += (double)histogram[k][value] * (srgb ? decode_srgb((unsigned char)value) : value / 255.0);
      mean_rgb[k] = count ? (float)(sum / (double)count) : 0.0f;
    }
  }
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, srgb ? GL_SRGB8 : GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE,
               pixels);
  glGenerateMipmap(GL_TEXTURE_2D);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER,
                  GL_LINEAR_MIPMAP_NEAREST); // trilinear costs on software GL
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  stbi_image_free(pixels);
  return texture;
}

GLuint bk_texture_solid(const unsigned char rgb[3]) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, 1, 1, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return texture;
}
