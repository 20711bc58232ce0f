/* xform.c - affine transforms: composition, inversion, the elementary ones. */
#include "core/xform.h"

affine3 affine3_identity(void) { return (affine3){{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0}}; }

affine3 affine3_compose(const affine3 *a, const affine3 *b)
{
    affine3 r;
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 4; j++) {
            double s = j == 3 ? a->m[4 * i + 3] : 0.0;
            for (int k = 0; k < 3; k++)
                s += a->m[4 * i + k] * b->m[4 * k + j];
            r.m[4 * i + j] = s;
        }
    }
    return r;
}

double affine3_det(const affine3 *t)
{
    const double *m = t->m;
    return m[0] * (m[5] * m[10] - m[6] * m[9]) + m[1] * (m[6] * m[8] - m[4] * m[10]) +
           m[2] * (m[4] * m[9] - m[5] * m[8]);
}

bool affine3_invert(const affine3 *t, affine3 *inv)
{
    const double *m = t->m;
    double c00 = m[5] * m[10] - m[6] * m[9], c01 = m[6] * m[8] - m[4] * m[10], c02 = m[4] * m[9] - m[5] * m[8];
    double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
    double scale = 0.0;
    for (int i = 0; i < 12; i++) {
        if (!isfinite(m[i]))
            return false;
        if (i % 4 != 3)
            scale = fmax(scale, fabs(m[i]));
    }
    if (!(fabs(det) > 1e-12 * scale * scale * scale) || !isfinite(det))
        return false;
    double id = 1.0 / det;
    double a[9] = {c00 * id, (m[2] * m[9] - m[1] * m[10]) * id, (m[1] * m[6] - m[2] * m[5]) * id,
                   c01 * id, (m[0] * m[10] - m[2] * m[8]) * id, (m[2] * m[4] - m[0] * m[6]) * id,
                   c02 * id, (m[1] * m[8] - m[0] * m[9]) * id, (m[0] * m[5] - m[1] * m[4]) * id};
    for (int i = 0; i < 3; i++) {
        inv->m[4 * i + 0] = a[3 * i + 0];
        inv->m[4 * i + 1] = a[3 * i + 1];
        inv->m[4 * i + 2] = a[3 * i + 2];
        inv->m[4 * i + 3] = -(a[3 * i + 0] * m[3] + a[3 * i + 1] * m[7] + a[3 * i + 2] * m[11]);
    }
    return true;
}

affine3 affine3_translate(vec3 t) { return (affine3){{1, 0, 0, t.x, 0, 1, 0, t.y, 0, 0, 1, t.z}}; }

affine3 affine3_scale(vec3 s) { return (affine3){{s.x, 0, 0, 0, 0, s.y, 0, 0, 0, 0, s.z, 0}}; }

box3 affine3_apply_box(const affine3 *t, box3 b)
{
    box3 out = box3_empty();
    for (int c = 0; c < 8; c++) {
        vec3 w = affine3_apply(t, v3((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z));
        out.lo = v3_min(out.lo, w);
        out.hi = v3_max(out.hi, w);
    }
    return out;
}

affine3 affine3_rotate(vec3 axis, double angle_deg)
{
    vec3 a = v3_normalize(axis);
    double th = angle_deg * PI / 180.0, c = cos(th), s = sin(th), k = 1.0 - c;
    /* Rodrigues' formula */
    return (affine3){{c + a.x * a.x * k, a.x * a.y * k - a.z * s, a.x * a.z * k + a.y * s, 0,
                      a.y * a.x * k + a.z * s, c + a.y * a.y * k, a.y * a.z * k - a.x * s, 0,
                      a.z * a.x * k - a.y * s, a.z * a.y * k + a.x * s, c + a.z * a.z * k, 0}};
}
