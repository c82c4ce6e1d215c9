/* c_modal: runs a modal case through the installed ffrf C API and prints every body's natural
 * frequencies, one line per mode: "<body> <mode> <frequency in Hz, %.17g>".
 *
 *   c_modal CASE.nml [MESH_DIR]
 *
 * Nothing is written to disk (output_dir NULL). Exit status: 0, or the ffrf status code of the
 * call that failed (its message on stderr). Build: see the Makefile (pkg-config ffrf). */
#include <stdio.h>
#include <stdlib.h>

#include <ffrf.h>

/* Prints the failed call, its status and the handle's message; returns the status. */
static int failed(const char *call, int status, const ffrf_case *c)
{
    fprintf(stderr, "c_modal: %s: status %d: %s\n", call, status,
            c != NULL ? ffrf_last_error(c) : "(no handle)");
    return status;
}

/* Prints the frequencies of body b (0-based). */
static int print_body(const ffrf_case *c, int b)
{
    char name[256];
    int count = 0, status;
    double *hz;

    status = ffrf_body_name(c, b, name, sizeof name);
    if (status != FFRF_OK) return failed("ffrf_body_name", status, c);
    /* a NULL array with capacity 0 asks for the size */
    status = ffrf_body_frequencies(c, b, NULL, 0, &count);
    if (status != FFRF_OK) return failed("ffrf_body_frequencies", status, c);
    hz = malloc((count > 0 ? (size_t)count : 1) * sizeof *hz);
    if (hz == NULL) {
        fprintf(stderr, "c_modal: out of memory\n");
        return EXIT_FAILURE;
    }
    status = ffrf_body_frequencies(c, b, hz, count, &count);
    if (status != FFRF_OK) {
        free(hz);
        return failed("ffrf_body_frequencies", status, c);
    }
    for (int i = 0; i < count; ++i) printf("%s %d %.17g\n", name, i + 1, hz[i]);
    free(hz);
    return FFRF_OK;
}

int main(int argc, char **argv)
{
    ffrf_case *c = NULL;
    int major, minor, patch, n = 0, status;

    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: c_modal CASE.nml [MESH_DIR]\n");
        return EXIT_FAILURE;
    }
    ffrf_version(&major, &minor, &patch);
    printf("# ffrf %d.%d.%d, case %s\n", major, minor, patch, argv[1]);

    status = ffrf_case_open(argv[1], argc == 3 ? argv[2] : NULL, NULL, &c);
    if (status != FFRF_OK) status = failed("ffrf_case_open", status, c);
    if (status == FFRF_OK) {
        status = ffrf_case_run(c);
        if (status != FFRF_OK) status = failed("ffrf_case_run", status, c);
    }
    if (status == FFRF_OK) {
        status = ffrf_body_count(c, &n);
        if (status != FFRF_OK) status = failed("ffrf_body_count", status, c);
    }
    for (int b = 0; status == FFRF_OK && b < n; ++b) status = print_body(c, b);
    ffrf_case_close(c);
    return status;
}
