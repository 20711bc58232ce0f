/* pbrt.h - what the files of the pbrt-v4 reader share (scene_pbrt.c and pbrt_*.c): the
 * tokens, a directive's parameter list, 4 x 4 transforms and the translation's state. The
 * reader's entry points are in scene/scene_pbrt.h. */
#ifndef BRUME_SCENE_PBRT_H
#define BRUME_SCENE_PBRT_H

#include <limits.h>
#include <stdbool.h>

#include "brume.h"
#include "core/vec.h"
#include "io/json.h"
#include "scene/scene_build.h"

#define PBRT_MAX_BYTES (64L << 20)
/* the values of one parameter (an inline grid's samples or a mesh's points, 3 numbers each)
 * and of one directive's parameters together (rgbgrid's two RGB grids): 100 MiB of doubles */
#define PBRT_MAX_VALUES (3 * SCENE_INLINE_MAX_VALUES)
#define PBRT_MAX_DIRECTIVE_VALUES (6 * SCENE_INLINE_MAX_VALUES)
/* the numbers of every inline grid and mesh of one scene: the translation's JSON nodes then
 * stay under about 300 MiB */
#define PBRT_MAX_SCENE_INLINE (2 * SCENE_INLINE_MAX_VALUES)
#define PBRT_MAX_PARAMS 32
#define PBRT_MAX_MEDIA 16
#define PBRT_MAX_DEPTH 64

/* ---- tokens ------------------------------------------------------------------------------ */

/* TOK_BAD: a token the file cannot hold (an unterminated string, an unknown escape, a word
 * longer than text); `bad` says which, and every refusal made on it reports that instead */
typedef enum { TOK_END, TOK_WORD, TOK_STRING, TOK_OPEN, TOK_CLOSE, TOK_BAD } tok_kind;

typedef struct lexer {
    const char *file;
    const char *p;
    int line;
    tok_kind kind; /* the current token */
    char text[1024];
    int tok_line;
    int dir_line;  /* the line of the directive being read: what refusals name */
    const char *bad; /* why the current token is TOK_BAD */
    /* Include's continued parameter lists: the including file's lexer, past the file's name
     * (owned by include_directive's frame while the included file is read; NULL in the main
     * file, in an Import and in a replayed object). A parameter list that reaches the end of
     * the included file goes on in the including one, as pbrt-v4's tokenizer does, and
     * `resumed` tells include_directive that the lexer is now the including file's. */
    const struct lexer *outer;
    bool in_params, resumed;
} lexer;

/* ---- parameter lists --------------------------------------------------------------------- */

typedef struct param {
    char type[16], name[64];
    int n, cap;                      /* values; numbers allocated in v */
    double *v;                       /* numbers (malloc'd; an array's values) */
    char s[1024];                    /* the string values, each ended by its NUL, one after another */
    bool is_string, used;
    int line;
} param;

typedef struct params {
    int n;
    long values; /* numbers over all n */
    param p[PBRT_MAX_PARAMS];
    struct cJSON *ignored; /* --lenient: pbrt_all_used lists an unknown parameter here (pbrt_ignore)
                              and goes on without it; NULL: it refuses it */
} params;

/* ---- transforms: 4 x 4 row-major, p' = M p ------------------------------------------------- */

typedef struct m4 {
    double m[16];
} m4;

/* ---- the translation ------------------------------------------------------------------------ */

typedef struct named_medium {
    char name[128];
    cJSON *json; /* the brume medium, emitted when a shape first uses it */
    bool emitted;
    bool homogeneous; /* json has no density until pbrt_media_finish: a constant one over `box` */
    double box[6];    /* homogeneous: lo, hi of what its uses need (empty: lo > hi) */
} named_medium;

/* A drawn shape's material as the JSON of a brume material (pbrt_materials.c), its textures
 * as {"$tex": index in pbrt_state.textures} (pbrt_material_json puts them in); "" for an
 * interface. */
#define PBRT_MATERIAL_JSON 2048

typedef struct attrs {
    m4 ctm;
    char material[32]; /* its pbrt type: "diffuse", "dielectric", ... or "interface" */
    char mat_json[PBRT_MATERIAL_JSON];
    bool textured; /* mat_json names a texture: the shape needs (u, v) */
    char inside[128], outside[128];
    int begin_line; /* the line of the AttributeBegin that opened this level (depth > 0) */
    bool area, area_two_sided; /* AreaLightSource "diffuse" in effect: shapes emit area_L */
    double area_L[3];
    double area_power; /* its "power", watts (0: none): area_L scaled per shape (pbrt_shapes.c) */
    bool reverse; /* ReverseOrientation in effect: the shapes' normals reversed (pbrt_shapes.c) */
} attrs;

typedef struct named_material {
    char name[128];
    char material[32]; /* as attrs' */
    char mat_json[PBRT_MATERIAL_JSON];
    bool textured;
} named_material;

/* Texture "name" "float"|"spectrum" "class": its brume JSON tree, kept to the end (a later
 * texture of the same name and kind replaces it for what follows, as in pbrt-v4). */
typedef struct named_texture {
    char name[128];
    bool is_float;
    cJSON *json;
} named_texture;
#define PBRT_MAX_TEXTURES 256
#define PBRT_MAX_MATERIALS 64

/* ObjectBegin "name" ... ObjectEnd: its directives, replayed by ObjectInstance. */
typedef struct pbrt_object {
    char name[128];
    lexer at;   /* just after ObjectBegin "name", in a text kept to the end */
    attrs a;    /* the graphics state at ObjectBegin */
} pbrt_object;
#define PBRT_MAX_OBJECTS 256
#define PBRT_MAX_TEXTS 256

/* A MediumInterface name a shape used before any MakeNamedMedium gave it: resolved at the
 * end of the file (pbrt_medium_bind), as pbrt-v4 resolves names when it creates the scene. */
typedef struct pbrt_pending_medium {
    char name[128];
    double box[6];
    bool outside;
    char *file; /* the Shape's file (malloc'd) and line */
    int line;
} pbrt_pending_medium;

typedef struct pbrt_state {
    lexer L;
    const char *path;
    char dir[PATH_MAX];
    attrs a[PBRT_MAX_DEPTH];
    int depth;
    bool have_camera, world;
    int world_line; /* the line of WorldBegin */
    bool mirror; /* pbrt's left-handed view: the world is translated mirrored in x (camera_directive) */
    char camera_medium[128]; /* the outside medium of the MediumInterface at Camera; "" for none */
    int camera_line;         /* the Camera directive's line */
    int far_light_line;      /* the first distant or infinite light's line (0: none) */
    char far_light[16];      /* and its type */
    double box_filter;       /* PixelFilter "box": its width in pixels (0: none given) */
    double max_component;    /* Film "maxcomponentvalue" (0: none given) */
    double white_balance;    /* Film "whitebalance", kelvin (0: none; a camera's 6500 K) */
    int sensor;              /* Film "sensor": film_sensor_find's number (0: cie1931) */
    double iso, exposure_time; /* Film "iso" and the Camera's shutterclose - shutteropen (pbrt_imaging) */
    m4 world_from_camera;
    double fov, lens_radius, focal_distance;
    int xres, yres, spp, max_depth;
    named_medium media[PBRT_MAX_MEDIA];
    int nmedia;
    pbrt_pending_medium *pending; /* malloc'd */
    int npending;
    named_material materials[PBRT_MAX_MATERIALS]; /* MakeNamedMaterial */
    int nmaterials;
    cJSON *root, *lights, *media_j, *surfaces;
    double background[3];
    bool have_background;
    double inline_numbers; /* numbers of the inline grids and meshes written so far */
    size_t text_bytes;     /* the file's, and those it includes */
    int includes;          /* Include and Import files open, one within the other */
    char *texts[PBRT_MAX_TEXTS]; /* the included files' texts, kept for ObjectInstance */
    int ntexts;
    pbrt_object objs[PBRT_MAX_OBJECTS]; /* ObjectBegin */
    int nobjs;
    bool instancing;       /* an ObjectInstance is being read */
    long objects;          /* typed directives read so far (count_translation) */
    named_texture textures[PBRT_MAX_TEXTURES];
    int ntextures;
    cJSON *ignored;        /* --lenient: the refusals of what was skipped, each once (pbrt_ignore); NULL: strict */
} pbrt_state;
#define PBRT_MAX_IGNORED SCENE_MAX_IGNORED

/* scene_pbrt.c */
/* Keeps the translation's estimated memory within the memory limit (pbrt_tokens.c). */
brume_status pbrt_count_translation(pbrt_state *S);
brume_status pbrt_count_inline(pbrt_state *S, const char *what, double n);
brume_status pbrt_resolve_file(pbrt_state *S, const char *what, const char *file, char abs[PATH_MAX]);

/* pbrt_tokens.c */
void pbrt_next(lexer *L);
/* Malformed input (BRUME_ERROR_PARSE) and what brume cannot honour (BRUME_ERROR_UNSUPPORTED):
 * "FILE:LINE: message", the directive's line. */
brume_status pbrt_fail(const lexer *L, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
brume_status pbrt_unsupported(const lexer *L, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* A refusal of the current token: "FILE:LINE: WHAT, found \"TOKEN\"", or "... found the end of
 * the file (truncated?)"; on a TOK_BAD, what is wrong with that token. */
brume_status pbrt_expected(const lexer *L, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
void pbrt_copy(char *dst, size_t cap, const char *src);
brume_status pbrt_numbers(lexer *L, const char *dir, int n, double *out);
void pbrt_params_clear(params *ps);
brume_status pbrt_read_params(lexer *L, params *ps);
param *pbrt_get(params *ps, const char *name);
brume_status pbrt_get_float(lexer *L, params *ps, const char *name, double *out);
brume_status pbrt_get_point(lexer *L, params *ps, const char *name, double out[3]);
brume_status pbrt_get_color(lexer *L, params *ps, const char *name, double out[3]);
brume_status pbrt_get_string(lexer *L, params *ps, const char *name, char *out, size_t n);
brume_status pbrt_all_used(const lexer *L, const params *ps, const char *dir);
/* --lenient: adds this thread's last message (a pbrt_unsupported refusal) to the list of what
 * was ignored unless it is there already, and clears it; a refusal past PBRT_MAX_IGNORED. */
brume_status pbrt_ignore(struct cJSON *ignored, const char *path);
brume_status pbrt_get_count(lexer *L, params *ps, const char *name, int *out);
brume_status pbrt_get_array(lexer *L, params *ps, const char *name, const char *const *types, param **out);

/* pbrt_structure.c: the block of each directive and the nesting of blocks, as pbrt-v4 checks them */
brume_status pbrt_structure_directive(pbrt_state *S, const char *dir);
brume_status pbrt_attribute_begin(pbrt_state *S, const char *dir);
brume_status pbrt_attribute_end(pbrt_state *S, const char *dir);
brume_status pbrt_structure_end(pbrt_state *S);

/* pbrt_materials.c: a Material or MakeNamedMaterial of the type, its parameters read, into
 * its pbrt type name (material) and brume's material JSON (json); *textured whether it names
 * a texture */
brume_status pbrt_material_read(pbrt_state *S, const char *type, const char *what, params *ps, char material[32],
                                char json[PBRT_MATERIAL_JSON], bool *textured);
/* The current material a's JSON with its textures put in (NULL when out of memory, err_set). */
cJSON *pbrt_material_json(const pbrt_state *S, const attrs *a);

/* pbrt_transform.c */
m4 pbrt_m4_identity(void);
m4 pbrt_m4_mul(m4 a, m4 b);
bool pbrt_m4_inverse(m4 a, m4 *out);
vec3 pbrt_m4_point(m4 a, vec3 p);
vec3 pbrt_m4_vector(m4 a, vec3 v);
m4 pbrt_m4_scale(double x, double y, double z);
/* What makes a into no placement: "not finite", "projective ...", "singular ..."; NULL when none. */
const char *pbrt_m4_flaw(m4 a);
cJSON *pbrt_transform_json(m4 a, bool *oom);
m4 pbrt_world_origin(const pbrt_state *S);
brume_status pbrt_transform_directive(pbrt_state *S, attrs *a, const char *dir, bool *handled);

/* pbrt_camera.c */
brume_status pbrt_camera_directive(pbrt_state *S, const char *type, params *ps);
brume_status pbrt_setting_directive(pbrt_state *S, attrs *a, const char *dir, const char *type, const char *what,
                                    params *ps);

/* pbrt_lights.c */
brume_status pbrt_light_directive(pbrt_state *S, const char *type, params *ps);
void pbrt_imaging(pbrt_state *S);
brume_status pbrt_illuminant(lexer *L, params *ps, const char *name, double out[3]);
brume_status pbrt_area_light_directive(pbrt_state *S, attrs *a, const char *type, params *ps);

/* pbrt_media.c */
brume_status pbrt_medium_directive(pbrt_state *S, const char *name, params *ps);
brume_status pbrt_camera_medium(pbrt_state *S, cJSON *cam, vec3 position);
/* A medium a shape names (pbrt_shapes.c): emitted into the scene once; a homogeneous one's
 * box grows to hold box (lo, hi; NULL: nothing), and with `outside` also 64 / sigma_t around
 * it, where pbrt-v4's unbounded medium has attenuated everything. Refuses an unknown name. */
brume_status pbrt_medium_use(pbrt_state *S, const char *name, const double box[6], bool outside);
/* pbrt_medium_use, or for a name not defined yet, kept to pbrt_media_resolve. */
brume_status pbrt_medium_bind(pbrt_state *S, const char *name, const double box[6], bool outside);
/* At the end of the file: each kept name's medium used, or a refusal naming the Shape's file
 * and line; frees what pbrt_medium_bind kept (also after an error: pbrt_media_free). */
brume_status pbrt_media_resolve(pbrt_state *S);
void pbrt_media_free(pbrt_state *S);
/* Gives each homogeneous medium used its `constant` density over its box, at the end of
 * the translation (after pbrt_camera_medium). */
brume_status pbrt_media_finish(pbrt_state *S);

/* pbrt_objects.c */
brume_status pbrt_object_directive(pbrt_state *S, params *ps, const char *dir,
                                   brume_status (*directive)(pbrt_state *, params *));

/* pbrt_textures.c */
brume_status pbrt_texture_directive(pbrt_state *S, params *ps);
/* The latest Texture of that name and kind: its index in S->textures, or -1. */
int pbrt_find_texture(const pbrt_state *S, const char *name, bool is_float);
void pbrt_textures_free(pbrt_state *S);
/* A mesh's "uv" parameter q (u v per point of nv) into *uv (malloc'd). */
brume_status pbrt_mesh_uv(pbrt_state *S, const param *q, const char *what, int nv, double **uv);
/* A mesh without uv given its own three points per triangle (idx renumbered, *P and *nv
 * replaced), with pbrt-v4's default uv: pattern holds 6 numbers (u v at each corner) per
 * triangle, repeating every `period` triangles. */
brume_status pbrt_uv_unshare(pbrt_state *S, const char *what, double **P, int *nv, int *idx, int nt,
                             const double *pattern, int period, double **uv);

/* pbrt_shapes.c */
brume_status pbrt_shape_directive(pbrt_state *S, const char *type, params *ps);

/* pbrt_facing.c: pbrt-v4's front side of a shape */
bool pbrt_ctm_mirrors(const pbrt_state *S);
/* Whether a quadric's (sphere, disk, cylinder) pbrt-v4 normal is its object normal carried to
 * the world and reversed: ReverseOrientation xor a handedness-swapping transform. */
bool pbrt_quadric_reversed(const pbrt_state *S);
/* For each of the nt triangles idx over the world points P (nv, wound as the object's), 1
 * where the winding must be reversed for brume's front to be pbrt-v4's geometric normal: the
 * object's carried through the transform (a quadric's by pbrt_quadric_reversed), reversed by
 * ReverseOrientation, and with shading normals N (a mesh's "normal N", or NULL) turned to
 * their side. *flip is malloc'd. */
brume_status pbrt_tris_facing(pbrt_state *S, const char *what, const param *N, bool quadric, const double *P, int nv,
                              const int *idx, int nt, unsigned char **flip);
void pbrt_tris_flip(int *idx, int nt, const unsigned char *flip);
bool pbrt_ply_has_normals(const char *path);

#endif
