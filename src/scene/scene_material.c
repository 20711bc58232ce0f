/* scene_material.c - a surface's "material" object in a scene file (docs/scene-format.md):
 * its type and that type's keys, with pbrt-v4's names, defaults and roughness remap. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core/error.h"
#include "io/json.h"
#include "scene/named_spectra.h"
#include "scene/scene_json_texture.h"
#include "scene/scene_material.h"

static const double BIG = 1e30;

static brume_status jcolor(const cJSON *j, jloc at, const char *key, double hi, double out[3])
{
    color c = col_rgb(out[0], out[1], out[2]);
    brume_status st = json_color(j, at, key, 0, 0.0, hi, &c);
    for (int i = 0; st == BRUME_OK && i < 3; i++)
        out[i] = c.c[i];
    return st;
}

/* j[key]: a number, an RGB triple or the name of one of pbrt-v4's spectra (named_spectra.c);
 * *given whether it is there. */
static brume_status spectrum(const cJSON *j, jloc at, const char *key, double out[3], bool *given)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    *given = it != NULL;
    if (!cJSON_IsString(it))
        return jcolor(j, at, key, 100.0, out);
    if (!named_spectrum_rgb(it->valuestring, out))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.%s: unknown spectrum \"%s\" (known: %s)", at.file, at.path, key,
                       it->valuestring, named_spectrum_list());
    return BRUME_OK;
}

/* j[key] as a texture object into the store, its brume_texture in *out; *given false (and
 * nothing done) when j[key] is not an object. */
static brume_status texture_key(const cJSON *j, jloc at, const char *key, bool is_float, scene_material_store *sm,
                                const brume_texture **out, bool *given)
{
    *given = cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(j, key));
    if (!*given)
        return BRUME_OK;
    if (sm->ntex == SCENE_MATERIAL_MAX_TEXTURES)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: more than %d textures in one material", at.file, at.path, key,
                       SCENE_MATERIAL_MAX_TEXTURES);
    brume_status st = scene_json_texture(j, at, key, is_float, &sm->tex[sm->ntex]);
    if (st)
        return st;
    *out = &sm->tex[sm->ntex++]->tex;
    return BRUME_OK;
}

/* pbrt-v4's roughness keys into the Trowbridge-Reitz alpha: uroughness and vroughness
 * (default roughness, default 0), remapped by alpha = sqrt(r) unless remaproughness is false;
 * roughness may be a float texture (remapped at each hit). */
static brume_status roughness(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm)
{
    double r = 0.0, u, v;
    bool remap = true, tex;
    brume_status st;
    if ((st = json_bool(j, at, "remaproughness", 0, &remap)) ||
        (st = texture_key(j, at, "roughness", true, sm, &m->roughness_texture, &tex)))
        return st;
    m->remap_roughness = remap;
    if (tex && (cJSON_HasObjectItem(j, "uroughness") || cJSON_HasObjectItem(j, "vroughness")))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s: a roughness texture with uroughness or vroughness: brume's "
                       "microfacets are isotropic", at.file, at.path);
    if (tex)
        return BRUME_OK;
    if ((st = json_number(j, at, "roughness", 0, 0.0, 100.0, &r)))
        return st;
    u = v = r;
    if ((st = json_number(j, at, "uroughness", 0, 0.0, 100.0, &u)) ||
        (st = json_number(j, at, "vroughness", 0, 0.0, 100.0, &v)))
        return st;
    if (u != v)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s: uroughness %g != vroughness %g: brume's microfacets are "
                       "isotropic (a surface carries no tangent direction)", at.file, at.path, u, v);
    m->roughness = remap ? sqrt(u) : u;
    return BRUME_OK;
}

/* j[key]: a colour in [0, 1] into out, or a spectrum texture object (m->albedo_texture);
 * *given whether it is there. */
static brume_status reflectance(const cJSON *j, jloc at, const char *key, double out[3], brume_material *m,
                                scene_material_store *sm, bool *given)
{
    brume_status st = texture_key(j, at, key, false, sm, &m->albedo_texture, given);
    if (st || *given)
        return st;
    *given = cJSON_HasObjectItem(j, key);
    return jcolor(j, at, key, 1.0, out);
}

static brume_status parse_diffuse(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm)
{
    brume_status st;
    bool given;
    if ((st = reflectance(j, at, "albedo", m->albedo, m, sm, &given))) return st;
    if (m->albedo_texture)
        m->albedo[0] = m->albedo[1] = m->albedo[2] = 0.0;
    if ((st = jcolor(j, at, "specular", 1.0, m->specular))) return st;
    if ((st = json_number(j, at, "exponent", 0, 0.0, 1e6, &m->exponent))) return st;
    for (int c = 0; c < 3; c++)
        if (m->albedo[c] + m->specular[c] > 1.0)
            return err_set(BRUME_ERROR_RANGE, "%s: %s: albedo + specular = %g > 1 would create energy", at.file,
                           at.path, m->albedo[c] + m->specular[c]);
    return BRUME_OK;
}

/* eta: a number or a named glass (its index at 550 nm). */
static brume_status parse_eta(const cJSON *j, jloc at, brume_material *m)
{
    double e[3] = {m->eta, m->eta, m->eta};
    bool given;
    brume_status st = spectrum(j, at, "eta", e, &given);
    if (st)
        return st;
    if (!(e[0] == e[1] && e[1] == e[2]))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s.eta: a dielectric's index is one number (brume does not "
                       "disperse light)", at.file, at.path);
    if (!(e[0] > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.eta: %g is not > 0", at.file, at.path, e[0]);
    m->eta = e[0];
    return BRUME_OK;
}

static brume_status parse_conductor(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm)
{
    bool has_eta = false, has_k = false, has_r;
    double r[3] = {0, 0, 0};
    brume_status st;
    bool eta_tex, k_tex;
    if ((st = texture_key(j, at, "eta", false, sm, &m->conductor_eta_texture, &eta_tex)) ||
        (st = texture_key(j, at, "k", false, sm, &m->conductor_k_texture, &k_tex)) ||
        (!eta_tex && (st = spectrum(j, at, "eta", m->conductor_eta, &has_eta))) ||
        (!k_tex && (st = spectrum(j, at, "k", m->conductor_k, &has_k))) ||
        (st = reflectance(j, at, "reflectance", r, m, sm, &has_r)))
        return st;
    has_eta = has_eta || eta_tex;
    has_k = has_k || k_tex;
    if (has_r && (has_eta || has_k))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: give either eta and k or reflectance", at.file, at.path);
    if (has_r && !m->albedo_texture) { /* pbrt-v4: eta = 1 and the k whose normal reflectance is r (at most 0.9999) */
        for (int c = 0; c < 3; c++) {
            double rc = fmin(r[c], 0.9999);
            m->conductor_eta[c] = 1.0;
            m->conductor_k[c] = 2.0 * sqrt(rc) / sqrt(1.0 - rc);
        }
    }
    return roughness(j, at, m, sm);
}

static brume_status parse_coated(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm)
{
    brume_status st;
    bool given;
    m->albedo[0] = m->albedo[1] = m->albedo[2] = 0.5;
    bool thick_tex, g_tex, layer_tex;
    if ((st = texture_key(j, at, "thickness", true, sm, &m->thickness_texture, &thick_tex)) ||
        (st = texture_key(j, at, "g", true, sm, &m->g_texture, &g_tex)) ||
        (st = texture_key(j, at, "layer_albedo", false, sm, &m->layer_albedo_texture, &layer_tex)))
        return st;
    if ((st = reflectance(j, at, "reflectance", m->albedo, m, sm, &given)) || (st = parse_eta(j, at, m)) ||
        (st = roughness(j, at, m, sm)) ||
        (!thick_tex && (st = json_number(j, at, "thickness", 0, 1e-300, 1e6, &m->thickness))) ||
        (!layer_tex && (st = jcolor(j, at, "layer_albedo", 1.0, m->layer_albedo))) ||
        (!g_tex && (st = json_number(j, at, "g", 0, -0.999, 0.999, &m->g))) ||
        (st = json_int(j, at, "max_depth", 0, 1, 1000, &m->max_depth)) ||
        (st = json_int(j, at, "nsamples", 0, 1, 1000, &m->nsamples)))
        return st;
    return BRUME_OK;
}

static brume_status parse_any(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm, int depth);

/* mix: "materials" [a, b] (material objects) and "amount" (a number in [0, 1] or a float
 * texture object). */
static brume_status parse_mix(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm, int depth)
{
    const cJSON *ms = cJSON_GetObjectItemCaseSensitive(j, "materials");
    bool tex;
    brume_status st;
    if (!cJSON_IsArray(ms) || cJSON_GetArraySize(ms) != 2)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.materials: expected an array of two material objects", at.file,
                       at.path);
    if (depth + 1 >= BRUME_MATERIAL_MAX_MIX)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: mixes nested more than %d deep", at.file, at.path,
                       BRUME_MATERIAL_MAX_MIX);
    if ((st = texture_key(j, at, "amount", true, sm, &m->amount_texture, &tex)) ||
        (!tex && (st = json_number(j, at, "amount", 0, 0.0, 1.0, &m->amount))))
        return st;
    for (int k = 0; k < 2; k++) {
        char kp[256], idx[32];
        snprintf(idx, sizeof idx, "materials[%d]", k);
        if (sm->nmat == SCENE_MATERIAL_MAX_PARTS)
            return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: more than %d mixed materials in one material", at.file,
                           at.path, idx, SCENE_MATERIAL_MAX_PARTS);
        brume_material *c = &sm->mat[sm->nmat++];
        if ((st = parse_any(cJSON_GetArrayItem(ms, k), (jloc){at.file, json_key_path(kp, sizeof kp, at.path, idx)}, c,
                            sm, depth + 1)))
            return st;
        m->materials[k] = c;
    }
    return BRUME_OK;
}

/* The keys of each type, the common ones (type, emission, two_sided) included. */
static const char *const *material_keys(const char *type, brume_material_type *t)
{
    static const char *const diffuse[] = {"type", "emission", "two_sided", "albedo", "specular", "exponent",
                                          "displacement", NULL};
    static const char *const dielectric[] = {"type", "emission", "two_sided", "eta", "roughness", "uroughness",
                                             "vroughness", "remaproughness", "displacement", NULL};
    static const char *const conductor[] = {"type", "emission", "two_sided", "eta", "k", "reflectance", "roughness",
                                            "uroughness", "vroughness", "remaproughness", "displacement", NULL};
    static const char *const coated[] = {"type", "emission", "two_sided", "reflectance", "eta", "roughness",
                                         "uroughness", "vroughness", "remaproughness", "thickness", "layer_albedo",
                                         "g", "max_depth", "nsamples", "displacement", NULL};
    static const char *const mix[] = {"type", "emission", "two_sided", "materials", "amount", NULL};
    static const struct {
        const char *name;
        brume_material_type t;
        const char *const *keys;
    } types[] = {{"diffuse", BRUME_MATERIAL_DIFFUSE, diffuse},
                 {"dielectric", BRUME_MATERIAL_DIELECTRIC, dielectric},
                 {"conductor", BRUME_MATERIAL_CONDUCTOR, conductor},
                 {"coateddiffuse", BRUME_MATERIAL_COATEDDIFFUSE, coated},
                 {"mix", BRUME_MATERIAL_MIX, mix}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(type, types[i].name) == 0) {
            *t = types[i].t;
            return types[i].keys;
        }
    return NULL;
}

static brume_status parse_any(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm, int depth)
{
    brume_material_default(m);
    if (!j)
        return BRUME_OK;
    if (!cJSON_IsObject(j))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object", at.file, at.path);
    char type[32] = "diffuse";
    brume_status st = json_string(j, at, "type", 0, type, sizeof type);
    if (st)
        return st;
    const char *const *keys = material_keys(type, &m->type);
    if (!keys)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.type: unknown material type '%s' (known: diffuse, dielectric, "
                       "conductor, coateddiffuse, mix, interface)", at.file, at.path, type);
    if ((st = json_check_object(j, at, keys))) return st;
    if ((st = jcolor(j, at, "emission", BIG, m->emission))) return st;
    if ((st = json_bool(j, at, "two_sided", 0, &m->two_sided))) return st;
    bool bump;
    if ((st = texture_key(j, at, "displacement", true, sm, &m->displacement_texture, &bump))) return st;
    if (!bump && cJSON_HasObjectItem(j, "displacement"))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.displacement: expected a float texture object", at.file, at.path);
    switch (m->type) {
    case BRUME_MATERIAL_DIFFUSE: return parse_diffuse(j, at, m, sm);
    case BRUME_MATERIAL_DIELECTRIC:
        if ((st = parse_eta(j, at, m)))
            return st;
        return roughness(j, at, m, sm);
    case BRUME_MATERIAL_CONDUCTOR: return parse_conductor(j, at, m, sm);
    case BRUME_MATERIAL_COATEDDIFFUSE: return parse_coated(j, at, m, sm);
    case BRUME_MATERIAL_MIX: return parse_mix(j, at, m, sm, depth);
    }
    return BRUME_OK;
}

brume_status scene_parse_material(const cJSON *j, jloc at, brume_material *m, scene_material_store *sm)
{
    sm->ntex = sm->nmat = 0;
    return parse_any(j, at, m, sm, 0);
}

void scene_material_store_free(scene_material_store *sm)
{
    for (int i = 0; i < sm->ntex; i++)
        scene_json_texture_free(sm->tex[i]);
    sm->ntex = 0;
}
