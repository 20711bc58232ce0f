/* blasi_rays.h - the light rays of Blasi's first pass (blasi_rays.c): where a ray starts and
 * with what power, how many rays each light gets, and the check of the work they make; the
 * pass that flies them is blasi_light.c. */
#ifndef BRUME_RENDER_BLASI_RAYS_H
#define BRUME_RENDER_BLASI_RAYS_H

#include <stdbool.h>
#include <stdint.h>

#include "brume.h"
#include "render/blasi_state.h"

/* blasi_rays.c */
bool blasi_light_ray(const brume_scene *s, const blasi_state *st, const light *l, uint64_t j, uint64_t n, rng *g,
                     ray *r, color *W);
uint64_t *blasi_rays_per_light(const brume_scene *s, const blasi_state *st, uint64_t nominal);
brume_status blasi_check_work(const brume_scene *s, const blasi_state *st, uint64_t nrays);
double blasi_units_per_watt(const brume_scene *s, const blasi_state *st, const uint64_t *first);

#endif
