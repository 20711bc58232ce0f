/* material.h - surface reflectance: a Lambertian lobe plus an optional normalized Phong
 * lobe, and emission. Directions are unit vectors pointing away from the surface (wo
 * towards the viewer, wi towards the light); n is the shading normal on the side wo is.
 *
 *   f(wi, wo) = albedo / pi + specular (e + 2) / (2 pi) max(0, r . wi)^e,  r = reflect(wo, n)
 *
 * The Phong lobe with the (e + 2) / 2 pi normalization reflects at most `specular` at any
 * incidence (Lafortune and Willems 1994); albedo + specular <= 1 per channel keeps the
 * surface from creating energy, which the scene reader enforces. */
#ifndef BRUME_SURFACE_MATERIAL_H
#define BRUME_SURFACE_MATERIAL_H

#include <stdbool.h>

#include "core/color.h"
#include "core/vec.h"

typedef struct material {
    color albedo;    /* diffuse reflectance in [0, 1] */
    color specular;  /* Phong lobe reflectance in [0, 1]; 0 = matte */
    double exponent; /* Phong exponent e >= 0 (larger = sharper) */
    color emission;  /* emitted radiance, W m^-2 sr^-1, from the front side(s) */
    bool two_sided_emission;
    /* NULL, or the albedo as a texture of the hit's (u, v) (surface/texture.h): owned by the
     * surfaces object, evaluated into the hit's own copy of the material (surface_hit.shade) */
    struct texture *albedo_tex;
} material;

/* f(wi, wo) (per steradian), without the cosine. */
color material_eval(const material *m, vec3 n, vec3 wo, vec3 wi);
/* Samples wi (in proportion to the lobes' reflectances) with its solid-angle pdf; returns
 * false when the sample falls below the surface. */
bool material_sample(const material *m, vec3 n, vec3 wo, double u0, double u1, double u2, vec3 *wi, double *pdf);
double material_pdf(const material *m, vec3 n, vec3 wo, vec3 wi);
bool material_is_black(const material *m);

#endif
