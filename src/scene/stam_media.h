/* stam_media.h - what Stam's options do to a scene's blob fields (scene/stam_media.c). */
#ifndef BRUME_SCENE_STAM_MEDIA_H
#define BRUME_SCENE_STAM_MEDIA_H

#include "density/randfield.h"
#include "scene/scene.h"

/* The extent of the scene's blob fields (bounds of all of them, per axis; 0 without any). */
vec3 stam_blob_extent(const brume_scene *s);

/* Stam's random field Q for the scene's blob fields (stam.*, at the scene's time, over their
 * extent): a new field owned by the caller, NULL on failure (err_set). The stam renderer,
 * stam.voxelize and blasi.voxels all draw their Q here. */
randfield *stam_scene_randfield(const brume_scene *s);

/* Every blob field of s as a dense grid of `resolution` cells along its longest axis
 * (density/blobs.h, blob_field_grid): one realization of Stam's random blobs, with one Q
 * (stam.*, at the scene's time) for all of them, when `realization` and stam.eps > 0, else
 * the mean. grids[m] is media[m]'s new grid, owned by the caller, or NULL when media[m] is no
 * blob field. Used by stam.voxelize and by blasi.voxels: one voxeliser for both. On failure
 * every grids[m] is NULL and err_set() names the source, the medium and `option`. */
brume_status stam_voxelize_blobs(const brume_scene *s, int resolution, bool realization, const char *option,
                                 density *grids[SCENE_MAX_MEDIA]);

/* At commit (stam_media.c): moves drifting blob fields to stam.time + the frame time, sets
 * their lookup (stam.bvh), and with stam.voxelize replaces each by a dense grid. */
brume_status stam_commit_media(brume_scene *s);
/* True when some blob field drifts or its Q evolves (stam.rate > 0): the world moves. */
bool stam_media_move(const brume_scene *s);

#endif
