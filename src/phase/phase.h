/* phase.h - phase functions of Blasi, Le Saec and Schlick 1993, Section 3.
 *
 * Conventions (shared/DESIGN.md): p(cos) is normalized over the sphere, the integral of p
 * over 4 pi sr is 1 (the paper's phi integrates to 2 over t in [-1, 1], so p = phi / 4 pi).
 * cos is the cosine between the incoming and the outgoing propagation directions:
 * cos = 1 is straight on; g > 0 or k > 0 scatters forward. */
#ifndef BRUME_PHASE_PHASE_H
#define BRUME_PHASE_PHASE_H

#include "core/vec.h"

typedef enum phase_kind {
    PHASE_ISOTROPIC,
    PHASE_HENYEY_GREENSTEIN
} phase_kind;

/* Opaque; immutable after construction, so one phase may be shared by threads. */
typedef struct phase phase;

phase *phase_new_isotropic(void);
/* Henyey-Greenstein (Blasi Eq. 19); NULL with err_set() unless |g| < 1. */
phase *phase_new_hg(double g);
void phase_release(phase *p);

phase_kind phase_get_kind(const phase *p);
/* p(cos) per steradian. */
double phase_eval(const phase *p, double cos_theta);
/* Pdf per steradian of phase_sample producing an outgoing direction at cosine cos_theta. */
double phase_pdf(const phase *p, double cos_theta);
/* An outgoing propagation direction for incoming propagation direction wi (unit), from two
 * uniform numbers; *pdf (per sr) receives phase_pdf of the result. */
vec3 phase_sample(const phase *p, vec3 wi, double u1, double u2, double *pdf);
/* Mean cosine: the integral of cos p(cos) over the sphere. */
double phase_mean_cosine(const phase *p);

#endif
