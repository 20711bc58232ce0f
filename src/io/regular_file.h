/* regular_file.h - opening an input file that a scene or a grid names: regular files only.
 *
 * A path in a scene may name anything: a FIFO would block the open itself, a terminal
 * (/dev/stdin, /dev/tty) would wait for a person, /dev/zero never ends. Readers therefore
 * open their inputs with io_open_regular, which never blocks and refuses anything but a
 * regular file with one line naming the path. */
#ifndef BRUME_IO_REGULAR_FILE_H
#define BRUME_IO_REGULAR_FILE_H

#include <stdio.h>

#include "brume.h"

/* *out: path opened for reading (binary); BRUME_ERROR_IO with err_set() when it cannot be
 * opened or is not a regular file. */
brume_status io_open_regular(const char *path, FILE **out);

#endif
