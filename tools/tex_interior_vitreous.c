/* Interiors of the vitreous materials (porcelain, eggshell porcelain,
 * glass): a dense body broken in a conchoidal fracture, smooth "mirror"
 * zones round where cracks started, ripple marks spreading from them and
 * hackle ridges further out (see tex.h). */
#include "tex.h"

/* A conchoidal fracture with n x n scallops per tile: each a shallow dish
 * scooped round the point where its crack started, the dishes meeting in
 * ridges; `rings` ripple marks per cell width spread as arcs from the
 * origin in the direction the crack ran, and radial hackle roughens the far
 * side. About [-1, 1]; *hackle_out gets the hackle alone (0..1) for
 * colouring. */
static float conchoidal(float u, float v, int n, float rings, int seed, float* hackle_out) {
  float wu = u + 0.03f * fbm(u, v, 4, 2, seed), wv = v + 0.03f * fbm(u, v, 4, 2, seed + 1);
  Cellular c = cellular(wu, wv, n, (uint32_t)seed + 2u);
  float d = c.f1;
  float dish = d * d;
  /* what depends on the cell's own origin and direction fades out towards
   * its edges, where the neighbour's takes over: no steps */
  float inner = smooth(0.0f, 0.2f, c.f2 - c.f1);
  /* the direction the crack ran: ripples ahead of the origin only */
  float a = 2.0f * PI_F * hashf(c.id, 3u, (uint32_t)seed);
  float ahead = d > 1e-4f ? (c.dx * cosf(a) + c.dy * sinf(a)) / c.f1 : 0.0f;
  float phase = rings * d + hashf(c.id, 2u, (uint32_t)seed) + 0.25f * fbm(u, v, 8, 2, seed + 3);
  float ripple = sinf(2.0f * PI_F * phase);
  ripple = ripple > 0.0f ? ripple * ripple * ripple : 0.3f * ripple; /* sharp crests, broad troughs */
  float ripples =
      ripple * smooth(0.08f, 0.3f, d) * smooth(-0.3f, 0.6f, ahead) * (1.0f - smooth(0.4f, 1.0f, d)) * inner;
  /* hackle: ridges along the crack's direction of travel (radial), from
   * noise of the angle round the origin, which wraps at +-pi */
  float angle = atan2f(c.dy, c.dx) * (1.0f / (2.0f * PI_F)) + 0.5f;
  float along = 0.7f * pn(angle, d * 0.25f, 64, 4, seed + 4) + 0.3f * pn(angle, d * 0.25f, 128, 4, seed + 5);
  float hackle = 1.0f - fabsf(along);
  hackle = hackle * hackle * hackle * smooth(0.45f, 0.9f, d) * smooth(-0.5f, 0.5f, ahead) * inner;
  if (hackle_out) *hackle_out = hackle;
  return 1.1f * dish + 0.35f * ripples + 0.25f * hackle;
}

/* A porcelain body: the glaze is on the outside only; inside, a fine
 * grey-white vitrified body with a few closed pores and iron specks. */
static void porcelain_body(Canvas* cv, Rgb body, Rgb shade, int seed) {
  FOR_PIXELS {
    PIXEL_SETUP;
    float hackle = 0.0f;
    float conch = conchoidal(u, v, 3, 5.0f, seed, &hackle);
    float mott = fbm(u, v, 4, 4, seed + 10);
    Rgb col = mix3(body, shade, 0.5f * smooth(-0.3f, 0.8f, mott));
    col = add3(col, 0.022f * grain(u, v, seed + 11));
    /* hackle ridges scatter a little more light than the smooth zones */
    col = add3(col, 0.03f * hackle);
    float pore = specks(u, v, 40, 0.22f, 0.22f, (uint32_t)seed + 12u, NULL);
    col = mix3(col, rgb(150, 148, 144), 0.5f * pore);
    float iron = specks(u, v, 20, 0.06f, 0.18f, (uint32_t)seed + 13u, NULL);
    col = mix3(col, rgb(150, 120, 90), 0.6f * iron);
    /* sugary fine texture of the broken body */
    float sugar = 0.6f * grain(u, v, seed + 14) + 0.4f * fbm(u, v, 64, 2, seed + 15);
    cv->h[idx] = 0.6f * conch + 0.18f * fbm(u, v, 2, 3, seed + 16) + 0.05f * sugar - 0.25f * pore;
    cv->occ[idx] = 0.3f * pore;
    cv->c[idx] = col;
  }
}

void make_porcelain_interior(Canvas* cv) { porcelain_body(cv, rgb(220, 218, 211), rgb(204, 204, 200), 400); }

/* The eggshell scene's porcelain is a warmer, creamier body. */
void make_eggshell_interior(Canvas* cv) { porcelain_body(cv, rgb(224, 210, 184), rgb(208, 194, 170), 420); }

/* Glass: soda-lime glass seen through its broken edge is green; mirror
 * zones clear and dark, ripples and hackle catching light. */
void make_glass_interior(Canvas* cv) {
  Rgb clear = rgb(132, 178, 156), pale = rgb(170, 206, 186);
  FOR_PIXELS {
    PIXEL_SETUP;
    float hackle = 0.0f;
    float conch = conchoidal(u, v, 2, 7.0f, 440, &hackle);
    float thick = fbm(u, v, 2, 3, 441);
    Rgb col = mix3(clear, pale, smooth(-0.5f, 0.6f, thick));
    col = mix3(col, rgb(206, 228, 214), 0.45f * hackle);
    col = add3(col, 0.05f * smooth(0.1f, 0.6f, conch));
    col = add3(col, 0.01f * grain(u, v, 442));
    cv->h[idx] = conch + 0.1f * fbm(u, v, 2, 3, 443);
    cv->c[idx] = col;
  }
}
