/* flight.h - one free flight of the path tracer through the media (render/flight.c), a
 * building block exposed so that other estimators (brume slab) run on exactly the code the
 * renderer runs. */
#ifndef BRUME_RENDER_FLIGHT_H
#define BRUME_RENDER_FLIGHT_H

#include "core/rng.h"
#include "render/track.h"
#include "scene/scene.h"

/* One free flight along r over [0, tmax] (docs/path-tracer.md, "Free flights"). The
 * flight walks every tentative collision against sigma_maj with a ratio-tracking
 * transmittance Tr, adds the emission term at each, and keeps one collision i among them
 * with probability a_i / A, where
 *   a_i = avg(beta Tr(t_i) sigma_s(t_i)) / sigma_maj   and   A = sum_i a_i
 * (a one-element reservoir): beta_s = A (beta Tr sigma_s)(t_i) / (sigma_maj a_i) is then
 * an unbiased weight for scattering there, and beta Tr(tmax) for what lies past tmax. Both
 * branches are estimated from one walk; a path never ends merely because it escaped. */
#define REAL_F 0
#define FLIGHT_SCENE brume_scene
#include "render/flight_type.h"
#undef FLIGHT_SCENE
#undef REAL_F

/* Runs a flight; true when it kept a scattering collision (f->A > 0). f->beta, f->L and
 * f->tail_Tr carry in; f->Tr, f->A, f->beta_s, f->t, f->ms come out. In a medium whose
 * extinction is gray (s->flight_control), once the largest channel of Tr falls below
 * f->tail_Tr each tentative collision is real with probability p = sigma_t / sigma_maj (of
 * the residual), and then the flight's last, its weight divided by p, and otherwise leaves
 * Tr as it is: the delta tail (docs/path-tracer.md), unbiased as the ratio steps are. The
 * next number of ug (its dimension is taken now, the value computed only if the flight
 * meets a collision) makes the reservoir's choices: one number for the whole flight, so a
 * sampler can stratify where flights scatter. The tracking draws from f->g. */
bool flight_run(flight *f, ray r, double tmax, rng *ug);

/* flight_run in pieces, for a flight that crosses surfaces bounding media (render/path.c):
 * flight_begin takes the reservoir's dimension; flight_track walks the piece r over
 * [0, tmax] in the media f->absent leaves, r starting at t0 along the flight (f->t counts
 * from the flight's start); flight_end is flight_run's result. */
void flight_begin(flight *f, rng *ug);
void flight_track(flight *f, ray r, double t0, double tmax);
bool flight_end(flight *f);

#endif
