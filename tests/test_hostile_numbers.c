/* test_hostile_numbers.c - extreme but finite numbers: refused in one line with the limit
 * printed exactly, or normalised so that the picture is right; never an abort, a hang or a
 * silent black image. Each case is an input an attacker tried (docs/scene-format.md#limits). */
#include "test.h"

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "density/fractal.h"
#include "io/sandbox.h"
#include "phase/phase.h"

/* Loads and commits the scene text (named name) as a user's file would be; returns the
 * status and copies the context's message into msg. */
static brume_status load_commit(const char *name, const char *json, char *msg, size_t n)
{
    brume_context *ctx = brume_context_new();
    ASSERT_TRUE(ctx != NULL);
    brume_source src = {name, json};
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &src, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    snprintf(msg, n, "%s", brume_context_last_error(ctx));
    brume_scene_release(s);
    brume_context_release(ctx);
    return st;
}

#define SCENE_HEAD "{\"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}], "
#define SPHERE "\"surfaces\": [{\"type\": \"sphere\", \"center\": [0, 0, 0], \"radius\": 1}], "
#define SMALL "\"render\": {\"width\": 8, \"height\": 8, \"spp\": 1, \"threads\": 1}}"

/* A limit and a value beyond it by one are printed as the integers they are: not
 * "1.67772e+07 outside [1, 1.67772e+07]", a value shown equal to its bound. */
TEST(limits_are_printed_exactly)
{
    char msg[1024];
    ASSERT_TRUE(load_commit("spp.json", "{\"render\": {\"spp\": 16777217}}", msg, sizeof msg) != BRUME_OK);
    ASSERT_CONTAINS(msg, "render.spp: 16777217 outside [1, 16777216]");
    /* a fraction beyond a limit by one part in 1e16 shows the difference */
    const char *fov = "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 179.00000000000003}}";
    ASSERT_TRUE(load_commit("fov.json", fov, msg, sizeof msg) != BRUME_OK);
    ASSERT_CONTAINS(msg, "179.00000000000003");
    /* and a plain number stays plain */
    char out[64];
    err_format(out, sizeof out, "%.17g %.17g %.17g %.17g", 0.1, 1e30, 400.0, -2.5);
    ASSERT_TRUE(strcmp(out, "0.1 1e+30 400 -2.5") == 0);
}

/* A thin lens or a camera far out put ray origins beyond what Embree accepts (it aborted the
 * process): refused at commit in one line naming the camera. */
TEST(camera_beyond_ray_tracing_reach_is_refused)
{
    static const char *const cams[] = {
        "\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"aperture_radius\": 1e30, "
        "\"focus_distance\": 4}, ",
        "\"camera\": {\"position\": [1e30, 0, 4], \"look_at\": [0, 0, 0]}, ",
        "\"camera\": {\"position\": [0, -2e18, 4], \"look_at\": [0, 0, 0]}, ",
        "\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"keyframes\": [{\"time\": 0, "
        "\"aperture_radius\": 0}, {\"time\": 1, \"aperture_radius\": 5e18}]}, ",
    };
    for (size_t i = 0; i < sizeof cams / sizeof cams[0]; i++) {
        char json[1024], msg[1024];
        snprintf(json, sizeof json, SCENE_HEAD SPHERE "%s" SMALL, cams[i]);
        brume_status st = load_commit("cam.json", json, msg, sizeof msg);
        if (st == BRUME_OK)
            TEST_FAIL("camera %zu accepted: %s", i, json);
        ASSERT_CONTAINS(msg, "cam.json: camera");
        ASSERT_CONTAINS(msg, "1e+18");
        ASSERT_TRUE(strchr(msg, '\n') == NULL);
    }
    /* within reach it renders */
    char json[1024], msg[1024];
    snprintf(json, sizeof json, SCENE_HEAD SPHERE "\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], "
             "\"aperture_radius\": 1e17, \"focus_distance\": 1e30}, " SMALL);
    ASSERT_EQ_INT(load_commit("cam.json", json, msg, sizeof msg), BRUME_OK);
    brume_image_release(test_render_json(json, 1));
}

/* The same through pbrt-v4's lensradius. */
TEST(pbrt_lensradius_beyond_reach_is_refused)
{
    const char *path = test_tmp_path("lens.pbrt");
    test_write_file(path, "LookAt 0 0 4  0 0 0  0 1 0\n"
                          "Camera \"perspective\" \"float fov\" [40] \"float lensradius\" [1e30]\n"
                          "Film \"rgb\" \"integer xresolution\" [8] \"integer yresolution\" [8]\n"
                          "WorldBegin\n"
                          "LightSource \"distant\" \"point3 from\" [0 1 0] \"point3 to\" [0 0 0]\n"
                          "Shape \"sphere\" \"float radius\" [1]\n");
    brume_context *ctx = brume_context_new();
    brume_source src = {path, NULL};
    brume_scene *s = NULL;
    brume_status st = brume_scene_load(ctx, &src, NULL, &s);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    ASSERT_TRUE(st != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "lensradius");
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
}

/* A chromatic medium whose channels differ by 1e12: every flight would take about 1e12
 * tentative collisions (the render ran for minutes and ignored SIGTERM). Refused at commit;
 * the same medium with channels 1 : 2 : 3 renders. */
#define BOX_MEDIUM(sa, ss)                                                                          \
    SCENE_HEAD "\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0]}, \"media\": [{\"density\": "     \
               "{\"type\": \"constant\", \"value\": 1, \"bounds\": [[-1, -1, -1], [1, 1, 1]]}, "                 \
               "\"sigma_a\": " sa ", \"sigma_s\": " ss "}], " SMALL

TEST(chromatic_medium_beyond_tracking_is_refused)
{
    char msg[1024];
    ASSERT_TRUE(load_commit("chroma.json", BOX_MEDIUM("[1e12, 1e-3, 1e-3]", "[1e12, 1, 1]"), msg, sizeof msg) !=
                BRUME_OK);
    ASSERT_CONTAINS(msg, "chroma.json: media[0]");
    ASSERT_CONTAINS(msg, "tentative collisions");
    /* a clear channel in a field 3.5 wide of optical depth 1e6 at the others' rate */
    ASSERT_TRUE(load_commit("chroma.json", BOX_MEDIUM("0", "[3e5, 3e5, 0]"), msg, sizeof msg) != BRUME_OK);
    ASSERT_EQ_INT(load_commit("chroma.json", BOX_MEDIUM("[0.1, 0.2, 0.3]", "[1, 2, 3]"), msg, sizeof msg), BRUME_OK);
    /* gray: every collision is real, whatever the extinction */
    ASSERT_EQ_INT(load_commit("chroma.json", BOX_MEDIUM("1e12", "1e12"), msg, sizeof msg), BRUME_OK);
}

/* A tabulated phase function's scale is arbitrary: values near DBL_MAX made the trapezoids'
 * sum infinite and the normalised table 0 (a black medium, exit 0). The table scaled by 1e300
 * is the same phase function as the table itself. */
TEST(tabulated_phase_with_huge_values_is_normalised)
{
    const double angle[3] = {0.0, 90.0, 180.0};
    const double v1[3] = {3.0, 1.0, 2.0};
    const double vhuge[3] = {3e307, 1e307, 2e307};
    phase *a = phase_new_tabulated(3, angle, v1), *b = phase_new_tabulated(3, angle, vhuge);
    ASSERT_TRUE(a != NULL && b != NULL);
    for (double c = -1.0; c <= 1.0; c += 0.125) {
        double pa = phase_eval(a, c), pb = phase_eval(b, c);
        ASSERT_TRUE(pa > 0.0 && isfinite(pb));
        ASSERT_NEAR(pb, pa, 1e-12 * pa);
    }
    phase_release(a);
    phase_release(b);
}

/* A fractal cloud's turbulence moved by wind x time reached Perlin's int lattice index with a
 * double far beyond INT_MAX (undefined behaviour): refused in one line. */
TEST(fractal_wind_times_time_beyond_lattice_is_refused)
{
    fractal_params p;
    fractal_params_default(&p);
    p.n[0] = p.n[1] = p.n[2] = 4;
    p.turbulence = 0.5;
    p.wind = v3(1e6, 0.0, 0.0);
    p.time = 1e6;
    err_clear();
    float *v = fractal_cloud_voxels(&p);
    ASSERT_TRUE(v == NULL);
    ASSERT_CONTAINS(err_message(), "wind x time");
    p.time = 1.0; /* a wind of 1e6 for a second: 32 million lattice cells at the finest octave */
    v = fractal_cloud_voxels(&p);
    ASSERT_TRUE(v != NULL);
    free(v);
}

/* A child reader killed with SIGKILL by someone other than brume (the system's out-of-memory
 * killer, when an oversized mesh asked for more memory than the machine has) is reported as
 * a refusal for memory, not as "crashed (signal 9)". */
TEST(child_killed_for_memory_is_said_so)
{
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        raise(SIGKILL);
        _exit(0);
    }
    err_clear();
    brume_status st = sandbox_reap(pid, -1, "big.gltf", "the mesh reader", "a malformed or hostile mesh file", 5.0, 15.0);
    ASSERT_EQ_INT(st, BRUME_ERROR_OUT_OF_MEMORY);
    ASSERT_CONTAINS(err_message(), "big.gltf: the mesh reader was refused memory");
    ASSERT_TRUE(strstr(err_message(), "signal 9") == NULL);
}

/* An empty attribute key is not a NULL one. */
TEST(empty_attribute_key_is_named_empty)
{
    brume_context *ctx = brume_context_new();
    brume_image *im = NULL;
    ASSERT_EQ_INT(brume_image_new(ctx, 2, 2, &im), BRUME_OK);
    ASSERT_TRUE(brume_image_set_attribute(ctx, im, "", "x") != BRUME_OK);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "key: empty");
    brume_image_release(im);
    brume_context_release(ctx);
}

TEST_MAIN(limits_are_printed_exactly, camera_beyond_ray_tracing_reach_is_refused,
          pbrt_lensradius_beyond_reach_is_refused, chromatic_medium_beyond_tracking_is_refused,
          tabulated_phase_with_huge_values_is_normalised, fractal_wind_times_time_beyond_lattice_is_refused,
          child_killed_for_memory_is_said_so, empty_attribute_key_is_named_empty)
