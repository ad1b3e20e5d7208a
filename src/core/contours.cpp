// Optimal tiling between two closed contours: Fuchs, Kedem and Uselton (1977).
//
// Contour a has m vertices, b has n. A tiling is a monotone lattice path on the torus
// Z_m x Z_n: node (i, j) is the span a_i - b_j; a step in i adds triangle
// (a_i, a_i+1, b_j) with weight wp[i][j], a step in j adds (a_i, b_j, b_j+1) with weight
// wq[i][j]. Every tiling holds a span from a_0, so the optimum is the best, over the n
// starts j0, of the shortest path from (0, j0) to (m, j0 + n) in the unrolled grid
// (rows 0..m, columns 0..2n).
//
// Sum objective: shortest paths of different starts can be chosen not to cross, so a
// start's path is searched only between the paths of two starts already solved
// (divide and conquer: O(m n log n)). Max objective: that exchange argument does not
// hold for bottleneck paths with ties, so every start is solved on the whole grid
// (O(m n^2)); the Python side passes the shorter contour as b.
// A given start (start >= 0) is one search on the whole grid.
//
// Every float operation (one addition or one max per candidate; ties to the first of
// g below, e below, g left, f left, then to the smaller start) is the Python reference's (optri.contours._reference),
// so both give identical bits.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/tuple.h>

#include "bind.hpp"

namespace nb = nanobind;

namespace optri {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct Path {
    std::vector<int> lo, hi;  // the columns the path occupies in each row, inclusive
    std::vector<std::uint8_t> steps;  // 0: a step in i, 1: a step in j, from the start
    double cost = kInf;
};

// A monotone path is a tiling unless it runs a whole row (a vertex of a fanned to all of
// b) or a whole column: such a path visits one torus node twice and gives a span four
// triangles. From start (0, j0) those are exactly the paths "up r, across n, up m - r"
// and "across c, up m, across n - c". They are excluded by following, beside the general
// layer g, the two forced path families that could become one:
//   e(i, j): up column j0 to row i, then along row i (must never reach column j0 + n);
//   f(i, j): along row 0 to column j, then up column j (must never reach row m).
// A step in i from e, or in j from f, leaves the family into g. e(i, j0) and f(0, j) hold
// the path's first run; the start is both.
class Tiler {
public:
    Tiler(const double* wp, const double* wq, int m, int n, bool is_max)
        : wp_(wp), wq_(wq), m_(m), n_(n), w_(2 * n + 1), is_max_(is_max),
          g_(static_cast<std::size_t>(m + 1) * (2 * n + 1), kInf),
          e_(g_.size(), kInf), f_(g_.size(), kInf), from_(g_.size(), 0) {}

    // The best tiling path from (0, j0) to (m, j0 + n) inside columns [lo[i], hi[i]] of row i.
    Path solve(int j0, const std::vector<int>& lo, const std::vector<int>& hi) {
        const int m = m_, n = n_;
        std::vector<int> cl(m + 1), ch(m + 1);
        for (int i = 0; i <= m; ++i) {
            cl[i] = std::max(lo[i], j0);
            ch[i] = std::min(hi[i], j0 + n);
        }
        for (int i = 0; i <= m; ++i) {
            for (int j = cl[i]; j <= ch[i]; ++j) {
                const std::size_t c = cell(i, j);
                const bool below = i > 0 && j >= cl[i - 1] && j <= ch[i - 1];
                const bool left = j > cl[i];
                double ev = kInf, fv = kInf, gv = kInf;
                std::uint8_t step = 0;
                if (i == 0 && j == j0) {
                    ev = fv = is_max_ ? -kInf : 0.0;
                } else {
                    const double up = below ? wp_[idx(i - 1, j)] : 0.0;
                    const double side = left ? wq_[idx(i, j - 1)] : 0.0;
                    if (j == j0 && i < m && below) ev = combine(e_[cell(i - 1, j)], up);
                    if (j > j0 && j < j0 + n && i < m && left) ev = combine(e_[c - 1], side);
                    if (i == 0 && j < j0 + n && left) fv = combine(f_[c - 1], side);
                    if (i > 0 && i < m && j > j0 && below) fv = combine(f_[cell(i - 1, j)], up);
                    if (i > 0 && j > j0) {
                        double cand[4] = {kInf, kInf, kInf, kInf};
                        if (below) {
                            cand[0] = combine(g_[cell(i - 1, j)], up);
                            if (i - 1 > 0) cand[1] = combine(e_[cell(i - 1, j)], up);
                        }
                        if (left) {
                            cand[2] = combine(g_[c - 1], side);
                            if (j - 1 > j0) cand[3] = combine(f_[c - 1], side);
                        }
                        gv = cand[0];
                        for (std::uint8_t k = 1; k < 4; ++k) {
                            if (cand[k] < gv) {
                                gv = cand[k];
                                step = k;
                            }
                        }
                    }
                }
                g_[c] = gv;
                e_[c] = ev;
                f_[c] = fv;
                from_[c] = step;
            }
        }
        return trace(j0);
    }

private:
    // The path back from (m, j0 + n) in layer g; steps and each row's columns.
    Path trace(int j0) const {
        const int m = m_, n = n_;
        Path p;
        p.cost = g_[cell(m, j0 + n)];
        p.lo.assign(m + 1, 0);
        p.hi.assign(m + 1, 0);
        if (!(p.cost < kInf)) {  // no tiling (n or m is 1, or infinite weights): no path
            p.hi.assign(m + 1, 2 * n);
            return p;
        }
        p.steps.assign(static_cast<std::size_t>(m + n), 0);
        int i = m, j = j0 + n, layer = 0;  // 0: g, 1: e, 2: f
        p.lo[i] = p.hi[i] = j;
        for (int s = m + n - 1; s >= 0; --s) {
            std::uint8_t step;  // 0: a step in i, 1: a step in j
            if (layer == 0) {
                const std::uint8_t k = from_[cell(i, j)];
                step = k < 2 ? 0 : 1;
                layer = k == 1 ? 1 : k == 3 ? 2 : 0;
            } else if (layer == 1) {
                step = j > j0 ? 1 : 0;
            } else {
                step = i > 0 ? 0 : 1;
            }
            p.steps[s] = step;
            if (step == 0) {
                --i;
                p.lo[i] = p.hi[i] = j;
            } else {
                --j;
                p.lo[i] = j;
            }
        }
        return p;
    }

    double combine(double d, double w) const { return is_max_ ? (w > d ? w : d) : d + w; }
    std::size_t cell(int i, int j) const { return static_cast<std::size_t>(i) * w_ + j; }
    std::size_t idx(int i, int j) const {
        return static_cast<std::size_t>(i % m_) * n_ + static_cast<std::size_t>(j % n_);
    }

    const double* wp_;
    const double* wq_;
    int m_, n_, w_;
    bool is_max_;
    std::vector<double> g_, e_, f_;
    std::vector<std::uint8_t> from_;
};

struct Best {
    double cost = kInf;
    int start = -1;
    std::vector<std::uint8_t> steps;

    void offer(int j0, Path& p) {
        if (!(p.cost < kInf)) return;  // no tiling from this start
        if (start < 0 || p.cost < cost || (p.cost == cost && j0 < start)) {
            cost = p.cost;
            start = j0;
            steps = p.steps;
        }
    }
};

Path shifted(const Path& p, int by) {
    Path q = p;
    for (auto& v : q.lo) v += by;
    for (auto& v : q.hi) v += by;
    return q;
}

// Starts strictly between jl and jh, their paths bounded by pl (left) and ph (right).
void divide(Tiler& t, int jl, const Path& pl, int jh, const Path& ph, Best& best) {
    if (jh - jl < 2) return;
    const int mid = jl + (jh - jl) / 2;
    Path pm = t.solve(mid, pl.lo, ph.hi);
    best.offer(mid, pm);
    pm.steps.clear();
    pm.steps.shrink_to_fit();
    divide(t, jl, pl, mid, pm, best);
    divide(t, mid, pm, jh, ph, best);
}

// start >= 0 fixes the first span at (a_0, b_start); else every start is searched.
Best tile(const double* wp, const double* wq, int m, int n, bool is_max, int start) {
    Tiler t(wp, wq, m, n, is_max);
    std::vector<int> lo(m + 1, 0), hi(m + 1, 2 * n);
    Best best;
    if (start >= 0) {
        Path p = t.solve(start, lo, hi);
        best.offer(start, p);
        return best;
    }
    if (is_max) {
        for (int j0 = 0; j0 < n; ++j0) {
            Path p = t.solve(j0, lo, hi);
            best.offer(j0, p);
        }
        return best;
    }
    Path p0 = t.solve(0, lo, hi);
    best.offer(0, p0);
    const Path pn = shifted(p0, n);
    divide(t, 0, p0, n, pn, best);
    return best;
}

using Table = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

}  // namespace

void bind_contours(nb::module_& m) {
    nb::module_ sub = m.def_submodule(
        "contours", "Optimal tiling between two closed contours (Fuchs-Kedem-Uselton).");
    sub.def(
        "tile",
        [](Table wp, Table wq, bool is_max, int start) {
            const int m = static_cast<int>(wp.shape(0));
            const int n = static_cast<int>(wp.shape(1));
            if (wq.shape(0) != wp.shape(0) || wq.shape(1) != wp.shape(1) || m < 1 || n < 1 || start >= n) {
                throw nb::value_error("wp and wq must be two (m, n) tables, m, n >= 1, start < n");
            }
            Best best;
            {
                nb::gil_scoped_release release;
                best = tile(wp.data(), wq.data(), m, n, is_max, start);
            }
            nb::bytes steps(reinterpret_cast<const char*>(best.steps.data()), best.steps.size());
            return nb::make_tuple(best.cost, best.start, steps);
        },
        nb::arg("wp"), nb::arg("wq"), nb::arg("is_max"), nb::arg("start") = -1,
        "(cost, start j0, steps as bytes: 0 a step along a, 1 along b) of the best tiling; "
        "(inf, -1, b'') when no tiling has a finite cost.");
}

}  // namespace optri
