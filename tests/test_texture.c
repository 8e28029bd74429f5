// Mipmap levels of colour textures: averaged in linear light, rounded to the
// nearest sRGB byte (the shaders filter the bytes and decode after). The CPU
// side only: no GL context. And the shipped interior textures
// (tools/make_textures.c): every material's colour and normal map with
// occlusion, tileable, in its material's colour range, with unit normals.
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include <stb/stb_image.h>

#include "ensure.h"
#include "render_internal.h"

// The exact sRGB curve, written out here independently of the renderer.
static double srgb_to_linear(int byte) {
  double x = byte / 255.0;
  return x <= 0.04045 ? x / 12.92 : pow((x + 0.055) / 1.055, 2.4);
}

static int nearest_srgb_byte(double linear) {
  int best = 0;
  for (int b = 1; b < 256; ++b)
    if (fabs(srgb_to_linear(b) - linear) < fabs(srgb_to_linear(best) - linear)) best = b;
  return best;
}

static void fill(unsigned char* rgb, int texels, const int* values) {
  for (int i = 0; i < texels; ++i)
    rgb[3 * i] = rgb[3 * i + 1] = rgb[3 * i + 2] = (unsigned char)values[i];
}

static void test_black_and_white(void) {
  // Half black, half white is half the light: sRGB 188, not the byte mean 128.
  unsigned char rgb[12], out[3];
  fill(rgb, 4, (const int[]){0, 255, 255, 0});
  texture_halve(rgb, 2, 2, true, out);
  ENSURE(out[0] == nearest_srgb_byte(0.5) && out[0] == 188);
  ENSURE(out[1] == out[0] && out[2] == out[0]);
  // Data that is not a colour (a normal map) averages its bytes.
  texture_halve(rgb, 2, 2, false, out);
  ENSURE(out[0] == 128 && out[1] == 128 && out[2] == 128);
}

static void test_every_byte_survives(void) {
  // A flat texture keeps its colour at every level, whatever the byte.
  for (int b = 0; b < 256; ++b) {
    unsigned char rgb[12], out[3];
    fill(rgb, 4, (const int[]){b, b, b, b});
    for (int srgb = 0; srgb < 2; ++srgb) {
      texture_halve(rgb, 2, 2, srgb, out);
      ENSURE_MSG(out[0] == b && out[1] == b && out[2] == b, "byte %d, srgb %d: got %d", b, srgb, out[0]);
    }
  }
}

static void test_mixed_channels(void) {
  // Each channel on its own: red from two dark and two light texels, green
  // and blue from other mixes, against the exact curve.
  const unsigned char rgb[12] = {10, 200, 0, 240, 200, 0, 10, 50, 255, 240, 50, 255};
  unsigned char out[3];
  texture_halve(rgb, 2, 2, true, out);
  for (int k = 0; k < 3; ++k) {
    double mean = 0.0;
    for (int i = 0; i < 4; ++i)
      mean += srgb_to_linear(rgb[3 * i + k]) / 4.0;
    ENSURE_MSG(out[k] == nearest_srgb_byte(mean), "channel %d: %d, expected %d", k, out[k],
               nearest_srgb_byte(mean));
  }
}

static void test_sizes(void) {
  // 3x3 to 1x1: the top-left 2x2 box; the last row and column are left out.
  unsigned char rgb[27], out[3];
  fill(rgb, 9, (const int[]){0, 0, 255, 0, 0, 255, 255, 255, 255});
  texture_halve(rgb, 3, 3, true, out);
  ENSURE(out[0] == 0);
  // 1x4 to 1x2: a single column halves its rows only.
  unsigned char column[12], half[6];
  fill(column, 4, (const int[]){0, 0, 255, 255});
  texture_halve(column, 1, 4, true, half);
  ENSURE(half[0] == 0 && half[3] == 255);
  // 1x1 stays itself.
  unsigned char one[3] = {7, 77, 177}, same[3];
  texture_halve(one, 1, 1, true, same);
  ENSURE(memcmp(one, same, 3) == 0);
}

static void test_in_place(void) {
  // The loader halves one buffer in place: the same as into a second one.
  enum { W = 8, H = 6 };
  unsigned char image[W * H * 3], copy[W * H * 3], out[(W / 2) * (H / 2) * 3];
  unsigned state = 12345;
  for (int i = 0; i < W * H * 3; ++i) {
    state = state * 1103515245u + 12345u;
    image[i] = (unsigned char)(state >> 16);
  }
  memcpy(copy, image, sizeof image);
  for (int srgb = 0; srgb < 2; ++srgb) {
    memcpy(image, copy, sizeof image);
    texture_halve(copy, W, H, srgb, out);
    texture_halve(image, W, H, srgb, image);
    ENSURE_MSG(memcmp(image, out, sizeof out) == 0, "srgb %d: in-place result differs", srgb);
  }
}

static void test_rgba_levels(void) {
  // A normal map with occlusion in alpha: four channels, every one a plain
  // rounded mean (no sRGB curve), each texel's four bytes kept together.
  const unsigned char rgba[16] = {0, 128, 255, 255, 255, 128, 255, 0, 255, 0, 250, 255, 0, 1, 250, 0};
  unsigned char out[4] = {0};
  texture_halve_rgba(rgba, 2, 2, out);
  ENSURE_MSG(out[0] == 128 && out[1] == 64 && out[2] == 253 && out[3] == 128, "got %d %d %d %d", out[0],
             out[1], out[2], out[3]);
  // Odd sizes and in place, as the RGB levels: a 3x1 row keeps its first two texels' mean.
  unsigned char row[12] = {10, 20, 30, 40, 30, 40, 50, 60, 255, 255, 255, 255};
  texture_halve_rgba(row, 3, 1, row);
  ENSURE(row[0] == 20 && row[1] == 30 && row[2] == 40 && row[3] == 50);
}

// ------------------------------------------------------------ interiors

typedef struct {
  const char* name;
  double lo[3], hi[3]; // mean sRGB byte per channel
  double max_chroma;   // largest channel mean minus smallest
  double min_tilt;     // mean 1 - n.z: how rough the broken face is
  double max_mean_ao;  // mean occlusion byte: pits and crevices do darken it
} interior_spec;

// Fresh fractures' colours: a grey-beige sandstone, grey concrete with its
// aggregate, fired red clay, light end grain, off-white porcelain bodies,
// and green soda-lime glass. None near white but the porcelains.
static const interior_spec interiors[] = {
    {"stone", {125, 115, 95}, {170, 160, 145}, 45, 0.04, 250},
    {"concrete", {105, 105, 100}, {150, 148, 145}, 20, 0.03, 250},
    {"brick", {140, 65, 40}, {190, 105, 75}, 130, 0.015, 253},
    {"wood", {150, 110, 65}, {200, 160, 110}, 110, 0.015, 253},
    {"porcelain", {195, 195, 190}, {235, 235, 230}, 15, 0.005, 254.5},
    {"eggshell", {200, 190, 160}, {240, 230, 210}, 50, 0.005, 254.5},
    {"glass", {120, 160, 140}, {180, 215, 200}, 60, 0.004, 255},
};

// Mean |difference| between texel lines a and b of one channel: columns
// (axis 0) or rows (axis 1), wrapping.
static double line_step(const unsigned char* px, int n, int channels, int k, int axis, int a, int b) {
  a = (a + n) % n, b = (b + n) % n;
  double sum = 0.0;
  for (int i = 0; i < n; ++i) {
    int pa = axis ? a * n + i : i * n + a, pb = axis ? b * n + i : i * n + b;
    sum += fabs((double)px[pa * channels + k] - px[pb * channels + k]);
  }
  return sum / n;
}

// How much larger the step from line a to line b is than the steps next to
// it on either side: about 1 where b continues a, more at a seam.
static double join_ratio(const unsigned char* px, int n, int channels, int k, int axis, int a, int b) {
  double around = 0.0;
  for (int i = 1; i <= 4; ++i)
    around += line_step(px, n, channels, k, axis, a - i, a - i + 1) +
              line_step(px, n, channels, k, axis, b + i - 1, b + i);
  return line_step(px, n, channels, k, axis, a, b) / (around / 8.0 + 0.5);
}

// Tiles: the step from the last column (row) to the first is like the steps
// next to it. The check has teeth: where neighbouring texels are much more
// alike than texels half a tile apart, joining two unrelated lines of the
// same texture (a quarter from either edge) does fail it.
static void ensure_tiles(const char* file, const unsigned char* px, int n, int channels) {
  for (int k = 0; k < channels; ++k)
    for (int axis = 0; axis < 2; ++axis) {
      double seam = join_ratio(px, n, channels, k, axis, n - 1, 0);
      ENSURE_MSG(seam < 1.6, "%s: channel %d has a seam across %s (%.2f)", file, k, axis ? "rows" : "columns",
                 seam);
      double near = 0.0, apart = 0.0;
      for (int i = 0; i < n; ++i) {
        near += line_step(px, n, channels, k, axis, i, i + 1) / n;
        apart += line_step(px, n, channels, k, axis, i, i + n / 2) / n;
      }
      if (apart > 2.5 * near) {
        double cut = 0.0;
        for (int i = 0; i < 8; ++i)
          cut += join_ratio(px, n, channels, k, axis, i * n / 8, i * n / 8 + n / 2 + 1) / 8.0;
        ENSURE_MSG(cut > 1.8, "%s: channel %d: unrelated %s joined score only %.2f", file, k,
                   axis ? "rows" : "columns", cut);
      }
    }
}

// The colour's mean and spread and the normal map's normals and occlusion.
static void ensure_interior(const interior_spec* spec, const unsigned char* color,
                            const unsigned char* normal, int n) {
  const size_t count = (size_t)n * (size_t)n;
  double mean[3] = {0, 0, 0}, luma_sum = 0.0, luma_sq = 0.0;
  for (size_t i = 0; i < count; ++i) {
    double luma = 0.2126 * color[3 * i] + 0.7152 * color[3 * i + 1] + 0.0722 * color[3 * i + 2];
    luma_sum += luma, luma_sq += luma * luma;
    for (int k = 0; k < 3; ++k)
      mean[k] += color[3 * i + k] / (double)count;
  }
  for (int k = 0; k < 3; ++k)
    ENSURE_MSG(mean[k] >= spec->lo[k] && mean[k] <= spec->hi[k],
               "%s interior: channel %d mean %.1f not in %g..%g", spec->name, k, mean[k], spec->lo[k],
               spec->hi[k]);
  double top = fmax(mean[0], fmax(mean[1], mean[2])), bottom = fmin(mean[0], fmin(mean[1], mean[2]));
  ENSURE_MSG(top - bottom <= spec->max_chroma, "%s interior: chroma %.1f over %g", spec->name, top - bottom,
             spec->max_chroma);
  // Not a flat colour: grain, aggregate, rings show.
  double sd = sqrt(luma_sq / (double)count - (luma_sum / (double)count) * (luma_sum / (double)count));
  ENSURE_MSG(sd > 2.0, "%s interior: luminance spread %.2f, flat", spec->name, sd);

  double tilt = 0.0, mean_x = 0.0, mean_y = 0.0, ao = 0.0, worst_length = 0.0;
  size_t open = 0, dark = 0;
  for (size_t i = 0; i < count; ++i) {
    double x = normal[4 * i] / 127.5 - 1.0, y = normal[4 * i + 1] / 127.5 - 1.0,
           z = normal[4 * i + 2] / 127.5 - 1.0;
    double length = sqrt(x * x + y * y + z * z);
    worst_length = fmax(worst_length, fabs(length - 1.0));
    ENSURE_MSG(z > 0.2, "%s interior normal %zu: z %.3f, not out of the surface", spec->name, i, z);
    tilt += (1.0 - z / length) / (double)count;
    mean_x += x / (double)count, mean_y += y / (double)count;
    ao += normal[4 * i + 3] / (double)count;
    open += normal[4 * i + 3] >= 240;
    dark += normal[4 * i + 3] < 200;
  }
  // Unit length within 8-bit rounding and the generator's +-1 dither.
  ENSURE_MSG(worst_length < 0.025, "%s interior normal: |n| off by %.4f", spec->name, worst_length);
  ENSURE_MSG(tilt >= spec->min_tilt, "%s interior normal: mean tilt %.4f, too flat", spec->name, tilt);
  // A tiling height field's slopes average to zero: no overall lean.
  ENSURE_MSG(fabs(mean_x) < 0.02 && fabs(mean_y) < 0.02, "%s interior normal leans (%.3f, %.3f)", spec->name,
             mean_x, mean_y);
  // Occlusion: mostly open, darker in pits (but for glass, which has none).
  ENSURE_MSG(open > count / 2, "%s interior occlusion: only %zu of %zu texels open", spec->name, open, count);
  ENSURE_MSG(ao <= spec->max_mean_ao, "%s interior occlusion: mean %.1f over %g", spec->name, ao,
             spec->max_mean_ao);
  if (spec->max_mean_ao < 255) ENSURE_MSG(dark > 0, "%s interior occlusion: no texel below 200", spec->name);
  printf("%-9s interior: mean sRGB %3.0f %3.0f %3.0f, luminance sd %4.1f, tilt %.4f, |n| within %.4f, mean "
         "occlusion %5.1f\n",
         spec->name, mean[0], mean[1], mean[2], sd, tilt, worst_length, ao);
}

// The shipped textures, or BK_TEXTURE_DIR's: a generator's output can be
// checked before it replaces them (make_textures /tmp/t, then
// BK_TEXTURE_DIR=/tmp/t test_texture).
static void test_interiors(void) {
  const char* dir = getenv("BK_TEXTURE_DIR") ? getenv("BK_TEXTURE_DIR") : BK_ASSET_DIR "/textures";
  for (size_t m = 0; m < sizeof interiors / sizeof interiors[0]; ++m) {
    const interior_spec* spec = &interiors[m];
    char path[1024];
    snprintf(path, sizeof path, "%s/%s_interior.png", dir, spec->name);
    int w = 0, h = 0, channels = 0;
    unsigned char* color = stbi_load(path, &w, &h, &channels, 3);
    ENSURE_MSG(color, "%s: %s", path, stbi_failure_reason());
    ENSURE_MSG(w == h && (w == 256 || w == 512) && channels == 3, "%s: %dx%d, %d channels", path, w, h,
               channels);
    const int n = w;
    ensure_tiles(path, color, n, 3);

    snprintf(path, sizeof path, "%s/%s_interior_normal.png", dir, spec->name);
    unsigned char* normal = stbi_load(path, &w, &h, &channels, 4);
    ENSURE_MSG(normal, "%s: %s", path, stbi_failure_reason());
    ENSURE_MSG(w == n && h == n && channels == 4, "%s: %dx%d, %d channels", path, w, h, channels);
    ensure_tiles(path, normal, n, 4);
    ensure_interior(spec, color, normal, n);
    stbi_image_free(color);
    stbi_image_free(normal);
  }
}

int main(void) {
  test_black_and_white();
  test_every_byte_survives();
  test_mixed_channels();
  test_sizes();
  test_in_place();
  test_rgba_levels();
  test_interiors();
  printf("test_texture: ok\n");
  return 0;
}
