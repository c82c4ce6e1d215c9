/* Benchmark program (not a test, not an example): the engine through the C API, either
 * integrated in one call to t_end ("full", the case's own loads) or advanced in chunks of DT
 * seconds ("chunks") with the host applying the load torque -c omega |omega| about the crank
 * axis (z) at a crank marker before each chunk, held constant over it (run it on a case without
 * the &load of type 'drag'). Nothing is written to disk.
 *
 *   benchmark_api_engine CASE MESH_DIR full|chunks [DT=1e-3] [C=3.6e-4] [BODY=0] [MARKER=2]
 *
 * Prints one CSV line: mode,dt,prepare_s,integrate_s,t_end,crank_angle_rad,crank_speed_rad_s,
 * integrate_cpu_s (prepare: open, modes and consistent start; integrate: t_start to t_end, wall
 * and process CPU time: the CPU time is what a loaded machine disturbs least). */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include <ffrf.h>

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int check(int status, const char *call, const ffrf_case *c)
{
    if (status != FFRF_OK)
        fprintf(stderr, "benchmark_api_engine: %s: status %d: %s\n", call, status,
                c != NULL ? ffrf_last_error(c) : "(no handle)");
    return status;
}

int main(int argc, char **argv)
{
    ffrf_case *c = NULL;
    double dt = 1e-3, coefficient = 3.6e-4, t, t_end, angle = 0, speed = 0, t0, t1, t2;
    clock_t cpu1, cpu2;
    int body = 0, marker = 2, chunks, status;

    if (argc < 4 || (strcmp(argv[3], "full") != 0 && strcmp(argv[3], "chunks") != 0)) {
        fprintf(stderr, "usage: benchmark_api_engine CASE MESH_DIR full|chunks [DT] [C] [BODY] "
                        "[MARKER]\n");
        return 1;
    }
    chunks = strcmp(argv[3], "chunks") == 0;
    if (argc > 4) dt = atof(argv[4]);
    if (argc > 5) coefficient = atof(argv[5]);
    if (argc > 6) body = atoi(argv[6]);
    if (argc > 7) marker = atoi(argv[7]);

    t0 = now();
    status = check(ffrf_case_open(argv[1], argv[2], NULL, &c), "ffrf_case_open", c);
    /* advancing to t_start (0 in the engine cases) only prepares: modes, mechanism, start */
    if (status == FFRF_OK) status = check(ffrf_mechanism_advance(c, 0.0), "ffrf_mechanism_advance", c);
    if (status == FFRF_OK) status = check(ffrf_mechanism_time(c, &t, &t_end), "ffrf_mechanism_time", c);
    t1 = now();
    cpu1 = clock();
    if (status == FFRF_OK && !chunks)
        status = check(ffrf_mechanism_advance(c, t_end), "ffrf_mechanism_advance", c);
    for (long k = 1; status == FFRF_OK && chunks; ++k) {
        double moment[3] = {0, 0, 0}, next = t + (double)k * dt;
        if (next > t_end - 1e-12) next = t_end;
        status = check(ffrf_crank_state(c, &angle, &speed), "ffrf_crank_state", c);
        moment[2] = -coefficient * speed * (speed < 0 ? -speed : speed);
        if (status == FFRF_OK)
            status = check(ffrf_marker_set_load(c, body, marker, NULL, moment),
                           "ffrf_marker_set_load", c);
        if (status == FFRF_OK)
            status = check(ffrf_mechanism_advance(c, next), "ffrf_mechanism_advance", c);
        if (next >= t_end) break;
    }
    t2 = now();
    cpu2 = clock();
    if (status == FFRF_OK) status = check(ffrf_crank_state(c, &angle, &speed), "ffrf_crank_state", c);
    if (status == FFRF_OK)
        printf("%s,%g,%.4f,%.4f,%.6g,%.17g,%.17g,%.4f\n", chunks ? "chunks" : "full", dt,
               t1 - t0, t2 - t1, t_end, angle, speed, (double)(cpu2 - cpu1) / CLOCKS_PER_SEC);
    ffrf_case_close(c);
    return status;
}
