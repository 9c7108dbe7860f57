// Small vector, matrix and bounds types shared by the whole renderer.
#pragma once

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

namespace kiln {

constexpr float kPi = 3.14159265358979323846f;
constexpr float kInfinity = std::numeric_limits<float>::infinity();

template <typename T>
struct Vec3T {
    T x = 0, y = 0, z = 0;
    constexpr Vec3T() = default;
    constexpr Vec3T(T x_, T y_, T z_) : x(x_), y(y_), z(z_) {}
    constexpr explicit Vec3T(T v) : x(v), y(v), z(v) {}
    template <typename U>
    constexpr explicit Vec3T(const Vec3T<U>& o) : x(T(o.x)), y(T(o.y)), z(T(o.z)) {}

    constexpr T operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr T& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }
    constexpr Vec3T operator+(const Vec3T& o) const { return {x + o.x, y + o.y, z + o.z}; }
    constexpr Vec3T operator-(const Vec3T& o) const { return {x - o.x, y - o.y, z - o.z}; }
    constexpr Vec3T operator*(const Vec3T& o) const { return {x * o.x, y * o.y, z * o.z}; }
    constexpr Vec3T operator/(const Vec3T& o) const { return {x / o.x, y / o.y, z / o.z}; }
    constexpr Vec3T operator*(T s) const { return {x * s, y * s, z * s}; }
    constexpr Vec3T operator/(T s) const { return {x / s, y / s, z / s}; }
    constexpr Vec3T operator-() const { return {-x, -y, -z}; }
    constexpr Vec3T& operator+=(const Vec3T& o) { return *this = *this + o; }
    constexpr Vec3T& operator-=(const Vec3T& o) { return *this = *this - o; }
    constexpr Vec3T& operator*=(const Vec3T& o) { return *this = *this * o; }
    constexpr Vec3T& operator*=(T s) { return *this = *this * s; }
    constexpr bool operator==(const Vec3T& o) const = default;
};

using Vec3 = Vec3T<float>;
using Vec3d = Vec3T<double>;
using Color = Vec3;  // linear RGB in the scene-linear working space (Rec.709 primaries)

template <typename T>
constexpr Vec3T<T> operator*(T s, const Vec3T<T>& v) {
    return v * s;
}
template <typename T>
constexpr T dot(const Vec3T<T>& a, const Vec3T<T>& b) {
    return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <typename T>
constexpr Vec3T<T> cross(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <typename T>
inline T length(const Vec3T<T>& v) {
    return std::sqrt(dot(v, v));
}
template <typename T>
inline Vec3T<T> normalize(const Vec3T<T>& v) {
    return v / length(v);
}
template <typename T>
constexpr Vec3T<T> abs(const Vec3T<T>& v) {
    return {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
}
template <typename T>
constexpr Vec3T<T> min(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)};
}
template <typename T>
constexpr Vec3T<T> max(const Vec3T<T>& a, const Vec3T<T>& b) {
    return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)};
}
template <typename T>
constexpr T maxComponent(const Vec3T<T>& v) {
    return std::max(v.x, std::max(v.y, v.z));
}
template <typename T>
constexpr int maxDimension(const Vec3T<T>& v) {
    return (v.x > v.y) ? (v.x > v.z ? 0 : 2) : (v.y > v.z ? 1 : 2);
}
template <typename T>
inline bool isFinite(const Vec3T<T>& v) {
    return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}
inline float luminance(const Color& c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

// A squared error d2 of an estimate of r, relative to r and robust near black (below a luminance
// of 0.1 it is absolute): the accuracy report's relative MSE and the noise threshold's measure.
constexpr double relativeSquaredError(double d2, double r) { return d2 / (r * r + 0.01); }

// Builds an orthonormal basis around a unit vector n (Duff et al. 2017).
inline void orthonormalBasis(const Vec3& n, Vec3& s, Vec3& t) {
    float sign = std::copysign(1.0f, n.z);
    float a = -1.0f / (sign + n.z);
    float b = n.x * n.y * a;
    s = {1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x};
    t = {b, sign + n.y * n.y * a, -n.y};
}

// Axis-aligned box; an empty box has lo > hi so that any union fixes it.
template <typename T>
struct Bounds3T {
    Vec3T<T> lo{std::numeric_limits<T>::max()};
    Vec3T<T> hi{std::numeric_limits<T>::lowest()};

    constexpr bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    constexpr bool contains(const Vec3T<T>& p) const {
        return p.x >= lo.x && p.y >= lo.y && p.z >= lo.z && p.x <= hi.x && p.y <= hi.y &&
               p.z <= hi.z;
    }
    constexpr void extend(const Vec3T<T>& p) { lo = min(lo, p), hi = max(hi, p); }
    constexpr void extend(const Bounds3T& b) { lo = min(lo, b.lo), hi = max(hi, b.hi); }
    constexpr Vec3T<T> diagonal() const { return hi - lo; }
    constexpr Vec3T<T> centroid() const { return (lo + hi) * T(0.5); }
    constexpr T surfaceArea() const {
        if (empty()) return 0;
        Vec3T<T> d = diagonal();
        return 2 * (d.x * d.y + d.y * d.z + d.z * d.x);
    }
};
using Bounds3 = Bounds3T<float>;

// Row-major 4x4 affine transform in double precision: import composes node matrices with it, and
// the precision keeps world positions faithful when files nest transforms.
struct Mat4 {
    double m[4][4] = {{1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};

    static Mat4 identity() { return {}; }
    Mat4 operator*(const Mat4& o) const {
        Mat4 r;
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                r.m[i][j] = 0;
                for (int k = 0; k < 4; ++k) r.m[i][j] += m[i][k] * o.m[k][j];
            }
        return r;
    }
    Vec3d point(const Vec3d& p) const {
        return {m[0][0] * p.x + m[0][1] * p.y + m[0][2] * p.z + m[0][3],
                m[1][0] * p.x + m[1][1] * p.y + m[1][2] * p.z + m[1][3],
                m[2][0] * p.x + m[2][1] * p.y + m[2][2] * p.z + m[2][3]};
    }
    Vec3d vector(const Vec3d& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z,
                m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
    Vec3 point(const Vec3& p) const { return Vec3(point(Vec3d(p))); }
    Vec3 vector(const Vec3& v) const { return Vec3(vector(Vec3d(v))); }
    // Normals transform by the inverse transpose; callers normalise.
    Vec3 normal(const Vec3& n) const;
    Mat4 inverse() const;
    double determinant3() const {
        return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
               m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
               m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    }
    bool isIdentity() const {
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j)
                if (m[i][j] != (i == j ? 1.0 : 0.0)) return false;
        return true;
    }
};

inline Mat4 Mat4::inverse() const {
    // General 4x4 inverse by cofactors (Gauss-Jordan with partial pivoting for robustness).
    double a[4][8];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            a[i][j] = m[i][j];
            a[i][j + 4] = (i == j) ? 1.0 : 0.0;
        }
    for (int c = 0; c < 4; ++c) {
        int pivot = c;
        for (int r = c + 1; r < 4; ++r)
            if (std::abs(a[r][c]) > std::abs(a[pivot][c])) pivot = r;
        if (pivot != c)
            for (int j = 0; j < 8; ++j) std::swap(a[c][j], a[pivot][j]);
        double d = a[c][c];
        if (d == 0) return Mat4{{{0}}};  // singular: callers check determinant3 first
        for (int j = 0; j < 8; ++j) a[c][j] /= d;
        for (int r = 0; r < 4; ++r) {
            if (r == c) continue;
            double f = a[r][c];
            for (int j = 0; j < 8; ++j) a[r][j] -= f * a[c][j];
        }
    }
    Mat4 r;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) r.m[i][j] = a[i][j + 4];
    return r;
}

// Normals transform by the inverse transpose; pass the inverse when it is already known.
inline Vec3 transformNormal(const Mat4& inv, const Vec3& n) {
    return Vec3(Vec3d(inv.m[0][0] * n.x + inv.m[1][0] * n.y + inv.m[2][0] * n.z,
                      inv.m[0][1] * n.x + inv.m[1][1] * n.y + inv.m[2][1] * n.z,
                      inv.m[0][2] * n.x + inv.m[1][2] * n.y + inv.m[2][2] * n.z));
}
inline Vec3 Mat4::normal(const Vec3& n) const { return transformNormal(inverse(), n); }

// pbrt's gamma(n) = n u / (1 - n u), u = eps / 2: bounds the relative error of n chained float
// operations.
constexpr float gamma(int n) {
    constexpr float u = std::numeric_limits<float>::epsilon() * 0.5f;
    return (float(n) * u) / (1 - float(n) * u);
}

// The next representable float towards +infinity / -infinity (pbrt's NextFloatUp/Down), without
// libm.
inline float nextFloatUp(float v) {
    if (std::isinf(v) && v > 0) return v;
    if (v == -0.0f) v = 0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v >= 0 ? bits + 1 : bits - 1;
    return std::bit_cast<float>(bits);
}
inline float nextFloatDown(float v) {
    if (std::isinf(v) && v < 0) return v;
    if (v == 0.0f) v = -0.0f;
    uint32_t bits = std::bit_cast<uint32_t>(v);
    bits = v > 0 ? bits - 1 : bits + 1;
    return std::bit_cast<float>(bits);
}

// Inverse error function, Giles' single-precision approximation ("Approximating the erfinv
// function", GPU Computing Gems, 2011): about 4e-7 relative on (-1, 1); x is clamped to
// +-0.99999.
inline float erfInv(float x) {
    x = std::clamp(x, -0.99999f, 0.99999f);
    float w = -std::log((1 - x) * (1 + x)), p;
    if (w < 5) {
        w -= 2.5f;
        p = 2.81022636e-08f;
        p = 3.43273939e-07f + p * w;
        p = -3.5233877e-06f + p * w;
        p = -4.39150654e-06f + p * w;
        p = 0.00021858087f + p * w;
        p = -0.00125372503f + p * w;
        p = -0.00417768164f + p * w;
        p = 0.246640727f + p * w;
        p = 1.50140941f + p * w;
    } else {
        w = std::sqrt(w) - 3;
        p = -0.000200214257f;
        p = 0.000100950558f + p * w;
        p = 0.00134934322f + p * w;
        p = -0.00367342844f + p * w;
        p = 0.00573950773f + p * w;
        p = -0.0076224613f + p * w;
        p = 0.00943887047f + p * w;
        p = 1.00167406f + p * w;
        p = 2.83297682f + p * w;
    }
    return p * x;
}

inline float radians(float deg) { return deg * (kPi / 180.0f); }
inline float degrees(float rad) { return rad * (180.0f / kPi); }

}  // namespace kiln
