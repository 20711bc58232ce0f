/* test_pbrt_grid.c - pbrt-v4's grid media as pbrt-v4 samples and bounds them (docs/pbrt.md):
 * SampledGrid::Lookup puts the samples at the cell centres of [p0, p1], reads them
 * trilinearly with samples beyond the grid taken as 0, and the medium is 0 outside
 * [p0, p1]. Checked against that lookup written out here from pbrt-v4's definition, at
 * points inside, on both sides of every face and beyond them, on a 4 x 4 x 4 grid whose
 * faces are not zero; and in a render, against the optical depth integrated by hand. */
#include "test.h"

#include <math.h>

#include "brume.h"
#include "scene/scene.h"

/* pbrt-v4's SampledGrid<float>::Lookup at p in [0, 1]^3 (the medium's bounds mapped by
 * Bounds3::Offset): pSamples = p n - 1/2, trilinear between the samples at floor(pSamples)
 * and the next, a sample outside [0, n) reading 0. */
static double pbrt_sample(const double *v, const int n[3], int x, int y, int z)
{
    if (x < 0 || y < 0 || z < 0 || x >= n[0] || y >= n[1] || z >= n[2])
        return 0.0;
    return v[((size_t)z * (size_t)n[1] + (size_t)y) * (size_t)n[0] + (size_t)x];
}

static double pbrt_lookup(const double *v, const int n[3], const double p[3])
{
    double s[3], d[3];
    int i[3];
    for (int k = 0; k < 3; k++) {
        s[k] = p[k] * n[k] - 0.5;
        i[k] = (int)floor(s[k]);
        d[k] = s[k] - i[k];
    }
    double r = 0.0;
    for (int c = 0; c < 8; c++) {
        int dx = c & 1, dy = (c >> 1) & 1, dz = c >> 2;
        double w = (dx ? d[0] : 1 - d[0]) * (dy ? d[1] : 1 - d[1]) * (dz ? d[2] : 1 - d[2]);
        r += w * pbrt_sample(v, n, i[0] + dx, i[1] + dy, i[2] + dz);
    }
    return r;
}

/* pbrt-v4's GridMedium density at the world point q: 0 outside [p0, p1]. */
static double pbrt_density(const double *v, const int n[3], const double p0[3], const double p1[3], const double q[3])
{
    double p[3];
    for (int k = 0; k < 3; k++) {
        if (q[k] < p0[k] || q[k] > p1[k])
            return 0.0;
        p[k] = (q[k] - p0[k]) / (p1[k] - p0[k]);
    }
    return pbrt_lookup(v, n, p);
}

/* The pbrt file of a uniformgrid "g" with these 64 values over [p0, p1], bounded by an
 * interface sphere; the scene, committed when asked. */
static brume_scene *load_grid(const char *head, const double *v, const double p0[3], const double p1[3], bool commit)
{
    char *text = malloc(8192);
    ASSERT_TRUE(text != NULL);
    int k = snprintf(text, 8192, "%sMakeNamedMedium \"g\" \"string type\" \"uniformgrid\" \"integer nx\" 4 "
                                 "\"integer ny\" 4 \"integer nz\" 4\n  \"point3 p0\" [%.17g %.17g %.17g] \"point3 p1\" "
                                 "[%.17g %.17g %.17g]\n  \"rgb sigma_a\" [0.1 0.1 0.1] \"rgb sigma_s\" [0 0 0] "
                                 "\"float density\" [",
                     head, p0[0], p0[1], p0[2], p1[0], p1[1], p1[2]);
    for (int i = 0; i < 64; i++)
        k += snprintf(text + k, 8192 - (size_t)k, " %.17g", v[i]);
    snprintf(text + k, 8192 - (size_t)k, "]\nAttributeBegin\nTranslate 0 0 2\nMaterial \"interface\"\n"
                                         "MediumInterface \"g\" \"\"\nShape \"sphere\" \"float radius\" 5\nAttributeEnd\n");
    const char *path = test_tmp_path("grid.pbrt");
    test_write_file(path, text);
    free(text);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK ||
        (commit && brume_scene_commit(ctx, s) != BRUME_OK))
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_context_release(ctx);
    remove(path);
    return s;
}

#define HEAD                                                                                     \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"                   \
    "Sampler \"halton\" \"integer pixelsamples\" [64]\n"                                         \
    "Scale -1 1 1\nLookAt 0 0 -8  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [1]\n"      \
    "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n"

/* Samples 1 + x + 4 y + 16 z over [-1, 3] x [0, 2] x [2, 3] (cells 1, 0.5 and 0.25 wide):
 * brume's field is pbrt-v4's lookup at every point of a lattice that steps through each
 * face (1e-3 of a cell either side) and the half cell beyond it; and by hand at a sample
 * (voxel (1, 2, 3): 58), inside a face (half of voxel (0, 1, 1): 10.5), inside a corner (an
 * eighth of voxel (0, 0, 0)) and just outside a face (0). The view is right-handed in
 * brume's sense (Scale -1 1 1 before LookAt), so brume's world is pbrt's. */
TEST(uniformgrid_is_pbrt_lookup_to_the_faces)
{
    const int n[3] = {4, 4, 4};
    const double p0[3] = {-1, 0, 2}, p1[3] = {3, 2, 3};
    double v[64];
    for (int i = 0; i < 64; i++)
        v[i] = 1 + i % 4 + 4 * (i / 4 % 4) + 16 * (i / 16);
    brume_scene *s = load_grid(HEAD, v, p0, p1, true);
    const density *rho = s->media[0].rho;
    int checked = 0;
    for (int a = 0; a <= 24; a++)
        for (int b = 0; b <= 24; b++)
            for (int c = 0; c <= 24; c++) {
                const int t[3] = {a, b, c};
                double q[3];
                for (int k = 0; k < 3; k++) { /* from 0.75 cell before p0 to 0.75 beyond p1 */
                    double cell = (p1[k] - p0[k]) / n[k], u = -0.75 + (n[k] + 1.5) * t[k] / 24.0;
                    if (fabs(u) < 1e-9 || fabs(u - n[k]) < 1e-9) /* a face: step to either side of it */
                        u += (t[k] % 2 ? 1e-3 : -1e-3);
                    q[k] = p0[k] + u * cell;
                }
                double want = pbrt_density(v, n, p0, p1, q), got = density_eval(rho, v3(q[0], q[1], q[2]));
                if (!(fabs(got - want) <= 1e-5 * (1 + want)))
                    TEST_FAIL("at (%g, %g, %g): brume %.9g, pbrt-v4's lookup %.9g", q[0], q[1], q[2], got, want);
                checked++;
            }
    ASSERT_EQ_INT(checked, 25 * 25 * 25);
    ASSERT_NEAR(density_eval(rho, v3(0.5, 1.25, 2.875)), 58.0, 1e-5);
    ASSERT_NEAR(density_eval(rho, v3(-1.0 + 1e-9, 0.75, 2.375)), 10.5, 1e-5);
    ASSERT_NEAR(density_eval(rho, v3(-1.0 + 1e-9, 1e-9, 2.0 + 1e-9)), 0.125, 1e-5);
    ASSERT_NEAR(density_eval(rho, v3(-1.0 - 1e-3, 0.75, 2.375)), 0.0, 0);
    brume_scene_release(s);
}

/* An absorbing grid (sigma_a 0.1) constant across x and y, f = 2, 3, 5, 7 along z over
 * [0, 4] (cells 1 deep), seen along +z through its middle against a sky of 1: pbrt-v4's
 * field along the ray rises from f0 / 2 at the face to f0 at the first centre, is linear
 * between centres and falls to f3 / 2 at the far face, so the optical depth is
 * 0.1 (3/8 f0 + (f0 + f1) / 2 + (f1 + f2) / 2 + (f2 + f3) / 2 + 3/8 f3) = 1.5875 and every
 * pixel exp(-1.5875) (a grid held out half a cell past its faces adds 0.1 (f0 + f3) / 8:
 * 11 % darker). Rays at the corners are longer by 8e-5 at most. Tolerance: 4 standard errors
 * plus that. */
TEST(uniformgrid_transmittance_is_pbrt)
{
    const double f[4] = {2, 3, 5, 7}, p0[3] = {-2, -2, 0}, p1[3] = {2, 2, 4};
    double v[64];
    for (int i = 0; i < 64; i++)
        v[i] = f[i / 16];
    brume_scene *s = load_grid(HEAD, v, p0, p1, false);
    brume_image *img = test_render_scene(s, -1, 17);
    int npix = brume_image_width(img) * brume_image_height(img);
    double tau = 0.1 * (0.375 * f[0] + (f[0] + f[1]) / 2 + (f[1] + f[2]) / 2 + (f[2] + f[3]) / 2 + 0.375 * f[3]);
    ASSERT_NEAR(tau, 1.5875, 1e-12);
    double want = exp(-tau);
    for (int c = 0; c < 3; c++) {
        double mean, se;
        test_channel_mean(brume_image_pixels(img), npix, c, &mean, &se);
        if (!(fabs(mean - want) <= 4.0 * se + tau * 8e-5 * want + 1e-6))
            TEST_FAIL("channel %d: mean %.6f, want exp(-%g) = %.6f (se %g)", c, mean, tau, want, se);
    }
    brume_image_release(img);
    brume_scene_release(s);
}

TEST_MAIN(uniformgrid_is_pbrt_lookup_to_the_faces, uniformgrid_transmittance_is_pbrt)
