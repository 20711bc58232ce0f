/* error.h - status codes and the last-error message of the calling thread.
 *
 * Every fallible internal function returns a brume_status and, on failure, sets a one-line
 * message with err_set() that names the file and the field or key at fault, e.g.
 *   "scene.json: camera.fov: expected a number in (0, 180), got 400"
 * The message is thread-local; the public API copies it into the context it was called
 * with (brume_context_last_error) and hands it to the context's error callback. */
#ifndef BRUME_CORE_ERROR_H
#define BRUME_CORE_ERROR_H

#include <stdarg.h>
#include <stddef.h>

#include "brume.h"

#if defined(__GNUC__)
#define BRUME_PRINTF(a, b) __attribute__((format(printf, a, b)))
#else
#define BRUME_PRINTF(a, b)
#endif

/* Longest string argument (bytes) a message quotes; longer ones are cut and end in "...". */
#define ERR_ARG_MAX 200

/* printf-style formatting into out[n] as every message is formatted: string arguments
 * (%s, %c) have control characters escaped (\n, \t, \x1b, ...) and a plain %s is cut after
 * ERR_ARG_MAX bytes (keys, names and values quoted from input); a %s with an explicit
 * precision ("%.1000s") is cut at that precision instead: the form for passing on a whole
 * message formatted before. Control characters in fmt itself become spaces. One line.
 * Numbers are printed in the "C" locale, and a plain "%.17g" prints the fewest digits that
 * read back as the same double: the form for a value checked against a limit and for the
 * limit itself ("render.spp: 16777217 outside [1, 16777216]"). */
void err_vformat(char *out, size_t n, const char *fmt, va_list ap);
void err_format(char *out, size_t n, const char *fmt, ...) BRUME_PRINTF(3, 4);

/* Record status and message (printf format) for this thread; returns status. */
brume_status err_set(brume_status status, const char *fmt, ...) BRUME_PRINTF(2, 3);
brume_status err_vset(brume_status status, const char *fmt, va_list ap);
/* This thread's last message ("" when none). */
const char *err_message(void);
/* Prepends "PREFIX: " (printf format) to this thread's message; returns its status. */
brume_status err_prefix(const char *fmt, ...) BRUME_PRINTF(1, 2);
brume_status err_status(void);
void err_clear(void);

#endif
