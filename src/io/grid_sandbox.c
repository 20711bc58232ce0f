/* grid_sandbox.c - OpenVDB reading in a child process under resource limits (grid_sandbox.h).
 *
 * Protocol on the pipe, child to parent: one tag byte, then
 *   'E' status (int32) length (uint32) message    an error, reported as is
 *   'B' size (uint64) bytes                       a NanoVDB buffer
 *   'L' count (uint32) count gridvdb_info         a grid list
 *   'K'                                           done, nothing to return
 * Anything else, a short read, a child killed by a signal or a timeout is an error naming
 * the file. The parent never trusts a size before checking it against its own limit. */
#include "io/grid_sandbox.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/error.h"
#include "io/regular_file.h"

#ifndef BRUME_HAVE_OPENVDB
#define BRUME_HAVE_OPENVDB 0
#endif
#if BRUME_HAVE_OPENVDB

#if defined(__SANITIZE_ADDRESS__)
#define SANDBOX_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SANDBOX_ASAN 1
#endif
#endif
#ifndef SANDBOX_ASAN
#define SANDBOX_ASAN 0
#endif

typedef struct sandbox_job {
    int kind; /* 0 to_nano, 1 list, 2 convert */
    const char *path, *out, *name, *grid;
    const void *bytes;
    size_t size;
    int vec3;
} sandbox_job;

static int write_all(int fd, const void *p, size_t n)
{
    const char *c = p;
    while (n > 0) {
        ssize_t w = write(fd, c, n);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return -1;
        c += w;
        n -= (size_t)w;
    }
    return 0;
}

static int child_sink(void *user, const void *data, size_t size)
{
    int fd = *(int *)user;
    uint64_t n = size;
    return write_all(fd, "B", 1) || write_all(fd, &n, sizeof n) || write_all(fd, data, size) ? -1 : 0;
}

static void child_error(int fd)
{
    const char *m = err_message();
    int32_t st = (int32_t)err_status();
    uint32_t len = (uint32_t)strlen(m);
    if (write_all(fd, "E", 1) == 0 && write_all(fd, &st, sizeof st) == 0 && write_all(fd, &len, sizeof len) == 0)
        (void)write_all(fd, m, len);
}

static void child_run(const sandbox_job *j, int fd, double cpu_seconds, size_t max_memory, size_t in_size)
{
    struct rlimit r;
    r.rlim_cur = r.rlim_max = (rlim_t)cpu_seconds + 1;
    setrlimit(RLIMIT_CPU, &r);
    r.rlim_cur = r.rlim_max = 0;
    setrlimit(RLIMIT_CORE, &r);
    if (!SANDBOX_ASAN) {
        /* OpenVDB stores at least a 64-byte mask per leaf of about 2 KiB: a tree is at most
         * some 40 times its file, the NanoVDB copy about as much again */
        rlim_t as = (rlim_t)2 * (rlim_t)max_memory;
        if ((double)in_size * 128.0 < (double)as)
            as = (rlim_t)in_size * 128;
        as += (rlim_t)1 << 30;
        if (getrlimit(RLIMIT_AS, &r) == 0 && (r.rlim_cur == RLIM_INFINITY || as < r.rlim_cur)) {
            r.rlim_cur = as;
            setrlimit(RLIMIT_AS, &r);
        }
    }
    /* OpenVDB's own messages would be a second line: the error comes back on the pipe */
    int devnull = open("/dev/null", O_WRONLY);
    if (devnull >= 0) {
        dup2(devnull, 2);
        dup2(devnull, 1);
        close(devnull);
    }
    brume_status st = BRUME_OK;
    if (j->kind == 0) {
        st = gridvdb_to_nano(j->path, j->bytes, j->size, j->name, j->grid, j->vec3, child_sink, &fd);
    } else if (j->kind == 1) {
        gridvdb_info *in = NULL;
        int count = 0;
        st = gridvdb_list(j->path, j->bytes, j->size, j->name, &in, &count);
        if (st == BRUME_OK) {
            uint32_t c = (uint32_t)count;
            if (write_all(fd, "L", 1) || write_all(fd, &c, sizeof c) || write_all(fd, in, c * sizeof *in))
                _exit(3);
        }
    } else {
        st = gridvdb_vdb_to_nvdb(j->path, j->out, j->grid);
        if (st == BRUME_OK && write_all(fd, "K", 1))
            _exit(3);
    }
    if (st != BRUME_OK)
        child_error(fd);
    _exit(0);
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Reads exactly n bytes before the deadline; 0 ok, -1 closed or error, -2 timeout. */
static int read_all(int fd, void *p, size_t n, double deadline)
{
    char *c = p;
    while (n > 0) {
        double left = deadline - now_seconds();
        if (left <= 0.0)
            return -2;
        struct pollfd pf = {fd, POLLIN, 0};
        int pr = poll(&pf, 1, (int)(left * 1000.0) + 1);
        if (pr < 0 && errno == EINTR)
            continue;
        if (pr < 0)
            return -1;
        if (pr == 0)
            continue;
        ssize_t r = read(fd, c, n);
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0)
            return -1;
        c += r;
        n -= (size_t)r;
    }
    return 0;
}

typedef struct sandbox_result {
    void *buf;
    size_t nbytes;
    gridvdb_info *infos;
    int count;
} sandbox_result;

static brume_status sandbox_run(const sandbox_job *j, size_t max_memory, sandbox_result *res)
{
    memset(res, 0, sizeof *res);
    size_t in_size = j->size;
    struct stat sb;
    io_input_note(j->path); /* read by the child: listed among the scene's inputs here */
    if (j->path && stat(j->path, &sb) == 0)
        in_size = (size_t)sb.st_size;
    double cpu = (5.0 + 2.0 * (double)in_size / 1048576.0) * (SANDBOX_ASAN ? 4.0 : 1.0); /* ASan: slower */
    double deadline = now_seconds() + 2.0 * cpu + 5.0;
    int fds[2];
    if (pipe(fds) != 0)
        return err_set(BRUME_ERROR_IO, "%s: cannot create a pipe: %s", j->name, strerror(errno));
    /* The child opens the OpenVDB module itself (io/grid_vdb.h): this process does not map
     * OpenVDB to read, so no thread of its libraries (log4cplus's pool starts at load) can
     * hold a lock across the fork. A module this process opened to write is handled here. */
    gridvdb_before_fork();
    fflush(NULL);
    pid_t pid = fork();
    if (pid < 0) {
        close(fds[0]);
        close(fds[1]);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: cannot start the OpenVDB reader process: %s", j->name,
                       strerror(errno));
    }
    if (pid == 0) {
        close(fds[0]);
        child_run(j, fds[1], cpu, max_memory, in_size);
    }
    close(fds[1]);
    int fd = fds[0];
    brume_status st = BRUME_OK;
    char tag = 0;
    int rr = read_all(fd, &tag, 1, deadline);
    if (rr == 0 && tag == 'E') {
        int32_t s = 0;
        uint32_t len = 0;
        char msg[1024];
        rr = read_all(fd, &s, sizeof s, deadline);
        if (rr == 0)
            rr = read_all(fd, &len, sizeof len, deadline);
        if (rr == 0 && len < sizeof msg)
            rr = read_all(fd, msg, len, deadline);
        else if (rr == 0)
            rr = -1;
        if (rr == 0) {
            msg[len] = '\0';
            for (char *c = msg; *c; c++)
                if (*c == '\n' || *c == '\r')
                    *c = ' ';
            st = err_set(s > 0 ? (brume_status)s : BRUME_ERROR_PARSE, "%s", msg);
        }
    } else if (rr == 0 && tag == 'B' && j->kind == 0) {
        uint64_t n = 0;
        rr = read_all(fd, &n, sizeof n, deadline);
        if (rr == 0 && n > max_memory) {
            st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: grid of %llu bytes (NanoVDB) exceeds the memory limit of %zu",
                         j->name, (unsigned long long)n, max_memory);
        } else if (rr == 0 && n < 64) {
            st = err_set(BRUME_ERROR_PARSE, "%s: OpenVDB reader returned %llu bytes", j->name, (unsigned long long)n);
        } else if (rr == 0) {
            res->buf = aligned_alloc(32, ((size_t)n + 31) / 32 * 32);
            if (!res->buf)
                st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a grid of %llu bytes", j->name,
                             (unsigned long long)n);
            else if ((rr = read_all(fd, res->buf, (size_t)n, deadline)) == 0)
                res->nbytes = (size_t)n;
        }
    } else if (rr == 0 && tag == 'L' && j->kind == 1) {
        uint32_t c = 0;
        rr = read_all(fd, &c, sizeof c, deadline);
        if (rr == 0 && c > 4096) {
            st = err_set(BRUME_ERROR_PARSE, "%s: %u grids, more than brume lists", j->name, (unsigned)c);
        } else if (rr == 0) {
            res->infos = calloc((size_t)c + 1, sizeof *res->infos);
            if (!res->infos)
                st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", j->name);
            else if ((rr = read_all(fd, res->infos, c * sizeof *res->infos, deadline)) == 0) {
                res->count = (int)c;
                for (uint32_t i = 0; i < c; i++) { /* strings from the child end inside their arrays */
                    res->infos[i].name[sizeof res->infos[i].name - 1] = '\0';
                    res->infos[i].type[sizeof res->infos[i].type - 1] = '\0';
                    res->infos[i].cls[sizeof res->infos[i].cls - 1] = '\0';
                }
            }
        }
    } else if (rr == 0 && tag != 'K') {
        rr = -1;
    } else if (rr == 0 && j->kind != 2) {
        rr = -1;
    }
    close(fd);
    if (rr == -2)
        kill(pid, SIGKILL);
    int wst = 0;
    while (waitpid(pid, &wst, 0) < 0 && errno == EINTR) {
    }
    if (st == BRUME_OK && rr != 0) {
        if (rr == -2)
            st = err_set(BRUME_ERROR_PARSE, "%s: OpenVDB reader gave no answer within %.0f s (malformed .vdb?)",
                         j->name, 2.0 * cpu + 5.0);
        else if (WIFSIGNALED(wst) && WTERMSIG(wst) == SIGXCPU)
            st = err_set(BRUME_ERROR_PARSE, "%s: OpenVDB reader exceeded its CPU limit of %.0f s (malformed .vdb?)",
                         j->name, cpu);
        else if (WIFSIGNALED(wst))
            st = err_set(BRUME_ERROR_PARSE, "%s: OpenVDB reader crashed (signal %d): malformed or hostile .vdb",
                         j->name, WTERMSIG(wst));
        else
            st = err_set(BRUME_ERROR_PARSE,
                         "%s: OpenVDB reader failed (exit %d): malformed .vdb, or over its memory limit", j->name,
                         WIFEXITED(wst) ? WEXITSTATUS(wst) : -1);
    }
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

#endif
