/* sampling.c - warps from uniform numbers to directions, points and distances. */
#include "core/sampling.h"

vec3 direction_from_cos(double cos_theta, double u_phi)
{
    double sin_theta = sqrt(fmax(0.0, 1.0 - cos_theta * cos_theta));
    double phi = 2.0 * PI * u_phi;
    return v3(sin_theta * cos(phi), sin_theta * sin(phi), cos_theta);
}

vec3 sample_sphere(double u1, double u2) { return direction_from_cos(1.0 - 2.0 * u1, u2); }

vec3 sample_cone(double u1, double u2, double cos_max)
{
    return direction_from_cos(1.0 - u1 * (1.0 - cos_max), u2);
}

double sample_cone_pdf(double cos_max) { return 1.0 / (2.0 * PI * (1.0 - cos_max)); }

vec3 sample_disk(double u1, double u2)
{
    double a = 2.0 * u1 - 1.0, b = 2.0 * u2 - 1.0;
    if (a == 0.0 && b == 0.0)
        return v3(0.0, 0.0, 0.0);
    double r, phi;
    if (fabs(a) > fabs(b)) {
        r = a;
        phi = (PI / 4.0) * (b / a);
    } else {
        r = b;
        phi = PI / 2.0 - (PI / 4.0) * (a / b);
    }
    return v3(r * cos(phi), r * sin(phi), 0.0);
}

vec3 sample_cosine_hemisphere(double u1, double u2)
{
    vec3 d = sample_disk(u1, u2);
    d.z = sqrt(fmax(0.0, 1.0 - d.x * d.x - d.y * d.y));
    return d;
}

