/* material.c - Lambert plus normalized Phong reflection, exact lobe sampling. */
#include "surface/material.h"

#include "core/sampling.h"

static vec3 reflect(vec3 wo, vec3 n) { return v3_sub(v3_scale(n, 2.0 * v3_dot(wo, n)), wo); }

static double lobe_weight_specular(const material *m)
{
    double d = col_avg(m->albedo), s = col_avg(m->specular);
    return d + s > 0.0 ? s / (d + s) : 0.0;
}

bool material_is_black(const material *m) { return col_is_black(m->albedo) && col_is_black(m->specular); }

color material_eval(const material *m, vec3 n, vec3 wo, vec3 wi)
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

double material_pdf(const material *m, vec3 n, vec3 wo, vec3 wi)
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

bool material_sample(const material *m, vec3 n, vec3 wo, double u0, double u1, double u2, vec3 *wi, double *pdf)
{
    double ps = lobe_weight_specular(m);
    if (u0 < ps) {
        /* Phong lobe about the mirror direction: cos^e distributed, pdf (e + 1) / 2 pi cos^e */
        double c = pow(u1, 1.0 / (m->exponent + 1.0));
        frame f = frame_from_n(reflect(wo, n));
        *wi = frame_to_world(&f, direction_from_cos(c, u2));
    } else {
        frame f = frame_from_n(n);
        *wi = frame_to_world(&f, sample_cosine_hemisphere(u1, u2));
    }
    if (v3_dot(*wi, n) <= 0.0)
        return false;
    *pdf = material_pdf(m, n, wo, *wi);
    return *pdf > 0.0;
}
