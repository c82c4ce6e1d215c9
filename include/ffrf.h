/* ffrf: flexible multibody (floating frame of reference) library, C API.
 *
 * C99. Every object is an opaque handle; the library keeps no global state, never aborts,
 * exits or prints, and installs no signal handlers. Every call returns a status (FFRF_OK = 0)
 * and keeps its message in the handle (ffrf_last_error). Reference: docs/api.md.
 *
 * Threads: distinct handles may be used from distinct threads, but computing modes and writing
 * results must be serialised by the host (ARPACK and a serial HDF5 are not reentrant).
 *
 * Indices are 0-based: body 0..n-1 in the order of the case's &body groups (the ground is not
 * a body here), marker 0..m-1, joint 0..j-1 in the order of the &joint groups, mode 0..k-1.
 * Arrays are column-major (Fortran order); lengths are counts of doubles.
 *
 * Buffers: a call that fills an array takes its capacity, writes at most that many values and
 * reports the full size in *count; with a NULL array and capacity 0 it only reports the size.
 * A capacity below the size is FFRF_BAD_CALL (the first `capacity` values are written).
 */
#ifndef FFRF_H
#define FFRF_H

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* Version of the library (also FFRF_VERSION_* of this header). */
#define FFRF_VERSION_MAJOR 0
#define FFRF_VERSION_MINOR 1
#define FFRF_VERSION_PATCH 0

/* A case: its input, the modes of its bodies and, for a mechanism case, its motion. */
typedef struct ffrf_case ffrf_case;

/* Status of every call. 2..5 are also the error codes of the library and the driver's exit codes. */
enum {
    FFRF_OK = 0,            /* success */
    FFRF_BAD_CALL = 1,      /* misuse: NULL handle or pointer, bad index, call out of order, buffer too small */
    FFRF_INPUT_ERROR = 2,   /* bad input: case file, mesh content, arrays, time beyond t_end */
    FFRF_FILE_ERROR = 3,    /* a file could not be opened, read or written */
    FFRF_NUMERIC_ERROR = 4, /* a numerical method failed (singular matrix, no convergence, NaN) */
    FFRF_INTERRUPTED = 5    /* stopped by a signal the host's own handlers recorded (ffrf installs none) */
};

/* ---------------------------------------------------------------- case */

/* Library version. Any pointer may be NULL. */
void ffrf_version(int *major, int *minor, int *patch);

/* Read and check the namelist case file. mesh_dir: folder of relative mesh files (NULL: the case
 * file's folder); output_dir: folder of the results (NULL: nothing is written).
 * On failure *c may hold a handle that carries the message: close it. */
int ffrf_case_open(const char *case_file, const char *mesh_dir, const char *output_dir,
                   ffrf_case **c);

/* Modal case: the modes of every body. Mechanism case: the modes, then the motion to t_end.
 * With an output_dir the results are written exactly as the ffrf driver writes them. Once. */
int ffrf_case_run(ffrf_case *c);

/* Number of bodies (&body groups). */
int ffrf_body_count(const ffrf_case *c, int *n);

/* Name of body `body` (0..n-1), NUL-terminated; len: size of buf including the NUL. */
int ffrf_body_name(const ffrf_case *c, int body, char *buf, size_t len);

/* Natural frequencies (Hz) of the body's modes, ascending (0 for a rigid body). Available after
 * ffrf_case_run, or after the first ffrf_mechanism_advance of a mechanism case. */
int ffrf_body_frequencies(const ffrf_case *c, int body, double *hz, int capacity, int *count);

/* Mechanism case: the starting pose of body `body`, as its &body keys (docs/mechanisms.md):
 * position (m) of the body frame, orientation: the rotation matrix A (body -> global, its
 * columns the body axes) by rows, 9 doubles A11 A12 A13 A21 ... A33 as the namelist gives it,
 * velocity (m/s) and angular_velocity (rad/s), global. NULL keeps the case's value (the file's,
 * or that of an earlier call). The case is read again with them as if given in the file, so
 * they are checked and the consistent start assembles them exactly as the namelist keys (the
 * log line of how far each body moved included). Before the first ffrf_mechanism_advance or
 * ffrf_case_run (FFRF_BAD_CALL after). A bad body index or a modal case: FFRF_BAD_CALL; a
 * value that is not finite, a rotation not orthonormal (largest |A A^T - I| > 1e-9) or with
 * det A = -1, a value out of the key's range: FFRF_INPUT_ERROR naming the body and the defect;
 * a refused call leaves the case as it was. */
int ffrf_body_set_pose(ffrf_case *c, int body, const double position[3],
                       const double orientation[9], const double velocity[3],
                       const double angular_velocity[3]);

/* The files written beside the results (&run export): formats, a blank-separated list of
 * export words, "xdmf" (<stem>.xdmf for ParaView, docs/results.md "XDMF export"); "" none.
 * Before ffrf_case_run or the first ffrf_mechanism_advance (FFRF_BAD_CALL after, and for a
 * case built from arrays); the case is read again with it as the override run.export, as the
 * driver's --set run.export=...: an unknown word is FFRF_INPUT_ERROR listing the known ones,
 * the case left as it was. Without an output_dir nothing is written. */
int ffrf_case_set_export(ffrf_case *c, const char *formats);

/* Mechanism case: the first call prepares (modes, mechanism, consistent start at t_start);
 * then integrates up to time t (current time <= t <= t_end; t = t_start on the first call only
 * prepares); call again to go on. Steps are the case's h; one shortened step lands on a t
 * between two steps, so with every t a multiple of h the states are the driver's, bitwise.
 * A t beyond t_end or before the current time: FFRF_INPUT_ERROR. */
int ffrf_mechanism_advance(ffrf_case *c, double t);

/* Crank angle (rad, unwrapped over revolutions) and speed (rad/s) of the current state. */
int ffrf_crank_state(const ffrf_case *c, double *angle_rad, double *speed_rad_s);

/* Message of the last call on c: "" when it succeeded. Owned by c, valid until the next call on
 * c or ffrf_case_close. Never NULL (a fixed text for c == NULL). */
const char *ffrf_last_error(const ffrf_case *c);

/* Release the case. NULL is allowed. */
void ffrf_case_close(ffrf_case *c);

/* ---------------------------------------------------------------- body data (after the modes) */

/* Sizes of a body: mesh nodes, modes, interfaces (virtual nodes). Rigid bodies without a mesh: 0. */
int ffrf_body_sizes(const ffrf_case *c, int body, int *num_nodes, int *num_modes,
                    int *num_interfaces);

/* Node coordinates (m), 3 x num_nodes: x0 y0 z0 x1 ... */
int ffrf_body_nodes(const ffrf_case *c, int body, double *xyz, size_t capacity, size_t *count);

/* Mass-normalised mode shapes, full field: (3 num_nodes) x num_modes, column-major (mode k is
 * the values k*3*num_nodes .. (k+1)*3*num_nodes-1: ux uy uz of node 0, node 1, ...). */
int ffrf_body_mode_shapes(const ffrf_case *c, int body, double *shape, size_t capacity,
                          size_t *count);

/* Virtual-node rows of the modes: (6 num_interfaces) x num_modes, column-major; per interface
 * [ux uy uz rx ry rz] in interface order (the markers of a flexible body). */
int ffrf_body_virtual_node_shapes(const ffrf_case *c, int body, double *rows, size_t capacity,
                                  size_t *count);

/* Mass (kg), centre of mass (m, body frame) and inertia tensor about it (kg m^2, 3 x 3) of a
 * meshed body, from the consistent mass matrix. */
int ffrf_body_mass_properties(const ffrf_case *c, int body, double *mass, double center[3],
                              double inertia[9]);

/* FFRF inertia invariants of a body's modes (docs/theory.md 3.2: exact Gram matrices of the
 * consistent mass matrix, what a host multibody code needs to build the reduced body itself),
 * by name, column-major, m = number of modes: "mass" (1, kg), "center_of_mass" (3, m),
 * "theta_u" (3 x 3, inertia about the body-frame origin, kg m^2), "M_PhitPsi" (3 x m),
 * "M_PhitPsit" (3 x 3m), "M_xPsi" (3 x m), "M_xPsit" (3 x 3m), "M_PsitPsi" (3m x m),
 * "M_PsitPsit" (3m x 3m), "M_PsiPsi" (m x m, the identity for mass-normalised modes), "K_ff"
 * (m, omega_j^2 in 1/s^2). The first request of a body assembles its mass matrix again. */
int ffrf_body_invariant(ffrf_case *c, int body, const char *name, double *values,
                        size_t capacity, size_t *count);

/* ---------------------------------------------------------------- mechanism state */

/* Time of the current state (s) and the case's end time (s). */
int ffrf_mechanism_time(const ffrf_case *c, double *t, double *t_end);

/* Coordinates q and velocities v of a body: rigid [R(3); Euler parameters(4)], flexible
 * [R; theta; modal coordinates]; *count = their number. Either array may be NULL. */
int ffrf_body_state(const ffrf_case *c, int body, double *q, double *v, int capacity,
                    int *count);

/* Number of markers of a body (flexible: its interfaces in input order, then one per joint end
 * whose frame is not the interface's node frame and one per node or group marker (&marker
 * node, group) that a load, spring, bushing or sensor uses; rigid: one per joint end and load
 * that uses its &marker points). */
int ffrf_marker_count(const ffrf_case *c, int body, int *n);

/* Global position (m), velocity (m/s) and angular velocity (rad/s) of a marker. Any of the
 * three may be NULL. */
int ffrf_marker_state(const ffrf_case *c, int body, int marker, double position[3],
                      double velocity[3], double angular_velocity[3]);

/* Number of joints and the name of joint `joint`. */
int ffrf_joint_count(const ffrf_case *c, int *n);
int ffrf_joint_name(const ffrf_case *c, int joint, char *buf, size_t len);

/* Reaction of a joint from the current multipliers, global: force (N) and moment (N m) as
 * 3 x 2 arrays, column 0 on the joint's body 1, column 1 on its body 2. */
int ffrf_joint_reaction(const ffrf_case *c, int joint, double force[6], double moment[6]);

/* The driver of joint `joint` (&driver; docs/mechanisms.md "Drivers") at the current state:
 * values[0] its angle (rad, revolute) or travel (m, prismatic), values[1] its rate, values[2]
 * the driving torque (N m) or force (N) on the joint's body 2 about or along the joint axis.
 * FFRF_BAD_CALL for a joint without a driver, a bad joint number or NULL values. */
int ffrf_driver_state(const ffrf_case *c, int joint, double values[3]);

/* Sensors (&sensor groups in input order, then an engine case's "crank_angle" and
 * "crank_speed"; docs/sensors.md): their number, the name of sensor `sensor` (0..n-1,
 * NUL-terminated; len: size of buf including the NUL), and its values at the current state
 * (*count = their number: 3 for position, velocity, acceleration, angular_velocity, 9 for
 * orientation, 1 for joint_coordinate, 12 for reaction, 2 for energy, 3 for node_displacement
 * and node_position; values may be NULL to ask the count). */
int ffrf_sensor_count(const ffrf_case *c, int *n);
int ffrf_sensor_name(const ffrf_case *c, int sensor, char *buf, size_t len);
int ffrf_sensor_values(const ffrf_case *c, int sensor, double *values, int capacity,
                       int *count);

/* Apply a global force (N) and moment (N m) at a marker from now on, until set again (the
 * host's load of the next interval of co-simulation). NULL means zero. After the first
 * ffrf_mechanism_advance (advance to t_start to set a load for the first interval). */
int ffrf_marker_set_load(ffrf_case *c, int body, int marker, const double force[3],
                         const double moment[3]);

/* ---------------------------------------------------------------- a case from arrays */

/* MPC kinds of an interface (ffrf_case_add_interface): RBE2 (rigid), RBE3 with uniform
 * weights (Nastran's default), RBE3 with tributary area weights, RBE3 with consistent area
 * weights (the integral of each node's shape function; docs/input.md "RBE3 weights").
 * ffrf_case_add_interface_nodes takes FFRF_RBE2 or FFRF_RBE3 (weights given per node). */
enum { FFRF_RBE2 = 1, FFRF_RBE3 = 2, FFRF_RBE3_AREA = 3, FFRF_RBE3_AREA_CONSISTENT = 4 };

/* An empty modal case to build from arrays; then ffrf_case_run computes the modes of its
 * bodies and the body queries above apply. Nothing is written. */
int ffrf_case_new(ffrf_case **c);

/* A body: xyz (3 x num_nodes, m), tets (nodes_per_tet x num_tets, node numbers 0..num_nodes-1,
 * Gmsh node order; nodes_per_tet 4 or 10), isotropic material (Pa, -, kg/m^3). */
int ffrf_case_add_body(ffrf_case *c, const char *name, int num_nodes, const double *xyz,
                       int nodes_per_tet, int num_tets, const int *tets, double young,
                       double poisson, double density);

/* A named set of surface triangles of a body (nodes_per_triangle 3 or 6, node numbers 0-based),
 * for its interfaces. */
int ffrf_case_add_surface(ffrf_case *c, int body, const char *name, int nodes_per_triangle,
                          int num_triangles, const int *triangles);

/* An interface on a surface: mpc FFRF_RBE2, FFRF_RBE3, FFRF_RBE3_AREA or
 * FFRF_RBE3_AREA_CONSISTENT, virtual node at virtual_node[3] (m; NULL: the area centroid of the
 * surface), reference conditions rc[6] (non-zero: the virtual node's Tx Ty Tz Rx Ry Rz is held;
 * NULL: none). */
int ffrf_case_add_interface(ffrf_case *c, int body, const char *surface, int mpc,
                            const double *virtual_node, const int rc[6]);

/* An interface called `name` on a node set of a body: nodes[num_nodes] (node numbers 0-based,
 * each once, every one a node of a tetrahedron), mpc FFRF_RBE2 or FFRF_RBE3, RBE3 weights
 * weights[num_nodes] (> 0; NULL: uniform), virtual node at virtual_node[3] (m; NULL: the
 * weighted centroid of the nodes), reference conditions rc[6] as above. With the nodes and
 * weights of a surface it is that surface's interface. */
int ffrf_case_add_interface_nodes(ffrf_case *c, int body, const char *name, int mpc,
                                  int num_nodes, const int *nodes, const double *weights,
                                  const double *virtual_node, const int rc[6]);

/* Number of flexible modes per body (default 12; free-free bodies: the rigid modes on top). */
int ffrf_case_set_num_modes(ffrf_case *c, int num_modes);

/* MPI build (-DFFRF_MPI=ON): run the case on the ranks of the communicator whose Fortran
 * handle is fortran_comm (an MPI_Fint: MPI_Comm_c2f(comm); include/ffrf_mpi.h has
 * ffrf_case_set_mpi_comm taking an MPI_Comm). Call it on every rank of the communicator before
 * ffrf_case_run / ffrf_mechanism_advance; every rank then calls the library with the same
 * case and gets the same modes; rank 0 alone writes the results. MPI must be initialised by
 * the host. The sequential build returns FFRF_INPUT_ERROR (rebuild with -DFFRF_MPI=ON). */
int ffrf_case_set_communicator(ffrf_case *c, int fortran_comm);

#ifdef __cplusplus
}
#endif

#endif /* FFRF_H */
