/* color_body.h - the colour type and its operations over one real type (core/real_names.h),
 * included by core/color.h once for double (color, col_add, ...) and once for float (colorf,
 * col_addf, ...). One definition, two instantiations. */
#include "core/real_names.h"

typedef struct RN(color) {
    R c[BRUME_NSAMPLES];
} RN(color);

static inline RN(color) RN(col)(R v)
{
    RN(color) r;
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        r.c[i] = v;
    return r;
}
static inline RN(color) RN(col_rgb)(R r, R g, R b) { return (RN(color)){{r, g, b}}; }
static inline RN(color) RN(col_add)(RN(color) a, RN(color) b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] += b.c[i];
    return a;
}
static inline RN(color) RN(col_sub)(RN(color) a, RN(color) b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] -= b.c[i];
    return a;
}
static inline RN(color) RN(col_mul)(RN(color) a, RN(color) b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] *= b.c[i];
    return a;
}
static inline RN(color) RN(col_div)(RN(color) a, RN(color) b)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] = b.c[i] != RC(0.0) ? a.c[i] / b.c[i] : RC(0.0);
    return a;
}
static inline RN(color) RN(col_scale)(RN(color) a, R s)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] *= s;
    return a;
}
/* a + b * s */
static inline RN(color) RN(col_madd)(RN(color) a, RN(color) b, R s)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] += b.c[i] * s;
    return a;
}
static inline RN(color) RN(col_exp)(RN(color) a)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        a.c[i] = R_EXP(a.c[i]);
    return a;
}
static inline R RN(col_avg)(RN(color) a)
{
    R s = RC(0.0);
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        s += a.c[i];
    return s / BRUME_NSAMPLES;
}
static inline R RN(col_max)(RN(color) a)
{
    R m = a.c[0];
    for (int i = 1; i < BRUME_NSAMPLES; i++)
        m = a.c[i] > m ? a.c[i] : m;
    return m;
}
static inline R RN(col_min)(RN(color) a)
{
    R m = a.c[0];
    for (int i = 1; i < BRUME_NSAMPLES; i++)
        m = a.c[i] < m ? a.c[i] : m;
    return m;
}
static inline bool RN(col_is_black)(RN(color) a)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        if (a.c[i] != RC(0.0))
            return false;
    return true;
}
static inline bool RN(col_isfinite)(RN(color) a)
{
    for (int i = 0; i < BRUME_NSAMPLES; i++)
        if (!isfinite(a.c[i]))
            return false;
    return true;
}

#include "core/real_names_end.h"
