/* cuda.c - NVIDIA GPUs through the CUDA driver API, opened at run time (gpu/cuda.h). */
#include "gpu/cuda.h"

#include <stdio.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/context.h"
#include "core/error.h"
#include "core/lazylib.h"
#include "gpu/device_scene.h"
#include "medium/blackbody.h"
#include "render/sample.h"

/* ---- the driver API: the few declarations brume uses (CUDA driver API reference) --------- */
typedef int CUresult; /* 0: CUDA_SUCCESS */
typedef int CUdevice;
typedef struct CUctx_st *CUcontext;
typedef struct CUmod_st *CUmodule;
typedef struct CUfunc_st *CUfunction;
typedef unsigned long long CUdeviceptr;
enum {
    CU_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT = 16,
    CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR = 75,
    CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR = 76,
    CU_LIMIT_STACK_SIZE = 0,
    CU_JIT_ERROR_LOG_BUFFER = 5,
    CU_JIT_ERROR_LOG_BUFFER_SIZE_BYTES = 6,
};

/* The driver functions brume calls: (return type, member, the driver's name, parameters);
 * the _v2 names take 64-bit sizes. */
#define CU_FUNCTIONS(X) \
    X(CUresult, Init, "cuInit", (unsigned)) \
    X(CUresult, DeviceGetCount, "cuDeviceGetCount", (int *)) \
    X(CUresult, DeviceGet, "cuDeviceGet", (CUdevice *, int)) \
    X(CUresult, DeviceGetName, "cuDeviceGetName", (char *, int, CUdevice)) \
    X(CUresult, DeviceTotalMem, "cuDeviceTotalMem_v2", (size_t *, CUdevice)) \
    X(CUresult, DeviceGetAttribute, "cuDeviceGetAttribute", (int *, int, CUdevice)) \
    X(CUresult, CtxCreate, "cuCtxCreate_v2", (CUcontext *, unsigned, CUdevice)) \
    X(CUresult, CtxSetCurrent, "cuCtxSetCurrent", (CUcontext)) \
    X(CUresult, CtxSetLimit, "cuCtxSetLimit", (int, size_t)) \
    X(CUresult, CtxSynchronize, "cuCtxSynchronize", (void)) \
    X(CUresult, ModuleLoadDataEx, "cuModuleLoadDataEx", (CUmodule *, const void *, unsigned, int *, void **)) \
    X(CUresult, ModuleGetFunction, "cuModuleGetFunction", (CUfunction *, CUmodule, const char *)) \
    X(CUresult, ModuleGetGlobal, "cuModuleGetGlobal_v2", (CUdeviceptr *, size_t *, CUmodule, const char *)) \
    X(CUresult, MemAlloc, "cuMemAlloc_v2", (CUdeviceptr *, size_t)) \
    X(CUresult, MemFree, "cuMemFree_v2", (CUdeviceptr)) \
    X(CUresult, MemGetInfo, "cuMemGetInfo_v2", (size_t *, size_t *)) \
    X(CUresult, MemcpyHtoD, "cuMemcpyHtoD_v2", (CUdeviceptr, const void *, size_t)) \
    X(CUresult, MemcpyDtoH, "cuMemcpyDtoH_v2", (void *, CUdeviceptr, size_t)) \
    X(CUresult, LaunchKernel, "cuLaunchKernel", (CUfunction, unsigned, unsigned, unsigned, unsigned, unsigned, unsigned, unsigned, void *,   \
                                             void **, void **))                                           \
    X(CUresult, GetErrorString, "cuGetErrorString", (CUresult, const char **))

#define CU_POINTER(ret, f, name, params) ret(*f) params;
#define CU_NAME(ret, f, name, params) name,
static struct {
    CU_FUNCTIONS(CU_POINTER)
} cu;
static const char *const cu_names[] = {CU_FUNCTIONS(CU_NAME) NULL};
static const char *const cu_sonames[] = {"libcuda.so.1", NULL};
static lazylib cu_so = LAZYLIB("the NVIDIA driver", cu_sonames, cu_names, &cu, sizeof cu);

static pthread_mutex_t cu_lock = PTHREAD_MUTEX_INITIALIZER;
static bool cu_ready;
static char cu_why[256]; /* why the driver could not be used, once it failed */

static const char *cu_error(CUresult r)
{
    const char *s = NULL;
    if (cu.GetErrorString)
        cu.GetErrorString(r, &s);
    return s ? s : "unknown CUDA error";
}

/* Opens the driver once; false with cu_why set when there is none. Under cu_lock. */
static bool cu_open(void)
{
    if (cu_ready)
        return true;
    if (cu_why[0])
        return false;
    if (!gpu_ptx[0]) {
        snprintf(cu_why, sizeof cu_why, "this brume was built without GPU support (no clang to compile its CUDA kernels)");
        return false;
    }
    if (!lazylib_open(&cu_so)) {
        if (!cu_so.handle)
            snprintf(cu_why, sizeof cu_why, "no NVIDIA driver (libcuda.so.1 cannot be opened)");
        else
            snprintf(cu_why, sizeof cu_why, "the NVIDIA driver lacks %s (too old)", cu_so.missing);
        return false;
    }
    CUresult r = cu.Init(0);
    if (r != 0) {
        snprintf(cu_why, sizeof cu_why, "the NVIDIA driver does not start (cuInit: %s)", cu_error(r));
        return false;
    }
    cu_ready = true;
    return true;
}

brume_status brume_devices(brume_context *ctx, brume_device_info *out, int max, int *count)
{
    err_clear();
    if (!out || !count)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_devices: %s: NULL", !out ? "out" : "count"));
    *count = 0;
    pthread_mutex_lock(&cu_lock);
    bool ok = cu_open();
    int n = 0;
    if (ok && cu.DeviceGetCount(&n) != 0)
        n = 0;
    for (int i = 0; ok && i < n && i < max; i++) {
        CUdevice d;
        memset(&out[i], 0, sizeof out[i]);
        if (cu.DeviceGet(&d, i) != 0)
            continue;
        cu.DeviceGetName(out[i].name, (int)sizeof out[i].name, d);
        cu.DeviceTotalMem(&out[i].memory, d);
        cu.DeviceGetAttribute(&out[i].cc_major, CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MAJOR, d);
        cu.DeviceGetAttribute(&out[i].cc_minor, CU_DEVICE_ATTRIBUTE_COMPUTE_CAPABILITY_MINOR, d);
        cu.DeviceGetAttribute(&out[i].multiprocessors, CU_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, d);
    }
    pthread_mutex_unlock(&cu_lock);
    if (!ok)
        return ctx_report(ctx, err_set(BRUME_ERROR_UNSUPPORTED, "no GPU: %s", cu_why));
    *count = n;
    if (n == 0)
        return ctx_report(ctx, err_set(BRUME_ERROR_UNSUPPORTED, "no GPU: the NVIDIA driver sees no device"));
    return BRUME_OK;
}

/* ---- one context and module per device, for the process's lifetime ------------------------- */
#define GPU_MAX_DEVICES 16
#define GPU_STACK_BYTES 65536 /* per device thread: the path's state lives in local memory, and the
                                 tracking loop's streams (track.h) take 13.9 kB a walk, nested
                                 up to three deep (docs/gpu.md, "Memory") */
typedef struct gpu_device {
    bool ready;
    CUcontext ctx;
    CUmodule mod;
    CUfunction paths, reduce;
    int sms; /* multiprocessors */
} gpu_device;
static gpu_device devices[GPU_MAX_DEVICES];

/* The device `ordinal`, its context current on this thread; NULL with err_set(). */
static gpu_device *gpu_open(const char *source, int ordinal)
{
    pthread_mutex_lock(&cu_lock);
    gpu_device *g = NULL;
    int n = 0;
    CUresult r = 0;
    const char *what = NULL;
    char log[2048] = "";
    if (!cu_open()) {
        pthread_mutex_unlock(&cu_lock);
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: render.device: no GPU: %s", source, cu_why);
        return NULL;
    }
    if (cu.DeviceGetCount(&n) != 0 || ordinal >= n || ordinal >= GPU_MAX_DEVICES) {
        pthread_mutex_unlock(&cu_lock);
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: render.device: no GPU cuda:%d (the driver sees %d; brume devices lists them)",
                source, ordinal, n);
        return NULL;
    }
    g = &devices[ordinal];
    if (!g->ready) {
        CUdevice d;
        int opt[2] = {CU_JIT_ERROR_LOG_BUFFER, CU_JIT_ERROR_LOG_BUFFER_SIZE_BYTES};
        void *val[2] = {log, (void *)(uintptr_t)sizeof log};
        if ((r = cu.DeviceGet(&d, ordinal)) != 0)
            what = "cuDeviceGet";
        else if ((r = cu.CtxCreate(&g->ctx, 0, d)) != 0)
            what = "cuCtxCreate";
        else if ((r = cu.CtxSetLimit(CU_LIMIT_STACK_SIZE, GPU_STACK_BYTES)) != 0)
            what = "cuCtxSetLimit";
        else if ((r = cu.DeviceGetAttribute(&g->sms, CU_DEVICE_ATTRIBUTE_MULTIPROCESSOR_COUNT, d)) != 0)
            what = "cuDeviceGetAttribute";
        else if ((r = cu.ModuleLoadDataEx(&g->mod, gpu_ptx, 2, opt, val)) != 0)
            what = "loading the kernels (cuModuleLoadDataEx)";
        else if ((r = cu.ModuleGetFunction(&g->paths, g->mod, "brume_paths")) != 0 ||
                 (r = cu.ModuleGetFunction(&g->reduce, g->mod, "brume_reduce")) != 0)
            what = "cuModuleGetFunction";
        if (!what) {
            /* the blackbody table the kernels interpolate */
            CUdeviceptr bb;
            size_t bytes;
            if ((r = cu.ModuleGetGlobal(&bb, &bytes, g->mod, "brume_device_blackbody")) != 0 ||
                (r = cu.MemcpyHtoD(bb, blackbody_table(), BLACKBODY_TABLE_N * sizeof(color))) != 0)
                what = "uploading the blackbody table";
        }
        g->ready = !what;
    } else {
        r = cu.CtxSetCurrent(g->ctx);
        if (r != 0)
            what = "cuCtxSetCurrent";
    }
    pthread_mutex_unlock(&cu_lock);
    if (what) {
        err_set(BRUME_ERROR_UNSUPPORTED, "%s: GPU cuda:%d: %s failed: %s%s%s", source, ordinal, what, cu_error(r),
                log[0] ? ": " : "", log);
        return NULL;
    }
    return g;
}

/* ---- a job on the GPU ----------------------------------------------------------------------- */
#define GPU_MAX_SAMPLES (1u << 22) /* samples of one launch: their values take 96 bytes each */
#define GPU_BLOCK 128
#define GPU_RESIDENT 2048 /* threads a multiprocessor holds at most (compute capability 7.0 to 9.0) */

typedef struct gpu_job {
    gpu_device *dev;
    CUdeviceptr scene;   /* the arena: scene and integrator state */
    size_t scene_at, state_at;
    CUdeviceptr params;  /* sample_params */
    CUdeviceptr pixels, n, sum, sq, aov, values;
    CUdeviceptr next;    /* brume_paths' counter of the samples taken */
    size_t npix, nvalues;
    uint32_t *list;      /* host: the active pixels of the pass */
} gpu_job;

static void gpu_free(gpu_job *gj)
{
    CUdeviceptr *p[] = {&gj->scene, &gj->params, &gj->pixels, &gj->n, &gj->sum, &gj->sq, &gj->aov, &gj->values, &gj->next};
    for (size_t i = 0; i < sizeof p / sizeof p[0]; i++)
        if (*p[i]) {
            cu.MemFree(*p[i]);
            *p[i] = 0;
        }
}

void gpu_job_release(brume_render_job *job)
{
    gpu_job *gj = job->gpu;
    if (!gj)
        return;
    if (gj->dev && cu.CtxSetCurrent(gj->dev->ctx) == 0)
        gpu_free(gj);
    free(gj->list);
    free(gj);
    job->gpu = NULL;
}

static brume_status gpu_fail(const brume_render_job *job, const char *what, CUresult r)
{
    return err_set(r == 2 ? BRUME_ERROR_OUT_OF_MEMORY : BRUME_ERROR_UNSUPPORTED, "%s: GPU cuda:%d: %s: %s",
                   job->s->source, job->rs.device, what, cu_error(r));
}

/* Device memory of `bytes`, within the job's budget: what the scene may take on the host
 * (render.max_memory_mb) bounds it on the GPU too, and so does the GPU's free memory. */
static brume_status gpu_alloc(brume_render_job *job, CUdeviceptr *p, size_t bytes, const char *what)
{
    size_t free_b = 0, total_b = 0;
    cu.MemGetInfo(&free_b, &total_b);
    if (bytes > free_b)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: GPU cuda:%d: %s need %zu MB, the GPU has %zu MB free",
                       job->s->source, job->rs.device, what, bytes >> 20, free_b >> 20);
    CUresult r = cu.MemAlloc(p, bytes ? bytes : 16);
    return r ? gpu_fail(job, what, r) : BRUME_OK;
}

static brume_status gpu_job_start(brume_render_job *job, gpu_job **out)
{
    const brume_scene *s = job->s;
    brume_status st = device_scene_check(s, (int)job->kind);
    if (st != BRUME_OK)
        return st;
    gpu_device *dev = gpu_open(s->source, job->rs.device);
    if (!dev)
        return err_status();
    gpu_job *gj = calloc(1, sizeof *gj);
    if (!gj || !(gj->list = malloc(job->npix * sizeof *gj->list))) {
        free(gj);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a GPU job", s->source);
    }
    gj->dev = dev;
    gj->npix = job->npix;
    job->gpu = gj;
    dev_arena a;
    arena_init(&a, s->max_memory);
    gj->scene_at = device_scene_put(s, job->state, &a, &gj->state_at);
    if (a.failed) {
        arena_free(&a);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: the scene's copy for the GPU exceeds render.max_memory_mb (%zu MB)",
                       s->source, s->max_memory >> 20);
    }
    if ((st = gpu_alloc(job, &gj->scene, a.size, "the scene")) != BRUME_OK) {
        arena_free(&a);
        return st;
    }
    arena_relocate(&a, (uint64_t)gj->scene);
    CUresult r = cu.MemcpyHtoD(gj->scene, a.buf, a.size);
    arena_free(&a);
    if (r)
        return gpu_fail(job, "uploading the scene", r);
    sample_params sp;
    job_sample_params(job, &sp);
    const size_t np = job->npix;
    if ((st = gpu_alloc(job, &gj->params, sizeof sp, "the parameters")) ||
        (st = gpu_alloc(job, &gj->pixels, np * sizeof(uint32_t), "the pixel list")) ||
        (st = gpu_alloc(job, &gj->next, sizeof(uint32_t), "the sample counter")) ||
        (st = gpu_alloc(job, &gj->n, np * sizeof(uint32_t), "the sample counts")) ||
        (st = gpu_alloc(job, &gj->sum, np * JOB_SUMS * sizeof(double), "the image sums")) ||
        (job->sq && (st = gpu_alloc(job, &gj->sq, np * JOB_SQS * sizeof(double), "the squares"))) ||
        (job->aov && (st = gpu_alloc(job, &gj->aov, np * JOB_AOVS * sizeof(double), "the layers"))))
        return st;
    if ((r = cu.MemcpyHtoD(gj->params, &sp, sizeof sp)))
        return gpu_fail(job, "uploading the parameters", r);
    *out = gj;
    return BRUME_OK;
}

brume_status gpu_job_prepare(brume_render_job *job)
{
    gpu_job *gj = job->gpu;
    return gj ? BRUME_OK : gpu_job_start(job, &gj);
}

brume_status gpu_job_pass(brume_render_job *job)
{
    brume_status st = gpu_job_prepare(job);
    if (st != BRUME_OK)
        return st;
    gpu_job *gj = job->gpu;
    if (cu.CtxSetCurrent(gj->dev->ctx) != 0)
        return gpu_fail(job, "cuCtxSetCurrent", 1);
    /* the pass's pixels: active ones of the job's part below the target */
    const uint32_t target = (uint32_t)job->target;
    uint32_t np = 0, n_min = target;
    for (size_t i = 0; i < job->npix; i++) {
        if (!job->active[i] || job->n[i] >= target)
            continue;
        if (job->nparts > 1) {
            size_t x = i % (size_t)job->rs.width, y = i / (size_t)job->rs.width;
            size_t tile = (y / JOB_TILE) * (size_t)job->tiles_x + x / JOB_TILE;
            if (tile % (size_t)job->nparts != (size_t)job->part)
                continue;
        }
        gj->list[np++] = (uint32_t)i;
        n_min = job->n[i] < n_min ? job->n[i] : n_min;
    }
    if (np == 0)
        return BRUME_OK;
    const size_t P = job->npix;
    CUresult r;
    if ((r = cu.MemcpyHtoD(gj->pixels, gj->list, np * sizeof(uint32_t))) ||
        (r = cu.MemcpyHtoD(gj->n, job->n, P * sizeof(uint32_t))) ||
        (r = cu.MemcpyHtoD(gj->sum, job->sum, P * JOB_SUMS * sizeof(double))) ||
        (job->sq && (r = cu.MemcpyHtoD(gj->sq, job->sq, P * JOB_SQS * sizeof(double)))) ||
        (job->aov && (r = cu.MemcpyHtoD(gj->aov, job->aov, P * JOB_AOVS * sizeof(double)))))
        return gpu_fail(job, "uploading the image", r);
    /* launches of at most GPU_MAX_SAMPLES samples: a few samples of every pixel each */
    uint32_t chunk = GPU_MAX_SAMPLES / np;
    chunk = chunk < 1 ? 1 : chunk;
    for (uint32_t from = n_min; from < target;) {
        uint32_t to = target - from < chunk ? target : from + chunk, per = to - from;
        size_t need = (size_t)np * per * sizeof(sample_value);
        if (need > gj->nvalues) {
            if (gj->values)
                cu.MemFree(gj->values);
            gj->values = 0;
            gj->nvalues = 0;
            if ((st = gpu_alloc(job, &gj->values, need, "the samples' values")) != BRUME_OK)
                return st;
            gj->nvalues = need;
        }
        CUdeviceptr scene = gj->scene + gj->scene_at;
        CUdeviceptr state = gj->state_at == ARENA_NULL ? 0 : gj->scene + gj->state_at;
        uint64_t threads = (uint64_t)np * per;
        /* as many threads as the GPU holds, each taking samples until none is left */
        uint32_t zero = 0;
        uint64_t resident = (uint64_t)gj->dev->sms * GPU_RESIDENT;
        uint64_t launch = threads < resident ? threads : resident;
        void *a1[] = {&scene, &state, &gj->params, &gj->pixels, &np, &gj->n, &to, &per, &gj->values, &gj->next};
        if ((r = cu.MemcpyHtoD(gj->next, &zero, sizeof zero)) ||
            (r = cu.LaunchKernel(gj->dev->paths, (unsigned)((launch + GPU_BLOCK - 1) / GPU_BLOCK), 1, 1, GPU_BLOCK, 1, 1,
                                 0, NULL, a1, NULL)))
            return gpu_fail(job, "launching the paths", r);
        CUdeviceptr sq = job->sq ? gj->sq : 0, aov = job->aov ? gj->aov : 0;
        void *a2[] = {&gj->params, &gj->pixels, &np, &gj->n, &to, &per, &gj->values, &gj->sum, &sq, &aov};
        if ((r = cu.LaunchKernel(gj->dev->reduce, (np + GPU_BLOCK - 1) / GPU_BLOCK, 1, 1, GPU_BLOCK, 1, 1, 0, NULL, a2, NULL)))
            return gpu_fail(job, "launching the sums", r);
        if ((r = cu.CtxSynchronize()))
            return gpu_fail(job, "rendering", r);
        from = to;
    }
    if ((r = cu.MemcpyDtoH(job->n, gj->n, P * sizeof(uint32_t))) ||
        (r = cu.MemcpyDtoH(job->sum, gj->sum, P * JOB_SUMS * sizeof(double))) ||
        (job->sq && (r = cu.MemcpyDtoH(job->sq, gj->sq, P * JOB_SQS * sizeof(double)))) ||
        (job->aov && (r = cu.MemcpyDtoH(job->aov, gj->aov, P * JOB_AOVS * sizeof(double)))))
        return gpu_fail(job, "reading the image back", r);
    return BRUME_OK;
}

