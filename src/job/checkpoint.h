/* checkpoint.h - the checkpoint file beyond the public brume_render_job_save/resume. */
#ifndef BRUME_JOB_CHECKPOINT_H
#define BRUME_JOB_CHECKPOINT_H

#include <stdbool.h>
#include <stdint.h>

#include "brume.h"

/* Removes path when, and only when, it is a regular file (not a symbolic link) whose header
 * says it is a checkpoint of this job: this build, scene_key, the job's settings and pixel
 * count. true when removed. Anything else at path (a file brume never wrote, the scene, a
 * device node, another render's checkpoint) is left as it is. */
bool checkpoint_remove_own(const brume_render_job *job, uint64_t scene_key, const char *path);

/* h with the contents of every file scene s was read from (grids, meshes, tables, images)
 * folded in (FNV-1a): a checkpoint key that changes when any of them does. */
uint64_t checkpoint_inputs_key(const brume_scene *s, uint64_t h);

#endif
