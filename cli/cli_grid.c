/* cli_grid.c - flags shared by the grid subcommands (see cli_grid.h). */
#include "cli_grid.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"

bool cli_parse_dims(const char *s, int n[3])
{
    long v[3];
    char *end;
    for (int a = 0; a < 3; a++) {
        errno = 0;
        v[a] = strtol(s, &end, 10);
        if (errno || end == s || v[a] < 1 || v[a] > INT32_MAX)
            return false;
        if (a == 0 && *end == '\0') { /* one number: a cube */
            n[0] = n[1] = n[2] = (int)v[0];
            return true;
        }
        if (a < 2 && *end != 'x' && *end != 'X')
            return false;
        s = end + 1;
    }
    if (*end != '\0')
        return false;
    for (int a = 0; a < 3; a++)
        n[a] = (int)v[a];
    return true;
}

bool cli_parse_doubles(const char *s, double *out, int count)
{
    char *end = NULL;
    if (count < 1)
        return false;
    for (int i = 0; i < count; i++) {
        out[i] = strtod(s, &end);
        if (end == s || !isfinite(out[i]))
            return false;
        if (i < count - 1 && *end != ',')
            return false;
        s = end + 1;
    }
    return *end == '\0';
}

bool cli_parse_bytes(const char *s, size_t *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (errno || end == s || !(v > 0.0))
        return false;
    double mul = 1.0;
    switch (*end) {
    case 'k': case 'K': mul = 1024.0; end++; break;
    case 'm': case 'M': mul = 1024.0 * 1024.0; end++; break;
    case 'g': case 'G': mul = 1024.0 * 1024.0 * 1024.0; end++; break;
    case 't': case 'T': mul = 1024.0 * 1024.0 * 1024.0 * 1024.0; end++; break;
    default: break;
    }
    if (*end == 'B' || *end == 'b')
        end++;
    if (*end != '\0' || v * mul >= (double)SIZE_MAX)
        return false;
    *out = (size_t)(v * mul);
    return true;
}

/* The grid loading flags' values into the brume_grid_file_options that begins the command's
 * options (cli_grid.h); each false after the message. */
static bool bad_value(const cli_flag *f, const char *v)
{
    cli_error("%s: bad value '%s'", f->name, v);
    return false;
}

bool cli_grid_format(void *opts, const cli_flag *f, const char *v)
{
    brume_grid_file_options *o = opts;
    o->format = BRUME_GRID_FORMAT_AUTO;
    return brume_grid_format_from_name(v, &o->format) || bad_value(f, v);
}

bool cli_grid_dims(void *opts, const cli_flag *f, const char *v)
{
    return cli_parse_dims(v, ((brume_grid_file_options *)opts)->dims) || bad_value(f, v);
}

bool cli_grid_bounds(void *opts, const cli_flag *f, const char *v)
{
    brume_grid_file_options *o = opts;
    double *b = o->bounds;
    o->has_bounds = cli_parse_doubles(v, b, 6) && b[3] > b[0] && b[4] > b[1] && b[5] > b[2];
    return o->has_bounds || bad_value(f, v);
}

bool cli_grid_transform(void *opts, const cli_flag *f, const char *v)
{
    brume_grid_file_options *o = opts;
    o->has_transform = cli_parse_doubles(v, o->transform, 12);
    return o->has_transform || bad_value(f, v);
}

bool cli_grid_filter(void *opts, const cli_flag *f, const char *v)
{
    brume_grid_file_options *o = opts;
    bool nearest = strcmp(v, "nearest") == 0;
    o->filter = nearest ? BRUME_GRID_NEAREST : BRUME_GRID_TRILINEAR;
    return nearest || strcmp(v, "trilinear") == 0 || bad_value(f, v);
}

bool cli_grid_scale(void *opts, const cli_flag *f, const char *v)
{
    brume_grid_file_options *o = opts;
    return (cli_parse_doubles(v, &o->scale, 1) && o->scale > 0.0) || bad_value(f, v);
}

bool cli_grid_name(void *opts, const cli_flag *f, const char *v)
{
    brume_grid_file_options *o = opts;
    snprintf(o->grid, sizeof o->grid, "%s", v);
    return (v[0] != '\0' && strlen(v) < sizeof o->grid) || bad_value(f, v);
}

bool cli_grid_max_memory(void *opts, const cli_flag *f, const char *v)
{
    size_t bytes = 0;
    bool ok = cli_parse_bytes(v, &bytes);
    /* exact below 2^53 bytes: the reader multiplies back */
    ((brume_grid_file_options *)opts)->max_memory_mb = (double)bytes / 1048576.0;
    return ok || bad_value(f, v);
}
