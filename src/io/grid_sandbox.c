/* grid_sandbox.c - OpenVDB reading in a child process under resource limits (grid_sandbox.h).
 *
 * Protocol on the pipe, child to parent: one tag byte, then
 *   'E' status (int32) length (uint32) message    an error, reported as is
 *   'B' size (uint64) bytes                       a NanoVDB buffer
 *   'L' count (uint32) count gridvdb_info         a grid list
 *   'K'                                           done, nothing to return
 * Anything else, a short read, a child killed by a signal or a timeout is an error naming
 * the file. The parent never trusts a size before checking it against its own limit.
 *
 * The child is a program of its own, brume-openvdb-reader (cli/openvdb_reader.c, beside the
 * OpenVDB module), started with posix_spawn: the job in its arguments, the file's bytes (when
 * there is no path) on its fd 4 from a memory file, the answer on its fd 3. A fork without
 * exec would copy a process whose other threads (a renderer's, a read-ahead's, Python's) may
 * hold a lock, such as AddressSanitizer's allocator's, which GCC's libasan does not take
 * across a fork: the child then blocked for good under the sanitizer. A new program holds no
 * lock of this one. */
#define _GNU_SOURCE /* memfd_create */
#include "io/grid_sandbox.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/mman.h>
#include <sys/wait.h>
#include <spawn.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"
#include "core/regular_file.h"
#include "io/sandbox.h"
#include "io/vdb_path.h"

#ifndef BRUME_HAVE_OPENVDB
#define BRUME_HAVE_OPENVDB 0
#endif
#if BRUME_HAVE_OPENVDB

typedef struct sandbox_job {
    int kind; /* 0 to_nano, 1 list, 2 convert */
    const char *path, *out, *name, *grid;
    const void *bytes;
    size_t size;
    int vec3;
} sandbox_job;

static int child_sink(void *user, const void *data, size_t size)
{
    int fd = *(int *)user;
    uint64_t n = size;
    return sandbox_write_all(fd, "B", 1) || sandbox_write_all(fd, &n, sizeof n) || sandbox_write_all(fd, data, size) ? -1
                                                                                                            : 0;
}

/* The child's answer goes to this descriptor, the file's bytes (no path) come on CHILD_BYTES_FD. */
#define CHILD_ANSWER_FD 3
#define CHILD_BYTES_FD 4

static _Noreturn void child_run(const sandbox_job *j, int fd, double cpu_seconds, size_t max_memory, size_t in_size)
{
    /* OpenVDB stores at least a 64-byte mask per leaf of about 2 KiB: a tree is at most some
     * 40 times its file, the NanoVDB copy about as much again */
    size_t as = 2 * max_memory;
    if ((double)in_size * 128.0 < (double)as)
        as = in_size * 128;
    sandbox_child_limits(cpu_seconds, as + ((size_t)1 << 30));
    brume_status st = BRUME_OK;
    if (j->kind == 0) {
        st = gridvdb_to_nano(j->path, j->bytes, j->size, j->name, j->grid, j->vec3, child_sink, &fd);
    } else if (j->kind == 1) {
        gridvdb_info *in = NULL;
        int count = 0;
        st = gridvdb_list(j->path, j->bytes, j->size, j->name, &in, &count);
        if (st == BRUME_OK) {
            uint32_t c = (uint32_t)count;
            if (sandbox_write_all(fd, "L", 1) || sandbox_write_all(fd, &c, sizeof c) ||
                sandbox_write_all(fd, in, c * sizeof *in))
                _exit(3);
        }
    } else {
        st = gridvdb_vdb_to_nvdb(j->path, j->out, j->grid);
        if (st == BRUME_OK && sandbox_write_all(fd, "K", 1))
            _exit(3);
    }
    if (st != BRUME_OK)
        sandbox_child_error(fd);
    _exit(0);
}

typedef struct sandbox_result {
    void *buf;
    size_t nbytes;
    gridvdb_info *infos;
    int count;
} sandbox_result;

/* The NanoVDB grid the child sends after its 'B' into res (within max_memory): the read's
 * result (0, or < 0 when the pipe failed); a refusal of what was read in *st. */
static int read_grid(int fd, const sandbox_job *j, size_t max_memory, double deadline, sandbox_result *res,
                     brume_status *st)
{
    uint64_t n = 0;
    int rr = sandbox_read_all(fd, &n, sizeof n, deadline);
    if (rr == 0 && n > max_memory) {
        *st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: grid of %llu bytes (NanoVDB) exceeds the memory limit of %zu",
                      j->name, (unsigned long long)n, max_memory);
    } else if (rr == 0 && n < 64) {
        *st = err_set(BRUME_ERROR_PARSE, "%s: OpenVDB reader returned %llu bytes", j->name, (unsigned long long)n);
    } else if (rr == 0) {
        res->buf = aligned_alloc(32, ((size_t)n + 31) / 32 * 32);
        if (!res->buf)
            *st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a grid of %llu bytes", j->name,
                          (unsigned long long)n);
        else if ((rr = sandbox_read_all(fd, res->buf, (size_t)n, deadline)) == 0)
            res->nbytes = (size_t)n;
    }
    return rr;
}

/* The grids the child lists after its 'L' into res: as read_grid. */
static int read_list(int fd, const sandbox_job *j, double deadline, sandbox_result *res, brume_status *st)
{
    uint32_t c = 0;
    int rr = sandbox_read_all(fd, &c, sizeof c, deadline);
    if (rr == 0 && c > 4096) {
        *st = err_set(BRUME_ERROR_PARSE, "%s: %u grids, more than brume lists", j->name, (unsigned)c);
    } else if (rr == 0) {
        res->infos = calloc((size_t)c + 1, sizeof *res->infos);
        if (!res->infos)
            *st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", j->name);
        else if ((rr = sandbox_read_all(fd, res->infos, c * sizeof *res->infos, deadline)) == 0) {
            res->count = (int)c;
            for (uint32_t i = 0; i < c; i++) { /* strings from the child end inside their arrays */
                res->infos[i].name[sizeof res->infos[i].name - 1] = '\0';
                res->infos[i].type[sizeof res->infos[i].type - 1] = '\0';
                res->infos[i].cls[sizeof res->infos[i].cls - 1] = '\0';
            }
        }
    }
    return rr;
}

/* A memory file holding the job's bytes (no path): the child's CHILD_BYTES_FD; -1 after a refusal. */
static int bytes_file(const sandbox_job *j)
{
    int mfd = memfd_create("brume-vdb", MFD_CLOEXEC);
    if (mfd < 0) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot hand the bytes to the OpenVDB reader: %s", j->name,
                strerror(errno));
        return -1;
    }
    if (sandbox_write_all(mfd, j->bytes, j->size) != 0) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot hand %zu bytes to the OpenVDB reader: %s", j->name, j->size,
                strerror(errno));
        close(mfd);
        return -1;
    }
    return mfd;
}

/* Starts brume-openvdb-reader on job j, its answer to `answer`: argv is the job, in the order
 * grid_sandbox_child_main reads it. */
static brume_status spawn_child(const sandbox_job *j, int answer, double cpu, size_t max_memory, size_t in_size,
                                pid_t *pid)
{
    char exe[PATH_MAX + 64];
    if (vdb_path_reader(exe, sizeof exe) != BRUME_OK) {
        char why[3000]; /* err_set writes over err_message()'s buffer */
        snprintf(why, sizeof why, "%s", err_message());
        return err_set(err_status(), "%s: %s", j->name, why);
    }
    char kind[8], vec3[8], cpu_s[40], mem_s[40], size_s[40];
    snprintf(kind, sizeof kind, "%d", j->kind);
    snprintf(vec3, sizeof vec3, "%d", j->vec3);
    snprintf(cpu_s, sizeof cpu_s, "%.17g", cpu);
    snprintf(mem_s, sizeof mem_s, "%zu", max_memory);
    snprintf(size_s, sizeof size_s, "%zu", j->path ? in_size : j->size);
    char *argv[] = {exe,     kind,   (char *)(j->path ? j->path : "-"), (char *)(j->out ? j->out : ""),
                    (char *)j->name, (char *)(j->grid ? j->grid : ""), vec3, cpu_s, mem_s, size_s, NULL};
    int mfd = j->path ? -1 : bytes_file(j);
    if (!j->path && mfd < 0)
        return err_status();
    /* both above the child's numbers, so that neither dup2 is onto itself or onto the other */
    int afd = fcntl(answer, F_DUPFD_CLOEXEC, 10), bfd = mfd >= 0 ? fcntl(mfd, F_DUPFD_CLOEXEC, 10) : -1;
    posix_spawn_file_actions_t fa;
    int e = afd < 0 || (mfd >= 0 && bfd < 0) ? errno : posix_spawn_file_actions_init(&fa);
    if (e == 0) {
        e = posix_spawn_file_actions_adddup2(&fa, afd, CHILD_ANSWER_FD);
        if (e == 0 && bfd >= 0)
            e = posix_spawn_file_actions_adddup2(&fa, bfd, CHILD_BYTES_FD);
        extern char **environ;
        if (e == 0)
            e = posix_spawn(pid, exe, &fa, NULL, argv, environ);
        posix_spawn_file_actions_destroy(&fa);
    }
    if (afd >= 0)
        close(afd);
    if (bfd >= 0)
        close(bfd);
    if (mfd >= 0)
        close(mfd);
    if (e != 0)
        return err_set(BRUME_ERROR_IO, "%s: cannot start the OpenVDB reader %s: %s", j->name, exe, strerror(e));
    return BRUME_OK;
}

static brume_status sandbox_run(const sandbox_job *j, size_t max_memory, sandbox_result *res)
{
    memset(res, 0, sizeof *res);
    size_t in_size = j->size;
    struct stat sb;
    io_input_note(j->path); /* read by the child: listed among the scene's inputs here */
    if (j->path && stat(j->path, &sb) == 0)
        in_size = (size_t)sb.st_size;
    double cpu = (5.0 + 2.0 * (double)in_size / 1048576.0) * (SANDBOX_ASAN ? 4.0 : 1.0); /* ASan: slower */
    double deadline = sandbox_now() + 2.0 * cpu + 5.0;
    int fds[2];
    if (pipe2(fds, O_CLOEXEC) != 0)
        return err_set(BRUME_ERROR_IO, "%s: cannot create a pipe: %s", j->name, strerror(errno));
    pid_t pid;
    brume_status st = spawn_child(j, fds[1], cpu, max_memory, in_size, &pid);
    if (st != BRUME_OK) {
        close(fds[0]);
        close(fds[1]);
        return st;
    }
    close(fds[1]);
    int fd = fds[0];
    char tag = 0;
    int rr = sandbox_read_all(fd, &tag, 1, deadline);
    if (rr == 0 && tag == 'E') {
        rr = sandbox_read_error(fd, deadline);
        st = rr == 0 ? err_status() : BRUME_OK;
    } else if (rr == 0 && tag == 'B' && j->kind == 0) {
        rr = read_grid(fd, j, max_memory, deadline, res, &st);
    } else if (rr == 0 && tag == 'L' && j->kind == 1) {
        rr = read_list(fd, j, deadline, res, &st);
    } else if (rr == 0 && tag != 'K') {
        rr = -1;
    } else if (rr == 0 && j->kind != 2) {
        rr = -1;
    }
    close(fd);
    brume_status reaped = sandbox_reap(pid, st == BRUME_OK ? rr : 0, j->name, "OpenVDB reader",
                                       "malformed or hostile .vdb", cpu, 2.0 * cpu + 5.0);
    if (st == BRUME_OK)
        st = reaped;
    if (st != BRUME_OK) {
        free(res->buf);
        free(res->infos);
        memset(res, 0, sizeof *res);
    }
    return st;
}

brume_status grid_sandbox_to_nano(const char *path, const void *bytes, size_t size, const char *name,
                                  const char *grid, int vec3, size_t max_memory, void **buf, size_t *nbytes)
{
    sandbox_job j = {0, path, NULL, name, grid, bytes, size, vec3};
    sandbox_result r;
    brume_status st = sandbox_run(&j, max_memory, &r);
    *buf = r.buf;
    *nbytes = r.nbytes;
    return st;
}

brume_status grid_sandbox_list(const char *path, const void *bytes, size_t size, const char *name,
                               size_t max_memory, gridvdb_info **out, int *count)
{
    sandbox_job j = {1, path, NULL, name, NULL, bytes, size, 0};
    sandbox_result r;
    brume_status st = sandbox_run(&j, max_memory, &r);
    *out = r.infos;
    *count = r.count;
    return st;
}

brume_status grid_sandbox_vdb_to_nvdb(const char *in, const char *out, const char *grid, size_t max_memory)
{
    sandbox_job j = {2, in, out, in, grid, NULL, 0, 0};
    sandbox_result r;
    return sandbox_run(&j, max_memory, &r);
}

/* brume-openvdb-reader's main: the job spawn_child wrote into argv. Not for users: refuses
 * any other command line with exit 2. */
int grid_sandbox_child_main(int argc, char **argv)
{
    if (argc != 10 || fcntl(CHILD_ANSWER_FD, F_GETFD) < 0) {
        fprintf(stderr, "%s: run by libbrume to read a .vdb in a process of its own; not a command\n", argv[0]);
        return 2;
    }
    sandbox_job j = {atoi(argv[1]), argv[2], argv[3], argv[4], argv[5], NULL, 0, atoi(argv[6])};
    double cpu = strtod(argv[7], NULL);
    size_t max_memory = (size_t)strtoull(argv[8], NULL, 10), in_size = (size_t)strtoull(argv[9], NULL, 10);
    if (strcmp(j.path, "-") == 0) { /* the bytes, in a memory file */
        j.path = NULL;
        j.size = in_size;
        j.bytes = in_size ? mmap(NULL, in_size, PROT_READ, MAP_PRIVATE, CHILD_BYTES_FD, 0) : "";
        if (j.bytes == MAP_FAILED)
            _exit(3);
    }
    if (!j.grid[0])
        j.grid = NULL;
    child_run(&j, CHILD_ANSWER_FD, cpu, max_memory, in_size);
}

#else /* built without OpenVDB */

static brume_status no_openvdb(const char *name)
{
    return err_set(BRUME_ERROR_UNSUPPORTED, "%s: .vdb needs OpenVDB, and brume was built without OpenVDB", name);
}

brume_status grid_sandbox_to_nano(const char *path, const void *bytes, size_t size, const char *name,
                                  const char *grid, int vec3, size_t max_memory, void **buf, size_t *nbytes)
{
    (void)path, (void)bytes, (void)size, (void)grid, (void)vec3, (void)max_memory;
    *buf = NULL;
    *nbytes = 0;
    return no_openvdb(name);
}

brume_status grid_sandbox_list(const char *path, const void *bytes, size_t size, const char *name,
                               size_t max_memory, gridvdb_info **out, int *count)
{
    (void)path, (void)bytes, (void)size, (void)max_memory;
    *out = NULL;
    *count = 0;
    return no_openvdb(name);
}

brume_status grid_sandbox_vdb_to_nvdb(const char *in, const char *out, const char *grid, size_t max_memory)
{
    (void)out, (void)grid, (void)max_memory;
    return no_openvdb(in);
}

int grid_sandbox_child_main(int argc, char **argv)
{
    (void)argc;
    fprintf(stderr, "%s: brume was built without OpenVDB\n", argv[0]);
    return 2;
}

#endif
