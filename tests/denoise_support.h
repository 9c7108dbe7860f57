// What the denoiser tests measure: a film's beauty or light-path layer as an image, and the
// relative MSE of luminance against a reference (docs/accuracy.md's figure) with its standard
// error.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "renderer/film/film.h"

namespace kiln::test {

inline std::vector<Color> beautyOf(const Film& film) {
    std::vector<Color> image(film.pixelCount());
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            image[size_t(y) * size_t(film.width()) + size_t(x)] = film.pixel(x, y);
    return image;
}

// The AOV layer's R, G, B channels ("direct").
inline std::vector<Color> layerOf(const Film& film, const std::string& layer) {
    const std::vector<AovChannel>& channels = film.layout().channels();
    size_t first = 0;
    while (first < channels.size() && channels[first].name != layer + ".R") ++first;
    if (first == channels.size()) throw std::logic_error("the film has no layer " + layer);
    std::vector<Color> image(film.pixelCount());
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x)
            for (int c = 0; c < 3; ++c)
                image[size_t(y) * size_t(film.width()) + size_t(x)][c] =
                    film.aov(x, y, first + size_t(c));
    return image;
}

// (x - r)^2 / (r^2 + 0.01) of luminance, per pixel.
inline std::vector<double> relErrors(const std::vector<Color>& image,
                                     const std::vector<Color>& reference) {
    std::vector<double> e;
    for (size_t p = 0; p < reference.size(); ++p) {
        double r = luminance(reference[p]), v = luminance(image[p]);
        e.push_back((v - r) * (v - r) / (r * r + 0.01));
    }
    return e;
}

// A mean over pixels and its standard error.
struct RelMse {
    double mean = 0, standardError = 0;
};
inline RelMse meanOf(const std::vector<double>& e) {
    RelMse m;
    for (double v : e) m.mean += v / double(e.size());
    for (double v : e) m.standardError += (v - m.mean) * (v - m.mean);
    m.standardError = std::sqrt(m.standardError / double(e.size() - 1) / double(e.size()));
    return m;
}

inline RelMse relMseOf(const std::vector<Color>& image, const std::vector<Color>& reference) {
    return meanOf(relErrors(image, reference));
}

// How much lower image's relMSE is than other's against the same reference, pixel by pixel (a
// paired comparison: the two errors of a pixel share its reference and its noise).
inline RelMse relMseDrop(const std::vector<Color>& image, const std::vector<Color>& other,
                         const std::vector<Color>& reference) {
    std::vector<double> a = relErrors(image, reference), b = relErrors(other, reference);
    for (size_t p = 0; p < a.size(); ++p) b[p] -= a[p];
    return meanOf(b);
}

}  // namespace kiln::test
