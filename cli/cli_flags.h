/* cli_flags.h - a command's flags in one table (name, value, help, the scene key or setting
 * each one sets), read by the one parser of every command, by its help (`brume help
 * COMMAND`, the man page and bash completion read that) and by README's usage block
 * (`brume help --usage`; ctest cli_help.* checks that they agree). */
#ifndef BRUME_CLI_CLI_FLAGS_H
#define BRUME_CLI_CLI_FLAGS_H

#include <stdbool.h>
#include <stddef.h>
#include <stdio.h>

typedef enum cli_flag_kind {
    CLI_FLAG_TRUE,   /* no value: the bool at off becomes true */
    CLI_FLAG_INT,    /* an int in [lo, hi], decimal digits only (arg_int) */
    CLI_FLAG_U64,    /* a uint64_t, decimal digits only (arg_u64) */
    CLI_FLAG_DOUBLE, /* a finite double in [lo, hi] (arg_double) */
    CLI_FLAG_STRING, /* the value as given, a const char * at off */
    CLI_FLAG_CALL    /* call(opts, flag, value); value NULL when arg is NULL */
} cli_flag_kind;

typedef struct cli_flag {
    const char *name;  /* "--spp" */
    const char *alias; /* "-o", or NULL */
    const char *arg;   /* the value's name in help ("N"); NULL: the flag takes no value */
    const char *help;  /* one or more lines, '\n' between them */
    const char *sets;  /* what it sets: a scene key ("render.spp"), a field of brume_render_settings
                          ("settings.aovs") or of brume_studio_options ("studio.up"), or NULL */
    cli_flag_kind kind;
    size_t off;        /* offsetof(the command's options, the field it sets) */
    double lo, hi;     /* CLI_FLAG_INT and CLI_FLAG_DOUBLE: the range */
    /* CLI_FLAG_CALL: false after printing the one-line message */
    bool (*call)(void *opts, const struct cli_flag *flag, const char *value);
} cli_flag;

typedef struct cli_command {
    const char *name;    /* "render", "gen fire": what follows "brume " */
    const char *summary; /* one line, for README's block */
    const char *usage;   /* the synopsis after "brume NAME ", lines '\n' apart */
    const char *about;   /* the paragraphs between synopsis and flags, or NULL */
    const cli_flag *flags;
    int nflags;
    const char *notes;   /* the text after the flags, or NULL */
    void (*epilogue)(FILE *out); /* what the help prints last (text made at run time), or NULL */
} cli_command;

#define CLI_NFLAGS(table) ((int)(sizeof(table) / sizeof *(table)))

/* Every command's table, in `brume help`'s order (cli_commands.c): X(name) for the table
 * cli_NAME_command, a subcommand's as gen_fire for `brume gen fire`. */
#define CLI_COMMAND_TABLES(X)                                                                              \
    X(render) X(phase_fit) X(phase_plot) X(slab) X(compare) X(denoise) X(info) X(convert) X(gen_cloud) X(gen_fire) \
    X(gen_upres) X(devices) X(figures) X(sweep) X(options)
#define X(name) extern const cli_command cli_##name##_command;
CLI_COMMAND_TABLES(X)
#undef X
/* Every command's table, in `brume help`'s order (cli_commands.c). */
extern const cli_command *const cli_all_commands[];
extern const int cli_ncommands;

/* Parses argv[1..argc) against c's flags into opts. Operands (arguments that are not flags,
 * "-" included) go to operands[*n] in order, at most max of them. Returns -1 to go on, 0
 * after printing the help for -h or --help, 2 after a one-line message for an unknown flag,
 * a missing value or a bad one, or an operand beyond max. */
int cli_flags_parse(const cli_command *c, void *opts, int argc, char **argv, const char **operands, int max, int *n);
/* The flag named name (or its alias), or NULL. */
const cli_flag *cli_flags_find(const cli_command *c, const char *name);
/* `brume help NAME`: synopsis, about, one entry per flag, notes. */
void cli_flags_help(FILE *out, const cli_command *c);
/* README's usage block: each command's synopsis with its flags, ``` fences included. */
void cli_flags_usage_block(FILE *out);
/* `brume help`: the commands. */
void cli_usage(FILE *out);
/* `brume help [COMMAND]` (and --usage for README's block): the exit status. */
int cli_help(int argc, char **argv);

#endif
