/* stam_profiles.h - radial kernel profiles the stam tests write (test_stam*.c): a profile
 * file of n + 1 rows, and the gaussian and cone profiles. */
#ifndef BRUME_TEST_STAM_PROFILES_H
#define BRUME_TEST_STAM_PROFILES_H

#include "test.h"

/* Writes n + 1 rows "k ds  w(k ds)" of a profile to a temporary file. */
static inline const char *write_profile(const char *name, double (*w)(double), int n, double ds)
{
    const char *path = test_tmp_path(name);
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f);
    fprintf(f, "# r/h  W\n");
    for (int k = 0; k <= n; k++)
        fprintf(f, "%.17g %.17g\n", k * ds, w(k * ds));
    fclose(f);
    return path;
}

static inline double gaussian(double s) { return exp(-0.5 * s * s); }
static inline double cone(double s) { return 1.0 - s / 2.0; } /* on [0, 2] */

#endif
