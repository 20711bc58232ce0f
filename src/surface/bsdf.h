/* bsdf.h - the BxDFs behind material.h, in the local frame of the surface (z along the front
 * normal ng), as pbrt-v4 writes them: wo.z < 0 means wo is behind the surface. Private to
 * src/surface (material.c and bsdf_*.c). */
#ifndef BRUME_SURFACE_BSDF_H
#define BRUME_SURFACE_BSDF_H

#include <math.h>
#include <stdbool.h>

#include "core/color.h"
#include "core/vec.h"
#include "surface/material_params.h"

/* Which lobes a sample may take (layered sampling asks for one kind). */
enum { BXDF_REFLECTION = 1, BXDF_TRANSMISSION = 2, BXDF_ALL = 3 };

typedef struct bxdf_sample {
    vec3 wi;
    color f;
    double pdf;
    bool delta;
    bool reflection;
    bool pdf_is_walk;
} bxdf_sample;

static inline bool same_hemisphere(vec3 a, vec3 b) { return a.z * b.z > 0.0; }

/* ---- Trowbridge-Reitz (GGX), isotropic alpha (bsdf_microfacet.c) ------------------------- */
double tr_D(double alpha, vec3 wm);
double tr_G1(double alpha, vec3 w);
double tr_G(double alpha, vec3 wo, vec3 wi);
/* The visible normals' density D_w(wm) = G1(w) max(0, w . wm) D(wm) / |w.z|. */
double tr_D_visible(double alpha, vec3 w, vec3 wm);
/* A visible normal for w (Heitz 2018), as pbrt-v4's Sample_wm. */
vec3 tr_sample_wm(double alpha, vec3 w, double u1, double u2);

/* Fresnel reflectance of a dielectric interface for cos_i (negative: from behind, eta then
 * inverted), eta = index behind over in front. */
double fr_dielectric(double cos_i, double eta);
/* Fresnel reflectance of a conductor of complex index eta + i k at cos_i in [0, 1]. */
double fr_complex(double cos_i, double eta, double k);
/* Refraction of wi about n (wi on either side); *etap the relative index that applied.
 * False on total internal reflection. */
bool refract(vec3 wi, vec3 n, double eta, double *etap, vec3 *wt);

/* ---- the BxDFs; radiance: transport of radiance (1 / eta'^2 on transmission) ------------- */
color dielectric_f(double eta, double alpha, vec3 wo, vec3 wi, bool radiance);
double dielectric_pdf(double eta, double alpha, vec3 wo, vec3 wi, int lobes);
bool dielectric_sample(double eta, double alpha, vec3 wo, double uc, double u1, double u2, int lobes, bool radiance,
                       bxdf_sample *s);

color conductor_f(const material *m, vec3 wo, vec3 wi);
double conductor_pdf(const material *m, vec3 wo, vec3 wi);
bool conductor_sample(const material *m, vec3 wo, double u1, double u2, bxdf_sample *s);

color coated_f(const material *m, vec3 wo, vec3 wi);
double coated_pdf(const material *m, vec3 wo, vec3 wi);
bool coated_sample(const material *m, vec3 wo, double uc, double u1, double u2, bxdf_sample *s);

#endif
