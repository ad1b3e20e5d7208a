// optri._core: the compiled core. Each part of the core binds its own functions in a
// bind_<part>(module) defined beside its code; this file only calls them.
#include <nanobind/nanobind.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include "bind.hpp"
#include "cpu.hpp"

namespace nb = nanobind;

NB_MODULE(_core, m) {
    m.doc() = "optri's compiled core (see optri.engines.core for the Python side).";

    m.def("simd_levels", []() {
        std::vector<std::string> out;
        for (auto s : optri::simd_available()) out.emplace_back(optri::simd_name(s));
        return out;
    }, "Instruction-set levels this CPU and build can run, lowest first.");
    m.def("simd_level", []() { return std::string(optri::simd_name(optri::simd_level())); },
          "The level the kernels use now.");
    m.def("set_simd", [](const std::string& name) {
        for (auto s : optri::simd_available()) {
            if (name == optri::simd_name(s)) return optri::set_simd(s);
        }
        return false;
    }, nb::arg("name"), "Use level ``name``; False when this CPU or build lacks it.");
    m.def("max_threads", &optri::max_threads,
          "Threads the calling thread may use (OpenMP's limit there; 1 without OpenMP).");
    m.def("has_openmp", &optri::has_openmp);

    optri::bind_all(m);
}
