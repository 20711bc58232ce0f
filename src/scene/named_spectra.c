/* named_spectra.c - pbrt-v4's named material spectra as RGB.
 *
 * The spectra are pbrt-v4's tables (src/pbrt/util/spectrum.cpp, github.com/mmp/pbrt-v4, the
 * measured metal indices it takes from the literature and the Sellmeier fits of Schott's
 * glasses); only the numbers derived from them are kept here. A metal's eta(lambda) and
 * k(lambda) each become one RGB the way an RGB film sees a spectrum under the colour space's
 * white: XYZ = integral of S(lambda) D65(lambda) (x, y, z)(lambda) d lambda over the integral
 * of D65 y, 360-830 nm at 1 nm with the CIE 1931 2-degree matching functions and pbrt-v4's
 * D65 table (piecewise linear, extended flat past its ends as pbrt-v4 does), then XYZ to
 * linear Rec. 709 (a constant spectrum of 1 gives (1, 1, 1) to 3e-6). pbrt-v4 itself renders
 * the spectra wavelength by wavelength; the Fresnel reflectance brume computes from these RGB
 * indices differs from the RGB of pbrt-v4's spectral Fresnel reflectance, at normal incidence
 * and averaged over the hemisphere, by at most 0.047 (Au, red), 0.018 (CuZn), 0.012 (Cu),
 * 0.002 (Ag, Al), 1e-4 (MgO, TiO2): docs/surfaces.md, "Materials". A glass is not dispersive in brume: its index at
 * 550 nm, pbrt-v4's table interpolated there. */
#include "scene/named_spectra.h"

#include <string.h>

typedef struct named_spectrum {
    const char *name;
    double rgb[3];
} named_spectrum;

static const named_spectrum spectra[] = {
    {"metal-Ag-eta", {0.128470, 0.123528, 0.150892}},   {"metal-Ag-k", {4.064894, 3.286320, 2.391747}},
    {"metal-Al-eta", {1.407425, 0.926654, 0.584035}},   {"metal-Al-k", {7.740424, 6.602603, 5.360286}},
    {"metal-Au-eta", {0.080051, 0.404654, 1.561352}},   {"metal-Au-k", {3.390473, 2.503771, 1.770891}},
    {"metal-Cu-eta", {0.104495, 0.978170, 1.204670}},   {"metal-Cu-k", {3.273344, 2.592350, 2.369242}},
    {"metal-CuZn-eta", {0.418445, 0.519917, 1.123135}}, {"metal-CuZn-k", {3.667771, 2.680756, 1.771028}},
    {"metal-MgO-eta", {1.733721, 1.740942, 1.753544}},  {"metal-MgO-k", {0.0, 0.0, 0.0}},
    {"metal-TiO2-eta", {2.860387, 2.956484, 3.185533}}, {"metal-TiO2-k", {0.000089, 0.0, 0.000551}},
    {"glass-BK7", {1.518537, 1.518537, 1.518537}},      {"glass-BAF10", {1.673051, 1.673051, 1.673051}},
    {"glass-FK51A", {1.487796, 1.487796, 1.487796}},    {"glass-LASF9", {1.855809, 1.855809, 1.855809}},
    {"glass-F5", {1.677089, 1.677089, 1.677089}},       {"glass-F10", {1.733574, 1.733574, 1.733574}},
    {"glass-F11", {1.791119, 1.791119, 1.791119}},
};

bool named_spectrum_rgb(const char *name, double rgb[3])
{
    for (size_t i = 0; i < sizeof spectra / sizeof spectra[0]; i++)
        if (strcmp(spectra[i].name, name) == 0) {
            memcpy(rgb, spectra[i].rgb, 3 * sizeof rgb[0]);
            return true;
        }
    return false;
}

const char *named_spectrum_list(void)
{
    return "metal-{Ag,Al,Au,Cu,CuZn,MgO,TiO2}-{eta,k}, glass-{BK7,BAF10,FK51A,LASF9,F5,F10,F11}";
}
