/* Results through the C API, printed for compare_driver.py, which checks them against the
 * ffrf driver's HDF5 results of the same cases:
 *  - a modal case run twice (with an output folder: results written as the driver writes
 *    them; without: nothing written): frequencies, sizes, shapes, mass properties;
 *  - a mechanism case advanced in chunks of `chunk` seconds from t_start to t_end: time, crank
 *    angle and speed after every chunk, joint reactions at the end; bad calls that need the
 *    prepared mechanism (a time before the current one or beyond t_end, bad marker and joint
 *    numbers, small arrays).
 * Usage: test_capi_run MODAL_CASE MECHANISM_CASE MESH_DIR OUTPUT_DIR CHUNK_SECONDS
 * Output lines: "frequency <body> <mode> <Hz>", "crank <t> <angle> <speed>",
 * "reaction <joint name> <12 values>" (%.17g: the doubles exactly). */
#include <math.h>

#include "check.h"

static void modal_case(const char *case_file, const char *mesh_dir, const char *output_dir)
{
    ffrf_case *c = NULL, *quiet = NULL;
    double hz[64], hz2[64], small[2], mass, center[3], inertia[9], *shape, *rows, *xyz;
    size_t count_size;
    int n, b, k, count, count2, nodes, modes, interfaces;
    char name[64];

    EXPECT(c, ffrf_case_open(case_file, mesh_dir, output_dir, &c), FFRF_OK, "");
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    EXPECT(c, ffrf_case_run(c), FFRF_BAD_CALL, "run: the case has already run");
    EXPECT(quiet, ffrf_case_open(case_file, mesh_dir, NULL, &quiet), FFRF_OK, "");
    EXPECT(quiet, ffrf_case_run(quiet), FFRF_OK, "");
    EXPECT(c, ffrf_body_count(c, &n), FFRF_OK, "");
    for (b = 0; b < n; b++) {
        EXPECT(c, ffrf_body_name(c, b, name, sizeof name), FFRF_OK, "");
        /* size query, then the values; a small array is a bad call that still reports */
        EXPECT(c, ffrf_body_frequencies(c, b, NULL, 0, &count), FFRF_OK, "");
        CHECK(count > 2 && count <= 64);
        EXPECT(c, ffrf_body_frequencies(c, b, hz, 64, &count), FFRF_OK, "");
        EXPECT(c, ffrf_body_frequencies(c, b, small, 2, &count2), FFRF_BAD_CALL,
               "the array holds 2 values");
        CHECK(count2 == count && small[0] == hz[0] && small[1] == hz[1]);
        EXPECT(c, ffrf_body_frequencies(c, b, NULL, 3, &count2), FFRF_BAD_CALL,
               "the array is NULL but its capacity is 3");
        /* without an output folder: the same numbers, bitwise */
        EXPECT(quiet, ffrf_body_frequencies(quiet, b, hz2, 64, &count2), FFRF_OK, "");
        CHECK(count2 == count);
        for (k = 0; k < count && k < count2; k++) {
            CHECK(hz[k] == hz2[k]);
            printf("frequency %s %d %.17g\n", name, k, hz[k]);
        }
        /* sizes and arrays */
        EXPECT(c, ffrf_body_sizes(c, b, &nodes, &modes, &interfaces), FFRF_OK, "");
        CHECK(modes == count && nodes > 0 && interfaces > 0);
        EXPECT(c, ffrf_body_mode_shapes(c, b, NULL, 0, &count_size), FFRF_OK, "");
        CHECK(count_size == (size_t)3 * nodes * modes);
        shape = malloc(count_size * sizeof *shape);
        EXPECT(c, ffrf_body_mode_shapes(c, b, shape, count_size, &count_size), FFRF_OK, "");
        EXPECT(c, ffrf_body_nodes(c, b, NULL, 0, &count_size), FFRF_OK, "");
        CHECK(count_size == (size_t)3 * nodes);
        xyz = malloc(count_size * sizeof *xyz);
        EXPECT(c, ffrf_body_nodes(c, b, xyz, count_size, &count_size), FFRF_OK, "");
        EXPECT(c, ffrf_body_nodes(c, b, xyz, 5, &count_size), FFRF_BAD_CALL,
               "the array holds 5 values");
        EXPECT(c, ffrf_body_virtual_node_shapes(c, b, NULL, 0, &count_size), FFRF_OK, "");
        CHECK(count_size == (size_t)6 * interfaces * modes);
        rows = malloc(count_size * sizeof *rows);
        EXPECT(c, ffrf_body_virtual_node_shapes(c, b, rows, count_size, &count_size), FFRF_OK,
               "");
        EXPECT(c, ffrf_body_mass_properties(c, b, &mass, center, inertia), FFRF_OK, "");
        /* steel crank: a few kg; inertia symmetric positive */
        CHECK(mass > 0.1 && mass < 100.0);
        CHECK(inertia[1] == inertia[3] && inertia[2] == inertia[6] && inertia[5] == inertia[7]);
        CHECK(inertia[0] > 0.0 && inertia[4] > 0.0 && inertia[8] > 0.0);
        printf("mass %s %.17g\n", name, mass);
        /* FFRF invariants: mass and centre as above (1e-12), M_PsiPsi = I for mass-normalised
         * modes (1e-10: the modes' orthonormality error), K_ff = (2 pi f)^2 (1e-14),
         * theta_u = J_c + m (|c|^2 I - c c^T) (parallel axes, 1e-10 of its largest entry) */
        {
            double inv[64 * 64], inv2[9], scale = 0.0, worst = 0.0, d;
            size_t n_inv;
            int r, s;
            EXPECT(c, ffrf_body_invariant(c, b, "mass", inv, 64 * 64, &n_inv), FFRF_OK, "");
            CHECK(n_inv == 1 && fabs(inv[0] - mass) <= 1e-12 * mass);
            EXPECT(c, ffrf_body_invariant(c, b, "M_PsiPsi", inv, 64 * 64, &n_inv), FFRF_OK, "");
            CHECK(n_inv == (size_t)modes * modes);
            for (r = 0; r < modes; r++)
                for (s = 0; s < modes; s++)
                    worst = fmax(worst, fabs(inv[r + modes * s] - (r == s ? 1.0 : 0.0)));
            CHECK(worst < 1e-10);
            printf("invariant %s M_PsiPsi %.3g\n", name, worst);
            EXPECT(c, ffrf_body_invariant(c, b, "K_ff", inv, 64 * 64, &n_inv), FFRF_OK, "");
            for (k = 0; k < modes; k++) {
                d = 2.0 * 3.14159265358979323846 * hz[k];
                CHECK(fabs(inv[k] - d * d) <= 1e-14 * d * d);
            }
            EXPECT(c, ffrf_body_invariant(c, b, "theta_u", inv2, 9, &n_inv), FFRF_OK, "");
            worst = 0.0;
            for (r = 0; r < 3; r++)
                for (s = 0; s < 3; s++) {
                    d = inertia[r + 3 * s] - mass * center[r] * center[s] +
                        (r == s ? mass * (center[0] * center[0] + center[1] * center[1] +
                                          center[2] * center[2]) : 0.0);
                    scale = fmax(scale, fabs(inv2[r + 3 * s]));
                    worst = fmax(worst, fabs(inv2[r + 3 * s] - d));
                }
            CHECK(worst <= 1e-10 * scale);
            printf("invariant %s theta_u %.3g of %.3g\n", name, worst, scale);
            EXPECT(c, ffrf_body_invariant(c, b, "M_xPsit", NULL, 0, &n_inv), FFRF_OK, "");
            CHECK(n_inv == (size_t)9 * modes);
            EXPECT(c, ffrf_body_invariant(c, b, "M_Psi", inv, 64, &n_inv), FFRF_BAD_CALL,
                   "no invariant \"M_Psi\"; the invariants are mass, center_of_mass");
        }
        printf("shape_value %s %.17g %.17g\n", name, shape[0], rows[0]);
        free(shape);
        free(rows);
        free(xyz);
    }
    EXPECT(c, ffrf_mechanism_advance(c, 1.0e-3), FFRF_BAD_CALL, "is a modal case");
    ffrf_case_close(c);
    ffrf_case_close(quiet);
}

static void mechanism_case(const char *case_file, const char *mesh_dir, double chunk)
{
    ffrf_case *c = NULL;
    double t = 0.0, t_end = 0.0, angle, speed, q[64], v[64], r[3], u[3], w[3], f[6], m[6],
        target, zero[3] = {0.0, 0.0, 0.0};
    int n, b, j, k, count, markers, steps;
    char name[64];

    EXPECT(c, ffrf_case_open(case_file, mesh_dir, NULL, &c), FFRF_OK, "");
    /* advance to t_start: prepares only */
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_time(c, &t, &t_end), FFRF_OK, "");
    CHECK(t == 0.0 && t_end > 0.0);
    EXPECT(c, ffrf_crank_state(c, &angle, &speed), FFRF_OK, "");
    printf("crank %.17g %.17g %.17g\n", t, angle, speed);
    EXPECT(c, ffrf_body_count(c, &n), FFRF_OK, "");
    /* bad indices on the prepared mechanism */
    EXPECT(c, ffrf_marker_count(c, n, &markers), FFRF_BAD_CALL, "does not exist");
    EXPECT(c, ffrf_marker_count(c, 0, &markers), FFRF_OK, "");
    CHECK(markers >= 1);
    EXPECT(c, ffrf_marker_state(c, 0, markers, r, u, w), FFRF_BAD_CALL,
           "does not exist; body \"crank\" has");
    EXPECT(c, ffrf_joint_count(c, &j), FFRF_OK, "");
    EXPECT(c, ffrf_joint_reaction(c, j, f, m), FFRF_BAD_CALL, "does not exist; the case has");
    EXPECT(c, ffrf_joint_name(c, 0, name, 2), FFRF_BAD_CALL, "the buffer has 2 bytes");
    EXPECT(c, ffrf_body_state(c, 0, q, v, 2, &count), FFRF_BAD_CALL, "the array holds 2");
    /* a zero host load changes nothing (bitwise: the driver comparison checks it) */
    EXPECT(c, ffrf_marker_set_load(c, 0, 0, zero, zero), FFRF_OK, "");
    EXPECT(c, ffrf_marker_set_load(c, 0, markers, zero, zero), FFRF_BAD_CALL,
           "does not exist");

    steps = (int)(t_end / chunk + 0.5);
    for (k = 1; k <= steps; k++) {
        target = k * chunk;
        if (k == steps)
            target = t_end;
        EXPECT(c, ffrf_mechanism_advance(c, target), FFRF_OK, "");
        EXPECT(c, ffrf_mechanism_time(c, &t, NULL), FFRF_OK, "");
        EXPECT(c, ffrf_crank_state(c, &angle, &speed), FFRF_OK, "");
        printf("crank %.17g %.17g %.17g\n", t, angle, speed);
    }
    CHECK(t == t_end);
    EXPECT(c, ffrf_mechanism_advance(c, 0.5 * t_end), FFRF_INPUT_ERROR,
           "before the current time");
    EXPECT(c, ffrf_mechanism_advance(c, 2.0 * t_end), FFRF_INPUT_ERROR, "beyond the case's t_end");
    EXPECT(c, ffrf_mechanism_advance(c, t_end), FFRF_OK, "");
    for (k = 0; k < j; k++) {
        EXPECT(c, ffrf_joint_name(c, k, name, sizeof name), FFRF_OK, "");
        EXPECT(c, ffrf_joint_reaction(c, k, f, m), FFRF_OK, "");
        printf("reaction %s %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g "
               "%.17g\n", name, f[0], f[1], f[2], m[0], m[1], m[2], f[3], f[4], f[5], m[3], m[4],
               m[5]);
    }
    for (b = 0; b < n; b++) {
        EXPECT(c, ffrf_body_name(c, b, name, sizeof name), FFRF_OK, "");
        EXPECT(c, ffrf_body_state(c, b, q, v, 64, &count), FFRF_OK, "");
        CHECK(count >= 7);
        printf("position %s %.17g %.17g %.17g\n", name, q[0], q[1], q[2]);
        EXPECT(c, ffrf_marker_count(c, b, &markers), FFRF_OK, "");
        for (k = 0; k < markers; k++) {
            EXPECT(c, ffrf_marker_state(c, b, k, r, u, w), FFRF_OK, "");
            printf("marker %s %d %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", name,
                   k, r[0], r[1], r[2], u[0], u[1], u[2], w[0], w[1], w[2]);
        }
    }
    /* run after advancing (no output folder): continues to t_end, here nothing left */
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    EXPECT(c, ffrf_case_run(c), FFRF_BAD_CALL, "already run");
    EXPECT(c, ffrf_crank_state(c, &angle, &speed), FFRF_OK, "");
    ffrf_case_close(c);
}

int main(int argc, char **argv)
{
    if (argc != 6) {
        fprintf(stderr, "usage: %s MODAL_CASE MECHANISM_CASE MESH_DIR OUTPUT_DIR CHUNK\n",
                argv[0]);
        return 2;
    }
    modal_case(argv[1], argv[3], argv[4]);
    mechanism_case(argv[2], argv[3], atof(argv[5]));
    if (failures > 0) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    fprintf(stderr, "test_capi_run: all checks passed\n");
    return 0;
}
