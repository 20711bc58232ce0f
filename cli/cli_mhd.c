/* cli_mhd.c - the libmicrohttpd functions the live view (cli_serve.c) calls, forwarded to
 * the library opened by its SONAME (BRUME_MHD_SONAME, read from the library CMake found) at
 * the first call, instead of linked: libmicrohttpd brings GnuTLS, Nettle, GMP, p11-kit and
 * libtasn1, whose loading and constructors took 7 ms of every brume process's start on the
 * project's machine, for the few runs with --serve (docs/performance.md, "Start-up").
 *
 * Each function keeps the header's declaration, so cli_serve.c reads as libmicrohttpd's
 * documentation. When the library cannot be opened, MHD_start_daemon returns NULL (its
 * failure, which cli_serve.c reports) after printing why; the other functions are only
 * called on a daemon, so they run with the library open. MHD_start_daemon forwards its
 * options through MHD_start_daemon_va; MHD_get_daemon_info forwards none, which is right for
 * the one query the view makes (MHD_DAEMON_INFO_CURRENT_CONNECTIONS takes no argument). */
#include <microhttpd.h>
#include <stdarg.h>
#include <stdio.h>

#include "commands.h"
#include "core/lazylib.h"

#ifndef BRUME_MHD_SONAME
#define BRUME_MHD_SONAME "libmicrohttpd.so.12"
#endif

#define MHD_FUNCTIONS(X)                                                                                \
    X(MHD_start_daemon_va) X(MHD_stop_daemon) X(MHD_get_daemon_info) X(MHD_lookup_connection_value)     \
    X(MHD_create_response_from_buffer) X(MHD_add_response_header) X(MHD_queue_response)                 \
    X(MHD_destroy_response)

static struct {
    MHD_FUNCTIONS(LAZYLIB_POINTER)
} mhd;
static const char *const mhd_names[] = {MHD_FUNCTIONS(LAZYLIB_NAME) NULL};
static const char *const mhd_sonames[] = {BRUME_MHD_SONAME, NULL};
static lazylib mhd_so = LAZYLIB("libmicrohttpd", mhd_sonames, mhd_names, &mhd, sizeof mhd);

struct MHD_Daemon *MHD_start_daemon(unsigned int flags, uint16_t port, MHD_AcceptPolicyCallback apc, void *apc_cls,
                                    MHD_AccessHandlerCallback dh, void *dh_cls, ...)
{
    if (!lazylib_open(&mhd_so)) {
        cli_error("--serve: %s", mhd_so.error);
        return NULL;
    }
    va_list ap;
    va_start(ap, dh_cls);
    struct MHD_Daemon *d = mhd.MHD_start_daemon_va(flags, port, apc, apc_cls, dh, dh_cls, ap);
    va_end(ap);
    return d;
}

void MHD_stop_daemon(struct MHD_Daemon *daemon) { mhd.MHD_stop_daemon(daemon); }

const union MHD_DaemonInfo *MHD_get_daemon_info(struct MHD_Daemon *daemon, enum MHD_DaemonInfoType info_type, ...)
{
    return mhd.MHD_get_daemon_info(daemon, info_type);
}

const char *MHD_lookup_connection_value(struct MHD_Connection *connection, enum MHD_ValueKind kind, const char *key)
{
    return mhd.MHD_lookup_connection_value(connection, kind, key);
}

struct MHD_Response *MHD_create_response_from_buffer(size_t size, void *buffer, enum MHD_ResponseMemoryMode mode)
{
    return mhd.MHD_create_response_from_buffer(size, buffer, mode);
}

enum MHD_Result MHD_add_response_header(struct MHD_Response *response, const char *header, const char *content)
{
    return mhd.MHD_add_response_header(response, header, content);
}

enum MHD_Result MHD_queue_response(struct MHD_Connection *connection, unsigned int status_code,
                                   struct MHD_Response *response)
{
    return mhd.MHD_queue_response(connection, status_code, response);
}

void MHD_destroy_response(struct MHD_Response *response) { mhd.MHD_destroy_response(response); }
