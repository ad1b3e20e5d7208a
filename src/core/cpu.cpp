#include "cpu.hpp"

#include <atomic>

#if defined(OPTRI_X86)
#if defined(_MSC_VER)
#include <intrin.h>
#else
#include <cpuid.h>
#endif
#endif

#if defined(OPTRI_OPENMP)
#include <omp.h>
#endif

namespace optri {

namespace {

#if defined(OPTRI_X86)
void cpuid(unsigned leaf, unsigned sub, unsigned r[4]) {
#if defined(_MSC_VER)
    int regs[4];
    __cpuidex(regs, static_cast<int>(leaf), static_cast<int>(sub));
    for (int i = 0; i < 4; ++i) r[i] = static_cast<unsigned>(regs[i]);
#else
    __cpuid_count(leaf, sub, r[0], r[1], r[2], r[3]);
#endif
}

unsigned long long xgetbv0() {
#if defined(_MSC_VER)
    return _xgetbv(0);
#else
    unsigned lo, hi;
    __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    return (static_cast<unsigned long long>(hi) << 32) | lo;
#endif
}

Simd detect() {
    unsigned r[4];
    cpuid(0, 0, r);
    const unsigned max_leaf = r[0];
    cpuid(1, 0, r);
    const bool osxsave = (r[2] >> 27) & 1u;
    const bool fma = (r[2] >> 12) & 1u;
    const bool avx = (r[2] >> 28) & 1u;
    if (!osxsave || !avx || max_leaf < 7) return Simd::baseline;
    const unsigned long long xcr0 = xgetbv0();
    const bool ymm = (xcr0 & 0x6) == 0x6;      // SSE and AVX state saved by the OS
    const bool zmm = (xcr0 & 0xe6) == 0xe6;    // plus opmask and the upper ZMM halves
    cpuid(7, 0, r);
    const bool avx2 = (r[1] >> 5) & 1u;
    const bool f = (r[1] >> 16) & 1u, dq = (r[1] >> 17) & 1u;
    const bool bw = (r[1] >> 30) & 1u, vl = (r[1] >> 31) & 1u;
    if (ymm && zmm && avx2 && fma && f && dq && bw && vl) return Simd::avx512;
    if (ymm && avx2 && fma) return Simd::avx2;
    return Simd::baseline;
}
#elif defined(OPTRI_ARM64)
Simd detect() { return Simd::baseline; }
#else
Simd detect() { return Simd::portable; }
#endif

const Simd kBest = detect();
std::atomic<int> g_level{static_cast<int>(kBest)};

}  // namespace

const char* simd_name(Simd s) {
    switch (s) {
        case Simd::portable: return "portable";
        case Simd::baseline: return "baseline";
        case Simd::avx2: return "avx2";
        case Simd::avx512: return "avx512";
    }
    return "?";
}

std::vector<Simd> simd_available() {
    std::vector<Simd> out;
    for (int s = 0; s <= static_cast<int>(kBest); ++s) out.push_back(static_cast<Simd>(s));
    return out;
}

Simd simd_best() { return kBest; }

Simd simd_level() { return static_cast<Simd>(g_level.load(std::memory_order_relaxed)); }

bool set_simd(Simd s) {
    if (static_cast<int>(s) < 0 || static_cast<int>(s) > static_cast<int>(kBest)) return false;
    g_level.store(static_cast<int>(s), std::memory_order_relaxed);
    return true;
}

int max_threads() {
#if defined(OPTRI_OPENMP)
    return omp_get_max_threads();
#else
    return 1;
#endif
}

bool has_openmp() {
#if defined(OPTRI_OPENMP)
    return true;
#else
    return false;
#endif
}

}  // namespace optri
