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
 * meet them; pow covers x >= 0 and negative x with integer y.
 *
 * The float versions (devmath_expf ... devmath_nextafterf, below) are for the GPU's single
 * precision stages: the same methods in float arithmetic alone, with polynomials of the
 * degree float needs and constants split so that their products stay exact, so that they
 * compile to no FP64 instruction. tests/test_gpu_float.c holds them to DEVMATH_MAX_ULPF
 * of glibc's float functions (docs/gpu.md, "Device math"). */
#ifndef BRUME_GPU_DEVMATH_H
#define BRUME_GPU_DEVMATH_H

#include <stdint.h>
#include <string.h>

#define DEVMATH_MAX_ULP 8 /* the bound tests/test_gpu.c holds each function to */
#define DEVMATH_MAX_ULPF 8 /* the bound tests/test_gpu_float.c holds each float function to */

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

/* ---- single precision: the same methods in float arithmetic --------------------------------- */

static inline uint32_t devmath_bitsf(float x)
{
    uint32_t u;
    __builtin_memcpy(&u, &x, sizeof u);
    return u;
}
static inline float devmath_from_bitsf(uint32_t u)
{
    float x;
    __builtin_memcpy(&x, &u, sizeof x);
    return x;
}

/* x 2^k for k in [-252, 254] without loss in the normal range (two steps). */
static inline float devmath_ldexpf(float x, int k)
{
    if (k > 127) {
        x *= 0x1p127f;
        k -= 127;
        if (k > 127)
            k = 127;
    } else if (k < -126) {
        x *= 0x1p-126f;
        k += 126;
        if (k < -126)
            k = -126;
    }
    return x * devmath_from_bitsf((uint32_t)(k + 127) << 23);
}

/* ln 2 in two parts: the first with 15 significant bits, so that k ln2_hi is exact for |k| < 2^9 */
#define DEVMATH_LN2F_HI 0.693145751953125f
#define DEVMATH_LN2F_LO 1.428606765330187e-06f

static inline float devmath_expf(float x)
{
    if (x != x)
        return x;
    if (x > 88.72283935546875f)
        return __builtin_inff();
    if (x < -103.98f)
        return 0.0f;
    float kf = __builtin_floorf(x * 1.44269502162933349609f + 0.5f);
    float r = (x - kf * DEVMATH_LN2F_HI) - kf * DEVMATH_LN2F_LO;
    /* e^r, |r| <= 0.347: Taylor to r^7 / 7! (remainder below 6e-10) */
    float p = 1.0f / 5040.0f;
    p = p * r + 1.0f / 720.0f;
    p = p * r + 1.0f / 120.0f;
    p = p * r + 1.0f / 24.0f;
    p = p * r + 1.0f / 6.0f;
    p = p * r + 0.5f;
    p = p * r * r + r; /* e^r - 1 */
    return devmath_ldexpf(1.0f + p, (int)kf);
}

static inline float devmath_logf(float x)
{
    if (x != x || x < 0.0f)
        return __builtin_nanf("");
    if (x == 0.0f)
        return -__builtin_inff();
    if (x == __builtin_inff())
        return x;
    int e = 0;
    if (x < 0x1p-126f) { /* subnormal */
        x *= 0x1p25f;
        e = -25;
    }
    uint32_t u = devmath_bitsf(x);
    e += (int)((u >> 23) & 0xff) - 127;
    float m = devmath_from_bitsf((u & 0x007fffffu) | 0x3f800000u); /* [1, 2) */
    if (m > 1.41421353816986083984f) {
        m *= 0.5f;
        e++;
    }
    /* log m = 2 atanh(f), f = (m - 1) / (m + 1), |f| <= 0.1716: the series to f^11 / 11 */
    float f = (m - 1.0f) / (m + 1.0f), f2 = f * f;
    float s = 1.0f / 11.0f;
    s = s * f2 + 1.0f / 9.0f;
    s = s * f2 + 1.0f / 7.0f;
    s = s * f2 + 1.0f / 5.0f;
    s = s * f2 + 1.0f / 3.0f;
    float lm = 2.0f * f + 2.0f * f * f2 * s;
    float ef = (float)e;
    return ef * DEVMATH_LN2F_HI + (lm + ef * DEVMATH_LN2F_LO);
}

static inline float devmath_powf(float x, float y)
{
    if (y == 0.0f)
        return 1.0f;
    if (x != x || y != y)
        return x + y;
    if (x == 0.0f)
        return y > 0.0f ? 0.0f : __builtin_inff();
    if (__builtin_floorf(y) == y && __builtin_fabsf(y) <= 64.0f) { /* small integer powers by squaring */
        float b = y < 0.0f ? 1.0f / x : x, r = 1.0f;
        for (int k = (int)__builtin_fabsf(y); k > 0; k >>= 1) {
            if (k & 1)
                r *= b;
            b *= b;
        }
        return r;
    }
    if (x < 0.0f) {
        float yi = __builtin_floorf(y);
        if (yi != y)
            return __builtin_nanf("");
        float v = devmath_expf(y * devmath_logf(-x));
        float half = yi * 0.5f;
        return __builtin_floorf(half) == half ? v : -v;
    }
    return devmath_expf(y * devmath_logf(x));
}

/* sin and cos of r, |r| <= pi/4 (Taylor to r^11 and r^10) */
static inline float devmath_sin_kernelf(float r)
{
    float r2 = r * r;
    float p = -1.0f / 39916800.0f;
    p = p * r2 + 1.0f / 362880.0f;
    p = p * r2 - 1.0f / 5040.0f;
    p = p * r2 + 1.0f / 120.0f;
    p = p * r2 - 1.0f / 6.0f;
    return r + r * r2 * p;
}
static inline float devmath_cos_kernelf(float r)
{
    float r2 = r * r;
    float p = -1.0f / 3628800.0f;
    p = p * r2 + 1.0f / 40320.0f;
    p = p * r2 - 1.0f / 720.0f;
    p = p * r2 + 1.0f / 24.0f;
    return 1.0f - 0.5f * r2 + r2 * r2 * p;
}
/* x = q pi/2 + r, |r| <= pi/4 (three-part pi/2, Cephes's: accurate for |x| < 8192) */
static inline float devmath_reducef(float x, int *q)
{
    float k = __builtin_floorf(x * 0.636619772367581343f + 0.5f);
    const float p1 = 1.5703125f, p2 = 4.837512969970703125e-4f, p3 = 7.54978995489188216e-8f;
    *q = (int)k & 3;
    return ((x - k * p1) - k * p2) - k * p3;
}
static inline float devmath_sinf(float x)
{
    if (!(__builtin_fabsf(x) < 8192.0f))
        return x != x || __builtin_fabsf(x) == __builtin_inff() ? __builtin_nanf("") : 0.0f; /* out of the supported range */
    int q;
    float r = devmath_reducef(x, &q);
    switch (q) {
    case 0: return devmath_sin_kernelf(r);
    case 1: return devmath_cos_kernelf(r);
    case 2: return -devmath_sin_kernelf(r);
    default: return -devmath_cos_kernelf(r);
    }
}
static inline float devmath_cosf(float x)
{
    if (!(__builtin_fabsf(x) < 8192.0f))
        return x != x || __builtin_fabsf(x) == __builtin_inff() ? __builtin_nanf("") : 1.0f;
    int q;
    float r = devmath_reducef(x, &q);
    switch (q) {
    case 0: return devmath_cos_kernelf(r);
    case 1: return -devmath_sin_kernelf(r);
    case 2: return -devmath_cos_kernelf(r);
    default: return devmath_sin_kernelf(r);
    }
}

static inline float devmath_tanf(float x) { return devmath_sinf(x) / devmath_cosf(x); }

/* log(1 + x) accurate near 0 (Goldberg 1991, as devmath_log1p) */
static inline float devmath_log1pf(float x)
{
    float u = 1.0f + x;
    if (u == 1.0f)
        return x;
    if (u == __builtin_inff())
        return u;
    return devmath_logf(u) * x / (u - 1.0f);
}

/* atan(t) as devmath_atan: to |t| <= tan(pi/16) by 1/t and two half-angle steps, then the
 * series to t^9 / 9 */
static inline float devmath_atanf(float t)
{
    if (t != t)
        return t;
    float sgn = t < 0.0f ? -1.0f : 1.0f, a = __builtin_fabsf(t), base = 0.0f, mul = 1.0f;
    if (a > 1.0f) {
        base = 1.57079632679489661923f;
        mul = -1.0f;
        a = 1.0f / a;
    }
    for (int i = 0; i < 2; i++)
        a = a / (1.0f + __builtin_sqrtf(1.0f + a * a));
    float a2 = a * a;
    float s = 1.0f / 9.0f;
    s = s * a2 - 1.0f / 7.0f;
    s = s * a2 + 1.0f / 5.0f;
    s = s * a2 - 1.0f / 3.0f;
    float at = 4.0f * (a + a * a2 * s);
    return sgn * (base + mul * at);
}
static inline float devmath_atan2f(float y, float x)
{
    const float pi = 3.14159265358979323846f;
    if (x != x || y != y)
        return x + y;
    if (x == 0.0f && y == 0.0f)
        return __builtin_copysignf(__builtin_signbit(x) ? pi : 0.0f, y);
    if (__builtin_fabsf(x) >= __builtin_fabsf(y)) {
        float a = devmath_atanf(y / x);
        if (x > 0.0f)
            return a;
        return y >= 0.0f ? a + pi : a - pi;
    }
    return __builtin_copysignf(0.5f * pi, y) - devmath_atanf(x / y);
}
static inline float devmath_acosf(float x)
{
    if (!(x >= -1.0f && x <= 1.0f))
        return __builtin_nanf("");
    return devmath_atan2f(__builtin_sqrtf((1.0f - x) * (1.0f + x)), x);
}
static inline float devmath_cbrtf(float x)
{
    if (x == 0.0f || x != x || __builtin_fabsf(x) == __builtin_inff())
        return x;
    float a = __builtin_fabsf(x);
    float y = devmath_expf(devmath_logf(a) / 3.0f);
    y = y - (y * y * y - a) / (3.0f * y * y);
    return __builtin_copysignf(y, x);
}
/* the next representable float after x towards y */
static inline float devmath_nextafterf(float x, float y)
{
    if (x != x || y != y)
        return x + y;
    if (x == y)
        return y;
    if (x == 0.0f)
        return __builtin_copysignf(devmath_from_bitsf(1), y);
    uint32_t u = devmath_bitsf(x);
    if ((y > x) == (x > 0.0f))
        u++;
    else
        u--;
    return devmath_from_bitsf(u);
}

#endif
