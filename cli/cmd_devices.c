/* cmd_devices.c - `brume devices`: the CUDA GPUs brume can render on (docs/gpu.md), one line
 * each, or one line saying why there are none (exit status 1). */
#include <stdio.h>
#include <string.h>

#include "brume.h"
#include "cli_flags.h"
#include "commands.h"

const cli_command cli_devices_command = {
    "devices", "the GPUs brume can render on (docs/gpu.md), or why there are none", "",
    "Lists the NVIDIA GPUs that `brume render --device cuda:N` can use: name, memory,\n"
    "compute capability. Says why there are none (no driver, a build without GPU kernels).\n",
    NULL, 0, NULL, NULL};

int cmd_devices(int argc, char **argv)
{
    int n = 0, rc = cli_flags_parse(&cli_devices_command, NULL, argc, argv, NULL, 0, &n);
    if (rc >= 0)
        return rc;
    brume_device_info d[16];
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
