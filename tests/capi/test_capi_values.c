/* Every value-returning entry point of include/ffrf.h, dumped on every path that produces it,
 * for compare_values.py, which checks each value against the ffrf driver's results file (or an
 * independent recomputation where the file does not hold it).
 *
 * Paths (one file OUT_DIR/<path>.txt each; a path with an output folder writes its results
 * under OUT_DIR/<path>/):
 *   modal_quiet    modal case, ffrf_case_run without an output folder
 *   modal_output   modal case, ffrf_case_run with an output folder
 *   chunks_quiet   mechanism case advanced from t_start to t_end in chunks of CHUNK seconds,
 *                  no output folder: body data after the first advance (t_start, prepare
 *                  only), the state after it and after every chunk
 *   chunks_output  the same with an output folder
 *   run_quiet      mechanism case run to t_end by one ffrf_case_run, no output folder: body
 *                  data and the state at t_end
 *   run_output     the same with an output folder: body data, time and crank state at t_end;
 *                  the other state queries are FFRF_BAD_CALL there (docs/api.md), dumped with
 *                  their status so that the comparison asserts it
 *   arrays_modal   the modal case's body built from arrays (the driver's mesh and interface
 *                  node sets, ARRAYS_FILE), ffrf_case_run: body data
 *
 * Line format ("%.17g": every double exactly; status = the call's return value, values only
 * when it is FFRF_OK):
 *   version : major minor patch                        (once per path)
 *   body_count <status> : n
 *   body_name <b> <status> : name
 *   body_sizes <b> <status> : num_nodes num_modes num_interfaces
 *   body_frequencies|body_nodes|body_mode_shapes|body_virtual_node_shapes <b> <status> : values
 *   body_mass_properties <b> <status> : mass center(3) inertia(9)
 *   body_invariant <b> <name> <status> : values
 *   mechanism_time <k> <status> : t t_end              (k: state number, 0 = first dump)
 *   crank_state <k> <status> : angle speed
 *   body_state <k> <b> <status> : q(count) v(count)
 *   marker_count <k> <b> <status> : n
 *   marker_state <k> <b> <m> <status> : position(3) velocity(3) angular_velocity(3)
 *   joint_count <k> <status> : n
 *   joint_name <k> <j> <status> : name
 *   joint_reaction <k> <j> <status> : force(6) moment(6)    (column-major 3 x 2, as returned)
 * Every call is also checked here for the status and message pattern of docs/api.md (a
 * successful call leaves ffrf_last_error ""), and a size query (NULL array, capacity 0) must
 * report the size the filled array has.
 * Usage: test_capi_values MODAL_CASE MECHANISM_CASE MESH_DIR OUT_DIR CHUNK_SECONDS ARRAYS_FILE */
#include <sys/stat.h>

#include "check.h"

static const char *const invariant_names[] = {
    "mass", "center_of_mass", "theta_u", "M_PhitPsi", "M_PhitPsit", "M_xPsi",
    "M_xPsit", "M_PsitPsi", "M_PsitPsit", "M_PsiPsi", "K_ff"};

/* Values on the current line. */
static void put_values(FILE *out, const double *values, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++)
        fprintf(out, " %.17g", values[i]);
}

/* Values, then the end of the line. */
static void print_values(FILE *out, const double *values, size_t n)
{
    put_values(out, values, n);
    fputc('\n', out);
}

/* A status line: "<head> <status> :", the values follow on the same line. */
static void head(FILE *out, const char *text, int status)
{
    fprintf(out, "%s %d :", text, status);
}

/* The status of a call and its message: "" exactly when it succeeded. */
static int checked(const ffrf_case *c, int status, int line)
{
    const char *message = ffrf_last_error(c);
    if ((status == FFRF_OK) != (message[0] == '\0')) {
        fprintf(stderr, "FAIL line %d: status %d with message \"%s\"\n", line, status, message);
        failures++;
    }
    return status;
}
#define CHECKED(c, call) checked((c), (call), __LINE__)

typedef int (*array_getter)(const ffrf_case *, int, double *, size_t, size_t *);

/* An array of a body: size query, then the values. */
static void dump_array(FILE *out, const ffrf_case *c, const char *name, int b, array_getter get)
{
    size_t count = 0, count2 = 0;
    double *values;
    char text[96];
    int status;
    snprintf(text, sizeof text, "%s %d", name, b);
    status = CHECKED(c, get(c, b, NULL, 0, &count));
    if (status != FFRF_OK) {
        head(out, text, status);
        fputc('\n', out);
        return;
    }
    values = malloc((count > 0 ? count : 1) * sizeof *values);
    status = CHECKED(c, get(c, b, values, count, &count2));
    CHECK(count2 == count);
    head(out, text, status);
    print_values(out, values, status == FFRF_OK ? count : 0);
    free(values);
}

/* The body data of every body (after the modes). */
static void dump_bodies(FILE *out, ffrf_case *c)
{
    int n = 0, b, i, status, count, count2, sizes[3] = {0, 0, 0};
    double hz[256], mass, center[3], inertia[9], *values;
    size_t n_values, n_values2;
    char name[128], text[160];
    status = CHECKED(c, ffrf_body_count(c, &n));
    head(out, "body_count", status);
    fprintf(out, " %d\n", n);
    for (b = 0; b < n; b++) {
        snprintf(text, sizeof text, "body_name %d", b);
        status = CHECKED(c, ffrf_body_name(c, b, name, sizeof name));
        head(out, text, status);
        fprintf(out, " %s\n", status == FFRF_OK ? name : "");
        snprintf(text, sizeof text, "body_sizes %d", b);
        status = CHECKED(c, ffrf_body_sizes(c, b, &sizes[0], &sizes[1], &sizes[2]));
        head(out, text, status);
        fprintf(out, " %d %d %d\n", sizes[0], sizes[1], sizes[2]);
        snprintf(text, sizeof text, "body_frequencies %d", b);
        status = CHECKED(c, ffrf_body_frequencies(c, b, NULL, 0, &count));
        if (status == FFRF_OK) {
            CHECK(count <= 256);
            status = CHECKED(c, ffrf_body_frequencies(c, b, hz, 256, &count2));
            CHECK(count2 == count);
        }
        head(out, text, status);
        print_values(out, hz, status == FFRF_OK ? (size_t)count : 0);
        dump_array(out, c, "body_nodes", b, ffrf_body_nodes);
        dump_array(out, c, "body_mode_shapes", b, ffrf_body_mode_shapes);
        dump_array(out, c, "body_virtual_node_shapes", b, ffrf_body_virtual_node_shapes);
        snprintf(text, sizeof text, "body_mass_properties %d", b);
        status = CHECKED(c, ffrf_body_mass_properties(c, b, &mass, center, inertia));
        head(out, text, status);
        if (status == FFRF_OK) {
            put_values(out, &mass, 1);
            put_values(out, center, 3);
            print_values(out, inertia, 9);
        } else {
            fputc('\n', out);
        }
        for (i = 0; i < (int)(sizeof invariant_names / sizeof *invariant_names); i++) {
            snprintf(text, sizeof text, "body_invariant %d %s", b, invariant_names[i]);
            status = CHECKED(c, ffrf_body_invariant(c, b, invariant_names[i], NULL, 0,
                                                    &n_values));
            if (status != FFRF_OK) {
                head(out, text, status);
                fputc('\n', out);
                continue;
            }
            values = malloc((n_values > 0 ? n_values : 1) * sizeof *values);
            status = CHECKED(c, ffrf_body_invariant(c, b, invariant_names[i], values, n_values,
                                                    &n_values2));
            CHECK(n_values2 == n_values);
            head(out, text, status);
            print_values(out, values, status == FFRF_OK ? n_values : 0);
            free(values);
        }
    }
}

/* The mechanism state (state number k). */
static void dump_state(FILE *out, const ffrf_case *c, int k)
{
    double t = 0.0, t_end = 0.0, values[2], q[128], v[128], r[9], f[6], m[6];
    int status, n = 0, b, markers, i, j, joints = 0, count = 0, count2 = 0;
    char text[160], name[128];
    snprintf(text, sizeof text, "mechanism_time %d", k);
    status = CHECKED(c, ffrf_mechanism_time(c, &t, &t_end));
    head(out, text, status);
    fprintf(out, " %.17g %.17g\n", t, t_end);
    snprintf(text, sizeof text, "crank_state %d", k);
    status = CHECKED(c, ffrf_crank_state(c, &values[0], &values[1]));
    head(out, text, status);
    print_values(out, values, status == FFRF_OK ? 2 : 0);
    CHECK(ffrf_body_count(c, &n) == FFRF_OK);
    for (b = 0; b < n; b++) {
        snprintf(text, sizeof text, "body_state %d %d", k, b);
        status = CHECKED(c, ffrf_body_state(c, b, NULL, NULL, 0, &count));
        if (status == FFRF_OK) {
            CHECK(count <= 128);
            status = CHECKED(c, ffrf_body_state(c, b, q, v, 128, &count2));
            CHECK(count2 == count);
        }
        head(out, text, status);
        if (status == FFRF_OK) {
            put_values(out, q, (size_t)count);
            print_values(out, v, (size_t)count);
        } else {
            fputc('\n', out);
        }
        snprintf(text, sizeof text, "marker_count %d %d", k, b);
        markers = 0;
        status = CHECKED(c, ffrf_marker_count(c, b, &markers));
        head(out, text, status);
        fprintf(out, " %d\n", markers);
        /* no markers to count (after a recorded run): marker 0 is asked all the same */
        for (i = 0; i < (status == FFRF_OK ? markers : 1); i++) {
            snprintf(text, sizeof text, "marker_state %d %d %d", k, b, i);
            status = CHECKED(c, ffrf_marker_state(c, b, i, r, r + 3, r + 6));
            head(out, text, status);
            print_values(out, r, status == FFRF_OK ? 9 : 0);
        }
    }
    snprintf(text, sizeof text, "joint_count %d", k);
    status = CHECKED(c, ffrf_joint_count(c, &joints));
    head(out, text, status);
    fprintf(out, " %d\n", joints);
    /* no joints to count (after a recorded run): joint 0 is asked all the same */
    for (j = 0; j < (status == FFRF_OK ? joints : 1); j++) {
        snprintf(text, sizeof text, "joint_name %d %d", k, j);
        status = CHECKED(c, ffrf_joint_name(c, j, name, sizeof name));
        head(out, text, status);
        fprintf(out, " %s\n", status == FFRF_OK ? name : "");
        snprintf(text, sizeof text, "joint_reaction %d %d", k, j);
        status = CHECKED(c, ffrf_joint_reaction(c, j, f, m));
        head(out, text, status);
        if (status == FFRF_OK)
            put_values(out, f, 6);
        print_values(out, m, status == FFRF_OK ? 6 : 0);
    }
}

static FILE *open_dump(const char *out_dir, const char *path, char *folder, size_t len)
{
    char file[1024];
    FILE *out;
    snprintf(folder, len, "%s/%s", out_dir, path);
    mkdir(folder, 0777);
    snprintf(file, sizeof file, "%s/%s.txt", out_dir, path);
    out = fopen(file, "w");
    if (out == NULL) {
        fprintf(stderr, "cannot write %s\n", file);
        exit(2);
    }
    {
        int major = -1, minor = -1, patch = -1;
        ffrf_version(&major, &minor, &patch);
        fprintf(out, "version : %d %d %d\n", major, minor, patch);
        CHECK(major == FFRF_VERSION_MAJOR && minor == FFRF_VERSION_MINOR &&
              patch == FFRF_VERSION_PATCH);
    }
    return out;
}

/* (a), (b): a modal case run with or without an output folder. */
static void modal_path(const char *case_file, const char *mesh_dir, const char *out_dir,
                       const char *path, int with_output)
{
    ffrf_case *c = NULL;
    char folder[1024];
    FILE *out = open_dump(out_dir, path, folder, sizeof folder);
    EXPECT(c, ffrf_case_open(case_file, mesh_dir, with_output ? folder : NULL, &c), FFRF_OK,
           "");
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    dump_bodies(out, c);
    fclose(out);
    ffrf_case_close(c);
}

/* (f): a modal case built from arrays (ffrf_case_new, _add_body, _add_interface_nodes,
 * _set_num_modes) read from ARRAYS_FILE, which compare_values.py writes from the driver's
 * modal results: one body "<name> <num_nodes> <nodes_per_tet> <num_tets> <young> <poisson>
 * <density> <num_modes> <num_interfaces>", its 3 num_nodes coordinates, its tets (0-based),
 * then per interface "<name> <mpc> <num_nodes> <weighted> <virtual node (3)> <rc (6)>", its
 * nodes (0-based) and, when weighted, their weights. */
static void arrays_path(const char *arrays_file, const char *out_dir)
{
    ffrf_case *c = NULL;
    char folder[1024], name[128], interface[128];
    double young, poisson, density, *xyz, *weights, virtual_node[3];
    int num_nodes, nodes_per_tet, num_tets, num_modes, num_interfaces, *tets, *nodes, i, k;
    int mpc, count, weighted, rc[6];
    FILE *in = fopen(arrays_file, "r"), *out;
    if (in == NULL || fscanf(in, "%127s %d %d %d %lf %lf %lf %d %d", name, &num_nodes,
                             &nodes_per_tet, &num_tets, &young, &poisson, &density, &num_modes,
                             &num_interfaces) != 9) {
        fprintf(stderr, "cannot read %s\n", arrays_file);
        exit(2);
    }
    xyz = malloc((size_t)3 * num_nodes * sizeof *xyz);
    tets = malloc((size_t)nodes_per_tet * num_tets * sizeof *tets);
    for (i = 0; i < 3 * num_nodes; i++)
        CHECK(fscanf(in, "%lf", &xyz[i]) == 1);
    for (i = 0; i < nodes_per_tet * num_tets; i++)
        CHECK(fscanf(in, "%d", &tets[i]) == 1);
    EXPECT(c, ffrf_case_new(&c), FFRF_OK, "");
    EXPECT(c, ffrf_case_add_body(c, name, num_nodes, xyz, nodes_per_tet, num_tets, tets, young,
                                 poisson, density), FFRF_OK, "");
    for (k = 0; k < num_interfaces; k++) {
        CHECK(fscanf(in, "%127s %d %d %d %lf %lf %lf %d %d %d %d %d %d", interface, &mpc,
                     &count, &weighted, &virtual_node[0], &virtual_node[1], &virtual_node[2],
                     &rc[0], &rc[1], &rc[2], &rc[3], &rc[4], &rc[5]) == 13);
        nodes = malloc((size_t)count * sizeof *nodes);
        weights = malloc((size_t)count * sizeof *weights);
        for (i = 0; i < count; i++)
            CHECK(fscanf(in, "%d", &nodes[i]) == 1);
        for (i = 0; i < (weighted ? count : 0); i++)
            CHECK(fscanf(in, "%lf", &weights[i]) == 1);
        EXPECT(c, ffrf_case_add_interface_nodes(c, 0, interface, mpc, count, nodes,
                                                weighted ? weights : NULL, virtual_node, rc),
               FFRF_OK, "");
        free(nodes);
        free(weights);
    }
    fclose(in);
    EXPECT(c, ffrf_case_set_num_modes(c, num_modes), FFRF_OK, "");
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    out = open_dump(out_dir, "arrays_modal", folder, sizeof folder);
    dump_bodies(out, c);
    fclose(out);
    ffrf_case_close(c);
    free(xyz);
    free(tets);
}

/* (c), (d): a mechanism advanced in chunks, with or without an output folder. */
static void chunks_path(const char *case_file, const char *mesh_dir, const char *out_dir,
                        const char *path, int with_output, double chunk)
{
    ffrf_case *c = NULL;
    char folder[1024];
    double t = 0.0, t_end = 0.0, target, zero[3] = {0.0, 0.0, 0.0};
    int k, chunks;
    FILE *out = open_dump(out_dir, path, folder, sizeof folder);
    EXPECT(c, ffrf_case_open(case_file, mesh_dir, with_output ? folder : NULL, &c), FFRF_OK,
           "");
    EXPECT(c, ffrf_mechanism_advance(c, 0.0), FFRF_OK, "");
    EXPECT(c, ffrf_mechanism_time(c, &t, &t_end), FFRF_OK, "");
    /* a zero host load at the first marker of body 0 changes nothing: the driver's rows must
     * still be matched (ffrf_marker_set_load returns no value; this is its check) */
    EXPECT(c, ffrf_marker_set_load(c, 0, 0, zero, zero), FFRF_OK, "");
    dump_bodies(out, c);
    dump_state(out, c, 0);
    chunks = (int)(t_end / chunk + 0.5);
    for (k = 1; k <= chunks; k++) {
        target = k == chunks ? t_end : k * chunk;
        EXPECT(c, ffrf_mechanism_advance(c, target), FFRF_OK, "");
        dump_state(out, c, k);
    }
    fclose(out);
    ffrf_case_close(c);
}

/* (e): a mechanism run to t_end in one ffrf_case_run, with or without an output folder. */
static void run_path(const char *case_file, const char *mesh_dir, const char *out_dir,
                     const char *path, int with_output)
{
    ffrf_case *c = NULL;
    char folder[1024];
    FILE *out = open_dump(out_dir, path, folder, sizeof folder);
    EXPECT(c, ffrf_case_open(case_file, mesh_dir, with_output ? folder : NULL, &c), FFRF_OK,
           "");
    EXPECT(c, ffrf_case_run(c), FFRF_OK, "");
    dump_bodies(out, c);
    dump_state(out, c, 0);
    fclose(out);
    ffrf_case_close(c);
}

int main(int argc, char **argv)
{
    double chunk;
    if (argc != 7) {
        fprintf(stderr, "usage: %s MODAL_CASE MECHANISM_CASE MESH_DIR OUT_DIR CHUNK "
                "ARRAYS_FILE\n", argv[0]);
        return 2;
    }
    chunk = atof(argv[5]);
    modal_path(argv[1], argv[3], argv[4], "modal_quiet", 0);
    modal_path(argv[1], argv[3], argv[4], "modal_output", 1);
    chunks_path(argv[2], argv[3], argv[4], "chunks_quiet", 0, chunk);
    chunks_path(argv[2], argv[3], argv[4], "chunks_output", 1, chunk);
    run_path(argv[2], argv[3], argv[4], "run_quiet", 0);
    run_path(argv[2], argv[3], argv[4], "run_output", 1);
    arrays_path(argv[6], argv[4]);
    if (failures > 0) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    fprintf(stderr, "test_capi_values: all checks passed\n");
    return 0;
}
