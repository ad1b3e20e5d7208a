// optri._core.holes: the 3-D hole-filling kernels (holes.hpp), bound for optri.holes.
//
// Internal: optri.holes.search and optri.holes.liepa call these with arrays they made;
// shapes are checked here (a mismatch is a ValueError, never a write out of bounds).
// Output arguments are never converted (a copy would be filled instead of the caller's
// array). The long loops run without the GIL; a Ctrl-C during one surfaces when it
// returns, which is why the callers run the searches a chunk of rows or lengths a call.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "arrays.hpp"
#include "bind.hpp"
#include "holes.hpp"
#include "weights.hpp"

namespace nb = nanobind;

namespace optri {

namespace {

using arrays::In;
using arrays::NewArray;
using arrays::Out;

void need(bool ok, const char* what) { arrays::need(ok, "optri._core.holes", what); }

template <class A>
bool shaped(const A& a, std::initializer_list<int64_t> shape) {
    if (a.ndim() != shape.size()) return false;
    size_t d = 0;
    for (int64_t s : shape) {
        if (static_cast<int64_t>(a.shape(d++)) != s) return false;
    }
    return true;
}


// Q holds the n points, then (with third points) the n third points
void check_points(const In<double>& Q, int64_t n, bool has_third) {
    need(n >= 3, "a polyline has at least 3 points");
    need(Q.ndim() == 2 && Q.shape(1) == 3, "points must be (rows, 3)");
    need(static_cast<int64_t>(Q.shape(0)) >= (has_third ? 2 * n : n),
         "points: fewer rows than the polyline (and its third points) need");
}

void check_mesh(const In<double>& MN, int64_t n, bool has_third) {
    need(MN.ndim() == 2 && MN.shape(1) == 4, "mesh normals must be (rows, 4)");
    need(!has_third || static_cast<int64_t>(MN.shape(0)) >= n, "mesh normals: fewer rows than n");
}

template <class A>
void check_rows(const A& U, int64_t rows, const char* what) {
    need(U.ndim() == 2 && U.shape(1) >= 4 && static_cast<int64_t>(U.shape(0)) == rows, what);
}

}  // namespace

void bind_holes(nb::module_& m) {
    nb::module_ h = m.def_submodule("holes", "The 3-D hole-filling searches (optri.holes).");
    using namespace optri::holes;
    h.attr("DEGENERATE_KEY") = kDegenerateKey;
    h.attr("FOLD_KEY") = kFoldKey;
    h.attr("DEGENERATE_SINE2") = kDegenerateSine2;
    h.attr("PENDING") = kPending;

    h.def("mesh_normals", [](In<double> Q, int64_t n) {
        check_points(Q, n, true);
        auto out = arrays::zeros<double>({static_cast<size_t>(n), 4});
        mesh_normals(Q.data(), n, out.data());
        return out;
    }, nb::arg("Q"), nb::arg("n"),
       "(n, 4) rows (x, y, z, degenerate) of the mesh triangles (p[s+1], p[s], t[s]).");

    h.def("triangle_normals", [](In<double> Q, In<int64_t> tris) {
        need(Q.ndim() == 2 && Q.shape(1) == 3, "points must be (rows, 3)");
        need(tris.ndim() == 2 && tris.shape(1) == 3, "triangles must be (m, 3)");
        const int64_t m = static_cast<int64_t>(tris.shape(0));
        const int64_t rows = static_cast<int64_t>(Q.shape(0));
        const int64_t* t = tris.data();
        for (int64_t r = 0; r < 3 * m; ++r) need(t[r] >= 0 && t[r] < rows, "triangle index");
        auto out = arrays::zeros<double>({static_cast<size_t>(m), 5});
        triangle_normals(Q.data(), t, m, out.data());
        return out;
    }, nb::arg("Q"), nb::arg("tris"),
       "(m, 5) rows (x, y, z, degenerate, area) of index triangles (sorted first).");

    h.def("collinear", [](In<double> P, In<int64_t> tris) {
        need(P.ndim() == 2 && P.shape(1) == 3, "points must be (rows, 3)");
        need(tris.ndim() == 2 && tris.shape(1) == 3, "triangles must be (m, 3)");
        const int64_t m = static_cast<int64_t>(tris.shape(0));
        const int64_t rows = static_cast<int64_t>(P.shape(0));
        const int64_t* t = tris.data();
        for (int64_t r = 0; r < 3 * m; ++r) need(t[r] >= 0 && t[r] < rows, "triangle index");
        auto out = arrays::zeros<bool>({static_cast<size_t>(m)});
        collinear_rows(P.data(), t, m, out.data());
        return out;
    }, nb::arg("P"), nb::arg("tris"),
       "(m,) flags: whether each index triangle's points are exactly collinear.");

    h.def("is_collinear", [](In<double> P, int64_t a, int64_t b, int64_t c) {
        need(P.ndim() == 2 && P.shape(1) == 3, "points must be (rows, 3)");
        const int64_t rows = static_cast<int64_t>(P.shape(0));
        need(a >= 0 && b >= 0 && c >= 0 && a < rows && b < rows && c < rows, "point index");
        return collinear(P.data(), a, b, c);
    }, nb::arg("P"), nb::arg("a"), nb::arg("b"), nb::arg("c"),
       "Whether points a, b, c of P are exactly collinear.");

    h.def("fewest_degenerate", [](In<double> P, In<double> Q, int64_t n, In<bool> allowed,
                                  Out<int32_t> K) {
        need(P.ndim() == 2 && P.shape(1) == 3 && static_cast<int64_t>(P.shape(0)) >= n,
             "P must be (>= n, 3)");
        check_points(Q, n, false);
        need(shaped(allowed, {n, n}), "allowed must be (n, n)");
        need(shaped(K, {n, n}), "K must be (n, n)");
        nb::gil_scoped_release unlocked;
        return fewest_degenerate(P.data(), Q.data(), n, allowed.data(), K.data());
    }, nb::arg("P"), nb::arg("Q"), nb::arg("n"), nb::arg("allowed"), nb::arg("K").noconvert(),
       "Least (exactly degenerate triangles, area) patch over allowed chords: its count "
       "(-1: none), apexes into K (n, n).");

    h.def("fewest_then_weight", [](In<double> P, int64_t n, int code, bool is_max,
                                   In<bool> allowed, Out<int32_t> K) {
        check_points(P, n, false);
        need(code >= 0 && code <= static_cast<int>(WeightCode::aspect_ratio),
             "code: a built-in weight");
        need(shaped(allowed, {n, n}), "allowed must be (n, n)");
        need(shaped(K, {n, n}), "K must be (n, n)");
        nb::gil_scoped_release unlocked;
        return fewest_then_weight(P.data(), n, code, is_max, allowed.data(), K.data());
    }, nb::arg("P"), nb::arg("n"), nb::arg("code"), nb::arg("is_max"), nb::arg("allowed"),
       nb::arg("K").noconvert(),
       "Least (exactly degenerate triangles, sum or max of built-in weight code) patch over "
       "allowed chords: its count (-1: none), apexes into K (n, n).");

    h.def("pair_keys", [](In<double> U, In<double> V) {
        const int64_t rows = U.ndim() == 2 ? static_cast<int64_t>(U.shape(0)) : -1;
        check_rows(U, rows, "U must be (rows, >= 4)");
        check_rows(V, rows, "V must be (rows, >= 4), as many rows as U");
        auto out = arrays::zeros<double>({static_cast<size_t>(rows)});
        pair_keys(U.data(), U.shape(1), V.data(), V.shape(1), rows, out.data());
        return out;
    }, nb::arg("U"), nb::arg("V"),
       "Keys of row pairs (x, y, z, degenerate, ...) of two patch-normal tables.");

    h.def("mesh_pair_keys", [](In<double> U, In<double> MN, In<int64_t> sides) {
        const int64_t rows = U.ndim() == 2 ? static_cast<int64_t>(U.shape(0)) : -1;
        check_rows(U, rows, "U must be (rows, >= 4)");
        need(shaped(sides, {rows}), "sides: one per row of U");
        need(MN.ndim() == 2 && MN.shape(1) == 4, "mesh normals must be (rows, 4)");
        const int64_t* s = sides.data();
        for (int64_t r = 0; r < rows; ++r) {
            need(s[r] >= 0 && s[r] < static_cast<int64_t>(MN.shape(0)), "side index");
        }
        auto out = arrays::zeros<double>({static_cast<size_t>(rows)});
        mesh_pair_keys(U.data(), U.shape(1), MN.data(), s, rows, out.data());
        return out;
    }, nb::arg("U"), nb::arg("MN"), nb::arg("sides"),
       "Keys of patch-normal rows U against the mesh triangles on sides.");

    h.def("dense_rows", [](In<double> Q, int64_t n, bool has_third, In<double> MN,
                           In<bool> allowed, Out<double> T, Out<int32_t> K, int64_t i_hi,
                           int64_t i_lo) {
        check_points(Q, n, has_third);
        check_mesh(MN, n, has_third);
        need(shaped(allowed, {n, n}), "allowed must be (n, n)");
        need(shaped(T, {n, 5, n}), "T must be (n, 5, n)");
        need(shaped(K, {n, n}), "K must be (n, n)");
        need(0 <= i_lo && i_lo <= i_hi && i_hi <= n - 3, "rows: 0 <= i_lo <= i_hi <= n - 3");
        nb::gil_scoped_release unlocked;
        dense_rows(Q.data(), n, has_third, MN.data(), allowed.data(), T.data(), K.data(), i_hi,
                   i_lo);
    }, nb::arg("Q"), nb::arg("n"), nb::arg("has_third"), nb::arg("MN"), nb::arg("allowed"),
       nb::arg("T").noconvert(), nb::arg("K").noconvert(), nb::arg("i_hi"), nb::arg("i_lo"),
       "Rows i = i_hi .. i_lo (descending) of Liepa's dense recurrence, in place.");

    h.def("sparse_chords", [](In<double> Q, int64_t n, bool has_third, In<double> MN,
                              In<int64_t> keys, In<int64_t> order, In<int64_t> ptr,
                              In<int64_t> apex, Out<double> V, Out<double> TN, Out<int64_t> K) {
        check_points(Q, n, has_third);
        check_mesh(MN, n, has_third);
        need(keys.ndim() == 1, "keys must be 1-D");
        const int64_t C = static_cast<int64_t>(keys.shape(0));
        need(shaped(order, {C}) && shaped(ptr, {C + 1}) && apex.ndim() == 1,
             "order (C,), ptr (C + 1,), apex 1-D");
        need(shaped(V, {C, 2}) && shaped(TN, {C, 4}) && shaped(K, {C}),
             "V (C, 2), TN (C, 4), K (C,)");
        const int64_t* kp = keys.data();
        const int64_t* pp = ptr.data();
        const int64_t* ap = apex.data();
        need(pp[0] == 0 && pp[C] == static_cast<int64_t>(apex.shape(0)), "ptr bounds");
        for (int64_t c = 0; c < C; ++c) {
            need(order.data()[c] >= 0 && order.data()[c] < C, "order: chord ids");
            need(pp[c] <= pp[c + 1], "ptr increasing");
            need(kp[c] >= 0 && kp[c] < n * n && (c == 0 || kp[c - 1] < kp[c]),
                 "keys: sorted chords i * n + j");
            const int64_t i = kp[c] / n, j = kp[c] % n;
            for (int64_t t = pp[c]; t < pp[c + 1]; ++t) need(i < ap[t] && ap[t] < j, "apex");
        }
        nb::gil_scoped_release unlocked;
        sparse_chords(Q.data(), n, has_third, MN.data(), kp, C, order.data(), pp, ap, V.data(),
                      TN.data(), K.data());
    }, nb::arg("Q"), nb::arg("n"), nb::arg("has_third"), nb::arg("MN"), nb::arg("keys"),
       nb::arg("order"), nb::arg("ptr"), nb::arg("apex"), nb::arg("V").noconvert(),
       nb::arg("TN").noconvert(), nb::arg("K").noconvert(),
       "Liepa's recurrence over candidate triangles, chord by chord, in place.");

    h.def("sparse_trace", [](int64_t n, In<int64_t> keys, In<int64_t> K, Out<int64_t> out) {
        need(n >= 3, "a polyline has at least 3 points");
        need(keys.ndim() == 1 && shaped(K, {static_cast<int64_t>(keys.shape(0))}),
             "keys and K: one per chord");
        need(shaped(out, {n - 2, 3}), "out must be (n - 2, 3)");
        const int64_t C = static_cast<int64_t>(keys.shape(0));
        for (int64_t c = 0; c < C; ++c) {
            const int64_t k = K.data()[c], key = keys.data()[c];
            need(k < 0 || (key / n < k && k < key % n), "K: an apex inside its chord");
        }
        nb::gil_scoped_release unlocked;
        return sparse_trace(n, keys.data(), C, K.data(), out.data());
    }, nb::arg("n"), nb::arg("keys"), nb::arg("K"), nb::arg("out").noconvert(),
       "Triangles of the sparse solution into out (n - 2, 3); False if it is incomplete.");

    h.def("state_count", &state_count, nb::arg("n"),
          "Slots of the exact search's compact state array: (n-1)(n-2)(n-3)/3 + 1.");

    h.def("state_offsets", [](int64_t n) {
        need(n >= 3, "a polyline has at least 3 points");
        auto off = arrays::zeros<int64_t>({static_cast<size_t>(n), static_cast<size_t>(n)});
        state_offsets(n, off.data());
        return off;
    }, nb::arg("n"), "First slot of each chord's states (-1 for sides); the root's is last.");

    h.def("leaf_table", [](In<double> Q, int64_t n, In<double> MN, bool has_third) {
        check_points(Q, n, has_third);
        check_mesh(MN, n, has_third);
        auto leaf = arrays::zeros<double>({static_cast<size_t>(n), static_cast<size_t>(n)});
        leaf_table(Q.data(), n, MN.data(), has_third, leaf.data());
        return leaf;
    }, nb::arg("Q"), nb::arg("n"), nb::arg("MN"), nb::arg("has_third"),
       "leaf[s, m]: key of side (s, s+1) between patch triangle (s, s+1, m) and the mesh.");

    auto check_states = [](int64_t n, const In<int64_t>& off, const In<double>& leaf,
                           int64_t states, int64_t L0, int64_t L1) {
        need(shaped(off, {n, n}) && shaped(leaf, {n, n}), "off and leaf must be (n, n)");
        need(states == state_count(n), "states: state_count(n) slots");
        need(2 <= L0 && L0 <= L1 && L1 <= n, "lengths: 2 <= L0 <= L1 <= n");
        std::vector<int64_t> want(static_cast<size_t>(n * n));
        state_offsets(n, want.data());
        need(std::memcmp(want.data(), off.data(), want.size() * sizeof(int64_t)) == 0,
             "off must be state_offsets(n)");
    };

    h.def("bottleneck_lengths", [check_states](In<double> Q, int64_t n, bool has_third,
                                               In<double> MN, In<double> leaf,
                                               In<bool> allowed, In<int64_t> off,
                                               Out<double> B, double U, int64_t L0,
                                               int64_t L1) {
        check_points(Q, n, has_third);
        check_mesh(MN, n, has_third);
        need(shaped(allowed, {n, n}), "allowed must be (n, n)");
        need(B.ndim() == 1, "states must be 1-D");
        check_states(n, off, leaf, static_cast<int64_t>(B.shape(0)), L0, L1);
        nb::gil_scoped_release unlocked;
        bottleneck_lengths(Q.data(), n, has_third, MN.data(), leaf.data(), allowed.data(),
                           off.data(), B.data(), U, L0, L1);
    }, nb::arg("Q"), nb::arg("n"), nb::arg("has_third"), nb::arg("MN"), nb::arg("leaf"),
       nb::arg("allowed"), nb::arg("off"), nb::arg("B").noconvert(), nb::arg("U"),
       nb::arg("L0"), nb::arg("L1"),
       "Pass 1 for chord lengths L0 <= j - i < L1: B[slot] = least max key (> U: +inf).");

    h.def("area_lengths", [check_states](In<double> Q, int64_t n, bool has_third,
                                         In<double> MN, In<double> leaf, In<int64_t> off,
                                         Out<double> A, double M, int64_t L0, int64_t L1) {
        check_points(Q, n, has_third);
        check_mesh(MN, n, has_third);
        need(A.ndim() == 1, "states must be 1-D");
        check_states(n, off, leaf, static_cast<int64_t>(A.shape(0)), L0, L1);
        nb::gil_scoped_release unlocked;
        area_lengths(Q.data(), n, has_third, MN.data(), leaf.data(), off.data(), A.data(), M,
                     L0, L1);
    }, nb::arg("Q"), nb::arg("n"), nb::arg("has_third"), nb::arg("MN"), nb::arg("leaf"),
       nb::arg("off"), nb::arg("A").noconvert(), nb::arg("M"), nb::arg("L0"), nb::arg("L1"),
       "Pass 2 for chord lengths L0 <= j - i < L1: pending slots get their least area.");

    h.def("mark_pending", [](Out<double> states, double M) {
        need(states.ndim() == 1, "states must be 1-D");
        nb::gil_scoped_release unlocked;
        mark_pending(states.data(), static_cast<int64_t>(states.shape(0)), M);
    }, nb::arg("states").noconvert(), nb::arg("M"),
       "Before pass 2: PENDING where pass 1 found <= M (a patch can use it), else +inf.");

    h.def("trace", [check_states](In<double> Q, int64_t n, bool has_third, In<double> MN,
                                  In<double> leaf, In<int64_t> off, In<double> A, double M,
                                  Out<int64_t> out) {
        check_points(Q, n, has_third);
        check_mesh(MN, n, has_third);
        need(A.ndim() == 1, "states must be 1-D");
        check_states(n, off, leaf, static_cast<int64_t>(A.shape(0)), 2, n);
        need(shaped(out, {n - 2, 3}), "out must be (n - 2, 3)");
        nb::gil_scoped_release unlocked;
        return exact_trace(Q.data(), n, has_third, MN.data(), leaf.data(), off.data(), A.data(),
                           M, out.data());
    }, nb::arg("Q"), nb::arg("n"), nb::arg("has_third"), nb::arg("MN"), nb::arg("leaf"),
       nb::arg("off"), nb::arg("A"), nb::arg("M"), nb::arg("out").noconvert(),
       "Triangles of the exact optimum into out (n - 2, 3); False if a state has no apex.");
}

}  // namespace optri
