/* scene_json_media.c - the scene file's media: phase function, coefficients and the fields
 * (albedo, temperature, emission, velocity) read beside the density. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/context.h"
#include "core/error.h"
#include "io/grid_io.h"
#include "io/grid_sequence.h"
#include "io/json.h"
#include "method/method.h"
#include "scene/scene_methods.h"
#include "scene/scene_stam.h"
#include "scene/scene_pbrt.h"
#include "scene/scene_studio.h"
#include "scene/scene_keys.h"
#include "scene/scene_override.h"
#include "scene/scene_surfaces.h"
#include "scene/scene.h"
#include "scene/scene_build.h"
#include "scene/scene_json_common.h"

#define PHASE_MAX_LOBES 16

static brume_status parse_phase(const cJSON *j, jloc at, brume_phase **out);

/* A "mixture" phase function j (Blasi Eq. 20): a normalized sum of lobes, each
 * {"weight": w, "phase": {...}}. */
static brume_status parse_mixture(const cJSON *j, jloc at, brume_phase **out)
{
    brume_status st;
    static const char *const keys[] = {"type", "lobes", NULL};
    static const char *const lobe_keys[] = {"weight", "phase", NULL};
    if ((st = json_check_object(j, at, keys))) return st;
    const cJSON *lobes = cJSON_GetObjectItemCaseSensitive(j, "lobes");
    int n = cJSON_GetArraySize(lobes);
    if (!cJSON_IsArray(lobes) || n < 1 || n > PHASE_MAX_LOBES)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.lobes: expected an array of 1 to %d lobes", at.file, at.path,
                       PHASE_MAX_LOBES);
    brume_phase *ph[PHASE_MAX_LOBES] = {0};
    double w[PHASE_MAX_LOBES];
    int i = 0;
    for (const cJSON *l = lobes->child; l && st == BRUME_OK; l = l->next, i++) {
        char kp[256], kp2[300];
        snprintf(kp, sizeof kp, "%s.lobes[%d]", at.path, i);
        jloc lat = {at.file, kp};
        if ((st = json_check_object(l, lat, lobe_keys))) break;
        if ((st = json_number(l, lat, "weight", 1, 0.0, 1e30, &w[i]))) break;
        const cJSON *lp = cJSON_GetObjectItemCaseSensitive(l, "phase");
        if (!lp) {
            st = err_set(BRUME_ERROR_PARSE, "%s: %s.phase: required key missing", at.file, kp);
            break;
        }
        snprintf(kp2, sizeof kp2, "%s.phase", kp);
        st = parse_phase(lp, (jloc){at.file, kp2}, &ph[i]);
    }
    if (st == BRUME_OK)
        st = scene_json_built(brume_phase_new_mixture(NULL, w, ph, n, out), at);
    if (st)
        for (int k = 0; k < n; k++)
            brume_phase_release(ph[k]);
    return st;
}

static brume_status parse_phase(const cJSON *j, jloc at, brume_phase **out)
{
    char type[32];
    *out = NULL;
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    static const char *const type_only[] = {"type", NULL};
    static const struct { const char *name; brume_phase_preset preset; } presets[] = {
        {"isotropic", BRUME_PHASE_ISOTROPIC}, {"rayleigh", BRUME_PHASE_RAYLEIGH}, {"hazy", BRUME_PHASE_HAZY},
        {"murky", BRUME_PHASE_MURKY}};
    for (size_t i = 0; i < sizeof presets / sizeof presets[0]; i++)
        if (strcmp(type, presets[i].name) == 0) {
            if ((st = json_check_object(j, at, type_only))) return st;
            return scene_json_built(brume_phase_new_preset(NULL, presets[i].preset, out), at);
        }
    if (strcmp(type, "hg") == 0) {
        static const char *const keys[] = {"type", "g", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        double g = 0.0;
        if ((st = json_number(j, at, "g", 1, -0.999999, 0.999999, &g))) return st;
        return scene_json_built(brume_phase_new_hg(NULL, g, out), at);
    }
    if (strcmp(type, "schlick") == 0) {
        /* k directly, or g converted by k = 1.55 g - 0.55 g^3 (docs/phase-functions.md) */
        static const char *const keys[] = {"type", "k", "g", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        int has_k = cJSON_HasObjectItem(j, "k"), has_g = cJSON_HasObjectItem(j, "g");
        if (has_k == has_g)
            return err_set(BRUME_ERROR_PARSE, "%s: %s: give exactly one of k and g", at.file, at.path);
        double v = 0.0;
        if ((st = json_number(j, at, has_k ? "k" : "g", 1, -0.999999, 0.999999, &v))) return st;
        return scene_json_built(brume_phase_new_schlick(NULL, has_k ? v : phase_schlick_k_from_g(v), out), at);
    }
    if (strcmp(type, "schlick_mix") == 0) {
        /* Blasi Eq. 22: r schlick(k) + (1 - r) schlick(kprime) */
        static const char *const keys[] = {"type", "r", "k", "kprime", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        double r = 0.0, k = 0.0, kp = 0.0;
        if ((st = json_number(j, at, "r", 1, 0.0, 1.0, &r))) return st;
        if ((st = json_number(j, at, "k", 1, -0.999999, 0.999999, &k))) return st;
        if ((st = json_number(j, at, "kprime", 1, -0.999999, 0.999999, &kp))) return st;
        return scene_json_built(brume_phase_new_schlick_mix(NULL, r, k, kp, out), at);
    }
    if (strcmp(type, "tabulated") == 0) {
        static const char *const keys[] = {"type", "file", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        char name[1024], path[2048];
        if ((st = json_string(j, at, "file", 1, name, sizeof name))) return st;
        json_resolve_path(at.file, name, path, sizeof path);
        return scene_json_built(brume_phase_load(NULL, path, out), at);
    }
    if (strcmp(type, "mixture") == 0)
        return parse_mixture(j, at, out);
    return err_set(BRUME_ERROR_PARSE,
                   "%s: %s.type: unknown phase function '%s' (known: isotropic, rayleigh, hazy, murky, hg, "
                   "schlick, schlick_mix, mixture, tabulated)",
                   at.file, at.path, type);
}

/* How a field's grid is read: brume_density_load (one field), _load_rgb or _load_velocity
 * (three). */
typedef brume_status (*field_loader)(brume_context *, const char *, const brume_grid_file_options *, brume_density **);

/* A field that names no grid, of a .vdb/.nvdb: its role's grid by the names fire tools write
 * (brume_grid_pick: "temperature" a temperature grid, "emission_field" an emission grid,
 * "albedo" an albedo grid), set in o->grid; when the file has none of those names, or for
 * other fields and formats, the loader's default grid. */
static brume_status pick_by_role(jloc fat, const char *key, const char *path, brume_grid_file_options *o)
{
    const char *role = strcmp(key, "temperature") == 0      ? "temperature"
                       : strcmp(key, "emission_field") == 0 ? "emission"
                       : strcmp(key, "albedo") == 0         ? "albedo"
                                                            : NULL;
    grid_format f = o->format != BRUME_GRID_FORMAT_AUTO ? (grid_format)o->format : grid_format_detect(path, NULL, 0);
    if (!role || (f != GRID_FORMAT_VDB && f != GRID_FORMAT_NVDB))
        return BRUME_OK;
    density_load_options lo; /* the listing's memory bound, as the load's */
    density_load_options_default(&lo);
    if (o->max_memory_mb > 0.0)
        lo.max_memory = (size_t)fmax(1.0, o->max_memory_mb * 1048576.0);
    int n = 0;
    gridvdb_info *gi = NULL;
    brume_grid_entry *e = NULL;
    brume_status st = grid_list_file(path, lo.max_memory, &gi, &n);
    if (st == BRUME_OK && n > 0 && !(e = calloc((size_t)n, sizeof *e)))
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", fat.file);
    if (st) {
        free(gi);
        return err_prefix("%s: %s", fat.file, fat.path);
    }
    for (int g = 0; g < n; g++) { /* what brume_grid_pick weighs: the names and value types */
        snprintf(e[g].name, sizeof e[g].name, "%s", gi[g].name);
        snprintf(e[g].type, sizeof e[g].type, "%s", gi[g].type);
        snprintf(e[g].grid_class, sizeof e[g].grid_class, "%s", gi[g].cls);
    }
    free(gi);
    int i = brume_grid_pick(e, n, role);
    if (i >= 0) /* else the file's default grid, as for the density (brume_density_load) */
        snprintf(o->grid, sizeof o->grid, "%s", e[i].name);
    free(e);
    return BRUME_OK;
}

/* A medium's field object ("albedo", "temperature", "emission_field", "velocity"): a grid
 * object whose keys default to the medium's grid density's (same file, placement, filter),
 * so that {"grid": "temperature"} is the temperature grid of the density's file. Loads the
 * fields by `load`. */
static brume_status parse_field(const cJSON *medium_j, jloc at, const brume_scene *s, const char *key,
                                const char *const *extra, field_loader load, brume_density **out,
                                brume_grid_file_options *used)
{
    char kp[256];
    jloc fat = {at.file, json_key_path(kp, sizeof kp, at.path, key)};
    const cJSON *f = cJSON_GetObjectItemCaseSensitive(medium_j, key);
    if (!cJSON_IsObject(f))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object such as {\"grid\": \"NAME\"}", at.file, kp);
    cJSON *merged = cJSON_Duplicate(f, 1);
    if (!merged)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(medium_j, "density");
    const cJSON *dt = d ? cJSON_GetObjectItemCaseSensitive(d, "type") : NULL;
    if (cJSON_IsString(dt) && strcmp(dt->valuestring, "grid") == 0) {
        static const char *const inherit[] = {"file", "format", "dims", "bounds", "transform", "filter", "edge",
                                              "max_memory_mb", "frame_offset", "frame_step", "beyond"};
        bool own_place = cJSON_HasObjectItem(f, "bounds") || cJSON_HasObjectItem(f, "transform");
        for (size_t k = 0; k < sizeof inherit / sizeof *inherit; k++) {
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(d, inherit[k]);
            bool place = strcmp(inherit[k], "bounds") == 0 || strcmp(inherit[k], "transform") == 0;
            if (v && !cJSON_HasObjectItem(f, inherit[k]) && !(place && own_place))
                cJSON_AddItemToObject(merged, inherit[k], cJSON_Duplicate(v, 1));
        }
    }
    brume_grid_file_options o;
    char path[2048];
    bool sequence = false;
    brume_status st = scene_parse_grid_options(merged, fat, extra, scene_frame_number(s), path, sizeof path, &o, &sequence);
    cJSON_Delete(merged);
    if (st) return st;
    if (!cJSON_HasObjectItem(f, "grid") && (st = pick_by_role(fat, key, path, &o))) return st;
    st = load(NULL, path, &o, out);
    if (used)
        *used = o;
    if (st == BRUME_OK && sequence)
        (*out)->evolves = true; /* the scene's builder marks the world moving (scene_build.c) */
    return st ? err_prefix("%s: %s", at.file, kp) : BRUME_OK;
}

/* The "blackbody" object j (NULL: the defaults) of a medium: pbrt-v4's model (scale) or
 * Cycles' ("model": "blender": intensity, tint), with the temperature's mapping shared
 * (docs/scene-format.md, "Emission"). */
static brume_status parse_blackbody(const cJSON *j, jloc at, brume_blackbody *bb)
{
    brume_blackbody_default(bb);
    if (!j)
        return BRUME_OK;
    static const char *const pbrt_keys[] = {"model", "scale", "temperature_scale", "temperature_offset", "cutoff", NULL};
    static const char *const blender_keys[] = {"model", "intensity", "tint", "temperature_scale", "temperature_offset",
                                               "cutoff", NULL};
    char model[16] = "pbrt";
    if (!cJSON_IsObject(j))
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected an object", at.file, at.path);
    brume_status st = json_string(j, at, "model", 0, model, sizeof model);
    if (st) return st;
    bool blender = strcmp(model, "blender") == 0;
    if (!blender && strcmp(model, "pbrt") != 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.model: unknown blackbody model '%s' (known: pbrt, blender)", at.file,
                       at.path, model);
    if ((st = json_check_object(j, at, blender ? blender_keys : pbrt_keys))) return st;
    if (blender) {
        bb->model = BRUME_BLACKBODY_BLENDER;
        bb->cutoff = 0.0; /* Cycles: every temperature above 0 K glows */
        if ((st = json_number(j, at, "intensity", 0, 0.0, 1.0, &bb->intensity))) return st;
        if ((st = scene_json_color(j, at, "tint", 0, BIG, bb->tint))) return st;
    } else if ((st = json_number(j, at, "scale", 0, 1e-30, 1e30, &bb->scale))) {
        return st;
    }
    if ((st = json_number(j, at, "temperature_scale", 0, 1e-30, 1e30, &bb->temperature_scale))) return st;
    if ((st = json_number(j, at, "temperature_offset", 0, -1e30, 1e30, &bb->temperature_offset))) return st;
    return json_number(j, at, "cutoff", 0, 0.0, 1e30, &bb->cutoff);
}

/* "albedo", "temperature" + "blackbody", "emission_field", "velocity": the medium's optional
 * fields. */
static brume_status parse_medium_fields(const cJSON *j, jloc at, brume_scene *s, int index)
{
    brume_status st;
    char kp[256];
    if (cJSON_HasObjectItem(j, "albedo")) {
        brume_density *rgb[3];
        if ((st = parse_field(j, at, s, "albedo", NULL, brume_density_load_rgb, rgb, NULL))) return st;
        if ((st = scene_json_built(brume_scene_set_medium_albedo(NULL, s, index, rgb),
                                   (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "albedo")}))) {
            for (int c = 0; c < 3; c++)
                brume_density_release(rgb[c]);
            return st;
        }
    }
    const cJSON *bbj = cJSON_GetObjectItemCaseSensitive(j, "blackbody");
    if (bbj && !cJSON_HasObjectItem(j, "temperature"))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.blackbody: needs a \"temperature\" grid", at.file, at.path);
    if (cJSON_HasObjectItem(j, "temperature")) {
        brume_blackbody bb;
        if ((st = parse_blackbody(bbj, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "blackbody")}, &bb)))
            return st;
        brume_density *t = NULL;
        if ((st = parse_field(j, at, s, "temperature", NULL, brume_density_load, &t, NULL))) return st;
        if ((st = scene_json_built(brume_scene_set_medium_temperature(NULL, s, index, t, &bb),
                                   (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "temperature")}))) {
            brume_density_release(t);
            return st;
        }
    }
    if (cJSON_HasObjectItem(j, "emission_field")) {
        static const char *const extra[] = {"color", NULL};
        double c[3] = {1, 1, 1};
        const cJSON *f = cJSON_GetObjectItemCaseSensitive(j, "emission_field");
        jloc eat = {at.file, json_key_path(kp, sizeof kp, at.path, "emission_field")};
        if (cJSON_IsObject(f) && (st = scene_json_color(f, eat, "color", 0, BIG, c))) return st;
        brume_density *e[3];
        if ((st = parse_field(j, at, s, "emission_field", extra, brume_density_load_rgb, e, NULL))) return st;
        if ((st = scene_json_built(brume_scene_set_medium_emission_field(NULL, s, index, e, 3, c), eat))) {
            for (int k = 0; k < 3; k++)
                brume_density_release(e[k]);
            return st;
        }
    }
    if (cJSON_HasObjectItem(j, "velocity")) {
        /* "grid" names a vec3 grid or the stem of NAME.x/.y/.z ("" = "vel"); "scale" multiplies
         * the values into world units per second; the grid's transform (its own or the
         * density's) turns and scales the vectors as it places the grid */
        brume_density *v[3];
        brume_grid_file_options o;
        if ((st = parse_field(j, at, s, "velocity", NULL, brume_density_load_velocity, v, &o))) return st;
        double lin[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
        for (int r = 0; r < 3 && o.has_transform; r++)
            for (int c = 0; c < 3; c++)
                lin[3 * r + c] = o.transform[4 * r + c];
        if ((st = scene_json_built(brume_scene_set_medium_velocity(NULL, s, index, v, lin),
                                   (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "velocity")}))) {
            for (int k = 0; k < 3; k++)
                brume_density_release(v[k]);
            return st;
        }
    }
    return BRUME_OK;
}

brume_status scene_parse_medium(const cJSON *j, jloc at, brume_scene *s)
{
    static const char *const keys[] = {"name", "density", "sigma_a", "sigma_s", "phase", "emission", "emission_units",
                                       "keyframes", "albedo", "temperature", "blackbody", "emission_field", "velocity",
                                       NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_medium m = {0};
    if ((st = json_string(j, at, "name", 0, m.name, sizeof m.name))) return st;
    if ((st = scene_json_color(j, at, "sigma_a", 1, 1e12, m.sigma_a))) return st;
    if ((st = scene_json_color(j, at, "sigma_s", 1, 1e12, m.sigma_s))) return st;
    if ((st = scene_json_color(j, at, "emission", 0, BIG, m.emission))) return st;
    char kp[256], units[32] = "radiance";
    if ((st = json_string(j, at, "emission_units", 0, units, sizeof units))) return st;
    if (strcmp(units, "radiance_per_length") == 0)
        m.emission_units = BRUME_EMISSION_PER_LENGTH;
    else if (strcmp(units, "radiance") != 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.emission_units: unknown units '%s' (known: radiance, "
                       "radiance_per_length)", at.file, at.path, units);
    const cJSON *d = cJSON_GetObjectItemCaseSensitive(j, "density");
    if (!d)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.density: required key missing", at.file, at.path);
    brume_density *rho = NULL;
    brume_phase *ph = NULL;
    if ((st = scene_parse_density(d, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "density")}, s, &rho)))
        return st;
    const cJSON *p = cJSON_GetObjectItemCaseSensitive(j, "phase");
    if (p && (st = parse_phase(p, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "phase")}, &ph))) {
        brume_density_release(rho);
        return st;
    }
    if ((st = scene_json_built(brume_scene_add_medium(NULL, s, &m, rho, ph), at))) {
        brume_density_release(rho);
        brume_phase_release(ph);
        return st;
    }
    if ((st = parse_medium_fields(j, at, s, brume_scene_medium_count(s) - 1))) return st;
    const cJSON *keys_j = cJSON_GetObjectItemCaseSensitive(j, "keyframes");
    if (keys_j) {
        /* the field moves: its placement at time t is the keyed transform after its own */
        brume_transform_key k[MOTION_MAX_KEYS];
        int n = 0;
        jloc kat = {at.file, json_key_path(kp, sizeof kp, at.path, "keyframes")};
        if ((st = keys_parse_motion(keys_j, kat, k, &n))) return st;
        return scene_json_built(brume_scene_set_medium_motion(NULL, s, brume_scene_medium_count(s) - 1, k, n), kat);
    }
    return BRUME_OK;
}
