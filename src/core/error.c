/* error.c - thread-local last error, status strings, and the context's error hand-off. */
#include "core/error.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>

static _Thread_local char err_buf[1024];
static _Thread_local brume_status err_code = BRUME_OK;

brume_status err_set(brume_status status, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err_buf, sizeof err_buf, fmt, ap);
    va_end(ap);
    err_code = status;
    return status;
}

const char *err_message(void) { return err_buf; }

brume_status err_prefix(const char *fmt, ...)
{
    char old[sizeof err_buf], head[512];
    snprintf(old, sizeof old, "%s", err_buf);
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(head, sizeof head, fmt, ap);
    va_end(ap);
    size_t hl = strlen(head), ol = strlen(old), cap = sizeof err_buf - 1;
    if (hl > cap - 2)
        hl = cap - 2;
    memcpy(err_buf, head, hl);
    memcpy(err_buf + hl, ": ", 2);
    if (ol > cap - hl - 2)
        ol = cap - hl - 2;
    memcpy(err_buf + hl + 2, old, ol);
    err_buf[hl + 2 + ol] = '\0';
    return err_code;
}
brume_status err_status(void) { return err_code; }
void err_clear(void)
{
    err_buf[0] = '\0';
    err_code = BRUME_OK;
}

const char *brume_status_string(brume_status s)
{
    switch (s) {
    case BRUME_OK: return "ok";
    case BRUME_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case BRUME_ERROR_IO: return "input/output error";
    case BRUME_ERROR_PARSE: return "malformed input";
    case BRUME_ERROR_OUT_OF_MEMORY: return "out of memory";
    case BRUME_ERROR_UNSUPPORTED: return "unsupported";
    case BRUME_ERROR_RANGE: return "value out of range";
    case BRUME_ERROR_STATE: return "object used in the wrong state";
    case BRUME_ERROR_CANCELLED: return "cancelled";
    }
    return "unknown status";
}
