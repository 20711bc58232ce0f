/* fuzz_readers.c - libFuzzer target for the readers of issue 36: the checkpoint reader
 * (brume_render_job_resume) and the mesh reader (io/mesh.c, assimp in its sandboxed child).
 * Built and run by fuzz/run.sh readers: any crash, sanitizer report, leak, hang or message
 * that is not one clean line naming the file is a failure.
 *
 * The first byte chooses: even, a checkpoint; odd, a mesh (its extension from the second
 * byte: .obj .ply .stl .gltf .off). A checkpoint input whose next byte is '!' edits a valid
 * checkpoint of the target's own scene instead of standing alone: the bytes after it are
 * (offset u16, xor u8) triples, so that mutation reaches the checks past the header (the
 * checksum, the settings, the sample counts) rather than stopping at the magic. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "brume.h"
#include "core/error.h"
#include "io/mesh.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define KEY 0x5eedULL

static brume_scene *g_scene;
static unsigned char *g_valid; /* a checkpoint of g_scene, KEY */
static size_t g_valid_size;
static char g_dir[64];

static void check_message(const char *file)
{
    const char *m = err_message();
    if (!m[0] || !strstr(m, file))
        abort(); /* every failure says why, naming the file */
    for (const char *c = m; *c; c++)
        if ((unsigned char)*c < 0x20 || *c == 0x7f)
            abort(); /* one line, no control characters */
}

static void setup(void)
{
    snprintf(g_dir, sizeof g_dir, "/tmp/brume-fuzz-readers-%d", (int)getpid());
    mkdir(g_dir, 0700);
    static const char json[] =
        "{\"camera\": {\"position\": [0, 0, 4], \"look_at\": [0, 0, 0], \"fov\": 40},"
        " \"lights\": [{\"type\": \"distant\", \"direction\": [0, -1, 0], \"irradiance\": 1}],"
        " \"media\": [{\"density\": {\"type\": \"constant\", \"value\": 1}, \"sigma_a\": 0.1, \"sigma_s\": 1}],"
        " \"render\": {\"width\": 5, \"height\": 3, \"spp\": 4, \"threads\": 1}}";
    brume_context *ctx = brume_context_new();
    brume_render_job *job = NULL;
    char path[128];
    snprintf(path, sizeof path, "%s/valid.ckpt", g_dir);
    if (scene_parse_json(json, "fuzz.json", &g_scene) != BRUME_OK || brume_scene_commit(ctx, g_scene) != BRUME_OK ||
        brume_render_begin(ctx, g_scene, &job) != BRUME_OK || brume_render_job_run(ctx, job) != BRUME_OK ||
        brume_render_job_save(ctx, job, KEY, path) != BRUME_OK)
        abort();
    brume_render_job_release(job);
    brume_context_release(ctx);
    FILE *f = fopen(path, "rb");
    g_valid = malloc(1 << 16);
    g_valid_size = f && g_valid ? fread(g_valid, 1, 1 << 16, f) : 0;
    if (f)
        fclose(f);
    if (g_valid_size == 0 || g_valid_size == 1 << 16)
        abort();
}

static void write_file(const char *path, const void *data, size_t n)
{
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(data, 1, n, f) != n)
        abort();
    fclose(f);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (!g_scene)
        setup();
    if (size < 2)
        return 0;
    char path[128];
    if (!(data[0] & 1)) {
        snprintf(path, sizeof path, "%s/in.ckpt", g_dir);
        if (data[1] == '!') {
            unsigned char *c = malloc(g_valid_size);
            memcpy(c, g_valid, g_valid_size);
            size_t len = g_valid_size;
            for (size_t i = 2; i + 3 <= size; i += 3) {
                size_t at = (size_t)(data[i] | data[i + 1] << 8);
                if (at == 0xffff)
                    len = data[i + 2] < len ? len - data[i + 2] : 0; /* truncate */
                else if (at < len)
                    c[at] ^= data[i + 2];
            }
            write_file(path, c, len);
            free(c);
        } else {
            write_file(path, data + 1, size - 1);
        }
        brume_context *ctx = brume_context_new();
        brume_render_job *job = NULL;
        brume_status st = brume_render_job_resume(ctx, g_scene, KEY, path, &job);
        if (st == BRUME_OK) {
            brume_render_progress p;
            brume_render_job_progress(job, &p); /* what was read must be usable */
            brume_render_job_release(job);
        } else {
            check_message("in.ckpt");
        }
        brume_context_release(ctx);
        return 0;
    }
    static const char *const ext[] = {"obj", "ply", "stl", "gltf", "off"};
    snprintf(path, sizeof path, "%s/in.%s", g_dir, ext[data[1] % 5]);
    write_file(path, data + 2, size - 2);
    double *pos = NULL;
    int *idx = NULL, nv = 0, ntri = 0;
    if (mesh_load(path, &pos, &nv, &idx, &ntri) == BRUME_OK) {
        for (int i = 0; i < 3 * ntri; i++)
            if (idx[i] < 0 || idx[i] >= nv)
                abort(); /* the parent checks every index */
        free(pos);
        free(idx);
    } else {
        check_message(path + strlen(g_dir) + 1);
    }
    return 0;
}
