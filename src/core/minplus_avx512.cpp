// The min-plus micro-kernels for AVX-512 (F, DQ, VL, BW), integer minimum throughout:
// * zmm: 8 x 16 blocks in 64-byte vectors, filling the 32 vector registers, where the
//   CPU has two full-width 512-bit ports;
// * ymm: 4 x 16 blocks in 32-byte vectors with AVX-512VL's 64-bit integer minimum, where
//   512-bit instructions run as two 256-bit halves (AMD), and the integer minimum runs on
//   ports the floating-point one cannot use.
#include "minplus_block.hpp"

#if defined(__GNUC__) && !defined(__clang__)
// GCC 12 warns of an undefined source in its own _mm512_set1_* (a false positive)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

#if defined(OPTRI_X86)
#include "minplus_x86_vectors.hpp"

namespace optri {
namespace minplus {

template <>
Kernels<double> kernels_avx512_zmm<double>() {
    using namespace x86;
    return detail::table<double, Z8d, 8, Z8d, Z8d, Y4dInt>();
}
template <>
Kernels<float> kernels_avx512_zmm<float>() {
    using namespace x86;
    return detail::table<float, Z16f, 8, Z16f, Y8f, X4f>();
}
template <>
Kernels<double> kernels_avx512_ymm<double>() {
    using namespace x86;
    return detail::table<double, Y4dInt, 4, Y4dInt, Y4dInt, Y4dInt>();
}
template <>
Kernels<float> kernels_avx512_ymm<float>() {
    using namespace x86;
    return detail::table<float, Y8f, 4, Y8f, Y8f, X4f>();
}

}  // namespace minplus
}  // namespace optri
#endif
