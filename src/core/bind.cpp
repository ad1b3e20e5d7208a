// One line a part: a part's bind_<part> adds its functions to optri._core.
#include "bind.hpp"

namespace optri {

void bind_all(nanobind::module_& m) {
    (void)m;
    bind_predicates(m);
    bind_domains(m);
    bind_holes(m);
    bind_contours(m);
    bind_generic(m);
    bind_minplus(m);
    bind_many(m);
    bind_simple(m);
    bind_refine(m);
    bind_topology(m);
    bind_fair(m);
}

}  // namespace optri
