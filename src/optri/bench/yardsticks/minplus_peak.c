/* minplus_peak: how many min-plus candidates (one addition, one minimum) per second this
 * machine can evaluate at best. Every thread repeats C = min(C, A (+) B) on its own three
 * 64 x 64 double tiles, which stay in its core's L1/L2 cache, with a register-blocked
 * kernel: 4 rows x 16 columns of C held in vector registers while k runs (AVX2; a portable
 * scalar-loop version elsewhere, left to the compiler's vectorizer).
 * Where the CPU has more, it also times the same product with
 *   - AVX-512VL: the minimum taken as 64-bit integers (vpminsq; for the non-negative
 *     values of a min-plus table it is the same value, bit for bit), which runs on vector
 *     ports the float minimum cannot use on some CPUs (AMD Zen 4);
 *   - AVX-512F: 512-bit vectors, 4 x 16 and 8 x 16 blocks, float and integer minimum
 *     (two 512-bit ports do twice the work of 256-bit instructions on Intel CPUs);
 *   - "-sched" versions of them compiled so that GCC's code does not hold them back (see
 *     SCHEDULED below: on Zen 4 the 4 x 16 integer-minimum block ran 1.2-1.3x as fast);
 * and reports the fastest kernel. Each kernel's product is first checked against the
 * plain loop, value for value; a kernel that disagrees is left out (and the program exits
 * with status 1 if none agrees). No dynamic programme over a real table can go faster,
 * so an engine's "fraction of peak" is (candidates it evaluates / its seconds) / this
 * rate, measured in one run.
 *
 * Build:  cc -O3 -march=native -pthread -o minplus_peak minplus_peak.c
 * Run:    minplus_peak [SECONDS [THREADS]]  (defaults: 1.0 s per kernel, every online CPU)
 * Prints: threads  candidates/s (all threads, wall clock)  per thread  per CPU-second
 *         kernel (of the fastest)  candidates/s of the AVX2 float kernel alone
 * and, on stderr, one line per kernel (or why it was left out). The per-CPU-second figure
 * divides by the CPU time the threads really got, so it stays meaningful on a machine
 * shared with other work. */
#define _GNU_SOURCE
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>
#ifdef __AVX2__
#include <immintrin.h>
#define ISA "avx2"
#else
#define ISA "portable"
#endif

enum { S = 64, COLS = 16 };

static double clock_s(clockid_t id) {
    struct timespec ts;
    clock_gettime(id, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

/* one ROWS x 16 block: C's block in registers, per k VECS loads of B's row k and ROWS
 * broadcasts of A[., k]; MIN is the vector minimum of two VEC; ATTR, the block's function
 * attributes (SCHEDULED below, or nothing) */
#define BLOCK(NAME, ROWS, VEC, LANES, LOAD, STORE, BCAST, ADD, MIN) \
    BLOCK_ATTR(NAME, , ROWS, VEC, LANES, LOAD, STORE, BCAST, ADD, MIN)
#define BLOCK_ATTR(NAME, ATTR, ROWS, VEC, LANES, LOAD, STORE, BCAST, ADD, MIN)            \
    ATTR static void NAME(const double *a, const double *b, double *c) {                  \
        enum { VECS = COLS / LANES };                                                     \
        VEC acc[ROWS][VECS];                                                              \
        for (int r = 0; r < ROWS; r++)                                                    \
            for (int q = 0; q < VECS; q++) acc[r][q] = LOAD(c + r * S + LANES * q);       \
        for (int k = 0; k < S; k++) {                                                     \
            VEC bk[VECS];                                                                 \
            for (int q = 0; q < VECS; q++) bk[q] = LOAD(b + k * S + LANES * q);           \
            for (int r = 0; r < ROWS; r++) {                                              \
                VEC ar = BCAST(a[r * S + k]);                                             \
                for (int q = 0; q < VECS; q++) acc[r][q] = MIN(acc[r][q], ADD(ar, bk[q])); \
            }                                                                             \
        }                                                                                 \
        for (int r = 0; r < ROWS; r++)                                                    \
            for (int q = 0; q < VECS; q++) STORE(c + r * S + LANES * q, acc[r][q]);       \
    }                                                                                     \
    ATTR static void NAME##_tile(const double *a, const double *b, double *c) {           \
        for (int i = 0; i < S; i += ROWS)                                                 \
            for (int j = 0; j < S; j += COLS) NAME(a + i * S, b + j, c + i * S + j);      \
    }

#ifdef __AVX2__
BLOCK(avx2_float, 4, __m256d, 4, _mm256_load_pd, _mm256_store_pd, _mm256_set1_pd,
      _mm256_add_pd, _mm256_min_pd)
#else
static inline double scalar_min(double x, double y) { return y < x ? y : x; }
static inline double scalar_load(const double *p) { return *p; }
static inline void scalar_store(double *p, double v) { *p = v; }
static inline double scalar_set(double v) { return v; }
static inline double scalar_add(double x, double y) { return x + y; }
BLOCK(portable, 4, double, 1, scalar_load, scalar_store, scalar_set, scalar_add, scalar_min)
#endif
#if defined(__AVX2__) && defined(__AVX512VL__)
static inline __m256d min_as_int(__m256d x, __m256d y) {
    return _mm256_castsi256_pd(_mm256_min_epi64(_mm256_castpd_si256(x), _mm256_castpd_si256(y)));
}
BLOCK(avx512vl_intmin, 4, __m256d, 4, _mm256_load_pd, _mm256_store_pd, _mm256_set1_pd,
      _mm256_add_pd, min_as_int)
#endif
/* The same kernels written so that GCC cannot hold them back: the integer minimum taken in
 * place (one instruction into the accumulator; from the intrinsic, GCC 12 wrote each
 * minimum to a temporary and copied it back, 16 register copies a step), and the block
 * scheduled before register allocation, for register pressure (GCC's default order
 * interleaves each addition with its minimum). On a 2-core AMD EPYC (Zen 4), one core:
 * the 4 x 16 integer-minimum block 1.9e10 candidates/s as above, 2.1e10 with the minimum
 * in place, 2.4-2.5e10 with it scheduled too. */
#if defined(__GNUC__) && !defined(__clang__)
#define SCHEDULED __attribute__((optimize("schedule-insns", "sched-pressure")))
#else
#define SCHEDULED
#endif
#if defined(__AVX2__) && defined(__AVX512VL__) && defined(__GNUC__)
#define ASM_MIN 1
static inline __m256d min_in_place(__m256d x, __m256d y) {
    __asm__("vpminsq %1, %0, %0" : "+v"(x) : "v"(y));
    return x;
}
BLOCK_ATTR(avx512vl_intmin_sched, SCHEDULED, 4, __m256d, 4, _mm256_load_pd, _mm256_store_pd,
           _mm256_set1_pd, _mm256_add_pd, min_in_place)
#endif
#ifdef __AVX2__
BLOCK_ATTR(avx2_float_sched, SCHEDULED, 4, __m256d, 4, _mm256_load_pd, _mm256_store_pd,
           _mm256_set1_pd, _mm256_add_pd, _mm256_min_pd)
#endif
#ifdef __AVX512F__
static inline __m512d min512_as_int(__m512d x, __m512d y) {
    return _mm512_castsi512_pd(_mm512_min_epi64(_mm512_castpd_si512(x), _mm512_castpd_si512(y)));
}
BLOCK(avx512_float, 4, __m512d, 8, _mm512_load_pd, _mm512_store_pd, _mm512_set1_pd,
      _mm512_add_pd, _mm512_min_pd)
BLOCK(avx512_intmin, 4, __m512d, 8, _mm512_load_pd, _mm512_store_pd, _mm512_set1_pd,
      _mm512_add_pd, min512_as_int)
BLOCK(avx512_float_8x16, 8, __m512d, 8, _mm512_load_pd, _mm512_store_pd, _mm512_set1_pd,
      _mm512_add_pd, _mm512_min_pd)
BLOCK(avx512_intmin_8x16, 8, __m512d, 8, _mm512_load_pd, _mm512_store_pd, _mm512_set1_pd,
      _mm512_add_pd, min512_as_int)
#ifdef ASM_MIN
static inline __m512d min512_in_place(__m512d x, __m512d y) {
    __asm__("vpminsq %1, %0, %0" : "+v"(x) : "v"(y));
    return x;
}
BLOCK_ATTR(avx512_intmin_sched, SCHEDULED, 4, __m512d, 8, _mm512_load_pd, _mm512_store_pd,
           _mm512_set1_pd, _mm512_add_pd, min512_in_place)
BLOCK_ATTR(avx512_intmin_8x16_sched, SCHEDULED, 8, __m512d, 8, _mm512_load_pd, _mm512_store_pd,
           _mm512_set1_pd, _mm512_add_pd, min512_in_place)
#endif
BLOCK_ATTR(avx512_float_8x16_sched, SCHEDULED, 8, __m512d, 8, _mm512_load_pd, _mm512_store_pd,
           _mm512_set1_pd, _mm512_add_pd, _mm512_min_pd)
#endif

/* C = min(C, A (+) B) over whole tiles: S^3 candidates; the first kernel is the AVX2 float
 * one (or the portable loop) */
static const struct kernel {
    const char *name;
    void (*tile)(const double *, const double *, double *);
} KERNELS[] = {
#ifdef __AVX2__
    {ISA, avx2_float_tile},
#else
    {ISA, portable_tile},
#endif
#if defined(__AVX2__) && defined(__AVX512VL__)
    {"avx512vl-intmin", avx512vl_intmin_tile},
#endif
#ifdef __AVX512F__
    {"avx512-float", avx512_float_tile},
    {"avx512-intmin", avx512_intmin_tile},
    {"avx512-float-8x16", avx512_float_8x16_tile},
    {"avx512-intmin-8x16", avx512_intmin_8x16_tile},
#endif
#ifdef __AVX2__
    {"avx2-sched", avx2_float_sched_tile},
#endif
#ifdef ASM_MIN
    {"avx512vl-intmin-sched", avx512vl_intmin_sched_tile},
#endif
#ifdef __AVX512F__
    {"avx512-float-8x16-sched", avx512_float_8x16_sched_tile},
#ifdef ASM_MIN
    {"avx512-intmin-sched", avx512_intmin_sched_tile},
    {"avx512-intmin-8x16-sched", avx512_intmin_8x16_sched_tile},
#endif
#endif
};
enum { NKERNELS = sizeof KERNELS / sizeof KERNELS[0] };

/* Whether a kernel's tile product equals the plain loop's, value for value (the same sums,
 * the same minima): a kernel that does not is left out of the timings. */
static int agrees(const struct kernel *kernel) {
    double *a = aligned_alloc(64, 4 * S * S * sizeof(double)), *b = a + S * S, *c = b + S * S;
    double *want = c + S * S;
    unsigned seed = 12345u;
    for (int x = 0; x < S * S; x++) {
        seed = seed * 1664525u + 1013904223u;
        a[x] = (seed >> 8) % 4096 * 0.25;
        seed = seed * 1664525u + 1013904223u;
        b[x] = (seed >> 8) % 4096 * 0.25;
        seed = seed * 1664525u + 1013904223u;
        c[x] = x % 7 ? (seed >> 8) % 8192 * 0.25 : 1e300;
        want[x] = c[x];
    }
    for (int i = 0; i < S; i++)
        for (int j = 0; j < S; j++)
            for (int k = 0; k < S; k++)
                if (a[i * S + k] + b[k * S + j] < want[i * S + j])
                    want[i * S + j] = a[i * S + k] + b[k * S + j];
    kernel->tile(a, b, c);
    int same = memcmp(c, want, S * S * sizeof(double)) == 0;
    free(a);
    return same;
}

struct job {
    const struct kernel *kernel;
    double seconds, cpu;
    long tiles;
    double check;
    pthread_barrier_t *gate;
};

static void *run(void *arg) {
    struct job *job = arg;
    double *a = aligned_alloc(64, 3 * S * S * sizeof(double)), *b = a + S * S, *c = b + S * S;
    unsigned seed = 2654435761u ^ (unsigned)(size_t)arg;
    for (int x = 0; x < S * S; x++) {
        seed = seed * 1664525u + 1013904223u;
        a[x] = (seed >> 8) % 4096;
        seed = seed * 1664525u + 1013904223u;
        b[x] = (seed >> 8) % 4096;
        c[x] = 1e300;
    }
    pthread_barrier_wait(job->gate);
    double start = clock_s(CLOCK_MONOTONIC), cpu0 = clock_s(CLOCK_THREAD_CPUTIME_ID);
    long tiles = 0;
    while (clock_s(CLOCK_MONOTONIC) - start < job->seconds) {
        for (int rep = 0; rep < 32; rep++, tiles++) {
            job->kernel->tile(a, b, c);
            a[tiles % (S * S)] += 0.5; /* keeps every product live; values stay >= 0 */
        }
    }
    job->cpu = clock_s(CLOCK_THREAD_CPUTIME_ID) - cpu0;
    job->tiles = tiles;
    job->check = c[S + 1];
    free(a);
    return NULL;
}

int main(int argc, char **argv) {
    double seconds = argc > 1 ? atof(argv[1]) : 1.0;
    long threads = argc > 2 ? atol(argv[2]) : sysconf(_SC_NPROCESSORS_ONLN);
    if (seconds <= 0 || threads < 1 || threads > 4096) {
        fprintf(stderr, "usage: minplus_peak [SECONDS [THREADS]]\n");
        return 2;
    }
    double rate[NKERNELS], per_cpu[NKERNELS];
    double check = 0;
    int best = 0;
    for (int kk = 0; kk < NKERNELS; kk++) {
        if (!agrees(&KERNELS[kk])) {
            fprintf(stderr, "%s: wrong product, left out\n", KERNELS[kk].name);
            rate[kk] = per_cpu[kk] = 0;
            continue;
        }
        pthread_t *ids = calloc(threads, sizeof *ids);
        struct job *jobs = calloc(threads, sizeof *jobs);
        pthread_barrier_t gate;
        pthread_barrier_init(&gate, NULL, (unsigned)threads + 1);
        for (long t = 0; t < threads; t++) {
            jobs[t].kernel = &KERNELS[kk];
            jobs[t].seconds = seconds;
            jobs[t].gate = &gate;
            pthread_create(&ids[t], NULL, run, &jobs[t]);
        }
        pthread_barrier_wait(&gate);
        double start = clock_s(CLOCK_MONOTONIC);
        long tiles = 0;
        double cpu = 0;
        for (long t = 0; t < threads; t++) {
            pthread_join(ids[t], NULL);
            tiles += jobs[t].tiles;
            cpu += jobs[t].cpu;
            check += jobs[t].check;
        }
        double wall = clock_s(CLOCK_MONOTONIC) - start;
        double cand = (double)tiles * S * S * S;
        rate[kk] = cand / wall;
        per_cpu[kk] = cand / cpu;
        fprintf(stderr, "%s %.4g\n", KERNELS[kk].name, rate[kk]);
        if (rate[kk] > rate[best]) best = kk;
        pthread_barrier_destroy(&gate);
        free(ids);
        free(jobs);
    }
    if (rate[best] <= 0) {
        fprintf(stderr, "minplus_peak: no kernel computed the product right\n");
        return 1;
    }
    printf("%ld %.4g %.4g %.4g %s %.4g\n", threads, rate[best], rate[best] / threads,
           per_cpu[best], KERNELS[best].name, rate[0]);
    return check < 0 ? 1 : 0;
}
