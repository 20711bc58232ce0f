/* cli_read_ahead.h - `brume render` over a sequence: the next frame's scene (its grids) read
 * and committed on a thread while the current frame renders (cli/cli_read_ahead.c,
 * docs/production.md "Sequences"). */
#ifndef BRUME_CLI_READ_AHEAD_H
#define BRUME_CLI_READ_AHEAD_H

#include <pthread.h>
#include <stdbool.h>
#include <stddef.h>

#include "brume.h"

/* Loads and commits frame `frame` with ctx, counting `held` bytes of another scene against
 * its memory limit (brume_load_options.memory_held); NULL on failure (ctx has the message).
 * Called on the read-ahead thread: it may read only what does not change while it runs. */
typedef brume_scene *(*cli_load_fn)(brume_context *ctx, const void *user, long frame, size_t held);

typedef struct cli_read_ahead {
    cli_load_fn load;
    const void *user;
    brume_context *ctx; /* the thread's own (made on the first start): its errors are not the render's */
    pthread_t thread;
    bool running;       /* a thread started and not yet joined */
    long frame;         /* the frame it reads */
    size_t held;
    brume_scene *scene; /* what it read, or NULL */
} cli_read_ahead;

/* Starts reading `frame` beside the committed scene `current` (the frame about to render)
 * when the memory limit holds both: twice the current scene's bytes (brume_scene_memory)
 * within its limit, and the read itself refused past it. true when a thread started (*why
 * unchanged); false with *why saying why not (nothing is read ahead: the frame is read
 * after, as without). */
bool cli_read_ahead_start(cli_read_ahead *ra, const brume_scene *current, long frame, const char **why);
/* Waits for the read under way and gives `frame`'s committed scene to the caller, or NULL:
 * none started, another frame, or the read failed (then the caller reads the frame again,
 * which reports its own error in one line). */
brume_scene *cli_read_ahead_take(cli_read_ahead *ra, long frame);
/* Ends a read under way (brume_context_cancel_loads: a sandboxed reader is killed), waits
 * for its thread, releases what it read and its context. Safe on a zeroed struct. */
void cli_read_ahead_end(cli_read_ahead *ra);

#endif
