/* test_bounded_media.c - media bounded by surfaces (docs/surfaces.md, "How surfaces meet
 * media"): interfaces crossed by flights and shadow rays, nested media added (JSON) or
 * replaced (an outside medium), the camera's starting membership, and the refusals. Every
 * statistical check uses fixed seeds and a tolerance of a few standard errors of its own
 * estimates. */
#include "test.h"

#include <math.h>

#include "brume.h"
#include "core/error.h"
#include "gpu/device_scene.h"
#include "render/integrator.h"
#include "render/path.h"
#include "scene/scene.h"

/* A camera for scenes that are not rendered. */
#define CAM "\"camera\": {\"position\": [0, 0, -9], \"look_at\": [0, 0, 0]}, "

/* A committed scene from JSON text; the test fails with the reader's message. */
static brume_scene *committed(brume_context *ctx, const char *json)
{
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s) != BRUME_OK ||
        brume_scene_commit(ctx, s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    return s;
}

/* The message of loading and committing JSON text, which must fail. */
static void expect_refusal(const char *json, const char *frag)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = "<test>", .text = json}, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    if (st == BRUME_OK)
        TEST_FAIL("accepted: %s", json);
    fprintf(stderr, "refused: %s\n", brume_context_last_error(ctx));
    ASSERT_CONTAINS(brume_context_last_error(ctx), frag);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The mean of n transmittance estimates (channel 0) along r from outside every bounded
 * medium, and their standard error. */
static void transmittance_mean(const brume_scene *s, ray r, int n, double *mean, double *se)
{
    double sum = 0.0, sq = 0.0;
    for (int i = 0; i < n; i++) {
        rng g = rng_make(23, (uint64_t)i, 0);
        double T = scene_transmittance(s, path_camera_absent(s, r), r.o, r.d, INFINITY, r.time, &g).c[0];
        sum += T;
        sq += T * T;
    }
    *mean = sum / n;
    *se = sqrt(fmax(0.0, sq / n - *mean * *mean) / n) + 1e-9;
}

/* An absorbing medium of extinction sigma_t filling [-4, 4]^3, as JSON. */
#define FOG(name, sigma_t)                                                                               \
    "{\"name\": \"" name "\", \"sigma_a\": " #sigma_t ", \"sigma_s\": 0,"                              \
    " \"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-4, -4, -4], [4, 4, 4]]}}"

/* A sphere of fog (sigma_t 0.8, radius 1) bounded by an interface sphere inside a fog box
 * [-4, 4]^3: the transmittance along a line through its centre is exp(-2 r sigma_t) and
 * along a chord at distance b exp(-2 sqrt(r^2 - b^2) sigma_t), where the free field would
 * give exp(-8 sigma_t). 20,000 ratio-tracked estimates each, within 5 standard errors (the
 * residual tracking's control is exact for a constant medium, so each estimate is exp(-tau)
 * to rounding and the error near 0: a piece of fog skipped at a crossing, as a ray spawned
 * 1e-4 off each surface would skip, fails by 3e-5). */
TEST(sphere_of_fog_transmittance)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = committed(
        ctx, "{" CAM "\"lights\": [], \"media\": [{\"name\": \"fog\", \"sigma_a\": 0.4, \"sigma_s\": 0.4,"
             " \"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-4, -4, -4], [4, 4, 4]]}}],"
             " \"surfaces\": [{\"type\": \"sphere\", \"radius\": 1, \"material\": {\"type\": \"interface\"},"
             "   \"medium_inside\": \"fog\"}]}");
    ASSERT_EQ_INT(s->bounded, 1);
    const double b[3] = {0.0, 0.5, 0.9}, sigma_t = 0.8;
    for (int k = 0; k < 3; k++) {
        double mean, se, want = exp(-2.0 * sqrt(1.0 - b[k] * b[k]) * sigma_t);
        transmittance_mean(s, (ray){v3(-3, b[k], 0), v3(1, 0, 0), 0.0}, 20000, &mean, &se);
        fprintf(stderr, "chord at %g: T %.5f (se %.2g), want %.5f\n", b[k], mean, se, want);
        ASSERT_NEAR(mean, want, 5.0 * se);
        ASSERT_TRUE(fabs(mean - exp(-8.0 * sigma_t)) > 10.0 * se); /* the bound matters */
    }
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* Nested fog spheres (outer radius 2, sigma_t 0.3; inner radius 1, sigma_t 1.1), both in
 * boxes [-4, 4]^3, along a line through the centre. With the inner sphere bounding only
 * its own fog (JSON's rule: overlapping media add), the inner part sees both:
 * T = exp(-2 (2 - 1) 0.3 - 2 (0.3 + 1.1)); with the outer fog as the inner sphere's outside
 * medium (pbrt-v4's rule: the inside replaces it), T = exp(-2 (2 - 1) 0.3 - 2 1.1). */
TEST(nested_spheres_add_or_replace)
{
    for (int replace = 0; replace < 2; replace++) {
        char json[2048];
        snprintf(json, sizeof json,
                 "{" CAM "\"lights\": [], \"media\": [" FOG("outer", 0.3) ", " FOG("inner", 1.1) "],"
                 " \"surfaces\": [{\"type\": \"sphere\", \"radius\": 2, \"material\": {\"type\": \"interface\"},"
                 "   \"medium_inside\": \"outer\"},"
                 "  {\"type\": \"sphere\", \"radius\": 1, \"material\": {\"type\": \"interface\"},"
                 "   \"medium_inside\": \"inner\"%s}]}",
                 replace ? ", \"medium_outside\": \"outer\"" : "");
        brume_context *ctx = brume_context_new();
        brume_scene *s = committed(ctx, json);
        double mean, se, want = exp(-2.0 * 0.3 - 2.0 * (replace ? 1.1 : 1.4));
        transmittance_mean(s, (ray){v3(-3, 0, 0), v3(1, 0, 0), 0.0}, 20000, &mean, &se);
        fprintf(stderr, "replace %d: T %.5f (se %.2g), want %.5f\n", replace, mean, se, want);
        ASSERT_NEAR(mean, want, 5.0 * se);
        brume_scene_release(s);
        brume_context_release(ctx);
    }
}

/* The mean of channel c over the image of JSON text and its standard error. */
static void image_mean(const char *json, unsigned long long seed, int c, double *mean, double *se)
{
    brume_image *img = test_render_json(json, seed);
    test_channel_mean(brume_image_pixels(img), brume_image_width(img) * brume_image_height(img), c, mean, se);
    brume_image_release(img);
}

/* A camera at the centre of an absorbing fog sphere (radius 1, sigma_a = 0.3, 0.6, 1.2)
 * looks at an emitting wall (radiance 1) 3 away, the fog's box [-2, 2]^3 beyond the sphere:
 * every camera ray crosses 1 of fog, so each pixel is exp(-sigma_a). A camera that did not
 * start inside would see 1 (it would leave the fog on crossing the sphere); the free field
 * would give exp(-2 sigma_a). Once with the camera's medium found by its line's crossings,
 * once named by camera.medium. Within 5 standard errors of the image's mean. */
TEST(camera_inside_fog_sphere)
{
    const double sigma[3] = {0.3, 0.6, 1.2};
    for (int named = 0; named < 2; named++) {
        char json[2048];
        snprintf(json, sizeof json,
                 "{\"camera\": {\"position\": [0, 0, 0], \"look_at\": [0, 0, 1], \"fov\": 20%s},"
                 " \"lights\": [],"
                 " \"media\": [{\"name\": \"fog\", \"sigma_a\": [0.3, 0.6, 1.2], \"sigma_s\": 0,"
                 "   \"density\": {\"type\": \"constant\", \"value\": 1, \"bounds\": [[-2, -2, -2], [2, 2, 2]]}}],"
                 " \"surfaces\": [{\"type\": \"sphere\", \"radius\": 1, \"material\": {\"type\": \"interface\"},"
                 "   \"medium_inside\": \"fog\"},"
                 "  {\"type\": \"quad\", \"corner\": [-5, -5, 3], \"edge_u\": [0, 10, 0], \"edge_v\": [10, 0, 0],"
                 "   \"material\": {\"albedo\": 0, \"emission\": 1}}],"
                 " \"render\": {\"width\": 16, \"height\": 16, \"spp\": 16, \"method\": \"path\"}}",
                 named ? ", \"medium\": \"fog\"" : "");
        for (int c = 0; c < 3; c++) {
            double mean, se, want = exp(-sigma[c]);
            image_mean(json, 5, c, &mean, &se);
            fprintf(stderr, "named %d, channel %d: %.5f (se %.2g), want %.5f\n", named, c, mean, se, want);
            ASSERT_NEAR(mean, want, 5.0 * se + 1e-6);
        }
    }
}

/* A scattering slab (sigma_s 1.5, sigma_a 0.3, HG g = 0.4) under a sun and a sky, seen from
 * above: as a free constant field in the box [-2, 2] x [-0.3, 0.3] x [-2, 2], and as the
 * same fog filling [-4, 4]^3 bounded by a box surface (12 triangles) that is an interface.
 * Flights, scattering, next-event estimation and shadow rays all cross the box; the two
 * images' means must agree within 5 standard errors of their difference, in every channel. */
TEST(slab_bounded_by_mesh_matches_box)
{
    const char *head =
        "{\"camera\": {\"position\": [0.5, 5, 3], \"look_at\": [0, 0, 0], \"fov\": 50},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [-0.3, -1, -0.2], \"irradiance\": [3, 3, 3]}],"
        " \"background\": [0.2, 0.3, 0.5],"
        " \"media\": [{\"name\": \"slab\", \"sigma_a\": 0.3, \"sigma_s\": 1.5,"
        "   \"phase\": {\"type\": \"hg\", \"g\": 0.4}, \"density\": {\"type\": \"constant\", \"value\": 1,";
    const char *tail = " \"render\": {\"width\": 24, \"height\": 24, \"spp\": 32, \"method\": \"path\"}}";
    char free_json[2048], bounded_json[2048];
    snprintf(free_json, sizeof free_json, "%s \"bounds\": [[-2, -0.3, -2], [2, 0.3, 2]]}}],%s", head, tail);
    snprintf(bounded_json, sizeof bounded_json,
             "%s \"bounds\": [[-4, -4, -4], [4, 4, 4]]}}],"
             " \"surfaces\": [{\"type\": \"box\", \"min\": [-2, -0.3, -2], \"max\": [2, 0.3, 2],"
             "   \"material\": {\"type\": \"interface\"}, \"medium_inside\": \"slab\"}],%s",
             head, tail);
    for (int c = 0; c < 3; c++) {
        double m0, s0, m1, s1;
        image_mean(free_json, 7, c, &m0, &s0);
        image_mean(bounded_json, 8, c, &m1, &s1);
        fprintf(stderr, "channel %d: free box %.5f (se %.2g), bounded %.5f (se %.2g)\n", c, m0, s0, m1, s1);
        ASSERT_NEAR(m0, m1, 5.0 * sqrt(s0 * s0 + s1 * s1));
        ASSERT_TRUE(5.0 * sqrt(s0 * s0 + s1 * s1) < 0.1 * m0); /* a test that can fail */
    }
}

/* What cannot be honoured is refused with one line naming the file and the key. */
TEST(refusals_name_the_key)
{
    const char *fog = "\"media\": [" FOG("fog", 1) "]";
    char json[2048];
    snprintf(json, sizeof json,
             "{" CAM "\"lights\": [], %s, \"surfaces\": [{\"type\": \"sphere\", \"material\": {\"type\": \"interface\"},"
             " \"medium_inside\": \"smoke\"}]}", fog);
    expect_refusal(json, "<test>: surface 'surfaces[0]': medium_inside: no medium named \"smoke\"");
    snprintf(json, sizeof json,
             "{" CAM "\"lights\": [], \"media\": [{\"name\": \"fog\", \"sigma_a\": 1, \"sigma_s\": 0,"
             " \"density\": {\"type\": \"constant\"}}], \"surfaces\": [{\"type\": \"quad\", \"corner\": [0, 0, 0],"
             " \"edge_u\": [1, 0, 0], \"edge_v\": [0, 1, 0], \"material\": {\"type\": \"interface\"},"
             " \"medium_inside\": \"fog\"}]}");
    expect_refusal(json, "surface 'surfaces[0]': medium_inside/medium_outside: the shape is not closed");
    expect_refusal("{" CAM "\"lights\": [], \"surfaces\": [{\"type\": \"sphere\", \"material\": {\"type\": \"interface\"}}]}",
                   "<test>: surfaces[0].material: an interface only bounds media");
    expect_refusal("{" CAM "\"lights\": [], \"surfaces\": [{\"type\": \"sphere\", \"material\": {\"type\": \"interface\","
                   " \"albedo\": 0.5}, \"medium_inside\": \"fog\"}]}",
                   "surfaces[0].material");
    /* the C builder checks its arguments at once */
    brume_context *cb = brume_context_new();
    brume_scene *sc = NULL;
    ASSERT_EQ_INT(brume_scene_new(cb, "api", &sc), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_add_sphere(cb, sc, (double[3]){0, 0, 0}, 1.0, NULL, NULL, NULL), BRUME_OK);
    ASSERT_TRUE(brume_scene_set_surface_media(cb, sc, 1, "fog", NULL, true) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(cb), "brume_scene_set_surface_media: surface: 1 is not a surface");
    ASSERT_TRUE(brume_scene_set_surface_media(cb, sc, 0, NULL, "", true) != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(cb), "an interface bounds a medium");
    ASSERT_EQ_INT(brume_scene_set_surface_media(cb, sc, 0, "fog", NULL, true), BRUME_OK);
    ASSERT_TRUE(brume_scene_commit(cb, sc) != BRUME_OK); /* names are resolved at commit */
    ASSERT_CONTAINS(brume_context_last_error(cb), "medium_inside: no medium named \"fog\"");
    brume_scene_release(sc);
    brume_context_release(cb);
    /* blasi and stam, and the GPU, refuse a bounded medium by name */
    brume_context *ctx = brume_context_new();
    brume_scene *s = committed(
        ctx, "{" CAM "\"lights\": [], \"media\": [{\"name\": \"fog\", \"sigma_a\": 1, \"sigma_s\": 0,"
             " \"density\": {\"type\": \"constant\"}}], \"surfaces\": [{\"type\": \"sphere\", \"radius\": 0.5,"
             " \"material\": {\"type\": \"interface\"}, \"medium_inside\": \"fog\"}]}");
    void *state = NULL;
    ASSERT_TRUE(integrator_prepare(INTEGRATOR_BLASI, s, &state) != BRUME_OK);
    ASSERT_CONTAINS(err_message(), "<test>: media[0] 'fog': a medium bounded by a surface");
    ASSERT_CONTAINS(err_message(), "renders with path and single only");
    ASSERT_TRUE(device_scene_check(s, INTEGRATOR_PATH) != BRUME_OK);
    ASSERT_CONTAINS(err_message(), "<test>: media bounded by surfaces (medium_inside/medium_outside) render on the "
                                   "CPU only (--device cpu)");
    brume_scene_release(s);
    brume_context_release(ctx);
}


/* The scene of a .pbrt text (written to a temporary file), committed or not, or NULL with
 * the message. */
static brume_scene *pbrt_scene(brume_context *ctx, const char *text, bool commit, char *msg, size_t cap)
{
    const char *path = test_tmp_path("bounded.pbrt");
    test_write_file(path, text);
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s);
    if (st == BRUME_OK && commit)
        st = brume_scene_commit(ctx, s);
    snprintf(msg, cap, "%s", st == BRUME_OK ? "" : brume_context_last_error(ctx));
    if (st != BRUME_OK) {
        brume_scene_release(s);
        return NULL;
    }
    return s;
}

#define PBRT_VIEW                                                                                           \
    "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [0.2]\n"                             \
    "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"                               \
    "Sampler \"independent\" \"integer pixelsamples\" [32]\n"

/* pbrt-v4's nested media: an absorbing fog sphere (radius 2, sigma_a 0.3) holds a smaller
 * one (radius 1, sigma_a 1.1) whose MediumInterface "inner" "outer" replaces the outer fog
 * inside it, seen through the centre against a sky of radiance 1 (a 0.2-degree view: the
 * chords are shorter than the diameters by 1e-4 at most): each pixel is
 * exp(-2 (2 - 1) 0.3 - 2 1.1) = exp(-2.8), where adding the fogs would give exp(-3.4).
 * Within 5 standard errors of the image's mean. */
TEST(pbrt_nested_fog_replaces)
{
    const char *text = PBRT_VIEW
        "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n"
        "MakeNamedMedium \"outer\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.3 0.3 0.3]"
        " \"rgb sigma_s\" [0 0 0]\n"
        "MakeNamedMedium \"inner\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1.1 1.1 1.1]"
        " \"rgb sigma_s\" [0 0 0]\n"
        "AttributeBegin\nMaterial \"interface\"\nMediumInterface \"outer\" \"\"\n"
        "Shape \"sphere\" \"float radius\" [2]\nAttributeEnd\n"
        "AttributeBegin\nMaterial \"interface\"\nMediumInterface \"inner\" \"outer\"\n"
        "Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n";
    char msg[2048];
    brume_context *ctx = brume_context_new();
    brume_scene *s = pbrt_scene(ctx, text, false, msg, sizeof msg);
    if (!s)
        TEST_FAIL("%s", msg);
    brume_image *img = test_render_scene(s, -1, 3);
    int n = brume_image_width(img) * brume_image_height(img);
    for (int c = 0; c < 3; c++) {
        double mean, se, want = exp(-2.8);
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        fprintf(stderr, "channel %d: %.5f (se %.2g), want %.5f (added: %.5f)\n", c, mean, se, want, exp(-3.4));
        ASSERT_NEAR(mean, want, 5.0 * se + 1e-4 * want);
        ASSERT_TRUE(5.0 * se < 0.5 * (want - exp(-3.4)));
    }
    ASSERT_EQ_INT(s->bounded, 3); /* both fogs bounded (set by the render's commit) */
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* pbrt-v4-scenes' disney-cloud bounds its grid by a sphere under a non-uniform scale: an
 * ellipsoid, which brume bounds by its triangles (corners on the surface). An absorbing fog
 * (sigma_a 0.2) in the sphere of radius 1 scaled by 3 along the view (z) is crossed over a
 * chord of 6 through the poles, where the triangles meet the surface exactly: each pixel
 * (a 0.2-degree view: chords shorter by 2e-3 at most) is exp(-1.2) of the sky, where the
 * unscaled sphere would give exp(-0.4). Within 5 standard errors plus that 2e-3 of the mean. */
TEST(pbrt_ellipsoid_bounds_fog)
{
    const char *text = PBRT_VIEW
        "WorldBegin\nLightSource \"infinite\" \"rgb L\" [1 1 1]\n"
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.2 0.2 0.2]"
        " \"rgb sigma_s\" [0 0 0]\n"
        "AttributeBegin\nMaterial \"interface\"\nMediumInterface \"fog\" \"\"\nScale 1 1 3\n"
        "Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n";
    char msg[2048];
    brume_context *ctx = brume_context_new();
    brume_scene *s = pbrt_scene(ctx, text, false, msg, sizeof msg);
    if (!s)
        TEST_FAIL("%s", msg);
    brume_image *img = test_render_scene(s, -1, 3);
    int n = brume_image_width(img) * brume_image_height(img);
    for (int c = 0; c < 3; c++) {
        double mean, se, want = exp(-1.2);
        test_channel_mean(brume_image_pixels(img), n, c, &mean, &se);
        fprintf(stderr, "channel %d: %.5f (se %.2g), want %.5f (unscaled: %.5f)\n", c, mean, se, want, exp(-0.4));
        ASSERT_NEAR(mean, want, 5.0 * se + 2e-3 * want);
    }
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* The camera in pbrt-v4's unbounded fog (sigma_a 0.1, the camera's medium) looks through a
 * sphere of radius 1 whose MediumInterface "cloud" "fog" replaces the fog by a cloud
 * (sigma_a 1) inside it, at a two-sided emitting wall (radiance 1) at z = 3: the line from
 * the camera at z = -5 crosses 6 of fog and 2 of cloud, so each pixel is exp(-2.6), where
 * adding the cloud to the fog would give exp(-2.8) and a fog that ended at the sphere
 * exp(-2.4). Within 5 standard errors of the image's mean (256 samples a pixel: the
 * absorbing walks end or pass, a Bernoulli estimate of spread 0.26 a sample). */
TEST(pbrt_camera_fog_outside_medium)
{
    const char *text =
        "MakeNamedMedium \"fog\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [0.1 0.1 0.1] \"rgb sigma_s\" [0 0 0]\n"
        "MediumInterface \"\" \"fog\"\n"
        "LookAt 0 0 -5  0 0 0  0 1 0\nCamera \"perspective\" \"float fov\" [0.2]\n"
        "Film \"rgb\" \"integer xresolution\" [16] \"integer yresolution\" [16]\n"
        "Sampler \"independent\" \"integer pixelsamples\" [256]\n"
        "WorldBegin\n"
        "MakeNamedMedium \"cloud\" \"string type\" \"homogeneous\" \"rgb sigma_a\" [1 1 1] \"rgb sigma_s\" [0 0 0]\n"
        "AttributeBegin\nMaterial \"interface\"\nMediumInterface \"cloud\" \"fog\"\n"
        "Shape \"sphere\" \"float radius\" [1]\nAttributeEnd\n"
        "AttributeBegin\nAreaLightSource \"diffuse\" \"rgb L\" [1 1 1] \"bool twosided\" true\n"
        "Material \"diffuse\" \"rgb reflectance\" [0 0 0]\n"
        "Shape \"bilinearmesh\" \"point3 P\" [-5 -5 3  5 -5 3  -5 5 3  5 5 3] \"integer indices\" [0 1 2 3]\n"
        "AttributeEnd\n";
    char msg[2048];
    brume_context *ctx = brume_context_new();
    brume_scene *s = pbrt_scene(ctx, text, false, msg, sizeof msg);
    if (!s)
        TEST_FAIL("%s", msg);
    brume_image *img = test_render_scene(s, -1, 4);
    int n = brume_image_width(img) * brume_image_height(img);
    double mean, se, want = exp(-2.6);
    test_channel_mean(brume_image_pixels(img), n, 1, &mean, &se);
    fprintf(stderr, "%.5f (se %.2g), want %.5f (added %.5f, fog ended %.5f)\n", mean, se, want, exp(-2.8), exp(-2.4));
    ASSERT_NEAR(mean, want, 5.0 * se + 1e-4 * want);
    ASSERT_TRUE(5.0 * se < 0.5 * (want - exp(-2.8)));
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* What .pbrt media on shapes still cannot be is refused with the file and the line: the
 * same medium on both sides of an interface, a disk bounding a medium, an open triangle
 * mesh (found at commit, the surface named by its line). */
TEST(pbrt_refusals_name_line)
{
    static const char *const cases[][2] = {
        {"Material \"interface\"\nMediumInterface \"fog\" \"fog\"\nShape \"sphere\"\n", ":9: MediumInterface"},
        {"Material \"interface\"\nMediumInterface \"fog\" \"\"\nShape \"disk\"\n", ":9: Shape \"disk\": an \"interface\""},
        {"Material \"interface\"\nMediumInterface \"fog\" \"\"\nShape \"trianglemesh\" \"point3 P\" [0 0 0 1 0 0 0 1 0]"
         " \"integer indices\" [0 1 2]\n", "bounded.pbrt:9': medium_inside/medium_outside: the shape is not closed"},
        {"Material \"interface\"\nMediumInterface \"smoke\" \"\"\nShape \"sphere\"\n", ":9: MediumInterface: no medium "
                                                                                       "named \"smoke\""},
        {"Scale 1 1 3\nShape \"sphere\"\n", ":8: Shape \"sphere\": a sphere under a non-uniform scale"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char text[2048], msg[2048];
        snprintf(text, sizeof text, "%sWorldBegin\nMakeNamedMedium \"fog\" \"string type\" \"homogeneous\"\n%s",
                 PBRT_VIEW, cases[i][0]);
        brume_context *ctx = brume_context_new();
        brume_scene *s = pbrt_scene(ctx, text, true, msg, sizeof msg);
        if (s)
            TEST_FAIL("accepted: %s", text);
        fprintf(stderr, "refused: %s\n", msg);
        ASSERT_CONTAINS(msg, cases[i][1]);
        ASSERT_CONTAINS(msg, test_tmp_path("bounded.pbrt"));
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
        brume_context_release(ctx);
    }
}

TEST_MAIN(sphere_of_fog_transmittance, nested_spheres_add_or_replace, camera_inside_fog_sphere,
          slab_bounded_by_mesh_matches_box, refusals_name_the_key, pbrt_nested_fog_replaces,
          pbrt_camera_fog_outside_medium, pbrt_refusals_name_line, pbrt_ellipsoid_bounds_fog)
