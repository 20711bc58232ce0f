/* regular_file.c - inputs and outputs are regular files (regular_file.h). */
#define _XOPEN_SOURCE 700 /* realpath */
#include "core/regular_file.h"

#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/error.h"

static _Thread_local io_inputs *g_rec; /* the list this thread fills, or NULL */

void io_inputs_record(io_inputs *rec) { g_rec = rec; }

static void note_stat(const char *path, const struct stat *sb)
{
    io_inputs *r = g_rec;
    if (!r || !S_ISREG(sb->st_mode))
        return;
    for (size_t i = 0; i < r->n; i++)
        if (r->v[i].dev == sb->st_dev && r->v[i].ino == sb->st_ino)
            return;
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 8;
        io_input *nv = realloc(r->v, cap * sizeof *nv);
        if (!nv) {
            r->oom = true;
            return;
        }
        r->v = nv;
        r->cap = cap;
    }
    char *copy = strdup(path);
    if (!copy) {
        r->oom = true;
        return;
    }
    r->v[r->n++] = (io_input){copy, sb->st_dev, sb->st_ino};
}

void io_input_note(const char *path)
{
    struct stat sb;
    if (g_rec && path && stat(path, &sb) == 0)
        note_stat(path, &sb);
}

void io_inputs_free(io_inputs *rec)
{
    if (!rec)
        return;
    for (size_t i = 0; i < rec->n; i++)
        free(rec->v[i].path);
    free(rec->v);
    memset(rec, 0, sizeof *rec);
}

static uint64_t fold(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ULL;
    }
    return h;
}

uint64_t io_inputs_hash(const io_inputs *rec, uint64_t h)
{
    if (!rec)
        return h;
    unsigned char buf[65536];
    for (size_t i = 0; i < rec->n; i++) {
        h = fold(h, rec->v[i].path, strlen(rec->v[i].path) + 1);
        FILE *fp = NULL;
        int e = 0;
        g_rec = NULL; /* hashing is not reading the scene */
        if (io_open_regular(rec->v[i].path, &fp) != BRUME_OK)
            e = errno ? errno : EIO;
        size_t got;
        while (fp && (got = fread(buf, 1, sizeof buf, fp)) > 0)
            h = fold(h, buf, got);
        if (fp && ferror(fp))
            e = EIO;
        if (fp)
            fclose(fp);
        h = fold(h, &e, sizeof e);
    }
    err_clear();
    return h;
}

/* What the first bytes of a file say it holds. */
typedef enum held { HELD_OTHER, HELD_TEXT, HELD_CHECKPOINT, HELD_LIGHT, HELD_IMAGE, HELD_GRID } held;

static held sniff(const unsigned char *b, size_t n)
{
    if (n >= 8 && memcmp(b, "BRUMECKP", 8) == 0)
        return HELD_CHECKPOINT;
    if (n >= 7 && memcmp(b, "BRUMEBL", 7) == 0)
        return HELD_LIGHT;
    if ((n >= 4 && memcmp(b, "\x76\x2f\x31\x01", 4) == 0) || (n >= 8 && memcmp(b, "\x89PNG\r\n\x1a\n", 8) == 0) ||
        (n >= 3 && b[0] == 'P' && (b[1] == 'F' || b[1] == 'f') && (b[2] == '\n' || b[2] == ' ' || b[2] == '\r')))
        return HELD_IMAGE;
    if ((n >= 3 && memcmp(b, "VOL", 3) == 0) || (n >= 7 && memcmp(b, "NanoVDB", 7) == 0) ||
        (n >= 4 && memcmp(b, "\x20\x42\x44\x56", 4) == 0))
        return HELD_GRID;
    for (size_t i = 0; i < n; i++)
        if (b[i] == 0)
            return HELD_OTHER;
    return HELD_TEXT;
}

static const char *held_name(held h)
{
    static const char *const names[] = {"data of another kind", "text", "a brume checkpoint", "a brume light file",
                                        "an image", "a grid file"};
    return names[h];
}

static bool name_ends(const char *path, const char *ext)
{
    size_t n = strlen(path), m = strlen(ext);
    if (n < m)
        return false;
    for (size_t i = 0; i < m; i++)
        if ((path[n - m + i] | 0x20) != ext[i])
            return false;
    return true;
}

brume_status io_target_check(const char *what, const char *path, brume_file_kind kind)
{
    struct stat sb;
    if (kind == BRUME_FILE_ANY || !path || stat(path, &sb) != 0 || !S_ISREG(sb.st_mode) || sb.st_size == 0)
        return BRUME_OK; /* absent, empty, or not a regular file (io_output_check's and the writer's) */
    unsigned char b[512];
    size_t n = 0;
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd >= 0) {
        ssize_t got = read(fd, b, sizeof b);
        n = got > 0 ? (size_t)got : 0;
        close(fd);
    }
    held h = sniff(b, n);
    static const held want[] = {[BRUME_FILE_IMAGE] = HELD_IMAGE, [BRUME_FILE_CHECKPOINT] = HELD_CHECKPOINT,
                                [BRUME_FILE_LIGHT] = HELD_LIGHT, [BRUME_FILE_GRID] = HELD_GRID,
                                [BRUME_FILE_TEXT] = HELD_TEXT};
    if (h == want[kind])
        return BRUME_OK;
    /* .raw and .df3 grids have no magic number: one replaces anything that is not brume's or text */
    if (kind == BRUME_FILE_GRID && h == HELD_OTHER && (name_ends(path, ".raw") || name_ends(path, ".df3")))
        return BRUME_OK;
    static const char *const kinds[] = {[BRUME_FILE_IMAGE] = "images", [BRUME_FILE_CHECKPOINT] = "its own checkpoints",
                                        [BRUME_FILE_LIGHT] = "its own light files", [BRUME_FILE_GRID] = "grid files",
                                        [BRUME_FILE_TEXT] = "text files"};
    static const char *const nouns[] = {[BRUME_FILE_IMAGE] = "an image", [BRUME_FILE_CHECKPOINT] = "a brume checkpoint",
                                        [BRUME_FILE_LIGHT] = "a brume light file", [BRUME_FILE_GRID] = "a grid file",
                                        [BRUME_FILE_TEXT] = "text"};
    if (what == path)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: holds %s, not %s: brume replaces only %s there", path,
                       held_name(h), nouns[kind], kinds[kind]);
    return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: holds %s, not %s: brume replaces only %s there", what, path,
                   held_name(h), nouns[kind], kinds[kind]);
}

/* The folder of path made absolute (realpath) and its last component; false when the folder
 * cannot be resolved. */
static bool canonical(const char *path, char *out, size_t cap)
{
    const char *slash = strrchr(path, '/');
    char dir[4096];
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else
        snprintf(dir, sizeof dir, "%.*s", slash == path ? 1 : (int)(slash - path), path);
    char *real = realpath(dir, NULL);
    if (!real)
        return false;
    int n = snprintf(out, cap, "%s/%s", real, slash ? slash + 1 : path);
    free(real);
    return n >= 0 && (size_t)n < cap;
}

bool io_same_file(const char *a, const char *b)
{
    if (!a || !b)
        return false;
    struct stat sa, sb;
    bool ea = stat(a, &sa) == 0, eb = stat(b, &sb) == 0;
    if (ea && eb)
        return sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
    if (ea != eb)
        return false;
    char ca[8192], cb[8192];
    if (canonical(a, ca, sizeof ca) && canonical(b, cb, sizeof cb))
        return strcmp(ca, cb) == 0;
    return strcmp(a, b) == 0;
}

brume_status io_output_check(const char *what, const char *path, brume_file_kind kind, const char *scene_file,
                             const io_inputs *inputs, const char *const *others, int nothers)
{
    for (int i = 0; path && i < nothers; i++)
        if (others[i] && others[i] != path && io_same_file(path, others[i]))
            return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                           "%s: %s: is '%s', another file of this command: brume does not write over its inputs or "
                           "write two outputs to one file",
                           what, path, others[i]);
    struct stat sb;
    if (!path || stat(path, &sb) != 0)
        return BRUME_OK; /* absent (or unreachable: the write itself will say why) */
    if (!S_ISREG(sb.st_mode))
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: not a regular file (%s): brume replaces only regular files",
                       what, path,
                       S_ISDIR(sb.st_mode) ? "a folder" : S_ISFIFO(sb.st_mode) ? "a pipe" : "a device or socket");
    struct stat ss;
    if (scene_file && stat(scene_file, &ss) == 0 && ss.st_dev == sb.st_dev && ss.st_ino == sb.st_ino)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: is the scene file: brume does not write over its inputs",
                       what, path);
    for (size_t i = 0; inputs && i < inputs->n; i++)
        if (inputs->v[i].dev == sb.st_dev && inputs->v[i].ino == sb.st_ino)
            return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                           "%s: %s: is '%s', an input of the scene: brume does not write over its inputs", what, path,
                           inputs->v[i].path);
    return io_target_check(what, path, kind);
}

brume_status io_open_regular(const char *path, FILE **out)
{
    *out = NULL;
    /* O_NONBLOCK: opening a FIFO without a writer must not wait */
    int fd = open(path, O_RDONLY | O_NONBLOCK);
    if (fd < 0)
        return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
    struct stat sb;
    if (fstat(fd, &sb) != 0) {
        int e = errno;
        close(fd);
        return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(e));
    }
    if (!S_ISREG(sb.st_mode)) {
        close(fd);
        return err_set(BRUME_ERROR_IO, "%s: not a regular file (%s)", path,
                       S_ISDIR(sb.st_mode) ? "a folder" : S_ISFIFO(sb.st_mode) ? "a pipe" : "a device or socket");
    }
    int flags = fcntl(fd, F_GETFL);
    if (flags < 0 || fcntl(fd, F_SETFL, flags & ~O_NONBLOCK) != 0 || !(*out = fdopen(fd, "rb"))) {
        int e = errno;
        close(fd);
        return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(e));
    }
    note_stat(path, &sb);
    return BRUME_OK;
}

brume_status io_check_size(FILE *fp, const char *path, const char *what, long long max_bytes)
{
    struct stat sb;
    if (fstat(fileno(fp), &sb) != 0)
        return err_set(BRUME_ERROR_IO, "%s: %s: cannot read its size: %s", path, what, strerror(errno));
    if ((long long)sb.st_size > max_bytes)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: %lld bytes, more than the %lld such a file can hold", path, what,
                       (long long)sb.st_size, max_bytes);
    return BRUME_OK;
}

brume_status io_open_input(const char *path, const char *what, FILE **out)
{
    brume_status st = io_open_regular(path, out);
    if (st == BRUME_OK)
        return st;
    char reason[1024];
    size_t n = strlen(path);
    const char *m = err_message();
    snprintf(reason, sizeof reason, "%s", strncmp(m, path, n) == 0 && m[n] == ':' && m[n + 1] == ' ' ? m + n + 2 : m);
    return err_set(st, "%s: %s: %.900s", path, what, reason);
}
