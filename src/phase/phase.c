/* phase.c - phase functions: evaluation, exact sampling, pdf and mean cosine. */
#include "phase/phase.h"

#include <stdlib.h>

#include "core/error.h"
#include "core/sampling.h"

struct phase {
    phase_kind kind;
    double g; /* Henyey-Greenstein asymmetry, |g| < 1 */
};

static phase *phase_alloc(phase_kind kind)
{
    phase *p = calloc(1, sizeof *p);
    if (!p) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "phase: out of memory");
        return NULL;
    }
    p->kind = kind;
    return p;
}

phase *phase_new_isotropic(void) { return phase_alloc(PHASE_ISOTROPIC); }

phase *phase_new_hg(double g)
{
    if (!(fabs(g) < 1.0)) {
        err_set(BRUME_ERROR_RANGE, "henyey-greenstein g = %g: need |g| < 1", g);
        return NULL;
    }
    phase *p = phase_alloc(PHASE_HENYEY_GREENSTEIN);
    if (p)
        p->g = g;
    return p;
}

void phase_release(phase *p) { free(p); }

phase_kind phase_get_kind(const phase *p) { return p->kind; }

/* Blasi Eq. 19, divided by 4 pi. */
static double hg_eval(double g, double cos_theta)
{
    double denom = 1.0 + g * g - 2.0 * g * cos_theta;
    return INV_4PI * (1.0 - g * g) / (denom * sqrt(denom));
}

/* Inverse CDF of the HG distribution of cos (forward for g > 0). */
static double hg_sample_cos(double g, double u)
{
    if (fabs(g) < 1e-4)
        return 1.0 - 2.0 * u;
    double s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    double c = (1.0 + g * g - s * s) / (2.0 * g);
    return fmin(1.0, fmax(-1.0, c));
}

double phase_eval(const phase *p, double cos_theta)
{
    switch (p->kind) {
    case PHASE_ISOTROPIC: return INV_4PI;
    case PHASE_HENYEY_GREENSTEIN: return hg_eval(p->g, cos_theta);
    }
    return 0.0;
}

double phase_pdf(const phase *p, double cos_theta) { return phase_eval(p, cos_theta); }

vec3 phase_sample(const phase *p, vec3 wi, double u1, double u2, double *pdf)
{
    double c = 0.0;
    switch (p->kind) {
    case PHASE_ISOTROPIC: c = 1.0 - 2.0 * u1; break;
    case PHASE_HENYEY_GREENSTEIN: c = hg_sample_cos(p->g, u1); break;
    }
    frame f = frame_from_n(wi);
    vec3 wo = frame_to_world(&f, direction_from_cos(c, u2));
    *pdf = phase_pdf(p, c);
    return wo;
}

double phase_mean_cosine(const phase *p)
{
    switch (p->kind) {
    case PHASE_ISOTROPIC: return 0.0;
    case PHASE_HENYEY_GREENSTEIN: return p->g;
    }
    return 0.0;
}
