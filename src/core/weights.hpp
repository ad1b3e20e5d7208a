// The built-in triangle weights, the compiled twin of src/optri/weights.py.
//
// Every function here is the Python formula of the same name written out in C++ with
// the same operations in the same order (the core is built with -ffp-contract=off and no
// -ffast-math), so both give the same double bit for bit: tests/test_core_weights.py
// evaluates every WeightCode on random and extreme triangles through
// optri._core.generic.triangle_weight and compares the bits. Python's max(a, b) keeps a
// unless b > a (min: unless b < a); py_max / py_min below do the same, which matters for
// the sign of a zero and for a NaN operand.
//
// Vertex data: a row-major n x dims array of doubles in the engines' internal order
// (1-D vertex values as dims = 1). Header-only: every part of the core includes it.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace optri {

// Which built-in formula computes a weight (optri.weights.WeightCode).
enum class WeightCode : int {
    custom = -1,
    perimeter = 0,
    diagonal = 1,
    area = 2,
    product = 3,
    max_angle = 4,
    min_angle = 5,
    aspect_ratio = 6,
};

// A view of the vertices: coordinate c of vertex v is p[v * dims + c].
struct Points {
    const double* p;
    int64_t n;
    int64_t dims;
    double at(int64_t v, int64_t c) const { return p[v * dims + c]; }
};

namespace weights_detail {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();
// weights.py's _SQ_LO, _SQRT_LO, _SHAPE_LO, _SHAPE_HI: 2**-960, 2**-480, 2**-250, 2**250
constexpr double SQ_LO = 0x1p-960;
constexpr double SQRT_LO = 0x1p-480;
constexpr double SHAPE_LO = 0x1p-250;
constexpr double SHAPE_HI = 0x1p250;

}  // namespace weights_detail

// Python's max(a, b) and min(a, b): the first argument unless the second compares above
// (below) it.
inline double py_max(double a, double b) { return b > a ? b : a; }
inline double py_min(double a, double b) { return b < a ? b : a; }

// The binary exponent of x as math.frexp gives it (0 for 0, inf and NaN).
inline int frexp_exp(double x) {
    int e = 0;
    (void)std::frexp(x, &e);
    return std::isfinite(x) ? e : 0;
}

// x * 2**e, infinite on overflow (weights._ldexp).
inline double ldexp_inf(double x, int e) {
    if (x != 0.0 && frexp_exp(x) + e > 1024) return std::copysign(weights_detail::inf, x);
    return std::ldexp(x, e);
}

// sqrt(dx^2 + dy^2 + dz^2) without overflow or underflow in the squares (_scaled_norm).
inline double scaled_norm(double dx, double dy, double dz) {
    double m = py_max(std::fabs(dx), py_max(std::fabs(dy), std::fabs(dz)));
    if (m == 0.0 || m == weights_detail::inf) return m;
    int e = frexp_exp(m);
    double x = std::ldexp(dx, -e), y = std::ldexp(dy, -e), z = std::ldexp(dz, -e);
    return ldexp_inf(std::sqrt(x * x + y * y + z * z), e);
}

// Euclidean distance of vertices a and b (1, 2 or 3 coordinates), for any finite input.
inline double side_length(const Points& p, int64_t a, int64_t b) {
    double dx = p.at(a, 0) - p.at(b, 0);
    double dy = p.dims > 1 ? p.at(a, 1) - p.at(b, 1) : 0.0;
    double dz = p.dims > 2 ? p.at(a, 2) - p.at(b, 2) : 0.0;
    double sq = dx * dx + dy * dy + dz * dz;
    if (weights_detail::SQ_LO < sq && sq < weights_detail::inf) return std::sqrt(sq);
    return scaled_norm(dx, dy, dz);
}

// e(a, b) from the length d of the segment (a, b) (_edge_of_length).
inline double edge_of_length(int code, const Points& p, int64_t a, int64_t b, double d) {
    if (code == static_cast<int>(WeightCode::diagonal)) {
        if (b - a == 1 || (a == 0 && b == p.n - 1)) return 0.0;  // a side is no diagonal
        return 0.5 * d;
    }
    return d;
}

// e(a, b), a < b, of an edge-decomposable weight: w(i, k, j) = e(i, k) + e(k, j) + e(i, j).
inline double edge_weight(int code, const Points& p, int64_t a, int64_t b) {
    return edge_of_length(code, p, a, b, side_length(p, a, b));
}

// out[q] = edge_weight(code, p, a, b0 + q) for q < count, the same values bit for bit: a
// first loop without branches (it vectorizes) takes the square roots of side_length's sums
// of squares; lengths outside the range where that is exact are then taken from
// side_length itself.
inline void edge_weight_row(int code, const Points& p, int64_t a, int64_t b0, double* out,
                            int64_t count) {
    const double* v = p.p;
    const int64_t d = p.dims;
    if (d == 2) {
        const double ax = v[a * 2], ay = v[a * 2 + 1];
        for (int64_t q = 0; q < count; ++q) {
            double dx = ax - v[(b0 + q) * 2];
            double dy = ay - v[(b0 + q) * 2 + 1];
            out[q] = std::sqrt(dx * dx + dy * dy + 0.0 * 0.0);
        }
    } else if (d == 3) {
        const double ax = v[a * 3], ay = v[a * 3 + 1], az = v[a * 3 + 2];
        for (int64_t q = 0; q < count; ++q) {
            double dx = ax - v[(b0 + q) * 3];
            double dy = ay - v[(b0 + q) * 3 + 1];
            double dz = az - v[(b0 + q) * 3 + 2];
            out[q] = std::sqrt(dx * dx + dy * dy + dz * dz);
        }
    } else {
        for (int64_t q = 0; q < count; ++q) out[q] = side_length(p, a, b0 + q);
    }
    int64_t inexact = 0;
    for (int64_t q = 0; q < count; ++q) {
        inexact += (weights_detail::SQRT_LO < out[q] && out[q] < weights_detail::inf) ? 0 : 1;
    }
    if (inexact) {
        for (int64_t q = 0; q < count; ++q) {
            if (!(weights_detail::SQRT_LO < out[q] && out[q] < weights_detail::inf)) {
                out[q] = side_length(p, a, b0 + q);
            }
        }
    }
    if (code != static_cast<int>(WeightCode::perimeter)) {
        for (int64_t q = 0; q < count; ++q) out[q] = edge_of_length(code, p, a, b0 + q, out[q]);
    }
}

// Clamped cosine of the angle opposite side x (law of cosines); -1 if degenerate.
inline double cosine(double x, double y, double z) {
    double den = 2.0 * y * z;
    if (den == 0.0) return -1.0;  // angle pi
    return py_max(-1.0, py_min(1.0, (y * y + z * z - x * x) / den));
}

// Area of triangle (i, k, j) in 2-D or 3-D, for any finite input (NaN for 1-D values,
// which the weight's check rejects before any engine runs).
inline double triangle_area(const Points& p, int64_t i, int64_t k, int64_t j) {
    using namespace weights_detail;
    const int64_t dim = p.dims;
    if (dim < 2) return nan;
    double u0 = p.at(k, 0) - p.at(i, 0), u1 = p.at(k, 1) - p.at(i, 1);
    double v0 = p.at(j, 0) - p.at(i, 0), v1 = p.at(j, 1) - p.at(i, 1);
    double u2 = dim > 2 ? p.at(k, 2) - p.at(i, 2) : 0.0;
    double v2 = dim > 2 ? p.at(j, 2) - p.at(i, 2) : 0.0;
    double m = py_max(py_max(py_max(std::fabs(u0), std::fabs(u1)),
                             py_max(std::fabs(v0), std::fabs(v1))),
                      py_max(std::fabs(u2), std::fabs(v2)));
    int e = 0;
    if (m > SHAPE_HI || (0.0 < m && m < SHAPE_LO)) {  // products would overflow or underflow
        e = frexp_exp(m);
        u0 = std::ldexp(u0, -e), u1 = std::ldexp(u1, -e), u2 = std::ldexp(u2, -e);
        v0 = std::ldexp(v0, -e), v1 = std::ldexp(v1, -e), v2 = std::ldexp(v2, -e);
    }
    if (dim == 2) return ldexp_inf(0.5 * std::fabs(u0 * v1 - u1 * v0), 2 * e);
    double cx = u1 * v2 - u2 * v1;
    double cy = u2 * v0 - u0 * v2;
    double cz = u0 * v1 - u1 * v0;
    return ldexp_inf(0.5 * std::sqrt(cx * cx + cy * cy + cz * cz), 2 * e);
}

// |(x, y, z)| * 2**-e, the components scaled first (exact) (_norm_at).
inline double norm_at(double x, double y, double z, int e) {
    x = std::ldexp(x, -e), y = std::ldexp(y, -e), z = std::ldexp(z, -e);
    return std::sqrt(x * x + y * y + z * z);
}

// Side lengths |kj|, |ij|, |ik|, all scaled by one power of two to near 1 (_scaled_sides).
inline void scaled_sides(const Points& p, int64_t i, int64_t k, int64_t j, double& a,
                         double& b, double& c) {
    const bool three = p.dims > 2;
    double ax = p.at(j, 0) - p.at(k, 0), ay = p.at(j, 1) - p.at(k, 1);
    double bx = p.at(j, 0) - p.at(i, 0), by = p.at(j, 1) - p.at(i, 1);
    double cx = p.at(k, 0) - p.at(i, 0), cy = p.at(k, 1) - p.at(i, 1);
    double az = three ? p.at(j, 2) - p.at(k, 2) : 0.0;
    double bz = three ? p.at(j, 2) - p.at(i, 2) : 0.0;
    double cz = three ? p.at(k, 2) - p.at(i, 2) : 0.0;
    double m = py_max(py_max(py_max(std::fabs(ax), std::fabs(ay)), std::fabs(az)),
                      py_max(py_max(std::fabs(bx), std::fabs(by)), std::fabs(bz)));
    int e = frexp_exp(
        py_max(m, py_max(py_max(std::fabs(cx), std::fabs(cy)), std::fabs(cz))));
    a = norm_at(ax, ay, az, e);
    b = norm_at(bx, by, bz, e);
    c = norm_at(cx, cy, cz, e);
}

// The side-length weights: largest angle, minus smallest angle, aspect ratio (_shape).
inline double shape(int code, const Points& p, int64_t i, int64_t k, int64_t j) {
    using namespace weights_detail;
    if (p.dims < 2) return nan;
    double a = side_length(p, k, j), b = side_length(p, i, j), c = side_length(p, i, k);
    double m = py_max(a, py_max(b, c));
    if (m > SHAPE_HI || (0.0 < m && m < SHAPE_LO)) scaled_sides(p, i, k, j, a, b, c);
    // acos is decreasing: the largest angle has the smallest cosine (one acos, not three)
    if (code == static_cast<int>(WeightCode::max_angle)) {
        return std::acos(py_min(py_min(cosine(a, b, c), cosine(b, c, a)), cosine(c, a, b)));
    }
    if (code == static_cast<int>(WeightCode::min_angle)) {
        return -std::acos(py_max(py_max(cosine(a, b, c), cosine(b, c, a)), cosine(c, a, b)));
    }
    double s = 0.5 * (a + b + c);
    double q = (s - a) * (s - b) * (s - c);
    if (q <= 0.0) return inf;  // degenerate
    return a * b * c / (8.0 * q);  // R / (2 r) = abc / (8 (s-a)(s-b)(s-c))
}

// Built-in weight `code` of triangle (i, k, j); NaN for an unknown code (custom included).
inline double triangle_weight(int code, const Points& p, int64_t i, int64_t k, int64_t j) {
    switch (static_cast<WeightCode>(code)) {
        case WeightCode::perimeter:
        case WeightCode::diagonal:
            return edge_weight(code, p, i, k) + edge_weight(code, p, k, j) +
                   edge_weight(code, p, i, j);
        case WeightCode::area:
            return triangle_area(p, i, k, j);
        case WeightCode::product:
            return p.at(i, 0) * p.at(k, 0) * p.at(j, 0);
        case WeightCode::max_angle:
        case WeightCode::min_angle:
        case WeightCode::aspect_ratio:
            return shape(code, p, i, k, j);
        default:
            return weights_detail::nan;
    }
}

}  // namespace optri
