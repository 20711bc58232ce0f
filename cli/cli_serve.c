/* cli_serve.c - `brume render --serve [HOST:]PORT`: a live view of the render job in a
 * browser, served by libmicrohttpd from its own thread.
 *
 * Four fixed endpoints and nothing else (no file is ever read from disk):
 *   /             the page: the image fitted to the window (1:1 and back, dragged to pan),
 *                 what it shows (beauty, denoised, noise, each layer), exposure and tone
 *                 curve (drawn), progress, samples, ETA, noise, a stop button and a download
 *                 link; #zoom=1 and #view=NAME in the address set the first state
 *   /image.png    the current image as PNG; ?exposure=STOPS in [-20, 20], &tone=clamp|filmic,
 *                 &view=beauty|denoised|noise|LAYER (denoised and noise need the variance
 *                 layer: --denoise or --aov variance)
 *   /status.json  the job's figures (brume_render_job_progress) and the views it offers
 *   /stop (POST)  stops the render as Ctrl-C does: the image so far is written; any number
 *                 of stops in a row stop it once (never the second Ctrl-C that ends at once)
 * Each connection has its own thread, so that a client that never reads, or a denoised view
 * being computed, holds no other request (a stop included); the denoised views are computed
 * one at a time, and cli_serve_stop cancels the one under way (brume_context_cancel_loads).
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
#include <signal.h>
#include <stdatomic.h>
#include <stdio.h>
#include <time.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "cli_job.h"
#include "commands.h"

struct cli_serve {
    struct MHD_Daemon *daemon;
    int fd;
    pthread_mutex_t lock;          /* job, label */
    const brume_render_job *job;   /* the job shown, or NULL */
    brume_context *ctx;            /* the denoised views' context (one at a time: denoise_lock);
                                      the other requests make their own (one per thread) */
    char label[256];               /* what is being rendered, for the page */
    char views[512];               /* what /image.png can show, comma-separated (from the last image) */
    char url[128];
    pthread_mutex_t denoise_lock;  /* held while a denoised view is computed with ctx */
    atomic_bool stopping;          /* cli_serve_stop began: no denoised view starts */
    atomic_int stops_pending;      /* POST /stop answers queued and not yet sent */
};

static const char page[] =
    "<!DOCTYPE html>\n"
    "<html lang=\"en\"><head><meta charset=\"utf-8\"><title>brume: live view</title>\n"
    "<style>\n"
    "html,body{height:100%;margin:0}\n"
    "body{background:#202124;color:#e8eaed;font:13px sans-serif;display:flex;flex-direction:column}\n"
    "#top{padding:6px 10px;display:flex;flex-wrap:wrap;gap:6px 14px;align-items:center}\n"
    "#view{flex:1;overflow:auto;background:#111;position:relative;cursor:grab}\n"
    "#img{display:block;image-rendering:pixelated;margin:auto}\n"
    "#view.fit #img{width:100%;height:100%;object-fit:contain}\n"
    "#bar{width:160px;height:8px;background:#444;display:inline-block}#fill{height:8px;width:0;background:#8ab4f8}\n"
    "button,select,a{font:inherit;color:#e8eaed;background:#3c4043;border:1px solid #5f6368;padding:2px 8px;text-decoration:none}\n"
    "#stats span{margin-right:12px}\n"
    "</style></head>\n"
    "<body>\n"
    "<div id=\"top\">\n"
    "<b id=\"label\">brume</b>\n"
    "<span><div id=\"bar\"><div id=\"fill\"></div></div> <span id=\"progress\">-</span></span>\n"
    "<label>show <select id=\"sel\"><option value=\"beauty\">beauty</option></select></label>\n"
    "<label>exposure <input id=\"exposure\" type=\"range\" min=\"-6\" max=\"6\" step=\"0.25\" value=\"0\"> <span id=\"ev\">0</span> stops</label>\n"
    "<label>tone <select id=\"tone\"><option value=\"clamp\">clamp</option><option value=\"filmic\">filmic</option></select></label>\n"
    "<canvas id=\"curve\" width=\"60\" height=\"36\" title=\"the tone curve: display value against scene value 0 to 4\"></canvas>\n"
    "<button id=\"zoom\">1:1</button>\n"
    "<button id=\"stop\">stop</button>\n"
    "<a id=\"dl\" href=\"/image.png\" download=\"brume.png\">download</a>\n"
    "</div>\n"
    "<div id=\"stats\"><span>spp <b id=\"spp\">-</b></span><span>elapsed <b id=\"elapsed\">-</b></span><span>ETA <b id=\"eta\">-</b></span><span>noise <b id=\"noise\">-</b></span></div>\n"
    "<div id=\"view\" class=\"fit\"><img id=\"img\" src=\"/image.png\" alt=\"the render\"></div>\n"
    "<script>\n"
    "const $ = (id) => document.getElementById(id);\n"
    "const hash = new URLSearchParams(location.hash.slice(1));\n"
    "let finished = false, loading = false, view = hash.get('view') || 'beauty';\n"
    "if (hash.get('zoom') === '1') { $('view').className = ''; $('zoom').textContent = 'fit'; }\n"
    "function src() {\n"
    "  return '/image.png?exposure=' + $('exposure').value + '&tone=' + $('tone').value + '&view=' + encodeURIComponent(view);\n"
    "}\n"
    "function reload() {\n"
    "  if (loading) return; loading = true;\n"
    "  const img = new Image(), s = src();\n"
    "  img.onload = () => { $('img').src = img.src; loading = false; };\n"
    "  img.onerror = () => { loading = false; };\n"
    "  img.src = s + '&t=' + Date.now();\n"
    "  $('dl').href = s; $('dl').download = 'brume-' + view + '.png';\n"
    "}\n"
    "function curve() {\n"
    "  const c = $('curve').getContext('2d'), k = Math.pow(2, $('exposure').value), f = $('tone').value === 'filmic';\n"
    "  c.fillStyle = '#3c4043'; c.fillRect(0, 0, 60, 36); c.strokeStyle = '#8ab4f8'; c.beginPath();\n"
    "  for (let i = 0; i <= 60; i++) {\n"
    "    const x = 4 * i / 60 * k;\n"
    "    let y = f ? (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14) : x;\n"
    "    y = Math.max(0, Math.min(1, y));\n"
    "    y = y <= 0.0031308 ? 12.92 * y : 1.055 * Math.pow(y, 1 / 2.4) - 0.055;\n"
    "    if (i) c.lineTo(i, 35 - 34 * y); else c.moveTo(i, 35 - 34 * y);\n"
    "  }\n"
    "  c.stroke();\n"
    "}\n"
    "function secs(s) { return s < 60 ? s.toFixed(1) + ' s' : (s / 60).toFixed(1) + ' min'; }\n"
    "async function tick() {\n"
    "  try {\n"
    "    const r = await fetch('/status.json', {cache: 'no-store'});\n"
    "    const s = await r.json();\n"
    "    const f = s.finished ? 1 : Math.max(0, s.fraction);\n"
    "    $('label').textContent = 'brume: ' + s.label + (s.finished ? ' (finished)' : '');\n"
    "    $('fill').style.width = (100 * f).toFixed(1) + '%';\n"
    "    $('progress').textContent = s.fraction < 0 && !s.finished ? 'not known yet' : (100 * f).toFixed(1) + ' %';\n"
    "    $('spp').textContent = s.spp_min + ' to ' + s.spp_max + ' (mean ' + s.spp_mean.toFixed(1) + ')';\n"
    "    $('elapsed').textContent = secs(s.elapsed);\n"
    "    $('eta').textContent = s.finished ? 'done' : s.eta < 0 ? 'not known yet' : secs(s.eta);\n"
    "    $('noise').textContent = s.noise > 0 ? (100 * s.noise).toFixed(2) + ' %' : '-';\n"
    "    const views = s.views.split(',');\n"
    "    if ($('sel').options.length !== views.length) {\n"
    "      $('sel').innerHTML = views.map((v) => '<option>' + v + '</option>').join('');\n"
    "      finished = false;\n"
    "    }\n"
    "    $('sel').value = views.includes(view) ? view : 'beauty';\n"
    "    if (!finished || !s.finished) reload();\n"
    "    finished = s.finished;\n"
    "  } catch (e) {}\n"
    "}\n"
    "function changed() { finished = false; curve(); reload(); }\n"
    "$('exposure').oninput = () => { $('ev').textContent = $('exposure').value; changed(); };\n"
    "$('tone').onchange = changed;\n"
    "$('sel').onchange = () => { view = $('sel').value; changed(); };\n"
    "$('zoom').onclick = () => {\n"
    "  const fit = $('view').className === 'fit';\n"
    "  $('view').className = fit ? '' : 'fit'; $('zoom').textContent = fit ? 'fit' : '1:1';\n"
    "};\n"
    "$('stop').onclick = () => { fetch('/stop', {method: 'POST'}); $('stop').textContent = 'stopping'; };\n"
    "let drag = null;\n"
    "$('view').onmousedown = (e) => { drag = [e.clientX, e.clientY]; e.preventDefault(); };\n"
    "window.onmouseup = () => { drag = null; };\n"
    "window.onmousemove = (e) => {\n"
    "  if (!drag) return;\n"
    "  $('view').scrollLeft -= e.clientX - drag[0]; $('view').scrollTop -= e.clientY - drag[1]; drag = [e.clientX, e.clientY];\n"
    "};\n"
    "curve(); tick(); setInterval(tick, 1000);\n"
    "</script>\n"
    "</body></html>\n";

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

static int find_layer(const brume_image *img, const char *name)
{
    for (int i = 0; i < brume_image_layer_count(img); i++)
        if (strcmp(brume_image_layer_name(img, i), name) == 0)
            return i;
    return -1;
}

/* "beauty", then "denoised" and "noise" when the image has the variance layer, then each layer. */
static void view_names(const brume_image *img, char *out, size_t n)
{
    int len = snprintf(out, n, "beauty%s", find_layer(img, "variance") >= 0 ? ",denoised,noise" : "");
    for (int i = 0; i < brume_image_layer_count(img) && len > 0 && (size_t)len < n; i++)
        len += snprintf(out + len, n - (size_t)len, ",%s", brume_image_layer_name(img, i));
}

/* The image of a view other than the beauty: *out, or NULL and why. Layers are shown as
 * data: depth and samples over their largest value, normals as 0.5 + 0.5 n, the rest as
 * they are; noise is a heat map of the relative standard error of each pixel's mean, black
 * at 0 through red to yellow at 10 % and above. */
static const char *view_image(cli_serve *sv, const brume_image *img, const char *view, brume_image **out)
{
    *out = NULL;
    int var = find_layer(img, "variance");
    if (strcmp(view, "denoised") == 0) {
        if (var < 0)
            return "denoised: the render has no variance layer (render with --denoise or --aov variance)\n";
        pthread_mutex_lock(&sv->denoise_lock);
        brume_status st = atomic_load(&sv->stopping) ? BRUME_ERROR_CANCELLED : brume_denoise(sv->ctx, img, 1, out);
        pthread_mutex_unlock(&sv->denoise_lock);
        return st == BRUME_OK ? NULL : st == BRUME_ERROR_CANCELLED ? "denoised: the live view is stopping\n"
                                                                   : "denoised: the denoiser failed\n";
    }
    int l = strcmp(view, "noise") == 0 ? var : find_layer(img, view);
    if (l < 0)
        return "view: unknown (see the views in /status.json)\n";
    int w = brume_image_width(img), h = brume_image_height(img), ch = brume_image_layer_channels(img, l);
    brume_image *o = NULL;
    if (brume_image_new(NULL, w, h, &o) != BRUME_OK)
        return "out of memory\n";
    const float *src = brume_image_layer_pixels(img, l), *rgba = brume_image_pixels(img);
    float *dst = brume_image_pixels(o);
    size_t npix = (size_t)w * (size_t)h;
    double top = 0.0;
    for (size_t i = 0; i < npix * (size_t)ch; i++)
        top = fmax(top, (double)src[i]);
    bool noise = strcmp(view, "noise") == 0, normal = strcmp(view, "normal") == 0;
    for (size_t i = 0; i < npix; i++) {
        float *d = dst + 4 * i;
        if (noise) {
            double mean = ((double)rgba[4 * i] + (double)rgba[4 * i + 1] + (double)rgba[4 * i + 2]) / 3.0;
            double v = ((double)src[3 * i] + (double)src[3 * i + 1] + (double)src[3 * i + 2]) / 3.0;
            double e = fmin(1.0, sqrt(fmax(v, 0.0)) / fmax(mean, 1e-3) / 0.1);
            d[0] = (float)fmin(1.0, 2.0 * e);
            d[1] = (float)fmax(0.0, 2.0 * e - 1.0);
            d[2] = 0.0f;
        } else {
            for (size_t c = 0; c < 3; c++) {
                double x = src[(size_t)ch * i + (ch == 3 ? c : 0)];
                d[c] = (float)(normal ? 0.5 + 0.5 * x : ch == 1 ? (top > 0.0 ? x / top : 0.0) : x);
            }
        }
        d[3] = 1.0f;
    }
    *out = o;
    return NULL;
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
    const char *tone = MHD_lookup_connection_value(conn, MHD_GET_ARGUMENT_KIND, "tone");
    if (tone && strcmp(tone, "filmic") == 0)
        opts.tonemap = BRUME_TONEMAP_FILMIC;
    else if (tone && strcmp(tone, "clamp") != 0)
        return error_page(conn, MHD_HTTP_BAD_REQUEST, "tone: expected clamp or filmic\n");
    const char *view = MHD_lookup_connection_value(conn, MHD_GET_ARGUMENT_KIND, "view");
    brume_image *img = NULL;
    pthread_mutex_lock(&sv->lock);
    if (sv->job)
        brume_render_job_image(NULL, sv->job, &img);
    if (img)
        view_names(img, sv->views, sizeof sv->views);
    pthread_mutex_unlock(&sv->lock);
    if (!img)
        return error_page(conn, MHD_HTTP_SERVICE_UNAVAILABLE, "no image yet\n");
    if (view && strcmp(view, "beauty") != 0) {
        brume_image *shown = NULL;
        const char *why = view_image(sv, img, view, &shown);
        brume_image_release(img);
        if (!shown)
            return error_page(conn, MHD_HTTP_NOT_FOUND, why);
        img = shown;
        if (strcmp(view, "denoised") != 0) /* data, not a picture: no exposure, no curve */
            opts = (brume_write_options){0.0, BRUME_TONEMAP_CLAMP};
    }
    unsigned char *png = NULL;
    size_t size = 0;
    brume_status st = brume_image_encode_png(NULL, img, &opts, &png, &size);
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
    char views[600];
    json_escape(sv->views[0] ? sv->views : "beauty", views, sizeof views);
    bool have = sv->job != NULL;
    pthread_mutex_unlock(&sv->lock);
    char *body = malloc(2048);
    if (!body)
        return MHD_NO;
    int len = snprintf(body, 2048,
                       "{\"label\": \"%s\", \"running\": %s, \"done\": %llu, \"total\": %llu, \"spp_min\": %d, "
                       "\"spp_max\": %d, \"spp_mean\": %.3f, \"noise\": %.6g, \"converged\": %.4f, "
                       "\"elapsed\": %.3f, \"eta\": %.3f, \"fraction\": %.4f, \"finished\": %s, \"views\": \"%s\"}\n",
                       label, have ? "true" : "false", (unsigned long long)p.done, (unsigned long long)p.total,
                       p.spp_min, p.spp_max, p.spp_mean, p.noise, p.converged, p.elapsed, p.eta, p.fraction,
                       p.finished ? "true" : "false", views);
    return respond(conn, MHD_HTTP_OK, "application/json", body, (size_t)len, MHD_RESPMEM_MUST_FREE);
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *conn, const char *url, const char *method,
                                  const char *version, const char *upload_data, size_t *upload_size, void **state)
{
    (void)version;
    (void)upload_data;
    cli_serve *sv = cls;
    if (*upload_size != 0)
        return MHD_NO;
    if (strcmp(method, "POST") == 0 && strcmp(url, "/stop") == 0) {
        /* counted before the signal: cli_serve_stop, which the signal may reach at once, lets
         * this answer go out first (on_completed) */
        atomic_fetch_add(&sv->stops_pending, 1);
        *state = &sv->stops_pending;
        cli_signals_raise(SIGINT); /* as Ctrl-C, once: the render stops, the image so far is written */
        return error_page(conn, MHD_HTTP_ACCEPTED, "stopping\n");
    }
    if (strcmp(method, "GET") != 0 && strcmp(method, "HEAD") != 0)
        return error_page(conn, MHD_HTTP_METHOD_NOT_ALLOWED, "only GET (and POST /stop)\n");
    if (strcmp(url, "/") == 0)
        return respond(conn, MHD_HTTP_OK, "text/html; charset=utf-8", (void *)page, sizeof page - 1,
                       MHD_RESPMEM_PERSISTENT);
    if (strcmp(url, "/image.png") == 0)
        return send_image(sv, conn);
    if (strcmp(url, "/status.json") == 0)
        return send_status(sv, conn);
    return error_page(conn, MHD_HTTP_NOT_FOUND, "not found: the live view serves /, /image.png, /status.json and POST /stop\n");
}

/* A request's end (sent, or its connection closed): a stop's answer is no longer pending. */
static void on_completed(void *cls, struct MHD_Connection *conn, void **state, enum MHD_RequestTerminationCode why)
{
    (void)conn;
    (void)why;
    cli_serve *sv = cls;
    if (*state == &sv->stops_pending)
        atomic_fetch_sub(&sv->stops_pending, 1);
    *state = NULL;
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
    pthread_mutex_init(&sv->denoise_lock, NULL);
    atomic_init(&sv->stopping, false);
    atomic_init(&sv->stops_pending, 0);
    sv->daemon = MHD_start_daemon(MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_THREAD_PER_CONNECTION, 0, NULL, NULL,
                                  on_request, sv, MHD_OPTION_NOTIFY_COMPLETED, on_completed, sv,
                                  MHD_OPTION_LISTEN_SOCKET, sv->fd, MHD_OPTION_CONNECTION_LIMIT, 64U,
                                  /* idle connections cannot hold the view (32 of them would
                                     block it): 16 per client address, above a browser's 6 per
                                     host with its polls and a stop request (4 refused the stop
                                     after three page loads), dropped after 10 s idle */
                                  MHD_OPTION_PER_IP_CONNECTION_LIMIT, 16U, MHD_OPTION_CONNECTION_TIMEOUT, 10U,
                                  MHD_OPTION_END);
    if (!sv->daemon) {
        cli_error("--serve: %s: libmicrohttpd could not start", spec);
        close(sv->fd);
        pthread_mutex_destroy(&sv->lock);
        pthread_mutex_destroy(&sv->denoise_lock);
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
    /* no denoised view starts from now, and the one under way (a second or more of a large
     * image) is cancelled until it lets go: the exit never waits for it */
    atomic_store(&sv->stopping, true);
    struct timespec ts = {0, 5000000};
    while (pthread_mutex_trylock(&sv->denoise_lock) != 0) {
        brume_context_cancel_loads(sv->ctx); /* again: one that began after the last call */
        nanosleep(&ts, NULL);
    }
    pthread_mutex_unlock(&sv->denoise_lock);
    /* POST /stop's 202 goes out first (it raced the stop and was sometimes cut), for at most
     * a second; no other connection is waited for: a browser's idle keep-alive connections
     * and a client that never reads do not hold the exit */
    for (int i = 0; i < 200 && atomic_load(&sv->stops_pending) > 0; i++)
        nanosleep(&ts, NULL);
    MHD_stop_daemon(sv->daemon); /* closes the listening socket too */
    pthread_mutex_destroy(&sv->lock);
    pthread_mutex_destroy(&sv->denoise_lock);
    brume_context_release(sv->ctx);
    free(sv);
}
