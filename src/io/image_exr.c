/* image_exr.c - OpenEXR images through the OpenEXR C core API (libOpenEXRCore, 3.1).
 *
 * Writing: one scanline part, channels R, G, B, A as 32-bit float, then each layer of the
 * image as channels "NAME.C" (OpenEXR's naming of layers: "albedo.R", "depth.Z"), ZIP
 * compression (16 scanlines per chunk), increasing y, data and display windows
 * (0,0)-(w-1,h-1); the image's attributes as string attributes. The bytes
 * go through a write callback to the temporary file of io/atomic.c, renamed over the
 * destination when complete.
 *
 * Reading: part 0 of a scanline file with channels R, G, B (half or float, converted to
 * float) and optionally A (default 1); channels "NAME.C" become layers (at most three
 * channels each, R G B or X Y Z order), other channels are skipped; string attributes
 * "brume.*" come back as the image's attributes. The image is the data
 * window, top row = its smallest y. Tiled and deep files are refused.
 *
 * The core API keeps a channel list sorted by name (A, B, G, R), so channels are found by
 * name, never by position. References: OpenEXR's openexr_encode.h / openexr_decode.h and
 * "Reading and Writing Image Files with the C API" (openexr.com, OpenEXR 3.1). */
#include <errno.h>
#include <openexr.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "core/regular_file.h"
#include "io/atomic.h"
#include "io/image_formats.h"

/* Passed to OpenEXR as user data: the file being written and the library's last message. */
typedef struct exr_io {
    int fd;              /* write: the temporary file; read: unused (-1) */
    char message[256];   /* last error reported by OpenEXR, one line */
} exr_io;

/* The exr_io of the file this thread is reading or writing. The handler cannot ask the context
 * for its user data: OpenEXR reports some errors (an attribute name too long, among others)
 * while it holds the context's lock, and exr_get_user_data takes that lock again (a deadlock). */
static _Thread_local exr_io *g_exr_io;

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    (void)ctxt;
    exr_io *io = g_exr_io;
    if (!io)
        return;
    snprintf(io->message, sizeof io->message, "%s", msg ? msg : exr_get_default_error_message(code));
    for (char *p = io->message; *p; p++) /* keep the message on one line */
        if (*p == '\n' || *p == '\r')
            *p = ' ';
}

/* pwrite at the offset OpenEXR asks for: it seeks back to fill in the chunk table. */
static int64_t exr_write_fd(exr_const_context_t ctxt, void *user, const void *buffer, uint64_t size,
                            uint64_t offset, exr_stream_error_func_ptr_t error_cb)
{
    exr_io *io = user;
    const unsigned char *p = buffer;
    uint64_t done = 0;
    while (done < size) {
        ssize_t n = pwrite(io->fd, p + done, (size_t)(size - done), (off_t)(offset + done));
        if (n <= 0) {
            error_cb(ctxt, EXR_ERR_WRITE_IO, "write failed at offset %llu", (unsigned long long)(offset + done));
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)done;
}

/* The brume status for an OpenEXR result, with a message naming the file. */
static brume_status exr_fail(const char *path, const char *doing, exr_result_t rv, const exr_io *io)
{
    brume_status st = BRUME_ERROR_PARSE;
    if (rv == EXR_ERR_FILE_ACCESS || rv == EXR_ERR_READ_IO || rv == EXR_ERR_WRITE_IO)
        st = BRUME_ERROR_IO;
    else if (rv == EXR_ERR_OUT_OF_MEMORY)
        st = BRUME_ERROR_OUT_OF_MEMORY;
    const char *detail = io->message[0] ? io->message : exr_get_default_error_message(rv);
    return err_set(st, "%s: %s: %s", path, doing, detail);
}

/* Index 0..3 (R, G, B, A) of a channel name, -1 for any other channel. */
static int rgba_index(const char *name)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    for (int c = 0; c < 4; c++)
        if (name && strcmp(name, names[c]) == 0)
            return c;
    return -1;
}

/* ---- writing ------------------------------------------------------------------------------ */

/* Where channel `name` of img lives: its first pixel and the stride between pixels in
 * floats; NULL for no channel of this image. */
static const float *channel_source(const brume_image *img, const char *name, int *stride)
{
    int k = rgba_index(name);
    if (k >= 0) {
        *stride = 4;
        return img->rgba + k;
    }
    for (int i = 0; i < img->nlayers; i++) {
        const image_layer *l = &img->layers[i];
        size_t n = strlen(l->name);
        if (strncmp(name, l->name, n) != 0 || name[n] != '.')
            continue;
        for (int c = 0; c < l->channels; c++)
            if (strcmp(name + n + 1, l->chan[c]) == 0) {
                *stride = l->channels;
                return l->px + c;
            }
    }
    return NULL;
}

static brume_status exr_write_body(const char *path, const brume_image *img, exr_context_t ctxt, exr_io *io)
{
    static const char *const names[4] = {"R", "G", "B", "A"};
    exr_result_t rv;
    int part = 0;
    if ((rv = exr_add_part(ctxt, "rgba", EXR_STORAGE_SCANLINE, &part)) != EXR_ERR_SUCCESS ||
        (rv = exr_initialize_required_attr_simple(ctxt, part, img->width, img->height,
                                                  EXR_COMPRESSION_ZIP)) != EXR_ERR_SUCCESS)
        return exr_fail(path, "writing the header", rv, io);
    for (int c = 0; c < 4; c++) {
        /* Radiance is linear: EXR_PERCEPTUALLY_LINEAR only guides lossy codecs anyway. */
        rv = exr_add_channel(ctxt, part, names[c], EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
        if (rv != EXR_ERR_SUCCESS)
            return exr_fail(path, "adding a channel", rv, io);
    }
    for (int i = 0; i < img->nlayers; i++) /* layers: channels "NAME.C" (OpenEXR's layer naming) */
        for (int c = 0; c < img->layers[i].channels; c++) {
            char name[64];
            snprintf(name, sizeof name, "%s.%s", img->layers[i].name, img->layers[i].chan[c]);
            rv = exr_add_channel(ctxt, part, name, EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1);
            if (rv != EXR_ERR_SUCCESS)
                return exr_fail(path, "adding a channel", rv, io);
        }
    for (int i = 0; i < img->nmeta; i++)
        if ((rv = exr_attr_set_string(ctxt, part, img->meta[i].key, img->meta[i].value)) != EXR_ERR_SUCCESS)
            return exr_fail(path, "writing an attribute", rv, io);
    if ((rv = exr_set_version(ctxt, part, 1)) != EXR_ERR_SUCCESS ||
        (rv = exr_write_header(ctxt)) != EXR_ERR_SUCCESS)
        return exr_fail(path, "writing the header", rv, io);

    int32_t lines = 1;
    if ((rv = exr_get_scanlines_per_chunk(ctxt, part, &lines)) != EXR_ERR_SUCCESS || lines < 1)
        return exr_fail(path, "writing the header", rv, io);

    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int initialized = 0;
    brume_status st = BRUME_OK;
    for (int y = 0; y < img->height && st == BRUME_OK; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_write_scanline_chunk_info(ctxt, part, y, &cinfo);
        if (rv == EXR_ERR_SUCCESS)
            rv = initialized ? exr_encoding_update(ctxt, part, &cinfo, &enc)
                             : exr_encoding_initialize(ctxt, part, &cinfo, &enc);
        if (rv != EXR_ERR_SUCCESS) {
            st = exr_fail(path, "writing pixels", rv, io);
            break;
        }
        for (int16_t c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            int stride = 4;
            const float *src = channel_source(img, ch->channel_name, &stride);
            if (!src)
                src = img->rgba;
            ch->encode_from_ptr = (const uint8_t *)(src + (size_t)y * (size_t)img->width * (size_t)stride);
            ch->user_pixel_stride = stride * (int32_t)sizeof(float);
            ch->user_line_stride = stride * (int32_t)sizeof(float) * img->width;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
        }
        if (!initialized) {
            initialized = 1;
            rv = exr_encoding_choose_default_routines(ctxt, part, &enc);
        }
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_encoding_run(ctxt, part, &enc);
        if (rv != EXR_ERR_SUCCESS)
            st = exr_fail(path, "writing pixels", rv, io);
    }
    if (initialized)
        exr_encoding_destroy(ctxt, &enc);
    return st;
}

brume_status image_write_exr(const char *path, const brume_image *img)
{
    atomic_file f;
    brume_status st = atomic_open_kind(&f, path, BRUME_FILE_IMAGE);
    if (st != BRUME_OK)
        return st;
    exr_io io = {fileno(f.fp), ""};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &io;
    init.write_fn = exr_write_fd; /* the file name is then only used in messages */
    exr_context_t ctxt = NULL;
    g_exr_io = &io;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        st = exr_fail(path, "cannot start writing", rv, &io);
    } else {
        /* attribute keys of 32 bytes and more (image_meta holds up to 47) need OpenEXR's long
         * names (a 2.0 file feature, read by every OpenEXR 2 and 3) */
        bool long_names = false;
        for (int i = 0; i < img->nmeta; i++)
            long_names |= strlen(img->meta[i].key) > 31;
        rv = long_names ? exr_set_longname_support(ctxt, 1) : EXR_ERR_SUCCESS;
        st = rv == EXR_ERR_SUCCESS ? exr_write_body(path, img, ctxt, &io)
                                   : exr_fail(path, "cannot write long attribute names", rv, &io);
    }
    /* exr_finish writes the chunk offset table: its result matters on success. */
    if (ctxt) {
        rv = exr_finish(&ctxt);
        if (st == BRUME_OK && rv != EXR_ERR_SUCCESS)
            st = exr_fail(path, "finishing the file", rv, &io);
    }
    g_exr_io = NULL;
    if (st != BRUME_OK) {
        atomic_abort(&f);
        return st;
    }
    return atomic_commit(&f);
}

/* ---- reading ------------------------------------------------------------------------------ */

/* Finds R, G, B (required) and A (optional) in part 0 and checks their types. */
static brume_status exr_check_channels(const char *path, exr_const_context_t ctxt)
{
    const exr_attr_chlist_t *chl = NULL;
    exr_result_t rv = exr_get_channels(ctxt, 0, &chl);
    if (rv != EXR_ERR_SUCCESS || !chl)
        return err_set(BRUME_ERROR_PARSE, "%s: channels: cannot read the channel list", path);
    int found[4] = {0, 0, 0, 0};
    char list[128] = "";
    for (int i = 0; i < chl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[i];
        size_t used = strlen(list);
        if (used + 2 < sizeof list)
            snprintf(list + used, sizeof list - used, "%s%s", used ? ", " : "", e->name.str);
        int k = rgba_index(e->name.str);
        if (k < 0)
            continue;
        if (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT)
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: channel %s: type uint is not supported (need half or float)",
                           path, e->name.str);
        if (e->x_sampling != 1 || e->y_sampling != 1)
            return err_set(BRUME_ERROR_UNSUPPORTED, "%s: channel %s: subsampled channels are not supported",
                           path, e->name.str);
        found[k] = 1;
    }
    if (!found[0] || !found[1] || !found[2])
        return err_set(BRUME_ERROR_PARSE, "%s: channels: need R, G and B, the file has: %s", path,
                       list[0] ? list : "none");
    return BRUME_OK; /* without an A channel, image_create's A = 1 stays */
}

/* Rank of a channel suffix within its layer: R, G, B and X, Y, Z in that order. */
static int suffix_rank(const char *c)
{
    static const char *const order[6] = {"R", "G", "B", "X", "Y", "Z"};
    for (int i = 0; i < 6; i++)
        if (strcmp(c, order[i]) == 0)
            return i % 3;
    return 3;
}

/* Channels "NAME.C" (half or float, not subsampled) become layers of img, at most three
 * channels each; others are skipped. */
static brume_status exr_read_layers(const char *path, exr_const_context_t ctxt, brume_image *img)
{
    const exr_attr_chlist_t *chl = NULL;
    if (exr_get_channels(ctxt, 0, &chl) != EXR_ERR_SUCCESS || !chl)
        return BRUME_OK;
    for (int i = 0; i < chl->num_channels; i++) {
        const exr_attr_chlist_entry_t *e = &chl->entries[i];
        const char *dot = strrchr(e->name.str, '.');
        if (!dot || dot == e->name.str || (size_t)(dot - e->name.str) >= sizeof img->layers[0].name ||
            strlen(dot + 1) >= sizeof img->layers[0].chan[0] || !dot[1] ||
            (e->pixel_type != EXR_PIXEL_HALF && e->pixel_type != EXR_PIXEL_FLOAT) || e->x_sampling != 1 ||
            e->y_sampling != 1)
            continue;
        int n = (int)(dot - e->name.str);
        bool seen = false;
        for (int k = 0; k < img->nlayers; k++)
            seen |= strncmp(img->layers[k].name, e->name.str, (size_t)n) == 0 && img->layers[k].name[n] == '\0';
        if (seen || img->nlayers >= IMAGE_MAX_LAYERS)
            continue;
        /* every channel of this layer, in R G B / X Y Z order */
        const char *chan[3];
        int nc = 0;
        bool ok = true;
        for (int j = 0; j < chl->num_channels && ok; j++) {
            const char *nm = chl->entries[j].name.str;
            if (strncmp(nm, e->name.str, (size_t)n + 1) != 0 || strchr(nm + n + 1, '.'))
                continue;
            if (nc == 3 || strlen(nm + n + 1) >= sizeof img->layers[0].chan[0])
                ok = false;
            else
                chan[nc++] = nm + n + 1;
        }
        if (!ok || nc == 2)
            continue;
        for (int a = 1; a < nc; a++) /* insertion sort by rank */
            for (int b = a; b > 0 && suffix_rank(chan[b]) < suffix_rank(chan[b - 1]); b--) {
                const char *t = chan[b];
                chan[b] = chan[b - 1];
                chan[b - 1] = t;
            }
        char name[32];
        snprintf(name, sizeof name, "%.*s", n, e->name.str);
        if (!image_add_layer(img, name, nc, chan))
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory for layer %s", path, name);
    }
    return BRUME_OK;
}

/* brume's own string attributes ("brume.*") of the file into img's metadata. */
static void exr_read_meta(exr_const_context_t ctxt, brume_image *img)
{
    int32_t nattr = 0; /* they come back through brume_image_attribute */
    if (exr_get_attribute_count(ctxt, 0, &nattr) == EXR_ERR_SUCCESS)
        for (int32_t i = 0; i < nattr; i++) {
            const exr_attribute_t *a = NULL;
            if (exr_get_attribute_by_index(ctxt, 0, EXR_ATTR_LIST_FILE_ORDER, i, &a) == EXR_ERR_SUCCESS && a &&
                a->type == EXR_ATTR_STRING && a->name && strncmp(a->name, "brume.", 6) == 0 && a->string &&
                a->string->str && a->string->length >= 0) {
                char v[80];
                snprintf(v, sizeof v, "%.*s", a->string->length, a->string->str);
                image_set_meta(img, a->name, v);
            }
        }
}

/* The scanline chunks of the data window dw (lines rows each) decoded into img's channels
 * and layers (w x h pixels). */
static brume_status exr_decode_pixels(const char *path, exr_const_context_t ctxt, exr_io *io, exr_attr_box2i_t dw,
                                      int32_t lines, int64_t w, int64_t h, brume_image *img)
{
    exr_result_t rv;
    brume_status st = BRUME_OK;
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int initialized = 0;
    for (int64_t y = dw.min.y; y <= dw.max.y && st == BRUME_OK; y += lines) {
        exr_chunk_info_t cinfo;
        rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo);
        if (rv == EXR_ERR_SUCCESS)
            rv = initialized ? exr_decoding_update(ctxt, 0, &cinfo, &dec)
                             : exr_decoding_initialize(ctxt, 0, &cinfo, &dec);
        if (rv != EXR_ERR_SUCCESS) {
            st = exr_fail(path, "reading pixels", rv, io);
            break;
        }
        initialized = 1;
        int64_t row = (int64_t)cinfo.start_y - dw.min.y;
        if (row < 0 || row + cinfo.height > h || cinfo.width != w) {
            st = err_set(BRUME_ERROR_PARSE, "%s: chunk at y = %d lies outside the data window", path,
                         cinfo.start_y);
            break;
        }
        for (int16_t c = 0; c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            int stride = 4;
            const float *dst = channel_source(img, ch->channel_name, &stride);
            ch->decode_to_ptr = dst ? (uint8_t *)(dst + (size_t)row * (size_t)w * (size_t)stride) : NULL;
            ch->user_pixel_stride = stride * (int32_t)sizeof(float);
            ch->user_line_stride = stride * (int32_t)sizeof(float) * (int32_t)w;
            ch->user_data_type = EXR_PIXEL_FLOAT;
            ch->user_bytes_per_element = (int16_t)sizeof(float);
        }
        rv = exr_decoding_choose_default_routines(ctxt, 0, &dec);
        if (rv == EXR_ERR_SUCCESS)
            rv = exr_decoding_run(ctxt, 0, &dec);
        if (rv != EXR_ERR_SUCCESS)
            st = exr_fail(path, "reading pixels", rv, io);
    }
    if (initialized)
        exr_decoding_destroy(ctxt, &dec);
    return st;
}

static brume_status exr_read_body(const char *path, exr_const_context_t ctxt, exr_io *io, brume_image **out)
{
    exr_result_t rv;
    int parts = 0;
    exr_storage_t storage = EXR_STORAGE_LAST_TYPE;
    if ((rv = exr_get_count(ctxt, &parts)) != EXR_ERR_SUCCESS || parts < 1 ||
        (rv = exr_get_storage(ctxt, 0, &storage)) != EXR_ERR_SUCCESS)
        return exr_fail(path, "reading the header", rv, io);
    if (storage != EXR_STORAGE_SCANLINE)
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: %s EXR files are not supported (only scanline images)",
                       path, storage == EXR_STORAGE_TILED ? "tiled" : "deep");
    brume_status st = exr_check_channels(path, ctxt);
    if (st != BRUME_OK)
        return st;
    exr_attr_box2i_t dw;
    int32_t lines = 0;
    if ((rv = exr_get_data_window(ctxt, 0, &dw)) != EXR_ERR_SUCCESS ||
        (rv = exr_get_scanlines_per_chunk(ctxt, 0, &lines)) != EXR_ERR_SUCCESS)
        return exr_fail(path, "reading the header", rv, io);
    if (lines < 1)
        return err_set(BRUME_ERROR_PARSE, "%s: header: invalid scanlines per chunk %d", path, lines);
    int64_t w = (int64_t)dw.max.x - dw.min.x + 1, h = (int64_t)dw.max.y - dw.min.y + 1;

    /* Every chunk's offset and size must lie in the file: a cut file fails here, before
     * the image is allocated. */
    for (int64_t y = dw.min.y; y <= dw.max.y; y += lines) {
        exr_chunk_info_t cinfo;
        if ((rv = exr_read_scanline_chunk_info(ctxt, 0, (int)y, &cinfo)) != EXR_ERR_SUCCESS)
            return exr_fail(path, "reading the chunk table", rv, io);
    }
    brume_image *img = NULL;
    if ((st = image_create(path, w, h, &img)) != BRUME_OK)
        return st;
    if ((st = exr_read_layers(path, ctxt, img)) != BRUME_OK) {
        brume_image_release(img);
        return st;
    }
    exr_read_meta(ctxt, img);
    st = exr_decode_pixels(path, ctxt, io, dw, lines, w, h, img);
    if (st != BRUME_OK) {
        brume_image_release(img);
        return st;
    }
    *out = img;
    return BRUME_OK;
}

brume_status image_exr_channel_order(const char *path, int *index, int cap, int *count)
{
    exr_io io = {-1, ""};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &io;
    exr_context_t ctxt = NULL;
    g_exr_io = &io;
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    const exr_attr_chlist_t *chl = NULL;
    brume_status st = BRUME_OK;
    if (rv != EXR_ERR_SUCCESS)
        st = exr_fail(path, "not a readable OpenEXR file", rv, &io);
    else if (exr_get_channels(ctxt, 0, &chl) != EXR_ERR_SUCCESS || !chl)
        st = err_set(BRUME_ERROR_PARSE, "%s: channels: cannot read the channel list", path);
    else {
        *count = chl->num_channels;
        for (int i = 0; i < cap && i < chl->num_channels; i++)
            index[i] = rgba_index(chl->entries[i].name.str);
    }
    if (ctxt)
        exr_finish(&ctxt);
    g_exr_io = NULL;
    return st;
}

brume_status image_read_exr(const char *path, brume_image **out)
{
    *out = NULL;
    FILE *probe = NULL; /* OpenEXR's own message for this is less direct */
    brume_status pst = io_open_regular(path, &probe);
    if (pst != BRUME_OK)
        return pst;
    fclose(probe);
    exr_io io = {-1, ""};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &io;
    init.max_image_width = IMAGE_MAX_SIDE;
    init.max_image_height = IMAGE_MAX_SIDE;
    init.flags = EXR_CONTEXT_FLAG_DISABLE_CHUNK_RECONSTRUCTION; /* a damaged file is an error */
    exr_context_t ctxt = NULL;
    g_exr_io = &io;
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    brume_status st;
    if (rv != EXR_ERR_SUCCESS)
        st = exr_fail(path, "not a readable OpenEXR file", rv, &io);
    else
        st = exr_read_body(path, ctxt, &io, out);
    if (ctxt)
        exr_finish(&ctxt);
    g_exr_io = NULL;
    return st;
}
