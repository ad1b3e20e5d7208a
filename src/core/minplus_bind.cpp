// optri._core.minplus: the min-plus fill's bindings, with the argument order and meaning
// of the Python engine's calls (optri.engines.jit).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>

#include <cstring>
#include <stdexcept>
#include <string>

#include "bind.hpp"
#include "minplus.hpp"

namespace nb = nanobind;

namespace optri {

namespace {

using minplus::BlockFn;
using minplus::Kernels;

template <class F>
using Table = nb::ndarray<F, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Pts = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Mask = nb::ndarray<const bool, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Flags = nb::ndarray<int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

void require(bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
}

template <class F>
int64_t square_side(const Table<F>& T) {
    require(T.shape(0) == T.shape(1), "the table must be square");
    return static_cast<int64_t>(T.shape(0));
}

Points points(const Pts& pts, int64_t n) {
    require(static_cast<int64_t>(pts.shape(0)) == n, "pts must have one row per vertex");
    require(pts.shape(1) >= 1 && pts.shape(1) <= 3, "pts must have 1, 2 or 3 columns");
    return Points{pts.data(), n, static_cast<int64_t>(pts.shape(1))};
}

void check_code(int code) {
    require(code == 0 || code == 1, "code must be an edge-decomposable weight's (0 or 1)");
}

const uint8_t* mask_of(const Mask& mask, int64_t n) {
    if (!mask.is_valid()) return nullptr;
    require(static_cast<int64_t>(mask.shape(0)) == n && static_cast<int64_t>(mask.shape(1)) == n,
            "mask must be n x n");
    static_assert(sizeof(bool) == 1, "numpy booleans are bytes");
    return reinterpret_cast<const uint8_t*>(mask.data());
}

template <class F>
void bind_typed(nb::module_& m) {
    m.def(
        "fill",
        [](Table<F> T, Pts pts, int code, Mask mask, int64_t tile, int threads, Flags done,
           Flags stop) {
            const int64_t n = square_side(T);
            const Points p = points(pts, n);
            check_code(code);
            const uint8_t* mk = mask_of(mask, n);
            require(tile >= 1 && threads >= 1, "tile and threads must be positive");
            const int64_t nt = (n + tile - 1) / tile;
            require(static_cast<int64_t>(done.shape(0)) >= nt * nt, "done has too few flags");
            require(stop.shape(0) >= 1, "stop needs one flag");
            nb::gil_scoped_release release;
            minplus::fill<F>(T.data(), n, p, code, mk, tile, threads, done.data(), stop.data());
        },
        nb::arg("T").noconvert(), nb::arg("pts"), nb::arg("code"), nb::arg("mask").none(),
        nb::arg("tile"), nb::arg("threads"), nb::arg("done").noconvert(),
        nb::arg("stop").noconvert());
    m.def(
        "mirror_table",
        [](Table<F> T) {
            const int64_t n = square_side(T);
            nb::gil_scoped_release release;
            minplus::mirror<F>(T.data(), n);
        },
        nb::arg("T").noconvert());
    m.def(
        "split",
        [](Table<F> T, int64_t i, int64_t j, bool mirrored) {
            const int64_t n = square_side(T);
            require(0 <= i && i < j && j < n, "need 0 <= i < j < n");
            return minplus::split<F>(T.data(), n, i, j, mirrored);
        },
        nb::arg("T").noconvert(), nb::arg("i"), nb::arg("j"), nb::arg("mirrored"));
    m.def(
        "_block",
        [](const std::string& kind, Table<F> C, int64_t ci, int64_t cj, Table<F> A, int64_t ai,
           int64_t ak, Table<F> B, int64_t bk, int64_t bj, int64_t kn) {
            const minplus::Plan& pl = minplus::plan();
            const Kernels<F>& K = pl.kernels<F>();
            int64_t rows = 4, cols = 16;
            BlockFn<F> f = nullptr;
            if (kind == "main" || kind == "main_fresh") {
                rows = pl.rows;
                f = kind == "main" ? K.main : K.main_fresh;
            } else if (kind == "4x16" || kind == "4x16_fresh") {
                f = kind == "4x16" ? K.b4x16 : K.b4x16_fresh;
            } else if (kind == "4x8") {
                cols = 8;
                f = K.b4x8;
            } else if (kind == "4x4") {
                cols = 4;
                f = K.b4x4;
            }
            require(f != nullptr, "unknown block " + kind);
            auto inside = [](const Table<F>& X, int64_t r0, int64_t c0, int64_t r, int64_t c) {
                return r0 >= 0 && c0 >= 0 && r >= 0 && c >= 0 &&
                       r0 + r <= static_cast<int64_t>(X.shape(0)) &&
                       c0 + c <= static_cast<int64_t>(X.shape(1));
            };
            require(inside(C, ci, cj, rows, cols) && inside(A, ai, ak, rows, kn) &&
                        inside(B, bk, bj, kn, cols),
                    "block out of bounds");
            const int64_t ldc = C.shape(1), lda = A.shape(1), ldb = B.shape(1);
            f(C.data() + ci * ldc + cj, ldc, A.data() + ai * lda + ak, lda,
              B.data() + bk * ldb + bj, ldb, kn);
        },
        nb::arg("kind"), nb::arg("C").noconvert(), nb::arg("ci"), nb::arg("cj"),
        nb::arg("A").noconvert(), nb::arg("ai"), nb::arg("ak"), nb::arg("B").noconvert(),
        nb::arg("bk"), nb::arg("bj"), nb::arg("kn"),
        "One micro-kernel of the current plan (tests): C block = min(C, A (+) B).");
    m.def(
        "_product",
        [](Table<F> T, Mask mask, int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0,
           int64_t k1) {
            const int64_t n = square_side(T);
            require(0 <= ia && ia <= ib && ib <= n && 0 <= ja && ja <= jb && jb <= n &&
                        0 <= k0 && k1 <= n,
                    "product out of bounds");
            minplus::testing::product<F>(T.data(), n, mask_of(mask, n), ia, ib, ja, jb, k0, k1);
        },
        nb::arg("T").noconvert(), nb::arg("mask").none(), nb::arg("ia"), nb::arg("ib"),
        nb::arg("ja"), nb::arg("jb"), nb::arg("k0"), nb::arg("k1"),
        "The framework's dense product (tests).");
    m.def(
        "_far",
        [](Table<F> T, int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0, int64_t k1,
           bool fresh) {
            const int64_t n = square_side(T);
            require(0 <= ia && ia <= ib && ib <= n && 0 <= ja && ja <= jb && jb <= n &&
                        0 <= k0 && k1 <= n && (!fresh || k0 < k1),
                    "product out of bounds");
            minplus::testing::far<F>(T.data(), n, ia, ib, ja, jb, k0, k1, fresh);
        },
        nb::arg("T").noconvert(), nb::arg("ia"), nb::arg("ib"), nb::arg("ja"), nb::arg("jb"),
        nb::arg("k0"), nb::arg("k1"), nb::arg("fresh") = false,
        "The framework's packed product (tests).");
}

nb::ndarray<nb::numpy, int64_t, nb::ndim<1>> zeros(int64_t size) {
    auto* data = new int64_t[static_cast<size_t>(size > 0 ? size : 1)]();
    nb::capsule owner(data, [](void* p) noexcept { delete[] static_cast<int64_t*>(p); });
    return nb::ndarray<nb::numpy, int64_t, nb::ndim<1>>(data, {static_cast<size_t>(size)}, owner);
}

const char* min_name(minplus::MinFlavour f) {
    return f == minplus::MinFlavour::integer ? "integer" : "float";
}

}  // namespace

void bind_minplus(nb::module_& core) {
    nb::module_ m = core.def_submodule(
        "minplus", "The min-plus fill (sum of an edge-decomposable weight): framework + plan.");
    bind_typed<double>(m);
    bind_typed<float>(m);
    m.def(
        "subtract_edges",
        [](Table<double> out, Pts pts, int code) {
            const int64_t n = square_side(out);
            const Points p = points(pts, n);
            check_code(code);
            nb::gil_scoped_release release;
            minplus::subtract_edges(out.data(), n, p, code);
        },
        nb::arg("out").noconvert(), nb::arg("pts"), nb::arg("code"),
        "``out[i, j] -= e(i, j)`` above the diagonal: costs from an exported E-table.");
    m.def(
        "tile_flags",
        [](int64_t n, int64_t tile) {
            require(n >= 0 && tile >= 1, "need n >= 0 and tile >= 1");
            const int64_t nt = (n + tile - 1) / tile;
            return nb::make_tuple(zeros(nt * nt), zeros(1));
        },
        nb::arg("n"), nb::arg("tile"), "Fresh ``(done, stop)`` int64 flags for ``fill``.");
    m.def("worker_bytes", &minplus::worker_bytes, nb::arg("tile"), nb::arg("itemsize"),
          "Bytes of one thread's buffers in ``fill``.");
    m.def("default_tile", &minplus::default_tile, nb::arg("n"));
    m.def(
        "plan",
        []() {
            const minplus::Plan& p = minplus::plan();
            nb::dict d;
            d["level"] = simd_name(p.level);
            d["isa"] = p.isa;
            d["rows"] = p.rows;
            d["cols"] = p.cols;
            d["kblock"] = p.kblock;
            d["vector_width"] = p.vector_width;
            d["min_float64"] = min_name(p.min_f64);
            d["min_float32"] = min_name(p.min_f32);
            return d;
        },
        "The plan of the current SIMD level: block shape, k-block, vector bytes, minima.");
}

}  // namespace optri
