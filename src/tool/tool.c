/* tool.c - the brume tool's messages, output checks, phase functions and slab over the
 * library's internals (tool.h). */
#include "tool/tool.h"

#include <stdlib.h>

#include "core/error.h"
#include "core/regular_file.h"
#include "io/atomic.h"
#include "io/grid_sequence.h"
#include "job/checkpoint.h"
#include "phase/phase.h"
#include "render/slab.h"

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

phase *tool_phase_named(const char *name) { return phase_new_from_name(name); }

phase *tool_phase_hg(double g) { return phase_new_hg(g); }

phase *tool_phase_schlick(double k) { return phase_new_schlick(k); }

phase *tool_phase_schlick_mix(double r, double k, double kprime) { return phase_new_schlick_mix(r, k, kprime); }

void tool_phase_release(phase *p) { phase_release(p); }

double tool_schlick_k_from_g(double g) { return phase_schlick_k_from_g(g); }

brume_status tool_slab_run(const tool_slab_params *p, tool_slab_result *out)
{
    slab_params sp = {.albedo = p->albedo, .tau = p->tau, .ph = p->ph, .samples = p->samples, .seed = p->seed,
                      .threads = p->threads, .max_depth = p->max_depth};
    slab_result r;
    brume_status st = slab_run(&sp, &r);
    if (st == BRUME_OK)
        *out = (tool_slab_result){r.Rd, r.Rd_stderr, r.Tt, r.Tt_stderr};
    return st;
}

struct tool_file {
    atomic_file af;
};

tool_file *tool_file_open(const char *path)
{
    tool_file *f = malloc(sizeof *f);
    if (!f) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
        return NULL;
    }
    if (atomic_open(&f->af, path) != BRUME_OK) {
        free(f);
        return NULL;
    }
    return f;
}

FILE *tool_file_stream(tool_file *f) { return f->af.fp; }

void tool_remove_temporaries(void) { atomic_remove_temporaries(NULL); }

const char *tool_file_by_name(tool_file *f)
{
    if (f->af.fp)
        fclose(f->af.fp);
    f->af.fp = NULL;
    return f->af.tmp_path;
}

brume_status tool_file_commit(tool_file *f)
{
    brume_status st = atomic_commit(&f->af);
    free(f);
    return st;
}

void tool_file_abort(tool_file *f)
{
    if (!f)
        return;
    atomic_abort(&f->af);
    free(f);
}

int tool_seq_is_pattern(const char *name) { return seq_is_pattern(name); }

void tool_seq_name(const char *pattern, long n, char *out, size_t cap) { seq_name(pattern, n, out, cap); }

brume_status tool_seq_range(const char *pattern, long *first, long *last) { return seq_range(pattern, first, last); }
