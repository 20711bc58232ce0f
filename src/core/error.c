/* error.c - thread-local last error, status strings, and the context's error hand-off.
 *
 * Every message is formatted by err_vformat, the one place where text from input (a key,
 * a file name, a value quoted from a file) enters a message: each string argument (%s) has
 * its control characters escaped (newline as \n, tab as \t, escape as \x1b, ...) and is
 * cut after ERR_ARG_MAX bytes, so that a message is always one line and a hostile key
 * cannot write to the terminal. */
#include "core/error.h"

#include <math.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "core/number.h"

static _Thread_local char err_buf[1024];
static _Thread_local brume_status err_code = BRUME_OK;

/* Appends s to out[*k], escaping control bytes and cutting after ERR_ARG_MAX input bytes,
 * or after prec bytes when a precision was given (then without the "..."). */
static void put_escaped(char *out, size_t n, size_t *k, const char *s, int prec)
{
    size_t len = s ? strnlen(s, prec >= 0 ? (size_t)prec : SIZE_MAX) : 6;
    if (!s)
        s = "(null)";
    size_t max = prec >= 0 ? (size_t)prec : ERR_ARG_MAX;
    bool cut = prec < 0 && len > max;
    if (cut) {
        len = max;
        while (len > 0 && ((unsigned char)s[len] & 0xC0) == 0x80) /* not inside a UTF-8 sequence */
            len--;
    }
    for (size_t i = 0; i < len && *k + 1 < n; i++) {
        unsigned char c = (unsigned char)s[i];
        char esc[8];
        const char *e = NULL;
        if (c == '\n')
            e = "\\n";
        else if (c == '\r')
            e = "\\r";
        else if (c == '\t')
            e = "\\t";
        else if (c < 0x20 || c == 0x7f) {
            snprintf(esc, sizeof esc, "\\x%02x", c);
            e = esc;
        }
        if (!e) {
            out[(*k)++] = (char)c;
            continue;
        }
        for (; *e && *k + 1 < n; e++)
            out[(*k)++] = *e;
    }
    if (cut)
        for (const char *e = "..."; *e && *k + 1 < n; e++)
            out[(*k)++] = *e;
    out[*k] = '\0';
}

/* One conversion of a format: %[flags][width][.precision][length]conv. */
typedef struct fmt_spec {
    char spec[32]; /* the conversion as snprintf takes it, length included */
    char len[3];   /* "", "l", "ll", "z", ... */
    char conv;     /* 'd', 's', ...; '\0' when the format ends inside the conversion */
    int star_w, star_p; /* width, precision given as arguments */
    int prec;           /* the written precision, -1 when none */
    const char *next;   /* the format after the conversion */
} fmt_spec;

static void fmt_parse(const char *p, fmt_spec *f)
{
    size_t s = 0;
    const char *q = p + 1;
    f->spec[s++] = '%';
    f->star_w = f->star_p = 0;
    f->prec = -1;
    while (*q && strchr("-+ #0", *q) && s < 8)
        f->spec[s++] = *q++;
    if (*q == '*') {
        f->star_w = 1;
        f->spec[s++] = *q++;
    } else {
        while (*q >= '0' && *q <= '9' && s < 16)
            f->spec[s++] = *q++;
    }
    if (*q == '.') {
        f->spec[s++] = *q++;
        if (*q == '*') {
            f->star_p = 1;
            f->spec[s++] = *q++;
        } else {
            f->prec = 0;
            while (*q >= '0' && *q <= '9' && s < 24) {
                f->prec = 10 * f->prec + (*q - '0');
                f->spec[s++] = *q++;
            }
        }
    }
    size_t ln = 0;
    while (*q && strchr("hlLzjt", *q) && ln < 2)
        f->len[ln++] = *q++;
    f->len[ln] = '\0';
    f->conv = *q;
    /* the length goes into the spec too: "%d" given a long long would print its low half */
    for (size_t i = 0; i < ln; i++)
        f->spec[s++] = f->len[i];
    f->spec[s++] = f->conv;
    f->spec[s] = '\0';
    f->next = *q ? q + 1 : q;
}

/* v in the fewest significant digits (at most 17) that read back as v: a limit or a value
 * quoted exactly, an integer below 1e9 as an integer ("16777217", not "1.67772e+07"). */
static void fmt_exact(double v, char *tmp, size_t ntmp)
{
    if (v == floor(v) && fabs(v) < 1e9) { /* 1000000, not 1e+06 */
        snprintf(tmp, ntmp, "%.0f", v);
        return;
    }
    for (int p = 6; p <= 17; p++) {
        snprintf(tmp, ntmp, "%.*g", p, v);
        if (!isfinite(v) || num_strtod(tmp, NULL) == v)
            return;
    }
}

/* A numeric (or %p, %%) conversion of f into tmp, its arguments taken from *ap. A plain
 * "%.17g" prints the shortest exact form (fmt_exact). */
static void fmt_number(const fmt_spec *f, int w, int pr, va_list *ap, char *tmp, size_t ntmp)
{
    const char *spec = f->spec, *len = f->len;
    int have_w = f->star_w, have_p = f->star_p;
    tmp[0] = '\0';
#define EMIT(v)                                                                                 \
    do {                                                                                        \
        if (have_w && have_p)                                                                   \
            snprintf(tmp, ntmp, spec, w, pr, v);                                                \
        else if (have_w)                                                                        \
            snprintf(tmp, ntmp, spec, w, v);                                                    \
        else if (have_p)                                                                        \
            snprintf(tmp, ntmp, spec, pr, v);                                                   \
        else                                                                                    \
            snprintf(tmp, ntmp, spec, v);                                                       \
    } while (0)
#if defined(__GNUC__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wformat-nonliteral"
#endif
    switch (f->conv) {
    case '%': snprintf(tmp, ntmp, "%%"); break;
    case 'd':
    case 'i':
        if (!strcmp(len, "l")) EMIT(va_arg(*ap, long));
        else if (!strcmp(len, "ll")) EMIT(va_arg(*ap, long long));
        else if (!strcmp(len, "z")) EMIT(va_arg(*ap, ptrdiff_t));
        else if (!strcmp(len, "j")) EMIT(va_arg(*ap, intmax_t));
        else if (!strcmp(len, "t")) EMIT(va_arg(*ap, ptrdiff_t));
        else EMIT(va_arg(*ap, int));
        break;
    case 'u':
    case 'x':
    case 'X':
    case 'o':
        if (!strcmp(len, "l")) EMIT(va_arg(*ap, unsigned long));
        else if (!strcmp(len, "ll")) EMIT(va_arg(*ap, unsigned long long));
        else if (!strcmp(len, "z")) EMIT(va_arg(*ap, size_t));
        else if (!strcmp(len, "j")) EMIT(va_arg(*ap, uintmax_t));
        else if (!strcmp(len, "t")) EMIT(va_arg(*ap, size_t));
        else EMIT(va_arg(*ap, unsigned));
        break;
    case 'f':
    case 'F':
    case 'e':
    case 'E':
    case 'g':
        if (f->prec == 17 && !have_w && !have_p && !strcmp(spec, "%.17g")) {
            fmt_exact(va_arg(*ap, double), tmp, ntmp);
            break;
        }
        /* fall through */
    case 'G':
    case 'a':
    case 'A':
        if (!strcmp(len, "L")) EMIT(va_arg(*ap, long double));
        else EMIT(va_arg(*ap, double));
        break;
    case 'p': EMIT(va_arg(*ap, void *)); break;
    default: snprintf(tmp, ntmp, "?"); break; /* not a conversion brume uses */
    }
#if defined(__GNUC__)
#pragma GCC diagnostic pop
#endif
#undef EMIT
}

void err_vformat(char *out, size_t n, const char *fmt, va_list ap_in)
{
    if (n == 0)
        return;
    va_list ap;
    va_copy(ap, ap_in);
    locale_t old = num_c_begin(); /* "0.5" in every locale */
    size_t k = 0;
    out[0] = '\0';
    for (const char *p = fmt; *p && k + 1 < n;) {
        if (*p != '%') {
            unsigned char c = (unsigned char)*p++;
            out[k++] = c < 0x20 || c == 0x7f ? ' ' : (char)c;
            out[k] = '\0';
            continue;
        }
        fmt_spec f;
        fmt_parse(p, &f);
        if (!f.conv)
            break;
        p = f.next;
        int w = f.star_w ? va_arg(ap, int) : 0;
        int pr = f.star_p ? va_arg(ap, int) : 0;
        int prec = f.star_p ? pr : f.prec;
        if (f.conv == 'c') {
            char one[2] = {(char)va_arg(ap, int), '\0'};
            put_escaped(out, n, &k, one, -1);
            continue;
        }
        if (f.conv == 's') {
            put_escaped(out, n, &k, va_arg(ap, const char *), prec);
            continue;
        }
        char tmp[512];
        fmt_number(&f, w, pr, &ap, tmp, sizeof tmp);
        for (const char *t = tmp; *t && k + 1 < n; t++)
            out[k++] = *t;
        out[k] = '\0';
    }
    out[k] = '\0';
    num_c_end(old);
    va_end(ap);
}

void err_format(char *out, size_t n, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    err_vformat(out, n, fmt, ap);
    va_end(ap);
}

brume_status err_vset(brume_status status, const char *fmt, va_list ap)
{
    err_vformat(err_buf, sizeof err_buf, fmt, ap);
    err_code = status;
    return status;
}

brume_status err_set(brume_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    err_vset(status, fmt, ap);
    va_end(ap);
    return status;
}

const char *err_message(void) { return err_buf; }

brume_status err_prefix(const char *fmt, ...)
{
    char old[sizeof err_buf], head[512];
    snprintf(old, sizeof old, "%s", err_buf);
    va_list ap;
    va_start(ap, fmt);
    err_vformat(head, sizeof head, fmt, ap);
    va_end(ap);
    size_t hl = strlen(head), ol = strlen(old), cap = sizeof err_buf - 1;
    if (hl > cap - 2)
        hl = cap - 2;
    memcpy(err_buf, head, hl);
    memcpy(err_buf + hl, ": ", 2);
    if (ol > cap - hl - 2)
        ol = cap - hl - 2;
    memcpy(err_buf + hl + 2, old, ol);
    err_buf[hl + 2 + ol] = '\0';
    return err_code;
}
brume_status err_status(void) { return err_code; }
void err_clear(void)
{
    err_buf[0] = '\0';
    err_code = BRUME_OK;
}

const char *brume_status_string(brume_status s)
{
    switch (s) {
    case BRUME_OK: return "ok";
    case BRUME_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case BRUME_ERROR_IO: return "input/output error";
    case BRUME_ERROR_PARSE: return "malformed input";
    case BRUME_ERROR_OUT_OF_MEMORY: return "out of memory";
    case BRUME_ERROR_UNSUPPORTED: return "unsupported";
    case BRUME_ERROR_RANGE: return "value out of range";
    case BRUME_ERROR_STATE: return "object used in the wrong state";
    case BRUME_ERROR_CANCELLED: return "cancelled";
    }
    return "unknown status";
}
