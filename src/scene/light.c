/* light.c - light sampling: delta lights, the sun disk, sphere and disk area lights. */
#include "scene/light.h"

#include "core/sampling.h"

void light_init(light *l)
{
    switch (l->kind) {
    case LIGHT_DISTANT:
        /* Below LIGHT_SUN_POINT_RADIUS the disk is the point sun it tends to: its cone
         * would be narrower than doubles resolve cosines near 1 (1 - cos underflows to 0
         * near 1e-8 rad and the sun would vanish), and no picture can tell them apart. */
        if (l->angular_radius < LIGHT_SUN_POINT_RADIUS)
            l->angular_radius = 0.0;
        l->cos_max = cos(l->angular_radius);
        l->f = frame_from_n(v3_neg(l->direction)); /* around the direction towards the sun */
        break;
    case LIGHT_SPOT:
    case LIGHT_DISK:
        l->f = frame_from_n(l->direction);
        break;
    case LIGHT_POINT:
    case LIGHT_SPHERE:
        break;
    }
}

bool light_is_area(const light *l)
{
    return l->kind == LIGHT_SPHERE || l->kind == LIGHT_DISK || (l->kind == LIGHT_DISTANT && l->angular_radius > 0.0);
}

/* Goniometric factor of a spot at cosine cos_t from its axis. */
static double spot_factor(const light *l, double cos_t)
{
    if (l->profile_n > 0) {
        double a = acos(fmin(1.0, fmax(-1.0, cos_t))) * 180.0 / PI;
        if (a <= l->profile_angle[0])
            return l->profile_value[0];
        for (int i = 1; i < l->profile_n; i++)
            if (a <= l->profile_angle[i]) {
                double s = (a - l->profile_angle[i - 1]) / (l->profile_angle[i] - l->profile_angle[i - 1]);
                return l->profile_value[i - 1] + s * (l->profile_value[i] - l->profile_value[i - 1]);
            }
        return l->profile_value[l->profile_n - 1];
    }
    if (cos_t >= l->cos_inner)
        return 1.0;
    if (cos_t <= l->cos_outer)
        return 0.0;
    double s = (cos_t - l->cos_outer) / (l->cos_inner - l->cos_outer);
    return s * s * (3.0 - 2.0 * s);
}

/* Sun disk radiance from its irradiance: E = L pi sin^2(angular radius). */
static color sun_radiance(const light *l)
{
    double s = sin(l->angular_radius);
    return col_scale(l->L, 1.0 / (PI * s * s));
}

static bool sphere_hit(vec3 c, double radius, vec3 p, vec3 wi, double *dist)
{
    vec3 oc = v3_sub(p, c);
    double b = v3_dot(oc, wi), cc = v3_dot(oc, oc) - radius * radius;
    double disc = b * b - cc;
    if (disc < 0.0)
        return false;
    double sq = sqrt(disc), t = -b - sq;
    if (t <= 0.0)
        t = -b + sq;
    if (t <= 0.0)
        return false;
    *dist = t;
    return true;
}

bool light_sample_at(const light *l, vec3 p, double u1, double u2, light_sample *ls)
{
    ls->delta = false;
    switch (l->kind) {
    case LIGHT_DISTANT:
        if (l->angular_radius <= 0.0) {
            ls->wi = v3_neg(l->direction);
            ls->dist = INFINITY;
            ls->Li = l->L;
            ls->pdf = 1.0;
            ls->delta = true;
            return true;
        }
        ls->wi = frame_to_world(&l->f, sample_cone(u1, u2, l->cos_max));
        ls->dist = INFINITY;
        ls->Li = sun_radiance(l);
        ls->pdf = sample_cone_pdf(l->cos_max);
        return true;
    case LIGHT_POINT:
    case LIGHT_SPOT: {
        vec3 d = v3_sub(l->position, p);
        double r2 = v3_dot(d, d);
        if (!(r2 > 0.0))
            return false;
        ls->dist = sqrt(r2);
        ls->wi = v3_scale(d, 1.0 / ls->dist);
        double factor = l->kind == LIGHT_SPOT ? spot_factor(l, v3_dot(v3_neg(ls->wi), l->direction)) : 1.0;
        if (factor <= 0.0)
            return false;
        ls->Li = col_scale(l->L, factor / r2);
        ls->pdf = 1.0;
        ls->delta = true;
        return true;
    }
    case LIGHT_SPHERE: {
        vec3 d = v3_sub(l->position, p);
        double dc2 = v3_dot(d, d), r2 = l->radius * l->radius;
        if (dc2 <= r2 * (1.0 + 1e-9)) /* inside: the sphere emits outward only */
            return false;
        double dc = sqrt(dc2);
        double cos_max = sqrt(fmax(0.0, 1.0 - r2 / dc2));
        frame f = frame_from_n(v3_scale(d, 1.0 / dc));
        ls->wi = frame_to_world(&f, sample_cone(u1, u2, cos_max));
        if (!sphere_hit(l->position, l->radius, p, ls->wi, &ls->dist))
            ls->dist = dc; /* grazing: numerically at the rim */
        ls->Li = l->L;
        ls->pdf = sample_cone_pdf(cos_max);
        return true;
    }
    case LIGHT_DISK: {
        vec3 q = sample_disk(u1, u2);
        vec3 y = v3_add(l->position, frame_to_world(&l->f, v3_scale(q, l->radius)));
        vec3 d = v3_sub(y, p);
        double dist2 = v3_dot(d, d);
        if (!(dist2 > 0.0))
            return false;
        ls->dist = sqrt(dist2);
        ls->wi = v3_scale(d, 1.0 / ls->dist);
        double cos_l = -v3_dot(ls->wi, l->direction); /* emission side only */
        if (cos_l <= 0.0)
            return false;
        ls->Li = l->L;
        ls->pdf = dist2 / (cos_l * PI * l->radius * l->radius);
        return true;
    }
    }
    return false;
}

bool light_hit(const light *l, vec3 p, vec3 wi, double *dist, color *Le, double *pdf)
{
    switch (l->kind) {
    case LIGHT_DISTANT:
        if (l->angular_radius <= 0.0 || v3_dot(wi, v3_neg(l->direction)) < l->cos_max)
            return false;
        *dist = INFINITY;
        *Le = sun_radiance(l);
        *pdf = sample_cone_pdf(l->cos_max);
        return true;
    case LIGHT_POINT:
    case LIGHT_SPOT:
        return false;
    case LIGHT_SPHERE: {
        vec3 d = v3_sub(l->position, p);
        double dc2 = v3_dot(d, d), r2 = l->radius * l->radius;
        if (dc2 <= r2 || !sphere_hit(l->position, l->radius, p, wi, dist))
            return false;
        *Le = l->L;
        *pdf = sample_cone_pdf(sqrt(fmax(0.0, 1.0 - r2 / dc2)));
        return true;
    }
    case LIGHT_DISK: {
        double denom = v3_dot(wi, l->direction);
        if (denom >= 0.0) /* seen from behind, or edge-on */
            return false;
        double t = v3_dot(v3_sub(l->position, p), l->direction) / denom;
        if (!(t > 0.0))
            return false;
        vec3 y = v3_madd(p, wi, t);
        vec3 q = v3_sub(y, l->position);
        if (v3_dot(q, q) > l->radius * l->radius)
            return false;
        *dist = t;
        *Le = l->L;
        *pdf = t * t / (-denom * PI * l->radius * l->radius);
        return true;
    }
    }
    return false;
}
