/* cmd_devices.c - `brume devices`: the CUDA GPUs brume can render on (docs/gpu.md), one line
 * each, or one line saying why there are none (exit status 1). */
#include <stdio.h>
#include <string.h>

#include "brume.h"
#include "commands.h"

int cmd_devices(int argc, char **argv)
{
    if (argc > 1 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        printf("usage: brume devices\n"
               "Lists the NVIDIA GPUs that `brume render --device cuda:N` can use: name, memory,\n"
               "compute capability. Says why there are none (no driver, a build without GPU kernels).\n");
        return 0;
    }
    if (argc > 1) {
        cli_error("devices: unexpected argument '%s' (usage: brume devices)", argv[1]);
        return 2;
    }
    brume_device_info d[16];
    int n = 0;
    brume_context *ctx = brume_context_new();
    if (!ctx) {
        cli_error("devices: out of memory");
        return 1;
    }
    if (brume_devices(ctx, d, 16, &n) != BRUME_OK) {
        cli_error("%s", brume_context_last_error(ctx));
        brume_context_release(ctx);
        return 1;
    }
    brume_context_release(ctx);
    for (int i = 0; i < n && i < 16; i++)
        printf("cuda:%d  %s  %.1f GiB  compute capability %d.%d  %d multiprocessors\n", i, d[i].name,
               (double)d[i].memory / (1024.0 * 1024.0 * 1024.0), d[i].cc_major, d[i].cc_minor, d[i].multiprocessors);
    return 0;
}
