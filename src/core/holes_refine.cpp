// optri._core.refine: a hole patch's refinement (Liepa's centroid splits and diametral
// edge relaxation) and the patch-against-mesh crossing check, bound for optri.holes.
//
// Both are the compiled twins of the Python references in optri/holes/refine.py and
// optri/holes/intersect.py, which the tests compare them with: every float expression
// is written in the Python source's order (the build has -ffp-contract=off), and the
// distances of the split test follow CPython's math.dist (scaled, compensated sum of
// squares, one correction step), so both decide every split and swap alike.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "arrays.hpp"
#include "bind.hpp"

namespace nb = nanobind;

namespace optri {

namespace refine {

struct P3 {
    double x, y, z;
};

struct Tri {
    int64_t a, b, c;
};

// ---------------------------------------------------------------- math.dist

struct DL {
    double hi, lo;
};

inline DL dl_fast_sum(double a, double b) {
    double x = a + b;
    double y = (a - x) + b;
    return {x, y};
}

inline DL dl_split(double x) {
    double t = x * 134217729.0;
    double hi = t - (t - x);
    double lo = x - hi;
    return {hi, lo};
}

inline DL dl_mul(double x, double y) {
    DL xx = dl_split(x);
    DL yy = dl_split(y);
    double p = xx.hi * yy.hi;
    double q = xx.hi * yy.lo + xx.lo * yy.hi;
    double z = p + q;
    double zz = p - z + q + xx.lo * yy.lo;
    return {z, zz};
}

// CPython's vector_norm for finite input (math.dist of two 3-D points)
double vector_norm(double* vec, int n, double max) {
    if (std::isinf(max)) return max;
    if (max == 0.0 || n <= 1) return max;
    int max_e = 0;
    std::frexp(max, &max_e);
    if (max_e < -1023) {
        for (int i = 0; i < n; ++i) vec[i] /= 2.2250738585072014e-308;
        return 2.2250738585072014e-308 * vector_norm(vec, n, max / 2.2250738585072014e-308);
    }
    double scale = std::ldexp(1.0, -max_e);
    double csum = 1.0, frac1 = 0.0, frac2 = 0.0;
    for (int i = 0; i < n; ++i) {
        double x = vec[i] * scale;
        DL pr = dl_mul(x, x);
        DL sm = dl_fast_sum(csum, pr.hi);
        csum = sm.hi;
        frac1 += pr.lo;
        frac2 += sm.lo;
    }
    double h = std::sqrt(csum - 1.0 + (frac1 + frac2));
    DL pr = dl_mul(-h, h);
    DL sm = dl_fast_sum(csum, pr.hi);
    csum = sm.hi;
    frac1 += pr.lo;
    frac2 += sm.lo;
    double x = csum - 1.0 + (frac1 + frac2);
    h += x / (2.0 * h);
    return h / scale;
}

double dist(const P3& p, const P3& q) {
    double d[3] = {std::fabs(p.x - q.x), std::fabs(p.y - q.y), std::fabs(p.z - q.z)};
    bool nan = false;
    double max = 0.0;
    for (double v : d) {
        nan |= std::isnan(v);
        if (v > max) max = v;
    }
    if (nan) return std::nan("");
    return vector_norm(d, 3, max);
}

// ---------------------------------------------------------------- relaxation

inline uint64_t key(int64_t u, int64_t v) {
    return (static_cast<uint64_t>(u) << 32) | static_cast<uint64_t>(static_cast<uint32_t>(v));
}

inline uint64_t ukey(int64_t u, int64_t v) { return u < v ? key(u, v) : key(v, u); }

inline P3 sub(const P3& a, const P3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline double dot(const P3& u, const P3& v) { return u.x * v.x + u.y * v.y + u.z * v.z; }
inline P3 cross(const P3& u, const P3& v) {
    return {u.y * v.z - u.z * v.y, u.z * v.x - u.x * v.z, u.x * v.y - u.y * v.x};
}
inline P3 normal(const P3& a, const P3& b, const P3& c) { return cross(sub(b, a), sub(c, a)); }

double cosine(const P3& a, const P3& b) {
    double na = dot(a, a), nb_ = dot(b, b);
    if (na == 0.0 || nb_ == 0.0) return 1.0;
    return dot(a, b) / std::sqrt(na * nb_);
}

bool inside_sphere(const P3& a, const P3& b, const P3& c, const P3& d) {
    double ax = a.x, ay = a.y, az = a.z;
    double bx = b.x - ax, by = b.y - ay, bz = b.z - az;
    double cx = c.x - ax, cy = c.y - ay, cz = c.z - az;
    double nx = by * cz - bz * cy, ny = bz * cx - bx * cz, nz = bx * cy - by * cx;
    double nn = nx * nx + ny * ny + nz * nz;
    if (nn == 0.0) return true;
    double s = (cx * cx + cy * cy + cz * cz) / (2 * nn);
    double t = (bx * bx + by * by + bz * bz) / (2 * nn);
    double ox = (ny * bz - nz * by) * s + (cy * nz - cz * ny) * t;
    double oy = (nz * bx - nx * bz) * s + (cz * nx - cx * nz) * t;
    double oz = (nx * by - ny * bx) * s + (cx * ny - cy * nx) * t;
    double r2 = ox * ox + oy * oy + oz * oz;
    double dx = d.x - ax - ox, dy = d.y - ay - oy, dz = d.z - az - oz;
    return dx * dx + dy * dy + dz * dz < r2 * (1 - 1e-12);
}

// refine.py's _folds: a swap may leave its faces nearly flat; otherwise it may not
// sharpen their fold, nor cross a crease sharper than crease_cos
bool folds(const P3& u, const P3& v, const P3& x, const P3& y, double fold_cos,
           double crease_cos) {
    double old = cosine(normal(u, v, x), normal(v, u, y));
    double nw = cosine(normal(u, y, x), normal(v, x, y));
    if (nw >= fold_cos) return false;
    return nw < old || old < crease_cos;
}

inline int64_t third(const Tri& f, int64_t u, int64_t v) {
    (void)v;
    if (f.a == u) return f.c;
    return f.b == u ? f.a : f.b;
}

struct Refiner {
    const double* pts;
    int64_t base;
    std::vector<P3> added;

    P3 point(int64_t i) const {
        if (i < base) return {pts[3 * i], pts[3 * i + 1], pts[3 * i + 2]};
        return added[static_cast<size_t>(i - base)];
    }
};

using Sides = std::unordered_map<uint64_t, int64_t>;  // directed edge -> its face

// refine.py's _sides
Sides sides(const std::vector<Tri>& faces) {
    Sides where;
    where.reserve(faces.size() * 3);
    for (size_t t = 0; t < faces.size(); ++t) {
        const Tri f = faces[t];
        const int64_t i = static_cast<int64_t>(t);
        where[key(f.a, f.b)] = i, where[key(f.b, f.c)] = i, where[key(f.c, f.a)] = i;
    }
    return where;
}

// what no swap may take away or make, and the fold limits of refine.py's _folds
struct Guards {
    const std::unordered_set<uint64_t>& fixed;
    const std::unordered_set<uint64_t>& blocked;
    double fold_cos, crease_cos;
};

// refine.py's _swap: swap u-v in place if it fails the diametral-sphere test
bool swap_edge(std::vector<Tri>& faces, Sides& where, int64_t u, int64_t v, const Refiner& R,
               const Guards& g) {
    auto i1 = where.find(key(u, v));
    auto i2 = where.find(key(v, u));
    if (i1 == where.end() || i2 == where.end() || g.fixed.count(ukey(u, v))) return false;
    const int64_t t1 = i1->second, t2 = i2->second;
    const int64_t x = third(faces[t1], u, v);
    const int64_t y = third(faces[t2], v, u);
    if (x == y || where.count(key(x, y)) || where.count(key(y, x)) ||
        g.blocked.count(ukey(x, y))) {
        return false;
    }
    const P3 pu = R.point(u), pv = R.point(v), px = R.point(x), py = R.point(y);
    if (!(inside_sphere(pu, pv, px, py) || inside_sphere(pv, pu, py, px))) return false;
    if (folds(pu, pv, px, py, g.fold_cos, g.crease_cos)) return false;
    faces[t1] = {u, y, x};
    faces[t2] = {v, x, y};
    where.erase(key(u, v));
    where.erase(key(v, u));
    where[key(u, y)] = t1, where[key(y, x)] = t1, where[key(x, u)] = t1;
    where[key(v, x)] = t2, where[key(x, y)] = t2, where[key(y, v)] = t2;
    return true;
}

// refine.py's _sweep: every interior edge once, in the order the faces first name it
void sweep(std::vector<Tri>& faces, Sides& where, const Refiner& R, const Guards& g) {
    std::vector<std::pair<int64_t, int64_t>> edges;
    edges.reserve(faces.size() * 3 / 2);
    for (size_t t = 0; t < faces.size(); ++t) {
        const Tri f = faces[t];
        const int64_t e[3][2] = {{f.a, f.b}, {f.b, f.c}, {f.c, f.a}};
        for (auto& uv : e) {
            auto across = where.find(key(uv[1], uv[0]));
            if (across != where.end() && across->second > static_cast<int64_t>(t)) {
                edges.emplace_back(uv[0], uv[1]);
            }
        }
    }
    for (auto [u, v] : edges) swap_edge(faces, where, u, v, R, g);
}

// ---------------------------------------------------------------- crossings

constexpr double kEps = 1e-9;
constexpr double kWide = 8.0;

inline P3 row(const double* v, int64_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }

inline double norm(const P3& a) { return std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z); }

// intersect.py's _segment_hits_triangle for one row
bool segment_hits(const P3& s0, const P3& s1, const P3& t0, const P3& t1, const P3& t2) {
    P3 d = sub(s1, s0);
    P3 e1 = sub(t1, t0), e2 = sub(t2, t0);
    P3 h = cross(d, e2);
    double det = dot(e1, h);
    double scale = norm(e1) * norm(e2) * norm(d);
    bool good = std::fabs(det) > 1e-12 * std::max(scale, 1e-300);
    if (!good) return false;
    double inv = 1.0 / det;
    P3 sv = sub(s0, t0);
    double u = inv * dot(sv, h);
    P3 q = cross(sv, e1);
    double w = inv * dot(d, q);
    double t = inv * dot(e2, q);
    return (u > kEps) && (w > kEps) && (u + w < 1 - kEps) && (t > kEps) && (t < 1 - kEps);
}

bool crosses(const double* v, const int64_t* A, const int64_t* B) {
    int shared = 0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) shared += A[i] == B[j];
    if (shared > 1) return false;
    const int64_t* pair[2][2] = {{A, B}, {B, A}};
    for (auto& fs : pair) {
        const int64_t* first = fs[0];
        const int64_t* second = fs[1];
        for (int e = 0; e < 3; ++e) {
            int64_t s0 = first[e], s1 = first[(e + 1) % 3];
            if (shared == 1) {
                bool opposite = true;
                for (int j = 0; j < 3; ++j) opposite &= s0 != second[j] && s1 != second[j];
                if (!opposite) continue;
            }
            if (segment_hits(row(v, s0), row(v, s1), row(v, second[0]), row(v, second[1]),
                             row(v, second[2]))) {
                return true;
            }
        }
    }
    return false;
}

struct Box {
    double lo[3], hi[3];
};

Box box(const double* v, const int64_t* f) {
    Box b;
    for (int k = 0; k < 3; ++k) {
        double a = v[3 * f[0] + k], c = v[3 * f[1] + k], d = v[3 * f[2] + k];
        b.lo[k] = std::min(std::min(a, c), d);
        b.hi[k] = std::max(std::max(a, c), d);
    }
    return b;
}

inline bool meets(const Box& f, const Box& p, double pad) {
    for (int k = 0; k < 3; ++k) {
        if (!(f.lo[k] <= p.hi[k] + pad && f.hi[k] >= p.lo[k] - pad)) return false;
    }
    return true;
}

std::vector<int64_t> intersecting_pairs(const double* v, const int64_t* f, int64_t nf,
                                        const int64_t* p, int64_t np_) {
    std::vector<int64_t> out;
    if (nf == 0 || np_ == 0) return out;
    std::vector<Box> fb(nf), pb(np_);
    double lo[3], hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int64_t i = 0; i < nf; ++i) fb[i] = box(v, f + 3 * i);
    for (int64_t i = 0; i < np_; ++i) pb[i] = box(v, p + 3 * i);
    Box whole;
    for (int k = 0; k < 3; ++k) whole.lo[k] = INFINITY, whole.hi[k] = -INFINITY;
    for (const Box& b : fb)
        for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
    for (const Box& b : pb)
        for (int k = 0; k < 3; ++k) {
            lo[k] = std::min(lo[k], b.lo[k]), hi[k] = std::max(hi[k], b.hi[k]);
            whole.lo[k] = std::min(whole.lo[k], b.lo[k]);
            whole.hi[k] = std::max(whole.hi[k], b.hi[k]);
        }
    double span = std::max(std::max(hi[0] - lo[0], hi[1] - lo[1]), hi[2] - lo[2]);
    const double pad = kEps * std::max(span, 1e-300);
    std::vector<int64_t> near;
    for (int64_t i = 0; i < nf; ++i)
        if (meets(fb[i], whole, pad)) near.push_back(i);
    if (near.empty()) return out;
    // candidates from a uniform grid over the patch's box: a nearby face is listed in
    // every cell its padded box meets, a patch face looks in the cells its box meets
    // (boxes that meet share a cell: the cell of a coordinate is monotone in it). Faces
    // much larger than the rest would fill many cells: they are tested against every
    // patch face directly
    auto size = [&](const Box& b) {
        return std::max(std::max(b.hi[0] - b.lo[0], b.hi[1] - b.lo[1]), b.hi[2] - b.lo[2]);
    };
    std::vector<double> extent(near.size());
    for (size_t j = 0; j < near.size(); ++j) extent[j] = size(fb[near[j]]);
    std::vector<double> sorted_ext = extent;
    auto mid = sorted_ext.begin() + static_cast<std::ptrdiff_t>(sorted_ext.size() / 2);
    std::nth_element(sorted_ext.begin(), mid, sorted_ext.end());
    const double median = *mid;
    const double cut = kWide * std::max(median, pad);
    std::vector<int64_t> narrow, wide;
    for (size_t j = 0; j < near.size(); ++j) (extent[j] > cut ? wide : narrow).push_back(near[j]);
    // cells about a median face wide, at most a few per face
    double cell = std::max(median, pad);
    const double budget = 4.0 * static_cast<double>(narrow.size() + static_cast<size_t>(np_)) + 64;
    auto cells_of = [&](double h) {
        double total = 1;
        for (int k = 0; k < 3; ++k) total *= std::floor((whole.hi[k] - whole.lo[k]) / h) + 1;
        return total;
    };
    const bool finite = std::isfinite(cells_of(1.0)) && std::isfinite(cell) && cell > 0;
    while (finite && !(cells_of(cell) <= budget)) cell *= 2;
    int64_t dim[3] = {1, 1, 1};
    for (int k = 0; finite && k < 3; ++k) {
        dim[k] = static_cast<int64_t>(std::floor((whole.hi[k] - whole.lo[k]) / cell)) + 1;
    }
    auto index = [&](int k, double x) {
        if (dim[k] == 1) return int64_t(0);
        double c = std::floor((x - whole.lo[k]) / cell);
        if (!(c > 0)) return int64_t(0);
        return std::min(static_cast<int64_t>(std::min(c, 9.0e15)), dim[k] - 1);
    };
    auto range = [&](const Box& b, double grow, int64_t* lo_, int64_t* hi_) {
        for (int k = 0; k < 3; ++k) lo_[k] = index(k, b.lo[k] - grow), hi_[k] = index(k, b.hi[k] + grow);
    };
    const int64_t ncell = dim[0] * dim[1] * dim[2];
    std::vector<int64_t> start(static_cast<size_t>(ncell) + 1, 0);
    int64_t a[3], z[3];
    std::vector<int64_t> members, fill;
    for (int pass = 0; pass < 2; ++pass) {  // count the members of each cell, then list them
        if (pass == 1) {
            for (int64_t c = 0; c < ncell; ++c) start[c + 1] += start[c];
            fill.assign(start.begin(), start.end() - 1);
            members.assign(static_cast<size_t>(start[ncell]), 0);
        }
        for (int64_t fi : narrow) {
            range(fb[fi], pad, a, z);
            for (int64_t i = a[0]; i <= z[0]; ++i)
                for (int64_t j = a[1]; j <= z[1]; ++j)
                    for (int64_t k = a[2]; k <= z[2]; ++k) {
                        const int64_t c = (i * dim[1] + j) * dim[2] + k;
                        if (pass == 0) {
                            ++start[c + 1];
                        } else {
                            members[static_cast<size_t>(fill[c]++)] = fi;
                        }
                    }
        }
        if (pass == 0) continue;
        std::vector<int64_t> seen(static_cast<size_t>(nf), -1);
        std::vector<int64_t> hits;
        for (int64_t q = 0; q < np_; ++q) {
            hits.clear();
            const Box& b = pb[q];
            for (int64_t w : wide)
                if (meets(fb[w], b, pad)) hits.push_back(w);
            range(b, 0.0, a, z);
            for (int64_t i = a[0]; i <= z[0]; ++i)
                for (int64_t j = a[1]; j <= z[1]; ++j)
                    for (int64_t k = a[2]; k <= z[2]; ++k) {
                        const int64_t c = (i * dim[1] + j) * dim[2] + k;
                        for (int64_t s = start[c]; s < start[c + 1]; ++s) {
                            const int64_t fi = members[static_cast<size_t>(s)];
                            if (seen[fi] == q) continue;
                            seen[fi] = q;
                            if (meets(fb[fi], b, pad)) hits.push_back(fi);
                        }
                    }
            std::sort(hits.begin(), hits.end());
            for (int64_t c : hits) {
                if (crosses(v, p + 3 * q, f + 3 * c)) {
                    out.push_back(q);
                    out.push_back(c);
                }
            }
        }
    }
    return out;
}

}  // namespace refine

namespace {

using arrays::In;
using arrays::NewArray;

void need(bool ok, const char* what) { arrays::need(ok, "optri._core.refine", what); }

template <class T>
NewArray<T> from_vector(std::vector<T>&& data, size_t rows, size_t cols) {
    return arrays::owning(std::move(data), {rows, cols});
}

void check_faces(const In<int64_t>& F, int64_t rows, const char* what) {
    need(F.ndim() == 2 && F.shape(1) == 3, what);
    const int64_t* f = F.data();
    for (size_t r = 0; r < 3 * F.shape(0); ++r) need(f[r] >= 0 && f[r] < rows, "vertex index");
}

}  // namespace

void bind_refine(nb::module_& m) {
    nb::module_ r = m.def_submodule("refine", "A hole patch's refinement and crossing check.");

    r.def("refine_patch", [](In<double> V, In<int64_t> patch, In<int64_t> loop,
                             In<double> scales, double density, int64_t max_rounds,
                             In<int64_t> forbidden, double fold_cos, double crease_cos) {
        need(V.ndim() == 2 && V.shape(1) == 3, "vertices must be (n, 3)");
        const int64_t n = static_cast<int64_t>(V.shape(0));
        need(n < (int64_t(1) << 31), "at most 2**31 vertices");
        check_faces(patch, n, "patch must be (m, 3)");
        need(loop.ndim() == 1 && scales.ndim() == 1 && loop.shape(0) == scales.shape(0),
             "loop and scales: one scale per loop vertex");
        need(forbidden.ndim() == 2 && forbidden.shape(1) == 2, "forbidden must be (k, 2)");
        using namespace refine;
        Refiner R{V.data(), n, {}};
        std::unordered_map<int64_t, double> sigma_old;
        const int64_t L = static_cast<int64_t>(loop.shape(0));
        std::unordered_set<uint64_t> fixed, blocked;
        for (int64_t i = 0; i < L; ++i) {
            const int64_t a = loop.data()[i], b = loop.data()[(i + 1) % L];
            need(a >= 0 && a < n, "loop vertex index");
            sigma_old[a] = scales.data()[i];
            fixed.insert(ukey(a, b));
        }
        for (size_t i = 0; i < forbidden.shape(0); ++i) {
            blocked.insert(ukey(forbidden.data()[2 * i], forbidden.data()[2 * i + 1]));
        }
        std::vector<double> sigma_new;
        std::vector<int64_t> parents;
        std::vector<Tri> faces(patch.shape(0));
        for (size_t t = 0; t < faces.size(); ++t) {
            const int64_t* f = patch.data() + 3 * t;
            faces[t] = {f[0], f[1], f[2]};
        }
        {
            nb::gil_scoped_release unlocked;
            auto sig = [&](int64_t i) {
                if (i >= n) return sigma_new[static_cast<size_t>(i - n)];
                auto it = sigma_old.find(i);
                return it == sigma_old.end() ? 0.0 : it->second;
            };
            const Guards g{fixed, blocked, fold_cos, crease_cos};
            Sides where = sides(faces);  // kept up to date by every split and swap
            for (int64_t round = 0; round < max_rounds; ++round) {
                bool split = false;
                const size_t count = faces.size();  // faces it adds wait: next round
                for (size_t t = 0; t < count; ++t) {
                    const Tri f = faces[t];
                    const P3 pa = R.point(f.a), pb = R.point(f.b), pc = R.point(f.c);
                    const P3 m{(pa.x + pb.x + pc.x) / 3.0, (pa.y + pb.y + pc.y) / 3.0,
                               (pa.z + pb.z + pc.z) / 3.0};
                    const double sm = (sig(f.a) + sig(f.b) + sig(f.c)) / 3.0;
                    bool go = sm > 0;
                    const std::pair<int64_t, P3> corners[3] = {{f.a, pa}, {f.b, pb}, {f.c, pc}};
                    for (int k = 0; go && k < 3; ++k) {
                        go = density * dist(m, corners[k].second) >
                             std::max(sm, sig(corners[k].first));
                    }
                    if (!go) continue;
                    const int64_t k = n + static_cast<int64_t>(R.added.size());
                    R.added.push_back(m);
                    sigma_new.push_back(sm);
                    parents.insert(parents.end(), {f.a, f.b, f.c});
                    const int64_t t1 = static_cast<int64_t>(t);
                    const int64_t t2 = static_cast<int64_t>(faces.size()), t3 = t2 + 1;
                    faces[t] = {f.a, f.b, k};
                    faces.push_back({f.b, f.c, k});
                    faces.push_back({f.c, f.a, k});
                    where[key(f.b, k)] = t1, where[key(k, f.a)] = t1;
                    where[key(f.b, f.c)] = t2, where[key(f.c, k)] = t2, where[key(k, f.b)] = t2;
                    where[key(f.c, f.a)] = t3, where[key(f.a, k)] = t3, where[key(k, f.c)] = t3;
                    // its sides, relaxed at once
                    swap_edge(faces, where, f.a, f.b, R, g);
                    swap_edge(faces, where, f.b, f.c, R, g);
                    swap_edge(faces, where, f.c, f.a, R, g);
                    split = true;
                }
                if (!split) break;
                sweep(faces, where, R, g);
            }
        }
        std::vector<double> nv;
        nv.reserve(3 * R.added.size());
        for (const P3& q : R.added) nv.insert(nv.end(), {q.x, q.y, q.z});
        std::vector<int64_t> nf;
        nf.reserve(3 * faces.size());
        for (const Tri& f : faces) nf.insert(nf.end(), {f.a, f.b, f.c});
        const size_t na = R.added.size(), nfaces = faces.size();
        return nb::make_tuple(from_vector(std::move(nv), na, 3),
                              from_vector(std::move(nf), nfaces, 3),
                              from_vector(std::move(parents), na, 3));
    }, nb::arg("vertices"), nb::arg("patch"), nb::arg("loop"), nb::arg("scales"),
       nb::arg("density"), nb::arg("max_rounds"), nb::arg("forbidden"), nb::arg("fold_cos"),
       nb::arg("crease_cos"),
       "(new_vertices, faces, parents) of optri.holes.refine's centroid splits and relaxation.");

    r.def("intersecting_pairs", [](In<double> V, In<int64_t> F, In<int64_t> P) {
        need(V.ndim() == 2 && V.shape(1) == 3, "vertices must be (n, 3)");
        const int64_t n = static_cast<int64_t>(V.shape(0));
        check_faces(F, n, "faces must be (m, 3)");
        check_faces(P, n, "patch must be (k, 3)");
        std::vector<int64_t> out;
        {
            nb::gil_scoped_release unlocked;
            out = refine::intersecting_pairs(V.data(), F.data(), static_cast<int64_t>(F.shape(0)),
                                             P.data(), static_cast<int64_t>(P.shape(0)));
        }
        const size_t k = out.size() / 2;
        return from_vector(std::move(out), k, 2);
    }, nb::arg("vertices"), nb::arg("faces"), nb::arg("patch"),
       "(k, 2) pairs (patch face, face) that cross, sorted; optri.holes.intersect's twin.");
}

}  // namespace optri
