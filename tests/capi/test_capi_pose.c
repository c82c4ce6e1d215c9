/* The starting pose of a body through the C API (ffrf_body_set_pose; issue 24, body pose).
 *
 * Usage: test_capi_pose POSE_FREE_CASE MESH_DIR OUT_DIR
 * POSE_FREE_CASE is tests/capi/pose_pendulum.nml (a rigid rod hinged at its end, no pose keys).
 *  - every refusal: its status and a message naming the body and the defect (bad body index,
 *    rotation not orthonormal, a reflection, a value not finite, after the first
 *    ffrf_mechanism_advance), and a refused call leaves the case as it was;
 *  - the pose set (consistent: end on the pivot, v = omega x r) is the state at t_start
 *    (body_state R and v to 1e-12: the assembly has nothing to move);
 *  - the same pose set in two calls (NULL keeps the values of the first) on a case with an
 *    output folder run to t_end: OUT_DIR holds the results that compare_pose.py compares,
 *    bitwise, with the driver's run of POSE_FREE_CASE with the pose as --set body[rod].KEY=...
 */
#include <math.h>

#include "check.h"

/* The pose of tests/capi/pose_pendulum_posed.nml: axis (0.6, 0, -0.8), centre 0.5 m along it,
 * omega = (0, 2, 0) rad/s, v = omega x r. */
static const double position[3] = {0.3, 0.0, -0.4};
static const double orientation[9] = {0.6, 0.0, 0.8, 0.0, 1.0, 0.0, -0.8, 0.0, 0.6};
static const double velocity[3] = {-0.8, 0.0, -0.6};
static const double angular_velocity[3] = {0.0, 2.0, 0.0};

int main(int argc, char **argv)
{
    ffrf_case *c = NULL, *rec = NULL;
    double q[7], v[6], t, t_end;
    int count = 0, k;
    if (argc != 4) {
        fprintf(stderr, "usage: test_capi_pose POSE_FREE_CASE MESH_DIR OUT_DIR\n");
        return 2;
    }
    EXPECT(NULL, ffrf_body_set_pose(NULL, 0, position, NULL, NULL, NULL), FFRF_BAD_CALL,
           "NULL");
    EXPECT(c, ffrf_case_open(argv[1], argv[2], NULL, &c), FFRF_OK, "");

    /* refusals: status and message naming the body and the defect */
    EXPECT(c, ffrf_body_set_pose(c, 1, position, NULL, NULL, NULL), FFRF_BAD_CALL,
           "body_set_pose: body 1 does not exist; the case has 1 bodies");
    EXPECT(c, ffrf_body_set_pose(c, -1, position, NULL, NULL, NULL), FFRF_BAD_CALL,
           "body -1 does not exist");
    {
        double stretched[9], reflected[9];
        for (k = 0; k < 9; k++) {
            stretched[k] = orientation[k];
            reflected[k] = orientation[k];
        }
        stretched[0] = 0.6 + 1.0e-6; /* |A A^T - I| = 1.2e-6 > 1e-9 */
        EXPECT(c, ffrf_body_set_pose(c, 0, NULL, stretched, NULL, NULL), FFRF_INPUT_ERROR,
               "\"rod\": the orientation is not orthonormal: largest |A A^T - I| = 1.2");
        reflected[6] = -reflected[6]; /* third row negated: det = -1 */
        reflected[7] = -reflected[7];
        reflected[8] = -reflected[8];
        EXPECT(c, ffrf_body_set_pose(c, 0, NULL, reflected, NULL, NULL), FFRF_INPUT_ERROR,
               "\"rod\": the orientation has det = -1");
    }
    {
        double bad[3] = {-0.8, NAN, -0.6};
        EXPECT(c, ffrf_body_set_pose(c, 0, NULL, NULL, bad, NULL), FFRF_INPUT_ERROR,
               "body 0 \"rod\": velocity value 2 is not finite");
        bad[1] = INFINITY;
        EXPECT(c, ffrf_body_set_pose(c, 0, NULL, NULL, NULL, bad), FFRF_INPUT_ERROR,
               "body 0 \"rod\": angular_velocity value 2 is not finite");
    }

    /* a refused call kept the default pose; the pose set now is the state at t_start */
    EXPECT(c, ffrf_body_set_pose(c, 0, position, orientation, velocity, angular_velocity),
           FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_body_state(c, 0, q, v, 7, &count), FFRF_OK, "");
    CHECK(count == 7);
    for (k = 0; k < 3; k++) {
        CHECK(fabs(q[k] - position[k]) <= 1.0e-12);
        CHECK(fabs(v[k] - velocity[k]) <= 1.0e-12);
    }
    /* Euler parameters of a turn by acos(0.6) about y: e0 = cos(theta/2) = sqrt(0.8),
     * e2 = sin(theta/2) = sqrt(0.2) (or both negated) */
    CHECK(fabs(fabs(q[3]) - sqrt(0.8)) <= 1.0e-12 && fabs(fabs(q[5]) - sqrt(0.2)) <= 1.0e-12);
    CHECK(fabs(q[4]) <= 1.0e-12 && fabs(q[6]) <= 1.0e-12 && q[3] * q[5] > 0.0);
    EXPECT(c, ffrf_body_set_pose(c, 0, position, NULL, NULL, NULL), FFRF_BAD_CALL,
           "body_set_pose: the motion has started");
    ffrf_case_close(c);

    /* the run the driver's is compared with: the pose in two calls, NULL keeping values */
    EXPECT(rec, ffrf_case_open(argv[1], argv[2], argv[3], &rec), FFRF_OK, "");
    EXPECT(rec, ffrf_body_set_pose(rec, 0, NULL, NULL, velocity, angular_velocity), FFRF_OK,
           "");
    EXPECT(rec, ffrf_body_set_pose(rec, 0, position, orientation, NULL, NULL), FFRF_OK, "");
    EXPECT(rec, ffrf_case_run(rec), FFRF_OK, "");
    EXPECT(rec, ffrf_mechanism_time(rec, &t, &t_end), FFRF_OK, "");
    CHECK(t == t_end && t_end == 0.5);
    EXPECT(rec, ffrf_body_set_pose(rec, 0, position, NULL, NULL, NULL), FFRF_BAD_CALL,
           "the motion has started");
    ffrf_case_close(rec);

    if (failures) {
        fprintf(stderr, "%d failures\n", failures);
        return 1;
    }
    printf("capi pose: all checks passed\n");
    return 0;
}
