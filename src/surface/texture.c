/* texture.c - pbrt-v4's textures as far as imagemap, scale, mix and checkerboard (brume.h,
 * "TEXTURES"): a tree of nodes kept in an array, each node's inputs at later indices, built
 * once (the caller's images decoded to linear RGB) and evaluated per surface hit. */
#include "surface/texture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/error.h"
#include "image/image.h"

typedef struct tex_node {
    brume_texture_type type;
    bool is_float;
    color value;
    int in[3]; /* tex1, tex2, amount: node indices, or -1 */
    double su, sv, du, dv;
    int w, h;   /* IMAGEMAP */
    float *rgb; /* w h linear RGB, top row first; owned */
    double scale;
    bool invert;
    brume_texture_wrap wrap;
} tex_node;

struct texture {
    int n;
    tex_node *node;
    size_t bytes;
};

void texture_free(texture *t)
{
    if (!t)
        return;
    for (int i = 0; i < t->n; i++)
        free(t->node[i].rgb);
    free(t->node);
    free(t);
}

size_t texture_bytes(const texture *t) { return t ? t->bytes : 0; }

/* An 8-bit file's stored values from brume's linear decoding (image_read_png decodes sRGB),
 * then decoded as `gamma` says: 0 sRGB (as read), 1 linear, else x^gamma. */
static double decode_8bit(double linear, double gamma)
{
    if (gamma == 0.0)
        return linear;
    double stored = image_srgb_encode(linear);
    return gamma == 1.0 ? stored : pow(stored, gamma);
}

static bool is_png(const char *path)
{
    size_t n = strlen(path);
    return n >= 4 && (strcmp(path + n - 4, ".png") == 0 || strcmp(path + n - 4, ".PNG") == 0);
}

/* The node's image in linear RGB (its alpha dropped), counted against the budget. */
static brume_status read_image(tex_node *d, const brume_texture_node *s, const brume_image *img, const char *at,
                               size_t *bytes)
{
    if (!img)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: no image given for it", at, s->filename);
    size_t npix = (size_t)img->width * (size_t)img->height;
    brume_status st = budget_take(3 * sizeof(float) * npix, at);
    if (st)
        return st;
    *bytes += 3 * sizeof(float) * npix;
    if (!(d->rgb = malloc(3 * sizeof(float) * npix)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at);
    d->w = img->width;
    d->h = img->height;
    bool eight_bit = is_png(s->filename);
    for (size_t i = 0; i < npix; i++)
        for (int c = 0; c < 3; c++) {
            double v = img->rgba[4 * i + (size_t)c];
            if (!isfinite(v))
                return err_set(BRUME_ERROR_RANGE, "%s: %s: pixel (%zu, %zu) channel %d is not finite", at, s->filename,
                               i % (size_t)d->w, i / (size_t)d->w, c);
            d->rgb[3 * i + (size_t)c] = (float)(eight_bit ? decode_8bit(v, s->gamma) : v);
        }
    return BRUME_OK;
}

static brume_status check_number(const char *at, const char *key, double v, double lo, double hi)
{
    if (!(v >= lo && v <= hi))
        return err_set(BRUME_ERROR_RANGE, "%s.%s: %g outside [%g, %g]", at, key, v, lo, hi);
    return BRUME_OK;
}

/* Node i of s checked into d; at names it ("FN: WHAT.nodes[i]"). */
static brume_status build_node(const brume_texture *s, brume_image *const *images, int i, tex_node *d, const char *at,
                               size_t *bytes)
{
    const brume_texture_node *n = &s->nodes[i];
    brume_status st;
    if ((unsigned)n->type > BRUME_TEXTURE_CHECKERBOARD)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s.type: %d is not a brume_texture_type", at, (int)n->type);
    const int in[3] = {n->tex1, n->tex2, n->amount};
    static const char *const in_name[3] = {"tex1", "tex2", "amount"};
    for (int k = 0; k < 3; k++) {
        if (in[k] != -1 && !(in[k] > i && in[k] < s->n))
            return err_set(BRUME_ERROR_RANGE, "%s.%s: %d is not -1 or a later node (%d to %d)", at, in_name[k], in[k],
                           i + 1, s->n - 1);
        d->in[k] = in[k];
    }
    const double map[4] = {n->uscale, n->vscale, n->udelta, n->vdelta};
    static const char *const map_name[4] = {"uscale", "vscale", "udelta", "vdelta"};
    for (int k = 0; k < 4; k++)
        if ((st = check_number(at, map_name[k], map[k], -1e12, 1e12)))
            return st;
    d->type = n->type;
    d->is_float = n->is_float;
    d->su = n->uscale != 0.0 ? n->uscale : 1.0;
    d->sv = n->vscale != 0.0 ? n->vscale : 1.0;
    d->du = n->udelta;
    d->dv = n->vdelta;
    for (int c = 0; c < 3; c++) {
        if (n->type == BRUME_TEXTURE_CONSTANT && (st = check_number(at, "value", n->value[c], -1e30, 1e30)))
            return st;
        d->value.c[c] = n->type == BRUME_TEXTURE_CONSTANT ? n->value[n->is_float ? 0 : c] : 0.0;
    }
    if (n->type != BRUME_TEXTURE_IMAGEMAP)
        return BRUME_OK;
    if (!n->filename || !n->filename[0])
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s.filename: none given", at);
    if ((st = check_number(at, "gamma", n->gamma, 0.0, 100.0)) ||
        (st = check_number(at, "scale", n->scale, -1e30, 1e30)))
        return st;
    if ((unsigned)n->wrap > BRUME_WRAP_CLAMP)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s.wrap: %d is not a brume_texture_wrap", at, (int)n->wrap);
    d->scale = n->scale != 0.0 ? n->scale : 1.0;
    d->invert = n->invert;
    d->wrap = n->wrap;
    return read_image(d, n, images ? images[i] : NULL, at, bytes);
}

texture *texture_build(const brume_texture *s, brume_image *const *images, const char *fn, const char *what)
{
    if (!s->nodes || s->n < 1 || s->n > BRUME_TEXTURE_MAX_NODES) {
        err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: %d nodes (NULL or outside [1, %d])", fn, what, s->n,
                BRUME_TEXTURE_MAX_NODES);
        return NULL;
    }
    texture *t = calloc(1, sizeof *t);
    if (t && !(t->node = calloc((size_t)s->n, sizeof *t->node))) {
        free(t);
        t = NULL;
    }
    if (!t) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s: out of memory", fn, what);
        return NULL;
    }
    t->n = s->n;
    for (int i = 0; i < s->n; i++) {
        char at[512];
        snprintf(at, sizeof at, "%s: %s.nodes[%d]", fn, what, i);
        if (build_node(s, images, i, &t->node[i], at, &t->bytes) != BRUME_OK) {
            budget_give(t->bytes);
            texture_free(t);
            return NULL;
        }
    }
    return t;
}

/* ---- evaluation ---------------------------------------------------------------------------- */

/* Texel (x, y) of the image under its wrap mode; y = 0 is the top row. */
static color texel(const tex_node *d, int x, int y)
{
    if (d->wrap == BRUME_WRAP_REPEAT) {
        x %= d->w;
        y %= d->h;
        x += x < 0 ? d->w : 0;
        y += y < 0 ? d->h : 0;
    } else if (d->wrap == BRUME_WRAP_CLAMP) {
        x = x < 0 ? 0 : (x >= d->w ? d->w - 1 : x);
        y = y < 0 ? 0 : (y >= d->h ? d->h - 1 : y);
    } else if (x < 0 || y < 0 || x >= d->w || y >= d->h) {
        return col(0.0);
    }
    const float *p = d->rgb + 3 * ((size_t)y * (size_t)d->w + (size_t)x);
    color c = {{p[0], p[1], p[2]}};
    return c;
}

/* pbrt-v4's Image::Bilerp at (s, t) in [0, 1]^2 image coordinates (t down from the top):
 * pixel centres at (i + 0.5) / width. */
static color bilerp(const tex_node *d, double s, double t)
{
    double x = s * d->w - 0.5, y = t * d->h - 0.5;
    if (!(fabs(x) < 1e9 && fabs(y) < 1e9))
        return col(0.0);
    double fx = floor(x), fy = floor(y), ax = x - fx, ay = y - fy;
    int xi = (int)fx, yi = (int)fy;
    color c00 = texel(d, xi, yi), c10 = texel(d, xi + 1, yi), c01 = texel(d, xi, yi + 1),
          c11 = texel(d, xi + 1, yi + 1), out;
    for (int c = 0; c < 3; c++)
        out.c[c] = (1 - ax) * (1 - ay) * c00.c[c] + ax * (1 - ay) * c10.c[c] + (1 - ax) * ay * c01.c[c] +
                   ax * ay * c11.c[c];
    return out;
}

static color eval_node(const texture *t, int i, double u, double v);

static color input(const texture *t, int k, color fallback, double u, double v)
{
    return k < 0 ? fallback : eval_node(t, k, u, v);
}

static color eval_node(const texture *t, int i, double u, double v)
{
    const tex_node *d = &t->node[i];
    double s = d->su * u + d->du, tt = d->sv * v + d->dv;
    color out = col(0.0);
    switch (d->type) {
    case BRUME_TEXTURE_CONSTANT:
        out = d->value;
        break;
    case BRUME_TEXTURE_IMAGEMAP:
        out = col_scale(bilerp(d, s, 1.0 - tt), d->scale);
        if (d->invert)
            out = col_sub(col(1.0), out);
        for (int c = 0; c < 3; c++)
            out.c[c] = fmax(out.c[c], 0.0);
        break;
    case BRUME_TEXTURE_SCALE:
        out = col_scale(input(t, d->in[0], col(1.0), u, v), input(t, d->in[2], col(1.0), u, v).c[0]);
        break;
    case BRUME_TEXTURE_MIX: {
        double a = input(t, d->in[2], col(0.5), u, v).c[0];
        out = col_add(col_scale(input(t, d->in[0], col(0.0), u, v), 1.0 - a),
                      col_scale(input(t, d->in[1], col(1.0), u, v), a));
        break;
    }
    case BRUME_TEXTURE_CHECKERBOARD: {
        double f = floor(s) + floor(tt);
        bool even = fmod(f, 2.0) == 0.0;
        out = even ? input(t, d->in[0], col(1.0), u, v) : input(t, d->in[1], col(0.0), u, v);
        break;
    }
    }
    if (d->is_float)
        out = col(out.c[0]);
    return out;
}

color texture_eval(const texture *t, double u, double v) { return eval_node(t, 0, u, v); }
