/* scene_material_build.c - brume.h's brume_material checked and built into the surfaces'
 * material (surface/material_params.h): its type's fields, its textures (their images read
 * here: the scene layer reads files) and the materials a mix nests. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/budget.h"
#include "core/error.h"
#include "scene/scene.h"
#include "scene/scene_build.h"
#include "scene/scene_material_build.h"
#include "surface/material_hit.h"
#include "surface/material.h"
#include "surface/texture.h"

/* "WHAT.KEY" in at (160 bytes). */
static const char *field(char at[160], const char *what, const char *key)
{
    snprintf(at, 160, "%s.%s", what, key);
    return at;
}

static brume_status material_eta(const char *fn, const char *what, const brume_material *bm, material *m)
{
    char at[160];
    brume_status st = build_number(fn, field(at, what, "eta"), bm->eta, 1e-3, 100.0);
    m->eta = bm->eta;
    return st;
}

/* The fields of bm's type, checked, into *m (albedo, specular, exponent and emission are
 * material_build's). */
static brume_status material_of_type(const char *fn, const char *what, const brume_material *bm, material *m)
{
    brume_status st;
    char at[160];
    m->type = (material_type)bm->type;
    switch (bm->type) {
    case BRUME_MATERIAL_DIFFUSE: return BRUME_OK;
    case BRUME_MATERIAL_CONDUCTOR:
        if ((st = build_color(fn, field(at, what, "conductor_eta"), bm->conductor_eta, 100.0, &m->eta_c)) ||
            (st = build_color(fn, field(at, what, "conductor_k"), bm->conductor_k, 100.0, &m->k_c)))
            return st;
        break;
    case BRUME_MATERIAL_COATEDDIFFUSE:
        if ((st = build_number(fn, field(at, what, "thickness"), bm->thickness, 1e-300, 1e6)) ||
            (st = build_color(fn, field(at, what, "layer_albedo"), bm->layer_albedo, 1.0, &m->layer_albedo)) ||
            (st = build_number(fn, field(at, what, "g"), bm->g, -0.999, 0.999)) ||
            (st = build_number(fn, field(at, what, "max_depth"), bm->max_depth, 1, 1000)) ||
            (st = build_number(fn, field(at, what, "nsamples"), bm->nsamples, 1, 1000)))
            return st;
        m->thickness = bm->thickness;
        m->g = bm->g;
        m->max_depth = bm->max_depth;
        m->nsamples = bm->nsamples;
        if ((st = material_eta(fn, what, bm, m))) /* the coat's */
            return st;
        break;
    case BRUME_MATERIAL_DIELECTRIC:
        if ((st = material_eta(fn, what, bm, m)))
            return st;
        break;
    default:
        return err_set(BRUME_ERROR_RANGE, "%s: %s.type: %d is not a brume_material_type", fn, what, (int)bm->type);
    }
    if ((st = build_number(fn, field(at, what, "roughness"), bm->roughness, 0.0, 100.0)))
        return st;
    m->alpha = bm->roughness;
    return BRUME_OK;
}

/* A material's texture built, its imagemaps' files read here (the scene layer reads files;
 * surface/texture.c decodes them). NULL after err_set. */
static texture *build_texture(const char *fn, const char *what, const char *key, const brume_texture *bt)
{
    char at[160];
    field(at, what, key);
    brume_image *img[BRUME_TEXTURE_MAX_NODES] = {NULL};
    int n = bt->nodes && bt->n >= 1 && bt->n <= BRUME_TEXTURE_MAX_NODES ? bt->n : 0;
    brume_status st = BRUME_OK;
    for (int i = 0; i < n && st == BRUME_OK; i++) {
        const brume_texture_node *node = &bt->nodes[i];
        if (node->type == BRUME_TEXTURE_IMAGEMAP && node->filename && node->filename[0] &&
            brume_image_read(NULL, node->filename, &img[i]) != BRUME_OK)
            st = err_prefix("%s: %s.nodes[%d]", fn, at, i);
    }
    texture *t = st == BRUME_OK ? texture_build(bt, img, fn, at) : NULL;
    for (int i = 0; i < n; i++)
        brume_image_release(img[i]);
    return t;
}


/* The textures only one type reads: conductor's index, coateddiffuse's layer. */
static brume_status type_textures(const char *fn, const char *what, const brume_material *bm, material *m)
{
    const struct {
        const brume_texture *from;
        texture **to;
        const char *key;
        brume_material_type type;
    } t[] = {{bm->conductor_eta_texture, &m->eta_tex, "conductor_eta_texture", BRUME_MATERIAL_CONDUCTOR},
             {bm->conductor_k_texture, &m->k_tex, "conductor_k_texture", BRUME_MATERIAL_CONDUCTOR},
             {bm->thickness_texture, &m->thickness_tex, "thickness_texture", BRUME_MATERIAL_COATEDDIFFUSE},
             {bm->g_texture, &m->g_tex, "g_texture", BRUME_MATERIAL_COATEDDIFFUSE},
             {bm->layer_albedo_texture, &m->layer_albedo_tex, "layer_albedo_texture", BRUME_MATERIAL_COATEDDIFFUSE}};
    char at[160];
    for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
        if (!t[i].from)
            continue;
        if (bm->type != t[i].type)
            return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: only a %s material reads it", fn,
                           field(at, what, t[i].key), material_type_name((material_type)t[i].type));
        if (!(*t[i].to = build_texture(fn, what, t[i].key, t[i].from)))
            return err_status();
    }
    return BRUME_OK;
}

/* The textures bm gives, each where its type reads it, built into m. */
static brume_status material_textures(const char *fn, const char *what, const brume_material *bm, material *m)
{
    char at[160];
    bool reflects = bm->type == BRUME_MATERIAL_DIFFUSE || bm->type == BRUME_MATERIAL_COATEDDIFFUSE ||
                    bm->type == BRUME_MATERIAL_CONDUCTOR;
    bool rough = bm->type == BRUME_MATERIAL_DIELECTRIC || bm->type == BRUME_MATERIAL_COATEDDIFFUSE ||
                 bm->type == BRUME_MATERIAL_CONDUCTOR;
    if (bm->albedo_texture && !reflects)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: a %s material has no reflectance to texture", fn,
                       field(at, what, "albedo_texture"), material_type_name(m->type));
    if (bm->roughness_texture && !rough)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: a %s material has no roughness", fn,
                       field(at, what, "roughness_texture"), material_type_name(m->type));
    if (bm->amount_texture && bm->type != BRUME_MATERIAL_MIX)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: only a mix has an amount", fn,
                       field(at, what, "amount_texture"));
    if (bm->displacement_texture && bm->type == BRUME_MATERIAL_MIX)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: a mix is not bumped (its materials are)", fn,
                       field(at, what, "displacement_texture"));
    m->remap = bm->remap_roughness;
    if (bm->albedo_texture && !(m->albedo_tex = build_texture(fn, what, "albedo_texture", bm->albedo_texture)))
        return err_status();
    if (bm->roughness_texture &&
        !(m->alpha_tex = build_texture(fn, what, "roughness_texture", bm->roughness_texture)))
        return err_status();
    if (bm->amount_texture && !(m->amount_tex = build_texture(fn, what, "amount_texture", bm->amount_texture)))
        return err_status();
    if (bm->displacement_texture &&
        !(m->bump_tex = build_texture(fn, what, "displacement_texture", bm->displacement_texture)))
        return err_status();
    return type_textures(fn, what, bm, m);
}

/* A mix's amount and its two materials, built depth + 1 deep. */
static brume_status material_mix(const char *fn, const char *what, const brume_material *bm, int depth, material *m)
{
    char at[160];
    brume_status st;
    if (depth + 1 >= BRUME_MATERIAL_MAX_MIX)
        return err_set(BRUME_ERROR_RANGE, "%s: %s: mixes nested more than %d deep", fn, what, BRUME_MATERIAL_MAX_MIX);
    if ((st = build_number(fn, field(at, what, "amount"), bm->amount, 0.0, 1.0)))
        return st;
    m->amount = bm->amount;
    for (int k = 0; k < 2; k++) {
        snprintf(at, sizeof at, "%s.materials[%d]", what, k);
        if (!bm->materials[k])
            return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: %s: NULL (a mix takes two materials)", fn, at);
        if (!(m->mix[k] = malloc(sizeof *m->mix[k])))
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: %s: out of memory", fn, at);
        if ((st = material_build(fn, at, bm->materials[k], depth + 1, m->mix[k]))) {
            free(m->mix[k]);
            m->mix[k] = NULL;
            return st;
        }
    }
    return BRUME_OK;
}

static brume_status material_fields(const char *fn, const char *what, const brume_material *bm, int depth,
                                    material *m)
{
    char at[160];
    brume_status st;
    if ((st = build_color(fn, field(at, what, "albedo"), bm->albedo, 1.0, &m->albedo)) ||
        (st = build_color(fn, field(at, what, "specular"), bm->specular, 1.0, &m->specular)) ||
        (st = build_number(fn, field(at, what, "exponent"), bm->exponent, 0.0, 1e6)) ||
        (st = build_color(fn, field(at, what, "emission"), bm->emission, 1e30, &m->emission)))
        return st;
    for (int c = 0; c < 3 && !bm->albedo_texture; c++)
        if (bm->albedo[c] + bm->specular[c] > 1.0)
            return err_set(BRUME_ERROR_RANGE, "%s: %s: albedo + specular = %g > 1 would create energy", fn, what,
                           bm->albedo[c] + bm->specular[c]);
    m->exponent = bm->exponent;
    m->two_sided_emission = bm->two_sided;
    if (bm->type == BRUME_MATERIAL_MIX) {
        m->type = MATERIAL_MIX;
        if ((st = material_mix(fn, what, bm, depth, m)))
            return st;
    } else if ((st = material_of_type(fn, what, bm, m))) {
        return st;
    }
    return material_textures(fn, what, bm, m);
}

brume_status material_build(const char *fn, const char *what, const brume_material *bm, int depth, material *m)
{
    *m = (material){.type = MATERIAL_DIFFUSE};
    brume_status st = material_fields(fn, what, bm, depth, m);
    if (st) {
        budget_give(material_bytes(m));
        material_release(m);
    }
    return st;
}
