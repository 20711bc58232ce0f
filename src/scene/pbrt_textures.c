/* pbrt_textures.c - pbrt-v4's Texture directive as far as brume reads textures (imagemap,
 * scale, mix, checkerboard, constant; the uv mapping), each translated to brume's texture
 * JSON (docs/scene-format.md, "Textures") with the textures it names copied in, and a
 * material's reflectance given as a texture. Float and spectrum textures have their own
 * names, as in pbrt-v4. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "io/json.h"
#include "scene/pbrt.h"

void pbrt_textures_free(pbrt_state *S)
{
    for (int i = 0; i < S->ntextures; i++)
        cJSON_Delete(S->textures[i].json);
    S->ntextures = 0;
}

/* The latest texture of that name and kind, or NULL. */
static const named_texture *find_texture(const pbrt_state *S, const char *name, bool is_float)
{
    for (int i = S->ntextures - 1; i >= 0; i--)
        if (S->textures[i].is_float == is_float && strcmp(S->textures[i].name, name) == 0)
            return &S->textures[i];
    return NULL;
}

/* The nodes of a texture tree as brume's JSON reader makes them (BRUME_TEXTURE_MAX_NODES at
 * most): one per texture object and one per input given as a value. */
static int count_nodes(const cJSON *j)
{
    const cJSON *type = cJSON_GetObjectItemCaseSensitive(j, "type");
    bool scale = cJSON_IsString(type) && strcmp(type->valuestring, "scale") == 0;
    int n = 1;
    for (const cJSON *c = j->child; c; c = c->next) {
        bool input = strcmp(c->string, "tex") == 0 || strcmp(c->string, "tex1") == 0 ||
                     strcmp(c->string, "tex2") == 0 || strcmp(c->string, "amount") == 0 ||
                     (scale && strcmp(c->string, "scale") == 0);
        n += !input ? 0 : cJSON_IsObject(c) ? count_nodes(c) : 1;
    }
    return n;
}

/* Parameter `name` as a texture input under `key` of node: a "texture" naming one of this
 * kind (copied in), a number (float) or a colour (spectrum); absent: the class's default. */
static brume_status texture_input(pbrt_state *S, params *ps, const char *what, const char *name, bool is_float,
                                  cJSON *node, const char *key)
{
    lexer *L = &S->L;
    param *q = pbrt_get(ps, name);
    if (!q)
        return BRUME_OK;
    if (strcmp(q->type, "texture") == 0) {
        const named_texture *t = q->is_string && q->n == 1 ? find_texture(S, q->s, is_float) : NULL;
        if (!t)
            return pbrt_fail(L, "%s: parameter \"texture %s\": no %s Texture named \"%s\" before it", what, name,
                             is_float ? "float" : "spectrum", q->is_string ? q->s : "");
        cJSON_AddItemToObject(node, key, cJSON_Duplicate(t->json, 1));
        return BRUME_OK;
    }
    double v[3] = {0, 0, 0};
    brume_status st = is_float ? pbrt_get_float(L, ps, name, v) : pbrt_get_color(L, ps, name, v);
    if (st)
        return st;
    cJSON_AddItemToObject(node, key, is_float ? cJSON_CreateNumber(v[0]) : cJSON_CreateDoubleArray(v, 3));
    return BRUME_OK;
}

/* The uv mapping's parameters (other mappings refused by name). */
static brume_status mapping(pbrt_state *S, params *ps, const char *what, cJSON *node)
{
    lexer *L = &S->L;
    char map[32] = "uv";
    brume_status st = pbrt_get_string(L, ps, "mapping", map, sizeof map);
    if (st)
        return st;
    if (strcmp(map, "uv") != 0)
        return pbrt_unsupported(L, "%s: parameter \"mapping\": \"%s\": brume maps textures by uv only", what, map);
    static const char *const keys[] = {"uscale", "vscale", "udelta", "vdelta"};
    for (int k = 0; k < 4; k++) {
        double v = k < 2 ? 1.0 : 0.0;
        if ((st = pbrt_get_float(L, ps, keys[k], &v)))
            return st;
        if (!(v >= -1e12 && v <= 1e12))
            return pbrt_fail(L, "%s: parameter \"%s\": %g outside [-1e12, 1e12]", what, keys[k], v);
        cJSON_AddNumberToObject(node, keys[k], v);
    }
    return BRUME_OK;
}

/* imagemap: filename (relative to the main file's folder), encoding, scale, invert, wrap; the
 * filter bilinear (pbrt-v4's default), the only one brume has. */
static brume_status imagemap(pbrt_state *S, params *ps, const char *what, cJSON *node)
{
    lexer *L = &S->L;
    char file[PATH_MAX] = "", abs[PATH_MAX], enc[64] = "sRGB", wrap[32] = "repeat", filter[32] = "bilinear";
    double scale = 1.0, aniso = 8.0;
    brume_status st;
    if ((st = pbrt_get_string(L, ps, "filename", file, sizeof file)) ||
        (st = pbrt_get_string(L, ps, "encoding", enc, sizeof enc)) ||
        (st = pbrt_get_string(L, ps, "wrap", wrap, sizeof wrap)) ||
        (st = pbrt_get_string(L, ps, "filter", filter, sizeof filter)) ||
        (st = pbrt_get_float(L, ps, "scale", &scale)) || (st = pbrt_get_float(L, ps, "maxanisotropy", &aniso)))
        return st;
    if (!file[0])
        return pbrt_fail(L, "%s: no \"string filename\"", what);
    if (strcmp(filter, "bilinear") != 0)
        return pbrt_unsupported(L, "%s: parameter \"filter\": \"%s\": brume looks images up bilinearly (\"bilinear\")",
                                what, filter);
    if (strcmp(wrap, "repeat") != 0 && strcmp(wrap, "black") != 0 && strcmp(wrap, "clamp") != 0)
        return pbrt_unsupported(L, "%s: parameter \"wrap\": \"%s\": brume wraps by repeat, black or clamp", what, wrap);
    if (!(scale >= -1e30 && scale <= 1e30))
        return pbrt_fail(L, "%s: parameter \"scale\": %g is not finite", what, scale);
    param *inv = pbrt_get(ps, "invert");
    bool invert = false;
    if (inv) {
        if (strcmp(inv->type, "bool") != 0 || inv->n != 1 ||
            (inv->is_string && strcmp(inv->s, "true") != 0 && strcmp(inv->s, "false") != 0))
            return pbrt_fail(L, "%s: parameter \"invert\": expected one bool", what);
        invert = inv->is_string ? strcmp(inv->s, "true") == 0 : inv->v[0] != 0.0;
    }
    if ((st = pbrt_resolve_file(S, what, file, abs)))
        return st;
    cJSON_AddStringToObject(node, "file", abs);
    cJSON_AddStringToObject(node, "encoding", enc);
    cJSON_AddNumberToObject(node, "scale", scale);
    cJSON_AddBoolToObject(node, "invert", invert);
    cJSON_AddStringToObject(node, "wrap", wrap);
    return BRUME_OK;
}

/* The class's own parameters into node. */
static brume_status texture_class(pbrt_state *S, params *ps, const char *what, const char *cls, bool is_float,
                                  cJSON *node)
{
    brume_status st;
    if (strcmp(cls, "constant") == 0)
        return texture_input(S, ps, what, "value", is_float, node, "value");
    if (strcmp(cls, "scale") == 0) {
        if ((st = texture_input(S, ps, what, "tex", is_float, node, "tex")))
            return st;
        return texture_input(S, ps, what, "scale", true, node, "scale");
    }
    if (strcmp(cls, "mix") == 0 || strcmp(cls, "checkerboard") == 0) {
        if ((st = texture_input(S, ps, what, "tex1", is_float, node, "tex1")) ||
            (st = texture_input(S, ps, what, "tex2", is_float, node, "tex2")))
            return st;
        if (strcmp(cls, "mix") == 0)
            return texture_input(S, ps, what, "amount", true, node, "amount");
        double dim = 2;
        if ((st = pbrt_get_float(&S->L, ps, "dimension", &dim)))
            return st;
        if (dim != 2)
            return pbrt_unsupported(&S->L, "%s: parameter \"dimension\": %g: brume's checkerboard is 2D (uv)", what,
                                    dim);
        return mapping(S, ps, what, node);
    }
    if ((st = mapping(S, ps, what, node)))
        return st;
    return imagemap(S, ps, what, node);
}

/* Texture "name" "float"|"spectrum" "class" parameters. */
brume_status pbrt_texture_directive(pbrt_state *S, params *ps)
{
    lexer *L = &S->L;
    char name[128], kind[16], cls[64], what[300];
    const char *part[3] = {"its name", "its kind (float or spectrum)", "its class"};
    char *out[3] = {name, kind, cls};
    size_t cap[3] = {sizeof name, sizeof kind, sizeof cls};
    for (int k = 0; k < 3; k++) {
        pbrt_next(L);
        if (L->kind != TOK_STRING)
            return pbrt_expected(L, "Texture: expected %s (a quoted string)", part[k]);
        if (strlen(L->text) >= cap[k])
            return pbrt_fail(L, "Texture: %s longer than %zu bytes", part[k], cap[k] - 1);
        pbrt_copy(out[k], cap[k], L->text);
    }
    pbrt_next(L);
    brume_status st = pbrt_read_params(L, ps);
    if (st)
        return st;
    snprintf(what, sizeof what, "Texture \"%s\" \"%s\" \"%s\"", name, kind, cls);
    if (strcmp(kind, "float") != 0 && strcmp(kind, "spectrum") != 0)
        return pbrt_fail(L, "%s: the kind is \"float\" or \"spectrum\"", what);
    static const char *const classes[] = {"imagemap", "scale", "mix", "checkerboard", "constant"};
    bool known = false;
    for (int k = 0; k < 5; k++)
        known = known || strcmp(cls, classes[k]) == 0;
    if (!known)
        return pbrt_unsupported(L, "%s: not supported by brume (imagemap, scale, mix, checkerboard, constant)", what);
    if (S->ntextures == PBRT_MAX_TEXTURES)
        return pbrt_fail(L, "%s: more than %d textures", what, PBRT_MAX_TEXTURES);
    cJSON *node = cJSON_CreateObject();
    if (!node)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", L->file);
    cJSON_AddStringToObject(node, "type", cls);
    bool is_float = strcmp(kind, "float") == 0;
    if ((st = texture_class(S, ps, what, cls, is_float, node)) || (st = pbrt_all_used(L, ps, what))) {
        cJSON_Delete(node);
        return st;
    }
    if (count_nodes(node) > BRUME_TEXTURE_MAX_NODES) {
        cJSON_Delete(node);
        return pbrt_fail(L, "%s: more than %d textures in one tree (the textures it names, each counted where named)",
                         what, BRUME_TEXTURE_MAX_NODES);
    }
    named_texture *t = &S->textures[S->ntextures++];
    pbrt_copy(t->name, sizeof t->name, name);
    t->is_float = is_float;
    t->json = node;
    return BRUME_OK;
}

int pbrt_find_texture(const pbrt_state *S, const char *name, bool is_float)
{
    const named_texture *t = find_texture(S, name, is_float);
    return t ? (int)(t - S->textures) : -1;
}

/* ---- texture coordinates of drawn shapes ---------------------------------------------------- */

brume_status pbrt_mesh_uv(pbrt_state *S, const param *q, const char *what, int nv, double **uv)
{
    *uv = NULL;
    if (q->is_string || q->n != 2 * nv)
        return pbrt_fail(&S->L, "%s: parameter \"%s %s\": %d values for %d points (u v each)", what, q->type, q->name,
                         q->n, nv);
    for (int i = 0; i < q->n; i++)
        if (!(q->v[i] >= -1e12 && q->v[i] <= 1e12))
            return pbrt_fail(&S->L, "%s: parameter \"%s\": value %d: %g outside [-1e12, 1e12]", what, q->name, i,
                             q->v[i]);
    if (!(*uv = malloc(sizeof **uv * 2 * (size_t)nv)))
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", S->L.file, S->L.dir_line, what);
    memcpy(*uv, q->v, sizeof **uv * 2 * (size_t)nv);
    return BRUME_OK;
}

brume_status pbrt_uv_unshare(pbrt_state *S, const char *what, double **P, int *nv, int *idx, int nt,
                             const double *pattern, int period, double **uv)
{
    double *np = malloc(sizeof *np * 9 * (size_t)nt), *nu = malloc(sizeof *nu * 6 * (size_t)nt);
    if (!np || !nu) {
        free(np);
        free(nu);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", S->L.file, S->L.dir_line, what);
    }
    for (int f = 0; f < nt; f++)
        for (int k = 0; k < 3; k++) {
            int v = 3 * f + k;
            memcpy(np + 3 * v, *P + 3 * idx[v], 3 * sizeof *np);
            memcpy(nu + 2 * v, pattern + 6 * (f % period) + 2 * k, 2 * sizeof *nu);
            idx[v] = v;
        }
    free(*P);
    *P = np;
    *nv = 3 * nt;
    *uv = nu;
    return BRUME_OK;
}
