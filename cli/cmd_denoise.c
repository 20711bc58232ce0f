/* cmd_denoise.c - `brume denoise IN.exr -o OUT.exr`: the library's denoiser (brume_denoise,
 * docs/denoise.md) on an image that `brume render --aov variance,...` wrote. */
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "args.h"
#include "cli_flags.h"
#include "brume.h"
#include "cli_job.h"
#include "commands.h"

typedef struct denoise_opts {
    const char *out;
    int threads;
    brume_write_options wopts;
} denoise_opts;

static bool flag_filmic(void *opts, const cli_flag *f, const char *v)
{
    (void)f, (void)v;
    ((denoise_opts *)opts)->wopts.tonemap = BRUME_TONEMAP_FILMIC;
    return true;
}

static const cli_flag denoise_flags[] = {
    {"--output", "-o", "OUT", "the denoised image: .exr (every layer kept) or .png", NULL, CLI_FLAG_STRING,
     offsetof(denoise_opts, out), 0, 0, NULL},
    {"--threads", NULL, "N", "worker threads (default: one per core); the result does not depend on it",
     "settings.threads", CLI_FLAG_INT, offsetof(denoise_opts, threads), 0, 1024, NULL},
    {"--exposure", NULL, "STOPS", "PNG only: scale by 2^STOPS before tone mapping", NULL, CLI_FLAG_DOUBLE,
     offsetof(denoise_opts, wopts.exposure), -64.0, 64.0, NULL},
    {"--filmic", NULL, NULL, "PNG only: ACES filmic tone curve instead of clamping", NULL, CLI_FLAG_CALL, 0, 0, 0,
     flag_filmic},
};

const cli_command cli_denoise_command = {
    "denoise", "filter a rendered EXR with its variance and feature layers (docs/denoise.md)",
    "IN.exr -o OUT.exr|OUT.png [options]",
    "Filters IN (an EXR from `brume render --aov variance[,albedo,normal,depth]` or --denoise\n"
    "without denoising) with brume's variance-guided a-trous filter (docs/denoise.md). OUT.exr\n"
    "keeps every layer, the unfiltered image in the layer \"raw\", and is marked by the\n"
    "attribute brume.denoised. The result does not depend on --threads. A denoised image is\n"
    "biased: never a validation result.\n",
    denoise_flags, CLI_NFLAGS(denoise_flags),
    "SIGINT (Ctrl-C), SIGTERM or SIGHUP stop the denoiser within a row of pixels: nothing is\n"
    "written and brume exits 130, 143 or 129; during the write the image is written whole.\n",
    NULL};

int cmd_denoise(int argc, char **argv)
{
    denoise_opts o = {NULL, 0, {0.0, BRUME_TONEMAP_CLAMP}};
    const char *in = NULL;
    int n = 0, rc = cli_flags_parse(&cli_denoise_command, &o, argc, argv, &in, 1, &n);
    if (rc >= 0)
        return rc;
    const char *out = o.out;
    int threads = o.threads;
    brume_write_options wopts = o.wopts;
    if (!in || !out) {
        cli_error("denoise: need IN.exr and -o OUT (try `brume help denoise`)");
        return 2;
    }
    int bad = cli_check_image_name("-o", out, false);
    if (bad)
        return bad;
    /* the output never replaces the input image, a device or a folder */
    if (cli_check_output("-o", out, BRUME_FILE_IMAGE, NULL, NULL, &in, 1) != 0 || cli_prepare_folder("-o", out, true) != 0)
        return 1;
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    brume_image *img = NULL, *den = NULL;
    rc = 1;
    cli_signals_install();
    if (brume_image_read(ctx, in, &img) != BRUME_OK)
        goto fail;
    cli_signals_cancel(ctx); /* a signal cancels the denoiser; the write that follows is whole */
    cli_signals_keep(true);
    if (brume_denoise(ctx, img, threads, &den) != BRUME_OK) {
        if (cli_signal()) {
            fprintf(stderr, "brume: interrupted by %s while denoising %s: nothing written\n",
                    cli_signal_name(cli_signal()), in);
            rc = 128 + cli_signal();
        } else
            cli_error("%s: %.1000s", in, brume_context_last_error(ctx));
        goto done;
    }
    if (brume_image_write(ctx, den, out, &wopts) != BRUME_OK)
        goto fail;
    rc = 0;
    goto done;
fail:
    cli_error("%.1000s", brume_context_last_error(ctx));
done:
    cli_signals_keep(false);
    cli_signals_cancel(NULL);
    brume_image_release(den);
    brume_image_release(img);
    brume_context_release(ctx);
    return rc;
}
