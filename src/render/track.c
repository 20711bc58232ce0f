/* track.c - the scene's media at a point, tentative collisions, ratio tracking. */
#include "render/track.h"

#include "core/sampling.h"
#include "core/stats.h"

void media_at(const brume_scene *s, uint32_t absent, vec3 p, double time, medium_sample *ms)
{
    ms->sigma_a = col(0.0);
    ms->sigma_s = col(0.0);
    ms->emission = col(0.0);
    ms->n = 0;
    if (stats_tls)
        stats_tls->density_lookups++;
    /* Velocity motion blur (medium.h): fields are read back along the velocity over the
     * time since the frame's, clamped to the shutter, the interval the moved majorants
     * (md->moved) were built for. */
    double dt = time - s->time;
    dt = dt < s->cam.shutter_open ? s->cam.shutter_open : (dt > s->cam.shutter_close ? s->cam.shutter_close : dt);
    for (int m = 0; m < s->nmedia; m++) {
        medium_coeffs mc;
        if ((absent >> m & 1u) || !medium_coeffs_at(&s->media[m], p, time, dt, &mc))
            continue;
        ms->sigma_a = col_add(ms->sigma_a, mc.sigma_a);
        ms->sigma_s = col_add(ms->sigma_s, mc.sigma_s);
        ms->emission = col_add(ms->emission, mc.emission);
        ms->index[ms->n] = m;
        ms->weight[ms->n] = col_avg(mc.sigma_s);
        ms->n++;
    }
}

const phase *media_choose_phase(const brume_scene *s, const medium_sample *ms, double u)
{
    if (ms->n == 1)
        return s->media[ms->index[0]].ph;
    double total = 0.0;
    for (int i = 0; i < ms->n; i++)
        total += ms->weight[i];
    double x = u * total;
    for (int i = 0; i < ms->n; i++) {
        if (x < ms->weight[i])
            return s->media[ms->index[i]].ph;
        x -= ms->weight[i];
    }
    return s->media[ms->index[ms->n - 1]].ph;
}

/* the shadow stage (roulette, residual ratio tracking), written once over the real type */
#define REAL_F 0
#define TRACK_SCENE brume_scene
#define TRACK_API
#include "render/track_steps.h"
