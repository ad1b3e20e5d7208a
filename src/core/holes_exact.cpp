// The exact Liepa search over all triangulations of a 3-D polyline.
//
// Liepa's objective (largest dihedral angle, then total area) is not a sum of triangle
// weights: a dihedral needs both triangles of an edge. The state (i, j, m) -- sub-polygon
// i..j with the triangle (i, j, m) across its chord -- makes every dihedral known when its
// two triangles meet (Barequet, Dickerson, Eppstein 1996): O(n^3) states, O(n) apexes
// each. Two passes make the pair exact: bottleneck_lengths finds the least largest key M
// (monotone), area_lengths the least area among patches whose keys are all <= M.
//
// * States are stored compactly, one double per (chord, outer vertex) pair: slot
//   off[i, j] + m for m < i and off[i, j] + m - (j - i + 1) for m > j (the root
//   (0, n - 1) has one slot, its mesh side): about n^3 / 3 slots, and the second pass
//   reuses the first pass's array.
// * Pass 1 is bounded by U, the value of a known patch (Liepa's): a state worth more
//   than U can never be part of the optimum, so it is stored as +inf and apexes over it
//   are dropped. The remaining apexes of a chord are sorted by their sub-patch value,
//   and a state's scan stops at the first apex whose sub-patch is already no better than
//   the best found: its value is still the exact minimum.
// * Pass 2 only visits states whose pass-1 value is <= M (marked kPending), with the
//   apexes sorted by (area, apex): the first apex whose key is <= M is the answer, the
//   smallest apex among equal areas.
//
// The chords of one length depend only on shorter ones, so a length's chords could run on
// threads without changing a value; they run on one (a barrier per length costs more than
// it gains on a busy machine). Every key uses the evaluator's arithmetic, so the result is
// the exact optimum under its numbers.
#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

#include "holes.hpp"

namespace optri::holes {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Columns of apexes and outer triangles of one chord: rows 0-3 the apex triangles'
// (x, y, z, degenerate), row 4 their sub-patch worth or area, row 5 the apex; rows 6-9
// the outer triangles' (x, y, z, degenerate), one column per state.
struct Scratch {
    int64_t n;
    std::vector<double> buf;
    std::vector<int64_t> idx;
    std::vector<std::pair<double, int64_t>> order;
    std::vector<double> tmp;
    explicit Scratch(int64_t n_)
        : n(n_), buf(10 * n_), idx(n_), order(n_), tmp(n_) {}
    double* row(int r) { return buf.data() + r * n; }
};

inline int64_t slot(const int64_t* off, int64_t n, int64_t a, int64_t b, int64_t m) {
    return m < a ? off[a * n + b] + m : off[a * n + b] + m - (b - a + 1);
}

inline int64_t states_of(int64_t n, int64_t i, int64_t j) {
    return i == 0 && j == n - 1 ? 1 : n - (j - i + 1);
}

// unit normal of triangle {a, b, c} (a < b), vertices sorted as sorted_normal takes them,
// into column col of the 4 rows from out (row stride ld)
inline void normal_column(const double* Q, int64_t a, int64_t b, int64_t c, double* out,
                          int64_t ld, int64_t col) {
    const Normal u = c < a ? unit_normal(Q, c, a, b)
                     : c < b ? unit_normal(Q, a, c, b)
                             : unit_normal(Q, a, b, c);
    out[col] = u.x;
    out[ld + col] = u.y;
    out[2 * ld + col] = u.z;
    out[3 * ld + col] = u.d ? 1.0 : 0.0;
}

// normals of the triangles across chord (i, j), in slot order, into rows 6-9; returns
// the kind: 0 patch triangles, 1 the root's mesh triangle, 2 nothing (root only)
int outer_normals(const double* Q, int64_t n, int64_t i, int64_t j, const double* MN,
                  bool has_third, Scratch& s) {
    double* out = s.row(6);
    if (i == 0 && j == n - 1) {
        if (!has_third) return 2;
        for (int r = 0; r < 4; ++r) out[r * n] = MN[4 * (n - 1) + r];
        return 1;
    }
    for (int64_t m = 0; m < i; ++m) normal_column(Q, i, j, m, out, n, m);
    for (int64_t m = j + 1; m < n; ++m) normal_column(Q, i, j, m, out, n, m - (j - i + 1));
    return 0;
}

// key of apex triangle (ax, ay, az, ad) against the outer one: key_of / mesh_key
inline double outer_key(double ax, double ay, double az, bool ad, double ox, double oy,
                        double oz, bool od, int kind) {
    if (kind == 2) return 0.0;
    if (ad) return kDegenerateKey;
    if (od) return kind == 0 ? kDegenerateKey : 0.0;
    return clamp_key(ax, ay, az, ox, oy, oz);
}

// key of apex column t against outer column c
inline double column_key(Scratch& s, int64_t t, int64_t c, int kind) {
    const double* b = s.buf.data();
    const int64_t n = s.n;
    return outer_key(b[t], b[n + t], b[2 * n + t], b[3 * n + t] != 0.0, b[6 * n + c],
                     b[7 * n + c], b[8 * n + c], b[9 * n + c] != 0.0, kind);
}

// sort columns 0..cnt-1 of rows 0..rows-1 by row `by`, ties in column order (a stable sort)
void rank(Scratch& s, int64_t cnt, int rows, int by) {
    const double* key = s.row(by);
    for (int64_t t = 0; t < cnt; ++t) s.order[t] = {key[t], t};
    std::sort(s.order.begin(), s.order.begin() + cnt);
    for (int r = 0; r < rows; ++r) {
        double* x = s.row(r);
        for (int64_t t = 0; t < cnt; ++t) s.tmp[t] = x[s.order[t].second];
        std::copy(s.tmp.begin(), s.tmp.begin() + cnt, x);
    }
}

// apexes k of chord (i, j) whose halves are worth <= U, as columns (x, y, z, degenerate,
// worth) in k order, but with one of least worth first; returns their count
int64_t apexes_by_base(const double* Q, int64_t n, int64_t i, int64_t j, const double* leaf,
                       const int64_t* off, const double* B, double U, Scratch& s) {
    int64_t cnt = 0, at = 0;
    double low = kInf;
    double* worth = s.row(4);
    for (int64_t k = i + 1; k < j; ++k) {
        const double left = k - i == 1 ? leaf[i * n + j] : B[slot(off, n, i, k, j)];
        const double right = j - k == 1 ? leaf[k * n + i] : B[slot(off, n, k, j, i)];
        const double base = pmax(left, right);
        if (base <= U) {
            s.idx[cnt] = k;
            worth[cnt] = base;
            if (base < low) {
                low = base;
                at = cnt;
            }
            ++cnt;
        }
    }
    if (cnt == 0) return 0;
    std::swap(worth[0], worth[at]);
    std::swap(s.idx[0], s.idx[at]);
    for (int64_t t = 0; t < cnt; ++t) normal_column(Q, i, j, s.idx[t], s.buf.data(), n, t);
    return cnt;
}

// apexes k of chord (i, j) whose halves have patches with keys <= M, as columns (x, y,
// z, degenerate, area of the sub-patch, k) in k order; returns their count and sets `at`
// to the column of the least (area, k)
int64_t apexes_by_area(const double* Q, int64_t n, int64_t i, int64_t j, const double* leaf,
                       const int64_t* off, const double* A, double M, Scratch& s,
                       int64_t& at) {
    int64_t cnt = 0;
    double low = kInf;
    at = 0;
    double* area = s.row(4);
    double* apex = s.row(5);
    for (int64_t k = i + 1; k < j; ++k) {
        const double left = k - i == 1 ? (leaf[i * n + j] <= M ? 0.0 : kInf)
                                       : A[slot(off, n, i, k, j)];
        const double right = j - k == 1 ? (leaf[k * n + i] <= M ? 0.0 : kInf)
                                        : A[slot(off, n, k, j, i)];
        if (left == kInf || right == kInf) continue;
        s.idx[cnt] = k;
        const double sub = (left + right) + unit_normal(Q, i, k, j).area;
        area[cnt] = sub;
        apex[cnt] = static_cast<double>(k);
        if (sub < low) {
            low = sub;
            at = cnt;
        }
        ++cnt;
    }
    for (int64_t t = 0; t < cnt; ++t) normal_column(Q, i, j, s.idx[t], s.buf.data(), n, t);
    return cnt;
}

// the first apex in (area, k) order whose key against outer c is <= M
double least_area(Scratch& s, int64_t cnt, int64_t c, int kind, double M) {
    for (int64_t t = 0; t < cnt; ++t) {
        if (column_key(s, t, c, kind) <= M) return s.row(4)[t];
    }
    return kInf;
}

void bottleneck_chord(const double* Q, int64_t n, int64_t i, int64_t j, bool has_third,
                      const double* MN, const double* leaf, const bool* allowed,
                      const int64_t* off, double* B, double U, double cap, Scratch& s) {
    const int64_t first = off[i * n + j], count = states_of(n, i, j);
    int64_t cnt = 0;
    if (j - i == n - 1 || allowed[i * n + j]) cnt = apexes_by_base(Q, n, i, j, leaf, off, B, U, s);
    if (cnt == 0) {
        std::fill(B + first, B + first + count, kInf);
        return;
    }
    const int kind = outer_normals(Q, n, i, j, MN, has_third, s);
    const double* worth = s.row(4);
    const double low = worth[0];  // the least worth (first after sorting; kept there before)
    bool ranked = false;
    for (int64_t c = 0; c < count; ++c) {
        double key = column_key(s, 0, c, kind);
        if (key <= low) {  // no apex can beat the least worth
            B[first + c] = low;
            continue;
        }
        if (!ranked) {
            rank(s, cnt, 5, 4);
            ranked = true;
        }
        double best = pmin(cap, pmax(low, key));
        for (int64_t t = 1; t < cnt; ++t) {
            if (worth[t] >= best) break;  // sorted: no later apex can do better
            key = column_key(s, t, c, kind);
            const double v = pmax(worth[t], key);
            if (v < best) best = v;
        }
        B[first + c] = best <= U ? best : kInf;
    }
}

void area_chord(const double* Q, int64_t n, int64_t i, int64_t j, bool has_third,
                const double* MN, const double* leaf, const int64_t* off, double* A, double M,
                Scratch& s) {
    const int64_t first = off[i * n + j], count = states_of(n, i, j);
    bool pending = false;
    for (int64_t c = 0; c < count; ++c) pending = pending || A[first + c] == kPending;
    if (!pending) return;
    int64_t at;
    const int64_t cnt = apexes_by_area(Q, n, i, j, leaf, off, A, M, s, at);
    const int kind = outer_normals(Q, n, i, j, MN, has_third, s);
    bool ranked = false;
    for (int64_t c = 0; c < count; ++c) {
        if (A[first + c] != kPending) continue;
        if (cnt && column_key(s, at, c, kind) <= M) {  // the least area fits: done
            A[first + c] = s.row(4)[at];
            continue;
        }
        if (!ranked) {
            rank(s, cnt, 6, 4);  // ties in k order: the smaller apex first
            ranked = true;
            at = 0;
        }
        A[first + c] = least_area(s, cnt, c, kind, M);
    }
}

// the chords of lengths L0 <= L < L1, one length after the other
template <class Chord>
void by_length(int64_t n, int64_t L0, int64_t L1, const Chord& chord) {
    Scratch s(n);
    for (int64_t L = L0; L < L1; ++L) {
        for (int64_t i = 0; i < n - L; ++i) chord(i, i + L, s);
    }
}

}  // namespace

int64_t state_count(int64_t n) { return (n - 1) * (n - 2) * (n - 3) / 3 + 1; }

void state_offsets(int64_t n, int64_t* off) {
    std::fill(off, off + n * n, int64_t{-1});
    int64_t s = 0;
    for (int64_t i = 0; i < n; ++i) {
        for (int64_t j = i + 2; j < n; ++j) {
            if (i == 0 && j == n - 1) continue;
            off[i * n + j] = s;
            s += n - (j - i + 1);
        }
    }
    off[n - 1] = s;  // the root (0, n - 1)
}

void leaf_table(const double* Q, int64_t n, const double* MN, bool has_third, double* leaf) {
    std::fill(leaf, leaf + n * n, 0.0);
    if (!has_third) return;
    for (int64_t s = 0; s < n - 1; ++s) {
        for (int64_t m = 0; m < n; ++m) {
            if (m == s || m == s + 1) continue;
            const Normal u = sorted_normal(Q, s, s + 1, m);
            leaf[s * n + m] = mesh_key(MN, s, u.x, u.y, u.z, u.d, has_third);
        }
    }
}

void bottleneck_lengths(const double* Q, int64_t n, bool has_third, const double* MN,
                        const double* leaf, const bool* allowed, const int64_t* off,
                        double* B, double U, int64_t L0, int64_t L1) {
    const double cap = std::nextafter(U, kInf);  // a value <= U replaces it
    by_length(n, L0, L1, [&](int64_t i, int64_t j, Scratch& s) {
        bottleneck_chord(Q, n, i, j, has_third, MN, leaf, allowed, off, B, U, cap, s);
    });
}

void area_lengths(const double* Q, int64_t n, bool has_third, const double* MN,
                  const double* leaf, const int64_t* off, double* A, double M,
                  int64_t L0, int64_t L1) {
    by_length(n, L0, L1, [&](int64_t i, int64_t j, Scratch& s) {
        area_chord(Q, n, i, j, has_third, MN, leaf, off, A, M, s);
    });
}

void mark_pending(double* states, int64_t count, double M) {
    for (int64_t s = 0; s < count; ++s) states[s] = states[s] <= M ? kPending : kInf;
}

bool exact_trace(const double* Q, int64_t n, bool has_third, const double* MN,
                 const double* leaf, const int64_t* off, const double* A, double M,
                 int64_t* out) {
    Scratch s(n);
    std::vector<int64_t> stack(3 * n);
    stack[0] = 0;
    stack[1] = n - 1;
    stack[2] = n;
    int64_t top = 1, t = 0;
    while (top > 0) {
        --top;
        const int64_t i = stack[3 * top], j = stack[3 * top + 1], m = stack[3 * top + 2];
        int64_t at;
        const int64_t cnt = apexes_by_area(Q, n, i, j, leaf, off, A, M, s, at);
        const int kind = outer_normals(Q, n, i, j, MN, has_third, s);
        rank(s, cnt, 6, 4);
        const int64_t c = m == n ? 0 : (m < i ? m : m - (j - i + 1));
        int64_t k = -1;
        for (int64_t r = 0; r < cnt; ++r) {
            if (column_key(s, r, c, kind) <= M) {
                k = static_cast<int64_t>(s.row(5)[r]);
                break;
            }
        }
        if (k < 0 || t >= n - 2) return false;
        out[3 * t] = i;
        out[3 * t + 1] = k;
        out[3 * t + 2] = j;
        ++t;
        const int64_t next[2][3] = {{i, k, j}, {k, j, i}};
        for (const auto& p : next) {
            if (p[1] - p[0] > 1) {
                stack[3 * top] = p[0];
                stack[3 * top + 1] = p[1];
                stack[3 * top + 2] = p[2];
                ++top;
            }
        }
    }
    return t == n - 2;
}

}  // namespace optri::holes
