/* cli_read_ahead.c - the next frame of a sequence read while the current one renders
 * (cli_read_ahead.h).
 *
 * A frame of a sequence whose world moves is a scene of its own: reading its grids (a .vdb
 * through the sandboxed OpenVDB reader) and committing it (majorants, moved majorants) is
 * work the render does not need, so it runs on one thread beside the render's, with its own
 * context. The scene it makes is the one the render loop would make after the frame: the
 * same files, options and settings, and brume_load_options.memory_held only refuses, never
 * changes, what is built (core/budget.h). So the images are the same bytes with or without
 * it; only the time differs. At most two frames' scenes live at once: the one rendering
 * and the next. */
#include "cli_read_ahead.h"

static void *read_main(void *arg)
{
    cli_read_ahead *ra = arg;
    ra->scene = ra->load(ra->ctx, ra->user, ra->frame, ra->held);
    return NULL;
}

/* Cancels and waits for a read under way, and releases what it read. */
static void stop(cli_read_ahead *ra)
{
    if (ra->running) {
        brume_context_cancel_loads(ra->ctx);
        pthread_join(ra->thread, NULL);
        ra->running = false;
    }
    brume_scene_release(ra->scene);
    ra->scene = NULL;
}

bool cli_read_ahead_start(cli_read_ahead *ra, const brume_scene *current, long frame, const char **why)
{
    stop(ra); /* nothing is left of an earlier read */
    size_t limit = 0;
    size_t used = brume_scene_memory(current, &limit);
    if (used > limit / 2) {
        *why = "no (two frames' grids would pass render.max_memory_mb)";
        return false;
    }
    if (!ra->ctx && !(ra->ctx = brume_context_new())) {
        *why = "no (out of memory)";
        return false;
    }
    ra->frame = frame;
    ra->held = used;
    ra->scene = NULL;
    if (pthread_create(&ra->thread, NULL, read_main, ra) != 0) {
        *why = "no (no thread)";
        return false;
    }
    ra->running = true;
    return true;
}

brume_scene *cli_read_ahead_take(cli_read_ahead *ra, long frame)
{
    if (!ra->running)
        return NULL;
    pthread_join(ra->thread, NULL);
    ra->running = false;
    brume_scene *s = ra->scene;
    ra->scene = NULL;
    if (s && ra->frame != frame) {
        brume_scene_release(s);
        s = NULL;
    }
    return s;
}

void cli_read_ahead_end(cli_read_ahead *ra)
{
    stop(ra);
    brume_context_release(ra->ctx);
    ra->ctx = NULL;
}
