// Textures from PNG files (stb_image), mipmapped and repeating.
#include <math.h>
#include <stb_image.h>
#include <string.h>

#include "render_internal.h"

// An sRGB-encoded byte in linear light.
static float decode_srgb(unsigned char c) {
  float x = (float)c / 255.0f;
  return x <= 0.04045f ? x / 12.92f : powf((x + 0.055f) / 1.055f, 2.4f);
}

// The byte whose decoded value is nearest to `linear` (`decoded` is the
// increasing table of all 256).
static unsigned char encode_srgb(const float decoded[256], float linear) {
  int low = 0, high = 255;
  while (low < high) { // the first byte decoding to at least `linear`
    int middle = (low + high) / 2;
    if (decoded[middle] < linear)
      low = middle + 1;
    else
      high = middle;
  }
  if (low > 0 && linear - decoded[low - 1] < decoded[low] - linear) low--;
  return (unsigned char)low;
}

void bk_texture_halve(const unsigned char* rgb, int width, int height, bool srgb, unsigned char* out) {
  float decoded[256];
  for (int value = 0; value < 256; ++value)
    decoded[value] = srgb ? decode_srgb((unsigned char)value) : (float)value;
  int next_width = width > 1 ? width / 2 : 1, next_height = height > 1 ? height / 2 : 1;
  // Row by row, each texel read before any write reaches it, so `out` may be `rgb`.
  for (int y = 0; y < next_height; ++y)
    for (int x = 0; x < next_width; ++x)
      for (int k = 0; k < 3; ++k) {
        int x0 = 2 * x, y0 = 2 * y;
        int x1 = x0 + 1 < width ? x0 + 1 : x0, y1 = y0 + 1 < height ? y0 + 1 : y0;
        float sum = decoded[rgb[3 * (y0 * width + x0) + k]] + decoded[rgb[3 * (y0 * width + x1) + k]] +
                    decoded[rgb[3 * (y1 * width + x0) + k]] + decoded[rgb[3 * (y1 * width + x1) + k]];
        out[3 * (y * next_width + x) + k] =
            srgb ? encode_srgb(decoded, 0.25f * sum) : (unsigned char)(0.25f * sum + 0.5f);
      }
}

// Uploads `pixels` (RGB bytes) as level 0 and the chain of bk_texture_halve
// levels below it. Colour textures are stored as plain bytes and decoded in
// the shader after filtering: a software renderer converts every texel of
// an sRGB texture it samples (measured: 1-1.5 ms a frame in the settled
// showcase). Their levels are still averaged in linear light, as the driver
// would average an sRGB texture's, so distant surfaces keep their
// brightness.
static void upload_levels(const unsigned char* pixels, int width, int height, bool srgb) {
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, pixels);
  unsigned char* level = bk_alloc((size_t)width * (size_t)height * 3);
  memcpy(level, pixels, (size_t)width * (size_t)height * 3);
  for (int index = 1; width > 1 || height > 1; ++index) {
    bk_texture_halve(level, width, height, srgb, level);
    width = width > 1 ? width / 2 : 1;
    height = height > 1 ? height / 2 : 1;
    glTexImage2D(GL_TEXTURE_2D, index, GL_RGB8, width, height, 0, GL_RGB, GL_UNSIGNED_BYTE, level);
  }
  free(level);
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
  upload_levels(pixels, width, height, srgb);
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
