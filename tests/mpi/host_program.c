/* A tiny MPI host program (test mpi_host_program): it splits MPI_COMM_WORLD into groups of
 * ranks {0, 1} and {2, ...} and runs the same modal case on each group's own communicator
 * through the C API (include/ffrf_mpi.h), so the library must work on the communicator it is
 * given, not on MPI_COMM_WORLD. Each group's rank 0 writes the frequencies of every body to
 * OUT_DIR/group<G>.txt, one "%.17g" per line, for run_mpi_case.py to compare with the
 * sequential driver's. The library writes nothing (no output folder). With ENGINE.nml, each
 * group also advances that mechanism case to its t_end in two halves and writes the final
 * "time angle speed" to OUT_DIR/group<G>_engine.txt.
 * Usage: mpirun -np 3 mpi_host_program CASE.nml MESH_DIR OUT_DIR [ENGINE.nml] */
#include <stdio.h>
#include <stdlib.h>

#include <mpi.h>

#include "ffrf_mpi.h"

int main(int argc, char **argv)
{
    int world_rank, group_rank, group_size, group, n, b, k, count, status = 0;
    double hz[64], t, t_end, angle, speed;
    char path[4096];
    ffrf_case *c = NULL, *engine = NULL;
    MPI_Comm comm;
    FILE *out;

    MPI_Init(&argc, &argv);
    if (argc != 4 && argc != 5) {
        fprintf(stderr, "usage: mpi_host_program CASE.nml MESH_DIR OUT_DIR [ENGINE.nml]\n");
        MPI_Finalize();
        return 1;
    }
    MPI_Comm_rank(MPI_COMM_WORLD, &world_rank);
    group = world_rank < 2 ? 0 : 1;
    MPI_Comm_split(MPI_COMM_WORLD, group, world_rank, &comm);
    MPI_Comm_rank(comm, &group_rank);
    MPI_Comm_size(comm, &group_size);

    if (ffrf_case_open(argv[1], argv[2], NULL, &c) != FFRF_OK ||
        ffrf_case_set_mpi_comm(c, comm) != FFRF_OK || ffrf_case_run(c) != FFRF_OK ||
        ffrf_body_count(c, &n) != FFRF_OK) {
        fprintf(stderr, "mpi_host_program: rank %d: %s\n", world_rank, ffrf_last_error(c));
        status = 1;
    }
    /* too late for a communicator: the case has run */
    if (status == 0 && ffrf_case_set_mpi_comm(c, comm) != FFRF_BAD_CALL) {
        fprintf(stderr, "mpi_host_program: set_communicator after run was accepted\n");
        status = 1;
    }
    if (status == 0 && group_rank == 0) {
        snprintf(path, sizeof path, "%s/group%d.txt", argv[3], group);
        out = fopen(path, "w");
        if (!out) {
            fprintf(stderr, "mpi_host_program: cannot write %s\n", path);
            status = 1;
        } else {
            fprintf(out, "# ranks %d\n", group_size);
            for (b = 0; b < n; b++) {
                if (ffrf_body_frequencies(c, b, hz, 64, &count) != FFRF_OK) {
                    status = 1;
                    break;
                }
                for (k = 0; k < count; k++) fprintf(out, "%.17g\n", hz[k]);
            }
            fclose(out);
        }
    }
    ffrf_case_close(c);
    if (status == 0 && argc == 5) {
        if (ffrf_case_open(argv[4], argv[2], NULL, &engine) != FFRF_OK ||
            ffrf_case_set_mpi_comm(engine, comm) != FFRF_OK ||
            ffrf_mechanism_advance(engine, 0.0) != FFRF_OK ||
            ffrf_mechanism_time(engine, &t, &t_end) != FFRF_OK ||
            ffrf_mechanism_advance(engine, 0.5 * t_end) != FFRF_OK ||
            ffrf_mechanism_advance(engine, t_end) != FFRF_OK ||
            ffrf_mechanism_time(engine, &t, &t_end) != FFRF_OK ||
            ffrf_crank_state(engine, &angle, &speed) != FFRF_OK) {
            fprintf(stderr, "mpi_host_program: rank %d, engine: %s\n", world_rank,
                    ffrf_last_error(engine));
            status = 1;
        } else if (group_rank == 0) {
            snprintf(path, sizeof path, "%s/group%d_engine.txt", argv[3], group);
            out = fopen(path, "w");
            if (!out) {
                status = 1;
            } else {
                fprintf(out, "%.17g %.17g %.17g\n", t, angle, speed);
                fclose(out);
            }
        }
        ffrf_case_close(engine);
    }
    MPI_Comm_free(&comm);
    MPI_Finalize();
    return status;
}
