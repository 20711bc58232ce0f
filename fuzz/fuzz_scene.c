/* fuzz_scene.c - libFuzzer target for the scene reader: JSON text through the whole reader
 * (every key, density, phase, light, surface and method option) to a committed scene.
 * Built and run by fuzz/run.sh scene: any crash, sanitizer report, leak, hang, allocation
 * past the limit or message that is not one clean line is a failure. The input runs in an
 * empty folder with a small memory budget; paths in it name files that mostly do not exist. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "brume.h"
#include "core/error.h"
#include "scene/scene.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *text = malloc(size + 1);
    if (!text)
        return 0;
    memcpy(text, data, size);
    text[size] = '\0';
    brume_scene *s = NULL;
    brume_status st = scene_parse_json(text, "fuzz.json", &s);
    free(text);
    if (st == BRUME_OK) {
        brume_context *ctx = brume_context_new();
        st = brume_scene_commit(ctx, s);
        brume_context_release(ctx);
        brume_scene_release(s);
    }
    if (st != BRUME_OK) {
        const char *m = err_message();
        if (!m[0])
            abort(); /* every failure says why */
        for (const char *c = m; *c; c++)
            if ((unsigned char)*c < 0x20 || *c == 0x7f)
                abort(); /* one line, no control characters */
    }
    return 0;
}
