// The generic recurrence: any built-in or user-compiled weight, "sum" or "max", one table
// per component of a lexicographic pair. The compiled engine (optri.engines.jit) fills a
// whole table with it in parallel; the many-polygon path calls the same serial fill and
// trace once per polygon.
//
// Table layout: T[i, j] (i < j) holds the cost of chord (i, j) and T[j, i] the same value,
// so for a cell (i, j) both operands of every split, cost(i, k) = T[i, k] and
// cost(k, j) = T[j, k], are read along the contiguous rows T[i] and T[j]. Tables are
// row-major n x n arrays of float or double; the sides (i, i + 1) hold the neutral cost
// before a fill (set_sides), the diagonal is never read.
//
// cost(i, j) = best_k combine(cost(i, k), cost(k, j), w(i, k, j)) compared on component 1,
// then (lexicographic) component 2, component-1 values within LEX_TIE_RTOL counting as
// equal; ties go to the smallest k; a split with a half of cost +inf (no triangulation, or
// not a diagonal) is skipped without evaluating its weight. A NaN weight, or a user weight
// that raised, is skipped too and flagged (Flags), and a fill stops early once flagged.
#pragma once

#include <cstdint>
#include <vector>

#include "objective.hpp"
#include "weights.hpp"

namespace optri {
namespace generic {

// The gate weight's code when there is no gate.
constexpr int NO_GATE = -2;

// A user's compiled weight (numba.cfunc): w(vertices, shape, i, k, j, error) over input
// vertex indices; vertices is a C-contiguous float64 array of the given shape (one or two
// entries). It sets *error to nonzero when the function raised.
using UserWeight = double (*)(const double* vertices, const int64_t* shape, int64_t i,
                              int64_t k, int64_t j, int64_t* error);

// Everything a fill reads besides the tables.
struct Problem {
    Points pts;                    // internal order, row-major n x dims
    int code[3] = {0, 0, NO_GATE};  // WeightCode of component 1, component 2, the gate
    double gate = 0.0;             // a triangle whose gate weight exceeds this gets +inf
    bool is_max[2] = {false, false};  // each component's rule: max (else sum)
    bool lex = false;              // a lexicographic pair (reads and writes table 2)
    const uint8_t* mask = nullptr;  // n x n allowed chords (sides included), or null: all
    // user weights (code custom) of component 1, 2 and the gate, called on the input
    // vertices with indices mapped back through order
    UserWeight user[3] = {nullptr, nullptr, nullptr};
    const double* vertices = nullptr;
    const int64_t* shape = nullptr;
    const int64_t* order = nullptr;
};

// Set while a fill runs (from any thread), read after it.
struct Flags {
    int64_t nan = 0;    // 1 once a weight returned NaN
    int64_t error = 0;  // 1 + the slot (0: component 1, 1: component 2, 2: gate) of a user
                        // weight that raised
};

template <class T>
struct Tables {
    T* t1;
    T* t2;  // component 2 of a lexicographic pair; may be null otherwise
    int64_t n;
};

// The best split of cell (i, j): its costs and k (-1 when no split is finite).
struct Split {
    double c1;
    double c2;
    int64_t k;
};

template <class T>
Split best_split(const Tables<T>& tables, const Problem& pr, Flags& flags, int64_t i,
                 int64_t j);

// Sides (i, i + 1) and (i + 1, i) of each table set to its component's neutral cost.
template <class T>
void set_sides(const Tables<T>& tables, const Problem& pr);

// Fill the whole table(s) on this thread (sides set first by set_sides). Stops early once
// flags has a NaN or an error.
template <class T>
void fill(const Tables<T>& tables, const Problem& pr, Flags& flags);

// Fill tile-diagonal by tile-diagonal on `threads` threads (OpenMP; one without it).
// Between tile-diagonals it returns when *stop is nonzero (another thread may set it) or
// flags are set; *reached is d + 1 once tile-diagonal d is finished (another thread may
// read it). tile >= 1.
template <class T>
void fill_tiles(const Tables<T>& tables, const Problem& pr, Flags& flags, int64_t tile,
                int threads, const int64_t* stop, int64_t* reached);

// The bounded walk from chord (0, n-1) down, each chord's split from split(i, j): the
// triangles into tris (room for (n - 2) x 3, rows i < k < j); returns their count.
// bad = (i, j) of the first chord whose split lies outside it (or one split too many:
// a corrupt table never loops), else (-1, -1). Shared by trace and the many-polygon
// kernel's min-plus walk.
template <class Split>
int64_t walk(int64_t n, Split split, int64_t* tris, int64_t bad[2]) {
    bad[0] = bad[1] = -1;
    if (n < 2) return 0;
    std::vector<int64_t> stack(2 * static_cast<size_t>(n) + 2);
    int64_t top = 1, m = 0;
    stack[0] = 0, stack[1] = n - 1;
    while (top > 0) {
        --top;
        const int64_t i = stack[2 * top], j = stack[2 * top + 1];
        if (j - i < 2) continue;
        const int64_t k = split(i, j);
        if (k <= i || k >= j || m >= n - 2) {
            bad[0] = i, bad[1] = j;
            return m;
        }
        tris[3 * m] = i, tris[3 * m + 1] = k, tris[3 * m + 2] = j;
        ++m;
        stack[2 * top] = k, stack[2 * top + 1] = j;
        stack[2 * top + 2] = i, stack[2 * top + 3] = k;
        top += 2;
    }
    return m;
}

// Optimal triangles from chord (0, n-1) down into tris (room for (n - 2) x 3, rows
// i < k < j): walk() over the recurrence's best splits; returns their count. bad = (i, j) of a chord with no finite split, else
// (-1, -1). Re-scans only the O(n) cells on the optimal path.
template <class T>
int64_t trace(const Tables<T>& tables, const Problem& pr, Flags& flags, int64_t* tris,
              int64_t bad[2]);

// The optimal split of every chord i + 2 <= j into out (n x n, -1 elsewhere), on
// `threads` threads: O(n^3), for an exported table.
template <class T>
void split_table(const Tables<T>& tables, const Problem& pr, Flags& flags, int32_t* out,
                 int threads);

}  // namespace generic
}  // namespace optri
