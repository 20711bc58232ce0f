/* bench_phase.c - eval and sample throughput of every phase function, and ratios to HG.
 *
 * Blasi et al. claim Schlick's function is much cheaper than Henyey-Greenstein's. This
 * measures, on one thread, millions of calls per second of phase_eval, phase_sample_cos
 * (the inversion alone) and phase_sample (inversion plus the frame around wi), the median
 * of RUNS runs over N precomputed inputs, and prints each rate relative to HG's in the same
 * process. The rows "inline formula" time the bare expressions of Eq. 19 and Eq. 21 in a
 * loop the compiler can see, without the call and the switch of phase_eval.
 *
 * Build: cmake --build build --target bench; run: build/bench/bench_phase */
#include "bench_common.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/progress.h"
#include "core/rng.h"
#include "phase/phase.h"

#define N 2000000
#define RUNS 7

static double *cosines, *u1s, *u2s;
static volatile double sink; /* keeps results alive */

typedef enum bench_op { OP_EVAL, OP_SAMPLE_COS, OP_SAMPLE } bench_op;

/* Millions of operations per second, median of RUNS. */
static double rate(const phase *p, bench_op op)
{
    double t[RUNS];
    vec3 wi = v3_normalize(v3(0.3, -0.5, 0.8));
    for (int run = 0; run < RUNS; run++) {
        double acc = 0.0, t0 = progress_now();
        switch (op) {
        case OP_EVAL:
            for (int i = 0; i < N; i++)
                acc += phase_eval(p, cosines[i]);
            break;
        case OP_SAMPLE_COS:
            for (int i = 0; i < N; i++)
                acc += phase_sample_cos(p, u1s[i]);
            break;
        case OP_SAMPLE:
            for (int i = 0; i < N; i++) {
                double pdf;
                vec3 wo = phase_sample(p, wi, u1s[i], u2s[i], &pdf);
                acc += wo.x + pdf;
            }
            break;
        }
        t[run] = progress_now() - t0;
        sink = acc;
    }
    return N / bench_median(t, RUNS) * 1e-6;
}

/* The bare formulas, g = 0.7 and the matching k, for comparison with the calls. */
static void inline_rates(double g, double k, double *hg_rate, double *schlick_rate)
{
    double th[RUNS], ts[RUNS];
    double c_hg = (1.0 - g * g) / (4.0 * PI), a = 1.0 + g * g, b = 2.0 * g;
    double c_s = (1.0 - k * k) / (4.0 * PI);
    for (int run = 0; run < RUNS; run++) {
        double acc = 0.0, t0 = progress_now();
        for (int i = 0; i < N; i++) {
            double d = a - b * cosines[i];
            acc += c_hg / (d * sqrt(d)); /* Blasi Eq. 19 */
        }
        th[run] = progress_now() - t0;
        sink = acc;
        acc = 0.0;
        t0 = progress_now();
        for (int i = 0; i < N; i++) {
            double d = 1.0 - k * cosines[i];
            acc += c_s / (d * d); /* Blasi Eq. 21 */
        }
        ts[run] = progress_now() - t0;
        sink = acc;
    }
    *hg_rate = N / bench_median(th, RUNS) * 1e-6;
    *schlick_rate = N / bench_median(ts, RUNS) * 1e-6;
}

int main(void)
{
    cosines = malloc(N * sizeof *cosines);
    u1s = malloc(N * sizeof *u1s);
    u2s = malloc(N * sizeof *u2s);
    if (!cosines || !u1s || !u2s)
        return 1;
    rng r = rng_make(1, 0, 0);
    for (int i = 0; i < N; i++) {
        cosines[i] = 2.0 * rng_next(&r) - 1.0;
        u1s[i] = rng_next(&r);
        u2s[i] = rng_next(&r);
    }
    bench_machine();

    const double g = 0.7, k = phase_schlick_k_from_g(g);
    char schlick_name[32], table_note[] = "tabulated (181 nodes, 1 degree)";
    snprintf(schlick_name, sizeof schlick_name, "schlick k=%.4f", k);
    double ang[181], val[181];
    for (int i = 0; i <= 180; i++) { /* a smooth forward-peaked table */
        ang[i] = i;
        val[i] = 0.5 + 16.5 * pow(0.5 * (1.0 + cos(i * PI / 180.0)), 32.0);
    }
    phase *lobes[2] = {phase_new_schlick(-0.381), phase_new_schlick(0.918)};
    const double w[2] = {0.252, 0.748};
    struct {
        const char *name;
        phase *p;
    } fns[] = {
        {"henyey-greenstein g=0.7", phase_new_hg(g)},
        {schlick_name, phase_new_schlick(k)},
        {"isotropic", phase_new_isotropic()},
        {"rayleigh", phase_new_rayleigh()},
        {"mie hazy", phase_new_mie_hazy()},
        {"mie murky", phase_new_mie_murky()},
        {"schlick mixture (murky fit)", phase_new_mixture(2, w, lobes)},
        {table_note, phase_new_tabulated(181, ang, val)},
    };
    int nf = (int)(sizeof fns / sizeof fns[0]);
    for (int i = 0; i < nf; i++)
        if (!fns[i].p) {
            fprintf(stderr, "bench_phase: cannot build %s\n", fns[i].name);
            return 1;
        }

    double base[3] = {0.0, 0.0, 0.0};
    printf("%-32s %9s %6s %11s %6s %9s %6s\n", "function", "eval", "/HG", "sample_cos", "/HG", "sample", "/HG");
    for (int i = 0; i < nf; i++) {
        double e = rate(fns[i].p, OP_EVAL), sc = rate(fns[i].p, OP_SAMPLE_COS), s = rate(fns[i].p, OP_SAMPLE);
        if (i == 0) {
            base[0] = e;
            base[1] = sc;
            base[2] = s;
        }
        printf("%-32s %9.1f %6.2f %11.1f %6.2f %9.1f %6.2f\n", fns[i].name, e, e / base[0], sc, sc / base[1], s,
               s / base[2]);
    }
    double hg_inline, schlick_inline;
    inline_rates(g, k, &hg_inline, &schlick_inline);
    printf("\ninline formula, HG Eq. 19      %9.1f   1.00\n", hg_inline);
    printf("inline formula, Schlick Eq. 21 %9.1f %6.2f\n", schlick_inline, schlick_inline / hg_inline);

    for (int i = 0; i < nf; i++)
        phase_release(fns[i].p);
    free(cosines);
    free(u1s);
    free(u2s);
    return 0;
}
