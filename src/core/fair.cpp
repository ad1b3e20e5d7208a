// optri._core.fair: the fairing solve of optri.holes.fair (L^(k+1) x = 0 for the free
// vertices, every other vertex fixed), the compiled twin of the numpy/scipy reference
// optri.holes.fair._solve, which the tests compare it with.
//
// One solve, as the reference does it:
// * the faces within k + 2 rings of the free vertices are selected (one ring a sweep, each
//   sweep decided on the rings before it);
// * the cotangent stiffness C and the mixed Voronoi areas A are those of
//   optri.holes.fair.laplacian, corner for corner (the same sine floor, the same obtuse
//   rule);
// * the operator (C A^-1)^k C, taken as C (A^-1 (C (A^-1 C))) row by row, is restricted to
//   the free rows; its free columns are the system, its fixed columns times the fixed
//   positions the right-hand side;
// * the system is symmetric (C is, A is diagonal): one LDL^T factorization without
//   pivoting under a nested-dissection order serves x, y and z.
// A zero or non-finite pivot, a free vertex without area or a non-finite solution is a
// status, not an exception: the caller keeps the input then. Floating sums run in another
// order than scipy's, so the results agree with the reference to rounding, not bit for bit.
//
// The order: recursive coordinate bisection of the free vertices (the patches are
// surfaces): each set is halved at the median of the axis whose cut leaves the fewest
// border vertices, the separator is the smaller border (the vertices of one half with a
// system neighbour in the other), ordered after both halves. The factorization is
// the up-looking LDL^T of Davis's LDL package: elimination tree and column counts from
// the pattern, then row k of L from the tree's reach of column k of A.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "arrays.hpp"
#include "bind.hpp"

namespace nb = nanobind;

namespace optri {

namespace fair {

// Same as optri.holes.fair._SINE_FLOOR.
constexpr double SINE_FLOOR = 1e-12;
// Sets of at most this many free vertices are ordered as they come (no further cut).
constexpr int64_t LEAF = 8;

enum Status : int { OK = 0, NO_AREA = 1, BAD_PIVOT = 2, NOT_FINITE = 3 };

struct Result {
    int status = OK;
    int64_t where = -1;      // the pivot's column (BAD_PIVOT) or the vertex (NO_AREA)
    std::vector<double> x;   // (free, 3) positions after every pass
};

// A sparse matrix by rows (compressed), values beside the pattern.
struct Csr {
    std::vector<int64_t> start, col;
    std::vector<double> val;
};

inline double norm3(double x, double y, double z) { return std::sqrt(x * x + y * y + z * z); }

// The cotangents, squared opposite sides and area of one face, as laplacian computes them.
struct Corners {
    double cot[3], sq[3], area;
};

Corners corners(const double* P, const int64_t* t) {
    Corners out;
    const double* p[3] = {P + 3 * t[0], P + 3 * t[1], P + 3 * t[2]};
    {
        const double ux = p[1][0] - p[0][0], uy = p[1][1] - p[0][1], uz = p[1][2] - p[0][2];
        const double vx = p[2][0] - p[0][0], vy = p[2][1] - p[0][1], vz = p[2][2] - p[0][2];
        out.area = 0.5 * norm3(uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx);
    }
    for (int c = 0; c < 3; ++c) {
        const double* o = p[c];
        const double* q = p[(c + 1) % 3];
        const double* r = p[(c + 2) % 3];
        const double ax = q[0] - o[0], ay = q[1] - o[1], az = q[2] - o[2];
        const double bx = r[0] - o[0], by = r[1] - o[1], bz = r[2] - o[2];
        const double cross = norm3(ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx);
        const double dot = ax * bx + ay * by + az * bz;
        const double scale = norm3(ax, ay, az) * norm3(bx, by, bz);
        out.cot[c] = dot / std::max(cross, SINE_FLOOR * std::max(scale, 1e-300));
        const double dx = bx - ax, dy = by - ay, dz = bz - az;
        out.sq[c] = dx * dx + dy * dy + dz * dz;
    }
    return out;
}

// The part of a solve that depends on the mesh's connectivity alone: the selected faces
// in compact vertex numbers (free vertices first), the pattern of C with each face
// corner's slots in it, the system's pattern and its order and symbolic factorization.
struct Plan {
    int64_t nf = 0, nc = 0;
    std::vector<int64_t> vid;    // compact -> mesh vertex
    std::vector<int64_t> faces;  // selected faces, compact numbers, 3 a face
    Csr C;                       // pattern of C (values filled per pass)
    std::vector<int64_t> slot;   // per face: 12 slots of C (ij, ji, ii, jj for each corner)
    Csr S;                       // the system (free rows and columns), pattern fixed
    std::vector<int64_t> perm, pinv, parent, lp;
};

// faces within continuity + 2 rings of the free vertices, as _solve selects them
std::vector<int64_t> select_faces(const int64_t* F, int64_t m, int64_t n, const int64_t* freev,
                                  int64_t nf, int rings) {
    std::vector<uint8_t> near(static_cast<size_t>(n), 0), touched(static_cast<size_t>(m), 0);
    for (int64_t i = 0; i < nf; ++i) near[freev[i]] = 1;
    std::vector<int64_t> fresh;
    for (int r = 0; r <= rings; ++r) {
        fresh.clear();
        for (int64_t t = 0; t < m; ++t) {
            if (touched[t]) continue;
            const int64_t* f = F + 3 * t;
            if (near[f[0]] | near[f[1]] | near[f[2]]) fresh.push_back(t);
        }
        for (int64_t t : fresh) touched[t] = 1;
        if (r == rings) break;  // the last sweep only selects: its faces' far ends stay out
        for (int64_t t : fresh) {
            const int64_t* f = F + 3 * t;
            near[f[0]] = near[f[1]] = near[f[2]] = 1;
        }
    }
    std::vector<int64_t> out;
    for (int64_t t = 0; t < m; ++t)
        if (touched[t]) out.push_back(t);
    return out;
}

// nested dissection by coordinate bisection of the system's graph
void dissect(const Csr& S, const double* pos, std::vector<int64_t>& ids, int64_t lo, int64_t hi,
             std::vector<int64_t>& stamp, int64_t& stamps, std::vector<int64_t>& perm) {
    const int64_t size = hi - lo;
    if (size <= LEAF) {
        for (int64_t i = lo; i < hi; ++i) perm.push_back(ids[i]);
        return;
    }
    double mn[3] = {INFINITY, INFINITY, INFINITY}, mx[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int64_t i = lo; i < hi; ++i)
        for (int a = 0; a < 3; ++a) {
            mn[a] = std::min(mn[a], pos[3 * ids[i] + a]);
            mx[a] = std::max(mx[a], pos[3 * ids[i] + a]);
        }
    // the cut at the median of each axis (the longest first); the one with the fewest
    // border vertices wins
    int axes[3] = {0, 1, 2};
    std::sort(axes, axes + 3, [&](int a, int b) { return mx[a] - mn[a] > mx[b] - mn[b]; });
    const int64_t mid = lo + size / 2;
    const int64_t s0 = stamps, s1 = stamps + 1, sep = stamps + 2;
    stamps += 3;
    std::vector<uint8_t> on(static_cast<size_t>(size), 0);
    int64_t border[2] = {0, 0};
    int best = -1;
    int64_t best_size = 0;
    for (int t = 0; t < 4; ++t) {
        // three trials, then the best again (its halves and border kept)
        const int axis = t < 3 ? axes[t] : best;
        if (t == 3 && best == axes[2]) break;  // the last trial was the best: kept as is
        std::nth_element(ids.begin() + lo, ids.begin() + mid, ids.begin() + hi,
                         [&](int64_t x, int64_t y) {
                             const double px = pos[3 * x + axis], py = pos[3 * y + axis];
                             return px < py || (px == py && x < y);
                         });
        for (int64_t i = lo; i < hi; ++i) stamp[ids[i]] = i < mid ? s0 : s1;
        // the border of each half towards the other; the smaller is the separator
        border[0] = border[1] = 0;
        std::fill(on.begin(), on.end(), 0);
        for (int64_t i = lo; i < hi; ++i) {
            const int64_t v = ids[i], other = stamp[v] == s0 ? s1 : s0;
            for (int64_t p = S.start[v]; p < S.start[v + 1]; ++p)
                if (stamp[S.col[p]] == other) {
                    on[i - lo] = 1;
                    ++border[i < mid ? 0 : 1];
                    break;
                }
        }
        if (t == 3) break;
        const int64_t cut = std::min(border[0], border[1]);
        if (best < 0 || cut < best_size) {
            best = axis;
            best_size = cut;
        }
    }
    const int side = border[0] <= border[1] ? 0 : 1;
    std::vector<int64_t> left, right, cut;
    for (int64_t i = lo; i < hi; ++i) {
        const int h = i < mid ? 0 : 1;
        if (on[i - lo] && h == side) {
            cut.push_back(ids[i]);
            stamp[ids[i]] = sep;
        } else {
            (h == 0 ? left : right).push_back(ids[i]);
        }
    }
    if (left.empty() || right.empty()) {  // no cut helps: order the set as it comes
        for (int64_t i = lo; i < hi; ++i) perm.push_back(ids[i]);
        return;
    }
    int64_t at = lo;
    for (int64_t v : left) ids[at++] = v;
    const int64_t lhi = at;
    for (int64_t v : right) ids[at++] = v;
    const int64_t rhi = at;
    for (int64_t v : cut) ids[at++] = v;
    dissect(S, pos, ids, lo, lhi, stamp, stamps, perm);
    dissect(S, pos, ids, lhi, rhi, stamp, stamps, perm);
    for (int64_t i = rhi; i < hi; ++i) perm.push_back(ids[i]);
}

// The plan's connectivity: selection, compact numbering, C's pattern, the system's pattern.
Plan make_plan(const int64_t* F, int64_t m, int64_t n, const int64_t* freev,
               int64_t nf, int k) {
    Plan P;
    const std::vector<int64_t> sel = select_faces(F, m, n, freev, nf, k + 2);
    std::vector<int64_t> cid(static_cast<size_t>(n), -1);
    P.nf = nf;
    for (int64_t i = 0; i < nf; ++i) {
        cid[freev[i]] = i;
        P.vid.push_back(freev[i]);
    }
    std::vector<uint8_t> used(static_cast<size_t>(n), 0);
    for (int64_t t : sel)
        for (int c = 0; c < 3; ++c) used[F[3 * t + c]] = 1;
    for (int64_t v = 0; v < n; ++v)
        if (used[v] && cid[v] < 0) {
            cid[v] = static_cast<int64_t>(P.vid.size());
            P.vid.push_back(v);
        }
    P.nc = static_cast<int64_t>(P.vid.size());
    P.faces.resize(3 * sel.size());
    for (size_t t = 0; t < sel.size(); ++t)
        for (int c = 0; c < 3; ++c) P.faces[3 * t + c] = cid[F[3 * sel[t] + c]];
    // C's pattern: each vertex, its neighbours, sorted (each corner c adds (i, j), (j, i),
    // (i, i), (j, j) for its opposite side i, j); then each corner's four slots in it
    const int64_t nc = P.nc;
    const size_t nt = sel.size();
    std::vector<int64_t> fstart(static_cast<size_t>(nc) + 1, 0), fof(3 * nt);
    for (size_t t = 0; t < 3 * nt; ++t) ++fstart[P.faces[t] + 1];
    for (int64_t v = 0; v < nc; ++v) fstart[v + 1] += fstart[v];
    {
        std::vector<int64_t> next(fstart.begin(), fstart.end() - 1);
        for (size_t t = 0; t < 3 * nt; ++t) fof[next[P.faces[t]]++] = static_cast<int64_t>(t / 3);
    }
    std::vector<int64_t> seen(static_cast<size_t>(nc), -1);
    P.C.start.assign(static_cast<size_t>(nc) + 1, 0);
    for (int64_t v = 0; v < nc; ++v) {
        const size_t row = P.C.col.size();
        P.C.col.push_back(v);
        seen[v] = v;
        for (int64_t p = fstart[v]; p < fstart[v + 1]; ++p)
            for (int q = 0; q < 3; ++q) {
                const int64_t w = P.faces[3 * fof[p] + q];
                if (seen[w] != v) {
                    seen[w] = v;
                    P.C.col.push_back(w);
                }
            }
        std::sort(P.C.col.begin() + static_cast<std::ptrdiff_t>(row), P.C.col.end());
        P.C.start[v + 1] = static_cast<int64_t>(P.C.col.size());
    }
    P.C.val.assign(P.C.col.size(), 0.0);
    auto at = [&](int64_t i, int64_t j) {
        int64_t p = P.C.start[i];
        while (P.C.col[p] != j) ++p;
        return p;
    };
    P.slot.resize(12 * nt);
    for (size_t t = 0; t < nt; ++t) {
        const int64_t* f = &P.faces[3 * t];
        for (int q = 0; q < 3; ++q) {
            const int64_t i = f[(q + 1) % 3], j = f[(q + 2) % 3];
            int64_t* s = &P.slot[12 * t + 4 * q];
            s[0] = at(i, j);
            s[1] = at(j, i);
            s[2] = at(i, i);
            s[3] = at(j, j);
        }
    }
    // the system's pattern: (C A^-1)^k C's free rows within the free columns, reached
    // through k intermediate rows of C
    std::vector<int64_t> mark(static_cast<size_t>(P.nc), -1);
    std::vector<int64_t> front, next;
    P.S.start.assign(static_cast<size_t>(nf) + 1, 0);
    for (int64_t i = 0; i < nf; ++i) {
        front.assign(1, i);
        mark[i] = i;
        std::vector<int64_t> reach(1, i);
        for (int step = 0; step <= k; ++step) {
            next.clear();
            for (int64_t u : front)
                for (int64_t p = P.C.start[u]; p < P.C.start[u + 1]; ++p) {
                    const int64_t w = P.C.col[p];
                    if (mark[w] != i) {
                        mark[w] = i;
                        reach.push_back(w);
                        next.push_back(w);
                    }
                }
            front.swap(next);
        }
        std::sort(reach.begin(), reach.end());
        for (int64_t w : reach)
            if (w < nf) P.S.col.push_back(w);
        P.S.start[i + 1] = static_cast<int64_t>(P.S.col.size());
    }
    P.S.val.assign(P.S.col.size(), 0.0);
    return P;
}

// The order and the symbolic factorization under it, from the free vertices' positions X
// (compact, 3 a vertex): nested dissection, then LDL's ldl_symbolic (elimination tree and
// column counts of L). Taken again at each pass, so that two passes equal two solves.
void order(Plan& P, const std::vector<double>& X) {
    const int64_t nf = P.nf;
    std::vector<int64_t> ids(static_cast<size_t>(nf)), stamp(static_cast<size_t>(nf), -1);
    for (int64_t i = 0; i < nf; ++i) ids[i] = i;
    int64_t stamps = 0;
    P.perm.clear();
    P.perm.reserve(static_cast<size_t>(nf));
    dissect(P.S, X.data(), ids, 0, nf, stamp, stamps, P.perm);
    P.pinv.assign(static_cast<size_t>(nf), 0);
    for (int64_t q = 0; q < nf; ++q) P.pinv[P.perm[q]] = q;
    P.parent.assign(static_cast<size_t>(nf), -1);
    std::vector<int64_t> flag(static_cast<size_t>(nf)), lnz(static_cast<size_t>(nf), 0);
    for (int64_t q = 0; q < nf; ++q) {
        flag[q] = q;
        const int64_t kk = P.perm[q];
        for (int64_t p = P.S.start[kk]; p < P.S.start[kk + 1]; ++p) {
            for (int64_t i = P.pinv[P.S.col[p]]; i < q && flag[i] != q; i = P.parent[i]) {
                if (P.parent[i] == -1) P.parent[i] = q;
                ++lnz[i];
                flag[i] = q;
            }
        }
    }
    P.lp.assign(static_cast<size_t>(nf) + 1, 0);
    for (int64_t q = 0; q < nf; ++q) P.lp[q + 1] = P.lp[q] + lnz[q];
}

// One pass: C and A at positions X (compact, 3 a vertex), the system and its solution;
// X's free rows are replaced by the solution when the status is OK.
int solve_pass(const Plan& P, std::vector<double>& X, int k, int64_t& where,
               std::vector<int64_t>& li, std::vector<double>& lx) {
    const int64_t nf = P.nf, nc = P.nc;
    const size_t nfaces = P.faces.size() / 3;
    std::vector<double> cval(P.C.col.size(), 0.0), area(static_cast<size_t>(nc), 0.0);
    for (size_t t = 0; t < nfaces; ++t) {
        const int64_t* f = &P.faces[3 * t];
        const Corners q = corners(X.data(), f);
        const int64_t* s = &P.slot[12 * t];
        for (int c = 0; c < 3; ++c) {
            const double w = -0.5 * q.cot[c];
            cval[s[4 * c]] += w;
            cval[s[4 * c + 1]] += w;
            cval[s[4 * c + 2]] += -w;
            cval[s[4 * c + 3]] += -w;
        }
        const bool any_obtuse = q.cot[0] < 0 || q.cot[1] < 0 || q.cot[2] < 0;
        for (int c = 0; c < 3; ++c) {
            const int c1 = (c + 1) % 3, c2 = (c + 2) % 3;
            const double vor = (q.sq[c2] * q.cot[c2] + q.sq[c1] * q.cot[c1]) / 8;
            area[f[c]] += any_obtuse ? (q.cot[c] < 0 ? q.area / 2 : q.area / 4) : vor;
        }
    }
    for (int64_t i = 0; i < nf; ++i)
        if (!(area[i] > 0)) {
            where = P.vid[i];
            return NO_AREA;
        }
    std::vector<double> inv(static_cast<size_t>(nc), 0.0);
    for (int64_t v = 0; v < nc; ++v)
        if (area[v] > 0) inv[v] = 1.0 / area[v];
    // rows of op = C (A^-1 op'), op' the operator one order lower, by a dense accumulator
    std::vector<double> acc(static_cast<size_t>(nc), 0.0);
    std::vector<int64_t> mark(static_cast<size_t>(nc), -1), touched;
    // rows of C A^-1 C (for continuity 2), on demand
    std::vector<int64_t> brow_of;
    Csr B;
    auto c_times = [&](int64_t row, auto&& right_row) {
        // acc[j] += C[row, l] * (inv[l] * R[l, j]) over l, R's row given by right_row(l, fn)
        touched.clear();
        for (int64_t p = P.C.start[row]; p < P.C.start[row + 1]; ++p) {
            const int64_t l = P.C.col[p];
            const double cl = cval[p];
            right_row(l, [&](int64_t j, double rv) {
                if (mark[j] != row) {
                    mark[j] = row;
                    acc[j] = 0.0;
                    touched.push_back(j);
                }
                acc[j] += cl * (inv[l] * rv);
            });
        }
    };
    auto c_row = [&](int64_t l, auto&& fn) {
        for (int64_t p = P.C.start[l]; p < P.C.start[l + 1]; ++p) fn(P.C.col[p], cval[p]);
    };
    if (k == 2) {
        brow_of.assign(static_cast<size_t>(nc), -1);
        B.start.push_back(0);
        for (int64_t i = 0; i < nf; ++i)
            for (int64_t p = P.C.start[i]; p < P.C.start[i + 1]; ++p) {
                const int64_t l = P.C.col[p];
                if (brow_of[l] >= 0) continue;
                brow_of[l] = static_cast<int64_t>(B.start.size()) - 1;
                c_times(l, c_row);
                for (int64_t j : touched) {
                    B.col.push_back(j);
                    B.val.push_back(acc[j]);
                    mark[j] = -1;
                }
                B.start.push_back(static_cast<int64_t>(B.col.size()));
            }
    }
    auto b_row = [&](int64_t l, auto&& fn) {
        const int64_t b = brow_of[l];
        for (int64_t p = B.start[b]; p < B.start[b + 1]; ++p) fn(B.col[p], B.val[p]);
    };
    std::vector<double> sval(P.S.col.size(), 0.0);
    std::vector<double> rhs(3 * static_cast<size_t>(nf), 0.0);
    for (int64_t i = 0; i < nf; ++i) {
        touched.clear();
        if (k == 0) {
            for (int64_t p = P.C.start[i]; p < P.C.start[i + 1]; ++p) {
                const int64_t j = P.C.col[p];
                mark[j] = i;
                acc[j] = cval[p];
                touched.push_back(j);
            }
        } else if (k == 1) {
            c_times(i, c_row);
        } else {
            c_times(i, b_row);
        }
        double s[3] = {0.0, 0.0, 0.0};
        for (int64_t j : touched)
            if (j >= nf)
                for (int a = 0; a < 3; ++a) s[a] += acc[j] * X[3 * j + a];
        for (int a = 0; a < 3; ++a) rhs[3 * i + a] = -s[a];
        for (int64_t p = P.S.start[i]; p < P.S.start[i + 1]; ++p) {
            const int64_t j = P.S.col[p];
            sval[p] = mark[j] == i ? acc[j] : 0.0;
        }
        for (int64_t j : touched) mark[j] = -1;
    }
    // numeric LDL^T, up-looking (LDL's ldl_numeric), row q of L from column perm[q] of S
    const std::vector<int64_t>& perm = P.perm;
    const std::vector<int64_t>& pinv = P.pinv;
    const std::vector<int64_t>& parent = P.parent;
    const std::vector<int64_t>& lp = P.lp;
    li.assign(static_cast<size_t>(lp[nf]), 0);
    lx.assign(static_cast<size_t>(lp[nf]), 0.0);
    std::vector<double> y(static_cast<size_t>(nf), 0.0), d(static_cast<size_t>(nf), 0.0);
    std::vector<int64_t> flag(static_cast<size_t>(nf), -1), lnz(static_cast<size_t>(nf), 0),
        pattern(static_cast<size_t>(nf));
    for (int64_t q = 0; q < nf; ++q) {
        int64_t top = nf;
        flag[q] = q;
        const int64_t kk = perm[q];
        for (int64_t p = P.S.start[kk]; p < P.S.start[kk + 1]; ++p) {
            int64_t i = pinv[P.S.col[p]];
            if (i > q) continue;
            y[i] += sval[p];
            int64_t len = 0;
            for (; flag[i] != q; i = parent[i]) {
                pattern[len++] = i;
                flag[i] = q;
            }
            while (len > 0) pattern[--top] = pattern[--len];
        }
        double dq = y[q];
        y[q] = 0.0;
        for (; top < nf; ++top) {
            const int64_t i = pattern[top];
            const double yi = y[i];
            y[i] = 0.0;
            const int64_t p2 = lp[i] + lnz[i];
            int64_t p = lp[i];
            for (; p < p2; ++p) y[li[p]] -= lx[p] * yi;
            const double lki = yi / d[i];
            dq -= lki * yi;
            li[p] = q;
            lx[p] = lki;
            ++lnz[i];
        }
        if (dq == 0.0 || !std::isfinite(dq)) {
            where = q;
            return BAD_PIVOT;
        }
        d[q] = dq;
    }
    // solve L D L^T (P x) = P b for the three coordinates at once
    std::vector<double> z(3 * static_cast<size_t>(nf));
    for (int64_t q = 0; q < nf; ++q)
        for (int a = 0; a < 3; ++a) z[3 * q + a] = rhs[3 * perm[q] + a];
    for (int64_t j = 0; j < nf; ++j)
        for (int64_t p = lp[j]; p < lp[j + 1]; ++p)
            for (int a = 0; a < 3; ++a) z[3 * li[p] + a] -= lx[p] * z[3 * j + a];
    for (int64_t j = 0; j < nf; ++j)
        for (int a = 0; a < 3; ++a) z[3 * j + a] /= d[j];
    for (int64_t j = nf - 1; j >= 0; --j)
        for (int64_t p = lp[j]; p < lp[j + 1]; ++p)
            for (int a = 0; a < 3; ++a) z[3 * j + a] -= lx[p] * z[3 * li[p] + a];
    for (int64_t q = 0; q < nf; ++q)
        for (int a = 0; a < 3; ++a)
            if (!std::isfinite(z[3 * q + a])) return NOT_FINITE;
    for (int64_t q = 0; q < nf; ++q)
        for (int a = 0; a < 3; ++a) X[3 * perm[q] + a] = z[3 * q + a];
    return OK;
}

Result solve(const double* V, int64_t n, const int64_t* F, int64_t m, const int64_t* freev,
             int64_t nf, int k, int64_t passes) {
    Result R;
    Plan P = make_plan(F, m, n, freev, nf, k);
    std::vector<double> X(3 * static_cast<size_t>(P.nc));
    for (int64_t v = 0; v < P.nc; ++v)
        for (int a = 0; a < 3; ++a) X[3 * v + a] = V[3 * P.vid[v] + a];
    std::vector<int64_t> li;
    std::vector<double> lx;
    for (int64_t pass = 0; pass < passes; ++pass) {
        order(P, X);
        R.status = solve_pass(P, X, k, R.where, li, lx);
        if (R.status != OK) return R;
    }
    R.x.assign(X.begin(), X.begin() + 3 * nf);
    return R;
}

// Entries of L (the fill) under this module's order: for measuring the order.
int64_t fill(const double* V, int64_t n, const int64_t* F, int64_t m, const int64_t* freev,
             int64_t nf, int k) {
    Plan P = make_plan(F, m, n, freev, nf, k);
    std::vector<double> X(3 * static_cast<size_t>(P.nc));
    for (int64_t v = 0; v < P.nc; ++v)
        for (int a = 0; a < 3; ++a) X[3 * v + a] = V[3 * P.vid[v] + a];
    order(P, X);
    return P.lp[nf];
}

}  // namespace fair

namespace {

using arrays::In;
using arrays::need;

void check(const In<double>& V, const In<int64_t>& F, const In<int64_t>& freev, int k,
           int64_t passes) {
    const char* mod = "optri._core.fair";
    need(V.ndim() == 2 && V.shape(1) == 3, mod, "vertices must be (n, 3)");
    need(F.ndim() == 2 && F.shape(1) == 3, mod, "faces must be (m, 3)");
    need(freev.ndim() == 1, mod, "free must be one-dimensional");
    need(k >= 0 && k <= 2, mod, "continuity must be 0, 1 or 2");
    need(passes >= 1, mod, "passes must be >= 1");
    const int64_t n = static_cast<int64_t>(V.shape(0));
    const int64_t* f = F.data();
    const size_t total = 3 * F.shape(0);
    for (size_t r = 0; r < total; ++r) need(f[r] >= 0 && f[r] < n, mod, "face index out of range");
    const int64_t* fr = freev.data();
    for (size_t i = 0; i < freev.shape(0); ++i) {
        need(fr[i] >= 0 && fr[i] < n, mod, "free vertex out of range");
        need(i == 0 || fr[i] > fr[i - 1], mod, "free vertices must be sorted and distinct");
    }
}

}  // namespace

void bind_fair(nb::module_& m) {
    nb::module_ s = m.def_submodule("fair", "The fairing solve of optri.holes.fair.");
    s.def("solve", [](In<double> V, In<int64_t> F, In<int64_t> freev, int k, int64_t passes) {
        check(V, F, freev, k, passes);
        fair::Result R;
        {
            nb::gil_scoped_release nogil;
            R = fair::solve(V.data(), static_cast<int64_t>(V.shape(0)), F.data(),
                            static_cast<int64_t>(F.shape(0)), freev.data(),
                            static_cast<int64_t>(freev.shape(0)), k, passes);
        }
        const size_t nf = R.status == fair::OK ? freev.shape(0) : 0;
        return nb::make_tuple(R.status, R.where, arrays::owning(std::move(R.x), {nf, 3}));
    }, nb::arg("vertices"), nb::arg("faces"), nb::arg("free"), nb::arg("continuity"),
       nb::arg("passes"),
       "(status, where, positions): status 0 solved (positions of the free vertices), 1 a free "
       "vertex (where) without area, 2 a zero or non-finite pivot (column where), 3 a "
       "non-finite solution.");
    s.def("fill", [](In<double> V, In<int64_t> F, In<int64_t> freev, int k) {
        check(V, F, freev, k, 1);
        nb::gil_scoped_release nogil;
        return fair::fill(V.data(), static_cast<int64_t>(V.shape(0)), F.data(),
                          static_cast<int64_t>(F.shape(0)), freev.data(),
                          static_cast<int64_t>(freev.shape(0)), k);
    }, nb::arg("vertices"), nb::arg("faces"), nb::arg("free"), nb::arg("continuity"),
       "Entries below the diagonal of the system's L factor under the solve's order.");
}

}  // namespace optri
