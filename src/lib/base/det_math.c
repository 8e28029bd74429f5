// sin, cos, atan2, cbrt, log2, exp2, pow and hypot from IEEE basic
// operations only (+ - * / sqrt are exactly rounded on every machine; frexp,
// ldexp and fmod are exact), so trees come out as the same bytes from GCC,
// clang, glibc on any x86 (whose libm picks FMA code where the CPU has it),
// musl and WebAssembly. Series are summed in a fixed order; nothing here
// may be contracted into FMAs (the libraries build with -ffp-contract=off).
#include <float.h>
#include <math.h>

#include "bk_base.h"

#define PI_HI 3.141592653589793116
#define HALF_PI_HI 1.57079632679489655800
// pi/2 in two parts: the first with few enough bits that n x HALF_PI_A is
// exact for the small n met here, the second what is left.
#define HALF_PI_A 1.57079632673412561417e+00
#define HALF_PI_B 6.07710050650619224932e-11
#define LN2 0.693147180559945286227

// sin and cos of r in [-pi/4, pi/4]: Taylor series to r^17 and r^18 (the
// remainders are below 1e-19), Horner from the small end.
static double sin_small(double r) {
  double r2 = r * r;
  double p = 1.0 / 355687428096000.0; // 1/17!
  p = p * r2 - 1.0 / 1307674368000.0; // 1/15!
  p = p * r2 + 1.0 / 6227020800.0;    // 1/13!
  p = p * r2 - 1.0 / 39916800.0;      // 1/11!
  p = p * r2 + 1.0 / 362880.0;        // 1/9!
  p = p * r2 - 1.0 / 5040.0;          // 1/7!
  p = p * r2 + 1.0 / 120.0;           // 1/5!
  p = p * r2 - 1.0 / 6.0;             // 1/3!
  return r + r * r2 * p;
}

static double cos_small(double r) {
  double r2 = r * r;
  double p = -1.0 / 6402373705728000.0; // 1/18!
  p = p * r2 + 1.0 / 20922789888000.0;  // 1/16!
  p = p * r2 - 1.0 / 87178291200.0;     // 1/14!
  p = p * r2 + 1.0 / 479001600.0;       // 1/12!
  p = p * r2 - 1.0 / 3628800.0;         // 1/10!
  p = p * r2 + 1.0 / 40320.0;           // 1/8!
  p = p * r2 - 1.0 / 720.0;             // 1/6!
  p = p * r2 + 1.0 / 24.0;              // 1/4!
  double h = 0.5 * r2;
  return (1.0 - h) + ((1.0 - (1.0 - h)) - h) + r2 * r2 * p;
}

// x = n pi/2 + r with r in [-pi/4, pi/4]; the quadrant n mod 4 into *q.
static double reduce(double x, int* q) {
  // fmod is exact: large angles are first brought near zero, which keeps
  // n small (the reduction is then against the double 2 pi beyond 2^20).
  if (fabs(x) > 1048576.0) x = fmod(x, 2.0 * PI_HI);
  double n = floor(x / HALF_PI_HI + 0.5);
  double r = (x - n * HALF_PI_A) - n * HALF_PI_B;
  long k = (long)n;
  *q = (int)(((k % 4) + 4) % 4);
  return r;
}

double bk_sin(double x) {
  if (!isfinite(x)) return x - x; // NaN for inf and NaN
  int q = 0;
  double r = reduce(x, &q);
  switch (q) {
  case 0:
    return sin_small(r);
  case 1:
    return cos_small(r);
  case 2:
    return -sin_small(r);
  default:
    return -cos_small(r);
  }
}

double bk_cos(double x) {
  if (!isfinite(x)) return x - x;
  int q = 0;
  double r = reduce(x, &q);
  switch (q) {
  case 0:
    return cos_small(r);
  case 1:
    return -sin_small(r);
  case 2:
    return -cos_small(r);
  default:
    return sin_small(r);
  }
}

// atan of t in [0, 1]: above tan(pi/8), atan(t) = pi/4 + atan((t - 1)/(t + 1));
// then one halving, atan(u) = 2 atan(u / (1 + sqrt(1 + u^2))), leaves |u| <
// 0.2, where the series to u^29 is within 1e-20.
static double atan_unit(double t) {
  double base = 0.0;
  if (t > 0.41421356237309503) {
    base = 0.25 * PI_HI;
    t = (t - 1.0) / (t + 1.0);
  }
  double u = t / (1.0 + sqrt(1.0 + t * t));
  double u2 = u * u;
  double p = 0.0;
  for (int k = 29; k >= 3; k -= 2)
    p = p * u2 + ((k & 2) ? -1.0 : 1.0) / (double)k; // +1/k for k = 1 mod 4, -1/k for k = 3 mod 4
  return base + 2.0 * (u + u * u2 * p);
}

double bk_atan2(double y, double x) {
  if (isnan(x) || isnan(y)) return x + y;
  double ax = fabs(x), ay = fabs(y);
  double a = 0.0;
  if (ax == 0.0 && ay == 0.0) {
    a = 0.0;
  } else if (isinf(ax) || isinf(ay)) {
    a = isinf(ax) && isinf(ay) ? 0.25 * PI_HI : isinf(ay) ? HALF_PI_HI : 0.0;
  } else if (ay <= ax) {
    a = atan_unit(ay / ax);
  } else {
    a = HALF_PI_HI - atan_unit(ax / ay);
  }
  if (signbit(x)) a = PI_HI - a;
  return signbit(y) ? -a : a;
}

double bk_cbrt(double x) {
  if (x == 0.0 || !isfinite(x)) return x;
  int e = 0;
  double m = frexp(fabs(x), &e); // |x| = m 2^e, m in [0.5, 1)
  int r = ((e % 3) + 3) % 3;     // m 2^r in [0.5, 4), e - r a multiple of 3
  m = ldexp(m, r);
  e -= r;
  double y = 0.6 + 0.4 * m; // within 40% of cbrt(m) on [0.5, 4): Newton doubles the digits
  for (int i = 0; i < 6; ++i)
    y = y - (y * y * y - m) / (3.0 * y * y);
  y = ldexp(y, e / 3);
  return x < 0.0 ? -y : y;
}

double bk_log2(double x) {
  if (isnan(x) || x < 0.0) return NAN;
  if (x == 0.0) return -INFINITY;
  if (isinf(x)) return x;
  int e = 0;
  double m = frexp(x, &e);                       // m in [0.5, 1)
  if (m < 0.70710678118654752) m *= 2.0, e -= 1; // m in [0.707, 1.414)
  // ln m = 2 atanh(s), s = (m - 1)/(m + 1) in [-0.172, 0.172]: to s^33 is within 1e-26.
  double s = (m - 1.0) / (m + 1.0);
  double s2 = s * s;
  double p = 0.0;
  for (int k = 33; k >= 3; k -= 2)
    p = p * s2 + 1.0 / (double)k;
  double ln_m = 2.0 * (s + s * s2 * p);
  return (double)e + ln_m / LN2;
}

double bk_exp2(double x) {
  if (isnan(x)) return x;
  if (x > 1024.0) return INFINITY;
  if (x < -1080.0) return 0.0;
  double n = floor(x + 0.5);
  double f = (x - n) * LN2; // |f| <= 0.347: the series to f^18 is within 1e-22
  double p = 1.0;
  for (int k = 18; k >= 1; --k)
    p = 1.0 + p * f / (double)k;
  return ldexp(p, (int)n);
}

double bk_pow(double x, double y) {
  if (isnan(x) || isnan(y)) return NAN;
  if (y == 0.0) return 1.0;
  if (x == 0.0) return y > 0.0 ? 0.0 : NAN;
  if (x < 0.0) return NAN;
  if (x == 1.0) return 1.0;
  return bk_exp2(y * bk_log2(x));
}

double bk_hypot(double x, double y) {
  double a = fabs(x), b = fabs(y);
  if (isinf(a) || isinf(b)) return INFINITY;
  if (isnan(a) || isnan(b)) return NAN;
  if (a < b) {
    double t = a;
    a = b, b = t;
  }
  if (a == 0.0) return 0.0;
  double r = b / a;
  return a * sqrt(1.0 + r * r);
}
