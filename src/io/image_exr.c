/* image_exr.c - OpenEXR images through the OpenEXR C core API (libOpenEXRCore, 3.1).
 *
 * Writing: one scanline part, channels R, G, B, A as 32-bit float, ZIP compression (16
 * scanlines per chunk), increasing y, data and display windows (0,0)-(w-1,h-1). The bytes
 * go through a write callback to the temporary file of io/atomic.c, renamed over the
 * destination when complete.
 *
 * Reading: part 0 of a scanline file with channels R, G, B (half or float, converted to
 * float) and optionally A (default 1); other channels are skipped. The image is the data
 * window, top row = its smallest y. Tiled and deep files are refused.
 *
 * The core API keeps a channel list sorted by name (A, B, G, R), so channels are found by
 * name, never by position. References: OpenEXR's openexr_encode.h / openexr_decode.h and
 * "Reading and Writing Image Files with the C API" (openexr.com, OpenEXR 3.1). */
#include <errno.h>
#include <openexr.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/error.h"
#include "io/regular_file.h"
#include "io/atomic.h"
#include "io/image.h"

/* Passed to OpenEXR as user data: the file being written and the library's last message. */
typedef struct exr_io {
    int fd;              /* write: the temporary file; read: unused (-1) */
    char message[256];   /* last error reported by OpenEXR, one line */
} exr_io;

static void on_exr_error(exr_const_context_t ctxt, exr_result_t code, const char *msg)
{
    void *user = NULL;
    if (exr_get_user_data(ctxt, &user) != EXR_ERR_SUCCESS || !user)
        return;
    exr_io *io = user;
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
    if ((rv = exr_set_version(ctxt, part, 1)) != EXR_ERR_SUCCESS ||
        (rv = exr_write_header(ctxt)) != EXR_ERR_SUCCESS)
        return exr_fail(path, "writing the header", rv, io);

    int32_t lines = 1;
    if ((rv = exr_get_scanlines_per_chunk(ctxt, part, &lines)) != EXR_ERR_SUCCESS || lines < 1)
        return exr_fail(path, "writing the header", rv, io);

    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    int initialized = 0;
    brume_status st = BRUME_OK;
    const int32_t pixel_stride = 4 * (int32_t)sizeof(float);
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
        const float *first = img->rgba + (size_t)y * (size_t)img->width * 4;
        for (int16_t c = 0; c < enc.channel_count; c++) {
            exr_coding_channel_info_t *ch = &enc.channels[c];
            int k = rgba_index(ch->channel_name);
            ch->encode_from_ptr = (const uint8_t *)(first + (k < 0 ? 0 : k));
            ch->user_pixel_stride = pixel_stride;
            ch->user_line_stride = pixel_stride * img->width;
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
    brume_status st = atomic_open(&f, path);
    if (st != BRUME_OK)
        return st;
    exr_io io = {fileno(f.fp), ""};
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = on_exr_error;
    init.user_data = &io;
    init.write_fn = exr_write_fd; /* the file name is then only used in messages */
    exr_context_t ctxt = NULL;
    exr_result_t rv = exr_start_write(&ctxt, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rv != EXR_ERR_SUCCESS) {
        st = exr_fail(path, "cannot start writing", rv, &io);
    } else {
        st = exr_write_body(path, img, ctxt, &io);
    }
    /* exr_finish writes the chunk offset table: its result matters on success. */
    if (ctxt) {
        rv = exr_finish(&ctxt);
        if (st == BRUME_OK && rv != EXR_ERR_SUCCESS)
            st = exr_fail(path, "finishing the file", rv, &io);
    }
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

    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    int initialized = 0;
    const int32_t pixel_stride = 4 * (int32_t)sizeof(float);
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
        float *first = img->rgba + (size_t)row * (size_t)w * 4;
        for (int16_t c = 0; c < dec.channel_count; c++) {
            exr_coding_channel_info_t *ch = &dec.channels[c];
            int k = rgba_index(ch->channel_name);
            ch->decode_to_ptr = k < 0 ? NULL : (uint8_t *)(first + k);
            ch->user_pixel_stride = pixel_stride;
            ch->user_line_stride = pixel_stride * (int32_t)w;
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
    if (st != BRUME_OK) {
        brume_image_release(img);
        return st;
    }
    *out = img;
    return BRUME_OK;
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
    exr_result_t rv = exr_start_read(&ctxt, path, &init);
    brume_status st;
    if (rv != EXR_ERR_SUCCESS)
        st = exr_fail(path, "not a readable OpenEXR file", rv, &io);
    else
        st = exr_read_body(path, ctxt, &io, out);
    if (ctxt)
        exr_finish(&ctxt);
    return st;
}
