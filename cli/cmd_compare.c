/* cmd_compare.c - `brume compare IMAGE REFERENCE`: error figures and a difference picture. */
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "commands.h"
#include "core/error.h"
#include "io/compare.h"

int cmd_compare(int argc, char **argv)
{
    const char *paths[2] = {NULL, NULL}, *diff = NULL;
    double scale = 0.5;
    int np = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i], *v;
        if (strcmp(a, "-h") == 0 || strcmp(a, "--help") == 0) {
            printf("usage: brume compare IMAGE REFERENCE [-o DIFF.png] [--scale S]\n"
                   "Prints rmse, rel_rmse (rmse / mean reference), mean_rel and max_rel (relative\n"
                   "luminance differences over pixels brighter than 1%% of the mean), one per line.\n"
                   "-o writes a false-colour difference picture: red brighter, blue darker than the\n"
                   "reference, saturating at a relative difference of S (default 0.5).\n");
            return 0;
        } else if (strcmp(a, "-o") == 0) {
            if (!(diff = arg_value(argc, argv, &i))) return 2;
        } else if (strcmp(a, "--scale") == 0) {
            if (!(v = arg_value(argc, argv, &i)) || !arg_double(a, v, 1e-6, 1e6, &scale)) return 2;
        } else if (np < 2 && (a[0] != '-' || a[1] == '\0')) {
            paths[np++] = a;
        } else {
            cli_error("compare: unexpected argument '%s'", a);
            return 2;
        }
    }
    if (np != 2) {
        cli_error("compare: need IMAGE and REFERENCE (try `brume help compare`)");
        return 2;
    }
    brume_context *ctx = brume_context_new();
    brume_image *img = NULL, *ref = NULL, *pic = NULL;
    int rc = 1;
    image_diff_stats st;
    if (brume_image_read(ctx, paths[0], &img) != BRUME_OK || brume_image_read(ctx, paths[1], &ref) != BRUME_OK) {
        cli_error("%.1000s", brume_context_last_error(ctx));
        goto done;
    }
    if (image_compare(img, ref, &st) != BRUME_OK) {
        cli_error("%s: %.1000s", paths[0], err_message());
        goto done;
    }
    printf("rmse %.6g\nrel_rmse %.6g\nmean_rel %.6g\nmax_rel %.6g\nmean %.6g\nmean_ref %.6g\n", st.rmse, st.rel_rmse,
           st.mean_rel, st.max_rel, st.mean_img, st.mean_ref);
    if (diff) {
        if (image_diff_picture(img, ref, scale, &pic) != BRUME_OK) {
            cli_error("%.1000s", err_message());
            goto done;
        }
        if (brume_image_write(ctx, pic, diff, NULL) != BRUME_OK) {
            cli_error("%.1000s", brume_context_last_error(ctx));
            goto done;
        }
    }
    rc = 0;
done:
    brume_image_release(img);
    brume_image_release(ref);
    brume_image_release(pic);
    brume_context_release(ctx);
    return rc;
}
