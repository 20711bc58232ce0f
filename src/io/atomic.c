/* atomic.c - write a file so that it appears whole or not at all (temp file + rename).
 *
 * The temporary file lives in the destination's folder so that rename(2) replaces the
 * destination atomically (POSIX rename: "If the link named by the new argument exists, it
 * shall be removed and old renamed to new ... a link named new shall remain visible to
 * other threads throughout the renaming operation"). Data are fsync'ed before the rename
 * so that a crash cannot leave a renamed but empty file.
 *
 * The folder is not fsync'ed after the rename: that would only make the new name itself
 * survive a power cut, and without it a crash leaves the old file or none, never a torn
 * one (the data reached the disk before the name). It cost 5-8 ms of every written file on
 * the project's machine, 2-3 % of Blasi's picture as `brume render` makes it,
 * for a durability that image writers (cp, Blender, ImageMagick) do not offer either; a
 * checkpoint whose rename is lost leaves the previous checkpoint, which resumes.
 *
 * Interruption: while a temporary file exists its name is in a small table, and the first
 * atomic_open installs handlers for SIGINT, SIGTERM, SIGHUP and SIGPIPE (only where the
 * disposition is still the default: a program's own handlers win and are expected to
 * return to atomic_abort) that remove every listed temporary file, restore the default
 * and re-raise, so that an interrupted write leaves nothing behind.
 *
 * Only regular files are replaced: a destination that exists and is anything else (a device
 * node such as /dev/null, a folder, a pipe, a socket) is refused by atomic_open, and again
 * just before the rename, since rename(2) would put the new file in place of the node. */
#include "io/atomic.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/context.h"
#include "core/error.h"
#include "core/regular_file.h"

static const char tmp_suffix[] = ".tmp-XXXXXX";

/* ---- temporary files removed on a fatal signal ------------------------------------------- */

#define ATOMIC_SLOTS 16 /* temporary files open at once (one per writer thread is typical) */
static char slot_path[ATOMIC_SLOTS][sizeof(((atomic_file *)0)->tmp_path)];
static atomic_int slot_state[ATOMIC_SLOTS]; /* 0 free, 1 being filled or emptied, 2 listed */
static _Atomic(const void *) slot_owner[ATOMIC_SLOTS]; /* the context of the call, or NULL */
static _Thread_local const void *t_owner;              /* this thread's, atomic_owner */
static atomic_flag handlers_installed = ATOMIC_FLAG_INIT;
static const int cleanup_signals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};

static void cleanup_on_signal(int sig)
{
    for (int i = 0; i < ATOMIC_SLOTS; i++)
        if (atomic_load(&slot_state[i]) == 2)
            (void)unlink(slot_path[i]); /* async-signal-safe */
    struct sigaction dfl;
    memset(&dfl, 0, sizeof dfl);
    dfl.sa_handler = SIG_DFL;
    sigemptyset(&dfl.sa_mask);
    (void)sigaction(sig, &dfl, NULL);
    (void)raise(sig);
}

static void install_handlers(void)
{
    if (atomic_flag_test_and_set(&handlers_installed))
        return;
    for (size_t i = 0; i < sizeof cleanup_signals / sizeof cleanup_signals[0]; i++) {
        struct sigaction old;
        if (sigaction(cleanup_signals[i], NULL, &old) != 0 || (old.sa_flags & SA_SIGINFO) ||
            old.sa_handler != SIG_DFL)
            continue; /* ignored, or the program's own handler */
        struct sigaction sa;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = cleanup_on_signal;
        sigemptyset(&sa.sa_mask);
        (void)sigaction(cleanup_signals[i], &sa, NULL);
    }
}

/* Lists tmp for removal on a signal; -1 when the table is full (the file is then only
 * removed by atomic_commit or atomic_abort). */
static int slot_take(const char *tmp)
{
    install_handlers();
    for (int i = 0; i < ATOMIC_SLOTS; i++) {
        int expect = 0;
        if (atomic_compare_exchange_strong(&slot_state[i], &expect, 1)) {
            snprintf(slot_path[i], sizeof slot_path[i], "%s", tmp);
            atomic_store(&slot_owner[i], t_owner);
            atomic_store(&slot_state[i], 2);
            return i;
        }
    }
    return -1;
}

static void slot_release(atomic_file *f)
{
    int i = f->slot - 1;
    f->slot = 0;
    if (i >= 0 && i < ATOMIC_SLOTS)
        atomic_store(&slot_state[i], 0);
}

/* Splits path into its folder ("." when none) and its last component. */
static brume_status split_path(const char *path, char *dir, size_t dir_size, const char **base)
{
    const char *slash = strrchr(path, '/');
    *base = slash ? slash + 1 : path;
    if (!**base)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: not a file name (ends with '/')", path);
    if (!slash) {
        snprintf(dir, dir_size, ".");
        return BRUME_OK;
    }
    size_t n = (size_t)(slash - path);
    if (n == 0)
        n = 1; /* "/name": the folder is the root */
    if (n >= dir_size)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: path too long", path);
    memcpy(dir, path, n);
    dir[n] = '\0';
    return BRUME_OK;
}

/* The mode a new file would get from open(path, O_CREAT, 0666): mkstemp creates 0600,
 * which would make every image private. The umask can only be read by setting it; the two
 * calls are back to back and brume creates files from one thread at a time. */
static mode_t default_file_mode(void)
{
    mode_t mask = umask(077);
    umask(mask);
    return (mode_t)(0666 & ~mask);
}

/* BRUME_OK when path is absent or a regular file (a symbolic link to one counts: the link is
 * what rename replaces); else a one-line error. */
static brume_status not_regular(const char *path)
{
    struct stat sb;
    if (stat(path, &sb) != 0 || S_ISREG(sb.st_mode))
        return BRUME_OK;
    return err_set(BRUME_ERROR_IO, "%s: not a regular file (%s): brume replaces only regular files", path,
                   S_ISDIR(sb.st_mode) ? "a folder" : S_ISFIFO(sb.st_mode) ? "a pipe" : "a device or socket");
}

brume_status atomic_open_kind(atomic_file *f, const char *path, brume_file_kind kind)
{
    memset(f, 0, sizeof *f);
    if (!path || !*path)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "atomic write: empty path");
    if (strlen(path) >= sizeof f->path)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%.200s...: path too long", path);
    char dir[sizeof f->path];
    const char *base;
    brume_status st = split_path(path, dir, sizeof dir, &base);
    if (st != BRUME_OK)
        return st;
    int n = snprintf(f->tmp_path, sizeof f->tmp_path, "%s/.%s%s", dir, base, tmp_suffix);
    if (n < 0 || (size_t)n >= sizeof f->tmp_path) {
        f->tmp_path[0] = '\0';
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: path too long", path);
    }
    memcpy(f->path, path, strlen(path) + 1);
    if ((st = not_regular(path)) != BRUME_OK || (st = io_target_check(path, path, kind)) != BRUME_OK)
        return st;

    /* blocked while the file is created and listed: a signal in between cannot leave it */
    sigset_t block, prev;
    sigemptyset(&block);
    for (size_t i = 0; i < sizeof cleanup_signals / sizeof cleanup_signals[0]; i++)
        sigaddset(&block, cleanup_signals[i]);
    pthread_sigmask(SIG_BLOCK, &block, &prev);
    int fd = mkstemp(f->tmp_path);
    if (fd >= 0)
        f->slot = slot_take(f->tmp_path) + 1;
    pthread_sigmask(SIG_SETMASK, &prev, NULL);
    if (fd < 0) {
        int e = errno;
        f->tmp_path[0] = '\0';
        return err_set(BRUME_ERROR_IO, "%s: cannot create a temporary file in '%s': %s", path, dir,
                       strerror(e));
    }
    /* Keep the mode of a file being replaced, else what open(2) would have given. */
    struct stat old;
    mode_t mode = stat(path, &old) == 0 && S_ISREG(old.st_mode) ? (mode_t)(old.st_mode & 07777)
                                                               : default_file_mode();
    if (fchmod(fd, mode) != 0) {
        int e = errno;
        close(fd);
        remove(f->tmp_path);
        slot_release(f);
        f->tmp_path[0] = '\0';
        return err_set(BRUME_ERROR_IO, "%s: cannot set the mode of the temporary file: %s", path,
                       strerror(e));
    }
    f->fp = fdopen(fd, "wb");
    if (!f->fp) {
        int e = errno;
        close(fd);
        remove(f->tmp_path);
        slot_release(f);
        f->tmp_path[0] = '\0';
        return err_set(BRUME_ERROR_IO, "%s: cannot open the temporary file: %s", path, strerror(e));
    }
    return BRUME_OK;
}

brume_status atomic_commit(atomic_file *f)
{
    if (!f->tmp_path[0])
        return err_set(BRUME_ERROR_STATE, "%s: atomic write was not opened", f->path);
    const char *what = NULL;
    int e = 0;
    if (f->fp) {
        if (fflush(f->fp) != 0) {
            what = "cannot write";
            e = errno;
        } else if (ferror(f->fp)) {
            what = "cannot write";
            e = EIO;
        } else if (fsync(fileno(f->fp)) != 0) {
            what = "cannot flush to disk";
            e = errno;
        }
        if (fclose(f->fp) != 0 && !what) {
            what = "cannot close";
            e = errno;
        }
        f->fp = NULL;
    }
    if (!what && not_regular(f->path) != BRUME_OK) {
        what = "no longer a regular file: not replaced";
        e = EEXIST;
    }
    if (!what && rename(f->tmp_path, f->path) != 0) {
        what = "cannot rename the temporary file over it";
        e = errno;
    }
    if (what) {
        remove(f->tmp_path);
        slot_release(f);
        f->tmp_path[0] = '\0';
        return err_set(BRUME_ERROR_IO, "%s: %s: %s", f->path, what, strerror(e));
    }
    slot_release(f);
    f->tmp_path[0] = '\0';
    return BRUME_OK;
}

void atomic_abort(atomic_file *f)
{
    if (f->fp) {
        fclose(f->fp);
        f->fp = NULL;
    }
    if (f->tmp_path[0]) {
        remove(f->tmp_path);
        slot_release(f);
        f->tmp_path[0] = '\0';
    }
}

brume_status atomic_open(atomic_file *f, const char *path) { return atomic_open_kind(f, path, BRUME_FILE_ANY); }

const void *atomic_owner(const void *owner)
{
    const void *prev = t_owner;
    t_owner = owner;
    return prev;
}

void atomic_remove_temporaries(const void *owner)
{
    for (int i = 0; i < ATOMIC_SLOTS; i++)
        if (atomic_load(&slot_state[i]) == 2 && (!owner || atomic_load(&slot_owner[i]) == owner))
            (void)unlink(slot_path[i]); /* async-signal-safe */
}

void brume_context_remove_temporaries(brume_context *ctx)
{
    if (ctx)
        atomic_remove_temporaries(ctx);
}

void brume_remove_all_temporaries(void) { atomic_remove_temporaries(NULL); }

brume_status brume_file_write(brume_context *ctx, const char *path, brume_file_kind kind, const void *data,
                              size_t size)
{
    err_clear();
    if (!path || (!data && size > 0))
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_file_write: %s: NULL",
                                       !path ? "path" : "data"));
    if ((unsigned)kind > BRUME_FILE_TEXT)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_file_write: kind: %d unknown", (int)kind));
    const void *owner = atomic_owner(ctx);
    atomic_file f;
    brume_status st = atomic_open_kind(&f, path, kind);
    if (st == BRUME_OK && size > 0 && fwrite(data, 1, size, f.fp) != size) {
        int e = errno;
        atomic_abort(&f);
        st = err_set(BRUME_ERROR_IO, "%s: cannot write: %s", path, strerror(e));
    } else if (st == BRUME_OK) {
        st = atomic_commit(&f);
    }
    atomic_owner(owner);
    return ctx_report(ctx, st);
}
