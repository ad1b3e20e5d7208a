// CPU features and the instruction-set level the kernels run at.
//
// The level is chosen once, at import, from what the CPU (and the OS, for the wide
// registers' state) supports; OPTRI_SIMD, read by the Python side, may lower it for
// tests and comparisons. Kernels ask simd_level() and never test features themselves.
#pragma once

#include <string>
#include <vector>

namespace optri {

// Ordered: a higher level can run every lower one's kernels.
enum class Simd : int {
    portable = 0,  // plain C++ loops the compiler may vectorize for the target's baseline
    baseline = 1,  // SSE2 on x86-64, NEON on ARM64: always there on those CPUs
    avx2 = 2,      // AVX2 + FMA (x86-64 only)
    avx512 = 3,    // AVX-512 F/DQ/VL/BW (x86-64 only)
};

const char* simd_name(Simd s);
// Levels this CPU and this build can run, lowest first.
std::vector<Simd> simd_available();
// The best available level.
Simd simd_best();
// The level the kernels use now (simd_best() unless set_simd lowered it).
Simd simd_level();
// Use level s; false (and nothing changed) when it is not available.
bool set_simd(Simd s);

// Threads the calling thread may use: OpenMP's limit there (OMP_NUM_THREADS,
// threadpoolctl), 1 in a build without OpenMP.
int max_threads();
// Whether this build has OpenMP.
bool has_openmp();

}  // namespace optri
