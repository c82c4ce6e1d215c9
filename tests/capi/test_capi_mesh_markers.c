/* Markers at mesh points of a flexible body through the C API (docs/mechanisms.md "Markers at
 * mesh points"): the clamped cantilever with a marker at its tip face's RBE3 point (&marker
 * group; no interface there).
 *  - ffrf_marker_count counts it after the root interface's marker (2 markers);
 *  - ffrf_marker_state of it equals the position sensor at it, bitwise (one marker);
 *  - a force of 10 N along -y set by ffrf_marker_set_load on the case without &load brings the
 *    bar to the same rest as the case whose &load applies it at the marker (to 1e-9 of the sag:
 *    two routes to one generalized force, round-off apart), and its sag is that of beam theory
 *    F L^3 / (3 E I) to 1 % (measured -3.1e-3 with 8 modes: the 3-D clamp and the modal
 *    truncation, docs/mechanisms.md);
 *  - a bad marker number (2) is refused.
 * Usage: test_capi_mesh_markers LOADED_CASE FREE_CASE MESH_DIR */
#include <math.h>

#include "check.h"

/* The y change of the tip-face sensor from t = 0 to 0.1 s; the free case gets the load by the
 * C API. */
static double sag(const char *case_file, const char *mesh_dir, int by_api)
{
    const double force[3] = {0.0, -10.0, 0.0};
    ffrf_case *c = NULL;
    double start[3], end[3], marker[3];
    int n, count;

    EXPECT(c, ffrf_case_open(case_file, mesh_dir, NULL, &c), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_marker_count(c, 0, &n), FFRF_OK, "");
    CHECK(n == 2);
    EXPECT(c, ffrf_sensor_values(c, 0, start, 3, &count), FFRF_OK, "");
    if (by_api) {
        EXPECT(c, ffrf_marker_set_load(c, 0, 2, force, NULL), FFRF_BAD_CALL, "markers, 0..1");
        EXPECT(c, ffrf_marker_set_load(c, 0, 1, force, NULL), FFRF_OK, "");
    }
    EXPECT(c, ffrf_mechanism_advance(c, 0.1), FFRF_OK, "");
    EXPECT(c, ffrf_sensor_values(c, 0, end, 3, &count), FFRF_OK, "");
    EXPECT(c, ffrf_marker_state(c, 0, 1, marker, NULL, NULL), FFRF_OK, "");
    CHECK(marker[0] == end[0] && marker[1] == end[1] && marker[2] == end[2]);
    ffrf_case_close(c);
    return start[1] - end[1];
}

int main(int argc, char **argv)
{
    const double length = 0.4, side = 0.01, young = 210e9;
    double loaded, by_api, beam;

    if (argc != 4) {
        fprintf(stderr, "usage: test_capi_mesh_markers LOADED_CASE FREE_CASE MESH_DIR\n");
        return 2;
    }
    loaded = sag(argv[1], argv[3], 0);
    by_api = sag(argv[2], argv[3], 1);
    beam = 10.0 * length * length * length / (3.0 * young * side * side * side * side / 12.0);
    printf("tip-face sag: &load %.12e m, ffrf_marker_set_load %.12e m, beam theory %.6e m "
           "(%+.2e)\n", loaded, by_api, beam, loaded / beam - 1.0);
    CHECK(fabs(by_api - loaded) <= 1e-9 * fabs(loaded));
    CHECK(fabs(loaded / beam - 1.0) <= 1e-2);
    if (failures > 0)
        fprintf(stderr, "%d failure(s)\n", failures);
    return failures > 0;
}
