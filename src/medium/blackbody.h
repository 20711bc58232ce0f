/* blackbody.h - the colour of blackbody emission (fire from a temperature grid).
 *
 * Convention (pbrt-v4's BlackbodySpectrum, used by its nanovdb medium): Planck's spectral
 * radiance B(lambda, T) normalized by its own peak, so the spectrum's maximum is 1 at every
 * temperature; integrated against the CIE 1931 2-degree observer over 360-830 nm and
 * divided by the integral of y-bar (a flat spectrum of 1 has Y = 1), then converted to
 * linear Rec. 709 RGB (D65 white). The colour matching functions are the CIE's table
 * (5 nm steps, read linearly in between). Units: T in kelvin; the result is a radiance
 * factor (dimensionless), multiplied by the medium's blackbody scale (radiance units).
 * Derivation and checks: docs/grids.md, "Fire: temperature and blackbody emission". */
#ifndef BRUME_MEDIUM_BLACKBODY_H
#define BRUME_MEDIUM_BLACKBODY_H

#include "core/color.h"

/* CIE XYZ of the peak-normalized blackbody at T kelvin (T > 0), 1 nm steps. Slow (470
 * wavelengths): for tables and tests. */
void blackbody_xyz(double T, double xyz[3]);
/* Linear Rec. 709 RGB of the same (may have small negative components far from white). */
color blackbody_rgb_exact(double T);
/* The same from a table built once (log-spaced in T over [400 K, 1e5 K] and [1e5 K, 1e7 K],
 * read geometrically in between where a channel keeps its sign; T^-4 above 1e7 K, as the
 * peak-normalized visible spectrum falls, pbrt-v4 setting no upper bound): for rendering.
 * blackbody_init() must have run (thread-safe). */
color blackbody_rgb(double T);
void blackbody_init(void);
/* Cycles' blackbody colour (Blender's Blackbody node and Principled Volume): the same
 * Planck colour scaled to a luminance (Rec. 709 Y) of 1, with T held within [800 K,
 * 12000 K] as Cycles holds it; negative components below about 1800 K, as in Cycles,
 * which does not clamp them in a volume. After blackbody_init. */
color blackbody_rgb_blender(double T);
/* The table blackbody_rgb interpolates (BLACKBODY_TABLE_N colors, after blackbody_init):
 * the GPU gets a copy (gpu/device_scene.c). */
#define BLACKBODY_TABLE_N 1024
const color *blackbody_table(void);

#endif
