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
    const int r = pick("R", 0), g = pick("G", 1), b = pick("B", 2), v = file.channel("variance");
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
        rel += d2 / (r * r + 0.01);
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

std::string svgLogLogPlot(const std::string& title, const std::string& xLabel,
                          const std::string& yLabel, const std::vector<PlotSeries>& series,
                          bool slopeMinusOne) {
    const double W = 640, H = 420, L = 70, R = 170, T = 40, B = 50;
    double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
    for (const PlotSeries& s : series)
        for (size_t i = 0; i < s.x.size(); ++i)
            if (s.x[i] > 0 && s.y[i] > 0) {
                x0 = std::min(x0, std::log10(s.x[i])), x1 = std::max(x1, std::log10(s.x[i]));
                y0 = std::min(y0, std::log10(s.y[i])), y1 = std::max(y1, std::log10(s.y[i]));
            }
    if (x0 > x1) x0 = 0, x1 = 1, y0 = 0, y1 = 1;
    x0 = std::floor(x0), x1 = std::ceil(x1 + 1e-9), y0 = std::floor(y0), y1 = std::ceil(y1 + 1e-9);
    auto px = [&](double lx) { return L + (lx - x0) / (x1 - x0) * (W - L - R); };
    auto py = [&](double ly) { return H - B - (ly - y0) / (y1 - y0) * (H - T - B); };
    const char* colours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                             "#9467bd", "#8c564b", "#e377c2", "#17becf"};
    std::string svg;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%g\" height=\"%g\" "
                  "font-family=\"sans-serif\" "
                  "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
                  "<text x=\"%g\" y=\"22\" font-size=\"14\">%s</text>\n",
                  W, H, L, title.c_str());
    svg += buf;
    for (double d = x0; d <= x1 + 1e-9; d += 1) {
        std::snprintf(buf, sizeof buf,
                      "<line x1=\"%.1f\" y1=\"%g\" x2=\"%.1f\" y2=\"%g\" stroke=\"#ddd\"/><text "
                      "x=\"%.1f\" y=\"%g\" "
                      "text-anchor=\"middle\">1e%d</text>\n",
                      px(d), T, px(d), H - B, px(d), H - B + 16, int(d));
        svg += buf;
    }
    for (double d = y0; d <= y1 + 1e-9; d += 1) {
        std::snprintf(buf, sizeof buf,
                      "<line x1=\"%g\" y1=\"%.1f\" x2=\"%g\" y2=\"%.1f\" stroke=\"#ddd\"/><text "
                      "x=\"%g\" y=\"%.1f\" "
                      "text-anchor=\"end\">1e%d</text>\n",
                      L, py(d), W - R, py(d), L - 6, py(d) + 4, int(d));
        svg += buf;
    }
    std::snprintf(
        buf, sizeof buf,
        "<text x=\"%g\" y=\"%g\" text-anchor=\"middle\">%s</text>\n<text x=\"16\" y=\"%g\" "
        "transform=\"rotate(-90 16 %g)\" text-anchor=\"middle\">%s</text>\n",
        (L + W - R) / 2, H - 12, xLabel.c_str(), (T + H - B) / 2, (T + H - B) / 2, yLabel.c_str());
    svg += buf;
    int k = 0;
    for (const PlotSeries& s : series) {
        const char* c = colours[k % 8];
        std::string points;
        for (size_t i = 0; i < s.x.size(); ++i)
            if (s.x[i] > 0 && s.y[i] > 0) {
                std::snprintf(buf, sizeof buf, "%.1f,%.1f ", px(std::log10(s.x[i])),
                              py(std::log10(s.y[i])));
                points += buf;
                std::snprintf(buf, sizeof buf,
                              "<circle cx=\"%.1f\" cy=\"%.1f\" r=\"2.5\" fill=\"%s\"/>\n",
                              px(std::log10(s.x[i])), py(std::log10(s.y[i])), c);
                svg += buf;
            }
        svg += "<polyline fill=\"none\" stroke=\"" + std::string(c) +
               "\" stroke-width=\"1.5\" points=\"" + points + "\"/>\n";
        std::snprintf(
            buf, sizeof buf,
            "<line x1=\"%g\" y1=\"%d\" x2=\"%g\" y2=\"%d\" stroke=\"%s\" stroke-width=\"2\"/>"
            "<text x=\"%g\" y=\"%d\">%s</text>\n",
            W - R + 10, 50 + 18 * k, W - R + 30, 50 + 18 * k, c, W - R + 35, 54 + 18 * k,
            s.name.c_str());
        svg += buf;
        ++k;
    }
    if (slopeMinusOne && !series.empty() && !series[0].x.empty()) {
        // Through the first series' first point, slope -1: error halves when time doubles.
        double lx = std::log10(series[0].x[0]), ly = std::log10(series[0].y[0]);
        double lx2 = x1, ly2 = ly - (lx2 - lx);
        std::snprintf(
            buf, sizeof buf,
            "<line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\" stroke=\"#888\" "
            "stroke-dasharray=\"6 4\"/><text x=\"%g\" y=\"%d\" fill=\"#888\">slope -1</text>\n",
            px(lx), py(ly), px(lx2), py(ly2), W - R + 35, 54 + 18 * k);
        svg += buf;
    }
    svg += "</svg>\n";
    return svg;
}

}  // namespace kiln
