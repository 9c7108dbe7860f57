#include "renderer/validation/accuracy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace kiln {

Image Image::fromFilm(const Film& film) {
    Image img;
    img.width = film.width(), img.height = film.height();
    for (int y = 0; y < film.height(); ++y)
        for (int x = 0; x < film.width(); ++x) {
            img.pixels.push_back(film.pixel(x, y));
            img.variance.push_back(film.luminanceVariance(x, y));
        }
    // Colour layers are three consecutive channels named layer.R, layer.G, layer.B.
    const auto& ch = film.layout().channels();
    for (size_t c = 0; c + 2 < ch.size(); ++c) {
        if (ch[c].name.size() < 3 || ch[c].name.compare(ch[c].name.size() - 2, 2, ".R") != 0)
            continue;
        img.layerNames.push_back(ch[c].name.substr(0, ch[c].name.size() - 2));
        std::vector<Color> layer;
        for (int y = 0; y < film.height(); ++y)
            for (int x = 0; x < film.width(); ++x)
                layer.emplace_back(film.aov(x, y, c), film.aov(x, y, c + 1), film.aov(x, y, c + 2));
        img.layers.push_back(std::move(layer));
    }
    return img;
}

Image Image::fromChannels(const ChannelImage& file, const std::vector<std::string>& layers) {
    const size_t nc = file.channelNames.size(), count = size_t(file.width) * file.height;
    auto pick = [&](const std::string& name, int fallback) {
        int c = file.channel(name);
        return c >= 0 ? c : fallback;
    };
    // Variance: kiln's layer name (variance.V), or the bare channel of older files.
    const int r = pick("R", 0), g = pick("G", 1), b = pick("B", 2),
              v = pick("variance.V", file.channel("variance"));
    Image img;
    img.width = file.width, img.height = file.height;
    for (size_t i = 0; i < count; ++i) {
        const float* p = &file.values[i * nc];
        img.pixels.emplace_back(p[r], p[g], p[b]);
        if (v >= 0) img.variance.push_back(p[v]);
    }
    for (const std::string& layer : layers) {
        int lr = file.channel(layer + ".R"), lg = file.channel(layer + ".G"),
            lb = file.channel(layer + ".B");
        if (lr < 0 || lg < 0 || lb < 0) continue;
        img.layerNames.push_back(layer);
        img.layers.emplace_back();
        for (size_t i = 0; i < count; ++i) {
            const float* p = &file.values[i * nc];
            img.layers.back().emplace_back(p[lr], p[lg], p[lb]);
        }
    }
    return img;
}

const std::vector<Color>* Image::layer(const std::string& name) const {
    for (size_t i = 0; i < layerNames.size(); ++i)
        if (layerNames[i] == name) return &layers[i];
    return nullptr;
}

namespace {

ErrorStats compare(const std::vector<Color>& test, const std::vector<Color>& reference,
                   const std::vector<double>& refVariance) {
    ErrorStats e;
    size_t n = std::min(test.size(), reference.size());
    if (n == 0) return e;
    double se = 0, rel = 0, meanT = 0, meanR = 0;
    for (size_t i = 0; i < n; ++i) {
        double t = luminance(test[i]), r = luminance(reference[i]);
        double refVar = refVariance.empty() ? 0.0 : refVariance[i];
        // E[(t - r_hat)^2] = E[(t - r)^2] + Var(r_hat): remove the reference's share.
        double d2 = (t - r) * (t - r) - refVar;
        se += d2;
        rel += relativeSquaredError(d2, r);
        meanT += t, meanR += r;
    }
    e.rmse = std::sqrt(std::max(0.0, se / double(n)));
    e.relMse = std::max(0.0, rel / double(n));
    e.bias = (meanT - meanR) / double(n);
    e.referenceMean = meanR / double(n);
    return e;
}

}  // namespace

ErrorStats compareImages(const Image& test, const Image& reference) {
    return compare(test.pixels, reference.pixels, reference.variance);
}

ErrorStats compareLayer(const Image& test, const Image& reference, const std::string& layer) {
    const std::vector<Color>* t = test.layer(layer);
    const std::vector<Color>* r = reference.layer(layer);
    return t && r ? compare(*t, *r, {}) : ErrorStats{};
}

double albedoEdgeContrast(const Image& test, const Image& reference,
                          const std::vector<Color>& albedo) {
    const int w = reference.width, h = reference.height;
    const size_t n = size_t(w) * size_t(h);
    if (test.pixels.size() != n || reference.pixels.size() != n || albedo.size() != n) return -1;
    double along = 0, sharp = 0;
    auto step = [&](size_t p, size_t q) {
        if (std::abs(luminance(albedo[p]) - luminance(albedo[q])) <= kAlbedoEdge) return;
        const double r = luminance(reference.pixels[p]) - luminance(reference.pixels[q]);
        const double t = luminance(test.pixels[p]) - luminance(test.pixels[q]);
        along += r >= 0 ? t : -t;
        sharp += std::abs(r);
    };
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const size_t p = size_t(y) * size_t(w) + size_t(x);
            if (x + 1 < w) step(p, p + 1);
            if (y + 1 < h) step(p, p + size_t(w));
        }
    return sharp > 0 ? along / sharp : -1;
}

double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
    double sx = 0, sy = 0, sxx = 0, sxy = 0;
    int n = 0;
    for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
        if (!(x[i] > 0 && y[i] > 0)) continue;
        double lx = std::log(x[i]), ly = std::log(y[i]);
        sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
        ++n;
    }
    if (n < 2) return 0;
    double den = n * sxx - sx * sx;
    return den != 0 ? (n * sxy - sx * sy) / den : 0.0;
}

}  // namespace kiln
