/* image_pfm.c - Portable Float Map images: RGB ("PF") or gray ("Pf") float32.
 *
 * Format (P. Debevec's HDRShop / Netpbm "pfm"): an ASCII header "PF" or "Pf", white space,
 * width, white space, height, white space, a scale factor, one white-space character, then
 * width * height * channels float32 samples. The sign of the scale gives the byte order
 * (negative: little-endian, positive: big-endian); its magnitude is not used here. Rows
 * run from the BOTTOM of the picture to the top, left to right within a row: brume's
 * images are top row first, so rows are flipped on the way in and out. */
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "core/error.h"
#include "core/number.h"
#include "core/regular_file.h"
#include "io/atomic.h"
#include "io/image_formats.h"

static void put_f32le(unsigned char *p, float v)
{
    uint32_t u;
    memcpy(&u, &v, 4);
    p[0] = (unsigned char)(u & 0xff);
    p[1] = (unsigned char)((u >> 8) & 0xff);
    p[2] = (unsigned char)((u >> 16) & 0xff);
    p[3] = (unsigned char)(u >> 24);
}

static float get_f32(const unsigned char *p, int little_endian)
{
    uint32_t u = little_endian
                     ? (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24
                     : (uint32_t)p[3] | (uint32_t)p[2] << 8 | (uint32_t)p[1] << 16 | (uint32_t)p[0] << 24;
    float v;
    memcpy(&v, &u, 4);
    return v;
}

brume_status image_write_pfm(const char *path, const brume_image *img)
{
    atomic_file f;
    brume_status st = atomic_open_kind(&f, path, BRUME_FILE_IMAGE);
    if (st != BRUME_OK)
        return st;
    size_t w = (size_t)img->width;
    unsigned char *row = malloc(w * 12);
    if (!row) {
        atomic_abort(&f);
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    int ok = fprintf(f.fp, "PF\n%d %d\n-1.0\n", img->width, img->height) > 0;
    for (int y = img->height - 1; ok && y >= 0; y--) { /* bottom row first */
        const float *src = img->rgba + (size_t)y * w * 4;
        for (size_t x = 0; x < w; x++)
            for (int c = 0; c < 3; c++)
                put_f32le(row + 12 * x + 4 * (size_t)c, src[4 * x + (size_t)c]);
        ok = fwrite(row, 12, w, f.fp) == w;
    }
    int e = errno;
    free(row);
    if (!ok) {
        atomic_abort(&f);
        return err_set(BRUME_ERROR_IO, "%s: cannot write: %s", path, strerror(e));
    }
    return atomic_commit(&f);
}

/* Reads one header token: skips white space (and '#' comments, which some writers emit),
 * then up to cap - 1 non-space characters. Returns the character after the token. */
static int read_token(FILE *fp, char *buf, size_t cap)
{
    int c = fgetc(fp);
    for (;;) {
        while (c == ' ' || c == '\t' || c == '\n' || c == '\r')
            c = fgetc(fp);
        if (c != '#')
            break;
        while (c != '\n' && c != EOF)
            c = fgetc(fp);
    }
    size_t n = 0;
    while (c != EOF && c != ' ' && c != '\t' && c != '\n' && c != '\r') {
        if (n + 1 < cap)
            buf[n] = (char)c;
        n++;
        c = fgetc(fp);
    }
    if (n >= cap) /* too long to be a valid field: make it fail to parse */
        n = cap - 1, buf[0] = 'x';
    buf[n] = '\0';
    return c;
}

/* A header dimension: decimal digits only. -1 when malformed; values beyond 9 digits
 * saturate at 10^9, far above any accepted size, so that the product cannot overflow. */
static int64_t parse_dimension(const char *s)
{
    size_t n = strlen(s);
    if (n == 0 || strspn(s, "0123456789") != n)
        return -1;
    if (n > 9)
        return 1000000000;
    int64_t v = 0;
    for (size_t i = 0; i < n; i++) {
        if (s[i] < '0' || s[i] > '9')
            return -1;
        v = v * 10 + (s[i] - '0');
    }
    return v;
}

/* The header of the PFM file open in fp: its channels (3 for "PF", 1 for "Pf"), size and
 * scale, checked (the size against the limits and the file's length) before any allocation;
 * fp is left at the first row. */
static brume_status pfm_header(FILE *fp, const char *path, int *channels, int64_t *w, int64_t *h, double *scale)
{
    char magic[8], tw[32], th[32], ts[64];
    read_token(fp, magic, sizeof magic);
    if (strcmp(magic, "PF") == 0)
        *channels = 3;
    else if (strcmp(magic, "Pf") == 0)
        *channels = 1;
    else
        return err_set(BRUME_ERROR_PARSE, "%s: not a PFM file (magic is not \"PF\" or \"Pf\")", path);
    read_token(fp, tw, sizeof tw);
    read_token(fp, th, sizeof th);
    int after = read_token(fp, ts, sizeof ts);
    *w = parse_dimension(tw);
    *h = parse_dimension(th);
    if (*w < 0 || *h < 0)
        return err_set(BRUME_ERROR_PARSE, "%s: header: width and height: expected two integers, got '%s' '%s'",
                       path, tw, th);
    char *end = NULL;
    *scale = num_strtod(ts, &end);
    if (!ts[0] || *end || !isfinite(*scale) || *scale == 0.0)
        return err_set(BRUME_ERROR_PARSE, "%s: header: scale: expected a finite nonzero number, got '%s'",
                       path, ts);
    if (after == EOF)
        return err_set(BRUME_ERROR_PARSE, "%s: truncated after the header", path);
    /* Size checks before any allocation: dimensions in range, then a file long enough. */
    if (*w < 1 || *w > IMAGE_MAX_SIDE || *h < 1 || *h > IMAGE_MAX_SIDE || *w * *h > IMAGE_MAX_PIXELS)
        return err_set(BRUME_ERROR_PARSE,
                       "%s: header: image size %s x %s: each side must be in [1, %d], at most %lld pixels",
                       path, tw, th, IMAGE_MAX_SIDE, (long long)IMAGE_MAX_PIXELS);
    long data_start = ftell(fp);
    struct stat sb;
    if (data_start < 0 || fstat(fileno(fp), &sb) != 0)
        return err_set(BRUME_ERROR_IO, "%s: cannot read: %s", path, strerror(errno));
    int64_t need = *w * *h * *channels * 4;
    int64_t have = (int64_t)sb.st_size - data_start;
    if (S_ISREG(sb.st_mode) && have != need)
        return err_set(BRUME_ERROR_PARSE, "%s: %s: %lld x %lld x %d floats need %lld bytes, file has %lld",
                       path, have < need ? "truncated" : "trailing bytes", (long long)*w, (long long)*h, *channels,
                       (long long)need, (long long)have);
    return BRUME_OK;
}

/* The h rows of w pixels from fp into img (the file is bottom first; one channel is grey). */
static brume_status pfm_rows(FILE *fp, const char *path, brume_image *img, int64_t w, int64_t h, int channels,
                             int little)
{
    size_t row_bytes = (size_t)w * (size_t)channels * 4;
    unsigned char *row = malloc(row_bytes);
    if (!row)
        return err_set(BRUME_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    for (int64_t r = 0; r < h; r++) {
        if (fread(row, 1, row_bytes, fp) != row_bytes) {
            free(row);
            return err_set(BRUME_ERROR_PARSE, "%s: truncated in row %lld of %lld", path, (long long)r,
                           (long long)h);
        }
        float *dst = img->rgba + (size_t)(h - 1 - r) * (size_t)w * 4; /* file is bottom first */
        for (size_t x = 0; x < (size_t)w; x++) {
            for (int c = 0; c < 3; c++) {
                int k = channels == 3 ? c : 0;
                dst[4 * x + (size_t)c] = get_f32(row + 4 * ((size_t)channels * x + (size_t)k), little);
            }
            dst[4 * x + 3] = 1.0f;
        }
    }
    free(row);
    return BRUME_OK;
}

brume_status image_read_pfm(const char *path, brume_image **out)
{
    *out = NULL;
    FILE *fp = NULL;
    brume_status ost = io_open_regular(path, &fp);
    if (ost != BRUME_OK)
        return ost;
    brume_image *img = NULL;
    int channels = 0;
    int64_t w = 0, h = 0;
    double scale = 0.0;
    brume_status st = pfm_header(fp, path, &channels, &w, &h, &scale);
    if (st == BRUME_OK)
        st = image_create(path, w, h, &img);
    if (st == BRUME_OK)
        st = pfm_rows(fp, path, img, w, h, channels, scale < 0.0);
    fclose(fp);
    if (st != BRUME_OK) {
        brume_image_release(img);
        return st;
    }
    *out = img;
    return BRUME_OK;
}
