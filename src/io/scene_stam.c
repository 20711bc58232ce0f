/* scene_stam.c - scene-file keys of Stam's method: blob densities (explicit blobs, cloud,
 * cluster and fire generators, drift velocity) and the "stam" object (statistics of the
 * perturbation, renderer options, scene time, voxelization for the reference renderers). */
#include "io/scene_stam.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "density/blobs.h"
#include "density/randfield.h"
#include "render/stam.h"

static const double BIG = 1e30;

/* Majorant cells along the longest axis of a blob field, for path and single. */
#define BLOB_MAJORANT_CELLS 32

static brume_status parse_pair(const cJSON *j, jloc at, const char *key, double lo, double hi, double out[2])
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!it)
        return BRUME_OK;
    const cJSON *a = cJSON_GetArrayItem(it, 0), *b = cJSON_GetArrayItem(it, 1);
    if (!cJSON_IsArray(it) || cJSON_GetArraySize(it) != 2 || !cJSON_IsNumber(a) || !cJSON_IsNumber(b))
        return err_set(BRUME_ERROR_PARSE, "%s: %s.%s: expected [min, max]", at.file, at.path, key);
    double x = a->valuedouble, y = b->valuedouble;
    if (!(x >= lo && y <= hi && x <= y))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: need %g <= min <= max <= %g, got [%g, %g]", at.file, at.path,
                       key, lo, hi, x, y);
    out[0] = x;
    out[1] = y;
    return BRUME_OK;
}

/* radii: a number (a sphere) or [rx, ry, rz], each > 0 */
static brume_status parse_radii(const cJSON *j, jloc at, const char *key, int required, vec3 *out)
{
    const cJSON *it = cJSON_GetObjectItemCaseSensitive(j, key);
    if (cJSON_IsNumber(it)) {
        double r = 0.0;
        brume_status st = json_number(j, at, key, 1, 1e-12, BIG, &r);
        if (st == BRUME_OK)
            *out = v3(r, r, r);
        return st;
    }
    brume_status st = json_vec3(j, at, key, required, out);
    if (st == BRUME_OK && it && !(out->x > 0.0 && out->y > 0.0 && out->z > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: %s.%s: every semi-axis must be > 0", at.file, at.path, key);
    return st;
}

static brume_status parse_cloud_params(const cJSON *j, jloc at, blob_cloud_params *p)
{
    brume_status st;
    double h[2] = {0.1, 0.3};
    p->count = 100;
    p->density = 1.0;
    p->falloff = 1.0;
    p->seed = 1;
    if ((st = json_int(j, at, "count", 0, 1, 1 << 22, &p->count))) return st;
    if ((st = parse_pair(j, at, "h", 1e-9, BIG, h))) return st;
    if ((st = json_number(j, at, "density", 0, 0.0, BIG, &p->density))) return st;
    if ((st = json_number(j, at, "falloff", 0, 0.0, 100.0, &p->falloff))) return st;
    if ((st = json_u64(j, at, "seed", 0, &p->seed))) return st;
    p->h_min = h[0];
    p->h_max = h[1];
    return BRUME_OK;
}

static brume_status parse_generator(const cJSON *j, jloc at, blob_list *out)
{
    char type[32];
    brume_status st = json_object_type(j, at, type, sizeof type);
    if (st) return st;
    if (strcmp(type, "cloud") == 0) {
        static const char *const keys[] = {"type", "center", "radii", "count", "h", "density", "falloff", "seed", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        blob_cloud_params p;
        if ((st = parse_cloud_params(j, at, &p))) return st;
        if ((st = json_vec3(j, at, "center", 1, &p.center))) return st;
        if ((st = parse_radii(j, at, "radii", 1, &p.radii))) return st;
        st = blob_gen_cloud(&p, out);
    } else if (strcmp(type, "cluster") == 0) {
        static const char *const keys[] = {"type", "bounds_min", "bounds_max", "clouds", "radii_min", "radii_max",
                                           "count", "h", "density", "falloff", "seed", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        blob_cloud_params p;
        box3 box;
        vec3 rmin, rmax;
        int clouds = 4;
        if ((st = parse_cloud_params(j, at, &p))) return st;
        if ((st = json_vec3(j, at, "bounds_min", 1, &box.lo))) return st;
        if ((st = json_vec3(j, at, "bounds_max", 1, &box.hi))) return st;
        if ((st = parse_radii(j, at, "radii_min", 1, &rmin))) return st;
        if ((st = parse_radii(j, at, "radii_max", 1, &rmax))) return st;
        if ((st = json_int(j, at, "clouds", 0, 1, 100000, &clouds))) return st;
        if (!(box.lo.x <= box.hi.x && box.lo.y <= box.hi.y && box.lo.z <= box.hi.z))
            return err_set(BRUME_ERROR_RANGE, "%s: %s: need bounds_min <= bounds_max", at.file, at.path);
        st = blob_gen_cluster(&p, box, rmin, rmax, clouds, out);
    } else if (strcmp(type, "fire") == 0) {
        static const char *const keys[] = {"type", "base", "up", "height", "radius", "count", "h", "density", "band",
                                           "seed", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        blob_fire_params p = {.up = v3(0, 1, 0), .height = 1.0, .radius = 0.2, .count = 14, .h = 0.15,
                              .density = 1.0, .band_lo = 0.0, .band_hi = 1.0, .seed = 1};
        double band[2] = {0.0, 1.0};
        if ((st = json_vec3(j, at, "base", 1, &p.base))) return st;
        if ((st = json_vec3(j, at, "up", 0, &p.up))) return st;
        if ((st = json_number(j, at, "height", 0, 1e-9, BIG, &p.height))) return st;
        if ((st = json_number(j, at, "radius", 0, 0.0, BIG, &p.radius))) return st;
        if ((st = json_int(j, at, "count", 0, 1, 1 << 22, &p.count))) return st;
        if ((st = json_number(j, at, "h", 0, 1e-9, BIG, &p.h))) return st;
        if ((st = json_number(j, at, "density", 0, 0.0, BIG, &p.density))) return st;
        if ((st = parse_pair(j, at, "band", 0.0, 1.0, band))) return st;
        if ((st = json_u64(j, at, "seed", 0, &p.seed))) return st;
        p.band_lo = band[0];
        p.band_hi = band[1] >= 1.0 ? 1.0 + 1e-9 : band[1];
        st = blob_gen_fire(&p, out);
    } else {
        return err_set(BRUME_ERROR_PARSE, "%s: %s.type: unknown generator '%s' (known: cloud, cluster, fire)", at.file,
                       at.path, type);
    }
    return st ? err_prefix("%s: %s", at.file, at.path) : BRUME_OK;
}

brume_status scene_parse_blobs(const cJSON *j, jloc at, density **out)
{
    static const char *const keys[] = {"type", "blobs", "generators", "velocity", "cutoff", NULL};
    brume_status st = json_check_object(j, at, keys);
    if (st) return st;
    double cutoff = BLOB_DEFAULT_CUTOFF;
    vec3 velocity = v3(0, 0, 0);
    if ((st = json_number(j, at, "cutoff", 0, 1.0, 10.0, &cutoff))) return st;
    if ((st = json_vec3(j, at, "velocity", 0, &velocity))) return st;
    blob_list list = {0};
    const cJSON *arr = cJSON_GetObjectItemCaseSensitive(j, "blobs");
    if (arr) {
        if (!cJSON_IsArray(arr))
            return err_set(BRUME_ERROR_PARSE, "%s: %s.blobs: expected an array of [x, y, z, mass, h]", at.file, at.path);
        int i = 0;
        for (const cJSON *e = arr->child; e; e = e->next, i++) {
            double v[5];
            int k = 0;
            for (const cJSON *c = cJSON_IsArray(e) ? e->child : NULL; c && k < 6; c = c->next, k++)
                if (k < 5)
                    v[k] = cJSON_IsNumber(c) ? c->valuedouble : (double)NAN;
            if (k != 5 || !isfinite(v[0] + v[1] + v[2] + v[3] + v[4]) || v[3] < 0.0 || !(v[4] > 0.0)) {
                blob_list_free(&list);
                return err_set(BRUME_ERROR_PARSE, "%s: %s.blobs[%d]: expected [x, y, z, mass >= 0, h > 0]", at.file,
                               at.path, i);
            }
            if ((st = blob_list_push(&list, (blob){v3(v[0], v[1], v[2]), v[3], v[4]}))) {
                blob_list_free(&list);
                return st;
            }
        }
    }
    const cJSON *gens = cJSON_GetObjectItemCaseSensitive(j, "generators");
    if (gens) {
        if (!cJSON_IsArray(gens)) {
            blob_list_free(&list);
            return err_set(BRUME_ERROR_PARSE, "%s: %s.generators: expected an array", at.file, at.path);
        }
        int i = 0;
        for (const cJSON *g = gens->child; g; g = g->next, i++) {
            char kp[300];
            snprintf(kp, sizeof kp, "%s.generators[%d]", at.path, i);
            if ((st = parse_generator(g, (jloc){at.file, kp}, &list))) {
                blob_list_free(&list);
                return st;
            }
        }
    }
    if (list.n == 0)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: no blobs (give \"blobs\" or \"generators\")", at.file, at.path);
    char who[300];
    snprintf(who, sizeof who, "%s: %s", at.file, at.path);
    blob_field *f = blob_field_new(list.b, list.n, cutoff, who);
    blob_list_free(&list);
    if (!f)
        return err_status();
    f->velocity = velocity;
    *out = density_new_blobs(f, BLOB_MAJORANT_CELLS);
    if (!*out) {
        blob_field_release(f);
        return err_prefix("%s", who);
    }
    return BRUME_OK;
}

/* Replaces each blob field by a dense grid (trilinear) of its mean, or of one realization. */
static brume_status voxelize_media(brume_scene *s, int resolution, bool realization, jloc at)
{
    randfield *q = NULL;
    if (realization) {
        randfield_params rp;
        stam_randfield_params(&s->stam, stam_blob_extent(s), &rp);
        if (!(q = randfield_new(&rp)))
            return err_prefix("%s: %s.voxelize", at.file, at.path);
    }
    brume_status st = BRUME_OK;
    for (int m = 0; m < s->nmedia && st == BRUME_OK; m++) {
        blob_field *f = density_get_blobs(s->media[m].rho);
        if (!f)
            continue;
        char who[600];
        snprintf(who, sizeof who, "%s: stam.voxelize", at.file);
        density *g = blob_field_grid(f, resolution, q, s->stam.eps, s->stam.eta, who);
        if (!g) {
            st = err_status();
            break;
        }
        density_release(s->media[m].rho);
        s->media[m].rho = g;
    }
    randfield_release(q);
    return st;
}

brume_status scene_parse_stam(const cJSON *root, brume_scene *s)
{
    const cJSON *j = cJSON_GetObjectItemCaseSensitive(root, "stam");
    jloc at = {s->source, "stam"};
    stam_params *p = &s->stam;
    int resolution = 0;
    bool realization = true;
    brume_status st;
    if (j) {
        static const char *const keys[] = {"eps", "eta", "alpha", "lattice", "cell", "seed", "time", "rate",
                                           "ambient", "steps", "light_grid", "bvh", "voxelize", "variant", NULL};
        if ((st = json_check_object(j, at, keys))) return st;
        if ((st = json_number(j, at, "eps", 0, 0.0, BIG, &p->eps))) return st;
        if ((st = json_number(j, at, "eta", 0, 1e-30, BIG, &p->eta))) return st;
        if ((st = json_number(j, at, "alpha", 0, 1e-9, BIG, &p->alpha))) return st;
        if ((st = json_int(j, at, "lattice", 0, 0, 512, &p->lattice))) return st;
        if (p->lattice == 1)
            return err_set(BRUME_ERROR_RANGE, "%s: stam.lattice: 1 is not 0 (automatic) or in [2, 512]", s->source);
        if ((st = json_number(j, at, "cell", 0, 0.0, BIG, &p->cell))) return st;
        if ((st = json_u64(j, at, "seed", 0, &p->seed))) return st;
        if ((st = json_number(j, at, "time", 0, -BIG, BIG, &p->time))) return st;
        if ((st = json_number(j, at, "rate", 0, 0.0, BIG, &p->rate))) return st;
        if ((st = json_color(j, at, "ambient", 0, 0.0, BIG, &p->ambient))) return st;
        if ((st = json_int(j, at, "steps", 0, 1, 256, &p->steps))) return st;
        if ((st = json_int(j, at, "light_grid", 0, 0, 512, &p->light_grid))) return st;
        if ((st = json_bool(j, at, "bvh", 0, &p->bvh))) return st;
        char variant[32] = "";
        if ((st = json_string(j, at, "variant", 0, variant, sizeof variant))) return st;
        if (variant[0]) {
            if (strcmp(variant, "paper") != 0 && strcmp(variant, "corrected") != 0)
                return err_set(BRUME_ERROR_PARSE, "%s: stam.variant: unknown variant '%s' (known: paper, corrected)",
                               s->source, variant);
            p->paper = variant[0] == 'p';
        }
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, "voxelize");
        if (v) {
            static const char *const vkeys[] = {"resolution", "realization", NULL};
            jloc vat = {s->source, "stam.voxelize"};
            if ((st = json_check_object(v, vat, vkeys))) return st;
            if ((st = json_int(v, vat, "resolution", 1, 2, 2048, &resolution))) return st;
            if ((st = json_bool(v, vat, "realization", 0, &realization))) return st;
        }
    }
    /* the frame's time (docs/animation.md) adds to the scene's own stam.time: blobs drift
     * and Q evolves from frame to frame, so the world is not static */
    p->time += s->time;
    for (int m = 0; m < s->nmedia; m++) {
        blob_field *f = density_get_blobs(s->media[m].rho);
        if (!f)
            continue;
        if (v3_length(f->velocity) > 0.0 || p->rate > 0.0)
            s->world_moves = true;
        f->use_bvh = p->bvh;
        if (p->time != 0.0 && v3_length(f->velocity) > 0.0 &&
            (st = density_blobs_at_time(s->media[m].rho, f->velocity, p->time)))
            return err_prefix("%s: media[%d]", s->source, m);
    }
    return resolution > 0 ? voxelize_media(s, resolution, realization, at) : BRUME_OK;
}
