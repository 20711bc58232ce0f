/* material_params.h - a material's parameters (the struct the scene fills and material.h's
 * BSDFs read), apart from the functions, so that the BxDFs (bsdf.h) read them without
 * depending on material.h, which calls them. Units and meanings in material.h. */
#ifndef BRUME_SURFACE_MATERIAL_PARAMS_H
#define BRUME_SURFACE_MATERIAL_PARAMS_H

#include <stdbool.h>

#include "core/color.h"

typedef enum material_type {
    MATERIAL_DIFFUSE = 0, /* Lambert plus Phong: brume's own, the default */
    MATERIAL_DIELECTRIC,
    MATERIAL_CONDUCTOR,
    MATERIAL_COATEDDIFFUSE,
    MATERIAL_MIX, /* pbrt-v4's MixMaterial: one of mix[] per shading point, never shaded itself */
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
    /* NULL, or the albedo as a texture of the hit's (u, v) (surface/texture.h): diffuse's
     * albedo, coateddiffuse's reflectance, conductor's reflectance (then eta 1 and the k of
     * that normal reflectance). Owned by the surfaces object, evaluated into the hit's own
     * copy of the material (surface_hit.shade, material_hit.h's material_at) */
    struct texture *albedo_tex;
    /* NULL, or pbrt-v4's roughness r as a float texture: alpha = sqrt(r) when remap, else r */
    struct texture *alpha_tex;
    bool remap;
    /* MATERIAL_MIX: mix[1] with probability amount (amount_tex's value when not NULL, at the
     * hit's (u, v)), else mix[0]; both owned */
    struct material *mix[2];
    double amount;
    struct texture *amount_tex;
    /* NULL, or pbrt-v4's displacement d(u, v) (a float texture, world units along the front
     * normal): bump mapping, the hit's shading normal (surface_hit.ns) tilted by it */
    struct texture *bump_tex;
    /* NULL, or textures in place of eta_c, k_c (conductor), thickness, g, layer_albedo
     * (coateddiffuse), evaluated at the hit as albedo_tex is */
    struct texture *eta_tex, *k_tex, *thickness_tex, *g_tex, *layer_albedo_tex;
    double eta;      /* dielectric, coateddiffuse's coat: index behind ng over in front, > 0 */
    color eta_c, k_c; /* conductor: complex index of refraction eta + i k per channel */
    double alpha;    /* Trowbridge-Reitz alpha (isotropic); < MATERIAL_SMOOTH_ALPHA: smooth */
    double thickness;    /* coateddiffuse: the layer's optical thickness (sigma_t = 1) */
    color layer_albedo;  /* coateddiffuse: single-scattering albedo in the layer; 0 = none */
    double g;            /* coateddiffuse: Henyey-Greenstein g in the layer */
    int max_depth;       /* coateddiffuse: the random walk's most events */
    int nsamples;        /* coateddiffuse: walks per evaluation */
} material;

#endif
