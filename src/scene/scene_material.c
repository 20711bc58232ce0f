/* scene_material.c - a surface's "material" object in a scene file (docs/scene-format.md):
 * its type and that type's keys, with pbrt-v4's names, defaults and roughness remap. */
#include <math.h>
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

/* pbrt-v4's roughness keys into the Trowbridge-Reitz alpha: uroughness and vroughness
 * (default roughness, default 0), remapped by alpha = sqrt(r) unless remaproughness is false. */
static brume_status roughness(const cJSON *j, jloc at, double *alpha)
{
    double r = 0.0, u, v;
    bool remap = true;
    brume_status st;
    if ((st = json_number(j, at, "roughness", 0, 0.0, 100.0, &r)))
        return st;
    u = v = r;
    if ((st = json_number(j, at, "uroughness", 0, 0.0, 100.0, &u)) ||
        (st = json_number(j, at, "vroughness", 0, 0.0, 100.0, &v)) ||
        (st = json_bool(j, at, "remaproughness", 0, &remap)))
        return st;
    if (u != v)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s: uroughness %g != vroughness %g: brume's microfacets are "
                       "isotropic (a surface carries no tangent direction)", at.file, at.path, u, v);
    *alpha = remap ? sqrt(u) : u;
    return BRUME_OK;
}

static brume_status parse_diffuse(const cJSON *j, jloc at, brume_material *m, json_texture **tex)
{
    brume_status st;
    if (cJSON_IsObject(cJSON_GetObjectItemCaseSensitive(j, "albedo"))) {
        if ((st = scene_json_texture(j, at, "albedo", tex))) return st;
        m->albedo_texture = &(*tex)->tex;
        m->albedo[0] = m->albedo[1] = m->albedo[2] = 0.0;
    } else if ((st = jcolor(j, at, "albedo", 1.0, m->albedo))) {
        return st;
    }
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

static brume_status parse_conductor(const cJSON *j, jloc at, brume_material *m)
{
    bool has_eta, has_k, has_r = cJSON_HasObjectItem(j, "reflectance");
    brume_status st;
    if ((st = spectrum(j, at, "eta", m->conductor_eta, &has_eta)) || (st = spectrum(j, at, "k", m->conductor_k, &has_k)))
        return st;
    if (has_r && (has_eta || has_k))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: give either eta and k or reflectance", at.file, at.path);
    if (has_r) { /* pbrt-v4: eta = 1 and the k whose normal reflectance is r (at most 0.9999) */
        double r[3] = {0, 0, 0};
        if ((st = jcolor(j, at, "reflectance", 1.0, r)))
            return st;
        for (int c = 0; c < 3; c++) {
            double rc = fmin(r[c], 0.9999);
            m->conductor_eta[c] = 1.0;
            m->conductor_k[c] = 2.0 * sqrt(rc) / sqrt(1.0 - rc);
        }
    }
    return roughness(j, at, &m->roughness);
}

static brume_status parse_coated(const cJSON *j, jloc at, brume_material *m)
{
    brume_status st;
    m->albedo[0] = m->albedo[1] = m->albedo[2] = 0.5;
    if ((st = jcolor(j, at, "reflectance", 1.0, m->albedo)) || (st = parse_eta(j, at, m)) ||
        (st = roughness(j, at, &m->roughness)) || (st = json_number(j, at, "thickness", 0, 1e-300, 1e6, &m->thickness)) ||
        (st = jcolor(j, at, "layer_albedo", 1.0, m->layer_albedo)) || (st = json_number(j, at, "g", 0, -0.999, 0.999, &m->g)) ||
        (st = json_int(j, at, "max_depth", 0, 1, 1000, &m->max_depth)) ||
        (st = json_int(j, at, "nsamples", 0, 1, 1000, &m->nsamples)))
        return st;
    return BRUME_OK;
}

/* The keys of each type, the common ones (type, emission, two_sided) included. */
static const char *const *material_keys(const char *type, brume_material_type *t)
{
    static const char *const diffuse[] = {"type", "emission", "two_sided", "albedo", "specular", "exponent", NULL};
    static const char *const dielectric[] = {"type", "emission", "two_sided", "eta", "roughness", "uroughness",
                                             "vroughness", "remaproughness", NULL};
    static const char *const conductor[] = {"type", "emission", "two_sided", "eta", "k", "reflectance", "roughness",
                                            "uroughness", "vroughness", "remaproughness", NULL};
    static const char *const coated[] = {"type", "emission", "two_sided", "reflectance", "eta", "roughness",
                                         "uroughness", "vroughness", "remaproughness", "thickness", "layer_albedo",
                                         "g", "max_depth", "nsamples", NULL};
    static const struct {
        const char *name;
        brume_material_type t;
        const char *const *keys;
    } types[] = {{"diffuse", BRUME_MATERIAL_DIFFUSE, diffuse},
                 {"dielectric", BRUME_MATERIAL_DIELECTRIC, dielectric},
                 {"conductor", BRUME_MATERIAL_CONDUCTOR, conductor},
                 {"coateddiffuse", BRUME_MATERIAL_COATEDDIFFUSE, coated}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(type, types[i].name) == 0) {
            *t = types[i].t;
            return types[i].keys;
        }
    return NULL;
}

brume_status scene_parse_material(const cJSON *j, jloc at, brume_material *m, json_texture **tex)
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
                       "conductor, coateddiffuse, interface)", at.file, at.path, type);
    if ((st = json_check_object(j, at, keys))) return st;
    if ((st = jcolor(j, at, "emission", BIG, m->emission))) return st;
    if ((st = json_bool(j, at, "two_sided", 0, &m->two_sided))) return st;
    switch (m->type) {
    case BRUME_MATERIAL_DIFFUSE: return parse_diffuse(j, at, m, tex);
    case BRUME_MATERIAL_DIELECTRIC:
        if ((st = parse_eta(j, at, m)))
            return st;
        return roughness(j, at, &m->roughness);
    case BRUME_MATERIAL_CONDUCTOR: return parse_conductor(j, at, m);
    case BRUME_MATERIAL_COATEDDIFFUSE: return parse_coated(j, at, m);
    }
    return BRUME_OK;
}
