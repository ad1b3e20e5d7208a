// Zero-area triangles of a hole's patch, decided exactly, and the patch with the fewest.
//
// A triangle is degenerate when its three points are collinear: its cross product is the
// zero vector, i.e. its projections on the three coordinate planes all have orient2d = 0.
// optri's exact orient2d (predicates.hpp) decides each sign without a tolerance, on the
// coordinates as given (the float test of unit_normal, sine <= 1e-12, only says when a
// normal is too noisy to compare; every exactly collinear triangle passes it as well,
// rounding moving the sine by about 1e-16).
//
// fewest_degenerate minimizes (degenerate count, area) lexicographically over every
// triangulation whose chords are allowed: both parts are sums over triangles, so the
// recurrence over chords is exact for the pair (the count is an integer; ties in area
// keep the smallest apex). fewest_then_weight does the same for (count, sum or max of a
// built-in triangle weight), the triangle-weight modes' objective. The searches call it when their patch has a degenerate
// triangle: then every patch has a key-3 triangle (kDegenerateKey), every patch's
// Liepa objective is (pi, area), and this is the lexicographic optimum of
// (count, objective).
#include <cstdint>
#include <limits>
#include <vector>

#include "holes.hpp"
#include "predicates.hpp"
#include "weights.hpp"

namespace optri::holes {

bool collinear(const double* P, int64_t a, int64_t b, int64_t c) {
    const double* A = P + 3 * a;
    const double* B = P + 3 * b;
    const double* C = P + 3 * c;
    return orient_sign(A[0], A[1], B[0], B[1], C[0], C[1]) == 0 &&
           orient_sign(A[1], A[2], B[1], B[2], C[1], C[2]) == 0 &&
           orient_sign(A[2], A[0], B[2], B[0], C[2], C[0]) == 0;
}

void collinear_rows(const double* P, const int64_t* tris, int64_t m, bool* out) {
    for (int64_t t = 0; t < m; ++t) {
        const int64_t* r = tris + 3 * t;
        out[t] = collinear(P, r[0], r[1], r[2]);
    }
}

namespace {

constexpr int64_t kNone = std::numeric_limits<int64_t>::max();

// The least (count, value) patch over allowed chords, chord by chord in length order:
// value(i, k, j, left, right) combines the halves' values with triangle (i, k, j)'s.
template <class Value>
int64_t fewest_then(const double* P, int64_t n, const bool* allowed, int32_t* K,
                    const Value& value) {
    constexpr double kInf = std::numeric_limits<double>::infinity();
    std::vector<int64_t> C(static_cast<size_t>(n * n), 0);  // sides: no triangle, count 0
    std::vector<double> A(static_cast<size_t>(n * n), 0.0);
    for (int64_t L = 2; L < n; ++L) {
        for (int64_t i = 0; i + L < n; ++i) {
            const int64_t j = i + L;
            int64_t best_c = kNone, best_k = -1;
            double best_a = kInf;
            if (allowed[i * n + j] || L == n - 1) {
                for (int64_t k = i + 1; k < j; ++k) {
                    const int64_t left = C[i * n + k], right = C[k * n + j];
                    if (left == kNone || right == kNone) continue;
                    const int64_t c = left + right + (collinear(P, i, k, j) ? 1 : 0);
                    if (c > best_c) continue;
                    const double a = value(i, k, j, A[i * n + k], A[k * n + j]);
                    if (c < best_c || a < best_a) {
                        best_c = c;
                        best_a = a;
                        best_k = k;
                    }
                }
            }
            C[i * n + j] = best_c;
            A[i * n + j] = best_a;
            K[i * n + j] = static_cast<int32_t>(best_k);
        }
    }
    const int64_t root = C[n - 1];
    return root == kNone ? -1 : root;
}

}  // namespace

int64_t fewest_degenerate(const double* P, const double* Q, int64_t n, const bool* allowed,
                          int32_t* K) {
    return fewest_then(P, n, allowed, K,
                       [Q](int64_t i, int64_t k, int64_t j, double left, double right) {
                           return (left + right) + unit_normal(Q, i, k, j).area;
                       });
}

int64_t fewest_then_weight(const double* P, int64_t n, int code, bool is_max,
                           const bool* allowed, int32_t* K) {
    const Points pts{P, n, 3};
    return fewest_then(P, n, allowed, K,
                       [&](int64_t i, int64_t k, int64_t j, double left, double right) {
                           const double w = triangle_weight(code, pts, i, k, j);
                           return is_max ? py_max(py_max(left, right), w) : left + right + w;
                       });
}

}  // namespace optri::holes
