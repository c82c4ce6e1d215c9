/* Sensors through the C API (ffrf_sensor_count, ffrf_sensor_name, ffrf_sensor_values):
 *  - the crank-less slider mechanism of tests/data/sensors/slider_wheel.nml advanced in 10 ms
 *    chunks: the case's 11 sensors in input order with their sizes; at every chunk the wheel
 *    bearing's angle equals the wheel's rotation about z from its orientation sensor (to 1e-12
 *    rad, two computations of one angle), the slider x equals the closed form of that angle
 *    (to 1e-9 m, the constraint tolerance), a ground marker stays put (bitwise);
 *  - the engine (capi_engine.nml) to 2 ms: its two sensors crank_angle and crank_speed equal
 *    ffrf_crank_state bitwise;
 *  - failure paths: before the mechanism is prepared, a bad sensor number, NULL count, an
 *    array too small, a buffer too small for the name.
 * Usage: test_capi_sensors SLIDER_CASE ENGINE_CASE MESH_DIR */
#include <math.h>

#include "check.h"

static void slider(const char *case_file, const char *mesh_dir)
{
    static const char *names[] = {"bearing_angle", "guide_travel", "slider_position",
                                  "pin_position", "pin_velocity", "pin_acceleration",
                                  "wheel_orientation", "wheel_omega", "bearing_reaction",
                                  "wheel_energy", "ground_point"};
    static const int sizes[] = {1, 1, 3, 3, 3, 3, 9, 3, 12, 2, 3};
    const double r = 0.05, l = 0.2, phi0 = 30.0 * 3.14159265358979323846 / 180.0;
    ffrf_case *c = NULL;
    double angle[1], orientation[9], position[3], ground[3], ground0[3], small[2], phi, x;
    char name[64], tiny[4];
    int n, k, count, step;

    EXPECT(c, ffrf_case_open(case_file, mesh_dir, NULL, &c), FFRF_OK, "");
    EXPECT(c, ffrf_sensor_count(c, &n), FFRF_BAD_CALL, "not prepared yet");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_sensor_count(c, &n), FFRF_OK, "");
    CHECK(n == 11);
    for (k = 0; k < n && k < 11; k++) {
        EXPECT(c, ffrf_sensor_name(c, k, name, sizeof name), FFRF_OK, "");
        CHECK(strcmp(name, names[k]) == 0);
        EXPECT(c, ffrf_sensor_values(c, k, NULL, 0, &count), FFRF_OK, "");
        CHECK(count == sizes[k]);
    }
    EXPECT(c, ffrf_sensor_count(c, NULL), FFRF_BAD_CALL, "n is NULL");
    EXPECT(c, ffrf_sensor_name(c, 11, name, sizeof name), FFRF_BAD_CALL,
           "sensor 11 does not exist; the case has 11 sensors");
    EXPECT(c, ffrf_sensor_name(c, -1, name, sizeof name), FFRF_BAD_CALL,
           "sensor -1 does not exist");
    EXPECT(c, ffrf_sensor_name(c, 0, tiny, sizeof tiny), FFRF_BAD_CALL, "the buffer has 4");
    EXPECT(c, ffrf_sensor_values(c, 11, position, 3, &count), FFRF_BAD_CALL,
           "sensor 11 does not exist");
    EXPECT(c, ffrf_sensor_values(c, 0, position, 3, NULL), FFRF_BAD_CALL, "count is NULL");
    EXPECT(c, ffrf_sensor_values(c, 2, small, 2, &count), FFRF_BAD_CALL,
           "the array holds 2 values");
    CHECK(count == 3);
    EXPECT(c, ffrf_sensor_values(c, 10, ground0, 3, &count), FFRF_OK, "");
    for (step = 1; step <= 10; step++) {
        EXPECT(c, ffrf_mechanism_advance(c, 0.01 * step), FFRF_OK, "");
        EXPECT(c, ffrf_sensor_values(c, 0, angle, 1, &count), FFRF_OK, "");
        EXPECT(c, ffrf_sensor_values(c, 6, orientation, 9, &count), FFRF_OK, "");
        CHECK(fabs(remainder(atan2(orientation[1], orientation[0]) - angle[0],
                             2.0 * 3.14159265358979323846)) < 1e-12);
        phi = phi0 + angle[0];
        x = r * cos(phi) + sqrt(l * l - r * r * sin(phi) * sin(phi));
        EXPECT(c, ffrf_sensor_values(c, 2, position, 3, &count), FFRF_OK, "");
        CHECK(fabs(position[0] - x) < 1e-9);
        EXPECT(c, ffrf_sensor_values(c, 10, ground, 3, &count), FFRF_OK, "");
        CHECK(ground[0] == ground0[0] && ground[1] == ground0[1] && ground[2] == ground0[2]);
    }
    printf("slider: wheel angle %.6f rad at t = 0.1 s\n", angle[0]);
    CHECK(fabs(angle[0]) > 1e-3);
    ffrf_case_close(c);
}

static void engine(const char *case_file, const char *mesh_dir)
{
    ffrf_case *c = NULL;
    double angle, speed, value[1];
    char name[64];
    int n, count;

    EXPECT(c, ffrf_case_open(case_file, mesh_dir, NULL, &c), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_advance(c, 0.002), FFRF_OK, "");
    EXPECT(c, ffrf_sensor_count(c, &n), FFRF_OK, "");
    CHECK(n == 2);
    EXPECT(c, ffrf_crank_state(c, &angle, &speed), FFRF_OK, "");
    EXPECT(c, ffrf_sensor_name(c, 0, name, sizeof name), FFRF_OK, "");
    CHECK(strcmp(name, "crank_angle") == 0);
    EXPECT(c, ffrf_sensor_values(c, 0, value, 1, &count), FFRF_OK, "");
    CHECK(count == 1 && value[0] == angle);
    EXPECT(c, ffrf_sensor_name(c, 1, name, sizeof name), FFRF_OK, "");
    CHECK(strcmp(name, "crank_speed") == 0);
    EXPECT(c, ffrf_sensor_values(c, 1, value, 1, &count), FFRF_OK, "");
    CHECK(count == 1 && value[0] == speed);
    printf("engine: crank angle %.17g rad, speed %.17g rad/s\n", angle, speed);
    ffrf_case_close(c);
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: test_capi_sensors SLIDER_CASE ENGINE_CASE MESH_DIR\n");
        return 2;
    }
    slider(argv[1], argv[3]);
    engine(argv[2], argv[3]);
    if (failures > 0)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures > 0;
}
