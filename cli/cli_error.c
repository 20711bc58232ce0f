/* cli_error.c - the one-line error report shared by the subcommands (commands.h). Kept in
 * the commands' library so that tests calling cmd_NAME() link without the tool's main; a
 * dispatcher that defines its own cli_error takes precedence (archive members are pulled
 * only for undefined symbols). */
#include <stdarg.h>
#include <stdio.h>

#include "commands.h"

void cli_error(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fputs("brume: ", stderr);
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
}
