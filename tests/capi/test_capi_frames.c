/* Marker frames through the C API (issue 24: joints act between marker frames):
 *  - the rigid pendulum of tests/data/frames/rigid_pendulum_oriented.nml, whose hinge frame is
 *    a ground &marker orientation (z along global y): advanced in 50 ms chunks to 0.5 s, the
 *    rod turns about y only (|w_x|, |w_z| < 1e-12 |w|), its end stays at the pivot (1e-9 m,
 *    the constraint tolerance), and |w| meets energy conservation of the rigid rod,
 *    w^2 = 2 m g d / (J_yy + m l^2), d the drop of its centre (5e-5 relative, measured 6e-6:
 *    generalized-alpha at h = 1 ms, rho_inf = 0.9);
 *  - the flexible double pendulum of tests/regression/frames_pendulum_xz.nml (joints about the
 *    links' y axis at their interfaces): link1 has its two interfaces and two framed markers
 *    (ffrf_marker_count 4), each framed marker at its interface's virtual node with its angular
 *    velocity (ffrf_marker_state, bitwise: the frame C is constant), the links turning about y
 *    (|w_x|, |w_z| < 1e-12 |w|: nothing drives out-of-plane motion, measured 0);
 *  - tests/data/frames/bad_marker_orientation.nml: FFRF_INPUT_ERROR naming the file, line,
 *    &marker key, the marker and the defect.
 * Usage: test_capi_frames RIGID_CASE FLEXIBLE_CASE BAD_CASE MESH_DIR */
#include <math.h>

#include "check.h"

static void rigid(const char *case_file)
{
    const double m = 1.0, g = 9.81, l = 0.5, j = 1.0 / 12.0;
    ffrf_case *c = NULL;
    double q[7], r[3], u[3], w[3], speed, expected, worst = 0.0;
    int count, step;

    EXPECT(c, ffrf_case_open(case_file, NULL, NULL, &c), FFRF_OK, "");
    for (step = 1; step <= 10; step++) {
        EXPECT(c, ffrf_mechanism_advance(c, 0.05 * step), FFRF_OK, "");
        EXPECT(c, ffrf_body_state(c, 0, q, NULL, 7, &count), FFRF_OK, "");
        EXPECT(c, ffrf_marker_state(c, 0, 0, r, u, w), FFRF_OK, "");
        speed = sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        CHECK(fabs(w[0]) < 1e-12 * speed && fabs(w[2]) < 1e-12 * speed);
        CHECK(sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) < 1e-9);
        expected = sqrt(2.0 * m * g * (-q[2]) / (j + m * l * l));
        if (fabs(speed - expected) / expected > worst)
            worst = fabs(speed - expected) / expected;
    }
    printf("rigid pendulum about a ground marker frame: |w| = %.6f rad/s at 0.5 s, worst "
           "relative deviation from energy conservation %.2e\n", speed, worst);
    CHECK(worst < 5e-5);
    CHECK(speed > 1.0);
    ffrf_case_close(c);
}

static void flexible(const char *case_file, const char *mesh_dir)
{
    ffrf_case *c = NULL;
    double r[4][3], u[4][3], w[4][3], speed;
    int n, k, step;

    EXPECT(c, ffrf_case_open(case_file, mesh_dir, NULL, &c), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_marker_count(c, 0, &n), FFRF_OK, "");
    CHECK(n == 4);
    EXPECT(c, ffrf_marker_count(c, 1, &n), FFRF_OK, "");
    CHECK(n == 3);
    for (step = 1; step <= 5; step++) {
        EXPECT(c, ffrf_mechanism_advance(c, 0.02 * step), FFRF_OK, "");
        for (k = 0; k < 4; k++)
            EXPECT(c, ffrf_marker_state(c, 0, k, r[k], u[k], w[k]), FFRF_OK, "");
        /* markers 2 and 3 are the shoulder's and the elbow's framed markers at end0, end1 */
        CHECK(memcmp(r[2], r[0], sizeof r[0]) == 0 && memcmp(w[2], w[0], sizeof w[0]) == 0);
        CHECK(memcmp(r[3], r[1], sizeof r[1]) == 0 && memcmp(w[3], w[1], sizeof w[1]) == 0);
        speed = sqrt(w[0][0] * w[0][0] + w[0][1] * w[0][1] + w[0][2] * w[0][2]);
        CHECK(fabs(w[0][0]) < 1e-12 * speed && fabs(w[0][2]) < 1e-12 * speed);
    }
    printf("flexible pendulum in the x-z plane: link1 w = (%.3e, %.6f, %.3e) rad/s at 0.1 s\n",
           w[0][0], w[0][1], w[0][2]);
    CHECK(speed > 1.0);
    ffrf_case_close(c);
}

int main(int argc, char **argv)
{
    ffrf_case *c = NULL;

    if (argc != 5) {
        fprintf(stderr, "usage: %s RIGID_CASE FLEXIBLE_CASE BAD_CASE MESH_DIR\n", argv[0]);
        return 2;
    }
    rigid(argv[1]);
    flexible(argv[2], argv[4]);
    EXPECT(c, ffrf_case_open(argv[3], NULL, NULL, &c), FFRF_INPUT_ERROR,
           "marker \"pivot\" of body \"ground\": the orientation is not orthonormal");
    CHECK(strstr(ffrf_last_error(c), "bad_marker_orientation.nml:11: &marker orientation = ")
          != NULL);
    printf("bad orientation: %s\n", ffrf_last_error(c));
    ffrf_case_close(c);
    if (failures > 0)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures > 0;
}
