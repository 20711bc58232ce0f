/* tool.c - the brume tool's messages and output checks over the library's internals
 * (tool.h). */
#include "tool/tool.h"

#include "core/error.h"
#include "core/regular_file.h"
#include "job/checkpoint.h"

void tool_vformat(char *out, size_t n, const char *fmt, va_list ap) { err_vformat(out, n, fmt, ap); }

const char *tool_last_error(void) { return err_message(); }

void tool_clear_error(void) { err_clear(); }

brume_status tool_output_check(const char *what, const char *path, const char *scene_file, const brume_scene *scene)
{
    return scene ? checkpoint_output_check(scene, what, path) : io_output_check(what, path, scene_file, NULL);
}

brume_status tool_checkpoint_target_check(const char *path) { return checkpoint_target_check(path); }

uint64_t tool_checkpoint_inputs_key(const brume_scene *scene, uint64_t h) { return checkpoint_inputs_key(scene, h); }

bool tool_checkpoint_remove_own(const brume_render_job *job, uint64_t scene_key, const char *path)
{
    return checkpoint_remove_own(job, scene_key, path);
}
