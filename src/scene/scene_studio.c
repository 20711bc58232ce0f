/* scene_studio.c - the studio scene around a grid file (`brume render smoke.vdb`): the grids
 * are listed, the density read once for its box and its maximum, and the scene is written
 * as scene-file JSON for the one scene reader (scene/scene_json.c). The camera is framed at
 * commit ("frame": "media", scene/scene_frame.c). docs/production.md gives the choices. */
#define _XOPEN_SOURCE 700 /* realpath */
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/error.h"
#include "io/grid_io.h"
#include "io/grid_roles.h"
#include "io/grid_sequence.h"
#include "io/json.h"
#include "scene/scene_studio.h"
#include "scene/scene.h"

/* Three-quarter view and sun, degrees: azimuth round from the front, elevation above the
 * horizon. The sun comes from the camera's other side, higher, so that the lit side and
 * the shadowed side both show. */
#define STUDIO_VIEW_AZIMUTH 35.0
#define STUDIO_VIEW_ELEVATION 20.0
#define STUDIO_SUN_AZIMUTH (-50.0)
#define STUDIO_SUN_ELEVATION 45.0
#define STUDIO_OPTICAL_DEPTH 10.0

/* The unit vector at (azimuth, elevation) degrees for up `u`. */
static vec3 studio_dir(vec3 u, double azimuth, double elevation)
{
    u = v3_normalize(u);
    vec3 front = fabs(u.z) < 0.9 ? v3(0, 0, 1) : v3(0, -1, 0);
    front = v3_normalize(v3_sub(front, v3_scale(u, v3_dot(front, u))));
    vec3 right = v3_cross(u, front);
    double a = azimuth * PI / 180.0, e = elevation * PI / 180.0;
    vec3 h = v3_add(v3_scale(right, sin(a)), v3_scale(front, cos(a)));
    return v3_add(v3_scale(h, cos(e)), v3_scale(u, sin(e)));
}

void scene_studio_direction(const double up[3], double position[3], double look_at[3])
{
    v3_to_array(studio_dir(v3(up[0], up[1], up[2]), STUDIO_VIEW_AZIMUTH, STUDIO_VIEW_ELEVATION), position);
    look_at[0] = look_at[1] = look_at[2] = 0.0;
}

bool scene_studio_is_grid(const char *path)
{
    const char *dot = strrchr(path, '.');
    return dot && (strcmp(dot, ".vdb") == 0 || strcmp(dot, ".nvdb") == 0);
}

/* Four significant digits: the printed scene is for people to edit. */
static double round4(double v)
{
    if (v == 0.0 || !isfinite(v))
        return v;
    double p = pow(10.0, 3 - (int)floor(log10(fabs(v))));
    return round(v * p) / p;
}

static cJSON *vec_json(vec3 v)
{
    double a[3] = {round4(v.x), round4(v.y), round4(v.z)};
    return cJSON_CreateDoubleArray(a, 3);
}

static const gridvdb_info *find_grid(const gridvdb_info *g, int n, const char *const *names)
{
    for (const char *const *nm = names; *nm; nm++)
        for (int i = 0; i < n; i++)
            if (strcmp(g[i].name, *nm) == 0 && strcmp(g[i].type, "float") == 0)
                return &g[i];
    return NULL;
}

/* The density grid's name and class, and the temperature grid's name ("" when none). */
static brume_status pick_grids(const char *path, const char *want, char *density_name, size_t n, char *temp_name,
                               double *temp_max)
{
    gridvdb_info *g = NULL;
    int count = 0;
    if (grid_list_file(path, 0, &g, &count) != BRUME_OK)
        return err_status();
    /* the names fire and smoke tools write (docs/grids.md, "Fire files: grids by name") */
    const char *const *dens = grid_role_list("density"), *const *temp = grid_role_list("temperature");
    const gridvdb_info *d = NULL;
    if (want && want[0]) {
        const char *one[] = {want, NULL};
        if (!(d = find_grid(g, count, one))) {
            free(g);
            return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: no float grid named \"%s\" (brume info lists the grids)",
                           path, want);
        }
    } else if (!(d = find_grid(g, count, dens))) {
        const gridvdb_info *only = NULL;
        int nfloat = 0;
        for (int i = 0; i < count; i++)
            if (strcmp(g[i].type, "float") == 0 && !find_grid(&g[i], 1, temp)) {
                nfloat++;
                only = &g[i];
            }
        if (nfloat != 1) {
            free(g);
            return err_set(BRUME_ERROR_INVALID_ARGUMENT,
                           "%s: %s float grid to render as the density: name one (brume info lists the grids)", path,
                           nfloat ? "more than one" : "no");
        }
        d = only;
    }
    if (strcmp(d->cls, "level set") == 0) {
        brume_status st = err_set(BRUME_ERROR_UNSUPPORTED,
                                  "%s: grid \"%s\" is a level set; brume renders fog volumes (convert it first, e.g. "
                                  "Houdini's VDB Convert to fog or openvdb's sdfToFogVolume)", path, d->name);
        free(g);
        return st;
    }
    snprintf(density_name, n, "%s", d->name);
    const gridvdb_info *t = find_grid(g, count, temp);
    temp_name[0] = '\0';
    *temp_max = 0.0;
    if (t && t != d && t->active > 0) {
        snprintf(temp_name, n, "%s", t->name);
        *temp_max = t->vmax;
    }
    free(g);
    return BRUME_OK;
}

/* The studio's one medium: fog, or fire (smoke with a blackbody) when a temperature grid
 * was found; extinction sigma_t per unit density. */
static cJSON *studio_medium(const char *file, const char *dname, const char *tname, double tmax, double sigma_t)
{
    bool fire = tname[0] != '\0';
    cJSON *m = cJSON_CreateObject();
    cJSON_AddStringToObject(m, "name", fire ? "fire" : "fog");
    cJSON *dj = cJSON_AddObjectToObject(m, "density");
    cJSON_AddStringToObject(dj, "type", "grid");
    cJSON_AddStringToObject(dj, "file", file);
    cJSON_AddStringToObject(dj, "grid", dname);
    if (fire) {
        /* smoke darker than cloud, and a blackbody in kelvin: a temperature grid whose
           values stay below 100 is taken as normalized (Houdini's pyro, Blender's smoke)
           and stretched so that its maximum is 3000 K */
        cJSON_AddNumberToObject(m, "sigma_a", round4(0.75 * sigma_t));
        cJSON_AddNumberToObject(m, "sigma_s", round4(0.25 * sigma_t));
        cJSON *tj = cJSON_AddObjectToObject(m, "temperature");
        cJSON_AddStringToObject(tj, "grid", tname);
        cJSON *bb = cJSON_AddObjectToObject(m, "blackbody");
        cJSON_AddNumberToObject(bb, "scale", 200);
        cJSON_AddNumberToObject(bb, "cutoff", 600);
        if (tmax > 0.0 && tmax < 100.0)
            cJSON_AddNumberToObject(bb, "temperature_scale", round4(3000.0 / tmax));
    } else {
        cJSON_AddNumberToObject(m, "sigma_a", round4(0.01 * sigma_t));
        cJSON_AddNumberToObject(m, "sigma_s", round4(0.99 * sigma_t));
    }
    cJSON *ph = cJSON_AddObjectToObject(m, "phase");
    cJSON_AddStringToObject(ph, "type", "hg");
    cJSON_AddNumberToObject(ph, "g", fire ? 0.3 : 0.6);
    return m;
}

/* A ground plane under box b along up (+y or +z), wide enough to reach the horizon of the
 * framed view. */
static void studio_ground(cJSON *root, box3 b, vec3 up)
{
    vec3 ext = v3_sub(b.hi, b.lo);
    vec3 centre = v3_scale(v3_add(b.lo, b.hi), 0.5);
    double below = v3_dot(b.lo, up); /* up is +y or +z */
    vec3 point = v3_add(v3_sub(centre, v3_scale(up, v3_dot(centre, up))), v3_scale(up, below));
    cJSON *surf = cJSON_AddArrayToObject(root, "surfaces");
    cJSON *pl = cJSON_CreateObject();
    cJSON_AddStringToObject(pl, "type", "plane");
    cJSON_AddStringToObject(pl, "name", "ground");
    cJSON_AddItemToObject(pl, "point", vec_json(point));
    cJSON_AddItemToObject(pl, "normal", vec_json(up));
    cJSON_AddNumberToObject(pl, "size", round4(40.0 * v3_length(ext)));
    cJSON *mat = cJSON_AddObjectToObject(pl, "material");
    cJSON_AddItemToObject(mat, "albedo", vec_json(v3(0.3, 0.3, 0.3)));
    cJSON_AddItemToArray(surf, pl);
}

/* The studio's files: `path`, or for a frame pattern (smoke_####.vdb) the range of its
 * files present (*first to *last; both -1 for one file). *abs gets the absolute name the
 * scene reads (the pattern kept: each frame reads its file), *one a file to list the grids
 * of (the first). */
static brume_status studio_files(const char *path, char *abs, char *one, size_t n, long *first, long *last)
{
    *first = *last = -1;
    int pat = seq_is_pattern(path);
    if (pat < 0)
        return err_status();
    if (pat == 0) {
        snprintf(one, n, "%s", path);
        if (!realpath(path, abs))
            return err_set(BRUME_ERROR_IO, "%s: cannot open: %s", path, strerror(errno));
        return BRUME_OK;
    }
    if (seq_range(path, first, last) != BRUME_OK)
        return err_status();
    seq_name(path, *first, one, n);
    const char *slash = strrchr(path, '/');
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%.*s", slash ? (int)(slash - path) + (slash == path) : 1, slash ? path : ".");
    if (!realpath(dir, abs))
        return err_set(BRUME_ERROR_IO, "%s: cannot open its folder: %s", path, strerror(errno));
    size_t len = strlen(abs);
    snprintf(abs + len, PATH_MAX - len, "/%s", slash ? slash + 1 : path);
    return BRUME_OK;
}

/* The box of grid dname's non-zero voxels and its maximum, over files first to last of a
 * sequence (one in memory at a time; first < 0: `one` alone): the box the camera frames is
 * then the same for every frame, as `brume info` gives it for the pattern. */
static brume_status studio_extent(const char *path, const char *one, long first, long last, const char *dname,
                                  box3 *b, double *rho_max)
{
    density_load_options lo;
    density_load_options_default(&lo);
    snprintf(lo.grid, sizeof lo.grid, "%s", dname);
    *b = box3_empty();
    *rho_max = 0.0;
    for (long k = first; k <= (first < 0 ? first : last); k++) {
        char name[PATH_MAX];
        if (first >= 0)
            seq_name(path, k, name, sizeof name);
        density *d = density_load_file(first >= 0 ? name : one, &lo);
        if (!d)
            return err_status();
        box3 a = scene_density_box(d);
        b->lo = v3_min(b->lo, a.lo);
        b->hi = v3_max(b->hi, a.hi);
        *rho_max = fmax(*rho_max, density_max(d));
        density_release(d);
    }
    return BRUME_OK;
}

brume_status scene_studio_json(const char *path, const brume_studio_options *opts, char **json)
{
    *json = NULL;
    brume_studio_options o = {0};
    if (opts)
        o = *opts;
    if (o.up != BRUME_AXIS_Y && o.up != BRUME_AXIS_Z)
        return err_set(BRUME_ERROR_INVALID_ARGUMENT, "%s: studio up axis %d: BRUME_AXIS_Y or BRUME_AXIS_Z", path,
                       (int)o.up);
    if (!(o.optical_depth >= 0.0 && o.optical_depth <= 1e6))
        return err_set(BRUME_ERROR_RANGE, "%s: studio optical depth %.17g outside [0, 1e6]", path, o.optical_depth);
    double depth = o.optical_depth > 0.0 ? o.optical_depth : STUDIO_OPTICAL_DEPTH;
    vec3 up = o.up == BRUME_AXIS_Z ? v3(0, 0, 1) : v3(0, 1, 0);

    char abs[PATH_MAX], one[PATH_MAX];
    long first, last;
    if (studio_files(path, abs, one, sizeof one, &first, &last) != BRUME_OK)
        return err_status();
    char dname[128], tname[128];
    double tmax = 0.0, rho_max;
    box3 b;
    if (pick_grids(one, o.grid, dname, sizeof dname, tname, &tmax) != BRUME_OK ||
        studio_extent(path, one, first, last, dname, &b, &rho_max) != BRUME_OK)
        return err_status();
    if (!(b.lo.x < b.hi.x && b.lo.y < b.hi.y && b.lo.z < b.hi.z) || !(rho_max > 0.0))
        return err_set(BRUME_ERROR_RANGE, "%s: grid \"%s\" is empty (no voxel above 0)", path, dname);
    vec3 ext = v3_sub(b.hi, b.lo);
    double shortest = fmin(ext.x, fmin(ext.y, ext.z));
    double sigma_t = depth / (rho_max * shortest);

    cJSON *root = cJSON_CreateObject();
    char note[512];
    snprintf(note, sizeof note,
             "brume's studio scene for %s: the camera framed on the grid, a sun and a sky%s; extinction scaled to "
             "optical depth %g across the box's shortest side at the densest voxel (docs/production.md)",
             path, o.no_ground ? "" : ", a ground plane", depth);
    cJSON_AddStringToObject(root, "comment", note);
    cJSON *cam = cJSON_AddObjectToObject(root, "camera");
    if (first < 0) {
        cJSON_AddStringToObject(cam, "frame", "media");
    } else { /* a sequence: the box over its files, the same camera for every frame */
        cJSON *fb = cJSON_AddArrayToObject(cam, "frame");
        cJSON_AddItemToArray(fb, vec_json(b.lo));
        cJSON_AddItemToArray(fb, vec_json(b.hi));
    }
    cJSON_AddItemToObject(cam, "up", vec_json(up));
    cJSON_AddNumberToObject(cam, "fov", 30);
    cJSON_AddItemToObject(root, "background", vec_json(v3(0.2, 0.33, 0.62)));
    cJSON *lights = cJSON_AddArrayToObject(root, "lights");
    cJSON *sun = cJSON_CreateObject();
    cJSON_AddStringToObject(sun, "type", "distant");
    cJSON_AddItemToObject(sun, "direction", vec_json(v3_neg(studio_dir(up, STUDIO_SUN_AZIMUTH, STUDIO_SUN_ELEVATION))));
    cJSON_AddItemToObject(sun, "irradiance", vec_json(v3(3.4, 3.2, 2.9)));
    cJSON_AddNumberToObject(sun, "angular_radius", 0.27);
    cJSON_AddItemToArray(lights, sun);

    cJSON_AddItemToArray(cJSON_AddArrayToObject(root, "media"), studio_medium(abs, dname, tname, tmax, sigma_t));
    if (!o.no_ground)
        studio_ground(root, b, up);
    cJSON *r = cJSON_AddObjectToObject(root, "render");
    cJSON_AddNumberToObject(r, "width", 640);
    cJSON_AddNumberToObject(r, "height", 480);
    cJSON_AddNumberToObject(r, "spp", 64);
    cJSON_AddStringToObject(r, "method", "path");
    cJSON_AddNumberToObject(r, "max_depth", 256);
    *json = cJSON_Print(root);
    cJSON_Delete(root);
    if (!*json)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    return BRUME_OK;
}
