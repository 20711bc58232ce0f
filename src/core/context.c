/* context.c - brume_context: last error and error callback. */
#include "core/context.h"

#include <stdlib.h>
#include <string.h>

#include "core/error.h"

#ifndef BRUME_VERSION_STRING
#define BRUME_VERSION_STRING "0.0.0"
#endif

const char *brume_version(void) { return BRUME_VERSION_STRING; }

brume_context *brume_context_new(void)
{
    brume_context *ctx = calloc(1, sizeof *ctx);
    if (ctx)
        atomic_init(&ctx->load_cancels, 0u);
    return ctx;
}

void brume_context_release(brume_context *ctx) { free(ctx); }

void brume_context_set_error_callback(brume_context *ctx, brume_error_fn fn, void *user)
{
    if (!ctx)
        return;
    ctx->callback = fn;
    ctx->callback_user = user;
}

const char *brume_context_last_error(const brume_context *ctx) { return ctx ? ctx->last_error : ""; }

void brume_vformat_message(char *out, size_t n, const char *fmt, va_list ap)
{
    if (!out || n == 0)
        return;
    if (!fmt)
        out[0] = '\0';
    else
        err_vformat(out, n, fmt, ap);
}
brume_status brume_context_last_status(const brume_context *ctx) { return ctx ? ctx->last_status : BRUME_OK; }

brume_status ctx_report(brume_context *ctx, brume_status status)
{
    if (!ctx)
        return status;
    ctx->last_status = status;
    if (status == BRUME_OK) {
        ctx->last_error[0] = '\0';
        return status;
    }
    const char *msg = err_message();
    if (!msg[0])
        msg = brume_status_string(status);
    size_t n = strlen(msg);
    if (n >= sizeof ctx->last_error)
        n = sizeof ctx->last_error - 1;
    memcpy(ctx->last_error, msg, n);
    ctx->last_error[n] = '\0';
    if (ctx->callback)
        ctx->callback(ctx->callback_user, status, ctx->last_error);
    return status;
}
