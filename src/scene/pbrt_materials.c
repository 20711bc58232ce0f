/* pbrt_materials.c - pbrt-v4's Material and MakeNamedMaterial types and their parameters,
 * read into the JSON of a brume material (docs/pbrt.md): diffuse, dielectric, conductor,
 * coateddiffuse, mix and interface. Every parameter of a material is read here (mat_*), so
 * that a texture lookup has one place to go: a texture is kept as {"$tex": index} until a
 * shape is written (pbrt_material_json). What brume cannot honour is refused through
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
    static const char *const no[] = {"normalmap"};
    for (size_t i = 0; i < sizeof no / sizeof no[0]; i++)
        if (pbrt_get(ps, no[i]))
            return pbrt_unsupported(&S->L, "%s: parameter \"%s\": brume bumps surfaces by \"displacement\" only",
                                    what, no[i]);
    return BRUME_OK;
}

static brume_status no_texture(pbrt_state *S, const param *q, const char *what)
{
    if (q && strcmp(q->type, "texture") == 0)
        return pbrt_unsupported(&S->L, "%s: parameter \"%s\": a texture (brume's materials take constant values)", what,
                         q->name);
    return BRUME_OK;
}

/* A "texture" parameter q naming a Texture of that kind as {"$tex": index} in o[key]. */
static brume_status tex_ref(pbrt_state *S, param *q, const char *what, bool is_float, cJSON *o, const char *key,
                            bool *textured)
{
    int k = q->is_string && q->n == 1 ? pbrt_find_texture(S, q->s, is_float) : -1;
    q->used = true;
    if (k < 0)
        return pbrt_fail(&S->L, "%s: parameter \"texture %s\": no %s Texture named \"%s\" before it", what, q->name,
                         is_float ? "float" : "spectrum", q->is_string ? q->s : "");
    cJSON *r = cJSON_CreateObject();
    cJSON_AddNumberToObject(r, "$tex", k);
    cJSON_AddItemToObject(o, key, r);
    *textured = true;
    return BRUME_OK;
}

/* A colour parameter (rgb, constant spectrum, float) into o[key]; a spectrum texture too when
 * textured is not NULL. */
static brume_status mat_color(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o,
                              const char *key, double hi, bool *textured)
{
    param *q = pbrt_get(ps, name);
    double c[3];
    brume_status st;
    if (!q)
        return BRUME_OK;
    if (textured && strcmp(q->type, "texture") == 0)
        return tex_ref(S, q, what, false, o, key, textured);
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

/* A conductor's eta or k: a spectrum texture, or as mat_index reads it. */
static brume_status mat_index_tex(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o,
                                  bool *textured)
{
    param *q = pbrt_get(ps, name);
    if (q && strcmp(q->type, "texture") == 0)
        return tex_ref(S, q, what, false, o, name, textured);
    return mat_index(S, ps, what, name, o, false);
}

/* A float parameter in [lo, hi] into o[key]; a float texture too when textured is not NULL. */
static brume_status mat_float(pbrt_state *S, params *ps, const char *what, const char *name, cJSON *o,
                              const char *key, double lo, double hi, bool *textured)
{
    param *q = pbrt_get(ps, name);
    double v = 0.0;
    brume_status st;
    if (!q)
        return BRUME_OK;
    if (textured && strcmp(q->type, "texture") == 0)
        return tex_ref(S, q, what, true, o, key, textured);
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

/* One of roughness, uroughness, vroughness: absent, a number, or a float texture's index. */
typedef struct rough_value {
    bool given;
    int tex; /* -1: v */
    double v;
} rough_value;

static brume_status rough_read(pbrt_state *S, params *ps, const char *what, const char *name, rough_value *r)
{
    param *q = pbrt_get(ps, name);
    brume_status st;
    *r = (rough_value){.given = q != NULL, .tex = -1};
    if (!q)
        return BRUME_OK;
    if (strcmp(q->type, "texture") == 0) {
        q->used = true;
        if (!q->is_string || q->n != 1 || (r->tex = pbrt_find_texture(S, q->s, true)) < 0)
            return pbrt_fail(&S->L, "%s: parameter \"texture %s\": no float Texture named \"%s\" before it", what,
                             name, q->is_string ? q->s : "");
        return BRUME_OK;
    }
    if ((st = pbrt_get_float(&S->L, ps, name, &r->v)))
        return st;
    if (!(r->v >= 0.0 && r->v <= 100.0))
        return pbrt_fail(&S->L, "%s: parameter \"%s\": %g outside [0, 100]", what, name, r->v);
    return BRUME_OK;
}

/* roughness, uroughness and vroughness (each a number or a float texture; u and v default to
 * roughness, as in pbrt-v4) into one isotropic o["roughness"], and remaproughness. */
static brume_status mat_roughness(pbrt_state *S, params *ps, const char *what, cJSON *o, bool *textured)
{
    rough_value r, u, v;
    brume_status st;
    if ((st = rough_read(S, ps, what, "roughness", &r)) || (st = rough_read(S, ps, what, "uroughness", &u)) ||
        (st = rough_read(S, ps, what, "vroughness", &v)) || (st = mat_bool(S, ps, what, "remaproughness", o)))
        return st;
    if (!u.given)
        u = r;
    if (!v.given)
        v = r;
    if (u.tex != v.tex || (u.tex < 0 && u.v != v.v))
        return pbrt_unsupported(&S->L, "%s: uroughness and vroughness differ: brume's microfacets are isotropic",
                                what);
    if (!u.given)
        return BRUME_OK;
    if (u.tex < 0) {
        cJSON_AddNumberToObject(o, "roughness", u.v);
        return BRUME_OK;
    }
    cJSON *ref = cJSON_CreateObject();
    cJSON_AddNumberToObject(ref, "$tex", u.tex);
    cJSON_AddItemToObject(o, "roughness", ref);
    *textured = true;
    return BRUME_OK;
}

/* mix: "string materials" [a b], two named materials before it (their JSON copied in), and
 * "amount" (a float or a float texture; 0.5). */
static brume_status mat_mix(pbrt_state *S, params *ps, const char *what, cJSON *o, bool *textured)
{
    param *q = pbrt_get(ps, "materials");
    brume_status st;
    if (!q || strcmp(q->type, "string") != 0 || !q->is_string || q->n != 2)
        return pbrt_fail(&S->L, "%s: expected \"string materials\" with two names", what);
    q->used = true;
    cJSON *arr = cJSON_AddArrayToObject(o, "materials");
    for (int k = 0; k < 2; k++) {
        const char *name = k == 0 ? q->s : q->s + strlen(q->s) + 1;
        int i = S->nmaterials - 1;
        while (i >= 0 && strcmp(S->materials[i].name, name) != 0)
            i--;
        if (i < 0)
            return pbrt_fail(&S->L, "%s: parameter \"materials\": no MakeNamedMaterial \"%s\" before it", what, name);
        if (!S->materials[i].mat_json[0])
            return pbrt_unsupported(&S->L, "%s: parameter \"materials\": \"%s\" is an interface (brume mixes "
                                           "surfaces that scatter)", what, name);
        cJSON *m = cJSON_Parse(S->materials[i].mat_json);
        if (!m)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", what);
        cJSON_AddItemToArray(arr, m);
        *textured = *textured || S->materials[i].textured;
    }
    param *a = pbrt_get(ps, "amount");
    if (a && strcmp(a->type, "texture") == 0)
        return tex_ref(S, a, what, true, o, "amount", textured);
    double amount = 0.5;
    if ((st = pbrt_get_float(&S->L, ps, "amount", &amount)))
        return st;
    if (!(amount >= 0.0 && amount <= 1.0))
        return pbrt_fail(&S->L, "%s: parameter \"amount\": %g outside [0, 1]", what, amount);
    cJSON_AddNumberToObject(o, "amount", amount);
    return BRUME_OK;
}

/* "displacement": a float texture (bump mapping, o["displacement"]); a constant, which bumps
 * nothing, is read and dropped. */
static brume_status mat_displacement(pbrt_state *S, params *ps, const char *what, cJSON *o, bool *textured)
{
    param *q = pbrt_get(ps, "displacement");
    double d;
    if (!q)
        return BRUME_OK;
    if (strcmp(q->type, "texture") == 0)
        return tex_ref(S, q, what, true, o, "displacement", textured);
    return pbrt_get_float(&S->L, ps, "displacement", &d);
}

/* The parameters of each type into o (the "type" key set). */
static brume_status material_params(pbrt_state *S, const char *type, const char *what, params *ps, cJSON *o,
                                    bool *tx)
{
    brume_status st;
    if (strcmp(type, "diffuse") == 0) {
        if ((st = mat_displacement(S, ps, what, o, tx)))
            return st;
        if (!pbrt_get(ps, "reflectance"))
            cJSON_AddItemToObject(o, "albedo", cJSON_CreateDoubleArray((const double[3]){0.5, 0.5, 0.5}, 3));
        return mat_color(S, ps, what, "reflectance", o, "albedo", 1.0, tx);
    }
    cJSON_AddStringToObject(o, "type", type);
    if (strcmp(type, "mix") == 0)
        return mat_mix(S, ps, what, o, tx);
    if ((st = mat_displacement(S, ps, what, o, tx)))
        return st;
    if (strcmp(type, "dielectric") == 0) {
        if ((st = mat_index(S, ps, what, "eta", o, true)))
            return st;
        return mat_roughness(S, ps, what, o, tx);
    }
    if (strcmp(type, "conductor") == 0) {
        if ((st = mat_index_tex(S, ps, what, "eta", o, tx)) || (st = mat_index_tex(S, ps, what, "k", o, tx)) ||
            (st = mat_color(S, ps, what, "reflectance", o, "reflectance", 1.0, tx)))
            return st;
        if (pbrt_get(ps, "reflectance") && (pbrt_get(ps, "eta") || pbrt_get(ps, "k")))
            return pbrt_fail(&S->L, "%s: give either \"eta\" and \"k\" or \"reflectance\"", what);
        return mat_roughness(S, ps, what, o, tx);
    }
    /* coateddiffuse */
    double maxdepth = 10, nsamples = 1;
    if ((st = mat_color(S, ps, what, "reflectance", o, "reflectance", 1.0, tx)) ||
        (st = mat_index(S, ps, what, "eta", o, true)) || (st = mat_roughness(S, ps, what, o, tx)) ||
        (st = mat_float(S, ps, what, "thickness", o, "thickness", 1e-300, 1e6, tx)) ||
        (st = mat_color(S, ps, what, "albedo", o, "layer_albedo", 1.0, tx)) ||
        (st = mat_float(S, ps, what, "g", o, "g", -0.999, 0.999, tx)) ||
        (st = pbrt_get_float(&S->L, ps, "maxdepth", &maxdepth)) || (st = pbrt_get_float(&S->L, ps, "nsamples", &nsamples)))
        return st;
    if (!(maxdepth >= 1 && maxdepth <= 1000 && nsamples >= 1 && nsamples <= 1000))
        return pbrt_fail(&S->L, "%s: maxdepth and nsamples must be in [1, 1000]", what);
    cJSON_AddNumberToObject(o, "max_depth", (int)maxdepth);
    cJSON_AddNumberToObject(o, "nsamples", (int)nsamples);
    return BRUME_OK;
}

brume_status pbrt_material_read(pbrt_state *S, const char *type, const char *what, params *ps, char material[32],
                                char json[PBRT_MATERIAL_JSON], bool *textured)
{
    *textured = false;
    static const char *const known[] = {"interface", "diffuse", "dielectric", "conductor", "coateddiffuse", "mix"};
    const char *t = type[0] ? type : "interface"; /* pbrt's "" is "interface" */
    bool ok = false;
    for (size_t i = 0; i < sizeof known / sizeof known[0]; i++)
        ok = ok || strcmp(t, known[i]) == 0;
    if (!ok)
        return pbrt_unsupported(&S->L, "%s: not supported by brume (diffuse, dielectric, conductor, coateddiffuse, "
                                       "mix, interface)", what);
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
    st = material_params(S, t, what, ps, o, textured);
    if (st == BRUME_OK && !cJSON_PrintPreallocated(o, json, PBRT_MATERIAL_JSON, false))
        st = pbrt_unsupported(&S->L, "%s: its parameters are too long for brume", what);
    cJSON_Delete(o);
    return st;
}

/* Each {"$tex": k} under j replaced by texture k's JSON. */
static bool put_textures(const pbrt_state *S, cJSON *j)
{
    for (cJSON *c = j->child; c; c = c->next) {
        const cJSON *k = cJSON_IsObject(c) ? cJSON_GetObjectItemCaseSensitive(c, "$tex") : NULL;
        if (!k) {
            if ((cJSON_IsObject(c) || cJSON_IsArray(c)) && !put_textures(S, c))
                return false;
            continue;
        }
        cJSON *t = cJSON_Duplicate(S->textures[(int)k->valuedouble].json, 1);
        if (!t || !(cJSON_IsObject(j) ? cJSON_ReplaceItemInObjectCaseSensitive(j, c->string, t)
                                      : cJSON_ReplaceItemViaPointer(j, c, t))) {
            cJSON_Delete(t);
            return false;
        }
        c = t;
    }
    return true;
}

cJSON *pbrt_material_json(const pbrt_state *S, const attrs *a)
{
    cJSON *mat = cJSON_Parse(a->mat_json);
    if (mat && put_textures(S, mat))
        return mat;
    cJSON_Delete(mat);
    err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", S->path);
    return NULL;
}
