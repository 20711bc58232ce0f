/* test_gpu_float.c - the single-precision device math (gpu/devmath.h, devmath_expf ...)
 * against the host's libm float functions, over the ranges the estimator uses, within
 * DEVMATH_MAX_ULPF; as test_gpu.c holds the double versions to DEVMATH_MAX_ULP. */
#include <math.h>
#include <stdint.h>

#include "gpu/devmath.h"
#include "test.h"

/* |a - b| in units of b's last place (the spacing of floats at |b|) */
static double ulpsf(float a, float b)
{
    if (a == b)
        return 0.0;
    double u = (double)nextafterf(fabsf(b), INFINITY) - (double)fabsf(b);
    return fabs((double)a - (double)b) / u;
}

/* a fixed sequence of uniforms (a 64-bit LCG) */
static float lcgf(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (float)(*s >> 40) * 0x1p-24f;
}

/* Each function within DEVMATH_MAX_ULPF on 10^6 arguments of the ranges the estimator
 * meets (as test_gpu.c's device_math_against_libm): sin and cos as an absolute error (their
 * relative error is unbounded near their zeros, as libm's own), pow relative to
 * |y log x| + 1 (the error of exp(y log x)). */
TEST(device_math_float_against_libm)
{
    double e_exp = 0, e_log = 0, e_log1p = 0, e_sin = 0, e_cos = 0, e_tan = 0, e_acos = 0, e_atan2 = 0, e_cbrt = 0,
           e_pow = 0;
    uint64_t s = 1;
    for (int i = 0; i < 1000000; i++) {
        float u = lcgf(&s), v = lcgf(&s);
        float x = (u - 0.5f) * 190.0f; /* past both ends of float's exp: 0 and infinity */
        e_exp = fmax(e_exp, ulpsf(devmath_expf(x), expf(x)));
        float y = expf((u - 0.5f) * 200.0f); /* subnormals to 2^72 */
        e_log = fmax(e_log, ulpsf(devmath_logf(y), logf(y)));
        float z = (u - 0.5f) * 2e-3f * powf(10.0f, 6.0f * v);
        e_log1p = fmax(e_log1p, ulpsf(devmath_log1pf(z), log1pf(z)));
        float w = (u - 0.5f) * 200.0f;
        e_sin = fmax(e_sin, fabs((double)devmath_sinf(w) - (double)sinf(w)));
        e_cos = fmax(e_cos, fabs((double)devmath_cosf(w) - (double)cosf(w)));
        float t = (u - 0.5f) * 3.0f; /* tan on (-1.5, 1.5): the camera's half field of view */
        e_tan = fmax(e_tan, ulpsf(devmath_tanf(t), tanf(t)));
        float c = 2.0f * u - 1.0f;
        e_acos = fmax(e_acos, ulpsf(devmath_acosf(c), acosf(c)));
        float a = (u - 0.5f) * 50.0f, b = (v - 0.5f) * 6.0f;
        e_atan2 = fmax(e_atan2, ulpsf(devmath_atan2f(a, b), atan2f(a, b)));
        float q = (u - 0.5f) * 1e6f;
        e_cbrt = fmax(e_cbrt, ulpsf(devmath_cbrtf(q), cbrtf(q)));
        float px = u * 10.0f, py = (v - 0.5f) * 40.0f;
        float ref = powf(px, py);
        if (ref > 0.0f && isfinite(ref))
            e_pow = fmax(e_pow, ulpsf(devmath_powf(px, py), ref) / (fabs((double)py * log((double)px)) + 1.0));
    }
    printf("max error: expf %.2f logf %.2f log1pf %.2f tanf %.2f acosf %.2f atan2f %.2f cbrtf %.2f ulp; powf %.2f ulp "
           "per unit of |y ln x| + 1; sinf %.3g cosf %.3g absolute\n",
           e_exp, e_log, e_log1p, e_tan, e_acos, e_atan2, e_cbrt, e_pow, e_sin, e_cos);
    ASSERT_TRUE(e_exp <= DEVMATH_MAX_ULPF && e_log <= DEVMATH_MAX_ULPF && e_log1p <= DEVMATH_MAX_ULPF);
    ASSERT_TRUE(e_tan <= DEVMATH_MAX_ULPF && e_acos <= DEVMATH_MAX_ULPF && e_atan2 <= DEVMATH_MAX_ULPF);
    ASSERT_TRUE(e_cbrt <= DEVMATH_MAX_ULPF && e_pow <= DEVMATH_MAX_ULPF);
    /* 2^-22: two units in the last place of a float in [1/2, 1) */
    ASSERT_TRUE(e_sin <= 0x1p-22 && e_cos <= 0x1p-22);
    /* special values the estimator can meet */
    ASSERT_TRUE(devmath_expf(-INFINITY) == 0.0f && devmath_expf(INFINITY) == INFINITY && isnan(devmath_expf(NAN)));
    ASSERT_TRUE(devmath_expf(-100.0f) == expf(-100.0f)); /* a subnormal result */
    ASSERT_TRUE(devmath_logf(0.0f) == -INFINITY && isnan(devmath_logf(-1.0f)) && devmath_logf(1.0f) == 0.0f);
    ASSERT_TRUE(ulpsf(devmath_logf(1.4e-45f), logf(1.4e-45f)) <= DEVMATH_MAX_ULPF);
    ASSERT_TRUE(devmath_powf(0.0f, 2.0f) == 0.0f && devmath_powf(2.0f, 0.0f) == 1.0f && devmath_powf(-2.0f, 3.0f) == -8.0f);
    ASSERT_TRUE(devmath_nextafterf(1.0f, 2.0f) == nextafterf(1.0f, 2.0f) &&
                devmath_nextafterf(0.0f, 1.0f) == nextafterf(0.0f, 1.0f));
    ASSERT_TRUE(devmath_nextafterf(-1.0f, INFINITY) == nextafterf(-1.0f, INFINITY));
    ASSERT_TRUE(devmath_sinf(0.0f) == 0.0f && devmath_cosf(0.0f) == 1.0f && devmath_atan2f(0.0f, -1.0f) == atan2f(0.0f, -1.0f));
}

TEST_MAIN(device_math_float_against_libm)
