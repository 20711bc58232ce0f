/* scene_json_density.c - a medium's "density" in the scene file: grid files (with their
 * placement, filter and frame sequence), inline arrays, fractal noise and blobs. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

static brume_status parse_box(const cJSON *j, jloc at, const char *key, double out[6])
{
    char kp[256];
    json_key_path(kp, sizeof kp, at.path, key);
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!it)
        return BRUME_OK;
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 2)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: expected [[xmin, ymin, zmin], [xmax, ymax, zmax]]", at.file, kp);
    cJSON *wrap = cJSON_CreateObject();
    if (!wrap)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", at.file);
    cJSON_AddItemReferenceToObject(wrap, "lo", cJSON_GetArrayItem(it, 0));
    cJSON_AddItemReferenceToObject(wrap, "hi", cJSON_GetArrayItem(it, 1));
    jloc sub = {at.file, kp};
    double r[6];
    brume_status st = scene_json_vec(wrap, sub, "lo", 1, r);
    if (!st)
        st = scene_json_vec(wrap, sub, "hi", 1, r + 3);
    cJSON_Delete(wrap);
    if (st)
        return st;
    if (!(r[0] < r[3] && r[1] < r[4] && r[2] < r[5]))
        return err_set(BRUME_ERROR_RANGE, "%s: %s: need min < max on every axis", at.file, kp);
    memcpy(out, r, sizeof r);
    return BRUME_OK;
}

static brume_status parse_filter(const cJSON *j, jloc at, brume_grid_filter *f)
{
    char name[32] = "";
    brume_status st = json_string(j, at, "filter", 0, name, sizeof name);
    if (st || !name[0])
        return st;
    if (strcmp(name, "nearest") == 0)
        *f = BRUME_GRID_NEAREST;
    else if (strcmp(name, "trilinear") == 0)
        *f = BRUME_GRID_TRILINEAR;
    else
        return err_set(BRUME_ERROR_PARSE, "%s: %s.filter: unknown filter '%s' (known: nearest, trilinear)", at.file,
                       at.path, name);
    return BRUME_OK;
}

/* The scene's frame number: the frame it was loaded at, or its time in frames. */
long scene_frame_number(const brume_scene *s)
{
    return lround(s->time * s->settings.fps);
}

/* A grid file name with a frame pattern (io/grid_sequence.h): the frame's file into path,
 * from frame_offset, frame_step and beyond. Without a pattern those keys are errors. */
static brume_status parse_sequence(const cJSON *j, jloc at, const char *name, long frame_no, char *path, size_t cap)
{
    int pat = seq_is_pattern(name);
    if (pat < 0)
        return err_prefix("%s: %s.file", at.file, at.path);
    if (!pat) {
        static const char *const seq_keys[] = {"frame_offset", "frame_step", "beyond"};
        for (int k = 0; k < 3; k++)
            if (cJSON_HasObjectItem(j, seq_keys[k]))
                return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s.%s: only with a frame pattern in file (%%04d, ####, $F4)",
                               at.file, at.path, seq_keys[k]);
        return BRUME_OK;
    }
    seq_options so = {0, 1, SEQ_REFUSE};
    double offset = 0.0, step = 1.0;
    char beyond[16] = "refuse";
    brume_status st;
    if ((st = json_number(j, at, "frame_offset", 0, -1e9, 1e9, &offset))) return st;
    if ((st = json_number(j, at, "frame_step", 0, 1.0, 1e6, &step))) return st;
    if (offset != floor(offset) || step != floor(step))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: must be an integer", at.file, at.path,
                       offset != floor(offset) ? "frame_offset" : "frame_step");
    if ((st = json_string(j, at, "beyond", 0, beyond, sizeof beyond))) return st;
    if (!seq_beyond_from_name(beyond, &so.beyond))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.beyond: unknown '%s' (known: refuse, hold, loop)", at.file, at.path,
                       beyond);
    so.offset = (long)offset;
    so.step = (long)step;
    char pattern[2048];
    snprintf(pattern, sizeof pattern, "%s", path);
    if (seq_file(pattern, &so, frame_no, path, cap) != BRUME_OK)
        return err_prefix("%s: %s.file", at.file, at.path);
    return BRUME_OK;
}

/* The file and loading options of a grid object (a density of type "grid", or a medium's
 * field) at scene frame `frame`; `extra` lists keys the caller handles itself. */
brume_status scene_parse_grid_options(const cJSON *j, jloc at, const char *const *extra, long frame_no, char *path,
                                      size_t cap, brume_grid_file_options *o, bool *sequence)
{
    static const char *const base[] = {"type", "file", "grid", "format", "dims", "bounds", "transform", "filter",
                                       "edge", "scale", "max_memory_mb", "frame_offset", "frame_step", "beyond"};
    const char *keys[24];
    int nk = 0;
    for (size_t k = 0; k < sizeof base / sizeof *base; k++)
        keys[nk++] = base[k];
    for (int k = 0; extra && extra[k] && nk < 23; k++)
        keys[nk++] = extra[k];
    keys[nk] = NULL;
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_grid_file_options_default(o);
    char name[1024];
    if ((st = json_string(j, at, "file", 1, name, sizeof name))) return st;
    json_resolve_path(at.file, name, path, cap);
    if ((st = parse_sequence(j, at, name, frame_no, path, cap))) return st;
    *sequence = seq_is_pattern(name) == 1; /* a file per frame: the world is not static */
    if ((st = json_string(j, at, "grid", 0, o->grid, sizeof o->grid))) return st;
    char format[16] = "";
    if ((st = json_string(j, at, "format", 0, format, sizeof format))) return st;
    if (format[0]) {
        o->format = (brume_grid_format)grid_format_from_name(format);
        if (o->format == BRUME_GRID_FORMAT_AUTO && strcmp(format, "auto") != 0)
            return err_set(BRUME_ERROR_PARSE, "%s: %s.format: unknown grid format '%s' (known: auto, raw, df3, vol, "
                           "nvdb, vdb)", at.file, at.path, format);
    }
    if (cJSON_HasObjectItem(j, "dims")) {
        double d[3] = {0, 0, 0};
        if ((st = scene_json_vec(j, at, "dims", 1, d))) return st;
        for (int k = 0; k < 3; k++) {
            if (!(d[k] >= 1 && d[k] <= 65536) || d[k] != floor(d[k]))
                return err_set(BRUME_ERROR_RANGE, "%s: %s.dims[%d]: %g is not an integer in [1, 65536]", at.file,
                               at.path, k, d[k]);
            o->dims[k] = (int)d[k];
        }
    }
    if (cJSON_HasObjectItem(j, "bounds")) {
        if ((st = parse_box(j, at, "bounds", o->bounds))) return st;
        o->has_bounds = true;
    }
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(j, "transform");
    if (tr) {
        char kp[256];
        affine3 xf;
        if ((st = json_transform(tr, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")}, true, &xf)))
            return st;
        memcpy(o->transform, xf.m, sizeof o->transform);
        o->has_transform = true;
    }
    if ((st = parse_filter(j, at, &o->filter))) return st;
    char edge[16] = "hold";
    if ((st = json_string(j, at, "edge", 0, edge, sizeof edge))) return st;
    if (strcmp(edge, "hold") != 0 && strcmp(edge, "zero") != 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.edge: unknown '%s' (known: hold, zero)", at.file, at.path, edge);
    o->edge_zero = strcmp(edge, "zero") == 0;
    if ((st = json_number(j, at, "scale", 0, 1e-30, 1e30, &o->scale))) return st;
    if ((st = json_number(j, at, "max_memory_mb", 0, 1.0, 1e9, &o->max_memory_mb))) return st;
    return BRUME_OK;
}

/* A voxel grid from a file (docs/grids.md lists the formats). `made_by`, the command that
 * makes a file a scene ships without (scenes/fire-vdb.json's `brume gen fire`), is named
 * when the file is missing. */
static brume_status parse_grid_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out)
{
    static const char *const extra[] = {"made_by", NULL};
    brume_grid_file_options o;
    char path[2048], made_by[512] = "";
    bool sequence = false;
    brume_status st = scene_parse_grid_options(j, at, extra, scene_frame_number(s), path, sizeof path, &o, &sequence);
    if (st || (st = json_string(j, at, "made_by", 0, made_by, sizeof made_by))) return st;
    st = brume_density_load(NULL, path, &o, out);
    if (st == BRUME_OK && sequence)
        (*out)->evolves = true; /* frames differ: the scene is loaded again for each */
    if (st && made_by[0] && access(path, F_OK) != 0) {
        char msg[1200];
        snprintf(msg, sizeof msg, "%s", err_message());
        return err_set(st, "%s: %s.file: %s (make it with: %s)", at.file, at.path, msg, made_by);
    }
    return st ? err_prefix("%s: %s.file", at.file, at.path) : BRUME_OK;
}

/* The values of `data` (nx ny nz of them, checked), x fastest, into a new array *out of
 * m[0] x m[1] x m[2] = (nx + 2 p) x (ny + 2 p) x (nz + 2 p), p layers of zeros around them. */
static brume_status array_values(const cJSON *data, jloc at, const int m[3], int p, float **out)
{
    const size_t nx = (size_t)(m[0] - 2 * p), ny = (size_t)(m[1] - 2 * p);
    float *v = calloc((size_t)m[0] * (size_t)m[1] * (size_t)m[2], sizeof *v);
    if (!v)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s.data: out of memory", at.file, at.path);
    size_t i = 0;
    for (const cJSON *e = data->child; e; e = e->next, i++) {
        if (!cJSON_IsNumber(e) || !(e->valuedouble >= 0.0 && e->valuedouble <= 1e30)) {
            free(v);
            return err_set(BRUME_ERROR_RANGE, "%s: %s.data[%zu]: expected a number in [0, 1e30]", at.file, at.path, i);
        }
        size_t x = i % nx + (size_t)p, y = i / nx % ny + (size_t)p, z = i / (nx * ny) + (size_t)p;
        v[x + (size_t)m[0] * (y + (size_t)m[1] * z)] = (float)e->valuedouble;
    }
    *out = v;
    return BRUME_OK;
}

/* A voxel grid given inline: `dims` [nx, ny, nz], `data` nx ny nz numbers >= 0, x fastest
 * (brume_density_new_array's layout), placed by `bounds` then `transform` as a grid file is. */
static brume_status parse_array_density(const cJSON *j, jloc at, brume_density **out)
{
    static const char *const keys[] = {"type", "dims", "data", "bounds", "transform", "filter", "edge", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    double d[3] = {0, 0, 0}, b[6] = {-1, -1, -1, 1, 1, 1};
    if ((st = scene_json_vec(j, at, "dims", 1, d))) return st;
    for (int k = 0; k < 3; k++)
        if (!(d[k] >= 1 && d[k] <= 65536) || d[k] != floor(d[k]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.dims[%d]: %g is not an integer in [1, 65536]", at.file, at.path,
                           k, d[k]);
    double count = d[0] * d[1] * d[2];
    if (count > SCENE_INLINE_MAX_VALUES)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.dims: %g x %g x %g voxels, over the %d an inline grid may hold "
                       "(a larger grid belongs in a file)", at.file, at.path, d[0], d[1], d[2], SCENE_INLINE_MAX_VALUES);
    const cJSON *data = cJSON_GetObjectItemCaseSensitive(j, "data");
    if (!cJSON_IsArray(data))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.data: expected an array of nx ny nz numbers", at.file, at.path);
    int n = cJSON_GetArraySize(data);
    if (n != (int)count)
        return err_set(BRUME_ERROR_RANGE, "%s: %s.data: %d values for dims %g x %g x %g (%g)", at.file, at.path, n,
                       d[0], d[1], d[2], count);
    if ((st = parse_box(j, at, "bounds", b))) return st;
    brume_grid_filter filter = BRUME_GRID_TRILINEAR;
    if ((st = parse_filter(j, at, &filter))) return st;
    char edge[16] = "hold";
    if ((st = json_string(j, at, "edge", 0, edge, sizeof edge))) return st;
    if (strcmp(edge, "hold") != 0 && strcmp(edge, "zero") != 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.edge: unknown '%s' (known: hold, zero)", at.file, at.path, edge);
    /* pbrt-v4's samples beyond the grid read 0; a nearest lookup never reads beyond it */
    bool zero = strcmp(edge, "zero") == 0 && filter == BRUME_GRID_TRILINEAR;
    affine3 xf;
    char kp[256];
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(j, "transform");
    if (tr && (st = json_transform(tr, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")}, true, &xf)))
        return st;
    /* edge zero: the grid inside a layer of zero samples, one cell wider on every side, and
       rho cut to the grid's own box: the trilinear field is pbrt-v4's SampledGrid there */
    int p = zero ? 1 : 0, m[3] = {(int)d[0] + 2 * p, (int)d[1] + 2 * p, (int)d[2] + 2 * p};
    float *v = NULL;
    if ((st = array_values(data, at, m, p, &v))) return st;
    double wb[6];
    for (int k = 0; k < 3; k++) {
        double cell = (b[k + 3] - b[k]) / d[k];
        wb[k] = b[k] - p * cell;
        wb[k + 3] = b[k + 3] + p * cell;
    }
    st = brume_density_new_array(NULL, v, m[0], m[1], m[2], wb, filter, NULL, NULL, out);
    free(v);
    if (st)
        return err_prefix("%s: %s", at.file, at.path);
    if (zero) {
        const double lo[3] = {1, 1, 1}, hi[3] = {d[0] + 1, d[1] + 1, d[2] + 1};
        density_crop((*out)->d, lo, hi);
    }
    if (tr) { /* after the bounds, as a grid file's `transform` */
        density_info info;
        density_get_info((*out)->d, &info);
        affine3 v2w = affine3_compose(&xf, &info.voxel_to_world);
        if (!density_place((*out)->d, &v2w)) {
            brume_density_release(*out);
            *out = NULL;
            return err_prefix("%s: %s.transform", at.file, at.path);
        }
    }
    return BRUME_OK;
}

/* A fractal cloud grid generated at load time (src/density/fractal.h, Blasi 4.1), at the
 * scene's frame time added to its own `time`: the threshold and the turbulence evolve. */
static brume_status parse_fractal_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out)
{
    static const char *const keys[] = {"type", "dims", "seed", "method", "hurst", "octaves", "frequency", "shape",
                                       "falloff", "threshold", "threshold_rate", "turbulence",
                                       "turbulence_frequency", "wind", "time", "density", "bounds", "filter", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    brume_fractal p;
    brume_fractal_default(&p);
    double d[3] = {p.dims[0], p.dims[1], p.dims[2]};
    if ((st = scene_json_vec(j, at, "dims", 0, d))) return st;
    for (int k = 0; k < 3; k++) {
        if (!(d[k] >= 1 && d[k] <= 1024) || d[k] != floor(d[k]))
            return err_set(BRUME_ERROR_RANGE, "%s: %s.dims[%d]: %g is not an integer in [1, 1024]", at.file, at.path,
                           k, d[k]);
        p.dims[k] = (int)d[k];
    }
    char m[32] = "", sh[32] = "";
    if ((st = json_u64(j, at, "seed", 0, &p.seed))) return st;
    if ((st = json_string(j, at, "method", 0, m, sizeof m))) return st;
    if (m[0]) {
        if (strcmp(m, "midpoint") == 0) p.method = BRUME_FRACTAL_MIDPOINT;
        else if (strcmp(m, "spectral") == 0) p.method = BRUME_FRACTAL_SPECTRAL;
        else if (strcmp(m, "perlin") == 0) p.method = BRUME_FRACTAL_PERLIN;
        else
            return err_set(BRUME_ERROR_PARSE, "%s: %s.method: unknown method '%s' (known: midpoint, spectral, perlin)",
                           at.file, at.path, m);
    }
    if ((st = json_string(j, at, "shape", 0, sh, sizeof sh))) return st;
    if (sh[0]) {
        if (strcmp(sh, "none") == 0) p.shape = BRUME_FRACTAL_SHAPE_NONE;
        else if (strcmp(sh, "ellipsoid") == 0) p.shape = BRUME_FRACTAL_SHAPE_ELLIPSOID;
        else if (strcmp(sh, "slab") == 0) p.shape = BRUME_FRACTAL_SHAPE_SLAB;
        else
            return err_set(BRUME_ERROR_PARSE, "%s: %s.shape: unknown shape '%s' (known: none, ellipsoid, slab)",
                           at.file, at.path, sh);
    }
    if ((st = json_number(j, at, "hurst", 0, 1e-3, 0.999, &p.hurst))) return st;
    if ((st = json_int(j, at, "octaves", 0, 1, 16, &p.octaves))) return st;
    if ((st = json_number(j, at, "frequency", 0, 1e-3, 1e3, &p.frequency))) return st;
    if ((st = json_number(j, at, "falloff", 0, 1e-3, 1.0, &p.falloff))) return st;
    if ((st = json_number(j, at, "threshold", 0, 0.0, 0.99, &p.threshold))) return st;
    if ((st = json_number(j, at, "threshold_rate", 0, -1e3, 1e3, &p.threshold_rate))) return st;
    if ((st = json_number(j, at, "turbulence", 0, 0.0, 1e3, &p.turbulence))) return st;
    if ((st = json_number(j, at, "turbulence_frequency", 0, 1e-3, 1e3, &p.turbulence_frequency))) return st;
    if ((st = scene_json_vec(j, at, "wind", 0, p.wind))) return st;
    if ((st = json_number(j, at, "time", 0, -1e9, 1e9, &p.time))) return st;
    if ((st = json_number(j, at, "density", 0, 1e-9, 1e9, &p.density))) return st;
    if ((st = parse_box(j, at, "bounds", p.bounds))) return st;
    if ((st = parse_filter(j, at, &p.filter))) return st;
    p.time += brume_scene_time(s);
    return scene_json_built(brume_density_new_fractal(NULL, &p, out), at);
}

/* pbrt-v4's cloud: its parameters, `bounds` its box [p0, p1], placed by `transform` after it
 * (pbrt's renderFromMedium), as an array's bounds and transform. */
static brume_status parse_pbrt_cloud(const cJSON *j, jloc at, brume_density **out)
{
    static const char *const keys[] = {"type", "density", "wispiness", "frequency", "bounds", "transform", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    double dens = 1.0, wispiness = 1.0, frequency = 5.0, b[6] = {0, 0, 0, 1, 1, 1};
    if ((st = json_number(j, at, "density", 0, 0.0, 1e30, &dens))) return st;
    if ((st = json_number(j, at, "wispiness", 0, 0.0, 1e30, &wispiness))) return st;
    if ((st = json_number(j, at, "frequency", 0, 0.0, 1e30, &frequency))) return st;
    if ((st = parse_box(j, at, "bounds", b))) return st;
    affine3 xf;
    char kp[256];
    const cJSON *tr = cJSON_GetObjectItemCaseSensitive(j, "transform");
    if (tr && (st = json_transform(tr, (jloc){at.file, json_key_path(kp, sizeof kp, at.path, "transform")}, true, &xf)))
        return st;
    if ((st = scene_json_built(brume_density_new_pbrt_cloud(NULL, dens, wispiness, frequency, b, out), at)))
        return st;
    if (tr) {
        density_info info;
        density_get_info((*out)->d, &info);
        affine3 v2w = affine3_compose(&xf, &info.voxel_to_world);
        if (!density_place((*out)->d, &v2w)) {
            brume_density_release(*out);
            *out = NULL;
            return err_prefix("%s: %s.transform", at.file, at.path);
        }
    }
    return BRUME_OK;
}

brume_status scene_parse_density(const cJSON *j, jloc at, const brume_scene *s, brume_density **out)
{
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    if (strcmp(type, "procedural_cloud") == 0) {
        static const char *const keys[] = {"type", "resolution", "seed", "bounds", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        int res = 64;
        uint64_t seed = 1;
        double b[6] = {-1, -1, -1, 1, 1, 1};
        if ((st = json_int(j, at, "resolution", 0, 2, 512, &res))) return st;
        if ((st = json_u64(j, at, "seed", 0, &seed))) return st;
        if ((st = parse_box(j, at, "bounds", b))) return st;
        return scene_json_built(brume_density_new_procedural_cloud(NULL, res, seed, b, out), at);
    }
    if (strcmp(type, "blobs") == 0)
        return scene_parse_blobs(j, at, out); /* Stam's gaussian blobs (scene/scene_stam.c) */
    if (strcmp(type, "constant") == 0) {
        /* homogeneous fog filling a box */
        static const char *const keys[] = {"type", "value", "bounds", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        double value = 1.0, b[6] = {-1, -1, -1, 1, 1, 1};
        if ((st = json_number(j, at, "value", 0, 0.0, 1e30, &value))) return st;
        if ((st = parse_box(j, at, "bounds", b))) return st;
        return scene_json_built(brume_density_new_constant(NULL, value, b, out), at);
    }
    if (strcmp(type, "grid") == 0)
        return parse_grid_density(j, at, s, out);
    if (strcmp(type, "array") == 0)
        return parse_array_density(j, at, out);
    if (strcmp(type, "fractal_cloud") == 0)
        return parse_fractal_density(j, at, s, out);
    if (strcmp(type, "pbrt_cloud") == 0)
        return parse_pbrt_cloud(j, at, out);
    return err_set(BRUME_ERROR_PARSE,
                   "%s: %s.type: unknown density type '%s' (known: constant, procedural_cloud, grid, array, fractal_cloud, "
                   "blobs, pbrt_cloud)",
                   at.file, at.path, type);
}
