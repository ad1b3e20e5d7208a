// optri._core.simple: the valid-diagonal mask of one simple polygon (mask.hpp's kernels).
//
// Every call releases the GIL. The long ones (ear_clip, visibility) take a stop flag, an
// int64 array whose first element another thread may set to 1 (Ctrl-C): they then return
// ok False at the next ear or row. The visibility walk's rows run on `threads` OpenMP
// threads; each row writes only itself, so the mask is the serial one's, bit for bit.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "bind.hpp"
#include "mask.hpp"

namespace nb = nanobind;

namespace optri {

namespace {

using Coords = nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Tris = nb::ndarray<const std::int64_t, nb::shape<-1, 3>, nb::c_contig, nb::device::cpu>;
using Stop = nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Mask = nb::ndarray<nb::numpy, bool, nb::ndim<2>>;
using TrisOut = nb::ndarray<nb::numpy, std::int64_t, nb::ndim<2>>;

constexpr std::int64_t kRowStride = 64;  // visibility: thread s walks rows s, s + 64, ...

// A zeroed n x n bool array owned by Python.
Mask new_mask(std::int64_t n, std::uint8_t*& data) {
    const size_t bytes = static_cast<size_t>(std::max<std::int64_t>(n * n, 1));
    data = static_cast<std::uint8_t*>(std::calloc(bytes, 1));
    if (data == nullptr) throw std::bad_alloc();
    nb::capsule owner(data, [](void* p) noexcept { std::free(p); });
    const size_t shape[2] = {static_cast<size_t>(n), static_cast<size_t>(n)};
    return Mask(data, 2, shape, owner);
}

std::int64_t same_length(const Coords& x, const Coords& y) {
    if (x.shape(0) != y.shape(0)) throw nb::value_error("x and y differ in length");
    return static_cast<std::int64_t>(x.shape(0));
}

const volatile std::int64_t* flag(const Stop& stop) {
    if (stop.shape(0) < 1) throw nb::value_error("the stop flag needs one element");
    return stop.data();
}

std::pair<TrisOut, bool> ear_clip(Coords x, Coords y, Stop stop) {
    const std::int64_t n = same_length(x, y);
    if (n < 3) throw nb::value_error("a polygon needs 3 vertices");
    const std::int64_t rows = n - 2;
    auto* tris = new std::int64_t[static_cast<size_t>(3 * rows)];
    nb::capsule owner(tris, [](void* p) noexcept { delete[] static_cast<std::int64_t*>(p); });
    bool ok;
    {
        nb::gil_scoped_release nogil;
        ok = simple::ear_clip(x.data(), y.data(), n, tris, flag(stop));
    }
    const size_t shape[2] = {static_cast<size_t>(rows), 3};
    return {TrisOut(tris, 2, shape, owner), ok};
}

// The visibility walk from every vertex, rows on `threads` threads (see the file comment).
bool visibility_into(const double* x, const double* y, std::int64_t n,
                     const std::int64_t* tris, std::int64_t count,
                     const volatile std::int64_t* stop, int threads, std::uint8_t* out) {
    std::vector<std::int32_t> left;
    if (!simple::left_triangles(tris, count, n, left)) return false;
    std::int64_t bad[kRowStride] = {};  // one flag per stride: no shared write
#if defined(OPTRI_OPENMP)
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
#endif
    for (std::int64_t s = 0; s < kRowStride; ++s) {
        std::vector<std::int64_t> stack(static_cast<size_t>(8 * n));
        for (std::int64_t i = s; i < n; i += kRowStride) {
            if (simple::stopped(stop) ||
                !simple::see_from(x, y, n, tris, left.data(), i, out + i * n, stack.data())) {
                bad[s] = 1;
                break;
            }
        }
    }
    for (std::int64_t s = 0; s < kRowStride; ++s) {
        if (bad[s]) return false;
    }
#if defined(OPTRI_OPENMP)
#pragma omp parallel for schedule(static) num_threads(threads)
#endif
    for (std::int64_t i = 0; i < n; ++i) simple::both_ways(out, n, i);
    (void)threads;
    return true;
}

std::pair<Mask, bool> visibility(Coords x, Coords y, Tris tris, Stop stop, int threads) {
    const std::int64_t n = same_length(x, y);
    std::uint8_t* out;
    Mask mask = new_mask(n, out);
    bool ok;
    {
        nb::gil_scoped_release nogil;
        ok = visibility_into(x.data(), y.data(), n, tris.data(),
                             static_cast<std::int64_t>(tris.shape(0)), flag(stop),
                             std::max(threads, 1), out);
    }
    return {mask, ok};
}

std::pair<Mask, bool> diagonals(Coords x, Coords y, Stop stop, int threads) {
    const std::int64_t n = same_length(x, y);
    if (n < 3) throw nb::value_error("a polygon needs 3 vertices");
    std::uint8_t* out;
    Mask mask = new_mask(n, out);
    bool ok;
    {
        nb::gil_scoped_release nogil;
        std::vector<std::int64_t> tris(static_cast<size_t>(3 * (n - 2)));
        ok = simple::ear_clip(x.data(), y.data(), n, tris.data(), flag(stop)) &&
             visibility_into(x.data(), y.data(), n, tris.data(), n - 2, flag(stop),
                             std::max(threads, 1), out);
    }
    return {mask, ok};
}

Mask scan(Coords x, Coords y) {
    const std::int64_t n = same_length(x, y);
    std::uint8_t* out;
    Mask mask = new_mask(n, out);
    {
        nb::gil_scoped_release nogil;
        simple::valid_mask(x.data(), y.data(), n, out);
    }
    return mask;
}

}  // namespace

void bind_simple(nb::module_& m) {
    nb::module_ s = m.def_submodule(
        "simple", "Valid-diagonal masks of simple polygons (counter-clockwise x, y).");
    s.def("ear_clip", &ear_clip, nb::arg("x"), nb::arg("y"), nb::arg("stop"),
          "(triangles (n-2, 3) int64, ok): some triangulation with no zero-area triangle; "
          "ok False when no ear was found (not simple) or once stop[0] is set.");
    s.def("visibility", &visibility, nb::arg("x"), nb::arg("y"), nb::arg("tris"),
          nb::arg("stop"), nb::arg("threads"),
          "(mask (n, n) bool, ok): vertex visibility through the triangulation tris, rows "
          "on `threads` threads; ok False when tris is not a triangulation of the polygon "
          "or once stop[0] is set.");
    s.def("diagonals", &diagonals, nb::arg("x"), nb::arg("y"), nb::arg("stop"),
          nb::arg("threads"),
          "ear_clip then visibility in one call: (mask, ok), sides as visibility leaves them.");
    s.def("valid_mask", &scan, nb::arg("x"), nb::arg("y"),
          "(n, n) bool by the direct scan (no triangulation needed): internal diagonals "
          "only, sides and the main diagonal False. O(n^2) to O(n^3).");
}

}  // namespace optri
