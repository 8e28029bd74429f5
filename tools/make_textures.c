/*
 * make_textures: writes the game's material textures as PNG files.
 *
 *   make_textures OUTPUT_DIR
 *
 * Every texture is 256x256, tiles seamlessly in both directions and is fully
 * deterministic (fixed seeds, no rand()). For each material M in
 * stone, brick, concrete, porcelain, glass, eggshell and wood it writes
 *
 *   M_albedo.png    RGB surface colour (sRGB),
 *   M_normal.png    RGB tangent-space normal map of the same height field,
 *   M_interior.png  RGB colour of freshly broken / cut surfaces,
 *
 * plus ground_albedo.png and ground_normal.png (stone paving slabs).
 *
 * Normal maps use the OpenGL convention: X right (+u), Y up towards image
 * row 0, Z out of the surface; stored as n * 0.5 + 0.5.
 *
 * Noise comes from stb_perlin (stb_perlin_noise3_seed with power-of-two wrap
 * periods, so every octave tiles); fbm, turbulence and ridge sums are built
 * here on top of it because stb's own fractal helpers do not wrap.
 */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <stb_image_write.h>
#include <stb_perlin.h>

#define N 256
#define PI_F 3.14159265358979f

/* ------------------------------------------------------------------------ */
/* Small math helpers                                                        */

typedef struct {
  float r, g, b;
} Rgb;

static Rgb rgb(float r, float g, float b) /* 0..255 inputs */
{
  Rgb c = {r / 255.0f, g / 255.0f, b / 255.0f};
  return c;
}

static Rgb mix3(Rgb a, Rgb b, float t) {
  Rgb c = {a.r + (b.r - a.r) * t, a.g + (b.g - a.g) * t, a.b + (b.b - a.b) * t};
  return c;
}

static Rgb scale3(Rgb a, float s) {
  Rgb c = {a.r * s, a.g * s, a.b * s};
  return c;
}

static Rgb add3(Rgb a, float s) {
  Rgb c = {a.r + s, a.g + s, a.b + s};
  return c;
}

static float clampf(float x, float lo, float hi) { return x < lo ? lo : (x > hi ? hi : x); }
static float mixf(float a, float b, float t) { return a + (b - a) * t; }

static float smooth(float e0, float e1, float x) {
  float t = clampf((x - e0) / (e1 - e0), 0.0f, 1.0f);
  return t * t * (3.0f - 2.0f * t);
}

static float wrap01(float x) { return x - floorf(x); }

/* Signed shortest difference a - b on the unit circle, in [-0.5, 0.5). */
static float wrapdiff(float a, float b) {
  float d = a - b;
  return d - floorf(d + 0.5f);
}

/* ------------------------------------------------------------------------ */
/* Hashing (deterministic per-cell randomness)                               */

static uint32_t hash3(uint32_t a, uint32_t b, uint32_t c) {
  uint32_t h = a * 0x9E3779B1u ^ (b + 0x7F4A7C15u) * 0x85EBCA77u ^ (c + 0x165667B1u) * 0xC2B2AE3Du;
  h ^= h >> 15;
  h *= 0x2C1B3C6Du;
  h ^= h >> 12;
  h *= 0x297A2D39u;
  h ^= h >> 15;
  return h;
}

static float hashf(uint32_t a, uint32_t b, uint32_t c) {
  return (float)(hash3(a, b, c) >> 8) * (1.0f / 16777216.0f);
}

/* ------------------------------------------------------------------------ */
/* Tileable noise on top of stb_perlin                                       */

/* One octave; (u, v) in tile units, px/py lattice cells per tile (powers of
 * two up to 256), so the result repeats exactly at u, v = 0 and 1. */
static float pn(float u, float v, int px, int py, int seed) {
  float z = 0.5f + 37.0f * wrap01((float)seed * 0.6180339887f);
  return stb_perlin_noise3_seed(u * (float)px, v * (float)py, z, px, py, 0, (seed * 73 + 11) & 255);
}

enum { FBM, TURB, RIDGE };

/* Fractal sum with lacunarity exactly 2 so every octave still tiles; the
 * result is normalised to roughly [-1, 1] (fbm) or [0, 1] (turb, ridge). */
static float fractal(int kind, float u, float v, int px, int py, int octaves, float gain, int seed) {
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

static float fbm(float u, float v, int period, int octaves, int seed) {
  return fractal(FBM, u, v, period, period, octaves, 0.5f, seed);
}

/* Tileable cellular (Worley) noise with n x n cells per tile. */
typedef struct {
  float f1, f2; /* nearest / second nearest distance, in cell units */
  uint32_t id;  /* hash of the nearest cell */
  float dx, dy; /* offset from the nearest feature point, cell units */
} Cellular;

static Cellular cellular(float u, float v, int n, uint32_t seed) {
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

/* Sparse round specks: 0 outside, up to 1 at a speck's centre. About
 * `density` of the cells carry a speck of radius up to `radius` (cell units). */
static float specks(float u, float v, int n, float density, float radius, uint32_t seed, uint32_t* id) {
  Cellular c = cellular(u, v, n, seed);
  if (id) *id = c.id;
  if ((float)(c.id & 0xFFFF) / 65536.0f > density) return 0.0f;
  float r = radius * (0.45f + 0.55f * (float)((c.id >> 16) & 0xFF) / 255.0f);
  return 1.0f - smooth(r * 0.5f, r, c.f1);
}

/* ------------------------------------------------------------------------ */
/* Block layouts (stone courses, bricks, planks, paving)                     */

#define MAX_ROWS 16
#define MAX_CUTS 8

typedef struct {
  int rows;
  float y[MAX_ROWS + 1];       /* row boundaries, y[0] = 0, y[rows] = 1 */
  int cuts[MAX_ROWS];          /* vertical joints per row (>= 1) */
  float x[MAX_ROWS][MAX_CUTS]; /* joint positions in [0, 1), ascending */
} Layout;

typedef struct {
  int row, col;
  uint32_t id;                    /* per-block hash */
  float dist;                     /* distance to the nearest joint, texels (rounded corners) */
  float lu, lv;                   /* position inside the block, 0..1 */
  float left, width, top, height; /* block extent, tile units (left may wrap) */
} Block;

static int cmpf(const void* a, const void* b) {
  float x = *(const float*)a, y = *(const float*)b;
  return (x > y) - (x < y);
}

static void layout_sort(Layout* l) {
  for (int r = 0; r < l->rows; r++) {
    for (int i = 0; i < l->cuts[r]; i++)
      l->x[r][i] = wrap01(l->x[r][i]);
    qsort(l->x[r], (size_t)l->cuts[r], sizeof(float), cmpf);
  }
}

static Block layout_query(const Layout* l, float u, float v, float corner) {
  Block b;
  u = wrap01(u);
  v = wrap01(v);
  int r = 0;
  while (r < l->rows - 1 && v >= l->y[r + 1])
    r++;
  int n = l->cuts[r];
  int c = n - 1;
  for (int i = 0; i < n; i++)
    if (u >= l->x[r][i]) c = i;
  float left = l->x[r][c];
  float width = n == 1 ? 1.0f : wrap01(l->x[r][(c + 1) % n] - left);
  if (width <= 0.0f) width = 1.0f;
  float du = wrap01(u - left);
  float top = l->y[r], height = l->y[r + 1] - l->y[r];
  float dv = v - top;
  float ex = fminf(du, width - du) * N, ey = fminf(dv, height - dv) * N;
  float d = fminf(ex, ey);
  if (ex < corner && ey < corner) {
    float qx = corner - ex, qy = corner - ey;
    d = corner - sqrtf(qx * qx + qy * qy);
  }
  b.row = r;
  b.col = c;
  b.id = hash3((uint32_t)r, (uint32_t)c, 0xB10Cu);
  b.dist = d;
  b.lu = du / width;
  b.lv = dv / height;
  b.left = left;
  b.width = width;
  b.top = top;
  b.height = height;
  return b;
}

/* ------------------------------------------------------------------------ */
/* Image buffers and output                                                  */

typedef struct {
  Rgb c[N * N];
  float h[N * N];
} Canvas;

static const char* g_outdir;
static int g_failed;

static unsigned char to8(float x) { return (unsigned char)lrintf(clampf(x, 0.0f, 1.0f) * 255.0f); }

static void write_png(const char* name, const unsigned char* px) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s.png", g_outdir, name);
  if (!stbi_write_png(path, N, N, 3, px, N * 3)) {
    fprintf(stderr, "make_textures: cannot write %s\n", path);
    g_failed = 1;
    return;
  }
  printf("wrote %s\n", path);
}

static void write_color(const char* mat, const char* kind, const Canvas* cv) {
  static unsigned char px[N * N * 3];
  for (int i = 0; i < N * N; i++) {
    px[3 * i + 0] = to8(cv->c[i].r);
    px[3 * i + 1] = to8(cv->c[i].g);
    px[3 * i + 2] = to8(cv->c[i].b);
  }
  char name[256];
  snprintf(name, sizeof name, "%s_%s", mat, kind);
  write_png(name, px);
}

/* Tangent-space normals from the height field by central differences
 * (wrapping at the borders). `strength` is the height, in texels, that a
 * height difference of 1.0 represents. The encoded values get a small
 * deterministic triangular dither so that nearly flat materials (glass,
 * porcelain) do not show 8-bit contour bands in their highlights. */
static void write_normal(const char* mat, const Canvas* cv, float strength) {
  static unsigned char px[N * N * 3];
  for (int y = 0; y < N; y++)
    for (int x = 0; x < N; x++) {
      int xl = (x + N - 1) % N, xr = (x + 1) % N;
      int yu = (y + N - 1) % N, yd = (y + 1) % N;
      float dhdx = 0.5f * (cv->h[y * N + xr] - cv->h[y * N + xl]) * strength;
      float dhdy = 0.5f * (cv->h[yu * N + x] - cv->h[yd * N + x]) * strength; /* +Y = up */
      float nx = -dhdx, ny = -dhdy, nz = 1.0f;
      float len = sqrtf(nx * nx + ny * ny + nz * nz);
      int i = y * N + x;
      float e[3] = {nx / len, ny / len, nz / len};
      for (int k = 0; k < 3; k++) {
        float dither = (hashf((uint32_t)x, (uint32_t)y, 0xD1u + (uint32_t)k) +
                        hashf((uint32_t)x, (uint32_t)y, 0xD4u + (uint32_t)k) - 1.0f) /
                       255.0f;
        px[3 * i + k] = to8(e[k] * 0.5f + 0.5f + dither);
      }
    }
  char name[256];
  snprintf(name, sizeof name, "%s_normal", mat);
  write_png(name, px);
}

#define FOR_PIXELS                                                                                           \
  for (int py_ = 0; py_ < N; py_++)                                                                          \
    for (int px_ = 0; px_ < N; px_++)

#define PIXEL_SETUP                                                                                          \
  const int idx = py_ * N + px_;                                                                             \
  const float u = ((float)px_ + 0.5f) / N;                                                                   \
  const float v = ((float)py_ + 0.5f) / N

/* Fine mineral grain shared by several stony materials: a few light and
 * dark single-texel-ish grains on top of high-frequency noise. */
static float grain(float u, float v, int seed) {
  return 0.6f * pn(u, v, 128, 128, seed) + 0.4f * pn(u, v, 256, 256, seed + 7);
}

/* ------------------------------------------------------------------------ */
/* Stone: grey-beige ashlar blocks with mortar joints                        */

static void make_stone(Canvas* cv) {
  static const float row_h[5] = {0.0f, 0.265625f, 0.5f, 0.75f, 1.0f};
  Layout l = {.rows = 4};
  for (int r = 0; r <= 4; r++)
    l.y[r] = row_h[r];
  for (int r = 0; r < 4; r++) {
    int k = 2 + (int)(hash3((uint32_t)r, 5u, 17u) % 2u);
    float start = hashf((uint32_t)r, 9u, 17u);
    l.cuts[r] = k;
    for (int i = 0; i < k; i++)
      l.x[r][i] = start + ((float)i + 0.35f * (hashf((uint32_t)r, (uint32_t)i, 23u) - 0.5f)) / (float)k;
  }
  layout_sort(&l);

  static const float palette[4][3] = {{166, 158, 142}, {150, 147, 140}, {172, 160, 136}, {140, 136, 128}};
  Rgb mortar = rgb(118, 112, 102);

  FOR_PIXELS {
    PIXEL_SETUP;
    float wu = u + 0.012f * fbm(u, v, 4, 3, 1);
    float wv = v + 0.012f * fbm(u, v, 4, 3, 2);
    Block b = layout_query(&l, wu, wv, 7.0f);
    float chip = 2.2f * fbm(u, v, 16, 3, 3) + 1.6f * fractal(TURB, u, v, 32, 32, 2, 0.5f, 4);
    float d = b.dist - chip;
    float jw = 2.6f;
    float t = smooth(jw, jw + 10.0f, d);
    float inside = smooth(jw - 0.6f, jw + 0.6f, d);

    /* block surface: rounded cushion + broad undulation + rough grain */
    int bs = (int)(b.id & 63u);
    float cushion = sqrtf(t);
    float undul = fbm(u, v, 4, 3, 20 + bs);
    float rough = fbm(u, v, 16, 5, 5);
    float pits = fractal(RIDGE, u, v, 16, 16, 3, 0.5f, 6);
    float tilt = (hashf(b.id, 1u, 2u) - 0.5f) * (b.lu - 0.5f) + (hashf(b.id, 3u, 4u) - 0.5f) * (b.lv - 0.5f);
    float hblock =
        0.45f + 0.45f * cushion + 0.10f * undul + 0.10f * rough - 0.06f * pits * pits + 0.25f * tilt;
    float hmortar = 0.12f + 0.04f * grain(u, v, 7);
    cv->h[idx] = mixf(hmortar, hblock, inside);

    /* colour */
    const float* p = palette[b.id % 4u];
    Rgb base = rgb(p[0], p[1], p[2]);
    base = scale3(base, 0.90f + 0.16f * hashf(b.id, 7u, 8u));
    float mott = fbm(u, v, 8, 4, 30 + bs);
    Rgb col = scale3(base, 1.0f + 0.09f * mott + 0.05f * rough);
    col = mix3(col, rgb(120, 110, 96), 0.35f * smooth(0.2f, 0.8f, fbm(u, v, 4, 3, 40)) * 0.6f);
    col = add3(col, 0.035f * grain(u, v, 8));
    col = scale3(col, 0.86f + 0.14f * t - 0.08f * pits * pits);
    Rgb mc = scale3(mortar, 1.0f + 0.10f * grain(u, v, 9) + 0.06f * fbm(u, v, 16, 3, 10));
    mc = scale3(mc, 0.72f + 0.28f * smooth(0.0f, jw, d + jw * 0.5f));
    cv->c[idx] = mix3(mc, col, inside);
  }
}

static void make_stone_interior(Canvas* cv) {
  Rgb base = rgb(188, 181, 166);
  FOR_PIXELS {
    PIXEL_SETUP;
    float broad = fbm(u, v, 4, 4, 50);
    Rgb col = scale3(base, 1.0f + 0.06f * broad);
    col = add3(col, 0.07f * grain(u, v, 51));
    uint32_t id;
    float s = specks(u, v, 64, 0.55f, 0.42f, 52, &id);
    float light = (id >> 24) & 1u ? 1.0f : 0.0f;
    col = mix3(col, light > 0.5f ? rgb(226, 222, 212) : rgb(108, 102, 94), 0.65f * s);
    float s2 = specks(u, v, 32, 0.25f, 0.35f, 53, NULL);
    col = mix3(col, rgb(150, 138, 118), 0.45f * s2);
    cv->c[idx] = col;
  }
}

/* Equal rows of equal blocks; odd rows shifted by `stagger` of a block (running bond). */
static Layout grid_layout(int rows, int columns, float stagger) {
  Layout l = {.rows = rows};
  for (int r = 0; r <= rows; r++)
    l.y[r] = (float)r / (float)rows;
  for (int r = 0; r < rows; r++) {
    l.cuts[r] = columns;
    for (int i = 0; i < columns; i++)
      l.x[r][i] = ((float)i + stagger * (float)(r & 1)) / (float)columns;
  }
  return l;
}

/* ------------------------------------------------------------------------ */
/* Brick: running bond, 4 bricks across, 8 courses                           */

static void make_brick(Canvas* cv) {
  Layout l = grid_layout(8, 4, 0.5f);
  // Hand-laid: joints wander by up to a texel and a half.
  for (int r = 0; r < 8; r++)
    for (int i = 0; i < 4; i++)
      l.x[r][i] += (hashf((uint32_t)r, (uint32_t)i, 61u) - 0.5f) * (3.0f / N);
  layout_sort(&l);

  static const float palette[6][3] = {{146, 64, 45}, {158, 76, 52}, {128, 56, 41},
                                      {170, 90, 62}, {112, 50, 40}, {150, 70, 56}};
  Rgb mortar = rgb(176, 168, 154);

  FOR_PIXELS {
    PIXEL_SETUP;
    float wu = u + 0.0035f * fbm(u, v, 8, 2, 60);
    float wv = v + 0.0035f * fbm(u, v, 8, 2, 61);
    Block b = layout_query(&l, wu, wv, 3.0f);
    float chip =
        1.2f * fbm(u, v, 32, 3, 62) + 1.4f * smooth(0.55f, 0.9f, fractal(TURB, u, v, 16, 16, 3, 0.5f, 63));
    float d = b.dist - chip;
    float jw = 2.4f;
    float inside = smooth(jw - 0.5f, jw + 0.5f, d);
    float t = smooth(jw, jw + 4.0f, d);

    int bs = (int)(b.id & 63u);
    float rough = fbm(u, v, 32, 4, 64);
    float pit = specks(u, v, 48, 0.35f, 0.35f, 65, NULL);
    float hbrick = 0.55f + 0.35f * t + 0.07f * rough + 0.05f * fbm(u, v, 8, 2, 70 + bs) - 0.18f * pit;
    float hmortar = 0.05f + 0.05f * grain(u, v, 66);
    cv->h[idx] = mixf(hmortar, hbrick, inside);

    const float* p = palette[b.id % 6u];
    Rgb base = scale3(rgb(p[0], p[1], p[2]), 0.92f + 0.14f * hashf(b.id, 1u, 9u));
    /* darker fired end on some bricks */
    float burn = hashf(b.id, 2u, 9u) < 0.3f
                     ? smooth(0.4f, 1.0f, hashf(b.id, 3u, 9u) < 0.5f ? b.lu : 1.0f - b.lu)
                     : 0.0f;
    base = mix3(base, rgb(88, 42, 34), 0.45f * burn);
    float mott = fbm(u, v, 8, 4, 80 + bs);
    Rgb col = scale3(base, 1.0f + 0.10f * mott + 0.05f * rough);
    uint32_t sid;
    float sp = specks(u, v, 64, 0.30f, 0.30f, 67, &sid);
    col = mix3(col, (sid >> 24) & 1u ? rgb(196, 150, 112) : rgb(72, 36, 30), 0.55f * sp);
    col = add3(col, 0.025f * grain(u, v, 68));
    col = scale3(col, (0.88f + 0.12f * t) * (1.0f - 0.25f * pit));
    Rgb mc = scale3(mortar, 1.0f + 0.10f * grain(u, v, 69) + 0.05f * fbm(u, v, 16, 3, 71));
    mc = scale3(mc, 0.78f + 0.22f * smooth(-jw, jw * 0.8f, d));
    cv->c[idx] = mix3(mc, col, inside);
  }
}

static void make_brick_interior(Canvas* cv) {
  Rgb base = rgb(184, 96, 66);
  FOR_PIXELS {
    PIXEL_SETUP;
    Rgb col = scale3(base, 1.0f + 0.07f * fbm(u, v, 8, 4, 90));
    col = add3(col, 0.06f * grain(u, v, 91));
    uint32_t id;
    float s = specks(u, v, 64, 0.45f, 0.38f, 92, &id);
    col = mix3(col, (id >> 24) & 1u ? rgb(222, 176, 132) : rgb(120, 58, 42), 0.6f * s);
    float pore = specks(u, v, 32, 0.35f, 0.30f, 93, NULL);
    col = scale3(col, 1.0f - 0.30f * pore);
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Concrete: grey, fine pores, faint aggregate                               */

static void make_concrete(Canvas* cv) {
  Rgb base = rgb(152, 152, 148);
  FOR_PIXELS {
    PIXEL_SETUP;
    float blot = fbm(u, v, 4, 5, 100);
    float stain = smooth(0.1f, 0.7f, fbm(u, v, 2, 4, 101));
    float pore = specks(u, v, 48, 0.45f, 0.30f, 102, NULL);
    float bug = specks(u, v, 16, 0.20f, 0.22f, 103, NULL);
    float agg = specks(u, v, 24, 0.5f, 0.40f, 104, NULL);
    float fine = grain(u, v, 105);
    cv->h[idx] = 0.5f + 0.08f * blot + 0.05f * fine + 0.06f * agg - 0.45f * pore - 0.7f * bug;
    Rgb col = scale3(base, 1.0f + 0.07f * blot);
    col = mix3(col, rgb(128, 128, 124), 0.35f * stain);
    col = mix3(col, rgb(168, 164, 156), 0.25f * agg);
    col = add3(col, 0.03f * fine);
    col = scale3(col, 1.0f - 0.35f * pore - 0.45f * bug);
    cv->c[idx] = col;
  }
}

static void make_concrete_interior(Canvas* cv) {
  static const float stones[5][3] = {
      {128, 126, 122}, {142, 130, 114}, {176, 170, 156}, {98, 98, 100}, {156, 148, 136}};
  Rgb matrix = rgb(172, 170, 163);
  FOR_PIXELS {
    PIXEL_SETUP;
    Rgb col = scale3(matrix, 1.0f + 0.05f * fbm(u, v, 8, 3, 110));
    col = add3(col, 0.06f * grain(u, v, 111));
    /* sand */
    uint32_t sid;
    float s = specks(u, v, 96, 0.5f, 0.45f, 112, &sid);
    col = mix3(col, (sid >> 24) & 1u ? rgb(200, 196, 184) : rgb(118, 114, 108), 0.45f * s);
    /* coarse, then medium aggregate where no coarse stone lies: broken
     * pebbles with irregular outlines and a thin shadowed rim */
    float covered = 0.0f;
    for (int layer = 0; layer < 2; layer++) {
      int n = layer == 0 ? 6 : 14;
      float amp = layer == 0 ? 0.025f : 0.012f;
      float wu = u + amp * fbm(u, v, 16, 2, 113 + layer);
      float wv = v + amp * fbm(u, v, 16, 2, 115 + layer);
      Cellular c = cellular(wu, wv, n, 120u + (uint32_t)layer);
      if ((float)(c.id & 255u) / 256.0f > (layer == 0 ? 0.7f : 0.6f)) continue;
      float r = (layer == 0 ? 0.26f : 0.22f) + 0.12f * (float)((c.id >> 8) & 255u) / 255.0f;
      float in = 1.0f - smooth(r - 0.03f, r + 0.02f, c.f1);
      in *= 1.0f - covered;
      if (in <= 0.0f) continue;
      const float* p = stones[(c.id >> 16) % 5u];
      Rgb st = scale3(rgb(p[0], p[1], p[2]), 0.92f + 0.16f * (float)((c.id >> 24) & 255u) / 255.0f);
      st = scale3(st, 1.0f + 0.08f * fbm(u, v, 32, 3, 130 + layer));
      st = add3(st, 0.035f * grain(u, v, 132));
      st = scale3(st, 0.78f + 0.22f * smooth(r, r - 0.06f, c.f1));
      col = mix3(col, st, in);
      covered = fmaxf(covered, in);
    }
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Porcelain: glossy white, very faint blue-grey variation                   */

static void make_porcelain(Canvas* cv) {
  Rgb white = rgb(243, 244, 246), tint = rgb(231, 235, 241);
  FOR_PIXELS {
    PIXEL_SETUP;
    float n = fbm(u, v, 2, 4, 140);
    float n2 = fbm(u, v, 8, 3, 141);
    cv->h[idx] = 0.5f * n + 0.04f * n2;
    cv->c[idx] = mix3(white, tint, smooth(-0.4f, 0.9f, n + 0.3f * n2));
  }
}

static void make_porcelain_interior(Canvas* cv) {
  Rgb base = rgb(234, 231, 224);
  FOR_PIXELS {
    PIXEL_SETUP;
    Rgb col = scale3(base, 1.0f + 0.025f * fbm(u, v, 8, 3, 150));
    col = add3(col, 0.035f * grain(u, v, 151));
    float pore = specks(u, v, 64, 0.25f, 0.3f, 152, NULL);
    col = scale3(col, 1.0f - 0.10f * pore);
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Glass: pale cyan, almost flat                                             */

static void make_glass(Canvas* cv) {
  Rgb a = rgb(198, 228, 230), b = rgb(186, 220, 226);
  FOR_PIXELS {
    PIXEL_SETUP;
    /* faint drawn-glass ripples along one direction */
    float rip = fractal(FBM, u, v, 2, 8, 2, 0.4f, 160);
    float n = fbm(u, v, 2, 3, 161);
    cv->h[idx] = 0.5f * rip + 0.3f * n;
    cv->c[idx] = mix3(a, b, smooth(-0.6f, 0.8f, n));
  }
}

static void make_glass_interior(Canvas* cv) {
  Rgb base = rgb(188, 208, 210);
  FOR_PIXELS {
    PIXEL_SETUP;
    /* conchoidal ripple marks */
    float wu = u + 0.05f * fbm(u, v, 2, 3, 170);
    float wv = v + 0.05f * fbm(u, v, 2, 3, 171);
    float ridge = fractal(RIDGE, wu, wv, 4, 4, 3, 0.5f, 172);
    float hackle = fractal(RIDGE, u, v, 16, 16, 2, 0.5f, 173);
    Rgb col = scale3(base, 1.0f + 0.06f * fbm(u, v, 4, 3, 174));
    col = mix3(col, rgb(226, 238, 238), 0.35f * smooth(0.55f, 0.95f, ridge));
    col = mix3(col, rgb(166, 186, 190), 0.12f * smooth(0.6f, 0.95f, hackle));
    col = add3(col, 0.02f * grain(u, v, 175));
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Eggshell: warm off-white with fine speckle                                */

static void make_eggshell(Canvas* cv) {
  Rgb base = rgb(238, 226, 204);
  FOR_PIXELS {
    PIXEL_SETUP;
    float mott = fbm(u, v, 4, 4, 180);
    float pore = specks(u, v, 96, 0.6f, 0.28f, 181, NULL);
    float bump = fbm(u, v, 32, 3, 182);
    cv->h[idx] = 0.25f * bump + 0.1f * mott - 0.35f * pore;
    Rgb col = scale3(base, 1.0f + 0.035f * mott);
    col = mix3(col, rgb(226, 206, 178), 0.3f * smooth(0.2f, 0.9f, fbm(u, v, 8, 3, 183)));
    uint32_t id;
    float s = specks(u, v, 48, 0.35f, 0.32f, 184, &id);
    float s2 = specks(u, v, 12, 0.3f, 0.18f, 185, NULL);
    col = mix3(col, (id >> 24) & 1u ? rgb(196, 170, 140) : rgb(214, 196, 170), 0.55f * s);
    col = mix3(col, rgb(170, 140, 110), 0.45f * s2);
    col = add3(col, 0.012f * grain(u, v, 186));
    col = scale3(col, 1.0f - 0.06f * pore);
    cv->c[idx] = col;
  }
}

static void make_eggshell_interior(Canvas* cv) {
  Rgb base = rgb(247, 241, 224);
  FOR_PIXELS {
    PIXEL_SETUP;
    /* faint fibrous membrane */
    float fib = fractal(RIDGE, u + 0.05f * fbm(u, v, 4, 2, 190), v, 16, 4, 3, 0.5f, 191);
    Rgb col = scale3(base, 1.0f + 0.02f * fbm(u, v, 4, 3, 192));
    col = mix3(col, rgb(236, 226, 204), 0.3f * smooth(0.5f, 1.0f, fib));
    col = add3(col, 0.015f * grain(u, v, 193));
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Wood: horizontal planks with grain                                        */

static Layout wood_layout(void) {
  Layout l = {.rows = 4};
  for (int r = 0; r <= 4; r++)
    l.y[r] = (float)r / 4.0f;
  for (int r = 0; r < 4; r++) {
    int k = r == 2 ? 2 : 1;
    float start = hashf((uint32_t)r, 2u, 200u);
    l.cuts[r] = k;
    for (int i = 0; i < k; i++)
      l.x[r][i] = start + ((float)i + 0.2f * (hashf((uint32_t)r, (uint32_t)i, 201u) - 0.5f)) / (float)k;
  }
  layout_sort(&l);
  return l;
}

static void make_wood(Canvas* cv) {
  Layout l = wood_layout();
  Rgb early = rgb(178, 126, 78), late = rgb(118, 74, 42), gap = rgb(46, 30, 20);
  FOR_PIXELS {
    PIXEL_SETUP;
    Block b = layout_query(&l, u, v, 1.5f);
    int bs = (int)(b.id & 63u);
    float inside = smooth(0.6f, 1.6f, b.dist);
    float edge = smooth(0.8f, 3.0f, b.dist);

    /* knot: one per board segment on some boards */
    float ku = b.left + b.width * (0.25f + 0.5f * hashf(b.id, 4u, 210u));
    float kv = b.top + b.height * (0.3f + 0.4f * hashf(b.id, 5u, 210u));
    float kdx = wrapdiff(u, ku) * N, kdy = (v - kv) * N;
    int has_knot = hashf(b.id, 6u, 210u) < 0.45f;
    float kr2 = kdx * kdx * 0.35f + kdy * kdy;
    float knot = has_knot ? expf(-kr2 / (2.0f * 36.0f)) : 0.0f;

    /* growth rings, stretched along the board, bent around the knot */
    float pv = (v - b.top) * N;
    float wob =
        1.6f * fractal(FBM, u, v, 2, 2, 3, 0.5f, 211 + bs) + 0.25f * fractal(FBM, u, v, 8, 16, 2, 0.5f, 212);
    float freq = 0.07f + 0.04f * hashf(b.id, 7u, 210u);
    float g = pv * freq + wob + 10.0f * hashf(b.id, 8u, 210u) + 4.0f * knot * (kdy >= 0.0f ? 1.0f : -1.0f);
    float ring = wrap01(g);
    float late_w = smooth(0.62f, 0.9f, ring) * (1.0f - smooth(0.93f, 1.0f, ring));
    float fibre = fractal(FBM, u, v, 4, 128, 3, 0.6f, 213);

    Rgb tone = scale3(rgb(255, 255, 255), 0.86f + 0.22f * hashf(b.id, 9u, 210u));
    float band = smooth(0.15f, 0.85f, ring) * (1.0f - smooth(0.9f, 1.0f, ring));
    Rgb col = mix3(early, late, 0.30f * band + 0.55f * late_w);
    col.r *= tone.r;
    col.g *= tone.g * (0.97f + 0.05f * hashf(b.id, 10u, 210u));
    col.b *= tone.b * (0.94f + 0.08f * hashf(b.id, 11u, 210u));
    col = scale3(col, 1.0f + 0.09f * fibre + 0.05f * fbm(u, v, 4, 3, 214 + bs));
    col = mix3(col, late, 0.25f * smooth(0.35f, 0.8f, fractal(TURB, u, v, 4, 128, 2, 0.5f, 215)));
    float kc = smooth(0.35f, 0.8f, knot);
    col = mix3(col, rgb(92, 56, 32), 0.8f * kc);
    col = mix3(col, rgb(64, 38, 22), 0.8f * smooth(0.85f, 0.97f, knot));
    col = scale3(col, 0.80f + 0.20f * edge);
    cv->c[idx] = mix3(gap, col, inside);

    float h = 0.7f + 0.08f * late_w + 0.06f * fibre + 0.2f * edge - 0.05f * kc;
    cv->h[idx] = mixf(0.1f, h, inside);
  }
}

static void make_wood_interior(Canvas* cv) {
  Rgb base = rgb(212, 174, 122), dark = rgb(176, 134, 86);
  FOR_PIXELS {
    PIXEL_SETUP;
    float wv = v + 0.012f * fractal(FBM, u, v, 2, 2, 2, 0.5f, 220);
    float fib = fractal(FBM, u, wv, 4, 128, 4, 0.6f, 221);
    float splinter = fractal(RIDGE, u, wv, 8, 64, 3, 0.5f, 222);
    float ring = wrap01(wv * 6.0f + 0.5f * fbm(u, v, 2, 2, 223));
    Rgb col = mix3(base, dark, 0.25f * smooth(0.6f, 1.0f, ring) * (1.0f - smooth(0.95f, 1.0f, ring)));
    col = scale3(col, 1.0f + 0.10f * fib);
    col = mix3(col, rgb(232, 202, 156), 0.45f * smooth(0.7f, 1.0f, splinter));
    col =
        mix3(col, rgb(150, 110, 70), 0.35f * smooth(0.55f, 0.85f, fractal(TURB, u, wv, 2, 64, 2, 0.5f, 224)));
    col = add3(col, 0.02f * grain(u, v, 225));
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Ground: stone paving slabs (4 x 4) with dirt and moss in the joints       */

static void make_ground(Canvas* cv) {
  Layout l = grid_layout(4, 4, 0.0f);
  layout_sort(&l);
  static const float palette[5][3] = {
      {150, 144, 132}, {138, 132, 122}, {160, 150, 134}, {128, 124, 118}, {146, 136, 120}};
  Rgb dirt = rgb(74, 64, 50), moss = rgb(72, 88, 44);

  FOR_PIXELS {
    PIXEL_SETUP;
    float wu = u + 0.006f * fbm(u, v, 8, 2, 240);
    float wv = v + 0.006f * fbm(u, v, 8, 2, 241);
    Block b = layout_query(&l, wu, wv, 6.0f);
    float chip =
        1.0f * fbm(u, v, 32, 3, 242) + 1.6f * smooth(0.55f, 0.9f, fractal(TURB, u, v, 16, 16, 3, 0.5f, 243));
    float d = b.dist - chip;
    float jw = 2.6f;
    float inside = smooth(jw - 0.6f, jw + 0.6f, d);
    float t = smooth(jw, jw + 6.0f, d);

    int bs = (int)(b.id & 63u);
    float rough = fbm(u, v, 16, 5, 244);
    float wear = fbm(u, v, 4, 3, 245 + bs);
    float tilt =
        (hashf(b.id, 1u, 250u) - 0.5f) * (b.lu - 0.5f) + (hashf(b.id, 2u, 250u) - 0.5f) * (b.lv - 0.5f);
    float hs = 0.5f + 0.4f * t + 0.08f * rough + 0.06f * wear + 0.18f * tilt;
    float hj = 0.08f + 0.06f * fbm(u, v, 64, 2, 246);
    cv->h[idx] = mixf(hj, hs, inside);

    const float* p = palette[b.id % 5u];
    Rgb col =
        scale3(mix3(rgb(p[0], p[1], p[2]), rgb(144, 138, 126), 0.4f), 0.95f + 0.08f * hashf(b.id, 3u, 250u));
    col = scale3(col, 1.0f + 0.08f * wear + 0.05f * rough);
    col = mix3(col, rgb(108, 100, 88), 0.35f * smooth(0.25f, 0.8f, fbm(u, v, 4, 4, 247)));
    col = mix3(col, rgb(176, 170, 158), 0.25f * smooth(0.3f, 0.9f, fbm(u, v, 8, 3, 248)));
    col = add3(col, 0.04f * grain(u, v, 249));
    uint32_t sid;
    float sp = specks(u, v, 64, 0.3f, 0.3f, 251, &sid);
    col = mix3(col, (sid >> 24) & 1u ? rgb(190, 184, 172) : rgb(92, 88, 82), 0.5f * sp);
    col = scale3(col, 0.84f + 0.16f * t);

    float mossy = smooth(-0.1f, 0.5f, fbm(u, v, 8, 3, 252));
    Rgb jc = mix3(dirt, moss, 0.8f * mossy);
    jc = scale3(jc, 1.0f + 0.18f * grain(u, v, 253));
    /* moss creeping slightly over slab edges */
    float creep =
        mossy * (1.0f - smooth(jw, jw + 3.0f, d)) * smooth(0.2f, 0.6f, fbm(u, v, 32, 2, 254) + 0.3f);
    col = mix3(col, moss, 0.6f * creep);
    cv->c[idx] = mix3(jc, col, inside);
  }
}

/* ------------------------------------------------------------------------ */

typedef struct {
  const char* name;
  void (*surface)(Canvas*);
  void (*interior)(Canvas*);
  float normal_strength;
} Material;

static const Material materials[] = {
    {"stone", make_stone, make_stone_interior, 6.0f},
    {"brick", make_brick, make_brick_interior, 5.0f},
    {"concrete", make_concrete, make_concrete_interior, 2.5f},
    {"porcelain", make_porcelain, make_porcelain_interior, 1.0f},
    {"glass", make_glass, make_glass_interior, 0.35f},
    {"eggshell", make_eggshell, make_eggshell_interior, 0.8f},
    {"wood", make_wood, make_wood_interior, 3.0f},
    {"ground", make_ground, NULL, 6.0f},
};

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: %s OUTPUT_DIR\n", argv[0]);
    return 2;
  }
  g_outdir = argv[1];
  if (mkdir(g_outdir, 0777) != 0 && errno != EEXIST) {
    fprintf(stderr, "make_textures: cannot create %s: %s\n", g_outdir, strerror(errno));
    return 1;
  }
  stbi_write_png_compression_level = 9;

  Canvas* cv = malloc(sizeof *cv);
  if (!cv) {
    fprintf(stderr, "make_textures: out of memory\n");
    return 1;
  }
  for (size_t m = 0; m < sizeof materials / sizeof materials[0]; m++) {
    const Material* mat = &materials[m];
    memset(cv, 0, sizeof *cv);
    mat->surface(cv);
    write_color(mat->name, "albedo", cv);
    write_normal(mat->name, cv, mat->normal_strength);
    if (mat->interior) {
      memset(cv, 0, sizeof *cv);
      mat->interior(cv);
      write_color(mat->name, "interior", cv);
    }
  }
  free(cv);
  return g_failed ? 1 : 0;
}
