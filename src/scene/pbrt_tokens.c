/* pbrt_tokens.c - the pbrt reader's tokens and a directive's parameter list ("type name"
 * [values]): reading them, the typed look-ups, the refusal of a parameter left unused; and
 * what every directive family shares: the scene's count of inline numbers, the files a
 * directive names. */
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
#include "core/number.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/json.h"
#include "scene/scene_build.h"
#include "core/budget.h"
#include "scene/pbrt.h"

void pbrt_next(lexer *L)
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
brume_status pbrt_fail(const lexer *L, const char *fmt, ...)
{
    char msg[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return err_set(BRUME_ERROR_UNSUPPORTED, "%s:%d: %s", L->file, L->dir_line, msg);
}

/* src into dst[cap], cut to fit. */
void pbrt_copy(char *dst, size_t cap, const char *src)
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
    double v = num_strtod(s, &end);
    if (end == s || *end || errno || !isfinite(v))
        return false;
    *out = v;
    return true;
}

/* n numbers as bare words (LookAt, Translate ...) or in brackets (Transform). */
brume_status pbrt_numbers(lexer *L, const char *dir, int n, double *out)
{
    bool bracket = false;
    pbrt_next(L);
    if (L->kind == TOK_OPEN) {
        bracket = true;
        pbrt_next(L);
    }
    for (int i = 0; i < n; i++) {
        if (L->kind != TOK_WORD || !number(L->text, &out[i]))
            return pbrt_fail(L, "%s: expected a number", dir);
        pbrt_next(L);
    }
    if (bracket) {
        if (L->kind != TOK_CLOSE)
            return pbrt_fail(L, "%s: expected ]", dir);
        pbrt_next(L);
    }
    return BRUME_OK;
}

/* Frees the values of the parameters read last. */
void pbrt_params_clear(params *ps)
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
        return pbrt_fail(L, "more than the %d values brume reads inline in one directive", PBRT_MAX_DIRECTIVE_VALUES);
    if (q->n < q->cap)
        return BRUME_OK;
    if (q->n >= PBRT_MAX_VALUES)
        return pbrt_fail(L, "parameter \"%s\": more than the %d values brume reads inline", q->name, PBRT_MAX_VALUES);
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
brume_status pbrt_read_params(lexer *L, params *ps)
{
    brume_status st;
    pbrt_params_clear(ps);
    while (L->kind == TOK_STRING) {
        if (ps->n == PBRT_MAX_PARAMS)
            return pbrt_fail(L, "more than %d parameters", PBRT_MAX_PARAMS);
        param *q = &ps->p[ps->n++];
        memset(q, 0, sizeof *q);
        q->line = L->tok_line;
        if (sscanf(L->text, "%15s %63s", q->type, q->name) != 2)
            return pbrt_fail(L, "parameter \"%s\": expected \"type name\"", L->text);
        pbrt_next(L);
        bool bracket = L->kind == TOK_OPEN;
        if (bracket)
            pbrt_next(L);
        do {
            if ((st = grow(L, ps, q)))
                return st;
            if (L->kind == TOK_STRING) {
                if (q->n == 0)
                    pbrt_copy(q->s, sizeof q->s, L->text);
                q->is_string = true;
                q->n++;
            } else if (L->kind == TOK_WORD && (strcmp(L->text, "true") == 0 || strcmp(L->text, "false") == 0)) {
                q->v[q->n] = strcmp(L->text, "true") == 0;
                q->n++;
            } else if (L->kind == TOK_WORD) {
                if (!number(L->text, &q->v[q->n]))
                    return pbrt_fail(L, "parameter \"%s\": expected a number", q->name);
                q->n++;
            } else {
                return pbrt_fail(L, "parameter \"%s\": expected a value", q->name);
            }
            pbrt_next(L);
        } while (bracket && L->kind != TOK_CLOSE && L->kind != TOK_END);
        if (bracket) {
            if (L->kind != TOK_CLOSE)
                return pbrt_fail(L, "parameter \"%s\": expected ]", q->name);
            pbrt_next(L);
        }
    }
    return BRUME_OK;
}

param *pbrt_get(params *ps, const char *name)
{
    for (int i = 0; i < ps->n; i++)
        if (strcmp(ps->p[i].name, name) == 0) {
            ps->p[i].used = true;
            return &ps->p[i];
        }
    return NULL;
}

brume_status pbrt_get_float(lexer *L, params *ps, const char *name, double *out)
{
    param *q = pbrt_get(ps, name);
    if (!q)
        return BRUME_OK;
    if (q->is_string || q->n != 1 || (strcmp(q->type, "float") != 0 && strcmp(q->type, "integer") != 0))
        return pbrt_fail(L, "parameter \"%s\": expected one float", name);
    *out = q->v[0];
    return BRUME_OK;
}

brume_status pbrt_get_point(lexer *L, params *ps, const char *name, double out[3])
{
    param *q = pbrt_get(ps, name);
    if (!q)
        return BRUME_OK;
    if (q->is_string || q->n != 3)
        return pbrt_fail(L, "parameter \"%s\": expected three numbers", name);
    memcpy(out, q->v, 3 * sizeof *out);
    return BRUME_OK;
}

/* An "rgb" value, or a "spectrum" given as one constant or as constant (lambda, value)
 * pairs; anything else (a blackbody, a named or varying spectrum) is refused: brume renders
 * in RGB and would have to guess the projection. */
brume_status pbrt_get_color(lexer *L, params *ps, const char *name, double out[3])
{
    param *q = pbrt_get(ps, name);
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
                return pbrt_fail(L, "parameter \"%s\": a spectrum that varies with wavelength (brume renders RGB)", name);
        out[0] = out[1] = out[2] = v;
        return BRUME_OK;
    }
    if (strcmp(q->type, "float") == 0 && !q->is_string && q->n == 1) {
        out[0] = out[1] = out[2] = q->v[0];
        return BRUME_OK;
    }
    return pbrt_fail(L, "parameter \"%s\": brume reads rgb values and constant spectra only", name);
}

brume_status pbrt_get_string(lexer *L, params *ps, const char *name, char *out, size_t n)
{
    param *q = pbrt_get(ps, name);
    if (!q)
        return BRUME_OK;
    if (!q->is_string || q->n != 1)
        return pbrt_fail(L, "parameter \"%s\": expected one string", name);
    snprintf(out, n, "%s", q->s);
    return BRUME_OK;
}

/* Every parameter must have been read: the first that was not is refused. */
brume_status pbrt_all_used(const lexer *L, const params *ps, const char *dir)
{
    for (int i = 0; i < ps->n; i++)
        if (!ps->p[i].used) {
            lexer at = *L;
            at.dir_line = ps->p[i].line;
            return pbrt_fail(&at, "%s: parameter \"%s %s\": not supported by brume", dir, ps->p[i].type, ps->p[i].name);
        }
    return BRUME_OK;
}

/* "integer NAME" in [1, 65536] (pbrt's nx, ny, nz; default 1). */
brume_status pbrt_get_count(lexer *L, params *ps, const char *name, int *out)
{
    double v = 1;
    brume_status st = pbrt_get_float(L, ps, name, &v);
    if (st)
        return st;
    if (!(v >= 1 && v <= 65536) || v != floor(v))
        return pbrt_fail(L, "parameter \"%s\": %g is not an integer in [1, 65536]", name, v);
    *out = (int)v;
    return BRUME_OK;
}

/* The numbers of an array parameter of one of the types given (NULL-terminated list);
 * NULL when absent. */
brume_status pbrt_get_array(lexer *L, params *ps, const char *name, const char *const *types, param **out)
{
    *out = NULL;
    param *q = pbrt_get(ps, name);
    if (!q)
        return BRUME_OK;
    bool ok = false;
    for (int i = 0; types[i]; i++)
        ok |= strcmp(q->type, types[i]) == 0;
    if (!ok || q->is_string || q->n < 1) {
        lexer at = *L;
        at.dir_line = q->line;
        return pbrt_fail(&at, "parameter \"%s %s\": expected %s values", q->type, name, types[0]);
    }
    *out = q;
    return BRUME_OK;
}

/* Counts n more inline numbers against the scene's limit. */
/* The translation's memory so far, estimated from what it holds: the text, a JSON object of
 * at most PBRT_OBJECT_BYTES for each typed directive (a shape, a light, a medium, with its
 * transform) and PBRT_NUMBER_BYTES for each inline number (a node and its printed form),
 * the printed JSON as large again. Kept within the memory limit (render.max_memory_mb's
 * default: the scene's own setting is read from the translation), so that a file of a
 * million spheres is refused instead of exhausting the machine. */
#define PBRT_OBJECT_BYTES 2048.0
#define PBRT_NUMBER_BYTES 100.0
brume_status pbrt_count_translation(pbrt_state *S)
{
    double bytes = (double)S->text_bytes + 2.0 * (PBRT_OBJECT_BYTES * (double)S->objects +
                                                   PBRT_NUMBER_BYTES * S->inline_numbers);
    if (bytes > (double)budget_left())
        return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                       "%s:%d: translating the pbrt scene needs about %.0f MiB (%ld directives that make objects, "
                       "%.0f inline numbers), more than the %.0f MiB memory limit (render.max_memory_mb)",
                       S->L.file, S->L.dir_line, bytes / 1048576.0, S->objects, S->inline_numbers,
                       (double)budget_left() / 1048576.0);
    return BRUME_OK;
}

brume_status pbrt_count_inline(pbrt_state *S, const char *what, double n)
{
    S->inline_numbers += n;
    if (S->inline_numbers > PBRT_MAX_SCENE_INLINE)
        return pbrt_fail(&S->L, "%s: the scene's inline grids and meshes come to more than %d numbers (larger data "
                                "belongs in nanovdb and ply files)", what, PBRT_MAX_SCENE_INLINE);
    return pbrt_count_translation(S);
}

/* A file a directive names, relative to the .pbrt's folder, as an absolute path in abs. */
brume_status pbrt_resolve_file(pbrt_state *S, const char *what, const char *file, char abs[PATH_MAX])
{
    char rel[PATH_MAX + 1100];
    if (file[0] == '/')
        pbrt_copy(rel, sizeof rel, file);
    else
        snprintf(rel, sizeof rel, "%s/%s", S->dir, file);
    if (!realpath(rel, abs))
        return err_set(BRUME_ERROR_IO, "%s:%d: %s: %s: %s", S->L.file, S->L.dir_line, what, rel, strerror(errno));
    return BRUME_OK;
}
