/* devmath.h - the elementary functions the estimator needs, in portable C, for the GPU.
 *
 * A CUDA device has no libm, and brume builds without the CUDA SDK (no libdevice): the
 * device's exp, log, log1p, pow, sin, cos, tan, acos, atan2, cbrt and nextafter are these functions
 * (gpu/kernel.cu maps the libm names to them). They are plain C on doubles, so the CPU
 * tests check them against the host's libm (tests/test_gpu.c): over the ranges the
 * estimator uses, each is within DEVMATH_MAX_ULP units in the last place of libm's value
 * (docs/gpu.md, "Device math", states the measured errors). Only sqrt, fabs, floor,
 * fmin, fmax and copysign are compiler built-ins, which the device has as instructions
 * (sqrt correctly rounded, as on the CPU).
 *
 * Methods: exp by Cody-Waite reduction to |r| <= ln2 / 2 and a degree-13 Taylor
 * polynomial; log by the mantissa in [sqrt(1/2), sqrt(2)) and the series of atanh;
 * sin and cos by reduction modulo pi/2 in three parts and Taylor polynomials on
 * [-pi/4, pi/4]; atan by two half-angle steps to |t| <= tan(pi/16) and its series; acos,
 * atan2 from atan; cbrt by one Newton step from exp(log(x) / 3). Special values (0,
 * infinities, NaN, negative arguments of log) follow C99's Annex F where the estimator can
 * meet them; pow covers x >= 0 and negative x with integer y. */
#ifndef BRUME_GPU_DEVMATH_H
#define BRUME_GPU_DEVMATH_H

#include <stdint.h>
#include <string.h>

#define DEVMATH_MAX_ULP 8 /* the bound tests/test_gpu.c holds each function to */

static inline uint64_t devmath_bits(double x)
{
    uint64_t u;
    __builtin_memcpy(&u, &x, sizeof u);
    return u;
}
static inline double devmath_from_bits(uint64_t u)
{
    double x;
    __builtin_memcpy(&x, &u, sizeof x);
    return x;
}

/* x 2^k for k in [-2044, 2046] without loss in the normal range (two steps). */
static inline double devmath_ldexp(double x, int k)
{
    if (k > 1023) {
        x *= 0x1p1023;
        k -= 1023;
        if (k > 1023)
            k = 1023;
    } else if (k < -1022) {
        x *= 0x1p-1022;
        k += 1022;
        if (k < -1022)
            k = -1022;
    }
    return x * devmath_from_bits((uint64_t)(k + 1023) << 52);
}

static inline double devmath_exp(double x)
{
    if (x != x)
        return x;
    if (x > 709.782712893384)
        return __builtin_inf();
    if (x < -745.2)
        return 0.0;
    const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    double kf = __builtin_floor(x * 1.4426950408889634 + 0.5);
    double r = (x - kf * ln2_hi) - kf * ln2_lo;
    /* e^r, |r| <= 0.347: Taylor to r^13 / 13! (remainder below 2e-18) */
    double p = 1.0 / 6227020800.0;
    p = p * r + 1.0 / 479001600.0;
    p = p * r + 1.0 / 39916800.0;
    p = p * r + 1.0 / 3628800.0;
    p = p * r + 1.0 / 362880.0;
    p = p * r + 1.0 / 40320.0;
    p = p * r + 1.0 / 5040.0;
    p = p * r + 1.0 / 720.0;
    p = p * r + 1.0 / 120.0;
    p = p * r + 1.0 / 24.0;
    p = p * r + 1.0 / 6.0;
    p = p * r + 0.5;
    p = p * r * r + r; /* e^r - 1 */
    return devmath_ldexp(1.0 + p, (int)kf);
}

static inline double devmath_log(double x)
{
    if (x != x || x < 0.0)
        return __builtin_nan("");
    if (x == 0.0)
        return -__builtin_inf();
    if (x == __builtin_inf())
        return x;
    int e = 0;
    if (x < 0x1p-1022) { /* subnormal */
        x *= 0x1p54;
        e = -54;
    }
    uint64_t u = devmath_bits(x);
    e += (int)((u >> 52) & 0x7ff) - 1023;
    double m = devmath_from_bits((u & 0x000fffffffffffffULL) | 0x3ff0000000000000ULL); /* [1, 2) */
    if (m > 1.4142135623730951) {
        m *= 0.5;
        e++;
    }
    /* log m = 2 atanh(f), f = (m - 1) / (m + 1), |f| <= 0.1716 */
    double f = (m - 1.0) / (m + 1.0), f2 = f * f;
    double s = 1.0 / 23.0;
    s = s * f2 + 1.0 / 21.0;
    s = s * f2 + 1.0 / 19.0;
    s = s * f2 + 1.0 / 17.0;
    s = s * f2 + 1.0 / 15.0;
    s = s * f2 + 1.0 / 13.0;
    s = s * f2 + 1.0 / 11.0;
    s = s * f2 + 1.0 / 9.0;
    s = s * f2 + 1.0 / 7.0;
    s = s * f2 + 1.0 / 5.0;
    s = s * f2 + 1.0 / 3.0;
    double lm = 2.0 * f + 2.0 * f * f2 * s;
    const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    return (e * ln2_hi + (lm + e * ln2_lo));
}

static inline double devmath_pow(double x, double y)
{
    if (y == 0.0)
        return 1.0;
    if (x != x || y != y)
        return x + y;
    if (x == 0.0)
        return y > 0.0 ? 0.0 : __builtin_inf();
    if (__builtin_floor(y) == y && __builtin_fabs(y) <= 64.0) { /* small integer powers by squaring */
        double b = y < 0.0 ? 1.0 / x : x, r = 1.0;
        for (int k = (int)__builtin_fabs(y); k > 0; k >>= 1) {
            if (k & 1)
                r *= b;
            b *= b;
        }
        return r;
    }
    if (x < 0.0) {
        double yi = __builtin_floor(y);
        if (yi != y)
            return __builtin_nan("");
        double v = devmath_exp(y * devmath_log(-x));
        double half = yi * 0.5;
        return __builtin_floor(half) == half ? v : -v;
    }
    return devmath_exp(y * devmath_log(x));
}

/* sin and cos of r, |r| <= pi/4 (Taylor to r^17 and r^16) */
static inline double devmath_sin_kernel(double r)
{
    double r2 = r * r;
    double p = -1.0 / 355687428096000.0;
    p = p * r2 + 1.0 / 1307674368000.0;
    p = p * r2 - 1.0 / 6227020800.0;
    p = p * r2 + 1.0 / 39916800.0;
    p = p * r2 - 1.0 / 362880.0;
    p = p * r2 + 1.0 / 5040.0;
    p = p * r2 - 1.0 / 120.0;
    p = p * r2 + 1.0 / 6.0;
    return r - r * r2 * p;
}
static inline double devmath_cos_kernel(double r)
{
    double r2 = r * r;
    double p = 1.0 / 20922789888000.0;
    p = p * r2 - 1.0 / 87178291200.0;
    p = p * r2 + 1.0 / 479001600.0;
    p = p * r2 - 1.0 / 3628800.0;
    p = p * r2 + 1.0 / 40320.0;
    p = p * r2 - 1.0 / 720.0;
    p = p * r2 + 1.0 / 24.0;
    return 1.0 - 0.5 * r2 + r2 * r2 * p;
}
/* x = q pi/2 + r, |r| <= pi/4 (three-part pi/2: exact for |q| < 2^20) */
static inline double devmath_reduce(double x, int *q)
{
    double k = __builtin_floor(x * 0.63661977236758134 + 0.5);
    const double p1 = 1.57079632673412561417e+00, p2 = 6.07710050650619224932e-11, p3 = 2.02226624879595063154e-21;
    *q = (int)((int64_t)k & 3);
    return ((x - k * p1) - k * p2) - k * p3;
}
static inline double devmath_sin(double x)
{
    if (!(__builtin_fabs(x) < 1e6))
        return x != x || __builtin_fabs(x) == __builtin_inf() ? __builtin_nan("") : 0.0; /* out of the supported range */
    int q;
    double r = devmath_reduce(x, &q);
    switch (q) {
    case 0: return devmath_sin_kernel(r);
    case 1: return devmath_cos_kernel(r);
    case 2: return -devmath_sin_kernel(r);
    default: return -devmath_cos_kernel(r);
    }
}
static inline double devmath_cos(double x)
{
    if (!(__builtin_fabs(x) < 1e6))
        return x != x || __builtin_fabs(x) == __builtin_inf() ? __builtin_nan("") : 1.0;
    int q;
    double r = devmath_reduce(x, &q);
    switch (q) {
    case 0: return devmath_cos_kernel(r);
    case 1: return -devmath_sin_kernel(r);
    case 2: return -devmath_cos_kernel(r);
    default: return devmath_sin_kernel(r);
    }
}

static inline double devmath_tan(double x) { return devmath_sin(x) / devmath_cos(x); }

/* log(1 + x) accurate near 0: log(u) x / (u - 1) with u = 1 + x rounded (Goldberg 1991) */
static inline double devmath_log1p(double x)
{
    double u = 1.0 + x;
    if (u == 1.0)
        return x;
    if (u == __builtin_inf())
        return u;
    return devmath_log(u) * x / (u - 1.0);
}

/* atan(t): atan(t) = pi/2 - atan(1/t) for |t| > 1, then two half-angle steps
 * atan(t) = 2 atan(t / (1 + sqrt(1 + t^2))) to |t| <= tan(pi/16), then the series. */
static inline double devmath_atan(double t)
{
    if (t != t)
        return t;
    double sgn = t < 0.0 ? -1.0 : 1.0, a = __builtin_fabs(t), base = 0.0, mul = 1.0;
    if (a > 1.0) {
        base = 1.5707963267948966;
        mul = -1.0;
        a = 1.0 / a;
    }
    for (int i = 0; i < 2; i++)
        a = a / (1.0 + __builtin_sqrt(1.0 + a * a));
    double a2 = a * a;
    double s = -1.0 / 27.0;
    s = s * a2 + 1.0 / 25.0;
    s = s * a2 - 1.0 / 23.0;
    s = s * a2 + 1.0 / 21.0;
    s = s * a2 - 1.0 / 19.0;
    s = s * a2 + 1.0 / 17.0;
    s = s * a2 - 1.0 / 15.0;
    s = s * a2 + 1.0 / 13.0;
    s = s * a2 - 1.0 / 11.0;
    s = s * a2 + 1.0 / 9.0;
    s = s * a2 - 1.0 / 7.0;
    s = s * a2 + 1.0 / 5.0;
    s = s * a2 - 1.0 / 3.0;
    double at = 4.0 * (a + a * a2 * s);
    return sgn * (base + mul * at);
}
static inline double devmath_atan2(double y, double x)
{
    const double pi = 3.14159265358979323846;
    if (x != x || y != y)
        return x + y;
    if (x == 0.0 && y == 0.0)
        return __builtin_copysign(__builtin_signbit(x) ? pi : 0.0, y);
    if (__builtin_fabs(x) >= __builtin_fabs(y)) {
        double a = devmath_atan(y / x);
        if (x > 0.0)
            return a;
        return y >= 0.0 ? a + pi : a - pi;
    }
    return __builtin_copysign(0.5 * pi, y) - devmath_atan(x / y);
}
static inline double devmath_acos(double x)
{
    if (!(x >= -1.0 && x <= 1.0))
        return __builtin_nan("");
    return devmath_atan2(__builtin_sqrt((1.0 - x) * (1.0 + x)), x);
}
static inline double devmath_cbrt(double x)
{
    if (x == 0.0 || x != x || __builtin_fabs(x) == __builtin_inf())
        return x;
    double a = __builtin_fabs(x);
    double y = devmath_exp(devmath_log(a) / 3.0);
    y = y - (y * y * y - a) / (3.0 * y * y);
    return __builtin_copysign(y, x);
}
/* the next representable double after x towards y */
static inline double devmath_nextafter(double x, double y)
{
    if (x != x || y != y)
        return x + y;
    if (x == y)
        return y;
    if (x == 0.0)
        return __builtin_copysign(devmath_from_bits(1), y);
    uint64_t u = devmath_bits(x);
    if ((y > x) == (x > 0.0))
        u++;
    else
        u--;
    return devmath_from_bits(u);
}

#endif
