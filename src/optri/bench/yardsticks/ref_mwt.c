/* ref_mwt: the minimum-weight triangulation of a convex polygon, triangle weight =
 * perimeter, objective = sum, by the textbook O(n^3) dynamic programme in plain C.
 * One thread, no tiling: what a careful programmer writes in an afternoon.
 *
 * W(i, j) = min over i < k < j of W(i, k) + W(k, j) + perimeter(i, k, j), W(i, i+1) = 0.
 * Written with E(i, j) = W(i, j) + |v_i v_j| (E of a side is its length):
 *     W(i, j) = min_k (E(i, k) + E(k, j)) + |v_i v_j|,
 * since perimeter(i, k, j) = |ik| + |kj| + |ij|. One n x n table holds E in both
 * triangles (E(j, i) = E(i, j)), so the inner loop over k reads rows i and j forwards;
 * i runs downwards and j upwards, so every E it reads is already final.
 *
 * Build:  cc -O3 -march=native -ffast-math -o ref_mwt ref_mwt.c -lm
 * (-ffast-math lets the compiler vectorize the minimum; the minimum of exact sums is exact)
 * Run:    ref_mwt POLYGON.csv      (one "x,y" vertex per line, in order)
 * Prints: n  weight (%.17g)  seconds of the dynamic programme (reading excluded) */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int read_csv(const char *path, double **xs, double **ys) {
    FILE *f = fopen(path, "r");
    if (!f) return -1;
    int n = 0, cap = 1024;
    double *x = malloc(cap * sizeof *x), *y = malloc(cap * sizeof *y), a, b;
    char line[256];
    while (fgets(line, sizeof line, f)) {
        if (sscanf(line, "%lf,%lf", &a, &b) != 2) continue; /* header or blank line */
        if (n == cap) {
            cap *= 2;
            x = realloc(x, cap * sizeof *x);
            y = realloc(y, cap * sizeof *y);
        }
        x[n] = a;
        y[n++] = b;
    }
    fclose(f);
    *xs = x;
    *ys = y;
    return n;
}

int main(int argc, char **argv) {
    double *x, *y;
    int n = argc == 2 ? read_csv(argv[1], &x, &y) : -1;
    if (n < 3) {
        fprintf(stderr, "usage: ref_mwt POLYGON.csv  (at least 3 \"x,y\" lines)\n");
        return 2;
    }
    double *E = malloc((size_t)n * n * sizeof *E);
    if (!E) {
        fprintf(stderr, "ref_mwt: out of memory\n");
        return 1;
    }
    double start = now(), weight = 0;
    for (int i = 0; i + 1 < n; i++)
        E[(size_t)i * n + i + 1] = E[(size_t)(i + 1) * n + i] = hypot(x[i + 1] - x[i], y[i + 1] - y[i]);
    for (int i = n - 3; i >= 0; i--)       /* row i stays in cache while j runs */
        for (int j = i + 2; j < n; j++) {  /* rows below i mirrored E(k, j) into row j */
            const double *ri = E + (size_t)i * n, *rj = E + (size_t)j * n;
            double best = INFINITY, side = hypot(x[j] - x[i], y[j] - y[i]);
            for (int k = i + 1; k < j; k++) {
                double c = ri[k] + rj[k];
                best = c < best ? c : best;
            }
            weight = best + side; /* W(i, j); the last one is the whole polygon's */
            E[(size_t)i * n + j] = E[(size_t)j * n + i] = weight + side;
        }
    printf("%d %.17g %.6f\n", n, weight, now() - start);
    free(E);
    free(x);
    free(y);
    return 0;
}
