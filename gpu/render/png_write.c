/* 8-bit RGB PNG through libpng. */
#include "png_write.h"

#include <errno.h>
#include <png.h>
#include <setjmp.h>
#include <stdio.h>
#include <string.h>

#include "gpu_error.h"

/* libpng reports through longjmp; the message is kept here until then. */
typedef struct wg_png_failure {
    char message[256];
} wg_png_failure;

static void on_png_error(png_structp png, png_const_charp msg) {
    wg_png_failure* f = (wg_png_failure*)png_get_error_ptr(png);
    snprintf(f->message, sizeof f->message, "%s", msg ? msg : "libpng error");
    png_longjmp(png, 1);
}

static void on_png_warning(png_structp png, png_const_charp msg) {
    (void)png;
    (void)msg;
}

/* Everything that may longjmp, with no locals of ours live across it. */
static int write_rows(png_structp png, png_infop info, FILE* fp, const unsigned char* rgba, int w,
                      int h) {
    if (setjmp(png_jmpbuf(png))) return 0;
    png_init_io(png, fp);
    png_set_IHDR(png, info, (png_uint_32)w, (png_uint_32)h, 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_set_filler(png, 0, PNG_FILLER_AFTER); /* rows are RGBX: the X byte is dropped */
    for (int y = 0; y < h; ++y)
        png_write_row(png, (png_const_bytep)(rgba + (size_t)y * 4 * (size_t)w));
    png_write_end(png, NULL);
    return 1;
}

wc_status wg_png_write(const char* path, const unsigned char* rgba, int w, int h, char* err,
                         size_t err_len) {
    wg_errorf(err, err_len, "%s", "");
    if (!path || !rgba) {
        wg_errorf(err, err_len, "wg_png_write: %s is NULL", path ? "rgba" : "path");
        return WC_ERROR_INVALID_ARGUMENT;
    }
    if (w < 1 || h < 1 || w > (1 << 24) || h > (1 << 24)) {
        wg_errorf(err, err_len, "%s: picture size %d x %d is not in 1..2^24", path, w, h);
        return WC_ERROR_INVALID_ARGUMENT;
    }
    FILE* fp = fopen(path, "wb");
    if (!fp) {
        wg_errorf(err, err_len, "%s: cannot open for writing: %s", path, strerror(errno));
        return WC_ERROR_IO;
    }
    wg_png_failure failure = {"out of memory"};
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &failure, on_png_error,
                                              on_png_warning);
    png_infop info = png ? png_create_info_struct(png) : NULL;
    int ok = png && info && write_rows(png, info, fp, rgba, w, h);
    png_destroy_write_struct(png ? &png : NULL, info ? &info : NULL);
    int io_errno = 0;
    if (fflush(fp) != 0 || ferror(fp)) io_errno = errno ? errno : EIO;
    if (fclose(fp) != 0 && !io_errno) io_errno = errno ? errno : EIO;
    if (ok && io_errno) {
        ok = 0;
        snprintf(failure.message, sizeof failure.message, "%s", strerror(io_errno));
    }
    if (!ok) {
        remove(path);
        wg_errorf(err, err_len, "%s: writing the PNG failed: %s", path, failure.message);
        return WC_ERROR_IO;
    }
    return WC_OK;
}
