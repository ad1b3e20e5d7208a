// The evaluator's geometry: normals and keys of whole triangle sets (optri.holes.liepa).
#include "holes.hpp"

namespace optri::holes {

void mesh_normals(const double* Q, int64_t n, double* out) {
    for (int64_t s = 0; s < n; ++s) {
        const Normal u = unit_normal(Q, (s + 1) % n, s, n + s);
        double* o = out + 4 * s;
        o[0] = u.x;
        o[1] = u.y;
        o[2] = u.z;
        o[3] = u.d ? 1.0 : 0.0;
    }
}

void triangle_normals(const double* Q, const int64_t* tris, int64_t m, double* out) {
    for (int64_t t = 0; t < m; ++t) {
        const int64_t* r = tris + 3 * t;
        const Normal u = sorted_normal(Q, r[0], r[1], r[2]);
        double* o = out + 5 * t;
        o[0] = u.x;
        o[1] = u.y;
        o[2] = u.z;
        o[3] = u.d ? 1.0 : 0.0;
        o[4] = u.area;
    }
}

void pair_keys(const double* U, int64_t u_cols, const double* V, int64_t v_cols,
               int64_t rows, double* out) {
    for (int64_t r = 0; r < rows; ++r) {
        const double* u = U + u_cols * r;
        const double* v = V + v_cols * r;
        out[r] = key_of(u[0], u[1], u[2], u[3] != 0.0, v[0], v[1], v[2], v[3] != 0.0);
    }
}

void mesh_pair_keys(const double* U, int64_t u_cols, const double* MN, const int64_t* sides,
                    int64_t rows, double* out) {
    for (int64_t r = 0; r < rows; ++r) {
        const double* u = U + u_cols * r;
        out[r] = mesh_key(MN, sides[r], u[0], u[1], u[2], u[3] != 0.0, true);
    }
}

}  // namespace optri::holes
