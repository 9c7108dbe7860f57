#include "color/chromaticities.h"

#include <cmath>

namespace kiln {
Mat3 multiply(const Mat3& a, const Mat3& b) {
    Mat3 r{};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
            for (int k = 0; k < 3; ++k) r[i][j] += a[i][k] * b[k][j];
    return r;
}

Mat3 inverse(const Mat3& m) {
    double det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
                 m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
                 m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    Mat3 r;
    r[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) / det;
    r[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) / det;
    r[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) / det;
    r[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) / det;
    r[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) / det;
    r[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) / det;
    r[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) / det;
    r[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) / det;
    r[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) / det;
    return r;
}

Color applyMatrix(const Mat3& m, const Color& c) {
    return Color(float(m[0][0] * c.x + m[0][1] * c.y + m[0][2] * c.z),
                 float(m[1][0] * c.x + m[1][1] * c.y + m[1][2] * c.z),
                 float(m[2][0] * c.x + m[2][1] * c.y + m[2][2] * c.z));
}

namespace {

std::array<double, 3> xyToXYZ(double x, double y) { return {x / y, 1.0, (1 - x - y) / y}; }

// Columns are the primaries' XYZ scaled so that RGB (1,1,1) maps to the white point (Y = 1).
Mat3 rgbToXyz(const Chromaticities& c) {
    Mat3 p;
    for (int i = 0; i < 3; ++i) {
        auto xyz = xyToXYZ(c[2 * i], c[2 * i + 1]);
        for (int r = 0; r < 3; ++r) p[r][i] = xyz[r];
    }
    auto w = xyToXYZ(c[6], c[7]);
    Mat3 inv = inverse(p);
    double s[3];
    for (int i = 0; i < 3; ++i) s[i] = inv[i][0] * w[0] + inv[i][1] * w[1] + inv[i][2] * w[2];
    for (int r = 0; r < 3; ++r)
        for (int i = 0; i < 3; ++i) p[r][i] *= s[i];
    return p;
}

// Bradford cone response: adapts XYZ from one white to another.
Mat3 bradford(double srcX, double srcY, double dstX, double dstY) {
    const Mat3 b = {
        {{0.8951, 0.2664, -0.1614}, {-0.7502, 1.7135, 0.0367}, {0.0389, -0.0685, 1.0296}}};
    auto s = xyToXYZ(srcX, srcY), d = xyToXYZ(dstX, dstY);
    Mat3 scale{};
    for (int i = 0; i < 3; ++i) {
        double cs = b[i][0] * s[0] + b[i][1] * s[1] + b[i][2] * s[2];
        double cd = b[i][0] * d[0] + b[i][1] * d[1] + b[i][2] * d[2];
        scale[i][i] = cd / cs;
    }
    return multiply(inverse(b), multiply(scale, b));
}

}  // namespace

bool sameChromaticities(const Chromaticities& a, const Chromaticities& b, float tolerance) {
    for (int i = 0; i < 8; ++i)
        if (std::abs(a[i] - b[i]) > tolerance) return false;
    return true;
}

Mat3 toWorkingSpace(const Chromaticities& from) {
    Mat3 adapt = bradford(from[6], from[7], kRec709D65[6], kRec709D65[7]);
    return multiply(inverse(rgbToXyz(kRec709D65)), multiply(adapt, rgbToXyz(from)));
}

}  // namespace kiln
