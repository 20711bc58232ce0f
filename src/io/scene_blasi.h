/* scene_blasi.h - the parts of the scene file that the blasi method brings
 * (docs/scene-format.md): the top-level "blasi" object of options. */
#ifndef BRUME_IO_SCENE_BLASI_H
#define BRUME_IO_SCENE_BLASI_H

#include "density/density.h"
#include "io/json.h"
#include "render/blasi_options.h"

/* Reads root's "blasi" object, if any, into *o. Paths are relative to the scene file. */
brume_status scene_parse_blasi(const cJSON *root, jloc top, blasi_options *o);

#endif
