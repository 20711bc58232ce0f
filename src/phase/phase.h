/* phase.h - phase functions of Blasi, Le Saec and Schlick 1993, Section 3.
 *
 * Conventions (docs/phase-functions.md): p(cos) is normalized over the sphere, the integral of p
 * over 4 pi sr is 1 (the paper's phi integrates to 2 over t in [-1, 1], so p = phi / 4 pi).
 * cos is the cosine between the incoming and the outgoing propagation directions:
 * cos = 1 is straight on; g > 0 or k > 0 scatters forward.
 *
 * Kinds, each with eval, exact sampling, pdf and mean cosine (docs/phase-functions.md):
 *   isotropic          Blasi Eq. 16
 *   rayleigh           Blasi Eq. 17, sampled by inverting a cubic in closed form
 *   mie hazy / murky   Blasi Eq. 18 (Nishita's approximations), sampled with an
 *                      inverse-CDF table polished by Newton steps on the closed-form CDF
 *   henyey-greenstein  Blasi Eq. 19, closed-form inversion
 *   schlick            Blasi Eq. 21, sampled with Eq. 23
 *   mixture            Blasi Eq. 20 and 22, sampled by choosing a lobe
 *   tabulated          (angle, value) pairs, linear in cos between the nodes, sampled by
 *                      exact inversion of its piecewise-quadratic CDF
 * Every sampler is exact: phase_pdf equals phase_eval.
 *
 * Lifecycle: a constructor returns a new phase owned by the caller, or NULL with err_set()
 * naming the bad value (nothing is allocated then). A phase is immutable after
 * construction, so one phase may be shared by threads. phase_release accepts NULL. */
#ifndef BRUME_PHASE_PHASE_H
#define BRUME_PHASE_PHASE_H

#include <stddef.h>

#include "core/vec.h"

typedef enum phase_kind {
    PHASE_ISOTROPIC,
    PHASE_HENYEY_GREENSTEIN,
    PHASE_RAYLEIGH,
    PHASE_MIE_HAZY,
    PHASE_MIE_MURKY,
    PHASE_SCHLICK,
    PHASE_MIXTURE,
    PHASE_TABULATED
} phase_kind;

/* Opaque; immutable after construction, so one phase may be shared by threads. */
typedef struct phase phase;

/* Copies p with its lobes and tables into a (core/arena.h) for the GPU; returns the copy's
 * offset (ARENA_NULL on failure: a->failed). */
struct dev_arena;
size_t phase_device_put(const phase *p, struct dev_arena *a);

phase *phase_new_isotropic(void);
/* Rayleigh, phi = 3/4 (1 + t^2) (Blasi Eq. 17). */
phase *phase_new_rayleigh(void);
/* Nishita's Mie approximations (Blasi Eq. 18): hazy 1/2 + 9/2 ((1+t)/2)^8,
 * murky 1/2 + 33/2 ((1+t)/2)^32. */
phase *phase_new_mie_hazy(void);
phase *phase_new_mie_murky(void);
/* Henyey-Greenstein (Blasi Eq. 19); NULL with err_set() unless |g| < 1. */
phase *phase_new_hg(double g);
/* Schlick (Blasi Eq. 21), phi = (1 - k^2) / (1 - k t)^2; NULL with err_set() unless |k| < 1. */
phase *phase_new_schlick(double k);
/* Normalized mixture sum w_i lobe_i / sum w (Blasi Eq. 20). Weights must be finite and
 * >= 0 with a positive sum; lobes must not be NULL. On success the mixture owns the n
 * lobes (phase_release of the mixture releases them) and borrows nothing else; on
 * failure it returns NULL and the caller still owns the lobes. */
phase *phase_new_mixture(int n, const double *weights, phase *const *lobes);
/* Blasi Eq. 22: r schlick(k) + (1 - r) schlick(kprime); NULL unless r in [0, 1] and
 * |k|, |kprime| < 1. */
phase *phase_new_schlick_mix(double r, double k, double kprime);
/* A tabulated phase function: n >= 2 pairs (angle in degrees, value), angles strictly
 * increasing in [0, 180], values finite and >= 0, not all zero. Values are interpolated
 * linearly in cos(angle), held constant beyond the first and last angle, and scaled so
 * that the function integrates to 1 over the sphere. The arrays are copied. */
phase *phase_new_tabulated(int n, const double *angle_deg, const double *value);
/* Reads a tabulated phase function from a text file: two numbers per line (angle in
 * degrees, value), '#' starts a comment, blank lines are skipped. Errors name the file,
 * the line and the value. */
phase *phase_load_tabulated(const char *path);
/* "isotropic", "rayleigh", "hazy", "murky", "hg:G", "schlick:K", or else the path of a
 * tabulated file. */
phase *phase_new_from_name(const char *name);
void phase_release(phase *p);

phase_kind phase_get_kind(const phase *p);
/* p(cos) per steradian. */
double phase_eval(const phase *p, double cos_theta);
/* Pdf per steradian of phase_sample producing an outgoing direction at cosine cos_theta. */
double phase_pdf(const phase *p, double cos_theta);
/* An outgoing propagation direction for incoming propagation direction wi (unit), from two
 * uniform numbers in [0, 1); *pdf (per sr) receives phase_pdf of the result. */
vec3 phase_sample(const phase *p, vec3 wi, double u1, double u2, double *pdf);
/* The cosine alone of phase_sample's direction, distributed with density
 * 2 pi phase_pdf(p, cos) on [-1, 1], from one uniform number in [0, 1). */
double phase_sample_cos(const phase *p, double u);
/* Introspection, for methods that treat lobes apart (Blasi's two passes): the number of
 * lobes of a mixture (0 for other kinds); lobe i (0 <= i < count) with its normalized
 * weight in *weight; Schlick's k of a PHASE_SCHLICK (NAN for other kinds). */
int phase_lobe_count(const phase *p);
const phase *phase_lobe(const phase *p, int i, double *weight);
double phase_schlick_k(const phase *p);
/* Mean cosine: the integral of cos p(cos) over the sphere. */
double phase_mean_cosine(const phase *p);

/* Schlick's k for Henyey-Greenstein's g: k = 1.55 g - 0.55 g^3 (pbrt, first edition,
 * after Blasi et al.). The cubic exceeds 1 in magnitude for |g| > 0.9381; the result is
 * clamped to |k| <= 1 - 1e-9 so that it is always a valid Schlick parameter. */
double phase_schlick_k_from_g(double g);
/* The inverse of phase_schlick_k_from_g on its monotone branch |g| <= 0.9381, solved
 * numerically (so the two maps round-trip); |k| < 1. See docs/phase-functions.md for why
 * this is not the map that equates mean cosines. */
double phase_hg_g_from_schlick_k(double k);

#endif
