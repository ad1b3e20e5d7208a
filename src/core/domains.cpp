// optri._core.domains: the geometry of a polygon with holes (optri/domains/).
//
// A domain is N vertices (all rings) and the boundary successor nxt[v], with the domain on
// the left of every edge v -> nxt[v]. From it:
//   * the valid diagonals: vertex pairs (a, b), a < b, not a boundary edge, whose segment
//     starts into the domain at both ends (strictly inside the angle between the two
//     boundary edges there), crosses no boundary edge properly and passes through no vertex;
//     with each one's row of turns orient(a, b, v) over every vertex v;
//   * the candidate triangles: counter-clockwise triples whose sides are boundary edges run
//     forward or valid diagonals, of non-zero area, with no hole inside (four vertices of each
//     hole tested: sides that cross nothing leave a hole wholly inside or wholly outside);
//   * the sides' edge ids and signs, in the order optri.domains.candidates documents.
// Every sign comes from orient_sign (predicates.hpp): exact for every finite input, so the
// sets are those exact arithmetic defines, whatever order the tests run in.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/tuple.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <tuple>
#include <utility>
#include <vector>

#ifdef OPTRI_OPENMP
#include <omp.h>
#endif

#include "bind.hpp"
#include "cpu.hpp"
#include "predicates.hpp"

namespace nb = nanobind;

namespace optri {

namespace {

using i64 = std::int64_t;
using i8 = std::int8_t;

using Points = nb::ndarray<const double, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
using Index = nb::ndarray<const i64, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Pairs = nb::ndarray<const i64, nb::shape<-1, 2>, nb::c_contig, nb::device::cpu>;
using Table8 = nb::ndarray<const i8, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

// Boundary edges around each end of a chord that screen it before the full test: most
// chords that are not diagonals leave the domain close to an end.
constexpr int kNear = 4;
// Vertices from which the O(N^2)-and-up loops run on threads (below, waking them costs more).
constexpr int kThreadsFrom = 256;

// A numpy array that owns a vector's storage.
template <typename T>
nb::ndarray<nb::numpy, T> owned(std::vector<T>&& v, std::initializer_list<std::size_t> shape) {
    auto* heap = new std::vector<T>(std::move(v));
    nb::capsule owner(heap, [](void* d) noexcept { delete static_cast<std::vector<T>*>(d); });
    return nb::ndarray<nb::numpy, T>(heap->data(), shape, owner);
}

struct Domain {
    const double* p;
    const i64* nxt;
    std::vector<i64> prv;
    int n;
    // es[e * n + v] = orient(e, nxt[e], v): vertex v's side of boundary edge e (row e), and
    // its transpose (row v), so both a chord's ends' sides of every edge are contiguous.
    std::vector<i8> es, es_t;

    Domain(const double* pts, const i64* next, int count) : p(pts), nxt(next), prv(count), n(count) {
        for (int v = 0; v < n; ++v) {
            const i64 w = nxt[v];
            if (w < 0 || w >= n) throw std::invalid_argument("nxt holds an index out of range");
            prv[w] = v;
        }
    }

    int orient(i64 a, i64 b, i64 c) const {
        return orient_sign(p[2 * a], p[2 * a + 1], p[2 * b], p[2 * b + 1], p[2 * c],
                           p[2 * c + 1]);
    }

    bool is_side(i64 a, i64 b) const { return nxt[a] == b || nxt[b] == a; }

    void edge_sides() {
        const std::size_t nn = static_cast<std::size_t>(n) * n;
        es.assign(nn, 0);
        es_t.assign(nn, 0);
#ifdef OPTRI_OPENMP
#pragma omp parallel for schedule(dynamic, 8) num_threads(max_threads()) if (n >= kThreadsFrom)
#endif
        for (int e = 0; e < n; ++e) {
            for (int v = 0; v < n; ++v) {
                const i8 s = static_cast<i8>(orient(e, nxt[e], v));
                es[static_cast<std::size_t>(e) * n + v] = s;
                es_t[static_cast<std::size_t>(v) * n + e] = s;
            }
        }
    }

    // The segment from vertex i towards vertex j starts strictly inside the domain's angle
    // at i (between prv[i] -> i and i -> nxt[i], on their left).
    bool in_wedge(i64 i, i64 j) const {
        const bool left_of_next = es[i * n + j] > 0;
        const bool left_of_prev = es[prv[i] * n + j] > 0;
        const bool convex = es[prv[i] * n + nxt[i]] > 0;
        return convex ? (left_of_next && left_of_prev) : (left_of_next || left_of_prev);
    }

    // Boundary edge e crosses chord (i, j) properly (turns of e's ends computed here).
    bool crosses(i64 i, i64 j, i64 e) const {
        if (es_t[i * n + e] * es_t[j * n + e] >= 0) return false;
        return orient(i, j, e) * orient(i, j, nxt[e]) < 0;
    }

    // Whether chord (i, j), in-cone at both ends, is a valid diagonal; its turns go to row.
    bool diagonal(i64 i, i64 j, i8* row) const {
        for (i64 base : {i, j}) {
            i64 e = base;
            for (int s = 0; s < kNear; ++s) e = prv[e];
            for (int s = 0; s < 2 * kNear + 1; ++s, e = nxt[e]) {
                if (crosses(i, j, e)) return false;
            }
        }
        // an edge crosses the chord only if the chord's ends lie on both sides of its line
        const i8* si = &es_t[i * n];
        const i8* sj = &es_t[j * n];
        for (int e = 0; e < n; ++e) {
            if (si[e] * sj[e] < 0 && orient(i, j, e) * orient(i, j, nxt[e]) < 0) return false;
        }
        const double ax = p[2 * i], ay = p[2 * i + 1], bx = p[2 * j], by = p[2 * j + 1];
        for (int v = 0; v < n; ++v) {
            const int s = orient_sign(ax, ay, bx, by, p[2 * v], p[2 * v + 1]);
            row[v] = static_cast<i8>(s);
            if (s == 0 && v != i && v != j &&
                strictly_between(ax, ay, bx, by, p[2 * v], p[2 * v + 1])) {
                return false;  // a vertex on the open chord
            }
        }
        return true;
    }
};

struct Diagonals {
    std::vector<i64> pairs;  // (D, 2), sorted pairs in increasing order
    std::vector<i8> turns;   // (D, N)
};

// Valid diagonals in the order of numpy's triu_indices: by a, then b.
Diagonals find_diagonals(const Domain& d) {
    const int n = d.n;
    std::vector<Diagonals> per(n);
#ifdef OPTRI_OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(max_threads()) if (n >= kThreadsFrom)
#endif
    for (int i = 0; i < n; ++i) {
        Diagonals& out = per[i];
        std::vector<i8> row(n);
        for (int j = i + 1; j < n; ++j) {
            if (d.is_side(i, j) || !d.in_wedge(i, j) || !d.in_wedge(j, i)) continue;
            if (!d.diagonal(i, j, row.data())) continue;
            out.pairs.push_back(i);
            out.pairs.push_back(j);
            out.turns.insert(out.turns.end(), row.begin(), row.end());
        }
    }
    Diagonals all;
    std::size_t count = 0;
    for (const auto& part : per) count += part.pairs.size() / 2;
    all.pairs.reserve(2 * count);
    all.turns.reserve(count * n);
    for (auto& part : per) {
        all.pairs.insert(all.pairs.end(), part.pairs.begin(), part.pairs.end());
        all.turns.insert(all.turns.end(), part.turns.begin(), part.turns.end());
        part = Diagonals();
    }
    return all;
}

// Edge ids by vertex pair: for each a, its neighbours b > a (sorted) and their edge ids.
struct EdgeIndex {
    std::vector<std::vector<std::pair<i64, i64>>> up;

    EdgeIndex(int n, const std::vector<i64>& edges) : up(n) {
        for (std::size_t e = 0; e < edges.size() / 2; ++e) {
            up[edges[2 * e]].emplace_back(edges[2 * e + 1], static_cast<i64>(e));
        }
        for (auto& list : up) std::sort(list.begin(), list.end());
    }

    // Edge id of {a, b}, or -1.
    i64 find(i64 a, i64 b) const {
        if (a > b) std::swap(a, b);
        const auto& list = up[a];
        auto it = std::lower_bound(list.begin(), list.end(), std::make_pair(b, i64{-1}));
        return it != list.end() && it->first == b ? it->second : -1;
    }
};

struct Triangles {
    std::vector<i64> tris, sides;
    std::vector<i8> signs;
};

// Candidate triangles, sorted by (t0, t1, t2); t0 is the smallest vertex.
Triangles find_triangles(const Domain& d, const std::vector<i64>& edges, const i64* reps,
                         std::size_t n_reps) {
    const int n = d.n;
    const EdgeIndex index(n, edges);
    std::vector<std::vector<i64>> per(n);
#ifdef OPTRI_OPENMP
#pragma omp parallel for schedule(dynamic, 1) num_threads(max_threads()) if (n >= kThreadsFrom)
#endif
    for (int a = 0; a < n; ++a) {
        const auto& nb_a = index.up[a];
        std::vector<std::array<i64, 3>> found;
        for (std::size_t x = 0; x < nb_a.size(); ++x) {
            const i64 b = nb_a[x].first;
            for (std::size_t y = x + 1; y < nb_a.size(); ++y) {
                const i64 c = nb_a[y].first;
                if (index.find(b, c) < 0) continue;
                const int turn = d.orient(a, b, c);
                if (turn == 0) continue;
                std::array<i64, 3> t = turn > 0 ? std::array<i64, 3>{a, b, c}
                                                : std::array<i64, 3>{a, c, b};
                bool ok = true;
                for (int m = 0; m < 3 && ok; ++m) {
                    const i64 u = t[m], v = t[(m + 1) % 3];
                    ok = !d.is_side(u, v) || d.nxt[u] == v;  // a boundary side runs forward
                }
                for (std::size_t r = 0; r < n_reps && ok; ++r) {
                    const i64 q = reps[r];
                    ok = !(d.orient(t[0], t[1], q) > 0 && d.orient(t[1], t[2], q) > 0 &&
                           d.orient(t[2], t[0], q) > 0);
                }
                if (ok) found.push_back(t);
            }
        }
        std::sort(found.begin(), found.end());
        auto& out = per[a];
        out.reserve(3 * found.size());
        for (const auto& t : found) out.insert(out.end(), t.begin(), t.end());
    }
    Triangles all;
    std::size_t count = 0;
    for (const auto& part : per) count += part.size();
    all.tris.reserve(count);
    for (auto& part : per) {
        all.tris.insert(all.tris.end(), part.begin(), part.end());
        part = std::vector<i64>();
    }
    all.sides.resize(count);
    all.signs.resize(count);
    for (std::size_t t = 0; t < count; t += 3) {
        for (int m = 0; m < 3; ++m) {
            const i64 u = all.tris[t + m], v = all.tris[t + (m + 1) % 3];
            all.sides[t + m] = index.find(u, v);
            all.signs[t + m] = u < v ? 1 : -1;
        }
    }
    return all;
}

Domain checked(const Points& points, const Index& nxt) {
    if (points.shape(0) != nxt.shape(0)) {
        throw std::invalid_argument("points and nxt differ in length");
    }
    if (points.shape(0) < 3) throw std::invalid_argument("a domain has at least 3 vertices");
    return Domain(points.data(), nxt.data(), static_cast<int>(points.shape(0)));
}

nb::tuple diagonals_py(Points points, Index nxt) {
    Domain d = checked(points, nxt);
    Diagonals out;
    {
        nb::gil_scoped_release nogil;
        d.edge_sides();
        out = find_diagonals(d);
    }
    const std::size_t count = out.pairs.size() / 2;
    return nb::make_tuple(owned(std::move(out.pairs), {count, 2}),
                          owned(std::move(out.turns), {count, static_cast<std::size_t>(d.n)}));
}

nb::tuple candidates_py(Points points, Index nxt, Index reps) {
    Domain d = checked(points, nxt);
    for (std::size_t r = 0; r < reps.shape(0); ++r) {
        if (reps.data()[r] < 0 || reps.data()[r] >= d.n) {
            throw std::invalid_argument("reps holds an index out of range");
        }
    }
    Diagonals diag;
    Triangles tri;
    {
        nb::gil_scoped_release nogil;
        d.edge_sides();
        diag = find_diagonals(d);
        std::vector<i64> edges;
        edges.reserve(2 * d.n + diag.pairs.size());
        for (int v = 0; v < d.n; ++v) {
            edges.push_back(std::min<i64>(v, d.nxt[v]));
            edges.push_back(std::max<i64>(v, d.nxt[v]));
        }
        edges.insert(edges.end(), diag.pairs.begin(), diag.pairs.end());
        tri = find_triangles(d, edges, reps.data(), reps.shape(0));
    }
    const std::size_t count = diag.pairs.size() / 2;
    const std::size_t t = tri.tris.size() / 3;
    return nb::make_tuple(owned(std::move(diag.pairs), {count, 2}),
                          owned(std::move(diag.turns), {count, static_cast<std::size_t>(d.n)}),
                          owned(std::move(tri.tris), {t, 3}), owned(std::move(tri.sides), {t, 3}),
                          owned(std::move(tri.signs), {t, 3}));
}

// orient(a, b, v) of every vertex v against each segment (a, b) of seg: (S, N).
nb::ndarray<nb::numpy, i8> side_signs_py(Points points, Pairs seg) {
    const std::size_t n = points.shape(0), s = seg.shape(0);
    const double* p = points.data();
    const i64* q = seg.data();
    for (std::size_t r = 0; r < 2 * s; ++r) {
        if (q[r] < 0 || static_cast<std::size_t>(q[r]) >= n) {
            throw std::invalid_argument("seg holds an index out of range");
        }
    }
    std::vector<i8> out(s * n);
    {
        nb::gil_scoped_release nogil;
        for (std::size_t r = 0; r < s; ++r) {
            const i64 a = q[2 * r], b = q[2 * r + 1];
            for (std::size_t v = 0; v < n; ++v) {
                out[r * n + v] = static_cast<i8>(
                    orient_sign(p[2 * a], p[2 * a + 1], p[2 * b], p[2 * b + 1], p[2 * v], p[2 * v + 1]));
            }
        }
    }
    return owned(std::move(out), {s, n});
}


// Rows of a maximal set of pairwise non-crossing diagonals, taken greedily in the order of
// rows; then those of them that no diagonal of rows crosses (see reduce.forced_diagonals).
// turns: (D, N), diagonals: (D, 2); rows index both.
nb::ndarray<nb::numpy, i64> forced_py(Table8 turns, Pairs diagonals, Index rows) {
    const std::size_t d = turns.shape(0), n = turns.shape(1), a = rows.shape(0);
    if (diagonals.shape(0) != d) throw std::invalid_argument("turns and diagonals differ");
    const i8* t = turns.data();
    const i64* ends = diagonals.data();
    const i64* r = rows.data();
    for (std::size_t m = 0; m < a; ++m) {
        if (r[m] < 0 || static_cast<std::size_t>(r[m]) >= d) {
            throw std::invalid_argument("rows holds an index out of range");
        }
    }
    for (std::size_t m = 0; m < 2 * d; ++m) {
        if (ends[m] < 0 || static_cast<std::size_t>(ends[m]) >= n) {
            throw std::invalid_argument("diagonals holds a vertex out of range");
        }
    }
    // segments x and y (rows of turns) cross properly: each one's ends on both sides of the other
    auto cross = [&](i64 x, i64 y) {
        const i8* tx = t + x * n;
        const i8* ty = t + y * n;
        return tx[ends[2 * y]] * tx[ends[2 * y + 1]] < 0 && ty[ends[2 * x]] * ty[ends[2 * x + 1]] < 0;
    };
    std::vector<i64> out;
    {
        nb::gil_scoped_release nogil;
        std::vector<i64> greedy;
        for (std::size_t m = 0; m < a; ++m) {
            bool free = true;
            for (i64 g : greedy) {
                if (cross(r[m], g)) {
                    free = false;
                    break;
                }
            }
            if (free) greedy.push_back(r[m]);
        }
        std::vector<char> crossed(greedy.size(), 0);
        const std::ptrdiff_t count = static_cast<std::ptrdiff_t>(greedy.size());
#ifdef OPTRI_OPENMP
#pragma omp parallel for schedule(dynamic, 8) num_threads(max_threads()) if (a >= 4096)
#endif
        for (std::ptrdiff_t g = 0; g < count; ++g) {
            for (std::size_t m = 0; m < a; ++m) {
                if (cross(greedy[g], r[m])) {
                    crossed[g] = 1;
                    break;
                }
            }
        }
        for (std::size_t g = 0; g < greedy.size(); ++g) {
            if (!crossed[g]) out.push_back(greedy[g]);
        }
    }
    const std::size_t count = out.size();
    return owned(std::move(out), {count});
}

// Union-find over items linked by equal keys: key[3 m + s] belongs to item m. Items whose
// keys are equal are joined, pairs of equal keys taken in a stable sort of the keys, each
// union pointing the first item's root at the second's (path halving). Returns every item's
// root; a block is the items of one root.
nb::ndarray<nb::numpy, i64> link_py(Index key, std::size_t per) {
    if (per == 0 || key.shape(0) % per != 0) {
        throw std::invalid_argument("key's length is not a multiple of per");
    }
    const std::size_t m = key.shape(0), items = m / per;
    const i64* k = key.data();
    std::vector<i64> root(items);
    {
        nb::gil_scoped_release nogil;
        std::vector<i64> order(m);
        for (std::size_t q = 0; q < m; ++q) order[q] = static_cast<i64>(q);
        std::stable_sort(order.begin(), order.end(), [k](i64 x, i64 y) { return k[x] < k[y]; });
        std::vector<i64> parent(items);
        for (std::size_t q = 0; q < items; ++q) parent[q] = static_cast<i64>(q);
        auto find = [&parent](i64 x) {
            while (parent[x] != x) {
                parent[x] = parent[parent[x]];
                x = parent[x];
            }
            return x;
        };
        for (std::size_t q = 1; q < m; ++q) {
            if (k[order[q]] != k[order[q - 1]]) continue;
            const i64 ra = find(order[q] / static_cast<i64>(per));
            const i64 rb = find(order[q - 1] / static_cast<i64>(per));
            if (ra != rb) parent[ra] = rb;
        }
        for (std::size_t q = 0; q < items; ++q) root[q] = find(static_cast<i64>(q));
    }
    return owned(std::move(root), {items});
}

}  // namespace

void bind_domains(nb::module_& m) {
    nb::module_ d = m.def_submodule("domains", "Geometry of polygons with holes (optri.domains).");
    d.def("diagonals", &diagonals_py, nb::arg("points"), nb::arg("nxt"),
          "Valid diagonals (D, 2) int64, sorted pairs in increasing order, and their turns "
          "(D, N) int8: orient(a, b, v) of every vertex v.");
    d.def("candidates", &candidates_py, nb::arg("points"), nb::arg("nxt"), nb::arg("reps"),
          "(diagonals, turns, triangles, sides, signs): see optri.domains.candidates. "
          "``reps``: the vertices tested for a hole inside a triangle.");
    d.def("side_signs", &side_signs_py, nb::arg("points"), nb::arg("seg"),
          "orient(a, b, v) of every vertex v against each segment (a, b): (S, N) int8.");
    d.def("forced", &forced_py, nb::arg("turns"), nb::arg("diagonals"), nb::arg("rows"),
          "Of the diagonals ``rows``: those in a greedy maximal non-crossing set (in the order "
          "of rows) that no diagonal of rows crosses, in that order.");
    d.def("link", &link_py, nb::arg("key"), nb::arg("per"),
          "Union-find root of each item (``per`` keys each) over items sharing a key.");
}

}  // namespace optri
