/* Tileable noise for the texture generator: gradient noise octaves, fractal
 * sums, cellular noise and specks (see tex.h). */
#include <stb_perlin.h>

#include "tex.h"

float pn(float u, float v, int px, int py, int seed) {
  float z = 0.5f + 37.0f * wrap01((float)seed * 0.6180339887f);
  return stb_perlin_noise3_seed(u * (float)px, v * (float)py, z, px, py, 0, (seed * 73 + 11) & 255);
}

float fractal(int kind, float u, float v, int px, int py, int octaves, float gain, int seed) {
  float sum = 0.0f, amp = 1.0f, norm = 0.0f;
  for (int i = 0; i < octaves; i++) {
    float n = pn(u, v, px, py, seed + 101 * i);
    if (kind == TURB)
      n = fabsf(n);
    else if (kind == RIDGE) {
      n = 1.0f - fabsf(n);
      n *= n;
    }
    sum += n * amp;
    norm += amp;
    amp *= gain;
    if (px < 256) px *= 2;
    if (py < 256) py *= 2;
  }
  sum /= norm;
  return kind == FBM ? sum * 1.6f : sum;
}

float fbm(float u, float v, int period, int octaves, int seed) {
  return fractal(FBM, u, v, period, period, octaves, 0.5f, seed);
}

Cellular cellular(float u, float v, int n, uint32_t seed) {
  float x = wrap01(u) * (float)n, y = wrap01(v) * (float)n;
  int ix = (int)floorf(x), iy = (int)floorf(y);
  Cellular c = {9.0f, 9.0f, 0, 0.0f, 0.0f};
  for (int j = -1; j <= 1; j++)
    for (int i = -1; i <= 1; i++) {
      int cx = ix + i, cy = iy + j;
      uint32_t wx = (uint32_t)((cx % n + n) % n), wy = (uint32_t)((cy % n + n) % n);
      float fx = (float)cx + 0.1f + 0.8f * hashf(wx, wy, seed);
      float fy = (float)cy + 0.1f + 0.8f * hashf(wx, wy, seed + 1u);
      float dx = x - fx, dy = y - fy;
      float d = sqrtf(dx * dx + dy * dy);
      if (d < c.f1) {
        c.f2 = c.f1;
        c.f1 = d;
        c.id = hash3(wx, wy, seed + 2u);
        c.dx = dx;
        c.dy = dy;
      } else if (d < c.f2) {
        c.f2 = d;
      }
    }
  return c;
}

float specks(float u, float v, int n, float density, float radius, uint32_t seed, uint32_t* id) {
  Cellular c = cellular(u, v, n, seed);
  if (id) *id = c.id;
  if ((float)(c.id & 0xFFFF) / 65536.0f > density) return 0.0f;
  float r = radius * (0.45f + 0.55f * (float)((c.id >> 16) & 0xFF) / 255.0f);
  return 1.0f - smooth(r * 0.5f, r, c.f1);
}

float grain(float u, float v, int seed) {
  return 0.6f * pn(u, v, 128, 128, seed) + 0.4f * pn(u, v, 256, 256, seed + 7);
}
