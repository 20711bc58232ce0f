/* flight.c - one free flight through the media (docs/path-tracer.md, "Free flights").
 *
 * Tentative collisions are drawn against the scalar majorant sigma_maj (track.h) and
 * walked with a ratio-tracking transmittance Tr (per channel). At each, emission
 * beta Tr sigma_a Le / sigma_maj is added, and the collision is offered to a one-element
 * reservoir with weight avg(beta Tr sigma_s) / sigma_maj (the history-aware spectral choice
 * of Kutz et al. 2017); the kept one is where the path scatters, and beta Tr at the
 * flight's end weighs what lies past it. The path tracer (path.c) and brume slab (slab.c)
 * run on it. */
#include "render/flight.h"

#include "core/stats.h"

#define REAL_F 0
#define FLIGHT_SCENE brume_scene
#define FLIGHT_MEDIUM medium
#define FLIGHT_API
#include "render/flight_body.h"
