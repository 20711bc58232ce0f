/* cli_grid.c - flags shared by the grid subcommands (see cli_grid.h). */
#include "cli_grid.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>

#include "commands.h"
#include "tool/tool.h"

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

int cli_load_flag(const char *cmd, int argc, char **argv, int *i, brume_grid_file_options *o)
{
    const char *f = argv[*i];
    static const char *const with_value[] = {"--format", "--dims", "--bounds", "--transform",
                                             "--filter", "--scale", "--max-memory", "--grid"};
    int known = 0;
    for (size_t k = 0; k < sizeof with_value / sizeof *with_value; k++)
        known |= strcmp(f, with_value[k]) == 0;
    if (!known)
        return 0;
    if (*i + 1 >= argc) {
        cli_error("%s: %s needs a value", cmd, f);
        return -1;
    }
    const char *v = argv[++*i];
    bool ok = true;
    if (strcmp(f, "--format") == 0) {
        ok = tool_grid_format_known(v);
        o->format = tool_grid_format_parse(ok ? v : NULL);
    } else if (strcmp(f, "--dims") == 0) {
        ok = cli_parse_dims(v, o->dims);
    } else if (strcmp(f, "--bounds") == 0) {
        ok = cli_parse_doubles(v, o->bounds, 6) && o->bounds[3] > o->bounds[0] && o->bounds[4] > o->bounds[1] &&
             o->bounds[5] > o->bounds[2];
        o->has_bounds = ok;
    } else if (strcmp(f, "--transform") == 0) {
        ok = cli_parse_doubles(v, o->transform, 12);
        o->has_transform = ok;
    } else if (strcmp(f, "--filter") == 0) {
        ok = strcmp(v, "nearest") == 0 || strcmp(v, "trilinear") == 0;
        o->filter = strcmp(v, "nearest") == 0 ? BRUME_GRID_NEAREST : BRUME_GRID_TRILINEAR;
    } else if (strcmp(f, "--scale") == 0) {
        ok = cli_parse_doubles(v, &o->scale, 1) && o->scale > 0.0;
    } else if (strcmp(f, "--grid") == 0) {
        ok = v[0] != '\0' && strlen(v) < sizeof o->grid;
        snprintf(o->grid, sizeof o->grid, "%s", v);
    } else {
        size_t bytes = 0;
        ok = cli_parse_bytes(v, &bytes);
        o->max_memory_mb = (double)bytes / 1048576.0; /* exact below 2^53 bytes: the reader multiplies back */
    }
    if (!ok) {
        cli_error("%s: bad value for %s: %s", cmd, f, v);
        return -1;
    }
    return 1;
}
