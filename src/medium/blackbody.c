/* blackbody.c - Planck's law against the CIE 1931 observer, to linear Rec. 709 (blackbody.h). */
#include "medium/blackbody.h"

#include <pthread.h>

/* The CIE 1931 2-degree standard colour matching functions x-bar, y-bar, z-bar (CIE
 * 018:2019, ISO 11664-1) every 5 nm from 360 to 830 nm, read linearly in between (within
 * 3e-4 of the 1 nm table in every colour brume computes from them). */
#define CMF_N 95
static const double cmf[CMF_N][3] = {
    {0.0001299, 3.917e-06, 0.0006061}, /* 360 nm */
    {0.0002321, 6.965e-06, 0.001086}, /* 365 nm */
    {0.0004149, 1.239e-05, 0.001946}, /* 370 nm */
    {0.0007416, 2.202e-05, 0.003486}, /* 375 nm */
    {0.001368, 3.9e-05, 0.00645}, /* 380 nm */
    {0.002236, 6.4e-05, 0.01055}, /* 385 nm */
    {0.004243, 0.00012, 0.02005}, /* 390 nm */
    {0.00765, 0.000217, 0.03621}, /* 395 nm */
    {0.01431, 0.000396, 0.06785}, /* 400 nm */
    {0.02319, 0.00064, 0.1102}, /* 405 nm */
    {0.04351, 0.00121, 0.2074}, /* 410 nm */
    {0.07763, 0.00218, 0.3713}, /* 415 nm */
    {0.13438, 0.004, 0.6456}, /* 420 nm */
    {0.21477, 0.0073, 1.03905}, /* 425 nm */
    {0.2839, 0.0116, 1.3856}, /* 430 nm */
    {0.3285, 0.01684, 1.62296}, /* 435 nm */
    {0.34828, 0.023, 1.74706}, /* 440 nm */
    {0.34806, 0.0298, 1.7826}, /* 445 nm */
    {0.3362, 0.038, 1.77211}, /* 450 nm */
    {0.3187, 0.048, 1.7441}, /* 455 nm */
    {0.2908, 0.06, 1.6692}, /* 460 nm */
    {0.2511, 0.0739, 1.5281}, /* 465 nm */
    {0.19536, 0.09098, 1.28764}, /* 470 nm */
    {0.1421, 0.1126, 1.0419}, /* 475 nm */
    {0.09564, 0.13902, 0.81295}, /* 480 nm */
    {0.05795, 0.1693, 0.6162}, /* 485 nm */
    {0.03201, 0.20802, 0.46518}, /* 490 nm */
    {0.0147, 0.2586, 0.3533}, /* 495 nm */
    {0.0049, 0.323, 0.272}, /* 500 nm */
    {0.0024, 0.4073, 0.2123}, /* 505 nm */
    {0.0093, 0.503, 0.1582}, /* 510 nm */
    {0.0291, 0.6082, 0.1117}, /* 515 nm */
    {0.06327, 0.71, 0.07825}, /* 520 nm */
    {0.1096, 0.7932, 0.05725}, /* 525 nm */
    {0.1655, 0.862, 0.04216}, /* 530 nm */
    {0.22575, 0.91485, 0.02984}, /* 535 nm */
    {0.2904, 0.954, 0.0203}, /* 540 nm */
    {0.3597, 0.9803, 0.0134}, /* 545 nm */
    {0.43345, 0.99495, 0.00875}, /* 550 nm */
    {0.51205, 1, 0.00575}, /* 555 nm */
    {0.5945, 0.995, 0.0039}, /* 560 nm */
    {0.6784, 0.9786, 0.00275}, /* 565 nm */
    {0.7621, 0.952, 0.0021}, /* 570 nm */
    {0.8425, 0.9154, 0.0018}, /* 575 nm */
    {0.9163, 0.87, 0.00165}, /* 580 nm */
    {0.9786, 0.8163, 0.0014}, /* 585 nm */
    {1.0263, 0.757, 0.0011}, /* 590 nm */
    {1.0567, 0.6949, 0.001}, /* 595 nm */
    {1.0622, 0.631, 0.0008}, /* 600 nm */
    {1.0456, 0.5668, 0.0006}, /* 605 nm */
    {1.0026, 0.503, 0.00034}, /* 610 nm */
    {0.9384, 0.4412, 0.00024}, /* 615 nm */
    {0.85445, 0.381, 0.00019}, /* 620 nm */
    {0.7514, 0.321, 0.0001}, /* 625 nm */
    {0.6424, 0.265, 5e-05}, /* 630 nm */
    {0.5419, 0.217, 3e-05}, /* 635 nm */
    {0.4479, 0.175, 2e-05}, /* 640 nm */
    {0.3608, 0.1382, 1e-05}, /* 645 nm */
    {0.2835, 0.107, 0}, /* 650 nm */
    {0.2187, 0.0816, 0}, /* 655 nm */
    {0.1649, 0.061, 0}, /* 660 nm */
    {0.1212, 0.04458, 0}, /* 665 nm */
    {0.0874, 0.032, 0}, /* 670 nm */
    {0.0636, 0.0232, 0}, /* 675 nm */
    {0.04677, 0.017, 0}, /* 680 nm */
    {0.0329, 0.01192, 0}, /* 685 nm */
    {0.0227, 0.00821, 0}, /* 690 nm */
    {0.01584, 0.005723, 0}, /* 695 nm */
    {0.0113592, 0.004102, 0}, /* 700 nm */
    {0.00811092, 0.002929, 0}, /* 705 nm */
    {0.00579035, 0.002091, 0}, /* 710 nm */
    {0.00410946, 0.001484, 0}, /* 715 nm */
    {0.00289933, 0.001047, 0}, /* 720 nm */
    {0.00204919, 0.00074, 0}, /* 725 nm */
    {0.00143997, 0.00052, 0}, /* 730 nm */
    {0.000999949, 0.0003611, 0}, /* 735 nm */
    {0.000690079, 0.0002492, 0}, /* 740 nm */
    {0.000476021, 0.0001719, 0}, /* 745 nm */
    {0.000332301, 0.00012, 0}, /* 750 nm */
    {0.000234826, 8.48e-05, 0}, /* 755 nm */
    {0.000166151, 6e-05, 0}, /* 760 nm */
    {0.000117413, 4.24e-05, 0}, /* 765 nm */
    {8.30753e-05, 3e-05, 0}, /* 770 nm */
    {5.87065e-05, 2.12e-05, 0}, /* 775 nm */
    {4.15099e-05, 1.499e-05, 0}, /* 780 nm */
    {2.93533e-05, 1.06e-05, 0}, /* 785 nm */
    {2.06738e-05, 7.4657e-06, 0}, /* 790 nm */
    {1.45598e-05, 5.2578e-06, 0}, /* 795 nm */
    {1.0254e-05, 3.7029e-06, 0}, /* 800 nm */
    {7.22146e-06, 2.6078e-06, 0}, /* 805 nm */
    {5.08587e-06, 1.8366e-06, 0}, /* 810 nm */
    {3.58165e-06, 1.2934e-06, 0}, /* 815 nm */
    {2.52253e-06, 9.1093e-07, 0}, /* 820 nm */
    {1.77651e-06, 6.4153e-07, 0}, /* 825 nm */
    {1.25114e-06, 4.5181e-07, 0}, /* 830 nm */
};

static void cie_xyz(int lambda_nm, double out[3])
{
    int i = (lambda_nm - 360) / 5;
    double f = (lambda_nm - 360 - 5 * i) / 5.0;
    if (i >= CMF_N - 1) {
        i = CMF_N - 2;
        f = 1.0;
    }
    for (int c = 0; c < 3; c++)
        out[c] = cmf[i][c] * (1.0 - f) + cmf[i + 1][c] * f;
}

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
        double s = planck(l, T) / peak, c[3];
        cie_xyz(l, c);
        X += s * c[0];
        Y += s * c[1];
        Z += s * c[2];
        Yw += c[1];
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

/* The table: BB_NMID + 1 colours log-spaced over [BB_TMIN, BB_TMID], then the rest over
 * [BB_TMID, BB_TMAX]; beyond BB_TMAX the colour goes as T^-4 from the last entry (the
 * Rayleigh-Jeans limit of the peak-normalized visible spectrum), below BB_TMIN it is the first
 * entry (a visible emission under 1e-25). Between entries each channel is read geometrically
 * where both entries have its sign (exact for a power law, and for the Wien tail exp(-a/T)
 * off by a relative h^2 a / 8 T for a step h of ln T), linearly where the sign changes. */
#define BB_N BLACKBODY_TABLE_N
#define BB_TMIN 400.0
#define BB_TMID 100000.0
#define BB_TMAX 10000000.0
#define BB_NMID 895
#if defined(__CUDA_ARCH__)
/* the GPU's copy, uploaded with the scene (gpu/kernel.cu, gpu/device_scene.c) */
#define table ((color *)brume_device_blackbody)
#else
static color table[BB_N];
#endif
static pthread_once_t once = PTHREAD_ONCE_INIT;

static void build(void)
{
    for (int i = 0; i <= BB_NMID; i++)
        table[i] = blackbody_rgb_exact(BB_TMIN * pow(BB_TMID / BB_TMIN, (double)i / BB_NMID));
    for (int i = BB_NMID + 1; i < BB_N; i++)
        table[i] = blackbody_rgb_exact(BB_TMID * pow(BB_TMAX / BB_TMID, (double)(i - BB_NMID) / (BB_N - 1 - BB_NMID)));
}

void blackbody_init(void) { pthread_once(&once, build); }

color blackbody_rgb(double T)
{
    if (!(T > BB_TMIN))
        return table[0];
    if (T >= BB_TMAX) {
        double r = BB_TMAX / T;
        return col_scale(table[BB_N - 1], r * r * r * r);
    }
    double x = T <= BB_TMID ? log(T / BB_TMIN) / log(BB_TMID / BB_TMIN) * BB_NMID
                            : BB_NMID + log(T / BB_TMID) / log(BB_TMAX / BB_TMID) * (BB_N - 1 - BB_NMID);
    int i = (int)x;
    i = i >= BB_N - 1 ? BB_N - 2 : i;
    double f = x - i;
    color c;
    for (int k = 0; k < BRUME_NSAMPLES; k++) {
        double a = table[i].c[k], b = table[i + 1].c[k];
        c.c[k] = a * b > 0.0 ? a * pow(b / a, f) : a * (1.0 - f) + b * f;
    }
    return c;
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
