/* film_sensor.h - the film's sensor and white balance, pbrt-v4's Film "sensor" and
 * "whitebalance" (render.sensor, render.white_balance), as 3 x 3 maps of brume's linear
 * Rec. 709 radiance that every camera sample goes through (render/sample.h, sample_set).
 * Made on the host once a render (film_sensor.c); docs/pbrt.md, Film, derives them. */
#ifndef BRUME_SCENE_FILM_SENSOR_H
#define BRUME_SCENE_FILM_SENSOR_H

#include <stdbool.h>

/* Sensor 0 is pbrt-v4's "cie1931", the CIE observer; 1 .. the cameras pbrt-v4 names
 * ("canon_eos_100d", ..., data/pbrt_sensors.inc). film_sensor_find gives a name's number
 * (-1: unknown), film_sensor_name a number's name (NULL: none; brume_sensor_name too). */
int film_sensor_find(const char *name);
const char *film_sensor_name(int sensor);

/* The sensor's two maps (row-major) with the white balance kelvin (0: none; a camera then
 * balances to 6500 K, as pbrt-v4 does): sensor_from_rgb gives its values (CIE XYZ for
 * cie1931, a camera's raw r, g, b), which max_component clamps; film the output RGB (linear
 * Rec. 709) from the radiance. False when film is the identity (cie1931 without a balance). */
bool film_sensor_maps(int sensor, double kelvin, double sensor_from_rgb[9], double film[9]);

/* pbrt-v4's white balance of the cie1931 sensor: the chromaticity (x, y) of its source white
 * at `kelvin`, and the 3 x 3 (row-major) that maps linear Rec. 709 colours from that white to
 * D65's. */
void film_daylight_xy(double kelvin, double xy[2]);
void film_white_balance(double kelvin, double m[9]);

#endif
