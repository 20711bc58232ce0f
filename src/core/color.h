/* color.h - linear RGB (Rec. 709 primaries), BRUME_NSAMPLES samples per ray.
 * Every radiometric quantity (radiance, sigma_a, albedo, path weights) is a color.
 * Keep loops over BRUME_NSAMPLES rather than naming r, g, b, so a spectral build stays possible. */
#ifndef BRUME_CORE_COLOR_H
#define BRUME_CORE_COLOR_H

#include <math.h>
#include <stdbool.h>

#define BRUME_NSAMPLES 3

typedef struct color {
    double c[BRUME_NSAMPLES];
} color;

static inline color col(double v)
{
    color r;
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        r.c[i] = v;
    return r;
}
static inline color col_rgb(double r, double g, double b) { return (color){{r, g, b}}; }
static inline color col_add(color a, color b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] += b.c[i];
    return a;
}
static inline color col_sub(color a, color b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] -= b.c[i];
    return a;
}
static inline color col_mul(color a, color b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] *= b.c[i];
    return a;
}
static inline color col_div(color a, color b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] = b.c[i] != 0.0 ? a.c[i] / b.c[i] : 0.0;
    return a;
}
static inline color col_scale(color a, double s)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] *= s;
    return a;
}
/* a + b * s */
static inline color col_madd(color a, color b, double s)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] += b.c[i] * s;
    return a;
}
static inline color col_exp(color a)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] = exp(a.c[i]);
    return a;
}
static inline double col_avg(color a)
{
    double s = 0.0;
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        s += a.c[i];
    return s / BRUME_NSAMPLES;
}
static inline double col_max(color a)
{
    double m = a.c[0];
    for (int i = 1; i < BRUME_NSAMPLES; i++)
        m = a.c[i] > m ? a.c[i] : m;
    return m;
}
static inline double col_min(color a)
{
    double m = a.c[0];
    for (int i = 1; i < BRUME_NSAMPLES; i++)
        m = a.c[i] < m ? a.c[i] : m;
    return m;
}
static inline bool col_is_black(color a)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        if (a.c[i] != 0.0)
            return false;
    return true;
}
static inline bool col_isfinite(color a)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        if (!isfinite(a.c[i]))
            return false;
    return true;
}

#endif
