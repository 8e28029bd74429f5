// Mipmap levels of colour textures: averaged in linear light, rounded to the
// nearest sRGB byte (the shaders filter the bytes and decode after). The CPU
// side only: no GL context.
#include <math.h>
#include <stdbool.h>
#include <string.h>

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
  bk_texture_halve(rgb, 2, 2, true, out);
  ENSURE(out[0] == nearest_srgb_byte(0.5) && out[0] == 188);
  ENSURE(out[1] == out[0] && out[2] == out[0]);
  // Data that is not a colour (a normal map) averages its bytes.
  bk_texture_halve(rgb, 2, 2, false, out);
  ENSURE(out[0] == 128 && out[1] == 128 && out[2] == 128);
}

static void test_every_byte_survives(void) {
  // A flat texture keeps its colour at every level, whatever the byte.
  for (int b = 0; b < 256; ++b) {
    unsigned char rgb[12], out[3];
    fill(rgb, 4, (const int[]){b, b, b, b});
    for (int srgb = 0; srgb < 2; ++srgb) {
      bk_texture_halve(rgb, 2, 2, srgb, out);
      ENSURE_MSG(out[0] == b && out[1] == b && out[2] == b, "byte %d, srgb %d: got %d", b, srgb, out[0]);
    }
  }
}

static void test_mixed_channels(void) {
  // Each channel on its own: red from two dark and two light texels, green
  // and blue from other mixes, against the exact curve.
  const unsigned char rgb[12] = {10, 200, 0, 240, 200, 0, 10, 50, 255, 240, 50, 255};
  unsigned char out[3];
  bk_texture_halve(rgb, 2, 2, true, out);
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
  bk_texture_halve(rgb, 3, 3, true, out);
  ENSURE(out[0] == 0);
  // 1x4 to 1x2: a single column halves its rows only.
  unsigned char column[12], half[6];
  fill(column, 4, (const int[]){0, 0, 255, 255});
  bk_texture_halve(column, 1, 4, true, half);
  ENSURE(half[0] == 0 && half[3] == 255);
  // 1x1 stays itself.
  unsigned char one[3] = {7, 77, 177}, same[3];
  bk_texture_halve(one, 1, 1, true, same);
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
    bk_texture_halve(copy, W, H, srgb, out);
    bk_texture_halve(image, W, H, srgb, image);
    ENSURE_MSG(memcmp(image, out, sizeof out) == 0, "srgb %d: in-place result differs", srgb);
  }
}

int main(void) {
  test_black_and_white();
  test_every_byte_survives();
  test_mixed_channels();
  test_sizes();
  test_in_place();
  printf("test_texture: ok\n");
  return 0;
}
