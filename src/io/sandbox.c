/* sandbox.c - the child's limits and the pipe of the sandboxed readers (sandbox.h). */
#include "io/sandbox.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "core/cancel.h"
#include "core/error.h"

double sandbox_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

void sandbox_child_limits(double cpu_seconds, size_t address_space)
{
    struct rlimit r;
    r.rlim_cur = r.rlim_max = (rlim_t)cpu_seconds + 1;
    setrlimit(RLIMIT_CPU, &r);
    r.rlim_cur = r.rlim_max = 0;
    setrlimit(RLIMIT_CORE, &r);
    if (!SANDBOX_ASAN && address_space > 0 && getrlimit(RLIMIT_AS, &r) == 0 &&
        (r.rlim_cur == RLIM_INFINITY || (rlim_t)address_space < r.rlim_cur)) {
        r.rlim_cur = (rlim_t)address_space;
        setrlimit(RLIMIT_AS, &r);
    }
    /* the library's own messages would be a second line: the error comes back on the pipe */
    int devnull = open("/dev/null", O_WRONLY);
    if (devnull >= 0) {
        dup2(devnull, 2);
        dup2(devnull, 1);
        close(devnull);
    }
}

int sandbox_write_all(int fd, const void *p, size_t n)
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

int sandbox_read_all(int fd, void *p, size_t n, double deadline)
{
    char *c = p;
    while (n > 0) {
        double left = deadline - sandbox_now();
        if (left <= 0.0)
            return -2;
        if (cancel_load_requested()) /* brume_context_cancel_loads: the child is killed */
            return -3;
        struct pollfd pf = {fd, POLLIN, 0};
        int pr = poll(&pf, 1, left > 0.1 ? 100 : (int)(left * 1000.0) + 1); /* asks the cancel at 10 Hz */
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

void sandbox_child_error(int fd)
{
    const char *m = err_message();
    int32_t st = (int32_t)err_status();
    uint32_t len = (uint32_t)strlen(m);
    if (sandbox_write_all(fd, "E", 1) == 0 && sandbox_write_all(fd, &st, sizeof st) == 0 &&
        sandbox_write_all(fd, &len, sizeof len) == 0)
        (void)sandbox_write_all(fd, m, len);
}

int sandbox_read_error(int fd, double deadline)
{
    int32_t s = 0;
    uint32_t len = 0;
    char msg[1024];
    int rr = sandbox_read_all(fd, &s, sizeof s, deadline);
    if (rr == 0)
        rr = sandbox_read_all(fd, &len, sizeof len, deadline);
    if (rr == 0 && len < sizeof msg)
        rr = sandbox_read_all(fd, msg, len, deadline);
    else if (rr == 0)
        rr = -1;
    if (rr == 0) {
        msg[len] = '\0';
        for (char *c = msg; *c; c++)
            if (*c == '\n' || *c == '\r')
                *c = ' ';
        err_set(s > 0 ? (brume_status)s : BRUME_ERROR_PARSE, "%s", msg);
    }
    return rr;
}

brume_status sandbox_reap(pid_t pid, int rr, const char *name, const char *what, const char *hint, double cpu_seconds,
                          double wall_seconds)
{
    if (rr == -2 || rr == -3)
        kill(pid, SIGKILL);
    int wst = 0;
    while (waitpid(pid, &wst, 0) < 0 && errno == EINTR) {
    }
    if (rr == 0)
        return BRUME_OK;
    if (rr == -3)
        return err_set(BRUME_ERROR_CANCELLED, "%s: loading cancelled (brume_context_cancel_loads)", name);
    if (rr == -2)
        return err_set(BRUME_ERROR_PARSE, "%s: %s gave no answer within %.0f s (%s?)", name, what, wall_seconds, hint);
    if (WIFSIGNALED(wst) && WTERMSIG(wst) == SIGXCPU)
        return err_set(BRUME_ERROR_PARSE, "%s: %s exceeded its CPU limit of %.0f s (%s?)", name, what, cpu_seconds,
                       hint);
    /* brume sends SIGKILL only past the deadline (rr -2, above): another one is the system's
     * out-of-memory killer ending a child that asked for more memory than the machine had */
    if (WIFSIGNALED(wst) && WTERMSIG(wst) == SIGKILL)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY,
                       "%s: %s was refused memory: the system ended it (SIGKILL) when the machine ran out of memory "
                       "(lower render.max_memory_mb, or a smaller file)",
                       name, what);
    if (WIFSIGNALED(wst))
        return err_set(BRUME_ERROR_PARSE, "%s: %s crashed (signal %d): %s", name, what, WTERMSIG(wst), hint);
    return err_set(BRUME_ERROR_PARSE, "%s: %s failed (exit %d): %s, or over its memory limit", name, what,
                   WIFEXITED(wst) ? WEXITSTATUS(wst) : -1, hint);
}
