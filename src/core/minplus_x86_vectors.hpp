// Vector types of the x86 min-plus micro-kernels (minplus_avx2.cpp, minplus_avx512.cpp):
// include only from a file compiled with AVX2 (and AVX-512 for the Z types).
#pragma once

#include <immintrin.h>

#include <limits>

namespace optri {
namespace minplus {
// Unnamed: each file compiled with its own flags gets its own copies of the blocks (one
// file's AVX-512 code must never stand in for another's AVX2 code at link time).
namespace {
namespace x86 {

// 32 bytes of float64, float minimum.
struct Y4d {
    using F = double;
    using Reg = __m256d;
    static constexpr int lanes = 4;
    static Reg load(const F* p) { return _mm256_loadu_pd(p); }
    static void store(F* p, Reg v) { _mm256_storeu_pd(p, v); }
    static Reg set1(F x) { return _mm256_set1_pd(x); }
    static Reg add(Reg x, Reg y) { return _mm256_add_pd(x, y); }
    static Reg min(Reg x, Reg y) { return _mm256_min_pd(x, y); }
    static Reg inf() { return _mm256_set1_pd(std::numeric_limits<F>::infinity()); }
};

// 32 bytes of float32, integer minimum (non-negative floats order as their bits do).
struct Y8f {
    using F = float;
    using Reg = __m256;
    static constexpr int lanes = 8;
    static Reg load(const F* p) { return _mm256_loadu_ps(p); }
    static void store(F* p, Reg v) { _mm256_storeu_ps(p, v); }
    static Reg set1(F x) { return _mm256_set1_ps(x); }
    static Reg add(Reg x, Reg y) { return _mm256_add_ps(x, y); }
    static Reg min(Reg x, Reg y) {
        return _mm256_castsi256_ps(_mm256_min_epi32(_mm256_castps_si256(x), _mm256_castps_si256(y)));
    }
    static Reg inf() { return _mm256_set1_ps(std::numeric_limits<F>::infinity()); }
};

// 16 bytes of float32, integer minimum (SSE4.1's pminsd).
struct X4f {
    using F = float;
    using Reg = __m128;
    static constexpr int lanes = 4;
    static Reg load(const F* p) { return _mm_loadu_ps(p); }
    static void store(F* p, Reg v) { _mm_storeu_ps(p, v); }
    static Reg set1(F x) { return _mm_set1_ps(x); }
    static Reg add(Reg x, Reg y) { return _mm_add_ps(x, y); }
    static Reg min(Reg x, Reg y) {
        return _mm_castsi128_ps(_mm_min_epi32(_mm_castps_si128(x), _mm_castps_si128(y)));
    }
    static Reg inf() { return _mm_set1_ps(std::numeric_limits<F>::infinity()); }
};

#if defined(__AVX512F__) && defined(__AVX512VL__)
// 32 bytes of float64, integer minimum (AVX-512VL's vpminsq).
struct Y4dInt : Y4d {
    static Reg min(Reg x, Reg y) {
        return _mm256_castsi256_pd(_mm256_min_epi64(_mm256_castpd_si256(x), _mm256_castpd_si256(y)));
    }
};

// 64 bytes of float64, integer minimum.
struct Z8d {
    using F = double;
    using Reg = __m512d;
    static constexpr int lanes = 8;
    static Reg load(const F* p) { return _mm512_loadu_pd(p); }
    static void store(F* p, Reg v) { _mm512_storeu_pd(p, v); }
    static Reg set1(F x) { return _mm512_set1_pd(x); }
    static Reg add(Reg x, Reg y) { return _mm512_add_pd(x, y); }
    static Reg min(Reg x, Reg y) {
        return _mm512_castsi512_pd(_mm512_min_epi64(_mm512_castpd_si512(x), _mm512_castpd_si512(y)));
    }
    static Reg inf() { return _mm512_set1_pd(std::numeric_limits<F>::infinity()); }
};

// 64 bytes of float32, integer minimum.
struct Z16f {
    using F = float;
    using Reg = __m512;
    static constexpr int lanes = 16;
    static Reg load(const F* p) { return _mm512_loadu_ps(p); }
    static void store(F* p, Reg v) { _mm512_storeu_ps(p, v); }
    static Reg set1(F x) { return _mm512_set1_ps(x); }
    static Reg add(Reg x, Reg y) { return _mm512_add_ps(x, y); }
    static Reg min(Reg x, Reg y) {
        return _mm512_castsi512_ps(_mm512_min_epi32(_mm512_castps_si512(x), _mm512_castps_si512(y)));
    }
    static Reg inf() { return _mm512_set1_ps(std::numeric_limits<F>::infinity()); }
};
#endif

}  // namespace x86
}  // namespace
}  // namespace minplus
}  // namespace optri
