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
#include "io/json.h"
#include "medium/blackbody.h"
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
 * them); pbrt-v4 divides the scale by L's luminance, so rgb L is brume's radiance as it is. */
brume_status pbrt_area_light_directive(pbrt_state *S, attrs *a, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    if (strcmp(type, "diffuse") != 0)
        return pbrt_unsupported(L, "AreaLightSource \"%s\": not supported by brume (diffuse)", type);
    double Lrgb[3] = {1, 1, 1}, scale = 1.0;
    if ((st = pbrt_illuminant(L, ps, "L", Lrgb)) || (st = pbrt_get_float(L, ps, "scale", &scale)))
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
    a->area = true;
    a->area_two_sided = two_sided;
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
    double I[3] = {1, 1, 1}, from[3] = {0, 0, 0}, to[3] = {0, 0, 1}, cone = 30.0, delta = 5.0;
    if ((st = pbrt_illuminant(L, ps, "I", I)) || (st = pbrt_get_point(L, ps, "from", from)) ||
        (st = pbrt_get_point(L, ps, "to", to)) || (st = pbrt_get_float(L, ps, "coneangle", &cone)) ||
        (st = pbrt_get_float(L, ps, "conedeltaangle", &delta)) || (st = pbrt_all_used(L, ps, "LightSource \"spot\"")))
        return st;
    if (!(cone >= 0.01 && cone <= 180.0 && delta >= 0.0 && delta <= cone))
        return pbrt_fail(L, "LightSource \"spot\": need coneangle in [0.01, 180] and conedeltaangle in [0, coneangle]");
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
        double from[3] = {0, 0, 0}, to[3] = {0, 0, 1};
        if ((st = pbrt_illuminant(L, ps, "L", Lrgb)) || (st = pbrt_get_point(L, ps, "from", from)) ||
            (st = pbrt_get_point(L, ps, "to", to)) || (st = pbrt_all_used(L, ps, "LightSource \"distant\"")))
            return st;
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
        double from[3] = {0, 0, 0};
        if ((st = pbrt_illuminant(L, ps, "I", Lrgb)) || (st = pbrt_get_point(L, ps, "from", from)) ||
            (st = pbrt_all_used(L, ps, "LightSource \"point\"")))
            return st;
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
        if ((st = pbrt_illuminant(L, ps, "L", Lrgb)) || (st = pbrt_all_used(L, ps, "LightSource \"infinite\"")))
            return st;
        for (int c = 0; c < 3; c++) /* several constant skies add */
            S->background[c] += Lrgb[c] * scale;
        S->have_background = true;
    } else {
        return pbrt_unsupported(L, "LightSource \"%s\": not supported by brume (distant, point, spot, infinite with L)", type);
    }
    return BRUME_OK;
}
