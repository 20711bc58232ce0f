/* stam_media.c - what Stam's options do to a scene's blob fields when it is committed:
 * the drift of the blobs to the scene's time (stam.time + the frame time), the choice of
 * blob lookup (stam.bvh), and with stam.voxelize.resolution the replacement of every blob
 * field by a dense grid of its mean or of one realization (for the reference renderers). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

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

static brume_status voxelize_media(brume_scene *s, const stam_params *p)
{
    randfield *q = NULL;
    if (p->voxelize_realization) {
        randfield_params rp;
        stam_randfield_params(p, s->time, stam_blob_extent(s), &rp);
        if (!(q = randfield_new(&rp)))
            return err_prefix("%s: stam.voxelize", s->source);
    }
    brume_status st = BRUME_OK;
    for (int m = 0; m < s->nmedia && st == BRUME_OK; m++) {
        blob_field *f = density_get_blobs(s->media[m].rho);
        if (!f)
            continue;
        char who[600];
        snprintf(who, sizeof who, "%s: stam.voxelize", s->source);
        density *g = blob_field_grid(f, p->voxelize_resolution, q, p->eps, p->eta, who);
        if (!g) {
            st = err_status();
            break;
        }
        density_release(s->media[m].rho);
        s->media[m].rho = g;
    }
    randfield_release(q);
    return st;
}

brume_status stam_commit_media(brume_scene *s)
{
    const stam_params *p = scene_options(s, METHOD_OPTIONS_STAM);
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
