/* blasi_setup.c - Blasi, Le Saec and Schlick's two-pass Monte-Carlo renderer (1993, Section 4):
 * setting up (blasi_prepare: the media as voxels, their occupancy, the first pass run or
 * loaded, and saved) and releasing. The passes: blasi_light.c (first) and blasi_view.c
 * (second); the walk they share: blasi_walk.h; light files: io/light_file.c. */
#include "render/blasi.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "core/progress.h"
#include "core/regular_file.h"
#include "density/blobs.h"
#include "io/light_file.h"
#include "render/blasi_state.h"
#include "render/blasi_walk.h"
#include "scene/stam_media.h"
#include "surface/surfaces.h"

/* ---- setting up --------------------------------------------------------------------------- */

/* Splits a medium's phase function into the paper's isotropic fraction r and directional
 * lobe (Eq. 22 with k = 0; docs/blasi.md "Phase functions"). */
static void split_phase(const phase *ph, double *r, const phase **dir)
{
    *r = BLASI_R_DEFAULT;
    *dir = ph;
    switch (phase_get_kind(ph)) {
    case PHASE_ISOTROPIC: *r = 1.0; return;
    case PHASE_SCHLICK: *r = 0.0; return;
    case PHASE_MIXTURE:
        if (phase_lobe_count(ph) == 2) {
            double w0, w1;
            const phase *a = phase_lobe(ph, 0, &w0), *b = phase_lobe(ph, 1, &w1);
            int iso = -1; /* the lobe treated as isotropic */
            if (phase_get_kind(a) == PHASE_ISOTROPIC)
                iso = 0;
            else if (phase_get_kind(b) == PHASE_ISOTROPIC)
                iso = 1;
            else if (phase_get_kind(a) == PHASE_SCHLICK && phase_get_kind(b) == PHASE_SCHLICK)
                iso = phase_schlick_k(a) <= phase_schlick_k(b) ? 0 : 1;
            if (iso >= 0) {
                *r = iso == 0 ? w0 : w1;
                *dir = iso == 0 ? b : a;
            }
        }
        return;
    default: return;
    }
}

static uint64_t fnv(uint64_t h, const void *p, size_t n)
{
    const unsigned char *b = p;
    for (size_t i = 0; i < n; i++)
        h = (h ^ b[i]) * 0x100000001b3ULL;
    return h;
}

static uint64_t fnv_d(uint64_t h, double x) { return fnv(h, &x, sizeof x); }
static uint64_t fnv_col(uint64_t h, color c)
{
    for (int i = 0; i < 3; i++)
        h = fnv_d(h, c.c[i]);
    return h;
}

/* A hash of everything the first pass depends on except the ray count and the seed:
 * grids, coefficients, the split of the phase functions, lights, surfaces and options. */
static uint64_t scene_hash(const brume_scene *s, const blasi_state *st)
{
    uint64_t h = 0xcbf29ce484222325ULL;
    h = fnv(h, &st->nm, sizeof st->nm);
    for (int m = 0; m < st->nm; m++) {
        const blasi_medium *bm = &st->m[m];
        h = fnv(h, bm->n, sizeof bm->n);
        for (int i = 0; i < 12; i++)
            h = fnv_d(h, bm->w2v.m[i]);
        h = fnv(h, st->rho + bm->offset, bm->nvox * sizeof(float));
        h = fnv_col(fnv_col(fnv_col(h, bm->md->sigma_a), bm->md->sigma_s), bm->md->Le);
        h = fnv_d(h, bm->r);
        if (bm->trilinear) /* the values behind the means; a voxel medium's key is unchanged */
            h = fnv(h, st->field + bm->offset, bm->nvox * sizeof(float));
        for (int i = 0; i <= 8; i++)
            h = fnv_d(h, phase_eval(bm->dir, -1.0 + 0.25 * i));
    }
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        int k = (int)l->kind;
        h = fnv(h, &k, sizeof k);
        h = fnv_d(fnv_d(fnv_d(h, l->direction.x), l->direction.y), l->direction.z);
        h = fnv_d(fnv_d(fnv_d(h, l->position.x), l->position.y), l->position.z);
        h = fnv_col(h, l->L);
        h = fnv_d(fnv_d(fnv_d(fnv_d(h, l->radius), l->angular_radius), l->cos_inner), l->cos_outer);
        h = fnv(h, &l->profile_n, sizeof l->profile_n);
        for (int p = 0; p < l->profile_n; p++)
            h = fnv_d(fnv_d(h, l->profile_angle[p]), l->profile_value[p]);
    }
    long ns = s->surf ? surfaces_count(s->surf) : 0, nt = s->surf ? surfaces_triangle_count(s->surf) : 0;
    h = fnv(fnv(h, &ns, sizeof ns), &nt, sizeof nt);
    int ex = (int)st->exit, src = blasi_opts(s)->sources;
    h = fnv(fnv(h, &ex, sizeof ex), &src, sizeof src);
    return fnv_d(fnv_d(h, st->step), st->threshold);
}

/* The light file's key and grid sizes for this state (io/light_file.h); n holds the sizes. */
static light_file_layout file_layout(const brume_scene *s, const blasi_state *st, int n[SCENE_MAX_MEDIA][3])
{
    for (int m = 0; m < st->nm; m++)
        memcpy(n[m], st->m[m].n, sizeof n[m]);
    return (light_file_layout){scene_hash(s, st), st->nm, (const int(*)[3])n, st->nvox};
}

/* blasi.load_light: the source read from a file instead of the first pass. */
static brume_status load_light(const char *path, const brume_scene *s, blasi_state *st)
{
    int n[SCENE_MAX_MEDIA][3];
    const light_file_layout l = file_layout(s, st, n);
    brume_status rc = light_file_read(path, &l, st->S);
    st->stats.loaded = true;
    /* one medium: an empty voxel holds no source, as after a first pass run here (the
     * view walk passes over it): a file that says otherwise is read as if it did not */
    for (size_t v = 0; rc == BRUME_OK && st->nm == 1 && v < st->nvox; v++)
        if (st->rho[v] == 0.0f)
            st->S[3 * v] = st->S[3 * v + 1] = st->S[3 * v + 2] = 0.0f;
    return rc;
}

/* blasi.save_light: the source written to a file. */
static brume_status save_light(const char *path, const brume_scene *s, const blasi_state *st)
{
    int n[SCENE_MAX_MEDIA][3];
    const light_file_layout l = file_layout(s, st, n);
    return light_file_write(path, &l, st->S);
}

void blasi_finish(blasi_state *st)
{
    if (!st)
        return;
    for (int m = 0; m < st->nm; m++) {
        phase_release(st->m[m].dir_owned);
        density_release(st->m[m].vox);
        free(st->m[m].occ);
    }
    free(st->rho);
    free(st->field);
    free(st->S);
    free(st);
}

/* A new state with the options and the lights' kinds; its media are set up next. */
static blasi_state *state_new(const brume_scene *s)
{
    blasi_state *st = calloc(1, sizeof *st);
    if (!st) {
        err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory", s->source);
        return NULL;
    }
    const blasi_options *o = blasi_opts(s);
    st->nm = s->nmedia;
    st->step = o->step;
    st->threshold = o->threshold;
    st->exit = o->exit_deposit;
    st->view = o->view_attenuation;
    st->gather_printed = o->gather == BLASI_GATHER_PRINTED;
    for (int i = 0; i < s->nlights; i++) {
        const light *l = &s->lights[i];
        st->area_lights |= l->kind == LIGHT_SPHERE || l->kind == LIGHT_DISK;
        st->sun_disks |= l->kind == LIGHT_DISTANT && l->angular_radius > 0.0;
    }
    st->bounds = box3_empty();
    return st;
}

/* The blob fields voxelized at blasi.voxels, one realization of Stam's random field
 * (stam.eps; scene/stam_media.h): bm->vox. A blob field without blasi.voxels is refused. */
static brume_status voxelize_blobs(const brume_scene *s, blasi_state *st)
{
    const blasi_options *o = blasi_opts(s);
    bool any = false;
    for (int m = 0; m < st->nm; m++) {
        const medium *md = &s->media[m];
        if (!density_get_blobs(md->rho))
            continue;
        any = true;
        if (o->voxels <= 0) /* a blob field has no voxels of its own; a silent coarse grid would not be Stam's field */
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: media[%d]%s%s: method blasi renders voxel grids and this medium is a blob field: give "
                           "blasi.voxels=N (e.g. --set blasi.voxels=128) to render one realization of it (stam.eps) "
                           "on N cells along its longest axis, or use --method stam, path or single",
                           s->source, m, md->name[0] ? " " : "", md->name);
    }
    if (!any)
        return BRUME_OK;
    density *grids[SCENE_MAX_MEDIA];
    if (stam_voxelize_blobs(s, o->voxels, true, "blasi.voxels", grids) != BRUME_OK)
        return err_status();
    for (int m = 0; m < st->nm; m++)
        st->m[m].vox = grids[m];
    return BRUME_OK;
}

/* Medium m's voxels, placement and coefficients (everything but its densities). */
static brume_status medium_setup(const brume_scene *s, blasi_state *st, int m)
{
    const blasi_options *o = blasi_opts(s);
    const medium *md = &s->media[m];
    blasi_medium *bm = &st->m[m];
    const density *rho = bm->vox ? bm->vox : md->rho;
    density_info info;
    density_get_info(rho, &info);
    bm->md = md;
    memcpy(bm->n, info.n, sizeof bm->n);
    bm->nvox = (size_t)info.n[0] * (size_t)info.n[1] * (size_t)info.n[2];
    bm->offset = st->nvox;
    if (st->nvox + bm->nvox > BLASI_MAX_VOXELS)
        return err_set(BRUME_ERROR_UNSUPPORTED,
                       "%s: media[%d] '%s': %d x %d x %d voxels; blasi keeps at most %u voxels over all media "
                       "(use a coarser grid)",
                       s->source, m, md->name, info.n[0], info.n[1], info.n[2], BLASI_MAX_VOXELS);
    st->nvox += bm->nvox;
    bm->volume = fabs(affine3_det(&info.voxel_to_world));
    bm->v2w = info.voxel_to_world;
    {   /* the voxel's edges in world space, for its surface area */
        vec3 c0 = affine3_apply(&bm->v2w, v3(0, 0, 0)), e[3];
        for (int a = 0; a < 3; a++)
            e[a] = v3_sub(affine3_apply(&bm->v2w, v3(a == 0, a == 1, a == 2)), c0);
        double area = 2.0 * (v3_length(v3_cross(e[0], e[1])) + v3_length(v3_cross(e[1], e[2])) +
                             v3_length(v3_cross(e[2], e[0])));
        bm->chord = area > 0.0 ? 4.0 * bm->volume / area : 0.0;
    }
    if (!affine3_invert(&info.voxel_to_world, &bm->w2v) || !(bm->volume > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: media[%d] '%s': singular grid placement", s->source, m, md->name);
    st->bounds = (box3){v3_min(st->bounds.lo, info.bounds.lo), v3_max(st->bounds.hi, info.bounds.hi)};
    bm->sigma_bar = col_avg(md->sigma_s);
    bm->sigma_t = col_add(md->sigma_a, md->sigma_s);
    bm->kappa = st->view == BLASI_VIEW_EXTINCTION ? bm->sigma_t : md->sigma_a;
    bm->emit = col_mul(md->sigma_a, md->Le);
    bm->emits = !col_is_black(bm->emit);
    bm->view_grey = col_is_grey(bm->kappa) && col_is_grey(bm->sigma_t);
    bm->trilinear = o->interpolate == BLASI_INTERPOLATE_TRILINEAR;
    split_phase(md->ph, &bm->r, &bm->dir);
    if (!isnan(o->r))
        bm->r = o->r;
    if (!isnan(o->kprime)) {
        bm->dir_owned = phase_new_schlick(o->kprime);
        bm->dir = bm->dir_owned;
        if (!bm->dir_owned)
            return err_prefix("%s: blasi.kprime", s->source);
    }
    return BRUME_OK;
}

/* A non-empty voxel (i, j, k) of bm widens the box and the diagonal slabs of them
 * (any: it is not the first). */
static void occupied_extend(blasi_medium *bm, int i, int j, int k, bool any)
{
    const int c[3] = {i, j, k};
    for (int a = 0; a < 3; a++) {
        bm->occ_lo[a] = !any || c[a] < bm->occ_lo[a] ? c[a] : bm->occ_lo[a];
        bm->occ_hi[a] = !any || c[a] + 1 > bm->occ_hi[a] ? c[a] + 1 : bm->occ_hi[a];
    }
    for (int sl = 0; sl < BLASI_SLABS; sl++) { /* the voxel's extent along n */
        const int *n = blasi_slab_n[sl];
        int lo = 0, hi = 0;
        for (int a = 0; a < 3; a++) {
            lo += n[a] * c[a] + (n[a] < 0 ? n[a] : 0);
            hi += n[a] * c[a] + (n[a] > 0 ? n[a] : 0);
        }
        bm->slab_lo[sl] = !any || lo < bm->slab_lo[sl] ? lo : bm->slab_lo[sl];
        bm->slab_hi[sl] = !any || hi > bm->slab_hi[sl] ? hi : bm->slab_hi[sl];
    }
    bm->occ[(size_t)(i / BLASI_BLOCK) +
            (size_t)bm->bn[0] * ((size_t)(j / BLASI_BLOCK) + (size_t)bm->bn[1] * (size_t)(k / BLASI_BLOCK))] = 1;
}

/* bm's densities into st->rho, constant per voxel (a trilinear medium's values into
 * st->field, their field's voxel means into st->rho), and what the walk skips by: the
 * occupancy blocks, the box and the diagonal slabs of the non-empty voxels. */
static brume_status medium_voxels(const brume_scene *s, blasi_state *st, blasi_medium *bm)
{
    size_t nblocks = 1;
    for (int a = 0; a < 3; a++) {
        bm->bn[a] = (bm->n[a] + BLASI_BLOCK - 1) / BLASI_BLOCK;
        nblocks *= (size_t)bm->bn[a];
    }
    bm->skip = bm->n[0] + bm->n[1] + bm->n[2] > BLASI_SKIP_CELLS;
    bm->occ = calloc(nblocks, 1);
    if (!bm->occ)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for %zu voxels", s->source, st->nvox);
    float *dst = (bm->trilinear ? st->field : st->rho) + bm->offset;
    for (int k = 0; k < bm->n[2]; k++)
        for (int j = 0; j < bm->n[1]; j++)
            for (int i = 0; i < bm->n[0]; i++)
                *dst++ = (float)density_voxel(bm->vox ? bm->vox : bm->md->rho, i, j, k);
    if (bm->trilinear)
        blasi_field_means(st, bm);
    const float *rho = st->rho + bm->offset;
    bool any = false; /* occ_lo, occ_hi stay 0 (calloc) for an empty grid */
    for (int k = 0; k < bm->n[2]; k++)
        for (int j = 0; j < bm->n[1]; j++)
            for (int i = 0; i < bm->n[0]; i++) {
                if (*rho++ != 0.0f) {
                    occupied_extend(bm, i, j, k, any);
                    any = true;
                }
            }
    for (int sl = 0; sl < BLASI_SLABS; sl++) { /* a millionth of a voxel wider: far more than
                                                 the rounding of a ray's clipping to them */
        bm->slab_lo[sl] -= 1e-6;
        bm->slab_hi[sl] += 1e-6;
    }
    return BRUME_OK;
}

/* The world box of each medium's non-empty voxels (for line_misses_box) and their union,
 * the box the light rays aim at, with its bounding sphere. */
static void light_box(blasi_state *st)
{
    st->light_box = box3_empty();
    for (int m = 0; m < st->nm; m++) {
        blasi_medium *bm = &st->m[m];
        bm->occ_c = v3(0.0, 0.0, 0.0);
        bm->occ_e = v3(-1.0, -1.0, -1.0); /* every line misses */
        if (bm->occ_hi[0] == 0)
            continue; /* no non-empty voxel */
        box3 b = affine3_apply_box(&bm->v2w, (box3){v3(bm->occ_lo[0], bm->occ_lo[1], bm->occ_lo[2]),
                                                    v3(bm->occ_hi[0], bm->occ_hi[1], bm->occ_hi[2])});
        st->light_box = (box3){v3_min(st->light_box.lo, b.lo), v3_max(st->light_box.hi, b.hi)};
        /* enlarged by 1e-9 of its size and place: far more than the rounding of the corners
         * and of the walk's own clipping in voxel space */
        bm->occ_c = v3_scale(v3_add(b.lo, b.hi), 0.5);
        vec3 e = v3_scale(v3_sub(b.hi, b.lo), 0.5);
        double pad = 1e-9 * (v3_length(e) + v3_length(bm->occ_c));
        bm->occ_e = v3(e.x + pad, e.y + pad, e.z + pad);
    }
    if (st->light_box.lo.x <= st->light_box.hi.x) {
        /* within the media's bounds (the corners' rounding must not take it outside) */
        st->light_box = (box3){v3_max(st->light_box.lo, st->bounds.lo), v3_min(st->light_box.hi, st->bounds.hi)};
        st->centre = v3_scale(v3_add(st->light_box.lo, st->light_box.hi), 0.5);
        st->radius = 0.5 * v3_length(v3_sub(st->light_box.hi, st->light_box.lo));
    }
}

/* Everything but the source: the media as voxels (blob fields voxelized), their
 * coefficients, the step limit, the densities and what the walk skips by. */
static brume_status media_setup(const brume_scene *s, blasi_state *st)
{
    brume_status rc = voxelize_blobs(s, st);
    for (int m = 0; m < st->nm && rc == BRUME_OK; m++)
        rc = medium_setup(s, st, m);
    if (rc != BRUME_OK)
        return rc;
    if (st->step > 0.0 && !(v3_length(v3_sub(st->bounds.hi, st->bounds.lo)) / st->step <= BLASI_MAX_STEPS))
        return err_set(BRUME_ERROR_RANGE,
                       "%s: blasi.step: %g is more than %.0f steps across the media (%g wide); use a longer step or "
                       "0 (voxel by voxel)",
                       s->source, st->step, BLASI_MAX_STEPS, v3_length(v3_sub(st->bounds.hi, st->bounds.lo)));
    if (st->nvox > 0) {
        st->rho = malloc(st->nvox * sizeof *st->rho);
        st->S = calloc(st->nvox * 3, sizeof *st->S);
        if (blasi_opts(s)->interpolate == BLASI_INTERPOLATE_TRILINEAR)
            st->field = malloc(st->nvox * sizeof *st->field);
        if (!st->rho || !st->S || (blasi_opts(s)->interpolate == BLASI_INTERPOLATE_TRILINEAR && !st->field))
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: blasi: out of memory for %zu voxels", s->source, st->nvox);
    }
    for (int m = 0; m < st->nm && rc == BRUME_OK; m++)
        rc = medium_voxels(s, st, &st->m[m]);
    if (rc == BRUME_OK)
        light_box(st);
    return rc;
}

brume_status blasi_prepare(const brume_scene *s, blasi_state **out)
{
    *out = NULL;
    double t0 = progress_now();
    const blasi_options *o = blasi_opts(s);
    /* before any work: the light file replaces only a brume light file, never the scene, one of
     * its inputs (the light file it loads included) or a device */
    const char *load = o->load_light[0] ? o->load_light : NULL;
    if (o->save_light[0] && io_output_check("blasi.save_light", o->save_light, BRUME_FILE_LIGHT,
                                            s->source[0] != '<' ? s->source : NULL, &s->inputs, &load, 1) != BRUME_OK)
        return err_status();
    for (int m = 0; m < s->nmedia; m++)
        if (s->media[m].moved) /* a velocity and an open shutter (medium.h) */
            return err_set(BRUME_ERROR_UNSUPPORTED,
                           "%s: media[%d].velocity: method blasi does not blur by velocity (its light pass is at the "
                           "frame time): use --method path or single, or a closed shutter",
                           s->source, m);
    blasi_state *st = state_new(s);
    if (!st)
        return err_status();
    brume_status rc = media_setup(s, st);
    if (rc == BRUME_OK)
        rc = o->load_light[0] ? load_light(o->load_light, s, st) : blasi_light_pass(s, st);
    if (rc == BRUME_OK && o->save_light[0])
        rc = save_light(o->save_light, s, st);
    if (rc != BRUME_OK) {
        blasi_finish(st);
        return rc;
    }
    st->stats.light_seconds = progress_now() - t0;
    *out = st;
    return BRUME_OK;
}

void blasi_get_stats(const blasi_state *st, blasi_stats *out) { *out = st->stats; }
