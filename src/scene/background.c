/* background.c - constant and environment-image backgrounds (latitude-longitude and
 * equal-area octahedral) with importance sampling. */
#include "scene/background.h"

#include <stddef.h>
#include <stdlib.h>

#include "core/sampling.h"
#include "core/arena.h"
#include "image/image.h"

bool background_init(background *b)
{
    b->has_dist = false;
    if (!b->img)
        return true;
    if (b->mapping == BG_LATLONG) {
        b->up = v3_normalize(b->up);
        b->f = frame_from_n(b->up);
    }
    int w = b->img->width, h = b->img->height;
    double *f = malloc(sizeof *f * (size_t)w * (size_t)h);
    if (!f)
        return false;
    for (int y = 0; y < h; y++) {
        /* a lat-long row's solid angle per pixel goes as sin(theta); an equal-area texel's
           is the same everywhere */
        double area = b->mapping == BG_LATLONG ? sin(PI * (y + 0.5) / h) : 1.0;
        for (int x = 0; x < w; x++) {
            const float *px = b->img->rgba + 4 * ((size_t)y * (size_t)w + (size_t)x);
            color c = col_rgb((double)px[0], (double)px[1], (double)px[2]);
            f[(size_t)y * (size_t)w + (size_t)x] = fmax(0.0, col_avg(c)) * area;
        }
    }
    b->has_dist = distrib2_init(&b->dist, f, w, h) != 0;
    free(f);
    return b->has_dist;
}

void background_release(background *b)
{
    if (b->has_dist)
        distrib2_free(&b->dist);
    b->has_dist = false;
    brume_image_release(b->img);
    b->img = NULL;
}

bool background_is_black(const background *b) { return !b->img && col_is_black(b->L); }

vec3 bg_equal_area_to_sphere(double u, double v)
{
    double a = 2.0 * u - 1.0, c = 2.0 * v - 1.0;
    double ap = fabs(a), cp = fabs(c);
    double signed_distance = 1.0 - (ap + cp); /* from the diagonal: > 0 on the upper half */
    double r = 1.0 - fabs(signed_distance);
    double phi = (r == 0.0 ? 1.0 : (cp - ap) / r + 1.0) * PI / 4.0;
    double z = copysign(1.0 - r * r, signed_distance);
    double k = r * sqrt(fmax(0.0, 2.0 - r * r));
    return v3(copysign(cos(phi), a) * k, copysign(sin(phi), c) * k, z);
}

void bg_sphere_to_equal_area(vec3 w, double *u, double *v)
{
    double x = fabs(w.x), y = fabs(w.y), z = fabs(w.z);
    double r = sqrt(fmax(0.0, 1.0 - z));
    double a = fmax(x, y), b = fmin(x, y);
    double phi = a == 0.0 ? 0.0 : atan2(b, a) * 2.0 / PI; /* atan(b / a), b <= a */
    if (x < y)
        phi = 1.0 - phi;
    double pv = phi * r, pu = r - pv;
    if (w.z < 0.0) { /* the lower hemisphere: the corners, mirrored across the diagonal */
        double t = pu;
        pu = 1.0 - pv;
        pv = 1.0 - t;
    }
    *u = 0.5 * (copysign(pu, w.x) + 1.0);
    *v = 0.5 * (copysign(pv, w.y) + 1.0);
}

static void dir_to_uv(const background *b, vec3 w, double *u, double *v)
{
    vec3 l = frame_to_local(&b->f, w);
    if (b->mapping == BG_EQUAL_AREA) {
        bg_sphere_to_equal_area(v3_normalize(l), u, v);
        return;
    }
    double theta = acos(fmin(1.0, fmax(-1.0, l.z)));
    double phi = atan2(l.y, l.x);
    *u = (phi + PI) / (2.0 * PI);
    *v = theta / PI;
    if (*u >= 1.0)
        *u = 0.0;
}

color background_eval(const background *b, vec3 w)
{
    if (!b->img)
        return b->L;
    double u, v;
    dir_to_uv(b, w, &u, &v);
    int x = (int)(u * b->img->width), y = (int)(v * b->img->height);
    x = x < 0 ? 0 : (x >= b->img->width ? b->img->width - 1 : x);
    y = y < 0 ? 0 : (y >= b->img->height ? b->img->height - 1 : y);
    const float *px = b->img->rgba + 4 * ((size_t)y * (size_t)b->img->width + (size_t)x);
    return col_scale(col_rgb((double)px[0], (double)px[1], (double)px[2]), b->scale);
}

vec3 background_sample(const background *b, double u1, double u2, double *pdf, color *L)
{
    if (!b->img) {
        *pdf = INV_4PI;
        *L = b->L;
        return sample_sphere(u1, u2);
    }
    double u, v, pdf_uv;
    distrib2_sample(&b->dist, u1, u2, &u, &v, &pdf_uv);
    vec3 w;
    if (b->mapping == BG_EQUAL_AREA) { /* the map's Jacobian: 4 pi steradians per unit square */
        w = frame_to_world(&b->f, bg_equal_area_to_sphere(u, v));
        *pdf = pdf_uv * INV_4PI;
    } else {
        double theta = v * PI, phi = u * 2.0 * PI - PI;
        double st = sin(theta);
        w = frame_to_world(&b->f, v3(st * cos(phi), st * sin(phi), cos(theta)));
        *pdf = st > 0.0 ? pdf_uv / (2.0 * PI * PI * st) : 0.0;
    }
    *L = background_eval(b, w);
    return w;
}

double background_pdf(const background *b, vec3 w)
{
    if (!b->img)
        return INV_4PI;
    double u, v;
    dir_to_uv(b, w, &u, &v);
    if (b->mapping == BG_EQUAL_AREA)
        return distrib2_pdf(&b->dist, u, v) * INV_4PI;
    double st = sin(v * PI);
    return st > 0.0 ? distrib2_pdf(&b->dist, u, v) / (2.0 * PI * PI * st) : 0.0;
}

void background_device_fix(const background *b, dev_arena *a, size_t at)
{
    size_t img = ARENA_NULL;
    if (b->img) {
        img = arena_put(a, b->img, sizeof *b->img);
        ARENA_PUT_MEMBER(a, img, brume_image, rgba, b->img->rgba,
                         (size_t)b->img->width * (size_t)b->img->height * 4 * sizeof(float));
        for (int l = 0; l < IMAGE_MAX_LAYERS && img != ARENA_NULL; l++) /* not read by rendering */
            arena_ptr(a, img + offsetof(brume_image, layers) + (size_t)l * sizeof(image_layer) + offsetof(image_layer, px),
                      ARENA_NULL);
    }
    arena_ptr(a, at + offsetof(background, img), img);
    if (b->has_dist)
        distrib2_device_fix(&b->dist, a, at + offsetof(background, dist));
}
