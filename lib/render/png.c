/* PNG files through stb_image_write's row filters, with zlib doing the deflate: stb's own
   deflate is simple and slow (about 5x zlib's level 2 on a 1280 x 720 frame). */
#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include "core/error.h"

/* Fast deflate: level 2 encodes a frame several times faster than stb's default (8) for a
   file a few per cent larger. stb passes its compression-level global as `quality`; it is
   ignored, so that global (like every stb global) is never written and the library keeps no
   mutable global state. */
#define PNG_ZLIB_LEVEL 2

static unsigned char* zlib_compress(unsigned char* data, int size, int* out_size, int quality)
{
    (void)quality;
    uLongf bound = compressBound((uLong)size);
    unsigned char* out = malloc(bound);
    if (!out)
        return NULL;
    if (compress2(out, &bound, data, (uLong)size, PNG_ZLIB_LEVEL) != Z_OK || bound > INT32_MAX) {
        free(out);
        return NULL;
    }
    *out_size = (int)bound;
    return out;
}

/* One row filter for every row: stbi_write_png_to_mem tries all five on each row and keeps the
   smallest sum of residuals (its filter choice is a global, which the library never writes).
   Measured on two demo frames (1280 x 720, zlib level 2, best of 15, one sitting): all five
   34 ms, "up" 11.5 ms, for files 2-3 % larger ("sub" 12 ms, -2 to +4.5 %; Paeth 17 ms,
   +1-1.6 %; none 9 ms, +11-24 %). */
#define PNG_FILTER_UP 2

#define STBIW_ZLIB_COMPRESS zlib_compress
#define STB_IMAGE_WRITE_STATIC
#define STB_IMAGE_WRITE_IMPLEMENTATION
/* Static, so stb's other writers are unused functions: GCC reports those at the end of the
   file, past any pop. */
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wmissing-field-initializers"
#pragma GCC diagnostic ignored "-Wpedantic"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

/* stbi_write_png_to_mem with one filter for every row (PNG_FILTER_UP) and no global read:
   8-bit RGB (n = 3) or RGBA (n = 4). */
static unsigned char* encode_png(const unsigned char* pixels, int stride, int w, int h, int n, int* out_len)
{
    size_t row = (size_t)w * (size_t)n + 1;
    unsigned char* filtered = malloc(row * (size_t)h);
    if (!filtered)
        return NULL;
    for (int y = 0; y < h; y++) {
        filtered[(size_t)y * row] = y == 0 ? 0 : PNG_FILTER_UP; /* no row above the first */
        stbiw__encode_png_line((unsigned char*)pixels, stride, w, h, y, n, PNG_FILTER_UP,
                               (signed char*)filtered + (size_t)y * row + 1);
    }
    int zlen = 0;
    unsigned char* zlib = zlib_compress(filtered, (int)(row * (size_t)h), &zlen, 0);
    free(filtered);
    if (!zlib)
        return NULL;
    static const unsigned char signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    unsigned char* out = malloc(8 + 12 + 13 + 12 + (size_t)zlen + 12);
    if (!out) {
        free(zlib);
        return NULL;
    }
    unsigned char* o = out;
    memcpy(o, signature, 8);
    o += 8;
    stbiw__wp32(o, 13);
    stbiw__wptag(o, "IHDR");
    stbiw__wp32(o, w);
    stbiw__wp32(o, h);
    *o++ = 8;                   /* bits per channel */
    *o++ = n == 4 ? 6 : 2;      /* colour type: RGBA or RGB */
    *o++ = 0;                   /* deflate, adaptive filtering, no interlace */
    *o++ = 0;
    *o++ = 0;
    stbiw__wpcrc(&o, 13);
    stbiw__wp32(o, zlen);
    stbiw__wptag(o, "IDAT");
    memcpy(o, zlib, (size_t)zlen);
    o += zlen;
    free(zlib);
    stbiw__wpcrc(&o, zlen);
    stbiw__wp32(o, 0);
    stbiw__wptag(o, "IEND");
    stbiw__wpcrc(&o, 0);
    *out_len = (int)(o - out);
    return out;
}

/* Writes the encoded bytes to a temporary file beside `path` and renames it into place. */
static cvk_result write_atomic(const char* path, const unsigned char* bytes, size_t size, cvk_error* error)
{
    size_t len = strlen(path);
    char* temp = malloc(len + 16);
    if (!temp)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of memory", path);
    snprintf(temp, len + 16, "%s.tmp-XXXXXX", path);
    int fd = mkstemp(temp);
    if (fd < 0) {
        int code = errno;
        free(temp);
        return cvk_fail_errno(error, path, "cannot create", code);
    }
    /* mkstemp makes 0600; give the file the permissions any new file gets. */
    mode_t mask = umask(0);
    umask(mask);
    fchmod(fd, 0666 & ~mask);
    int code = 0;
    for (size_t done = 0; done < size && !code;) {
        ssize_t n = write(fd, bytes + done, size - done);
        if (n < 0 && errno != EINTR)
            code = errno;
        else if (n > 0)
            done += (size_t)n;
    }
    if (close(fd) != 0 && !code)
        code = errno;
    if (!code && rename(temp, path) != 0)
        code = errno;
    if (code)
        unlink(temp);
    free(temp);
    return code ? cvk_fail_errno(error, path, "cannot write", code) : CVK_SUCCESS;
}

cvk_result cvk_image_write_png(const cvk_image* image, const char* path, cvk_error* error)
{
    if (!image || !image->pixels || !path)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "cvk_image_write_png needs an image with pixels and a path");
    if (image->width == 0 || image->height == 0 || image->width > INT32_MAX / 4 || image->height > INT32_MAX ||
        image->row_bytes < 4u * image->width || image->row_bytes > INT32_MAX)
        return cvk_fail(error, CVK_ERROR_INVALID_ARGUMENT, "%s: cannot encode a %u x %u image with %u bytes per row",
                        path, image->width, image->height, image->row_bytes);
    /* The file is renamed over the target: a device node, FIFO, folder or link there would be
       replaced by a plain file, so such a target is refused. */
    struct stat st;
    if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return cvk_fail(error, CVK_ERROR_IO, "%s: exists and is not a regular file; it is not "
                        "replaced", path);
    /* An opaque image (every alpha 255, as the renderer makes them) is written as RGB: a
       quarter less to filter and compress. */
    size_t w = image->width, h = image->height;
    unsigned char* rgb = malloc(w * h * 3);
    bool opaque = rgb != NULL;
    for (size_t y = 0; y < h && opaque; y++) {
        const uint8_t* row = image->pixels + y * image->row_bytes;
        unsigned char* out = rgb + y * w * 3;
        for (size_t x = 0; x < w; x++) {
            opaque = opaque && row[4 * x + 3] == 255;
            out[3 * x] = row[4 * x];
            out[3 * x + 1] = row[4 * x + 1];
            out[3 * x + 2] = row[4 * x + 2];
        }
    }
    int size = 0;
    unsigned char* png = opaque ? encode_png(rgb, (int)(w * 3), (int)w, (int)h, 3, &size)
                                : encode_png(image->pixels, (int)image->row_bytes, (int)w, (int)h, 4, &size);
    free(rgb);
    if (!png)
        return cvk_fail(error, CVK_ERROR_OUT_OF_MEMORY, "%s: out of memory encoding a %u x %u PNG", path,
                        image->width, image->height);
    cvk_result r = write_atomic(path, png, (size_t)size, error);
    free(png);
    return r;
}
