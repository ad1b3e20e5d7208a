// The min-plus micro-kernels for x86-64's baseline, SSE2 (16-byte vectors, float minimum).
#include "minplus_block.hpp"

#if defined(OPTRI_X86)
#include <emmintrin.h>

namespace optri {
namespace minplus {
namespace {

struct D2 {
    using F = double;
    using Reg = __m128d;
    static constexpr int lanes = 2;
    static Reg load(const F* p) { return _mm_loadu_pd(p); }
    static void store(F* p, Reg v) { _mm_storeu_pd(p, v); }
    static Reg set1(F x) { return _mm_set1_pd(x); }
    static Reg add(Reg x, Reg y) { return _mm_add_pd(x, y); }
    static Reg min(Reg x, Reg y) { return _mm_min_pd(x, y); }
    static Reg inf() { return _mm_set1_pd(std::numeric_limits<F>::infinity()); }
};

struct S4 {
    using F = float;
    using Reg = __m128;
    static constexpr int lanes = 4;
    static Reg load(const F* p) { return _mm_loadu_ps(p); }
    static void store(F* p, Reg v) { _mm_storeu_ps(p, v); }
    static Reg set1(F x) { return _mm_set1_ps(x); }
    static Reg add(Reg x, Reg y) { return _mm_add_ps(x, y); }
    static Reg min(Reg x, Reg y) { return _mm_min_ps(x, y); }
    static Reg inf() { return _mm_set1_ps(std::numeric_limits<F>::infinity()); }
};

}  // namespace

template <>
Kernels<double> kernels_sse2<double>() {
    return detail::table<double, D2, 4, D2, D2, D2>();
}
template <>
Kernels<float> kernels_sse2<float>() {
    return detail::table<float, S4, 4, S4, S4, S4>();
}

}  // namespace minplus
}  // namespace optri
#endif
