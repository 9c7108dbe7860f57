// The denoiser's images: float pixels with a fixed number of channels, row-major, interleaved.
#pragma once

#include <cstddef>
#include <functional>
#include <vector>

namespace kiln::denoise {

struct Image {
    int width = 0, height = 0, channels = 0;
    std::vector<float> values;
    Image() = default;
    Image(int w, int h, int c) : width(w), height(h), channels(c), values(size_t(w) * h * c) {}
    size_t pixels() const { return size_t(width) * size_t(height); }
    float* at(int x, int y) { return &values[(size_t(y) * size_t(width) + size_t(x)) * channels]; }
    const float* at(int x, int y) const {
        return &values[(size_t(y) * size_t(width) + size_t(x)) * channels];
    }
};

// A rectangle of pixels [x0, x1) x [y0, y1).
struct Rect {
    int x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    int width() const { return x1 - x0; }
    int height() const { return y1 - y0; }
};

// body(begin, end) over [0, n) in chunks of at least grain on TBB's threads: for passes that
// write each index from one chunk, so the result is the same for any thread count.
void parallelChunks(size_t n, const std::function<void(size_t, size_t)>& body,
                    size_t grain = 16384);

// Channels [first, first + count) of an image.
Image channelsOf(const Image& image, int first, int count);

// The mean of each value over the (2r+1)^2 box around its pixel, clamped at the image's edges.
Image boxMean(const Image& image, int r);

// The tiles of size tile covering the image, row by row.
std::vector<Rect> tilesOf(int width, int height, int tile);

}  // namespace kiln::denoise
