/* pbrt_media.c - pbrt's MakeNamedMedium (homogeneous, uniformgrid, rgbgrid, nanovdb, cloud) as
 * brume's media; a medium is emitted when a shape first uses it (pbrt_shapes.c). */
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

/* The coefficients every pbrt medium shares: brume's sigma per unit density is pbrt's sigma
 * times `scale` (pbrt-v4: sigma_a(p) = scale sigma_a d(p), the same for sigma_s), HG g as is.
 * A new medium object with name, sigma_a, sigma_s and phase; NULL after a refusal. */
static cJSON *medium_new(lexer *L, const char *name, const double sa[3], const double ss[3], double scale, double g)
{
    if (!(g > -1.0 && g < 1.0)) {
        pbrt_fail(L, "MakeNamedMedium \"%s\": parameter \"g\": %g outside (-1, 1)", name, g);
        return NULL;
    }
    if (!(scale >= 0.0) || sa[0] < 0 || sa[1] < 0 || sa[2] < 0 || ss[0] < 0 || ss[1] < 0 || ss[2] < 0) {
        pbrt_fail(L, "MakeNamedMedium \"%s\": negative sigma_a, sigma_s or scale", name);
        return NULL;
    }
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "name", name);
    double a3[3] = {sa[0] * scale, sa[1] * scale, sa[2] * scale}, s3[3] = {ss[0] * scale, ss[1] * scale, ss[2] * scale};
    cJSON_AddItemToObject(m, "sigma_a", cJSON_CreateDoubleArray(a3, 3));
    cJSON_AddItemToObject(m, "sigma_s", cJSON_CreateDoubleArray(s3, 3));
    cJSON *ph = cJSON_AddObjectToObject(m, "phase");
    cJSON_AddStringToObject(ph, "type", "hg");
    cJSON_AddNumberToObject(ph, "g", g);
    return m;
}

/* The transform at MakeNamedMedium (pbrt's renderFromMedium) as the density's `transform`
 * (none when it is the identity); false after a refusal (shear). */
static bool medium_place(pbrt_state *S, cJSON *dj, const char *name)
{
    m4 ctm = S->a[S->depth].ctm;
    m4 id = pbrt_m4_identity();
    if (memcmp(&ctm, &id, sizeof id) == 0)
        return true;
    bool oom;
    cJSON *t = pbrt_transform_json(ctm, &oom);
    if (!t) {
        if (oom)
            pbrt_fail(&S->L, "MakeNamedMedium \"%s\": out of memory", name);
        else
            pbrt_unsupported(&S->L, "MakeNamedMedium \"%s\": a transform with shear (brume places grids by scale, rotation, "
                                    "translation)", name);
        return false;
    }
    cJSON_AddItemToObject(dj, "transform", t);
    return true;
}

/* Adds the medium m (owned from here) to the named media. */
static brume_status medium_add(pbrt_state *S, const char *name, cJSON *m, bool homogeneous)
{
    if (S->nmedia == PBRT_MAX_MEDIA) {
        cJSON_Delete(m);
        return pbrt_fail(&S->L, "MakeNamedMedium \"%s\": more than %d media", name, PBRT_MAX_MEDIA);
    }
    named_medium *nm = &S->media[S->nmedia++];
    pbrt_copy(nm->name, sizeof nm->name, name);
    nm->json = m;
    nm->emitted = false;
    nm->homogeneous = homogeneous;
    for (int k = 0; k < 3; k++) {
        nm->box[k] = INFINITY;
        nm->box[3 + k] = -INFINITY;
    }
    return BRUME_OK;
}

/* The smallest positive channel of a medium's sigma_a + sigma_s; INFINITY when none is. */
static double medium_sigma_t_min(const cJSON *m)
{
    double sigma_t = INFINITY;
    const cJSON *sa = cJSON_GetObjectItemCaseSensitive(m, "sigma_a");
    const cJSON *ss = cJSON_GetObjectItemCaseSensitive(m, "sigma_s");
    for (int c = 0; c < 3; c++) {
        double t = cJSON_GetArrayItem(sa, c)->valuedouble + cJSON_GetArrayItem(ss, c)->valuedouble;
        if (t > 0.0)
            sigma_t = fmin(sigma_t, t);
    }
    return sigma_t;
}

/* The named medium, or NULL. */
static named_medium *medium_find(pbrt_state *S, const char *name)
{
    for (int i = 0; i < S->nmedia; i++)
        if (strcmp(S->media[i].name, name) == 0)
            return &S->media[i];
    return NULL;
}

/* Emits nm into the scene's media (once) and grows a homogeneous one's box by box (lo, hi),
 * widened by w on every side. */
static void medium_emit(pbrt_state *S, named_medium *nm, const double box[6], double w)
{
    if (!nm->emitted) {
        cJSON_AddItemToArray(S->media_j, nm->json);
        nm->emitted = true;
    }
    for (int k = 0; box && nm->homogeneous && k < 3; k++) {
        nm->box[k] = fmin(nm->box[k], box[k] - w);
        nm->box[3 + k] = fmax(nm->box[3 + k], box[3 + k] + w);
    }
}

brume_status pbrt_medium_use(pbrt_state *S, const char *name, const double box[6], bool outside)
{
    named_medium *nm = medium_find(S, name);
    if (!nm)
        return pbrt_fail(&S->L, "MediumInterface: no medium named \"%s\"", name);
    double sigma_t = nm->homogeneous ? medium_sigma_t_min(nm->json) : (double)INFINITY;
    /* a margin: the shape's facets and points lie inside the box, not on its faces (and a
     * flat shape's box has some depth) */
    double b[6], size = box ? fmax(box[3] - box[0], fmax(box[4] - box[1], box[5] - box[2])) : 0.0;
    for (int k = 0; box && k < 3; k++) {
        double pad = 1e-4 * size + 1e-9 * fmax(fabs(box[k]), fabs(box[3 + k])) + 1e-300;
        b[k] = box[k] - pad;
        b[3 + k] = box[3 + k] + pad;
    }
    medium_emit(S, nm, box ? b : NULL, outside && isfinite(sigma_t) ? 64.0 / sigma_t : 0.0);
    return BRUME_OK;
}

brume_status pbrt_medium_bind(pbrt_state *S, const char *name, const double box[6], bool outside)
{
    if (medium_find(S, name))
        return pbrt_medium_use(S, name, box, outside);
    if (S->npending >= 1 << 20)
        return pbrt_fail(&S->L, "MediumInterface: more than %d shapes name media not defined yet", 1 << 20);
    pbrt_pending_medium *p = realloc(S->pending, sizeof *p * (size_t)(S->npending + 1));
    size_t n = strlen(S->L.file) + 1;
    char *file = malloc(n);
    if (file)
        memcpy(file, S->L.file, n);
    if (!p || !file) {
        free(file);
        if (p)
            S->pending = p;
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: out of memory", S->L.file, S->L.dir_line);
    }
    S->pending = p;
    p = &S->pending[S->npending++];
    pbrt_copy(p->name, sizeof p->name, name);
    memcpy(p->box, box, sizeof p->box);
    p->outside = outside;
    p->file = file;
    p->line = S->L.dir_line;
    return BRUME_OK;
}

brume_status pbrt_media_resolve(pbrt_state *S)
{
    brume_status st = BRUME_OK;
    for (int i = 0; i < S->npending && st == BRUME_OK; i++) {
        const pbrt_pending_medium *p = &S->pending[i];
        if (!medium_find(S, p->name))
            st = err_set(BRUME_ERROR_PARSE, "%s:%d: MediumInterface: no medium named \"%s\" (no MakeNamedMedium in the "
                         "scene gives it)", p->file, p->line, p->name);
        else
            st = pbrt_medium_use(S, p->name, p->box, p->outside);
    }
    pbrt_media_free(S);
    return st;
}

void pbrt_media_free(pbrt_state *S)
{
    for (int i = 0; i < S->npending; i++)
        free(S->pending[i].file);
    free(S->pending);
    S->pending = NULL;
    S->npending = 0;
}

brume_status pbrt_media_finish(pbrt_state *S)
{
    for (int i = 0; i < S->nmedia; i++) {
        named_medium *nm = &S->media[i];
        if (!nm->emitted || !nm->homogeneous)
            continue;
        double *b = nm->box;
        if (!(b[0] <= b[3] && b[1] <= b[4] && b[2] <= b[5])) /* no extent asked: no extinction either */
            b[0] = b[1] = b[2] = -1.0, b[3] = b[4] = b[5] = 1.0;
        double reach = 0.0;
        for (int k = 0; k < 6; k++)
            reach = fmax(reach, fabs(b[k]));
        if (!(reach <= 1e17))
            return pbrt_fail(&S->L, "MakeNamedMedium \"%s\": the homogeneous medium would reach %g from the origin "
                                    "(64 / sigma_t past what it bounds); brume traces rays within 1e18", nm->name,
                             reach);
        cJSON *d = cJSON_AddObjectToObject(nm->json, "density");
        cJSON_AddStringToObject(d, "type", "constant");
        cJSON_AddNumberToObject(d, "value", 1);
        cJSON *bounds = cJSON_AddArrayToObject(d, "bounds");
        cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(b, 3));
        cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(b + 3, 3));
    }
    return BRUME_OK;
}

/* pbrt's grid media (uniformgrid, rgbgrid): n = nx ny nz samples d (x fastest) at the
 * centres of the cells of [p0, p1], read trilinearly with samples beyond the grid taken as
 * 0, so the field falls to d/2 at the faces, and 0 outside [p0, p1] (pbrt-v4's SampledGrid
 * and the grid media's bounds): brume's `array` density with `edge` "zero", which is that
 * field exactly (its zero layer counts against the inline limit). Placed by the transform at
 * MakeNamedMedium (docs/pbrt.md). */
static cJSON *grid_density(pbrt_state *S, const char *name, const double *d, const int n[3], const double p0[3],
                           const double p1[3])
{
    char what[200];
    snprintf(what, sizeof what, "MakeNamedMedium \"%s\"", name);
    if (pbrt_count_inline(S, what, (double)(n[0] + 2) * (n[1] + 2) * (n[2] + 2)))
        return NULL;
    cJSON *dj = cJSON_CreateObject();
    cJSON_AddStringToObject(dj, "type", "array");
    cJSON_AddItemToObject(dj, "dims", cJSON_CreateIntArray(n, 3));
    cJSON *data = cJSON_AddArrayToObject(dj, "data");
    size_t count = (size_t)n[0] * (size_t)n[1] * (size_t)n[2];
    for (size_t i = 0; i < count; i++)
        cJSON_AddItemToArray(data, cJSON_CreateNumber(d[i]));
    cJSON *bounds = cJSON_AddArrayToObject(dj, "bounds");
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(p0, 3));
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(p1, 3));
    cJSON_AddStringToObject(dj, "filter", "trilinear");
    cJSON_AddStringToObject(dj, "edge", "zero");
    if (!medium_place(S, dj, name)) {
        cJSON_Delete(dj);
        return NULL;
    }
    return dj;
}

/* A medium of the coefficients and the grid d (grid_density) added to the named media. */
static brume_status grid_medium_add(pbrt_state *S, const char *name, const double sa[3], const double ss[3],
                                    double scale, double g, const double *d, const int n[3], const double p0[3],
                                    const double p1[3])
{
    cJSON *m = medium_new(&S->L, name, sa, ss, scale, g);
    cJSON *dj = m ? grid_density(S, name, d, n, p0, p1) : NULL;
    if (!dj) {
        cJSON_Delete(m);
        return err_status();
    }
    cJSON_AddItemToObject(m, "density", dj);
    return medium_add(S, name, m, false);
}

/* nx, ny, nz, p0 and p1 of a grid medium, checked against the count of its values. */
static brume_status grid_shape(lexer *L, params *ps, const char *what, int count, int n[3], double p0[3], double p1[3])
{
    brume_status st;
    if ((st = pbrt_get_count(L, ps, "nx", &n[0])) || (st = pbrt_get_count(L, ps, "ny", &n[1])) ||
        (st = pbrt_get_count(L, ps, "nz", &n[2])) || (st = pbrt_get_point(L, ps, "p0", p0)) || (st = pbrt_get_point(L, ps, "p1", p1)))
        return st;
    double total = (double)n[0] * n[1] * n[2];
    if ((double)count != total)
        return pbrt_fail(L, "%s: %d values for nx ny nz = %d x %d x %d = %.0f", what, count, n[0], n[1], n[2], total);
    if ((double)(n[0] + 2) * (n[1] + 2) * (n[2] + 2) > SCENE_INLINE_MAX_VALUES)
        return pbrt_fail(L, "%s: %d x %d x %d samples, over the %d brume takes inline (a larger grid belongs in a "
                            "nanovdb file)", what, n[0], n[1], n[2], SCENE_INLINE_MAX_VALUES);
    for (int k = 0; k < 3; k++)
        if (!(p1[k] > p0[k]))
            return pbrt_fail(L, "%s: p1 must exceed p0 on every axis", what);
    return BRUME_OK;
}

/* "homogeneous": the coefficients everywhere inside the shapes that bound it; the density is
 * made at each such shape (shape_directive). */
static brume_status medium_homogeneous(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, Le[3] = {0, 0, 0}, scale = 1.0, g = 0.0, Lescale = 1.0;
    char preset[128] = "";
    if ((st = pbrt_get_string(L, ps, "preset", preset, sizeof preset))) return st;
    if (preset[0])
        return pbrt_unsupported(L, "MakeNamedMedium \"%s\": parameter \"preset\": brume has no table of pbrt's measured media "
                                   "(give sigma_a and sigma_s)", name);
    if ((st = pbrt_get_color(L, ps, "sigma_a", sa)) || (st = pbrt_get_color(L, ps, "sigma_s", ss)) ||
        (st = pbrt_get_float(L, ps, "scale", &scale)) || (st = pbrt_get_float(L, ps, "g", &g)) ||
        (st = pbrt_illuminant(L, ps, "Le", Le)) || (st = pbrt_get_float(L, ps, "Lescale", &Lescale)) ||
        (st = pbrt_all_used(L, ps, "MakeNamedMedium \"homogeneous\"")))
        return st;
    cJSON *m = medium_new(L, name, sa, ss, scale, g);
    if (!m)
        return err_status();
    if (Le[0] > 0 || Le[1] > 0 || Le[2] > 0) {
        /* pbrt emits Lescale Le at the rate sigma_a: brume's `emission` */
        if (!(Lescale >= 0) || Le[0] < 0 || Le[1] < 0 || Le[2] < 0) {
            cJSON_Delete(m);
            return pbrt_fail(L, "MakeNamedMedium \"%s\": negative Le or Lescale", name);
        }
        double e[3] = {Le[0] * Lescale, Le[1] * Lescale, Le[2] * Lescale};
        cJSON_AddItemToObject(m, "emission", cJSON_CreateDoubleArray(e, 3));
    }
    return medium_add(S, name, m, true);
}

/* "uniformgrid": a density grid d given inline, sigma(p) = scale sigma d(p). */
static brume_status medium_uniformgrid(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    static const char *const floats[] = {"float", NULL};
    const char *what = "MakeNamedMedium \"uniformgrid\"";
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, scale = 1.0, g = 0.0, p0[3] = {0, 0, 0}, p1[3] = {1, 1, 1}, t = 0;
    int n[3];
    param *d = NULL;
    if ((st = pbrt_get_array(L, ps, "density", floats, &d))) return st;
    if (!d)
        return pbrt_fail(L, "%s \"%s\": no \"float density\" values", what, name);
    if (pbrt_get(ps, "temperature"))
        return pbrt_unsupported(L, "%s: parameter \"temperature\": brume reads temperature grids from files (nanovdb), not "
                                   "inline", what);
    if (pbrt_get(ps, "Le") || pbrt_get(ps, "Lescale"))
        return pbrt_unsupported(L, "%s: parameters \"Le\" and \"Lescale\": pbrt-v4 scales Le by a Lescale grid read "
                                   "trilinearly (without one, a 1 x 1 x 1 grid that fades toward the faces); brume's "
                                   "emission is one colour or a grid from a file", what);
    if ((st = grid_shape(L, ps, what, d->n, n, p0, p1)) || (st = pbrt_get_color(L, ps, "sigma_a", sa)) ||
        (st = pbrt_get_color(L, ps, "sigma_s", ss)) || (st = pbrt_get_float(L, ps, "scale", &scale)) ||
        (st = pbrt_get_float(L, ps, "g", &g)) || (st = pbrt_get_float(L, ps, "temperaturescale", &t)) ||
        (st = pbrt_get_float(L, ps, "temperatureoffset", &t)) || (st = pbrt_get_float(L, ps, "temperaturecutoff", &t)) ||
        (st = pbrt_all_used(L, ps, what)))
        return st; /* the temperature mapping is read and unused: there is no temperature grid */
    for (int i = 0; i < d->n; i++)
        if (!(d->v[i] >= 0.0 && d->v[i] <= 1e30))
            return pbrt_fail(L, "%s: density value %d: %g outside [0, 1e30]", what, i, d->v[i]);
    return grid_medium_add(S, name, sa, ss, scale, g, d->v, n, p0, p1);
}

/* "rgbgrid": RGB grids of sigma_a and sigma_s (both: pbrt's default for a missing one is a
 * constant 1, which does not fade at the faces as the grid given does), times scale. brume's
 * medium is one density times one colour per coefficient, so the grid is taken when every
 * sample is d_i (c_a, c_s) for one pair of colours: d_i = the sample's largest coefficient,
 * each coefficient within 1e-5 of the grid's largest (values written with 6 digits); any
 * other grid is refused (docs/pbrt.md). */
static brume_status medium_rgbgrid(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    static const char *const rgbs[] = {"rgb", NULL};
    const char *what = "MakeNamedMedium \"rgbgrid\"";
    double scale = 1.0, g = 0.0, p0[3] = {0, 0, 0}, p1[3] = {1, 1, 1}, Lescale = 1.0;
    int n[3];
    param *A = NULL, *Sg = NULL;
    if ((st = pbrt_get_array(L, ps, "sigma_a", rgbs, &A)) || (st = pbrt_get_array(L, ps, "sigma_s", rgbs, &Sg))) return st;
    if (!A && !Sg)
        return pbrt_fail(L, "%s \"%s\": neither \"rgb sigma_a\" nor \"rgb sigma_s\" values", what, name);
    if (pbrt_get(ps, "Le"))
        return pbrt_unsupported(L, "%s: parameter \"Le\": an RGB emission grid; brume reads emission grids from files", what);
    if (!A || !Sg)
        return pbrt_unsupported(L, "%s: no \"rgb %s\" grid: pbrt then takes %s as 1 up to the faces while the other grid fades "
                                   "to half its outer samples there, which one density cannot carry", what,
                                A ? "sigma_s" : "sigma_a", A ? "sigma_s" : "sigma_a");
    if (A->n % 3 || Sg->n % 3 || A->n != Sg->n)
        return pbrt_fail(L, "%s: sigma_a and sigma_s must be RGB triples, as many of each", what);
    int count = A->n / 3;
    if ((st = grid_shape(L, ps, what, count, n, p0, p1)) || (st = pbrt_get_float(L, ps, "scale", &scale)) ||
        (st = pbrt_get_float(L, ps, "g", &g)) || (st = pbrt_get_float(L, ps, "Lescale", &Lescale)) ||
        (st = pbrt_all_used(L, ps, what)))
        return st; /* Lescale is read and unused: it scales Le only */
    double *d = malloc((size_t)count * sizeof *d);
    if (!d)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s:%d: %s: out of memory", L->file, L->dir_line, what);
    int top = 0;
    for (int i = 0; i < count; i++) {
        d[i] = 0.0;
        for (int c = 0; c < 3; c++) {
            double a = A->v[3 * i + c], s = Sg->v[3 * i + c];
            if (!(a >= 0.0 && s >= 0.0 && a <= 1e30 && s <= 1e30)) {
                free(d);
                return pbrt_fail(L, "%s: sample %d: sigma_a or sigma_s outside [0, 1e30]", what, i);
            }
            d[i] = fmax(d[i], fmax(a, s));
        }
        if (d[i] > d[top])
            top = i;
    }
    double ca[3] = {0, 0, 0}, cs[3] = {0, 0, 0};
    for (int c = 0; c < 3 && d[top] > 0.0; c++) {
        ca[c] = A->v[3 * top + c] / d[top];
        cs[c] = Sg->v[3 * top + c] / d[top];
    }
    for (int i = 0; i < count; i++)
        for (int c = 0; c < 3; c++) {
            double a = A->v[3 * i + c], s = Sg->v[3 * i + c];
            if (fabs(a - d[i] * ca[c]) > 1e-5 * d[top] || fabs(s - d[i] * cs[c]) > 1e-5 * d[top]) {
                free(d);
                return pbrt_unsupported(L, "%s: sigma_a or sigma_s changes colour over the grid (sample %d against %d); "
                                           "brume's media are one density times one colour per coefficient", what, i, top);
            }
        }
    st = grid_medium_add(S, name, ca, cs, scale, g, d, n, p0, p1);
    free(d);
    return st;
}

static brume_status medium_nanovdb(pbrt_state *S, const char *name, params *ps);

/* "cloud": pbrt-v4's CloudMedium, sigma(p) = sigma d(p) with d its procedural density over
 * [p0, p1] (brume's pbrt_cloud density, docs/pbrt.md), placed by the transform at
 * MakeNamedMedium. pbrt-v4 reads no scale and no emission for it: those are refused. */
static brume_status medium_cloud(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    const char *what = "MakeNamedMedium \"cloud\"";
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, g = 0.0, dens = 1.0, wisp = 1.0, freq = 5.0;
    double p0[3] = {0, 0, 0}, p1[3] = {1, 1, 1};
    if ((st = pbrt_get_color(L, ps, "sigma_a", sa)) || (st = pbrt_get_color(L, ps, "sigma_s", ss)) ||
        (st = pbrt_get_float(L, ps, "g", &g)) || (st = pbrt_get_float(L, ps, "density", &dens)) ||
        (st = pbrt_get_float(L, ps, "wispiness", &wisp)) || (st = pbrt_get_float(L, ps, "frequency", &freq)) ||
        (st = pbrt_get_point(L, ps, "p0", p0)) || (st = pbrt_get_point(L, ps, "p1", p1)) ||
        (st = pbrt_all_used(L, ps, what)))
        return st;
    for (int a = 0; a < 3; a++)
        if (!(p1[a] > p0[a]))
            return pbrt_fail(L, "%s: p1 must exceed p0 on every axis", what);
    if (!(dens >= 0.0 && dens <= 1e30 && wisp >= 0.0 && wisp <= 1e30 && freq >= 0.0 && freq <= 1e30))
        return pbrt_fail(L, "%s: density, wispiness and frequency must be in [0, 1e30]", what);
    cJSON *m = medium_new(L, name, sa, ss, 1.0, g);
    if (!m)
        return err_status();
    cJSON *dj = cJSON_AddObjectToObject(m, "density");
    cJSON_AddStringToObject(dj, "type", "pbrt_cloud");
    cJSON_AddNumberToObject(dj, "density", dens);
    cJSON_AddNumberToObject(dj, "wispiness", wisp);
    cJSON_AddNumberToObject(dj, "frequency", freq);
    cJSON *bounds = cJSON_AddArrayToObject(dj, "bounds");
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(p0, 3));
    cJSON_AddItemToArray(bounds, cJSON_CreateDoubleArray(p1, 3));
    if (!medium_place(S, dj, name)) {
        cJSON_Delete(m);
        return err_status();
    }
    return medium_add(S, name, m, false);
}

brume_status pbrt_medium_directive(pbrt_state *S, const char *name, params *ps)
{
    char type[64] = "";
    brume_status st = pbrt_get_string(&S->L, ps, "type", type, sizeof type);
    if (st)
        return st;
    if (strcmp(type, "nanovdb") == 0)
        return medium_nanovdb(S, name, ps);
    if (strcmp(type, "homogeneous") == 0)
        return medium_homogeneous(S, name, ps);
    if (strcmp(type, "uniformgrid") == 0)
        return medium_uniformgrid(S, name, ps);
    if (strcmp(type, "rgbgrid") == 0)
        return medium_rgbgrid(S, name, ps);
    if (strcmp(type, "cloud") == 0)
        return medium_cloud(S, name, ps);
    return pbrt_unsupported(&S->L, "MakeNamedMedium type \"%s\": not supported by brume (homogeneous, uniformgrid, rgbgrid, "
                                   "nanovdb, cloud)", type);
}

/* The nanovdb medium's emission scale: pbrt-v4 reads "Lescale", as for its other media;
 * pbrt-v4-scenes' explosion writes "LeScale". Either spelling, not both. */
static brume_status nanovdb_lescale(lexer *L, params *ps, double *out)
{
    bool lower = pbrt_get(ps, "Lescale") != NULL, upper = pbrt_get(ps, "LeScale") != NULL;
    if (lower && upper)
        return pbrt_fail(L, "MakeNamedMedium \"nanovdb\": both \"Lescale\" and \"LeScale\" (one emission scale)");
    return pbrt_get_float(L, ps, upper ? "LeScale" : "Lescale", out);
}

static brume_status medium_nanovdb(pbrt_state *S, const char *name, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    char file[1024] = "", gname[128] = "density", tname[128] = "temperature";
    double sa[3] = {1, 1, 1}, ss[3] = {1, 1, 1}, scale = 1.0, g = 0.0, Lescale = 1.0, tscale = 1.0, toff = 0.0,
           tcut = 0.0;
    /* pbrt-v4 names the grids it reads: "gridname" (density) and "temperaturename" */
    if ((st = pbrt_get_string(L, ps, "gridname", gname, sizeof gname)) ||
        (st = pbrt_get_string(L, ps, "temperaturename", tname, sizeof tname)))
        return st;
    if ((st = pbrt_get_string(L, ps, "filename", file, sizeof file)) || (st = pbrt_get_color(L, ps, "sigma_a", sa)) ||
        (st = pbrt_get_color(L, ps, "sigma_s", ss)) || (st = pbrt_get_float(L, ps, "scale", &scale)) ||
        (st = pbrt_get_float(L, ps, "g", &g)) || (st = nanovdb_lescale(L, ps, &Lescale)) ||
        (st = pbrt_get_float(L, ps, "temperaturescale", &tscale)) || (st = pbrt_get_float(L, ps, "temperaturecutoff", &tcut)))
        return st;
    toff = tcut; /* pbrt-v4: temperatureoffset defaults to temperaturecutoff */
    if ((st = pbrt_get_float(L, ps, "temperatureoffset", &toff))) return st;
    if ((st = pbrt_all_used(L, ps, "MakeNamedMedium \"nanovdb\"")))
        return st;
    if (!file[0])
        return pbrt_fail(L, "MakeNamedMedium \"%s\": no \"string filename\"", name);
    char abs[PATH_MAX], what[200];
    snprintf(what, sizeof what, "MakeNamedMedium \"%s\"", name);
    if ((st = pbrt_resolve_file(S, what, file, abs)))
        return st;
    /* pbrt reads the file's temperature grid ("temperaturename") when it has one */
    bool has_temp = false;
    gridvdb_info *gi = NULL;
    int ng = 0;
    if (grid_list_file(abs, 0, &gi, &ng) != BRUME_OK)
        return err_prefix("%s:%d: MakeNamedMedium \"%s\"", L->file, L->dir_line, name);
    for (int i = 0; i < ng; i++)
        has_temp |= strcmp(gi[i].name, tname) == 0;
    free(gi);
    cJSON *m = medium_new(L, name, sa, ss, scale, g);
    if (!m)
        return err_status();
    cJSON *d = cJSON_AddObjectToObject(m, "density");
    cJSON_AddStringToObject(d, "type", "grid");
    cJSON_AddStringToObject(d, "file", abs);
    cJSON_AddStringToObject(d, "grid", gname);
    cJSON_AddStringToObject(d, "edge", "zero"); /* pbrt-v4's NanoVDB lookup (docs/scene-format.md) */
    if (!medium_place(S, d, name)) {
        cJSON_Delete(m);
        return err_status();
    }
    if (has_temp && Lescale > 0.0) { /* pbrt-v4 emits only with a positive LeScale */
        /* pbrt-v4: T' = (T - offset) scale; above 100 K, Le = Lescale B(T') with B the
           peak-normalized blackbody, emitted at the rate sigma_a rho Le: brume's model. Its
           film's Y is the integral of y-bar times the spectrum, unnormalized (every light
           divides that out of its spectrum; this Le does not), where brume's B has the Y of
           that integral over the integral of y-bar, CIE_Y_integral = 106.856895 */
        cJSON *t = cJSON_AddObjectToObject(m, "temperature");
        cJSON_AddStringToObject(t, "grid", tname);
        cJSON *bb = cJSON_AddObjectToObject(m, "blackbody");
        cJSON_AddNumberToObject(bb, "scale", Lescale * 106.856895);
        cJSON_AddNumberToObject(bb, "temperature_scale", tscale);
        cJSON_AddNumberToObject(bb, "temperature_offset", toff);
        cJSON_AddNumberToObject(bb, "cutoff", 100);
    }
    return medium_add(S, name, m, false);
}

/* The camera's medium (the outside one of the MediumInterface at Camera), with the camera at
 * position (world) and its JSON object cam, once the scene is read. A grid medium is its
 * field, bounded as in pbrt-v4: added as it is. A homogeneous one is unbounded in pbrt-v4
 * (shapes end it only where their MediumInterface says so: then it is a bounded medium,
 * docs/pbrt.md): its constant density's box holds the cube of half-side
 * 64 / sigma_t (the smallest positive channel) around the camera, beyond which whatever
 * reaches the camera has crossed an optical depth of 64 in pbrt-v4 too (a transmittance of
 * 1.6e-28; a channel of sigma_t 0 crosses nothing either way). pbrt-v4 attenuates distant and
 * infinite lights there over twice the scene's radius, which a bounded medium cannot follow:
 * they are refused. cam gets "medium". */
brume_status pbrt_camera_medium(pbrt_state *S, cJSON *cam, vec3 position)
{
    const char *name = S->camera_medium;
    if (!name[0])
        return BRUME_OK;
    lexer *L = &S->L;
    L->dir_line = S->camera_line;
    named_medium *nm = medium_find(S, name);
    if (!nm)
        return pbrt_fail(L, "Camera: its MediumInterface names no medium \"%s\"", name);
    if (!nm->homogeneous) {
        medium_emit(S, nm, NULL, 0.0);
        return BRUME_OK;
    }
    double sigma_t = medium_sigma_t_min(nm->json);
    if (!isfinite(sigma_t)) /* no extinction and so no emission: the camera sees through it */
        return BRUME_OK;
    if (S->far_light_line) {
        L->dir_line = S->far_light_line;
        return pbrt_unsupported(L, "LightSource \"%s\" with the camera in the homogeneous medium \"%s\": pbrt-v4 attenuates "
                                   "this light over twice the scene's radius of that unbounded medium, which brume's bounded "
                                   "media cannot follow", S->far_light, name);
    }
    double h = 64.0 / sigma_t;
    double reach = h + fmax(fabs(position.x), fmax(fabs(position.y), fabs(position.z)));
    if (!(reach <= 1e17))
        return pbrt_fail(L, "Camera: its medium \"%s\" (sigma_t %g) would reach %g from the origin; brume traces "
                            "rays within 1e18", name, sigma_t, reach);
    double cube[6] = {position.x, position.y, position.z, position.x, position.y, position.z};
    medium_emit(S, nm, cube, h);
    cJSON_AddStringToObject(cam, "medium", name);
    return BRUME_OK;
}
