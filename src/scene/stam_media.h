/* stam_media.h - what Stam's options do to a scene's blob fields (scene/stam_media.c). */
#ifndef BRUME_SCENE_STAM_MEDIA_H
#define BRUME_SCENE_STAM_MEDIA_H

#include "scene/scene.h"

/* The extent of the scene's blob fields (bounds of all of them, per axis; 0 without any). */
vec3 stam_blob_extent(const brume_scene *s);

/* At commit (stam_media.c): moves drifting blob fields to stam.time + the frame time, sets
 * their lookup (stam.bvh), and with stam.voxelize replaces each by a dense grid. */
brume_status stam_commit_media(brume_scene *s);
/* True when some blob field drifts or its Q evolves (stam.rate > 0): the world moves. */
bool stam_media_move(const brume_scene *s);

#endif
