/* cmd_render.c - `brume render`: load a scene (or the default), render, write an image. */
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "args.h"
#include "brume.h"
#include "commands.h"

static void render_usage(FILE *out)
{
    fprintf(out,
            "usage: brume render [SCENE.json] [options]\n"
            "Renders SCENE (or the built-in default scene) and writes an image.\n\n"
            "  -o, --output FILE   output image: .png (8-bit sRGB), .exr (float RGBA), .pfm (float RGB)\n"
            "                      (default brume.png)\n"
            "  --spp N             samples per pixel\n"
            "  --width W, --height H   image size in pixels\n"
            "  --seed S            random seed: the image depends on seed and spp, not on threads\n"
            "  --threads N         worker threads (default: one per core)\n"
            "  --method NAME       integrator: path (unbiased reference), single (single scattering),\n"
            "                      blasi (Blasi et al. 1993 two-pass method, docs/blasi.md)\n"
            "                      stam (Stam 1994, blob fields only)\n"
            "  --max-depth N       maximum scattering events per path\n"
            "  --exposure STOPS    PNG only: scale by 2^STOPS before tone mapping\n"
            "  --filmic            PNG only: ACES filmic tone curve instead of clamping\n"
            "  --set KEY=VALUE     a method option, e.g. --set blasi.r=1 (docs/scene-format.md); repeatable\n"
            "  --save-light PATH   blasi: write the first pass's radiance grid (= --set blasi.save_light=PATH)\n"
            "  --load-light PATH   blasi: reuse a saved first pass instead of running it\n"
            "  --quiet             no progress bar or summary\n");
}

static double now_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int cmd_render(int argc, char **argv)
{
    const char *scene_path = NULL, *out_path = "brume.png", *method = NULL;
    int spp = 0, width = 0, height = 0, threads = -1, max_depth = 0;
    uint64_t seed = 0;
    bool have_seed = false, quiet = false;
    brume_write_options wopts = {0.0, BRUME_TONEMAP_CLAMP};
    enum { MAX_SETS = 64 };
    const char *set_key[MAX_SETS], *set_value[MAX_SETS];
    char set_buf[MAX_SETS][256];
    int nsets = 0;

    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            render_usage(stdout);
            return 0;
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (!(out_path = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--spp") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 1 << 24, &spp)) return 2;
        } else if (strcmp(a, "--width") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 65536, &width)) return 2;
        } else if (strcmp(a, "--height") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 65536, &height)) return 2;
        } else if (strcmp(a, "--threads") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 0, 1024, &threads)) return 2;
        } else if (strcmp(a, "--max-depth") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 1, 100000, &max_depth)) return 2;
        } else if (strcmp(a, "--seed") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_u64(a, v, &seed)) return 2;
            have_seed = true;
        } else if (strcmp(a, "--method") == 0) {
            if (!(method = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--exposure") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, -64.0, 64.0, &wopts.exposure)) return 2;
        } else if (strcmp(a, "--filmic") == 0) {
            wopts.tonemap = BRUME_TONEMAP_FILMIC;
        } else if (strcmp(a, "--set") == 0 || strcmp(a, "--save-light") == 0 || strcmp(a, "--load-light") == 0) {
            if (!(v = arg_value(argc, argv, &i))) return 2;
            if (nsets == MAX_SETS) {
                cli_error("render: more than %d options", MAX_SETS);
                return 2;
            }
            if (a[2] != 's' || a[3] != 'e' || a[4] != 't' || a[5] != '\0') { /* --save-light, --load-light */
                set_key[nsets] = a[2] == 's' ? "blasi.save_light" : "blasi.load_light";
                set_value[nsets++] = v;
                continue;
            }
            const char *eq = strchr(v, '=');
            if (!eq || eq == v || (size_t)(eq - v) >= sizeof set_buf[0]) {
                cli_error("--set: expected KEY=VALUE, got '%s'", v);
                return 2;
            }
            snprintf(set_buf[nsets], sizeof set_buf[0], "%.*s", (int)(eq - v), v);
            set_key[nsets] = set_buf[nsets];
            set_value[nsets++] = eq + 1;
        } else if (strcmp(a, "--quiet") == 0 || strcmp(a, "-q") == 0) {
            quiet = true;
        } else if (a[0] == '-' && a[1] != '\0') {
            cli_error("render: unknown option '%s' (try `brume help render`)", a);
            return 2;
        } else if (!scene_path) {
            scene_path = a;
        } else {
            cli_error("render: more than one scene given ('%s' and '%s')", scene_path, a);
            return 2;
        }
    }

    brume_context *ctx = brume_context_new();
    brume_scene *scene = NULL;
    brume_image *image = NULL;
    int rc = 1;
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    brume_status st = scene_path ? brume_scene_load(ctx, scene_path, &scene) : brume_scene_new_default(ctx, &scene);
    if (st != BRUME_OK)
        goto fail;
    brume_render_settings rs;
    brume_scene_get_settings(scene, &rs);
    if (spp) rs.spp = spp;
    if (width) rs.width = width;
    if (height) rs.height = height;
    if (threads >= 0) rs.threads = threads;
    if (max_depth) rs.max_depth = max_depth;
    if (have_seed) rs.seed = seed;
    if (method) {
        if (strlen(method) >= sizeof rs.method) {
            cli_error("--method: unknown method '%s'", method);
            goto done;
        }
        snprintf(rs.method, sizeof rs.method, "%s", method);
    }
    rs.progress = !quiet;
    for (int k = 0; k < nsets; k++)
        if (brume_scene_set_option(ctx, scene, set_key[k], set_value[k]) != BRUME_OK)
            goto fail;
    if (brume_scene_set_settings(ctx, scene, &rs) != BRUME_OK || brume_scene_commit(ctx, scene) != BRUME_OK)
        goto fail;
    double t0 = now_seconds();
    if (brume_render(ctx, scene, &image) != BRUME_OK)
        goto fail;
    double secs = now_seconds() - t0;
    if (brume_image_write(ctx, image, out_path, &wopts) != BRUME_OK)
        goto fail;
    if (!quiet)
        fprintf(stderr, "brume: %s: %d x %d, %d spp, method %s, %.2f s (%.2f M samples/s)\n", out_path, rs.width,
                rs.height, rs.spp, rs.method, secs, (double)rs.width * rs.height * rs.spp / secs * 1e-6);
    rc = 0;
    goto done;
fail:
    cli_error("%s", brume_context_last_error(ctx));
done:
    brume_image_release(image);
    brume_scene_release(scene);
    brume_context_release(ctx);
    return rc;
}
