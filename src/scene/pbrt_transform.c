/* pbrt_transform.c - the pbrt reader's 4 x 4 transforms (row-major, p' = M p), as brume's
 * scale, rotation and translation, and the transform directives (Translate, Rotate, LookAt,
 * ...). */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/vec.h"
#include "io/grid_io.h"
#include "io/json.h"
#include "scene/scene_build.h"
#include "scene/pbrt.h"

m4 pbrt_m4_identity(void)
{
    m4 r = {{0}};
    r.m[0] = r.m[5] = r.m[10] = r.m[15] = 1.0;
    return r;
}

m4 pbrt_m4_mul(m4 a, m4 b)
{
    m4 r;
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++)
                s += a.m[4 * i + k] * b.m[4 * k + j];
            r.m[4 * i + j] = s;
        }
    return r;
}

bool pbrt_m4_inverse(m4 a, m4 *out)
{
    m4 r = pbrt_m4_identity();
    for (int c = 0; c < 4; c++) {
        int piv = c;
        for (int i = c + 1; i < 4; i++)
            if (fabs(a.m[4 * i + c]) > fabs(a.m[4 * piv + c]))
                piv = i;
        if (fabs(a.m[4 * piv + c]) < 1e-300)
            return false;
        for (int j = 0; j < 4; j++) {
            double t = a.m[4 * c + j];
            a.m[4 * c + j] = a.m[4 * piv + j];
            a.m[4 * piv + j] = t;
            t = r.m[4 * c + j];
            r.m[4 * c + j] = r.m[4 * piv + j];
            r.m[4 * piv + j] = t;
        }
        double d = a.m[4 * c + c];
        for (int j = 0; j < 4; j++) {
            a.m[4 * c + j] /= d;
            r.m[4 * c + j] /= d;
        }
        for (int i = 0; i < 4; i++)
            if (i != c) {
                double f = a.m[4 * i + c];
                for (int j = 0; j < 4; j++) {
                    a.m[4 * i + j] -= f * a.m[4 * c + j];
                    r.m[4 * i + j] -= f * r.m[4 * c + j];
                }
            }
    }
    *out = r;
    return true;
}

vec3 pbrt_m4_point(m4 a, vec3 p)
{
    const double *m = a.m;
    return v3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
              m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}

vec3 pbrt_m4_vector(m4 a, vec3 v)
{
    const double *m = a.m;
    return v3(m[0] * v.x + m[1] * v.y + m[2] * v.z, m[4] * v.x + m[5] * v.y + m[6] * v.z,
              m[8] * v.x + m[9] * v.y + m[10] * v.z);
}

static m4 m4_translate(double x, double y, double z)
{
    m4 r = pbrt_m4_identity();
    r.m[3] = x;
    r.m[7] = y;
    r.m[11] = z;
    return r;
}

m4 pbrt_m4_scale(double x, double y, double z)
{
    m4 r = pbrt_m4_identity();
    r.m[0] = x;
    r.m[5] = y;
    r.m[10] = z;
    return r;
}

static m4 m4_rotate(double deg, vec3 axis)
{
    vec3 a = v3_normalize(axis);
    double t = deg * PI / 180.0, s = sin(t), c = cos(t);
    m4 r = pbrt_m4_identity();
    r.m[0] = a.x * a.x + (1 - a.x * a.x) * c;
    r.m[1] = a.x * a.y * (1 - c) - a.z * s;
    r.m[2] = a.x * a.z * (1 - c) + a.y * s;
    r.m[4] = a.x * a.y * (1 - c) + a.z * s;
    r.m[5] = a.y * a.y + (1 - a.y * a.y) * c;
    r.m[6] = a.y * a.z * (1 - c) - a.x * s;
    r.m[8] = a.x * a.z * (1 - c) - a.y * s;
    r.m[9] = a.y * a.z * (1 - c) + a.x * s;
    r.m[10] = a.z * a.z + (1 - a.z * a.z) * c;
    return r;
}

/* pbrt's LookAt: the camera-from-world matrix with the eye at the origin looking down +z;
 * NULL, or why there is none (pbrt-v4 stops on the parallel case only, with LOG_FATAL). */
static const char *m4_look_at(vec3 eye, vec3 look, vec3 up, m4 *out)
{
    vec3 d = v3_sub(look, eye);
    if (!isfinite(d.x) || !isfinite(d.y) || !isfinite(d.z))
        return "the view direction look - eye overflows";
    if (d.x == 0.0 && d.y == 0.0 && d.z == 0.0)
        return "eye and look are the same point: there is no view direction";
    if (up.x == 0.0 && up.y == 0.0 && up.z == 0.0)
        return "up is the zero vector";
    vec3 dir = v3_normalize(d);
    vec3 right = v3_cross(v3_normalize(up), dir);
    if (!(v3_length(right) > 1e-12))
        return "up parallel to the view direction";
    right = v3_normalize(right);
    vec3 nup = v3_cross(dir, right);
    m4 w = pbrt_m4_identity(); /* world from camera */
    w.m[0] = right.x; w.m[4] = right.y; w.m[8] = right.z;
    w.m[1] = nup.x; w.m[5] = nup.y; w.m[9] = nup.z;
    w.m[2] = dir.x; w.m[6] = dir.y; w.m[10] = dir.z;
    w.m[3] = eye.x; w.m[7] = eye.y; w.m[11] = eye.z;
    return pbrt_m4_inverse(w, out) ? NULL : "a view that cannot be inverted";
}

const char *pbrt_m4_flaw(m4 a)
{
    for (int i = 0; i < 16; i++)
        if (!isfinite(a.m[i]))
            return "is not finite (its product overflows)";
    if (a.m[12] != 0.0 || a.m[13] != 0.0 || a.m[14] != 0.0 || a.m[15] != 1.0)
        return "is projective (its last row is not 0 0 0 1): brume places by scale, rotation and translation";
    /* the volume of the columns over the product of their lengths: 0 when the linear part
     * flattens space, whatever the scene's unit */
    const double *c = a.m;
    double l0 = sqrt(c[0] * c[0] + c[4] * c[4] + c[8] * c[8]), l1 = sqrt(c[1] * c[1] + c[5] * c[5] + c[9] * c[9]),
           l2 = sqrt(c[2] * c[2] + c[6] * c[6] + c[10] * c[10]);
    double det = c[0] * (c[5] * c[10] - c[6] * c[9]) - c[1] * (c[4] * c[10] - c[6] * c[8]) +
                 c[2] * (c[4] * c[9] - c[5] * c[8]);
    if (!(l0 > 0.0 && l1 > 0.0 && l2 > 0.0) || !(fabs(det) / l0 / l1 / l2 > 1e-12))
        return "is singular (it flattens space to a plane, a line or a point): it has no inverse";
    return NULL;
}

/* brume's transform object {"translate", "rotate", "scale"} = T R S for an affine map
 * without shear (columns of the linear part orthogonal, rotation proper); NULL (a refusal by
 * the caller) otherwise, or with *oom set when memory ran out. */
cJSON *pbrt_transform_json(m4 a, bool *oom)
{
    *oom = false;
    vec3 col[3];
    double s[3];
    for (int j = 0; j < 3; j++) {
        col[j] = v3(a.m[j], a.m[4 + j], a.m[8 + j]);
        s[j] = v3_length(col[j]);
        if (!(s[j] > 0.0))
            return NULL;
        col[j] = v3_scale(col[j], 1.0 / s[j]);
    }
    if (fabs(v3_dot(col[0], col[1])) > 1e-6 || fabs(v3_dot(col[0], col[2])) > 1e-6 || fabs(v3_dot(col[1], col[2])) > 1e-6)
        return NULL;
    if (v3_dot(v3_cross(col[0], col[1]), col[2]) < 0.0) { /* a mirror: one negative scale */
        s[0] = -s[0];
        col[0] = v3_neg(col[0]);
    }
    /* axis-angle of the rotation R = [col0 col1 col2] */
    double tr = col[0].x + col[1].y + col[2].z;
    double angle = acos(fmax(-1.0, fmin(1.0, 0.5 * (tr - 1.0))));
    vec3 axis = v3(col[1].z - col[2].y, col[2].x - col[0].z, col[0].y - col[1].x);
    if (v3_length(axis) < 1e-9) {
        if (angle < 1e-6) {
            axis = v3(0, 0, 1);
            angle = 0.0;
        } else { /* a half turn: the axis from R + I */
            vec3 c = v3_add(col[0], v3(1, 0, 0));
            if (v3_length(c) < 1e-6)
                c = v3_add(col[1], v3(0, 1, 0));
            if (v3_length(c) < 1e-6)
                c = v3_add(col[2], v3(0, 0, 1));
            axis = c;
        }
    }
    axis = v3_normalize(axis);
    cJSON *t = cJSON_CreateObject();
    double tv[3] = {a.m[3], a.m[7], a.m[11]}, av[3] = {axis.x, axis.y, axis.z};
    cJSON *tr_j = cJSON_CreateDoubleArray(tv, 3), *axis_j = cJSON_CreateDoubleArray(av, 3),
          *scale_j = cJSON_CreateDoubleArray(s, 3);
    cJSON *r = t ? cJSON_AddObjectToObject(t, "rotate") : NULL;
    if (!t || !r || !tr_j || !axis_j || !scale_j || !cJSON_AddNumberToObject(r, "angle", angle * 180.0 / PI)) {
        cJSON_Delete(t); /* out of memory: not a transform brume cannot place */
        cJSON_Delete(tr_j);
        cJSON_Delete(axis_j);
        cJSON_Delete(scale_j);
        *oom = true;
        return NULL;
    }
    cJSON_AddItemToObject(t, "translate", tr_j);
    cJSON_AddItemToObject(r, "axis", axis_j);
    cJSON_AddItemToObject(t, "scale", scale_j);
    return t;
}

/* The transform that stands for pbrt's identity: in the world block of a mirrored view
 * (camera_directive) the mirror x -> -x, else the identity. */
m4 pbrt_world_origin(const pbrt_state *S)
{
    return S->world && S->mirror ? pbrt_m4_scale(-1.0, 1.0, 1.0) : pbrt_m4_identity();
}

/* The transform directives: *handled false when dir is none of them. A zero scale, a
 * rotation about no axis, a degenerate LookAt and a transform that overflows are refused
 * where they are given; a singular or projective one where something is placed by it. */
brume_status pbrt_transform_directive(pbrt_state *S, attrs *a, const char *dir, bool *handled)
{
    lexer *L = &S->L;
    double v[16];
    brume_status st;
    *handled = true;
    if (strcmp(dir, "Identity") == 0) {
        a->ctm = pbrt_world_origin(S);
        pbrt_next(L);
    } else if (strcmp(dir, "Translate") == 0) {
        if ((st = pbrt_numbers(L, dir, 3, v))) return st;
        a->ctm = pbrt_m4_mul(a->ctm, m4_translate(v[0], v[1], v[2]));
    } else if (strcmp(dir, "Scale") == 0) {
        if ((st = pbrt_numbers(L, dir, 3, v))) return st;
        if (v[0] == 0.0 || v[1] == 0.0 || v[2] == 0.0)
            return pbrt_fail(L, "%s %g %g %g: a zero scale flattens space (a degenerate transform)", dir, v[0], v[1],
                             v[2]);
        a->ctm = pbrt_m4_mul(a->ctm, pbrt_m4_scale(v[0], v[1], v[2]));
    } else if (strcmp(dir, "Rotate") == 0) {
        if ((st = pbrt_numbers(L, dir, 4, v))) return st;
        double big = fmax(fabs(v[1]), fmax(fabs(v[2]), fabs(v[3]))); /* scales the axis before its length */
        if (big == 0.0)
            return pbrt_fail(L, "%s: the axis (0, 0, 0) has zero length: a rotation about no axis", dir);
        a->ctm = pbrt_m4_mul(a->ctm, m4_rotate(v[0], v3(v[1] / big, v[2] / big, v[3] / big)));
    } else if (strcmp(dir, "LookAt") == 0) {
        if ((st = pbrt_numbers(L, dir, 9, v))) return st;
        m4 la;
        const char *why = m4_look_at(v3(v[0], v[1], v[2]), v3(v[3], v[4], v[5]), v3(v[6], v[7], v[8]), &la);
        if (why)
            return pbrt_fail(L, "%s: %s", dir, why);
        a->ctm = pbrt_m4_mul(a->ctm, la);
    } else if (strcmp(dir, "Transform") == 0 || strcmp(dir, "ConcatTransform") == 0) {
        if ((st = pbrt_numbers(L, dir, 16, v))) return st;
        m4 t; /* pbrt's matrices are given column by column */
        for (int i = 0; i < 4; i++)
            for (int j = 0; j < 4; j++)
                t.m[4 * i + j] = v[4 * j + i];
        a->ctm = dir[0] == 'T' ? pbrt_m4_mul(pbrt_world_origin(S), t) : pbrt_m4_mul(a->ctm, t);
    } else {
        *handled = false;
        return BRUME_OK;
    }
    for (int i = 0; i < 16; i++)
        if (!isfinite(a->ctm.m[i]))
            return pbrt_fail(L, "%s: the current transform overflows (an entry is no longer finite)", dir);
    return BRUME_OK;
}
