/* compare.c - error figures between an image and a reference (over a region, with a
 * bootstrap interval), and signed difference pictures (brume.h, "comparing images"). */
#include "brume.h"

#include <cairo.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "io/atomic.h"
#include "core/rng.h"
#include "io/cairo_lib.h"
#include "io/chart.h"
#include "image/image.h"

#define TILE 8 /* the bootstrap's blocks, pixels a side */

static double lum(const float *p) { return 0.2126 * (double)p[0] + 0.7152 * (double)p[1] + 0.0722 * (double)p[2]; }

/* Both images hold light: finite, non-negative values (a NaN would make every figure NaN). */
static brume_status check_pair(const brume_image *img, const brume_image *ref)
{
    if (img->width != ref->width || img->height != ref->height)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "compare: image is %d x %d but the reference is %d x %d",
                       img->width, img->height, ref->width, ref->height);
    if (image_check_values(img, "the image", false) != BRUME_OK ||
        image_check_values(ref, "the reference", false) != BRUME_OK)
        return err_status();
    return BRUME_OK;
}

static brume_status diff_full(const brume_image *img, const brume_image *ref, brume_image_diff *o)
{
    brume_status bad = check_pair(img, ref);
    if (bad)
        return bad;
    long n = (long)img->width * img->height;
    double se = 0.0, sr = 0.0, si = 0.0, slum = 0.0;
    for (long i = 0; i < n; i++) {
        const float *a = img->rgba + 4 * i, *b = ref->rgba + 4 * i;
        for (int c = 0; c < 3; c++) {
            double d = (double)a[c] - (double)b[c];
            se += d * d;
            sr += (double)b[c];
            si += (double)a[c];
        }
        slum += lum(b);
    }
    o->pixels = n;
    o->rmse = sqrt(se / (3.0 * (double)n));
    o->mean_ref = sr / (3.0 * (double)n);
    o->mean_img = si / (3.0 * (double)n);
    o->rel_rmse = o->mean_ref > 0.0 ? o->rmse / o->mean_ref : HUGE_VAL;
    o->floor = 0.01 * slum / (double)n;
    double srel = 0.0, mrel = 0.0;
    long m = 0;
    for (long i = 0; i < n; i++) {
        double lr = lum(ref->rgba + 4 * i);
        if (lr <= o->floor)
            continue;
        double r = fabs(lum(img->rgba + 4 * i) - lr) / lr;
        srel += r;
        mrel = fmax(mrel, r);
        m++;
    }
    o->mean_rel = m ? srel / (double)m : 0.0;
    o->max_rel = mrel;
    return BRUME_OK;
}


/* Sums over one tile's pixels in the region: what every figure is made of. */
typedef struct tile_sums {
    double n, sa, sr, se; /* pixels; sums over channels of img, ref, (img - ref)^2 */
    double srel, nrel;    /* sum and count of the signed relative luminance differences */
} tile_sums;

static void figures_of(const tile_sums *t, double *fig)
{
    double mr = t->sr / (3.0 * t->n);
    fig[BRUME_FIG_RATIO] = mr > 0.0 ? t->sa / t->sr : HUGE_VAL;
    fig[BRUME_FIG_REL_RMSE] = mr > 0.0 ? sqrt(t->se / (3.0 * t->n)) / mr : HUGE_VAL;
    fig[BRUME_FIG_SIGNED_REL] = t->nrel > 0.0 ? t->srel / t->nrel : 0.0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sums the region's pixels per 8 x 8 tile into t (tw tiles a row); floor: signed_rel's. */
static void tile_accumulate(const brume_image *img, const brume_image *ref, const unsigned char *mask, double floor_,
                            int tw, tile_sums *t)
{
    int w = img->width, h = img->height;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            long i = (long)y * w + x;
            if (mask && !mask[i])
                continue;
            tile_sums *s = &t[(y / TILE) * tw + x / TILE];
            const float *a = img->rgba + 4 * i, *b = ref->rgba + 4 * i;
            s->n += 1.0;
            for (int c = 0; c < 3; c++) {
                double d = (double)a[c] - (double)b[c];
                s->se += d * d;
                s->sa += (double)a[c];
                s->sr += (double)b[c];
            }
            double lr = lum(b);
            if (lr > floor_) {
                s->srel += (lum(a) - lr) / lr;
                s->nrel += 1.0;
            }
        }
}

static void tile_add(tile_sums *s, const tile_sums *q)
{
    s->n += q->n, s->sa += q->sa, s->sr += q->sr, s->se += q->se;
    s->srel += q->srel, s->nrel += q->nrel;
}

/* The 95 % block-bootstrap interval of each figure over the nt packed tiles t. */
static brume_status bootstrap(const tile_sums *t, long nt, int boot, uint64_t seed, brume_region_stats *o)
{
    double *draws = boot > 0 ? malloc((size_t)boot * BRUME_NFIGS * sizeof *draws) : NULL;
    if (boot > 0 && !draws)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "compare: out of memory");
    for (int b = 0; b < boot; b++) {
        tile_sums s = {0};
        for (long k = 0; k < nt; k++) {
            uint64_t u = hash_mix64(hash_mix64(seed + UINT64_C(0x9e3779b97f4a7c15) * (uint64_t)(b + 1)) ^ (uint64_t)k);
            long j = (long)((double)(u >> 11) * 0x1p-53 * (double)nt);
            tile_add(&s, &t[j < nt ? j : nt - 1]);
        }
        double fig[BRUME_NFIGS];
        figures_of(&s, fig);
        for (int f = 0; f < BRUME_NFIGS; f++)
            draws[(size_t)f * (size_t)boot + (size_t)b] = fig[f];
    }
    for (int f = 0; f < BRUME_NFIGS && boot > 0; f++) {
        double *d = draws + (size_t)f * (size_t)boot;
        qsort(d, (size_t)boot, sizeof *d, cmp_double);
        o->lo[f] = d[(size_t)floor(0.025 * (boot - 1) + 0.5)];
        o->hi[f] = d[(size_t)floor(0.975 * (boot - 1) + 0.5)];
    }
    free(draws);
    return BRUME_OK;
}

static brume_status region_stats(const brume_image *img, const brume_image *ref, const unsigned char *mask, int boot,
                                  uint64_t seed, brume_region_stats *o)
{
    memset(o, 0, sizeof *o);
    brume_status bad = check_pair(img, ref);
    if (bad)
        return bad;
    if (boot < 0 || boot > 100000)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "compare: %d bootstrap draws outside [0, 100000]", boot);
    int w = img->width, h = img->height;
    long n = (long)w * h;
    double slum = 0.0;
    long m = 0;
    for (long i = 0; i < n; i++)
        if (!mask || mask[i]) {
            slum += lum(ref->rgba + 4 * i);
            m++;
        }
    if (m == 0)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "compare: the region holds no pixel");
    o->pixels = m;
    o->floor = 0.01 * slum / (double)m;
    int tw = (w + TILE - 1) / TILE, th = (h + TILE - 1) / TILE;
    tile_sums *t = calloc((size_t)tw * (size_t)th, sizeof *t);
    if (!t)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "compare: out of memory");
    tile_accumulate(img, ref, mask, o->floor, tw, t);
    /* keep the tiles that hold pixels of the region, packed */
    long nt = 0;
    tile_sums all = {0};
    for (long k = 0; k < (long)tw * th; k++)
        if (t[k].n > 0.0) {
            t[nt++] = t[k];
            tile_add(&all, &t[k]);
        }
    o->tiles = nt;
    o->mean_img = all.sa / (3.0 * all.n);
    o->mean_ref = all.sr / (3.0 * all.n);
    if (!(o->mean_ref > 0.0)) {
        free(t);
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "compare: the reference is black over the region");
    }
    figures_of(&all, o->fig);
    for (int f = 0; f < BRUME_NFIGS; f++)
        o->lo[f] = o->hi[f] = o->fig[f];
    brume_status st = bootstrap(t, nt, boot, seed, o);
    free(t);
    return st;
}

static brume_status mask_alpha(const brume_image *ref, double threshold, unsigned char **mask, long *count)
{
    long n = (long)ref->width * ref->height, m = 0;
    unsigned char *k = malloc((size_t)n);
    *mask = NULL;
    *count = 0;
    if (!k)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "compare: out of memory");
    for (long i = 0; i < n; i++) {
        k[i] = (double)ref->rgba[4 * i + 3] > threshold;
        m += k[i];
    }
    *mask = k;
    *count = m;
    return BRUME_OK;
}

static brume_status mask_picture(const brume_image *pic, int width, int height, unsigned char **mask, long *count)
{
    *mask = NULL;
    *count = 0;
    if (pic->width != width || pic->height != height)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "compare: the mask is %d x %d but the images are %d x %d",
                       pic->width, pic->height, width, height);
    long n = (long)width * height, m = 0;
    unsigned char *k = malloc((size_t)n);
    if (!k)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "compare: out of memory");
    for (long i = 0; i < n; i++) {
        k[i] = lum(pic->rgba + 4 * i) > 0.5;
        m += k[i];
    }
    *mask = k;
    *count = m;
    return BRUME_OK;
}

void brume_diff_color(double r, double s, float rgb[3])
{
    if (!rgb)
        return;
    /* two sRGB ramps from white (ColorBrewer's RdBu ends and midpoints) */
    static const double blue[3][3] = {{1.0, 1.0, 1.0}, {0.57, 0.77, 0.87}, {0.02, 0.19, 0.38}};
    static const double red[3][3] = {{1.0, 1.0, 1.0}, {0.96, 0.65, 0.51}, {0.40, 0.00, 0.12}};
    double t = isfinite(r) ? fmin(1.0, fabs(r) / s) : 1.0;
    const double(*ramp)[3] = r < 0.0 ? blue : red;
    int k = t < 0.5 ? 0 : 1;
    double u = t < 0.5 ? 2.0 * t : 2.0 * t - 1.0;
    for (int c = 0; c < 3; c++)
        rgb[c] = (float)((1.0 - u) * ramp[k][c] + u * ramp[k + 1][c]);
}

static double srgb_to_linear(double v) { return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4); }

/* The signed relative luminance difference of pixel i. */
static double rel_diff(const brume_image *img, const brume_image *ref, long i, double floor)
{
    double lr = lum(ref->rgba + 4 * i), la = lum(img->rgba + 4 * i);
    return (la - lr) / fmax(lr, floor);
}

static brume_status diff_picture(const brume_image *img, const brume_image *ref, double scale, brume_image **out)
{
    *out = NULL;
    brume_image_diff st;
    brume_status s = diff_full(img, ref, &st);
    if (s)
        return s;
    brume_image *d = image_new(img->width, img->height);
    if (!d)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "compare: out of memory");
    long n = (long)img->width * img->height;
    for (long i = 0; i < n; i++) {
        float *p = d->rgba + 4 * i, c[3];
        brume_diff_color(rel_diff(img, ref, i, st.floor), scale, c);
        for (int k = 0; k < 3; k++) /* the image is linear; the map is given in sRGB */
            p[k] = (float)srgb_to_linear(c[k]);
        p[3] = 1.0f;
    }
    *out = d;
    return BRUME_OK;
}

/* cairo's RGB24 pixel of an sRGB colour in [0, 1] */
static uint32_t rgb24(const float c[3])
{
    uint32_t v = 0;
    for (int k = 0; k < 3; k++)
        v = v << 8 | (uint32_t)lround(255.0 * (double)c[k]);
    return v;
}

#define BAR_H 56   /* the scale bar's strip under the picture */
#define BAR_MIN_W 320

static brume_status diff_png(const brume_image *img, const brume_image *ref, const unsigned char *mask, double scale,
                            const char *path)
{
    brume_image_diff st;
    brume_status s = diff_full(img, ref, &st);
    if (s)
        return s;
    if ((s = cairo_lib_open(path)) != BRUME_OK)
        return s;
    int w = img->width, h = img->height, W = w > BAR_MIN_W ? w : BAR_MIN_W, H = h + BAR_H;
    cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, W, H);
    if (cairo_surface_status(sf) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(sf);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot make a %d x %d picture", path, W, H);
    }
    cairo_surface_flush(sf);
    unsigned char *px = cairo_image_surface_get_data(sf);
    int stride = cairo_image_surface_get_stride(sf);
    for (int y = 0; y < H; y++)
        memset(px + (size_t)y * (size_t)stride, 0xff, (size_t)W * 4);
    int x0 = (W - w) / 2;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            long i = (long)y * w + x;
            float c[3];
            brume_diff_color(rel_diff(img, ref, i, st.floor), scale, c);
            if (mask && !mask[i]) /* outside the region: dimmed towards grey */
                for (int k = 0; k < 3; k++)
                    c[k] = 0.35f * c[k] + 0.65f * 0.62f;
            uint32_t v = rgb24(c);
            memcpy(px + (size_t)y * (size_t)stride + 4 * (size_t)(x0 + x), &v, 4);
        }
    int bx0 = 24, bx1 = W - 24;
    for (int x = bx0; x < bx1; x++) {
        float c[3];
        brume_diff_color(scale * (2.0 * (x - bx0 + 0.5) / (bx1 - bx0) - 1.0), scale, c);
        uint32_t v = rgb24(c);
        for (int y = h + 6; y < h + 18; y++)
            memcpy(px + (size_t)y * (size_t)stride + 4 * (size_t)x, &v, 4);
    }
    cairo_surface_mark_dirty(sf);
    cairo_t *cr = cairo_create(sf);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, bx0 - 0.5, h + 5.5, bx1 - bx0 + 1.0, 13.0);
    cairo_stroke(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 11.0);
    for (int k = -2; k <= 2; k++) {
        double x = bx0 + (bx1 - bx0) * (k + 2) / 4.0;
        char label[48];
        if (k == 0)
            snprintf(label, sizeof label, "0");
        else
            snprintf(label, sizeof label, "%s%.3g %%", k > 0 ? "+" : "-", 100.0 * scale * abs(k) / 2.0);
        cairo_move_to(cr, x + 0.5, h + 18);
        cairo_line_to(cr, x + 0.5, h + 23);
        cairo_stroke(cr);
        chart_text(cr, x, h + 34, label, k == -2 ? 0.2 : k == 2 ? 0.8 : 0.5);
    }
    chart_text(cr, bx0, h + 49, "darker (beyond: saturated)", 0.0);
    chart_text(cr, bx1, h + 49, "brighter", 1.0);
    return chart_write_png(sf, cr, path);
}

/* ---- the public calls: arguments checked, errors reported to ctx ---------------------------- */

static brume_status null_arg(brume_context *ctx, const char *fn, const char *what)
{
    return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: NULL", fn, what));
}

brume_status brume_image_compare(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                 brume_image_diff *out)
{
    err_clear();
    if (!image || !ref || !out)
        return null_arg(ctx, "brume_image_compare", !image ? "image" : !ref ? "ref" : "out");
    return ctx_report(ctx, diff_full(image, ref, out));
}

brume_status brume_image_compare_region(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                        const unsigned char *mask, int boot, uint64_t seed, brume_region_stats *out)
{
    err_clear();
    if (!image || !ref || !out)
        return null_arg(ctx, "brume_image_compare_region", !image ? "image" : !ref ? "ref" : "out");
    return ctx_report(ctx, region_stats(image, ref, mask, boot, seed, out));
}

brume_status brume_image_mask_alpha(brume_context *ctx, const brume_image *ref, double threshold,
                                    unsigned char **mask, long *count)
{
    err_clear();
    if (mask)
        *mask = NULL;
    if (!ref || !mask || !count)
        return null_arg(ctx, "brume_image_mask_alpha", !ref ? "ref" : !mask ? "mask" : "count");
    if (!isfinite(threshold))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_image_mask_alpha: threshold: %g is not finite",
                                       threshold));
    return ctx_report(ctx, mask_alpha(ref, threshold, mask, count));
}

brume_status brume_image_mask_picture(brume_context *ctx, const brume_image *picture, int width, int height,
                                      unsigned char **mask, long *count)
{
    err_clear();
    if (mask)
        *mask = NULL;
    if (!picture || !mask || !count)
        return null_arg(ctx, "brume_image_mask_picture", !picture ? "picture" : !mask ? "mask" : "count");
    return ctx_report(ctx, mask_picture(picture, width, height, mask, count));
}

brume_status brume_image_diff_picture(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                      double scale, brume_image **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (!image || !ref || !out)
        return null_arg(ctx, "brume_image_diff_picture", !image ? "image" : !ref ? "ref" : "out");
    if (!(scale > 0.0) || !isfinite(scale))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_image_diff_picture: scale: %g is not > 0", scale));
    return ctx_report(ctx, diff_picture(image, ref, scale, out));
}

brume_status brume_image_diff_png(brume_context *ctx, const brume_image *image, const brume_image *ref,
                                  const unsigned char *mask, double scale, const char *path)
{
    err_clear();
    if (!image || !ref || !path)
        return null_arg(ctx, "brume_image_diff_png", !image ? "image" : !ref ? "ref" : "path");
    if (!(scale > 0.0) || !isfinite(scale))
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_image_diff_png: scale: %g is not > 0", scale));
    const void *owner = atomic_owner(ctx);
    brume_status st = diff_png(image, ref, mask, scale, path);
    atomic_owner(owner);
    return ctx_report(ctx, st);
}
