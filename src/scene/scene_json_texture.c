/* scene_json_texture.c - a scene file's texture objects flattened into brume_texture nodes,
 * each node before its inputs, with every key checked where it stands. */
#include "scene/scene_json_texture.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#define TEXTURE_MAX_DEPTH BRUME_TEXTURE_MAX_NODES /* a chain of nodes is as deep as it is long */

static brume_status add_node(json_texture *t, const cJSON *j, jloc at, bool is_float, int depth, int *index);

/* Input `key` of the texture object j: absent (-1, the default), a number, an RGB triple
 * (spectrum textures) or a texture object. */
static brume_status add_input(json_texture *t, const cJSON *j, jloc at, const char *key, bool is_float, int depth,
                              int *index)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, key);
    char kp[512];
    jloc kat = {at.file, json_key_path(kp, sizeof kp, at.path, key)};
    *index = -1;
    if (!v)
        return BRUME_OK;
    if (cJSON_IsObject(v))
        return add_node(t, v, kat, is_float, depth + 1, index);
    if (t->tex.n == BRUME_TEXTURE_MAX_NODES)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: more than %d texture nodes", at.file, kat.path,
                       BRUME_TEXTURE_MAX_NODES);
    color c;
    brume_status st = is_float && !cJSON_IsNumber(v)
                          ? err_set(BRUME_ERROR_PARSE, "%s: %s: expected a number or a texture object (a float "
                                    "texture)", at.file, kat.path)
                          : json_color(j, at, key, 1, -1e30, 1e30, &c);
    if (st) return st;
    *index = t->tex.n++;
    t->node[*index] = (brume_texture_node){.type = BRUME_TEXTURE_CONSTANT, .is_float = is_float,
                                           .value = {c.c[0], c.c[1], c.c[2]}, .tex1 = -1, .tex2 = -1, .amount = -1};
    return BRUME_OK;
}

/* An imagemap's own keys: file, encoding, scale, invert, wrap. */
static brume_status imagemap_keys(json_texture *t, const cJSON *j, jloc at, brume_texture_node *n, int index)
{
    char file[1024], path[4096], enc[64] = "sRGB", wrap[32] = "repeat";
    brume_status st;
    if ((st = json_string(j, at, "file", 1, file, sizeof file)) ||
        (st = json_string(j, at, "encoding", 0, enc, sizeof enc)) ||
        (st = json_string(j, at, "wrap", 0, wrap, sizeof wrap)) ||
        (st = json_number(j, at, "scale", 0, -1e30, 1e30, &n->scale)) ||
        (st = json_bool(j, at, "invert", 0, &n->invert)))
        return st;
    double g = 0.0;
    if (strcmp(enc, "linear") == 0)
        g = 1.0;
    else if (strncmp(enc, "gamma ", 6) == 0)
        g = strtod(enc + 6, NULL);
    else if (strcmp(enc, "sRGB") != 0)
        g = -1.0;
    if (!(g >= 0.0 && g <= 100.0) || (strncmp(enc, "gamma ", 6) == 0 && !(g > 0.0)))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.encoding: '%s' (known: sRGB, linear, \"gamma G\" with G in (0, 100])",
                       at.file, at.path, enc);
    n->gamma = g;
    static const char *const wraps[] = {"repeat", "black", "clamp"};
    int w = -1;
    for (int k = 0; k < 3; k++)
        if (strcmp(wrap, wraps[k]) == 0)
            w = k;
    if (w < 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.wrap: '%s' (known: repeat, black, clamp)", at.file, at.path, wrap);
    n->wrap = (brume_texture_wrap)w;
    json_resolve_path(at.file, file, path, sizeof path);
    size_t len = strlen(path) + 1;
    if (!(t->file[index] = malloc(len)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s: out of memory", at.file, at.path);
    memcpy(t->file[index], path, len);
    n->filename = t->file[index];
    return BRUME_OK;
}

static brume_status add_node(json_texture *t, const cJSON *j, jloc at, bool is_float, int depth, int *index)
{
    static const char *const constant_keys[] = {"type", "value", NULL};
    static const char *const image_keys[] = {"type", "file", "encoding", "scale", "invert", "wrap", "uscale", "vscale",
                                             "udelta", "vdelta", NULL};
    static const char *const scale_keys[] = {"type", "tex", "scale", NULL};
    static const char *const mix_keys[] = {"type", "tex1", "tex2", "amount", NULL};
    static const char *const checker_keys[] = {"type", "tex1", "tex2", "uscale", "vscale", "udelta", "vdelta", NULL};
    if (depth > TEXTURE_MAX_DEPTH)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: textures nested more than %d deep", at.file, at.path,
                       TEXTURE_MAX_DEPTH);
    if (t->tex.n == BRUME_TEXTURE_MAX_NODES)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: more than %d texture nodes", at.file, at.path,
                       BRUME_TEXTURE_MAX_NODES);
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    static const char *const names[] = {"constant", "imagemap", "scale", "mix", "checkerboard"};
    static const char *const *const keys[] = {constant_keys, image_keys, scale_keys, mix_keys, checker_keys};
    int k = -1;
    for (int i = 0; i < 5; i++)
        if (strcmp(type, names[i]) == 0)
            k = i;
    if (k < 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s.type: unknown texture '%s' (known: constant, imagemap, scale, mix, "
                       "checkerboard)", at.file, at.path, type);
    if ((st = json_check_object(j, at, keys[k]))) return st;
    int me = *index = t->tex.n++;
    brume_texture_node n = {.type = (brume_texture_type)k, .is_float = is_float, .tex1 = -1, .tex2 = -1, .amount = -1};
    if ((st = json_number(j, at, "uscale", 0, -1e12, 1e12, &n.uscale)) ||
        (st = json_number(j, at, "vscale", 0, -1e12, 1e12, &n.vscale)) ||
        (st = json_number(j, at, "udelta", 0, -1e12, 1e12, &n.udelta)) ||
        (st = json_number(j, at, "vdelta", 0, -1e12, 1e12, &n.vdelta)))
        return st;
    if (n.type == BRUME_TEXTURE_CONSTANT) {
        color c;
        if ((st = is_float ? json_number(j, at, "value", 1, -1e30, 1e30, &c.c[0])
                           : json_color(j, at, "value", 1, -1e30, 1e30, &c)))
            return st;
        for (int i = 0; i < 3; i++)
            n.value[i] = c.c[is_float ? 0 : i];
    } else if (n.type == BRUME_TEXTURE_IMAGEMAP) {
        if ((st = imagemap_keys(t, j, at, &n, me))) return st;
    } else if (n.type == BRUME_TEXTURE_SCALE) {
        if ((st = add_input(t, j, at, "tex", is_float, depth, &n.tex1)) ||
            (st = add_input(t, j, at, "scale", true, depth, &n.amount)))
            return st;
    } else {
        if ((st = add_input(t, j, at, "tex1", is_float, depth, &n.tex1)) ||
            (st = add_input(t, j, at, "tex2", is_float, depth, &n.tex2)) ||
            (n.type == BRUME_TEXTURE_MIX && (st = add_input(t, j, at, "amount", true, depth, &n.amount))))
            return st;
    }
    t->node[me] = n;
    return BRUME_OK;
}

brume_status scene_json_texture(const cJSON *j, jloc at, const char *key, bool is_float, json_texture **out)
{
    *out = calloc(1, sizeof **out);
    if (!*out)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s: out of memory", at.file, at.path);
    (*out)->tex.nodes = (*out)->node;
    char kp[512];
    int root;
    brume_status st = add_node(*out, cJSON_GetObjectItemCaseSensitive(j, key),
                               (jloc){at.file, json_key_path(kp, sizeof kp, at.path, key)}, is_float, 0, &root);
    if (st) {
        scene_json_texture_free(*out);
        *out = NULL;
    }
    return st;
}

void scene_json_texture_free(json_texture *t)
{
    if (!t)
        return;
    for (int i = 0; i < BRUME_TEXTURE_MAX_NODES; i++)
        free(t->file[i]);
    free(t);
}
