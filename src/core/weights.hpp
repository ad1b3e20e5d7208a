// Edge weights of the built-in edge-decomposable weights (perimeter, diagonal), bit for bit
// the formulas of optri/weights.py (no fused multiply-add: the build has -ffp-contract=off).
//
// A stand-in with the interface of the weights part of the core: replaced by that part's
// header when the branches are merged.
#pragma once

#include <cmath>
#include <cstdint>

namespace optri {

// Vertex data: n rows of dims float64 coordinates (1, 2 or 3), row-major.
struct Points {
    const double* p;
    int64_t n;
    int64_t dims;
};

namespace weights_detail {

constexpr double kSqLo = 0x1p-960;    // a sum of squares above this lost nothing to underflow
constexpr double kSqrtLo = 0x1p-480;  // its square root: a length above this is exact

inline double ldexp_inf(double x, int e) {
    int ex = 0;
    if (x != 0.0) {
        std::frexp(x, &ex);
        if (ex + e > 1024) return std::copysign(INFINITY, x);
    }
    return std::ldexp(x, e);
}

inline double scaled_norm(double dx, double dy, double dz) {
    double m = std::fmax(std::fabs(dx), std::fmax(std::fabs(dy), std::fabs(dz)));
    if (m == 0.0 || m == INFINITY) return m;
    int e = 0;
    std::frexp(m, &e);
    double x = std::ldexp(dx, -e), y = std::ldexp(dy, -e), z = std::ldexp(dz, -e);
    return ldexp_inf(std::sqrt(x * x + y * y + z * z), e);
}

inline double side_length(const Points& pts, int64_t a, int64_t b) {
    const double* pa = pts.p + a * pts.dims;
    const double* pb = pts.p + b * pts.dims;
    double dx = pa[0] - pb[0];
    double dy = pts.dims > 1 ? pa[1] - pb[1] : 0.0;
    double dz = pts.dims > 2 ? pa[2] - pb[2] : 0.0;
    double sq = dx * dx + dy * dy + dz * dz;
    if (kSqLo < sq && sq < INFINITY) return std::sqrt(sq);
    return scaled_norm(dx, dy, dz);
}

inline double of_length(int code, const Points& pts, int64_t a, int64_t b, double d) {
    if (code == 1) {  // diagonal
        if (b - a == 1 || (a == 0 && b == pts.n - 1)) return 0.0;
        return 0.5 * d;
    }
    return d;
}

}  // namespace weights_detail

// e(a, b), a < b, of edge-decomposable weight `code` (0 perimeter, 1 diagonal).
inline double edge_weight(int code, const Points& pts, int64_t a, int64_t b) {
    return weights_detail::of_length(code, pts, a, b, weights_detail::side_length(pts, a, b));
}

// out[q] = edge_weight(code, pts, a, b0 + q) for q < count.
inline void edge_weight_row(int code, const Points& pts, int64_t a, int64_t b0, double* out,
                            int64_t count) {
    using namespace weights_detail;
    const double* pa = pts.p + a * pts.dims;
    if (pts.dims == 2) {
        for (int64_t q = 0; q < count; ++q) {
            const double* pb = pts.p + (b0 + q) * 2;
            double dx = pa[0] - pb[0], dy = pa[1] - pb[1];
            out[q] = std::sqrt(dx * dx + dy * dy);
        }
    } else if (pts.dims == 3) {
        for (int64_t q = 0; q < count; ++q) {
            const double* pb = pts.p + (b0 + q) * 3;
            double dx = pa[0] - pb[0], dy = pa[1] - pb[1], dz = pa[2] - pb[2];
            out[q] = std::sqrt(dx * dx + dy * dy + dz * dz);
        }
    } else {
        for (int64_t q = 0; q < count; ++q) out[q] = side_length(pts, a, b0 + q);
    }
    for (int64_t q = 0; q < count; ++q) {
        if (!(kSqrtLo < out[q] && out[q] < INFINITY)) out[q] = side_length(pts, a, b0 + q);
    }
    if (code != 0) {
        for (int64_t q = 0; q < count; ++q) out[q] = of_length(code, pts, a, b0 + q, out[q]);
    }
}

}  // namespace optri
