/* args.h - strict parsing of command-line values, shared by the subcommands. */
#ifndef BRUME_CLI_ARGS_H
#define BRUME_CLI_ARGS_H

#include <stdbool.h>
#include <stdint.h>

/* Each returns false and prints "brume: FLAG: ..." when text is not a valid value in range. */
bool arg_int(const char *flag, const char *text, long lo, long hi, int *out);
bool arg_u64(const char *flag, const char *text, uint64_t *out);
bool arg_double(const char *flag, const char *text, double lo, double hi, double *out);
/* Integer text (optional '-', decimal digits only) in [lo, hi] without overflow; no message. */
bool arg_parse_long(const char *text, long lo, long hi, long *out);
/* Rewrites every "--key=value" before a "--" into the two arguments "--key" "value", so
 * that every flag of every subcommand takes both forms (getopt's convention). */
void args_split_equals(int *argc, char ***argv);
/* The value after argv[*i] (advancing *i), or NULL with a message when missing. */
const char *arg_value(int argc, char **argv, int *i);

#endif
