/* scene_pbrt.c - pbrt-v4 scene files translated to brume's scene description (JSON), then
 * read by the one scene reader (scene/scene_json.c). The subset read and the mapping of units
 * and conventions are in docs/production.md, "pbrt-v4 scenes". Every directive, type or
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

#include "core/error.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/json.h"
#include "scene/scene_build.h"
#include "scene/scene_pbrt.h"

#define PBRT_MAX_BYTES (64L << 20)
/* the values of one parameter (an inline grid's samples or a mesh's points, 3 numbers each)
 * and of one directive's parameters together (rgbgrid's two RGB grids): 100 MiB of doubles */
#define PBRT_MAX_VALUES (3 * SCENE_INLINE_MAX_VALUES)
#define PBRT_MAX_DIRECTIVE_VALUES (6 * SCENE_INLINE_MAX_VALUES)
/* the numbers of every inline grid and mesh of one scene: the translation's JSON nodes then
 * stay under about 300 MiB */
#define PBRT_MAX_SCENE_INLINE (2 * SCENE_INLINE_MAX_VALUES)
#define PBRT_MAX_PARAMS 32
#define PBRT_MAX_MEDIA 16
#define PBRT_MAX_DEPTH 64

/* ---- tokens ------------------------------------------------------------------------------ */

typedef enum { TOK_END, TOK_WORD, TOK_STRING, TOK_OPEN, TOK_CLOSE } tok_kind;

typedef struct lexer {
    const char *file;
    const char *p;
    int line;
    tok_kind kind; /* the current token */
    char text[1024];
    int tok_line;
    int dir_line;  /* the line of the directive being read: what refusals name */
} lexer;

static void next(lexer *L)
{
    for (;;) {
        while (isspace((unsigned char)*L->p)) {
            if (*L->p == '\n')
                L->line++;
            L->p++;
        }
        if (*L->p != '#')
            break;
        while (*L->p && *L->p != '\n')
            L->p++;
    }
    L->tok_line = L->line;
    char c = *L->p;
    size_t n = 0;
    if (!c) {
        L->kind = TOK_END;
    } else if (c == '[' || c == ']') {
        L->kind = c == '[' ? TOK_OPEN : TOK_CLOSE;
        L->p++;
    } else if (c == '"') {
        L->kind = TOK_STRING;
        L->p++;
        while (*L->p && *L->p != '"' && *L->p != '\n') {
            if (n + 1 < sizeof L->text)
                L->text[n++] = *L->p;
            L->p++;
        }
        if (*L->p == '"')
            L->p++;
        else
            L->kind = TOK_END; /* unterminated: reported by the caller as a syntax error */
    } else {
        L->kind = TOK_WORD;
        while (*L->p && !isspace((unsigned char)*L->p) && *L->p != '"' && *L->p != '[' && *L->p != ']' && *L->p != '#') {
            if (n + 1 < sizeof L->text)
                L->text[n++] = *L->p;
            L->p++;
        }
    }
    L->text[n] = '\0';
}

/* A refusal: "FILE:LINE: " and the message. */
static brume_status fail(const lexer *L, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static brume_status fail(const lexer *L, const char *fmt, ...)
{
    char msg[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return err_set(BRUME_ERROR_UNSUPPORTED, "%s:%d: %s", L->file, L->dir_line, msg);
}

/* src into dst[cap], cut to fit. */
static void copy(char *dst, size_t cap, const char *src)
{
    size_t n = strlen(src);
    if (n >= cap)
        n = cap - 1;
    memmove(dst, src, n);
    dst[n] = '\0';
}

static bool number(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v))
        return false;
    *out = v;
    return true;
}

/* n numbers as bare words (LookAt, Translate ...) or in brackets (Transform). */
static brume_status numbers(lexer *L, const char *dir, int n, double *out)
{
    bool bracket = false;
    next(L);
    if (L->kind == TOK_OPEN) {
        bracket = true;
        next(L);
    }
    for (int i = 0; i < n; i++) {
        if (L->kind != TOK_WORD || !number(L->text, &out[i]))
            return fail(L, "%s: expected a number", dir);
        next(L);
    }
    if (bracket) {
        if (L->kind != TOK_CLOSE)
            return fail(L, "%s: expected ]", dir);
        next(L);
    }
    return BRUME_OK;
}

/* ---- parameter lists --------------------------------------------------------------------- */

typedef struct param {
    char type[16], name[64];
    int n, cap;                      /* values; numbers allocated in v */
    double *v;                       /* numbers (malloc'd; an array's values) */
    char s[256];                     /* the first string value */
    bool is_string, used;
    int line;
} param;

typedef struct params {
    int n;
    long values; /* numbers over all n */
    param p[PBRT_MAX_PARAMS];
} params;

/* Frees the values of the parameters read last. */
static void params_clear(params *ps)
{
    for (int i = 0; i < ps->n; i++)
        free(ps->p[i].v);
    ps->n = 0;
    ps->values = 0;
}

/* Room for one more value in q, one of ps. */
static brume_status grow(lexer *L, params *ps, param *q)
{
    if (++ps->values > PBRT_MAX_DIRECTIVE_VALUES)
        return fail(L, "more than the %d values brume reads inline in one directive", PBRT_MAX_DIRECTIVE_VALUES);
    if (q->n < q->cap)
        return BRUME_OK;
    if (q->n >= PBRT_MAX_VALUES)
        return fail(L, "parameter \"%s\": more than the %d values brume reads inline", q->name, PBRT_MAX_VALUES);
    int cap = q->cap ? 2 * q->cap : 16;
    if (cap > PBRT_MAX_VALUES)
        cap = PBRT_MAX_VALUES;
    double *v = realloc(q->v, (size_t)cap * sizeof *v);
    if (!v)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: parameter \"%s\": out of memory", L->file, L->dir_line,
                       q->name);
    q->v = v;
    q->cap = cap;
    return BRUME_OK;
}

/* Reads "type name" value pairs after a directive; L is on the first token after the
 * directive's own arguments and is left on the next directive. */
static brume_status read_params(lexer *L, params *ps)
{
    brume_status st;
    params_clear(ps);
    while (L->kind == TOK_STRING) {
        if (ps->n == PBRT_MAX_PARAMS)
            return fail(L, "more than %d parameters", PBRT_MAX_PARAMS);
        param *q = &ps->p[ps->n++];
        memset(q, 0, sizeof *q);
        q->line = L->tok_line;
        if (sscanf(L->text, "%15s %63s", q->type, q->name) != 2)
            return fail(L, "parameter \"%s\": expected \"type name\"", L->text);
        next(L);
        bool bracket = L->kind == TOK_OPEN;
        if (bracket)
            next(L);
        do {
            if ((st = grow(L, ps, q)))
                return st;
            if (L->kind == TOK_STRING) {
                if (q->n == 0)
                    copy(q->s, sizeof q->s, L->text);
                q->is_string = true;
                q->n++;
            } else if (L->kind == TOK_WORD && (strcmp(L->text, "true") == 0 || strcmp(L->text, "false") == 0)) {
                q->v[q->n] = strcmp(L->text, "true") == 0;
                q->n++;
            } else if (L->kind == TOK_WORD) {
                if (!number(L->text, &q->v[q->n]))
                    return fail(L, "parameter \"%s\": expected a number", q->name);
                q->n++;
            } else {
                return fail(L, "parameter \"%s\": expected a value", q->name);
            }
            next(L);
        } while (bracket && L->kind != TOK_CLOSE && L->kind != TOK_END);
        if (bracket) {
            if (L->kind != TOK_CLOSE)
                return fail(L, "parameter \"%s\": expected ]", q->name);
            next(L);
        }
    }
    return BRUME_OK;
}

static param *get(params *ps, const char *name)
{
    for (int i = 0; i < ps->n; i++)
        if (strcmp(ps->p[i].name, name) == 0) {
            ps->p[i].used = true;
            return &ps->p[i];
        }
    return NULL;
}

static brume_status get_float(lexer *L, params *ps, const char *name, double *out)
{
    param *q = get(ps, name);
    if (!q)
        return BRUME_OK;
    if (q->is_string || q->n != 1 || (strcmp(q->type, "float") != 0 && strcmp(q->type, "integer") != 0))
        return fail(L, "parameter \"%s\": expected one float", name);
    *out = q->v[0];
    return BRUME_OK;
}

static brume_status get_point(lexer *L, params *ps, const char *name, double out[3])
{
    param *q = get(ps, name);
    if (!q)
        return BRUME_OK;
    if (q->is_string || q->n != 3)
        return fail(L, "parameter \"%s\": expected three numbers", name);
    memcpy(out, q->v, 3 * sizeof *out);
    return BRUME_OK;
}

/* An "rgb" value, or a "spectrum" given as one constant or as constant (lambda, value)
 * pairs; anything else (a blackbody, a named or varying spectrum) is refused: brume renders
 * in RGB and would have to guess the projection. */
static brume_status get_color(lexer *L, params *ps, const char *name, double out[3])
{
    param *q = get(ps, name);
    if (!q)
        return BRUME_OK;
    if (strcmp(q->type, "rgb") == 0 && !q->is_string && q->n == 3) {
        memcpy(out, q->v, 3 * sizeof *out);
        return BRUME_OK;
    }
    if (strcmp(q->type, "spectrum") == 0 && !q->is_string && (q->n == 1 || (q->n >= 4 && q->n % 2 == 0))) {
        double v = q->n == 1 ? q->v[0] : q->v[1];
        for (int i = 3; i < q->n; i += 2)
            if (q->v[i] != v)
                return fail(L, "parameter \"%s\": a spectrum that varies with wavelength (brume renders RGB)", name);
        out[0] = out[1] = out[2] = v;
        return BRUME_OK;
    }
    if (strcmp(q->type, "float") == 0 && !q->is_string && q->n == 1) {
        out[0] = out[1] = out[2] = q->v[0];
        return BRUME_OK;
    }
    return fail(L, "parameter \"%s\": brume reads rgb values and constant spectra only", name);
}

static brume_status get_string(lexer *L, params *ps, const char *name, char *out, size_t n)
{
    param *q = get(ps, name);
    if (!q)
        return BRUME_OK;
    if (!q->is_string || q->n != 1)
        return fail(L, "parameter \"%s\": expected one string", name);
    snprintf(out, n, "%s", q->s);
    return BRUME_OK;
}

/* Every parameter must have been read: the first that was not is refused. */
static brume_status all_used(const lexer *L, const params *ps, const char *dir)
{
    for (int i = 0; i < ps->n; i++)
        if (!ps->p[i].used) {
            lexer at = *L;
            at.dir_line = ps->p[i].line;
            return fail(&at, "%s: parameter \"%s %s\": not supported by brume", dir, ps->p[i].type, ps->p[i].name);
        }
    return BRUME_OK;
}

/* ---- transforms: 4 x 4 row-major, p' = M p ------------------------------------------------- */

typedef struct m4 {
    double m[16];
} m4;

static m4 m4_identity(void)
{
    m4 r = {{0}};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
    return r;
}

static m4 m4_mul(m4 a, m4 b)
{
    m4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a.m[4 * i + k] * b.m[4 * k + j];
            r.m[4 * i + j] = s;
        }
    return r;
}

static bool m4_inverse(m4 a, m4 *out)
{
    m4 r = m4_identity();
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int i = c + 1; i < 4; i++)
            if (fabs(a.m[4 * i + c]) > fabs(a.m[4 * piv + c]))
                piv = i;
        if (fabs(a.m[4 * piv + c]) < 1e-300)
            return false;
        for (int j = 0; j < 4; j++) {
            double t = a.m[4 * c + j];
            a.m[4 * c + j] = a.m[4 * piv + j];
            a.m[4 * piv + j] = t;
            t = r.m[4 * c + j];
            r.m[4 * c + j] = r.m[4 * piv + j];
            r.m[4 * piv + j] = t;
        }
        double d = a.m[4 * c + c];
        for (int j = 0; j < 4; j++) {
            a.m[4 * c + j] /= d;
            r.m[4 * c + j] /= d;
        }
        for (int i = 0; i < 4; i++)
            if (i != c) {
                double f = a.m[4 * i + c];
                for (int j = 0; j < 4; j++) {
                    a.m[4 * i + j] -= f * a.m[4 * c + j];
                    r.m[4 * i + j] -= f * r.m[4 * c + j];
                }
            }
    }
    *out = r;
    return true;
}

static vec3 m4_point(m4 a, vec3 p)
{
    const double *m = a.m;
    return v3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
              m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

static vec3 m4_vector(m4 a, vec3 v)
{
    const double *m = a.m;
    return v3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
              m[8] * v.x + m[9] * v.y + m[10] * v.z);
}

static m4 m4_translate(double x, double y, double z)
{
    m4 r = m4_identity();
    r.m[3] = x;
    r.m[7] = y;
    r.m[11] = z;
    return r;
}

static m4 m4_scale(double x, double y, double z)
{
    m4 r = m4_identity();
    r.m[0] = x;
    r.m[5] = y;
    r.m[10] = z;
    return r;
}

static m4 m4_rotate(double deg, vec3 axis)
{
    vec3 a = v3_normalize(axis);
    double t = deg * PI / 180.0, s = sin(t), c = cos(t);
    m4 r = m4_identity();
    r.m[0] = a.x * a.x + (1 - a.x * a.x) * c;
    r.m[1] = a.x * a.y * (1 - c) - a.z * s;
    r.m[2] = a.x * a.z * (1 - c) + a.y * s;
    r.m[4] = a.x * a.y * (1 - c) + a.z * s;
    r.m[5] = a.y * a.y + (1 - a.y * a.y) * c;
    r.m[6] = a.y * a.z * (1 - c) - a.x * s;
    r.m[8] = a.x * a.z * (1 - c) - a.y * s;
    r.m[9] = a.y * a.z * (1 - c) + a.x * s;
    r.m[10] = a.z * a.z + (1 - a.z * a.z) * c;
    return r;
}

/* pbrt's LookAt: the camera-from-world matrix with the eye at the origin looking down +z. */
static bool m4_look_at(vec3 eye, vec3 look, vec3 up, m4 *out)
{
    vec3 dir = v3_normalize(v3_sub(look, eye));
    vec3 right = v3_cross(v3_normalize(up), dir);
    if (!(v3_length(right) > 1e-12))
        return false;
    right = v3_normalize(right);
    vec3 nup = v3_cross(dir, right);
    m4 w = m4_identity(); /* world from camera */
    w.m[0] = right.x; w.m[4] = right.y; w.m[8] = right.z;
    w.m[1] = nup.x; w.m[5] = nup.y; w.m[9] = nup.z;
    w.m[2] = dir.x; w.m[6] = dir.y; w.m[10] = dir.z;
    w.m[3] = eye.x; w.m[7] = eye.y; w.m[11] = eye.z;
    return m4_inverse(w, out);
}

/* brume's transform object {"translate", "rotate", "scale"} = T R S for an affine map
 * without shear (columns of the linear part orthogonal, rotation proper); NULL (a refusal by
 * the caller) otherwise. */
static cJSON *transform_json(m4 a)
{
    vec3 col[3];
    double s[3];
    for (int j = 0; j < 3; j++) {
        col[j] = v3(a.m[j], a.m[4 + j], a.m[8 + j]);
        s[j] = v3_length(col[j]);
        if (!(s[j] > 0.0))
            return NULL;
        col[j] = v3_scale(col[j], 1.0 / s[j]);
    }
    if (fabs(v3_dot(col[0], col[1])) > 1e-6 || fabs(v3_dot(col[0], col[2])) > 1e-6 || fabs(v3_dot(col[1], col[2])) > 1e-6)
        return NULL;
    if (v3_dot(v3_cross(col[0], col[1]), col[2]) < 0.0) { /* a mirror: one negative scale */
        s[0] = -s[0];
        col[0] = v3_neg(col[0]);
    }
    /* axis-angle of the rotation R = [col0 col1 col2] */
    double tr = col[0].x + col[1].y + col[2].z;
    double angle = acos(fmax(-1.0, fmin(1.0, 0.5 * (tr - 1.0))));
    vec3 axis = v3(col[1].z - col[2].y, col[2].x - col[0].z, col[0].y - col[1].x);
    if (v3_length(axis) < 1e-9) {
        if (angle < 1e-6) {
            axis = v3(0, 0, 1);
            angle = 0.0;
        } else { /* a half turn: the axis from R + I */
            vec3 c = v3_add(col[0], v3(1, 0, 0));
            if (v3_length(c) < 1e-6)
                c = v3_add(col[1], v3(0, 1, 0));
            if (v3_length(c) < 1e-6)
                c = v3_add(col[2], v3(0, 0, 1));
            axis = c;
        }
    }
    axis = v3_normalize(axis);
    cJSON *t = cJSON_CreateObject();
    double tv[3] = {a.m[3], a.m[7], a.m[11]}, av[3] = {axis.x, axis.y, axis.z};
    cJSON_AddItemToObject(t, "translate", cJSON_CreateDoubleArray(tv, 3));
    cJSON *r = cJSON_AddObjectToObject(t, "rotate");
    cJSON_AddItemToObject(r, "axis", cJSON_CreateDoubleArray(av, 3));
    cJSON_AddNumberToObject(r, "angle", angle * 180.0 / PI);
    cJSON_AddItemToObject(t, "scale", cJSON_CreateDoubleArray(s, 3));
    return t;
}

/* ---- the translation ------------------------------------------------------------------------ */

typedef struct named_medium {
    char name[128];
    cJSON *json; /* the brume medium, emitted when a shape first uses it */
    bool emitted;
    bool homogeneous; /* json has no density: a box is made for each shape that bounds it */
} named_medium;

typedef struct attrs {
    m4 ctm;
    char material[32]; /* "diffuse" or "interface" */
    double albedo[3];
    char inside[128], outside[128];
} attrs;

typedef struct pbrt_state {
    lexer L;
    const char *path;
    char dir[PATH_MAX];
    attrs a[PBRT_MAX_DEPTH];
    int depth;
    bool have_camera, world;
    bool mirror; /* pbrt's left-handed view: the world is translated mirrored in x (camera_directive) */
    m4 world_from_camera;
    double fov, lens_radius, focal_distance;
    int xres, yres, spp, max_depth;
    named_medium media[PBRT_MAX_MEDIA];
    int nmedia;
    cJSON *root, *lights, *media_j, *surfaces;
    double background[3];
    bool have_background;
    double inline_numbers; /* numbers of the inline grids and meshes written so far */
} pbrt_state;

/* Counts n more inline numbers against the scene's limit. */
static brume_status count_inline(pbrt_state *S, const char *what, double n)
{
    S->inline_numbers += n;
    if (S->inline_numbers > PBRT_MAX_SCENE_INLINE)
        return fail(&S->L, "%s: the scene's inline grids and meshes come to more than %d numbers (larger data "
                           "belongs in nanovdb and ply files)", what, PBRT_MAX_SCENE_INLINE);
    return BRUME_OK;
}

/* A file a directive names, relative to the .pbrt's folder, as an absolute path in abs. */
static brume_status resolve_file(pbrt_state *S, const char *what, const char *file, char abs[PATH_MAX])
{
    char rel[PATH_MAX + 1100];
    if (file[0] == '/')
        copy(rel, sizeof rel, file);
    else
        snprintf(rel, sizeof rel, "%s/%s", S->dir, file);
    if (!realpath(rel, abs))
        return err_set(BRUME_ERROR_IO, "%s:%d: %s: %s: %s", S->L.file, S->L.dir_line, what, rel, strerror(errno));
    return BRUME_OK;
}

static brume_status camera_directive(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    if (strcmp(type, "perspective") != 0)
        return fail(L, "Camera \"%s\": brume has a perspective camera only", type);
    S->fov = 90.0;
    S->lens_radius = 0.0;
    S->focal_distance = 1e6;
    if ((st = get_float(L, ps, "fov", &S->fov)) || (st = get_float(L, ps, "lensradius", &S->lens_radius)) ||
        (st = get_float(L, ps, "focaldistance", &S->focal_distance)))
        return st;
    if ((st = all_used(L, ps, "Camera \"perspective\"")))
        return st;
    m4 wc;
    if (!m4_inverse(S->a[S->depth].ctm, &wc))
        return fail(L, "Camera: the current transform is not invertible");
    /* pbrt images camera +x to the right, +y up, looking down +z; brume's camera has right =
       forward x up. Where +x = up x forward instead (pbrt's own LookAt without a mirror: most
       of pbrt-v4-scenes), the whole world is translated mirrored, x -> -x: the camera too, so
       that the picture is pbrt's, pixel for pixel. The mirror M multiplies the camera's
       world-from-camera on the left and starts the world block's transform (WorldBegin,
       Identity, Transform). */
    vec3 R = m4_vector(wc, v3(1, 0, 0)), U = m4_vector(wc, v3(0, 1, 0)), F = m4_vector(wc, v3(0, 0, 1));
    S->mirror = v3_dot(v3_cross(F, U), R) <= 0.0;
    if (S->mirror)
        wc = m4_mul(m4_scale(-1.0, 1.0, 1.0), wc);
    S->world_from_camera = wc;
    S->have_camera = true;
    return BRUME_OK;
}

static brume_status light_directive(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    double Lrgb[3] = {1, 1, 1}, scale = 1.0;
    if ((st = get_float(L, ps, "scale", &scale))) return st;
    m4 ctm = S->a[S->depth].ctm;
    if (strcmp(type, "distant") == 0) {
        double from[3] = {0, 0, 0}, to[3] = {0, 0, 1};
        if ((st = get_color(L, ps, "L", Lrgb)) || (st = get_point(L, ps, "from", from)) ||
            (st = get_point(L, ps, "to", to)) || (st = all_used(L, ps, "LightSource \"distant\"")))
            return st;
        vec3 d = m4_vector(ctm, v3(to[0] - from[0], to[1] - from[1], to[2] - from[2]));
        if (!(v3_length(d) > 0.0))
            return fail(L, "LightSource \"%s\": from equals to", type);
        d = v3_normalize(d);
        cJSON *l = cJSON_CreateObject();
        double dv[3] = {d.x, d.y, d.z}, E[3] = {Lrgb[0] * scale, Lrgb[1] * scale, Lrgb[2] * scale};
        cJSON_AddStringToObject(l, "type", "distant");
        cJSON_AddItemToObject(l, "direction", cJSON_CreateDoubleArray(dv, 3));
        cJSON_AddItemToObject(l, "irradiance", cJSON_CreateDoubleArray(E, 3));
        cJSON_AddItemToArray(S->lights, l);
    } else if (strcmp(type, "point") == 0) {
        double from[3] = {0, 0, 0};
        if ((st = get_color(L, ps, "I", Lrgb)) || (st = get_point(L, ps, "from", from)) ||
            (st = all_used(L, ps, "LightSource \"point\"")))
            return st;
        vec3 p = m4_point(ctm, v3(from[0], from[1], from[2]));
        cJSON *l = cJSON_CreateObject();
        double pv[3] = {p.x, p.y, p.z}, I[3] = {Lrgb[0] * scale, Lrgb[1] * scale, Lrgb[2] * scale};
        cJSON_AddStringToObject(l, "type", "point");
        cJSON_AddItemToObject(l, "position", cJSON_CreateDoubleArray(pv, 3));
        cJSON_AddItemToObject(l, "intensity", cJSON_CreateDoubleArray(I, 3));
        cJSON_AddItemToArray(S->lights, l);
    } else if (strcmp(type, "infinite") == 0) {
        if ((st = get_color(L, ps, "L", Lrgb)) || (st = all_used(L, ps, "LightSource \"infinite\"")))
            return st;
        for (int c = 0; c < 3; c++) /* several constant skies add */
            S->background[c] += Lrgb[c] * scale;
        S->have_background = true;
    } else {
        return fail(L, "LightSource \"%s\": not supported by brume (distant, point, infinite with L)", type);
    }
    return BRUME_OK;
}

/* The coefficients every pbrt medium shares: brume's sigma per unit density is pbrt's sigma
 * times `scale` (pbrt-v4: sigma_a(p) = scale sigma_a d(p), the same for sigma_s), HG g as is.
 * A new medium object with name, sigma_a, sigma_s and phase; NULL after a refusal. */
static cJSON *medium_new(lexer *L, const char *name, const double sa[3], const double ss[3], double scale, double g)
{
    if (!(g > -1.0 && g < 1.0)) {
        fail(L, "MakeNamedMedium \"%s\": parameter \"g\": %g outside (-1, 1)", name, g);
        return NULL;
    }
    if (!(scale >= 0.0) || sa[0] < 0 || sa[1] < 0 || sa[2] < 0 || ss[0] < 0 || ss[1] < 0 || ss[2] < 0) {
        fail(L, "MakeNamedMedium \"%s\": negative sigma_a, sigma_s or scale", name);
        return NULL;
    }
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "name", name);
    double a3[3] = {sa[0] * scale, sa[1] * scale, sa[2] * scale}, s3[3] = {ss[0] * scale, ss[1] * scale, ss[2] * scale};
    cJSON_AddItemToObject(m, "sigma_a", cJSON_CreateDoubleArray(a3, 3));
    cJSON_AddItemToObject(m, "sigma_s", cJSON_CreateDoubleArray(s3, 3));
    cJSON *ph = cJSON_AddObjectToObject(m, "phase");
    cJSON_AddStringToObject(ph, "type", "hg");
    cJSON_AddNumberToObject(ph, "g", g);
    return m;
}

/* The transform at MakeNamedMedium (pbrt's renderFromMedium) as the density's `transform`
 * (none when it is the identity); false after a refusal (shear). */
static bool medium_place(pbrt_state *S, cJSON *dj, const char *name)
{
    m4 ctm = S->a[S->depth].ctm;
    m4 id = m4_identity();
    if (memcmp(&ctm, &id, sizeof id) == 0)
        return true;
    cJSON *t = transform_json(ctm);
    if (!t) {
        fail(&S->L, "MakeNamedMedium \"%s\": a transform with shear (brume places grids by scale, rotation, "
                    "translation)", name);
        return false;
    }
    cJSON_AddItemToObject(dj, "transform", t);
    return true;
}

/* Adds the medium m (owned from here) to the named media. */
static brume_status medium_add(pbrt_state *S, const char *name, cJSON *m, bool homogeneous)
{
    if (S->nmedia == PBRT_MAX_MEDIA) {
        cJSON_Delete(m);
        return fail(&S->L, "MakeNamedMedium \"%s\": more than %d media", name, PBRT_MAX_MEDIA);
    }
    named_medium *nm = &S->media[S->nmedia++];
    copy(nm->name, sizeof nm->name, name);
    nm->json = m;
    nm->emitted = false;
    nm->homogeneous = homogeneous;
    return BRUME_OK;
}

/* "integer NAME" in [1, 65536] (pbrt's nx, ny, nz; default 1). */
static brume_status get_count(lexer *L, params *ps, const char *name, int *out)
{
    double v = 1;
    brume_status st = get_float(L, ps, name, &v);
    if (st)
        return st;
    if (!(v >= 1 && v <= 65536) || v != floor(v))
        return fail(L, "parameter \"%s\": %g is not an integer in [1, 65536]", name, v);
    *out = (int)v;
    return BRUME_OK;
}

/* The numbers of an array parameter of one of the types given (NULL-terminated list);
 * NULL when absent. */
static brume_status get_array(lexer *L, params *ps, const char *name, const char *const *types, param **out)
{
    *out = NULL;
    param *q = get(ps, name);
    if (!q)
        return BRUME_OK;
    bool ok = false;
    for (int i = 0; types[i]; i++)
        ok |= strcmp(q->type, types[i]) == 0;
    if (!ok || q->is_string || q->n < 1) {
        lexer at = *L;
        at.dir_line = q->line;
        return fail(&at, "parameter \"%s %s\": expected %s values", q->type, name, types[0]);
    }
    *out = q;
    return BRUME_OK;
}

/* pbrt's grid media (uniformgrid, rgbgrid): n = nx ny nz samples d (x fastest) at the
 * centres of the cells of [p0, p1], read trilinearly with samples beyond the grid taken as
 * 0, so the field falls to d/2 at the faces. brume's trilinear grid holds its outermost
 * samples to its faces instead: the grid is written with a layer of zero samples around it
 * and bounds one cell wider, which gives pbrt's field exactly inside [p0, p1]; it adds the
 * half cell beyond each face, where brume's field falls from d/2 to 0 and pbrt's is 0
 * (none for a grid whose outer samples are 0). An `array` density, placed by the transform
 * at MakeNamedMedium (docs/production.md). */
static cJSON *grid_density(pbrt_state *S, const char *name, const double *d, const int n[3], const double p0[3],
                           const double p1[3])
{
    int m[3] = {n[0] + 2, n[1] + 2, n[2] + 2};
    char what[200];
    snprintf(what, sizeof what, "MakeNamedMedium \"%s\"", name);
    if (count_inline(S, what, (double)m[0] * m[1] * m[2]))
        return NULL;
    double b[2][3];
    for (int k = 0; k < 3; k++) {
        double cell = (p1[k] - p0[k]) / n[k];
        b[0][k] = p0[k] - cell;
        b[1][k] = p1[k] + cell;
    }
    cJSON *dj = cJSON_CreateObject();
    cJSON_AddStringToObject(dj, "type", "array");
    cJSON_AddItemToObject(dj, "dims", cJSON_CreateIntArray(m, 3));
    cJSON *data = cJSON_AddArrayToObject(dj, "data");
    for (int z = 0; z < m[2]; z++)
        for (int y = 0; y < m[1]; y++)
            for (int x = 0; x < m[0]; x++) {
                bool in = x > 0 && y > 0 && z > 0 && x <= n[0] && y <= n[1] && z <= n[2];
                double v = in ? d[((size_t)(z - 1) * (size_t)n[1] + (size_t)(y - 1)) * (size_t)n[0] + (size_t)(x - 1)] : 0.0;
                cJSON_AddItemToArray(data, cJSON_CreateNumber(v));
            }
    cJSON *bounds = cJSON_AddArrayToObject(dj, "bounds");
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(b[0], 3));
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(b[1], 3));
    cJSON_AddStringToObject(dj, "filter", "trilinear");
    if (!medium_place(S, dj, name)) {
        cJSON_Delete(dj);
        return NULL;
    }
    return dj;
}

/* A medium of the coefficients and the grid d (grid_density) added to the named media. */
static brume_status grid_medium_add(pbrt_state *S, const char *name, const double sa[3], const double ss[3],
                                    double scale, double g, const double *d, const int n[3], const double p0[3],
                                    const double p1[3])
{
    cJSON *m = medium_new(&S->L, name, sa, ss, scale, g);
    cJSON *dj = m ? grid_density(S, name, d, n, p0, p1) : NULL;
    if (!dj) {
        cJSON_Delete(m);
        return err_status();
    }
    cJSON_AddItemToObject(m, "density", dj);
    return medium_add(S, name, m, false);
}

/* nx, ny, nz, p0 and p1 of a grid medium, checked against the count of its values. */
static brume_status grid_shape(lexer *L, params *ps, const char *what, int count, int n[3], double p0[3], double p1[3])
{
    brume_status st;
    if ((st = get_count(L, ps, "nx", &n[0])) || (st = get_count(L, ps, "ny", &n[1])) ||
        (st = get_count(L, ps, "nz", &n[2])) || (st = get_point(L, ps, "p0", p0)) || (st = get_point(L, ps, "p1", p1)))
        return st;
    double total = (double)n[0] * n[1] * n[2];
    if ((double)count != total)
        return fail(L, "%s: %d values for nx ny nz = %d x %d x %d = %.0f", what, count, n[0], n[1], n[2], total);
    if ((double)(n[0] + 2) * (n[1] + 2) * (n[2] + 2) > SCENE_INLINE_MAX_VALUES)
        return fail(L, "%s: %d x %d x %d samples, over the %d brume takes inline (a larger grid belongs in a "
                       "nanovdb file)", what, n[0], n[1], n[2], SCENE_INLINE_MAX_VALUES);
    for (int k = 0; k < 3; k++)
        if (!(p1[k] > p0[k]))
            return fail(L, "%s: p1 must exceed p0 on every axis", what);
    return BRUME_OK;
}

/* "homogeneous": the coefficients everywhere inside the shapes that bound it; the density is
 * made at each such shape (shape_directive). */
static brume_status medium_homogeneous(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, Le[3] = {0, 0, 0}, scale = 1.0, g = 0.0, Lescale = 1.0;
    char preset[128] = "";
    if ((st = get_string(L, ps, "preset", preset, sizeof preset))) return st;
    if (preset[0])
        return fail(L, "MakeNamedMedium \"%s\": parameter \"preset\": brume has no table of pbrt's measured media "
                       "(give sigma_a and sigma_s)", name);
    if ((st = get_color(L, ps, "sigma_a", sa)) || (st = get_color(L, ps, "sigma_s", ss)) ||
        (st = get_float(L, ps, "scale", &scale)) || (st = get_float(L, ps, "g", &g)) ||
        (st = get_color(L, ps, "Le", Le)) || (st = get_float(L, ps, "Lescale", &Lescale)) ||
        (st = all_used(L, ps, "MakeNamedMedium \"homogeneous\"")))
        return st;
    cJSON *m = medium_new(L, name, sa, ss, scale, g);
    if (!m)
        return err_status();
    if (Le[0] > 0 || Le[1] > 0 || Le[2] > 0) {
        /* pbrt emits Lescale Le at the rate sigma_a: brume's `emission` */
        if (!(Lescale >= 0) || Le[0] < 0 || Le[1] < 0 || Le[2] < 0) {
            cJSON_Delete(m);
            return fail(L, "MakeNamedMedium \"%s\": negative Le or Lescale", name);
        }
        double e[3] = {Le[0] * Lescale, Le[1] * Lescale, Le[2] * Lescale};
        cJSON_AddItemToObject(m, "emission", cJSON_CreateDoubleArray(e, 3));
    }
    return medium_add(S, name, m, true);
}

/* "uniformgrid": a density grid d given inline, sigma(p) = scale sigma d(p). */
static brume_status medium_uniformgrid(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    static const char *const floats[] = {"float", NULL};
    const char *what = "MakeNamedMedium \"uniformgrid\"";
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, scale = 1.0, g = 0.0, p0[3] = {0, 0, 0}, p1[3] = {1, 1, 1}, t = 0;
    int n[3];
    param *d = NULL;
    if ((st = get_array(L, ps, "density", floats, &d))) return st;
    if (!d)
        return fail(L, "%s \"%s\": no \"float density\" values", what, name);
    if (get(ps, "temperature"))
        return fail(L, "%s: parameter \"temperature\": brume reads temperature grids from files (nanovdb), not "
                       "inline", what);
    if (get(ps, "Le") || get(ps, "Lescale"))
        return fail(L, "%s: parameters \"Le\" and \"Lescale\": pbrt-v4 scales Le by a Lescale grid read "
                       "trilinearly (without one, a 1 x 1 x 1 grid that fades toward the faces); brume's "
                       "emission is one colour or a grid from a file", what);
    if ((st = grid_shape(L, ps, what, d->n, n, p0, p1)) || (st = get_color(L, ps, "sigma_a", sa)) ||
        (st = get_color(L, ps, "sigma_s", ss)) || (st = get_float(L, ps, "scale", &scale)) ||
        (st = get_float(L, ps, "g", &g)) || (st = get_float(L, ps, "temperaturescale", &t)) ||
        (st = get_float(L, ps, "temperatureoffset", &t)) || (st = get_float(L, ps, "temperaturecutoff", &t)) ||
        (st = all_used(L, ps, what)))
        return st; /* the temperature mapping is read and unused: there is no temperature grid */
    for (int i = 0; i < d->n; i++)
        if (!(d->v[i] >= 0.0 && d->v[i] <= 1e30))
            return fail(L, "%s: density value %d: %g outside [0, 1e30]", what, i, d->v[i]);
    return grid_medium_add(S, name, sa, ss, scale, g, d->v, n, p0, p1);
}

/* "rgbgrid": RGB grids of sigma_a and sigma_s (both: pbrt's default for a missing one is a
 * constant 1, which does not fade at the faces as the grid given does), times scale. brume's
 * medium is one density times one colour per coefficient, so the grid is taken when every
 * sample is d_i (c_a, c_s) for one pair of colours: d_i = the sample's largest coefficient,
 * each coefficient within 1e-5 of the grid's largest (values written with 6 digits); any
 * other grid is refused (docs/production.md). */
static brume_status medium_rgbgrid(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    static const char *const rgbs[] = {"rgb", NULL};
    const char *what = "MakeNamedMedium \"rgbgrid\"";
    double scale = 1.0, g = 0.0, p0[3] = {0, 0, 0}, p1[3] = {1, 1, 1}, Lescale = 1.0;
    int n[3];
    param *A = NULL, *Sg = NULL;
    if ((st = get_array(L, ps, "sigma_a", rgbs, &A)) || (st = get_array(L, ps, "sigma_s", rgbs, &Sg))) return st;
    if (!A && !Sg)
        return fail(L, "%s \"%s\": neither \"rgb sigma_a\" nor \"rgb sigma_s\" values", what, name);
    if (get(ps, "Le"))
        return fail(L, "%s: parameter \"Le\": an RGB emission grid; brume reads emission grids from files", what);
    if (!A || !Sg)
        return fail(L, "%s: no \"rgb %s\" grid: pbrt then takes %s as 1 up to the faces while the other grid fades "
                       "to half its outer samples there, which one density cannot carry", what,
                    A ? "sigma_s" : "sigma_a", A ? "sigma_s" : "sigma_a");
    if (A->n % 3 || Sg->n % 3 || A->n != Sg->n)
        return fail(L, "%s: sigma_a and sigma_s must be RGB triples, as many of each", what);
    int count = A->n / 3;
    if ((st = grid_shape(L, ps, what, count, n, p0, p1)) || (st = get_float(L, ps, "scale", &scale)) ||
        (st = get_float(L, ps, "g", &g)) || (st = get_float(L, ps, "Lescale", &Lescale)) ||
        (st = all_used(L, ps, what)))
        return st; /* Lescale is read and unused: it scales Le only */
    double *d = malloc((size_t)count * sizeof *d);
    if (!d)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", L->file, L->dir_line, what);
    int top = 0;
    for (int i = 0; i < count; i++) {
        d[i] = 0.0;
        for (int c = 0; c < 3; c++) {
            double a = A->v[3 * i + c], s = Sg->v[3 * i + c];
            if (!(a >= 0.0 && s >= 0.0 && a <= 1e30 && s <= 1e30)) {
                free(d);
                return fail(L, "%s: sample %d: sigma_a or sigma_s outside [0, 1e30]", what, i);
            }
            d[i] = fmax(d[i], fmax(a, s));
        }
        if (d[i] > d[top])
            top = i;
    }
    double ca[3] = {0, 0, 0}, cs[3] = {0, 0, 0};
    for (int c = 0; c < 3 && d[top] > 0.0; c++) {
        ca[c] = A->v[3 * top + c] / d[top];
        cs[c] = Sg->v[3 * top + c] / d[top];
    }
    for (int i = 0; i < count; i++)
        for (int c = 0; c < 3; c++) {
            double a = A->v[3 * i + c], s = Sg->v[3 * i + c];
            if (fabs(a - d[i] * ca[c]) > 1e-5 * d[top] || fabs(s - d[i] * cs[c]) > 1e-5 * d[top]) {
                free(d);
                return fail(L, "%s: sigma_a or sigma_s changes colour over the grid (sample %d against %d); "
                               "brume's media are one density times one colour per coefficient", what, i, top);
            }
        }
    st = grid_medium_add(S, name, ca, cs, scale, g, d, n, p0, p1);
    free(d);
    return st;
}

static brume_status medium_nanovdb(pbrt_state *S, const char *name, params *ps);

static brume_status medium_directive(pbrt_state *S, const char *name, params *ps)
{
    char type[64] = "";
    brume_status st = get_string(&S->L, ps, "type", type, sizeof type);
    if (st)
        return st;
    if (strcmp(type, "nanovdb") == 0)
        return medium_nanovdb(S, name, ps);
    if (strcmp(type, "homogeneous") == 0)
        return medium_homogeneous(S, name, ps);
    if (strcmp(type, "uniformgrid") == 0)
        return medium_uniformgrid(S, name, ps);
    if (strcmp(type, "rgbgrid") == 0)
        return medium_rgbgrid(S, name, ps);
    return fail(&S->L, "MakeNamedMedium type \"%s\": not supported by brume (homogeneous, uniformgrid, rgbgrid, "
                       "nanovdb)", type);
}

static brume_status medium_nanovdb(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    char file[1024] = "";
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, scale = 1.0, g = 0.0, Lescale = 1.0, tscale = 1.0, toff = 0.0,
           tcut = 0.0;
    if ((st = get_string(L, ps, "filename", file, sizeof file)) || (st = get_color(L, ps, "sigma_a", sa)) ||
        (st = get_color(L, ps, "sigma_s", ss)) || (st = get_float(L, ps, "scale", &scale)) ||
        (st = get_float(L, ps, "g", &g)) || (st = get_float(L, ps, "Lescale", &Lescale)) ||
        (st = get_float(L, ps, "temperaturescale", &tscale)) || (st = get_float(L, ps, "temperaturecutoff", &tcut)))
        return st;
    toff = tcut; /* pbrt-v4: temperatureoffset defaults to temperaturecutoff */
    if ((st = get_float(L, ps, "temperatureoffset", &toff))) return st;
    if ((st = all_used(L, ps, "MakeNamedMedium \"nanovdb\"")))
        return st;
    if (!file[0])
        return fail(L, "MakeNamedMedium \"%s\": no \"string filename\"", name);
    char abs[PATH_MAX], what[200];
    snprintf(what, sizeof what, "MakeNamedMedium \"%s\"", name);
    if ((st = resolve_file(S, what, file, abs)))
        return st;
    /* pbrt reads the file's "temperature" grid when it has one */
    bool has_temp = false;
    gridvdb_info *gi = NULL;
    int ng = 0;
    if (grid_list_file(abs, 0, &gi, &ng) != BRUME_OK)
        return err_prefix("%s:%d: MakeNamedMedium \"%s\"", L->file, L->dir_line, name);
    for (int i = 0; i < ng; i++)
        has_temp |= strcmp(gi[i].name, "temperature") == 0;
    free(gi);
    cJSON *m = medium_new(L, name, sa, ss, scale, g);
    if (!m)
        return err_status();
    cJSON *d = cJSON_AddObjectToObject(m, "density");
    cJSON_AddStringToObject(d, "type", "grid");
    cJSON_AddStringToObject(d, "file", abs);
    cJSON_AddStringToObject(d, "grid", "density");
    if (!medium_place(S, d, name)) {
        cJSON_Delete(m);
        return err_status();
    }
    if (has_temp) {
        /* pbrt-v4: T' = (T - offset) scale; above 100 K, Le = Lescale B(T') with B the
           peak-normalized blackbody, emitted at the rate sigma_a rho Le: brume's model */
        cJSON *t = cJSON_AddObjectToObject(m, "temperature");
        cJSON_AddStringToObject(t, "grid", "temperature");
        cJSON *bb = cJSON_AddObjectToObject(m, "blackbody");
        cJSON_AddNumberToObject(bb, "scale", Lescale);
        cJSON_AddNumberToObject(bb, "temperature_scale", tscale);
        cJSON_AddNumberToObject(bb, "temperature_offset", toff);
        cJSON_AddNumberToObject(bb, "cutoff", 100);
    }
    return medium_add(S, name, m, false);
}

/* A shape's triangles in world space (pbrt's trianglemesh and bilinearmesh, transformed by
 * the current transform, which may then hold any affine map). */
typedef struct tris {
    double *P; /* 3 nv */
    int *idx;  /* 3 nt */
    int nv, nt;
} tris;

static void tris_free(tris *t)
{
    free(t->P);
    free(t->idx);
}

/* Whether the triangles are exactly the surface of an axis-aligned box, which they give in
 * b: every triangle lies in a face plane, faces out, and each face's triangles add up to its
 * area (within 1e-9 of the box's size and 1e-6 of the area). pbrt puts a shape's inside
 * medium behind its faces' normals, (p1 - p0) x (p2 - p0) reversed when the transform
 * mirrors (flip); shading normals N are not consulted. */
static bool tris_are_box(const tris *t, bool flip, double b[6])
{
    for (int k = 0; k < 3; k++) {
        b[k] = INFINITY;
        b[3 + k] = -INFINITY;
    }
    for (int i = 0; i < t->nv; i++)
        for (int k = 0; k < 3; k++) {
            b[k] = fmin(b[k], t->P[3 * i + k]);
            b[3 + k] = fmax(b[3 + k], t->P[3 * i + k]);
        }
    double size = fmax(b[3] - b[0], fmax(b[4] - b[1], b[5] - b[2])), eps = 1e-9 * size, area[6] = {0};
    for (int k = 0; k < 3; k++)
        if (!(b[3 + k] - b[k] > eps))
            return false;
    for (int f = 0; f < t->nt; f++) {
        const double *p[3] = {&t->P[3 * t->idx[3 * f]], &t->P[3 * t->idx[3 * f + 1]], &t->P[3 * t->idx[3 * f + 2]]};
        int face = -1;
        for (int s = 0; s < 6 && face < 0; s++) {
            int k = s % 3;
            if (fabs(p[0][k] - b[s]) <= eps && fabs(p[1][k] - b[s]) <= eps && fabs(p[2][k] - b[s]) <= eps)
                face = s;
        }
        if (face < 0)
            return false;
        vec3 u = v3(p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]);
        vec3 v = v3(p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]);
        vec3 n = v3_cross(u, v);
        double out = (face < 3 ? -1.0 : 1.0) * (flip ? -1.0 : 1.0) * (face % 3 == 0 ? n.x : face % 3 == 1 ? n.y : n.z);
        if (!(out > 0.0))
            return false;
        area[face] += 0.5 * v3_length(n);
    }
    for (int s = 0; s < 6; s++) {
        int k = s % 3, k1 = (k + 1) % 3, k2 = (k + 2) % 3;
        double want = (b[3 + k1] - b[k1]) * (b[3 + k2] - b[k2]);
        if (fabs(area[s] - want) > 1e-6 * want)
            return false;
    }
    return true;
}

/* "point3 P" and "integer indices" (per = 3 for triangles, 4 for bilinear patches; without
 * indices, the one primitive of exactly `per` points) into t, P transformed to world space. */
static brume_status mesh_params(pbrt_state *S, params *ps, const char *what, int per, tris *t, int **quad)
{
    lexer *L = &S->L;
    static const char *const points[] = {"point3", "point", NULL}, *const ints[] = {"integer", NULL};
    param *P = NULL, *I = NULL;
    brume_status st;
    *quad = NULL;
    if ((st = get_array(L, ps, "P", points, &P)) || (st = get_array(L, ps, "indices", ints, &I)))
        return st;
    if (!P || P->n % 3)
        return fail(L, "%s: \"point3 P\" must be given as x y z triples", what);
    int nv = P->n / 3, ni = I ? I->n : per;
    if (!I && nv != per)
        return fail(L, "%s: no \"integer indices\" (allowed only for exactly %d points)", what, per);
    if (ni % per)
        return fail(L, "%s: %d indices, not a multiple of %d", what, ni, per);
    if (P->n > SCENE_INLINE_MAX_VALUES || (double)ni / per * 3 * (per - 2) > SCENE_INLINE_MAX_VALUES)
        return fail(L, "%s: more than the %d coordinates or triangle indices brume takes inline (a larger mesh "
                       "belongs in a plymesh)", what, SCENE_INLINE_MAX_VALUES);
    int *idx = malloc((size_t)ni * sizeof *idx);
    t->P = malloc((size_t)P->n * sizeof *t->P);
    if (!idx || !t->P) {
        free(idx);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", L->file, L->dir_line, what);
    }
    for (int i = 0; i < ni; i++) {
        double x = I ? I->v[i] : i;
        if (!(x >= 0 && x < nv) || x != floor(x)) {
            free(idx);
            return fail(L, "%s: index %d: %g is not a point of P (0 to %d)", what, i, x, nv - 1);
        }
        idx[i] = (int)x;
    }
    m4 ctm = S->a[S->depth].ctm;
    for (int i = 0; i < nv; i++) {
        vec3 w = m4_point(ctm, v3(P->v[3 * i], P->v[3 * i + 1], P->v[3 * i + 2]));
        t->P[3 * i] = w.x;
        t->P[3 * i + 1] = w.y;
        t->P[3 * i + 2] = w.z;
    }
    t->nv = nv;
    if (per == 3) {
        t->idx = idx;
        t->nt = ni / 3;
    } else {
        *quad = idx;
        t->nt = ni / 4;
    }
    return BRUME_OK;
}

/* pbrt's bilinear patches (corners p00, p10, p01, p11) as two triangles each, (p00, p10,
 * p11) and (p00, p11, p01), facing along (p10 - p00) x (p01 - p00) as pbrt's patch does:
 * exact for a planar patch (its surface is then the quadrilateral). A non-planar patch is
 * curved, and is refused rather than flattened. */
static brume_status bilinear_tris(lexer *L, const int *quad, tris *t)
{
    int np = t->nt;
    t->idx = malloc((size_t)np * 6 * sizeof *t->idx);
    if (!t->idx)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: bilinearmesh: out of memory", L->file, L->dir_line);
    for (int i = 0; i < np; i++) {
        const int *q = &quad[4 * i];
        vec3 p[4];
        for (int c = 0; c < 4; c++)
            p[c] = v3(t->P[3 * q[c]], t->P[3 * q[c] + 1], t->P[3 * q[c] + 2]);
        vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
        double size = fmax(v3_length(v3_sub(p[3], p[0])), v3_length(v3_sub(p[2], p[1])));
        if (!(v3_length(n) > 0.0) || fabs(v3_dot(v3_normalize(n), v3_sub(p[3], p[0]))) > 1e-9 * size)
            return fail(L, "Shape \"bilinearmesh\": patch %d is not planar (or is degenerate): brume renders "
                           "triangles, exact only for planar patches", i);
        int tri[6] = {q[0], q[1], q[3], q[0], q[3], q[2]};
        memcpy(&t->idx[6 * i], tri, sizeof tri);
    }
    t->nt = 2 * np;
    return BRUME_OK;
}

/* The medium inside a shape whose material is "interface": brume's media are fields in
 * vacuum, so the shape is not drawn. A grid medium is the whole grid (exact when the shape
 * bounds it, as pbrt-v4-scenes' bounding spheres do; not checked); a homogeneous one fills
 * the shape, which must then be an axis-aligned box of triangles (a `constant` density). */
static brume_status shape_interface(pbrt_state *S, const char *type, const tris *t)
{
    lexer *L = &S->L;
    attrs *a = &S->a[S->depth];
    if (!a->inside[0])
        return fail(L, "Shape: an \"interface\" material without a medium inside (MediumInterface)");
    named_medium *nm = NULL;
    for (int i = 0; i < S->nmedia; i++)
        if (strcmp(S->media[i].name, a->inside) == 0)
            nm = &S->media[i];
    if (!nm)
        return fail(L, "MediumInterface: no medium named \"%s\"", a->inside);
    if (!nm->homogeneous) {
        if (!nm->emitted) {
            cJSON_AddItemToArray(S->media_j, nm->json);
            nm->emitted = true;
        }
        return BRUME_OK;
    }
    double b[6];
    const double *c = a->ctm.m; /* a mirror reverses pbrt's normals */
    double det = c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) +
                 c[2] * (c[4] * c[9] - c[5] * c[8]);
    if (!t || !tris_are_box(t, det < 0.0, b))
        return fail(L, "Shape \"%s\" bounding the homogeneous medium \"%s\": brume's homogeneous media fill "
                       "axis-aligned boxes (a trianglemesh or bilinearmesh that is one, faces facing out)", type,
                    nm->name);
    cJSON *m = cJSON_Duplicate(nm->json, 1);
    cJSON *d = cJSON_AddObjectToObject(m, "density");
    cJSON_AddStringToObject(d, "type", "constant");
    cJSON_AddNumberToObject(d, "value", 1);
    cJSON *bounds = cJSON_AddArrayToObject(d, "bounds");
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(b, 3));
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(b + 3, 3));
    cJSON_AddItemToArray(S->media_j, m);
    return BRUME_OK;
}

/* A drawn shape: s (owned from here) with the current diffuse material. */
static brume_status shape_surface(pbrt_state *S, cJSON *s)
{
    attrs *a = &S->a[S->depth];
    if (a->inside[0]) {
        cJSON_Delete(s);
        return fail(&S->L, "Shape: medium \"%s\" inside a shape whose material is not \"interface\"", a->inside);
    }
    cJSON *mat = cJSON_AddObjectToObject(s, "material");
    cJSON_AddItemToObject(mat, "albedo", cJSON_CreateDoubleArray(a->albedo, 3));
    cJSON_AddItemToArray(S->surfaces, s);
    return BRUME_OK;
}

/* A new brume surface of the type, placed by the current transform; NULL after a refusal
 * (shear: brume's transform object is translate, rotate, scale). */
static cJSON *placed_surface(pbrt_state *S, const char *what, const char *type)
{
    m4 m = S->a[S->depth].ctm;
    const double *c = m.m;
    double det = c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) +
                 c[2] * (c[4] * c[9] - c[5] * c[8]);
    if (det < 0.0 && strcmp(type, "sphere") == 0) {
        m = m4_mul(m, m4_scale(-1.0, 1.0, 1.0)); /* the same points: the unit sphere is its own mirror image */
    } else if (det < 0.0) {
        fail(&S->L, "%s: a mirroring transform (brume places a mesh file with positive scales only; a pbrt view "
                    "without \"Scale -1 1 1\" mirrors the whole world, docs/production.md)", what);
        return NULL;
    }
    cJSON *t = transform_json(m);
    if (!t) {
        fail(&S->L, "%s: a transform with shear", what);
        return NULL;
    }
    cJSON *s = cJSON_CreateObject();
    cJSON_AddStringToObject(s, "type", type);
    cJSON_AddItemToObject(s, "transform", t);
    return s;
}

static brume_status shape_directive(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    attrs *a = &S->a[S->depth];
    char what[160];
    snprintf(what, sizeof what, "Shape \"%s\"", type);
    if (a->outside[0])
        return fail(L, "MediumInterface: an outside medium \"%s\" (brume's media are fields in vacuum)", a->outside);
    bool interface = strcmp(a->material, "interface") == 0;
    if (strcmp(type, "sphere") == 0) {
        double radius = 1.0;
        if ((st = get_float(L, ps, "radius", &radius)) || (st = all_used(L, ps, what)))
            return st;
        if (interface)
            return shape_interface(S, type, NULL);
        cJSON *s = placed_surface(S, what, "sphere");
        if (!s)
            return err_status();
        cJSON_AddNumberToObject(s, "radius", radius);
        return shape_surface(S, s);
    }
    if (strcmp(type, "plymesh") == 0) {
        char file[1024] = "", abs[PATH_MAX];
        if ((st = get_string(L, ps, "filename", file, sizeof file)) || (st = all_used(L, ps, what)))
            return st;
        if (!file[0])
            return fail(L, "%s: no \"string filename\"", what);
        if ((st = resolve_file(S, what, file, abs)))
            return st;
        if (interface) /* a grid's bound; a homogeneous medium's box needs the triangles, read later by assimp */
            return shape_interface(S, type, NULL);
        cJSON *s = placed_surface(S, what, "mesh");
        if (!s)
            return err_status();
        cJSON_AddStringToObject(s, "file", abs);
        return shape_surface(S, s);
    }
    bool tri = strcmp(type, "trianglemesh") == 0;
    if (!tri && strcmp(type, "bilinearmesh") != 0)
        return fail(L, "%s: not supported by brume's pbrt reader (sphere, trianglemesh, bilinearmesh, plymesh)", what);
    /* shading normals, uv and tangents do not change a diffuse surface's geometry: read and
       not used (brume shades by the geometric normal) */
    get(ps, "N");
    get(ps, "uv");
    if (tri) {
        get(ps, "S");
        get(ps, "faceIndices");
    }
    tris t = {0};
    int *quad = NULL;
    if ((st = mesh_params(S, ps, what, tri ? 3 : 4, &t, &quad)) || (st = all_used(L, ps, what)) ||
        (!tri && (st = bilinear_tris(L, quad, &t)))) {
        free(quad);
        tris_free(&t);
        return st;
    }
    free(quad);
    if (interface) {
        st = shape_interface(S, type, &t);
        tris_free(&t);
        return st;
    }
    if ((st = count_inline(S, what, 3.0 * t.nv + 3.0 * t.nt))) {
        tris_free(&t);
        return st;
    }
    cJSON *s = cJSON_CreateObject();
    cJSON_AddStringToObject(s, "type", "mesh");
    cJSON_AddItemToObject(s, "positions", cJSON_CreateDoubleArray(t.P, 3 * t.nv));
    cJSON_AddItemToObject(s, "indices", cJSON_CreateIntArray(t.idx, 3 * t.nt));
    tris_free(&t);
    return shape_surface(S, s);
}

/* Film, Sampler, Integrator, ColorSpace, Material: what they set of the scene or of the
 * current attributes a (their type and parameters read). */
static brume_status setting_directive(pbrt_state *S, attrs *a, const char *dir, const char *type, const char *what,
                                      params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    if (strcmp(dir, "Film") == 0) {
        double x = 1280, y = 720;
        char fn[512];
        if ((st = get_float(L, ps, "xresolution", &x)) || (st = get_float(L, ps, "yresolution", &y)) ||
            (st = get_string(L, ps, "filename", fn, sizeof fn)))
            return st;
        if (!(x >= 1 && x <= 65536 && y >= 1 && y <= 65536))
            return fail(L, "%s: resolution outside [1, 65536]", what);
        S->xres = (int)x;
        S->yres = (int)y;
    } else if (strcmp(dir, "Sampler") == 0) {
        double n = 16;
        if ((st = get_float(L, ps, "pixelsamples", &n))) return st;
        if (!(n >= 1 && n <= 1 << 24))
            return fail(L, "%s: pixelsamples outside [1, 2^24]", what);
        S->spp = (int)n;
    } else if (strcmp(dir, "Integrator") == 0) {
        if (strcmp(type, "volpath") != 0 && strcmp(type, "path") != 0)
            return fail(L, "%s: brume's path tracer stands for volpath and path only", what);
        double d = 5;
        if ((st = get_float(L, ps, "maxdepth", &d))) return st;
        if (!(d >= 1 && d <= 100000))
            return fail(L, "%s: maxdepth outside [1, 100000]", what);
        S->max_depth = (int)d;
    } else if (strcmp(dir, "ColorSpace") == 0) {
        if (strcmp(type, "srgb") != 0)
            return fail(L, "%s: brume renders linear Rec. 709 (srgb) only", what);
    } else { /* Material */
        if (strcmp(type, "interface") != 0 && strcmp(type, "diffuse") != 0 && type[0])
            return fail(L, "%s: not supported by brume (diffuse, interface)", what);
        copy(a->material, sizeof a->material, type[0] ? type : "interface"); /* pbrt: "" is "interface" */
        a->albedo[0] = a->albedo[1] = a->albedo[2] = 0.5;
        if (strcmp(type, "diffuse") == 0 && (st = get_color(L, ps, "reflectance", a->albedo)))
            return st;
    }
    return all_used(L, ps, what);
}

static bool is_typed_directive(const char *dir)
{
    static const char *const typed[] = {"Camera", "Film", "Sampler", "Integrator", "Material",
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
    next(L);
    if (L->kind != TOK_STRING)
        return fail(L, "%s: expected its %s", dir, strcmp(dir, "MakeNamedMedium") == 0 ? "name" : "type");
    char type[128], what[200];
    copy(type, sizeof type, L->text);
    snprintf(what, sizeof what, "%s \"%s\"", dir, type);
    next(L);
    if ((st = read_params(L, ps))) return st;
    if (strcmp(dir, "Camera") == 0)
        return camera_directive(S, type, ps);
    if (strcmp(dir, "LightSource") == 0)
        return light_directive(S, type, ps);
    if (strcmp(dir, "Shape") == 0)
        return shape_directive(S, type, ps);
    if (strcmp(dir, "MakeNamedMedium") == 0)
        return medium_directive(S, type, ps);
    return setting_directive(S, a, dir, type, what, ps);
}

/* The transform that stands for pbrt's identity: in the world block of a mirrored view
 * (camera_directive) the mirror x -> -x, else the identity. */
static m4 world_origin(const pbrt_state *S)
{
    return S->world && S->mirror ? m4_scale(-1.0, 1.0, 1.0) : m4_identity();
}

/* The transform directives: *handled false when dir is none of them. */
static brume_status transform_directive(pbrt_state *S, attrs *a, const char *dir, bool *handled)
{
    lexer *L = &S->L;
    double v[16];
    brume_status st;
    *handled = true;
    if (strcmp(dir, "Identity") == 0) {
        a->ctm = world_origin(S);
        next(L);
    } else if (strcmp(dir, "Translate") == 0) {
        if ((st = numbers(L, dir, 3, v))) return st;
        a->ctm = m4_mul(a->ctm, m4_translate(v[0], v[1], v[2]));
    } else if (strcmp(dir, "Scale") == 0) {
        if ((st = numbers(L, dir, 3, v))) return st;
        a->ctm = m4_mul(a->ctm, m4_scale(v[0], v[1], v[2]));
    } else if (strcmp(dir, "Rotate") == 0) {
        if ((st = numbers(L, dir, 4, v))) return st;
        a->ctm = m4_mul(a->ctm, m4_rotate(v[0], v3(v[1], v[2], v[3])));
    } else if (strcmp(dir, "LookAt") == 0) {
        if ((st = numbers(L, dir, 9, v))) return st;
        m4 la;
        if (!m4_look_at(v3(v[0], v[1], v[2]), v3(v[3], v[4], v[5]), v3(v[6], v[7], v[8]), &la))
            return fail(L, "%s: up parallel to the view direction", dir);
        a->ctm = m4_mul(a->ctm, la);
    } else if (strcmp(dir, "Transform") == 0 || strcmp(dir, "ConcatTransform") == 0) {
        if ((st = numbers(L, dir, 16, v))) return st;
        m4 t; /* pbrt's matrices are given column by column */
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                t.m[4 * i + j] = v[4 * j + i];
        a->ctm = dir[0] == 'T' ? m4_mul(world_origin(S), t) : m4_mul(a->ctm, t);
    } else {
        *handled = false;
    }
    return BRUME_OK;
}

static brume_status directive(pbrt_state *S, params *ps)
{
    lexer *L = &S->L;
    char dir[64];
    copy(dir, sizeof dir, L->text);
    L->dir_line = L->tok_line;
    attrs *a = &S->a[S->depth];
    if (L->kind != TOK_WORD)
        return fail(L, "expected a directive, found \"%s\"", L->text);
    bool handled;
    brume_status st = transform_directive(S, a, dir, &handled);
    if (handled)
        return st;
    if (is_typed_directive(dir))
        return typed_directive(S, a, dir, ps);
    if (strcmp(dir, "WorldBegin") == 0) {
        if (!S->have_camera)
            return fail(L, "%s before a Camera", dir);
        S->world = true;
        a->ctm = world_origin(S);
        next(L);
    } else if (strcmp(dir, "AttributeBegin") == 0) {
        if (S->depth + 1 == PBRT_MAX_DEPTH)
            return fail(L, "%s: nested too deep", dir);
        S->a[S->depth + 1] = *a;
        S->depth++;
        next(L);
    } else if (strcmp(dir, "AttributeEnd") == 0) {
        if (S->depth == 0)
            return fail(L, "%s without AttributeBegin", dir);
        S->depth--;
        next(L);
    } else if (strcmp(dir, "MediumInterface") == 0) {
        next(L);
        if (L->kind != TOK_STRING)
            return fail(L, "%s: expected a medium name", dir);
        copy(a->inside, sizeof a->inside, L->text);
        next(L);
        a->outside[0] = '\0';
        if (L->kind == TOK_STRING) {
            copy(a->outside, sizeof a->outside, L->text);
            next(L);
        } else {
            copy(a->outside, sizeof a->outside, a->inside);
        }
    } else {
        return fail(L, "%s: not supported by brume's pbrt reader (docs/production.md lists what is)", dir);
    }
    return BRUME_OK;
}

bool scene_pbrt_is_pbrt(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot && strcmp(dot, ".pbrt") == 0;
}

static brume_status read_all(const char *path, char **out)
{
    *out = NULL;
    FILE *f = fopen(path, "rb");
    if (!f)
        return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    char *buf = malloc((size_t)PBRT_MAX_BYTES + 1);
    size_t n = buf ? fread(buf, 1, (size_t)PBRT_MAX_BYTES + 1, f) : 0;
    int bad = ferror(f);
    fclose(f);
    if (!buf)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    if (bad || n > (size_t)PBRT_MAX_BYTES) {
        free(buf);
        return err_set(bad ? BRUME_ERROR_IO : BRUME_ERROR_RANGE, "%s: %s", path, bad ? "read error" : "larger than 64 MiB");
    }
    buf[n] = '\0';
    if (strlen(buf) != n) {
        free(buf);
        return err_set(BRUME_ERROR_PARSE, "%s: contains a NUL byte; not a pbrt scene", path);
    }
    *out = buf;
    return BRUME_OK;
}

brume_status scene_pbrt_json(const char *path, char **json)
{
    *json = NULL;
    char *text = NULL;
    if (read_all(path, &text) != BRUME_OK)
        return err_status();
    pbrt_state *S = calloc(1, sizeof *S);
    params *ps = calloc(1, sizeof *ps);
    if (!S || !ps) {
        free(S);
        free(ps);
        free(text);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    S->L = (lexer){path, text, 1, TOK_END, "", 1, 1};
    S->path = path;
    char tmp[PATH_MAX];
    copy(tmp, sizeof tmp, path);
    char *slash = strrchr(tmp, '/');
    snprintf(S->dir, sizeof S->dir, "%s", slash ? (*slash = '\0', tmp[0] ? tmp : "/") : ".");
    S->a[0].ctm = m4_identity();
    snprintf(S->a[0].material, sizeof S->a[0].material, "diffuse");
    S->a[0].albedo[0] = S->a[0].albedo[1] = S->a[0].albedo[2] = 0.5;
    S->xres = 1280;
    S->yres = 720;
    S->spp = 16;
    S->max_depth = 5;
    S->root = cJSON_CreateObject();
    S->lights = cJSON_CreateArray();
    S->media_j = cJSON_CreateArray();
    S->surfaces = cJSON_CreateArray();
    brume_status st = BRUME_OK;
    next(&S->L);
    while (st == BRUME_OK && S->L.kind != TOK_END)
        st = directive(S, ps);
    if (st == BRUME_OK && *S->L.p)
        st = fail(&S->L, "syntax error near \"%.64s\"", S->L.text);
    if (st == BRUME_OK && !S->world)
        st = err_set(BRUME_ERROR_PARSE, "%s: no WorldBegin", path);
    if (st == BRUME_OK) {
        char note[600];
        snprintf(note, sizeof note, "translated by brume from the pbrt-v4 scene %s (docs/production.md)", path);
        cJSON_AddStringToObject(S->root, "comment", note);
        cJSON *cam = cJSON_AddObjectToObject(S->root, "camera");
        vec3 P = m4_point(S->world_from_camera, v3(0, 0, 0));
        vec3 F = v3_normalize(m4_vector(S->world_from_camera, v3(0, 0, 1)));
        vec3 U = v3_normalize(m4_vector(S->world_from_camera, v3(0, 1, 0)));
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
        cJSON *r = cJSON_AddObjectToObject(S->root, "render");
        cJSON_AddNumberToObject(r, "width", S->xres);
        cJSON_AddNumberToObject(r, "height", S->yres);
        cJSON_AddNumberToObject(r, "spp", S->spp);
        cJSON_AddStringToObject(r, "method", "path");
        cJSON_AddNumberToObject(r, "max_depth", S->max_depth);
        if (!(*json = cJSON_Print(S->root)))
            st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    for (int i = 0; i < S->nmedia; i++)
        if (!S->media[i].emitted)
            cJSON_Delete(S->media[i].json);
    cJSON_Delete(S->lights);
    cJSON_Delete(S->media_j);
    cJSON_Delete(S->surfaces);
    cJSON_Delete(S->root);
    free(S);
    params_clear(ps);
    free(ps);
    free(text);
    return st;
}
