/* pbrt_materials.c - pbrt-v4's Material and MakeNamedMaterial types and their parameters,
 * read into the JSON of a brume material (docs/pbrt.md): diffuse, dielectric, conductor,
 * coateddiffuse and interface. Every parameter of a material is read here (mat_*), so that
 * a texture lookup has one place to go. What brume cannot honour is refused through
 * pbrt_unsupported, malformed values through pbrt_fail. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "scene/named_spectra.h"
#include "scene/pbrt.h"

/* A parameter brume cannot honour on any material. */
static brume_status refuse_common(pbrt_state *S, params *ps, const char *what)
{
    static const char *const no[] = {"displacement", "normalmap"};
    for (size_t i = 0; i < sizeof no / sizeof no[0]; i++)
        if (pbrt_get(ps, no[i]))
            return pbrt_unsupported(&S->L, "%s: parameter \"%s\": brume neither displaces nor bumps surfaces", what,
                                    no[i]);
    return BRUME_OK;
}

static brume_status no_texture(pbrt_state *S, const param *q, const char *what)
{
    if (q && strcmp(q->type, "texture") == 0)
        return pbrt_unsupported(&S->L, "%s: parameter \"%s\": a texture (brume's materials take constant values)", what,
                         q->name);
    return BRUME_OK;
}

/* A colour parameter (rgb, constant spectrum, float) into o[key]. */
static brume_status mat_color(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o,
                              const char *key, double hi)
{
    param *q = pbrt_get(ps, name);
    double c[3];
    brume_status st;
    if (!q)
        return BRUME_OK;
    if ((st = no_texture(S, q, what)) || (st = pbrt_get_color(&S->L, ps, name, c)))
        return st;
    for (int i = 0; i < 3; i++)
        if (!(c[i] >= 0.0 && c[i] <= hi))
            return pbrt_fail(&S->L, "%s: parameter \"%s\": %g outside [0, %g]", what, name, c[i], hi);
    cJSON_AddItemToObject(o, key, cJSON_CreateDoubleArray(c, 3));
    return BRUME_OK;
}

/* An index of refraction: a number, an RGB, a constant spectrum or one of pbrt-v4's named
 * spectra (kept by name); one number only for a dielectric (`scalar`). */
static brume_status mat_index(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o, bool scalar)
{
    param *q = pbrt_get(ps, name);
    double c[3];
    brume_status st;
    if (!q)
        return BRUME_OK;
    if ((st = no_texture(S, q, what)))
        return st;
    if (strcmp(q->type, "spectrum") == 0 && q->is_string && q->n == 1) {
        q->used = true;
        if (!named_spectrum_rgb(q->s, c))
            return pbrt_unsupported(&S->L, "%s: parameter \"%s\": unknown named spectrum \"%s\" (brume knows %s)",
                                    what, name, q->s, named_spectrum_list());
        if (scalar && strncmp(q->s, "glass-", 6) != 0)
            return pbrt_unsupported(&S->L, "%s: parameter \"%s\": \"%s\" is not a glass", what, name, q->s);
        cJSON_AddStringToObject(o, name, q->s);
        return BRUME_OK;
    }
    if ((st = pbrt_get_color(&S->L, ps, name, c)))
        return st;
    if (scalar && !(c[0] == c[1] && c[1] == c[2]))
        return pbrt_unsupported(&S->L, "%s: parameter \"%s\": one index for every wavelength (brume does not "
                                       "disperse light)", what, name);
    for (int i = 0; i < 3; i++)
        if (!((scalar ? c[i] > 0.0 : c[i] >= 0.0) && c[i] <= 100.0))
            return pbrt_fail(&S->L, "%s: parameter \"%s\": %g outside %s0, 100]", what, name, c[i], scalar ? "(" : "[");
    if (scalar)
        cJSON_AddNumberToObject(o, name, c[0]);
    else
        cJSON_AddItemToObject(o, name, cJSON_CreateDoubleArray(c, 3));
    return BRUME_OK;
}

/* A float parameter in [lo, hi] into o[key]. */
static brume_status mat_float(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o,
                              const char *key, double lo, double hi)
{
    param *q = pbrt_get(ps, name);
    double v = 0.0;
    brume_status st;
    if (!q)
        return BRUME_OK;
    if ((st = no_texture(S, q, what)) || (st = pbrt_get_float(&S->L, ps, name, &v)))
        return st;
    if (!(v >= lo && v <= hi))
        return pbrt_fail(&S->L, "%s: parameter \"%s\": %g outside [%g, %g]", what, name, v, lo, hi);
    cJSON_AddNumberToObject(o, key, v);
    return BRUME_OK;
}

static brume_status mat_bool(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o)
{
    param *q = pbrt_get(ps, name);
    if (!q)
        return BRUME_OK;
    q->used = true;
    if (strcmp(q->type, "bool") != 0 || q->n != 1 ||
        (q->is_string && strcmp(q->s, "true") != 0 && strcmp(q->s, "false") != 0))
        return pbrt_fail(&S->L, "%s: parameter \"%s\": expected one bool", what, name);
    cJSON_AddBoolToObject(o, name, q->is_string ? strcmp(q->s, "true") == 0 : q->v[0] != 0.0);
    return BRUME_OK;
}

/* roughness, uroughness, vroughness and remaproughness, as brume's JSON names them too. */
static brume_status mat_roughness(pbrt_state *S, params *ps, const char *what, cJSON *o)
{
    brume_status st;
    if ((st = mat_float(S, ps, what, "roughness", o, "roughness", 0.0, 100.0)) ||
        (st = mat_float(S, ps, what, "uroughness", o, "uroughness", 0.0, 100.0)) ||
        (st = mat_float(S, ps, what, "vroughness", o, "vroughness", 0.0, 100.0)) ||
        (st = mat_bool(S, ps, what, "remaproughness", o)))
        return st;
    const cJSON *u = cJSON_GetObjectItem(o, "uroughness"), *v = cJSON_GetObjectItem(o, "vroughness"),
                *r = cJSON_GetObjectItem(o, "roughness");
    double ru = u ? u->valuedouble : (r ? r->valuedouble : 0.0), rv = v ? v->valuedouble : (r ? r->valuedouble : 0.0);
    if (ru != rv)
        return pbrt_unsupported(&S->L, "%s: uroughness %g and vroughness %g differ: brume's microfacets are "
                                       "isotropic", what, ru, rv);
    return BRUME_OK;
}

/* The parameters of each type into o (the "type" key set). */
static brume_status material_params(pbrt_state *S, const char *type, const char *what, params *ps, cJSON *o,
                                    const cJSON **albedo_tex)
{
    brume_status st;
    if (strcmp(type, "diffuse") == 0) { /* a texture's JSON replaces albedo when the shape is written */
        double albedo[3] = {0.5, 0.5, 0.5};
        if ((st = pbrt_spectrum_or_texture(S, ps, "reflectance", albedo, albedo_tex)))
            return st;
        cJSON_AddItemToObject(o, "albedo", cJSON_CreateDoubleArray(albedo, 3));
        return BRUME_OK;
    }
    cJSON_AddStringToObject(o, "type", type);
    if (strcmp(type, "dielectric") == 0) {
        if ((st = mat_index(S, ps, what, "eta", o, true)))
            return st;
        return mat_roughness(S, ps, what, o);
    }
    if (strcmp(type, "conductor") == 0) {
        if ((st = mat_index(S, ps, what, "eta", o, false)) || (st = mat_index(S, ps, what, "k", o, false)) ||
            (st = mat_color(S, ps, what, "reflectance", o, "reflectance", 1.0)))
            return st;
        if (pbrt_get(ps, "reflectance") && (pbrt_get(ps, "eta") || pbrt_get(ps, "k")))
            return pbrt_fail(&S->L, "%s: give either \"eta\" and \"k\" or \"reflectance\"", what);
        return mat_roughness(S, ps, what, o);
    }
    /* coateddiffuse */
    double maxdepth = 10, nsamples = 1;
    if ((st = mat_color(S, ps, what, "reflectance", o, "reflectance", 1.0)) ||
        (st = mat_index(S, ps, what, "eta", o, true)) || (st = mat_roughness(S, ps, what, o)) ||
        (st = mat_float(S, ps, what, "thickness", o, "thickness", 1e-300, 1e6)) ||
        (st = mat_color(S, ps, what, "albedo", o, "layer_albedo", 1.0)) ||
        (st = mat_float(S, ps, what, "g", o, "g", -0.999, 0.999)) ||
        (st = pbrt_get_float(&S->L, ps, "maxdepth", &maxdepth)) || (st = pbrt_get_float(&S->L, ps, "nsamples", &nsamples)))
        return st;
    if (!(maxdepth >= 1 && maxdepth <= 1000 && nsamples >= 1 && nsamples <= 1000))
        return pbrt_fail(&S->L, "%s: maxdepth and nsamples must be in [1, 1000]", what);
    cJSON_AddNumberToObject(o, "max_depth", (int)maxdepth);
    cJSON_AddNumberToObject(o, "nsamples", (int)nsamples);
    return BRUME_OK;
}

brume_status pbrt_material_read(pbrt_state *S, const char *type, const char *what, params *ps, char material[32],
                                char json[PBRT_MATERIAL_JSON], const cJSON **albedo_tex)
{
    *albedo_tex = NULL;
    static const char *const known[] = {"interface", "diffuse", "dielectric", "conductor", "coateddiffuse"};
    const char *t = type[0] ? type : "interface"; /* pbrt's "" is "interface" */
    bool ok = false;
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        ok = ok || strcmp(t, known[i]) == 0;
    if (!ok)
        return pbrt_unsupported(&S->L, "%s: not supported by brume (diffuse, dielectric, conductor, coateddiffuse, "
                                       "interface)", what);
    brume_status st = refuse_common(S, ps, what);
    if (st)
        return st;
    pbrt_copy(material, 32, t);
    json[0] = '\0';
    if (strcmp(t, "interface") == 0)
        return BRUME_OK;
    cJSON *o = cJSON_CreateObject();
    if (!o)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
    st = material_params(S, t, what, ps, o, albedo_tex);
    if (st == BRUME_OK && !cJSON_PrintPreallocated(o, json, PBRT_MATERIAL_JSON, false))
        st = pbrt_unsupported(&S->L, "%s: its parameters are too long for brume", what);
    cJSON_Delete(o);
    return st;
}
