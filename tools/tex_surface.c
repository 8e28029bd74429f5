/* The materials' outer surfaces: colour and height for each material's
 * albedo and normal map, and the ground's paving (see tex.h). */
#include <stdlib.h>

#include "tex.h"

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
/* Stone: grey-beige ashlar blocks with mortar joints                        */

void make_stone(Canvas* cv) {
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

void make_brick(Canvas* cv) {
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

/* ------------------------------------------------------------------------ */
/* Concrete: grey, fine pores, faint aggregate                               */

void make_concrete(Canvas* cv) {
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

/* ------------------------------------------------------------------------ */
/* Porcelain: glossy white, very faint blue-grey variation                   */

void make_porcelain(Canvas* cv) {
  Rgb white = rgb(243, 244, 246), tint = rgb(231, 235, 241);
  FOR_PIXELS {
    PIXEL_SETUP;
    float n = fbm(u, v, 2, 4, 140);
    float n2 = fbm(u, v, 8, 3, 141);
    cv->h[idx] = 0.5f * n + 0.04f * n2;
    cv->c[idx] = mix3(white, tint, smooth(-0.4f, 0.9f, n + 0.3f * n2));
  }
}

/* ------------------------------------------------------------------------ */
/* Glass: pale cyan, almost flat                                             */

void make_glass(Canvas* cv) {
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

/* ------------------------------------------------------------------------ */
/* Eggshell: warm off-white with fine speckle                                */

void make_eggshell(Canvas* cv) {
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

void make_wood(Canvas* cv) {
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

/* ------------------------------------------------------------------------ */
/* Ground: stone paving slabs (4 x 4) with dirt and moss in the joints       */

void make_ground(Canvas* cv) {
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
