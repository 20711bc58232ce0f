/* run_bad.c - runs the bad-input corpus of tests/bad/ (cases.txt) against the brume tool.
 *
 * Usage: run_bad BRUME CORPUS_DIR GROUP [--no-as-limit]
 * Each case of GROUP runs `brume ARGS` with stdout discarded, under a time limit (10 s of CPU
 * time, all threads together, which a loaded machine does not stretch, and 60 s of wall-clock
 * time for a case that blocks without working) and a 2 GiB address-space limit (setrlimit RLIMIT_AS; off under the sanitizers, whose shadow
 * memory needs more), and must exit with its expected status; a non-zero exit must print
 * exactly one line on stderr, free of control characters, matching the case's pattern
 * (POSIX extended regular expression). A case killed by a signal or by the time limit
 * fails. Every failing case is named; the exit status is 1 if any failed.
 *
 * cases.txt: one case per line, '#' comments, fields separated by '|':
 *   GROUP|NAME|EXIT|ARGS|PATTERN   (the pattern last: it may hold '|')
 * ARGS are split at spaces; {D} is the corpus folder, {T} a fresh folder for the case's
 * outputs; in ARGS \s is a space, \n a newline, \e an escape character, \\ a backslash. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <fcntl.h>
#include <regex.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#define MAX_ARGS 64
#define TIME_LIMIT_S 10.0 /* CPU seconds, all threads */
#define WALL_LIMIT_S 60.0

/* CPU time (user + system) the running process pid has used so far, from /proc; 0 when it
 * cannot be read (the process has just ended). */
static double cpu_seconds(pid_t pid)
{
    char path[64], buf[1024];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f)
        return 0.0;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    const char *p = strrchr(buf, ')'); /* after the command name, which may hold spaces */
    unsigned long long utime = 0, stime = 0;
    if (!p || sscanf(p + 1, " %*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %llu %llu", &utime, &stime) != 2)
        return 0.0;
    return (double)(utime + stime) / (double)sysconf(_SC_CLK_TCK);
}
#define AS_LIMIT ((rlim_t)2 << 30)

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Replaces every occurrence of key in s (in place, s has room for cap bytes). */
static void subst(char *s, size_t cap, const char *key, const char *val)
{
    char out[8192];
    size_t k = 0, kl = strlen(key), vl = strlen(val);
    for (const char *p = s; *p && k + 1 < sizeof out;) {
        if (strncmp(p, key, kl) == 0 && k + vl + 1 < sizeof out) {
            memcpy(out + k, val, vl);
            k += vl;
            p += kl;
        } else {
            out[k++] = *p++;
        }
    }
    out[k] = '\0';
    snprintf(s, cap, "%s", out);
}

static void unescape(char *s)
{
    char *w = s;
    for (const char *r = s; *r; r++) {
        if (*r == '\\' && r[1]) {
            r++;
            *w++ = *r == 's' ? ' ' : *r == 'n' ? '\n' : *r == 'e' ? '\x1b' : *r == 't' ? '\t' : *r;
        } else {
            *w++ = *r;
        }
    }
    *w = '\0';
}

static void rm_tree(const char *dir)
{
    char cmd[4300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "run_bad: could not remove %s\n", dir);
}

/* Runs `brume ARGS` ({D} and {T} replaced, escapes undone) in the case's folder tdir, stdout
 * discarded, stderr to errpath, within the time and address-space limits; returns its wait
 * status, *timed_out set when the limits killed it, and the seconds it took in *secs. */
static int run_brume(const char *brume, const char *corpus, const char *tdir, const char *args, int as_limit,
                     const char *errpath, int *timed_out, double *secs)
{
    char line[8192];
    snprintf(line, sizeof line, "%s", args);
    subst(line, sizeof line, "{D}", corpus);
    subst(line, sizeof line, "{T}", tdir);
    char *argv[MAX_ARGS + 2];
    int argc = 0;
    argv[argc++] = (char *)brume;
    for (char *tok = strtok(line, " "); tok && argc < MAX_ARGS; tok = strtok(NULL, " ")) {
        unescape(tok);
        argv[argc++] = tok;
    }
    argv[argc] = NULL;
    double t0 = now();
    pid_t pid = fork();
    if (pid == 0) {
        if (as_limit) {
            struct rlimit rl = {AS_LIMIT, AS_LIMIT};
            setrlimit(RLIMIT_AS, &rl);
        }
        int err = open(errpath, O_WRONLY | O_CREAT | O_TRUNC, 0600), nul = open("/dev/null", O_WRONLY);
        if (err < 0 || nul < 0)
            _exit(127);
        dup2(nul, 1);
        dup2(err, 2);
        if (chdir(tdir) != 0)
            _exit(127);
        execv(brume, argv);
        _exit(127);
    }
    int status = 0;
    *timed_out = 0;
    for (;;) {
        pid_t r = waitpid(pid, &status, WNOHANG);
        if (r == pid)
            break;
        if (cpu_seconds(pid) > TIME_LIMIT_S || now() - t0 > WALL_LIMIT_S) {
            kill(pid, SIGKILL);
            waitpid(pid, &status, 0);
            *timed_out = 1;
            break;
        }
        struct timespec ts = {0, 5000000};
        nanosleep(&ts, NULL);
    }
    *secs = now() - t0;
    return status;
}

/* Whether the n bytes of a failed case's stderr are one line, free of control characters,
 * matching pattern; 0 with the reason in why when not. */
static int message_ok(const char *err, size_t n, const char *pattern, char *why, size_t cap)
{
    size_t lines = 0;
    int ctrl = 0, ok = 1;
    for (size_t i = 0; i < n; i++) {
        unsigned char c = (unsigned char)err[i];
        if (c == '\n')
            lines++;
        else if (c < 0x20 || c == 0x7f)
            ctrl = 1;
    }
    regex_t re;
    int rc = regcomp(&re, pattern, REG_EXTENDED | REG_NOSUB);
    if (rc != 0) {
        snprintf(why, cap, "bad pattern '%.400s'", pattern);
        return 0;
    }
    if (lines != 1 || n == 0 || err[n - 1] != '\n') {
        snprintf(why, cap, "message is %zu lines, not one", lines);
        ok = 0;
    } else if (ctrl) {
        snprintf(why, cap, "message holds a control character");
        ok = 0;
    } else if (regexec(&re, err, 0, NULL, 0) != 0) {
        snprintf(why, cap, "message does not match /%.400s/", pattern);
        ok = 0;
    }
    regfree(&re);
    return ok;
}

/* Runs one case; returns 1 when it passed. */
static int run_case(const char *brume, const char *corpus, const char *name, int want, const char *pattern,
                    char *args, int as_limit)
{
    char tdir[4096];
    const char *tmp = getenv("TMPDIR");
    snprintf(tdir, sizeof tdir, "%s/brume-bad-%d-%s", tmp && *tmp ? tmp : "/tmp", (int)getpid(), name);
    rm_tree(tdir);
    if (mkdir(tdir, 0700) != 0) {
        printf("FAIL %s: cannot create %s: %s\n", name, tdir, strerror(errno));
        return 0;
    }
    char errpath[4200];
    snprintf(errpath, sizeof errpath, "%s/stderr.txt", tdir);
    int timed_out;
    double secs;
    int status = run_brume(brume, corpus, tdir, args, as_limit, errpath, &timed_out, &secs);
    char err[4096] = "";
    FILE *f = fopen(errpath, "rb");
    size_t n = f ? fread(err, 1, sizeof err - 1, f) : 0;
    if (f)
        fclose(f);
    err[n] = '\0';
    int ok = 1;
    char why[512] = "";
    if (timed_out) {
        snprintf(why, sizeof why, "did not end within %.0f s of CPU time or %.0f s", TIME_LIMIT_S, WALL_LIMIT_S);
        ok = 0;
    } else if (WIFSIGNALED(status)) {
        snprintf(why, sizeof why, "killed by signal %d", WTERMSIG(status));
        ok = 0;
    } else if (WEXITSTATUS(status) != want) {
        snprintf(why, sizeof why, "exit %d, expected %d", WEXITSTATUS(status), want);
        ok = 0;
    } else if (want != 0) {
        ok = message_ok(err, n, pattern, why, sizeof why);
    }
    if (ok)
        printf("ok   %-40s exit %d  %.2f s\n", name, want, secs);
    else
        printf("FAIL %-40s %s (%.2f s)\n     stderr: %s\n", name, why, secs, err[0] ? err : "(empty)\n");
    fflush(stdout);
    rm_tree(tdir);
    return ok;
}

int main(int argc, char **argv)
{
    if (argc < 4) {
        fprintf(stderr, "usage: run_bad BRUME CORPUS_DIR GROUP [--no-as-limit]\n");
        return 2;
    }
    static char brume[4096], corpus[4096]; /* absolute: each case runs in its own folder */
    const char *group = argv[3];
    if (!realpath(argv[1], brume) || !realpath(argv[2], corpus)) {
        fprintf(stderr, "run_bad: %s or %s: %s\n", argv[1], argv[2], strerror(errno));
        return 2;
    }
    int as_limit = !(argc > 4 && strcmp(argv[4], "--no-as-limit") == 0);
    char path[4200];
    snprintf(path, sizeof path, "%s/cases.txt", corpus);
    FILE *f = fopen(path, "r");
    if (!f) {
        fprintf(stderr, "run_bad: %s: %s\n", path, strerror(errno));
        return 2;
    }
    char line[8192];
    int run = 0, failed = 0;
    char failures[8192] = "";
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\r\n")] = '\0';
        if (!line[0] || line[0] == '#')
            continue;
        char *field[5];
        char *p = line;
        int k = 0;
        for (; k < 4; k++) {
            field[k] = p;
            char *bar = strchr(p, '|');
            if (!bar)
                break;
            *bar = '\0';
            p = bar + 1;
        }
        if (k < 4) {
            fprintf(stderr, "run_bad: malformed line in cases.txt: %s\n", line);
            return 2;
        }
        field[4] = p;
        if (strcmp(field[0], group) != 0)
            continue;
        run++;
        if (!run_case(brume, corpus, field[1], atoi(field[2]), field[4], field[3], as_limit)) {
            failed++;
            size_t l = strlen(failures);
            snprintf(failures + l, sizeof failures - l, " %s", field[1]);
        }
    }
    fclose(f);
    if (run == 0) {
        fprintf(stderr, "run_bad: no case in group %s\n", group);
        return 2;
    }
    printf("%d of %d %s cases passed%s%s\n", run - failed, run, group, failed ? "; failed:" : "", failures);
    return failed ? 1 : 0;
}
