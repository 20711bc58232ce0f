/* test_gpu.c - what of the GPU path can be checked without a GPU (docs/gpu.md, "Testing"):
 *   - the device math (gpu/devmath.h) against the host's libm, over the ranges the
 *     estimator uses, within its stated error;
 *   - the scene's copy for the device (core/arena.h, gpu/device_scene.c): relocated to the
 *     address of its own host buffer, the copy renders bit for bit the original's values
 *     on the CPU, for scenes that exercise every pointer the copy carries (dense and
 *     NanoVDB grids, several media, mixture and tabulated phase functions, a temperature
 *     field, an environment map, motion, a velocity and its moved majorants, the sun
 *     roulette's grid, solid objects with their hierarchy and emitters, a blob field);
 *   - brume's own hierarchy of solid objects (core/bvh.h, what the GPU traverses) gives
 *     Embree's hits and occlusions on the CPU;
 *   - what the GPU refuses (the Blasi and Stam methods), with one line;
 *   - a GPU asked for where there is no driver: one line, and the CPU's images unchanged.
 * The GPU itself is checked by tests/gpu/run.sh on a machine that has one. */
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "brume.h"
#include "core/error.h"
#include "density/density.h"
#include "core/arena.h"
#include "gpu/devmath.h"
#include "gpu/device_scene.h"
#include "io/grid_io.h"
#include "render/integrator.h"
#include "scene/scene.h"
#include "surface/surfaces.h"
#include "test.h"

/* |a - b| in units of b's last place (the spacing of doubles at |b|) */
static double ulps(double a, double b)
{
    if (a == b)
        return 0.0;
    double u = nextafter(fabs(b), INFINITY) - fabs(b);
    return fabs(a - b) / u;
}

/* a fixed sequence of uniforms (a 64-bit LCG) */
static double lcg(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) * 0x1p-53;
}

/* Each function within its stated bound on 10^6 arguments of the ranges the estimator
 * meets; sin and cos as an absolute error (their relative error is unbounded near their
 * zeros, as libm's own), pow relative to |y log x| + 1 (the error of exp(y log x)). */
TEST(device_math_against_libm)
{
    double e_exp = 0, e_log = 0, e_log1p = 0, e_sin = 0, e_cos = 0, e_tan = 0, e_acos = 0, e_atan2 = 0, e_cbrt = 0,
           e_pow = 0;
    uint64_t s = 1;
    for (int i = 0; i < 1000000; i++) {
        double u = lcg(&s), v = lcg(&s);
        double x = (u - 0.5) * 1400.0;
        e_exp = fmax(e_exp, ulps(devmath_exp(x), exp(x)));
        double y = exp((u - 0.5) * 1400.0);
        e_log = fmax(e_log, ulps(devmath_log(y), log(y)));
        double z = (u - 0.5) * 2e-3 * pow(10.0, 6.0 * v);
        e_log1p = fmax(e_log1p, ulps(devmath_log1p(z), log1p(z)));
        double w = (u - 0.5) * 200.0;
        e_sin = fmax(e_sin, fabs(devmath_sin(w) - sin(w)));
        e_cos = fmax(e_cos, fabs(devmath_cos(w) - cos(w)));
        double t = (u - 0.5) * 3.0; /* tan on (-1.5, 1.5): the camera's half field of view */
        e_tan = fmax(e_tan, ulps(devmath_tan(t), tan(t)));
        double c = 2.0 * u - 1.0;
        e_acos = fmax(e_acos, ulps(devmath_acos(c), acos(c)));
        double a = (u - 0.5) * 50.0, b = (v - 0.5) * 6.0;
        e_atan2 = fmax(e_atan2, ulps(devmath_atan2(a, b), atan2(a, b)));
        double q = (u - 0.5) * 1e6;
        e_cbrt = fmax(e_cbrt, ulps(devmath_cbrt(q), cbrt(q)));
        double px = u * 10.0, py = (v - 0.5) * 40.0;
        double ref = pow(px, py);
        if (ref > 0.0 && isfinite(ref))
            e_pow = fmax(e_pow, ulps(devmath_pow(px, py), ref) / (fabs(py * log(px)) + 1.0));
    }
    printf("max error: exp %.2f log %.2f log1p %.2f tan %.2f acos %.2f atan2 %.2f cbrt %.2f ulp; pow %.2f ulp per "
           "unit of |y ln x| + 1; sin %.3g cos %.3g absolute\n",
           e_exp, e_log, e_log1p, e_tan, e_acos, e_atan2, e_cbrt, e_pow, e_sin, e_cos);
    ASSERT_TRUE(e_exp <= DEVMATH_MAX_ULP && e_log <= DEVMATH_MAX_ULP && e_log1p <= DEVMATH_MAX_ULP);
    ASSERT_TRUE(e_tan <= DEVMATH_MAX_ULP && e_acos <= DEVMATH_MAX_ULP && e_atan2 <= DEVMATH_MAX_ULP);
    ASSERT_TRUE(e_cbrt <= DEVMATH_MAX_ULP && e_pow <= DEVMATH_MAX_ULP);
    ASSERT_TRUE(e_sin <= 1e-13 && e_cos <= 1e-13);
    /* special values the estimator can meet */
    ASSERT_TRUE(devmath_exp(-INFINITY) == 0.0 && devmath_exp(INFINITY) == INFINITY && isnan(devmath_exp(NAN)));
    ASSERT_TRUE(devmath_log(0.0) == -INFINITY && isnan(devmath_log(-1.0)) && devmath_log(1.0) == 0.0);
    ASSERT_TRUE(ulps(devmath_log(4.9e-324), log(4.9e-324)) <= DEVMATH_MAX_ULP);
    ASSERT_TRUE(devmath_pow(0.0, 2.0) == 0.0 && devmath_pow(2.0, 0.0) == 1.0 && devmath_pow(-2.0, 3.0) == -8.0);
    ASSERT_TRUE(devmath_nextafter(1.0, 2.0) == nextafter(1.0, 2.0) && devmath_nextafter(0.0, 1.0) == nextafter(0.0, 1.0));
    ASSERT_TRUE(devmath_nextafter(-1.0, INFINITY) == nextafter(-1.0, INFINITY));
}

/* The scene of `json` and its copy relocated to its own host buffer render the same path
 * values, bit for bit, for n camera rays through the media's box. */
static void copy_renders_the_same(const char *json, int n)
{
    brume_scene *s = NULL;
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_EQ_INT(device_scene_check(s, INTEGRATOR_PATH), BRUME_OK);
    void *state = NULL;
    ASSERT_EQ_INT(integrator_prepare(INTEGRATOR_PATH, s, &state), BRUME_OK);
    /* the copy traverses brume's hierarchy: the original too, so that the two agree bit for
     * bit (bvh_matches_embree compares the hierarchy with Embree) */
    if (s->surf)
        ASSERT_EQ_INT(surfaces_use_bvh(s->surf), BRUME_OK);
    dev_arena a;
    arena_init(&a, 0);
    size_t state_at = ARENA_NULL;
    size_t at = device_scene_put(s, state, &a, &state_at);
    ASSERT_TRUE(!a.failed && at != ARENA_NULL);
    arena_relocate(&a, (uint64_t)(uintptr_t)a.buf);
    const brume_scene *c = (const brume_scene *)arena_at(&a, at);
    const void *cstate = state_at == ARENA_NULL ? NULL : arena_at(&a, state_at);
    ASSERT_TRUE((c->surf != NULL) == (s->surf != NULL) && c->prepared == NULL && (cstate != NULL) == (state != NULL));
    ASSERT_TRUE(c->surf == NULL || (const void *)c->surf != (const void *)s->surf);
    /* the copy shares nothing with the original */
    for (int m = 0; m < s->nmedia; m++)
        ASSERT_TRUE((const void *)c->media[m].rho != (const void *)s->media[m].rho);
    int differ = 0, nonzero = 0;
    for (int i = 0; i < n; i++) {
        double u = (i + 0.5) / n;
        ray r;
        r.o = s->cam.position;
        r.d = v3_normalize(v3_sub(v3(0.6 * (u - 0.5), 0.4 * sin(40.0 * u), 0.0), s->cam.position));
        r.time = 0.5 * u;
        rng g0 = rng_make(7, (uint64_t)i, 0), g1 = g0;
        bool h0 = false, h1 = false;
        color T0 = col(1.0), T1 = col(1.0);
        color L0 = path_Li_alpha(s, state, r, s->settings.max_depth, &g0, &h0, &T0);
        color L1 = path_Li_alpha(c, cstate, r, c->settings.max_depth, &g1, &h1, &T1);
        differ += memcmp(&L0, &L1, sizeof L0) != 0 || memcmp(&T0, &T1, sizeof T0) != 0 || h0 != h1;
        nonzero += col_max(L0) > 0.0;
    }
    printf("%d of %d rays differ (%d with light)\n", differ, n, nonzero);
    ASSERT_EQ_INT(differ, 0);
    ASSERT_TRUE(nonzero > n / 4); /* the rays met the media and their light */
    arena_free(&a);
    integrator_finish(INTEGRATOR_PATH, state);
    brume_scene_release(s);
    brume_context_release(ctx);
}

TEST(device_copy_dense_media)
{
    /* two overlapping media, one dense fractal grid with a Schlick mixture, one constant with a
     * tabulated-free HG; a sun (roulette grid, lobe tables), a point light, a moving medium */
    copy_renders_the_same(
        "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 30},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.2], \"irradiance\": 3.0},"
        "   {\"type\": \"point\", \"position\": [1, 2, 1], \"intensity\": 2.0}],"
        " \"background\": [0.2, 0.3, 0.5],"
        " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 6.0,"
        "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 3, \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
        "   \"phase\": {\"type\": \"mixture\", \"lobes\": [{\"weight\": 0.7, \"phase\": {\"type\": \"hg\", \"g\": 0.8}},"
        "                                               {\"weight\": 0.3, \"phase\": {\"type\": \"hg\", \"g\": -0.3}}]}},"
        "  {\"sigma_a\": 0.05, \"sigma_s\": [0.3, 0.4, 0.5],"
        "   \"density\": {\"type\": \"constant\", \"bounds\": [[-2, -2, -0.5], [2, 2, 0.5]]},"
        "   \"phase\": {\"type\": \"rayleigh\"},"
        "   \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}}, {\"time\": 1, \"transform\": {\"translate\": [0.3, 0, 0]}}]}],"
        " \"render\": {\"max_depth\": 64}}",
        400);
}

/* The 1/16 Disney cloud, with the tree's majorants (hashes, entries, tables) as a large grid
 * gets them, and an environment map with its sampling tables. */
TEST(device_copy_nanovdb_and_environment)
{
    const char *env = test_tmp_path("env.pfm");
    {
        FILE *f = fopen(env, "wb");
        ASSERT_TRUE(f != NULL);
        fprintf(f, "PF\n8 4\n-1\n");
        for (int i = 0; i < 8 * 4 * 3; i++) {
            float v = 0.1f + 0.05f * (float)(i % 7);
            fwrite(&v, sizeof v, 1, f);
        }
        fclose(f);
    }
    uint64_t old = nanovdb_set_cell_grid_limit(0);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 30},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.2], \"irradiance\": 3.0,"
             "   \"angular_radius\": 0.02}],"
             " \"background\": {\"file\": \"%s\", \"scale\": 2.0},"
             " \"media\": [{\"sigma_a\": 0.5, \"sigma_s\": 4.0,"
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s/wdas_cloud_sixteenth.vdb\","
             "                 \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
             "   \"phase\": {\"type\": \"hazy\"}}],"
             " \"render\": {\"max_depth\": 32}}",
             env, BRUME_DATA_DIR);
    copy_renders_the_same(json, 400);
    nanovdb_set_cell_grid_limit(old);
}

/* Solid objects as the default scene has them and more: a ground plane, a box, a moving
 * sphere, an emissive quad (an area light of the surfaces' own) over a medium. */
TEST(device_copy_surfaces)
{
    copy_renders_the_same(
        "{\"camera\": {\"position\": [0, 1, 6], \"look_at\": [0, 0, 0], \"fov\": 40,"
        "  \"shutter\": [0, 1]},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.2], \"irradiance\": 3.0}],"
        " \"background\": [0.2, 0.3, 0.5],"
        " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 3.0,"
        "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 16, \"seed\": 3, \"bounds\": [[-1, -0.5, -1], [1, 1, 1]]}}],"
        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, -0.6, 0], \"normal\": [0, 1, 0], \"size\": 40,"
        "                 \"material\": {\"albedo\": [0.3, 0.32, 0.28]}},"
        "   {\"type\": \"box\", \"min\": [1.2, -0.6, -0.5], \"max\": [1.8, 0.8, 0.1], \"material\": {\"albedo\": 0.6}},"
        "   {\"type\": \"sphere\", \"center\": [-1.5, 0, 0.5], \"radius\": 0.4, \"material\": {\"albedo\": 0.5},"
        "    \"keyframes\": [{\"time\": 0, \"transform\": {\"translate\": [0, 0, 0]}},"
        "                   {\"time\": 1, \"transform\": {\"translate\": [0, 0.4, 0]}}]},"
        "   {\"type\": \"quad\", \"corner\": [-0.5, 2.0, -0.5], \"edge_u\": [1, 0, 0], \"edge_v\": [0, 0, 1],"
        "    \"material\": {\"albedo\": 0, \"emission\": [4, 3.5, 3], \"two_sided\": true}}],"
        " \"render\": {\"max_depth\": 16}}",
        400);
}

/* A cloud of 60 blobs under a sun; %s: more top-level keys, each followed by a comma. */
#define BLOB_CLOUD_JSON                                                                                            \
    "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 30},"                                 \
    " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.2], \"irradiance\": 3.0}],"               \
    " \"background\": [0.2, 0.3, 0.5],"                                                                           \
    " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 4.0,"                                                           \
    "   \"density\": {\"type\": \"blobs\", \"generators\": [{\"type\": \"cloud\", \"center\": [0, 0, 0],"          \
    "     \"radii\": [1.0, 0.6, 0.8], \"count\": 60, \"seed\": 4}]}}],"                                           \
    " %s \"render\": {\"max_depth\": 32}}"

/* Stam's blob field (its hierarchy and the per-blob tables) rendered by the path tracer. */
TEST(device_copy_blobs)
{
    char json[2048];
    snprintf(json, sizeof json, BLOB_CLOUD_JSON, "");
    copy_renders_the_same(json, 400);
}

/* The same with a tabulated kernel (stam.kernel = table): the copy carries the kernel's
 * table of W, and its point densities are the original's bit for bit. */
TEST(device_copy_blobs_kernel_table)
{
    const char *path = test_tmp_path("cone.txt");
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f);
    for (int k = 0; k <= 64; k++)
        fprintf(f, "%.17g %.17g\n", k * 2.0 / 64, 1.0 - k / 64.0);
    fclose(f);
    char extra[1100], json[4096];
    snprintf(extra, sizeof extra, "\"stam\": {\"kernel\": \"table\", \"kernel_file\": \"%s\"},", path);
    snprintf(json, sizeof json, BLOB_CLOUD_JSON, extra);
    copy_renders_the_same(json, 400);
    remove(path);
}


/* pbrt-v4's cloud (its permutation carried inside the density) and an equal-area sky turned
 * and mirrored (its frame and mapping inside the background), as the GPU's copy has them. */
TEST(device_copy_pbrt_cloud_and_equal_area_sky)
{
    char env[512];
    snprintf(env, sizeof env, "%s", test_tmp_path("sky.pfm"));
    {
        FILE *f = fopen(env, "wb");
        ASSERT_TRUE(f != NULL);
        fprintf(f, "PF\n8 8\n-1\n");
        for (int i = 0; i < 8 * 8 * 3; i++) {
            float v = 0.1f + 0.3f * (float)(i % 5);
            fwrite(&v, sizeof v, 1, f);
        }
        fclose(f);
    }
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 30},"
             " \"background\": {\"file\": \"%s\", \"mapping\": \"equal_area\","
             "   \"transform\": {\"rotate\": {\"axis\": [1, 0, 0], \"angle\": -90}, \"scale\": [-1, 1, 1]}},"
             " \"media\": [{\"sigma_a\": 0.2, \"sigma_s\": 5.0,"
             "   \"density\": {\"type\": \"pbrt_cloud\", \"bounds\": [[-1, -1, -1], [1, 1, 1]]},"
             "   \"phase\": {\"type\": \"hg\", \"g\": 0.6}}],"
             " \"render\": {\"max_depth\": 32}}",
             env);
    copy_renders_the_same(json, 400);
    remove(env);
}

/* A triangle soup, a box, spheres and moving objects: brume's hierarchy (the GPU's) and
 * Embree (the CPU's) agree on the nearest hit (object, primitive, distance and normal) and on
 * occlusion, ray for ray. Embree intersects in single precision and brume's hierarchy in
 * double, so a ray that grazes an edge may go either way: such rays are counted, and must
 * be rarer than one in a thousand; distances agree to single precision of the ray's scale. */
TEST(bvh_matches_embree)
{
    surfaces *sf[2];
    material m = {.albedo = col(0.5)};
    uint64_t seed = 11;
    for (int v = 0; v < 2; v++) {
        sf[v] = surfaces_new();
        ASSERT_TRUE(sf[v] != NULL);
        uint64_t g = seed;
        enum { NT = 300 };
        double pos[9 * NT];
        int idx[3 * NT];
        for (int i = 0; i < NT; i++) {
            vec3 c = v3(4.0 * (lcg(&g) - 0.5), 4.0 * (lcg(&g) - 0.5), 4.0 * (lcg(&g) - 0.5));
            for (int k = 0; k < 3; k++) {
                pos[9 * i + 3 * k + 0] = c.x + 0.6 * (lcg(&g) - 0.5);
                pos[9 * i + 3 * k + 1] = c.y + 0.6 * (lcg(&g) - 0.5);
                pos[9 * i + 3 * k + 2] = c.z + 0.6 * (lcg(&g) - 0.5);
                idx[3 * i + k] = 3 * i + k;
            }
        }
        ASSERT_EQ_INT(surfaces_add_mesh(sf[v], pos, 3 * NT, idx, NT, &m, "soup"), BRUME_OK);
        double ground[] = {-5, -2.5, -5, 5, -2.5, -5, 5, -2.5, 5, -5, -2.5, 5};
        int gi[] = {0, 2, 1, 0, 3, 2};
        ASSERT_EQ_INT(surfaces_add_mesh(sf[v], ground, 4, gi, 2, &m, "ground"), BRUME_OK);
        for (int k = 0; k < 6; k++)
            ASSERT_EQ_INT(surfaces_add_sphere(sf[v], v3(3.0 * (lcg(&g) - 0.5), 3.0 * (lcg(&g) - 0.5), 3.0 * (lcg(&g) - 0.5)),
                                              0.1 + 0.4 * lcg(&g), &m, "ball"),
                          BRUME_OK);
        /* a moving sphere (linear) and a turning soup (17 steps) */
        motion mo = {.n = 2};
        mo.key[0].time = 0.0;
        mo.key[0].scale = v3(1, 1, 1);
        mo.key[0].q[0] = 1.0;
        mo.key[1] = mo.key[0];
        mo.key[1].time = 1.0;
        mo.key[1].translate = v3(0.8, 0.3, 0.0);
        ASSERT_EQ_INT(surfaces_set_motion(sf[v], 3, &mo), BRUME_OK);
        mo.key[1].translate = v3(0, 0, 0);
        motion_quat_axis_angle(v3(0, 1, 0.3), 40.0, mo.key[1].q);
        ASSERT_EQ_INT(surfaces_set_motion(sf[v], 0, &mo), BRUME_OK);
        surfaces_set_shutter(sf[v], 0.0, 1.0);
        ASSERT_EQ_INT(surfaces_commit(sf[v]), BRUME_OK);
    }
    ASSERT_EQ_INT(surfaces_use_bvh(sf[1]), BRUME_OK);
    int n = 20000, hits = 0, grazing = 0, occl_differ = 0;
    double worst_t = 0.0, worst_n = 0.0;
    uint64_t g = 99;
    for (int i = 0; i < n; i++) {
        vec3 o = v3(12.0 * (lcg(&g) - 0.5), 12.0 * (lcg(&g) - 0.5), 12.0 * (lcg(&g) - 0.5));
        vec3 to = v3(3.0 * (lcg(&g) - 0.5), 3.0 * (lcg(&g) - 0.5), 3.0 * (lcg(&g) - 0.5));
        ray r = {o, v3_normalize(v3_sub(to, o)), lcg(&g)};
        double tmax = i % 3 == 0 ? 6.0 + 6.0 * lcg(&g) : INFINITY;
        surface_hit h0, h1;
        bool a = surfaces_intersect(sf[0], r, 0.0, tmax, &h0), b = surfaces_intersect(sf[1], r, 0.0, tmax, &h1);
        if (a != b || (a && (h0.object != h1.object || h0.prim != h1.prim))) {
            grazing++;
            continue;
        }
        if (a) {
            hits++;
            worst_t = fmax(worst_t, fabs(h0.t - h1.t) / (v3_length(o) + h1.t)); /* Embree's float inputs' scale */
            worst_n = fmax(worst_n, v3_length(v3_sub(h0.ng, h1.ng)));
        }
        double d = a ? h1.t * (0.5 + 0.5 * lcg(&g)) : 20.0;
        occl_differ += surfaces_occluded(sf[0], r.o, r.d, 0.0, d, r.time) != surfaces_occluded(sf[1], r.o, r.d, 0.0, d, r.time);
    }
    printf("%d of %d rays hit; %d differ at an edge, %d occlusions differ; worst relative distance %.2g, normal %.2g\n",
           hits, n, grazing, occl_differ, worst_t, worst_n);
    ASSERT_TRUE(hits > n / 4);
    ASSERT_TRUE(grazing <= n / 1000 && occl_differ <= n / 1000);
    ASSERT_TRUE(worst_t < 1e-5 && worst_n < 1e-4);
    surfaces_release(sf[0]);
    surfaces_release(sf[1]);
}

/* A medium blurred by its velocity (`brume gen fire --velocity`): the velocity's three
 * component fields (one NanoVDB buffer) and the moved majorants, with a temperature field,
 * over the shutter [0, 0.5] the rays' times span. */
TEST(device_copy_velocity_blur)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB (writing .nvdb)\n");
        exit(77);
    }
    const char *fire = test_tmp_path("gpu-fire.nvdb");
    char cmd[1024], json[2048];
    snprintf(cmd, sizeof cmd, "%s gen fire --resolution 32 --height 1 --velocity 2 -o %s >/dev/null", BRUME_EXE, fire);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 20, \"shutter\": [0, 0.5]},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0.3, -1, -0.2], \"irradiance\": 3.0}],"
             " \"media\": [{\"sigma_a\": 2.0, \"sigma_s\": 6.0,"
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s\", \"transform\": {\"scale\": [4, 1.5, 4], \"translate\": [0, -0.75, 0]}},"
             "   \"temperature\": {\"grid\": \"temperature\"}, \"blackbody\": {\"scale\": 0.5},"
             "   \"velocity\": {\"grid\": \"vel\", \"scale\": 1.5}}],"
             " \"render\": {\"max_depth\": 16}}",
             fire);
    copy_renders_the_same(json, 400);
}

/* Emission as Cycles sets it (per unit length, an emission grid, Blender's blackbody) is the
 * same medium code on the device: its copy renders the same path values. */
TEST(device_copy_emission_per_length)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB (writing .nvdb)\n");
        exit(77);
    }
    const char *fire = test_tmp_path("gpu-fire-emit.nvdb");
    char cmd[1024], json[2048];
    snprintf(cmd, sizeof cmd, "%s gen fire --resolution 32 --height 1 -o %s >/dev/null", BRUME_EXE, fire);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 20},"
             " \"media\": [{\"sigma_a\": 0.5, \"sigma_s\": 2.0, \"emission_units\": \"radiance_per_length\","
             "   \"density\": {\"type\": \"grid\", \"file\": \"%s\", \"transform\": {\"scale\": [4, 1.5, 4], \"translate\": [0, -0.75, 0]}},"
             "   \"emission_field\": {\"grid\": \"density\", \"color\": [1, 0.4, 0.1]},"
             "   \"temperature\": {}, \"blackbody\": {\"model\": \"blender\", \"intensity\": 0.8, \"tint\": [1, 0.9, 0.8]}}],"
             " \"render\": {\"max_depth\": 16}}",
             fire);
    copy_renders_the_same(json, 400);
    remove(fire);
}

/* What the GPU does not render yet is refused with one line naming it. */
TEST(device_refuses_with_one_line)
{
    const char *cases[][2] = {
        {"{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0]},"
         " \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 1.0, \"density\": {\"type\": \"constant\", \"bounds\": [[-1,-1,-1],[1,1,1]]}}],"
         " \"render\": {\"method\": \"blasi\"}}",
         "runs on the CPU only"},
    };
    for (int k = 0; k < (int)(sizeof cases / sizeof cases[0]); k++) {
        brume_scene *s = NULL;
        brume_context *ctx = brume_context_new();
        ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = cases[k][0]}, NULL, &s),
                      BRUME_OK);
        ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
        ASSERT_EQ_INT(device_scene_check(s, (int)s->settings.method), BRUME_ERROR_UNSUPPORTED);
        ASSERT_CONTAINS(err_message(), cases[k][1]);
        ASSERT_TRUE(strchr(err_message(), '\n') == NULL);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
}

/* Without a driver (CI), --device cuda says so in one line and exits 1; the device names
 * are checked; the CPU's image is the same with render.device "cpu" as without it. */
TEST(device_without_driver)
{
    const char *scene = test_tmp_path("gpu.json"), *log = test_tmp_path("gpu.log");
    test_write_file(scene, "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0]}, \"media\": [{\"sigma_a\": 0.1, \"sigma_s\": 1.0, \"density\": {\"type\": \"constant\", \"bounds\": [[-1,-1,-1],[1,1,1]]}}],"
                           " \"render\": {\"width\": 8, \"height\": 8, \"spp\": 2}}");
    char cmd[1024];
    snprintf(cmd, sizeof cmd, "LD_LIBRARY_PATH=/nonexistent %s render %s --device cuda -o %s.png 2>%s", BRUME_EXE, scene,
             scene, log);
    int rc = test_system(cmd);
    size_t n = 0;
    char *text = test_slurp(log, &n);
    if (rc == 0) { /* a machine with a GPU: nothing to check here (tests/gpu/run.sh is) */
        free(text);
        return;
    }
    ASSERT_EQ_INT(rc, 1);
    ASSERT_CONTAINS(text, "no GPU");
    ASSERT_TRUE(n > 0 && strchr(text, '\n') == text + n - 1); /* one line */
    free(text);
    snprintf(cmd, sizeof cmd, "%s render %s --device cuda:x -o %s.png 2>%s", BRUME_EXE, scene, scene, log);
    ASSERT_EQ_INT(test_system(cmd), 2);
    text = test_slurp(log, &n);
    ASSERT_CONTAINS(text, "--device: unknown device 'cuda:x'");
    free(text);
    snprintf(cmd, sizeof cmd, "%s devices 2>%s", BRUME_EXE, log);
    ASSERT_EQ_INT(test_system(cmd), 1);
    text = test_slurp(log, &n);
    ASSERT_CONTAINS(text, "no GPU");
    free(text);
    int dev = 5;
    ASSERT_EQ_INT(brume_device_from_name(NULL, "cuda:3", &dev), BRUME_OK);
    ASSERT_EQ_INT(dev, 3);
    ASSERT_EQ_INT(brume_device_from_name(NULL, "cpu", &dev), BRUME_OK);
    ASSERT_EQ_INT(dev, -1);
    ASSERT_EQ_INT(brume_device_from_name(NULL, "cuda:64", &dev), BRUME_ERROR_INVALID_ARGUMENT);
    ASSERT_EQ_INT(brume_device_from_name(NULL, "gpu", &dev), BRUME_ERROR_INVALID_ARGUMENT);
}

TEST_MAIN(device_math_against_libm, device_copy_dense_media, device_copy_nanovdb_and_environment,
          device_copy_surfaces, device_copy_blobs, device_copy_blobs_kernel_table, bvh_matches_embree,
          device_copy_velocity_blur, device_copy_emission_per_length, device_refuses_with_one_line,
          device_without_driver, device_copy_pbrt_cloud_and_equal_area_sky)
