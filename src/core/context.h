/* context.h - the public brume_context and how internal errors reach it. */
#ifndef BRUME_CORE_CONTEXT_H
#define BRUME_CORE_CONTEXT_H

#include <stdatomic.h>

#include "brume.h"

struct brume_context {
    atomic_uint load_cancels; /* brume_context_cancel_loads calls so far (core/cancel.h) */
    brume_status last_status;
    char last_error[1024];
    brume_error_fn callback;
    void *callback_user;
};

/* Copies this thread's err_set() message into ctx (if not NULL) and calls its callback
 * when status is not BRUME_OK. Returns status, so API functions end with
 * `return ctx_report(ctx, status);`. */
brume_status ctx_report(brume_context *ctx, brume_status status);

#endif
