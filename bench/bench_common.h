/* bench_common.h - what every benchmark prints and computes the same way: the machine
 * (cores, CPU model, load average at the start) and medians of repeated runs. */
#ifndef BRUME_BENCH_COMMON_H
#define BRUME_BENCH_COMMON_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"

/* "machine: N x MODEL, load L1 L5 L15" from /proc. */
static inline void bench_machine(void)
{
    FILE *fp = fopen("/proc/cpuinfo", "r");
    char line[512], model[256] = "unknown";
    int cpus = 0;
    while (fp && fgets(line, sizeof line, fp)) {
        if (strncmp(line, "model name", 10) == 0) {
            char *c = strchr(line, ':');
            if (c) {
                snprintf(model, sizeof model, "%s", c + 2);
                model[strcspn(model, "\n")] = '\0';
            }
            cpus++;
        }
    }
    if (fp)
        fclose(fp);
    double load[3] = {0, 0, 0};
    fp = fopen("/proc/loadavg", "r");
    if (fp) {
        if (fscanf(fp, "%lf %lf %lf", &load[0], &load[1], &load[2]) != 3)
            load[0] = load[1] = load[2] = -1.0;
        fclose(fp);
    }
    printf("machine: %d x %s, load average %.2f %.2f %.2f\n", cpus, model, load[0], load[1], load[2]);
}

static inline int bench_cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorts v and returns its median (the upper one for even n). */
static inline double bench_median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, bench_cmp_double);
    return v[n / 2];
}

/* The relative RMSE of an image of spp samples, from m, its relative RMSE measured against a
 * reference of ref_spp samples rendered with another seed: the two noises are independent,
 * so m^2 = e^2 + e^2 spp / ref_spp and e = m / sqrt(1 + spp / ref_spp) (docs/performance.md,
 * "The error's noise"). */
static inline double bench_error_without_reference(double m, int spp, int ref_spp)
{
    return m / sqrt(1.0 + (double)spp / ref_spp);
}

/* The index of img's layer `name` (an AOV: "variance", "depth" ...), or -1. */
static inline int bench_layer(const brume_image *img, const char *name)
{
    for (int i = 0; i < brume_image_layer_count(img); i++)
        if (strcmp(brume_image_layer_name(img, i), name) == 0)
            return i;
    return -1;
}

#endif
