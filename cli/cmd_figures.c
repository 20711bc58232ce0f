/* cmd_figures.c - `brume figures -o DIR [--quick] [--only NAME]`: every figure of both papers
 * (Blasi et al. 1993: Figures 2-7 and the three pictures of Section 5; Stam 1994: Figures 1
 * and 4-8) into DIR, with index.md and index.html giving each figure beside its caption, the
 * command that makes it alone, and the time it took. docs/gallery.md shows the result. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "brume.h"
#include "cli_flags.h"
#include "commands.h"
#include "figures_table.h"

#ifndef BRUME_SCENES_DIR
#define BRUME_SCENES_DIR "scenes"
#endif

typedef enum fig_kind {
    FIG_RENDER,     /* a scene file rendered as it says */
    FIG_PHASE_FIT,  /* Blasi Figures 2-4: true function and Figure 7's mixture */
    FIG_OVERLAY,    /* Blasi Figures 5-6: a family on one axis */
    FIG_BLASI7,     /* Blasi Figure 7: the table, scored, and its three fits */
    FIG_STAM1,
    FIG_STAM4
} fig_kind;

typedef struct figure {
    const char *name;  /* file DIR/NAME.png and --only NAME */
    const char *paper; /* "Blasi 1993" or "Stam 1994" */
    const char *title; /* "Figure 5 (top left)" */
    fig_kind kind;
    const char *arg;   /* scene name, phase names, or the given triple */
    const char *caption;
} figure;

static const figure figures[] = {
    {"blasi-fig2", "Blasi 1993", "Figure 2", FIG_PHASE_FIT, "rayleigh 0.50,-0.46,0.46",
     "Rayleigh phase function (Eq. 17): (a) the true function (solid), (b) the Schlick mixture of Figure 7, r = 0.5, k = -0.46, "
     "k' = 0.46 (dashed). Polar plot left (light arrives from the left), phi against the angle right."},
    {"blasi-fig3", "Blasi 1993", "Figure 3", FIG_PHASE_FIT, "hazy 0.12,-0.50,0.70",
     "Hazy Mie phase function (Eq. 18), true (solid) and Figure 7's mixture r = 0.12, k = -0.50, k' = 0.70 (dashed); "
     "polar plot linear (phi / max phi), phi against the angle on a log scale."},
    {"blasi-fig4", "Blasi 1993", "Figure 4", FIG_PHASE_FIT, "murky 0.19,-0.65,0.91",
     "Murky Mie phase function (Eq. 18), true (solid) and Figure 7's mixture r = 0.19, k = -0.65, k' = 0.91 (dashed; the "
     "caption's k' = -0.91 is a slip, docs/errata.md, erratum 2); polar plot linear (phi / max phi), phi against the angle on a log scale."},
    {"blasi-fig5", "Blasi 1993", "Figure 5", FIG_OVERLAY, "hg:-0.9 hg:-0.6 hg:0 hg:0.6 hg:0.9",
     "Henyey-Greenstein phase functions (the paper's \"Henyey-Bernstein\", erratum 1) for g = -0.9, -0.6, 0, 0.6, 0.9 "
     "on one pair of axes; polar plot linear (phi / max phi), phi against the angle on a log scale."},
    {"blasi-fig6", "Blasi 1993", "Figure 6", FIG_OVERLAY, "schlick:-0.95 schlick:-0.8 schlick:0 schlick:0.8 schlick:0.95",
     "Schlick phase functions (Eq. 21) for k = -0.95, -0.8, 0, 0.8, 0.95 on one pair of axes; polar plot linear (phi / max phi), phi against the angle on a log scale."},
    {"blasi-fig7", "Blasi 1993", "Figure 7", FIG_BLASI7, "",
     "Figure 7's parameters for the three theoretical functions: each true function (solid), Figure 7's mixture "
     "(orange, dashed) and brume's fit in the angle norm (green, dashed); polar plot linear (phi / max phi), phi against the angle on a log scale. The table below scores both."},
    {"blasi-picture1", "Blasi 1993", "Section 5, picture 1", FIG_RENDER, "blasi-picture1",
     "The 65 x 65 x 10 fractal cloud seen from below and to the side, the sun above it; the paper's variant of the "
     "two-pass method, 2^21 light rays, 400 x 400."},
    {"blasi-picture2", "Blasi 1993", "Section 5, picture 2", FIG_RENDER, "blasi-picture2",
     "The same cloud seen from above on its sunlit side."},
    {"blasi-picture3", "Blasi 1993", "Section 5, picture 3", FIG_RENDER, "blasi-picture3",
     "The same cloud seen edge-on, lit from the side (the sun 102 degrees from the view direction)."},
    {"stam-fig1", "Stam 1994", "Figure 1", FIG_STAM1, "",
     "A random blob rho = mean + sigma Q along a line through its centre: without clamping sigma^2 = eps mean, so the "
     "dense centre is the most perturbed; with clamping sigma^2 = eps min(mean, eta) (Section 4) the perturbation is "
     "bounded where the mean exceeds eta. Drawn as a profile (our choice: the paper shows the blob itself)."},
    {"stam-fig4", "Stam 1994", "Figure 4", FIG_STAM4, "",
     "Variance of the optical depth T_i of one blob against the distance d_i of the ray from its centre, for several "
     "eta: brume's closed form Var T_i = eps sqrt(2 pi) alpha c I_F (lines; docs/stam.md) against the sample variance "
     "over explicit 3-D realizations of the density (points). Without clamping the variance is proportional to the "
     "mean T_i, as the paper notes; clamping flattens it near the centre."},
    {"stam-fig5-a", "Stam 1994", "Figure 5 (top left)", FIG_RENDER, "stam-fig5-a",
     "One cloud of 30 large blobs of peak density 0.6, eps = 0.2, eta = 0.3 (low perturbation, high threshold), 640 x "
     "480. The cloud is thin and lit much brighter than the sky, so that the holes the perturbation cuts show (our "
     "choices, docs/stam.md)."},
    {"stam-fig5-b", "Stam 1994", "Figure 5 (top right)", FIG_RENDER, "stam-fig5-b",
     "eps = 1.6, eta = 0.3: the perturbation cuts holes through the blobs."},
    {"stam-fig5-c", "Stam 1994", "Figure 5 (bottom left)", FIG_RENDER, "stam-fig5-c",
     "eps = 0.2, eta = 0.03: the lower threshold clamps the blobs' variance."},
    {"stam-fig5-d", "Stam 1994", "Figure 5 (bottom right)", FIG_RENDER, "stam-fig5-d",
     "eps = 1.6, eta = 0.03: clamped harder than the top row, the blobs stay whole (9 % relative RMSE against the top "
     "right image over the cloud, docs/stam.md)."},
    {"stam-fig6-shadow", "Stam 1994", "Figure 6 (a)", FIG_RENDER, "stam-fig6-shadow",
     "A self-shadowed cloud and its shadow on the ground."},
    {"stam-fig6-cluster-a", "Stam 1994", "Figure 6 (b)", FIG_RENDER, "stam-fig6-cluster-a",
     "A cluster of 6 clouds from random ellipsoids."},
    {"stam-fig6-cluster-b", "Stam 1994", "Figure 6 (c)", FIG_RENDER, "stam-fig6-cluster-b",
     "A cluster of 12 clouds."},
    {"stam-fig6-city", "Stam 1994", "Figure 6 (d)", FIG_RENDER, "stam-fig6-city",
     "Fog over a city of boxes seen from above: a veil through which the buildings fade with distance (a layer of "
     "1591 blobs thinning with height, weakly perturbed), 640 x 480."},
    {"stam-fig7-t0", "Stam 1994", "Figure 7, t = 0", FIG_RENDER, "stam-fig7-t0",
     "A cloud drifting past a tower: the tower is occluded by the cloud and shadows it."},
    {"stam-fig7-t1", "Stam 1994", "Figure 7, t = 1", FIG_RENDER, "stam-fig7-t1", "The same, one time unit later."},
    {"stam-fig7-t2", "Stam 1994", "Figure 7, t = 2", FIG_RENDER, "stam-fig7-t2", "t = 2."},
    {"stam-fig7-t3", "Stam 1994", "Figure 7, t = 3", FIG_RENDER, "stam-fig7-t3", "t = 3."},
    {"stam-fig8", "Stam 1994", "Figure 8", FIG_RENDER, "stam-fig8",
     "A flame of 14 blobs under a plume of smoke rising from its tip, in a room lit by five point lights inside the "
     "flame: their shadow rays through the perturbed flame and smoke cast random light patterns on the walls and "
     "floor, 640 x 480."},
};
#define NFIG ((int)(sizeof figures / sizeof figures[0]))

const char *figures_caption(const char *name, const char **scene)
{
    for (int i = 0; i < NFIG; i++)
        if (strcmp(figures[i].name, name) == 0) {
            if (scene)
                *scene = figures[i].kind == FIG_RENDER ? figures[i].arg : "";
            return figures[i].caption;
        }
    return NULL;
}

/* Quick mode: one sample, few light rays, few realizations, at a size still worth looking
 * at: QUICK_WIDTH wide, or the scene's own width when it is narrower. */
#define QUICK_WIDTH 256
#define QUICK_LIGHT_RAYS "20000"

/* rs at the quick size and one sample. */
static void quick_settings(brume_render_settings *rs)
{
    if (rs->width > QUICK_WIDTH) {
        rs->height = rs->height * QUICK_WIDTH / rs->width > 0 ? rs->height * QUICK_WIDTH / rs->width : 1;
        rs->width = QUICK_WIDTH;
    }
    rs->spp = 1;
}

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

typedef struct fig_run {
    double seconds;
    char command[1024];
    char extra[2048]; /* more text for the index (Figure 7's table) */
} fig_run;

/* Renders a scene file into path; quick: quick_settings, few light rays. */
static int run_render(const char *scenes, const figure *f, const char *path, bool quick, fig_run *r)
{
    char scene[PATH_MAX];
    snprintf(scene, sizeof scene, "%s/%s.json", scenes, f->arg);
    brume_context *ctx = brume_context_new();
    brume_scene *s = NULL;
    brume_image *img = NULL;
    int rc = 1;
    const char *ov[] = {"blasi.light_rays=" QUICK_LIGHT_RAYS};
    bool blasi = strncmp(f->arg, "blasi", 5) == 0;
    brume_load_options lo = {0.0, 0, ov, quick && blasi ? 1 : 0, NULL, 0, false};
    if (!ctx || brume_scene_load(ctx, &(brume_source){.path = scene}, &lo, &s) != BRUME_OK)
        goto fail;
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    char size[160] = "";
    if (quick) {
        quick_settings(&rs);
        snprintf(size, sizeof size, " --width %d --height %d --spp 1%s", rs.width, rs.height,
                 blasi ? " --set blasi.light_rays=" QUICK_LIGHT_RAYS : "");
    }
    if (brume_scene_set_settings(ctx, s, &rs) != BRUME_OK || brume_scene_commit(ctx, s) != BRUME_OK ||
        brume_render(ctx, s, &img) != BRUME_OK || brume_image_write(ctx, img, path, NULL) != BRUME_OK)
        goto fail;
    snprintf(r->command, sizeof r->command, "brume render scenes/%s.json%s -o %s.png", f->arg, size, f->name);
    rc = 0;
    goto done;
fail:
    cli_error("figures: %s: %s", f->name, ctx ? brume_context_last_error(ctx) : "out of memory");
done:
    brume_image_release(img);
    brume_scene_release(s);
    brume_context_release(ctx);
    return rc;
}

/* Figure 7: the three functions with Figure 7's mixture and brume's fit, and the table. */
static int run_blasi7(const char *path, fig_run *r)
{
    static const char *const names[3] = {"rayleigh", "hazy", "murky"};
    static const double given[3][3] = {{0.50, -0.46, 0.46}, {0.12, -0.50, 0.70}, {0.19, -0.65, 0.91}};
    brume_phase *ph[3][3] = {{0}};
    brume_context *ctx = brume_context_new();
    static char titles[3][160];
    static const char *labels[3][3];
    static const bool dashed[3] = {false, true, true};
    brume_phase_plot_row rows[3];
    int rc = 1;
    size_t used = 0;
    used += (size_t)snprintf(r->extra, sizeof r->extra,
                             "| function | Figure 7: r, k, k' | its error | brume's fit: r, k, k' | its error |\n"
                             "| --- | --- | --- | --- | --- |\n");
    for (int i = 0; i < 3; i++) {
        brume_phase_fit fit;
        if (!ctx || brume_phase_new_named(ctx, names[i], &ph[i][0]) != BRUME_OK ||
            brume_phase_fit_schlick_mix(ctx, ph[i][0], BRUME_PHASE_FIT_ANGLE, &fit) != BRUME_OK)
            goto fail;
        double e7 = brume_phase_fit_error(ph[i][0], BRUME_PHASE_FIT_ANGLE, given[i][0], given[i][1], given[i][2]);
        if (brume_phase_new_schlick_mix(ctx, given[i][0], given[i][1], given[i][2], &ph[i][1]) != BRUME_OK ||
            brume_phase_new_schlick_mix(ctx, fit.r, fit.k, fit.kprime, &ph[i][2]) != BRUME_OK)
            goto fail;
        labels[i][0] = names[i];
        labels[i][1] = "Figure 7";
        labels[i][2] = "brume's fit";
        snprintf(titles[i], sizeof titles[i], "%s: Figure 7 r %.2f k %.2f k' %.2f (error %.4f); ours r %.4f k %.4f "
                 "k' %.4f (error %.4f)", names[i], given[i][0], given[i][1], given[i][2], e7, fit.r, fit.k, fit.kprime,
                 fit.error);
        rows[i] = (brume_phase_plot_row){titles[i], NULL, NULL, 3, (const brume_phase *const *)ph[i], labels[i], dashed};
        if (used < sizeof r->extra)
            used += (size_t)snprintf(r->extra + used, sizeof r->extra - used,
                                     "| %s | %.2f, %.2f, %.2f | %.5f | %.4f, %.4f, %.4f | %.5f |\n", names[i], given[i][0],
                                     given[i][1], given[i][2], e7, fit.r, fit.k, fit.kprime, fit.error);
    }
    if (used < sizeof r->extra)
        snprintf(r->extra + used, sizeof r->extra - used,
                 "\nErrors: the relative L2 norm over the angle (`brume phase fit NAME --given r,k,kprime`, "
                 "docs/phase-functions.md).\n");
    if (brume_phase_plot_png(ctx, path, 3, rows, true) != BRUME_OK)
        goto fail;
    rc = 0;
    goto done;
fail:
    cli_error("figures: blasi-fig7: %s", ctx ? brume_context_last_error(ctx) : "out of memory");
done:
    for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++)
            brume_phase_release(ph[i][k]);
    brume_context_release(ctx);
    return rc;
}

static int run_phase(const figure *f, const char *path, fig_run *r)
{
    char names[256];
    snprintf(names, sizeof names, "%s", f->arg);
    brume_phase *ph[8] = {0};
    const char *labels[8];
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("figures: %s: out of memory", f->name);
        return 1;
    }
    int n = 0, rc = 1;
    brume_phase_plot_row row = {0};
    static char title[1024];
    if (f->kind == FIG_PHASE_FIT) {
        char *sp = strchr(names, ' ');
        *sp = '\0';
        double g[3];
        sscanf(sp + 1, "%lf,%lf,%lf", &g[0], &g[1], &g[2]);
        n = 2;
        if (brume_phase_new_named(ctx, names, &ph[0]) != BRUME_OK ||
            brume_phase_new_schlick_mix(ctx, g[0], g[1], g[2], &ph[1]) != BRUME_OK)
            goto fail;
        snprintf(title, sizeof title, "%s: true (solid), Figure 7's Schlick mixture r %.2f, k %.2f, k' %.2f (dashed), "
                 "error %.4f", names, g[0], g[1], g[2], brume_phase_fit_error(ph[0], BRUME_PHASE_FIT_ANGLE, g[0], g[1], g[2]));
        row = (brume_phase_plot_row){title, ph[0], ph[1], 0, NULL, NULL, NULL};
        snprintf(r->command, sizeof r->command, "brume phase plot %s --given %s%s -o %s.png", names, sp + 1,
                 strcmp(names, "rayleigh") == 0 ? "" : " --log", f->name);
        if (brume_phase_plot_png(ctx, path, 1, &row, strcmp(names, "rayleigh") != 0) != BRUME_OK)
            goto fail;
    } else {
        for (char *tok = strtok(names, " "); tok && n < 8; tok = strtok(NULL, " ")) {
            labels[n] = tok;
            if (brume_phase_new_named(ctx, tok, &ph[n++]) != BRUME_OK)
                goto fail;
        }
        snprintf(title, sizeof title, "%s", f->caption);
        char *dot = strchr(title, ';'); /* the caption up to its first remark */
        if (dot)
            *dot = '\0';
        row = (brume_phase_plot_row){title, NULL, NULL, n, (const brume_phase *const *)ph, labels, NULL};
        snprintf(r->command, sizeof r->command, "brume phase plot %s --overlay --log -o %s.png", f->arg, f->name);
        if (brume_phase_plot_png(ctx, path, 1, &row, true) != BRUME_OK)
            goto fail;
    }
    rc = 0;
    goto done;
fail:
    cli_error("figures: %s: %s", f->name, brume_context_last_error(ctx));
done:
    for (int i = 0; i < n; i++)
        brume_phase_release(ph[i]);
    brume_context_release(ctx);
    return rc;
}

/* --compare: the figure as printed, as corrected and the `path` truth side by side, each
 * method's error over the cloud (the truth's alpha above 0.05, `brume compare --alpha 0.05`)
 * under its picture, into DIR/NAME-compare.png. For blasi: variant paper and physical, the
 * truth `path` on the same grid; for stam: variant paper and corrected, the truth `path` on
 * the explicit realization of the same Q (stam.voxelize). */
#define COMPARE_SPP 64
#define COMPARE_VOXELS "192"
/* Column k of a --compare sheet: the scene with overrides ov, path at COMPARE_SPP for the
 * truth (k 2). 0; 1 on a failure the context explains; -1 after a message. */
static int render_variant(brume_context *ctx, const char *scene, const figure *f, const char *const *ov, int nov, int k,
                          bool quick, brume_image **img)
{
    brume_scene *s = NULL;
    brume_load_options lo = {0.0, 0, ov, nov, NULL, 0, false};
    if (brume_scene_load(ctx, &(brume_source){.path = scene}, &lo, &s) != BRUME_OK)
        return 1;
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    if (k == 0 && rs.method != BRUME_METHOD_BLASI && rs.method != BRUME_METHOD_STAM) {
        brume_scene_release(s);
        cli_error("figures: --compare: %s is rendered by %s, which has no printed and corrected variants", f->name,
                  brume_method_name(rs.method));
        return -1;
    }
    if (quick)
        quick_settings(&rs);
    if (k == 2) {
        rs.method = BRUME_METHOD_PATH;
        rs.spp = quick ? 2 : COMPARE_SPP;
    }
    brume_status st = brume_scene_set_settings(ctx, s, &rs);
    if (st == BRUME_OK)
        st = brume_scene_commit(ctx, s);
    if (st == BRUME_OK)
        st = brume_render(ctx, s, img);
    brume_scene_release(s);
    return st != BRUME_OK;
}

static int run_compare(const char *scenes, const figure *f, const char *dir, bool quick, fig_run *r)
{
    char scene[PATH_MAX], path[PATH_MAX];
    snprintf(scene, sizeof scene, "%s/%s.json", scenes, f->arg);
    snprintf(path, sizeof path, "%s/%s-compare.png", dir, f->name);
    bool blasi = strncmp(f->arg, "blasi", 5) == 0;
    static const char *const cols[3] = {"as printed", "as corrected", "path (the truth)"};
    const char *ov[3][4] = {
        {blasi ? "blasi.variant=paper" : "stam.variant=paper", "blasi.light_rays=" QUICK_LIGHT_RAYS},
        {blasi ? "blasi.variant=physical" : "stam.variant=corrected", "blasi.light_rays=" QUICK_LIGHT_RAYS},
        {"stam.voxelize.resolution=" COMPARE_VOXELS, "stam.voxelize.realization=true"}};
    int nov[3] = {quick && blasi ? 2 : 1, quick && blasi ? 2 : 1, blasi ? 0 : 2};
    if (quick && !blasi)
        ov[2][0] = "stam.voxelize.resolution=48";
    brume_image *img[3] = {NULL, NULL, NULL};
    static char caption[3][160];
    const char *captions[3] = {caption[0], caption[1], caption[2]};
    unsigned char *mask = NULL;
    long count = 0;
    int rc = 1;
    brume_context *ctx = brume_context_new();
    double t0 = now();
    memset(r, 0, sizeof *r);
    for (int k = 0; k < 3 && ctx; k++) {
        int st = render_variant(ctx, scene, f, ov[k], nov[k], k, quick, &img[k]);
        if (st < 0)
            goto done;
        if (st > 0)
            goto fail;
    }
    if (!ctx || brume_image_mask_alpha(ctx, img[2], 0.05, &mask, &count) != BRUME_OK)
        goto fail;
    for (int k = 0; k < 2; k++) {
        brume_region_stats st;
        if (count == 0 || brume_image_compare_region(ctx, img[k], img[2], mask, 0, 1, &st) != BRUME_OK)
            snprintf(caption[k], sizeof caption[k], "no cloud pixel in the truth");
        else
            snprintf(caption[k], sizeof caption[k], "cloud: ratio %.3f, rel RMSE %.3f", st.fig[BRUME_FIG_RATIO],
                     st.fig[BRUME_FIG_REL_RMSE]);
    }
    snprintf(caption[2], sizeof caption[2], "%d spp%s", quick ? 2 : COMPARE_SPP,
             blasi ? "" : ", explicit realization of Q");
    if (brume_image_sheet_png(ctx, path, f->title, 3, 1, (const brume_image *const *)img, cols, NULL, captions, NULL) !=
        BRUME_OK)
        goto fail;
    snprintf(r->command, sizeof r->command, "brume figures --compare --only %s%s -o DIR", f->name,
             quick ? " --quick" : "");
    r->seconds = now() - t0;
    rc = 0;
    goto done;
fail:
    cli_error("figures: %s: %s", f->name, ctx ? brume_context_last_error(ctx) : "out of memory");
done:
    free(mask);
    for (int k = 0; k < 3; k++)
        brume_image_release(img[k]);
    brume_context_release(ctx);
    return rc;
}

static int run_figure(const char *scenes, const char *dir, const figure *f, bool quick, fig_run *r)
{
    char path[PATH_MAX];
    snprintf(path, sizeof path, "%s/%s.png", dir, f->name);
    memset(r, 0, sizeof *r);
    snprintf(r->command, sizeof r->command, "brume figures --only %s%s -o DIR", f->name, quick ? " --quick" : "");
    double t0 = now();
    int rc = 1;
    double z = 0.0;
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("figures: %s: out of memory", f->name);
        return 1;
    }
    switch (f->kind) {
    case FIG_RENDER: rc = run_render(scenes, f, path, quick, r); break;
    case FIG_PHASE_FIT:
    case FIG_OVERLAY: rc = run_phase(f, path, r); break;
    case FIG_BLASI7: rc = run_blasi7(path, r); break;
    case FIG_STAM1:
        rc = brume_stam_figure_png(ctx, 1, path, quick, NULL) == BRUME_OK ? 0 : 1;
        break;
    case FIG_STAM4:
        rc = brume_stam_figure_png(ctx, 4, path, quick, &z) == BRUME_OK ? 0 : 1;
        if (rc == 0)
            snprintf(r->extra, sizeof r->extra,
                     "Largest distance between a sample variance and the closed form: %.2f standard errors of the "
                     "sample variance (the test `stam.transparency_statistics_monte_carlo` checks 5 rays at 5 s.e.).\n",
                     z);
        break;
    }
    if (rc != 0 && (f->kind == FIG_STAM1 || f->kind == FIG_STAM4))
        cli_error("figures: %s: %s", f->name, brume_context_last_error(ctx));
    brume_context_release(ctx);
    r->seconds = now() - t0;
    return rc;
}

/* The markdown and HTML indexes; text is ours (no markup to escape but <, >, &). */
static void html_text(FILE *fp, const char *s)
{
    for (; *s; s++) {
        if (*s == '<')
            fputs("&lt;", fp);
        else if (*s == '>')
            fputs("&gt;", fp);
        else if (*s == '&')
            fputs("&amp;", fp);
        else
            fputc(*s, fp);
    }
}

/* Figure 7's markdown table as HTML rows. */
static void html_table(FILE *fp, const char *md)
{
    fputs("<table>\n", fp);
    int row = 0;
    for (const char *line = md; *line == '|'; row++) {
        const char *end = strchr(line, '\n');
        if (!end)
            break;
        if (row != 1) {
            fputs("<tr>", fp);
            for (const char *c = line + 1; c < end;) {
                const char *bar = memchr(c, '|', (size_t)(end - c));
                if (!bar)
                    break;
                fputs(row == 0 ? "<th>" : "<td>", fp);
                char cell[256];
                snprintf(cell, sizeof cell, "%.*s", (int)(bar - c), c);
                html_text(fp, cell);
                fputs(row == 0 ? "</th>" : "</td>", fp);
                c = bar + 1;
            }
            fputs("</tr>\n", fp);
        }
        line = end + 1;
    }
    fputs("</table>\n", fp);
    const char *after = strstr(md, "\n\n");
    if (after) {
        fputs("<p>", fp);
        html_text(fp, after + 2);
        fputs("</p>\n", fp);
    }
}

static int write_indexes(const char *dir, const fig_run *runs, bool quick, double total)
{
    char *text[2] = {NULL, NULL};
    size_t size[2] = {0, 0};
    FILE *m = open_memstream(&text[0], &size[0]), *h = open_memstream(&text[1], &size[1]);
    if (!m || !h) {
        if (m)
            fclose(m);
        free(text[0]);
        cli_error("figures: out of memory");
        return 1;
    }
    fprintf(m, "# The figures of both papers%s\n\nMade by `brume figures -o DIR%s` (brume %s) in %.1f s. Each figure "
               "is followed by its caption, the command that makes it alone, and the time it took. The papers: "
               "Blasi, Le Saec and Schlick, *A Rendering Algorithm for Discrete Volume Density Objects* "
               "(Eurographics 1993); Stam, *Stochastic Rendering of Density Fields* (Graphics Interface 1994). "
               "Which choices in each scene are the papers' and which are ours: the scene files' comments, "
               "docs/blasi.md and docs/stam.md.\n",
            quick ? " (quick sizes)" : "", quick ? " --quick" : "", brume_version(), total);
    fprintf(h, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>brume: the figures of both "
               "papers</title>\n<style>body{font-family:sans-serif;max-width:980px;margin:auto;padding:1em}"
               "figure{margin:2em 0;border-top:1px solid #ccc;padding-top:1em}img{max-width:100%%}"
               "code{background:#f3f3f3;padding:2px 4px}table{border-collapse:collapse}"
               "td,th{border:1px solid #bbb;padding:2px 8px}.time{color:#666}</style></head><body>\n"
               "<h1>The figures of both papers%s</h1>\n<p>Made by <code>brume figures -o DIR%s</code> (brume %s) in "
               "%.1f s. Each figure is followed by its caption, the command that makes it alone, and the time it "
               "took.</p>\n",
            quick ? " (quick sizes)" : "", quick ? " --quick" : "", brume_version(), total);
    const char *last_paper = "";
    for (int i = 0; i < NFIG; i++) {
        const figure *f = &figures[i];
        if (strcmp(f->paper, last_paper) != 0) {
            fprintf(m, "\n## %s\n", f->paper);
            fprintf(h, "<h2>%s</h2>\n", f->paper);
            last_paper = f->paper;
        }
        fprintf(m, "\n### %s: %s\n\n![%s](%s.png)\n\n%s\n\n", f->paper, f->title, f->name, f->name, f->caption);
        if (runs[i].extra[0])
            fprintf(m, "%s\n", runs[i].extra);
        fprintf(m, "`%s` (%.2f s)\n", runs[i].command, runs[i].seconds);
        fprintf(h, "<figure id=\"%s\"><h3>%s: %s</h3><img src=\"%s.png\" alt=\"%s\">\n<figcaption><p>", f->name,
                f->paper, f->title, f->name, f->name);
        html_text(h, f->caption);
        fputs("</p>\n", h);
        if (runs[i].extra[0]) {
            if (runs[i].extra[0] == '|')
                html_table(h, runs[i].extra);
            else {
                fputs("<p>", h);
                html_text(h, runs[i].extra);
                fputs("</p>\n", h);
            }
        }
        fputs("<p><code>", h);
        html_text(h, runs[i].command);
        fprintf(h, "</code> <span class=\"time\">(%.2f s)</span></p></figcaption></figure>\n", runs[i].seconds);
    }
    fputs("</body></html>\n", h);
    bool closed_m = fclose(m) == 0, closed_h = fclose(h) == 0, written = closed_m && closed_h;
    int rc = 0;
    brume_context *ctx = brume_context_new();
    static const char *const names[2] = {"index.md", "index.html"};
    for (int k = 0; k < 2 && rc == 0; k++) {
        char path[PATH_MAX];
        snprintf(path, sizeof path, "%s/%s", dir, names[k]);
        if (!written || !ctx || brume_file_write(ctx, path, BRUME_FILE_TEXT, text[k], size[k]) != BRUME_OK) {
            cli_error("figures: %s", ctx && written ? brume_context_last_error(ctx) : "out of memory");
            rc = 1;
        }
    }
    brume_context_release(ctx);
    free(text[0]);
    free(text[1]);
    return rc;
}

/* mkdir -p */
static bool make_dirs(const char *dir)
{
    char p[PATH_MAX];
    snprintf(p, sizeof p, "%s", dir);
    for (char *s = p + 1; *s; s++)
        if (*s == '/') {
            *s = '\0';
            if (mkdir(p, 0777) != 0 && errno != EEXIST)
                return false;
            *s = '/';
        }
    return mkdir(p, 0777) == 0 || errno == EEXIST;
}

/* The absolute, resolved form of path, which need not exist yet: its longest existing
 * prefix resolved, the rest appended. */
static bool resolve(const char *path, char *out, size_t n)
{
    char abs[2 * PATH_MAX + 2], r[PATH_MAX], cwd[PATH_MAX];
    if (path[0] == '/')
        cwd[0] = '\0';
    else if (!getcwd(cwd, sizeof cwd))
        return false;
    if (snprintf(abs, sizeof abs, "%s/%s", cwd, path) >= (int)sizeof abs)
        return false;
    for (size_t i = strlen(abs); i > 0; i--) {
        if (abs[i] != '/' && abs[i] != '\0')
            continue;
        char keep = abs[i];
        abs[i] = '\0';
        bool ok = realpath(abs, r) != NULL;
        abs[i] = keep;
        if (ok)
            return snprintf(out, n, "%s%s", r, abs + i) < (int)n;
    }
    return false;
}

/* True when dir lies in the docs/ folder beside the scenes folder (the source tree's). */
static bool inside_docs(const char *scenes, const char *dir)
{
    char docs[PATH_MAX], d[PATH_MAX + 8], rd[PATH_MAX], rdocs[PATH_MAX];
    snprintf(docs, sizeof docs, "%s/../docs", scenes);
    if (!realpath(docs, rdocs) || !resolve(dir, rd, sizeof rd))
        return false;
    size_t n = strlen(rdocs);
    snprintf(d, sizeof d, "%s/", rd);
    return strncmp(d, rdocs, n) == 0 && d[n] == '/';
}

typedef struct figures_opts {
    const char *dir, *only, *scenes;
    bool quick, into_docs, compare;
} figures_opts;

#define OFF(field) offsetof(figures_opts, field)

static const cli_flag figures_flags[] = {
    {"--output", "-o", "DIR", "the folder of the figures and their index (required)", NULL, CLI_FLAG_STRING, OFF(dir),
     0, 0, NULL},
    {"--quick", NULL, NULL, "quick images (256 pixels wide, or the scene's width if narrower;\n"
     "1 sample, 20000 light rays, fewer realizations), for tests", NULL, CLI_FLAG_TRUE, OFF(quick), 0, 0, NULL},
    {"--only", NULL, "NAME", "one figure (its file only, no index); NAME as in the index", NULL, CLI_FLAG_STRING,
     OFF(only), 0, 0, NULL},
    {"--scenes", NULL, "DIR", "the paper scenes (default: ./scenes if present, else the source tree's)", NULL,
     CLI_FLAG_STRING, OFF(scenes), 0, 0, NULL},
    {"--into-docs", NULL, NULL, "allow DIR inside the source tree's docs/ (refused otherwise)", NULL, CLI_FLAG_TRUE,
     OFF(into_docs), 0, 0, NULL},
    {"--compare", NULL, NULL, "instead: each rendered figure of a method with variants (Blasi's pictures,\n"
     "Stam's Figures 5-8) as printed, as corrected and by `path` (the truth; for\n"
     "Stam on the explicit realization of the same Q), side by side with each\n"
     "method's error over the cloud under it: DIR/NAME-compare.png, no index", NULL, CLI_FLAG_TRUE, OFF(compare), 0,
     0, NULL},
};

const cli_command cli_figures_command = {
    "figures", "every figure of both papers into a folder, with index.md and index.html (docs/gallery.md)",
    "-o DIR [options]",
    "Renders every figure of Blasi et al. 1993 (Figures 2-7, pictures 1-3 of Section 5) and\n"
    "Stam 1994 (Figures 1, 4-8) into DIR (created if missing), with DIR/index.md and\n"
    "DIR/index.html: each figure beside its caption, the command that makes it alone and the\n"
    "time it took.\n",
    figures_flags, CLI_NFLAGS(figures_flags), NULL, NULL};

/* The figure --only names (-1: every one), or -2 after the message. */
static int figure_named(const char *only)
{
    if (!only)
        return -1;
    for (int i = 0; i < NFIG; i++)
        if (strcmp(figures[i].name, only) == 0)
            return i;
    char list[1024] = "";
    for (int i = 0; i < NFIG; i++)
        snprintf(list + strlen(list), sizeof list - strlen(list), "%s%s", i ? ", " : "", figures[i].name);
    cli_error("figures: --only: unknown figure '%s' (known: %s)", only, list);
    return -2;
}

/* Renders the figures (every one, or `which`) into dir. The exit status. */
static int render_figures(const figures_opts *o, const char *scenes, int which)
{
    const char *dir = o->dir;
    bool quick = o->quick, compare = o->compare;
    static fig_run runs[NFIG];
    double t0 = now();
    int failed = 0;
    for (int i = 0; i < NFIG; i++) {
        if (which >= 0 && i != which)
            continue;
        if (compare) { /* the figures rendered by a method with variants; --only names one */
            bool variants = figures[i].kind == FIG_RENDER &&
                            (strncmp(figures[i].arg, "blasi", 5) == 0 || strncmp(figures[i].arg, "stam", 4) == 0);
            if (!variants && which < 0)
                continue;
            if (!variants) {
                cli_error("figures: --compare: %s is not a render with printed and corrected variants", figures[i].name);
                return 2;
            }
            if (run_compare(scenes, &figures[i], dir, quick, &runs[i]) != 0)
                return 1;
            fprintf(stderr, "brume: figures: %s/%s-compare.png (%.2f s)\n", dir, figures[i].name, runs[i].seconds);
            continue;
        }
        if (run_figure(scenes, dir, &figures[i], quick, &runs[i]) != 0) {
            failed++;
            continue;
        }
        fprintf(stderr, "brume: figures: %s/%s.png (%.2f s)\n", dir, figures[i].name, runs[i].seconds);
    }
    if (failed)
        return 1;
    if (which >= 0 || compare)
        return 0;
    return write_indexes(dir, runs, quick, now() - t0);
}

int cmd_figures(int argc, char **argv)
{
    figures_opts o = {NULL, NULL, NULL, false, false, false};
    int n = 0, rc = cli_flags_parse(&cli_figures_command, &o, argc, argv, NULL, 0, &n);
    if (rc >= 0)
        return rc;
    const char *dir = o.dir, *scenes = o.scenes;
    if (!dir) {
        cli_error("figures: -o DIR is required (try `brume figures --help`)");
        return 2;
    }
    int which = figure_named(o.only);
    if (which == -2)
        return 2;
    struct stat sb;
    if (!scenes)
        scenes = stat("scenes/blasi-picture1.json", &sb) == 0 ? "scenes" : BRUME_SCENES_DIR;
    char probe[PATH_MAX];
    snprintf(probe, sizeof probe, "%s/blasi-picture1.json", scenes);
    if (stat(probe, &sb) != 0) {
        cli_error("figures: %s: no paper scenes there (give --scenes DIR)", scenes);
        return 1;
    }
    if (!o.into_docs && inside_docs(scenes, dir)) {
        cli_error("figures: %s is inside the source tree's docs/: give --into-docs to write there", dir);
        return 2;
    }
    if (!make_dirs(dir)) {
        cli_error("figures: %s: cannot create: %s", dir, strerror(errno));
        return 1;
    }
    /* before any work: mkdir's EEXIST also means a file there (-o FILE would render every
     * figure, then fail on each) */
    if (stat(dir, &sb) != 0 || !S_ISDIR(sb.st_mode) || access(dir, W_OK | X_OK) != 0) {
        cli_error("figures: -o %s: %s", dir, stat(dir, &sb) == 0 && !S_ISDIR(sb.st_mode) ? "not a folder" : "cannot write there");
        return 1;
    }
    return render_figures(&o, scenes, which);
}
