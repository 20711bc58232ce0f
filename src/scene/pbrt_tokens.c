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

/* A quoted string's body into L->text, escapes resolved as pbrt-v4's tokenizer does; L->p is
 * on the opening quote. TOK_BAD when the line or the file ends first, or the text would not fit. */
static void string_token(lexer *L)
{
    static const char escapes[] = "b\bf\fn\nr\rt\t\\\\''\"\"";
    size_t n = 0;
    L->kind = TOK_STRING;
    L->p++;
    for (;;) {
        char c = *L->p;
        if (c == '"') {
            L->p++;
            break;
        }
        if (c == '\0' || c == '\n') {
            L->kind = TOK_BAD;
            L->bad = c ? "unterminated string (a string ends on the line it starts)"
                       : "unterminated string (the file ends in it)";
            break;
        }
        if (c == '\\') {
            const char *e = L->p[1] ? strchr(escapes, L->p[1]) : NULL;
            if (!e || (e - escapes) % 2) {
                L->kind = TOK_BAD;
                L->bad = "a string with an unknown escape (pbrt-v4's: \\b \\f \\n \\r \\t \\\\ \\' \\\")";
                break;
            }
            c = e[1];
            L->p++;
        }
        if (n + 1 == sizeof L->text) {
            L->kind = TOK_BAD;
            L->bad = "a string longer than 1023 bytes";
            break;
        }
        L->text[n++] = c;
        L->p++;
    }
    L->text[n] = '\0';
}

/* The end of an included file inside a parameter list, where the including file goes on
 * with a parameter (a string: no directive starts with one): the list goes on there, whose
 * lexer stands on the token after the Include's file name. Refusals of the directive then
 * name the including file and the Include's line. */
static void resume_outer(lexer *L)
{
    *L = *L->outer;
    L->in_params = true;
    L->resumed = true;
}

void pbrt_next(lexer *L)
{
    if (L->kind == TOK_BAD)
        return; /* the file cannot be read past it: every caller refuses it */
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
    if (!c && L->in_params && L->outer && L->outer->kind == TOK_STRING) {
        resume_outer(L); /* stands on the including file's token */
        return;
    }
    if (!c) {
        L->kind = TOK_END;
    } else if (c == '[' || c == ']') {
        L->kind = c == '[' ? TOK_OPEN : TOK_CLOSE;
        L->p++;
    } else if (c == '"') {
        string_token(L);
        return;
    } else {
        L->kind = TOK_WORD;
        while (*L->p && !isspace((unsigned char)*L->p) && *L->p != '"' && *L->p != '[' && *L->p != ']' && *L->p != '#') {
            if (n + 1 == sizeof L->text) {
                L->kind = TOK_BAD;
                L->bad = "a word longer than 1023 bytes";
                break;
            }
            L->text[n++] = *L->p;
            L->p++;
        }
    }
    L->text[n] = '\0';
}

/* "FILE:LINE: " and the message, with the status; on a token the file cannot hold, that
 * token's fault at its own line instead (the directive read cannot be complete). */
__attribute__((format(printf, 3, 0))) static brume_status refuse(const lexer *L, brume_status code, const char *fmt,
                                                                  va_list ap)
{
    if (L->kind == TOK_BAD)
        return err_set(BRUME_ERROR_PARSE, "%s:%d: %s", L->file, L->tok_line, L->bad);
    char msg[600];
    vsnprintf(msg, sizeof msg, fmt, ap);
    return err_set(code, "%s:%d: %s", L->file, L->dir_line, msg);
}

/* A refusal of malformed input (BRUME_ERROR_PARSE). */
brume_status pbrt_fail(const lexer *L, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    brume_status st = refuse(L, BRUME_ERROR_PARSE, fmt, ap);
    va_end(ap);
    return st;
}

/* A refusal of what is well formed but brume cannot honour (a type, a parameter, a value):
 * BRUME_ERROR_UNSUPPORTED, which --lenient turns into a warning and a skipped directive. */
brume_status pbrt_unsupported(const lexer *L, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    brume_status st = refuse(L, BRUME_ERROR_UNSUPPORTED, fmt, ap);
    va_end(ap);
    return st;
}

brume_status pbrt_expected(const lexer *L, const char *fmt, ...)
{
    char msg[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (L->kind == TOK_END)
        return err_set(BRUME_ERROR_PARSE, "%s:%d: %s, found the end of the file (truncated?)", L->file, L->dir_line, msg);
    if (L->kind == TOK_OPEN || L->kind == TOK_CLOSE)
        return pbrt_fail(L, "%s, found \"%c\"", msg, L->kind == TOK_OPEN ? '[' : ']');
    return pbrt_fail(L, "%s, found \"%.64s\"", msg, L->text);
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

/* A decimal number as pbrt-v4 writes one: [+-] digits [. digits] [e [+-] digits], at least
 * one digit before the exponent; no hexadecimal, inf or nan (which strtod would take). */
static bool decimal(const char *s)
{
    size_t i = (s[0] == '+' || s[0] == '-') ? 1 : 0, digits = 0;
    for (; isdigit((unsigned char)s[i]); i++)
        digits++;
    if (s[i] == '.')
        for (i++; isdigit((unsigned char)s[i]); i++)
            digits++;
    if (digits == 0)
        return false;
    if (s[i] == 'e' || s[i] == 'E') {
        i += (s[i + 1] == '+' || s[i + 1] == '-') ? 2 : 1;
        if (!isdigit((unsigned char)s[i]))
            return false;
        while (isdigit((unsigned char)s[i]))
            i++;
    }
    return s[i] == '\0';
}

static bool number(const char *s, double *out)
{
    char *end;
    if (!decimal(s))
        return false;
    errno = 0;
    double v = num_strtod(s, &end);
    /* an underflow is the number it rounds to (0 or a subnormal); an overflow is refused */
    if (end == s || *end || !isfinite(v) || (errno && fabs(v) >= 1.0))
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
            return pbrt_expected(L, "%s: expected a number (%d of %d)", dir, i + 1, n);
        pbrt_next(L);
    }
    if (bracket) {
        if (L->kind != TOK_CLOSE)
            return pbrt_expected(L, "%s: expected ] after %d numbers", dir, n);
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

/* pbrt-v4's parameter types (parser.cpp, paramdict.cpp) */
static const char *const param_types[] = {"integer", "float", "point2", "vector2", "point3", "vector3", "normal3",
                                          "normal", "point", "vector", "bool", "string", "texture", "spectrum",
                                          "rgb", "blackbody", NULL};

/* The declaration "type name" of q from L->text: exactly two words, a type pbrt-v4 knows, and
 * a name not given before in the same list (pbrt-v4 would take the first silently). */
static brume_status declaration(lexer *L, params *ps, param *q)
{
    lexer at = *L; /* refused at the declaration's own line */
    at.dir_line = q->line;
    L = &at;
    char extra[2];
    int got = sscanf(L->text, "%15s %63s %1s", q->type, q->name, extra);
    size_t tl = strcspn(L->text + strspn(L->text, " \t"), " \t");
    if (got != 2 || tl >= sizeof q->type || strlen(q->name) + 1 >= sizeof q->name)
        return pbrt_fail(L, "parameter \"%.200s\": expected \"type name\" (a type of at most 15 letters, a name of "
                            "at most 62)", L->text);
    bool known = false;
    for (int i = 0; param_types[i]; i++)
        known |= strcmp(q->type, param_types[i]) == 0;
    if (!known)
        return pbrt_fail(L, "parameter \"%s %s\": unknown type \"%s\" (pbrt-v4's: integer, float, point2, vector2, "
                            "point3, vector3, normal3, bool, string, texture, spectrum, rgb, blackbody)",
                         q->type, q->name, q->type);
    for (param *o = ps->p; o < q; o++)
        if (strcmp(o->name, q->name) == 0 && o->line == q->line)
            return pbrt_fail(L, "parameter \"%s\" given twice in one parameter list", q->name);
        else if (strcmp(o->name, q->name) == 0)
            return pbrt_fail(L, "parameter \"%s\" given twice in one parameter list (lines %d and %d)", q->name,
                             o->line, q->line);
    return BRUME_OK;
}

/* One value of q (L on it) appended: a string, true/false, or a finite number (an integer for
 * an "integer" parameter); strings and numbers are not mixed. */
static brume_status param_value(lexer *L, params *ps, param *q)
{
    brume_status st;
    if ((st = grow(L, ps, q)))
        return st;
    if (L->kind == TOK_STRING) {
        if (q->n > 0 && !q->is_string)
            return pbrt_fail(L, "parameter \"%s\": mixes strings and numbers", q->name);
        size_t at = 0; /* after the strings before it, each ended by its NUL */
        for (int k = 0; k < q->n; k++)
            at += strlen(q->s + at) + 1;
        if (at + strlen(L->text) + 1 > sizeof q->s)
            return pbrt_fail(L, "parameter \"%s\": its strings are longer than %zu bytes in all", q->name,
                             sizeof q->s - 1);
        memcpy(q->s + at, L->text, strlen(L->text) + 1);
        q->is_string = true;
    } else if (L->kind == TOK_WORD && q->is_string) {
        return pbrt_fail(L, "parameter \"%s\": mixes strings and numbers", q->name);
    } else if (L->kind == TOK_WORD && (strcmp(L->text, "true") == 0 || strcmp(L->text, "false") == 0)) {
        if (strcmp(q->type, "bool") != 0)
            return pbrt_fail(L, "parameter \"%s %s\": %s is not a number", q->type, q->name, L->text);
        q->v[q->n] = strcmp(L->text, "true") == 0;
    } else if (L->kind == TOK_WORD) {
        if (!number(L->text, &q->v[q->n]))
            return pbrt_expected(L, "parameter \"%s\": expected a number", q->name);
        if (strcmp(q->type, "integer") == 0 && !(fabs(q->v[q->n]) <= 2147483647.0 && q->v[q->n] == floor(q->v[q->n])))
            return pbrt_fail(L, "parameter \"integer %s\": %s is not an integer", q->name, L->text);
    } else {
        return pbrt_expected(L, "parameter \"%s\": expected a value", q->name);
    }
    q->n++;
    pbrt_next(L);
    return BRUME_OK;
}

/* Reads "type name" value pairs after a directive; L is on the first token after the
 * directive's own arguments and is left on the next directive. */
static brume_status read_params(lexer *L, params *ps);

brume_status pbrt_read_params(lexer *L, params *ps)
{
    pbrt_params_clear(ps);
    if (L->kind == TOK_END && L->outer && L->outer->kind == TOK_STRING)
        resume_outer(L);
    L->in_params = true;
    brume_status st = read_params(L, ps);
    L->in_params = false;
    return st;
}

static brume_status read_params(lexer *L, params *ps)
{
    brume_status st;
    while (L->kind == TOK_STRING) {
        if (ps->n == PBRT_MAX_PARAMS)
            return pbrt_fail(L, "more than %d parameters", PBRT_MAX_PARAMS);
        param *q = &ps->p[ps->n++];
        memset(q, 0, sizeof *q);
        q->line = L->tok_line;
        if ((st = declaration(L, ps, q)))
            return st;
        pbrt_next(L);
        bool bracket = L->kind == TOK_OPEN;
        if (bracket)
            pbrt_next(L);
        do {
            if ((st = param_value(L, ps, q)))
                return st;
        } while (bracket && L->kind != TOK_CLOSE && L->kind != TOK_END && L->kind != TOK_BAD);
        if (bracket) {
            if (L->kind != TOK_CLOSE)
                return pbrt_expected(L, "parameter \"%s\": expected ]", q->name);
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
                return pbrt_unsupported(L, "parameter \"%s\": a spectrum that varies with wavelength (brume renders RGB)", name);
        out[0] = out[1] = out[2] = v;
        return BRUME_OK;
    }
    if (strcmp(q->type, "float") == 0 && !q->is_string && q->n == 1) {
        out[0] = out[1] = out[2] = q->v[0];
        return BRUME_OK;
    }
    return pbrt_unsupported(L, "parameter \"%s\": brume reads rgb values and constant spectra only", name);
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

/* Every parameter must have been read: the first that was not is refused; with --lenient
 * each is listed as ignored instead, and the directive goes on as if it were absent. */
brume_status pbrt_all_used(const lexer *L, const params *ps, const char *dir)
{
    for (int i = 0; i < ps->n; i++)
        if (!ps->p[i].used) {
            lexer at = *L;
            at.dir_line = ps->p[i].line;
            brume_status st = pbrt_unsupported(&at, "%s: parameter \"%s %s\": not supported by brume", dir, ps->p[i].type,
                                               ps->p[i].name);
            if (!ps->ignored || st != BRUME_ERROR_UNSUPPORTED || (st = pbrt_ignore(ps->ignored, L->file)))
                return st;
        }
    return BRUME_OK;
}

brume_status pbrt_ignore(cJSON *ignored, const char *path)
{
    const char *msg = err_message();
    for (const cJSON *i = ignored->child; i; i = i->next)
        if (strcmp(i->valuestring, msg) == 0) {
            err_clear();
            return BRUME_OK;
        }
    if (cJSON_GetArraySize(ignored) >= PBRT_MAX_IGNORED)
        return err_prefix("more than %d constructs ignored (--lenient)", PBRT_MAX_IGNORED);
    cJSON *item = cJSON_CreateString(msg);
    if (!item || !cJSON_AddItemToArray(ignored, item)) {
        cJSON_Delete(item);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    err_clear();
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
