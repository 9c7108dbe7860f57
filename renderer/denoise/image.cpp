#include "renderer/denoise/image.h"

#include <algorithm>

namespace kiln::denoise {

Image channelsOf(const Image& image, int first, int count) {
    Image out(image.width, image.height, count);
    for (size_t p = 0; p < image.pixels(); ++p)
        for (int c = 0; c < count; ++c)
            out.values[p * size_t(count) + size_t(c)] =
                image.values[p * size_t(image.channels) + size_t(first + c)];
    return out;
}

Image boxMean(const Image& image, int r) {
    const int w = image.width, h = image.height, nc = image.channels;
    Image rows(w, h, nc), out(w, h, nc);
    // Separable: along rows, then along columns; a fixed order of additions per value.
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < nc; ++c) {
                float sum = 0;
                for (int d = -r; d <= r; ++d) sum += image.at(std::clamp(x + d, 0, w - 1), y)[c];
                rows.at(x, y)[c] = sum;
            }
    const float norm = 1.0f / float((2 * r + 1) * (2 * r + 1));
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            for (int c = 0; c < nc; ++c) {
                float sum = 0;
                for (int d = -r; d <= r; ++d) sum += rows.at(x, std::clamp(y + d, 0, h - 1))[c];
                out.at(x, y)[c] = sum * norm;
            }
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
