// optri._core.predicates: the exact predicates of predicates.hpp over rows of an array, for
// tests (against exact rational arithmetic) and for Python code that wants many signs.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <cstdint>

#include "bind.hpp"
#include "predicates.hpp"

namespace nb = nanobind;

namespace optri {

namespace {

using Rows = nb::ndarray<const double, nb::shape<-1, 6>, nb::c_contig, nb::device::cpu>;
using Signs = nb::ndarray<nb::numpy, std::int8_t, nb::ndim<1>>;

template <int (*F)(double, double, double, double, double, double)>
Signs signs(Rows pts) {
    const std::size_t m = pts.shape(0);
    auto* out = new std::int8_t[m];
    const double* p = pts.data();
    {
        nb::gil_scoped_release nogil;
        for (std::size_t r = 0; r < m; ++r) {
            const double* q = p + 6 * r;
            out[r] = static_cast<std::int8_t>(F(q[0], q[1], q[2], q[3], q[4], q[5]));
        }
    }
    nb::capsule owner(out, [](void* d) noexcept { delete[] static_cast<std::int8_t*>(d); });
    return Signs(out, {m}, owner);
}

int between(double ax, double ay, double bx, double by, double cx, double cy) {
    return strictly_between(ax, ay, bx, by, cx, cy) ? 1 : 0;
}

}  // namespace

void bind_predicates(nb::module_& m) {
    nb::module_ p = m.def_submodule("predicates", "Exact predicates over rows (ax ay bx by cx cy).");
    p.def("orient_sign", &signs<orient_sign>, nb::arg("pts"),
          "Exact sign of each row's turn a -> b -> c (int8: +1 left, -1 right, 0 collinear).");
    p.def("orient_exact", &signs<orient_exact>, nb::arg("pts"),
          "orient_sign without the float filter (expansions, then integers).");
    p.def("orient_bigint", &signs<orient_bigint>, nb::arg("pts"),
          "orient_sign by integer arithmetic alone.");
    p.def("strictly_between", &signs<between>, nb::arg("pts"),
          "1 where c lies strictly between a and b (for c collinear with ab), else 0.");
}

}  // namespace optri
