/* A mechanism advanced through the C API with an output folder records the driver's results
 * (issue 11: one integration path), checked by compare_record.py against the driver's file:
 *  - OUTPUT_DIR/chunked: the case advanced in chunks of CHUNK seconds to t_end. Between two
 *    advances the results file is being written under its partial name (<file>.part, flushed
 *    after every advance) and not yet in place; the advance that reaches t_end puts it in
 *    place, complete.
 *  - OUTPUT_DIR/stopped: the case advanced to about t_end / 2, then closed: ffrf_case_close
 *    puts the file in place with status "stopped: ..." and every step so far.
 *  - no output folder (NULL): the same advance to t_end writes nothing (no results file in
 *    the current folder).
 * Usage: test_capi_record CASE MESH_DIR OUTPUT_DIR CHUNK_SECONDS RESULTS_NAME */
#include <sys/stat.h>

#include "check.h"

static int exists(const char *path)
{
    struct stat s;
    return stat(path, &s) == 0;
}

/* Open `case_file` with `output_dir` and advance it in chunks up to fraction * t_end;
 * `results`: the path of its results file, checked between the advances. */
static void advance(const char *case_file, const char *mesh_dir, const char *output_dir,
                    double chunk, double fraction, const char *results)
{
    ffrf_case *c = NULL;
    double t = 0.0, t_end = 0.0, target, stop;
    char partial[1024];
    int k, chunks;

    snprintf(partial, sizeof partial, "%s.part", results);
    EXPECT(c, ffrf_case_open(case_file, mesh_dir, output_dir, &c), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_time(c, &t, &t_end), FFRF_OK, "");
    stop = fraction == 1.0 ? t_end : fraction * t_end;
    chunks = (int)(stop / chunk + 0.5);
    for (k = 1; k <= chunks; k++) {
        target = k * chunk;
        if (k == chunks)
            target = stop;
        EXPECT(c, ffrf_mechanism_advance(c, target), FFRF_OK, "");
        if (output_dir != NULL && target < t_end) {
            /* recorded under the partial name, not yet in place */
            CHECK(exists(partial));
            CHECK(!exists(results));
        }
    }
    if (output_dir != NULL && stop == t_end) {
        CHECK(exists(results));
        CHECK(!exists(partial));
        /* nothing left: the file stays as it is */
        EXPECT(c, ffrf_mechanism_advance(c, t_end), FFRF_OK, "");
    }
    ffrf_case_close(c);
    if (output_dir != NULL) {
        CHECK(exists(results));
        CHECK(!exists(partial));
    }
}

int main(int argc, char **argv)
{
    char folder[2][1024], results[2][1024];
    const char *names[2] = {"chunked", "stopped"};
    int i;
    if (argc != 6) {
        fprintf(stderr, "usage: %s CASE MESH_DIR OUTPUT_DIR CHUNK RESULTS_NAME\n", argv[0]);
        return 2;
    }
    for (i = 0; i < 2; i++) {
        snprintf(folder[i], sizeof folder[i], "%s/%s", argv[3], names[i]);
        snprintf(results[i], sizeof results[i], "%s/%s", folder[i], argv[5]);
        mkdir(folder[i], 0777);
        remove(results[i]);
    }
    advance(argv[1], argv[2], folder[0], atof(argv[4]), 1.0, results[0]);
    advance(argv[1], argv[2], folder[1], atof(argv[4]), 0.5, results[1]);
    /* without an output folder nothing is written (here: not in the current folder) */
    remove(argv[5]);
    advance(argv[1], argv[2], NULL, atof(argv[4]), 1.0, argv[5]);
    CHECK(!exists(argv[5]));
    if (failures > 0) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    fprintf(stderr, "test_capi_record: all checks passed\n");
    return 0;
}
