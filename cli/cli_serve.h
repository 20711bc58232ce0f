/* cli_serve.h - the live view of `brume render --serve`: an HTTP server (libmicrohttpd) on
 * its own thread that shows a render job while it runs and after (cli/cli_serve.c). */
#ifndef BRUME_CLI_SERVE_H
#define BRUME_CLI_SERVE_H

#include "brume.h"

typedef struct cli_serve cli_serve;

/* Listens on "[HOST:]PORT" (HOST defaults to 127.0.0.1; port 0 picks a free one) and starts
 * serving; NULL with a one-line message (bad host, port in use). */
cli_serve *cli_serve_start(const char *spec);
/* "http://ADDRESS:PORT/" actually listened on. */
const char *cli_serve_url(const cli_serve *sv);
/* Shows `job` from now on (NULL: none); the job must stay alive until it is replaced. */
void cli_serve_show(cli_serve *sv, const brume_render_job *job, const char *label);
void cli_serve_stop(cli_serve *sv);

#endif
