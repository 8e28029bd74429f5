// Textures from PNG files (stb_image), mipmapped and repeating.
#include <limits.h>
#include <math.h>
#include <stb_image.h>
#include <stdlib.h>
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

// texture_halve for `channels` bytes a texel; `srgb` decodes the first
// three only (alpha, when there is one, is linear coverage or occlusion).
static void halve(const unsigned char* pixels, int width, int height, int channels, bool srgb,
                  unsigned char* out) {
  float decoded[256], linear[256];
  for (int value = 0; value < 256; ++value) {
    linear[value] = (float)value;
    decoded[value] = srgb ? decode_srgb((unsigned char)value) : (float)value;
  }
  int next_width = width > 1 ? width / 2 : 1, next_height = height > 1 ? height / 2 : 1;
  // Row by row, each texel read before any write reaches it, so `out` may be `pixels`.
  for (int y = 0; y < next_height; ++y)
    for (int x = 0; x < next_width; ++x)
      for (int k = 0; k < channels; ++k) {
        int x0 = 2 * x, y0 = 2 * y;
        int x1 = x0 + 1 < width ? x0 + 1 : x0, y1 = y0 + 1 < height ? y0 + 1 : y0;
        bool colour = srgb && k < 3;
        const float* table = colour ? decoded : linear;
        float sum = table[pixels[channels * (y0 * width + x0) + k]] +
                    table[pixels[channels * (y0 * width + x1) + k]] +
                    table[pixels[channels * (y1 * width + x0) + k]] +
                    table[pixels[channels * (y1 * width + x1) + k]];
        out[channels * (y * next_width + x) + k] =
            colour ? encode_srgb(decoded, 0.25f * sum) : (unsigned char)(0.25f * sum + 0.5f);
      }
}

void texture_halve(const unsigned char* rgb, int width, int height, bool srgb, unsigned char* out) {
  halve(rgb, width, height, 3, srgb, out);
}

void texture_halve_rgba(const unsigned char* rgba, int width, int height, unsigned char* out) {
  halve(rgba, width, height, 4, false, out);
}

// Uploads `pixels` (RGB or, with `channels` 4, linear RGBA bytes) as level 0
// and the chain of halved levels below it. Colour textures are stored as plain bytes and decoded in
// the shader after filtering: a software renderer converts every texel of
// an sRGB texture it samples (measured: 1-1.5 ms a frame in the settled
// showcase). Their levels are still averaged in linear light, as the driver
// would average an sRGB texture's, so distant surfaces keep their
// brightness.
static void upload_levels(const unsigned char* pixels, int width, int height, int channels, bool srgb) {
  GLint internal = channels == 4 ? GL_RGBA8 : GL_RGB8;
  GLenum format = channels == 4 ? GL_RGBA : GL_RGB;
  size_t bytes = (size_t)width * (size_t)height * (size_t)channels;
  glTexImage2D(GL_TEXTURE_2D, 0, internal, width, height, 0, format, GL_UNSIGNED_BYTE, pixels);
  unsigned char* level = bk_alloc(bytes);
  memcpy(level, pixels, bytes);
  for (int index = 1; width > 1 || height > 1; ++index) {
    halve(level, width, height, channels, srgb, level);
    width = width > 1 ? width / 2 : 1;
    height = height > 1 ? height / 2 : 1;
    glTexImage2D(GL_TEXTURE_2D, index, internal, width, height, 0, format, GL_UNSIGNED_BYTE, level);
  }
  free(level);
}

// Mipmapped (nearest level: trilinear costs on software GL) and repeating.
static GLuint make_texture(const unsigned char* pixels, int width, int height, int channels, bool srgb) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  upload_levels(pixels, width, height, channels, srgb);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_REPEAT);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_REPEAT);
  return texture;
}

/// Texture files larger than this are refused.
#define TEXTURE_MAX_FILE_BYTES ((uint64_t)1 << 28)

// The file is read by bk_file_read (a regular file only: stbi_load would
// block forever on a FIFO) and decoded from memory.
static unsigned char* load_pixels(const char* path, int wanted, int* width, int* height, bk_error* err) {
  void* data = NULL;
  size_t size = 0;
  if (!bk_file_read(path, TEXTURE_MAX_FILE_BYTES, "256 MiB", &data, &size, err)) return NULL;
  int channels = 0;
  unsigned char* pixels =
      size <= INT_MAX ? stbi_load_from_memory(data, (int)size, width, height, &channels, wanted) : NULL;
  free(data);
  if (!pixels) bk_error_set(err, "%s: cannot load texture: %s", path, stbi_failure_reason());
  return pixels;
}

// The mean colour (linear when srgb) of RGB pixels, and the texture of them.
static GLuint make_colour_texture(const unsigned char* pixels, int width, int height, bool srgb,
                                  float mean_rgb[3]) {
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
  return make_texture(pixels, width, height, 3, srgb);
}

GLuint texture_load(const char* path, bool srgb, float mean_rgb[3], bk_error* err) {
  int width = 0, height = 0;
  unsigned char* pixels = load_pixels(path, 3, &width, &height, err);
  if (!pixels) return 0;
  GLuint texture = make_colour_texture(pixels, width, height, srgb, mean_rgb);
  stbi_image_free(pixels);
  return texture;
}

GLuint texture_load_memory_flipped(const void* data, size_t size, const float color[3], float mean_rgb[3],
                                   bk_error* err) {
  int width = 0, height = 0, channels = 0;
  unsigned char white[3] = {255, 255, 255};
  unsigned char* pixels = NULL;
  if (!data) { // the colour alone
    width = height = 1;
    pixels = white;
  } else {
    if (size > INT_MAX || !stbi_info_from_memory(data, (int)size, &width, &height, &channels))
      return bk_error_set(err, "cannot load texture: not an image stb_image reads"), 0;
    // Refused before any pixel is allocated (as the library's image limit).
    if (width <= 0 || height <= 0 || width > (1 << 14) || height > (1 << 14) ||
        (uint64_t)width * (uint64_t)height > ((uint64_t)1 << 26))
      return bk_error_set(err, "cannot load texture: %d x %d pixels is too large", width, height), 0;
    pixels = stbi_load_from_memory(data, (int)size, &width, &height, &channels, 3);
    if (!pixels) return bk_error_set(err, "cannot load texture: a broken image"), 0;
  }
  // The colour multiplies the texture in linear light.
  float decoded[256];
  for (int value = 0; value < 256; ++value)
    decoded[value] = decode_srgb((unsigned char)value);
  size_t count = (size_t)width * (size_t)height;
  for (int k = 0; k < 3 && color && color[k] != 1.0f; ++k)
    for (size_t i = 0; i < count; ++i)
      pixels[3 * i + k] =
          encode_srgb(decoded, decoded[pixels[3 * i + k]] * fminf(fmaxf(color[k], 0.0f), 1.0f));
  // Row 0 of the texture is v = 0, the image's bottom row in a model's UVs.
  size_t row = 3u * (size_t)width;
  unsigned char* swap = bk_alloc(row);
  for (int y = 0; y < height / 2; ++y) {
    unsigned char *top = pixels + row * (size_t)y, *bottom = pixels + row * (size_t)(height - 1 - y);
    memcpy(swap, top, row);
    memcpy(top, bottom, row);
    memcpy(bottom, swap, row);
  }
  free(swap);
  GLuint texture = make_colour_texture(pixels, width, height, true, mean_rgb);
  if (data) stbi_image_free(pixels);
  return texture;
}

GLuint texture_load_rgba(const char* path, bk_error* err) {
  int width = 0, height = 0;
  unsigned char* pixels = load_pixels(path, 4, &width, &height, err);
  if (!pixels) return 0;
  GLuint texture = make_texture(pixels, width, height, 4, false);
  stbi_image_free(pixels);
  return texture;
}

GLuint texture_solid(const unsigned char rgba[4]) {
  GLuint texture = 0;
  glGenTextures(1, &texture);
  glBindTexture(GL_TEXTURE_2D, texture);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, 1, 1, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  return texture;
}
