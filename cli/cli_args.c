/* args.c - strict number parsing for command-line flags. */
#include "args.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "commands.h"

void args_split_equals(int *argc, char ***argv)
{
    static char **split; /* lives as long as the process: argv's strings are reused */
    int n = *argc, extra = 0;
    for (int i = 0; i < n; i++) {
        const char *a = (*argv)[i];
        if (strcmp(a, "--") == 0)
            break;
        if (a[0] == '-' && a[1] == '-' && a[2] != '=' && strchr(a, '='))
            extra++;
    }
    if (extra == 0)
        return;
    char **out = malloc(((size_t)n + (size_t)extra + 1) * sizeof *out);
    char *names = malloc((size_t)extra * 256);
    if (!out || !names) {
        free(out);
        free(names);
        return; /* the flags are then refused as unknown, which is the message they deserve */
    }
    int k = 0, e = 0;
    bool done = false;
    for (int i = 0; i < n; i++) {
        char *a = (*argv)[i];
        char *eq = done ? NULL : strchr(a, '=');
        if (!done && strcmp(a, "--") == 0)
            done = true;
        if (eq && a[0] == '-' && a[1] == '-' && a[2] != '=' && (size_t)(eq - a) < 256) {
            char *name = names + 256 * e++;
            memcpy(name, a, (size_t)(eq - a));
            name[eq - a] = '\0';
            out[k++] = name;
            out[k++] = eq + 1;
        } else {
            out[k++] = a;
        }
    }
    out[k] = NULL;
    free(split);
    split = out;
    *argc = k;
    *argv = out;
}

bool arg_parse_long(const char *text, long lo, long hi, long *out)
{
    /* digits only after an optional minus sign: no spaces, no plus, no hex; overflow checked */
    const char *p = text;
    if (*p == '-')
        p++;
    if (*p < '0' || *p > '9')
        return false;
    for (const char *q = p; *q; q++)
        if (*q < '0' || *q > '9')
            return false;
    char *end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno == ERANGE || *end || v < lo || v > hi)
        return false;
    *out = v;
    return true;
}

bool arg_int(const char *flag, const char *text, long lo, long hi, int *out)
{
    long v = 0;
    if (!arg_parse_long(text, lo, hi, &v)) {
        cli_error("%s: expected an integer in [%ld, %ld], got '%s'", flag, lo, hi, text);
        return false;
    }
    *out = (int)v;
    return true;
}

bool arg_u64(const char *flag, const char *text, uint64_t *out)
{
    char *end = NULL;
    errno = 0;
    bool digits = text[0] >= '0' && text[0] <= '9'; /* strtoull would take " -1" as 2^64 - 1 */
    for (const char *q = text; digits && *q; q++)
        digits = *q >= '0' && *q <= '9';
    unsigned long long v = digits ? strtoull(text, &end, 10) : 0;
    if (!digits || errno == ERANGE) {
        cli_error("%s: expected an integer in [0, 18446744073709551615], got '%s'", flag, text);
        return false;
    }
    *out = (uint64_t)v;
    return true;
}

/* A decimal number as written by hand ("2", "-0.5", ".5", "1e3"): strtod alone would also take
 * " 4", "+4" and "0x10". */
static bool decimal_text(const char *text)
{
    if (!((text[0] >= '0' && text[0] <= '9') || text[0] == '-' || text[0] == '.'))
        return false;
    for (const char *q = text; *q; q++) {
        bool sign_after_e = (*q == '+' || *q == '-') && q > text && (q[-1] == 'e' || q[-1] == 'E');
        if (!((*q >= '0' && *q <= '9') || *q == '.' || *q == 'e' || *q == 'E' || sign_after_e || (*q == '-' && q == text)))
            return false;
    }
    return true;
}

bool arg_double(const char *flag, const char *text, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = decimal_text(text) ? strtod(text, &end) : 0.0;
    if (!end || errno || end == text || *end || !isfinite(v) || v < lo || v > hi) {
        cli_error("%s: expected a number in [%g, %g], got '%s'", flag, lo, hi, text);
        return false;
    }
    *out = v;
    return true;
}

const char *arg_value(int argc, char **argv, int *i)
{
    if (*i + 1 >= argc) {
        cli_error("%s: missing value", argv[*i]);
        return NULL;
    }
    return argv[++*i];
}
