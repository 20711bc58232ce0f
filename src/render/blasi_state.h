/* blasi_state.h - what the files of Blasi's method share (private to src/render/blasi*.c):
 * the state blasi_prepare builds (blasi_setup.c) and both passes read (blasi_light.c, the first;
 * blasi_view.c, the second), its limits, and the voxel integral both passes use. */
#ifndef BRUME_RENDER_BLASI_STATE_H
#define BRUME_RENDER_BLASI_STATE_H

#include <math.h>

#include "render/blasi.h"

static inline const blasi_options *blasi_opts(const brume_scene *s) { return scene_options(s, METHOD_OPTIONS_BLASI); }

#define BLASI_MAX_VOXELS (1u << 24)   /* over all media */
/* Limits that keep every walk finite (docs/scene-format.md#limits): uniform steps across
 * the media (and BLASI_MAX_INTERCEPTS in blasi_light.c: interceptions of one light ray). */
#define BLASI_MAX_STEPS 1e7
#define BLASI_BLOCK 4              /* voxels per side of an occupancy block (empty-space skipping) */
#define BLASI_SKIP_CELLS 192       /* skip empty blocks when nx + ny + nz exceeds this: a ray through a
                                      smaller grid crosses too few voxels for the restarts to pay */
#define BLASI_R_DEFAULT 0.1        /* "a small proportion (r ~ 0.1) of isotropic scattering" (4.2) */
#define BLASI_SLABS 6               /* diagonal slabs around the non-empty voxels (walk_begin_one) */

typedef struct blasi_medium {
    const medium *md;
    density *vox;        /* owned: a blob field voxelized at blasi.voxels, or NULL (md->rho is a grid) */
    int n[3];
    size_t nvox, offset; /* its voxels are [offset, offset + nvox) of the state's arrays */
    affine3 w2v;         /* world -> voxel space */
    affine3 v2w;         /* voxel -> world space */
    double volume;       /* world volume of one voxel */
    double chord;        /* mean chord of one voxel, 4 volume / surface area (blasi.gather = printed) */
    double sigma_bar;    /* Eq. 10: mean over channels of sigma_s, per unit density */
    color sigma_t;       /* sigma_a + sigma_s */
    color kappa;         /* view attenuation per unit density: sigma_a or sigma_t */
    color emit;          /* sigma_a Le: emitted radiance per unit length per unit density */
    bool emits;          /* emit is not black */
    bool view_grey;      /* kappa and sigma_t each the same in every channel */
    double r;            /* fraction stored isotropically at an interception */
    const phase *dir;    /* the directional lobe (the medium's, or dir_owned) */
    phase *dir_owned;
    bool skip;           /* walk occupancy blocks first (BLASI_SKIP_CELLS) */
    bool trilinear;      /* blasi.interpolate = trilinear: the density along a ray is st->field's
                            trilinear field, st->rho its mean over each voxel (blasi_field.c) */
    int occ_lo[3], occ_hi[3]; /* the box of the voxels with rho > 0, [lo, hi) (all 0 if none) */
    double slab_lo[BLASI_SLABS], slab_hi[BLASI_SLABS]; /* the voxels with rho > 0 between the planes
                                                          n . x = lo and hi, n = blasi_slab_n (voxel space) */
    vec3 occ_c, occ_e;   /* a world box holding that box (centre, half-extents slightly enlarged;
                            e < 0 when it is empty), for line_misses_box */
    int bn[3];           /* occupancy blocks per axis: ceil(n / BLASI_BLOCK) */
    unsigned char *occ;  /* per block: 1 if any of its voxels has rho > 0 */
} blasi_medium;

struct blasi_state {
    int nm;
    blasi_medium m[SCENE_MAX_MEDIA];
    size_t nvox;      /* over all media */
    float *rho;       /* nvox densities, constant per voxel; a trilinear medium's: the field's mean
                         over the voxel (0 exactly where the field is 0 throughout the voxel) */
    float *field;     /* nvox: a trilinear medium's voxel values, the field's samples at the voxels'
                         centres; NULL when no medium is trilinear */
    float *S;         /* 3 nvox: isotropic source, radiance per unit length (RGB) */
    box3 bounds;      /* union of the media's world boxes */
    box3 light_box;   /* union of the world boxes of the media's non-empty voxels: the light
                         rays aim at it (empty when every voxel is empty) */
    vec3 centre;      /* bounding sphere of `light_box` */
    double radius;
    double step;      /* first pass: 0 = voxel walk */
    double threshold;
    blasi_exit exit;
    blasi_view_atten view;
    bool gather_printed; /* blasi.gather = printed: A L_V per voxel visited (view_voxel) */
    bool area_lights; /* some light is a sphere or a disk: view rays may end on it */
    bool sun_disks;   /* some distant light has a disk: view rays may see it */
    blasi_stats stats;
};

/* T = exp(-tau) and f = (1 - T) / tau, the fraction of a voxel's length that its source
 * fills, for tau >= 0. Most voxels are optically thin (tau ~ 0.01 in the paper's scenes):
 * there the Taylor series of f to tau^7 (truncation below 1e-15 for tau < 1/16) gives
 * both without calling exp. */
static inline void voxel_exp(double tau, double *T, double *f)
{
    if (tau < 0.0625) {
        /* Estrin's scheme: the terms in pairs, so the series costs a few multiplications of
         * latency rather than a chain of eight */
        double x = tau, x2 = x * x, x4 = x2 * x2;
        double p01 = 1.0 - x * (1.0 / 2), p23 = 1.0 / 6 - x * (1.0 / 24), p45 = 1.0 / 120 - x * (1.0 / 720),
               p67 = 1.0 / 5040 - x * (1.0 / 40320);
        *f = (p01 + x2 * p23) + x4 * (p45 + x2 * p67);
        *T = 1.0 - x * *f;
        return;
    }
    *T = exp(-tau);
    *f = (1.0 - *T) / tau;
}

static inline bool col_is_grey(color a)
{
    for (int c = 1; c < BRUME_NSAMPLES; c++)
        if (a.c[c] != a.c[0])
            return false;
    return true;
}

/* blasi_field.c, for a trilinear medium bm (points in its voxel space): the field at u; its
 * mean along the segment [a, b] inside one voxel (exact: Simpson's rule between the planes
 * through the voxel's centre, where the field is a cubic along the segment), and with S not
 * NULL the mean there of the stored source st->S read the same way (voxel values at the
 * centres, trilinear between them); and the field's means over bm's voxels from st->field
 * into st->rho. */
double blasi_field_point(const blasi_state *st, const blasi_medium *bm, vec3 u);
double blasi_crossing_mean(const blasi_state *st, const blasi_medium *bm, vec3 a, vec3 b, color *S);
void blasi_field_means(blasi_state *st, const blasi_medium *bm);

/* The first pass (blasi_light.c): fills st->S from the lights, and st->stats. */
brume_status blasi_light_pass(const brume_scene *s, blasi_state *st);

#endif
