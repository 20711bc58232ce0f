/* atomic.h - write a file so that it appears whole or not at all.
 *
 * atomic_open creates a temporary file beside the destination (same folder, so rename is
 * atomic); the writer writes it, by fp or by tmp_path; atomic_commit flushes, closes and
 * renames it over the destination; atomic_abort closes and removes it. */
#ifndef BRUME_IO_ATOMIC_H
#define BRUME_IO_ATOMIC_H

#include <stdio.h>

#include "brume.h"

typedef struct atomic_file {
    char path[4096];     /* destination */
    char tmp_path[4096]; /* "<dir>/.<name>.tmp-XXXXXX" */
    FILE *fp;            /* open for writing, binary */
    int slot;            /* private: 1 + index in atomic.c's table of files removed on a signal */
} atomic_file;

/* Refuses (one line, nothing created) a path that exists and is not a regular file, or holds
 * content of another kind than the file being written (io_target_check: a light file replaces
 * only a light file). Every writer of the library names its kind; atomic_open is
 * BRUME_FILE_ANY, for tests of the mechanism. */
brume_status atomic_open_kind(atomic_file *f, const char *path, brume_file_kind kind);
brume_status atomic_open(atomic_file *f, const char *path);
/* Closes fp if open, then renames. On failure the temporary file is removed. */
brume_status atomic_commit(atomic_file *f);
void atomic_abort(atomic_file *f);

/* Temporary files are listed with the context whose call made them (brume_image_write,
 * brume_render_job_save, a render's blasi.save_light): those public calls name their
 * context for the calling thread with atomic_owner (it returns the previous one, to put
 * back), and brume_context_remove_temporaries(ctx) removes the files listed with ctx.
 * atomic_remove_temporaries(NULL) removes every listed file, whoever made it: what a
 * program's own fatal-signal handler calls (the command-line tool's). Both are
 * async-signal-safe. */
const void *atomic_owner(const void *owner);
void atomic_remove_temporaries(const void *owner);

#endif
