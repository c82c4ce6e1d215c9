#define _DEFAULT_SOURCE
#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/mman.h>
#include <unistd.h>

/* Threads of the BLAS: OpenBLAS's openblas_set_num_threads/openblas_get_num_threads when the
 * BLAS linked is OpenBLAS (weak references: another BLAS links too, and is then left alone). */
void openblas_set_num_threads(int) __attribute__((weak));
int openblas_get_num_threads(void) __attribute__((weak));

/* Set the BLAS threads to n (n >= 1); returns the threads the BLAS then uses, -1 when the BLAS
 * linked has no such control (not OpenBLAS). */
static int room_for(long long bytes);

/* OpenBLAS's largest work buffer on x86-64 (BUFFER_SIZE 128 MiB) and its header: the room a
 * thread's buffer takes. */
#define BLAS_BUFFER_BYTES ((128LL << 20) + (1LL << 20))

int ffrf_blas_set_threads(int n)
{
    sigset_t set, previous;
    int current;
    if (!openblas_set_num_threads || !openblas_get_num_threads) return -1;
    /* each new worker maps its buffer as it starts, and OpenBLAS retries a failed mapping
     * forever: no new workers without room for their buffers (-2) */
    current = openblas_get_num_threads();
    if (n > current && !room_for((long long)(n - current) * BLAS_BUFFER_BYTES)) return -2;
    /* new worker threads inherit this mask: they never take the run signals (posix.c,
     * ffrf_signals_install) */
    sigemptyset(&set);
    sigaddset(&set, SIGTERM);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGHUP);
    sigaddset(&set, SIGUSR1);
    sigaddset(&set, SIGXCPU);
    pthread_sigmask(SIG_BLOCK, &set, &previous);
    openblas_set_num_threads(n);
    pthread_sigmask(SIG_SETMASK, &previous, NULL);
    return openblas_get_num_threads();
}

/* The threads the BLAS uses, -1 when unknown (not OpenBLAS). */
int ffrf_blas_threads(void)
{
    return openblas_get_num_threads ? openblas_get_num_threads() : -1;
}

/* ---- issue 24, item 3: small dense work on one BLAS thread ----
 * Threaded LAPACK on a matrix of about 100 x 100 (the integrator's iteration matrix) stalls on
 * a busy machine (8.7 s against 0.2 s for a 0.1 s run on 2 shared cores). The integrator runs
 * its steps between ffrf_blas_single_begin and ffrf_blas_single_end: the BLAS goes to one
 * thread and back to the count it had, which the eigen and MUMPS stages of the modes keep.
 * Controls known (weak references, so any BLAS links): OpenBLAS (openblas_set_num_threads,
 * pthreads or OpenMP build) and BLIS (bli_thread_set_num_threads, dim_t = int64_t). Another
 * BLAS (reference BLAS: never threaded; MKL, ATLAS) is left alone. No room check and no signal
 * mask here: going down never starts a worker, and going back up restores a count the process
 * already had, whose workers OpenBLAS keeps (0.3.21: blas_num_threads never shrinks). The count
 * is process-wide: a host running handles in several threads shares it (docs/api.md). */
typedef long long blis_dim_t;
blis_dim_t bli_thread_get_num_threads(void) __attribute__((weak));
void bli_thread_set_num_threads(blis_dim_t) __attribute__((weak));

/* Which BLAS threads ffrf can set: 1 OpenBLAS, 2 BLIS, 0 none known. */
int ffrf_blas_kind(void)
{
    if (openblas_set_num_threads && openblas_get_num_threads) return 1;
    if (bli_thread_set_num_threads && bli_thread_get_num_threads) return 2;
    return 0;
}

/* Put the BLAS on one thread; returns the count before (the argument of
 * ffrf_blas_single_end), 0 when nothing was changed (already one, or no known control). */
int ffrf_blas_single_begin(void)
{
    int before;
    switch (ffrf_blas_kind()) {
    case 1:
        before = openblas_get_num_threads();
        if (before <= 1) return 0;
        openblas_set_num_threads(1);
        return before;
    case 2:
        before = (int)bli_thread_get_num_threads();
        if (before <= 1) return 0; /* BLIS: -1 = not set, its own default (one thread) */
        bli_thread_set_num_threads(1);
        return before;
    default:
        return 0;
    }
}

/* Give the BLAS back the count ffrf_blas_single_begin returned (nothing for 0). */
void ffrf_blas_single_end(int before)
{
    if (before <= 1) return;
    switch (ffrf_blas_kind()) {
    case 1:
        openblas_set_num_threads(before);
        break;
    case 2:
        bli_thread_set_num_threads((blis_dim_t)before);
        break;
    default:
        break;
    }
}

/* ---- issue 23, item 6: allocation failure inside OpenBLAS ----
 * OpenBLAS 0.3.21 maps a work buffer per thread the first time a thread needs one (level-3
 * calls) and keeps it for the life of the process (blas_memory_free only marks it free); when
 * that mmap fails (an address-space limit, ulimit -v) blas_memory_alloc retries forever, deaf
 * to signals. So the buffers the run can need are taken at the
 * start, while the process is small: later calls reuse them and never map again. Before each
 * one a probe mapping of the buffer size (PROT_NONE, nothing touched) checks that the
 * address space has room, so that the reservation itself cannot spin: without room the run
 * stops at once with ENOMEM. Weak references: another BLAS is left alone. */
void *blas_memory_alloc(int) __attribute__((weak));
void blas_memory_free(void *) __attribute__((weak));

/* Bytes of address space the process uses (/proc/self/statm), -1 when unknown. */
static long long address_space_bytes(void)
{
    long long pages = -1;
    FILE *statm = fopen("/proc/self/statm", "r");
    if (statm == NULL) return -1;
    if (fscanf(statm, "%lld", &pages) != 1) pages = -1;
    fclose(statm);
    return pages < 0 ? -1 : pages * (long long)sysconf(_SC_PAGESIZE);
}

/* Whether `bytes` of address space can still be mapped. */
static int room_for(long long bytes)
{
    void *probe = mmap(NULL, (size_t)bytes, PROT_NONE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_NORESERVE,
                       -1, 0);
    if (probe == MAP_FAILED) return 0;
    munmap(probe, (size_t)bytes);
    return 1;
}

/* Under an address-space limit (RLIMIT_AS, ulimit -v) OpenBLAS's worker threads, started when
 * the library is loaded, may find no room for their buffers and spin forever before main()
 * runs. Called first thing by the driver: with a finite limit and more than one BLAS thread,
 * the program is executed again (same arguments) with OPENBLAS_NUM_THREADS=1, so that no
 * worker starts; --threads N adds workers later only when their buffers fit
 * (ffrf_blas_set_threads). Returns only when nothing had to be done or the exec failed. */
int ffrf_blas_fit_address_limit(void)
{
    struct rlimit limit;
    char *arguments[4096], *text;
    static char command_line[1 << 16];
    size_t length;
    int count = 0;
    FILE *file;
    const char *threads = getenv("OPENBLAS_NUM_THREADS");
    if (!openblas_get_num_threads || openblas_get_num_threads() <= 1) return 0;
    if (getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return 0;
    if (threads != NULL && strcmp(threads, "1") == 0) return 0;
    file = fopen("/proc/self/cmdline", "rb");
    if (file == NULL) return errno;
    length = fread(command_line, 1, sizeof command_line - 1, file);
    fclose(file);
    if (length == 0 || length >= sizeof command_line - 1) return E2BIG;
    command_line[length] = '\0';
    for (text = command_line; text < command_line + length && count < 4095;
         text += strlen(text) + 1)
        arguments[count++] = text;
    arguments[count] = NULL;
    if (setenv("OPENBLAS_NUM_THREADS", "1", 1) != 0) return errno;
    execv("/proc/self/exe", arguments);
    return errno;
}

/* Reserve OpenBLAS's work buffers (above): the calling thread's, which OpenBLAS maps at its
 * first level-3 call (its workers map theirs as they start), and one more when it fits (a
 * LAPACK routine may hold one while a BLAS call inside takes another). 0: done (*count
 * buffers of *bytes each; 0 and 0 when the BLAS is not OpenBLAS), ENOMEM: no room even for
 * the first (*bytes: the room asked for). */
int ffrf_blas_reserve_buffers(int *count, long long *bytes)
{
    void *taken[2];
    long long size = BLAS_BUFFER_BYTES, before, after;
    int k;
    *count = 0;
    *bytes = 0;
    if (!blas_memory_alloc || !blas_memory_free || !openblas_get_num_threads) return 0;
    for (k = 0; k < 2; ++k) {
        if (!room_for(size)) break;
        before = address_space_bytes();
        taken[k] = blas_memory_alloc(0);
        after = address_space_bytes();
        if (taken[k] == NULL) break;
        /* a slot mapped earlier comes back without growth: nothing to learn from it */
        if (before > 0 && after > before) size = after - before;
    }
    *count = k;
    *bytes = size;
    for (int j = 0; j < k; ++j) blas_memory_free(taken[j]);
    return k == 0 ? ENOMEM : 0;
}
