/* blob_gen.c - generators of blob fields (Stam 1994, Section 7): a cloud from a user's
 * ellipsoid (after Gardner 1985), clusters of such clouds, and a flame. Every random number
 * comes from a counter-based stream of the seed, so a generator's output depends on its
 * parameters only. */
#include <stdlib.h>

#include "core/budget.h"
#include "core/cancel.h"
#include "core/error.h"
#include "core/rng.h"
#include "density/blobs.h"

/* (2 pi)^(3/2): a blob of radius h and peak density rho has mass rho (2 pi)^(3/2) h^3 */
#define TWO_PI_3_2 15.749609945722419

brume_status blob_list_push(blob_list *l, blob b)
{
    if (l->n == l->cap) {
        int cap = l->cap ? 2 * l->cap : 64;
        if (cap > BLOB_MAX_COUNT)
            return err_set(BRUME_ERROR_RANGE, "blobs: more than %d blobs", BLOB_MAX_COUNT);
        /* the list and, once built, the field with its hierarchy: counted before allocating */
        if (budget_take((size_t)(cap - l->cap) * BLOB_BYTES, "blobs") != BRUME_OK)
            return err_status();
        blob *nb = realloc(l->b, (size_t)cap * sizeof *nb);
        if (!nb)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "blobs: out of memory for %d blobs", cap);
        l->b = nb;
        l->cap = cap;
    }
    l->b[l->n++] = b;
    return BRUME_OK;
}

void blob_list_free(blob_list *l)
{
    free(l->b);
    *l = (blob_list){0};
}

/* A uniform point in the unit ball by rejection. */
static vec3 unit_ball(rng *g)
{
    for (;;) {
        vec3 p = v3(2.0 * rng_next(g) - 1.0, 2.0 * rng_next(g) - 1.0, 2.0 * rng_next(g) - 1.0);
        if (v3_dot(p, p) <= 1.0)
            return p;
    }
}

static brume_status cloud_with_stream(const blob_cloud_params *p, uint64_t stream, blob_list *out)
{
    if (p->count < 1 || !(p->h_min > 0.0) || !(p->h_max >= p->h_min) || !(p->density >= 0.0) ||
        !(p->falloff >= 0.0) || !(p->radii.x > 0.0 && p->radii.y > 0.0 && p->radii.z > 0.0))
        return err_set(BRUME_ERROR_RANGE, "cloud: need count >= 1, 0 < h_min <= h_max, radii > 0, density >= 0");
    rng g = rng_make(p->seed, stream, 0);
    for (int i = 0; i < p->count; i++) {
        if ((i & 0xffff) == 0 && cancel_load_check("blob cloud") != BRUME_OK)
            return BRUME_ERROR_CANCELLED;
        vec3 u = unit_ball(&g);
        double s = v3_length(u);
        double h = p->h_max + (p->h_min - p->h_max) * s;
        double rho = p->density * pow(fmax(0.0, 1.0 - s * s), p->falloff);
        blob b = {v3_add(p->center, v3_mul(u, p->radii)), rho * TWO_PI_3_2 * h * h * h, h};
        brume_status st = blob_list_push(out, b);
        if (st)
            return st;
    }
    return BRUME_OK;
}

brume_status blob_gen_cloud(const blob_cloud_params *p, blob_list *out) { return cloud_with_stream(p, 0, out); }

brume_status blob_gen_cluster(const blob_cloud_params *tmpl, box3 box, vec3 radii_min, vec3 radii_max, int clouds,
                              blob_list *out)
{
    if (clouds < 1)
        return err_set(BRUME_ERROR_RANGE, "cluster: need at least one cloud");
    rng g = rng_make(tmpl->seed, 0x636c7573ULL, 0);
    for (int c = 0; c < clouds; c++) {
        blob_cloud_params p = *tmpl;
        double t = rng_next(&g);
        p.center = v3(box.lo.x + rng_next(&g) * (box.hi.x - box.lo.x), box.lo.y + rng_next(&g) * (box.hi.y - box.lo.y),
                      box.lo.z + rng_next(&g) * (box.hi.z - box.lo.z));
        p.radii = v3_add(radii_min, v3_scale(v3_sub(radii_max, radii_min), t));
        /* smaller clouds have smaller blobs */
        double scale = v3_length(p.radii) / v3_length(radii_max);
        p.h_min *= scale;
        p.h_max *= scale;
        brume_status st = cloud_with_stream(&p, (uint64_t)c + 1, out);
        if (st)
            return st;
    }
    return BRUME_OK;
}

brume_status blob_gen_fire(const blob_fire_params *p, blob_list *out)
{
    if (p->count < 1 || !(p->height > 0.0) || !(p->radius >= 0.0) || !(p->h > 0.0) || !(p->density >= 0.0) ||
        !(v3_length(p->up) > 0.0))
        return err_set(BRUME_ERROR_RANGE, "fire: need count >= 1, height > 0, radius >= 0, h > 0, density >= 0");
    vec3 up = v3_normalize(p->up);
    frame f = frame_from_n(up);
    rng g = rng_make(p->seed, 0x66697265ULL, 0);
    for (int i = 0; i < p->count; i++) {
        /* stratified heights: blob i in the i-th slice of the flame */
        double s = (i + rng_next(&g)) / p->count;
        double r = p->radius * sqrt(rng_next(&g)) * pow(1.0 - s, 0.7);
        double phi = 2.0 * PI * rng_next(&g);
        if (!(s >= p->band_lo && s < p->band_hi))
            continue;
        double h = p->h * (1.0 - 0.6 * s);
        double rho = p->density * (1.0 - 0.7 * s);
        vec3 x = v3_add(p->base, v3_scale(up, s * p->height));
        x = v3_add(x, v3_add(v3_scale(f.s, r * cos(phi)), v3_scale(f.t, r * sin(phi))));
        brume_status st = blob_list_push(out, (blob){x, rho * TWO_PI_3_2 * h * h * h, h});
        if (st)
            return st;
    }
    return BRUME_OK;
}
