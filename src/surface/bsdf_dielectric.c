/* bsdf_dielectric.c - pbrt-v4's DielectricBxDF in the local frame (bsdf.h): smooth (delta
 * reflection and refraction with the exact Fresnel term) or rough (Trowbridge-Reitz facets,
 * Walter et al. 2007), sampled in proportion to the Fresnel term of the facet. eta is the
 * index behind the surface (z < 0) over the one in front. */
#include "surface/bsdf.h"

static double dl_sqr(double x) { return x * x; }

static bool dielectric_smooth(double eta, double alpha) { return eta == 1.0 || alpha < MATERIAL_SMOOTH_ALPHA; }

/* The generalized half vector of wo and wi for a facet that joins them, facing +z, and
 * eta' (1 for reflection); false where no facet joins them or it faces away from either. */
static bool half_vector(double eta, vec3 wo, vec3 wi, vec3 *wm, double *etap)
{
    double cos_o = wo.z, cos_i = wi.z;
    bool reflect = cos_i * cos_o > 0.0;
    *etap = reflect ? 1.0 : (cos_o > 0.0 ? eta : 1.0 / eta);
    vec3 h = v3_add(v3_scale(wi, *etap), wo);
    if (cos_i == 0.0 || cos_o == 0.0 || v3_dot(h, h) == 0.0)
        return false;
    h = v3_normalize(h);
    if (h.z < 0.0)
        h = v3_neg(h);
    /* back-facing microfacets are discarded */
    if (v3_dot(h, wi) * cos_i < 0.0 || v3_dot(h, wo) * cos_o < 0.0)
        return false;
    *wm = h;
    return true;
}

color dielectric_f(double eta, double alpha, vec3 wo, vec3 wi, bool radiance)
{
    vec3 wm;
    double etap;
    if (dielectric_smooth(eta, alpha) || !half_vector(eta, wo, wi, &wm, &etap))
        return col(0.0);
    double F = fr_dielectric(v3_dot(wo, wm), eta);
    if (etap == 1.0 && wo.z * wi.z > 0.0)
        return col(tr_D(alpha, wm) * tr_G(alpha, wo, wi) * F / fabs(4.0 * wi.z * wo.z));
    double denom = dl_sqr(v3_dot(wi, wm) + v3_dot(wo, wm) / etap) * wi.z * wo.z;
    double ft = tr_D(alpha, wm) * (1.0 - F) * tr_G(alpha, wo, wi) * fabs(v3_dot(wi, wm) * v3_dot(wo, wm) / denom);
    return col(radiance ? ft / dl_sqr(etap) : ft);
}

double dielectric_pdf(double eta, double alpha, vec3 wo, vec3 wi, int lobes)
{
    vec3 wm;
    double etap;
    if (dielectric_smooth(eta, alpha) || !half_vector(eta, wo, wi, &wm, &etap))
        return 0.0;
    double R = fr_dielectric(v3_dot(wo, wm), eta), T = 1.0 - R;
    double pr = lobes & BXDF_REFLECTION ? R : 0.0, pt = lobes & BXDF_TRANSMISSION ? T : 0.0;
    if (pr == 0.0 && pt == 0.0)
        return 0.0;
    if (wo.z * wi.z > 0.0)
        return tr_D_visible(alpha, wo, wm) / (4.0 * fabs(v3_dot(wo, wm))) * pr / (pr + pt);
    double denom = dl_sqr(v3_dot(wi, wm) + v3_dot(wo, wm) / etap);
    double dwm_dwi = fabs(v3_dot(wi, wm)) / denom;
    return tr_D_visible(alpha, wo, wm) * dwm_dwi * pt / (pr + pt);
}

static bool sample_smooth(double eta, vec3 wo, double uc, int lobes, bool radiance, bxdf_sample *s)
{
    double R = fr_dielectric(wo.z, eta), T = 1.0 - R;
    double pr = lobes & BXDF_REFLECTION ? R : 0.0, pt = lobes & BXDF_TRANSMISSION ? T : 0.0;
    if (pr == 0.0 && pt == 0.0)
        return false;
    s->delta = true;
    if (uc < pr / (pr + pt)) {
        s->wi = v3(-wo.x, -wo.y, wo.z);
        s->f = col(R / fabs(s->wi.z));
        s->pdf = pr / (pr + pt);
        s->reflection = true;
        return true;
    }
    double etap;
    if (!refract(wo, v3(0, 0, 1), eta, &etap, &s->wi))
        return false;
    double ft = T / fabs(s->wi.z);
    s->f = col(radiance ? ft / dl_sqr(etap) : ft);
    s->pdf = pt / (pr + pt);
    s->reflection = false;
    return true;
}

bool dielectric_sample(double eta, double alpha, vec3 wo, double uc, double u1, double u2, int lobes, bool radiance,
                       bxdf_sample *s)
{
    s->pdf_is_walk = false;
    if (dielectric_smooth(eta, alpha))
        return sample_smooth(eta, wo, uc, lobes, radiance, s);
    if (wo.z == 0.0)
        return false;
    vec3 wm = tr_sample_wm(alpha, wo, u1, u2);
    double R = fr_dielectric(v3_dot(wo, wm), eta), T = 1.0 - R;
    double pr = lobes & BXDF_REFLECTION ? R : 0.0, pt = lobes & BXDF_TRANSMISSION ? T : 0.0;
    if (pr == 0.0 && pt == 0.0)
        return false;
    s->delta = false;
    if (uc < pr / (pr + pt)) {
        s->wi = v3_sub(v3_scale(wm, 2.0 * v3_dot(wo, wm)), wo);
        if (!same_hemisphere(wo, s->wi))
            return false;
        s->reflection = true;
    } else {
        double etap;
        if (!refract(wo, wm, eta, &etap, &s->wi) || same_hemisphere(wo, s->wi) || s->wi.z == 0.0)
            return false;
        s->reflection = false;
    }
    /* f and pdf as evaluated, so that a sample and an evaluation of its direction agree */
    s->f = dielectric_f(eta, alpha, wo, s->wi, radiance);
    s->pdf = dielectric_pdf(eta, alpha, wo, s->wi, lobes);
    return s->pdf > 0.0;
}
