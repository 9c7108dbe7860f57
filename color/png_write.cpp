#include "color/png_write.h"

#include <png.h>

#include <cstring>
#include <stdexcept>

#include "color/atomic_file.h"

namespace kiln {
namespace {

// libpng reports errors by longjmp: its message is kept here, and no C++ object with a destructor
// lives between setjmp and the calls that may jump (encode below).
struct PngError {
    char message[256] = "";
};

void onError(png_structp png, png_const_charp message) {
    auto* error = static_cast<PngError*>(png_get_error_ptr(png));
    std::strncpy(error->message, message, sizeof error->message - 1);
    png_longjmp(png, 1);
}

void onWarning(png_structp, png_const_charp) {}

// AtomicFile's writes do not throw (a short write is reported by commit()).
void toFile(png_structp png, png_bytep data, size_t bytes) {
    static_cast<AtomicFile*>(png_get_io_ptr(png))->write(data, bytes);
}

void noFlush(png_structp) {}

bool encode(AtomicFile& file, int w, int h, int channels, const uint8_t* codes, PngError& error) {
    png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &error, onError, onWarning);
    if (!png) return false;
    png_infop info = png_create_info_struct(png);
    if (!info) {
        png_destroy_write_struct(&png, nullptr);
        return false;
    }
    if (setjmp(png_jmpbuf(png))) {
        png_destroy_write_struct(&png, &info);
        return false;
    }
    png_set_write_fn(png, &file, toFile, noFlush);
    png_set_IHDR(png, info, png_uint_32(w), png_uint_32(h), 8,
                 channels == 4 ? PNG_COLOR_TYPE_RGBA : PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE,
                 PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_set_compression_level(png, 1);
    png_write_info(png, info);
    for (int y = 0; y < h; ++y)
        png_write_row(png, codes + size_t(y) * size_t(w) * size_t(channels));
    png_write_end(png, info);
    png_destroy_write_struct(&png, &info);
    return true;
}

}  // namespace

void writePng(const std::string& path, int w, int h, int channels, const uint8_t* codes,
              const char* what) {
    AtomicFile file(path);
    PngError error;
    if (!encode(file, w, h, channels, codes, error))
        throw std::runtime_error(path + ": cannot write " + what + ": " +
                                 (*error.message ? error.message : "libpng failed"));
    file.commit();
}

}  // namespace kiln
