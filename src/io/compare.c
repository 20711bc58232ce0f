/* compare.c - error figures between an image and a reference, and difference pictures. */
#include "io/compare.h"

#include <math.h>
#include <stddef.h>

#include "core/error.h"
#include "io/image.h"

static double lum(const float *p) { return 0.2126 * (double)p[0] + 0.7152 * (double)p[1] + 0.0722 * (double)p[2]; }

brume_status image_compare(const brume_image *img, const brume_image *ref, image_diff_stats *o)
{
    if (img->width != ref->width || img->height != ref->height)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "compare: image is %d x %d but the reference is %d x %d",
                       img->width, img->height, ref->width, ref->height);
    long n = (long)img->width * img->height;
    double se = 0.0, sr = 0.0, si = 0.0, slum = 0.0;
    for (long i = 0; i < n; i++) {
        const float *a = img->rgba + 4 * i, *b = ref->rgba + 4 * i;
        for (int c = 0; c < 3; c++) {
            double d = (double)a[c] - (double)b[c];
            se += d * d;
            sr += (double)b[c];
            si += (double)a[c];
        }
        slum += lum(b);
    }
    o->pixels = n;
    o->rmse = sqrt(se / (3.0 * (double)n));
    o->mean_ref = sr / (3.0 * (double)n);
    o->mean_img = si / (3.0 * (double)n);
    o->rel_rmse = o->mean_ref > 0.0 ? o->rmse / o->mean_ref : HUGE_VAL;
    o->floor = 0.01 * slum / (double)n;
    double srel = 0.0, mrel = 0.0;
    long m = 0;
    for (long i = 0; i < n; i++) {
        double lr = lum(ref->rgba + 4 * i);
        if (lr <= o->floor)
            continue;
        double r = fabs(lum(img->rgba + 4 * i) - lr) / lr;
        srel += r;
        mrel = fmax(mrel, r);
        m++;
    }
    o->mean_rel = m ? srel / (double)m : 0.0;
    o->max_rel = mrel;
    return BRUME_OK;
}

brume_status image_diff_picture(const brume_image *img, const brume_image *ref, double scale, brume_image **out)
{
    *out = NULL;
    image_diff_stats st;
    brume_status s = image_compare(img, ref, &st);
    if (s)
        return s;
    brume_image *d = brume_image_new(img->width, img->height);
    if (!d)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "compare: out of memory");
    long n = (long)img->width * img->height;
    for (long i = 0; i < n; i++) {
        double lr = lum(ref->rgba + 4 * i), la = lum(img->rgba + 4 * i);
        double r = (la - lr) / fmax(lr, st.floor);
        double t = fmin(1.0, fabs(r) / scale);
        float *p = d->rgba + 4 * i;
        /* black at 0, towards red (brighter) or blue (darker), white at the scale */
        double hot = t, warm = t * t;
        p[0] = (float)(r > 0 ? hot : warm);
        p[1] = (float)warm;
        p[2] = (float)(r > 0 ? warm : hot);
        p[3] = 1.0f;
    }
    *out = d;
    return BRUME_OK;
}
