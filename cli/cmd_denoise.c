/* cmd_denoise.c - `brume denoise IN.exr -o OUT.exr`: the library's denoiser (brume_denoise,
 * docs/denoise.md) on an image that `brume render --aov variance,...` wrote. */
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "brume.h"
#include "cli_job.h"
#include "commands.h"

int cmd_denoise(int argc, char **argv)
{
    const char *in = NULL, *out = NULL;
    int threads = 0;
    brume_write_options wopts = {0.0, BRUME_TONEMAP_CLAMP};
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            printf("usage: brume denoise IN.exr -o OUT.exr|OUT.png [--threads N] [--exposure STOPS] [--filmic]\n"
                   "Filters IN (an EXR from `brume render --aov variance[,albedo,normal,depth]` or --denoise\n"
                   "without denoising) with brume's variance-guided a-trous filter (docs/denoise.md). OUT.exr\n"
                   "keeps every layer, the unfiltered image in the layer \"raw\", and is marked by the\n"
                   "attribute brume.denoised. The result does not depend on --threads. A denoised image is\n"
                   "biased: never a validation result.\n");
            return 0;
        } else if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
            if (!(out = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--threads") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_int(a, v, 0, 1024, &threads)) return 2;
        } else if (strcmp(a, "--exposure") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, -64.0, 64.0, &wopts.exposure)) return 2;
        } else if (strcmp(a, "--filmic") == 0) {
            wopts.tonemap = BRUME_TONEMAP_FILMIC;
        } else if (!in && (a[0] != '-' || a[1] == '\0')) {
            in = a;
        } else {
            cli_error("denoise: unexpected argument '%s' (try `brume help denoise`)", a);
            return 2;
        }
    }
    if (!in || !out) {
        cli_error("denoise: need IN.exr and -o OUT (try `brume help denoise`)");
        return 2;
    }
    int bad = cli_check_image_name("-o", out, false);
    if (bad)
        return bad;
    /* the output never replaces the input image, a device or a folder */
    if (cli_check_output("-o", out, in, NULL) != 0 || cli_prepare_folder("-o", out, true) != 0)
        return 1;
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("out of memory");
        return 1;
    }
    brume_image *img = NULL, *den = NULL;
    int rc = 1;
    if (brume_image_read(ctx, in, &img) != BRUME_OK)
        goto fail;
    if (brume_denoise(ctx, img, threads, &den) != BRUME_OK) {
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
    brume_image_release(den);
    brume_image_release(img);
    brume_context_release(ctx);
    return rc;
}
