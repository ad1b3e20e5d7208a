// The valid-diagonal mask of a simple polygon: which chords are internal diagonals.
//
// Serial kernels, shared by the mask of one polygon (mask.cpp, which runs the visibility
// walk's rows on every thread) and the many-polygon kernel (many.cpp, one polygon per
// thread). Vertices are x[0..n), y[0..n) in counter-clockwise order; masks are n x n bytes,
// row-major, 1 where a chord is allowed. Every sign is exact (predicates.hpp).
//
// The usual path: ear clipping gives some triangulation (O(n^2) for most polygons); each
// vertex then sees through it, narrowing an angular window from triangle to triangle
// (O(n) per vertex). The direct scan (valid_mask: each chord against the edges outward
// from its first endpoint) needs no triangulation and is the fallback for input that is
// not simple.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "predicates.hpp"

namespace optri {
namespace simple {

using std::int64_t;

// Python's a % n for n > 0: never negative.
inline int64_t wrap(int64_t a, int64_t n) {
    const int64_t r = a % n;
    return r < 0 ? r + n : r;
}

// A stop flag another thread may set (nullptr: never stopped).
inline bool stopped(const volatile int64_t* stop) { return stop != nullptr && stop[0] != 0; }

inline int orient_at(const double* x, const double* y, int64_t a, int64_t b, int64_t c) {
    return orient_sign(x[a], y[a], x[b], y[b], x[c], y[c]);
}

// Whether the chord from vertex i towards j starts inside the (CCW) polygon.
inline bool in_cone(const double* x, const double* y, int64_t n, int64_t i, int64_t j) {
    const int64_t p = wrap(i - 1, n);
    const int64_t q = wrap(i + 1, n);
    const bool left_of_next = orient_at(x, y, i, q, j) > 0;
    const bool left_of_prev = orient_at(x, y, p, i, j) > 0;
    if (orient_at(x, y, p, i, q) > 0) return left_of_next && left_of_prev;  // convex corner
    return left_of_next || left_of_prev;  // reflex or straight: the union of half-planes
}

// No vertex on the open chord (i, j) and no edge crossing it properly. Vertices are visited
// outward from i in both directions: the edges that block a chord of a simple polygon are
// most often near its endpoint, so most invalid chords stop after a few steps.
inline bool clear(const double* x, const double* y, int64_t n, int64_t i, int64_t j) {
    for (int64_t s = 0; s < n - 1; ++s) {
        const int64_t off = s / 2 + 1;
        const int64_t a = s % 2 == 0 ? wrap(i + off, n) : wrap(i - off, n);
        if (a == j) continue;
        const int sa = orient_at(x, y, i, j, a);
        if (sa == 0 && strictly_between(x[i], y[i], x[j], y[j], x[a], y[a])) {
            return false;  // the chord runs through vertex a
        }
        const int64_t b = wrap(a + 1, n);
        if (b == i || b == j) continue;
        const int sb = orient_at(x, y, i, j, b);
        if (sa * sb < 0) {
            const int s1 = orient_at(x, y, a, b, i);
            const int s2 = orient_at(x, y, a, b, j);
            if (s1 * s2 < 0) return false;  // edge (a, a+1) crosses the chord
        }
    }
    return true;
}

// Row i of the direct scan: chords (i, j), j > i + 1, written at (i, j) and (j, i).
inline void scan_row(const double* x, const double* y, int64_t n, int64_t i, uint8_t* out) {
    for (int64_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;  // a polygon side
        if (in_cone(x, y, n, i, j) && in_cone(x, y, n, j, i) && clear(x, y, n, i, j)) {
            out[i * n + j] = 1;
            out[j * n + i] = 1;
        }
    }
}

// The direct scan into a zeroed n x n mask: O(n^2) to O(n^3). Sides and the main diagonal
// are left 0.
inline void valid_mask(const double* x, const double* y, int64_t n, uint8_t* out) {
    for (int64_t i = 0; i < n; ++i) scan_row(x, y, n, i, out);
}

// Whether w lies in the closed counter-clockwise triangle (p, v, q).
inline bool blocks_ear(const double* x, const double* y, int64_t p, int64_t v, int64_t q,
                       int64_t w) {
    return orient_at(x, y, p, v, w) >= 0 && orient_at(x, y, v, q, w) >= 0 &&
           orient_at(x, y, q, p, w) >= 0;
}

inline bool is_ear(const double* x, const double* y, const int64_t* prv, const int64_t* nxt,
                   int64_t v) {
    const int64_t p = prv[v];
    const int64_t q = nxt[v];
    if (orient_at(x, y, p, v, q) <= 0) return false;  // flat or outside
    for (int64_t w = nxt[q]; w != p; w = nxt[w]) {
        if (blocks_ear(x, y, p, v, q, w)) return false;
    }
    return true;
}

// Some triangulation of a simple CCW polygon with no zero-area triangle, into tris
// (max(n - 2, 0) rows of 3, CCW). False if no ear was found (input that is not simple:
// with exact predicates every simple polygon has one) or once *stop is set.
inline bool ear_clip(const double* x, const double* y, int64_t n, int64_t* tris,
                     const volatile int64_t* stop) {
    std::vector<int64_t> prv(n), nxt(n);
    for (int64_t k = 0; k < n; ++k) {
        prv[k] = wrap(k - 1, n);
        nxt[k] = wrap(k + 1, n);
    }
    int64_t left = n, v = 0, misses = 0, m = 0;
    while (left > 3) {
        if (stopped(stop)) return false;
        if (is_ear(x, y, prv.data(), nxt.data(), v)) {
            const int64_t p = prv[v], q = nxt[v];
            tris[3 * m] = p;
            tris[3 * m + 1] = v;
            tris[3 * m + 2] = q;
            ++m;
            nxt[p] = q;
            prv[q] = p;
            --left;
            misses = 0;
            v = p;  // the new corner at p may have become an ear
        } else {
            if (++misses > left) return false;
            v = nxt[v];
        }
    }
    tris[3 * m] = prv[v];
    tris[3 * m + 1] = v;
    tris[3 * m + 2] = nxt[v];
    return true;
}

// left[a * n + b]: the triangle lying left of the directed edge a -> b, or -1. Empty (and
// false) if a triangle names no vertex.
inline bool left_triangles(const int64_t* tris, int64_t count, int64_t n,
                           std::vector<int32_t>& left) {
    for (int64_t t = 0; t < 3 * count; ++t) {
        if (tris[t] < 0 || tris[t] >= n) return false;
    }
    left.assign(static_cast<size_t>(n * n), -1);
    for (int64_t t = 0; t < count; ++t) {
        const int64_t a = tris[3 * t], b = tris[3 * t + 1], c = tris[3 * t + 2];
        left[a * n + b] = static_cast<int32_t>(t);
        left[b * n + c] = static_cast<int32_t>(t);
        left[c * n + a] = static_cast<int32_t>(t);
    }
    return true;
}

inline int64_t third(const int64_t* tris, int64_t t, int64_t a, int64_t b) {
    for (int m = 0; m < 3; ++m) {
        const int64_t c = tris[3 * t + m];
        if (c != a && c != b) return c;
    }
    return -1;
}

// Mark in row (n bytes) every vertex visible from vertex i through the polygon.
//
// Walks the triangulation's dual tree from the fan of triangles around i, carrying the open
// angular window (rays i->lo and i->hi) that still reaches through the current edge; a
// vertex strictly inside the window is visible, one exactly on a ray is hidden behind the
// vertex defining it. Returns false, having stopped, if tris is not a triangulation (the
// walk would leave its bounds): every step is bounded. stack: scratch of 8 n values.
inline bool see_from(const double* x, const double* y, int64_t n, const int64_t* tris,
                     const int32_t* left, int64_t i, uint8_t* row, int64_t* stack) {
    // stack rows: directed edge (a, b) with the unvisited triangle on the left of b -> a,
    // and the window rays' vertices (lo on a's side, hi on b's side); each triangulation
    // edge is pushed at most once, so 2n rows always suffice
    int64_t top = 0;
    auto push = [&](int64_t a, int64_t b, int64_t lo, int64_t hi) {
        int64_t* s = stack + 4 * top;
        s[0] = a; s[1] = b; s[2] = lo; s[3] = hi;
        ++top;
    };
    int64_t a = wrap(i + 1, n);
    int64_t t = left[i * n + a];
    while (t >= 0) {  // the fan around i, counter-clockwise from side (i, i+1)
        const int64_t b = third(tris, t, i, a);
        if (b < 0 || top >= n) return false;  // a fan of more than n - 2 triangles
        row[a] = 1;
        row[b] = 1;
        push(a, b, a, b);
        a = b;
        t = left[i * n + a];
    }
    int64_t pushes = top;
    while (top > 0) {
        --top;
        const int64_t* s = stack + 4 * top;
        const int64_t ea = s[0], eb = s[1], lo = s[2], hi = s[3];
        const int64_t u = left[eb * n + ea];
        if (u < 0) continue;  // a polygon side: the view stops here
        const int64_t c = third(tris, u, ea, eb);
        if (c < 0 || pushes + 2 > 2 * n) return false;  // an edge seen twice
        const bool past_lo = orient_at(x, y, i, lo, c) > 0;
        const bool before_hi = orient_at(x, y, i, hi, c) < 0;
        if (past_lo && before_hi) {
            row[c] = 1;
            push(ea, c, lo, c);
            push(c, eb, c, hi);
            pushes += 2;
        } else if (past_lo) {  // c at or beyond the hi ray: the window leaves through (a, c)
            push(ea, c, lo, hi);
            pushes += 1;
        } else {  // c at or before the lo ray: the window leaves through (c, b)
            push(c, eb, lo, hi);
            pushes += 1;
        }
    }
    return true;
}

// Chord (i, j), j > i, is visible iff seen from both ends; writes row i right of the
// diagonal and column i below it (so rows may run on different threads).
inline void both_ways(uint8_t* out, int64_t n, int64_t i) {
    for (int64_t j = i + 1; j < n; ++j) {
        const uint8_t both = out[i * n + j] && out[j * n + i];
        out[i * n + j] = both;
        out[j * n + i] = both;
    }
}

// Vertex visibility from a triangulation (count rows of tris) into a zeroed n x n mask;
// O(n^2) in all. out[i, j] iff the open segment (i, j) lies in the polygon's interior
// (sides included). False when tris turned out not to be a triangulation of the polygon.
inline bool visibility_mask(const double* x, const double* y, int64_t n, const int64_t* tris,
                            int64_t count, uint8_t* out) {
    std::vector<int32_t> left;
    if (!left_triangles(tris, count, n, left)) return false;
    std::vector<int64_t> stack(static_cast<size_t>(8 * n));
    for (int64_t i = 0; i < n; ++i) {
        if (!see_from(x, y, n, tris, left.data(), i, out + i * n, stack.data())) return false;
    }
    for (int64_t i = 0; i < n; ++i) both_ways(out, n, i);
    return true;
}

// The mask's polygon sides set and its main diagonal cleared.
inline void set_sides(uint8_t* out, int64_t n) {
    for (int64_t v = 0; v < n; ++v) {
        const int64_t w = wrap(v + 1, n);
        out[v * n + w] = 1;
        out[w * n + v] = 1;
        out[v * n + v] = 0;
    }
}

// The chord mask of a CCW polygon, sides set, into a zeroed n x n mask: ear clipping and
// the visibility walk, or the direct scan when ear clipping fails. False when the walk
// stopped (tris was not a triangulation: the polygon is not simple).
inline bool chord_mask(const double* x, const double* y, int64_t n, uint8_t* out) {
    std::vector<int64_t> tris(static_cast<size_t>(3 * std::max<int64_t>(n - 2, 0)));
    bool ok = ear_clip(x, y, n, tris.data(), nullptr);
    if (ok) {
        ok = visibility_mask(x, y, n, tris.data(), std::max<int64_t>(n - 2, 0), out);
    } else {
        valid_mask(x, y, n, out);
        ok = true;
    }
    set_sides(out, n);
    return ok;
}

}  // namespace simple
}  // namespace optri
