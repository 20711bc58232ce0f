/* brume.c - the brume tool: dispatches subcommands (cli/commands.h) over libbrume. */
#include <errno.h>
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "brume.h"
#include "cli_flags.h"
#include "commands.h"

/* Standard output written whole, or the exit status 1 with a message (a full disk, a closed
 * pipe, /dev/full): a command's output that did not arrive is a failure. */
static int stdout_written(int rc)
{
    int err = fflush(stdout) == 0 ? 0 : errno;
    if (!err && !ferror(stdout))
        return rc;
    cli_error("cannot write to standard output: %s", err ? strerror(err) : "a write failed");
    return rc ? rc : 1;
}

static int run(int argc, char **argv)
{
    const char *cmd = argv[1];
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("brume %s\n", brume_version());
        return 0;
    }
    if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0)
        return cli_help(argc - 1, argv + 1);
#define X(name, summary)                                                                        \
    if (strcmp(cmd, #name) == 0)                                                                \
        return cmd_##name(argc - 1, argv + 1);
    BRUME_COMMANDS(X)
#undef X
    cli_error("unknown command '%s' (try `brume help`)", cmd);
    return 2;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        cli_usage(stderr);
        return 2;
    }
    args_split_equals(&argc, &argv); /* --key=value as --key value, for every command */
    return stdout_written(run(argc, argv));
}
