// The parts of the core, each bound by a function defined beside its code.
#pragma once

#include <nanobind/nanobind.h>

namespace optri {

void bind_all(nanobind::module_& m);
void bind_predicates(nanobind::module_& m);
void bind_domains(nanobind::module_& m);
void bind_holes(nanobind::module_& m);
void bind_contours(nanobind::module_& m);
void bind_generic(nanobind::module_& m);
void bind_minplus(nanobind::module_& m);
void bind_many(nanobind::module_& m);
void bind_simple(nanobind::module_& m);
void bind_refine(nanobind::module_& m);
void bind_topology(nanobind::module_& m);
void bind_fair(nanobind::module_& m);

}  // namespace optri
