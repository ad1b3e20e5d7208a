// The register block of the min-plus micro-kernels, written once over a vector type.
//
// Each minplus_<isa>.cpp defines small vector types (load, store, broadcast, add, min)
// with its instruction set's intrinsics and instantiates block<> with them; this header
// holds no intrinsics. A block of R x C cells lives in R * C / lanes accumulators for
// the whole loop over the splits: each split loads C values of a row of B, broadcasts
// one value of A per row, and takes R * C / lanes additions and minima.
#pragma once

#include <cstdint>
#include <limits>

#include "minplus.hpp"

namespace optri {
namespace minplus {
namespace detail {

template <class V, int R, int C, bool Fresh>
void block(typename V::F* c, int64_t ldc, const typename V::F* a, int64_t lda,
           const typename V::F* b, int64_t ldb, int64_t kn) {
    using Reg = typename V::Reg;
    constexpr int L = V::lanes;
    constexpr int NV = C / L;
    static_assert(C % L == 0, "a block's columns are whole vectors");
    Reg acc[R][NV];
    for (int r = 0; r < R; ++r) {
        for (int v = 0; v < NV; ++v) acc[r][v] = Fresh ? V::inf() : V::load(c + r * ldc + v * L);
    }
    for (int64_t t = 0; t < kn; ++t) {
        Reg bv[NV];
        for (int v = 0; v < NV; ++v) bv[v] = V::load(b + t * ldb + v * L);
        for (int r = 0; r < R; ++r) {
            const Reg av = V::set1(a[r * lda + t]);
            for (int v = 0; v < NV; ++v) acc[r][v] = V::min(acc[r][v], V::add(av, bv[v]));
        }
    }
    for (int r = 0; r < R; ++r) {
        for (int v = 0; v < NV; ++v) V::store(c + r * ldc + v * L, acc[r][v]);
    }
}

// The kernel table of an instruction set: V16 / V8 / V4 are its vector types for blocks of
// 16, 8 and 4 columns (a vector never wider than the block), Vmain that of the main block.
template <class F, class VMain, int Rows, class V16, class V8, class V4>
Kernels<F> table() {
    Kernels<F> k;
    k.main = &block<VMain, Rows, 16, false>;
    k.main_fresh = &block<VMain, Rows, 16, true>;
    k.b4x16 = &block<V16, 4, 16, false>;
    k.b4x16_fresh = &block<V16, 4, 16, true>;
    k.b4x8 = &block<V8, 4, 8, false>;
    k.b4x4 = &block<V4, 4, 4, false>;
    return k;
}

// Plain C++: one value a "vector"; the compiler may vectorize for the target's baseline.
template <class T>
struct Scalar {
    using F = T;
    using Reg = T;
    static constexpr int lanes = 1;
    static Reg load(const F* p) { return *p; }
    static void store(F* p, Reg v) { *p = v; }
    static Reg set1(F x) { return x; }
    static Reg add(Reg x, Reg y) { return x + y; }
    static Reg min(Reg x, Reg y) { return y < x ? y : x; }
    static Reg inf() { return std::numeric_limits<F>::infinity(); }
};

}  // namespace detail
}  // namespace minplus
}  // namespace optri
