/* cli_serve.c - `brume render --serve [HOST:]PORT`: a live view of the render job in a
 * browser, served by libmicrohttpd from its own thread.
 *
 * Three fixed endpoints and nothing else (no file is ever read from disk):
 *   /             the page: the image as it converges, progress, samples, ETA, noise
 *                 estimate and an exposure control (a slider that asks for another PNG)
 *   /image.png    the current image as PNG; ?exposure=STOPS in [-20, 20]
 *   /status.json  the job's figures (brume_render_job_progress)
 * The listening socket is made here (so a port in use or a bad host is reported with the
 * system's reason before any rendering) and handed to libmicrohttpd. */
#include "cli_serve.h"

#include <arpa/inet.h>
#include <errno.h>
#include <math.h>
#include <microhttpd.h>
#include <netdb.h>
#include <netinet/in.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "commands.h"

struct cli_serve {
    struct MHD_Daemon *daemon;
    int fd;
    pthread_mutex_t lock;          /* job, label */
    const brume_render_job *job;   /* the job shown, or NULL */
    brume_context *ctx;            /* the server thread's own context */
    char label[256];               /* what is being rendered, for the page */
    char url[128];
};

static const char page[] =
    "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>brume: live view</title>\n"
    "<style>body{background:#202124;color:#e8eaed;font:14px sans-serif;margin:16px}"
    "#img{display:block;image-rendering:pixelated;max-width:100%;background:#000}"
    "#bar{width:320px;height:8px;background:#444}#fill{height:8px;width:0;background:#8ab4f8}"
    "td{padding:0 12px 0 0}</style></head>\n<body>\n"
    "<h3 id=\"label\">brume</h3>\n<img id=\"img\" src=\"/image.png\" alt=\"the render\">\n"
    "<p><div id=\"bar\"><div id=\"fill\"></div></div></p>\n<table>\n"
    "<tr><td>progress</td><td id=\"progress\">-</td></tr>\n"
    "<tr><td>samples per pixel</td><td id=\"spp\">-</td></tr>\n"
    "<tr><td>elapsed</td><td id=\"elapsed\">-</td></tr>\n"
    "<tr><td>ETA</td><td id=\"eta\">-</td></tr>\n"
    "<tr><td>noise (relative standard error)</td><td id=\"noise\">-</td></tr>\n"
    "<tr><td>exposure</td><td><input id=\"exposure\" type=\"range\" min=\"-6\" max=\"6\" step=\"0.25\" value=\"0\">"
    " <span id=\"ev\">0</span> stops</td></tr>\n</table>\n"
    "<script>\n"
    "let finished = false, loading = false;\n"
    "function exposure() { return document.getElementById('exposure').value; }\n"
    "function reload() {\n"
    "  if (loading) return; loading = true;\n"
    "  const img = new Image();\n"
    "  img.onload = () => { document.getElementById('img').src = img.src; loading = false; };\n"
    "  img.onerror = () => { loading = false; };\n"
    "  img.src = '/image.png?exposure=' + exposure() + '&t=' + Date.now();\n"
    "}\n"
    "function secs(s) { return s < 60 ? s.toFixed(1) + ' s' : (s / 60).toFixed(1) + ' min'; }\n"
    "async function tick() {\n"
    "  try {\n"
    "    const r = await fetch('/status.json', {cache: 'no-store'});\n"
    "    const s = await r.json();\n"
    "    const f = s.total > 0 ? Math.min(1, s.done / s.total) : 0;\n"
    "    document.getElementById('label').textContent = 'brume: ' + s.label + (s.finished ? ' (finished)' : '');\n"
    "    document.getElementById('fill').style.width = (100 * f).toFixed(1) + '%';\n"
    "    document.getElementById('progress').textContent = (100 * f).toFixed(1) + ' %';\n"
    "    document.getElementById('spp').textContent = s.spp_min + ' to ' + s.spp_max + ' (mean ' + s.spp_mean.toFixed(1) + ')';\n"
    "    document.getElementById('elapsed').textContent = secs(s.elapsed);\n"
    "    document.getElementById('eta').textContent = s.finished ? 'done' : secs(s.eta);\n"
    "    document.getElementById('noise').textContent = s.noise > 0 ? (100 * s.noise).toFixed(2) + ' %' : '-';\n"
    "    if (!finished || !s.finished) reload();\n"
    "    finished = s.finished;\n"
    "  } catch (e) {}\n"
    "}\n"
    "document.getElementById('exposure').oninput = () => {\n"
    "  document.getElementById('ev').textContent = exposure(); finished = false; reload(); };\n"
    "tick(); setInterval(tick, 1000);\n"
    "</script>\n</body></html>\n";

static enum MHD_Result respond(struct MHD_Connection *conn, unsigned status, const char *type, void *data,
                               size_t size, enum MHD_ResponseMemoryMode mode)
{
    struct MHD_Response *r = MHD_create_response_from_buffer(size, data, mode);
    if (!r) {
        if (mode == MHD_RESPMEM_MUST_FREE)
            free(data);
        return MHD_NO;
    }
    MHD_add_response_header(r, "Content-Type", type);
    MHD_add_response_header(r, "Cache-Control", "no-store");
    enum MHD_Result ret = MHD_queue_response(conn, status, r);
    MHD_destroy_response(r);
    return ret;
}

static enum MHD_Result error_page(struct MHD_Connection *conn, unsigned status, const char *text)
{
    return respond(conn, status, "text/plain; charset=utf-8", (void *)text, strlen(text), MHD_RESPMEM_PERSISTENT);
}

static enum MHD_Result send_image(cli_serve *sv, struct MHD_Connection *conn)
{
    brume_write_options opts = {0.0, BRUME_TONEMAP_CLAMP};
    const char *ev = MHD_lookup_connection_value(conn, MHD_GET_ARGUMENT_KIND, "exposure");
    if (ev) {
        char *end;
        double v = strtod(ev, &end);
        if (end == ev || *end || !isfinite(v) || v < -20.0 || v > 20.0)
            return error_page(conn, MHD_HTTP_BAD_REQUEST, "exposure: expected a number of stops in [-20, 20]\n");
        opts.exposure = v;
    }
    brume_image *img = NULL;
    pthread_mutex_lock(&sv->lock);
    if (sv->job)
        brume_render_job_image(sv->ctx, sv->job, &img);
    pthread_mutex_unlock(&sv->lock);
    if (!img)
        return error_page(conn, MHD_HTTP_SERVICE_UNAVAILABLE, "no image yet\n");
    unsigned char *png = NULL;
    size_t size = 0;
    brume_status st = brume_image_encode_png(sv->ctx, img, &opts, &png, &size);
    brume_image_release(img);
    if (st != BRUME_OK)
        return error_page(conn, MHD_HTTP_INTERNAL_SERVER_ERROR, "cannot encode the image\n");
    return respond(conn, MHD_HTTP_OK, "image/png", png, size, MHD_RESPMEM_MUST_FREE);
}

/* The label as a JSON string body (quotes, backslashes and control characters escaped). */
static void json_escape(const char *in, char *out, size_t n)
{
    size_t k = 0;
    for (; *in && k + 7 < n; in++) {
        unsigned char c = (unsigned char)*in;
        if (c == '"' || c == '\\') {
            out[k++] = '\\';
            out[k++] = (char)c;
        } else if (c < 0x20) {
            k += (size_t)snprintf(out + k, n - k, "\\u%04x", c);
        } else {
            out[k++] = (char)c;
        }
    }
    out[k] = '\0';
}

static enum MHD_Result send_status(cli_serve *sv, struct MHD_Connection *conn)
{
    brume_render_progress p;
    char label[600];
    pthread_mutex_lock(&sv->lock);
    brume_render_job_progress(sv->job, &p);
    json_escape(sv->label, label, sizeof label);
    bool have = sv->job != NULL;
    pthread_mutex_unlock(&sv->lock);
    char *body = malloc(1024);
    if (!body)
        return MHD_NO;
    int len = snprintf(body, 1024,
                       "{\"label\": \"%s\", \"running\": %s, \"done\": %llu, \"total\": %llu, \"spp_min\": %d, "
                       "\"spp_max\": %d, \"spp_mean\": %.3f, \"noise\": %.6g, \"converged\": %.4f, "
                       "\"elapsed\": %.3f, \"eta\": %.3f, \"finished\": %s}\n",
                       label, have ? "true" : "false", (unsigned long long)p.done, (unsigned long long)p.total,
                       p.spp_min, p.spp_max, p.spp_mean, p.noise, p.converged, p.elapsed, p.eta,
                       p.finished ? "true" : "false");
    return respond(conn, MHD_HTTP_OK, "application/json", body, (size_t)len, MHD_RESPMEM_MUST_FREE);
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn, const char *url, const char *method,
                                  const char *version, const char *upload_data, size_t *upload_size, void **state)
{
    (void)version;
    (void)upload_data;
    cli_serve *sv = cls;
    if (strcmp(method, "GET") != 0 && strcmp(method, "HEAD") != 0)
        return error_page(conn, MHD_HTTP_METHOD_NOT_ALLOWED, "only GET\n");
    if (*upload_size != 0)
        return MHD_NO;
    (void)state;
    if (strcmp(url, "/") == 0)
        return respond(conn, MHD_HTTP_OK, "text/html; charset=utf-8", (void *)page, sizeof page - 1,
                       MHD_RESPMEM_PERSISTENT);
    if (strcmp(url, "/image.png") == 0)
        return send_image(sv, conn);
    if (strcmp(url, "/status.json") == 0)
        return send_status(sv, conn);
    return error_page(conn, MHD_HTTP_NOT_FOUND, "not found: the live view serves /, /image.png and /status.json\n");
}

/* "[HOST:]PORT" -> a bound, listening socket; -1 with a message. */
static int listen_on(const char *spec, char *url, size_t url_size)
{
    char host[256] = "127.0.0.1";
    const char *port_text = spec;
    const char *colon = strrchr(spec, ':');
    if (colon) {
        size_t n = (size_t)(colon - spec);
        if (n == 0 || n >= sizeof host) {
            cli_error("--serve: '%s': expected [HOST:]PORT", spec);
            return -1;
        }
        memcpy(host, spec, n);
        host[n] = '\0';
        if (host[0] == '[' && n > 2 && host[n - 1] == ']') { /* [::1]:8080 */
            memmove(host, host + 1, n - 2);
            host[n - 2] = '\0';
        }
        port_text = colon + 1;
    }
    char *end;
    long port = strtol(port_text, &end, 10);
    if (!*port_text || *end || port < 0 || port > 65535) {
        cli_error("--serve: '%s': the port must be an integer in [0, 65535]", spec);
        return -1;
    }
    struct addrinfo hints = {0}, *res = NULL;
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = SOCK_STREAM;
    hints.ai_flags = AI_PASSIVE;
    int gai = getaddrinfo(host, port_text, &hints, &res);
    if (gai != 0 || !res) {
        cli_error("--serve: host '%s': %s", host, gai_strerror(gai));
        return -1;
    }
    int fd = socket(res->ai_family, res->ai_socktype | SOCK_CLOEXEC, res->ai_protocol);
    if (fd < 0) {
        cli_error("--serve: %s: cannot make a socket: %s", spec, strerror(errno));
        freeaddrinfo(res);
        return -1;
    }
    int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (bind(fd, res->ai_addr, res->ai_addrlen) != 0 || listen(fd, 16) != 0) {
        cli_error("--serve: cannot listen on %s port %ld: %s", host, port, strerror(errno));
        close(fd);
        freeaddrinfo(res);
        return -1;
    }
    freeaddrinfo(res);
    struct sockaddr_storage sa;
    socklen_t len = sizeof sa;
    char addr[INET6_ADDRSTRLEN] = "?";
    unsigned actual = 0;
    if (getsockname(fd, (struct sockaddr *)&sa, &len) == 0) {
        if (sa.ss_family == AF_INET) {
            struct sockaddr_in *in = (struct sockaddr_in *)&sa;
            inet_ntop(AF_INET, &in->sin_addr, addr, sizeof addr);
            actual = ntohs(in->sin_port);
        } else if (sa.ss_family == AF_INET6) {
            struct sockaddr_in6 *in6 = (struct sockaddr_in6 *)&sa;
            inet_ntop(AF_INET6, &in6->sin6_addr, addr, sizeof addr);
            actual = ntohs(in6->sin6_port);
        }
    }
    snprintf(url, url_size, sa.ss_family == AF_INET6 ? "http://[%s]:%u/" : "http://%s:%u/", addr, actual);
    bool loopback = (sa.ss_family == AF_INET && (ntohl(((struct sockaddr_in *)&sa)->sin_addr.s_addr) >> 24) == 127) ||
                    (sa.ss_family == AF_INET6 && IN6_IS_ADDR_LOOPBACK(&((struct sockaddr_in6 *)&sa)->sin6_addr));
    if (!loopback)
        fprintf(stderr, "brume: warning: --serve: the live view listens on %s, beyond this machine: whoever can reach "
                        "it sees the render (give 127.0.0.1:PORT to keep it local)\n", addr);
    return fd;
}

cli_serve *cli_serve_start(const char *spec)
{
    cli_serve *sv = calloc(1, sizeof *sv);
    if (!sv) {
        cli_error("--serve: out of memory");
        return NULL;
    }
    sv->ctx = brume_context_new();
    sv->fd = listen_on(spec, sv->url, sizeof sv->url);
    if (sv->fd < 0 || !sv->ctx) {
        brume_context_release(sv->ctx);
        free(sv);
        return NULL;
    }
    pthread_mutex_init(&sv->lock, NULL);
    sv->daemon = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD, 0, NULL, NULL, on_request, sv,
                                  MHD_OPTION_LISTEN_SOCKET, sv->fd, MHD_OPTION_CONNECTION_LIMIT, 64U,
                                  /* idle connections cannot hold the view (issue 36: 32 of them
                                     blocked it): 4 per client address, dropped after 10 s idle */
                                  MHD_OPTION_PER_IP_CONNECTION_LIMIT, 4U, MHD_OPTION_CONNECTION_TIMEOUT, 10U,
                                  MHD_OPTION_END);
    if (!sv->daemon) {
        cli_error("--serve: %s: libmicrohttpd could not start", spec);
        close(sv->fd);
        pthread_mutex_destroy(&sv->lock);
        brume_context_release(sv->ctx);
        free(sv);
        return NULL;
    }
    return sv;
}

const char *cli_serve_url(const cli_serve *sv) { return sv->url; }

void cli_serve_show(cli_serve *sv, const brume_render_job *job, const char *label)
{
    if (!sv)
        return;
    pthread_mutex_lock(&sv->lock);
    sv->job = job;
    snprintf(sv->label, sizeof sv->label, "%s", label ? label : "");
    pthread_mutex_unlock(&sv->lock);
}

void cli_serve_stop(cli_serve *sv)
{
    if (!sv)
        return;
    MHD_stop_daemon(sv->daemon); /* closes the listening socket too */
    pthread_mutex_destroy(&sv->lock);
    brume_context_release(sv->ctx);
    free(sv);
}
