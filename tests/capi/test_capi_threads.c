/* Distinct handles in distinct threads (docs/api.md, "Threads, signals and output"): two modal
 * cases (one writing its results, one writing nothing) and two mechanisms advanced in 1 ms
 * chunks run at the same time, started together at a barrier. Each result must equal, bitwise,
 * the same computation done alone beforehand: frequencies of every body, crank angle and speed
 * after every chunk. Meanwhile OPENERS more threads open and close both cases OPENINGS times each
 * (reading and checking a case: namelists, meshes are read later), every one with status FFRF_OK.
 * ARPACK (SAVEd reverse-communication state) and HDF5 (a serial build) are
 * entered one thread at a time inside ffrf; everything else lives in the handles.
 * Usage: test_capi_threads MODAL_CASE MECHANISM_CASE MESH_DIR OUTPUT_DIR */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "ffrf.h"

enum { MAX_VALUES = 256, CHUNKS = 5, THREADS = 4, OPENERS = 4, OPENINGS = 25 };

typedef struct {
    const char *case_file, *mesh_dir, *output_dir; /* output_dir NULL: nothing written */
    int mechanism;                                 /* 0: modal case, 1: advance in chunks */
    double values[MAX_VALUES];                     /* frequencies, or angle/speed per chunk */
    int count;
    int status;                                    /* FFRF_OK, or the failing call's status */
    char message[512];
} job;

static pthread_barrier_t start_line;

static int fail(job *j, ffrf_case *c, int status, const char *what)
{
    snprintf(j->message, sizeof j->message, "%s: status %d: %s", what, status,
             ffrf_last_error(c));
    j->status = status;
    return status;
}

/* One job on its own handle: a modal run (frequencies of every body, in order) or the
 * mechanism advanced in CHUNKS chunks of 1 ms (angle and speed after each). */
static int run_job(job *j)
{
    ffrf_case *c = NULL;
    int status, n, b, count;
    j->count = 0;
    j->status = FFRF_OK;
    status = ffrf_case_open(j->case_file, j->mesh_dir, j->output_dir, &c);
    if (status != FFRF_OK) return fail(j, c, status, "open"), ffrf_case_close(c), status;
    if (j->mechanism) {
        for (int k = 1; k <= CHUNKS && status == FFRF_OK; k++) {
            double angle, speed;
            status = ffrf_mechanism_advance(c, 1.0e-3 * k);
            if (status == FFRF_OK) status = ffrf_crank_state(c, &angle, &speed);
            if (status == FFRF_OK) {
                j->values[j->count++] = angle;
                j->values[j->count++] = speed;
            }
        }
        if (status != FFRF_OK) fail(j, c, status, "advance");
    } else {
        status = ffrf_case_run(c);
        if (status == FFRF_OK) status = ffrf_body_count(c, &n);
        for (b = 0; status == FFRF_OK && b < n; b++) {
            status = ffrf_body_frequencies(c, b, j->values + j->count, MAX_VALUES - j->count,
                                           &count);
            if (status == FFRF_OK) j->count += count;
        }
        if (status != FFRF_OK) fail(j, c, status, "run");
    }
    ffrf_case_close(c);
    return status;
}

static void *thread_main(void *argument)
{
    pthread_barrier_wait(&start_line);
    run_job(argument);
    return NULL;
}

/* An opener: both cases opened and closed OPENINGS times; the first failure is kept. */
typedef struct {
    const char *case_files[2], *mesh_dir;
    int status;
    char message[512];
} opener;

static void *open_main(void *argument)
{
    opener *o = argument;
    pthread_barrier_wait(&start_line);
    for (int k = 0; k < 2 * OPENINGS && o->status == FFRF_OK; k++) {
        ffrf_case *c = NULL;
        int status = ffrf_case_open(o->case_files[k % 2], o->mesh_dir, NULL, &c);
        if (status != FFRF_OK) {
            snprintf(o->message, sizeof o->message, "open %d of %s: status %d: %s", k,
                     o->case_files[k % 2], status, ffrf_last_error(c));
            o->status = status;
        }
        ffrf_case_close(c);
    }
    return NULL;
}

int main(int argc, char **argv)
{
    job alone[2], jobs[THREADS];
    opener openers[OPENERS];
    pthread_t threads[THREADS], opener_threads[OPENERS];
    char written[1024];
    int failures = 0;

    if (argc != 5) {
        fprintf(stderr, "usage: %s MODAL_CASE MECHANISM_CASE MESH_DIR OUTPUT_DIR\n", argv[0]);
        return 2;
    }
    snprintf(written, sizeof written, "%s/threads", argv[4]);
    mkdir(written, 0755);

    /* references: each computation alone, nothing written */
    memset(alone, 0, sizeof alone);
    alone[0] = (job){.case_file = argv[1], .mesh_dir = argv[3], .mechanism = 0};
    alone[1] = (job){.case_file = argv[2], .mesh_dir = argv[3], .mechanism = 1};
    for (int r = 0; r < 2; r++)
        if (run_job(&alone[r]) != FFRF_OK || alone[r].count == 0) {
            fprintf(stderr, "FAIL reference %d: %s\n", r, alone[r].message);
            return 1;
        }

    /* the same four at once: modal with and without output, two mechanisms */
    for (int t = 0; t < THREADS; t++) {
        jobs[t] = alone[t / 2];
        jobs[t].output_dir = t == 0 ? written : NULL;
    }
    for (int t = 0; t < OPENERS; t++)
        openers[t] = (opener){.case_files = {argv[1], argv[2]}, .mesh_dir = argv[3]};
    pthread_barrier_init(&start_line, NULL, THREADS + OPENERS);
    for (int t = 0; t < THREADS; t++) pthread_create(&threads[t], NULL, thread_main, &jobs[t]);
    for (int t = 0; t < OPENERS; t++)
        pthread_create(&opener_threads[t], NULL, open_main, &openers[t]);
    for (int t = 0; t < THREADS; t++) pthread_join(threads[t], NULL);
    for (int t = 0; t < OPENERS; t++) pthread_join(opener_threads[t], NULL);
    pthread_barrier_destroy(&start_line);

    for (int t = 0; t < THREADS; t++) {
        const job *ref = &alone[t / 2];
        int differ = 0;
        double worst = 0.0;
        if (jobs[t].status != FFRF_OK) {
            fprintf(stderr, "FAIL thread %d: %s\n", t, jobs[t].message);
            failures++;
            continue;
        }
        for (int k = 0; k < ref->count; k++) {
            double d = fabs(jobs[t].values[k] - ref->values[k]) / fmax(fabs(ref->values[k]), 1e-300);
            differ += jobs[t].values[k] != ref->values[k];
            worst = fmax(worst, d);
        }
        printf("thread %d (%s%s): %d values, %d differ from the run alone (largest relative "
               "difference %.3g)\n", t, t / 2 ? "mechanism" : "modal",
               t == 0 ? ", results written" : "", jobs[t].count, differ, worst);
        if (jobs[t].count != ref->count || differ) failures++;
    }
    for (int t = 0; t < OPENERS; t++)
        if (openers[t].status != FFRF_OK) {
            fprintf(stderr, "FAIL opener %d: %s\n", t, openers[t].message);
            failures++;
        }
    printf("%d openers, %d case openings each: %s\n", OPENERS, 2 * OPENINGS,
           failures ? "see above" : "all FFRF_OK");
    if (failures) fprintf(stderr, "%d failure(s)\n", failures);
    return failures ? 1 : 0;
}
