/* xform.h - affine transforms of 3-space: a 3 x 4 matrix, row-major, [R | t], so that
 * x' = R x + t. Used to place grids, surfaces and (later) anything that moves. */
#ifndef BRUME_CORE_XFORM_H
#define BRUME_CORE_XFORM_H

#include <stdbool.h>

#include "core/vec.h"

typedef struct affine3 {
    double m[12];
} affine3;

static inline vec3 affine3_apply(const affine3 *t, vec3 p)
{
    const double *m = t->m;
    return v3(m[0] * p.x + m[1] * p.y + m[2] * p.z + m[3], m[4] * p.x + m[5] * p.y + m[6] * p.z + m[7],
              m[8] * p.x + m[9] * p.y + m[10] * p.z + m[11]);
}
static inline vec3 affine3_apply_dir(const affine3 *t, vec3 d)
{
    const double *m = t->m;
    return v3(m[0] * d.x + m[1] * d.y + m[2] * d.z, m[4] * d.x + m[5] * d.y + m[6] * d.z,
              m[8] * d.x + m[9] * d.y + m[10] * d.z);
}
affine3 affine3_identity(void);
/* a after b: x -> a(b(x)). */
affine3 affine3_compose(const affine3 *a, const affine3 *b);
/* False when singular or not finite. */
bool affine3_invert(const affine3 *t, affine3 *inv);
affine3 affine3_translate(vec3 t);
affine3 affine3_scale(vec3 s);
/* Rotation by angle_deg degrees about a unit axis, counter-clockwise seen from its tip. */
affine3 affine3_rotate(vec3 axis, double angle_deg);
/* Determinant of the linear part. */
double affine3_det(const affine3 *t);
/* The axis-aligned box around the image of box b (its eight corners mapped by t). */
box3 affine3_apply_box(const affine3 *t, box3 b);

#endif
