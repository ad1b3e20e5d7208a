// Exact geometric predicates: the sign of a turn a -> b -> c for any finite doubles.
//
// The same three-stage ladder as optri/predicates.py, whose docstring states the proof:
//   1. a float filter (Shewchuk's orient2d bound with the eps^2 term doubled, and a floor
//      of 2**-960 below which it never answers, so an underflowed product cannot fool it);
//   2. expansion arithmetic after scaling all six coordinates by one power of two (exact)
//      so the largest has exponent 450, when then every non-zero one is >= 2**-400;
//   3. integer arithmetic in 26-bit limbs for the rest (coordinates spread over more than
//      2**849 within one triple).
// Every sign is the sign exact rational arithmetic gives; there is no tolerance anywhere.
// The expressions are written in the order of the Python source; the build has
// -ffp-contract=off and no -ffast-math, which the error-free transformations need. The
// code needs IEEE doubles with gradual underflow (no flush-to-zero), as numpy does.
//
// References: J. R. Shewchuk, "Adaptive Precision Floating-Point Arithmetic and Fast
// Robust Geometric Predicates", Discrete Comput. Geom. 18, 1997; T. J. Dekker, "A
// floating-point technique for extending the available precision", Numer. Math. 18, 1971.
#pragma once

#include <cmath>
#include <cstdint>

namespace optri {

namespace pred_detail {

constexpr double kEps = 1.1102230246251565e-16;  // 2**-53
// Relative error bound of the float filter (ccwerrboundA with the eps^2 term doubled).
constexpr double kOrientFilter = (3.0 + 32.0 * kEps) * kEps;
// The filter never answers for |det| at or below this (products may have underflowed).
constexpr double kFilterFloor = 0x1p-960;
constexpr double kSplitter = 134217729.0;  // 2**27 + 1
constexpr int kTop = 450;     // stage 2 scales the largest coordinate to [2**449, 2**450)
constexpr int kSpread = 849;  // ... and needs every non-zero one >= 2**-400 then
constexpr int kLimb = 26;     // stage 3: bits per limb
constexpr std::int64_t kMask = (std::int64_t{1} << kLimb) - 1;
constexpr int kLimbs = 170;   // 26 * 170 bits hold any sum of products, times 2**2252
constexpr int kOffset = 1126; // -(smallest exponent of a double's integer mantissa)

inline void two_sum(double a, double b, double& x, double& y) {
    x = a + b;
    const double bv = x - a;
    const double av = x - bv;
    y = (a - av) + (b - bv);
}

inline void two_diff(double a, double b, double& x, double& y) {
    x = a - b;
    const double bv = a - x;
    const double av = x + bv;
    y = (a - av) + (bv - b);
}

inline void split(double a, double& hi, double& lo) {
    const double c = kSplitter * a;
    hi = c - (c - a);
    lo = a - hi;
}

// x = fl(a * b), x + y == a * b exactly (for |a|, |b| < 2**995 and no partial underflow).
inline void two_product(double a, double b, double& x, double& y) {
    x = a * b;
    double ah, al, bh, bl;
    split(a, ah, al);
    split(b, bh, bl);
    const double err = ((x - ah * bh) - al * bh) - ah * bl;
    y = al * bl - err;
}

// Grow-Expansion with zero elimination: adds b to h[0:m] in place, returns the new length.
inline int grow(double* h, int m, double b) {
    double q = b;
    int out = 0;
    for (int idx = 0; idx < m; ++idx) {
        double e;
        two_sum(q, h[idx], q, e);
        if (e != 0.0) h[out++] = e;
    }
    if (q != 0.0) h[out++] = q;
    return out;
}

// Sign of (ux+uxt)(vy+vyt) - (uy+uyt)(vx+vxt) from exact products and sums.
inline int sign_of_products(double ux, double uxt, double uy, double uyt, double vx,
                            double vxt, double vy, double vyt) {
    double h[16];
    int m = 0;
    const double p[8] = {ux, ux, uxt, uxt, uy, uy, uyt, uyt};
    const double q[8] = {vy, vyt, vy, vyt, vx, vxt, vx, vxt};
    for (int k = 0; k < 8; ++k) {
        if (p[k] != 0.0 && q[k] != 0.0) {
            const double s = k < 4 ? 1.0 : -1.0;
            double x, y;
            two_product(p[k], q[k], x, y);
            m = grow(h, m, s * y);
            m = grow(h, m, s * x);
        }
    }
    if (m == 0) return 0;
    return h[m - 1] > 0.0 ? 1 : -1;
}

inline void mantissa(double x, std::int64_t& m, int& e) {
    int ex;
    const double f = std::frexp(x, &ex);
    m = static_cast<std::int64_t>(f * 9007199254740992.0);
    e = ex - 53;
}

// acc += sign * v * 2**pos for 0 <= v < 2**54, limb by limb (no carries yet).
inline void add_shifted(std::int64_t* acc, std::int64_t v, int pos, std::int64_t sign) {
    int limb = pos / kLimb;
    const int r = pos % kLimb;
    while (v > 0) {
        const std::int64_t w = (v & kMask) << r;  // < 2**52
        acc[limb] += sign * (w & kMask);
        acc[limb + 1] += sign * (w >> kLimb);
        v >>= kLimb;
        ++limb;
    }
}

// acc += sign * x * y exactly, in units of 2**-2252.
inline void add_product(std::int64_t* acc, double x, double y, std::int64_t sign) {
    if (x == 0.0 || y == 0.0) return;
    std::int64_t mx, my;
    int ex, ey;
    mantissa(x, mx, ex);
    mantissa(y, my, ey);
    if (mx < 0) { mx = -mx; sign = -sign; }
    if (my < 0) { my = -my; sign = -sign; }
    const std::int64_t a1 = mx >> kLimb, a0 = mx & kMask;
    const std::int64_t b1 = my >> kLimb, b0 = my & kMask;
    const int pos = ex + ey + 2 * kOffset;
    add_shifted(acc, a0 * b0, pos, sign);
    add_shifted(acc, a0 * b1 + a1 * b0, pos + kLimb, sign);
    add_shifted(acc, a1 * b1, pos + 2 * kLimb, sign);
}

}  // namespace pred_detail

// Exact sign of the turn a -> b -> c in integer arithmetic; any finite doubles.
inline int orient_bigint(double ax, double ay, double bx, double by, double cx, double cy) {
    using namespace pred_detail;
    std::int64_t acc[kLimbs] = {};
    add_product(acc, bx, cy, 1);
    add_product(acc, bx, ay, -1);
    add_product(acc, ax, cy, -1);
    add_product(acc, by, cx, -1);
    add_product(acc, by, ax, 1);
    add_product(acc, ay, cx, 1);
    std::int64_t carry = 0;
    for (int k = 0; k < kLimbs; ++k) {
        const std::int64_t t = acc[k] + carry;
        // floor division by 2**26 (an arithmetic shift, written without shifting negatives)
        carry = t >= 0 ? t / (std::int64_t{1} << kLimb)
                       : -((-t + kMask) / (std::int64_t{1} << kLimb));
        acc[k] = t - carry * (std::int64_t{1} << kLimb);
    }
    if (carry != 0) return carry > 0 ? 1 : -1;
    for (int k = 0; k < kLimbs; ++k) {
        if (acc[k] != 0) return 1;
    }
    return 0;
}

// Exact sign of the turn a -> b -> c (stages 2 and 3).
inline int orient_exact(double ax, double ay, double bx, double by, double cx, double cy) {
    using namespace pred_detail;
    const double big = std::fmax(std::fmax(std::fmax(std::fabs(ax), std::fabs(ay)),
                                           std::fmax(std::fabs(bx), std::fabs(by))),
                                 std::fmax(std::fabs(cx), std::fabs(cy)));
    if (big == 0.0) return 0;
    int top;
    std::frexp(big, &top);
    int low = top;
    const double vs[6] = {ax, ay, bx, by, cx, cy};
    for (double v : vs) {
        if (v != 0.0) {
            int e;
            std::frexp(v, &e);
            if (e < low) low = e;
        }
    }
    if (top - low > kSpread) return orient_bigint(ax, ay, bx, by, cx, cy);
    const int s = kTop - top;  // one power of two for all six: exact
    ax = std::ldexp(ax, s); ay = std::ldexp(ay, s);
    bx = std::ldexp(bx, s); by = std::ldexp(by, s);
    cx = std::ldexp(cx, s); cy = std::ldexp(cy, s);
    double ux, uxt, uy, uyt, vx, vxt, vy, vyt;
    two_diff(bx, ax, ux, uxt);
    two_diff(by, ay, uy, uyt);
    two_diff(cx, ax, vx, vxt);
    two_diff(cy, ay, vy, vyt);
    if (uxt == 0.0 && uyt == 0.0 && vxt == 0.0 && vyt == 0.0) {
        double lh, lt, rh, rt;
        two_product(ux, vy, lh, lt);
        two_product(uy, vx, rh, rt);
        if (lh != rh) return lh > rh ? 1 : -1;
        if (lt != rt) return lt > rt ? 1 : -1;
        return 0;
    }
    return sign_of_products(ux, uxt, uy, uyt, vx, vxt, vy, vyt);
}

// Exact sign of the turn a -> b -> c: +1 left, -1 right, 0 exactly collinear.
// The float filter answers almost every call; orient_exact the rest.
inline int orient_sign(double ax, double ay, double bx, double by, double cx, double cy) {
    using namespace pred_detail;
    const double ux = bx - ax;
    const double uy = by - ay;
    const double vx = cx - ax;
    const double vy = cy - ay;
    const double left = ux * vy;
    const double right = uy * vx;
    const double det = left - right;
    double bound = kOrientFilter * (std::fabs(left) + std::fabs(right));
    if (bound < kFilterFloor) bound = kFilterFloor;
    if (det > bound) return 1;
    if (det < -bound) return -1;
    return orient_exact(ax, ay, bx, by, cx, cy);
}

// For c collinear with segment ab: whether c lies strictly between a and b.
// Comparisons only, so exact: x orders the points on a line that is not vertical, y on one
// that is.
inline bool strictly_between(double ax, double ay, double bx, double by, double cx,
                             double cy) {
    if (ax != bx) return std::fmin(ax, bx) < cx && cx < std::fmax(ax, bx);
    return std::fmin(ay, by) < cy && cy < std::fmax(ay, by);
}

}  // namespace optri
