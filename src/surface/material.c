/* material.c - the BSDF by material type: brume's Lambert plus normalized Phong (exact lobe
 * sampling), and pbrt-v4's dielectric, conductor and coated diffuse (bsdf_*.c), evaluated in
 * the frame of the front normal. */
#include "surface/material.h"

#include "core/sampling.h"
#include "surface/bsdf.h"

/* ---- diffuse: Lambert plus Phong, on wo's side ----------------------------------------- */

static vec3 reflect(vec3 wo, vec3 n) { return v3_sub(v3_scale(n, 2.0 * v3_dot(wo, n)), wo); }

/* The normal on wo's side. */
static vec3 facing(vec3 ng, vec3 wo) { return v3_dot(ng, v3_neg(wo)) < 0.0 ? ng : v3_neg(ng); }

static double lobe_weight_specular(const material *m)
{
    double d = col_avg(m->albedo), s = col_avg(m->specular);
    return d + s > 0.0 ? s / (d + s) : 0.0;
}

static color phong_eval(const material *m, vec3 n, vec3 wo, vec3 wi)
{
    if (v3_dot(wi, n) <= 0.0 || v3_dot(wo, n) <= 0.0)
        return col(0.0);
    color f = col_scale(m->albedo, INV_PI);
    if (!col_is_black(m->specular)) {
        double c = v3_dot(reflect(wo, n), wi);
        if (c > 0.0)
            f = col_madd(f, m->specular, (m->exponent + 2.0) / (2.0 * PI) * pow(c, m->exponent));
    }
    return f;
}

static double phong_pdf(const material *m, vec3 n, vec3 wo, vec3 wi)
{
    double cos_i = v3_dot(wi, n);
    if (cos_i <= 0.0 || v3_dot(wo, n) <= 0.0)
        return 0.0;
    double ps = lobe_weight_specular(m);
    double pdf = (1.0 - ps) * cos_i * INV_PI;
    if (ps > 0.0) {
        double c = v3_dot(reflect(wo, n), wi);
        if (c > 0.0)
            pdf += ps * (m->exponent + 1.0) / (2.0 * PI) * pow(c, m->exponent);
    }
    return pdf;
}

static bool phong_sample(const material *m, vec3 n, vec3 wo, double u0, double u1, double u2, bsdf_sample *s)
{
    double ps = lobe_weight_specular(m);
    vec3 wi;
    if (u0 < ps) {
        /* Phong lobe about the mirror direction: cos^e distributed, pdf (e + 1) / 2 pi cos^e */
        double c = pow(u1, 1.0 / (m->exponent + 1.0));
        frame f = frame_from_n(reflect(wo, n));
        wi = frame_to_world(&f, direction_from_cos(c, u2));
    } else {
        frame f = frame_from_n(n);
        wi = frame_to_world(&f, sample_cosine_hemisphere(u1, u2));
    }
    if (v3_dot(wi, n) <= 0.0)
        return false;
    *s = (bsdf_sample){.wi = wi, .pdf = phong_pdf(m, n, wo, wi), .delta = false, .pdf_is_walk = false};
    s->f = phong_eval(m, n, wo, wi);
    return s->pdf > 0.0;
}

/* ---- dispatch ------------------------------------------------------------------------------ */

const char *material_type_name(material_type t)
{
    switch (t) {
    case MATERIAL_DIFFUSE: return "diffuse";
    case MATERIAL_DIELECTRIC: return "dielectric";
    case MATERIAL_CONDUCTOR: return "conductor";
    case MATERIAL_COATEDDIFFUSE: return "coateddiffuse";
    case MATERIAL_MIX: return "mix";
    }
    return "?";
}

bool material_is_black(const material *m)
{
    switch (m->type) {
    case MATERIAL_DIFFUSE: return col_is_black(m->albedo) && col_is_black(m->specular);
    case MATERIAL_DIELECTRIC: return false;
    case MATERIAL_CONDUCTOR: return false;
    case MATERIAL_COATEDDIFFUSE: return false; /* the coat reflects whatever the base */
    case MATERIAL_MIX: return false;           /* resolved per hit before it is shaded */
    }
    return true;
}

bool material_is_delta(const material *m)
{
    switch (m->type) {
    case MATERIAL_DIELECTRIC: return m->eta == 1.0 || m->alpha < MATERIAL_SMOOTH_ALPHA;
    case MATERIAL_CONDUCTOR: return m->alpha < MATERIAL_SMOOTH_ALPHA;
    default: return false;
    }
}

color material_eval(const material *m, vec3 ng, vec3 wo, vec3 wi)
{
    if (m->type == MATERIAL_DIFFUSE)
        return phong_eval(m, facing(ng, wo), wo, wi);
    frame fr = frame_from_n(ng);
    vec3 o = frame_to_local(&fr, wo), i = frame_to_local(&fr, wi);
    switch (m->type) {
    case MATERIAL_DIELECTRIC: return dielectric_f(m->eta, m->alpha, o, i, true);
    case MATERIAL_CONDUCTOR: return conductor_f(m, o, i);
    case MATERIAL_COATEDDIFFUSE: return coated_f(m, o, i);
    default: return col(0.0);
    }
}

double material_pdf(const material *m, vec3 ng, vec3 wo, vec3 wi)
{
    if (m->type == MATERIAL_DIFFUSE)
        return phong_pdf(m, facing(ng, wo), wo, wi);
    frame fr = frame_from_n(ng);
    vec3 o = frame_to_local(&fr, wo), i = frame_to_local(&fr, wi);
    switch (m->type) {
    case MATERIAL_DIELECTRIC: return dielectric_pdf(m->eta, m->alpha, o, i, BXDF_ALL);
    case MATERIAL_CONDUCTOR: return conductor_pdf(m, o, i);
    case MATERIAL_COATEDDIFFUSE: return coated_pdf(m, o, i);
    default: return 0.0;
    }
}

bool material_sample(const material *m, vec3 ng, vec3 wo, double u0, double u1, double u2, bsdf_sample *s)
{
    if (m->type == MATERIAL_DIFFUSE)
        return phong_sample(m, facing(ng, wo), wo, u0, u1, u2, s);
    frame fr = frame_from_n(ng);
    vec3 o = frame_to_local(&fr, wo);
    bxdf_sample b;
    bool ok = false;
    switch (m->type) {
    case MATERIAL_DIELECTRIC: ok = dielectric_sample(m->eta, m->alpha, o, u0, u1, u2, BXDF_ALL, true, &b); break;
    case MATERIAL_CONDUCTOR: ok = conductor_sample(m, o, u1, u2, &b); break;
    case MATERIAL_COATEDDIFFUSE: ok = coated_sample(m, o, u0, u1, u2, &b); break;
    default: break;
    }
    if (!ok || !(b.pdf > 0.0) || col_is_black(b.f))
        return false;
    *s = (bsdf_sample){.wi = frame_to_world(&fr, b.wi), .f = b.f, .pdf = b.pdf, .delta = b.delta,
                       .pdf_is_walk = b.pdf_is_walk};
    return true;
}
