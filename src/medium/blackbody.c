/* blackbody.c - Planck's law against the CIE 1931 observer, to linear Rec. 709 (blackbody.h). */
#include "medium/blackbody.h"

#include <pthread.h>

/* Wyman, Sloan, Shirley 2013, "Simple Analytic Approximations to the CIE XYZ Color
 * Matching Functions", multi-lobe fit: piecewise gaussians with a different width on each
 * side of the mean. */
static double lobe(double l, double mu, double s1, double s2)
{
    double t = (l - mu) / (l < mu ? s1 : s2);
    return exp(-0.5 * t * t);
}
static double cie_x(double l)
{
    return 1.056 * lobe(l, 599.8, 37.9, 31.0) + 0.362 * lobe(l, 442.0, 16.0, 26.7) - 0.065 * lobe(l, 501.1, 20.4, 26.2);
}
static double cie_y(double l) { return 0.821 * lobe(l, 568.8, 46.9, 40.5) + 0.286 * lobe(l, 530.9, 16.3, 31.1); }
static double cie_z(double l) { return 1.217 * lobe(l, 437.0, 11.8, 36.0) + 0.681 * lobe(l, 459.0, 26.0, 13.8); }

/* Planck's law, lambda in nm, up to a constant factor (it cancels in the normalization). */
static double planck(double lambda_nm, double T)
{
    const double c2 = 1.4387769e-2; /* h c / k, m K (CODATA 2018) */
    double l = lambda_nm * 1e-9;
    return 1.0 / (l * l * l * l * l * expm1(c2 / (l * T)));
}

void blackbody_xyz(double T, double xyz[3])
{
    /* Wien's displacement law gives the peak: lambda_max = b / T, b = 2.897771955e-3 m K */
    double peak = planck(2.897771955e-3 / T * 1e9, T);
    double X = 0.0, Y = 0.0, Z = 0.0, Yw = 0.0;
    for (int l = 360; l <= 830; l++) {
        double s = planck(l, T) / peak;
        X += s * cie_x(l);
        Y += s * cie_y(l);
        Z += s * cie_z(l);
        Yw += cie_y(l);
    }
    xyz[0] = X / Yw;
    xyz[1] = Y / Yw;
    xyz[2] = Z / Yw;
}

color blackbody_rgb_exact(double T)
{
    double v[3];
    blackbody_xyz(T, v);
    /* XYZ -> linear Rec. 709 (sRGB primaries, D65), IEC 61966-2-1 */
    return col_rgb(3.2404542 * v[0] - 1.5371385 * v[1] - 0.4985314 * v[2],
                   -0.9692660 * v[0] + 1.8760108 * v[1] + 0.0415560 * v[2],
                   0.0556434 * v[0] - 0.2040259 * v[1] + 1.0572252 * v[2]);
}

#define BB_N BLACKBODY_TABLE_N
#define BB_TMIN 100.0
#define BB_TMAX 100000.0
#if defined(__CUDA_ARCH__)
/* the GPU's copy, uploaded with the scene (gpu/kernel.cu, gpu/device_scene.c) */
#define table ((color *)brume_device_blackbody)
#else
static color table[BB_N];
#endif
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void build(void)
{
    for (int i = 0; i < BB_N; i++)
        table[i] = blackbody_rgb_exact(BB_TMIN * pow(BB_TMAX / BB_TMIN, (double)i / (BB_N - 1)));
}

void blackbody_init(void) { pthread_once(&once, build); }

color blackbody_rgb(double T)
{
    double x = log(T / BB_TMIN) / log(BB_TMAX / BB_TMIN) * (BB_N - 1);
    if (!(x > 0.0))
        return table[0];
    if (x >= BB_N - 1)
        return table[BB_N - 1];
    int i = (int)x;
    double f = x - i;
    return col_add(col_scale(table[i], 1.0 - f), col_scale(table[i + 1], f));
}

color blackbody_rgb_blender(double T)
{
    color c = blackbody_rgb(T < 800.0 ? 800.0 : (T > 12000.0 ? 12000.0 : T));
    double Y = 0.2126729 * c.c[0] + 0.7151522 * c.c[1] + 0.0721750 * c.c[2];
    return col_scale(c, 1.0 / Y);
}

const color *blackbody_table(void)
{
    blackbody_init();
    return table;
}
