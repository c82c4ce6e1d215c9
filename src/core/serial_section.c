/* Process-wide locks, so that distinct ffrf handles may be used from distinct threads
 * (docs/api.md, "Threads, signals and output"), around what keeps process-wide state:
 *  - ARPACK-NG 3.8: dsaupd/dsaup2/dsaitr keep the reverse-communication state in SAVEd variables;
 *  - MUMPS 5.5 (sequential): load-balancing state in module variables (DMUMPS_LOAD);
 *  - METIS 5.1: GKlib's process-wide random generator (orderings would vary with timing);
 *  - HDF5: Debian's build is serial (not thread-safe);
 *  - Fortran I/O: a file is connected to one unit at a time in the whole process, so two
 *    threads opening one mesh file would fail.
 * The mutexes are recursive (an HDF5 wrapper may call another one while holding the lock).
 * ARPACK's section is entered before MUMPS's (the Lanczos loop solves with MUMPS), never the
 * other way round, so they cannot deadlock. */
#define _GNU_SOURCE
#include <pthread.h>

/* 0 ARPACK, 1 HDF5, 2 MUMPS, 3 METIS, 4 reading an input file (ffrf_core_serial_section) */
enum { SECTION_COUNT = 5 };

static pthread_mutex_t sections[SECTION_COUNT];
static pthread_once_t sections_once = PTHREAD_ONCE_INIT;

static void make_sections(void)
{
    pthread_mutexattr_t attr;
    pthread_mutexattr_init(&attr);
    pthread_mutexattr_settype(&attr, PTHREAD_MUTEX_RECURSIVE);
    for (int k = 0; k < SECTION_COUNT; ++k) pthread_mutex_init(&sections[k], &attr);
    pthread_mutexattr_destroy(&attr);
}

/* Enter section k (blocks while another thread is inside); 0, or an errno value. */
int ffrf_serial_enter(int k)
{
    if (k < 0 || k >= SECTION_COUNT) return 22; /* EINVAL */
    pthread_once(&sections_once, make_sections);
    return pthread_mutex_lock(&sections[k]);
}

/* Leave section k, entered before by this thread; 0, or an errno value. */
int ffrf_serial_leave(int k)
{
    if (k < 0 || k >= SECTION_COUNT) return 22;
    pthread_once(&sections_once, make_sections);
    return pthread_mutex_unlock(&sections[k]);
}
