/* material.h - surface scattering (a BSDF per material type) and emission. Directions are
 * unit vectors pointing away from the surface (wo towards the viewer, wi towards the light);
 * ng is the surface's front (outward) normal, whichever side wo is on. Types
 * (docs/surfaces.md, "Materials"):
 *
 *   diffuse        a Lambertian lobe plus an optional normalized Phong lobe, both sides:
 *                  f(wi, wo) = albedo / pi + specular (e + 2) / (2 pi) max(0, r . wi)^e,
 *                  r = reflect(wo, n), n the normal on wo's side. The (e + 2) / 2 pi
 *                  normalization reflects at most `specular` at any incidence (Lafortune and
 *                  Willems 1994); albedo + specular <= 1 keeps the surface from creating energy.
 *   dielectric     pbrt-v4's DielectricBxDF: index eta inside (behind ng) over outside; smooth
 *                  (delta reflection and refraction, exact Fresnel) or rough (Trowbridge-Reitz);
 *                  transmitted radiance scaled by 1 / eta'^2.
 *   conductor      pbrt-v4's ConductorBxDF: complex index eta + i k per channel, smooth or rough.
 *   coateddiffuse  pbrt-v4's CoatedDiffuseBxDF: a dielectric coat over a Lambertian base with an
 *                  optional scattering layer between; f and pdf are unbiased stochastic
 *                  estimates (deterministic in wo and wi, so MIS weights still sum to one).
 *
 * Every type is two-sided but the dielectric, whose two sides differ by eta. */
#ifndef BRUME_SURFACE_MATERIAL_H
#define BRUME_SURFACE_MATERIAL_H

#include <stdbool.h>

#include "core/color.h"
#include "core/vec.h"

typedef enum material_type {
    MATERIAL_DIFFUSE = 0, /* Lambert plus Phong: brume's own, the default */
    MATERIAL_DIELECTRIC,
    MATERIAL_CONDUCTOR,
    MATERIAL_COATEDDIFFUSE,
} material_type;

/* Copper's complex index as an RGB film sees it (conductor's default, pbrt-v4's metal-Cu):
 * scene/named_spectra.c says how it is made. */
#define MATERIAL_CU_ETA 0.104495, 0.978170, 1.204670
#define MATERIAL_CU_K 3.273344, 2.592350, 2.369242

/* A roughness alpha below this is a smooth (delta) interface, as in pbrt-v4. */
#define MATERIAL_SMOOTH_ALPHA 1e-3

typedef struct material {
    material_type type;
    color albedo;    /* diffuse reflectance in [0, 1] (diffuse; coateddiffuse's base) */
    color specular;  /* Phong lobe reflectance in [0, 1]; 0 = matte (diffuse) */
    double exponent; /* Phong exponent e >= 0 (larger = sharper) (diffuse) */
    color emission;  /* emitted radiance, W m^-2 sr^-1, from the front side(s) */
    bool two_sided_emission;
    /* NULL, or the albedo as a texture of the hit's (u, v) (surface/texture.h): owned by the
     * surfaces object, evaluated into the hit's own copy of the material (surface_hit.shade) */
    struct texture *albedo_tex;
    double eta;      /* dielectric, coateddiffuse's coat: index behind ng over in front, > 0 */
    color eta_c, k_c; /* conductor: complex index of refraction eta + i k per channel */
    double alpha;    /* Trowbridge-Reitz alpha (isotropic); < MATERIAL_SMOOTH_ALPHA: smooth */
    double thickness;    /* coateddiffuse: the layer's optical thickness (sigma_t = 1) */
    color layer_albedo;  /* coateddiffuse: single-scattering albedo in the layer; 0 = none */
    double g;            /* coateddiffuse: Henyey-Greenstein g in the layer */
    int max_depth;       /* coateddiffuse: the random walk's most events */
    int nsamples;        /* coateddiffuse: walks per evaluation */
} material;

/* A sampled direction: f (no cosine; for a delta lobe f |cos| / pdf is the lobe's weight),
 * its pdf (solid angle; for a delta lobe the lobe's discrete probability), whether the
 * lobe is a delta (no light sampling against it), and whether pdf is the sampled walk's
 * (coateddiffuse: f / pdf is right, but MIS must ask material_pdf). */
typedef struct bsdf_sample {
    vec3 wi;
    color f;
    double pdf;
    bool delta;
    bool pdf_is_walk;
} bsdf_sample;

/* f(wi, wo) (per steradian), without the cosine; 0 for delta lobes. */
color material_eval(const material *m, vec3 ng, vec3 wo, vec3 wi);
/* Samples wi from three uniform numbers; false when nothing is sent (below the surface,
 * total internal reflection of a rough facet, ...). */
bool material_sample(const material *m, vec3 ng, vec3 wo, double u0, double u1, double u2, bsdf_sample *s);
/* The solid-angle pdf of material_sample's non-delta lobes (delta lobes: 0). */
double material_pdf(const material *m, vec3 ng, vec3 wo, vec3 wi);
/* Scatters nothing (the path ends there). */
bool material_is_black(const material *m);
/* Scatters only into delta lobes: next-event estimation at it can bring nothing. */
bool material_is_delta(const material *m);
/* The type's name in scene files ("diffuse", "dielectric", ...). */
const char *material_type_name(material_type t);

#endif
