/* film_white.c - pbrt-v4's white balance for its cie1931 sensor, as a 3 x 3 map of linear
 * Rec. 709 colours (render/film.h). Host only: the map is made once a render and carried to
 * every sample (render/sample.h, sample_set). */
#include "render/film.h"

#include <math.h>

#include "medium/blackbody.h"

/* pbrt-v4's source white (Spectra::D): the temperature is turned into a correlated colour
 * temperature by 1.4388 / 1.4380 (the second radiation constant's old and new values);
 * below 4000 K the blackbody's chromaticity, from 4000 K the CIE daylight locus (CIE 15:
 * x_D a cubic in 1 / T, y_D = -3 x_D^2 + 2.870 x_D - 0.275). pbrt-v4 integrates the D
 * spectrum made from that point over the colour matching functions, which gives the point
 * back within the spectrum's 10 nm tabulation; brume takes the point. */
void film_daylight_xy(double kelvin, double xy[2])
{
    double cct = kelvin * 1.4388 / 1.4380;
    if (cct < 4000.0) {
        double xyz[3];
        blackbody_xyz(cct, xyz);
        double s = xyz[0] + xyz[1] + xyz[2];
        xy[0] = xyz[0] / s;
        xy[1] = xyz[1] / s;
        return;
    }
    double t = 1.0 / cct, x;
    if (cct <= 7000.0)
        x = -4.607e9 * t * t * t + 2.9678e6 * t * t + 0.09911e3 * t + 0.244063;
    else
        x = -2.0064e9 * t * t * t + 1.9018e6 * t * t + 0.24748e3 * t + 0.23704;
    xy[0] = x;
    xy[1] = -3.0 * x * x + 2.870 * x - 0.275;
}

static void mat3_mul(const double a[9], const double b[9], double out[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}

/* pbrt-v4's WhiteBalance (util/color.h): von Kries in Bradford's cone space, from the source
 * white to the colour space's (sRGB's D65, xy 0.3127, 0.3290), both of luminance 1; then,
 * since brume's colours are linear Rec. 709 and pbrt-v4's sensor values CIE XYZ, conjugated
 * by the Rec. 709 matrices: m = RGB_from_XYZ WB XYZ_from_RGB. */
void film_white_balance(double kelvin, double m[9])
{
    static const double lms_from_xyz[9] = {0.8951, 0.2664, -0.1614, -0.7502, 1.7135, 0.0367, 0.0389, -0.0685, 1.0296};
    static const double xyz_from_lms[9] = {0.986993,  -0.147054, 0.159963,  0.432305, 0.51836,
                                           0.0492912, -0.00852866, 0.0400428, 0.968487};
    static const double xyz_from_rgb[9] = {0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522,
                                           0.0721750, 0.0193339, 0.1191920, 0.9503041};
    static const double rgb_from_xyz[9] = {3.2404542, -1.5371385, -0.4985314, -0.9692660, 1.8760108,
                                           0.0415560, 0.0556434,  -0.2040259, 1.0572252};
    double src[2], dst[2] = {0.3127, 0.3290};
    film_daylight_xy(kelvin, src);
    const double sx[3] = {src[0] / src[1], 1.0, (1.0 - src[0] - src[1]) / src[1]};
    const double dx[3] = {dst[0] / dst[1], 1.0, (1.0 - dst[0] - dst[1]) / dst[1]};
    double d[9] = {0};
    for (int r = 0; r < 3; r++) {
        double s = 0.0, t = 0.0;
        for (int c = 0; c < 3; c++) {
            s += lms_from_xyz[3 * r + c] * sx[c];
            t += lms_from_xyz[3 * r + c] * dx[c];
        }
        d[4 * r] = t / s;
    }
    double a[9], b[9], wb[9];
    mat3_mul(d, lms_from_xyz, a);
    mat3_mul(xyz_from_lms, a, wb);
    mat3_mul(wb, xyz_from_rgb, b);
    mat3_mul(rgb_from_xyz, b, m);
}
