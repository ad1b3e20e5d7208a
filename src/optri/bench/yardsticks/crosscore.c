/* crosscore: how fast one CPU reads what another has just written, against how fast it
 * reads what it wrote itself. A writer thread, pinned to the first CPU this process may
 * run on, fills a buffer (4 MB: the size of the tiles and rows a thread of optri's fill
 * reads from the other's, in the caches rather than in memory); a reader thread, pinned
 * to the second, then reads all of it. The best of REPS rounds is the cross-core rate;
 * the writer reading a buffer it has just written is the local rate. On a virtual
 * machine whose host sometimes places its CPUs on cores that do not share a cache, the
 * cross-core rate drops for a while (on the 2-core AMD EPYC of docs/fast-engine.md, from
 * about 78 to about 28 GB/s) and so does optri's fill on two threads, whose threads read
 * each other's finished tiles, while a peak microbenchmark whose threads share nothing
 * does not slow down: optri bench runs this beside its solves to say so.
 *
 * With "rewrite", what a spell slows: the writer writes KB kilobytes, the reader reads
 * them, and the writer's next store to each cache line is timed (before it, the reader's
 * copy of the line must be invalidated); then the same stores with no read between. The
 * best of 200 rounds each, in ns a 64-byte line (on the EPYC: 3.6 and 0.6 outside its
 * spells, 12.7 and 0.6 in them; optri's fill rewrites, solve after solve, lines both its
 * threads read, and claims them first).
 *
 * Build:  cc -O3 -march=native -pthread -o crosscore crosscore.c
 * Run:    crosscore [MB [REPS]]  (defaults: 4 MB, 5 rounds)
 *         crosscore rewrite [KB]  (default 64)
 * Prints: cross-core GB/s  local GB/s  the writer's CPU  the reader's CPU
 *         (rewrite: ns a line after the other CPU read it, ns a line with no read)
 * Exits with status 1, saying why on stderr, where the process may run on one CPU only,
 * and 2 on bad arguments. */
#define _GNU_SOURCE
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static cpu_set_t only(int cpu) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    return set;
}

static double *buf;
static size_t count;
static int reps;
static atomic_int turn; /* odd: the buffer is written, the reader's turn; even: the writer's */
static double cross_best, sink;
static int reader_ran_on = -1;

static double read_all(void) {
    double s = 0;
    for (size_t k = 0; k < count; k++) s += buf[k];
    return s;
}

static void write_all(int rep) {
    for (size_t k = 0; k < count; k++) buf[k] = (double)(k + rep);
}

/* Seconds to store one value in each cache line of the buffer. */
static double store_lines(int rep) {
    double t = now();
    for (size_t k = 0; k < count; k += 8) buf[k] = (double)rep;
    return now() - t;
}

static void *reader(void *arg) {
    (void)arg;
    for (int rep = 0; rep < reps; rep++) {
        while (atomic_load_explicit(&turn, memory_order_acquire) != 2 * rep + 1) {
        }
        double t = now();
        sink += read_all();
        t = now() - t;
        if (count * 8 / t / 1e9 > cross_best) cross_best = count * 8 / t / 1e9;
        reader_ran_on = sched_getcpu();
        atomic_store_explicit(&turn, 2 * rep + 2, memory_order_release);
    }
    return NULL;
}

int main(int argc, char **argv) {
    int rewrite = argc > 1 && strcmp(argv[1], "rewrite") == 0;
    double mb;
    if (rewrite) {
        long kb = argc > 2 ? atol(argv[2]) : 64;
        mb = kb / 1024.0;
        reps = 200;
        if (argc > 3 || kb < 1 || kb > (1L << 20)) mb = 0;
    } else {
        mb = argc > 1 ? atof(argv[1]) : 4.0;
        reps = argc > 2 ? atoi(argv[2]) : 5;
    }
    if (mb <= 0 || mb > 4096 || reps < 1) {
        fprintf(stderr, "usage: crosscore [MB [REPS]] | crosscore rewrite [KB]\n");
        return 2;
    }
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) != 0 || CPU_COUNT(&set) < 2) {
        fprintf(stderr, "crosscore: this process may run on one CPU only\n");
        return 1;
    }
    int writer_cpu = -1, reader_cpu = -1;
    for (int c = 0; c < CPU_SETSIZE && reader_cpu < 0; c++)
        if (CPU_ISSET(c, &set)) {
            if (writer_cpu < 0)
                writer_cpu = c;
            else
                reader_cpu = c;
        }
    count = (size_t)(mb * (1 << 20)) / 8 / 8 * 8;
    buf = aligned_alloc(64, count * 8);
    cpu_set_t mine = only(writer_cpu), theirs = only(reader_cpu);
    if (buf == NULL || pthread_setaffinity_np(pthread_self(), sizeof mine, &mine) != 0) {
        fprintf(stderr, "crosscore: no buffer, or CPU %d refused\n", writer_cpu);
        return 1;
    }
    pthread_attr_t attr; /* the reader starts on its CPU, or not at all */
    pthread_t id;
    pthread_attr_init(&attr);
    if (pthread_attr_setaffinity_np(&attr, sizeof theirs, &theirs) != 0 ||
        pthread_create(&id, &attr, reader, NULL) != 0) {
        fprintf(stderr, "crosscore: no second thread on CPU %d\n", reader_cpu);
        return 1;
    }
    pthread_attr_destroy(&attr);
    if (rewrite) {
        double shared = 1e9, alone = 1e9;
        for (int rep = 0; rep < reps; rep++) {
            write_all(rep); /* every line held here only */
            atomic_store_explicit(&turn, 2 * rep + 1, memory_order_release);
            while (atomic_load_explicit(&turn, memory_order_acquire) != 2 * rep + 2) {
            }
            double t = store_lines(rep + 1); /* the reader has a copy of every line */
            if (t < shared) shared = t;
            store_lines(rep + 2);
            t = store_lines(rep + 3); /* held here only again */
            if (t < alone) alone = t;
        }
        pthread_join(id, NULL);
        printf("%.1f %.1f\n", shared / (count / 8) * 1e9, alone / (count / 8) * 1e9);
        return 0;
    }
    for (int rep = 0; rep < reps; rep++) {
        write_all(rep);
        atomic_store_explicit(&turn, 2 * rep + 1, memory_order_release);
        while (atomic_load_explicit(&turn, memory_order_acquire) != 2 * rep + 2) {
        }
    }
    pthread_join(id, NULL);
    double local_best = 0;
    for (int rep = 0; rep < reps; rep++) {
        write_all(rep);
        double t = now();
        sink += read_all();
        t = now() - t;
        if (count * 8 / t / 1e9 > local_best) local_best = count * 8 / t / 1e9;
    }
    printf("%.1f %.1f %d %d\n", cross_best, local_best, sched_getcpu(), reader_ran_on);
    return sink < 0 ? 1 : 0;
}
