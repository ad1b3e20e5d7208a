// Geometry shared by the 3-D hole-filling searches (optri._core.holes).
//
// Vertex array Q (row-major (rows, 3) doubles) holds the n polyline points, followed
// (when the mesh around the hole is known) by the n third points: Q[n + s] is the third
// vertex of the mesh triangle on boundary edge (s, s + 1). Every triangle normal a
// search compares is computed by unit_normal from the triangle's *sorted* vertex indices,
// so the searches and the evaluator (triangle_normals) see bit-identical values and their
// max-dihedral comparisons agree exactly.
//
// The dihedral "key" of two adjacent, consistently oriented triangles is
// 1 - cos(angle between their normals) in [0, 2]: monotone in the angle, so comparing
// keys compares angles without an acos. A degenerate (zero-area) patch triangle gets
// kDegenerateKey = 3 against every neighbour: worse than any real fold (2), so a patch
// with a zero-area triangle wins only when every patch has one. A degenerate mesh
// triangle has no normal to compare with: the key across its edge is 0.
//
// Every float expression is written in the order of optri's Python reference (the
// evaluator's arithmetic), and the build neither contracts a*b+c nor reassociates, so
// results are the same bits on every platform. pmax/pmin are Python's max/min of two
// floats: the first argument unless the second is strictly greater (smaller).
#pragma once

#include <cmath>
#include <cstdint>

namespace optri::holes {

// Key of any pair involving a zero-area patch triangle: worse than a full fold.
constexpr double kDegenerateKey = 3.0;
// Key of a full fold (angle pi), the worst a real pair of triangles can have.
constexpr double kFoldKey = 2.0;
// A triangle whose squared sine of the angle at its first vertex is at most this is
// degenerate (sine <= 1e-12).
constexpr double kDegenerateSine2 = 1e-24;

inline double pmax(double acc, double v) { return v > acc ? v : acc; }
inline double pmin(double acc, double v) { return v < acc ? v : acc; }

// A unit normal, its degenerate flag and the triangle's area.
struct Normal {
    double x, y, z;
    bool d;
    double area;
};

// Unit normal of triangle a->b->c of the (rows, 3) array Q.
inline Normal unit_normal(const double* Q, int64_t a, int64_t b, int64_t c) {
    const double* A = Q + 3 * a;
    const double* B = Q + 3 * b;
    const double* C = Q + 3 * c;
    const double ux = B[0] - A[0], uy = B[1] - A[1], uz = B[2] - A[2];
    const double vx = C[0] - A[0], vy = C[1] - A[1], vz = C[2] - A[2];
    const double nx = uy * vz - uz * vy;
    const double ny = uz * vx - ux * vz;
    const double nz = ux * vy - uy * vx;
    const double uu = ux * ux + uy * uy + uz * uz;
    const double vv = vx * vx + vy * vy + vz * vz;
    const double n2 = nx * nx + ny * ny + nz * nz;
    const double nn = std::sqrt(n2);
    if (n2 <= kDegenerateSine2 * (uu * vv)) return {0.0, 0.0, 0.0, true, 0.5 * nn};
    const double inv = 1.0 / nn;
    return {nx * inv, ny * inv, nz * inv, false, 0.5 * nn};
}

// unit_normal of the triangle's vertices sorted (the same rounding always).
inline Normal sorted_normal(const double* Q, int64_t a, int64_t b, int64_t c) {
    int64_t t;
    if (a > b) { t = a; a = b; b = t; }
    if (b > c) { t = b; b = c; c = t; }
    if (a > b) { t = a; a = b; b = t; }
    return unit_normal(Q, a, b, c);
}

// The clamped key 1 - (a . b) of two unit normals.
inline double clamp_key(double ax, double ay, double az, double bx, double by, double bz) {
    const double k = 1.0 - (ax * bx + ay * by + az * bz);
    return pmin(pmax(k, 0.0), kFoldKey);
}

// Key of two patch triangles (unit normals, degenerate flags).
inline double key_of(double x1, double y1, double z1, bool d1,
                     double x2, double y2, double z2, bool d2) {
    if (d1 || d2) return kDegenerateKey;
    return clamp_key(x1, y1, z1, x2, y2, z2);
}

// Key of patch triangle (x, y, z, d) against the mesh triangle on side s; MN rows are
// (x, y, z, degenerate) of the mesh triangles (mesh_normals).
inline double mesh_key(const double* MN, int64_t s, double x, double y, double z, bool d,
                       bool has_third) {
    if (!has_third) return 0.0;
    if (d) return kDegenerateKey;
    const double* m = MN + 4 * s;
    if (m[3] != 0.0) return 0.0;  // a zero-area mesh triangle has no normal to fold against
    return clamp_key(x, y, z, m[0], m[1], m[2]);
}

}  // namespace optri::holes

// --- the kernels (holes_geometry, holes_liepa, holes_exact, holes_degenerate .cpp) --------
// Arrays are C-contiguous; the binding (holes_bind.cpp) checks their shapes.
namespace optri::holes {

// (n, 4) rows (x, y, z, degenerate) of the mesh triangles (p[s+1], p[s], t[s]).
void mesh_normals(const double* Q, int64_t n, double* out);
// (m, 5) rows (x, y, z, degenerate, area) of index triangles (sorted first).
void triangle_normals(const double* Q, const int64_t* tris, int64_t m, double* out);
// Keys of row pairs (x, y, z, degenerate, ...) of two patch-normal tables with
// u_cols and v_cols columns.
void pair_keys(const double* U, int64_t u_cols, const double* V, int64_t v_cols,
               int64_t rows, double* out);
// Keys of patch-normal rows U against the mesh triangles (MN rows) on sides.
void mesh_pair_keys(const double* U, int64_t u_cols, const double* MN, const int64_t* sides,
                    int64_t rows, double* out);

// Liepa's recurrence, rows i = i_hi .. i_lo (descending), in place: T (n, 5, n) holds
// (key, area, top normal) of chord (a, b) at [a, :, b] and [b, :, a] (zeros on the sides),
// K (n, n) its apex (-1: no patch).
void dense_rows(const double* Q, int64_t n, bool has_third, const double* MN,
                const bool* allowed, double* T, int32_t* K, int64_t i_hi, int64_t i_lo);
// The recurrence over candidate triangles, chord by chord (see holes_liepa.cpp).
void sparse_chords(const double* Q, int64_t n, bool has_third, const double* MN,
                   const int64_t* keys, int64_t chords, const int64_t* order,
                   const int64_t* ptr, const int64_t* apex, double* V, double* TN, int64_t* K);
// Triangles of the sparse solution into out (n - 2, 3); false if it is incomplete.
bool sparse_trace(int64_t n, const int64_t* keys, int64_t chords, const int64_t* K,
                  int64_t* out);

// The exact search's compact states (see holes_exact.cpp).
int64_t state_count(int64_t n);
void state_offsets(int64_t n, int64_t* off);
void leaf_table(const double* Q, int64_t n, const double* MN, bool has_third, double* leaf);
void bottleneck_lengths(const double* Q, int64_t n, bool has_third, const double* MN,
                        const double* leaf, const bool* allowed, const int64_t* off,
                        double* B, double U, int64_t L0, int64_t L1);
void area_lengths(const double* Q, int64_t n, bool has_third, const double* MN,
                  const double* leaf, const int64_t* off, double* A, double M,
                  int64_t L0, int64_t L1);
void mark_pending(double* states, int64_t count, double M);
bool exact_trace(const double* Q, int64_t n, bool has_third, const double* MN,
                 const double* leaf, const int64_t* off, const double* A, double M,
                 int64_t* out);

// Whether P's points a, b, c are exactly collinear (orient2d = 0 in all three coordinate
// planes); the flags of index triangles (m, 3) into out.
bool collinear(const double* P, int64_t a, int64_t b, int64_t c);
void collinear_rows(const double* P, const int64_t* tris, int64_t m, bool* out);
// The least (exactly degenerate triangles, area) patch over allowed chords (areas from Q):
// its count (-1: no patch) and its apexes K (n, n) of chords (i, j), i < j (-1: none).
int64_t fewest_degenerate(const double* P, const double* Q, int64_t n, const bool* allowed,
                          int32_t* K);
// The same for (count, sum or max of built-in triangle weight `code` on P (n, 3)).
int64_t fewest_then_weight(const double* P, int64_t n, int code, bool is_max,
                           const bool* allowed, int32_t* K);

// Pass-2 mark of a state whose area is still to be computed (areas are >= 0).
constexpr double kPending = -1.0;

}  // namespace optri::holes
