/* Interior of wood: end grain, as a board cut or snapped across shows it
 * (see tex.h). Growth rings run across the tile as arcs of a trunk whose
 * pith lies off the tile, each a pale earlywood band with a row of open
 * pores darkening into dense latewood; rays cross them radially; the broken
 * surface is fibrous, torn fibres standing along the rays. */
#include "tex.h"

void make_wood_interior(Canvas* cv) {
  Rgb early = rgb(198, 152, 102), late = rgb(140, 92, 56), ray_c = rgb(212, 172, 120);
  const int rings = 8; /* whole rings per tile, so that the phase tiles */
  FOR_PIXELS {
    PIXEL_SETUP;
    /* ring phase: rows of the tile bent into arcs (a cos of u, periodic),
     * with the irregular wobble of real growth */
    float wob = 0.5f * fbm(u, v, 1, 3, 460) + 0.05f * fbm(u, v, 8, 2, 461);
    float phase = (float)rings * v + 0.3f * cosf(2.0f * PI_F * u) + wob;
    float ring = wrap01(phase);
    /* earlywood -> latewood through the year, then a sharp boundary */
    float lateness = smooth(0.55f, 0.9f, ring) * (1.0f - smooth(0.97f, 1.0f, ring));
    int year = ((int)floorf(phase) % rings + rings) % rings;
    float tone = 0.94f + 0.12f * hashf((uint32_t)year, 1u, 462u);
    Rgb col = scale3(mix3(early, late, lateness), tone);

    /* rays: thin radial ribbons, here along v (across the rings) */
    float ru = u + 0.004f * fbm(u, v, 4, 2, 463);
    float rays = fractal(RIDGE, ru, v, 64, 4, 2, 0.5f, 464);
    rays = smooth(0.8f, 0.95f, rays) * smooth(0.1f, 0.5f, fbm(u, v, 16, 2, 465) + 0.3f);
    col = mix3(col, ray_c, 0.6f * rays);

    /* earlywood pores: a row of open vessels at the start of each ring */
    uint32_t pid;
    float pore = specks(u, v, 80, 0.55f, 0.42f, 466u, &pid);
    pore *= 1.0f - smooth(0.08f, 0.3f, ring);
    col = mix3(col, rgb(92, 60, 38), 0.7f * pore);

    /* fibres: fine streaks along the rays, and torn bundles standing up */
    float fibre = fractal(FBM, u, v, 128, 16, 2, 0.5f, 467);
    float torn = fractal(RIDGE, u, v, 32, 4, 3, 0.5f, 468);
    col = scale3(col, 1.0f + 0.06f * fibre + 0.05f * fbm(u, v, 4, 3, 469));
    col = add3(col, 0.02f * grain(u, v, 470));

    /* latewood is denser and stands a little proud of the softer earlywood */
    float h = 0.25f * fbm(u, v, 2, 4, 471) + 0.10f * lateness + 0.08f * fibre + 0.16f * torn * torn -
              0.3f * pore + 0.04f * rays;
    cv->h[idx] = h;
    cv->occ[idx] = 0.35f * pore;
    cv->c[idx] = col;
  }
}
