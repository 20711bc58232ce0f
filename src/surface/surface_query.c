/* surface_query.c - the solid objects' queries: nearest hit, occlusion, emission and
 * emitter sampling. Compiled for the CPU and, by gpu/kernel.cu, for the GPU: on the CPU
 * the hits come from Embree's scene (surfaces.c); where there is none (the device, and a
 * scene given brume's own hierarchy by surfaces_use_bvh) they come from core/bvh.h, with
 * each primitive intersected in double precision at the ray's time. */
#include "surface/surfaces_impl.h"
#if !defined(__CUDA_ARCH__)
#include "surface/material_hit.h"
#endif

/* ---- brume's own hierarchy -------------------------------------------------------------- */

/* The ray parameter of the nearest hit of the primitive (object o, prim) in (tmin, tmax) at
 * shutter time u, and its unit geometric normal (front side: counter-clockwise, or
 * outward). */
static bool prim_hit(const surface_object *o, int prim, ray r, double u, double tmin, double tmax, double *t, vec3 *ng)
{
    if (o->is_sphere) {
        vec3 center;
        if (!sphere_hit(o, u, r, tmin, tmax, t, &center))
            return false;
        if (ng)
            *ng = v3_normalize(v3_sub(ray_at(r, *t), center));
        return true;
    }
    /* Moller and Trumbore 1997 */
    vec3 a = tri_vertex(o, prim, 0, u), e1 = v3_sub(tri_vertex(o, prim, 1, u), a), e2 = v3_sub(tri_vertex(o, prim, 2, u), a);
    vec3 pv = v3_cross(r.d, e2);
    double det = v3_dot(e1, pv);
    if (det == 0.0 || !isfinite(det))
        return false;
    double inv = 1.0 / det;
    vec3 tv = v3_sub(r.o, a);
    double bu = v3_dot(tv, pv) * inv;
    if (bu < 0.0 || bu > 1.0)
        return false;
    vec3 qv = v3_cross(tv, e1);
    double bv = v3_dot(r.d, qv) * inv;
    if (bv < 0.0 || bu + bv > 1.0)
        return false;
    double th = v3_dot(e2, qv) * inv;
    if (!(th > tmin && th < tmax))
        return false;
    *t = th;
    if (ng)
        *ng = v3_normalize(v3_cross(e1, e2));
    return true;
}

typedef struct bvh_query {
    const surfaces *s;
    ray r;
    double u, tmin;
    int item;    /* the nearest hit's, or -1 */
    vec3 ng;
} bvh_query;

static bool leaf_nearest(void *user, int item, double *tmax)
{
    bvh_query *q = (bvh_query *)user;
    const surface_ref *f = &q->s->ref[item];
    double t;
    vec3 ng;
    if (prim_hit(&q->s->obj[f->object], f->prim, q->r, q->u, q->tmin, *tmax, &t, &ng)) {
        *tmax = t;
        q->item = item;
        q->ng = ng;
    }
    return false;
}

static bool leaf_any(void *user, int item, double *tmax)
{
    bvh_query *q = (bvh_query *)user;
    const surface_ref *f = &q->s->ref[item];
    double t;
    return prim_hit(&q->s->obj[f->object], f->prim, q->r, q->u, q->tmin, *tmax, &t, NULL);
}

#if !defined(__CUDA_ARCH__)
/* (u, v) at the hit: a triangle's vertex coordinates (pbrt-v4's (0, 0), (1, 0), (1, 1) when
 * the mesh has none) weighted by the hit's barycentric coordinates; a sphere's pbrt-v4
 * longitude phi / 2 pi and latitude 1 - theta / pi (theta from +z, in world axes). */
static void hit_uv(const surfaces *s, const surface_object *o, const surface_hit *h, double *u, double *v)
{
    double when = shutter_time(s, h->time);
    if (o->is_sphere) {
        vec3 c;
        double r;
        sphere_at(o, when, &c, &r);
        vec3 d = v3_sub(h->p, c);
        double phi = atan2(d.y, d.x), z = fmax(-1.0, fmin(1.0, d.z / r));
        *u = (phi < 0.0 ? phi + 2.0 * PI : phi) / (2.0 * PI);
        *v = 1.0 - acos(z) / PI;
        return;
    }
    vec3 a = tri_vertex(o, h->prim, 0, when), e1 = v3_sub(tri_vertex(o, h->prim, 1, when), a),
         e2 = v3_sub(tri_vertex(o, h->prim, 2, when), a), ep = v3_sub(h->p, a);
    double d00 = v3_dot(e1, e1), d01 = v3_dot(e1, e2), d11 = v3_dot(e2, e2), d20 = v3_dot(ep, e1), d21 = v3_dot(ep, e2);
    double den = d00 * d11 - d01 * d01;
    double b1 = den > 0.0 ? (d11 * d20 - d01 * d21) / den : 0.0, b2 = den > 0.0 ? (d00 * d21 - d01 * d20) / den : 0.0;
    static const double corner[6] = {0, 0, 1, 0, 1, 1};
    double w[3] = {1.0 - b1 - b2, b1, b2};
    *u = *v = 0.0;
    for (int k = 0; k < 3; k++) {
        const double *t = o->uv ? o->uv + 2 * (size_t)o->idx[3 * h->prim + k] : corner + 2 * k;
        *u += w[k] * t[0];
        *v += w[k] * t[1];
    }
}

/* dp/du, dp/dv at the hit (dp[0], dp[1]) and the front normal's dn/du, dn/dv, as pbrt-v4's
 * shapes give them: a triangle's from its points and (u, v) (a frame about ng where the (u, v)
 * are degenerate), flat (dn 0); a sphere's from its longitude phi = 2 pi u and colatitude
 * theta = pi (1 - v), dn = dp / r. */
static void hit_derivatives(const surfaces *s, const surface_object *o, const surface_hit *h, vec3 dp[2], vec3 dn[2])
{
    double when = shutter_time(s, h->time);
    if (o->is_sphere) {
        vec3 c;
        double r;
        sphere_at(o, when, &c, &r);
        vec3 d = v3_sub(h->p, c);
        double rho = hypot(d.x, d.y), cos_phi = rho > 0.0 ? d.x / rho : 1.0, sin_phi = rho > 0.0 ? d.y / rho : 0.0;
        dp[0] = v3(-2.0 * PI * d.y, 2.0 * PI * d.x, 0.0);
        dp[1] = v3_scale(v3(d.z * cos_phi, d.z * sin_phi, -rho), -PI); /* -r sin(theta) = -rho */
        dn[0] = v3_scale(dp[0], 1.0 / r);
        dn[1] = v3_scale(dp[1], 1.0 / r);
        return;
    }
    static const double corner[6] = {0, 0, 1, 0, 1, 1};
    vec3 p[3];
    const double *t[3];
    for (int k = 0; k < 3; k++) {
        p[k] = tri_vertex(o, h->prim, k, when);
        t[k] = o->uv ? o->uv + 2 * (size_t)o->idx[3 * h->prim + k] : corner + 2 * k;
    }
    double du02 = t[0][0] - t[2][0], dv02 = t[0][1] - t[2][1], du12 = t[1][0] - t[2][0], dv12 = t[1][1] - t[2][1];
    vec3 dp02 = v3_sub(p[0], p[2]), dp12 = v3_sub(p[1], p[2]);
    double det = du02 * dv12 - dv02 * du12;
    dn[0] = dn[1] = v3(0, 0, 0);
    bool degenerate = fabs(det) < 1e-9;
    if (!degenerate) {
        dp[0] = v3_scale(v3_sub(v3_scale(dp02, dv12), v3_scale(dp12, dv02)), 1.0 / det);
        dp[1] = v3_scale(v3_sub(v3_scale(dp12, du02), v3_scale(dp02, du12)), 1.0 / det);
        degenerate = !(v3_length(v3_cross(dp[0], dp[1])) > 0.0);
    }
    if (degenerate) { /* pbrt-v4: any frame about the normal */
        frame f = frame_from_n(h->ng);
        dp[0] = frame_to_world(&f, v3(1, 0, 0));
        dp[1] = frame_to_world(&f, v3(0, 1, 0));
    }
}

/* A textured or mixed object's material at the hit, seen from direction wo, in h->shade
 * (material_hit.h's material_at). */
static void shade_hit(const surfaces *s, surface_hit *h, vec3 wo)
{
    const surface_object *o = &s->obj[h->object];
    if (!material_varies(&o->mat))
        return;
    hit_uv(s, o, h, &h->uv[0], &h->uv[1]);
    material_at(&o->mat, h->p, wo, h->uv[0], h->uv[1], &h->shade);
    h->mat = &h->shade;
    if (h->shade.bump_tex) {
        vec3 dp[2], dn[2];
        hit_derivatives(s, o, h, dp, dn);
        h->ns = material_bump(h->shade.bump_tex, h->uv[0], h->uv[1], dp, dn, h->ng);
    }
}
#endif

bool surfaces_intersect(const surfaces *s, ray r, double tmin, double tmax, surface_hit *h)
{
    if (!s || s->n == 0)
        return false;
#if !defined(__CUDA_ARCH__)
    if (!s->hier.nnodes) {
        bool hit = surfaces_embree_intersect(s, r, tmin, tmax, h);
        if (hit) {
            h->ns = h->ng;
            shade_hit(s, h, v3_neg(r.d));
        }
        return hit;
    }
#endif
    bvh_query q = {s, r, shutter_time(s, r.time), tmin, -1, v3(0, 0, 0)};
    double t = tmax;
    bvh_traverse(&s->hier, r.o, r.d, tmin, &t, leaf_nearest, &q);
    if (q.item < 0)
        return false;
    const surface_ref *f = &s->ref[q.item];
    h->t = t;
    h->p = ray_at(r, t);
    h->ng = q.ng;
    h->ns = q.ng;
    h->object = f->object;
    h->prim = s->obj[f->object].is_sphere ? 0 : f->prim;
    h->mat = &s->obj[f->object].mat;
    h->media = s->obj[f->object].media;
    h->time = r.time;
#if !defined(__CUDA_ARCH__)
    shade_hit(s, h, v3_neg(r.d));
#endif
    return true;
}

bool surfaces_occluded(const surfaces *s, vec3 o, vec3 d, double tmin, double tmax, double time)
{
    if (!s || s->n == 0)
        return false;
#if !defined(__CUDA_ARCH__)
    if (!s->hier.nnodes)
        return surfaces_embree_occluded(s, o, d, tmin, tmax, time);
#endif
    ray r = {o, d, time};
    bvh_query q = {s, r, shutter_time(s, time), tmin, -1, v3(0, 0, 0)};
    double t = tmax;
    return bvh_traverse(&s->hier, o, d, tmin, &t, leaf_any, &q);
}

/* ---- emission and emitters ---------------------------------------------------------------- */

vec3 surface_offset(const surface_hit *h, vec3 d)
{
    double scale = 1e-4 * (1.0 + fmax(fabs(h->p.x), fmax(fabs(h->p.y), fabs(h->p.z))));
    double side = v3_dot(d, h->ng) >= 0.0 ? 1.0 : -1.0;
    return v3_madd(h->p, h->ng, side * scale);
}

bool surfaces_has_emitters(const surfaces *s) { return s && s->nem > 0; }

color surface_emission(const surface_hit *h, vec3 w)
{
    const material *m = h->mat;
    if (col_is_black(m->emission))
        return col(0.0);
    if (v3_dot(w, h->ng) > 0.0 || m->two_sided_emission)
        return m->emission;
    return col(0.0);
}

bool surfaces_sample_emitter(const surfaces *s, vec3 p, double time, double u0, double u1, double u2, vec3 *wi,
                             double *dist, color *Le, double *pdf)
{
    if (!surfaces_has_emitters(s))
        return false;
    double pick;
    int k;
    distrib1_sample(&s->em_dist, u0, &pick, &k);
    const emitter *e = &s->em[k];
    const surface_object *o = &s->obj[e->object];
    double u = shutter_time(s, time);
    vec3 y, n;
    if (o->is_sphere) {
        vec3 center;
        double radius;
        sphere_at(o, u, &center, &radius);
        n = sample_sphere(u1, u2);
        y = v3_madd(center, n, radius);
    } else {
        double su = sqrt(u1), b0 = 1.0 - su, b1 = u2 * su;
        vec3 a = tri_vertex(o, e->prim, 0, u), b = tri_vertex(o, e->prim, 1, u), c = tri_vertex(o, e->prim, 2, u);
        y = v3_add(v3_add(v3_scale(a, b0), v3_scale(b, b1)), v3_scale(c, 1.0 - b0 - b1));
        n = v3_normalize(v3_cross(v3_sub(b, a), v3_sub(c, a)));
    }
    vec3 d = v3_sub(y, p);
    double d2 = v3_dot(d, d);
    if (!(d2 > 0.0))
        return false;
    *dist = sqrt(d2);
    *wi = v3_scale(d, 1.0 / *dist);
    double cos_l = -v3_dot(*wi, n);
    if (cos_l <= 0.0 && !o->mat.two_sided_emission)
        return false;
    cos_l = fabs(cos_l);
    if (cos_l < 1e-12)
        return false;
    /* pick probability (pdf over the unit interval / number of bins) x area pdf -> solid angle */
    double p_pick = pick / s->nem;
    *pdf = p_pick / emitter_area(o, e, u) * d2 / cos_l;
    *Le = o->mat.emission;
    return true;
}

double surfaces_emitter_pdf(const surfaces *s, const surface_hit *h, vec3 p)
{
    if (!surfaces_has_emitters(s) || col_is_black(h->mat->emission))
        return 0.0;
    const surface_object *o = &s->obj[h->object];
    /* emitters are stored object by object, primitives in order */
    if (s->em_first[h->object] < 0)
        return 0.0;
    int k = s->em_first[h->object] + (o->is_sphere ? 0 : h->prim);
    double p_pick = distrib1_pdf(&s->em_dist, (k + 0.5) / s->nem) / s->nem;
    vec3 d = v3_sub(h->p, p);
    double d2 = v3_dot(d, d);
    double cos_l = fabs(v3_dot(v3_normalize(d), h->ng));
    if (cos_l < 1e-12)
        return 0.0;
    return p_pick / emitter_area(o, &s->em[k], shutter_time(s, h->time)) * d2 / cos_l;
}
