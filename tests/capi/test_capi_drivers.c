/* Drivers through the C API (ffrf_driver_state) on input/driven_crank.nml, advanced in 50 ms
 * chunks to 1 s: a crank whose speed is a smooth step 0 -> 2 pi rad/s over T = 0.5 s under
 * gravity. At every chunk the driver's angle equals the spin-up law
 * theta = (W/T)(t^2/2 + (T/(2 pi))^2 (cos(2 pi t/T) - 1)) (then W T/2 + W (t - T)) wrapped
 * into (-pi, pi] (1e-9 rad, the Newton tolerance), its rate theta' (2e-5 W) and its torque the
 * closed form I_O theta'' + m g (L/2) cos(theta) (1.5e-4 of the largest torque, 9 N m); the
 * driver sensor "motor" gives the same three numbers (bitwise). Failure paths: a NULL handle,
 * before the mechanism is prepared, a joint without a driver (the prismatic "rail"), a bad
 * joint number, NULL values.
 * Usage: test_capi_drivers CASE MESH_DIR */
#include <math.h>

#include "check.h"

int main(int argc, char **argv)
{
    const double pi = 3.14159265358979323846, w = 2.0 * pi, ramp = 0.5;
    const double m = 2.0, l = 0.5, g = 9.81;
    ffrf_case *c = NULL;
    double values[3], sensor[3], t, theta, rate, accel, tau, wrapped;
    int step, count, k;

    if (argc != 3) {
        fprintf(stderr, "usage: test_capi_drivers CASE MESH_DIR\n");
        return 2;
    }
    EXPECT(NULL, ffrf_driver_state(NULL, 0, values), FFRF_BAD_CALL, "NULL");
    EXPECT(c, ffrf_case_open(argv[1], argv[2], NULL, &c), FFRF_OK, "");
    EXPECT(c, ffrf_driver_state(c, 0, values), FFRF_BAD_CALL, "not prepared yet");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_driver_state(c, 1, values), FFRF_BAD_CALL, "joint 1 (\"rail\") has no driver");
    EXPECT(c, ffrf_driver_state(c, 2, values), FFRF_BAD_CALL, "joint 2 does not exist");
    EXPECT(c, ffrf_driver_state(c, 0, NULL), FFRF_BAD_CALL, "values is NULL");
    for (step = 1; step <= 20; step++) {
        t = 0.05 * step;
        EXPECT(c, ffrf_mechanism_advance(c, t), FFRF_OK, "");
        EXPECT(c, ffrf_driver_state(c, 0, values), FFRF_OK, "");
        EXPECT(c, ffrf_sensor_values(c, 0, sensor, 3, &count), FFRF_OK, "");
        CHECK(count == 3);
        for (k = 0; k < 3; k++)
            CHECK(sensor[k] == values[k]);
        if (t <= ramp) {
            theta = w / ramp * (0.5 * t * t +
                                pow(ramp / (2.0 * pi), 2) * (cos(2.0 * pi * t / ramp) - 1.0));
            rate = w / ramp * (t - ramp / (2.0 * pi) * sin(2.0 * pi * t / ramp));
            accel = w / ramp * (1.0 - cos(2.0 * pi * t / ramp));
        } else {
            theta = w * ramp / 2.0 + w * (t - ramp);
            rate = w;
            accel = 0.0;
        }
        wrapped = atan2(sin(theta), cos(theta));
        tau = m * l * l / 3.0 * accel + m * g * l / 2.0 * cos(theta);
        CHECK(fabs(remainder(values[0] - wrapped, 2.0 * pi)) < 1e-9);
        CHECK(fabs(values[1] - rate) < 2e-5 * w);
        CHECK(fabs(values[2] - tau) < 1.5e-4 * 9.0);
    }
    ffrf_case_close(c);
    if (failures > 0)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures > 0;
}
