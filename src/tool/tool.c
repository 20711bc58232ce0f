/* tool.c - phase functions by name and the slab (brume.h). */
#include "brume.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "phase/phase.h"
#include "render/slab.h"
#include "scene/scene_build.h"


brume_status brume_phase_new_named(brume_context *ctx, const char *name, brume_phase **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (!name || !out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_phase_new_named: %s: NULL",
                                       !name ? "name" : "out"));
    phase *p = phase_new_from_name(name);
    brume_phase *h = p ? malloc(sizeof *h) : NULL;
    if (!h) {
        if (p) {
            phase_release(p);
            err_set(BRUME_ERROR_OUT_OF_MEMORY, "brume_phase_new_named: out of memory");
        }
        return ctx_report(ctx, err_status());
    }
    h->p = p;
    *out = h;
    return ctx_report(ctx, BRUME_OK);
}

double brume_schlick_k_from_g(double g)
{
    if (isnan(g))
        return 0.0;
    double k = phase_schlick_k_from_g(g);
    return fmin(0.999999, fmax(-0.999999, k)); /* what brume_phase_new_schlick takes */
}

brume_status brume_slab_run(brume_context *ctx, const brume_slab_params *p, brume_slab_result *out)
{
    err_clear();
    if (out)
        memset(out, 0, sizeof *out);
    if (!p || !p->phase || !out)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_slab_run: %s: NULL",
                                       !p ? "params" : !p->phase ? "params->phase" : "out"));
    if (p->threads < 0 || p->threads > 1024)
        return ctx_report(ctx, err_set(BRUME_ERROR_RANGE, "brume_slab_run: threads: %d outside [0, 1024]", p->threads));
    slab_params sp = {.albedo = p->albedo, .tau = p->tau, .ph = p->phase->p, .samples = p->samples, .seed = p->seed,
                      .threads = p->threads, .max_depth = p->max_depth};
    slab_result r;
    brume_status st = slab_run(&sp, &r);
    if (st == BRUME_OK)
        *out = (brume_slab_result){r.Rd, r.Rd_stderr, r.Tt, r.Tt_stderr};
    return ctx_report(ctx, st);
}
