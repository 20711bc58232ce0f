/* device_name.c - render.device's names (brume.h, brume_device_from_name): parsed where the
 * scene's settings are read (scene_json.c), below the GPU code that renders on the device. */
#include <stdlib.h>
#include <string.h>

#include "brume.h"
#include "core/context.h"
#include "core/error.h"

brume_status brume_device_from_name(brume_context *ctx, const char *name, int *device)
{
    err_clear();
    if (!name || !device)
        return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "brume_device_from_name: %s: NULL",
                                       !name ? "name" : "device"));
    if (strcmp(name, "cpu") == 0) {
        *device = -1;
        return BRUME_OK;
    }
    if (strcmp(name, "cuda") == 0) {
        *device = 0;
        return BRUME_OK;
    }
    if (strncmp(name, "cuda:", 5) == 0 && name[5] >= '0' && name[5] <= '9' && strlen(name) <= 7) {
        char *end;
        long v = strtol(name + 5, &end, 10);
        if (*end == '\0' && v < 64) {
            *device = (int)v;
            return BRUME_OK;
        }
    }
    return ctx_report(ctx, err_set(BRUME_ERROR_INVALID_ARGUMENT, "unknown device '%s' (known: cpu, cuda, cuda:N)", name));
}
