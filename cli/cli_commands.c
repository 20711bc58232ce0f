/* cli_commands.c - every command's flag table (cli_flags.h), in `brume help`'s order: the
 * list README's usage block and the help follow. */
#include "cli_flags.h"
#include "commands.h"

const cli_command *const cli_all_commands[] = {
#define X(name) &cli_##name##_command,
    CLI_COMMAND_TABLES(X)
#undef X
};
const int cli_ncommands = (int)(sizeof cli_all_commands / sizeof *cli_all_commands);
