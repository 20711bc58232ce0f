/* motion.c - keyframe interpolation of transforms: lerp, quaternion slerp, matrices. */
#include "core/motion.h"

void motion_quat_axis_angle(vec3 axis, double angle_deg, double q[4])
{
    vec3 a = v3_normalize(axis);
    double h = 0.5 * angle_deg * PI / 180.0, s = sin(h);
    q[0] = cos(h);
    q[1] = a.x * s;
    q[2] = a.y * s;
    q[3] = a.z * s;
}

/* Shoemake 1985, along the shorter arc; nlerp when the two are nearly equal. */
static void quat_slerp(const double a[4], const double b[4], double u, double out[4])
{
    double d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
    double sb = 1.0;
    if (d < 0.0) {
        d = -d;
        sb = -1.0;
    }
    double wa = 1.0 - u, wb = u;
    if (d < 0.9995) {
        double th = acos(d), st = sin(th);
        wa = sin((1.0 - u) * th) / st;
        wb = sin(u * th) / st;
    }
    double n = 0.0;
    for (int k = 0; k < 4; k++) {
        out[k] = wa * a[k] + wb * sb * b[k];
        n += out[k] * out[k];
    }
    n = 1.0 / sqrt(n);
    for (int k = 0; k < 4; k++)
        out[k] *= n;
}

static affine3 compose_trs(vec3 t, const double q[4], vec3 s)
{
    double w = q[0], x = q[1], y = q[2], z = q[3];
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                   2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
    return (affine3){{r[0] * s.x, r[1] * s.y, r[2] * s.z, t.x, r[3] * s.x, r[4] * s.y, r[5] * s.z, t.y,
                      r[6] * s.x, r[7] * s.y, r[8] * s.z, t.z}};
}

static vec3 lerp3(vec3 a, vec3 b, double u) { return v3_add(a, v3_scale(v3_sub(b, a), u)); }

affine3 motion_at(const motion *m, double t)
{
    const motion_key *k = m->key;
    if (m->n == 1 || t <= k[0].time)
        return compose_trs(k[0].translate, k[0].q, k[0].scale);
    if (t >= k[m->n - 1].time)
        return compose_trs(k[m->n - 1].translate, k[m->n - 1].q, k[m->n - 1].scale);
    int i = 0;
    while (i + 2 < m->n && t >= k[i + 1].time)
        i++;
    double u = (t - k[i].time) / (k[i + 1].time - k[i].time);
    double q[4];
    quat_slerp(k[i].q, k[i + 1].q, u, q);
    return compose_trs(lerp3(k[i].translate, k[i + 1].translate, u), q, lerp3(k[i].scale, k[i + 1].scale, u));
}

bool motion_rotation_constant(const motion *m)
{
    for (int i = 1; i < m->n; i++)
        for (int c = 0; c < 4; c++)
            if (m->key[i].q[c] != m->key[0].q[c])
                return false;
    return true;
}

bool motion_key_inside(const motion *m, double t0, double t1)
{
    for (int i = 0; i < m->n; i++)
        if (m->key[i].time > t0 && m->key[i].time < t1)
            return true;
    return false;
}
