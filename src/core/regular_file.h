/* regular_file.h - the files a scene reads and the files brume writes: regular files only.
 *
 * Reading: a path in a scene may name anything: a FIFO would block the open itself, a
 * terminal (/dev/stdin, /dev/tty) would wait for a person, /dev/zero never ends. Readers
 * therefore open their inputs with io_open_regular, which never blocks and refuses anything
 * but a regular file with one line naming the path.
 *
 * Inputs: while a thread records (io_inputs_record, around the loading of one scene), every
 * file opened by io_open_regular or named by io_input_note is listed once (by device and
 * inode), so that the scene knows what it was made from: the checkpoint key hashes their
 * contents (io_inputs_hash) and no output may replace one of them (io_output_check).
 *
 * Writing: brume replaces only regular files (io/atomic.c refuses anything else), and the
 * outputs a user names are checked before any work by io_output_check. */
#ifndef BRUME_CORE_REGULAR_FILE_H
#define BRUME_CORE_REGULAR_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>

#include "brume.h"

/* *out: path opened for reading (binary); BRUME_ERROR_IO with err_set() when it cannot be
 * opened or is not a regular file. */
brume_status io_open_regular(const char *path, FILE **out);

/* io_open_regular for the input a key names: the message reads "PATH: WHAT: reason". */
brume_status io_open_input(const char *path, const char *what, FILE **out);

/* Whether the file opened as fp (named path) holds at most max_bytes: a reader's plausible
 * size, checked before it reads (a sparse file of a terabyte is a regular file too). One line
 * naming what (the key or the kind of file), BRUME_ERROR_RANGE, when it holds more. */
brume_status io_check_size(FILE *fp, const char *path, const char *what, long long max_bytes);

typedef struct io_input {
    char *path; /* owned: as the scene named it (resolved against the scene's folder) */
    dev_t dev;
    ino_t ino;
} io_input;

typedef struct io_inputs {
    io_input *v; /* owned */
    size_t n, cap;
    bool oom; /* a note was lost to a failed allocation: the list is incomplete */
} io_inputs;

/* From now on this thread lists the files it opens in *rec (NULL: stops). Not nested. */
void io_inputs_record(io_inputs *rec);
/* Lists path (a regular file, else nothing) in the recording list, if any; readers that do not
 * open through io_open_regular (the OpenVDB child, assimp) call it for the file they read. */
void io_input_note(const char *path);
void io_inputs_free(io_inputs *rec);
/* FNV-1a folded over every input's bytes in list order, starting from h; an input that cannot
 * be read folds its errno instead (the key then differs from a run that could read it). */
uint64_t io_inputs_hash(const io_inputs *rec, uint64_t h);

/* Whether brume may write `path` (named by `what`, "-o" or "--checkpoint" or a scene key) as a
 * file of `kind`: absent, or a regular file that is neither scene_file (may be NULL), nor one
 * of *inputs (may be NULL), nor one of others[0..nothers-1] (the command's other inputs and
 * outputs; NULL entries skipped), and that holds nothing (0 bytes) or content of the kind
 * being written (io_target_check). Otherwise a one-line BRUME_ERROR_INVALID_ARGUMENT (err_set)
 * naming both. */
brume_status io_output_check(const char *what, const char *path, brume_file_kind kind, const char *scene_file,
                             const io_inputs *inputs, const char *const *others, int nothers);

/* Whether path may be replaced by a file of kind: absent, empty, or holding that kind (by its
 * first bytes: a brume checkpoint, a brume light file, an EXR, PNG or PFM image, a .vol,
 * NanoVDB or OpenVDB grid, or for a .raw or .df3 name, which have no magic number, anything but
 * the others; text for BRUME_FILE_TEXT; anything for BRUME_FILE_ANY). Otherwise a one-line
 * BRUME_ERROR_INVALID_ARGUMENT naming what path holds. */
brume_status io_target_check(const char *what, const char *path, brume_file_kind kind);

/* Whether a and b name the same file: the same device and inode when both exist, else the same
 * name in the same folder (folders compared by realpath when they exist). */
bool io_same_file(const char *a, const char *b);

#endif
