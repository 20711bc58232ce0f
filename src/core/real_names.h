/* real_names.h - the names of one instantiation of a body written over a real type: the
 * estimator's hot path (colours, vectors, the majorant walk, the stages) is written once
 * over REAL and compiled in double (the CPU's, the validated reference) and in float (the
 * GPU's single-precision stages: docs/gpu.md, "Single precision"). A body includes this
 * header at its top with REAL_F set to 0 (double) or 1 (float), and real_names_end.h at its
 * end. No include guard: each inclusion defines the names afresh.
 *   R          the real type
 *   RN(name)   the instantiation's name of `name`: name itself in double, name##f in float
 *              (col_add, col_addf; vec3, vec3f), as libm names exp and expf
 *   RC(lit)    a floating literal of type R (1.0, 1.0f), so float code stays float
 *   R_LOG ...  libm's function of that type; R_INF infinity of that type */
#if !defined(REAL_F)
#error "real_names.h: set REAL_F to 0 (double) or 1 (float) before including it"
#endif
#if REAL_F
#define R float
#define RN(name) name##f
#define RC(lit) lit##f
#define R_LOG logf
#define R_EXP expf
#define R_SQRT sqrtf
#define R_FLOOR floorf
#define R_FABS fabsf
#define R_FMIN fminf
#define R_FMAX fmaxf
#define R_NEXTAFTER nextafterf
#define R_INF __builtin_inff()
#define R_ONE_BELOW 0x1.fffffep-1f
#else
#define R double
#define RN(name) name
#define RC(lit) lit
#define R_LOG log
#define R_EXP exp
#define R_SQRT sqrt
#define R_FLOOR floor
#define R_FABS fabs
#define R_FMIN fmin
#define R_FMAX fmax
#define R_NEXTAFTER nextafter
#define R_INF INFINITY
#define R_ONE_BELOW 0x1.fffffffffffffp-1
#endif
