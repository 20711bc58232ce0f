/* grid_sequence.c - frame sequences of grid files (io/grid_sequence.h, docs/grids.md
 * "Sequences"): the frame patterns, the range found in the folder, a frame's file. */
#define _XOPEN_SOURCE 700
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/context.h"
#include "core/error.h"
#include "io/grid_sequence.h"

/* One pattern split: prefix, zero-padding width, suffix (byte offsets into the name). */
typedef struct seq_parts {
    size_t at, len; /* the pattern's place and length in the full name */
    int width;      /* 0: no padding */
} seq_parts;

/* Finds patterns in the base name: %d, %0Nd, a run of '#' (width = its length), $F and $FN
 * (Houdini's: $F4 is frame padded to 4). Returns their count; *p receives the last. */
static int find(const char *name, seq_parts *p, bool *bad)
{
    const char *slash = strrchr(name, '/');
    size_t start = slash ? (size_t)(slash - name) + 1 : 0;
    int n = 0;
    *bad = false;
    for (size_t i = start; name[i]; i++) {
        if (name[i] == '%') {
            size_t j = i + 1;
            int w = 0;
            if (name[j] == '%') { /* a literal percent */
                i = j;
                continue;
            }
            bool zero = name[j] == '0';
            while (isdigit((unsigned char)name[j]))
                w = w * 10 + (name[j++] - '0');
            if (name[j] != 'd' || (w > 0 && !zero) || w > 18) {
                *bad = true;
                return n;
            }
            *p = (seq_parts){i, j + 1 - i, w};
            n++;
            i = j;
        } else if (name[i] == '#') {
            size_t j = i;
            while (name[j] == '#')
                j++;
            *p = (seq_parts){i, j - i, (int)(j - i) > 1 ? (int)(j - i) : 0};
            n++;
            i = j - 1;
        } else if (name[i] == '$' && name[i + 1] == 'F') {
            size_t j = i + 2;
            int w = 0;
            while (isdigit((unsigned char)name[j]) && w < 100)
                w = w * 10 + (name[j++] - '0');
            if (w > 18) {
                *bad = true;
                return n;
            }
            *p = (seq_parts){i, j - i, w};
            n++;
            i = j - 1;
        }
    }
    return n;
}

int seq_is_pattern(const char *name)
{
    seq_parts p;
    bool bad;
    int n = find(name, &p, &bad);
    if (bad || n > 1) {
        err_set(BRUME_ERROR_PARSE, "%s: %s frame pattern (one of %%04d, ####, $F4 in the file name)", name,
                bad ? "a malformed" : "more than one");
        return -1;
    }
    return n;
}

void seq_name(const char *pattern, long n, char *out, size_t cap)
{
    seq_parts p;
    bool bad;
    find(pattern, &p, &bad);
    snprintf(out, cap, "%.*s%0*ld%s", (int)p.at, pattern, p.width, n, pattern + p.at + p.len);
}

static bool exists(const char *path)
{
    struct stat sb;
    return stat(path, &sb) == 0 && S_ISREG(sb.st_mode);
}

brume_status seq_range(const char *pattern, long *first, long *last)
{
    seq_parts p;
    bool bad;
    find(pattern, &p, &bad);
    const char *slash = strrchr(pattern, '/');
    size_t start = slash ? (size_t)(slash - pattern) + 1 : 0;
    char dir[4096];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - pattern) : 1, slash ? pattern : ".");
    if (slash == pattern)
        snprintf(dir, sizeof dir, "/");
    const char *pre = pattern + start, *suf = pattern + p.at + p.len;
    size_t npre = p.at - start, nsuf = strlen(suf);
    DIR *d = opendir(dir);
    if (!d)
        return err_set(BRUME_ERROR_IO, "%s: cannot list its folder %s: %s", pattern, dir, strerror(errno));
    long lo = 0, hi = -1, count = 0;
    struct dirent *e;
    while ((e = readdir(d))) {
        const char *nm = e->d_name;
        size_t len = strlen(nm);
        if (len <= npre + nsuf || strncmp(nm, pre, npre) != 0 || strcmp(nm + len - nsuf, suf) != 0)
            continue;
        size_t nd = len - npre - nsuf;
        const char *digits = nm + npre;
        bool ok = nd <= 18;
        for (size_t k = 0; ok && k < nd; k++)
            ok = isdigit((unsigned char)digits[k]);
        /* the number as the pattern writes it: padded to the width, no other leading zero */
        if (!ok || (nd < (size_t)p.width) || (nd > (size_t)(p.width > 0 ? p.width : 1) && digits[0] == '0'))
            continue;
        long v = strtol(digits, NULL, 10);
        lo = count ? (v < lo ? v : lo) : v;
        hi = count ? (v > hi ? v : hi) : v;
        count++;
    }
    closedir(d);
    if (count == 0)
        return err_set(BRUME_ERROR_IO, "%s: no file of the sequence in %s", pattern, dir);
    if (count != hi - lo + 1) {
        char name[4096];
        for (long n = lo; n <= hi; n++) {
            seq_name(pattern, n, name, sizeof name);
            if (!exists(name))
                return err_set(BRUME_ERROR_IO, "%s: frame file %ld missing (%s) in the sequence's files %ld to %ld",
                               pattern, n, name, lo, hi);
        }
    }
    *first = lo;
    *last = hi;
    return BRUME_OK;
}

bool seq_beyond_from_name(const char *s, seq_beyond *out)
{
    static const char *const names[] = {"refuse", "hold", "loop"};
    for (int k = 0; k < 3; k++)
        if (strcmp(s, names[k]) == 0) {
            *out = (seq_beyond)k;
            return true;
        }
    return false;
}

brume_status seq_file(const char *pattern, const seq_options *o, long frame_no, char *out, size_t cap)
{
    long first, last;
    if (seq_range(pattern, &first, &last) != BRUME_OK)
        return err_status();
    long n = o->offset + o->step * frame_no;
    if (n < first || n > last) {
        if (o->beyond == SEQ_REFUSE)
            return err_set(BRUME_ERROR_RANGE,
                           "%s: frame %ld wants file %ld, outside the files %ld to %ld (frame_offset, frame_step; "
                           "\"beyond\": \"hold\" or \"loop\" to reuse them)", pattern, frame_no, n, first, last);
        long len = last - first + 1;
        n = o->beyond == SEQ_HOLD ? (n < first ? first : last) : first + (((n - first) % len) + len) % len;
    }
    seq_name(pattern, n, out, cap);
    return BRUME_OK;
}

brume_status brume_sequence_pattern(brume_context *ctx, const char *name, bool *is_pattern)
{
    err_clear();
    if (is_pattern)
        *is_pattern = false;
    if (!name || !is_pattern)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_sequence_pattern: %s: NULL",
                                       !name ? "name" : "is_pattern"));
    int k = seq_is_pattern(name);
    *is_pattern = k == 1;
    if (k < 0) { /* a name the caller gave: an argument, whatever the reader called it */
        char msg[1024];
        snprintf(msg, sizeof msg, "%s", err_message());
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s", msg));
    }
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_sequence_name(brume_context *ctx, const char *pattern, long n, char *out, size_t cap)
{
    err_clear();
    if (!pattern || !out || cap == 0)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_sequence_name: %s",
                                       !pattern ? "pattern: NULL" : !out ? "out: NULL" : "cap: 0"));
    out[0] = '\0';
    int k = seq_is_pattern(pattern);
    if (k != 1)
        return ctx_report(ctx, k < 0 ? err_status()
                                     : err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no frame pattern in the name", pattern));
    char buf[8192];
    seq_name(pattern, n, buf, sizeof buf);
    if (strlen(buf) >= cap) {
        out[0] = '\0';
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: frame %ld: the name needs %zu bytes, %zu given",
                                       pattern, n, strlen(buf) + 1, cap));
    }
    memcpy(out, buf, strlen(buf) + 1);
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_sequence_range(brume_context *ctx, const char *pattern, long *first, long *last)
{
    err_clear();
    if (!pattern || !first || !last)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_sequence_range: %s: NULL",
                                       !pattern ? "pattern" : !first ? "first" : "last"));
    *first = *last = 0;
    if (seq_is_pattern(pattern) != 1)
        return ctx_report(ctx, err_status() != BRUME_OK ? err_status()
                                    : err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no frame pattern in the name", pattern));
    return ctx_report(ctx, seq_range(pattern, first, last));
}
