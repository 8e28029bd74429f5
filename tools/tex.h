/*
 * What the texture generator's files share: the tile size, colour and
 * scalar helpers, tileable noise (tex_noise.c), the canvas a material paints
 * into and the PNG writers (tex_output.c).
 *
 * Every texture is N x N texels and tiles seamlessly; (u, v) are tile units
 * with v = 0 at image row 0. Noise comes from stb_perlin with power-of-two
 * wrap periods so every octave tiles; fbm, turbulence and ridge sums are
 * built on top of it because stb's own fractal helpers do not wrap.
 */
#ifndef TEX_H
#define TEX_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#define N 256
#define PI_F 3.14159265358979f

/* ------------------------------------------------------------------------ */
/* Small math helpers                                                        */

typedef struct {
  float r, g, b;
} Rgb;

static inline Rgb rgb(float r, float g, float b) /* 0..255 inputs */
{
  Rgb c = {r / 255.0f, g / 255.0f, b / 255.0f};
  return c;
}

static inline Rgb mix3(Rgb a, Rgb b, float t) {
  Rgb c = {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
  return c;
}

static inline Rgb scale3(Rgb a, float s) {
  Rgb c = {a.r * s, a.g * s, a.b * s};
  return c;
}

static inline Rgb add3(Rgb a, float s) {
  Rgb c = {a.r + s, a.g + s, a.b + s};
  return c;
}

static inline float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
static inline float mixf(float a, float b, float t) { return a + (b - a) * t; }

static inline float smooth(float e0, float e1, float x) {
  float t = clampf((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

static inline float wrap01(float x) { return x - floorf(x); }

/* Signed shortest difference a - b on the unit circle, in [-0.5, 0.5). */
static inline float wrapdiff(float a, float b) {
  float d = a - b;
  return d - floorf(d + 0.5f);
}

/* ------------------------------------------------------------------------ */
/* Hashing (deterministic per-cell randomness)                               */

static inline uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}

static inline float hashf(uint32_t a, uint32_t b, uint32_t c) {
  return (float)(hash3(a, b, c) >> 8) * (1.0f / 16777216.0f);
}

/* ------------------------------------------------------------------------ */
/* Tileable noise (tex_noise.c)                                              */

/* One octave; px/py lattice cells per tile (powers of two up to 256), so the
 * result repeats exactly at u, v = 0 and 1. */
float pn(float u, float v, int px, int py, int seed);

enum { FBM, TURB, RIDGE };

/* Fractal sum with lacunarity exactly 2 so every octave still tiles; the
 * result is normalised to roughly [-1, 1] (fbm) or [0, 1] (turb, ridge). */
float fractal(int kind, float u, float v, int px, int py, int octaves, float gain, int seed);
float fbm(float u, float v, int period, int octaves, int seed);

/* Tileable cellular (Worley) noise with n x n cells per tile (any n >= 1). */
typedef struct {
  float f1, f2; /* nearest / second nearest distance, in cell units */
  uint32_t id;  /* hash of the nearest cell */
  float dx, dy; /* offset from the nearest feature point, cell units */
} Cellular;

Cellular cellular(float u, float v, int n, uint32_t seed);

/* Sparse round specks: 0 outside, up to 1 at a speck's centre. About
 * `density` of the cells carry a speck of radius up to `radius` (cell units). */
float specks(float u, float v, int n, float density, float radius, uint32_t seed, uint32_t* id);

/* Fine mineral grain shared by several stony materials: high-frequency noise
 * at one to two texels. */
float grain(float u, float v, int seed);

/* ------------------------------------------------------------------------ */
/* Canvas and output (tex_output.c)                                          */

typedef struct {
  Rgb c[N * N];   /* colour, sRGB 0..1 */
  float h[N * N]; /* height; the material's normal strength gives its scale */
  /* Interiors only: occlusion the height field does not show (a pore's
   * depth below what a bump map can slope to), 0 = none, 1 = black. */
  float occ[N * N];
} Canvas;

#define FOR_PIXELS                                                                                           \
  for (int py_ = 0; py_ < N; py_++)                                                                          \
    for (int px_ = 0; px_ < N; px_++)

#define PIXEL_SETUP                                                                                          \
  const int idx = py_ * N + px_;                                                                             \
  const float u = ((float)px_ + 0.5f) / N;                                                                   \
  const float v = ((float)py_ + 0.5f) / N

/* Where the PNGs go; set once by main. Writers report failures on stderr
 * and set tex_failed. */
extern const char* tex_outdir;
extern int tex_failed;

/* MAT_KIND.png: RGB from cv->c. */
void write_color(const char* mat, const char* kind, const Canvas* cv);

/* MAT_normal.png: RGB tangent-space normals of cv->h, `strength` texels of
 * height per unit of h. */
void write_normal(const char* mat, const Canvas* cv, float strength);

/* MAT_interior_normal.png: RGB normals as write_normal, A ambient occlusion
 * (255 open) from the height field's cavities and cv->occ. Darkens cv->c by
 * `cavity` of that occlusion first (see tex_output.c for why), so call it
 * before write_color. */
void write_interior_normal(const char* mat, Canvas* cv, float strength, float ao_strength, float cavity);

/* ------------------------------------------------------------------------ */
/* Materials (tex_surface.c, tex_interior_*.c)                               */

void make_stone(Canvas* cv);
void make_brick(Canvas* cv);
void make_concrete(Canvas* cv);
void make_porcelain(Canvas* cv);
void make_glass(Canvas* cv);
void make_eggshell(Canvas* cv);
void make_wood(Canvas* cv);
void make_ground(Canvas* cv);

void make_stone_interior(Canvas* cv);
void make_brick_interior(Canvas* cv);
void make_concrete_interior(Canvas* cv);
void make_porcelain_interior(Canvas* cv);
void make_glass_interior(Canvas* cv);
void make_eggshell_interior(Canvas* cv);
void make_wood_interior(Canvas* cv);

#endif
