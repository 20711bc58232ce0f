/* regular_file.c - inputs and outputs are regular files (regular_file.h). */
#include "core/regular_file.h"

#include <errno.h>
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

const io_input *io_inputs_find(const io_inputs *rec, const char *path)
{
    struct stat sb;
    if (!rec || stat(path, &sb) != 0)
        return NULL;
    for (size_t i = 0; i < rec->n; i++)
        if (rec->v[i].dev == sb.st_dev && rec->v[i].ino == sb.st_ino)
            return &rec->v[i];
    return NULL;
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

brume_status io_output_check(const char *what, const char *path, const char *scene_file, const io_inputs *inputs)
{
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
    return BRUME_OK;
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
