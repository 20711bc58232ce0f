/* image_png.c - PNG images through libpng: 8-bit sRGB RGB out, any PNG in.
 *
 * Writing: R, G, B are exposed, tone mapped and sRGB encoded (image_encode_srgb8, by table). The
 * PNG is opaque: a rendered pixel already holds the background seen through the media, so
 * an alpha channel would make viewers composite the background a second time; the
 * coverage (A) is kept in EXR output, where compositing tools expect it. The file carries an sRGB chunk, plus the gAMA and cHRM chunks
 * that the PNG specification (11.3.3.5) recommends beside it for older decoders.
 *
 * Reading: 1..16-bit gray, gray+alpha, palette, RGB or RGBA, interlaced or not, are
 * normalized by libpng transforms to 8- or 16-bit RGBA; colour is decoded from sRGB to
 * linear (IEC 61966-2-1), so that write then read returns the linear values to within
 * half an 8-bit step of the sRGB encoding.
 *
 * libpng reports errors by longjmp to the jmp_buf of the png struct; each function that
 * calls setjmp does nothing else, and the work after it happens in a callee, so no local
 * variable of the setjmp caller changes between setjmp and longjmp (C11 7.13.2.1). */
#include <errno.h>
#include <png.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <zlib.h> /* Z_RLE (libpng-dev brings zlib1g-dev) */

#include "core/error.h"
#include "core/regular_file.h"
#include "io/atomic.h"
#include "io/image_formats.h"

/* libpng's messages for this call, reported with the path. */
typedef struct png_msg {
    char text[256];
} png_msg;

static void on_png_error(png_structp png, png_const_charp msg)
{
    png_msg *m = png_get_error_ptr(png);
    snprintf(m->text, sizeof m->text, "%s", msg ? msg : "unknown libpng error");
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg)
{
    (void)png; /* warnings (unknown ancillary chunks, bad CRC in them) do not stop a read */
    (void)msg;
}

/* ---- writing ------------------------------------------------------------------------------ */

/* A growing memory buffer that libpng writes into (image_encode_png). */
typedef struct png_membuf {
    unsigned char *data;
    size_t size, cap;
} png_membuf;

static void png_mem_write(png_structp png, png_bytep bytes, size_t n)
{
    png_membuf *b = png_get_io_ptr(png);
    if (b->size + n > b->cap) {
        size_t cap = b->cap ? b->cap : 65536;
        while (cap < b->size + n)
            cap *= 2;
        unsigned char *p = realloc(b->data, cap);
        if (!p)
            png_error(png, "out of memory");
        b->data = p;
        b->cap = cap;
    }
    memcpy(b->data + b->size, bytes, n);
    b->size += n;
}

static void png_mem_flush(png_structp png) { (void)png; }

/* fp NULL: the bytes go to the png_membuf given as io pointer by the caller. */
static void png_write_body(png_structp png, png_infop info, FILE *fp, const brume_image *img,
                           const brume_write_options *opts, unsigned char *row)
{
    if (fp)
        png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)img->width, (png_uint_32)img->height, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_sRGB_gAMA_and_cHRM(png, info, PNG_sRGB_INTENT_PERCEPTUAL);
    /* zlib's run-length strategy over libpng's filters chosen row by row: a rendered image's
     * filtered rows are mostly runs of small differences. Against zlib's default, on the
     * docs' pictures: 3 to 7 x faster (Blasi's picture 1, 400 x 400: 33 -> 11 ms), files
     * 1 to 6 % larger, a small noisy one 1.6 x (cloud64 at 256 spp: 16 -> 24 KB) */
    png_set_compression_strategy(png, Z_RLE);
    png_write_info(png, info);
    size_t w = (size_t)img->width;
    image_srgb8_table codes; /* image_encode_srgb8's bytes, by table */
    image_srgb8_table_init(&codes, opts);
    for (int y = 0; y < img->height; y++) {
        const float *src = img->rgba + (size_t)y * w * 4;
        for (size_t i = 0; i < w; i++) {
            for (size_t c = 0; c < 3; c++) /* the pixel to the left as the guess */
                row[3 * i + c] = image_srgb8_lookup(&codes, src[4 * i + c], i > 0 ? row[3 * (i - 1) + c] : 0);
        }
        png_write_row(png, row);
    }
    png_write_end(png, NULL);
}

/* 1 on success, 0 when libpng raised an error (message in the error pointer). */
static int png_write_guarded(png_structp png, png_infop info, FILE *fp, const brume_image *img,
                             const brume_write_options *opts, unsigned char *row)
{
    if (setjmp(png_jmpbuf(png)))
        return 0;
    png_write_body(png, info, fp, img, opts, row);
    return 1;
}

brume_status image_write_png(const char *path, const brume_image *img, const brume_write_options *opts)
{
    atomic_file f;
    brume_status st = atomic_open_kind(&f, path, BRUME_FILE_IMAGE);
    if (st != BRUME_OK)
        return st;
    png_msg msg = {""};
    unsigned char *row = malloc((size_t)img->width * 4);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &msg, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!row || !png || !info) {
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    } else if (!png_write_guarded(png, info, f.fp, img, opts, row)) {
        st = err_set(BRUME_ERROR_IO, "%s: cannot write PNG: %s", path, msg.text);
    }
    png_destroy_write_struct(&png, &info);
    free(row);
    if (st != BRUME_OK) {
        atomic_abort(&f);
        return st;
    }
    return atomic_commit(&f);
}

brume_status image_encode_png(const brume_image *img, const brume_write_options *opts, unsigned char **data,
                              size_t *size)
{
    *data = NULL;
    *size = 0;
    brume_status st = BRUME_OK;
    png_msg msg = {""};
    png_membuf buf = {NULL, 0, 0};
    unsigned char *row = malloc((size_t)img->width * 4);
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &msg, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!row || !png || !info) {
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "PNG encoding: out of memory");
    } else {
        png_set_write_fn(png, &buf, png_mem_write, png_mem_flush);
        if (!png_write_guarded(png, info, NULL, img, opts, row))
            st = err_set(BRUME_ERROR_IO, "PNG encoding: %s", msg.text);
    }
    png_destroy_write_struct(&png, &info);
    free(row);
    if (st != BRUME_OK) {
        free(buf.data);
        return st;
    }
    *data = buf.data;
    *size = buf.size;
    return BRUME_OK;
}

/* ---- reading ------------------------------------------------------------------------------ */

/* Allocations of a read, released by the caller whether or not libpng jumped. */
typedef struct png_read_state {
    const char *path;
    size_t file_size;     /* bytes, for the plausibility check of the header's size */
    brume_image *img;     /* the result */
    unsigned char *buf;   /* one row, or the whole image when interlaced */
    png_bytep *rows;      /* row pointers into buf when interlaced */
} png_read_state;

/* Converts one decoded row of RGBA, 8 or 16 bits per sample (big-endian, PNG 7.1). */
static void png_convert_row(const unsigned char *src, int depth, size_t w, const float *lut8, float *dst)
{
    for (size_t i = 0; i < 4 * w; i++) {
        double v;
        if (depth == 16) {
            unsigned u = (unsigned)src[2 * i] << 8 | src[2 * i + 1];
            v = u / 65535.0;
            dst[i] = (float)((i & 3) == 3 ? v : image_srgb_decode(v));
        } else {
            dst[i] = (i & 3) == 3 ? (float)(src[i] / 255.0) : lut8[src[i]];
        }
    }
}

static brume_status png_read_body(png_structp png, png_infop info, FILE *fp, png_read_state *s)
{
    png_init_io(png, fp);
    png_set_sig_bytes(png, 8);
    png_set_user_limits(png, IMAGE_MAX_SIDE, IMAGE_MAX_SIDE);
    png_read_info(png, info);

    png_uint_32 w, h;
    int depth, ctype, interlace;
    png_get_IHDR(png, info, &w, &h, &depth, &ctype, &interlace, NULL, NULL);
    /* A file cannot hold more than 1032 times its size of pixel data: deflate's largest
     * ratio (zlib technical details, "maximum compression factor"). This refuses truncated
     * files that claim a huge size before the image is allocated. */
    uint64_t samples = ctype == PNG_COLOR_TYPE_PALETTE ? 1 : png_get_channels(png, info);
    uint64_t raw = (uint64_t)h * (((uint64_t)w * samples * (uint64_t)depth + 7) / 8);
    if (raw / 1032 > s->file_size)
        return err_set(BRUME_ERROR_PARSE, "%s: truncated: a %u x %u PNG cannot fit in %zu bytes", s->path,
                       (unsigned)w, (unsigned)h, s->file_size);

    int has_trns = png_get_valid(png, info, PNG_INFO_tRNS) != 0;
    if (ctype == PNG_COLOR_TYPE_PALETTE)
        png_set_palette_to_rgb(png);
    if ((ctype == PNG_COLOR_TYPE_GRAY || ctype == PNG_COLOR_TYPE_GRAY_ALPHA) && depth < 8)
        png_set_expand_gray_1_2_4_to_8(png);
    if (has_trns)
        png_set_tRNS_to_alpha(png);
    if (ctype == PNG_COLOR_TYPE_GRAY || ctype == PNG_COLOR_TYPE_GRAY_ALPHA)
        png_set_gray_to_rgb(png);
    if (!(ctype & PNG_COLOR_MASK_ALPHA) && !has_trns)
        png_set_filler(png, depth == 16 ? 0xffff : 0xff, PNG_FILLER_AFTER);
    int passes = png_set_interlace_handling(png);
    png_read_update_info(png, info);

    int out_depth = png_get_bit_depth(png, info);
    size_t rowbytes = png_get_rowbytes(png, info);
    if (png_get_channels(png, info) != 4 || (out_depth != 8 && out_depth != 16) ||
        rowbytes != (size_t)w * 4 * (size_t)(out_depth / 8))
        return err_set(BRUME_ERROR_UNSUPPORTED, "%s: PNG layout not supported (color type %d, %d bits)",
                       s->path, ctype, depth);
    brume_status st = image_create(s->path, w, h, &s->img);
    if (st != BRUME_OK)
        return st;

    float lut8[256];
    for (int i = 0; i < 256; i++)
        lut8[i] = (float)image_srgb_decode(i / 255.0);
    if (passes > 1) { /* Adam7: libpng needs every row at once */
        s->buf = malloc(rowbytes * h);
        s->rows = malloc(sizeof *s->rows * h);
        if (!s->buf || !s->rows)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", s->path);
        for (png_uint_32 y = 0; y < h; y++)
            s->rows[y] = s->buf + (size_t)y * rowbytes;
        png_read_image(png, s->rows);
        for (png_uint_32 y = 0; y < h; y++)
            png_convert_row(s->rows[y], out_depth, w, lut8, s->img->rgba + (size_t)y * w * 4);
    } else {
        s->buf = malloc(rowbytes);
        if (!s->buf)
            return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", s->path);
        for (png_uint_32 y = 0; y < h; y++) {
            png_read_row(png, s->buf, NULL);
            png_convert_row(s->buf, out_depth, w, lut8, s->img->rgba + (size_t)y * w * 4);
        }
    }
    png_read_end(png, NULL); /* reads to IEND: a file cut after the pixels fails too */
    return BRUME_OK;
}

static brume_status png_read_guarded(png_structp png, png_infop info, FILE *fp, png_read_state *s,
                                     const png_msg *msg)
{
    if (setjmp(png_jmpbuf(png))) {
        if (feof(fp)) /* libpng says only "Read Error" */
            return err_set(BRUME_ERROR_PARSE, "%s: truncated PNG: the file ends early", s->path);
        return err_set(BRUME_ERROR_PARSE, "%s: malformed PNG: %s", s->path, msg->text);
    }
    return png_read_body(png, info, fp, s);
}

brume_status image_read_png(const char *path, brume_image **out)
{
    *out = NULL;
    FILE *fp = NULL;
    brume_status ost = io_open_regular(path, &fp);
    if (ost != BRUME_OK)
        return ost;
    struct stat sb;
    unsigned char sig[8];
    if (fstat(fileno(fp), &sb) != 0) {
        int e = errno;
        fclose(fp);
        return err_set(BRUME_ERROR_IO, "%s: cannot read: %s", path, strerror(e));
    }
    if (fread(sig, 1, 8, fp) != 8 || png_sig_cmp(sig, 0, 8) != 0) {
        fclose(fp);
        return err_set(BRUME_ERROR_PARSE, "%s: not a PNG file (bad signature)", path);
    }

    png_msg msg = {""};
    png_read_state s = {path, (size_t)sb.st_size, NULL, NULL, NULL};
    brume_status st;
    png_structp png = png_create_read_struct(PNG_LIBPNG_VER_STRING, &msg, on_png_error, on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    if (!png || !info)
        st = err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    else
        st = png_read_guarded(png, info, fp, &s, &msg);
    png_destroy_read_struct(&png, &info, NULL);
    fclose(fp);
    free(s.buf);
    free(s.rows);
    if (st != BRUME_OK) {
        brume_image_release(s.img);
        return st;
    }
    *out = s.img;
    return BRUME_OK;
}
