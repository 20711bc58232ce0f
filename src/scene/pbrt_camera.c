/* pbrt_camera.c - the pbrt directives that set the view and the render: Camera, and Film,
 * Sampler, Integrator, ColorSpace and Material (read by pbrt_materials.c). */
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
#include "scene/film_sensor.h"
#include "scene/scene_build.h"
#include "scene/pbrt.h"

brume_status pbrt_camera_directive(pbrt_state *S, const char *type, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    if (strcmp(type, "perspective") != 0)
        return pbrt_unsupported(L, "Camera \"%s\": brume has a perspective camera only", type);
    S->fov = 90.0;
    S->lens_radius = 0.0;
    S->focal_distance = 1e6;
    double open = 0.0, close = 1.0;
    if ((st = pbrt_get_float(L, ps, "fov", &S->fov)) || (st = pbrt_get_float(L, ps, "lensradius", &S->lens_radius)) ||
        (st = pbrt_get_float(L, ps, "focaldistance", &S->focal_distance)) ||
        (st = pbrt_get_float(L, ps, "shutteropen", &open)) || (st = pbrt_get_float(L, ps, "shutterclose", &close)))
        return st;
    /* without animated transforms the shutter sets only the exposure time (pbrt-v4 swaps a
       close before the open) */
    S->exposure_time = fabs(close - open);
    if (!(S->exposure_time <= 1e30))
        return pbrt_fail(L, "Camera: shutteropen and shutterclose must be finite");
    if ((st = pbrt_all_used(L, ps, "Camera \"perspective\"")))
        return st;
    if (!(S->lens_radius >= 0.0))
        return pbrt_fail(L, "Camera: parameter \"lensradius\": %g is negative", S->lens_radius);
    /* pbrt-v4's camera starts its rays in the outside medium of the MediumInterface in effect,
       resolved by name when the scene is complete (pbrt_camera_medium) */
    pbrt_copy(S->camera_medium, sizeof S->camera_medium, S->a[S->depth].outside);
    S->camera_line = L->dir_line;
    m4 wc;
    if (!pbrt_m4_inverse(S->a[S->depth].ctm, &wc))
        return pbrt_fail(L, "Camera: the current transform is not invertible");
    /* pbrt images camera +x to the right, +y up, looking down +z; brume's camera has right =
       forward x up. Where +x = up x forward instead (pbrt's own LookAt without a mirror: most
       of pbrt-v4-scenes), the whole world is translated mirrored, x -> -x: the camera too, so
       that the picture is pbrt's, pixel for pixel. The mirror M multiplies the camera's
       world-from-camera on the left and starts the world block's transform (WorldBegin,
       Identity, Transform). */
    vec3 R = pbrt_m4_vector(wc, v3(1, 0, 0)), U = pbrt_m4_vector(wc, v3(0, 1, 0)), F = pbrt_m4_vector(wc, v3(0, 0, 1));
    S->mirror = v3_dot(v3_cross(F, U), R) <= 0.0;
    if (S->mirror)
        wc = pbrt_m4_mul(pbrt_m4_scale(-1.0, 1.0, 1.0), wc);
    S->world_from_camera = wc;
    S->have_camera = true;
    return BRUME_OK;
}

/* MakeNamedMaterial "name" "string type" ... and NamedMaterial "name": a material kept by
 * name (a later one of the same name replaces it, as in pbrt-v4), and set as the current. */
static brume_status named_material_directive(pbrt_state *S, attrs *a, const char *dir, const char *name,
                                             const char *what, params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    int i = 0;
    while (i < S->nmaterials && strcmp(S->materials[i].name, name) != 0)
        i++;
    if (strcmp(dir, "NamedMaterial") == 0) {
        if ((st = pbrt_all_used(L, ps, what)))
            return st;
        if (i == S->nmaterials)
            return pbrt_fail(L, "%s: no MakeNamedMaterial of that name before it", what);
        pbrt_copy(a->material, sizeof a->material, S->materials[i].material);
        pbrt_copy(a->mat_json, sizeof a->mat_json, S->materials[i].mat_json);
        a->textured = S->materials[i].textured;
        return BRUME_OK;
    }
    if (i == PBRT_MAX_MATERIALS)
        return pbrt_fail(L, "%s: more than %d named materials", what, PBRT_MAX_MATERIALS);
    char type[64] = "";
    named_material m;
    if ((st = pbrt_get_string(L, ps, "type", type, sizeof type)))
        return st;
    if (!pbrt_get(ps, "type"))
        return pbrt_fail(L, "%s: no \"string type\"", what);
    if ((st = pbrt_material_read(S, type, what, ps, m.material, m.mat_json, &m.textured)) ||
        (st = pbrt_all_used(L, ps, what)))
        return st;
    pbrt_copy(m.name, sizeof m.name, name);
    S->materials[i] = m;
    if (i == S->nmaterials)
        S->nmaterials++;
    return BRUME_OK;
}

/* Film, Sampler, Integrator, ColorSpace, Material, MakeNamedMaterial, NamedMaterial: what they
 * set of the scene or of the current attributes a (their type and parameters read). */
brume_status pbrt_setting_directive(pbrt_state *S, attrs *a, const char *dir, const char *type, const char *what,
                                    params *ps)
{
    lexer *L = &S->L;
    brume_status st;
    if (strcmp(dir, "Film") == 0) {
        /* gbuffer writes rgb's image plus layers; spectral writes spectral bands brume has not */
        if (strcmp(type, "rgb") != 0 && strcmp(type, "gbuffer") != 0)
            return pbrt_unsupported(L, "%s: brume's image is pbrt's \"rgb\" film (rgb, gbuffer)", what);
        double x = 1280, y = 720, wb = 0.0, mc = INFINITY;
        char fn[512], sensor[64] = "cie1931";
        if ((st = pbrt_get_float(L, ps, "xresolution", &x)) || (st = pbrt_get_float(L, ps, "yresolution", &y)) ||
            (st = pbrt_get_string(L, ps, "filename", fn, sizeof fn)) ||
            (st = pbrt_get_string(L, ps, "sensor", sensor, sizeof sensor)) ||
            (st = pbrt_get_float(L, ps, "iso", &S->iso)) || (st = pbrt_get_float(L, ps, "whitebalance", &wb)) ||
            (st = pbrt_get_float(L, ps, "maxcomponentvalue", &mc)))
            return st;
        /* pbrt-v4's per-sample clamp of the sensor's values (X, Y, Z with cie1931): brume's
           render.max_component; pbrt-v4's default, infinity, is none */
        if (!(mc > 0.0))
            return pbrt_fail(L, "%s: parameter \"maxcomponentvalue\": %g must be > 0", what, mc);
        S->max_component = mc <= 1e30 ? mc : 0.0;
        /* pbrt-v4's cie1931 sensor is the XYZ observer, which an RGB film turns into the colour
           space's RGB: brume's own values; a camera it names weighs the spectrum with its measured
           curves: brume's render.sensor (scene/film_sensor.c) */
        S->sensor = film_sensor_find(sensor);
        if (S->sensor < 0)
            return pbrt_unsupported(L, "%s: parameter \"sensor\": \"%s\": no sensor pbrt-v4 names (cie1931 or a camera: "
                                       "docs/pbrt.md, Film)", what, sensor);
        /* pbrt-v4 adapts the sensor's values from the daylight white of that temperature to the
           colour space's (a camera's to 6500 K's by default): brume's render.white_balance */
        if (!(wb == 0.0 || (wb >= 1000.0 && wb <= 1e5)))
            return pbrt_unsupported(L, "%s: parameter \"whitebalance\": %g K: 0 (none) or in [1000, 100000]", what, wb);
        S->white_balance = wb;
        if (!(S->iso >= 0.0 && S->iso <= 1e30))
            return pbrt_fail(L, "%s: parameter \"iso\": %g outside [0, 1e30]", what, S->iso);
        if (!(x >= 1 && x <= 65536 && y >= 1 && y <= 65536))
            return pbrt_fail(L, "%s: resolution outside [1, 65536]", what);
        S->xres = (int)x;
        S->yres = (int)y;
    } else if (strcmp(dir, "Sampler") == 0) {
        double n = 16;
        if ((st = pbrt_get_float(L, ps, "pixelsamples", &n))) return st;
        if (!(n >= 1 && n <= 1 << 24))
            return pbrt_fail(L, "%s: pixelsamples outside [1, 2^24]", what);
        S->spp = (int)n;
    } else if (strcmp(dir, "Integrator") == 0) {
        if (strcmp(type, "volpath") != 0 && strcmp(type, "path") != 0)
            return pbrt_unsupported(L, "%s: brume's path tracer stands for volpath and path only", what);
        double d = 5;
        if ((st = pbrt_get_float(L, ps, "maxdepth", &d))) return st;
        if (!(d >= 1 && d <= 100000))
            return pbrt_fail(L, "%s: maxdepth outside [1, 100000]", what);
        S->max_depth = (int)d;
    } else if (strcmp(dir, "ColorSpace") == 0) {
        if (strcmp(type, "srgb") != 0)
            return pbrt_unsupported(L, "%s: brume renders linear Rec. 709 (srgb) only", what);
    } else if (strcmp(dir, "PixelFilter") == 0) {
        /* pbrt-v4's box filter weighs the samples within radius of the pixel's centre alike:
           brume's box of side 2 radius. Its other filters' shapes differ from brume's */
        double rx = 0.5, ry = 0.5;
        if (strcmp(type, "box") != 0)
            return pbrt_unsupported(L, "%s: brume reads pbrt's \"box\" filter (without PixelFilter, pbrt-v4's gaussian is "
                                       "rendered with brume's, docs/pbrt.md)", what);
        if ((st = pbrt_get_float(L, ps, "xradius", &rx)) || (st = pbrt_get_float(L, ps, "yradius", &ry)))
            return st;
        if (!(rx == ry && rx >= 0.05 && rx <= 8.0))
            return pbrt_fail(L, "%s: xradius and yradius must be equal, in [0.05, 8]", what);
        S->box_filter = 2.0 * rx;
    } else if (strcmp(dir, "Material") == 0) {
        if ((st = pbrt_material_read(S, type, what, ps, a->material, a->mat_json, &a->textured)))
            return st;
    } else {
        return named_material_directive(S, a, dir, type, what, ps);
    }
    return pbrt_all_used(L, ps, what);
}
