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
#include "surface/material_params.h"


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
