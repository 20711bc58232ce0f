/* checkpoint.c - the checkpoint file of a render job: brume_render_job_save and
 * brume_render_job_resume (format in docs/render-jobs.md).
 *
 * Layout, every number in the writing machine's byte order (the marker tells which):
 *   "BRUMECKP"  u32 format (1)  u32 0x01020304  char[32] brume build  u64 scene key
 *   settings:   i32 width height spp min_spp max_depth filter  u32 aovs  i32 part nparts
 *               i32 sampler (0 independent, 1 sobol; 0 in checkpoints older than the field, which
 *               filled padding that was written as 0)  u64 seed  f64 filter_width noise_target
 *               char[32] method
 *   job:        i32 spp_done target  f64 elapsed  u64 pixels
 *   per pixel:  u32 n[pixels]  u8 active[pixels]  f64 sum[4 pixels]  f64 sq[4 pixels]
 *               f64 aov[8 pixels] (only when depth, albedo or normal are asked)
 *   u64 FNV-1a hash of every byte before it
 * The build is the version and BRUME_BUILD_ID, a hash of the sources, compiler and flags
 * (cmake/build_id.cmake): a render resumes only in the build that wrote it, since another
 * may draw its samples differently. A checkpoint is written atomically (io/atomic.c): it is
 * whole or absent. */
#include <errno.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "build_id.h"
#include "core/context.h"
#include "core/error.h"
#include "io/atomic.h"
#include "job/checkpoint.h"
#include "core/regular_file.h"
#include "render/job.h"
#include "scene/scene.h"

#define CKPT_FORMAT 1u
#define CKPT_ORDER 0x01020304u

typedef struct ckpt_settings {
    int32_t width, height, spp, min_spp, max_depth, filter;
    uint32_t aovs;
    int32_t part, nparts;
    int32_t sampler; /* brume_sampler; takes what was 4 bytes of padding before the seed */
    uint64_t seed;
    double filter_width, noise_target;
    char method[32];
} ckpt_settings;

_Static_assert(offsetof(ckpt_settings, seed) == 40, "ckpt_settings: the seed stays where format 1 put it");

typedef struct ckpt_header {
    char magic[8];
    uint32_t format, order;
    char version[32];
    uint64_t scene_key;
    ckpt_settings set;
    int32_t spp_done, target;
    double elapsed;
    uint64_t pixels;
} ckpt_header;

static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; i++) {
        h ^= p[i];
        h *= 0x100000001b3ULL;
    }
    return h;
}
#define FNV_START 0xcbf29ce484222325ULL

static void settings_record(const brume_render_job *job, ckpt_settings *c)
{
    memset(c, 0, sizeof *c);
    const brume_render_settings *rs = &job->rs;
    c->width = rs->width;
    c->height = rs->height;
    c->spp = rs->spp;
    c->min_spp = rs->min_spp;
    c->max_depth = rs->max_depth;
    c->filter = (int32_t)rs->filter;
    c->aovs = rs->aovs;
    c->part = job->part;
    c->nparts = job->nparts;
    c->sampler = (int32_t)rs->sampler;
    c->seed = rs->seed;
    c->filter_width = rs->filter_width;
    c->noise_target = rs->noise_target;
    snprintf(c->method, sizeof c->method, "%s", brume_method_name(rs->method)); /* the file keeps the name */
}

/* Writes n bytes and folds them into the hash. */
static bool put(FILE *fp, uint64_t *h, const void *data, size_t n)
{
    *h = fnv1a(*h, data, n);
    return fwrite(data, 1, n, fp) == n;
}

/* This build's name in checkpoints: the version and BRUME_BUILD_ID (22 characters). */
static void build_name(char out[32]) { snprintf(out, 32, "%s+%s", brume_version(), BRUME_BUILD_ID); }

brume_status brume_render_job_save(brume_context *ctx, const brume_render_job *job, uint64_t scene_key,
                                   const char *path)
{
    err_clear();
    if (!job || !path || !*path)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_job_save: %s: NULL",
                                       !job ? "job" : "path"));
    ckpt_header hd;
    memset(&hd, 0, sizeof hd);
    memcpy(hd.magic, "BRUMECKP", 8);
    hd.format = CKPT_FORMAT;
    hd.order = CKPT_ORDER;
    build_name(hd.version);
    hd.scene_key = scene_key;
    settings_record(job, &hd.set);
    size_t np = job->npix;
    hd.pixels = np;
    /* a consistent copy under the lock (every finished tile), written without it */
    uint32_t *n = malloc(np * sizeof *n);
    uint8_t *active = malloc(np);
    double *sum = malloc(np * JOB_SUMS * sizeof *sum), *sq = malloc(np * JOB_SQS * sizeof *sq);
    double *aov = job->trace_aovs ? malloc(np * JOB_AOVS * sizeof *aov) : NULL;
    if (!n || !active || !sum || !sq || (job->trace_aovs && !aov)) {
        free(n), free(active), free(sum), free(sq), free(aov);
        return ctx_report(ctx, err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for the checkpoint", path));
    }
    brume_render_job *j = (brume_render_job *)job; /* the lock only */
    pthread_mutex_lock(&j->lock);
    hd.spp_done = job->spp_done;
    hd.target = job->target;
    hd.elapsed = job->elapsed + (job->t_pass > 0.0 ? progress_now() - job->t_pass : 0.0);
    memcpy(n, job->n, np * sizeof *n);
    memcpy(active, job->active, np);
    memcpy(sum, job->sum, np * JOB_SUMS * sizeof *sum);
    memcpy(sq, job->sq, np * JOB_SQS * sizeof *sq);
    if (aov)
        memcpy(aov, job->aov, np * JOB_AOVS * sizeof *aov);
    pthread_mutex_unlock(&j->lock);

    atomic_file f;
    const void *owner = atomic_owner(ctx); /* the temporary file is ctx's (io/atomic.h) */
    brume_status st = atomic_open_kind(&f, path, BRUME_FILE_CHECKPOINT);
    atomic_owner(owner);
    if (st == BRUME_OK) {
        uint64_t h = FNV_START;
        bool ok = put(f.fp, &h, &hd, sizeof hd) && put(f.fp, &h, n, np * sizeof *n) && put(f.fp, &h, active, np) &&
                  put(f.fp, &h, sum, np * JOB_SUMS * sizeof *sum) && put(f.fp, &h, sq, np * JOB_SQS * sizeof *sq) &&
                  (!aov || put(f.fp, &h, aov, np * JOB_AOVS * sizeof *aov));
        uint64_t hash = h;
        ok = ok && fwrite(&hash, sizeof hash, 1, f.fp) == 1;
        if (!ok) {
            int e = errno;
            atomic_abort(&f);
            st = err_set(BRUME_ERROR_IO, "%s: cannot write the checkpoint: %s", path, strerror(e));
        } else {
            st = atomic_commit(&f);
        }
    }
    free(n), free(active), free(sum), free(sq), free(aov);
    return ctx_report(ctx, st);
}

/* The whole file in memory, at most max bytes (the largest checkpoint the scene can have): the
 * file must be a regular file (/dev/zero never ends) and no larger. err_set on failure. */
static brume_status slurp(const char *path, size_t max, unsigned char **data, size_t *size)
{
    *data = NULL;
    *size = 0;
    FILE *fp = NULL;
    if (io_open_regular(path, &fp) != BRUME_OK)
        return err_status(); /* "PATH: not a regular file (a device or socket)" */
    size_t cap = max < (1u << 16) ? max + 1 : (1u << 16), len = 0;
    unsigned char *buf = malloc(cap);
    for (;;) {
        if (!buf) {
            fclose(fp);
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory reading the checkpoint", path);
        }
        len += fread(buf + len, 1, cap - len, fp);
        if (len < cap)
            break;
        if (len > max) {
            free(buf);
            fclose(fp);
            return err_set(BRUME_ERROR_PARSE,
                           "%s: not a checkpoint of this scene: larger than its largest checkpoint (%zu bytes)", path,
                           max);
        }
        size_t ncap = cap > max / 2 ? max + 1 : 2 * cap;
        unsigned char *nb = realloc(buf, ncap);
        if (!nb)
            free(buf);
        buf = nb;
        cap = ncap;
    }
    bool bad = ferror(fp);
    fclose(fp);
    if (bad) {
        free(buf);
        return err_set(BRUME_ERROR_IO, "%s: cannot read the checkpoint", path);
    }
    *data = buf;
    *size = len;
    return BRUME_OK;
}

/* The first setting of the checkpoint that differs from this render's, as a message. */
static brume_status compare_settings(const char *path, const ckpt_settings *a, const ckpt_settings *b)
{
#define SAME_INT(field, key)                                                                                    \
    if (a->field != b->field)                                                                                 \
        return err_set(BRUME_ERROR_STATE, "%s: %s: the checkpoint has %lld, this render %lld", path, key,         \
                       (long long)a->field, (long long)b->field);
    SAME_INT(width, "render.width")
    SAME_INT(height, "render.height")
    SAME_INT(spp, "render.spp")
    SAME_INT(min_spp, "render.min_spp")
    SAME_INT(max_depth, "render.max_depth")
    SAME_INT(filter, "render.filter.type")
    SAME_INT(aovs, "aovs")
    SAME_INT(part, "render part")
    SAME_INT(nparts, "render parts")
    SAME_INT(seed, "render.seed")
    SAME_INT(sampler, "render.sampler")
#undef SAME_INT
    if (a->filter_width != b->filter_width)
        return err_set(BRUME_ERROR_STATE, "%s: render.filter.width: the checkpoint has %g, this render %g", path,
                       a->filter_width, b->filter_width);
    if (a->noise_target != b->noise_target)
        return err_set(BRUME_ERROR_STATE, "%s: render.noise: the checkpoint has %g, this render %g", path,
                       a->noise_target, b->noise_target);
    if (strncmp(a->method, b->method, sizeof a->method) != 0)
        return err_set(BRUME_ERROR_STATE, "%s: render.method: the checkpoint has '%.31s', this render '%.31s'", path,
                       a->method, b->method);
    return BRUME_OK;
}

/* Bytes per pixel of a checkpoint, with or without the AOV sums. */
static uint64_t pixel_bytes(bool aovs)
{
    return sizeof(uint32_t) + 1 + (uint64_t)(JOB_SUMS + JOB_SQS + (aovs ? JOB_AOVS : 0)) * sizeof(double);
}

/* The largest checkpoint a render of s can write: every pixel of the image, AOVs included. */
static size_t max_size(const brume_scene *s)
{
    brume_render_settings rs;
    brume_scene_settings(s, &rs);
    uint64_t np = (uint64_t)(rs.width > 0 ? rs.width : 0) * (uint64_t)(rs.height > 0 ? rs.height : 0);
    return (size_t)(sizeof(ckpt_header) + np * pixel_bytes(true) + sizeof(uint64_t));
}

/* The header of the checkpoint data (size bytes) into *hd, checked: magic, format, build,
 * size, checksum, scene and render part. Refusals are err_set's; data stays the caller's. */
static brume_status check_header(const char *path, const unsigned char *data, size_t size, uint64_t scene_key,
                                 ckpt_header *hd)
{
    if (size < sizeof *hd + sizeof(uint64_t) || memcmp(data, "BRUMECKP", 8) != 0) {
        bool magic = size >= 8 && memcmp(data, "BRUMECKP", 8) == 0;
        return err_set(BRUME_ERROR_PARSE, "%s: not a brume checkpoint%s", path, magic ? " (truncated)" : "");
    }
    memcpy(hd, data, sizeof *hd);
    if (hd->order != CKPT_ORDER || hd->format != CKPT_FORMAT)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: checkpoint format %u (byte order 0x%08x): this brume reads format %u "
                       "written on a machine of its byte order", path, hd->format, hd->order, CKPT_FORMAT);
    hd->version[sizeof hd->version - 1] = '\0';
    char build[32];
    build_name(build);
    if (strcmp(hd->version, build) != 0)
        return err_set(BRUME_ERROR_UNSUPPORTED,
                       "%s: checkpoint of brume %s, this is brume %s (another build may draw its samples "
                       "differently): render again",
                       path, hd->version, build);
    uint64_t np = hd->pixels;
    bool aovs = (hd->set.aovs & (BRUME_AOV_DEPTH | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL)) != 0;
    uint64_t per = pixel_bytes(aovs);
    if (np > ((uint64_t)1 << 28) || size != sizeof *hd + np * per + sizeof(uint64_t))
        return err_set(BRUME_ERROR_PARSE, "%s: checkpoint truncated or padded: %zu bytes, its header says %llu", path,
                       size, np > ((uint64_t)1 << 28) ? 0ULL : (unsigned long long)(sizeof *hd + np * per + 8));
    uint64_t hash;
    memcpy(&hash, data + size - sizeof hash, sizeof hash);
    if (fnv1a(FNV_START, data, size - sizeof hash) != hash)
        return err_set(BRUME_ERROR_PARSE, "%s: checkpoint corrupt (its checksum does not match)", path);
    if (hd->scene_key != scene_key)
        return err_set(BRUME_ERROR_STATE, "%s: the checkpoint was made from another scene (or other scene options)",
                       path);
    if (hd->set.nparts < 1 || hd->set.part < 0 || hd->set.part >= hd->set.nparts)
        return err_set(BRUME_ERROR_PARSE, "%s: checkpoint corrupt (render part)", path);
    return BRUME_OK;
}

/* The pixels' counts, states and sums (and AOV sums when aovs) after the header of data. */
static void restore_sums(brume_render_job *job, const unsigned char *data, uint64_t np, bool aovs)
{
    const unsigned char *p = data + sizeof(ckpt_header);
    memcpy(job->n, p, np * sizeof *job->n);
    p += np * sizeof *job->n;
    memcpy(job->active, p, np);
    p += np;
    memcpy(job->sum, p, np * JOB_SUMS * sizeof *job->sum);
    p += np * JOB_SUMS * sizeof *job->sum;
    memcpy(job->sq, p, np * JOB_SQS * sizeof *job->sq);
    p += np * JOB_SQS * sizeof *job->sq;
    if (aovs)
        memcpy(job->aov, p, np * JOB_AOVS * sizeof *job->aov);
}

/* Why pixel i's sums cannot come from its n samples, or NULL when they can. Every sample is a
 * finite radiance >= 0 and an alpha in [0, 1] (the first JOB_ALPHA_SAMPLES only), so the sums
 * are finite and >= 0, the alpha sum at most min(n, JOB_ALPHA_SAMPLES), and each sum of
 * squares lies between sum^2 / n (Cauchy-Schwarz) and sum^2 (non-negative terms); no sample,
 * all zero. */
static const char *sums_fault(const brume_render_job *job, size_t i)
{
    const double *s = job->sum + JOB_SUMS * i, *q = job->sq ? job->sq + JOB_SQS * i : NULL;
    const double n = job->n[i], slack = 1e-6; /* the sums' rounding over 2^30 samples */
    for (int c = 0; c < JOB_SUMS; c++)
        if (!isfinite(s[c]) || s[c] < 0.0)
            return "a sum that is not finite and >= 0";
    for (int c = 0; q && c < JOB_SQS; c++)
        if (!isfinite(q[c]) || q[c] < 0.0)
            return "a sum of squares that is not finite and >= 0";
    for (int c = 0; job->aov && c < JOB_AOVS; c++)
        if (!isfinite(job->aov[JOB_AOVS * i + (size_t)c]))
            return "a layer's sum that is not finite";
    if (n == 0.0) {
        for (int c = 0; c < JOB_SUMS; c++)
            if (s[c] != 0.0 || (q && q[c] != 0.0))
                return "sums without samples";
        return NULL;
    }
    if (s[3] > fmin(n, JOB_ALPHA_SAMPLES) * (1.0 + slack))
        return "an alpha sum over its sample count";
    for (int c = 0; q && c < JOB_SQS; c++) {
        double sc = c < 3 ? s[c] : (s[0] + s[1] + s[2]) / 3.0;
        if (q[c] < sc * sc / n * (1.0 - slack) || q[c] > sc * sc * (1.0 + slack))
            return "sums of squares that no samples give with these sums";
    }
    return NULL;
}

/* Every pixel's sums against its count (sums_fault): BRUME_OK, or a one-line error naming the
 * first pixel that no samples can explain. */
static brume_status sums_check(const brume_render_job *job, const char *path)
{
    for (size_t i = 0; i < job->npix; i++) {
        const char *why = sums_fault(job, i);
        if (why)
            return err_set(BRUME_ERROR_PARSE, "%s: checkpoint corrupt: pixel (%zu, %zu): %s", path,
                           i % (size_t)job->rs.width, i / (size_t)job->rs.width, why);
    }
    return BRUME_OK;
}

static brume_status resume(const brume_scene *s, uint64_t scene_key, const char *path, brume_render_job **out)
{
    unsigned char *data = NULL;
    size_t size = 0;
    brume_status st = slurp(path, max_size(s), &data, &size);
    if (st != BRUME_OK)
        return st;
    ckpt_header hd;
    if ((st = check_header(path, data, size, scene_key, &hd)) != BRUME_OK) {
        free(data);
        return st;
    }
    uint64_t np = hd.pixels;
    bool aovs = (hd.set.aovs & (BRUME_AOV_DEPTH | BRUME_AOV_ALBEDO | BRUME_AOV_NORMAL)) != 0;
    brume_render_job *job = NULL;
    if ((st = job_create(s, hd.set.part, hd.set.nparts, true, &job)) != BRUME_OK) {
        free(data);
        return st;
    }
    ckpt_settings mine;
    settings_record(job, &mine);
    if ((st = compare_settings(path, &hd.set, &mine)) != BRUME_OK || np != job->npix) {
        if (st == BRUME_OK)
            st = err_set(BRUME_ERROR_PARSE, "%s: checkpoint corrupt (pixel count)", path);
        free(data);
        brume_render_job_release(job);
        return st;
    }
    restore_sums(job, data, np, aovs);
    free(data);
    bool sane = hd.spp_done >= 0 && hd.target >= hd.spp_done && hd.target <= (1 << 30) && isfinite(hd.elapsed) &&
                hd.elapsed >= 0.0;
    for (size_t i = 0; i < job->npix && sane; i++)
        sane = job->active[i] <= 1 && job->n[i] <= (uint32_t)hd.target;
    if (!sane) {
        brume_render_job_release(job);
        return err_set(BRUME_ERROR_PARSE, "%s: checkpoint corrupt (sample counts)", path);
    }
    if ((st = sums_check(job, path)) != BRUME_OK) {
        brume_render_job_release(job);
        return st;
    }
    job->spp_done = hd.spp_done;
    job->target = hd.target;
    job->elapsed = hd.elapsed;
    job->elapsed_saved = hd.elapsed; /* reported; this run's budget is its own */
    job_refresh(job);
    *out = job;
    return BRUME_OK;
}

brume_status brume_render_job_resume(brume_context *ctx, const brume_scene *scene, uint64_t scene_key,
                                     const char *path, brume_render_job **out)
{
    err_clear();
    if (out)
        *out = NULL;
    if (!out || !scene || !path || !*path)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_job_resume: %s: NULL",
                                       !scene ? "scene" : !path || !*path ? "path" : "out"));
    return ctx_report(ctx, resume(scene, scene_key, path, out));
}

bool checkpoint_remove_own(const brume_render_job *job, uint64_t scene_key, const char *path)
{
    if (!job || !path)
        return false;
    /* the header is read through the path that would be removed; a symbolic link is left (its
     * target is not what the name holds) */
    struct stat sb;
    if (lstat(path, &sb) != 0 || !S_ISREG(sb.st_mode))
        return false;
    FILE *fp = NULL;
    if (io_open_regular(path, &fp) != BRUME_OK) {
        err_clear();
        return false;
    }
    ckpt_header hd;
    bool whole = fread(&hd, sizeof hd, 1, fp) == 1;
    fclose(fp);
    if (!whole || memcmp(hd.magic, "BRUMECKP", 8) != 0 || hd.format != CKPT_FORMAT || hd.order != CKPT_ORDER ||
        hd.scene_key != scene_key || hd.pixels != job->npix)
        return false;
    char build[32];
    build_name(build);
    hd.version[sizeof hd.version - 1] = '\0';
    ckpt_settings mine;
    settings_record(job, &mine);
    if (strcmp(hd.version, build) != 0 || memcmp(&hd.set, &mine, sizeof mine) != 0)
        return false;
    return remove(path) == 0;
}

uint64_t checkpoint_inputs_key(const brume_scene *s, uint64_t h)
{
    if (!s)
        return h;
    if (s->inputs.oom)
        h ^= 0x9e3779b97f4a7c15ULL; /* an incomplete list: never the key of a complete one */
    return io_inputs_hash(&s->inputs, h);
}

uint64_t brume_scene_inputs_key(const brume_scene *scene, uint64_t h) { return checkpoint_inputs_key(scene, h); }

brume_status brume_render_job_remove_checkpoint(brume_context *ctx, const brume_render_job *job, uint64_t scene_key,
                                                const char *path, bool *removed)
{
    err_clear();
    if (removed)
        *removed = false;
    if (!job || !path || !removed)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_render_job_remove_checkpoint: %s: NULL",
                                       !job ? "job" : !path ? "path" : "removed"));
    *removed = checkpoint_remove_own(job, scene_key, path);
    err_clear();
    return ctx_report(ctx, BRUME_OK);
}

brume_status brume_output_check(brume_context *ctx, const char *what, const char *path, brume_file_kind kind,
                                const brume_scene *scene, const char *const *others, int nothers)
{
    err_clear();
    if (!what || !path || (nothers > 0 && !others) || nothers < 0 || (unsigned)kind > BRUME_FILE_TEXT)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_output_check: %s",
                                       !what ? "what: NULL" : !path ? "path: NULL"
                                       : (unsigned)kind > BRUME_FILE_TEXT ? "kind: unknown" : "others: NULL"));
    const char *file = scene && scene->source[0] != '<' ? scene->source : NULL;
    return ctx_report(ctx, io_output_check(what, path, kind, file, scene ? &scene->inputs : NULL, others, nothers));
}
