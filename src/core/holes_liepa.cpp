// Liepa's O(n^3) recurrence: over all apexes (dense) or candidate lists (sparse).
//
// Both minimize (max dihedral key, area) lexicographically per chord, measuring the
// dihedral across chord (i, k) against the *optimal* top triangle of sub-polygon (i, k)
// only: a heuristic for the max-dihedral objective (the exact search is holes_exact.cpp).
// A chord that `allowed` forbids (an edge the mesh already has) is never used. The
// kernels fill arrays the caller allocated, so the caller can run the dense recurrence a
// range of rows per call and let a Ctrl-C surface between calls.
#include <algorithm>
#include <limits>
#include <vector>

#include "holes.hpp"

namespace optri::holes {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// T[r, f, c] of the dense (n, 5, n) table
inline double* cell(double* T, int64_t n, int64_t r, int64_t f) { return T + (r * 5 + f) * n; }

// chord (i, j) admits no patch (forbidden, or every split is): +inf for its parents
void store_none(double* T, int32_t* K, int64_t n, int64_t i, int64_t j) {
    K[i * n + j] = -1;
    const int64_t rc[2][2] = {{i, j}, {j, i}};
    for (const auto& p : rc) {
        cell(T, n, p[0], 0)[p[1]] = kInf;
        cell(T, n, p[0], 1)[p[1]] = kInf;
        cell(T, n, p[0], 2)[p[1]] = 0.0;
        cell(T, n, p[0], 3)[p[1]] = 0.0;
        cell(T, n, p[0], 4)[p[1]] = 0.0;
    }
}

// apex k = i + 1 or j - 1 puts a polygon side in the triangle: its key is against the
// mesh (or nothing), not a sub-polygon's top; the root also meets the mesh across side
// (n - 1, 0). C0 is indexed by t = k - i - 1.
void fix_ends(const double* Q, int64_t n, int64_t i, int64_t j, bool has_third,
              const double* MN, double* T, double* C0) {
    const int64_t ends[2] = {i + 1, j - 1};
    const int count = j - i > 2 ? 2 : 1;
    for (int e = 0; e < count; ++e) {
        const int64_t k = ends[e];
        const Normal u = unit_normal(Q, i, k, j);
        double c1;
        if (k - i == 1) {
            c1 = mesh_key(MN, i, u.x, u.y, u.z, u.d, has_third);
        } else {
            c1 = pmax(cell(T, n, i, 0)[k],
                      key_of(u.x, u.y, u.z, u.d, cell(T, n, i, 2)[k], cell(T, n, i, 3)[k],
                             cell(T, n, i, 4)[k], false));
        }
        if (j - k == 1) {
            c1 = pmax(c1, mesh_key(MN, k, u.x, u.y, u.z, u.d, has_third));
        } else {
            c1 = pmax(pmax(c1, cell(T, n, j, 0)[k]),
                      key_of(u.x, u.y, u.z, u.d, cell(T, n, j, 2)[k], cell(T, n, j, 3)[k],
                             cell(T, n, j, 4)[k], false));
        }
        C0[k - i - 1] = c1;
    }
    if (i == 0 && j == n - 1 && has_third) {
        for (int64_t k = i + 1; k < j; ++k) {
            const Normal u = unit_normal(Q, i, k, j);
            C0[k - 1] = pmax(C0[k - 1], mesh_key(MN, n - 1, u.x, u.y, u.z, u.d, has_third));
        }
    }
}

// index of chord key (i * n + j) in the sorted keys, -1 if absent
inline int64_t chord_id(const int64_t* keys, int64_t chords, int64_t key) {
    const int64_t* p = std::lower_bound(keys, keys + chords, key);
    return (p < keys + chords && *p == key) ? p - keys : -1;
}

}  // namespace

void dense_rows(const double* Q, int64_t n, bool has_third, const double* MN,
                const bool* allowed, double* T, int32_t* K, int64_t i_hi, int64_t i_lo) {
    std::vector<double> X(n), Y(n), Z(n), C0(n), C1(n);
    for (int64_t v = 0; v < n; ++v) {
        X[v] = Q[3 * v];
        Y[v] = Q[3 * v + 1];
        Z[v] = Q[3 * v + 2];
    }
    for (int64_t i = i_hi; i >= i_lo; --i) {
        for (int64_t j = i + 2; j < n; ++j) {
            if (!allowed[i * n + j] && !(i == 0 && j == n - 1)) {
                store_none(T, K, n, i, j);
                continue;
            }
            const int64_t m = j - i - 1;
            const double vx = X[j] - X[i], vy = Y[j] - Y[i], vz = Z[j] - Z[i];
            const double vv = vx * vx + vy * vy + vz * vz;
            const double xi = X[i], yi = Y[i], zi = Z[i];
            const double *Xs = X.data() + i + 1, *Ys = Y.data() + i + 1, *Zs = Z.data() + i + 1;
            const int64_t o = i + 1;
            const double *Ti0 = cell(T, n, i, 0) + o, *Ti1 = cell(T, n, i, 1) + o;
            const double *Ti2 = cell(T, n, i, 2) + o, *Ti3 = cell(T, n, i, 3) + o;
            const double *Ti4 = cell(T, n, i, 4) + o;
            const double *Tj0 = cell(T, n, j, 0) + o, *Tj1 = cell(T, n, j, 1) + o;
            const double *Tj2 = cell(T, n, j, 2) + o, *Tj3 = cell(T, n, j, 3) + o;
            const double *Tj4 = cell(T, n, j, 4) + o;
            double* c0 = C0.data();
            double* c1 = C1.data();
            for (int64_t t = 0; t < m; ++t) {
                const double ux = Xs[t] - xi, uy = Ys[t] - yi, uz = Zs[t] - zi;
                const double nx = uy * vz - uz * vy;
                const double ny = uz * vx - ux * vz;
                const double nz = ux * vy - uy * vx;
                const double n2 = nx * nx + ny * ny + nz * nz;
                const double nn = std::sqrt(n2);
                const double uu = ux * ux + uy * uy + uz * uz;
                const bool deg = n2 <= kDegenerateSine2 * (uu * vv);
                const double inv = deg ? 0.0 : 1.0 / nn;  // a zero normal, never NaN
                const double ax = nx * inv, ay = ny * inv, az = nz * inv;
                double kl = 1.0 - (ax * Ti2[t] + ay * Ti3[t] + az * Ti4[t]);
                double kr = 1.0 - (ax * Tj2[t] + ay * Tj3[t] + az * Tj4[t]);
                kl = pmin(pmax(kl, 0.0), kFoldKey);
                kr = pmin(pmax(kr, 0.0), kFoldKey);
                kl = deg ? kDegenerateKey : kl;
                kr = deg ? kDegenerateKey : kr;
                c0[t] = pmax(pmax(Ti0[t], Tj0[t]), pmax(kl, kr));
                c1[t] = Ti1[t] + Tj1[t] + 0.5 * nn;
            }
            fix_ends(Q, n, i, j, has_third, MN, T, c0);
            double best1 = kInf, best2 = kInf;
            int64_t bt = 0;
            for (int64_t t = 0; t < m; ++t) {
                const double v1 = c0[t];
                if (v1 < best1 || (v1 == best1 && c1[t] < best2)) {
                    best1 = v1;
                    best2 = c1[t];
                    bt = t;
                }
            }
            if (best1 == kInf) {
                store_none(T, K, n, i, j);
                continue;
            }
            K[i * n + j] = static_cast<int32_t>(i + 1 + bt);
            const Normal top = unit_normal(Q, i, i + 1 + bt, j);
            const int64_t rc[2][2] = {{i, j}, {j, i}};
            for (const auto& p : rc) {
                // a degenerate top folds against anything above it: its parents' key is
                // then the worst, kDegenerateKey, whatever their normal
                cell(T, n, p[0], 0)[p[1]] = top.d ? kDegenerateKey : best1;
                cell(T, n, p[0], 1)[p[1]] = best2;
                cell(T, n, p[0], 2)[p[1]] = top.x;
                cell(T, n, p[0], 3)[p[1]] = top.y;
                cell(T, n, p[0], 4)[p[1]] = top.z;
            }
        }
    }
}

// keys (sorted): chords i * n + j with candidate apexes apex[ptr[c]:ptr[c + 1]]
// (increasing); order: chord ids by increasing j - i. Fills V[c] = (key, area) (+inf:
// no patch), TN[c] = the top triangle's (x, y, z, degenerate) and K[c] its apex.
void sparse_chords(const double* Q, int64_t n, bool has_third, const double* MN,
                   const int64_t* keys, int64_t chords, const int64_t* order,
                   const int64_t* ptr, const int64_t* apex, double* V, double* TN, int64_t* K) {
    for (int64_t p = 0; p < chords; ++p) {
        const int64_t c = order[p];
        const int64_t i = keys[c] / n, j = keys[c] % n;
        const bool root = i == 0 && j == n - 1;
        double best1 = kInf, best2 = kInf;
        int64_t bestk = -1;
        double bx = 0.0, by = 0.0, bz = 0.0;
        bool bd = false;
        for (int64_t t = ptr[c]; t < ptr[c + 1]; ++t) {
            const int64_t k = apex[t];
            const int64_t cl = k - i == 1 ? -1 : chord_id(keys, chords, i * n + k);
            const int64_t cr = j - k == 1 ? -1 : chord_id(keys, chords, k * n + j);
            if ((k - i > 1 && (cl < 0 || V[2 * cl] == kInf)) ||
                (j - k > 1 && (cr < 0 || V[2 * cr] == kInf))) {
                continue;
            }
            const Normal u = unit_normal(Q, i, k, j);
            double c1, c2;
            if (cl < 0) {
                c1 = mesh_key(MN, i, u.x, u.y, u.z, u.d, has_third);
                c2 = u.area;
            } else {
                const double* tn = TN + 4 * cl;
                c1 = pmax(V[2 * cl], key_of(u.x, u.y, u.z, u.d, tn[0], tn[1], tn[2], tn[3] != 0));
                c2 = V[2 * cl + 1] + u.area;
            }
            if (cr < 0) {
                c1 = pmax(c1, mesh_key(MN, k, u.x, u.y, u.z, u.d, has_third));
            } else {
                const double* tn = TN + 4 * cr;
                c1 = pmax(pmax(c1, V[2 * cr]),
                          key_of(u.x, u.y, u.z, u.d, tn[0], tn[1], tn[2], tn[3] != 0));
                c2 = c2 + V[2 * cr + 1];
            }
            if (root) c1 = pmax(c1, mesh_key(MN, n - 1, u.x, u.y, u.z, u.d, has_third));
            if (c1 < best1 || (c1 == best1 && c2 < best2)) {
                best1 = c1;
                best2 = c2;
                bestk = k;
                bx = u.x;
                by = u.y;
                bz = u.z;
                bd = u.d;
            }
        }
        V[2 * c] = best1;
        V[2 * c + 1] = best2;
        K[c] = bestk;
        TN[4 * c] = bx;
        TN[4 * c + 1] = by;
        TN[4 * c + 2] = bz;
        TN[4 * c + 3] = bd ? 1.0 : 0.0;
    }
}

bool sparse_trace(int64_t n, const int64_t* keys, int64_t chords, const int64_t* K,
                  int64_t* out) {
    std::vector<int64_t> stack(2 * n);
    stack[0] = 0;
    stack[1] = n - 1;
    int64_t top = 1, t = 0;
    while (top > 0) {
        --top;
        const int64_t i = stack[2 * top], j = stack[2 * top + 1];
        const int64_t c = chord_id(keys, chords, i * n + j);
        if (c < 0 || K[c] < 0 || t >= n - 2) return false;
        const int64_t k = K[c];
        out[3 * t] = i;
        out[3 * t + 1] = k;
        out[3 * t + 2] = j;
        ++t;
        if (k - i > 1) {
            stack[2 * top] = i;
            stack[2 * top + 1] = k;
            ++top;
        }
        if (j - k > 1) {
            stack[2 * top] = k;
            stack[2 * top + 1] = j;
            ++top;
        }
    }
    return t == n - 2;
}

}  // namespace optri::holes
