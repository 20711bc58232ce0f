/* material_hit.c - a material's textures and mixes (material_hit.h): freed and counted, and
 * resolved at a hit as pbrt-v4 resolves them. */
#include "surface/material_hit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/hash.h"
#include "surface/texture.h"

/* m's texture fields, for what is done to each alike. */
#define MATERIAL_TEXTURES(m)                                                                                   \
    {&(m)->albedo_tex, &(m)->alpha_tex, &(m)->amount_tex, &(m)->bump_tex, &(m)->eta_tex, &(m)->k_tex,          \
     &(m)->thickness_tex, &(m)->g_tex, &(m)->layer_albedo_tex}
#define MATERIAL_NTEXTURES 9

bool material_textured(const material *m)
{
    texture *const *t[MATERIAL_NTEXTURES] = MATERIAL_TEXTURES(m);
    for (int i = 0; i < MATERIAL_NTEXTURES; i++)
        if (*t[i])
            return true;
    return m->type == MATERIAL_MIX && (material_textured(m->mix[0]) || material_textured(m->mix[1]));
}

bool material_varies(const material *m) { return m->type == MATERIAL_MIX || material_textured(m); }

size_t material_bytes(const material *m)
{
    texture *const *t[MATERIAL_NTEXTURES] = MATERIAL_TEXTURES(m);
    size_t n = 0;
    for (int i = 0; i < MATERIAL_NTEXTURES; i++)
        n += texture_bytes(*t[i]);
    for (int k = 0; k < 2; k++)
        n += m->mix[k] ? material_bytes(m->mix[k]) : 0;
    return n;
}

void material_release(material *m)
{
    texture **t[MATERIAL_NTEXTURES] = MATERIAL_TEXTURES(m);
    for (int i = 0; i < MATERIAL_NTEXTURES; i++) {
        texture_free(*t[i]);
        *t[i] = NULL;
    }
    for (int k = 0; k < 2; k++) {
        if (m->mix[k]) {
            material_release(m->mix[k]);
            free(m->mix[k]);
        }
        m->mix[k] = NULL;
    }
}

static uint64_t bits(double x)
{
    uint64_t b;
    x = x == 0.0 ? 0.0 : x; /* -0 hashes as +0 */
    memcpy(&b, &x, sizeof b);
    return b;
}

/* A number in [0, 1) from the point, the direction and the mix's depth (so that nested mixes
 * choose independently), the same for the same arguments on every run and thread. */
static double mix_hash(vec3 p, vec3 wo, int depth)
{
    const double in[6] = {p.x, p.y, p.z, wo.x, wo.y, wo.z};
    uint64_t h = hash_mix64((uint64_t)0x6d69786d6174u + (uint64_t)depth);
    for (int i = 0; i < 6; i++)
        h = hash_mix64(h ^ bits(in[i]));
    return (double)(h >> 11) * (1.0 / 9007199254740992.0);
}

static color clamped(const texture *t, double u, double v, double lo, double hi)
{
    color c = texture_eval(t, u, v);
    for (int k = 0; k < 3; k++)
        c.c[k] = c.c[k] > lo ? fmin(c.c[k], hi) : lo;
    return c;
}

/* A conductor's textured complex index, a coated diffuse's textured layer. */
static void layer_and_index_at(const material *c, double u, double v, material *out)
{
    if (c->eta_tex)
        out->eta_c = clamped(c->eta_tex, u, v, 0.0, 100.0);
    if (c->k_tex)
        out->k_c = clamped(c->k_tex, u, v, 0.0, 100.0);
    if (c->thickness_tex)
        out->thickness = clamped(c->thickness_tex, u, v, 0.0, 1e6).c[0];
    if (c->g_tex)
        out->g = clamped(c->g_tex, u, v, -0.999, 0.999).c[0];
    if (c->layer_albedo_tex)
        out->layer_albedo = clamped(c->layer_albedo_tex, u, v, 0.0, 1.0);
}

void material_at(const material *m, vec3 p, vec3 wo, double u, double v, material *out)
{
    const material *c = m;
    for (int depth = 0; c->type == MATERIAL_MIX; depth++) {
        double a = c->amount_tex ? texture_eval(c->amount_tex, u, v).c[0] : c->amount;
        /* pbrt-v4: materials[0] when amount <= 0, materials[1] when >= 1, else by the hash */
        c = a <= 0.0 ? c->mix[0] : a >= 1.0 ? c->mix[1] : (mix_hash(p, wo, depth) < a ? c->mix[1] : c->mix[0]);
    }
    *out = *c;
    out->emission = m->emission;
    out->two_sided_emission = m->two_sided_emission;
    if (c->albedo_tex) {
        color a = texture_eval(c->albedo_tex, u, v);
        for (int k = 0; k < 3; k++) {
            double x = a.c[k] > 0.0 ? fmin(a.c[k], 1.0) : 0.0;
            if (c->type == MATERIAL_DIFFUSE)
                out->albedo.c[k] = fmin(x, 1.0 - c->specular.c[k]);
            else if (c->type == MATERIAL_CONDUCTOR) { /* pbrt-v4: eta 1, k of normal reflectance r */
                double r = fmin(x, 0.9999);
                out->eta_c.c[k] = 1.0;
                out->k_c.c[k] = 2.0 * sqrt(r) / sqrt(1.0 - r);
            } else
                out->albedo.c[k] = x;
        }
    }
    if (c->alpha_tex) {
        double r = fmax(texture_eval(c->alpha_tex, u, v).c[0], 0.0);
        out->alpha = c->remap ? sqrt(r) : r;
    }
    layer_and_index_at(c, u, v, out);
    texture *bump = c->bump_tex; /* kept: material_bump's */
    texture **t[MATERIAL_NTEXTURES] = MATERIAL_TEXTURES(out);
    for (int i = 0; i < MATERIAL_NTEXTURES; i++)
        *t[i] = NULL;
    out->bump_tex = bump;
}

vec3 material_bump(const struct texture *disp, double u, double v, const vec3 dp[2], const vec3 dn[2], vec3 ng)
{
    /* pbrt-v4's BumpMap with its fallback offsets (brume has no ray differentials) */
    const double du = 0.0005, dv = 0.0005;
    double d = texture_eval(disp, u, v).c[0], d_u = texture_eval(disp, u + du, v).c[0],
           d_v = texture_eval(disp, u, v + dv).c[0];
    vec3 dpdu = v3_add(v3_madd(dp[0], ng, (d_u - d) / du), v3_scale(dn[0], d)),
         dpdv = v3_add(v3_madd(dp[1], ng, (d_v - d) / dv), v3_scale(dn[1], d));
    vec3 ns = v3_cross(dpdu, dpdv);
    double len = v3_length(ns);
    if (!(len > 0.0) || !isfinite(len))
        return ng;
    ns = v3_scale(ns, 1.0 / len);
    return v3_dot(ns, ng) < 0.0 ? v3_neg(ns) : ns; /* on ng's side, as pbrt-v4 turns it */
}
