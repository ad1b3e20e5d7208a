// The generic recurrence (generic.hpp) and its bindings, optri._core.generic.
#include "generic.hpp"

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/tuple.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <optional>
#include <tuple>
#include <vector>

#ifdef OPTRI_OPENMP
#include <omp.h>
#endif

#include "bind.hpp"

namespace optri {
namespace generic {

namespace {

constexpr double inf = std::numeric_limits<double>::infinity();
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

// Flags and the stop / progress words are shared between threads: atomic accesses.
inline int64_t load_relaxed(const int64_t* p) {
#if defined(_MSC_VER) && !defined(__clang__)
    return *reinterpret_cast<const volatile int64_t*>(p);
#else
    return __atomic_load_n(p, __ATOMIC_RELAXED);
#endif
}

inline int64_t load_acquire(const int64_t* p) {
#if defined(_MSC_VER) && !defined(__clang__)
    int64_t v = *reinterpret_cast<const volatile int64_t*>(p);
    std::atomic_thread_fence(std::memory_order_acquire);
    return v;
#else
    return __atomic_load_n(p, __ATOMIC_ACQUIRE);
#endif
}

inline void store_relaxed(int64_t* p, int64_t v) {
#if defined(_MSC_VER) && !defined(__clang__)
    *reinterpret_cast<volatile int64_t*>(p) = v;
#else
    __atomic_store_n(p, v, __ATOMIC_RELAXED);
#endif
}

inline void store_release(int64_t* p, int64_t v) {
#if defined(_MSC_VER) && !defined(__clang__)
    std::atomic_thread_fence(std::memory_order_release);
    *reinterpret_cast<volatile int64_t*>(p) = v;
#else
    __atomic_store_n(p, v, __ATOMIC_RELEASE);
#endif
}

inline bool flagged(const Flags& f) {
    return load_relaxed(&f.nan) != 0 || load_relaxed(&f.error) != 0;
}

// Weight `slot` (0: component 1, 1: component 2, 2: the gate) of triangle (i, k, j).
inline double weight(const Problem& pr, int slot, Flags& flags, int64_t i, int64_t k,
                     int64_t j) {
    const int code = pr.code[slot];
    if (code != static_cast<int>(WeightCode::custom)) {
        return triangle_weight(code, pr.pts, i, k, j);
    }
    UserWeight fn = pr.user[slot];
    if (fn == nullptr) return nan;
    int64_t error = 0;
    double w = fn(pr.vertices, pr.shape, pr.order[i], pr.order[k], pr.order[j], &error);
    if (error != 0) {
        store_relaxed(&flags.error, 1 + slot);
        return nan;
    }
    return w;
}

// Weight of component 1; +inf when a gate is set and the gate weight exceeds its bound.
inline double gated_first(const Problem& pr, Flags& flags, int64_t i, int64_t k, int64_t j) {
    double w1 = weight(pr, 0, flags, i, k, j);
    if (pr.code[2] != NO_GATE) {  // a triangle above the gate's threshold is forbidden
        if (weight(pr, 2, flags, i, k, j) > pr.gate) w1 = inf;
    }
    return w1;
}

// Cells of one tile, rows upwards and columns rightwards, so that both halves of every
// split are final when read.
template <class T>
void fill_tile(const Tables<T>& tb, const Problem& pr, Flags& flags, int64_t i0, int64_t i1,
               int64_t j0, int64_t j1) {
    const int64_t n = tb.n;
    for (int64_t i = i1 - 1; i >= i0; --i) {
        for (int64_t j = std::max(j0, i + 2); j < j1; ++j) {
            double c1 = inf, c2 = inf;
            if (pr.mask == nullptr || pr.mask[i * n + j]) {
                Split s = best_split(tb, pr, flags, i, j);
                c1 = s.c1, c2 = s.c2;
            }
            tb.t1[i * n + j] = static_cast<T>(c1);
            tb.t1[j * n + i] = static_cast<T>(c1);
            if (pr.lex) {
                tb.t2[i * n + j] = static_cast<T>(c2);
                tb.t2[j * n + i] = static_cast<T>(c2);
            }
        }
    }
}

}  // namespace

template <class T>
Split best_split(const Tables<T>& tb, const Problem& pr, Flags& flags, int64_t i, int64_t j) {
    const int64_t n = tb.n;
    const bool lex = pr.lex;
    const T* r1i = tb.t1 + i * n;
    const T* r1j = tb.t1 + j * n;
    const T* r2i = lex ? tb.t2 + i * n : r1i;
    const T* r2j = lex ? tb.t2 + j * n : r1j;
    double b1 = inf, b2 = inf;
    int64_t arg = -1;
    for (int64_t k = i + 1; k < j; ++k) {
        if (r1i[k] == inf || r1j[k] == inf) continue;  // a half with no triangulation
        double w1 = gated_first(pr, flags, i, k, j);
        if (w1 != w1) {
            store_relaxed(&flags.nan, 1);
            continue;
        }
        double v1 = combine(pr.is_max[0], r1i[k], r1j[k], w1);
        if (!lex) {
            if (v1 < b1) b1 = v1, arg = k;
            continue;
        }
        double w2 = weight(pr, 1, flags, i, k, j);
        if (w2 != w2) {
            store_relaxed(&flags.nan, 1);
            continue;
        }
        double v2 = combine(pr.is_max[1], r2i[k], r2j[k], w2);
        if (lex_better(v1, v2, b1, b2)) b1 = v1, b2 = v2, arg = k;
    }
    return {b1, b2, arg};
}

template <class T>
void set_sides(const Tables<T>& tb, const Problem& pr) {
    const int64_t n = tb.n;
    for (int c = 0; c < (pr.lex ? 2 : 1); ++c) {
        T* t = c == 0 ? tb.t1 : tb.t2;
        const T neutral = static_cast<T>(pr.is_max[c] ? -inf : 0.0);
        for (int64_t i = 0; i + 1 < n; ++i) t[i * n + i + 1] = t[(i + 1) * n + i] = neutral;
    }
}

template <class T>
void fill(const Tables<T>& tb, const Problem& pr, Flags& flags) {
    const int64_t n = tb.n;
    for (int64_t i = n - 1; i >= 0 && !flagged(flags); --i) fill_tile(tb, pr, flags, i, i + 1, 0, n);
}

template <class T>
void fill_tiles(const Tables<T>& tb, const Problem& pr, Flags& flags, int64_t tile,
                int threads, const int64_t* stop, int64_t* reached) {
    const int64_t n = tb.n;
    tile = std::max<int64_t>(tile, 1);
    const int64_t nt = (n + tile - 1) / tile;
    for (int64_t d = 0; d < nt; ++d) {
        if ((stop != nullptr && load_acquire(stop) != 0) || flagged(flags)) break;
        const int64_t count = nt - d;
#ifdef OPTRI_OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1) if (threads > 1 && count > 1)
#endif
        for (int64_t t = 0; t < count; ++t) {
            const int64_t i0 = t * tile, i1 = std::min(n, t * tile + tile);
            const int64_t j0 = (t + d) * tile, j1 = std::min(n, (t + d) * tile + tile);
            fill_tile(tb, pr, flags, i0, i1, j0, j1);
        }
        if (reached != nullptr) store_release(reached, d + 1);
    }
    (void)threads;
}

template <class T>
int64_t trace(const Tables<T>& tb, const Problem& pr, Flags& flags, int64_t* tris,
              int64_t bad[2]) {
    return walk(
        tb.n, [&](int64_t i, int64_t j) { return best_split(tb, pr, flags, i, j).k; }, tris,
        bad);
}

template <class T>
void split_table(const Tables<T>& tb, const Problem& pr, Flags& flags, int32_t* out,
                 int threads) {
    const int64_t n = tb.n;
    std::fill(out, out + n * n, -1);
#ifdef OPTRI_OPENMP
#pragma omp parallel for num_threads(threads) schedule(dynamic, 8) if (threads > 1)
#endif
    for (int64_t i = 0; i < n; ++i) {
        for (int64_t j = i + 2; j < n; ++j) {
            out[i * n + j] = static_cast<int32_t>(best_split(tb, pr, flags, i, j).k);
        }
    }
    (void)threads;
}

#define OPTRI_GENERIC_INSTANTIATE(T)                                                        \
    template Split best_split<T>(const Tables<T>&, const Problem&, Flags&, int64_t, int64_t); \
    template void set_sides<T>(const Tables<T>&, const Problem&);                           \
    template void fill<T>(const Tables<T>&, const Problem&, Flags&);                        \
    template void fill_tiles<T>(const Tables<T>&, const Problem&, Flags&, int64_t, int,     \
                                const int64_t*, int64_t*);                                  \
    template int64_t trace<T>(const Tables<T>&, const Problem&, Flags&, int64_t*,           \
                              int64_t[2]);                                                  \
    template void split_table<T>(const Tables<T>&, const Problem&, Flags&, int32_t*, int);

OPTRI_GENERIC_INSTANTIATE(float)
OPTRI_GENERIC_INSTANTIATE(double)
#undef OPTRI_GENERIC_INSTANTIATE

}  // namespace generic

// --- bindings: optri._core.generic ------------------------------------------------------

namespace {

namespace nb = nanobind;
using namespace nb::literals;

using Cpu = nb::device::cpu;
template <class T>
using Table = nb::ndarray<T, nb::ndim<2>, nb::c_contig, Cpu>;
using Words = nb::ndarray<int64_t, nb::ndim<1>, nb::c_contig, Cpu>;
using Coords = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, Cpu>;
using Vertices = nb::ndarray<const double, nb::c_contig, Cpu>;
using Order = nb::ndarray<const int64_t, nb::ndim<1>, nb::c_contig, Cpu>;
using Mask = nb::ndarray<const bool, nb::ndim<2>, nb::c_contig, Cpu>;

// A problem as Python builds it: the arrays it points into are kept alive with it.
struct PyProblem {
    generic::Problem pr;
    generic::Flags flags;
    Coords pts;
    std::optional<Mask> mask;
    std::optional<Vertices> vertices;
    std::optional<Order> order;
    std::vector<int64_t> shape;
};

PyProblem* make_problem(Coords pts, std::tuple<int, int, int> codes, double gate,
                        std::tuple<int, int> rules, bool lex, std::optional<Mask> mask,
                        std::optional<Vertices> vertices, std::optional<Order> order,
                        std::tuple<uintptr_t, uintptr_t, uintptr_t> users) {
    const int64_t n = static_cast<int64_t>(pts.shape(0));
    auto* out = new PyProblem{};
    out->pts = pts;
    out->mask = mask;
    out->vertices = vertices;
    out->order = order;
    generic::Problem& pr = out->pr;
    pr.pts = Points{pts.data(), n, static_cast<int64_t>(pts.shape(1))};
    pr.code[0] = std::get<0>(codes), pr.code[1] = std::get<1>(codes);
    pr.code[2] = std::get<2>(codes);
    pr.gate = gate;
    pr.is_max[0] = std::get<0>(rules) == static_cast<int>(Objective::max);
    pr.is_max[1] = std::get<1>(rules) == static_cast<int>(Objective::max);
    pr.lex = lex;
    if (mask) {
        if (static_cast<int64_t>(mask->shape(0)) != n || static_cast<int64_t>(mask->shape(1)) != n) {
            delete out;
            throw nb::value_error("the chord mask must be n x n");
        }
        pr.mask = reinterpret_cast<const uint8_t*>(mask->data());
    }
    const uintptr_t fns[3] = {std::get<0>(users), std::get<1>(users), std::get<2>(users)};
    bool custom = false;
    for (int s = 0; s < 3; ++s) {
        pr.user[s] = reinterpret_cast<generic::UserWeight>(fns[s]);
        custom = custom || (pr.code[s] == static_cast<int>(WeightCode::custom));
    }
    if (custom) {
        if (!vertices || !order || static_cast<int64_t>(order->shape(0)) != n) {
            delete out;
            throw nb::value_error("a user weight needs the input vertices and the order");
        }
        for (size_t d = 0; d < vertices->ndim(); ++d) {
            out->shape.push_back(static_cast<int64_t>(vertices->shape(d)));
        }
        pr.vertices = vertices->data();
        pr.shape = out->shape.data();
        pr.order = order->data();
    }
    return out;
}

template <class T>
generic::Tables<T> tables_of(Table<T>& t1, Table<T>& t2, const PyProblem& p) {
    const int64_t n = static_cast<int64_t>(t1.shape(0));
    if (static_cast<int64_t>(t1.shape(1)) != n || n != p.pr.pts.n) {
        throw nb::value_error("the table must be n x n for the problem's n vertices");
    }
    if (p.pr.lex && (static_cast<int64_t>(t2.shape(0)) != n || static_cast<int64_t>(t2.shape(1)) != n)) {
        throw nb::value_error("a lexicographic problem needs a second n x n table");
    }
    return {t1.data(), p.pr.lex ? t2.data() : nullptr, n};
}

template <class T>
void bind_typed(nb::module_& m) {
    m.def(
        "generic_tiles",
        [](Table<T> t1, Table<T> t2, PyProblem& p, int64_t tile, int threads, Words stop,
           Words reached) {
            auto tb = tables_of(t1, t2, p);
            if (stop.shape(0) < 1 || reached.shape(0) < 1) {
                throw nb::value_error("stop and reached need one word each");
            }
            nb::gil_scoped_release unlocked;
            generic::fill_tiles(tb, p.pr, p.flags, tile, std::max(threads, 1), stop.data(),
                                reached.data());
        },
        "t1"_a.noconvert(), "t2"_a.noconvert(), "problem"_a, "tile"_a, "threads"_a,
        "stop"_a.noconvert(), "reached"_a.noconvert(),
        "Fill the table(s) tile-diagonal by tile-diagonal (sides set already); the GIL "
        "released. Returns early once stop[0] is nonzero or the problem's flags are set; "
        "reached[0] = d + 1 once tile-diagonal d is done.");
    m.def(
        "fill",
        [](Table<T> t1, Table<T> t2, PyProblem& p) {
            auto tb = tables_of(t1, t2, p);
            nb::gil_scoped_release unlocked;
            generic::set_sides(tb, p.pr);
            generic::fill(tb, p.pr, p.flags);
        },
        "t1"_a.noconvert(), "t2"_a.noconvert(), "problem"_a,
        "Set the sides to the neutral cost and fill the table(s) on this thread.");
    m.def(
        "trace",
        [](Table<T> t1, Table<T> t2, PyProblem& p) {
            auto tb = tables_of(t1, t2, p);
            const int64_t n = tb.n;
            const size_t rows = static_cast<size_t>(std::max<int64_t>(n - 2, 0));
            auto* buf = new int64_t[std::max<size_t>(rows, 1) * 3];
            int64_t bad[2];
            int64_t m;
            {
                nb::gil_scoped_release unlocked;
                m = generic::trace(tb, p.pr, p.flags, buf, bad);
            }
            nb::capsule owner(buf, [](void* q) noexcept { delete[] static_cast<int64_t*>(q); });
            nb::ndarray<nb::numpy, int64_t, nb::ndim<2>> tris(
                buf, {static_cast<size_t>(m), 3}, owner);
            return std::make_tuple(tris, std::make_tuple(bad[0], bad[1]));
        },
        "t1"_a.noconvert(), "t2"_a.noconvert(), "problem"_a,
        "Optimal triangles from chord (0, n-1) down: (triangles, bad), bad = (i, j) of a "
        "chord with no finite split, else (-1, -1).");
    m.def(
        "split_table",
        [](Table<T> t1, Table<T> t2, PyProblem& p, int threads) {
            auto tb = tables_of(t1, t2, p);
            const size_t n = static_cast<size_t>(tb.n);
            auto* buf = new int32_t[std::max<size_t>(n * n, 1)];
            {
                nb::gil_scoped_release unlocked;
                generic::split_table(tb, p.pr, p.flags, buf, std::max(threads, 1));
            }
            nb::capsule owner(buf, [](void* q) noexcept { delete[] static_cast<int32_t*>(q); });
            return nb::ndarray<nb::numpy, int32_t, nb::ndim<2>>(buf, {n, n}, owner);
        },
        "t1"_a.noconvert(), "t2"_a.noconvert(), "problem"_a, "threads"_a = 1,
        "The optimal split of every chord (-1 where j < i + 2): O(n^3).");
}

}  // namespace

void bind_generic(nb::module_& root) {
    nb::module_ m = root.def_submodule(
        "generic", "The generic recurrence: any weight, sum / max / lexicographic objectives.");
    m.attr("NO_GATE") = generic::NO_GATE;
    nb::class_<PyProblem>(m, "Problem",
                          "Everything a fill reads besides the tables, and its flags.")
        .def(nb::new_(&make_problem), "pts"_a, "codes"_a, "gate"_a, "rules"_a, "lex"_a,
             "mask"_a = nb::none(), "vertices"_a = nb::none(), "order"_a = nb::none(),
             "users"_a = std::make_tuple(uintptr_t(0), uintptr_t(0), uintptr_t(0)),
             "pts: internal-order vertices (n x dims float64); codes: WeightCode of "
             "component 1, 2 and the gate (NO_GATE: none); gate: its bound; rules: each "
             "component's ObjectiveCode (SUM or MAX); lex: a pair; mask: n x n allowed "
             "chords or None; vertices, order and users: the input vertices, the internal "
             "order and the addresses of the user weights' C functions (0: none).")
        .def_prop_ro("nan", [](const PyProblem& p) { return generic::load_relaxed(&p.flags.nan); })
        .def_prop_ro("error", [](const PyProblem& p) { return generic::load_relaxed(&p.flags.error); })
        .def("reset", [](PyProblem& p) { p.flags = generic::Flags{}; }, "Clear the flags.");
    bind_typed<double>(m);
    bind_typed<float>(m);
    m.def(
        "triangle_weight",
        [](int code, Coords pts, int64_t i, int64_t k, int64_t j) {
            const int64_t n = static_cast<int64_t>(pts.shape(0));
            if (i < 0 || k < 0 || j < 0 || i >= n || k >= n || j >= n) {
                throw nb::index_error("vertex index out of range");
            }
            Points p{pts.data(), n, static_cast<int64_t>(pts.shape(1))};
            return triangle_weight(code, p, i, k, j);
        },
        "code"_a, "pts"_a, "i"_a, "k"_a, "j"_a,
        "Built-in weight `code` of triangle (i, k, j) of pts (n x dims float64).");
    m.def(
        "edge_weight",
        [](int code, Coords pts, int64_t a, int64_t b) {
            const int64_t n = static_cast<int64_t>(pts.shape(0));
            if (a < 0 || b < 0 || a >= n || b >= n) throw nb::index_error("vertex index out of range");
            Points p{pts.data(), n, static_cast<int64_t>(pts.shape(1))};
            return edge_weight(code, p, a, b);
        },
        "code"_a, "pts"_a, "a"_a, "b"_a, "e(a, b) of an edge-decomposable weight.");
    m.def(
        "edge_weight_row",
        [](int code, Coords pts, int64_t a, int64_t b0, int64_t count) {
            const int64_t n = static_cast<int64_t>(pts.shape(0));
            if (a < 0 || a >= n || b0 < 0 || count < 0 || b0 + count > n) {
                throw nb::index_error("vertex index out of range");
            }
            Points p{pts.data(), n, static_cast<int64_t>(pts.shape(1))};
            auto* buf = new double[static_cast<size_t>(std::max<int64_t>(count, 1))];
            edge_weight_row(code, p, a, b0, buf, count);
            nb::capsule owner(buf, [](void* q) noexcept { delete[] static_cast<double*>(q); });
            return nb::ndarray<nb::numpy, double, nb::ndim<1>>(buf, {static_cast<size_t>(count)},
                                                               owner);
        },
        "code"_a, "pts"_a, "a"_a, "b0"_a, "count"_a,
        "[e(a, b0), ..., e(a, b0 + count - 1)] by the row formula (edge_weight_row).");
}

}  // namespace optri
