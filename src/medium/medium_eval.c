/* medium_eval.c - one medium at a point and along a ray: its coefficients, its emission and
 * the majorant cells a tracker walks (medium.h). What spans the scene's media (their sum at
 * a point, their merged majorant) is the trackers' (render/track.h). */
#include "medium/medium.h"

#include "medium/blackbody.h"

/* The blackbody radiance at the mapped temperature T (kelvin, > 0) in the medium's
 * convention (medium.h): pbrt-v4's peak-normalized colour times its scale, or Cycles'
 * Stefan-Boltzmann intensity sigma T^4 (sigma = 5.670373e-8 W m^-2 K^-4, in Cycles' 1e-6
 * per steradian: 5.670373e-14 / pi) mixed with 1 by the intensity, times tint and colour. */
static color medium_blackbody(const medium *md, double T)
{
    if (!md->bb_blender)
        return col_scale(blackbody_rgb(T), md->bb_scale);
    const double sigma = 5.670373e-8 * 1e-6 / 3.14159265358979323846, T2 = T * T;
    double intensity = sigma * ((1.0 - md->bb_intensity) + md->bb_intensity * T2 * T2);
    return col_scale(col_mul(md->bb_tint, blackbody_rgb_blender(T)), intensity);
}

/* The optional fields of a medium at its local point p: albedo scales sigma_s per
 * channel; temperature and emission fields add to Le (medium.h). */
static void medium_fields_at(const medium *md, vec3 p, color *ss, color *Le)
{
    if (md->albedo[0])
        for (int c = 0; c < BRUME_NSAMPLES; c++)
            ss->c[c] *= density_eval(md->albedo[c], p);
    if (md->temperature) {
        double T = (density_eval(md->temperature, p) - md->bb_offset) * md->bb_tscale;
        if (T > md->bb_cutoff)
            *Le = col_add(*Le, medium_blackbody(md, T));
    }
    if (md->emission[0]) {
        if (md->emission[1])
            for (int c = 0; c < BRUME_NSAMPLES; c++)
                Le->c[c] += md->emission_color.c[c] * density_eval(md->emission[c], p);
        else
            *Le = col_madd(*Le, md->emission_color, density_eval(md->emission[0], p));
    }
}

/* Velocity motion blur (docs/animation.md, "Velocity motion blur"): the point whose
 * frame-time fields a lookup at p reads, p - v(p) dt, first-order Eulerian back-advection
 * as in Cycles and Arnold. */
static vec3 velocity_advect(const medium *md, vec3 p, double dt)
{
    if (dt == 0.0 || !md->moved)
        return p;
    const vec3 u = v3(density_eval(md->velocity[0], p), density_eval(md->velocity[1], p),
                      density_eval(md->velocity[2], p));
    const double *M = md->velocity_map;
    const vec3 v = v3(M[0] * u.x + M[1] * u.y + M[2] * u.z, M[3] * u.x + M[4] * u.y + M[5] * u.z,
                      M[6] * u.x + M[7] * u.y + M[8] * u.z);
    return v3_sub(p, v3_scale(v, dt));
}

bool medium_coeffs_at(const medium *md, vec3 p, double time, double dt, medium_coeffs *mc)
{
    vec3 pm = p;
    if (md->motion) {
        affine3 to_world = motion_at(md->motion, time), to_local;
        if (!affine3_invert(&to_world, &to_local))
            return false;
        pm = affine3_apply(&to_local, p);
    }
    if (md->velocity[0])
        pm = velocity_advect(md, pm, dt);
    double rho = density_eval(md->rho, pm);
    if (rho <= 0.0)
        return false;
    mc->sigma_a = col_scale(md->sigma_a, rho);
    mc->sigma_s = col_scale(md->sigma_s, rho);
    color Le = md->Le;
    if (medium_has_fields(md))
        medium_fields_at(md, pm, &mc->sigma_s, &Le);
    mc->emission = md->emit_per_length ? Le : col_mul(mc->sigma_a, Le);
    return true;
}

bool medium_majorant_begin(const medium *md, ray r, double tmax, majorant_iter *it)
{
    /* A moving medium: the ray in the field's frame at the ray's instant. An affine map
     * keeps the ray parameter t, so segments need no conversion back. */
    if (md->motion) {
        affine3 to_world = motion_at(md->motion, r.time), to_local;
        if (!affine3_invert(&to_world, &to_local))
            return false;
        r.o = affine3_apply(&to_local, r.o);
        r.d = affine3_apply_dir(&to_local, r.d);
    }
    /* a medium blurred by its velocity: the majorants of its density moved (medium.h) */
    density_majorant_begin(md->moved ? md->moved : md->rho, r, 0.0, tmax, it);
    return true;
}
