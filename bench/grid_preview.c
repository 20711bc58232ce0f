/* grid_preview.c - a quick look at a density grid for the docs: a ray march with
 * absorption, single scattering of one sun (shadow rays marched too) and a constant sky
 * term, written as an 8-bit sRGB PNG. Not the renderer: no multiple scattering, fixed
 * steps. Usage: grid_preview IN OUT.png [width height sigma_t]
 * (docs/grids.md has the command that made docs/images/gen-cloud.png). */
#include <png.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/error.h"
#include "io/grid_io.h"

static double srgb(double x)
{
    x = x < 0 ? 0 : (x > 1 ? 1 : x);
    return x <= 0.0031308 ? 12.92 * x : 1.055 * pow(x, 1 / 2.4) - 0.055;
}

/* Optical depth from p towards the sun, fixed steps. */
static double tau_to_sun(const density *d, vec3 p, vec3 sun, double step, double sigma_t)
{
    ray r = {p, sun, 0};
    double t0, t1, tau = 0;
    if (!box3_intersect(density_bounds(d), r, 0, INFINITY, &t0, &t1))
        return 0;
    for (double t = t0 + 0.5 * step; t < t1; t += step)
        tau += sigma_t * density_eval(d, ray_at(r, t)) * step;
    return tau;
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: grid_preview IN OUT.png [width height sigma_t]\n");
        return 2;
    }
    int w = argc > 4 ? atoi(argv[3]) : 512, h = argc > 4 ? atoi(argv[4]) : 288;
    double sigma_t = argc > 5 ? atof(argv[5]) : 60.0;
    density *d = density_load_file(argv[1], NULL);
    if (!d) {
        fprintf(stderr, "grid_preview: %s\n", err_message());
        return 1;
    }
    box3 b = density_bounds(d);
    vec3 c = v3_scale(v3_add(b.lo, b.hi), 0.5), e = v3_sub(b.hi, b.lo);
    double size = fmax(e.x, fmax(e.y, e.z));
    density_info in;
    density_get_info(d, &in);
    double step = 0.35 * size / fmax(in.n[0], fmax(in.n[1], in.n[2]));
    /* z up; camera below and to the side, looking slightly up at the cloud layer */
    vec3 eye = v3_add(c, v3(0.15 * size, -1.25 * size, -0.35 * size));
    vec3 fwd = v3_normalize(v3_sub(c, eye)), right = v3_normalize(v3_cross(fwd, v3(0, 0, 1)));
    vec3 up = v3_cross(right, fwd), sun = v3_normalize(v3(0.3, -0.4, 1.0));
    double tan_half = tan(0.5 * 36.0 * PI / 180.0), aspect = (double)w / h;
    const double sun_l[3] = {1.15, 1.08, 0.98}, sky_l[3] = {0.30, 0.42, 0.62}, albedo = 0.95;
    unsigned char *img = malloc((size_t)w * (size_t)h * 3);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double u = (2 * (x + 0.5) / w - 1) * tan_half * aspect, v = (1 - 2 * (y + 0.5) / h) * tan_half;
            ray r = {eye, v3_normalize(v3_add(fwd, v3_add(v3_scale(right, u), v3_scale(up, v)))), 0};
            /* sky: brighter towards the horizon */
            double hz = 1 - fmax(0, r.d.z);
            double L[3] = {0.25 + 0.35 * hz, 0.45 + 0.30 * hz, 0.85 + 0.1 * hz}, T = 1, S[3] = {0, 0, 0};
            double t0, t1;
            if (box3_intersect(b, r, 0, INFINITY, &t0, &t1)) {
                /* isotropic-ish phase with a forward lobe towards the sun (HG g = 0.5) */
                double cs = v3_dot(r.d, sun), g = 0.5;
                double ph = 0.3 / (4 * PI) + 0.7 * (1 - g * g) / (4 * PI * pow(1 + g * g - 2 * g * cs, 1.5));
                for (double t = t0 + 0.5 * step; t < t1 && T > 1e-3; t += step) {
                    vec3 p = ray_at(r, t);
                    double rho = density_eval(d, p);
                    if (rho <= 0)
                        continue;
                    double st = sigma_t * rho, dT = exp(-st * step);
                    double Ts = exp(-tau_to_sun(d, p, sun, 2 * step, sigma_t));
                    /* powder-free single scattering + a constant ambient for the multiple part */
                    for (int k = 0; k < 3; k++) {
                        double Lin = albedo * (4 * PI * ph * Ts * sun_l[k] + 0.55 * sky_l[k] + 0.35 * Ts);
                        S[k] += T * (1 - dT) * Lin;
                    }
                    T *= dT;
                }
            }
            for (int k = 0; k < 3; k++)
                img[3 * ((size_t)y * (size_t)w + (size_t)x) + (size_t)k] =
                    (unsigned char)lround(255 * srgb(0.8 * (S[k] + T * L[k])));
        }
    FILE *f = fopen(argv[2], "wb");
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, NULL, NULL, NULL);
    png_infop info = png_create_info_struct(png);
    if (!f || !png || !info || setjmp(png_jmpbuf(png))) {
        fprintf(stderr, "grid_preview: %s: cannot write\n", argv[2]);
        return 1;
    }
    png_init_io(png, f);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    for (int y = 0; y < h; y++)
        png_write_row(png, img + (size_t)y * (size_t)w * 3);
    png_write_end(png, NULL);
    png_destroy_write_struct(&png, &info);
    fclose(f);
    free(img);
    density_release(d);
    return 0;
}
