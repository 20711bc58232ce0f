/* test_surfaces.c - solid objects: closed forms that fail on a missing transmittance term
 * or a wrong cosine, furnaces with surfaces and media, meshes good and bad. */
#include "test.h"

#include "brume.h"
#include "core/error.h"
#include "io/mesh.h"
#include "scene/scene.h"

#define PI_D 3.14159265358979323846

/* Mean and standard error of channel c over the pixels of img. */
static void image_mean(const brume_image *img, int c, double *mean, double *se)
{
    test_channel_mean(brume_image_pixels(img), brume_image_width(img) * brume_image_height(img), c, mean, se);
}

/* A white-ish Lambertian plane (albedo 0.7) under a distant light at 60 degrees from the
 * normal (irradiance E = 2 normal to the light), seen straight down through a slab of
 * absorbing fog (sigma_a = 0.4) of thickness d = 1.5 lying on it:
 *   L = albedo / pi * E cos(60) exp(-sigma_a d / cos(60)) * exp(-sigma_a d). */
TEST(lit_plane_through_fog)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 10, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, -1], \"fov\": 3},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0.8660254037844386, -0.5, 0], \"irradiance\": 2.0}],"
        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"size\": 200,"
        "                 \"material\": {\"albedo\": 0.7}}],"
        " \"media\": [{\"sigma_a\": 0.4, \"sigma_s\": 0,"
        "   \"density\": {\"type\": \"constant\", \"bounds\": [[-100, 0, -100], [100, 1.5, 100]]}}],"
        " \"render\": {\"width\": 24, \"height\": 24, \"spp\": 256, \"max_depth\": 1}}";
    brume_image *img = test_render_json(json, 1);
    double mean, se;
    image_mean(img, 0, &mean, &se);
    double expect = 0.7 / PI_D * 2.0 * 0.5 * exp(-0.4 * 1.5 / 0.5) * exp(-0.4 * 1.5);
    fprintf(stderr, "lit plane: %.6f +- %.6f, expected %.6f\n", mean, se, expect);
    ASSERT_NEAR(mean, expect, 5.0 * se + 1e-9);
    /* sharp enough that dropping either transmittance (x 3.3 or x 1.8) or the cosine (x 2) fails */
    ASSERT_TRUE(5.0 * se < 0.05 * expect);
    brume_image_release(img);
}

/* The shadow of a box of absorbing fog on a plane lit from straight above: every shadowed
 * point receives E exp(-sigma_a h) through the box height h, every other point E.
 * The camera looks down at the plane; per pixel the expected radiance is computed from
 * the plane point the pixel sees, so the check covers the shadow's edge too. */
TEST(fog_shadow_matches_transmittance)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 8, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, -1], \"fov\": 20},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 3.0}],"
        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"size\": 100,"
        "                 \"material\": {\"albedo\": 0.5}}],"
        " \"media\": [{\"sigma_a\": 0.9, \"sigma_s\": 0,"
        "   \"density\": {\"type\": \"constant\", \"bounds\": [[-0.5, 2, -0.5], [0.5, 3, 0.5]]}}],"
        " \"render\": {\"width\": 32, \"height\": 32, \"spp\": 128, \"max_depth\": 1,"
        "             \"filter\": {\"type\": \"box\", \"width\": 0.001}}}";
    brume_image *img = test_render_json(json, 2);
    const float *px = brume_image_pixels(img);
    /* the camera sees, through pixel (x, y) centre, the plane point below; the fog box
     * (seen from above) covers |x|, |z| < 0.5 and also dims the view ray itself */
    double tan_half = tan(0.5 * 20.0 * PI_D / 180.0);
    double sum_img = 0.0, sum_exp = 0.0, sum2 = 0.0;
    int n = 0;
    for (int y = 0; y < 32; y++)
        for (int x = 0; x < 32; x++) {
            double sx = (2.0 * (x + 0.5) / 32 - 1.0) * tan_half, sy = (1.0 - 2.0 * (y + 0.5) / 32) * tan_half;
            /* camera frame: forward -y, up -z, right = forward x up = (-1, 0, 0)... */
            vec3 d = v3_normalize(v3(-sx, -1.0, -sy));
            double t = 8.0 / -d.y;
            vec3 p = v3(d.x * t, 0.0, d.z * t);
            double view_T = 1.0, light_T = 1.0;
            /* the view ray crosses the box between heights 3 and 2 if it is inside in x, z there */
            vec3 p3 = v3(d.x * (5.0 / -d.y), 3, d.z * (5.0 / -d.y)), p2 = v3(d.x * (6.0 / -d.y), 2, d.z * (6.0 / -d.y));
            int in3 = fabs(p3.x) < 0.5 && fabs(p3.z) < 0.5, in2 = fabs(p2.x) < 0.5 && fabs(p2.z) < 0.5;
            if (in3 != in2)
                continue; /* the view ray grazes a side of the box: skip the few edge pixels */
            if (in3)
                view_T = exp(-0.9 * 1.0 / -d.y);
            if (fabs(p.x) < 0.5 && fabs(p.z) < 0.5)
                light_T = exp(-0.9 * 1.0);
            if (fabs(fabs(p.x) - 0.5) < 0.02 || fabs(fabs(p.z) - 0.5) < 0.02)
                continue; /* shadow edge within a pixel */
            double expect = 0.5 / PI_D * 3.0 * light_T * view_T;
            double v = px[4 * (y * 32 + x)];
            sum_img += v;
            sum2 += v * v;
            sum_exp += expect;
            n++;
        }
    double mean = sum_img / n, ref = sum_exp / n;
    double se = sqrt(fmax(sum2 / n - mean * mean, 0.0) / n) + 1e-12;
    fprintf(stderr, "fog shadow: mean %.6f, expected %.6f, se %.6f over %d pixels\n", mean, ref, se, n);
    ASSERT_TRUE(n > 500);
    ASSERT_NEAR(mean, ref, 5.0 * se + 1e-4 * ref);
    brume_image_release(img);
}

/* A furnace: renders json with `seed`, and asserts that channel c's image mean is `expect`
 * within 5 standard errors, and that 5 standard errors are below rel_tol of it (so an
 * energy error of rel_tol would fail). */
static void check_furnace(const char *what, const char *json, uint64_t seed, int c, double expect, double rel_tol)
{
    brume_image *img = test_render_json(json, seed);
    double mean, se;
    image_mean(img, c, &mean, &se);
    fprintf(stderr, "%s: %.5f +- %.5f\n", what, mean, se);
    ASSERT_NEAR(mean, expect, 5.0 * se + 1e-9);
    ASSERT_TRUE(5.0 * se < rel_tol * expect);
    brume_image_release(img);
}

/* Camera inside a closed sphere whose inner wall has albedo a = 0.75 and emits Le = 0.25,
 * filled with a heterogeneous medium of albedo 1: the equilibrium radiance is
 * Le / (1 - a) = 1 everywhere, whatever the medium does. */
TEST(furnace_inside_emitting_sphere)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 0, 0.5], \"look_at\": [0, 0, 0], \"fov\": 60},"
        " \"surfaces\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 2,"
        "                 \"material\": {\"albedo\": 0.75, \"emission\": 0.25, \"two_sided\": true}}],"
        " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 6,"
        "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 9}}],"
        " \"render\": {\"width\": 24, \"height\": 24, \"spp\": 192, \"max_depth\": 100000}}";
    check_furnace("emitting sphere furnace", json, 3, 1, 1.0, 0.01);
}

/* A closed white (albedo 1) sphere holding a medium of albedo 1, under a constant
 * background of 0.6: seen from outside it is exactly as bright as the background. */
TEST(furnace_white_sphere_outside)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 0, 6], \"look_at\": [0, 0, 0], \"fov\": 25},"
        " \"background\": 0.6,"
        " \"surfaces\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1.2,"
        "                 \"material\": {\"albedo\": 1.0}}],"
        " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 5,"
        "   \"density\": {\"type\": \"constant\", \"bounds\": [[-1, -1, -1], [1, 1, 1]]}}],"
        " \"render\": {\"width\": 24, \"height\": 24, \"spp\": 64, \"max_depth\": 100000}}";
    check_furnace("white sphere furnace", json, 4, 0, 0.6, 0.01);
}

/* A white (albedo 1) ground plane under a constant background of 0.6, with a white
 * heterogeneous cloud resting on it: everything is in equilibrium at 0.6. Flights that end
 * on the ground carry a fractional ratio-tracked transmittance and a kept scattering
 * collision at once, so the choice between the reflection and the scattering branch is
 * exercised; a bias in either branch's weight shows against the background. */
TEST(furnace_white_ground_cloud)
{
    const char *json =
        "{\"camera\": {\"position\": [0, 2.5, 3], \"look_at\": [0, 0.3, 0], \"fov\": 40},"
        " \"background\": 0.6,"
        " \"surfaces\": [{\"type\": \"plane\", \"point\": [0, 0, 0], \"normal\": [0, 1, 0], \"size\": 200,"
        "                 \"material\": {\"albedo\": 1.0}}],"
        " \"media\": [{\"sigma_a\": 0, \"sigma_s\": 12,"
        "   \"density\": {\"type\": \"procedural_cloud\", \"resolution\": 24, \"seed\": 5,"
        "                 \"bounds\": [[-1.2, -0.2, -1.2], [1.2, 1.5, 1.2]]}}],"
        " \"render\": {\"width\": 24, \"height\": 24, \"spp\": 96, \"max_depth\": 100000}}";
    check_furnace("white ground cloud furnace", json, 6, 0, 0.6, 0.01);
}

/* A one-sided emissive quad whose front (edge_u x edge_v) faces +y: seen from above it has
 * its radiance exactly, from below it is black. Fails on a flipped geometric normal. */
TEST(emitter_front_side)
{
    const char *above =
        "{\"camera\": {\"position\": [0, 5, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, -1], \"fov\": 5},"
        " \"surfaces\": [{\"type\": \"quad\", \"corner\": [-5, 0, -5], \"edge_u\": [0, 0, 10], \"edge_v\": [10, 0, 0],"
        "                 \"material\": {\"albedo\": 0, \"emission\": 2.5}}],"
        " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 2}}";
    const char *below =
        "{\"camera\": {\"position\": [0, -5, 0], \"look_at\": [0, 0, 0], \"up\": [0, 0, -1], \"fov\": 5},"
        " \"surfaces\": [{\"type\": \"quad\", \"corner\": [-5, 0, -5], \"edge_u\": [0, 0, 10], \"edge_v\": [10, 0, 0],"
        "                 \"material\": {\"albedo\": 0, \"emission\": 2.5}}],"
        " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 2}}";
    brume_image *a = test_render_json(above, 1), *b = test_render_json(below, 1);
    for (int i = 0; i < 16; i++) {
        ASSERT_NEAR(brume_image_pixels(a)[4 * i], 2.5, 1e-6);
        ASSERT_NEAR(brume_image_pixels(b)[4 * i], 0.0, 0.0);
    }
    brume_image_release(a);
    brume_image_release(b);
}

static const char *write_file(const char *name, const char *text)
{
    const char *path = test_tmp_path(name);
    FILE *fp = fopen(path, "w");
    ASSERT_TRUE(fp != NULL);
    fputs(text, fp);
    fclose(fp);
    return path;
}

static void expect_scene_error(const char *json, const char *frag)
{
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = "<mesh test>", .text = json}, NULL, &s);
    if (st == BRUME_OK)
        TEST_FAIL("scene loaded but should fail: %s", json);
    ASSERT_CONTAINS(brume_context_last_error(ctx), frag);
    brume_context_release(ctx);
}

TEST(bad_meshes_are_errors)
{
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
             " \"surfaces\": [{\"type\": \"mesh\", \"file\": \"/nonexistent/bunny.obj\"}]}");
    expect_scene_error(json, "/nonexistent/bunny.obj");
    const char *garbage = write_file("garbage.obj", "this is not\n a mesh \x01\x02 at all\n");
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
             " \"surfaces\": [{\"type\": \"mesh\", \"file\": \"%s\"}]}", garbage);
    expect_scene_error(json, "surfaces[0]");
    const char *nan = write_file("nan.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n");
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
             " \"surfaces\": [{\"type\": \"mesh\", \"file\": \"%s\"}]}", nan);
    expect_scene_error(json, "non-finite");
    const char *badidx = write_file("badidx.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
             " \"surfaces\": [{\"type\": \"mesh\", \"file\": \"%s\"}]}", badidx);
    expect_scene_error(json, "surfaces[0]");
    expect_scene_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
                       " \"surfaces\": [{\"type\": \"sphere\", \"radius\": -1}]}",
                       "surfaces[0].radius");
    expect_scene_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
                       " \"surfaces\": [{\"type\": \"sphere\", \"material\": {\"albedo\": 0.8, \"specular\": 0.5}}]}",
                       "create energy");
    expect_scene_error("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
                       " \"surfaces\": [{\"type\": \"torus\"}]}",
                       "torus");
    remove(garbage);
    remove(nan);
    remove(badidx);
}

/* A mesh of 125,000 triangles (a height field written as OBJ) loads and renders. */
TEST(large_mesh_renders)
{
    const char *path = test_tmp_path("terrain.obj");
    FILE *fp = fopen(path, "w");
    ASSERT_TRUE(fp != NULL);
    enum { N = 250 };
    for (int j = 0; j <= N; j++)
        for (int i = 0; i <= N; i++) {
            double x = 4.0 * i / N - 2.0, z = 4.0 * j / N - 2.0;
            fprintf(fp, "v %.6f %.6f %.6f\n", x, 0.15 * sin(3 * x) * cos(2 * z), z);
        }
    for (int j = 0; j < N; j++)
        for (int i = 0; i < N; i++) {
            int a = j * (N + 1) + i + 1, b = a + 1, c = a + N + 1, d = c + 1;
            fprintf(fp, "f %d %d %d\nf %d %d %d\n", a, c, b, b, c, d);
        }
    fclose(fp);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"camera\": {\"position\": [0, 3, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
             " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, -0.3], \"irradiance\": 3}],"
             " \"surfaces\": [{\"type\": \"mesh\", \"file\": \"%s\", \"material\": {\"albedo\": 0.5}}],"
             " \"render\": {\"width\": 32, \"height\": 24, \"spp\": 2}}",
             path);
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(NULL, &(brume_source){.path = "<mesh>", .text = json}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(surfaces_triangle_count(s->surf), 2 * N * N);
    brume_scene_release(s);
    brume_image *img = test_render_json(json, 5);
    double mean, se;
    image_mean(img, 0, &mean, &se);
    ASSERT_TRUE(mean > 0.05); /* the terrain is lit and visible */
    brume_image_release(img);
    remove(path);
}

/* assimp is not linked (io/mesh.c): a fresh test process does not hold it, and reading a mesh
 * does not map it either, since assimp runs only in the reader's child process. */
TEST(assimp_opened_on_first_use)
{
    ASSERT_TRUE(!test_mapped("libassimp"));
    const char *path = test_tmp_path("one_triangle.obj");
    test_write_file(path, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    double *pos = NULL;
    int *idx = NULL, nv = 0, ntri = 0;
    if (mesh_load(path, &pos, &nv, &idx, &ntri) != BRUME_OK)
        TEST_FAIL("%s", err_message());
    ASSERT_EQ_INT(nv, 3);
    ASSERT_EQ_INT(ntri, 1);
    free(pos);
    free(idx);
    remove(path);
    ASSERT_TRUE(!test_mapped("libassimp"));
}

/* Embree is opened when a scene with surfaces is built, not at the process's start, and
 * not by a scene without surfaces (docs/performance.md, "Start-up"). */
TEST(embree_opened_on_first_use)
{
    ASSERT_TRUE(!test_mapped("libembree"));
    brume_image *img = test_render_json("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
                                        " \"media\": [{\"sigma_a\": 0.5, \"sigma_s\": 0.5,"
                                        " \"density\": {\"type\": \"constant\", \"bounds\": [[-1, -1, -1], [1, 1, 1]]}}],"
                                        " \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1}}",
                                        1);
    brume_image_release(img);
    ASSERT_TRUE(!test_mapped("libembree"));
    img = test_render_json("{\"camera\": {\"position\": [0, 0, 5], \"look_at\": [0, 0, 0]},"
                           " \"surfaces\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1,"
                           " \"material\": {\"albedo\": 0.5}}], \"render\": {\"width\": 4, \"height\": 4, \"spp\": 1}}",
                           1);
    brume_image_release(img);
    ASSERT_TRUE(test_mapped("libembree"));
}

TEST_MAIN(lit_plane_through_fog, fog_shadow_matches_transmittance, furnace_inside_emitting_sphere,
          furnace_white_sphere_outside, furnace_white_ground_cloud, emitter_front_side, bad_meshes_are_errors,
          large_mesh_renders, assimp_opened_on_first_use, embree_opened_on_first_use)
