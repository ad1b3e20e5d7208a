// optri._core.topology: whole-mesh passes of hole filling (optri.holes.mesh, optri.meshdata).
//
// Each function replaces a numpy pipeline of sorts and unique calls over every face or
// vertex of the mesh with one linear pass, and returns exactly what that pipeline
// returned (the tests compare them on random meshes):
//
// * weld_first: for each row of an (n, 3) array, the lowest row index with equal values
//   (float equality: -0.0 equals 0.0; the caller rejects NaN);
// * components: the connected component of each vertex through the faces' edges, named
//   by its lowest vertex id (a vertex no face uses is its own component);
// * single_edges: the face edges (row 3 * face + corner: corner -> corner + 1) whose
//   undirected edge no other face edge repeats, in row order;
// * edges_among: the sorted, distinct undirected keys min * nv + max of the face edges
//   whose two ends are both flagged.
//
// Edges are grouped by their smaller end with a counting sort (O(faces + vertices)); the
// few edges of one vertex are then compared directly.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "bind.hpp"

namespace nb = nanobind;

namespace optri {

namespace {

using arrays::In;
using arrays::NewArray;

void need(bool ok, const char* what) { arrays::need(ok, "optri._core.topology", what); }

template <class T>
NewArray<T> from_vector(std::vector<T>&& v) {
    const size_t n = v.size();
    return arrays::owning(std::move(v), {n});
}

struct RowKey {
    uint64_t x, y, z;
    bool operator==(const RowKey& o) const { return x == o.x && y == o.y && z == o.z; }
};

struct RowHash {
    size_t operator()(const RowKey& k) const {
        uint64_t h = k.x * 0x9E3779B97F4A7C15ULL;
        h ^= (k.y + 0x7F4A7C159E3779B9ULL + (h << 6) + (h >> 2)) * 0xC2B2AE3D27D4EB4FULL;
        h ^= (k.z + 0x165667B19E3779F9ULL + (h << 6) + (h >> 2)) * 0x9E3779B97F4A7C15ULL;
        return static_cast<size_t>(h ^ (h >> 29));
    }
};

inline uint64_t bits(double v) {
    const double w = v == 0.0 ? 0.0 : v;  // -0.0 and 0.0 are one value
    uint64_t u;
    std::memcpy(&u, &w, sizeof u);
    return u;
}

std::vector<int64_t> weld_first(const double* p, int64_t n) {
    std::vector<int64_t> rep(static_cast<size_t>(n));
    std::unordered_map<RowKey, int64_t, RowHash> first;
    first.reserve(static_cast<size_t>(n));
    for (int64_t i = 0; i < n; ++i) {
        const RowKey k{bits(p[3 * i]), bits(p[3 * i + 1]), bits(p[3 * i + 2])};
        rep[i] = first.emplace(k, i).first->second;  // the first row seen keeps the key
    }
    return rep;
}

int64_t find(std::vector<int64_t>& parent, int64_t v) {
    while (parent[v] != v) {
        parent[v] = parent[parent[v]];
        v = parent[v];
    }
    return v;
}

std::vector<int64_t> components(const int64_t* f, int64_t m, int64_t nv) {
    std::vector<int64_t> parent(static_cast<size_t>(nv));
    for (int64_t v = 0; v < nv; ++v) parent[v] = v;
    for (int64_t t = 0; t < m; ++t) {
        for (int c = 0; c < 2; ++c) {  // two edges join a face's three corners
            const int64_t a = find(parent, f[3 * t + c]), b = find(parent, f[3 * t + c + 1]);
            if (a != b) parent[std::max(a, b)] = std::min(a, b);  // the root is the lowest id
        }
    }
    for (int64_t v = 0; v < nv; ++v) parent[v] = find(parent, v);
    return parent;
}

// face-edge rows grouped by their smaller end: rows[start[v] .. start[v + 1])
struct ByLow {
    std::vector<int64_t> start, rows;
};

ByLow group_by_low(const int64_t* f, int64_t m, int64_t nv, const uint8_t* keep) {
    ByLow g;
    g.start.assign(static_cast<size_t>(nv) + 1, 0);
    for (int64_t r = 0; r < 3 * m; ++r) {
        if (keep != nullptr && !keep[r]) continue;
        const int64_t a = f[r], b = f[r % 3 == 2 ? r - 2 : r + 1];
        ++g.start[std::min(a, b) + 1];
    }
    for (int64_t v = 0; v < nv; ++v) g.start[v + 1] += g.start[v];
    g.rows.resize(static_cast<size_t>(g.start[nv]));
    std::vector<int64_t> at(g.start.begin(), g.start.end() - 1);
    for (int64_t r = 0; r < 3 * m; ++r) {  // rows ascend within each group
        if (keep != nullptr && !keep[r]) continue;
        const int64_t a = f[r], b = f[r % 3 == 2 ? r - 2 : r + 1];
        g.rows[at[std::min(a, b)]++] = r;
    }
    return g;
}

inline int64_t high_end(const int64_t* f, int64_t r) {
    const int64_t a = f[r], b = f[r % 3 == 2 ? r - 2 : r + 1];
    return std::max(a, b);
}

std::vector<int64_t> single_edges(const int64_t* f, int64_t m, int64_t nv) {
    const ByLow g = group_by_low(f, m, nv, nullptr);
    std::vector<uint8_t> single(static_cast<size_t>(3 * m), 0);
    std::vector<std::pair<int64_t, int64_t>> his;  // (other end, row) of one group, sorted
    for (int64_t v = 0; v < nv; ++v) {
        his.clear();
        for (int64_t p = g.start[v]; p < g.start[v + 1]; ++p) {
            his.emplace_back(high_end(f, g.rows[p]), g.rows[p]);
        }
        std::sort(his.begin(), his.end());
        const size_t k = his.size();
        for (size_t p = 0; p < k; ++p) {
            const bool same_before = p > 0 && his[p - 1].first == his[p].first;
            const bool same_after = p + 1 < k && his[p + 1].first == his[p].first;
            single[his[p].second] = !same_before && !same_after;
        }
    }
    std::vector<int64_t> out;
    for (int64_t r = 0; r < 3 * m; ++r) {
        if (single[r]) out.push_back(r);
    }
    return out;
}

std::vector<int64_t> edges_among(const int64_t* f, int64_t m, int64_t nv, const bool* flag) {
    std::vector<uint8_t> keep(static_cast<size_t>(3 * m));
    for (int64_t r = 0; r < 3 * m; ++r) {
        keep[r] = flag[f[r]] && flag[f[r % 3 == 2 ? r - 2 : r + 1]];
    }
    const ByLow g = group_by_low(f, m, nv, keep.data());
    std::vector<int64_t> out, his;
    for (int64_t v = 0; v < nv; ++v) {
        his.clear();
        for (int64_t p = g.start[v]; p < g.start[v + 1]; ++p) his.push_back(high_end(f, g.rows[p]));
        std::sort(his.begin(), his.end());
        his.erase(std::unique(his.begin(), his.end()), his.end());
        for (int64_t hi : his) out.push_back(v * nv + hi);
    }
    return out;
}

void check_faces(const In<int64_t>& faces, int64_t nv) {
    need(faces.ndim() == 2 && faces.shape(1) == 3, "faces must be (m, 3)");
    need(nv >= 0, "vertex count must be >= 0");
    const int64_t* f = faces.data();
    const int64_t total = 3 * static_cast<int64_t>(faces.shape(0));
    for (int64_t r = 0; r < total; ++r) need(f[r] >= 0 && f[r] < nv, "face index out of range");
}

}  // namespace

void bind_topology(nb::module_& m) {
    nb::module_ t = m.def_submodule("topology", "Whole-mesh passes of hole filling.");

    t.def("weld_first", [](In<double> points) {
        need(points.ndim() == 2 && points.shape(1) == 3, "points must be (n, 3)");
        const int64_t n = static_cast<int64_t>(points.shape(0));
        std::vector<int64_t> rep;
        {
            nb::gil_scoped_release nogil;
            rep = weld_first(points.data(), n);
        }
        return from_vector(std::move(rep));
    }, nb::arg("points"), "For each row, the lowest row index with equal values.");

    t.def("components", [](In<int64_t> faces, int64_t nv) {
        check_faces(faces, nv);
        std::vector<int64_t> label;
        {
            nb::gil_scoped_release nogil;
            label = components(faces.data(), static_cast<int64_t>(faces.shape(0)), nv);
        }
        return from_vector(std::move(label));
    }, nb::arg("faces"), nb::arg("nv"),
       "Component of each vertex, named by its lowest vertex id.");

    t.def("single_edges", [](In<int64_t> faces, int64_t nv) {
        check_faces(faces, nv);
        std::vector<int64_t> rows;
        {
            nb::gil_scoped_release nogil;
            rows = single_edges(faces.data(), static_cast<int64_t>(faces.shape(0)), nv);
        }
        return from_vector(std::move(rows));
    }, nb::arg("faces"), nb::arg("nv"),
       "Rows 3 * face + corner of the face edges no other face edge repeats, ascending.");

    t.def("edges_among", [](In<int64_t> faces, int64_t nv, In<bool> flag) {
        check_faces(faces, nv);
        need(flag.ndim() == 1 && static_cast<int64_t>(flag.shape(0)) == nv,
             "flag must have one entry per vertex");
        std::vector<int64_t> keys;
        {
            nb::gil_scoped_release nogil;
            keys = edges_among(faces.data(), static_cast<int64_t>(faces.shape(0)), nv,
                               flag.data());
        }
        return from_vector(std::move(keys));
    }, nb::arg("faces"), nb::arg("nv"), nb::arg("flag"),
       "Sorted distinct keys min * nv + max of the face edges with both ends flagged.");
}

}  // namespace optri
