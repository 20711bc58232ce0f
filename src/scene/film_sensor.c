/* film_sensor.c - pbrt-v4's film sensors (Film "sensor") and white balance as two 3 x 3 maps
 * of brume's linear Rec. 709 radiance (scene/film_sensor.h): the sensor's values, which
 * pbrt-v4's maxcomponentvalue clamps, and the film's output RGB. Host only: the maps are made
 * once a render and carried to every sample (render/sample.h, sample_set).
 *
 * pbrt-v4 (film.h, PixelSensor) records a camera's raw values r, g, b = integral of the
 * sensor's curves times the radiance spectrum, maps them to XYZ by a 3 x 3 XYZFromSensorRGB
 * that it fits by least squares over 24 ColorChecker swatches (lit by the white-balance
 * illuminant on the camera's side, by the colour space's D65 on the XYZ side, scaled so that
 * the illuminant's luminance is kept), then XYZ to the colour space's RGB. brume's radiance is
 * linear Rec. 709, so the camera's raw values of a colour c are estimated linearly, c times a
 * 3 x 3 fitted over the same 24 swatches lit by D65 (their Rec. 709 colours against the
 * camera's values), constrained to map brume's white exactly to the camera's values of pbrt-v4's
 * white (the D65 spectrum an rgb (1, 1, 1) light has): a grey scene is pbrt-v4's exactly, a
 * coloured one within the fit's residual. Derivation and figures: docs/pbrt.md, Film rows. */
#include "scene/film_sensor.h"

#include <math.h>
#include <string.h>

#include "brume.h"
#include "medium/blackbody.h"
#include "pbrt_sensors.inc" /* data/, on the include path */

#define LAMBDA_MIN 360 /* pbrt-v4's Lambda_min .. Lambda_max, nm: its sums over whole nm */
#define NLAMBDA 471

static const double xyz_from_rgb[9] = {0.4124564, 0.3575761, 0.1804375, 0.2126729, 0.7151522,
                                       0.0721750, 0.0193339, 0.1191920, 0.9503041};
static const double rgb_from_xyz[9] = {3.2404542, -1.5371385, -0.4985314, -0.9692660, 1.8760108,
                                       0.0415560, 0.0556434,  -0.2040259, 1.0572252};

int film_sensor_find(const char *name)
{
    if (strcmp(name, "cie1931") == 0)
        return 0;
    for (int i = 0; i < PBRT_SENSOR_CAMERAS; i++)
        if (strcmp(name, pbrt_cameras[i].name) == 0)
            return i + 1;
    return -1;
}

const char *brume_sensor_name(int sensor) { return film_sensor_name(sensor); }

const char *film_sensor_name(int sensor)
{
    if (sensor == 0)
        return "cie1931";
    return sensor >= 1 && sensor <= PBRT_SENSOR_CAMERAS ? pbrt_cameras[sensor - 1].name : NULL;
}

static void mat3_mul(const double a[9], const double b[9], double out[9])
{
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++)
            out[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
}

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

/* pbrt-v4's WhiteBalance (util/color.h): von Kries in Bradford's cone space, from the source
 * white to the colour space's (sRGB's D65, xy 0.3127, 0.3290), both of luminance 1; then,
 * since brume's colours are linear Rec. 709 and pbrt-v4's sensor values CIE XYZ, conjugated
 * by the Rec. 709 matrices: m = RGB_from_XYZ WB XYZ_from_RGB. */
void film_white_balance(double kelvin, double m[9])
{
    static const double lms_from_xyz[9] = {0.8951, 0.2664, -0.1614, -0.7502, 1.7135, 0.0367, 0.0389, -0.0685, 1.0296};
    static const double xyz_from_lms[9] = {0.986993,  -0.147054, 0.159963,  0.432305, 0.51836,
                                           0.0492912, -0.00852866, 0.0400428, 0.968487};
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

/* A spectrum given as interleaved (nm, value) pairs, n numbers, at whole nm 360 .. 830: as
 * pbrt-v4's PiecewiseLinearSpectrum::FromInterleaved, linear between its points and its end
 * values held out to 360 and 830 nm. */
static void sample_pairs(const double *v, int n, double out[NLAMBDA])
{
    int k = 0;
    for (int i = 0; i < NLAMBDA; i++) {
        double l = LAMBDA_MIN + i;
        if (l <= v[0]) {
            out[i] = v[1];
            continue;
        }
        if (l >= v[n - 2]) {
            out[i] = v[n - 1];
            continue;
        }
        while (v[2 * k + 2] < l)
            k++;
        double t = (l - v[2 * k]) / (v[2 * k + 2] - v[2 * k]);
        out[i] = (1.0 - t) * v[2 * k + 1] + t * v[2 * k + 3];
    }
}

/* pbrt-v4's white-balance illuminant Spectra::D(kelvin), up to a scale (which cancels): the
 * temperature times 1.4388 / 1.4380 as the correlated colour temperature; below 4000 K the
 * blackbody, from 4000 K the CIE daylight S0 + M1 S1 + M2 S2 at the daylight locus' point. */
static void daylight(double kelvin, double out[NLAMBDA])
{
    double cct = kelvin * 1.4388 / 1.4380;
    if (cct < 4000.0) {
        const double c = 299792458.0, h = 6.62606957e-34, kb = 1.3806488e-23;
        for (int i = 0; i < NLAMBDA; i++) {
            double l = (LAMBDA_MIN + i) * 1e-9;
            out[i] = 2.0 * h * c * c / (pow(l, 5) * (exp(h * c / (l * kb * cct)) - 1.0));
        }
        return;
    }
    double xy[2];
    film_daylight_xy(kelvin, xy);
    double x = xy[0], y = xy[1], M = 0.0241 + 0.2562 * x - 0.7341 * y;
    double M1 = (-1.3515 - 1.7703 * x + 5.9114 * y) / M, M2 = (0.0300 - 31.4424 * x + 30.0717 * y) / M;
    double pairs[2 * 107];
    for (int i = 0; i < 107; i++) {
        pairs[2 * i] = pbrt_cie_s_lambda[i];
        pairs[2 * i + 1] = pbrt_cie_s0[i] + M1 * pbrt_cie_s1[i] + M2 * pbrt_cie_s2[i];
    }
    sample_pairs(pairs, 2 * 107, out);
}

/* The sum over whole nm of a b c, pbrt-v4's ProjectReflectance and InnerProduct. */
static double dot3(const double *a, const double *b, const double *c)
{
    double s = 0.0;
    for (int i = 0; i < NLAMBDA; i++)
        s += a[i] * b[i] * (c ? c[i] : 1.0);
    return s;
}

static bool mat3_inverse(const double m[9], double out[9])
{
    double c[9] = {m[4] * m[8] - m[5] * m[7], m[2] * m[7] - m[1] * m[8], m[1] * m[5] - m[2] * m[4],
                   m[5] * m[6] - m[3] * m[8], m[0] * m[8] - m[2] * m[6], m[2] * m[3] - m[0] * m[5],
                   m[3] * m[7] - m[4] * m[6], m[1] * m[6] - m[0] * m[7], m[0] * m[4] - m[1] * m[3]};
    double det = m[0] * c[0] + m[1] * c[3] + m[2] * c[6];
    if (!(fabs(det) > 0.0))
        return false;
    for (int i = 0; i < 9; i++)
        out[i] = c[i] / det;
    return true;
}

/* The 3 x 3 m (row-major) with m a_i closest to b_i over the n rows in the least-squares sense
 * (pbrt-v4's LinearLeastSquares: the normal equations); with w, exactly m 1 = w (a Lagrange
 * multiplier per row of m). */
static bool fit3(const double (*a)[3], const double (*b)[3], int n, const double *w, double m[9])
{
    double G[9] = {0}, H[9] = {0}, Gi[9];
    for (int i = 0; i < n; i++)
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) {
                G[3 * r + c] += a[i][r] * a[i][c];
                H[3 * r + c] += a[i][r] * b[i][c];
            }
    if (!mat3_inverse(G, Gi))
        return false;
    for (int k = 0; k < 3; k++) {
        double row[3], g1[3], mu = 0.0;
        for (int r = 0; r < 3; r++) {
            row[r] = Gi[3 * r] * H[k] + Gi[3 * r + 1] * H[3 + k] + Gi[3 * r + 2] * H[6 + k];
            g1[r] = Gi[3 * r] + Gi[3 * r + 1] + Gi[3 * r + 2];
        }
        if (w)
            mu = (row[0] + row[1] + row[2] - w[k]) / (g1[0] + g1[1] + g1[2]);
        for (int r = 0; r < 3; r++)
            m[3 * k + r] = row[r] - mu * g1[r];
    }
    return true;
}

/* The camera's curves, the CIE matching functions and D65 at whole nm. */
typedef struct sensor_spectra {
    double curve[3][NLAMBDA], cmf[3][NLAMBDA], d65[NLAMBDA];
} sensor_spectra;

static void sensor_spectra_make(int camera, sensor_spectra *sp)
{
    const struct pbrt_camera_curves *cc = &pbrt_cameras[camera];
    for (int c = 0; c < 3; c++)
        sample_pairs(cc->v[c], cc->n[c], sp->curve[c]);
    memcpy(sp->cmf[0], pbrt_cie_x, sizeof sp->cmf[0]);
    memcpy(sp->cmf[1], pbrt_cie_y, sizeof sp->cmf[1]);
    memcpy(sp->cmf[2], pbrt_cie_z, sizeof sp->cmf[2]);
    sample_pairs(pbrt_d65, (int)(sizeof pbrt_d65 / sizeof pbrt_d65[0]), sp->d65);
}

/* pbrt-v4's XYZFromSensorRGB for the camera under the illuminant ill (PixelSensor's
 * constructor): the swatches' camera values under ill over the camera's g of ill, against
 * their XYZ under D65 over D65's Y, times ill's Y over its g. */
static bool camera_xyz_from_raw(const sensor_spectra *sp, const double ill[NLAMBDA], double m[9])
{
    double cam[24][3], xyz[24][3], refl[NLAMBDA];
    double g_ill = dot3(sp->curve[1], ill, NULL), y_ill = dot3(sp->cmf[1], ill, NULL);
    double y_w = dot3(sp->cmf[1], sp->d65, NULL);
    for (int i = 0; i < 24; i++) {
        sample_pairs(pbrt_swatches[i], (int)(sizeof pbrt_swatches[i] / sizeof pbrt_swatches[i][0]), refl);
        for (int c = 0; c < 3; c++) {
            cam[i][c] = dot3(sp->curve[c], refl, ill) / g_ill;
            xyz[i][c] = dot3(sp->cmf[c], refl, sp->d65) / y_w * (y_ill / g_ill);
        }
    }
    return fit3((const double (*)[3])cam, (const double (*)[3])xyz, 24, NULL, m);
}

/* brume's uplift: the camera's raw values of a linear Rec. 709 colour, the 3 x 3 that maps the
 * 24 swatches' Rec. 709 colours under D65 to the camera's values of them (both over D65's Y),
 * white held exactly. */
static bool camera_raw_from_rgb(const sensor_spectra *sp, double m[9])
{
    double rgb[24][3], raw[24][3], white[3], refl[NLAMBDA];
    double y_w = dot3(sp->cmf[1], sp->d65, NULL);
    for (int i = 0; i < 24; i++) {
        sample_pairs(pbrt_swatches[i], (int)(sizeof pbrt_swatches[i] / sizeof pbrt_swatches[i][0]), refl);
        double xyz[3];
        for (int c = 0; c < 3; c++) {
            xyz[c] = dot3(sp->cmf[c], refl, sp->d65) / y_w;
            raw[i][c] = dot3(sp->curve[c], refl, sp->d65) / y_w;
        }
        for (int c = 0; c < 3; c++)
            rgb[i][c] = rgb_from_xyz[3 * c] * xyz[0] + rgb_from_xyz[3 * c + 1] * xyz[1] + rgb_from_xyz[3 * c + 2] * xyz[2];
    }
    for (int c = 0; c < 3; c++)
        white[c] = dot3(sp->curve[c], sp->d65, NULL) / y_w;
    return fit3((const double (*)[3])rgb, (const double (*)[3])raw, 24, white, m);
}

bool film_sensor_maps(int sensor, double kelvin, double sensor_from_rgb[9], double film[9])
{
    static const double identity[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    if (sensor <= 0 || sensor > PBRT_SENSOR_CAMERAS) {
        /* the cie1931 observer: the sensor's values are XYZ, the film white-balances them */
        memcpy(sensor_from_rgb, xyz_from_rgb, sizeof xyz_from_rgb);
        if (kelvin > 0.0)
            film_white_balance(kelvin, film);
        else
            memcpy(film, identity, sizeof identity);
        return kelvin > 0.0;
    }
    /* pbrt-v4 balances a camera to 6500 K when no white balance is given */
    double ill[NLAMBDA], xyz_raw[9], out_raw[9];
    sensor_spectra sp;
    sensor_spectra_make(sensor - 1, &sp);
    daylight(kelvin > 0.0 ? kelvin : 6500.0, ill);
    /* the fits fail only on swatches that span fewer than three dimensions, which the
       committed data does not (tests/test_pbrt_sensor.c fits every camera) */
    if (!camera_xyz_from_raw(&sp, ill, xyz_raw) || !camera_raw_from_rgb(&sp, sensor_from_rgb)) {
        memcpy(sensor_from_rgb, xyz_from_rgb, sizeof xyz_from_rgb);
        memcpy(film, identity, sizeof identity);
        return false;
    }
    mat3_mul(rgb_from_xyz, xyz_raw, out_raw);
    mat3_mul(out_raw, sensor_from_rgb, film);
    return true;
}
