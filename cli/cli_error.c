/* cli_error.c - the one-line error report shared by the subcommands (commands.h). Kept in
 * the commands' library so that tests calling cmd_NAME() link without the tool's main; a
 * dispatcher that defines its own cli_error takes precedence (archive members are pulled
 * only for undefined symbols). */
#include <stdarg.h>
#include <stdio.h>

#include "brume.h"
#include "commands.h"

void cli_error(const char *fmt, ...)
{
    /* formatted as the library's messages are: control characters in arguments escaped */
    char msg[2048];
    va_list ap;
    va_start(ap, fmt);
    brume_vformat_message(msg, sizeof msg, fmt, ap);
    va_end(ap);
    fprintf(stderr, "brume: %s\n", msg);
}
