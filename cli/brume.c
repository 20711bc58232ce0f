/* brume.c - the brume tool: dispatches subcommands (cli/commands.h) over libbrume. */
#include <stdio.h>
#include <string.h>

#include "args.h"
#include "brume.h"
#include "commands.h"

static void usage(FILE *out)
{
    fprintf(out, "usage: brume COMMAND [ARGS]\n\ncommands:\n");
#define X(name, summary) fprintf(out, "  %-10s %s\n", #name, summary);
    BRUME_COMMANDS(X)
#undef X
    fprintf(out, "  %-10s %s\n", "help", "this text, or `brume help COMMAND` for one command");
    fprintf(out, "\noptions:\n  --version  print the version\n"
                 "\nenvironment:\n  BRUME_MODULE_PATH  the folder of libbrume-openvdb.so (.vdb files), when not beside\n"
                 "                     libbrume or in the install's library folder\n"
                 "\nSee `man brume`, and README.md and docs/ (installed in PREFIX/share/doc/brume);\n"
                 "example scenes and their data are installed in PREFIX/share/brume.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage(stderr);
        return 2;
    }
    args_split_equals(&argc, &argv); /* --key=value as --key value, for every command */
    const char *cmd = argv[1];
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "version") == 0) {
        printf("brume %s\n", brume_version());
        return 0;
    }
    if (strcmp(cmd, "help") == 0 || strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0) {
        if (argc >= 3) {
            char *sub[] = {argv[2], "--help", NULL};
#define X(name, summary)                                                                        \
    if (strcmp(argv[2], #name) == 0)                                                            \
        return cmd_##name(2, sub);
            BRUME_COMMANDS(X)
#undef X
            cli_error("help: unknown command '%s'", argv[2]);
            return 2;
        }
        usage(stdout);
        return 0;
    }
#define X(name, summary)                                                                        \
    if (strcmp(cmd, #name) == 0)                                                                \
        return cmd_##name(argc - 1, argv + 1);
    BRUME_COMMANDS(X)
#undef X
    cli_error("unknown command '%s' (try `brume help`)", cmd);
    return 2;
}
