/* fuzz_grid.c - libFuzzer target for one grid reader, chosen at compile time by
 * FUZZ_FORMAT (GRID_FORMAT_RAW, _DF3, _VOL, _NVDB, _VDB). Built and run by fuzz/run.sh:
 * any crash, sanitizer report, leak or multi-line error message is a failure. */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "io/grid_io.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    density_load_options o;
    density_load_options_default(&o);
    o.format = FUZZ_FORMAT;
    o.max_memory = (size_t)64 << 20; /* keep each input quick */
    o.filter = size & 1 ? GRID_NEAREST : GRID_TRILINEAR;
    if (FUZZ_FORMAT == GRID_FORMAT_RAW && size >= 3) {
        /* raw has no header: the first 3 bytes give the dimensions (0 = infer a cube) */
        for (int a = 0; a < 3; a++)
            o.raw_dims[a] = data[a] % 17;
        if (!o.raw_dims[0] || !o.raw_dims[1] || !o.raw_dims[2])
            o.raw_dims[0] = o.raw_dims[1] = o.raw_dims[2] = 0;
        data += 3;
        size -= 3;
    }
    density *d = density_load_memory(data, size, "fuzz", &o);
    if (!d) {
        const char *m = err_message();
        if (strncmp(m, "fuzz", 4) != 0 || strchr(m, '\n'))
            abort(); /* every error is one line naming the input */
        return 0;
    }
    /* use what was loaded: lookups and a few rays must stay in bounds */
    box3 b = density_bounds(d);
    vec3 c = v3_scale(v3_add(b.lo, b.hi), 0.5);
    volatile double sink = density_eval(d, c) + density_eval(d, b.lo) + density_eval(d, b.hi);
    for (int r = 0; r < 4; r++) {
        ray ry = {v3_sub(c, v3(r + 1.0, 2.0 - r, 0.5 * r + 0.25)), v3(r + 1.0, 2.0 - r, 0.5 * r + 0.25), 0};
        majorant_iter mi;
        majorant_seg s;
        density_majorant_begin(d, ry, 0, 2, &mi);
        for (int k = 0; k < 1000 && majorant_next(&mi, &s); k++)
            sink += s.rho_maj + density_eval(d, ray_at(ry, 0.5 * (s.t0 + s.t1)));
    }
    (void)sink;
    density_release(d);
    return 0;
}
