/* Bad calls of every entry point of include/ffrf.h: NULL handles and pointers, bad body, marker
 * and joint indices, calls out of order, a missing and a bad case file, buffers too small.
 * Each asserts the status and the message. Nothing here computes modes, so the test also runs
 * under AddressSanitizer and valgrind in seconds.
 * Usage: test_capi_bad_calls MODAL_CASE MECHANISM_CASE MESH_DIR WORK_DIR */
#include "check.h"

int main(int argc, char **argv)
{
    ffrf_case *modal = NULL, *mechanism = NULL, *missing = NULL, *bad = NULL;
    char name[64], small[4], path[1024];
    double hz[4], q[8], v[8], r[3], f6[6], m6[6], t, t_end, angle, speed, mass, center[3],
        inertia[9], force[3] = {0.0, 0.0, 0.0};
    size_t count_size;
    int n, count, nodes, modes, interfaces, major = -1, minor = -1, patch = -1;
    FILE *file;

    if (argc != 5) {
        fprintf(stderr, "usage: %s MODAL_CASE MECHANISM_CASE MESH_DIR WORK_DIR\n", argv[0]);
        return 2;
    }

    /* version: any pointer may be NULL */
    ffrf_version(&major, &minor, &patch);
    CHECK(major == FFRF_VERSION_MAJOR && minor == FFRF_VERSION_MINOR &&
          patch == FFRF_VERSION_PATCH);
    ffrf_version(NULL, NULL, NULL);

    /* NULL handle: every call FFRF_BAD_CALL, the fixed message, close(NULL) harmless */
    CHECK(strstr(ffrf_last_error(NULL), "NULL case handle") != NULL);
    EXPECT(NULL, ffrf_case_run(NULL), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_count(NULL, &n), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_case_set_communicator(NULL, 0), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_name(NULL, 0, name, sizeof name), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_frequencies(NULL, 0, hz, 4, &count), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_mechanism_advance(NULL, 1.0e-3), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_crank_state(NULL, &angle, &speed), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_sizes(NULL, 0, &nodes, &modes, &interfaces), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_nodes(NULL, 0, NULL, 0, &count_size), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_mode_shapes(NULL, 0, NULL, 0, &count_size), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_virtual_node_shapes(NULL, 0, NULL, 0, &count_size), FFRF_BAD_CALL,
           "NULL");
    EXPECT(NULL, ffrf_body_mass_properties(NULL, 0, &mass, center, inertia), FFRF_BAD_CALL,
           "NULL");
    EXPECT(NULL, ffrf_mechanism_time(NULL, &t, &t_end), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_body_state(NULL, 0, q, v, 8, &count), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_marker_count(NULL, 0, &n), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_marker_state(NULL, 0, 0, r, r, r), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_joint_count(NULL, &n), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_joint_name(NULL, 0, name, sizeof name), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_joint_reaction(NULL, 0, f6, m6), FFRF_BAD_CALL, "NULL");
    EXPECT(NULL, ffrf_marker_set_load(NULL, 0, 0, force, force), FFRF_BAD_CALL, "NULL");
    ffrf_case_close(NULL);
    CHECK(ffrf_case_open(argv[1], NULL, NULL, NULL) == FFRF_BAD_CALL);

    /* a NULL case file and a missing one: a handle that carries the message */
    EXPECT(missing, ffrf_case_open(NULL, NULL, NULL, &missing), FFRF_BAD_CALL,
           "case_file is NULL");
    CHECK(missing != NULL);
    ffrf_case_close(missing);
    missing = NULL;
    EXPECT(missing, ffrf_case_open("no/such/case.nml", NULL, NULL, &missing), FFRF_FILE_ERROR,
           "case file \"no/such/case.nml\" does not exist");
    CHECK(missing != NULL);
    /* calls on a case that did not open */
    EXPECT(missing, ffrf_body_count(missing, &n), FFRF_BAD_CALL, "the case is not open");
    EXPECT(missing, ffrf_case_run(missing), FFRF_BAD_CALL, "the case is not open");
    EXPECT(missing, ffrf_mechanism_advance(missing, 1.0e-3), FFRF_BAD_CALL,
           "the case is not open");
    ffrf_case_close(missing);

    /* a bad case file: the reader's message (key misspelt) */
    snprintf(path, sizeof path, "%s/capi_bad_case.nml", argv[4]);
    file = fopen(path, "w");
    CHECK(file != NULL);
    if (file == NULL)
        return 1;
    fputs("&run title = 'bad' /\n&body name = 'crank', mesh_filez = 'crank.msh' /\n", file);
    fclose(file);
    EXPECT(bad, ffrf_case_open(path, argv[3], NULL, &bad), FFRF_INPUT_ERROR, "mesh_filez");
    ffrf_case_close(bad);

    /* the modal case: open, then out-of-order calls and bad indices (nothing computed) */
    EXPECT(modal, ffrf_case_open(argv[1], argv[3], NULL, &modal), FFRF_OK, "");
    EXPECT(modal, ffrf_body_count(modal, &n), FFRF_OK, "");
    CHECK(n == 1);
    EXPECT(modal, ffrf_body_count(modal, NULL), FFRF_BAD_CALL, "n is NULL");
    EXPECT(modal, ffrf_body_name(modal, 0, name, sizeof name), FFRF_OK, "");
    CHECK(strcmp(name, "crank") == 0);
    EXPECT(modal, ffrf_body_name(modal, 0, small, sizeof small), FFRF_BAD_CALL,
           "the buffer has 4 bytes; \"crank\" needs 6 with its NUL");
    CHECK(strcmp(small, "cra") == 0);
    EXPECT(modal, ffrf_body_name(modal, 0, small, 0), FFRF_BAD_CALL, "length 0");
    EXPECT(modal, ffrf_body_name(modal, 0, NULL, 8), FFRF_BAD_CALL, "the buffer is NULL");
    EXPECT(modal, ffrf_body_name(modal, 1, name, sizeof name), FFRF_BAD_CALL,
           "body 1 does not exist; the case has 1 bodies, 0..0");
    EXPECT(modal, ffrf_body_name(modal, -1, name, sizeof name), FFRF_BAD_CALL,
           "body -1 does not exist");
    EXPECT(modal, ffrf_body_frequencies(modal, 0, hz, 4, &count), FFRF_BAD_CALL,
           "no modes yet; call ffrf_case_run first");
    EXPECT(modal, ffrf_body_frequencies(modal, 0, hz, 4, NULL), FFRF_BAD_CALL,
           "count is NULL");
    EXPECT(modal, ffrf_body_frequencies(modal, 0, hz, -1, &count), FFRF_BAD_CALL,
           "capacity -1 is negative");
    EXPECT(modal, ffrf_body_frequencies(modal, 3, hz, 4, &count), FFRF_BAD_CALL,
           "body 3 does not exist");
    EXPECT(modal, ffrf_body_sizes(modal, 0, &nodes, &modes, &interfaces), FFRF_BAD_CALL,
           "no modes yet");
    EXPECT(modal, ffrf_body_mode_shapes(modal, 0, NULL, 0, &count_size), FFRF_BAD_CALL,
           "no modes yet");
    EXPECT(modal, ffrf_body_mass_properties(modal, 0, &mass, center, NULL), FFRF_BAD_CALL,
           "is NULL");
    EXPECT(modal, ffrf_mechanism_advance(modal, 1.0e-3), FFRF_BAD_CALL,
           "is a modal case (no &joint groups); only a mechanism case moves");
    EXPECT(modal, ffrf_crank_state(modal, &angle, &speed), FFRF_BAD_CALL, "is a modal case");
    EXPECT(modal, ffrf_crank_state(modal, NULL, &speed), FFRF_BAD_CALL, "is NULL");
    EXPECT(modal, ffrf_joint_count(modal, &n), FFRF_BAD_CALL, "is a modal case");
    EXPECT(modal, ffrf_body_state(modal, 0, q, v, 8, &count), FFRF_BAD_CALL,
           "is a modal case");
    EXPECT(modal, ffrf_body_set_pose(modal, 0, NULL, NULL, NULL, NULL), FFRF_BAD_CALL,
           "body_set_pose: \"");
    EXPECT(modal, ffrf_body_set_pose(modal, 0, NULL, NULL, NULL, NULL), FFRF_BAD_CALL,
           "is a modal case (no &joint groups); only a mechanism case moves");
    /* a successful call clears the message */
    EXPECT(modal, ffrf_body_count(modal, &n), FFRF_OK, "");
    ffrf_case_close(modal);

    /* the mechanism case: state queries before the first advance, a time beyond t_end */
    EXPECT(mechanism, ffrf_case_open(argv[2], argv[3], NULL, &mechanism), FFRF_OK, "");
    EXPECT(mechanism, ffrf_crank_state(mechanism, &angle, &speed), FFRF_BAD_CALL,
           "the mechanism is not prepared yet; call ffrf_mechanism_advance first");
    EXPECT(mechanism, ffrf_mechanism_time(mechanism, &t, &t_end), FFRF_BAD_CALL,
           "not prepared");
    EXPECT(mechanism, ffrf_marker_count(mechanism, 0, &n), FFRF_BAD_CALL, "not prepared");
    EXPECT(mechanism, ffrf_marker_state(mechanism, 0, 0, r, NULL, NULL), FFRF_BAD_CALL,
           "not prepared");
    EXPECT(mechanism, ffrf_joint_name(mechanism, 0, name, sizeof name), FFRF_BAD_CALL,
           "not prepared");
    EXPECT(mechanism, ffrf_joint_reaction(mechanism, 0, f6, m6), FFRF_BAD_CALL,
           "not prepared");
    EXPECT(mechanism, ffrf_marker_set_load(mechanism, 0, 0, force, NULL), FFRF_BAD_CALL,
           "not prepared");
    EXPECT(mechanism, ffrf_mechanism_advance(mechanism, 1.0e3), FFRF_INPUT_ERROR,
           "advance to t = 1000 s, beyond the case's t_end");
    ffrf_case_close(mechanism);

    /* a case from arrays: bad arguments and order (nothing computed) */
    {
        ffrf_case *arrays = NULL;
        const double xyz[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1};
        const int tet[4] = {0, 1, 2, 3}, bad_tet[4] = {0, 1, 2, 4}, tri[3] = {0, 1, 2};
        CHECK(ffrf_case_new(NULL) == FFRF_BAD_CALL);
        EXPECT(arrays, ffrf_case_new(&arrays), FFRF_OK, "");
        EXPECT(arrays, ffrf_case_run(arrays), FFRF_BAD_CALL, "the case has no bodies");
        EXPECT(arrays, ffrf_case_add_body(arrays, "block", 4, xyz, 5, 1, tet, 2e11, 0.3, 7850),
               FFRF_BAD_CALL, "4 or 10 nodes per tetrahedron");
        EXPECT(arrays, ffrf_case_add_body(arrays, "block", 4, NULL, 4, 1, tet, 2e11, 0.3, 7850),
               FFRF_BAD_CALL, "name, xyz or tets is NULL");
        EXPECT(arrays, ffrf_case_add_body(arrays, "block", 4, xyz, 4, 1, bad_tet, 2e11, 0.3,
               7850), FFRF_INPUT_ERROR, "must lie in 0..3 (C, 0-based); found 0..4");
        EXPECT(arrays, ffrf_case_add_surface(arrays, 0, "face", 3, 1, tri), FFRF_BAD_CALL,
               "body 0 does not exist; the case has 0 bodies");
        EXPECT(arrays, ffrf_case_add_body(arrays, "block", 4, xyz, 4, 1, tet, 2e11, 0.3, 7850),
               FFRF_OK, "");
        EXPECT(arrays, ffrf_case_add_body(arrays, "block", 4, xyz, 4, 1, tet, 2e11, 0.3, 7850),
               FFRF_BAD_CALL, "a body \"block\" exists already");
        EXPECT(arrays, ffrf_case_add_interface(arrays, 0, "face", FFRF_RBE3, NULL, NULL),
               FFRF_BAD_CALL, "has no surface \"face\"; add it with add_surface first");
        EXPECT(arrays, ffrf_case_add_surface(arrays, 0, "face", 4, 1, tri), FFRF_BAD_CALL,
               "give at least one triangle of 3 or 6 nodes");
        EXPECT(arrays, ffrf_case_add_surface(arrays, 0, "face", 3, 1, tri), FFRF_OK, "");
        EXPECT(arrays, ffrf_case_add_interface(arrays, 0, "face", 7, NULL, NULL), FFRF_BAD_CALL,
               "mpc = 7; give FFRF_RBE2 (1), FFRF_RBE3 (2), FFRF_RBE3_AREA (3) or "
               "FFRF_RBE3_AREA_CONSISTENT (4)");
        EXPECT(arrays, ffrf_case_add_interface(arrays, 0, "face", FFRF_RBE3, NULL, NULL),
               FFRF_OK, "");
        /* interfaces on node sets with per-node weights */
        {
            const int set[3] = {0, 1, 3}, twice[3] = {0, 1, 0}, outside[2] = {0, 4};
            const double w[3] = {1.0, 2.0, 0.5}, zero_w[3] = {1.0, 0.0, 1.0},
                         negative_w[3] = {1.0, 1.0, -1.0};
            const double xyz5[15] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 2, 2, 2};
            CHECK(ffrf_case_add_interface_nodes(NULL, 0, "set", FFRF_RBE3, 3, set, w, NULL,
                                                NULL) == FFRF_BAD_CALL);
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, NULL, FFRF_RBE3, 3, set, w,
                   NULL, NULL), FFRF_BAD_CALL, "name or nodes is NULL");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 3, NULL, w,
                   NULL, NULL), FFRF_BAD_CALL, "name or nodes is NULL");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 0, set, w,
                   NULL, NULL), FFRF_BAD_CALL, "num_nodes = 0; give at least one node");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, -2, set,
                   NULL, NULL, NULL), FFRF_BAD_CALL, "num_nodes = -2");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 1, "set", FFRF_RBE3, 3, set, w,
                   NULL, NULL), FFRF_BAD_CALL, "body 1 does not exist");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3_AREA, 3, set,
                   NULL, NULL, NULL), FFRF_BAD_CALL,
                   "mpc = 3; give FFRF_RBE2 (1) or FFRF_RBE3 (2); RBE3 weights come with the "
                   "nodes");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "face", FFRF_RBE3, 3, set, w,
                   NULL, NULL), FFRF_BAD_CALL,
                   "body \"block\" has an interface or a surface of that name already");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE2, 3, set, w,
                   NULL, NULL), FFRF_BAD_CALL, "weights are for an RBE3 (mpc = FFRF_RBE3)");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 2, outside,
                   NULL, NULL, NULL), FFRF_INPUT_ERROR,
                   "node 4 (position 1) is not in 0..3 (C, 0-based)");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 3, twice,
                   NULL, NULL, NULL), FFRF_INPUT_ERROR,
                   "node 0 (C, 0-based) is listed twice, at positions 0 and 2");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 3, set,
                   zero_w, NULL, NULL), FFRF_INPUT_ERROR,
                   "weight 1 (C, 0-based) is 0; RBE3 weights must be positive and finite");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 3, set,
                   negative_w, NULL, NULL), FFRF_INPUT_ERROR, "weight 2 (C, 0-based) is -1");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 3, set, w,
                   NULL, NULL), FFRF_OK, "");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 0, "set", FFRF_RBE3, 3, set, w,
                   NULL, NULL), FFRF_BAD_CALL, "has an interface or a surface of that name");
            /* a body whose node 4 belongs to no tetrahedron */
            EXPECT(arrays, ffrf_case_add_body(arrays, "loose", 5, xyz5, 4, 1, tet, 2e11, 0.3,
                   7850), FFRF_OK, "");
            EXPECT(arrays, ffrf_case_add_interface_nodes(arrays, 1, "set", FFRF_RBE3, 2, outside,
                   NULL, NULL, NULL), FFRF_INPUT_ERROR,
                   "node 4 (C, 0-based) is not a node of any tetrahedron");
        }
        EXPECT(arrays, ffrf_case_set_num_modes(arrays, 0), FFRF_BAD_CALL,
               "num_modes = 0, must be at least 1");
        EXPECT(arrays, ffrf_body_frequencies(arrays, 0, hz, 4, &count), FFRF_BAD_CALL,
               "no modes yet");
        /* the sequential build has no MPI: a communicator is refused with the remedy */
        EXPECT(arrays, ffrf_case_set_communicator(arrays, 0), FFRF_INPUT_ERROR,
               "an MPI host code needs the MPI build: configure with -DFFRF_MPI=ON");
        ffrf_case_close(arrays);
        EXPECT(modal, ffrf_case_open(argv[1], argv[3], NULL, &modal), FFRF_OK, "");
        EXPECT(modal, ffrf_case_add_body(modal, "block", 4, xyz, 4, 1, tet, 2e11, 0.3, 7850),
               FFRF_BAD_CALL, "only for a case made by ffrf_case_new");
        ffrf_case_close(modal);
    }

    if (failures > 0) {
        fprintf(stderr, "%d failure(s)\n", failures);
        return 1;
    }
    printf("test_capi_bad_calls: all checks passed\n");
    return 0;
}
