/* track_float.c - the float view of a scene for the single-precision stages
 * (render/track_float.h), built on the host from the double scene. */
#include "render/track_float.h"

#include "scene/scene.h"

static colorf colf_of(color c)
{
    colorf r;
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        r.c[i] = (float)c.c[i];
    return r;
}

const char *scenef_make(const brume_scene *s, scenef *v)
{
    if (s->nmedia != 1)
        return "a scene without exactly one medium";
    const medium *md = &s->media[0];
    if (md->motion || md->velocity[0] || md->moved)
        return "a moving medium";
    if (md->albedo[0] || md->temperature || md->emission[0])
        return "a medium with albedo, temperature or emission fields";
    if (!density_float_view(md->rho, &v->media[0].rho))
        return "a density other than a trilinear dense grid (or a NanoVDB grid's dense copy)";
    mediumf *mf = &v->media[0];
    mf->sigma_a = colf_of(md->sigma_a);
    mf->sigma_s = colf_of(md->sigma_s);
    mf->Le = colf_of(md->Le);
    mf->emit_per_length = md->emit_per_length;
    mf->sigma_t_max = (float)md->sigma_t_max;
    mf->sigma_flight = (float)md->sigma_flight;
    mf->sigma_t_min = (float)md->sigma_t_min;
    v->nmedia = 1;
    v->flight_control = s->flight_control;
    return NULL;
}
