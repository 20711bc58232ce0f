/* scene.h - the scene behind brume_scene: camera, lights, media, background, settings.
 * Built unlocked through the public builders (scene/scene_build.c, scene_media.c,
 * scene_shapes.c; the scene file reader is their client), then frozen by commit; rendering
 * reads it from many threads and never writes. */
#ifndef BRUME_SCENE_SCENE_H
#define BRUME_SCENE_SCENE_H

#include "brume.h"
#include "core/budget.h"
#include "medium/medium.h"
#include "scene/background.h"
#include "scene/camera.h"
#include "scene/light.h"
#include "core/regular_file.h"
#include "method/method_options.h"
#include "surface/surfaces.h"

#define SCENE_MAX_MEDIA 16
#define SCENE_MAX_LIGHTS 4096
#define SCENE_MAX_WORK_DEFAULT BUDGET_DEFAULT_WORK /* render.max_work (core/budget.h) */

struct brume_scene {
    bool committed;
    char source[512]; /* file the scene came from, or "<default scene>" */
    camera cam;
    light *lights; /* owned */
    int nlights, lights_cap;
    medium media[SCENE_MAX_MEDIA];
    int nmedia;
    surfaces *surf;   /* solid objects (owned), or NULL when the scene has none */
    background bg;    /* radiance arriving from infinity (Blasi's L-infinity) */
    brume_render_settings settings;
    void *options[METHOD_OPTIONS_COUNT]; /* owned: each method's options, opaque here
                                            (method/method_options.h; scene_options()) */
    bool has_emission; /* some medium has Le > 0 (set by commit) */
    bool flight_control; /* scene_flight_control, set by commit */
    bool has_indirect_sources; /* emission, area lights or a background: light a path can reach by
                                  phase sampling (set by commit) */
    double time;       /* the frame's time, seconds (brume_scene_set_time) */
    bool world_moves;  /* something besides the camera depends on time (set by the builders;
                          brume_scene_world_is_static adds moving surfaces and blobs) */
    struct scene_prepared *prepared; /* owned: the integrator state kept across renders */
    size_t max_memory; /* bytes: render.max_memory_mb, the limit of what rendering allocates too */
    size_t memory_used; /* bytes of max_memory taken by reading and committing (core/budget.h) */
    size_t memory_held; /* bytes another scene holds until commit (brume_load_options.memory_held) */
    io_inputs inputs;   /* the files the scene was read from (core/regular_file.h), owned */
    double max_work;    /* render.max_work: units of work a method may estimate before it starts
                           (a step of a ray, a voxel generated, a blob at a lattice point) */
    char camera_medium[64]; /* brume_scene_set_camera_medium: "" or the medium the camera sits in */
    /* Bounded media (docs/surfaces.md, "How surfaces meet media"): bit m is set when a
     * surface names media[m] as its inside or outside medium (set by commit); 0 when every
     * medium is a free field, present everywhere (then nothing below is looked at). */
    uint32_t bounded;
    bool has_interfaces;     /* some surface bounds media (set by commit): rays cross surfaces */
    uint32_t camera_members; /* bounded media the camera.medium names (set by commit) */
    struct scene_bound *bound; /* owned: brume_scene_set_surface_media's, resolved by commit */
    int nbound;
    char **ignored;     /* the scene file's "ignored" list (brume_scene_ignored), owned */
    int nignored;
    struct {
        bool on;        /* brume_scene_frame_camera was called: commit moves the camera */
        char media[64]; /* "media" = all of them, else one medium's name */
        bool box;       /* brume_scene_frame_camera_box: frame `bounds`, not the media */
        box3 bounds;
        double margin;  /* fraction of the frame left around the box, [0, 0.9] */
    } frame;
};

/* What integrator_prepare built for this scene, reused by later renders of it. Rendering
 * reads a scene through a const pointer; this is the one part it writes (one render at a
 * time per scene). prepare must depend on the world only, never on the camera, so that
 * brume_scene_set_camera_time keeps it valid. */
typedef struct scene_prepared {
    bool valid;
    int kind;    /* integrator_kind */
    void *state; /* integrator_prepare's */
    void (*finish)(int kind, void *state); /* releases state (integrator_finish: the renderer
                                              above this layer sets it) */
    brume_stats stats; /* of the last render (brume_scene_stats) */
} scene_prepared;

/* An empty scene with default settings and camera; NULL when out of memory. */
brume_scene *scene_new(const char *source);
/* Method `id`'s options struct (method/method_options.h): blasi_options, stam_params. */
const void *scene_options(const brume_scene *s, method_options_id id);

/* Validates settings (err_set names the field); BRUME_OK when usable. */
brume_status scene_check_settings(const char *source, const brume_render_settings *rs);
void scene_default_settings(brume_render_settings *rs);

/* The built-in default scene as scene-file JSON (docs/scene-format.md). */
extern const char scene_default_json[];

/* Reads a scene file text (scene/scene_json.c) at time 0. `source` names it in messages. */
brume_status scene_parse_json(const char *text, const char *source, brume_scene **out);
/* The same at frame time `time` (seconds), or, when frame_no >= 0, at frame_no / render.fps. */
brume_status scene_parse_json_at(const char *text, const char *source, double time, long frame_no, brume_scene **out);
/* The same after applying overrides "KEY=VALUE" to the document (scene/scene_override.h). */
brume_status scene_parse_json_with(const char *text, const char *source, double time, long frame_no,
                                   const char *const *overrides, int noverrides, brume_scene **out);
/* A source's name in messages: its path, "<json>" for an unnamed text, "<default scene>". */
const char *scene_source_name(const brume_source *src);
/* brume_scene_text without a context: the JSON the loader reads for src (scene/scene_json.c). */
brume_status scene_load_text(const brume_source *src, const brume_load_options *opts, char **json);

/* Whether flights may take control collisions (integrator.c, flight_step): one medium, no
 * fields, gray sigma_t. Call after medium_init. */
bool scene_flight_control(const brume_scene *s);

/* Commit's resolution of brume_scene_set_surface_media (scene/scene_bounded.c): names to
 * media, s->bounded, s->camera_members, each surface's surface_media; refuses unknown
 * names and open shapes bounding media (err_set names the key). Before surfaces_commit. */
brume_status scene_bounded_resolve(brume_scene *s);

/* Commit's auto-framing (scene/scene_frame.c): moves the camera onto the media that
 * brume_scene_frame_camera named; BRUME_OK at once when it was not called. */
brume_status scene_frame_resolve(brume_scene *s);
/* Commit's check of brume_scene_set_camera_medium (scene/scene_frame.c): the medium named
 * exists, is at rest, and its field's box holds every point a camera ray starts from. */
brume_status scene_camera_medium_check(const brume_scene *s);
/* The world box holding every non-zero value of d (its voxel box cut to the cells that are
 * not empty), or an empty box: what framing looks at. */
box3 scene_density_box(const density *d);

#endif
