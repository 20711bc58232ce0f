/* grid_sequence.h - frame sequences of grid files: a file name with a frame pattern
 * (smoke_%04d.vdb, smoke_####.vdb, smoke_$F4.vdb) names one file per frame (docs/grids.md,
 * "Sequences"). The files present in the folder make the sequence's range; a gap in it is an
 * error naming the first missing frame. */
#ifndef BRUME_IO_GRID_SEQUENCE_H
#define BRUME_IO_GRID_SEQUENCE_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

/* What a frame beyond the files takes. */
typedef enum seq_beyond {
    SEQ_REFUSE = 0, /* an error naming the frame and the range */
    SEQ_HOLD,       /* the first or the last file */
    SEQ_LOOP        /* the range repeats */
} seq_beyond;

/* File number n = offset + step x frame (frame: the scene's frame number). */
typedef struct seq_options {
    long offset;
    long step;
    seq_beyond beyond;
} seq_options;

/* 1 when the file name (the part after the last '/') holds one frame pattern, 0 when none,
 * -1 (err_set naming `name`) when it holds a malformed one or more than one. */
int seq_is_pattern(const char *name);
/* The name with n in place of the pattern (zero-padded to its width; wider when n needs
 * it). Requires seq_is_pattern(pattern) == 1. */
void seq_name(const char *pattern, long n, char *out, size_t cap);
/* The range of files present: the smallest and largest number in the folder; a gap is an
 * error naming the first missing number and its file, no file at all an error too. */
brume_status seq_range(const char *pattern, long *first, long *last);
/* The file of frame `frame`: out gets its path. Errors name the pattern and the frame. */
brume_status seq_file(const char *pattern, const seq_options *o, long frame_no, char *out, size_t cap);
/* Parses "refuse", "hold", "loop"; false when unknown. */
bool seq_beyond_from_name(const char *s, seq_beyond *out);

#endif
