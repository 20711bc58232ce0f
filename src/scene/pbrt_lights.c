/* pbrt_lights.c - pbrt's LightSource directive as brume's lights. */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/image_formats.h"
#include "io/json.h"
#include "medium/blackbody.h"
#include "scene/background.h"
#include "scene/scene_build.h"
#include "scene/pbrt.h"

/* A light's L or I, or a medium's Le, as pbrt-v4 gives it to an RGB film: every light and
 * emitting medium divides its scale by the spectrum's luminance (SpectrumToPhotometric), of
 * the colour space's illuminant for rgb (so rgb is read as it is) and of the spectrum itself
 * otherwise (so a spectrum's own magnitude drops out, Y = 1): a constant spectrum is the
 * equal-energy white, "blackbody" T (kelvin) the peak-normalized Planck spectrum, each seen
 * by the cie1931 sensor and written in linear Rec. 709 (XYZ / Y). */
brume_status pbrt_illuminant(lexer *L, params *ps, const char *name, double out[3])
{
    param *q = pbrt_get(ps, name);
    if (q && strcmp(q->type, "spectrum") == 0) {
        /* a constant spectrum (pbrt_get_color checks it) of luminance 1: the equal-energy
           white, X = Y = Z, in Rec. 709 (the XYZ to Rec. 709 matrix's row sums) */
        brume_status st = pbrt_get_color(L, ps, name, out);
        const double white[3] = {1.2047843, 0.9483008, 0.9088427};
        for (int c = 0; c < 3 && st == BRUME_OK; c++)
            out[c] = out[c] > 0.0 ? white[c] : 0.0;
        return st;
    }
    if (!q || strcmp(q->type, "blackbody") != 0)
        return pbrt_get_color(L, ps, name, out);
    double T = q->n == 1 && !q->is_string ? q->v[0] : -1.0;
    if (!(T >= 100.0 && T <= 1e5))
        return pbrt_fail(L, "parameter \"blackbody %s\": one temperature in [100, 100000] K", name);
    double xyz[3];
    blackbody_xyz(T, xyz);
    color rgb = blackbody_rgb_exact(T);
    for (int c = 0; c < 3; c++) {
        out[c] = rgb.c[c] / xyz[1];
        if (!(out[c] >= 0.0))
            return pbrt_unsupported(L, "parameter \"blackbody %s\": %g K is outside Rec. 709 (channel %d: %g)", name, T, c,
                                    out[c]);
    }
    return BRUME_OK;
}

/* "diffuse": the shapes that follow in the attribute block emit L scale from the side pbrt's
 * normal faces (both with twosided), as brume's surface emission does (pbrt_shapes.c faces
 * them); pbrt-v4 divides the scale by L's luminance, so rgb L is brume's radiance as it is.
 * With "power", pbrt-v4 (DiffuseAreaLight::Create) multiplies it by power / (pi A), A the
 * shape's area (twice that when two-sided): pbrt_shapes.c applies it per shape. */
brume_status pbrt_area_light_directive(pbrt_state *S, attrs *a, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    if (strcmp(type, "diffuse") != 0)
        return pbrt_unsupported(L, "AreaLightSource \"%s\": not supported by brume (diffuse)", type);
    double Lrgb[3] = {1, 1, 1}, scale = 1.0, power = 0.0;
    if ((st = pbrt_illuminant(L, ps, "L", Lrgb)) || (st = pbrt_get_float(L, ps, "scale", &scale)) ||
        (st = pbrt_get_float(L, ps, "power", &power)))
        return st;
    param *two = pbrt_get(ps, "twosided");
    bool two_sided = false;
    if (two) {
        bool word = strcmp(two->type, "bool") == 0 && two->n == 1;
        if (!word || (two->is_string && strcmp(two->s, "true") != 0 && strcmp(two->s, "false") != 0))
            return pbrt_fail(L, "AreaLightSource: parameter \"twosided\": expected one bool");
        two_sided = two->is_string ? strcmp(two->s, "true") == 0 : two->v[0] != 0.0;
    }
    if ((st = pbrt_all_used(L, ps, "AreaLightSource \"diffuse\"")))
        return st;
    if (!(scale >= 0.0 && scale <= 1e30))
        return pbrt_fail(L, "AreaLightSource: parameter \"scale\": %g outside [0, 1e30]", scale);
    if (!(power <= 1e30))
        return pbrt_fail(L, "AreaLightSource: parameter \"power\": %g outside (-inf, 1e30]", power);
    a->area = true;
    a->area_two_sided = two_sided;
    a->area_power = power > 0.0 ? power : 0.0; /* pbrt-v4 ignores a power that is not positive */
    for (int c = 0; c < 3; c++)
        a->area_L[c] = Lrgb[c] * scale;
    return BRUME_OK;
}

/* pbrt-v4's exposure: the film records radiance times the imaging ratio, the exposure time
 * (the Camera's shutterclose - shutteropen, 1 by default) times iso / 100 (Film "iso", 100 by
 * default). The image is linear in its sources taken together, so brume scales every one of
 * them, the lights, the sky, the media's and the surfaces' emission, by the ratio. */
void pbrt_imaging(pbrt_state *S)
{
    double k = S->exposure_time * S->iso / 100.0;
    if (k == 1.0)
        return;
    static const char *const keys[] = {"irradiance", "intensity", "emission"};
    cJSON *lists[2] = {S->lights, S->media_j};
    for (int l = 0; l < 2; l++)
        for (cJSON *o = lists[l] ? lists[l]->child : NULL; o; o = o->next) {
            for (int i = 0; i < 3; i++) {
                cJSON *arr = cJSON_GetObjectItemCaseSensitive(o, keys[i]);
                for (cJSON *v = arr ? arr->child : NULL; v; v = v->next)
                    cJSON_SetNumberHelper(v, v->valuedouble * k);
            }
            cJSON *bb = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(o, "blackbody"), "scale");
            if (bb)
                cJSON_SetNumberHelper(bb, bb->valuedouble * k);
        }
    for (int c = 0; c < 3; c++)
        S->background[c] *= k;
    cJSON *sky = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(S->root, "background"), "scale");
    if (sky)
        cJSON_SetNumberHelper(sky, sky->valuedouble * k);
    for (cJSON *o = S->surfaces ? S->surfaces->child : NULL; o; o = o->next) {
        cJSON *e = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(o, "material"), "emission");
        for (cJSON *v = e ? e->child : NULL; v; v = v->next)
            cJSON_SetNumberHelper(v, v->valuedouble * k);
    }
}

/* "spot": pbrt-v4's SpotLight, I scale times SmoothStep(cos coneangle, cos(coneangle -
 * conedeltaangle), cos theta) from the axis from -> to: brume's smooth cone, cone_angle and
 * falloff_start, the same smoothstep in cos theta. The cone is circular in pbrt's light space:
 * a transform that is not a rotation times a uniform scale would make it elliptical, and is
 * refused. */
static brume_status light_spot(pbrt_state *S, params *ps, double scale)
{
    lexer *L = &S->L;
    brume_status st;
    double I[3] = {1, 1, 1}, from[3] = {0, 0, 0}, to[3] = {0, 0, 1}, cone = 30.0, delta = 5.0, phi_v = -1.0;
    if ((st = pbrt_illuminant(L, ps, "I", I)) || (st = pbrt_get_point(L, ps, "from", from)) ||
        (st = pbrt_get_point(L, ps, "to", to)) || (st = pbrt_get_float(L, ps, "coneangle", &cone)) ||
        (st = pbrt_get_float(L, ps, "conedeltaangle", &delta)) || (st = pbrt_get_float(L, ps, "power", &phi_v)) ||
        (st = pbrt_all_used(L, ps, "LightSource \"spot\"")))
        return st;
    if (!(cone >= 0.01 && cone <= 180.0 && delta >= 0.0 && delta <= cone))
        return pbrt_fail(L, "LightSource \"spot\": need coneangle in [0.01, 180] and conedeltaangle in [0, coneangle]");
    if (phi_v > 0.0) { /* pbrt-v4: the power over the cone, its falloff counted half */
        double cos_end = cos(cone * PI / 180.0), cos_start = cos((cone - delta) * PI / 180.0);
        scale *= phi_v / (2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0));
    }
    m4 ctm = S->a[S->depth].ctm;
    vec3 c[3] = {pbrt_m4_vector(ctm, v3(1, 0, 0)), pbrt_m4_vector(ctm, v3(0, 1, 0)), pbrt_m4_vector(ctm, v3(0, 0, 1))};
    double n0 = v3_length(c[0]);
    for (int a = 0; a < 3; a++)
        for (int b = a; b < 3; b++)
            if (fabs(v3_dot(c[a], c[b]) - (a == b ? n0 * n0 : 0.0)) > 1e-9 * n0 * n0)
                return pbrt_unsupported(L, "LightSource \"spot\": a transform that is not a rotation and a uniform scale "
                                           "(pbrt-v4's cone would be elliptical)");
    vec3 p = pbrt_m4_point(ctm, v3(from[0], from[1], from[2]));
    vec3 d = pbrt_m4_vector(ctm, v3(to[0] - from[0], to[1] - from[1], to[2] - from[2]));
    if (!(v3_length(d) > 0.0))
        return pbrt_fail(L, "LightSource \"spot\": from equals to");
    d = v3_normalize(d);
    cJSON *l = cJSON_CreateObject();
    double pv[3] = {p.x, p.y, p.z}, dv[3] = {d.x, d.y, d.z}, Iv[3] = {I[0] * scale, I[1] * scale, I[2] * scale};
    cJSON_AddStringToObject(l, "type", "spot");
    cJSON_AddItemToObject(l, "position", cJSON_CreateDoubleArray(pv, 3));
    cJSON_AddItemToObject(l, "direction", cJSON_CreateDoubleArray(dv, 3));
    cJSON_AddItemToObject(l, "intensity", cJSON_CreateDoubleArray(Iv, 3));
    cJSON_AddNumberToObject(l, "cone_angle", cone);
    cJSON_AddNumberToObject(l, "falloff_start", cone - delta);
    cJSON_AddItemToArray(S->lights, l);
    return BRUME_OK;
}

/* pbrt-v4's normalisation of an image sky to an illuminance E_v: its own estimate of the
 * map's illuminance on an upward-facing (+z in the light's frame) surface, each texel of the
 * upper half weighted by its luminance (Rec. 709's Y) times cos theta and by 2 pi / texels,
 * as pbrt-v4's lights.cpp sums it. A texel covers 4 pi / texels steradians, so that sum is half
 * the map's illuminance, and the map as pbrt-v4 scales it lights such a surface with 2 E_v;
 * brume renders pbrt-v4's image, so it scales as pbrt-v4 does. pbrt-v4 weighs the image's
 * first three channels in the order the file holds them (OpenEXR's: sorted by name, so B,
 * G, R in an RGB file, A, B, G in an RGBA one): chan[k] is the RGBA index of the channel
 * that Rec. 709's k-th luminance weight multiplies. */
static double sky_illuminance_as_pbrt(const brume_image *img, const int chan[3])
{
    int n = brume_image_width(img);
    const float *rgba = brume_image_pixels(img);
    double sum = 0.0;
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++) {
            vec3 w = bg_equal_area_to_sphere((x + 0.5) / n, (y + 0.5) / n);
            if (w.z <= 0.0)
                continue;
            const float *px = rgba + 4 * ((size_t)y * (size_t)n + (size_t)x);
            sum += (0.212639 * (double)px[chan[0]] + 0.715169 * (double)px[chan[1]] + 0.072192 * (double)px[chan[2]]) *
                   w.z;
        }
    return sum * 2.0 * PI / ((double)n * (double)n);
}

/* The sky's light-to-world: the CTM's linear part, which must turn directions rigidly (a
 * rotation, with the reader's mirror or a Scale -1, times a uniform scale) since pbrt-v4
 * looks the map up along the normalized inverse image of the direction. */
static cJSON *sky_transform(pbrt_state *S)
{
    m4 ctm = S->a[S->depth].ctm;
    vec3 c[3] = {pbrt_m4_vector(ctm, v3(1, 0, 0)), pbrt_m4_vector(ctm, v3(0, 1, 0)), pbrt_m4_vector(ctm, v3(0, 0, 1))};
    double n0 = v3_length(c[0]);
    for (int a = 0; a < 3; a++)
        for (int b = a; b < 3; b++)
            if (!(fabs(v3_dot(c[a], c[b]) - (a == b ? n0 * n0 : 0.0)) <= 1e-9 * n0 * n0)) {
                pbrt_unsupported(&S->L, "LightSource \"infinite\": a transform that is not a rotation and a uniform "
                                        "scale (pbrt-v4's sky would be distorted)");
                return NULL;
            }
    ctm.m[3] = ctm.m[7] = ctm.m[11] = 0.0; /* directions: no translation */
    bool oom;
    cJSON *t = pbrt_transform_json(ctm, &oom);
    if (!t)
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: out of memory", S->L.file, S->L.dir_line);
    return t;
}

/* The order in which pbrt-v4's illuminance sum reads the channels of the sky image at abs
 * (sky_illuminance_as_pbrt): the file's own for OpenEXR, R, G, B otherwise. A channel other
 * than R, G, B, A among the first three is refused: brume does not read it. */
static brume_status sky_channel_order(pbrt_state *S, const char *abs, const char *file, int chan[3])
{
    size_t len = strlen(abs);
    if (len < 4 || abs[len - 4] != '.' || tolower((unsigned char)abs[len - 3]) != 'e' ||
        tolower((unsigned char)abs[len - 2]) != 'x' || tolower((unsigned char)abs[len - 1]) != 'r')
        return BRUME_OK;
    int count = 0;
    if (image_exr_channel_order(abs, chan, 3, &count) != BRUME_OK)
        return err_prefix("%s:%d: LightSource \"infinite\"", S->L.file, S->L.dir_line);
    for (int k = 0; k < 3; k++)
        if (k >= count || chan[k] < 0)
            return pbrt_unsupported(&S->L, "LightSource \"infinite\": \"illuminance\": pbrt-v4 weighs the first three "
                                           "channels of %s in the file's order, and channel %d is none of R, G, B, A",
                                    file, k + 1);
    return BRUME_OK;
}

/* "infinite" with "string filename": pbrt-v4's ImageInfiniteLight, a square equal-area map
 * (a background with mapping equal_area), oriented by the CTM; its scale divided by the
 * colour space's illuminant's luminance, so the pixel values are radiance as written. */
static brume_status light_sky_image(pbrt_state *S, const char *file, double scale, double E_v)
{
    lexer *L = &S->L;
    char abs[PATH_MAX];
    brume_status st;
    if ((st = pbrt_resolve_file(S, "LightSource \"infinite\": \"filename\"", file, abs)))
        return st;
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL;
    st = ctx ? brume_image_read(ctx, abs, &img) : BRUME_ERROR_OUT_OF_MEMORY;
    if (st)
        err_set(st, "%s:%d: LightSource \"infinite\": %.1000s", L->file, L->dir_line,
                ctx ? brume_context_last_error(ctx) : "out of memory");
    brume_context_release(ctx);
    if (st)
        return st;
    int w = brume_image_width(img), h = brume_image_height(img), chan[3] = {0, 1, 2};
    if (E_v > 0.0 && (st = sky_channel_order(S, abs, file, chan))) {
        brume_image_release(img);
        return st;
    }
    double k_e = w == h && E_v > 0.0 ? sky_illuminance_as_pbrt(img, chan) : 1.0;
    brume_image_release(img);
    if (w != h)
        return pbrt_fail(L, "LightSource \"infinite\": %s is %d x %d pixels: pbrt-v4 reads square equal-area maps only",
                         file, w, h);
    if (E_v > 0.0) {
        if (!(k_e > 0.0))
            return pbrt_fail(L, "LightSource \"infinite\": \"illuminance\" on a map black over its upper half");
        scale *= E_v / k_e;
    }
    cJSON *t = sky_transform(S);
    if (!t)
        return err_status();
    cJSON *b = cJSON_CreateObject();
    if (!b) {
        cJSON_Delete(t);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: out of memory", L->file, L->dir_line);
    }
    cJSON_AddStringToObject(b, "file", abs);
    cJSON_AddStringToObject(b, "mapping", "equal_area");
    cJSON_AddNumberToObject(b, "scale", scale);
    cJSON_AddItemToObject(b, "transform", t);
    cJSON_AddItemToObject(S->root, "background", b);
    return BRUME_OK;
}

/* "infinite": a constant sky (L, or the colour space's illuminant, of luminance 1: white) or
 * an image; an illuminance E_v > 0 makes the constant sky's E_v / pi (the illuminance of a
 * uniform sky of luminance 1 is pi) and scales an image as pbrt-v4 does. brume has one
 * background: constant skies add, an image sky stands alone. */
static brume_status light_infinite(pbrt_state *S, params *ps, double scale)
{
    lexer *L = &S->L;
    brume_status st;
    double Lrgb[3] = {1, 1, 1}, E_v = -1.0;
    char file[1024] = "";
    if (pbrt_get(ps, "portal"))
        return pbrt_unsupported(L, "LightSource \"infinite\": parameter \"portal\": not supported by brume");
    if ((st = pbrt_get_float(L, ps, "illuminance", &E_v)) || (st = pbrt_get_string(L, ps, "filename", file, sizeof file)))
        return st;
    if (file[0] && pbrt_get(ps, "L"))
        return pbrt_fail(L, "LightSource \"infinite\": both \"L\" and \"filename\" (pbrt-v4 takes one)");
    if (!file[0] && (st = pbrt_illuminant(L, ps, "L", Lrgb)))
        return st;
    if ((st = pbrt_all_used(L, ps, "LightSource \"infinite\"")))
        return st;
    bool image_sky = cJSON_HasObjectItem(S->root, "background");
    if (image_sky || (file[0] && S->have_background))
        return pbrt_unsupported(L, "LightSource \"infinite\": a second infinite light with an image sky (brume has "
                                   "one background: constant skies add, an image sky stands alone)");
    if (file[0])
        return light_sky_image(S, file, scale, E_v);
    if (E_v > 0.0)
        scale *= E_v / PI;
    for (int c = 0; c < 3; c++) /* several constant skies add */
        S->background[c] += Lrgb[c] * scale;
    S->have_background = true;
    return BRUME_OK;
}

brume_status pbrt_light_directive(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    double Lrgb[3] = {1, 1, 1}, scale = 1.0;
    if ((st = pbrt_get_float(L, ps, "scale", &scale))) return st;
    m4 ctm = S->a[S->depth].ctm;
    if (!S->far_light_line && (strcmp(type, "distant") == 0 || strcmp(type, "infinite") == 0)) {
        S->far_light_line = L->dir_line; /* what an unbounded camera medium refuses (pbrt_camera_medium) */
        pbrt_copy(S->far_light, sizeof S->far_light, type);
    }
    if (strcmp(type, "distant") == 0) {
        double from[3] = {0, 0, 0}, to[3] = {0, 0, 1}, E_v = -1.0;
        if ((st = pbrt_illuminant(L, ps, "L", Lrgb)) || (st = pbrt_get_point(L, ps, "from", from)) ||
            (st = pbrt_get_point(L, ps, "to", to)) || (st = pbrt_get_float(L, ps, "illuminance", &E_v)) ||
            (st = pbrt_all_used(L, ps, "LightSource \"distant\"")))
            return st;
        if (E_v > 0.0) /* pbrt-v4: the scale times an illuminance E_v > 0, L being of luminance 1 */
            scale *= E_v;
        vec3 d = pbrt_m4_vector(ctm, v3(to[0] - from[0], to[1] - from[1], to[2] - from[2]));
        if (!(v3_length(d) > 0.0))
            return pbrt_fail(L, "LightSource \"%s\": from equals to", type);
        d = v3_normalize(d);
        cJSON *l = cJSON_CreateObject();
        double dv[3] = {d.x, d.y, d.z}, E[3] = {Lrgb[0] * scale, Lrgb[1] * scale, Lrgb[2] * scale};
        cJSON_AddStringToObject(l, "type", "distant");
        cJSON_AddItemToObject(l, "direction", cJSON_CreateDoubleArray(dv, 3));
        cJSON_AddItemToObject(l, "irradiance", cJSON_CreateDoubleArray(E, 3));
        cJSON_AddItemToArray(S->lights, l);
    } else if (strcmp(type, "point") == 0) {
        double from[3] = {0, 0, 0}, phi_v = -1.0;
        if ((st = pbrt_illuminant(L, ps, "I", Lrgb)) || (st = pbrt_get_point(L, ps, "from", from)) ||
            (st = pbrt_get_float(L, ps, "power", &phi_v)) || (st = pbrt_all_used(L, ps, "LightSource \"point\"")))
            return st;
        if (phi_v > 0.0) /* pbrt-v4: a power phi_v > 0 spread over the sphere, I being of luminance 1 */
            scale *= phi_v / (4.0 * PI);
        vec3 p = pbrt_m4_point(ctm, v3(from[0], from[1], from[2]));
        cJSON *l = cJSON_CreateObject();
        double pv[3] = {p.x, p.y, p.z}, I[3] = {Lrgb[0] * scale, Lrgb[1] * scale, Lrgb[2] * scale};
        cJSON_AddStringToObject(l, "type", "point");
        cJSON_AddItemToObject(l, "position", cJSON_CreateDoubleArray(pv, 3));
        cJSON_AddItemToObject(l, "intensity", cJSON_CreateDoubleArray(I, 3));
        cJSON_AddItemToArray(S->lights, l);
    } else if (strcmp(type, "spot") == 0) {
        if ((st = light_spot(S, ps, scale)))
            return st;
    } else if (strcmp(type, "infinite") == 0) {
        if ((st = light_infinite(S, ps, scale)))
            return st;
    } else {
        return pbrt_unsupported(L, "LightSource \"%s\": not supported by brume (distant, point, spot, infinite)", type);
    }
    return BRUME_OK;
}
