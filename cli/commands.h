/* commands.h - the subcommands of the brume tool, one line each: X(name, summary).
 * Each is implemented as `int cmd_NAME(int argc, char **argv)` in cli/cmd_NAME.c, gets
 * argv[0] = "NAME", and returns the process exit status (0 ok, 1 failure, 2 usage). */
#ifndef BRUME_CLI_COMMANDS_H
#define BRUME_CLI_COMMANDS_H

#include <stdio.h>

#define BRUME_COMMANDS(X)                                                   \
    X(render, "render a scene (or the built-in default scene) to an image") \
    X(phase, "phase functions: fit a Schlick mixture, plot")               \
    X(slab, "reflectance and transmittance of a plane-parallel slab")     \
    X(compare, "error figures and a difference picture of two images")    \
    X(denoise, "filter a rendered EXR with its variance and feature layers") \
    X(info, "print a grid file's format, dimensions, bounds, values and memory") \
    X(convert, "convert a grid file between raw, df3, vol, nvdb and vdb")       \
    X(gen, "generate grids: a fractal cloud, a flame, an upsampled cloud (gen cloud|fire|upres)") \
    X(devices, "list the GPUs brume can render on (or say why there are none)") \
    X(figures, "render every figure of both papers into a folder, with an index") \
    X(sweep, "render a scene over one or two parameters into a labelled contact sheet") \
    X(options, "list the rendering methods' options (METHOD.KEY for --set and scene files)")

#define X(name, summary) int cmd_##name(int argc, char **argv);
BRUME_COMMANDS(X)
#undef X

/* The methods' option keys, wrapped, for a command's help (cmd_options.c). */
void cli_options_keys(FILE *out);
/* docs/scene-format.md's tables of "Method options" (`brume options --markdown`). */
void cli_options_markdown(FILE *out);

/* Shared by commands: print "brume: MESSAGE" on stderr. */
void cli_error(const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 1, 2)))
#endif
    ;

#endif
