// The min-plus micro-kernels in plain C++ (no intrinsics): ARM64, other targets, and
// OPTRI_SIMD=portable. Compiled for the target's baseline.
#include "minplus_block.hpp"

namespace optri {
namespace minplus {

template <class F>
Kernels<F> kernels_portable() {
    using S = detail::Scalar<F>;
    return detail::table<F, S, 4, S, S, S>();
}

template Kernels<double> kernels_portable<double>();
template Kernels<float> kernels_portable<float>();

}  // namespace minplus
}  // namespace optri
