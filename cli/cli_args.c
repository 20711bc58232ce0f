/* args.c - strict number parsing for command-line flags. */
#include "args.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>

#include "commands.h"

bool arg_int(const char *flag, const char *text, long lo, long hi, int *out)
{
    char *end = NULL;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (errno || end == text || *end || v < lo || v > hi) {
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
    unsigned long long v = strtoull(text, &end, 10);
    if (errno || end == text || *end || text[0] == '-') {
        cli_error("%s: expected a non-negative integer, got '%s'", flag, text);
        return false;
    }
    *out = (uint64_t)v;
    return true;
}

bool arg_double(const char *flag, const char *text, double lo, double hi, double *out)
{
    char *end = NULL;
    errno = 0;
    double v = strtod(text, &end);
    if (errno || end == text || *end || !isfinite(v) || v < lo || v > hi) {
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
