// The min-plus fill's framework: tiles, their queue and flags, far and near products,
// packing, the recursion of diagonal tiles, edge weights. It never names a vector width:
// the register blocks are the plan's (minplus.hpp).
//
// Every split is evaluated by a register block, in an order that makes almost all of the
// work a dense product of finished cells:
// * tiles of tile x tile cells, taken from a queue by each thread; a tile starts when the
//   tiles left of it and below it are done;
// * in a tile, the "far" splits (between its rows and its columns) first: one dense
//   product, whose B rows are first copied into a contiguous buffer along table rows
//   (far()). A tile on an even tile-diagonal applies most of the far splits of the tile
//   above it too, from the same copy (run_tile());
// * then the "near" splits, by recursive halving of the tile (bottom-left, bottom-right,
//   top-left, top-right): before a quarter is solved, the splits through quarters already
//   finished are applied to it as dense products (the large ones packed as the far ones);
//   only blocks of at most kLeaf rows or columns go cell by cell.
// A diagonal tile (a triangle) halves into two triangles and the square between them.
//
// The framework is compiled twice over: with a chord mask and without (Masked), so that
// the fill without a mask tests none.
#include "minplus.hpp"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <limits>
#include <mutex>
#include <new>
#include <stdexcept>
#include <thread>
#include <vector>

#if defined(OPTRI_OPENMP)
#include <omp.h>
#endif
#if defined(OPTRI_X86) && defined(_MSC_VER)
#include <intrin.h>
#elif defined(OPTRI_X86)
#include <cpuid.h>
#endif

namespace optri {
namespace minplus {

namespace {

constexpr int64_t kCols = 16;  // columns of every register block of a dense product
// splits per pass of a register block over a product: a block's A rows stay in L1
constexpr int64_t kKblock = 256;
// rows of far()'s packed buffer per strip: one more than a block of splits, so that the
// copy's stores of a table row (one per strip) do not all fall in one L1 set
constexpr int64_t kStrip = kKblock + 1;
// cells of B from which a near product packs B as far() does (smaller: the copy costs
// more than it saves)
constexpr int64_t kPack = 64 * 64;
constexpr int64_t kLeaf = 4;  // blocks this small (rows or columns) are solved cell by cell
constexpr int kSpins = 2000;  // polls of a tile's flag before a waiting thread yields its CPU

static_assert(sizeof(std::atomic<int64_t>) == sizeof(int64_t), "flags are plain int64");

inline int64_t load_acquire(const int64_t* p) {
    return reinterpret_cast<const std::atomic<int64_t>*>(p)->load(std::memory_order_acquire);
}

inline void store_release(int64_t* p, int64_t v) {
    reinterpret_cast<std::atomic<int64_t>*>(p)->store(v, std::memory_order_release);
}

// Wait until *p is set: spin briefly, then yield between polls (on a machine with more
// runnable threads than cores the thread waited on may be descheduled).
inline void wait_done(const int64_t* p) {
    int spins = 0;
    while (load_acquire(p) == 0) {
        if (++spins >= kSpins) std::this_thread::yield();
    }
}

// Ask for a cache line to be written (prefetchw where the CPU has it): taking it from
// another core overlaps the work that follows. Nothing but timing changes.
inline void claim(const void* p) {
#if defined(__GNUC__) || defined(__clang__)
    __builtin_prefetch(p, 1, 3);
#else
    (void)p;
#endif
}

template <class F>
inline F mn(F x, F y) {
    return y < x ? y : x;
}

template <class F>
constexpr F kInf = std::numeric_limits<F>::infinity();

// Whether the tile below a tile on tile-diagonal d applies their shared far splits: a tile
// on an odd tile-diagonal d >= 5 and the tile below it, on d - 1.
inline bool below_shares(int64_t d) { return d % 2 == 1 && d >= 5; }

// Where to halve `size`: the largest `unit` times a power of two below it (so that the
// halving ends in the 16 x 16 and 8 x 8 blocks of straight-line code and 4 x 4 leaves);
// below 2 unit, about half.
inline int64_t half(int64_t size, int64_t unit) {
    int64_t h = size / 2;
    if (h >= unit) {
        h = unit;
        while (2 * h < size) h *= 2;
    }
    return h;
}

// One thread's view of a fill: the table, the plan's kernels, its buffers.
template <class F, bool Masked>
struct Filler {
    F* T;
    int64_t n;
    const Kernels<F>* K;
    int64_t rows;           // rows of the main block
    const uint8_t* mask;    // Masked only: n x n, nonzero where a chord is allowed
    const Points* pts;
    int code;
    double* W = nullptr;    // e(i, j) of the current tile: W[(i - wi) * wld + j - wj]
    int64_t wi = 0, wj = 0, wld = 0;
    F* P = nullptr;         // far()'s packed rows: kStrip rows of kCols a strip

    F* at(int64_t i, int64_t j) const { return T + i * n + j; }
    F get(int64_t i, int64_t j) const { return T[i * n + j]; }
    double edge(int64_t i, int64_t j) const { return W[(i - wi) * wld + (j - wj)]; }

    // Whether any cell of rows i0..i1-1, columns j0..j1-1 is an allowed chord.
    bool any_allowed(bool use_mask, int64_t i0, int64_t i1, int64_t j0, int64_t j1) const {
        if (!Masked || !use_mask) return true;
        for (int64_t i = i0; i < i1; ++i) {
            for (int64_t j = j0; j < j1; ++j) {
                if (mask[i * n + j]) return true;
            }
        }
        return false;
    }

    // min(best, min over k0 <= k < k1 of T[i, k] + T[k, j]): row i, column j.
    F colmin(F best, int64_t i, int64_t j, int64_t k0, int64_t k1) const {
        for (int64_t k = k0; k < k1; ++k) best = mn(best, F(get(i, k) + get(k, j)));
        return best;
    }

    void fill_inf(int64_t ia, int64_t ib, int64_t ja, int64_t jb) {
        for (int64_t i = ia; i < ib; ++i) {
            for (int64_t j = ja; j < jb; ++j) *at(i, j) = kInf<F>;
        }
    }

    // Register block rows i..i+3 x `cols` (16, 8 or 4) columns from j, kn splits from k0;
    // skipped when no cell of it is an allowed chord.
    void block4(bool use_mask, int64_t i, int64_t j, int64_t k0, int64_t kn, int cols) {
        if (!any_allowed(use_mask, i, i + 4, j, j + cols)) return;
        BlockFn<F> f = cols == 16 ? K->b4x16 : cols == 8 ? K->b4x8 : K->b4x4;
        f(at(i, j), n, at(i, k0), n, at(k0, j), n, kn);
    }

    // T[i, j] = min(T[i, j], min over k0 <= k < k1 of T[i, k] + T[k, j]) for rows
    // ia <= i < ib, columns ja <= j < jb; every operand cell must be final. The plan's
    // main blocks first where it has more than 4 rows, the rest in 4-row blocks (16, 8, 4
    // columns, then cell by cell at the edges), kKblock splits at a time. With a mask,
    // blocks whose cells are all disallowed are skipped (they end up +inf either way).
    void product(bool use_mask, int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0,
                 int64_t k1) {
        if (rows == 4) {
            product4(use_mask, ia, ib, ja, jb, k0, k1);
            return;
        }
        const int64_t ir = ia + (ib - ia) / rows * rows;
        const int64_t jf = ja + (jb - ja) / kCols * kCols;
        for (int64_t kb = k0; kb < k1; kb += kKblock) {
            const int64_t kn = std::min(k1, kb + kKblock) - kb;
            for (int64_t i = ia; i < ir; i += rows) {
                for (int64_t j = ja; j < jf; j += kCols) {
                    if (any_allowed(use_mask, i, i + rows, j, j + kCols)) {
                        K->main(at(i, j), n, at(i, kb), n, at(kb, j), n, kn);
                    }
                }
            }
        }
        product4(use_mask, ia, ir, jf, jb, k0, k1);
        product4(use_mask, ir, ib, ja, jb, k0, k1);
    }

    void product4(bool use_mask, int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0,
                  int64_t k1) {
        if (k1 <= k0 || ib <= ia || jb <= ja) return;
        for (int64_t kb = k0; kb < k1; kb += kKblock) {
            const int64_t ke = std::min(k1, kb + kKblock);
            int64_t i = ia;
            for (; i + 4 <= ib; i += 4) {
                int64_t j = ja;
                for (; j + 16 <= jb; j += 16) block4(use_mask, i, j, kb, ke - kb, 16);
                for (int cols : {8, 4}) {
                    if (j + cols <= jb) {
                        block4(use_mask, i, j, kb, ke - kb, cols);
                        j += cols;
                    }
                }
                for (int64_t r = i; r < i + 4; ++r) {
                    for (int64_t c = j; c < jb; ++c) *at(r, c) = colmin(get(r, c), r, c, kb, ke);
                }
            }
            for (int64_t r = i; r < ib; ++r) {
                for (int64_t c = ja; c < jb; ++c) *at(r, c) = colmin(get(r, c), r, c, kb, ke);
            }
        }
    }

    // product() without a mask, from packed rows: for each block of kKblock splits, the
    // rows B[k, j:j + 16] of each 16-column strip are first copied into P (strip s at rows
    // s * kStrip on), along table rows: row k's whole strips, one contiguous run of the
    // table, go to the k-th row of every strip. The register block then reads its B
    // operand as one contiguous run. Columns and rows beyond whole strips and blocks go
    // through product(). `fresh` (with k0 < k1): the cells start from +inf, not from the
    // table, whose values are not read: the first block of splits writes the whole strips
    // without loading them, and only the cells beyond them are set to +inf first.
    void far(int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0, int64_t k1,
             bool fresh = false) {
        const int64_t jf = ja + (jb - ja) / kCols * kCols;
        const int64_t ir = ia + (ib - ia) / rows * rows;
        const int64_t strips = (jf - ja) / kCols;
        if (fresh) {
            fill_inf(ia, ib, jf, jb);
            fill_inf(ir, ib, ja, jf);
        }
        for (int64_t kb = k0; kb < k1; kb += kKblock) {
            const int64_t kn = std::min(k1, kb + kKblock) - kb;
            for (int64_t t = 0; t < kn; ++t) {
                const F* src = at(kb + t, ja);
                for (int64_t s = 0; s < strips; ++s) {
                    std::memcpy(P + (s * kStrip + t) * kCols, src + s * kCols, kCols * sizeof(F));
                }
            }
            const BlockFn<F> f = fresh && kb == k0 ? K->main_fresh : K->main;
            for (int64_t i = ia; i < ir; i += rows) {
                for (int64_t s = 0; s < strips; ++s) {
                    f(at(i, ja + kCols * s), n, at(i, kb), n, P + s * kStrip * kCols, kCols, kn);
                }
            }
        }
        product(false, ia, ib, jf, jb, k0, k1);
        product(false, ir, ib, ja, jf, k0, k1);
    }

    // product() between the quarters of a block of near splits; without a mask, one whose
    // B holds kPack cells or more is packed first.
    void near(int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0, int64_t k1) {
        if (!Masked && (k1 - k0) * (jb - ja) >= kPack) {
            far(ia, ib, ja, jb, k0, k1);
        } else {
            product(Masked, ia, ib, ja, jb, k0, k1);
        }
    }

    // Store and return E(i, j) = best + 2 e(i, j) (a side: e; disallowed: +inf), as stored.
    F final_cell(int64_t i, int64_t j, F best) {
        if (j == i + 1) {
            const F v = F(edge(i, j));
            *at(i, j) = v;
            return v;
        }
        return final_chord(i, j, best);
    }

    F final_chord(int64_t i, int64_t j, F best) {
        double v = double(best) + 2.0 * edge(i, j);
        if (Masked && !mask[i * n + j]) v = kInf<double>;  // not a diagonal: never used
        const F out = F(v);
        *at(i, j) = out;
        return out;
    }

    // Final value of cell (i, j): its splits i < k < b and c <= k < j, then 2 e; every
    // other split must be applied already.
    void cell(int64_t i, int64_t j, int64_t b, int64_t c) {
        F best = colmin(get(i, j), i, j, i + 1, std::min(b, j));
        best = colmin(best, i, j, c, j);
        final_cell(i, j, best);
    }

    // Block rows [a, a + 4) x columns [c, c + 4), a + 4 <= c, in straight-line code. xrq is
    // cell (a + r, c + q); its splits run through the rows' triangle (arr', final) and the
    // cells below it (xr'q), and through the cells left of it (xrq') and the columns'
    // triangle (bq'q, final). Only cell (a + 3, c) can be a polygon side.
    void leaf4(int64_t a, int64_t c) {
        const F a01 = get(a, a + 1), a02 = get(a, a + 2), a03 = get(a, a + 3);
        const F a12 = get(a + 1, a + 2), a13 = get(a + 1, a + 3), a23 = get(a + 2, a + 3);
        const F b01 = get(c, c + 1), b02 = get(c, c + 2), b03 = get(c, c + 3);
        const F b12 = get(c + 1, c + 2), b13 = get(c + 1, c + 3), b23 = get(c + 2, c + 3);
        const int64_t c1 = c + 1, c2 = c + 2, c3 = c + 3;
        int64_t i = a + 3;
        F t0 = get(i, c), t1 = get(i, c1), t2 = get(i, c2), t3 = get(i, c3);
        const F x30 = final_cell(i, c, t0);
        const F x31 = final_chord(i, c1, mn(t1, F(x30 + b01)));
        const F x32 = final_chord(i, c2, mn(mn(t2, F(x30 + b02)), F(x31 + b12)));
        F m = mn(mn(t3, F(x30 + b03)), F(x31 + b13));
        const F x33 = final_chord(i, c3, mn(m, F(x32 + b23)));
        i = a + 2;
        t0 = get(i, c), t1 = get(i, c1), t2 = get(i, c2), t3 = get(i, c3);
        const F x20 = final_chord(i, c, mn(t0, F(a23 + x30)));
        m = mn(t1, F(a23 + x31));
        const F x21 = final_chord(i, c1, mn(m, F(x20 + b01)));
        m = mn(mn(t2, F(a23 + x32)), F(x20 + b02));
        const F x22 = final_chord(i, c2, mn(m, F(x21 + b12)));
        m = mn(mn(t3, F(a23 + x33)), mn(F(x20 + b03), F(x21 + b13)));
        const F x23 = final_chord(i, c3, mn(m, F(x22 + b23)));
        i = a + 1;
        t0 = get(i, c), t1 = get(i, c1), t2 = get(i, c2), t3 = get(i, c3);
        const F x10 = final_chord(i, c, mn(mn(t0, F(a12 + x20)), F(a13 + x30)));
        m = mn(mn(t1, F(a12 + x21)), F(a13 + x31));
        const F x11 = final_chord(i, c1, mn(m, F(x10 + b01)));
        m = mn(mn(t2, F(a12 + x22)), mn(F(a13 + x32), F(x10 + b02)));
        const F x12 = final_chord(i, c2, mn(m, F(x11 + b12)));
        m = mn(mn(mn(t3, F(a12 + x23)), F(a13 + x33)),
               mn(mn(F(x10 + b03), F(x11 + b13)), F(x12 + b23)));
        const F x13 = final_chord(i, c3, m);
        i = a;
        t0 = get(i, c), t1 = get(i, c1), t2 = get(i, c2), t3 = get(i, c3);
        m = mn(mn(t0, F(a01 + x10)), mn(F(a02 + x20), F(a03 + x30)));
        const F x00 = final_chord(i, c, m);
        m = mn(mn(t1, F(a01 + x11)), mn(F(a02 + x21), F(a03 + x31)));
        const F x01 = final_chord(i, c1, mn(m, F(x00 + b01)));
        m = mn(mn(mn(t2, F(a01 + x12)), mn(F(a02 + x22), F(a03 + x32))), F(x00 + b02));
        const F x02 = final_chord(i, c2, mn(m, F(x01 + b12)));
        m = mn(mn(mn(t3, F(a01 + x13)), mn(F(a02 + x23), F(a03 + x33))),
               mn(mn(F(x00 + b03), F(x01 + b13)), F(x02 + b23)));
        final_chord(i, c3, m);
    }

    // square() of an 8 x 8 block: four leaves, the products between them inline.
    void square8(int64_t a, int64_t c) {
        leaf4(a + 4, c);
        block4(Masked, a + 4, c + 4, c, 4, 4);
        leaf4(a + 4, c + 4);
        block4(Masked, a, c, a + 4, 4, 4);
        leaf4(a, c);
        block4(Masked, a, c + 4, a + 4, 4, 4);
        block4(Masked, a, c + 4, c, 4, 4);
        leaf4(a, c + 4);
    }

    // square() of a 16 x 16 block: four 8 x 8 blocks, the products between them.
    void square16(int64_t a, int64_t c) {
        square8(a + 8, c);
        for (int64_t r = a + 8; r < a + 16; r += 4) block4(Masked, r, c + 8, c, 8, 8);
        square8(a + 8, c + 8);
        for (int64_t r = a; r < a + 8; r += 4) block4(Masked, r, c, a + 8, 8, 8);
        square8(a, c);
        for (int64_t r = a; r < a + 8; r += 4) {
            block4(Masked, r, c + 8, a + 8, 8, 8);
            block4(Masked, r, c + 8, c, 8, 8);
        }
        square8(a, c + 8);
    }

    // Finish block rows [a, b) x columns [c, e), b <= c: its near splits. On entry every
    // split outside (a, b) + [c, e) is applied, and the cells left of the block (its rows)
    // and below it (its columns) are final. Quarters in order bottom-left, bottom-right,
    // top-left, top-right; before each, the splits through the quarters already finished.
    void square(int64_t a, int64_t b, int64_t c, int64_t e) {
        if (b - a == 16 && e - c == 16) {
            square16(a, c);
            return;
        }
        if (b - a == 8 && e - c == 8) {
            square8(a, c);
            return;
        }
        if (b - a == 4 && e - c == 4) {
            leaf4(a, c);
            return;
        }
        if (b - a <= kLeaf || e - c <= kLeaf) {
            for (int64_t i = b - 1; i >= a; --i) {
                for (int64_t j = c; j < e; ++j) cell(i, j, b, c);
            }
            return;
        }
        const int64_t m = b - half(b - a, 4);   // bottom rows [m, b), top rows [a, m)
        const int64_t m2 = c + half(e - c, 16);  // left columns [c, m2), right [m2, e)
        square(m, b, c, m2);
        near(m, b, m2, e, c, m2);
        square(m, b, m2, e);
        near(a, m, c, m2, m, b);
        square(a, m, c, m2);
        near(a, m, m2, e, m, b);
        near(a, m, m2, e, c, m2);
        square(a, m, m2, e);
    }

    // Finish every chord inside vertices [a, e): two triangles, then the square between.
    void triangle(int64_t a, int64_t e) {
        if (e - a <= kLeaf) {
            for (int64_t i = e - 2; i >= a; --i) {
                for (int64_t j = i + 1; j < e; ++j) cell(i, j, e, e);
            }
            return;
        }
        const int64_t m = a + half(e - a, 16);
        triangle(a, m);
        triangle(m, e);
        square(a, m, m, e);
    }

    // claim() every cache line of cells T[i, a:b] (a < b).
    void claim_row(int64_t i, int64_t a, int64_t b) {
        const int64_t step = std::max<int64_t>(1, 64 / int64_t(sizeof(F)));
        for (int64_t j = a; j < b; j += step) claim(at(i, j));
        claim(at(i, b - 1));
    }

    // W = e(i, j) for rows [i0, i1) x columns [j0, j1), j > i only (the cells the fill
    // reads). Each row first claims the cache lines of the tile's cells (and those of
    // row i - above where above > 0: the tile above, whose rows this one fills too), so
    // that taking them from another core overlaps the square roots.
    void tile_edges(int64_t i0, int64_t i1, int64_t j0, int64_t j1, int64_t above) {
        wi = i0;
        wj = j0;
        for (int64_t i = i0; i < i1; ++i) {
            if (above > 0) claim_row(i - above, j0, j1);
            const int64_t b = std::max(j0, i + 1);
            if (b < j1) {
                claim_row(i, b, j1);
                edge_weight_row(code, *pts, i, b, W + (i - i0) * wld + (b - j0), j1 - b);
            }
        }
    }

    // Solve tile (ti, tj); done[a * nt + b] says whether tile (a, b) is finished.
    //
    // The far splits of two tiles of one column, (ti, tj) with tj - ti even and the tile
    // above it, are mostly the same products with the same B rows: the lower tile applies
    // both, k in [i1, j0 - tile), from one copy of B. The tile above then applies only what
    // is left: k in the lower tile's rows and in its left neighbour. The shared splits read
    // the upper tile's rows left of j0 - tile, final once tile (ti - 1, tj - 2) is done.
    // The lower tile sets done[tj * nt + ti - 1] (below the diagonal, where no tile is)
    // once the shared splits are applied; the tile above then starts with the splits
    // through its left neighbour before the tile below is finished.
    void run_tile(int64_t tile, int64_t ti, int64_t tj, int64_t* done, int64_t nt) {
        const int64_t i0 = ti * tile, i1 = std::min(n, ti * tile + tile);
        const int64_t j0 = tj * tile, j1 = std::min(n, tj * tile + tile);
        const int64_t d = tj - ti;
        const int64_t above = !Masked && ti >= 1 && below_shares(d + 1) ? tile : 0;
        tile_edges(i0, i1, j0, j1, above);
        if (d == 0) {
            for (int64_t i = i0; i < i1; ++i) {
                for (int64_t j = i + 2; j < j1; ++j) *at(i, j) = kInf<F>;
            }
            triangle(i0, i1);
            return;
        }
        if (Masked) {
            fill_inf(i0, i1, j0, j1);
            product(true, i0, i1, j0, j1, i1, j0);
        } else if (below_shares(d)) {  // the tile below applied the shared far splits
            far(i0, i1, j0, j1, j0 - tile, j0);
            wait_done(done + (ti + 1) * nt + tj);
            far(i0, i1, j0, j1, i1, i1 + tile);
        } else if (above > 0) {  // also the shared far splits of the tile above
            wait_done(done + (ti - 1) * nt + tj - 2);
            far(i0 - tile, i1, j0, j1, i1, j0 - tile, true);
            store_release(done + tj * nt + ti - 1, 1);  // the tile above may start
            far(i0, i1, j0, j1, j0 - tile, j0);
        } else if (d > 1) {
            far(i0, i1, j0, j1, i1, j0, true);
        } else {  // next to the diagonal: near splits only
            fill_inf(i0, i1, j0, j1);
        }
        square(i0, i1, j0, j1);
    }
};

template <class F, bool Masked>
void fill_impl(F* T, int64_t n, const Points& pts, int code, const uint8_t* mask,
               int64_t tile, int threads, int64_t* done, const int64_t* stop) {
    if (n < 2) return;
    const Plan& pl = plan();
    const Kernels<F>& K = pl.kernels<F>();
    const int64_t nt = (n + tile - 1) / tile;
    std::vector<int64_t> order;  // (t, d) of each tile, diagonal by diagonal
    order.reserve(nt * (nt + 1));
    for (int64_t d = 0; d < nt; ++d) {
        for (int64_t t = 0; t < nt - d; ++t) {
            order.push_back(t);
            order.push_back(d);
        }
    }
    const int64_t m = nt * (nt + 1) / 2;
    std::atomic<int64_t> taken{0};
    std::atomic<bool> failed{false};
    auto work = [&]() {
        std::vector<double> W;
        std::vector<F> P;
        try {
            W.resize(tile * tile);
            if (!Masked) P.resize(kStrip * (tile / kCols) * kCols);
        } catch (const std::bad_alloc&) {
            failed = true;  // the other threads take the tiles; none was taken here
            return;
        }
        Filler<F, Masked> f{T, n, &K, pl.rows, mask, &pts, code};
        f.W = W.data();
        f.wld = tile;
        f.P = P.data();
        while (stop == nullptr || load_acquire(stop) == 0) {
            const int64_t k = taken.fetch_add(1);
            if (k >= m) break;
            const int64_t t = order[2 * k], d = order[2 * k + 1];
            if (d > 0) {
                wait_done(done + t * nt + t + d - 1);
                if (!Masked && below_shares(d)) {  // only the tile below's shared splits
                    wait_done(done + (t + d) * nt + t);
                } else {
                    wait_done(done + (t + 1) * nt + t + d);
                }
            }
            f.run_tile(tile, t, t + d, done, nt);
            store_release(done + t * nt + t + d, 1);
        }
    };
#if defined(OPTRI_OPENMP)
    if (threads > 1) {
#pragma omp parallel num_threads(threads)
        work();
    } else {
        work();
    }
#else
    (void)threads;
    work();
#endif
    if (failed && taken.load() < m && (stop == nullptr || load_acquire(stop) == 0)) {
        throw std::bad_alloc();
    }
}

template <class F>
void mirror_block(F* T, int64_t n, int64_t i0, int64_t i1, int64_t j0, int64_t j1) {
    for (int64_t j = j0; j < j1; j += 8) {  // eight rows of the other half at a time
        for (int64_t i = i0; i < i1; i += 8) {
            for (int64_t r = i; r < std::min(i + 8, i1); ++r) {
                for (int64_t c = std::max(j, r + 1); c < std::min(j + 8, j1); ++c) {
                    T[c * n + r] = T[r * n + c];
                }
            }
        }
    }
}

#if defined(OPTRI_X86)
bool amd() {
    unsigned r[4] = {0, 0, 0, 0};
#if defined(_MSC_VER)
    int regs[4];
    __cpuid(regs, 0);
    for (int i = 0; i < 4; ++i) r[i] = static_cast<unsigned>(regs[i]);
#else
    __cpuid(0, r[0], r[1], r[2], r[3]);
#endif
    return r[1] == 0x68747541u && r[3] == 0x69746e65u && r[2] == 0x444d4163u;  // AuthenticAMD
}
#endif

Plan make_plan(Simd level) {
    Plan p{};
    p.cols = int(kCols);
    p.kblock = int(kKblock);
    p.level = level;
    p.rows = 4;
    p.vector_width = 0;
    p.min_f64 = p.min_f32 = MinFlavour::floating;
    p.isa = "portable";
    p.f64 = kernels_portable<double>();
    p.f32 = kernels_portable<float>();
#if defined(OPTRI_X86)
    if (level == Simd::baseline) {
        p.isa = "sse2";
        p.vector_width = 16;
        p.f64 = kernels_sse2<double>();
        p.f32 = kernels_sse2<float>();
    } else if (level == Simd::avx2) {
        p.isa = "avx2";
        p.vector_width = 32;
        p.min_f32 = MinFlavour::integer;
        p.f64 = kernels_avx2<double>();
        p.f32 = kernels_avx2<float>();
    } else if (level == Simd::avx512 && amd()) {
        // 512-bit instructions run as two 256-bit halves: 32-byte vectors, integer minima
        p.isa = "avx512-ymm";
        p.vector_width = 32;
        p.min_f64 = p.min_f32 = MinFlavour::integer;
        p.f64 = kernels_avx512_ymm<double>();
        p.f32 = kernels_avx512_ymm<float>();
    } else if (level == Simd::avx512) {
        p.isa = "avx512-zmm";
        p.rows = 8;
        p.vector_width = 64;
        p.min_f64 = p.min_f32 = MinFlavour::integer;
        p.f64 = kernels_avx512_zmm<double>();
        p.f32 = kernels_avx512_zmm<float>();
    }
#endif
    return p;
}

}  // namespace

const Plan& plan_for(Simd level) {
    static Plan plans[4];
    static std::once_flag once[4];
    const int x = static_cast<int>(level);
    std::call_once(once[x], [&] { plans[x] = make_plan(level); });
    return plans[x];
}

const Plan& plan() { return plan_for(simd_level()); }

int64_t default_tile(int64_t n) { return n < 800 ? 64 : n < 4000 ? 128 : 256; }

int64_t worker_bytes(int64_t tile, int64_t itemsize) {
    return tile * tile * 8 + kStrip * (tile / kCols) * kCols * itemsize;
}

template <class F>
void fill(F* T, int64_t n, const Points& pts, int code, const uint8_t* mask, int64_t tile,
          int threads, int64_t* done, const int64_t* stop) {
    if (mask != nullptr) {
        fill_impl<F, true>(T, n, pts, code, mask, tile, threads, done, stop);
    } else {
        fill_impl<F, false>(T, n, pts, code, mask, tile, threads, done, stop);
    }
}

template <class F>
void fill_serial(F* T, int64_t n, const Points& pts, int code, const uint8_t* mask) {
    const int64_t tile = default_tile(n);
    const int64_t nt = (n + tile - 1) / tile;
    std::vector<int64_t> done(static_cast<size_t>(nt * nt), 0);
    fill<F>(T, n, pts, code, mask, tile, 1, done.data(), nullptr);
}

template <class F>
void mirror(F* T, int64_t n) {
    // in blocks of 64 x 64 cells, so that both halves' lines stay in cache
    for (int64_t i0 = 0; i0 < n; i0 += 64) {
        for (int64_t j0 = i0; j0 < n; j0 += 64) {
            mirror_block(T, n, i0, std::min(n, i0 + 64), j0, std::min(n, j0 + 64));
        }
    }
}

template <class F>
int64_t split(const F* T, int64_t n, int64_t i, int64_t j, bool mirrored) {
    // the minimum first, then the first split that reaches it (the same additions both
    // times, so equality is exact)
    const F* ri = T + i * n;
    F best = kInf<F>;
    if (mirrored) {
        const F* rj = T + j * n;
        for (int64_t k = i + 1; k < j; ++k) best = mn(best, F(ri[k] + rj[k]));
        if (best == kInf<F>) return -1;
        for (int64_t k = i + 1; k < j; ++k) {
            if (F(ri[k] + rj[k]) == best) return k;
        }
        return -1;
    }
    for (int64_t k = i + 1; k < j; ++k) best = mn(best, F(ri[k] + T[k * n + j]));
    if (best == kInf<F>) return -1;
    for (int64_t k = i + 1; k < j; ++k) {
        if (F(ri[k] + T[k * n + j]) == best) return k;
    }
    return -1;
}

void subtract_edges(double* out, int64_t n, const Points& pts, int code) {
    for (int64_t i = 0; i + 1 < n; ++i) {
        for (int64_t j = i + 1; j < n; ++j) out[i * n + j] -= edge_weight(code, pts, i, j);
    }
}

namespace testing {

template <class F>
void product(F* T, int64_t n, const uint8_t* mask, int64_t ia, int64_t ib, int64_t ja,
             int64_t jb, int64_t k0, int64_t k1) {
    const Plan& pl = plan();
    if (mask != nullptr) {
        Filler<F, true> f{T, n, &pl.kernels<F>(), pl.rows, mask, nullptr, 0};
        f.product(true, ia, ib, ja, jb, k0, k1);
    } else {
        Filler<F, false> f{T, n, &pl.kernels<F>(), pl.rows, nullptr, nullptr, 0};
        f.product(false, ia, ib, ja, jb, k0, k1);
    }
}

template <class F>
void far(F* T, int64_t n, int64_t ia, int64_t ib, int64_t ja, int64_t jb, int64_t k0,
         int64_t k1, bool fresh) {
    const Plan& pl = plan();
    std::vector<F> P(static_cast<size_t>(kStrip * ((jb - ja) / kCols + 1) * kCols));
    Filler<F, false> f{T, n, &pl.kernels<F>(), pl.rows, nullptr, nullptr, 0};
    f.P = P.data();
    f.far(ia, ib, ja, jb, k0, k1, fresh);
}

}  // namespace testing

#define OPTRI_MINPLUS_INSTANTIATE(F)                                                        \
    template void fill<F>(F*, int64_t, const Points&, int, const uint8_t*, int64_t, int,   \
                          int64_t*, const int64_t*);                                        \
    template void fill_serial<F>(F*, int64_t, const Points&, int, const uint8_t*);          \
    template void mirror<F>(F*, int64_t);                                                   \
    template int64_t split<F>(const F*, int64_t, int64_t, int64_t, bool);                \
    template void testing::product<F>(F*, int64_t, const uint8_t*, int64_t, int64_t,       \
                                      int64_t, int64_t, int64_t, int64_t);                  \
    template void testing::far<F>(F*, int64_t, int64_t, int64_t, int64_t, int64_t, int64_t, \
                                  int64_t, bool);
OPTRI_MINPLUS_INSTANTIATE(double)
OPTRI_MINPLUS_INSTANTIATE(float)
#undef OPTRI_MINPLUS_INSTANTIATE

}  // namespace minplus
}  // namespace optri
