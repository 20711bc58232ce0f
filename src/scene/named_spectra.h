/* named_spectra.h - pbrt-v4's named spectra of materials ("metal-Cu-eta", "glass-BK7", ...)
 * as the RGB values brume renders with. */
#ifndef BRUME_SCENE_NAMED_SPECTRA_H
#define BRUME_SCENE_NAMED_SPECTRA_H

#include <stdbool.h>

/* The RGB of the named spectrum; false for a name brume does not know. */
bool named_spectrum_rgb(const char *name, double rgb[3]);
/* The names, comma-separated, for messages. */
const char *named_spectrum_list(void);

#endif
