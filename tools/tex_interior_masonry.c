/* Interiors of the masonry materials (stone, concrete, brick): colour,
 * height and extra occlusion of a freshly broken face (see tex.h). A tile
 * spans 10 cm of a cut face at the demo's texture scale, so a texel is
 * about 0.4 mm: sand grains are a few texels, coarse aggregate tens. */
#include "tex.h"

/* Where a fracture ran: broad undulation with sharper steps where the crack
 * front jumped, about [-1, 1]. */
static float fracture_relief(float u, float v, int seed) {
  float broad = fbm(u, v, 2, 5, seed);
  float steps = fractal(TURB, u, v, 4, 4, 4, 0.5f, seed + 1);
  return 0.7f * broad + 0.6f * (steps - 0.25f);
}

/* A round pit (an air void, a plucked grain): depth profile of a sphere cap,
 * 0 outside, 1 at the centre, from a speck's 0..1 falloff. */
static float pit_depth(float speck) { return sqrtf(clampf(speck, 0.0f, 1.0f)); }

/* ------------------------------------------------------------------------ */
/* Stone: a grey-beige sandstone, grains of quartz, feldspar and rock
 * fragments in a fine cement, with a few larger clasts.                     */

void make_stone_interior(Canvas* cv) {
  static const float grains[6][3] = {{170, 164, 150}, {160, 146, 126}, {146, 140, 130},
                                     {112, 108, 102}, {166, 142, 112}, {184, 178, 166}};
  static const float clasts[4][3] = {{118, 112, 104}, {140, 126, 106}, {170, 162, 148}, {128, 114, 98}};
  Rgb cement = rgb(138, 128, 112);
  FOR_PIXELS {
    PIXEL_SETUP;
    float relief = fracture_relief(u, v, 300);

    /* sand grains, warped so that they are not round */
    float wu = u + 0.005f * fbm(u, v, 16, 2, 302), wv = v + 0.005f * fbm(u, v, 16, 2, 303);
    Cellular g = cellular(wu, wv, 64, 304u);
    float edge = g.f2 - g.f1; /* 0 on the boundary between two grains */
    float dome = smooth(0.0f, 0.5f, edge);
    float between = 1.0f - smooth(0.02f, 0.1f, edge);
    const float* p = grains[g.id % 6u];
    Rgb col = mix3(rgb(p[0], p[1], p[2]), cement, 0.35f);
    col = scale3(col, 0.93f + 0.14f * hashf(g.id, 2u, 305u));
    /* quartz grains glint a little lighter where the break crossed them */
    col = add3(col, 0.04f * (1.0f - g.f1) * (g.id % 6u == 0u || g.id % 6u == 5u ? 1.0f : 0.0f));
    col = mix3(col, cement, 0.4f * between);

    /* larger clasts: rock fragments and shell pieces a few mm across */
    float cu = u + 0.015f * fbm(u, v, 4, 3, 306), cvv = v + 0.015f * fbm(u, v, 4, 3, 307);
    Cellular c = cellular(cu, cvv, 7, 308u);
    float in_clast = 0.0f;
    if (hashf(c.id, 1u, 309u) < 0.2f) {
      float r = 0.16f + 0.12f * hashf(c.id, 2u, 309u);
      in_clast = (1.0f - smooth(r - 0.02f, r + 0.015f, c.f1)) * smooth(0.02f, 0.06f, c.f2 - c.f1);
      const float* q = clasts[c.id % 4u];
      Rgb cc = scale3(rgb(q[0], q[1], q[2]), 1.0f + 0.06f * fbm(u, v, 64, 2, 310));
      col = mix3(col, cc, 0.7f * in_clast);
    }

    /* iron staining in broad, faint bands along the bedding, and the
     * cement's fine grain */
    float stain =
        smooth(-0.2f, 0.7f,
               fbm(u, v, 2, 4, 311) + 0.5f * sinf(2.0f * PI_F * (3.0f * v + 0.2f * fbm(u, v, 2, 2, 316))));
    col = mix3(col, rgb(150, 120, 86), 0.22f * stain);
    col = scale3(col, 1.0f + 0.05f * fbm(u, v, 8, 3, 312));
    col = add3(col, 0.03f * grain(u, v, 313));

    /* grains plucked out of the face leave pits */
    float pluck = pit_depth(specks(u, v, 24, 0.12f, 0.32f, 314u, NULL));

    float h = 0.9f * relief + 0.10f * dome + 0.08f * hashf(g.id, 3u, 305u) - 0.06f * between +
              0.05f * in_clast + 0.02f * grain(u, v, 315) - 0.25f * pluck;
    cv->h[idx] = h;
    cv->occ[idx] = 0.35f * pluck;
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Concrete: grey cement paste with sand, air voids, and coarse and medium
 * aggregate broken through (or pulled out of the paste).                    */

void make_concrete_interior(Canvas* cv) {
  /* limestone, flint, granite, basalt, quartzite, sandstone */
  static const float stones[6][3] = {{150, 146, 136}, {128, 104, 82},  {160, 142, 132},
                                     {88, 88, 90},    {164, 158, 148}, {146, 126, 100}};
  Rgb paste = rgb(134, 133, 128);
  FOR_PIXELS {
    PIXEL_SETUP;
    float relief = fracture_relief(u, v, 320);
    Rgb col = scale3(paste, 1.0f + 0.06f * fbm(u, v, 8, 3, 321));
    col = add3(col, 0.04f * grain(u, v, 322));
    /* sand: light quartz and dark grains */
    uint32_t sid;
    float s = specks(u, v, 72, 0.6f, 0.48f, 323u, &sid);
    col = mix3(col, (sid >> 24) & 1u ? rgb(176, 172, 160) : rgb(96, 92, 86), 0.55f * s);
    float h = 0.8f * relief + 0.05f * s + 0.02f * grain(u, v, 324);

    /* coarse, then medium aggregate where no coarse stone lies: broken
     * stones with irregular outlines, set in a thin dark transition zone */
    float covered = 0.0f, rim_all = 0.0f;
    for (int layer = 0; layer < 2; layer++) {
      int n = layer == 0 ? 5 : 12;
      float amp = layer == 0 ? 0.02f : 0.01f;
      float wu = u + amp * fbm(u, v, layer == 0 ? 4 : 8, 2, 325 + layer);
      float wv = v + amp * fbm(u, v, layer == 0 ? 4 : 8, 2, 327 + layer);
      Cellular c = cellular(wu, wv, n, 330u + (uint32_t)layer);
      if (hashf(c.id, 1u, 332u) > (layer == 0 ? 0.75f : 0.6f)) continue;
      /* a disc clipped by its cell's edges: crushed stone's flat sides */
      float r = (layer == 0 ? 0.32f : 0.26f) + 0.16f * hashf(c.id, 2u, 332u);
      float shape = fmaxf(c.f1 / r, 1.0f - (c.f2 - c.f1) / 0.12f);
      float in = 1.0f - smooth(0.94f, 1.03f, shape);
      float rim = (1.0f - smooth(0.0f, 0.1f, fabsf(shape - 1.0f))) * (1.0f - covered);
      in *= 1.0f - covered;
      rim_all = fmaxf(rim_all, rim);
      if (in <= 0.0f) continue;
      uint32_t kind = (c.id >> 16) % 6u;
      const float* p = stones[kind];
      Rgb st = scale3(rgb(p[0], p[1], p[2]), 0.9f + 0.2f * hashf(c.id, 3u, 332u));
      st = scale3(st, 1.0f + 0.07f * fbm(u, v, 32, 3, 333 + layer));
      if (kind == 2u) { /* granite: black mica and pink feldspar crystals */
        uint32_t gid;
        float x = specks(u, v, 128, 0.6f, 0.5f, 335u, &gid);
        st = mix3(st, (gid >> 24) & 1u ? rgb(40, 38, 40) : rgb(184, 146, 130), 0.8f * x);
      } else {
        st = add3(st, 0.03f * grain(u, v, 336));
      }
      col = mix3(col, st, in);
      /* a stone broken through is flatter than the paste around it, and
       * either stands proud or sits in its socket */
      float ht = 0.4f * relief + 0.5f * (hashf(c.id, 4u, 332u) - 0.4f) + 0.02f * fbm(u, v, 32, 2, 337);
      h = mixf(h, ht, in);
      covered = fmaxf(covered, in);
    }
    col = scale3(col, 1.0f - 0.25f * rim_all);
    h -= 0.18f * rim_all;

    /* entrapped air: round voids 1 to 3 mm across, and a few larger ones */
    float voids = fmaxf(specks(u, v, 14, 0.45f, 0.3f, 338u, NULL), specks(u, v, 5, 0.2f, 0.14f, 339u, NULL));
    float depth = pit_depth(voids) * (1.0f - covered); /* none inside a stone */
    h -= 0.55f * depth;
    col = scale3(col, 1.0f - 0.15f * depth);
    cv->h[idx] = h;
    cv->occ[idx] = 0.45f * depth;
    cv->c[idx] = col;
  }
}

/* ------------------------------------------------------------------------ */
/* Brick: fired clay, orange-red with darker and lighter firing, grog
 * (crushed fired clay) and lime specks, and the flat pores and laminations
 * of an extruded body.                                                      */

void make_brick_interior(Canvas* cv) {
  Rgb clay = rgb(166, 80, 52), orange = rgb(184, 100, 62), dark = rgb(124, 56, 42);
  FOR_PIXELS {
    PIXEL_SETUP;
    float relief = fracture_relief(u, v, 340);
    /* firing: broad warmer and darker zones */
    float f = fbm(u, v, 2, 4, 341);
    Rgb col = mix3(clay, orange, smooth(0.0f, 0.7f, f));
    col = mix3(col, dark, 0.6f * smooth(0.1f, 0.8f, -f));
    col = scale3(col, 1.0f + 0.06f * fbm(u, v, 16, 3, 342));
    col = add3(col, 0.035f * grain(u, v, 343));

    /* grog: angular light and dark grains */
    float gu = u + 0.004f * fbm(u, v, 32, 2, 344), gv = v + 0.004f * fbm(u, v, 32, 2, 345);
    Cellular g = cellular(gu, gv, 44, 346u);
    float grog = 0.0f;
    if (hashf(g.id, 1u, 347u) < 0.4f) {
      /* a disc clipped by its cell's edges: an angular outline */
      float r = 0.3f + 0.2f * hashf(g.id, 2u, 347u);
      grog = (1.0f - smooth(r - 0.05f, r + 0.02f, g.f1)) * smooth(0.03f, 0.1f, g.f2 - g.f1);
      int light = hashf(g.id, 3u, 347u) < 0.6f;
      Rgb gc = light ? rgb(206, 148, 110) : rgb(104, 44, 34);
      col = mix3(col, gc, 0.75f * grog);
    }
    /* lime and iron specks */
    float lime = specks(u, v, 18, 0.12f, 0.22f, 348u, NULL);
    col = mix3(col, rgb(214, 196, 172), 0.8f * lime);
    float iron = specks(u, v, 60, 0.1f, 0.35f, 349u, NULL);
    col = mix3(col, rgb(52, 30, 26), 0.7f * iron);

    /* laminations along the extrusion, and flattened pores between them */
    float lam = fractal(RIDGE, u, v + 0.02f * fbm(u, v, 4, 2, 350), 4, 32, 3, 0.5f, 351);
    Cellular pc = cellular(u, v + 0.01f * fbm(u, v, 8, 2, 352), 24, 353u);
    float pore = 0.0f;
    if (hashf(pc.id, 1u, 354u) < 0.3f) {
      /* cells twice as long as high: stretch the distance across the layers */
      float ex = pc.dx, ey = pc.dy * 2.2f;
      float d = sqrtf(ex * ex + ey * ey);
      pore = 1.0f - smooth(0.12f, 0.26f, d);
    }
    col = scale3(col, 1.0f - 0.08f * pore);

    float h = 0.75f * relief + 0.07f * lam + 0.06f * grog + 0.03f * grain(u, v, 355) +
              0.04f * fbm(u, v, 32, 2, 356) - 0.4f * pit_depth(pore);
    cv->h[idx] = h;
    cv->occ[idx] = 0.2f * pore;
    cv->c[idx] = col;
  }
}
