/* scene_pbrt.c - pbrt-v4 scene files translated to brume's scene description (JSON), then
 * read by the one scene reader (scene/scene_json.c). The subset read and the mapping of units
 * and conventions are in docs/pbrt.md. Every directive, type or
 * parameter outside that subset is refused with one line "FILE:LINE: ..." naming it. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/budget.h"
#include "core/error.h"
#include "core/regular_file.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/json.h"
#include "scene/film_sensor.h"
#include "scene/scene_build.h"
#include "scene/scene_pbrt.h"
#include "scene/pbrt.h"

static bool is_typed_directive(const char *dir)
{
    static const char *const typed[] = {"Camera", "Film", "Sampler", "Integrator", "Material", "AreaLightSource",
                                        "MakeNamedMaterial", "NamedMaterial", "PixelFilter",
                                        "LightSource", "Shape", "ColorSpace", "MakeNamedMedium"};
    for (size_t i = 0; i < sizeof typed / sizeof typed[0]; i++)
        if (strcmp(dir, typed[i]) == 0)
            return true;
    return false;
}

/* DIRECTIVE "type" (a medium's "name") and a parameter list. */
static brume_status typed_directive(pbrt_state *S, attrs *a, const char *dir, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    pbrt_next(L);
    const char *arg = strncmp(dir, "Make", 4) == 0 || strcmp(dir, "NamedMaterial") == 0 ? "name" : "type";
    if (L->kind != TOK_STRING)
        return pbrt_expected(L, "%s: expected its %s (a quoted string)", dir, arg);
    char type[128], what[200];
    if (strlen(L->text) >= sizeof type)
        return pbrt_fail(L, "%s: a %s longer than %zu bytes", dir, arg, sizeof type - 1);
    pbrt_copy(type, sizeof type, L->text);
    snprintf(what, sizeof what, "%s \"%s\"", dir, type);
    pbrt_next(L);
    if ((st = pbrt_read_params(L, ps))) return st;
    S->objects++;
    if ((st = pbrt_count_translation(S))) return st;
    /* what is placed by the current transform: pbrt-v4 inverts it for each of these */
    bool placed = strcmp(dir, "Camera") == 0 || strcmp(dir, "LightSource") == 0 || strcmp(dir, "Shape") == 0 ||
                  strcmp(dir, "MakeNamedMedium") == 0;
    const char *flaw = placed ? pbrt_m4_flaw(a->ctm) : NULL;
    if (flaw)
        return pbrt_fail(L, "%s: the current transform %s", what, flaw);
    if (strcmp(dir, "Camera") == 0)
        return pbrt_camera_directive(S, type, ps);
    if (strcmp(dir, "LightSource") == 0)
        return pbrt_light_directive(S, type, ps);
    if (strcmp(dir, "Shape") == 0)
        return pbrt_shape_directive(S, type, ps);
    if (strcmp(dir, "MakeNamedMedium") == 0)
        return pbrt_medium_directive(S, type, ps);
    if (strcmp(dir, "AreaLightSource") == 0)
        return pbrt_area_light_directive(S, a, type, ps);
    return pbrt_setting_directive(S, a, dir, type, what, ps);
}

static brume_status directive(pbrt_state *S, params *ps);
static brume_status lenient_directive(pbrt_state *S, params *ps);
static brume_status read_all(const char *path, char **out, size_t *len);

/* Include "file" and Import "file": the file's directives read in place, as pbrt-v4 does (the
 * path relative to the main file's folder). Import in pbrt-v4 works on a copy of the
 * graphics state (its transform, material and media do not come back); Include shares it. */
static brume_status include_directive(pbrt_state *S, params *ps, const char *dir)
{
    lexer *L = &S->L;
    pbrt_next(L);
    if (L->kind != TOK_STRING)
        return pbrt_fail(L, "%s: expected a file name", dir);
    if (S->includes == 8)
        return pbrt_fail(L, "%s \"%s\": included files nested more than 8 deep", dir, L->text);
    char abs[PATH_MAX], what[80];
    snprintf(what, sizeof what, "%s", dir);
    brume_status st = pbrt_resolve_file(S, what, L->text, abs);
    if (st)
        return st;
    char *text = NULL;
    size_t bytes = 0;
    if (read_all(abs, &text, &bytes) != BRUME_OK)
        return err_prefix("%s:%d: %s", L->file, L->dir_line, dir);
    if (bytes > PBRT_MAX_BYTES - S->text_bytes) {
        free(text);
        return pbrt_fail(L, "%s: the scene's files are over %ld bytes together", dir, (long)PBRT_MAX_BYTES);
    }
    S->text_bytes += bytes;
    pbrt_next(L); /* past the name: where the including file goes on */
    lexer outer = *L;
    int depth = S->depth;
    attrs *saved = strcmp(dir, "Import") == 0 ? malloc(sizeof S->a) : NULL;
    if (saved)
        memcpy(saved, S->a, sizeof S->a);
    *L = (lexer){abs, text, 1, TOK_END, "", 1, 1, NULL, NULL, false, false};
    L->outer = saved ? NULL : &outer; /* Include only: its last parameter list may go on */
    S->includes++;
    pbrt_next(L);
    while (st == BRUME_OK && L->kind != TOK_END && !L->resumed)
        st = lenient_directive(S, ps);
    S->includes--;
    bool resumed = L->resumed; /* L already reads on in the including file */
    L->resumed = false;
    if (st == BRUME_OK && !resumed && *L->p)
        st = pbrt_fail(L, "syntax error near \"%.64s\"", L->text);
    if (st == BRUME_OK && S->depth != depth)
        st = pbrt_fail(L, "%s: AttributeBegin and AttributeEnd do not balance in this file", dir);
    if (saved) {
        memcpy(S->a, saved, sizeof S->a);
        free(saved);
    }
    if (!resumed)
        *L = outer;
    if (st == BRUME_OK && S->ntexts == PBRT_MAX_TEXTS)
        st = pbrt_fail(L, "%s: more than %d included files", dir, PBRT_MAX_TEXTS);
    if (st == BRUME_OK)
        S->texts[S->ntexts++] = text; /* kept to the end: ObjectInstance may replay it */
    else
        free(text);
    return st;
}

/* MediumInterface "inside" ["outside"]: one name stands for both. */
static brume_status medium_interface(pbrt_state *S, attrs *a, const char *dir)
{
    lexer *L = &S->L;
    pbrt_next(L);
    if (L->kind != TOK_STRING)
        return pbrt_expected(L, "%s: expected a medium name (a quoted string)", dir);
    if (strlen(L->text) >= sizeof a->inside)
        return pbrt_fail(L, "%s: a medium name longer than %zu bytes", dir, sizeof a->inside - 1);
    pbrt_copy(a->inside, sizeof a->inside, L->text);
    pbrt_next(L);
    if (L->kind != TOK_STRING) {
        pbrt_copy(a->outside, sizeof a->outside, a->inside);
        return BRUME_OK;
    }
    if (strlen(L->text) >= sizeof a->outside)
        return pbrt_fail(L, "%s: a medium name longer than %zu bytes", dir, sizeof a->outside - 1);
    pbrt_copy(a->outside, sizeof a->outside, L->text);
    pbrt_next(L);
    return BRUME_OK;
}

static brume_status directive(pbrt_state *S, params *ps)
{
    lexer *L = &S->L;
    char dir[64];
    pbrt_copy(dir, sizeof dir, L->text);
    L->dir_line = L->tok_line;
    attrs *a = &S->a[S->depth];
    if (L->kind != TOK_WORD)
        return pbrt_expected(L, "expected a directive");
    brume_status st = pbrt_structure_directive(S, dir);
    if (st)
        return st;
    bool handled;
    st = pbrt_transform_directive(S, a, dir, &handled);
    if (handled)
        return st;
    if (is_typed_directive(dir))
        return typed_directive(S, a, dir, ps);
    if (strcmp(dir, "Include") == 0 || strcmp(dir, "Import") == 0)
        return include_directive(S, ps, dir);
    if (strcmp(dir, "Texture") == 0)
        return pbrt_texture_directive(S, ps);
    if (strncmp(dir, "Object", 6) == 0)
        return pbrt_object_directive(S, ps, dir, lenient_directive);
    if (strcmp(dir, "WorldBegin") == 0) {
        if (!S->have_camera)
            return pbrt_fail(L, "%s before a Camera", dir);
        S->world = true;
        S->world_line = L->dir_line;
        a->ctm = pbrt_world_origin(S);
        pbrt_next(L);
    } else if (strcmp(dir, "AttributeBegin") == 0 || strcmp(dir, "TransformBegin") == 0) {
        return pbrt_attribute_begin(S, dir);
    } else if (strcmp(dir, "AttributeEnd") == 0 || strcmp(dir, "TransformEnd") == 0) {
        return pbrt_attribute_end(S, dir);
    } else if (strcmp(dir, "MediumInterface") == 0) {
        return medium_interface(S, a, dir);
    } else if (strcmp(dir, "ReverseOrientation") == 0) {
        a->reverse = !a->reverse; /* pbrt-v4 toggles it for the shapes that follow in the block */
        pbrt_next(L);
    } else {
        return pbrt_unsupported(L, "%s: not supported by brume's pbrt reader (docs/pbrt.md lists what is)", dir);
    }
    return BRUME_OK;
}

/* With --lenient, a directive refused as unsupported (pbrt_unsupported) becomes one entry
 * of the list of what was ignored ("FILE:LINE: what", each once) and is skipped as if absent:
 * the graphics state it may have begun to change is restored, and the tokens up to the next
 * directive (a word with a capital) are passed over. Malformed input stays an error. */
static brume_status lenient_directive(pbrt_state *S, params *ps)
{
    lexer *L = &S->L;
    const char *after_word = L->p;
    int depth = S->depth;
    attrs saved = S->a[depth];
    brume_status st = directive(S, ps);
    if (st != BRUME_ERROR_UNSUPPORTED || !S->ignored)
        return st;
    if ((st = pbrt_ignore(S->ignored, S->path)))
        return st;
    if (S->depth == depth)
        S->a[depth] = saved;
    if (L->p == after_word)
        pbrt_next(L); /* refused at its name: its arguments follow */
    while (L->kind != TOK_END && !(L->kind == TOK_WORD && isupper((unsigned char)L->text[0]))) {
        if (L->kind == TOK_BAD)
            return pbrt_fail(L, "a token brume cannot read");
        pbrt_next(L);
    }
    return BRUME_OK;
}

bool scene_pbrt_is_pbrt(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot && strcmp(dot, ".pbrt") == 0;
}

static brume_status read_all(const char *path, char **out, size_t *len)
{
    *out = NULL;
    FILE *f = NULL;
    if (io_open_regular(path, &f) != BRUME_OK)
        return err_status();
    if (io_check_size(f, path, "a pbrt scene", PBRT_MAX_BYTES) != BRUME_OK) {
        fclose(f);
        return err_status();
    }
    struct stat sb;
    size_t size = fstat(fileno(f), &sb) == 0 ? (size_t)sb.st_size : 0;
    char *buf = malloc(size + 1);
    /* one byte more than the size: a file that grew since is refused, not cut */
    size_t n = buf ? fread(buf, 1, size + 1, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (!buf)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (bad || n > size) {
        free(buf);
        return err_set(BRUME_ERROR_IO, "%s: %s", path, bad ? "read error" : "changed while it was read");
    }
    *len = n;
    buf[n] = '\0';
    if (strlen(buf) != n) {
        free(buf);
        return err_set(BRUME_ERROR_PARSE, "%s: contains a NUL byte; not a pbrt scene", path);
    }
    *out = buf;
    return BRUME_OK;
}

/* The translation read (S) as brume's scene description: the camera, the lights, media and
 * surfaces collected, and the render settings, printed into *json. */
static brume_status emit_scene(pbrt_state *S, const char *path, char **json)
{
    char note[600];
    snprintf(note, sizeof note, "translated by brume from the pbrt-v4 scene %s (docs/pbrt.md)", path);
    cJSON_AddStringToObject(S->root, "comment", note);
    cJSON *cam = cJSON_AddObjectToObject(S->root, "camera");
    vec3 P = pbrt_m4_point(S->world_from_camera, v3(0, 0, 0));
    vec3 F = v3_normalize(pbrt_m4_vector(S->world_from_camera, v3(0, 0, 1)));
    vec3 U = v3_normalize(pbrt_m4_vector(S->world_from_camera, v3(0, 1, 0)));
    vec3 A = v3_add(P, F);
    double pv[3] = {P.x, P.y, P.z}, av[3] = {A.x, A.y, A.z}, uv[3] = {U.x, U.y, U.z};
    cJSON_AddItemToObject(cam, "position", cJSON_CreateDoubleArray(pv, 3));
    cJSON_AddItemToObject(cam, "look_at", cJSON_CreateDoubleArray(av, 3));
    cJSON_AddItemToObject(cam, "up", cJSON_CreateDoubleArray(uv, 3));
    /* pbrt's fov spans the shorter image side; brume's is vertical */
    double fov = S->fov;
    if (S->yres > S->xres)
        fov = 2.0 * atan(tan(0.5 * fov * PI / 180.0) * S->yres / S->xres) * 180.0 / PI;
    cJSON_AddNumberToObject(cam, "fov", fov);
    if (pbrt_media_resolve(S) != BRUME_OK || pbrt_camera_medium(S, cam, P) != BRUME_OK ||
        pbrt_media_finish(S) != BRUME_OK)
        return err_status();
    pbrt_imaging(S);
    if (S->lens_radius > 0.0) {
        cJSON_AddNumberToObject(cam, "aperture_radius", S->lens_radius);
        cJSON_AddNumberToObject(cam, "focus_distance", S->focal_distance);
    }
    if (S->have_background)
        cJSON_AddItemToObject(S->root, "background", cJSON_CreateDoubleArray(S->background, 3));
    cJSON_AddItemToObject(S->root, "lights", S->lights);
    cJSON_AddItemToObject(S->root, "media", S->media_j);
    cJSON_AddItemToObject(S->root, "surfaces", S->surfaces);
    S->lights = S->media_j = S->surfaces = NULL;
    if (S->ignored && cJSON_GetArraySize(S->ignored) > 0) {
        cJSON_AddItemToObject(S->root, "ignored", S->ignored);
        S->ignored = NULL;
    }
    cJSON *r = cJSON_AddObjectToObject(S->root, "render");
    cJSON_AddNumberToObject(r, "width", S->xres);
    cJSON_AddNumberToObject(r, "height", S->yres);
    cJSON_AddNumberToObject(r, "spp", S->spp);
    cJSON_AddStringToObject(r, "method", "path");
    cJSON_AddNumberToObject(r, "max_depth", S->max_depth);
    if (S->max_component > 0.0)
        cJSON_AddNumberToObject(r, "max_component", S->max_component);
    if (S->white_balance > 0.0)
        cJSON_AddNumberToObject(r, "white_balance", S->white_balance);
    if (S->sensor > 0)
        cJSON_AddStringToObject(r, "sensor", film_sensor_name(S->sensor));
    if (S->box_filter > 0.0) {
        cJSON *f = cJSON_AddObjectToObject(r, "filter");
        cJSON_AddStringToObject(f, "type", "box");
        cJSON_AddNumberToObject(f, "width", S->box_filter);
    }
    if (!(*json = cJSON_Print(S->root)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    return BRUME_OK;
}

brume_status scene_pbrt_json(const char *path, char **json) { return scene_pbrt_read(path, false, json); }

brume_status scene_pbrt_read(const char *path, bool lenient, char **json)
{
    *json = NULL;
    char *text = NULL;
    size_t text_bytes = 0;
    if (read_all(path, &text, &text_bytes) != BRUME_OK)
        return err_status();
    pbrt_state *S = calloc(1, sizeof *S);
    params *ps = calloc(1, sizeof *ps);
    if (!S || !ps) {
        free(S);
        free(ps);
        free(text);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    S->L = (lexer){path, text, 1, TOK_END, "", 1, 1, NULL, NULL, false, false};
    S->path = path;
    S->text_bytes = text_bytes;
    char tmp[PATH_MAX];
    pbrt_copy(tmp, sizeof tmp, path);
    char *slash = strrchr(tmp, '/');
    snprintf(S->dir, sizeof S->dir, "%s", slash ? (*slash = '\0', tmp[0] ? tmp : "/") : ".");
    S->a[0].ctm = pbrt_m4_identity();
    snprintf(S->a[0].material, sizeof S->a[0].material, "diffuse");
    pbrt_copy(S->a[0].mat_json, sizeof S->a[0].mat_json, "{\"albedo\":[0.5,0.5,0.5]}");
    S->xres = 1280;
    S->yres = 720;
    S->spp = 16;
    S->max_depth = 5;
    S->iso = 100.0;
    S->exposure_time = 1.0;
    S->root = cJSON_CreateObject();
    S->lights = cJSON_CreateArray();
    S->media_j = cJSON_CreateArray();
    S->surfaces = cJSON_CreateArray();
    S->ignored = lenient ? cJSON_CreateArray() : NULL;
    ps->ignored = S->ignored;
    brume_status st = lenient && !S->ignored ? err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path) : BRUME_OK;
    pbrt_next(&S->L);
    while (st == BRUME_OK && S->L.kind != TOK_END)
        st = lenient_directive(S, ps);
    if (st == BRUME_OK)
        st = pbrt_structure_end(S);
    if (st == BRUME_OK)
        st = emit_scene(S, path, json);
    for (int i = 0; i < S->nmedia; i++)
        if (!S->media[i].emitted)
            cJSON_Delete(S->media[i].json);
    for (int i = 0; i < S->ntexts; i++)
        free(S->texts[i]);
    pbrt_textures_free(S);
    pbrt_media_free(S);
    cJSON_Delete(S->lights);
    cJSON_Delete(S->media_j);
    cJSON_Delete(S->surfaces);
    cJSON_Delete(S->ignored);
    cJSON_Delete(S->root);
    free(S);
    pbrt_params_clear(ps);
    free(ps);
    free(text);
    return st;
}
