// PCG32 (O'Neill, pcg-random.org): the generator every random choice of the
// libraries draws from, the same numbers on every platform for a seed.
#include <math.h>

#include "bk_base.h"

bk_rng bk_rng_seed(uint64_t seed, uint64_t stream) {
  bk_rng rng = {0u, (stream << 1u) | 1u};
  (void)bk_rng_next(&rng);
  rng.state += seed;
  (void)bk_rng_next(&rng);
  return rng;
}

uint32_t bk_rng_next(bk_rng* rng) {
  uint64_t old = rng->state;
  rng->state = old * 6364136223846793005ull + rng->inc;
  uint32_t xorshifted = (uint32_t)(((old >> 18u) ^ old) >> 27u);
  uint32_t rot = (uint32_t)(old >> 59u);
  return (xorshifted >> rot) | (xorshifted << ((32u - rot) & 31u));
}

double bk_rng_unit(bk_rng* rng) {
  // 53 random bits for a full-precision double in [0, 1).
  uint64_t hi = bk_rng_next(rng) >> 5, lo = bk_rng_next(rng) >> 6;
  return (double)((hi << 26) | lo) * (1.0 / 9007199254740992.0);
}

bk_vec3 bk_rng_direction(bk_rng* rng) {
  // Uniform on the sphere: z uniform in [-1, 1], azimuth uniform.
  double z = 2.0 * bk_rng_unit(rng) - 1.0;
  double phi = 2.0 * 3.14159265358979323846 * bk_rng_unit(rng);
  double r = sqrt(fmax(0.0, 1.0 - z * z));
  return bk_v3(r * bk_cos(phi), r * bk_sin(phi), z);
}
