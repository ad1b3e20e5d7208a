// optri._core.many: many small polygons in one call: checks, chord mask and DP, parallel
// over polygons.
//
// Polygons arrive as ragged arrays: all vertices concatenated in xy ((m, 2) float64, as
// given: a closing vertex may still be there) and, per polygon, its first row and row
// count. Each polygon goes through, on one thread:
//
// 1. the checks of optri.polygon.normalize_vertices and as_polygon (finite, closing
//    vertices dropped, at least 3 vertices, all distinct, orientation from the exact turn
//    at the lowest vertex, strict convexity) and, unless convex, the exact simplicity test
//    of find_self_intersection, with the exact predicates (predicates.hpp);
// 2. the valid-diagonal mask (mask.hpp: ear clipping and the visibility walk) in internal
//    (counter-clockwise) order;
// 3. the recurrence by the engines' own fills: MODE_PYTHON (the Python engines' values,
//    cost(i, k) + cost(k, j) + w(i, k, j), ties to the smallest k) is the generic fill and
//    trace (generic.hpp), or for a sum of an edge-decomposable weight the same recurrence
//    with each edge's weight computed once and read inline (edge_fill); MODE_FAST is the
//    compiled engine: the min-plus E-table (minplus.hpp) for a sum of an edge-decomposable
//    weight, else the generic fill.
//
// A polygon that fails a check, or whose DP ends in NaN, an infinite cost or an
// inconsistent walk, gets a non-zero status and no result: the caller solves it with
// optri.triangulate, which raises the exact error (or warning). The output is columnar
// (one array per field, triangles of all polygons in one array), built without Python
// objects per polygon.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <tuple>
#include <vector>

#include "bind.hpp"
#include "generic.hpp"
#include "mask.hpp"
#include "minplus.hpp"
#include "predicates.hpp"
#include "weights.hpp"

namespace nb = nanobind;

namespace optri {
namespace many {

namespace {

using std::int64_t;
using simple::wrap;

// How a polygon of n vertices is solved: modes[n] (batch/compiled.py's mode_of).
enum Mode : int64_t { MODE_NONE = 0, MODE_PYTHON = 1, MODE_FAST = 2 };
// Statuses: 0 solved, any other declined (batch/compiled.py's STATUS names them).
enum Status : int8_t {
    OK = 0, NONFINITE, FEW, REPEAT, FLAT, NOT_SIMPLE, SIZE, MASK, DP, ZERO,
};

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

struct Settings {
    const int64_t* modes;
    int64_t nmodes;
    int code;
    bool is_max;
    bool edge;  // a sum of an edge-decomposable weight: MODE_FAST takes the min-plus fill
};

// One thread's buffers, reused from polygon to polygon.
struct Scratch {
    std::vector<double> x, y, pts, table, edges;
    std::vector<int64_t> order, tris;
    std::vector<int32_t> splits;
    std::vector<uint8_t> mask;
};

// The best split of chord (i, j) for a sum of edge weights, from the symmetric n x n cost
// table T and edge table E: generic::best_split's rules and arithmetic with the triangle
// weight (e(i, k) + e(k, j)) + e(i, j) (triangle_weight's sum of the same edge weights,
// each computed once per polygon) read inline from rows i and j of E. A half of cost +inf
// is skipped; a NaN weight of a split not skipped sets nan; ties go to the smallest k.
inline void edge_split(const double* T, const double* E, int64_t n, int64_t i, int64_t j,
                       double& best, int64_t& arg, bool& nan) {
    const double* ti = T + i * n;
    const double* tj = T + j * n;
    const double* ei = E + i * n;
    const double* ej = E + j * n;  // e(k, j) = e(j, k): the table is symmetric
    const double eij = ei[j];
    double b = kInf;
    int64_t at = -1;
    bool bad = false;
    for (int64_t k = i + 1; k < j; ++k) {
        const double x = ti[k], y = tj[k];
        const bool skip = x == kInf || y == kInf;
        const double w = (ei[k] + ej[k]) + eij;
        const double v = x + y + w;
        bad = bad || (!skip && w != w);
        if (!skip && v < b) b = v, at = k;
    }
    best = b, arg = at, nan = nan || bad;
}

// The Python engines' recurrence for a sum of edge weights (generic::fill and trace with
// the same values and ties), each split's k kept from the fill for the walk. False when a
// weight was NaN (the generic fill flags it and the polygon is declined alike).
bool edge_fill(const Points& pts, int code, const uint8_t* mask, int64_t n, Scratch& sc,
               double& cost) {
    double* T = sc.table.data();
    sc.edges.resize(static_cast<size_t>(n * n));
    sc.splits.resize(static_cast<size_t>(n * n));
    double* E = sc.edges.data();
    int32_t* K = sc.splits.data();
    for (int64_t a = 0; a < n; ++a) {
        for (int64_t b = a + 1; b < n; ++b) {
            const bool chord = mask == nullptr || mask[a * n + b];
            const double e = chord ? edge_weight(code, pts, a, b) : 0.0;
            E[a * n + b] = E[b * n + a] = e;  // unused when no chord
        }
    }
    for (int64_t i = 0; i + 1 < n; ++i) T[i * n + i + 1] = T[(i + 1) * n + i] = 0.0;
    bool nan = false;
    for (int64_t i = n - 1; i >= 0; --i) {
        for (int64_t j = i + 2; j < n; ++j) {
            double c = kInf;
            int64_t k = -1;
            if (mask == nullptr || mask[i * n + j]) edge_split(T, E, n, i, j, c, k, nan);
            T[i * n + j] = T[j * n + i] = c;
            K[i * n + j] = static_cast<int32_t>(k);
        }
    }
    cost = T[n - 1];
    return !nan;
}

// normalize_vertices' checks on rows s .. s + count - 1: the status, n without closing rows.
Status normalized(const double* xy, int64_t s, int64_t count, int64_t& n) {
    n = count;
    for (int64_t v = s; v < s + count; ++v) {
        if (!(std::isfinite(xy[2 * v]) && std::isfinite(xy[2 * v + 1]))) return NONFINITE;
    }
    while (n > 3 && xy[2 * s] == xy[2 * (s + n - 1)] &&
           xy[2 * s + 1] == xy[2 * (s + n - 1) + 1]) {
        --n;  // closing vertices
    }
    if (n < 3) return FEW;
    for (int64_t a = s; a < s + n; ++a) {
        for (int64_t b = a + 1; b < s + n; ++b) {
            if (xy[2 * a] == xy[2 * b] && xy[2 * a + 1] == xy[2 * b + 1]) return REPEAT;
        }
    }
    return OK;
}

// Index of the lowest vertex, the leftmost among equals (as np.lexsort).
int64_t lowest(const double* xy, int64_t s, int64_t n) {
    int64_t low = 0;
    for (int64_t v = 1; v < n; ++v) {
        const double* p = xy + 2 * (s + v);
        const double* q = xy + 2 * (s + low);
        if (p[1] < q[1] || (p[1] == q[1] && p[0] < q[0])) low = v;
    }
    return low;
}

// as_polygon's convexity of CCW x, y: every turn strictly left, winding once.
bool strictly_convex(const double* x, const double* y, int64_t n) {
    int64_t winds = 0;
    for (int64_t v = 0; v < n; ++v) {
        const int64_t p = wrap(v - 1, n), q = wrap(v + 1, n);
        if (simple::orient_at(x, y, p, v, q) <= 0) return false;
        const int64_t w = wrap(q + 1, n);
        const bool up_v = y[q] > y[v] || (y[q] == y[v] && x[q] > x[v]);
        const bool up_q = y[w] > y[q] || (y[w] == y[q] && x[w] > x[q]);
        if (!up_v && up_q) ++winds;
    }
    return winds == 1;
}

// predicates.on_open_segment for one point: in the closed box, not an endpoint.
bool on_open_segment(double ax, double ay, double bx, double by, double cx, double cy) {
    const bool inside = std::min(ax, bx) <= cx && cx <= std::max(ax, bx) &&
                        std::min(ay, by) <= cy && cy <= std::max(ay, by);
    return inside && !(cx == ax && cy == ay) && !(cx == bx && cy == by);
}

// predicates.segment_pair_fault for edges e -> e+1 and f -> f+1: they cross or touch.
bool pair_fault(const double* x, const double* y, int64_t n, int64_t e, int64_t f) {
    const int64_t e1 = wrap(e + 1, n), f1 = wrap(f + 1, n);
    const double ax = x[e], ay = y[e], bx = x[e1], by = y[e1];
    const double cx = x[f], cy = y[f], dx = x[f1], dy = y[f1];
    if (std::min(ax, bx) > std::max(cx, dx) || std::min(cx, dx) > std::max(ax, bx)) {
        return false;  // bounding boxes apart
    }
    if (std::min(ay, by) > std::max(cy, dy) || std::min(cy, dy) > std::max(ay, by)) {
        return false;
    }
    const int o1 = orient_sign(ax, ay, bx, by, cx, cy);
    const int o2 = orient_sign(ax, ay, bx, by, dx, dy);
    const int o3 = orient_sign(cx, cy, dx, dy, ax, ay);
    const int o4 = orient_sign(cx, cy, dx, dy, bx, by);
    if (o1 * o2 < 0 && o3 * o4 < 0) return true;
    return (o1 == 0 && on_open_segment(ax, ay, bx, by, cx, cy)) ||
           (o2 == 0 && on_open_segment(ax, ay, bx, by, dx, dy)) ||
           (o3 == 0 && on_open_segment(cx, cy, dx, dy, ax, ay)) ||
           (o4 == 0 && on_open_segment(cx, cy, dx, dy, bx, by));
}

// No two edges cross, touch or fold back (find_self_intersection finds nothing).
bool is_simple(const double* x, const double* y, int64_t n) {
    for (int64_t e = 0; e < n; ++e) {
        for (int64_t f = e + 1; f < n; ++f) {
            if (pair_fault(x, y, n, e, f)) return false;
        }
    }
    return true;
}

// The optimum of the CCW polygon in sc.pts by the recurrence: false when it has no
// finite optimum or its walk is inconsistent. Triangles into sc.tris.
bool optimum(const Settings& st, bool minplus, const uint8_t* mask, int64_t n, Scratch& sc,
             double& cost) {
    sc.table.resize(static_cast<size_t>(n * n));
    sc.tris.resize(static_cast<size_t>(3 * (n - 2)));
    double* T = sc.table.data();
    const Points pts{sc.pts.data(), n, 2};
    bool ok;
    if (minplus) {
        minplus::fill_serial<double>(T, n, pts, st.code, mask);
        cost = T[n - 1] - edge_weight(st.code, pts, 0, n - 1);
        int64_t bad[2];
        const int64_t m = generic::walk(
            n, [&](int64_t i, int64_t j) { return minplus::split<double>(T, n, i, j, false); },
            sc.tris.data(), bad);
        ok = bad[0] < 0 && m == n - 2;
    } else if (st.edge) {  // a sum of edge weights: each edge's weight taken once
        ok = edge_fill(pts, st.code, mask, n, sc, cost);
        const int32_t* K = sc.splits.data();
        int64_t bad[2];
        const int64_t m = generic::walk(
            n, [&](int64_t i, int64_t j) { return static_cast<int64_t>(K[i * n + j]); },
            sc.tris.data(), bad);
        ok = ok && bad[0] < 0 && m == n - 2;
    } else {
        generic::Problem pr;
        pr.pts = pts;
        pr.code[0] = pr.code[1] = st.code;
        pr.code[2] = generic::NO_GATE;
        pr.is_max[0] = pr.is_max[1] = st.is_max;
        pr.mask = mask;
        const generic::Tables<double> tb{T, nullptr, n};
        generic::Flags flags;
        generic::set_sides(tb, pr);
        generic::fill(tb, pr, flags);
        cost = T[n - 1];
        int64_t bad[2];
        const int64_t m = generic::trace(tb, pr, flags, sc.tris.data(), bad);
        ok = bad[0] < 0 && flags.nan == 0 && flags.error == 0 && m == n - 2;
    }
    return ok && (cost == -kInf || std::isfinite(cost));
}

// One polygon: its status, n, orientation and cost; its triangles (input indices) into
// tris_out.
Status solve_one(const Settings& st, const double* xy, int64_t s, int64_t count,
                 int64_t* tris_out, Scratch& sc, int64_t& n, bool& cw, double& cost) {
    cw = false;
    cost = kNaN;
    Status status = normalized(xy, s, count, n);
    if (status != OK) return status;
    if (n >= st.nmodes || st.modes[n] == MODE_NONE) return SIZE;
    const int64_t low = lowest(xy, s, n);
    const double* p = xy + 2 * (s + wrap(low - 1, n));
    const double* v = xy + 2 * (s + low);
    const double* q = xy + 2 * (s + wrap(low + 1, n));
    const int turn = orient_sign(p[0], p[1], v[0], v[1], q[0], q[1]);
    if (turn == 0) return FLAT;
    cw = turn < 0;
    sc.x.resize(static_cast<size_t>(n));
    sc.y.resize(static_cast<size_t>(n));
    sc.pts.resize(static_cast<size_t>(2 * n));
    sc.order.resize(static_cast<size_t>(n));
    double* x = sc.x.data();
    double* y = sc.y.data();
    for (int64_t u = 0; u < n; ++u) {
        const int64_t o = cw ? wrap(n - u, n) : u;  // internal (CCW) -> input index
        sc.order[u] = o;
        x[u] = sc.pts[2 * u] = xy[2 * (s + o)];
        y[u] = sc.pts[2 * u + 1] = xy[2 * (s + o) + 1];
    }
    const uint8_t* mask = nullptr;
    if (!strictly_convex(x, y, n)) {
        if (!is_simple(x, y, n)) return NOT_SIMPLE;
        sc.mask.assign(static_cast<size_t>(n * n), 0);
        if (!simple::chord_mask(x, y, n, sc.mask.data())) return MASK;
        mask = sc.mask.data();
    }
    const bool minplus = st.modes[n] == MODE_FAST && st.edge;
    if (!optimum(st, minplus, mask, n, sc, cost)) {
        cost = kNaN;
        return DP;
    }
    const int64_t* tris = sc.tris.data();
    for (int64_t t = 0; t < n - 2; ++t) {
        const int64_t a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2];
        if (simple::orient_at(x, y, a, b, c) == 0) {
            cost = kNaN;
            return ZERO;
        }
        for (int m = 0; m < 3; ++m) tris_out[3 * t + m] = sc.order[tris[3 * t + m]];
    }
    return OK;
}

template <class T>
using Out1 = nb::ndarray<nb::numpy, T, nb::ndim<1>>;
using Out2 = nb::ndarray<nb::numpy, int64_t, nb::ndim<2>>;

template <class T>
T* alloc(size_t count, nb::capsule& owner) {
    T* data = new T[std::max<size_t>(count, 1)]();
    owner = nb::capsule(data, [](void* d) noexcept { delete[] static_cast<T*>(d); });
    return data;
}

using Xy = nb::ndarray<const double, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
using Ints = nb::ndarray<const int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

std::tuple<Out1<int8_t>, Out1<int64_t>, Out1<bool>, Out1<double>, Out2, Out1<int64_t>> solve(
    Xy xy, Ints starts, Ints counts, Ints modes, int code, bool is_max, bool edge,
    int threads) {
    const int64_t m = static_cast<int64_t>(starts.shape(0));
    if (static_cast<int64_t>(counts.shape(0)) != m) {
        throw nb::value_error("starts and counts differ in length");
    }
    const int64_t rows = static_cast<int64_t>(xy.shape(0));
    const int64_t* st0 = starts.data();
    const int64_t* ct0 = counts.data();
    nb::capsule o_first;
    auto* first = alloc<int64_t>(static_cast<size_t>(m), o_first);
    int64_t tri_rows = 0;
    for (int64_t p = 0; p < m; ++p) {
        if (ct0[p] < 0 || st0[p] < 0 || st0[p] + ct0[p] > rows) {
            throw nb::value_error("a polygon's rows lie outside xy");
        }
        first[p] = tri_rows;
        tri_rows += std::max<int64_t>(ct0[p] - 2, 0);
    }
    nb::capsule o_status, o_sizes, o_cw, o_costs, o_tris;
    auto* status = alloc<int8_t>(static_cast<size_t>(m), o_status);
    auto* sizes = alloc<int64_t>(static_cast<size_t>(m), o_sizes);
    auto* cw = alloc<bool>(static_cast<size_t>(m), o_cw);
    auto* costs = alloc<double>(static_cast<size_t>(m), o_costs);
    auto* tris = alloc<int64_t>(static_cast<size_t>(3 * tri_rows), o_tris);
    const Settings settings{modes.data(), static_cast<int64_t>(modes.shape(0)), code, is_max,
                            edge};
    {
        nb::gil_scoped_release nogil;
        // largest first: the dynamic schedule then ends with the small ones
        std::vector<int64_t> perm(static_cast<size_t>(m));
        std::iota(perm.begin(), perm.end(), int64_t{0});
        std::stable_sort(perm.begin(), perm.end(),
                         [&](int64_t a, int64_t b) { return ct0[a] > ct0[b]; });
        const double* data = xy.data();
#if defined(OPTRI_OPENMP)
#pragma omp parallel num_threads(std::max(1, threads))
#endif
        {
            Scratch sc;
#if defined(OPTRI_OPENMP)
#pragma omp for schedule(dynamic, 1)
#endif
            for (int64_t r = 0; r < m; ++r) {
                const int64_t p = perm[static_cast<size_t>(r)];
                int64_t n;
                bool c;
                double cost;
                status[p] = solve_one(settings, data, st0[p], ct0[p], tris + 3 * first[p], sc,
                                      n, c, cost);
                sizes[p] = n;
                cw[p] = c;
                costs[p] = cost;
            }
        }
        (void)threads;
    }
    const size_t vm = static_cast<size_t>(m);
    const size_t shape[2] = {static_cast<size_t>(tri_rows), 3};
    return {Out1<int8_t>(status, 1, &vm, o_status), Out1<int64_t>(sizes, 1, &vm, o_sizes),
            Out1<bool>(cw, 1, &vm, o_cw), Out1<double>(costs, 1, &vm, o_costs),
            Out2(tris, 2, shape, o_tris), Out1<int64_t>(first, 1, &vm, o_first)};
}

}  // namespace

}  // namespace many

void bind_many(nb::module_& m) {
    nb::module_ s = m.def_submodule("many", "Many small polygons per call (see many.cpp).");
    s.def("solve", &many::solve, nb::arg("xy"), nb::arg("starts"), nb::arg("counts"),
          nb::arg("modes"), nb::arg("code"), nb::arg("is_max"), nb::arg("edge"),
          nb::arg("threads"),
          "Solve polygon p from rows starts[p] .. starts[p] + counts[p] - 1 of xy ((rows, 2) "
          "float64).\n\n"
          "modes[n]: 0 not here, 1 the Python engines' values, 2 the compiled engine's. "
          "code: the built-in weight (WeightCode); is_max: objective max (else sum); edge: "
          "a sum of an edge-decomposable weight. Returns (status int8, sizes int64 (n after "
          "closing vertices), cw bool, costs float64, triangles (rows, 3) int64, first "
          "int64): polygon p's n - 2 triangles, in input indices, from row first[p] (the "
          "sum of max(counts[q] - 2, 0) over q < p). Status 0 is "
          "solved; any other means declined (optri.batch.compiled.STATUS). Runs on `threads` "
          "threads without the GIL.");
}

}  // namespace optri
