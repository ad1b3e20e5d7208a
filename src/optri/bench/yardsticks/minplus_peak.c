/* minplus_peak: how many min-plus candidates (one addition, one minimum) per second this
 * machine can evaluate at best. Every thread repeats C = min(C, A (+) B) on its own three
 * 64 x 64 double tiles, which stay in its core's L1/L2 cache, with a register-blocked
 * kernel: 4 rows x 16 columns of C held in 16 vector registers while k runs (AVX2; a
 * portable scalar-loop version elsewhere, left to the compiler's vectorizer).
 * With AVX-512VL it also times the same kernel taking the minimum as 64-bit integers
 * (vpminsq; for the non-negative values of a min-plus table it is the same value, bit for
 * bit), which runs on vector ports the float minimum cannot use, and reports the faster.
 * No dynamic programme over a real table can go faster, so an engine's "fraction of
 * peak" is (candidates it evaluates / its seconds) / this rate, measured in one run.
 *
 * Build:  cc -O3 -march=native -pthread -o minplus_peak minplus_peak.c
 * Run:    minplus_peak [SECONDS [THREADS]]     (defaults: 1.0 s, every online CPU)
 * Prints: threads  candidates/s (all threads, wall clock)  per thread  per CPU-second  isa
 *         float-min candidates/s (the AVX2 kernel alone: the first figure when isa is avx2)
 * The last figure divides by the CPU time the threads really got, so it stays meaningful
 * on a machine shared with other work. */
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
#if defined(__AVX2__) && defined(__AVX512VL__)
#define INT_MIN_KERNEL 1
#else
#define INT_MIN_KERNEL 0
#endif

enum { S = 64, ROWS = 4, COLS = 16 };

static double clock_s(clockid_t id) {
    struct timespec ts;
    clock_gettime(id, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

#ifdef __AVX2__
/* one 4 x 16 block: 16 accumulators, 4 loads of B's row k, 4 broadcasts of A[., k];
 * MIN is the vector minimum of two __m256d */
#define BLOCK(NAME, MIN)                                                                  \
    static void NAME(const double *a, const double *b, double *c) {                       \
        __m256d acc[ROWS][4];                                                             \
        for (int r = 0; r < ROWS; r++)                                                    \
            for (int q = 0; q < 4; q++) acc[r][q] = _mm256_load_pd(c + r * S + 4 * q);    \
        for (int k = 0; k < S; k++) {                                                     \
            __m256d bk[4];                                                                \
            for (int q = 0; q < 4; q++) bk[q] = _mm256_load_pd(b + k * S + 4 * q);        \
            for (int r = 0; r < ROWS; r++) {                                              \
                __m256d ar = _mm256_broadcast_sd(a + r * S + k);                          \
                for (int q = 0; q < 4; q++)                                               \
                    acc[r][q] = MIN(acc[r][q], _mm256_add_pd(ar, bk[q]));                 \
            }                                                                             \
        }                                                                                 \
        for (int r = 0; r < ROWS; r++)                                                    \
            for (int q = 0; q < 4; q++) _mm256_store_pd(c + r * S + 4 * q, acc[r][q]);    \
    }
BLOCK(block_float, _mm256_min_pd)
#if INT_MIN_KERNEL
static inline __m256d min_as_int(__m256d x, __m256d y) {
    return _mm256_castsi256_pd(_mm256_min_epi64(_mm256_castpd_si256(x), _mm256_castpd_si256(y)));
}
BLOCK(block_int, min_as_int)
#endif
static void block(const double *a, const double *b, double *c, int as_int) {
#if INT_MIN_KERNEL
    if (as_int) {
        block_int(a, b, c);
        return;
    }
#endif
    (void)as_int;
    block_float(a, b, c);
}
#else
static void block(const double *a, const double *b, double *c, int as_int) {
    double acc[ROWS][COLS];
    (void)as_int;
    for (int r = 0; r < ROWS; r++) memcpy(acc[r], c + r * S, sizeof acc[r]);
    for (int k = 0; k < S; k++)
        for (int r = 0; r < ROWS; r++) {
            double ar = a[r * S + k];
            for (int q = 0; q < COLS; q++) {
                double v = ar + b[k * S + q];
                acc[r][q] = v < acc[r][q] ? v : acc[r][q];
            }
        }
    for (int r = 0; r < ROWS; r++) memcpy(c + r * S, acc[r], sizeof acc[r]);
}
#endif

/* C = min(C, A (+) B) over whole tiles: S^3 candidates */
static void tile_product(const double *a, const double *b, double *c, int as_int) {
    if (as_int) {
        /* the loop is duplicated so that each version is compiled with a constant flag */
        for (int i = 0; i < S; i += ROWS)
            for (int j = 0; j < S; j += COLS) block(a + i * S, b + j, c + i * S + j, 1);
    } else {
        for (int i = 0; i < S; i += ROWS)
            for (int j = 0; j < S; j += COLS) block(a + i * S, b + j, c + i * S + j, 0);
    }
}

struct job {
    int as_int;
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
            tile_product(a, b, c, job->as_int);
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
    double rate[2] = {0, 0}, per_cpu[2] = {0, 0};
    double check = 0;
    for (int as_int = 0; as_int <= INT_MIN_KERNEL; as_int++) {
        pthread_t *ids = calloc(threads, sizeof *ids);
        struct job *jobs = calloc(threads, sizeof *jobs);
        pthread_barrier_t gate;
        pthread_barrier_init(&gate, NULL, (unsigned)threads + 1);
        for (long t = 0; t < threads; t++) {
            jobs[t].as_int = as_int;
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
        rate[as_int] = cand / wall;
        per_cpu[as_int] = cand / cpu;
        pthread_barrier_destroy(&gate);
        free(ids);
        free(jobs);
    }
    int best = rate[1] > rate[0];
    printf("%ld %.4g %.4g %.4g %s %.4g\n", threads, rate[best], rate[best] / threads,
           per_cpu[best], best ? "avx512vl-intmin" : ISA, rate[0]);
    return check < 0 ? 1 : 0;
}
