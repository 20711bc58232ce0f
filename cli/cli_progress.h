/* cli_progress.h - what `brume render` shows of a render as it goes: a bar redrawn in place
 * when stderr is a terminal, else a line every few seconds (a log), and why it stopped
 * (cli/cli_progress.c). The figures are the library's (brume_render_job_progress); this file
 * only draws them. */
#ifndef BRUME_CLI_PROGRESS_H
#define BRUME_CLI_PROGRESS_H

#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

#define CLI_PROGRESS_LOG_SECONDS 10.0 /* between two log lines by default (Cycles and pbrt log alike) */

/* Starts the display of one render: a bar on a terminal, else a line every log_seconds
 * (0: CLI_PROGRESS_LOG_SECONDS; < 0: none off a terminal); nothing when !enabled. */
void cli_progress_begin(bool enabled, double log_seconds);
/* From the render's progress callback (never two at once): redraws when due, ten times a
 * second on a terminal, once per interval in a log, with job's figures; job NULL: the
 * render has no job yet (a light pass before the first tile), shown with its elapsed time. */
void cli_progress_tick(const brume_render_job *job);
/* Ends the display: the bar drawn once more with the job's last figures ("done" when it is
 * finished, else as far as it got) and a newline; a log gets no last line. */
void cli_progress_end(const brume_render_job *job);

/* Why a render stopped, as the end-of-run line says it ("every pixel met the 3 % noise
 * target", "the 20 s time budget ran out", ...), into buf of size n; "" while it runs. */
void cli_progress_stop_reason(const brume_render_progress *p, const brume_render_settings *rs, char *buf, size_t n);

#endif
