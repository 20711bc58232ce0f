/* cuda.c - NVIDIA GPUs through the CUDA driver API, opened at run time (gpu/cuda.h). */
#include "gpu/cuda.h"

#include <stdio.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

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
#define GPU_MAX_SAMPLES (1u << 22) /* samples of one launch at most: their values take 104 bytes each */
#define GPU_LAUNCH_SECONDS 0.1 /* a launch's length, from the last launch's time per sample: a
                                  stop or a time budget is honoured between launches, and a
                                  display GPU's watchdog is never reached */
#define GPU_BLOCK 128
#define GPU_RESIDENT 2048 /* threads a multiprocessor holds at most (compute capability 7.0 to 9.0) */

struct gpu_pass {
    gpu_device *dev;
    const char *source;  /* the scene's, for messages */
    int ordinal;         /* the device's */
    size_t max_memory;   /* render.max_memory_mb, bytes */
    size_t max_pixels;
    bool squares, aovs;
    CUdeviceptr scene;   /* the arena: scene and integrator state */
    size_t scene_at, state_at;
    CUdeviceptr params;  /* sample_params */
    CUdeviceptr pixels, n, sum, sq, aov, values; /* per listed pixel but values, per sample */
    CUdeviceptr counts;  /* brume_paths' counter of the samples taken, brume_reduce's of non-finite ones */
    size_t nvalues;
    double sample_seconds; /* the last launch's seconds per sample, 0 before any */
};

static void gpu_free(gpu_pass *g)
{
    CUdeviceptr *p[] = {&g->scene, &g->params, &g->pixels, &g->n, &g->sum, &g->sq, &g->aov, &g->values, &g->counts};
    for (size_t i = 0; i < sizeof p / sizeof p[0]; i++)
        if (*p[i]) {
            cu.MemFree(*p[i]);
            *p[i] = 0;
        }
}

void gpu_pass_close(gpu_pass *g)
{
    if (!g)
        return;
    if (g->dev && cu.CtxSetCurrent(g->dev->ctx) == 0)
        gpu_free(g);
    free(g);
}

static brume_status gpu_fail(const gpu_pass *g, const char *what, CUresult r)
{
    return err_set(r == 2 ? BRUME_ERROR_OUT_OF_MEMORY : BRUME_ERROR_UNSUPPORTED, "%s: GPU cuda:%d: %s: %s", g->source,
                   g->ordinal, what, cu_error(r));
}

/* Device memory of `bytes`, within the job's budget: what the scene may take on the host
 * (render.max_memory_mb) bounds it on the GPU too, and so does the GPU's free memory. */
static brume_status gpu_alloc(const gpu_pass *g, CUdeviceptr *p, size_t bytes, const char *what)
{
    size_t free_b = 0, total_b = 0;
    cu.MemGetInfo(&free_b, &total_b);
    if (bytes > free_b)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: GPU cuda:%d: %s need %zu MB, the GPU has %zu MB free", g->source,
                       g->ordinal, what, bytes >> 20, free_b >> 20);
    CUresult r = cu.MemAlloc(p, bytes ? bytes : 16);
    return r ? gpu_fail(g, what, r) : BRUME_OK;
}

/* The scene's copy uploaded to g's device. */
static brume_status gpu_upload_scene(gpu_pass *g, const render_pass *shape)
{
    dev_arena a;
    arena_init(&a, g->max_memory);
    g->scene_at = device_scene_put(shape->s, shape->state, &a, &g->state_at);
    if (a.failed) {
        arena_free(&a);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: the scene's copy for the GPU exceeds render.max_memory_mb (%zu MB)",
                       g->source, g->max_memory >> 20);
    }
    brume_status st = gpu_alloc(g, &g->scene, a.size, "the scene");
    if (st != BRUME_OK) {
        arena_free(&a);
        return st;
    }
    arena_relocate(&a, (uint64_t)g->scene);
    CUresult r = cu.MemcpyHtoD(g->scene, a.buf, a.size);
    arena_free(&a);
    return r ? gpu_fail(g, "uploading the scene", r) : BRUME_OK;
}

brume_status gpu_pass_open(const render_pass *shape, int device, size_t max_pixels, gpu_pass **out)
{
    *out = NULL;
    const brume_scene *s = shape->s;
    brume_status st = device_scene_check(s, shape->sp.kind);
    if (st != BRUME_OK)
        return st;
    gpu_device *dev = gpu_open(s->source, device);
    if (!dev)
        return err_status();
    gpu_pass *g = calloc(1, sizeof *g);
    if (!g)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for a GPU job", s->source);
    *g = (gpu_pass){.dev = dev,
                    .source = s->source,
                    .ordinal = device,
                    .max_memory = s->max_memory,
                    .max_pixels = max_pixels,
                    .squares = shape->sp.squares,
                    .aovs = shape->sp.trace_aovs};
    const size_t np = max_pixels;
    CUresult r = 0;
    if ((st = gpu_upload_scene(g, shape)) || (st = gpu_alloc(g, &g->params, sizeof shape->sp, "the parameters")) ||
        (st = gpu_alloc(g, &g->pixels, np * sizeof(uint32_t), "the pixel list")) ||
        (st = gpu_alloc(g, &g->counts, 2 * sizeof(uint64_t), "the sample counters")) ||
        (st = gpu_alloc(g, &g->n, np * sizeof(uint32_t), "the sample counts")) ||
        (st = gpu_alloc(g, &g->sum, np * JOB_SUMS * sizeof(double), "the image sums")) ||
        (g->squares && (st = gpu_alloc(g, &g->sq, np * JOB_SQS * sizeof(double), "the squares"))) ||
        (g->aovs && (st = gpu_alloc(g, &g->aov, np * JOB_AOVS * sizeof(double), "the layers"))) ||
        ((r = cu.MemcpyHtoD(g->params, &shape->sp, sizeof shape->sp)) && (st = gpu_fail(g, "uploading the parameters", r)))) {
        gpu_pass_close(g);
        return st;
    }
    *out = g;
    return BRUME_OK;
}

/* Room for `need` bytes of samples' values on g's device. */
static brume_status gpu_values(gpu_pass *g, size_t need)
{
    if (need <= g->nvalues)
        return BRUME_OK;
    if (g->values)
        cu.MemFree(g->values);
    g->values = 0;
    g->nvalues = 0;
    brume_status st = gpu_alloc(g, &g->values, need, "the samples' values");
    if (st == BRUME_OK)
        g->nvalues = need;
    return st;
}

static double gpu_now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One launch of brume_paths and brume_reduce, timed into g->sample_seconds: samples up to
 * to - 1 of listed pixels p0 .. p0 + np - 1, per at most a pixel (those below each pixel's
 * count are skipped). The pixel arrays are list-indexed, so the launch sees its pixels'
 * slice of each. */
static brume_status gpu_launch(gpu_pass *g, uint32_t p0, uint32_t np, uint32_t to, uint32_t per)
{
    brume_status st = gpu_values(g, (size_t)np * per * sizeof(sample_value));
    if (st != BRUME_OK)
        return st;
    double t0 = gpu_now();
    CUdeviceptr scene = g->scene + g->scene_at;
    CUdeviceptr state = g->state_at == ARENA_NULL ? 0 : g->scene + g->state_at;
    CUdeviceptr pixels = g->pixels + (CUdeviceptr)p0 * sizeof(uint32_t), n = g->n + (CUdeviceptr)p0 * sizeof(uint32_t);
    CUdeviceptr sum = g->sum + (CUdeviceptr)p0 * JOB_SUMS * sizeof(double);
    CUdeviceptr sq = g->squares ? g->sq + (CUdeviceptr)p0 * JOB_SQS * sizeof(double) : 0;
    CUdeviceptr aov = g->aovs ? g->aov + (CUdeviceptr)p0 * JOB_AOVS * sizeof(double) : 0;
    CUdeviceptr nonfinite = g->counts + sizeof(uint64_t);
    uint64_t threads = (uint64_t)np * per;
    /* as many threads as the GPU holds, each taking samples until none is left */
    uint32_t zero = 0;
    uint64_t resident = (uint64_t)g->dev->sms * GPU_RESIDENT;
    uint64_t launch = threads < resident ? threads : resident;
    CUresult r;
    void *a1[] = {&scene, &state, &g->params, &pixels, &np, &n, &to, &per, &g->values, &g->counts};
    if ((r = cu.MemcpyHtoD(g->counts, &zero, sizeof zero)) ||
        (r = cu.LaunchKernel(g->dev->paths, (unsigned)((launch + GPU_BLOCK - 1) / GPU_BLOCK), 1, 1, GPU_BLOCK, 1, 1, 0,
                             NULL, a1, NULL)))
        return gpu_fail(g, "launching the paths", r);
    void *a2[] = {&g->params, &np, &n, &to, &per, &g->values, &sum, &sq, &aov, &nonfinite};
    if ((r = cu.LaunchKernel(g->dev->reduce, (np + GPU_BLOCK - 1) / GPU_BLOCK, 1, 1, GPU_BLOCK, 1, 1, 0, NULL, a2, NULL)))
        return gpu_fail(g, "launching the sums", r);
    if ((r = cu.CtxSynchronize()))
        return gpu_fail(g, "rendering", r);
    g->sample_seconds = (gpu_now() - t0) / (double)threads;
    return BRUME_OK;
}

/* The samples the next launch takes: GPU_LAUNCH_SECONDS of them at the last launch's rate,
 * or for the first launch one per thread the GPU holds; within [1, GPU_MAX_SAMPLES]. */
static uint64_t gpu_launch_samples(const gpu_pass *g)
{
    double want = g->sample_seconds > 0.0 ? GPU_LAUNCH_SECONDS / g->sample_seconds
                                          : (double)g->dev->sms * GPU_RESIDENT;
    return want < 1.0 ? 1 : want > (double)GPU_MAX_SAMPLES ? GPU_MAX_SAMPLES : (uint64_t)want;
}

brume_status gpu_pass_render(gpu_pass *g, render_pass *p)
{
    if (p->npixels == 0)
        return BRUME_OK;
    if (p->npixels > g->max_pixels)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: GPU cuda:%d: a pass of %zu pixels, over the %zu opened for",
                       g->source, g->ordinal, p->npixels, g->max_pixels);
    if (cu.CtxSetCurrent(g->dev->ctx) != 0)
        return gpu_fail(g, "cuCtxSetCurrent", 1);
    const uint32_t target = p->target, np = (uint32_t)p->npixels;
    uint32_t n_min = target;
    uint64_t before = 0, after = 0;
    for (size_t j = 0; j < p->npixels; j++) {
        n_min = p->n[j] < n_min ? p->n[j] : n_min;
        before += p->n[j];
    }
    CUresult r;
    uint64_t zero = 0;
    if ((r = cu.MemcpyHtoD(g->pixels, p->pixels, np * sizeof(uint32_t))) ||
        (r = cu.MemcpyHtoD(g->n, p->n, np * sizeof(uint32_t))) ||
        (r = cu.MemcpyHtoD(g->sum, p->sum, np * sizeof *p->sum)) ||
        (p->sq && (r = cu.MemcpyHtoD(g->sq, p->sq, np * sizeof *p->sq))) ||
        (p->aov && (r = cu.MemcpyHtoD(g->aov, p->aov, np * sizeof *p->aov))) ||
        (r = cu.MemcpyHtoD(g->counts + sizeof(uint64_t), &zero, sizeof zero)))
        return gpu_fail(g, "uploading the image", r);
    /* sweeps of a few samples of every pixel, each in launches of about GPU_LAUNCH_SECONDS:
     * all the pixels in one launch, or when one sample of each takes longer, slices of the
     * list. Each pixel's samples are still added in their order, whatever the split; p->cut
     * is asked after each launch, and a cut pass leaves each pixel with the samples its
     * launches added */
    bool cut = false;
    for (uint32_t from = n_min; from < target && !cut;) {
        uint64_t want = gpu_launch_samples(g);
        uint32_t per = want / np < 1 ? 1 : want / np > target - from ? target - from : (uint32_t)(want / np);
        uint32_t m = per > 1 || want >= np ? np : (uint32_t)want;
        for (uint32_t p0 = 0; p0 < np && !cut; p0 += m) {
            brume_status st = gpu_launch(g, p0, np - p0 < m ? np - p0 : m, from + per, per);
            if (st != BRUME_OK)
                return st;
            cut = p->cut && p->cut(p->user);
        }
        from += per;
    }
    uint64_t nonfinite = 0;
    if ((r = cu.MemcpyDtoH(p->n, g->n, np * sizeof(uint32_t))) ||
        (r = cu.MemcpyDtoH(p->sum, g->sum, np * sizeof *p->sum)) ||
        (p->sq && (r = cu.MemcpyDtoH(p->sq, g->sq, np * sizeof *p->sq))) ||
        (p->aov && (r = cu.MemcpyDtoH(p->aov, g->aov, np * sizeof *p->aov))) ||
        (r = cu.MemcpyDtoH(&nonfinite, g->counts + sizeof(uint64_t), sizeof nonfinite)))
        return gpu_fail(g, "reading the image back", r);
    for (size_t j = 0; j < p->npixels; j++)
        after += p->n[j];
    p->taken += after - before;
    p->nonfinite += nonfinite;
    return BRUME_OK;
}
