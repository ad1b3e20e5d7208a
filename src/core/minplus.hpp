// The min-plus fill: sum of an edge-decomposable weight (perimeter, diagonal).
//
// With w(i, k, j) = e(i, k) + e(k, j) + e(i, j) the table holds E = cost + e, and
//     E(i, j) = 2 e(i, j) + min_k E(i, k) + E(k, j)        (i < k < j),
// a pure min-plus product; a polygon side holds E(i, i + 1) = e(i, i + 1), a chord the
// mask forbids +inf. T[i * n + j] (i < j) holds E(i, j); the fill reads and writes
// nothing on or below the diagonal.
//
// Organised as BLIS is: the framework (minplus.cpp) owns the loops (tiles taken from a
// queue, far and near products, packing of the B operand, recursion of diagonal tiles,
// the edge weights) and never names a vector width; it reads a Plan, chosen at run time
// from optri::simd_level(), whose micro-kernels (minplus_<isa>.cpp) evaluate register
// blocks of `rows x cols` cells. The minimum of a set of sums does not depend on the
// order they are taken in, and every candidate is one addition, so every plan and every
// order gives the same table, bit for bit.
#pragma once

#include <cstdint>
#include <type_traits>

#include "cpu.hpp"
#include "weights.hpp"

namespace optri {
namespace minplus {

// How a micro-kernel takes the minimum. Both give the same bits: table values are sums
// of non-negative lengths (never NaN, never -0.0; +inf allowed), which order as their
// bit patterns do as signed integers.
enum class MinFlavour : int { floating = 0, integer = 1 };

// One register block: for r < rows, q < cols,
//     c[r * ldc + q] = min(c[r * ldc + q], min over t < kn of a[r * lda + t] + b[t * ldb + q]),
// the block held in registers while t runs. "fresh" blocks start from +inf instead of
// reading c (which they only write; kn == 0 writes +inf). The cells of c are never among
// the operands read.
template <class F>
using BlockFn = void (*)(F* c, int64_t ldc, const F* a, int64_t lda, const F* b,
                         int64_t ldb, int64_t kn);

// The micro-kernels of one instruction set for one float type.
template <class F>
struct Kernels {
    BlockFn<F> main;        // rows x cols (the plan's block)
    BlockFn<F> main_fresh;  // the same, fresh
    BlockFn<F> b4x16;       // 4 x 16, for edges of products and the near splits
    BlockFn<F> b4x16_fresh;
    BlockFn<F> b4x8;
    BlockFn<F> b4x4;
};

// What the framework reads: the register block's shape, the splits per pass (k-block),
// the vector width and min flavour of its kernels (for reports), and the kernels.
struct Plan {
    int rows;          // rows of the main block: 8 or 4
    int cols;          // columns of every main block: 16 (also the packed strips' width)
    int kblock;        // splits per pass of a register block over a product
    int vector_width;  // bytes per vector register the kernels use (1 value: portable)
    MinFlavour min_f64, min_f32;
    Simd level;
    const char* isa;   // "avx512-zmm", "avx512-ymm", "avx2", "sse2", "portable"
    Kernels<double> f64;
    Kernels<float> f32;

    template <class F>
    const Kernels<F>& kernels() const {
        if constexpr (std::is_same_v<F, float>) {
            return f32;
        } else {
            return f64;
        }
    }
};

// The plan for simd_level() now.
const Plan& plan();
// The plan for a given level (the level must be available).
const Plan& plan_for(Simd level);

// Tile side for n vertices when the caller has no preference: 64, 128 or 256.
int64_t default_tile(int64_t n);
// Bytes of one thread's buffers in fill: a tile of edge weights, the packed operand.
int64_t worker_bytes(int64_t tile, int64_t itemsize);

// Fill the E-table T (n x n, row-major) above the diagonal, tile by tile, on `threads`
// threads. pts: the vertices; code: 0 perimeter, 1 diagonal; mask: nullptr (every chord
// allowed) or n x n bytes, nonzero where a chord is allowed (polygon sides included).
// done: nt * nt flags (nt = ceil(n / tile)), all 0 on entry: done[ti * nt + tj] becomes 1
// when tile (ti, tj) is finished (progress); done[tj * nt + ti] (below the diagonal)
// becomes 1 when the far splits tile (ti, tj) shares with the tile below it are applied.
// stop: when *stop becomes nonzero, no thread takes a further tile (the call returns
// within about one tile's time). Both may be read and written by other threads meanwhile.
template <class F>
void fill(F* T, int64_t n, const Points& pts, int code, const uint8_t* mask, int64_t tile,
          int threads, int64_t* done, const int64_t* stop);

// fill on the calling thread alone, for small tables (the many-polygon kernel calls it
// per polygon): default_tile(n), its own buffers, no flags.
template <class F>
void fill_serial(F* T, int64_t n, const Points& pts, int code, const uint8_t* mask);

// T[j, i] = T[i, j] below the diagonal, so that split() can read column j as row j.
template <class F>
void mirror(F* T, int64_t n);

// Smallest k (i < k < j) minimizing E(i, k) + E(k, j); -1 if every split is infinite.
// E(k, j) from column j, or from row j of the lower half where `mirrored`.
template <class F>
int64_t split(const F* T, int64_t n, int64_t i, int64_t j, bool mirrored);

// out[i, j] -= e(i, j) above the diagonal (out: n x n float64): costs from an E-table.
void subtract_edges(double* out, int64_t n, const Points& pts, int code);

// The micro-kernel tables of each instruction set (minplus_<isa>.cpp); only call one
// whose level simd_available() lists.
template <class F>
Kernels<F> kernels_portable();
template <class F>
Kernels<F> kernels_sse2();
template <class F>
Kernels<F> kernels_avx2();
template <class F>
Kernels<F> kernels_avx512_zmm();  // 8 x 16 in 64-byte vectors, integer minimum
template <class F>
Kernels<F> kernels_avx512_ymm();  // 4 x 16 in 32-byte vectors, integer minimum (AVX-512VL)

}  // namespace minplus
}  // namespace optri

namespace optri {
namespace minplus {
namespace testing {

// The framework's pieces, for the tests of the bindings (optri._core.minplus): on an
// n x n table with the current plan.
// product(): T[i, j] = min(T[i, j], min over k0 <= k < k1 of T[i, k] + T[k, j]) for
// ia <= i < ib, ja <= j < jb (mask: nullptr, or blocks whose cells are all disallowed
// may be skipped).
template <class F>
void product(F* T, int64_t n, const uint8_t* mask, int64_t ia, int64_t ib, int64_t ja,
             int64_t jb, int64_t k0, int64_t k1);
// far(): the same product from packed rows, no mask; fresh: from +inf, not from T.
template <class F>
void far(F* T, int64_t n, int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0,
         int64_t k1, bool fresh);

}  // namespace testing
}  // namespace minplus
}  // namespace optri
