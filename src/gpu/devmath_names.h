/* devmath_names.h - libm's names on the device, for the GPU's translation units
 * (gpu/kernel.cu, gpu/stages.cu): each name calls gpu/devmath.h's function (tested in ulps
 * against glibc on the CPU) or clang's builtin. Included inside the units' anonymous
 * namespace and `#pragma clang force_cuda_host_device`, where the names hide the host's
 * declarations. */
#ifndef BRUME_GPU_DEVMATH_NAMES_H
#define BRUME_GPU_DEVMATH_NAMES_H

#include "gpu/devmath.h"

/* libm's names on the device; they hide the host's declarations inside this namespace */
static inline double exp(double x) { return devmath_exp(x); }
static inline double log(double x) { return devmath_log(x); }
static inline double pow(double x, double y) { return devmath_pow(x, y); }
static inline double sin(double x) { return devmath_sin(x); }
static inline double cos(double x) { return devmath_cos(x); }
static inline double acos(double x) { return devmath_acos(x); }
static inline double atan2(double y, double x) { return devmath_atan2(y, x); }
static inline double cbrt(double x) { return devmath_cbrt(x); }
static inline double tan(double x) { return devmath_tan(x); }
static inline double log1p(double x) { return devmath_log1p(x); }
static inline double nextafter(double x, double y) { return devmath_nextafter(x, y); }
static inline double sqrt(double x) { return __builtin_sqrt(x); }
static inline double fabs(double x) { return __builtin_fabs(x); }
static inline double floor(double x) { return __builtin_floor(x); }
static inline double fmin(double a, double b) { return __builtin_fmin(a, b); }
static inline double fmax(double a, double b) { return __builtin_fmax(a, b); }
static inline double copysign(double a, double b) { return __builtin_copysign(a, b); }
/* the float names, for single-precision stages (gpu/devmath.h) */
static inline float expf(float x) { return devmath_expf(x); }
static inline float logf(float x) { return devmath_logf(x); }
static inline float powf(float x, float y) { return devmath_powf(x, y); }
static inline float sinf(float x) { return devmath_sinf(x); }
static inline float cosf(float x) { return devmath_cosf(x); }
static inline float tanf(float x) { return devmath_tanf(x); }
static inline float acosf(float x) { return devmath_acosf(x); }
static inline float atan2f(float y, float x) { return devmath_atan2f(y, x); }
static inline float cbrtf(float x) { return devmath_cbrtf(x); }
static inline float log1pf(float x) { return devmath_log1pf(x); }
static inline float nextafterf(float x, float y) { return devmath_nextafterf(x, y); }
static inline float sqrtf(float x) { return __builtin_sqrtf(x); }
static inline float fabsf(float x) { return __builtin_fabsf(x); }
static inline float floorf(float x) { return __builtin_floorf(x); }
static inline float fminf(float a, float b) { return __builtin_fminf(a, b); }
static inline float fmaxf(float a, float b) { return __builtin_fmaxf(a, b); }
static inline float copysignf(float a, float b) { return __builtin_copysignf(a, b); }
static inline void *memcpy(void *d, const void *s, size_t n) { return __builtin_memcpy(d, s, n); }
static inline void *memset(void *d, int c, size_t n) { return __builtin_memset(d, c, n); }

#endif
