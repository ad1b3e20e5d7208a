// The min-plus micro-kernels for AVX2: 4 x 16 blocks in 32-byte vectors (16 registers);
// float64 takes the float minimum (AVX2 has no 64-bit integer minimum), float32 the
// integer one, which runs on more vector ports. No multiply: FMA plays no part.
#include "minplus_block.hpp"

#if defined(OPTRI_X86)
#include "minplus_x86_vectors.hpp"

namespace optri {
namespace minplus {

template <>
Kernels<double> kernels_avx2<double>() {
    using x86::Y4d;
    return detail::table<double, Y4d, 4, Y4d, Y4d, Y4d>();
}
template <>
Kernels<float> kernels_avx2<float>() {
    using x86::X4f;
    using x86::Y8f;
    return detail::table<float, Y8f, 4, Y8f, Y8f, X4f>();
}

}  // namespace minplus
}  // namespace optri
#endif
