/* The exports of a case through the C API (ffrf_case_set_export; issue 26, &run export).
 *
 * Usage: test_capi_export CASE MESH_DIR OUT_DIR
 * CASE is a modal case without &run export (xdmf_beam_tet4_plain.nml of tests/regression/
 * xdmf.cmake: the Tet4 beam, 4 modes, results <stem>.h5).
 *  - refusals: a NULL handle or formats (FFRF_BAD_CALL), an unknown word (FFRF_INPUT_ERROR
 *    listing the known words, the case left as it was: it then runs), a case built from arrays
 *    and a call after the run (FFRF_BAD_CALL);
 *  - "xdmf, XDMF" and "" accepted, then "XDMF" set (the last call counts), the case run with an output folder: OUT_DIR/<stem>.xdmf exists and names the
 *    results file, the Tet4 topology and mode 4; ctest capi_export_xdmf then reads it back with
 *    meshio (check_xdmf.py: every mode bitwise equal to the results file's).
 */
#include "check.h"

int main(int argc, char **argv)
{
    ffrf_case *c = NULL, *arrays = NULL;
    char path[4096], text[8192];
    size_t length;
    FILE *file;
    if (argc != 4) {
        fprintf(stderr, "usage: test_capi_export CASE MESH_DIR OUT_DIR\n");
        return 2;
    }
    EXPECT(NULL, ffrf_case_set_export(NULL, "xdmf"), FFRF_BAD_CALL, "NULL");
    EXPECT(c, ffrf_case_open(argv[1], argv[2], argv[3], &c), FFRF_OK, "");
    EXPECT(c, ffrf_case_set_export(c, NULL), FFRF_BAD_CALL,
           "ffrf_case_set_export: formats is NULL");
    EXPECT(c, ffrf_case_set_export(c, "xdmf bogus"), FFRF_INPUT_ERROR,
           "export = \"bogus\" is not an export format; use one of xdmf");
    EXPECT(c, ffrf_case_set_export(c, "'xdmf'"), FFRF_INPUT_ERROR, "holds a quote");
    /* commas, any case, a repeated word kept once; the last call is the one that counts */
    EXPECT(c, ffrf_case_set_export(c, "xdmf, XDMF"), FFRF_OK, "");
    EXPECT(c, ffrf_case_set_export(c, ""), FFRF_OK, "");
    EXPECT(c, ffrf_case_set_export(c, "XDMF"), FFRF_OK, "");
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    EXPECT(c, ffrf_case_set_export(c, "xdmf"), FFRF_BAD_CALL,
           "case_set_export: the case has run");
    ffrf_case_close(c);

    EXPECT(arrays, ffrf_case_new(&arrays), FFRF_OK, "");
    EXPECT(arrays, ffrf_case_set_export(arrays, "xdmf"), FFRF_BAD_CALL,
           "a case built from arrays writes no files");
    ffrf_case_close(arrays);

    snprintf(path, sizeof path, "%s/xdmf_beam_tet4_plain.xdmf", argv[3]);
    file = fopen(path, "r");
    CHECK(file != NULL);
    if (file != NULL) {
        length = fread(text, 1, sizeof text - 1, file);
        text[length] = '\0';
        fclose(file);
        CHECK(strstr(text, "<Xdmf Version=\"3.0\">") != NULL);
        CHECK(strstr(text, "TopologyType=\"Tetrahedron\"") != NULL);
        CHECK(strstr(text, "xdmf_beam_tet4_plain.h5:/xdmf/beam/mode_4") != NULL);
        CHECK(strstr(text, "mode_5") == NULL);
    }
    if (failures > 0) {
        fprintf(stderr, "test_capi_export: %d failure(s)\n", failures);
        return 1;
    }
    printf("test_capi_export: all checks passed\n");
    return 0;
}
