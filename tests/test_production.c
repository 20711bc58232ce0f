/* test_production.c - files as artists hand them over (docs/production.md): auto-framing of
 * the camera on the media, and the studio scene of a grid file. */
#include "test.h"

#include "brume.h"
#include "io/grid_io.h"
#include "io/grid_sequence.h"
#include "scene/scene.h"

/* The largest of |x| / (t_h) and |y| / (t_v) over the box's corners projected by the
 * committed camera: 1 - margin when the framing is tight, and every corner in front. */
static double corner_extent(const brume_scene *s, const double box[6])
{
    const camera *c = &s->cam;
    double worst = 0.0;
    for (int k = 0; k < 8; k++) {
        vec3 p = v3(box[k & 1 ? 3 : 0], box[k & 2 ? 4 : 1], box[k & 4 ? 5 : 2]);
        vec3 d = v3_sub(p, c->position);
        double z = v3_dot(d, c->f.n);
        ASSERT_TRUE(z > 0.0);
        double x = fabs(v3_dot(d, c->f.s)) / (z * c->tan_half * c->aspect);
        double y = fabs(v3_dot(d, c->f.t)) / (z * c->tan_half);
        worst = fmax(worst, fmax(x, y));
    }
    return worst;
}

static brume_scene *box_scene(brume_context *ctx, const double *box_a, const double *box_b)
{
    char json[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"frame\": \"%s\", \"frame_margin\": 0.2, \"position\": [3, 1, 2], \"look_at\": [0, 0, 0], "
             "\"fov\": 25},"
             " \"media\": [{\"name\": \"a\", \"density\": {\"type\": \"constant\", \"bounds\": [[%g, %g, %g], [%g, %g, %g]]},"
             " \"sigma_a\": 0, \"sigma_s\": 1}, {\"name\": \"b\", \"density\": {\"type\": \"constant\", \"bounds\": "
             "[[%g, %g, %g], [%g, %g, %g]]}, \"sigma_a\": 0, \"sigma_s\": 1}],"
             " \"render\": {\"width\": 300, \"height\": 120}}",
             box_b ? "a" : "media", box_a[0], box_a[1], box_a[2], box_a[3], box_a[4], box_a[5],
             box_b ? box_b[0] : box_a[0], box_b ? box_b[1] : box_a[1], box_b ? box_b[2] : box_a[2],
             box_b ? box_b[3] : box_a[3], box_b ? box_b[4] : box_a[4], box_b ? box_b[5] : box_a[5]);
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = "frame.json", .text = json}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    return s;
}

/* The framed camera sees the whole box, with exactly the margin on the tighter side, and
 * keeps the direction it was given. */
TEST(frame_fits_box_with_margin)
{
    brume_context *ctx = brume_context_new();
    const double box[6] = {1, 2, 3, 2, 4, 4};
    brume_scene *s = box_scene(ctx, box, NULL);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_NEAR(corner_extent(s, box), 0.8, 1e-9);
    vec3 want = v3_normalize(v3(3, 1, 2)), got = v3_normalize(v3_sub(s->cam.position, s->cam.look_at));
    ASSERT_NEAR(v3_dot(want, got), 1.0, 1e-12);
    ASSERT_NEAR(s->cam.look_at.x, 1.5, 1e-12);
    ASSERT_NEAR(s->cam.look_at.y, 3.0, 1e-12);
    ASSERT_NEAR(s->cam.look_at.z, 3.5, 1e-12);
    brume_scene_release(s);
    /* the final image size counts: a tall image after loading reframes for it */
    s = box_scene(ctx, box, NULL);
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.width = 100;
    rs.height = 400;
    ASSERT_EQ_INT(brume_scene_set_settings(ctx, s, &rs), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_NEAR(corner_extent(s, box), 0.8, 1e-9);
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* "frame": a medium's name frames that medium alone; an unknown name is an error. */
TEST(frame_named_medium)
{
    brume_context *ctx = brume_context_new();
    const double a[6] = {-1, -1, -1, 0, 0, 0}, b[6] = {5, 5, 5, 9, 6, 7};
    brume_scene *s = box_scene(ctx, a, b);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_NEAR(corner_extent(s, a), 0.8, 1e-9);
    ASSERT_NEAR(s->cam.look_at.x, -0.5, 1e-12);
    brume_scene_release(s);
    s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = "f.json", .text = "{\"camera\": {\"frame\": \"nope\"}, \"media\": [{\"name\": \"a\", \"density\": "
                                        "{\"type\": \"constant\"}, \"sigma_a\": 0, \"sigma_s\": 1}]}"}, NULL, &s),
                  BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_ERROR_INVALID_ARGUMENT);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "camera.frame: no medium of that name");
    brume_scene_release(s);
    brume_context_release(ctx);
}

/* A small grid file made by `brume gen`; returns its path, or skips without OpenVDB. */
static const char *gen_grid(const char *name, const char *args)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB (writing .nvdb/.vdb)\n");
        exit(77);
    }
    const char *path = test_tmp_path(name);
    if (strcmp(name, "pbrt-grid.nvdb") == 0 && test_exists(path)) /* one grid for every pbrt case */
        return path;
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "%s gen %s -o %s", BRUME_EXE, args, path);
    ASSERT_EQ_INT(test_system(cmd), 0);
    return path;
}

/* A .vdb as the scene: framed on its non-zero voxels, lit, and the extinction scaled to the
 * documented optical depth across the shortest side. */
TEST(studio_scene_of_a_grid)
{
    const char *path = gen_grid("studio.vdb", "cloud --dims 24x12x16 --shape ellipsoid --bounds 2,0,0,6,2,3");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_studio_options so = {0};
    so.up = BRUME_AXIS_Z;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, &(brume_load_options){.studio = &so}, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    ASSERT_EQ_INT(brume_scene_medium_count(s), 1);
    ASSERT_EQ_INT(s->nlights, 1);
    ASSERT_TRUE(s->surf != NULL); /* the ground */
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    box3 b = scene_density_box(s->media[0].rho);
    const double box[6] = {b.lo.x, b.lo.y, b.lo.z, b.hi.x, b.hi.y, b.hi.z};
    ASSERT_NEAR(corner_extent(s, box), 0.9, 1e-9);
    ASSERT_NEAR(s->cam.up.z, 1.0, 1e-12);
    ASSERT_TRUE(s->cam.position.z > s->cam.look_at.z); /* from above the horizon, z up */
    double shortest = fmin(b.hi.x - b.lo.x, fmin(b.hi.y - b.lo.y, b.hi.z - b.lo.z));
    double tau = (s->media[0].sigma_a.c[0] + s->media[0].sigma_s.c[0]) * density_max(s->media[0].rho) * shortest;
    ASSERT_NEAR(tau, 10.0, 10.0 * 1e-3); /* the printed coefficients keep four digits */
    brume_scene_release(s);
    /* no ground, and a name that is not a grid */
    so.no_ground = true;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path}, &(brume_load_options){.studio = &so}, &s), BRUME_OK);
    ASSERT_TRUE(s->surf == NULL);
    brume_scene_release(s);
    so.grid = "nope";
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path}, &(brume_load_options){.studio = &so}, &s), BRUME_ERROR_INVALID_ARGUMENT);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "no float grid named \"nope\"");
    brume_context_release(ctx);
    remove(path);
}

/* A temperature grid makes the studio scene a fire. */
TEST(studio_scene_of_a_fire)
{
    const char *path = gen_grid("studio-fire.vdb", "fire --resolution 16");
    brume_context *ctx = brume_context_new();
    char *text = NULL;
    if (brume_scene_text(ctx, &(brume_source){.path = path}, NULL, &text) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    ASSERT_CONTAINS(text, "\"temperature\"");
    ASSERT_CONTAINS(text, "\"blackbody\"");
    brume_scene *s = NULL;
    ASSERT_EQ_INT(brume_scene_load(ctx, &(brume_source){.path = path, .text = text}, NULL, &s), BRUME_OK);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    ASSERT_TRUE(s->has_emission);
    brume_scene_release(s);
    free(text);
    brume_context_release(ctx);
    remove(path);
}

/* brume render FILE.vdb renders; --print-scene writes JSON that renders the same image. */
TEST(cli_renders_a_grid_file)
{
    const char *path = gen_grid("cli.nvdb", "cloud --dims 16x16x8 --shape ellipsoid");
    const char *png = test_tmp_path("cli-a.png"), *png2 = test_tmp_path("cli-b.png");
    const char *json = test_tmp_path("cli.json");
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "%s render %s -o %s --spp 2 --width 24 --height 16 --threads 2 -q", BRUME_EXE, path, png);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s render %s --print-scene > %s", BRUME_EXE, path, json);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(cmd, sizeof cmd, "%s render %s -o %s --spp 2 --width 24 --height 16 --threads 1 -q", BRUME_EXE, json, png2);
    ASSERT_EQ_INT(test_system(cmd), 0);
    size_t n1 = 0, n2 = 0;
    char *a = test_slurp(png, &n1), *b = test_slurp(png2, &n2);
    ASSERT_TRUE(n1 == n2 && memcmp(a, b, n1) == 0);
    free(a);
    free(b);
    snprintf(cmd, sizeof cmd, "%s render %s --up x --print-scene 2>/dev/null", BRUME_EXE, path);
    ASSERT_EQ_INT(test_system(cmd), 2);
    remove(png);
    remove(png2);
    remove(json);
    remove(path);
}

/* The patterns: %0Nd, %d, a run of '#', $F and $FN; one per name, in the file name. */
TEST(sequence_patterns)
{
    char out[256];
    ASSERT_EQ_INT(seq_is_pattern("a/smoke_%04d.vdb"), 1);
    seq_name("a/smoke_%04d.vdb", 7, out, sizeof out);
    ASSERT_EQ_STR(out, "a/smoke_0007.vdb");
    seq_name("smoke_###.vdb", 12345, out, sizeof out);
    ASSERT_EQ_STR(out, "smoke_12345.vdb"); /* wider when the number needs it */
    seq_name("smoke_$F4.vdb", 3, out, sizeof out);
    ASSERT_EQ_STR(out, "smoke_0003.vdb");
    seq_name("smoke_$F.vdb", 3, out, sizeof out);
    ASSERT_EQ_STR(out, "smoke_3.vdb");
    seq_name("s_%d_100%%.vdb", 3, out, sizeof out);
    ASSERT_EQ_STR(out, "s_3_100%%.vdb"); /* %% stays as written: a file name, not printf */
    ASSERT_EQ_INT(seq_is_pattern("a_#/smoke.vdb"), 0); /* folders are not patterns */
    ASSERT_EQ_INT(seq_is_pattern("smoke.vdb"), 0);
    ASSERT_EQ_INT(seq_is_pattern("smoke_%4d.vdb"), -1);
    ASSERT_EQ_INT(seq_is_pattern("smoke_%04d_##.vdb"), -1);
}

/* Three files told apart by their bounds: x from k to k + 1 for file k. */
static const char *make_sequence(void)
{
    if (!grid_have_openvdb()) {
        printf("skipped: no OpenVDB (writing .nvdb)\n");
        exit(77);
    }
    const char *dir = test_tmp_path("seq");
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "rm -rf %s && mkdir -p %s", dir, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    for (int k = 1; k <= 3; k++) {
        snprintf(cmd, sizeof cmd, "%s gen cloud --dims 8x8x4 --shape none --bounds %d,0,0,%d,1,1 -o %s/smoke_%04d.nvdb",
                 BRUME_EXE, k, k + 1, dir, k);
        ASSERT_EQ_INT(test_system(cmd), 0);
    }
    return dir;
}

/* The file frame f reads, told by the loaded density's x bounds (0 = refused). */
static int file_of_frame(const char *dir, const char *keys, long f, const char *want_error)
{
    char json[1024], path[1024];
    snprintf(json, sizeof json,
             "{\"camera\": {\"frame\": \"media\"}, \"media\": [{\"density\": {\"type\": \"grid\", "
             "\"file\": \"smoke_####.nvdb\"%s}, \"sigma_a\": 0, \"sigma_s\": 1}]}", keys);
    snprintf(path, sizeof path, "%s/s.json", dir);
    test_write_file(path, json);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_load_options lo = {0.0, f, NULL, 0, NULL, 0, false};
    brume_status st = brume_scene_load(ctx, &(brume_source){.path = path}, &lo, &s);
    int k = 0;
    if (st == BRUME_OK) {
        k = (int)lround(density_bounds(s->media[0].rho).lo.x);
        ASSERT_TRUE(!brume_scene_world_is_static(s)); /* so that each frame is loaded again */
        brume_scene_release(s);
    } else if (!want_error) {
        TEST_FAIL("%s", brume_context_last_error(ctx));
    } else {
        ASSERT_CONTAINS(brume_context_last_error(ctx), want_error);
        ASSERT_TRUE(strchr(brume_context_last_error(ctx), '\n') == NULL);
    }
    brume_context_release(ctx);
    return k;
}

/* Each frame reads its file: offset, step, and hold / loop / refuse beyond the files. */
TEST(sequence_frames_read_their_files)
{
    const char *dir = make_sequence();
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1", 0, NULL), 1);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1", 2, NULL), 3);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1, \"frame_step\": 2", 1, NULL), 3);
    ASSERT_EQ_INT(file_of_frame(dir, "", 1, NULL), 1);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1", 3, "frame 3 wants file 4, outside the files 1 to 3"), 0);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1, \"beyond\": \"hold\"", 7, NULL), 3);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1, \"beyond\": \"loop\"", 4, NULL), 2);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"beyond\": \"sometimes\"", 1, "beyond: unknown 'sometimes'"), 0);
    char cmd[2048];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

/* A gap: the whole sequence is refused before any frame renders, naming the first missing
 * frame; brume info on the pattern gives the range and the bounds over it. */
TEST(sequence_checked_before_rendering)
{
    const char *dir = make_sequence();
    char cmd[4096], path[1024], err[1024];
    snprintf(cmd, sizeof cmd, "%s info %s/smoke_%%04d.nvdb > %s/info.txt", BRUME_EXE, dir, dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(path, sizeof path, "%s/info.txt", dir);
    size_t n = 0;
    char *info = test_slurp(path, &n);
    ASSERT_CONTAINS(info, "files 1 to 3 (3 files)");
    ASSERT_CONTAINS(info, "(1, 0, 0) to (4, 1, 1) over the sequence");
    free(info);
    ASSERT_EQ_INT(file_of_frame(dir, ", \"frame_offset\": 1, \"beyond\": \"hold\"", 0, NULL), 1); /* writes s.json */
    snprintf(cmd, sizeof cmd, "rm %s/smoke_0002.nvdb", dir);
    ASSERT_EQ_INT(test_system(cmd), 0);
    snprintf(path, sizeof path, "%s/s.json", dir);
    brume_context *ctx = brume_context_new();
    ASSERT_EQ_INT(brume_scene_check_frames(ctx, &(brume_source){.path = path}, NULL, 0, 0), BRUME_ERROR_IO);
    ASSERT_CONTAINS(brume_context_last_error(ctx), "frame file 2 missing");
    brume_context_release(ctx);
    snprintf(err, sizeof err, "%s/err.txt", dir);
    snprintf(cmd, sizeof cmd, "%s render %s --frames 0-2 --spp 1 --width 8 --height 8 -q -o %s/f_%%d.png 2> %s",
             BRUME_EXE, path, dir, err);
    ASSERT_EQ_INT(test_system(cmd), 1);
    char *msg = test_slurp(err, &n);
    ASSERT_CONTAINS(msg, "frame file 2 missing (");
    ASSERT_TRUE(strchr(msg, '\n') == msg + strlen(msg) - 1); /* one line */
    free(msg);
    snprintf(path, sizeof path, "%s/f_0.png", dir);
    ASSERT_TRUE(!test_exists(path)); /* no frame rendered */
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    test_system(cmd);
}

/* A small pbrt-v4 scene beside a grid made by brume gen; returns the .pbrt's path. */
static const char *write_pbrt(const char *name, const char *camera_prefix, const char *extra)
{
    const char *grid = gen_grid("pbrt-grid.nvdb", "cloud --dims 8x8x8 --shape ellipsoid --bounds 0,0,0,1,1,1");
    char text[4096];
    snprintf(text, sizeof text,
             "Integrator \"volpath\" \"integer maxdepth\" [7]\n"
             "Sampler \"sobol\" \"integer pixelsamples\" 8\n"
             "Film \"rgb\" \"integer xresolution\" [64] \"integer yresolution\" [32] \"string filename\" \"x.exr\"\n"
             "%sLookAt 0 0 5  0 0 0  0 1 0\n"
             "Camera \"perspective\" \"float fov\" [30]\n"
             "WorldBegin\n"
             "LightSource \"infinite\" \"rgb L\" [0.1 0.2 0.3]\n"
             "LightSource \"distant\" \"point3 to\" [0 -1 0] \"rgb L\" [1 2 3] \"float scale\" 2\n"
             "AttributeBegin\n"
             "  Translate 1 0 0\n"
             "  MakeNamedMedium \"smoke\" \"string type\" \"nanovdb\" \"string filename\" \"%s\"\n"
             "    \"rgb sigma_a\" [1 2 3] \"spectrum sigma_s\" [200 0.5 900 0.5] \"float scale\" [2] \"float g\" 0.3\n"
             "AttributeEnd\n"
             "AttributeBegin\n"
             "  Material \"interface\"\n"
             "  MediumInterface \"smoke\" \"\"\n"
             "  Shape \"sphere\" \"float radius\" 3\n"
             "AttributeEnd\n%s",
             camera_prefix, grid, extra);
    const char *path = test_tmp_path(name);
    test_write_file(path, text);
    return path;
}

/* pbrt-v4's units and conventions: sigma x scale per unit density, L x scale, the film,
 * samples and depth, the medium's transform, the camera's handedness and fov. */
TEST(pbrt_scene_maps_units)
{
    const char *path = write_pbrt("units.pbrt", "Scale -1 1 1\n", "");
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    if (brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK)
        TEST_FAIL("%s", brume_context_last_error(ctx));
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    ASSERT_EQ_INT(rs.width, 64);
    ASSERT_EQ_INT(rs.height, 32);
    ASSERT_EQ_INT(rs.spp, 8);
    ASSERT_EQ_INT(rs.max_depth, 7);
    ASSERT_EQ_INT(brume_scene_commit(ctx, s), BRUME_OK);
    const medium *m = &s->media[0];
    ASSERT_NEAR(m->sigma_a.c[0], 2.0, 1e-12);
    ASSERT_NEAR(m->sigma_a.c[2], 6.0, 1e-12);
    ASSERT_NEAR(m->sigma_s.c[1], 1.0, 1e-12);
    /* the CTM at MakeNamedMedium: the 8 voxels on [1, 2], their box one voxel wider on each
       side for pbrt-v4's NanoVDB lookup (edge zero, docs/scene-format.md) */
    ASSERT_NEAR(density_bounds(m->rho).lo.x, 1.0 - 0.125, 1e-9);
    ASSERT_NEAR(density_bounds(m->rho).hi.x, 2.0 + 0.125, 1e-9);
    ASSERT_NEAR(s->bg.L.c[2], 0.3, 1e-12);
    ASSERT_EQ_INT(s->nlights, 1);
    ASSERT_NEAR(s->lights[0].L.c[2], 6.0, 1e-12);
    ASSERT_NEAR(s->lights[0].direction.y, -1.0, 1e-12);
    ASSERT_NEAR(s->cam.position.z, 5.0, 1e-12);
    ASSERT_NEAR(s->cam.f.s.x, 1.0, 1e-12); /* image right is +x, as pbrt draws it with Scale -1 1 1 */
    ASSERT_NEAR(s->cam.fov, 30.0, 1e-12); /* the shorter side is vertical */
    ASSERT_EQ_INT(brume_scene_surface_count(s), 1); /* the interface sphere bounds the medium */
    ASSERT_EQ_INT(s->bounded, 1);
    brume_scene_release(s);
    brume_context_release(ctx);
    remove(path);
    remove(test_tmp_path("pbrt-grid.nvdb"));
}

static void expect_refusal(const char *prefix, const char *extra, const char *line, const char *frag)
{
    const char *path = write_pbrt("bad.pbrt", prefix, extra);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    ASSERT_TRUE(brume_scene_load(ctx, &(brume_source){.path = path}, NULL, &s) != BRUME_OK);
    const char *msg = brume_context_last_error(ctx);
    char want[1200];
    snprintf(want, sizeof want, "%s:%s: ", path, line);
    ASSERT_CONTAINS(msg, want);
    ASSERT_CONTAINS(msg, frag);
    ASSERT_TRUE(strchr(msg, '\n') == NULL);
    brume_context_release(ctx);
    remove(path);
}

/* What brume cannot honour is refused with FILE:LINE and the directive or parameter. */
TEST(pbrt_refuses_what_it_cannot_honour)
{
    expect_refusal("Scale -1 1 1\n", "Shape \"cone\" \"float radius\" 2\n", "20", "Shape \"cone\"");
    expect_refusal("Scale -1 1 1\n", "LightSource \"distant\" \"float power\" 3\n", "20", "parameter \"float power\"");
    expect_refusal("Scale -1 1 1\n", "LightSource \"distant\" \"spectrum L\" [400 1 700 2]\n", "20",
                   "varies with wavelength");
    expect_refusal("Scale -1 1 1\n", "MakeNamedMedium \"f\" \"string type\" \"fog\"\n", "20", "type \"fog\"");
    expect_refusal("Scale -1 1 1\n", "CoordinateSystem \"c\"\n", "20", "CoordinateSystem: not supported");
    remove(test_tmp_path("pbrt-grid.nvdb"));
}

TEST_MAIN(pbrt_scene_maps_units, pbrt_refuses_what_it_cannot_honour, frame_fits_box_with_margin, frame_named_medium, studio_scene_of_a_grid, studio_scene_of_a_fire,
          cli_renders_a_grid_file, sequence_patterns, sequence_frames_read_their_files, sequence_checked_before_rendering)
