/* vec_body.h - 3-vectors and rays over one real type (core/real_names.h), included by
 * core/vec.h once for double (vec3, ray, v3_add, ray_at ...) and once for float (vec3f, rayf,
 * v3_addf, ray_atf ...): what the estimator's stages compute with. */
#include "core/real_names.h"

typedef struct RN(vec3) {
    R x, y, z;
} RN(vec3);

/* A ray o + t d. d need not be unit length unless a caller says so; t is in units of |d|. */
typedef struct RN(ray) {
    RN(vec3) o;
    RN(vec3) d;
    R time; /* seconds, inside the camera's shutter interval */
} RN(ray);

static inline RN(vec3) RN(v3)(R x, R y, R z) { return (RN(vec3)){x, y, z}; }
static inline RN(vec3) RN(v3_add)(RN(vec3) a, RN(vec3) b) { return RN(v3)(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline RN(vec3) RN(v3_sub)(RN(vec3) a, RN(vec3) b) { return RN(v3)(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline RN(vec3) RN(v3_mul)(RN(vec3) a, RN(vec3) b) { return RN(v3)(a.x * b.x, a.y * b.y, a.z * b.z); }
static inline RN(vec3) RN(v3_scale)(RN(vec3) a, R s) { return RN(v3)(a.x * s, a.y * s, a.z * s); }
static inline RN(vec3) RN(v3_madd)(RN(vec3) a, RN(vec3) b, R s)
{
    return RN(v3)(a.x + b.x * s, a.y + b.y * s, a.z + b.z * s);
}
static inline RN(vec3) RN(v3_neg)(RN(vec3) a) { return RN(v3)(-a.x, -a.y, -a.z); }
static inline R RN(v3_dot)(RN(vec3) a, RN(vec3) b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline RN(vec3) RN(v3_cross)(RN(vec3) a, RN(vec3) b)
{
    return RN(v3)(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}
static inline R RN(v3_length)(RN(vec3) a) { return R_SQRT(RN(v3_dot)(a, a)); }
static inline RN(vec3) RN(v3_normalize)(RN(vec3) a) { return RN(v3_scale)(a, RC(1.0) / RN(v3_length)(a)); }

static inline RN(vec3) RN(ray_at)(RN(ray) r, R t) { return RN(v3_madd)(r.o, r.d, t); }

#include "core/real_names_end.h"
