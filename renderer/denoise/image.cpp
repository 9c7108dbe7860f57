#include "renderer/denoise/image.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

namespace kiln::denoise {

void parallelChunks(size_t n, const std::function<void(size_t, size_t)>& body, size_t grain) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, grain),
                      [&](const tbb::blocked_range<size_t>& r) { body(r.begin(), r.end()); });
}

Image channelsOf(const Image& image, int first, int count) {
    Image out(image.width, image.height, count);
    parallelChunks(image.pixels(), [&](size_t begin, size_t end) {
        for (size_t p = begin; p < end; ++p)
            for (int c = 0; c < count; ++c)
                out.values[p * size_t(count) + size_t(c)] =
                    image.values[p * size_t(image.channels) + size_t(first + c)];
    });
    return out;
}

namespace {

// One separable pass of the box sum: along rows (dx = 1) or columns (dy = 1), clamped at the
// edges, each sum times scale; a fixed order of additions per value.
void boxPass(const Image& in, Image& out, int r, int dx, int dy, float scale) {
    const int w = in.width, h = in.height, nc = in.channels;
    parallelChunks(
        size_t(h),
        [&](size_t y0, size_t y1) {
            for (int y = int(y0); y < int(y1); ++y)
                for (int x = 0; x < w; ++x)
                    for (int c = 0; c < nc; ++c) {
                        float sum = 0;
                        for (int d = -r; d <= r; ++d)
                            sum += in.at(std::clamp(x + d * dx, 0, w - 1),
                                         std::clamp(y + d * dy, 0, h - 1))[c];
                        out.at(x, y)[c] = sum * scale;
                    }
        },
        8);
}

}  // namespace

Image boxMean(const Image& image, int r) {
    Image rows(image.width, image.height, image.channels), out = rows;
    boxPass(image, rows, r, 1, 0, 1.0f);
    boxPass(rows, out, r, 0, 1, 1.0f / float((2 * r + 1) * (2 * r + 1)));
    return out;
}

std::vector<Rect> tilesOf(int width, int height, int tile) {
    std::vector<Rect> tiles;
    for (int y = 0; y < height; y += tile)
        for (int x = 0; x < width; x += tile)
            tiles.push_back({x, y, std::min(x + tile, width), std::min(y + tile, height)});
    return tiles;
}

}  // namespace kiln::denoise
