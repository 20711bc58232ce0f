/* cmd_compare.c - `brume compare IMAGE REFERENCE`: error figures over the frame and over a
 * region (the cloud), with bootstrap intervals, and a signed difference picture; with
 * --scene and --seeds, the figures of K renders of a scene at independent seeds, mean +- s.e. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli_flags.h"
#include "brume.h"
#include "cli_job.h"
#include "commands.h"

#define MAX_SETS 32
#define MAX_SEEDS 256

static const char *const fig_names[BRUME_NFIGS] = {"ratio", "rel_rmse", "signed_rel"};

static void print_region(const char *name, const brume_region_stats *st, int boot)
{
    printf("%s pixels %ld tiles %ld\n", name, st->pixels, st->tiles);
    for (int f = 0; f < BRUME_NFIGS; f++) {
        if (boot > 0)
            printf("%s %s %.6g [%.6g, %.6g]\n", name, fig_names[f], st->fig[f], st->lo[f], st->hi[f]);
        else
            printf("%s %s %.6g\n", name, fig_names[f], st->fig[f]);
    }
}

typedef struct scene_run {
    const char *path;
    const char *sets[MAX_SETS];
    int nsets;
    const char *method;
    int spp, width, height, threads, seeds;
    uint64_t seed0;
    const char *diff; /* -o, or NULL: never one of the scene's inputs */
} scene_run;

/* Renders the scene at seed; *out is new. */
static brume_image *render_seed(brume_context *ctx, const scene_run *r, uint64_t seed)
{
    brume_scene *s = NULL;
    brume_image *img = NULL;
    brume_load_options lo = {0.0, 0, r->sets, r->nsets, NULL, 0, false};
    if (brume_scene_load(ctx, &(brume_source){.path = r->path}, &lo, &s) != BRUME_OK)
        return NULL;
    if (r->diff && brume_output_check(ctx, "-o", r->diff, BRUME_FILE_IMAGE, s, NULL, 0) != BRUME_OK) {
        brume_scene_release(s);
        return NULL;
    }
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    rs.seed = seed;
    if (r->method && brume_method_from_name(ctx, r->method, &rs.method) != BRUME_OK) {
        brume_scene_release(s);
        return NULL;
    }
    if (r->spp)
        rs.spp = r->spp;
    if (r->width)
        rs.width = r->width;
    if (r->height)
        rs.height = r->height;
    rs.threads = r->threads;
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render(ctx, s, &img) != BRUME_OK)
        img = NULL;
    brume_scene_release(s);
    return img;
}

typedef struct compare_opts {
    const char *paths[2]; /* IMAGE REFERENCE, or REFERENCE alone with --scene */
    int np;
    const char *diff, *mask_path; /* -o, --mask, or NULL */
    double scale, alpha;          /* --scale; --alpha, < 0 without */
    int boot;
    scene_run sr;                 /* --scene and its render options */
} compare_opts;

static bool flag_set(void *opts, const cli_flag *f, const char *v)
{
    (void)f;
    scene_run *sr = &((compare_opts *)opts)->sr;
    if (sr->nsets == MAX_SETS) {
        cli_error("compare: more than %d --set options", MAX_SETS);
        return false;
    }
    sr->sets[sr->nsets++] = v;
    return true;
}

#define OFF(field) offsetof(compare_opts, field)

static const cli_flag compare_flags[] = {
    {"--alpha", NULL, "T", "region: the pixels where REFERENCE's alpha (1 - the media's transmittance,\n"
     "an EXR written by brume render) exceeds T, e.g. 0.05 for the cloud", NULL, CLI_FLAG_DOUBLE, OFF(alpha), 0.0,
     0.999999, NULL},
    {"--mask", NULL, "FILE", "region: the pixels where FILE (same size) is brighter than 0.5", NULL, CLI_FLAG_STRING,
     OFF(mask_path), 0, 0, NULL},
    {"--boot", NULL, "N", "bootstrap draws (default 1000; 0: no interval)", NULL, CLI_FLAG_INT, OFF(boot), 0, 100000,
     NULL},
    {"--output", "-o", "DIFF.png", "signed difference picture: blue darker, red brighter than the reference,\n"
     "white equal, dark at +-S or beyond, a scale bar in percent under it; the\n"
     "pixels outside the region greyed (.exr/.pfm: the colours alone, linear)", NULL, CLI_FLAG_STRING, OFF(diff), 0, 0,
     NULL},
    {"--scale", NULL, "S", "the difference where the colours saturate (default 0.5 = 50 %)", NULL, CLI_FLAG_DOUBLE,
     OFF(scale), 1e-6, 1e6, NULL},
    {"--scene", NULL, "FILE", "render FILE instead of reading IMAGE, --seeds K times (seeds S0 .. S0+K-1),\n"
     "and print each render's figures and their mean +- standard error over K", NULL, CLI_FLAG_STRING, OFF(sr.path), 0,
     0, NULL},
    {"--seeds", NULL, "K", "with --scene: the number of independent renders (2 .. 256)", NULL, CLI_FLAG_INT,
     OFF(sr.seeds), 2, MAX_SEEDS, NULL},
    {"--seed", NULL, "S0", "the first seed (default 1); -o then pictures the last render", "render.seed",
     CLI_FLAG_U64, OFF(sr.seed0), 0, 0, NULL},
    {"--set", NULL, "KEY=VALUE", "as for brume render, for --scene", NULL, CLI_FLAG_CALL, 0, 0, 0, flag_set},
    {"--method", NULL, "M", "as for brume render, for --scene", "render.method", CLI_FLAG_STRING, OFF(sr.method), 0, 0,
     NULL},
    {"--spp", NULL, "N", "as for brume render, for --scene", "render.spp", CLI_FLAG_INT, OFF(sr.spp), 1, 1 << 24,
     NULL},
    {"--width", NULL, "W", "as for brume render, for --scene", "render.width", CLI_FLAG_INT, OFF(sr.width), 1, 65536,
     NULL},
    {"--height", NULL, "H", "as for brume render, for --scene", "render.height", CLI_FLAG_INT, OFF(sr.height), 1,
     65536, NULL},
    {"--threads", NULL, "N", "as for brume render, for --scene", "render.threads", CLI_FLAG_INT, OFF(sr.threads), 0,
     1024, NULL},
};

const cli_command cli_compare_command = {
    "compare", "error figures over the frame and the cloud, with bootstrap intervals, and a difference picture",
    "IMAGE REFERENCE [options]\n--scene SCENE.json --seeds K REFERENCE [options]",
    "Prints the error figures of IMAGE against REFERENCE, one per line:\n"
    "  rmse, rel_rmse (rmse / mean reference), mean_rel, max_rel (relative luminance differences\n"
    "  over pixels brighter than 1% of the mean), mean, mean_ref (the old figures, whole frame);\n"
    "  then for the frame, and for the region when --alpha or --mask gives one:\n"
    "  REGION pixels N tiles T\n"
    "  REGION ratio X [LO, HI]        mean(IMAGE) / mean(REFERENCE)\n"
    "  REGION rel_rmse X [LO, HI]     rms difference / mean(REFERENCE)\n"
    "  REGION signed_rel X [LO, HI]   mean signed relative luminance difference (< 0: darker)\n"
    "  [LO, HI] is a 95% block-bootstrap interval (8 x 8-pixel tiles, fixed seed).\n"
    "With --scene, the figures of K renders of a scene at independent seeds, mean +- s.e.\n",
    compare_flags, CLI_NFLAGS(compare_flags), NULL, NULL};

/* The command line into *o. -1: go on; otherwise the exit status (0 after --help, 2 with a
 * message). */
static int parse_compare(compare_opts *o, int argc, char **argv)
{
    return cli_flags_parse(&cli_compare_command, o, argc, argv, o->paths, 2, &o->np);
}

/* The options that go together: 0, or 2 with a message. */
static int check_compare(const compare_opts *o)
{
    const scene_run *sr = &o->sr;
    if (o->alpha >= 0.0 && o->mask_path) {
        cli_error("compare: --alpha and --mask both give the region: choose one");
        return 2;
    }
    if (!sr->path && (sr->seeds || sr->nsets || sr->method || sr->spp || sr->width || sr->height)) {
        cli_error("compare: --seeds, --set, --method, --spp, --width and --height need --scene");
        return 2;
    }
    if (sr->path && (!sr->seeds || o->np != 1)) {
        cli_error("compare: --scene needs --seeds K and the REFERENCE alone (try `brume help compare`)");
        return 2;
    }
    if (!sr->path && o->np != 2) {
        cli_error("compare: need IMAGE and REFERENCE (try `brume help compare`)");
        return 2;
    }
    return 0;
}

/* IMAGE against REFERENCE: the whole-frame figures, then the frame's and the region's (rname
 * not NULL) with their intervals. 0, or 1 with a message. */
static int compare_two(brume_context *ctx, const compare_opts *o, const brume_image *img, const brume_image *ref,
                       const unsigned char *mask, const char *rname)
{
    brume_image_diff st;
    brume_region_stats fr, rg;
    if (brume_image_compare(ctx, img, ref, &st) != BRUME_OK ||
        brume_image_compare_region(ctx, img, ref, NULL, o->boot, 1, &fr) != BRUME_OK ||
        (rname && brume_image_compare_region(ctx, img, ref, mask, o->boot, 1, &rg) != BRUME_OK)) {
        cli_error("%s: %.1000s", o->paths[0], brume_context_last_error(ctx));
        return 1;
    }
    printf("rmse %.6g\nrel_rmse %.6g\nmean_rel %.6g\nmax_rel %.6g\nmean %.6g\nmean_ref %.6g\n", st.rmse,
           st.rel_rmse, st.mean_rel, st.max_rel, st.mean_img, st.mean_ref);
    print_region("frame", &fr, o->boot);
    if (rname)
        print_region(rname, &rg, o->boot);
    return 0;
}

/* K renders of the scene: each one's figures, then the mean and its standard error over K.
 * *img is the last render (the caller releases it). 0, or 1 with a message. */
static int compare_seeds(brume_context *ctx, const scene_run *sr, const brume_image *ref, const unsigned char *mask,
                         const char *rname, brume_image **img)
{
    double sum[2][BRUME_NFIGS] = {{0}}, sum2[2][BRUME_NFIGS] = {{0}};
    int nreg = rname ? 2 : 1;
    for (int k = 0; k < sr->seeds; k++) {
        uint64_t seed = sr->seed0 + (uint64_t)k;
        brume_image_release(*img);
        if (!(*img = render_seed(ctx, sr, seed))) {
            cli_error("%.1000s", brume_context_last_error(ctx));
            return 1;
        }
        for (int g = 0; g < nreg; g++) {
            brume_region_stats st;
            if (brume_image_compare_region(ctx, *img, ref, g ? mask : NULL, 0, 1, &st) != BRUME_OK) {
                cli_error("%s: %.1000s", sr->path, brume_context_last_error(ctx));
                return 1;
            }
            printf("seed %llu %s", (unsigned long long)seed, g ? rname : "frame");
            for (int f = 0; f < BRUME_NFIGS; f++) {
                printf(" %s %.6g", fig_names[f], st.fig[f]);
                sum[g][f] += st.fig[f];
                sum2[g][f] += st.fig[f] * st.fig[f];
            }
            printf("\n");
        }
    }
    double K = sr->seeds;
    for (int g = 0; g < nreg; g++)
        for (int f = 0; f < BRUME_NFIGS; f++) {
            double m = sum[g][f] / K, var = fmax(0.0, (sum2[g][f] - K * m * m) / (K - 1.0));
            printf("%s %s %.6g +- %.2g (%d seeds)\n", g ? rname : "frame", fig_names[f], m, sqrt(var / K), sr->seeds);
        }
    return 0;
}

/* -o: the signed difference picture, as a PNG with its scale bar or as linear colours. 0, or
 * 1 with a message. */
static int write_diff(brume_context *ctx, const compare_opts *o, const brume_image *img, const brume_image *ref,
                      const unsigned char *mask)
{
    size_t n = strlen(o->diff);
    bool png = n >= 4 && strcmp(o->diff + n - 4, ".png") == 0;
    brume_image *pic = NULL;
    if (png ? brume_image_diff_png(ctx, img, ref, mask, o->scale, o->diff) != BRUME_OK
            : brume_image_diff_picture(ctx, img, ref, o->scale, &pic) != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(ctx));
        return 1;
    }
    if (pic && brume_image_write(ctx, pic, o->diff, NULL) != BRUME_OK) {
        brume_image_release(pic);
        cli_error("%.1000s", brume_context_last_error(ctx));
        return 1;
    }
    brume_image_release(pic);
    return 0;
}

int cmd_compare(int argc, char **argv)
{
    compare_opts o = {.scale = 0.5, .alpha = -1.0, .boot = 1000, .sr = {.seed0 = 1}};
    int rc = parse_compare(&o, argc, argv);
    if (rc >= 0)
        return rc;
    if ((rc = check_compare(&o)) != 0)
        return rc;
    const scene_run *sr = &o.sr;
    const char *ref_path = sr->path ? o.paths[0] : o.paths[1], *mask_path = o.mask_path;
    /* before any work: the picture is none of the inputs (nor, with --scene, the files the
     * scene reads: checked as soon as it is loaded, render_seed) */
    const char *inputs[3] = {sr->path ? NULL : o.paths[0], ref_path, mask_path};
    if (o.diff && cli_check_output("-o", o.diff, BRUME_FILE_IMAGE, sr->path, NULL, inputs, 3) != 0)
        return 1;
    o.sr.diff = o.diff;
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL, *ref = NULL, *mpic = NULL;
    unsigned char *mask = NULL;
    long mcount = 0;
    rc = 1;
    if (!ctx || brume_image_read(ctx, ref_path, &ref) != BRUME_OK ||
        (!sr->path && brume_image_read(ctx, o.paths[0], &img) != BRUME_OK) ||
        (mask_path && brume_image_read(ctx, mask_path, &mpic) != BRUME_OK)) {
        cli_error("%.1000s", ctx ? brume_context_last_error(ctx) : "out of memory");
        goto done;
    }
    /* light is finite and >= 0: a NaN or a negative value would make every figure meaningless */
    if ((img && brume_image_check_values(ctx, img, o.paths[0], false) != BRUME_OK) ||
        brume_image_check_values(ctx, ref, ref_path, false) != BRUME_OK ||
        (mpic && brume_image_check_values(ctx, mpic, mask_path, false) != BRUME_OK)) { /* a NaN mask picks nothing */
        cli_error("%.1000s", brume_context_last_error(ctx));
        goto done;
    }
    const char *rname = o.alpha >= 0.0 || mask_path ? "region" : NULL;
    if ((o.alpha >= 0.0 && brume_image_mask_alpha(ctx, ref, o.alpha, &mask, &mcount) != BRUME_OK) ||
        (mpic && brume_image_mask_picture(ctx, mpic, brume_image_width(ref), brume_image_height(ref), &mask, &mcount) !=
                     BRUME_OK)) {
        cli_error("%s: %.1000s", mask_path ? mask_path : ref_path, brume_context_last_error(ctx));
        goto done;
    }
    if (rname && mcount == 0) {
        cli_error("%s: the region is empty (%s)", mask_path ? mask_path : ref_path,
                  mask_path ? "no pixel brighter than 0.5" : "no pixel of the reference's alpha above --alpha");
        goto done;
    }
    if (sr->path ? compare_seeds(ctx, sr, ref, mask, rname, &img) != 0 : compare_two(ctx, &o, img, ref, mask, rname) != 0)
        goto done;
    if (o.diff && write_diff(ctx, &o, img, ref, mask) != 0)
        goto done;
    rc = 0;
done:
    free(mask);
    brume_image_release(img);
    brume_image_release(ref);
    brume_image_release(mpic);
    brume_context_release(ctx);
    return rc;
}
