/* bsdf_microfacet.c - the Trowbridge-Reitz microfacet distribution with visible-normal
 * sampling, the Fresnel terms and refraction, in the local frame (bsdf.h), following
 * pbrt-v4's definitions (Pharr, Jakob, Humphreys, 4th ed., sections 9.3-9.6). */
#include "surface/bsdf.h"

static double mf_sqr(double x) { return x * x; }

double tr_D(double alpha, vec3 wm)
{
    double cos2 = wm.z * wm.z, sin2 = fmax(0.0, 1.0 - cos2);
    if (cos2 * cos2 < 1e-16)
        return 0.0;
    double tan2 = sin2 / cos2, e = tan2 / (alpha * alpha);
    return 1.0 / (PI * alpha * alpha * cos2 * cos2 * mf_sqr(1.0 + e));
}

/* Smith's Lambda(w) = (sqrt(1 + alpha^2 tan^2) - 1) / 2. */
static double tr_lambda(double alpha, vec3 w)
{
    double cos2 = w.z * w.z, sin2 = fmax(0.0, 1.0 - cos2);
    if (cos2 == 0.0)
        return INFINITY;
    return (sqrt(1.0 + alpha * alpha * sin2 / cos2) - 1.0) / 2.0;
}

double tr_G1(double alpha, vec3 w) { return 1.0 / (1.0 + tr_lambda(alpha, w)); }

double tr_G(double alpha, vec3 wo, vec3 wi) { return 1.0 / (1.0 + tr_lambda(alpha, wo) + tr_lambda(alpha, wi)); }

double tr_D_visible(double alpha, vec3 w, vec3 wm)
{
    if (w.z == 0.0)
        return 0.0;
    return tr_G1(alpha, w) / fabs(w.z) * tr_D(alpha, wm) * fabs(v3_dot(w, wm));
}

vec3 tr_sample_wm(double alpha, vec3 w, double u1, double u2)
{
    vec3 wh = v3_normalize(v3(alpha * w.x, alpha * w.y, w.z));
    if (wh.z < 0.0)
        wh = v3_neg(wh);
    vec3 t1 = wh.z < 0.99999 ? v3_normalize(v3_cross(v3(0, 0, 1), wh)) : v3(1, 0, 0);
    vec3 t2 = v3_cross(wh, t1);
    /* a uniform disk point, squeezed onto the projected visible hemisphere */
    double r = sqrt(u1), phi = 2.0 * PI * u2;
    double px = r * cos(phi), py = r * sin(phi);
    double h = sqrt(fmax(0.0, 1.0 - px * px)), s = (1.0 + wh.z) / 2.0;
    py = (1.0 - s) * h + s * py;
    double pz = sqrt(fmax(0.0, 1.0 - px * px - py * py));
    vec3 nh = v3_add(v3_add(v3_scale(t1, px), v3_scale(t2, py)), v3_scale(wh, pz));
    return v3_normalize(v3(alpha * nh.x, alpha * nh.y, fmax(1e-6, nh.z)));
}

double fr_dielectric(double cos_i, double eta)
{
    cos_i = fmin(1.0, fmax(-1.0, cos_i));
    if (cos_i < 0.0) {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    double sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0)
        return 1.0;
    double cos_t = sqrt(fmax(0.0, 1.0 - sin2_t));
    double r_parl = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    double r_perp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    return (r_parl * r_parl + r_perp * r_perp) / 2.0;
}

/* Complex arithmetic by hand: the GPU build has no <complex.h>. */
typedef struct cplx {
    double re, im;
} cplx;
static cplx c_mul(cplx a, cplx b) { return (cplx){a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re}; }
static cplx c_div(cplx a, cplx b)
{
    double d = b.re * b.re + b.im * b.im;
    return (cplx){(a.re * b.re + a.im * b.im) / d, (a.im * b.re - a.re * b.im) / d};
}
static cplx c_sqrt(cplx z)
{
    double n = sqrt(z.re * z.re + z.im * z.im);
    if (n == 0.0)
        return (cplx){0.0, 0.0};
    double t1 = sqrt(0.5 * (n + fabs(z.re))), t2 = 0.5 * z.im / t1;
    if (z.re >= 0.0)
        return (cplx){t1, t2};
    return (cplx){fabs(t2), copysign(t1, z.im)};
}
static double c_norm(cplx z) { return z.re * z.re + z.im * z.im; }

double fr_complex(double cos_i, double eta, double k)
{
    cos_i = fmin(1.0, fmax(0.0, cos_i));
    cplx e = {eta, k};
    double sin2_i = 1.0 - cos_i * cos_i;
    cplx sin2_t = c_div((cplx){sin2_i, 0.0}, c_mul(e, e));
    cplx cos_t = c_sqrt((cplx){1.0 - sin2_t.re, -sin2_t.im});
    cplx ec = {e.re * cos_i, e.im * cos_i}, ect = c_mul(e, cos_t);
    cplx r_parl = c_div((cplx){ec.re - cos_t.re, ec.im - cos_t.im}, (cplx){ec.re + cos_t.re, ec.im + cos_t.im});
    cplx r_perp = c_div((cplx){cos_i - ect.re, -ect.im}, (cplx){cos_i + ect.re, ect.im});
    return (c_norm(r_parl) + c_norm(r_perp)) / 2.0;
}

bool refract(vec3 wi, vec3 n, double eta, double *etap, vec3 *wt)
{
    double cos_i = v3_dot(n, wi);
    if (cos_i < 0.0) {
        eta = 1.0 / eta;
        cos_i = -cos_i;
        n = v3_neg(n);
    }
    double sin2_t = fmax(0.0, 1.0 - cos_i * cos_i) / (eta * eta);
    if (sin2_t >= 1.0)
        return false;
    double cos_t = sqrt(1.0 - sin2_t);
    *wt = v3_add(v3_scale(wi, -1.0 / eta), v3_scale(n, cos_i / eta - cos_t));
    *etap = eta;
    return true;
}

/* ---- conductor (pbrt-v4's ConductorBxDF), per channel Fresnel -------------------------- */

static color fr_conductor(const material *m, double cos_i)
{
    color F;
    for (int c = 0; c < 3; c++)
        F.c[c] = fr_complex(cos_i, m->eta_c.c[c], m->k_c.c[c]);
    return F;
}

color conductor_f(const material *m, vec3 wo, vec3 wi)
{
    if (!same_hemisphere(wo, wi) || m->alpha < MATERIAL_SMOOTH_ALPHA)
        return col(0.0);
    double cos_o = fabs(wo.z), cos_i = fabs(wi.z);
    vec3 wm = v3_add(wi, wo);
    if (cos_i == 0.0 || cos_o == 0.0 || v3_dot(wm, wm) == 0.0)
        return col(0.0);
    wm = v3_normalize(wm);
    color F = fr_conductor(m, fabs(v3_dot(wo, wm)));
    return col_scale(F, tr_D(m->alpha, wm) * tr_G(m->alpha, wo, wi) / (4.0 * cos_i * cos_o));
}

double conductor_pdf(const material *m, vec3 wo, vec3 wi)
{
    if (!same_hemisphere(wo, wi) || m->alpha < MATERIAL_SMOOTH_ALPHA)
        return 0.0;
    vec3 wm = v3_add(wo, wi);
    if (v3_dot(wm, wm) == 0.0)
        return 0.0;
    wm = v3_normalize(wm);
    if (wm.z < 0.0)
        wm = v3_neg(wm);
    return tr_D_visible(m->alpha, wo, wm) / (4.0 * fabs(v3_dot(wo, wm)));
}

bool conductor_sample(const material *m, vec3 wo, double u1, double u2, bxdf_sample *s)
{
    s->reflection = true;
    s->pdf_is_walk = false;
    if (m->alpha < MATERIAL_SMOOTH_ALPHA) {
        s->wi = v3(-wo.x, -wo.y, wo.z);
        s->f = col_scale(fr_conductor(m, fabs(wo.z)), 1.0 / fabs(wo.z));
        s->pdf = 1.0;
        s->delta = true;
        return wo.z != 0.0;
    }
    if (wo.z == 0.0)
        return false;
    /* visible normals are sampled on wo's side; the lobe is the same on both (two-sided) */
    vec3 wo_up = wo.z < 0.0 ? v3_neg(wo) : wo;
    vec3 wm = tr_sample_wm(m->alpha, wo_up, u1, u2);
    vec3 wi = v3_sub(v3_scale(wm, 2.0 * v3_dot(wo_up, wm)), wo_up);
    if (wi.z <= 0.0)
        return false;
    s->wi = wo.z < 0.0 ? v3_neg(wi) : wi;
    s->delta = false;
    s->pdf = conductor_pdf(m, wo, s->wi);
    s->f = conductor_f(m, wo, s->wi);
    return s->pdf > 0.0;
}
