// Images glTF cannot hold (TGA, BMP, GIF: a model's textures are often
// those) converted to PNG for an export, decoded by stb_image. Only these
// decoders are built, with internal linkage: the library exports no stb
// symbol, and a program linking its own stb_image keeps it.
#include <stdint.h>
#include <stdlib.h>

#include "bk_geom.h"

#define STB_IMAGE_IMPLEMENTATION
#define STB_IMAGE_STATIC
#define STBI_NO_STDIO
#define STBI_ONLY_TGA
#define STBI_ONLY_BMP
#define STBI_ONLY_GIF
#define STBI_NO_LINEAR
#define STBI_NO_HDR
// The largest side decoded: 16384 (stb_image would take up to 2^24).
#define STBI_MAX_DIMENSIONS (1 << 14)
#if defined(__GNUC__)
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#endif
#include <stb/stb_image.h>
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif

bool bk_image_convert_to_png(const void* data, size_t size, uint8_t** png, size_t* png_size) {
  *png = NULL, *png_size = 0;
  if (!data || size == 0 || size > INT32_MAX) return false;
  int width = 0, height = 0, channels = 0;
  // The size is checked before any pixel is allocated.
  if (!stbi_info_from_memory(data, (int)size, &width, &height, &channels)) return false;
  if (width <= 0 || height <= 0 || width > (1 << 14) || height > (1 << 14) ||
      (uint64_t)width * (uint64_t)height > BK_IMAGE_MAX_PIXELS)
    return false;
  stbi_uc* rgba = stbi_load_from_memory(data, (int)size, &width, &height, &channels, 4);
  if (!rgba) return false;
  bool ok = bk_png_encode_rgba(rgba, (uint32_t)width, (uint32_t)height, png, png_size);
  stbi_image_free(rgba);
  return ok;
}
