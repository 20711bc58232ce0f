/* stam_media.c - what Stam's options do to a scene's blob fields when it is committed:
 * the drift of the blobs to the scene's time (stam.time + the frame time), the choice of
 * blob lookup (stam.bvh), and with stam.voxelize.resolution the replacement of every blob
 * field by a dense grid of its mean or of one realization (for the reference renderers). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/error.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "method/stam_params.h"
#include "scene/stam_media.h"

vec3 stam_blob_extent(const brume_scene *s)
{
    box3 b = box3_empty();
    for (int m = 0; m < s->nmedia; m++) {
        const blob_field *f = density_get_blobs(s->media[m].rho);
        if (f) {
            b.lo = v3_min(b.lo, f->bounds.lo);
            b.hi = v3_max(b.hi, f->bounds.hi);
        }
    }
    return b.lo.x <= b.hi.x ? v3_sub(b.hi, b.lo) : v3(0, 0, 0);
}

randfield *stam_scene_randfield(const brume_scene *s)
{
    randfield_params rp;
    stam_randfield_params(scene_options(s, METHOD_OPTIONS_STAM), s->time, stam_blob_extent(s), &rp);
    /* the work before it starts (render.max_work): a mode drawn per lattice point,
     * then the FFT's log2(points) butterflies per point */
    double points = (double)rp.n[0] * rp.n[1] * rp.n[2], work = points * (1.0 + log2(points));
    if (work > s->max_work) {
        err_set(BRUME_ERROR_RANGE,
                "stam.lattice: the random field's %d x %d x %d lattice points are %.3g units of work (the FFT's "
                "log2 per point), over render.max_work (%.3g): lower stam.lattice or raise stam.cell (or raise "
                "render.max_work)",
                rp.n[0], rp.n[1], rp.n[2], work, s->max_work);
        return NULL;
    }
    /* its loops ask the render's progress callback too: a 512^3 lattice takes minutes,
     * and the library's cancel stops it within a second */
    cancel_poll cancel;
    cancel_poll_init(&cancel, &s->settings);
    cancel_load_watch(&cancel);
    randfield *q = randfield_new(&rp);
    cancel_load_watch(NULL);
    cancel_poll_finish(&cancel);
    return q;
}

brume_status stam_voxelize_blobs(const brume_scene *s, int resolution, bool realization, const char *option,
                                 density *grids[SCENE_MAX_MEDIA])
{
    const stam_params *p = scene_options(s, METHOD_OPTIONS_STAM);
    for (int m = 0; m < SCENE_MAX_MEDIA; m++)
        grids[m] = NULL;
    randfield *q = NULL; /* one Q for all the fields, made at the first (with eps = 0 it adds nothing) */
    brume_status st = BRUME_OK;
    for (int m = 0; m < s->nmedia && st == BRUME_OK; m++) {
        const blob_field *f = density_get_blobs(s->media[m].rho);
        if (!f)
            continue;
        if (!q && realization && p->eps > 0.0 && !(q = stam_scene_randfield(s))) {
            st = err_prefix("%s: %s", s->source, option);
            break;
        }
        char who[600];
        snprintf(who, sizeof who, "%s: media[%d]: %s", s->source, m, option);
        if (!(grids[m] = blob_field_grid(f, resolution, q, p->eps, p->eta, who)))
            st = err_status();
    }
    randfield_release(q);
    for (int m = 0; m < s->nmedia && st != BRUME_OK; m++) {
        density_release(grids[m]);
        grids[m] = NULL;
    }
    return st;
}

/* stam.voxelize: every blob field replaced by its grid. */
static brume_status voxelize_media(brume_scene *s, const stam_params *p)
{
    density *grids[SCENE_MAX_MEDIA];
    if (stam_voxelize_blobs(s, p->voxelize_resolution, p->voxelize_realization, "stam.voxelize", grids) != BRUME_OK)
        return err_status();
    for (int m = 0; m < s->nmedia; m++)
        if (grids[m]) {
            density_release(s->media[m].rho);
            s->media[m].rho = grids[m];
        }
    return BRUME_OK;
}

/* stam.kernel: every blob field takes the kernel read from stam.kernel_file. */
static brume_status set_kernel(brume_scene *s, const stam_params *p)
{
    if (p->kernel == STAM_KERNEL_GAUSSIAN) {
        if (p->kernel_file[0])
            return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                           "%s: stam.kernel_file: given, but stam.kernel is gaussian (set stam.kernel = table to use it)",
                           s->source);
        return BRUME_OK;
    }
    if (!p->kernel_file[0])
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: stam.kernel: table needs stam.kernel_file", s->source);
    blob_kernel *k = blob_kernel_read(p->kernel_file, "stam.kernel_file");
    if (!k)
        return err_status();
    brume_status st = budget_take((size_t)(k->n + 2 + (BLOB_KERNEL_G + 1) * (BLOB_KERNEL_G + 1)) * sizeof(double),
                                  "stam.kernel_file");
    for (int m = 0; m < s->nmedia && st == BRUME_OK; m++)
        if (density_get_blobs(s->media[m].rho) && density_blobs_set_kernel(s->media[m].rho, k) != BRUME_OK)
            st = err_prefix("%s: media[%d]", s->source, m);
    blob_kernel_release(k); /* the fields hold it */
    return st;
}

brume_status stam_commit_media(brume_scene *s)
{
    const stam_params *p = scene_options(s, METHOD_OPTIONS_STAM);
    if (set_kernel(s, p) != BRUME_OK)
        return err_status();
    double t = p->time + s->time;
    for (int m = 0; m < s->nmedia; m++) {
        blob_field *f = density_get_blobs(s->media[m].rho);
        if (!f)
            continue;
        f->use_bvh = p->bvh;
        if (t != 0.0 && v3_length(f->velocity) > 0.0 && density_blobs_at_time(s->media[m].rho, f->velocity, t))
            return err_prefix("%s: media[%d]", s->source, m);
    }
    return p->voxelize_resolution > 0 ? voxelize_media(s, p) : BRUME_OK;
}

bool stam_media_move(const brume_scene *s)
{
    const stam_params *p = scene_options(s, METHOD_OPTIONS_STAM);
    for (int m = 0; m < s->nmedia; m++) {
        const blob_field *f = density_get_blobs(s->media[m].rho);
        if (f && (v3_length(f->velocity) > 0.0 || p->rate > 0.0))
            return true;
    }
    return false;
}
