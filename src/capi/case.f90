!> The case object of the public APIs: a typed Fortran `ffrf_case_t` (exported by `use ffrf`)
!> that the C API (ffrf_capi, include/ffrf.h) wraps one to one. It holds a case read from its
!> namelist file, the modes of its bodies once computed and, for a mechanism case, its
!> mechanism session (ffrf_app_mechanism_session). Every procedure reports through
!> `type(error_t), allocatable, intent(out) :: error` (code FFRF_BAD_CALL for a call out of
!> order or a bad index, else the library's codes); nothing here stops, prints or installs
!> signal handlers, and there is no state outside the object.
!>
!> Indices here are 1-based (bodies in &body order, markers, joints in &joint order, modes);
!> the C API shifts them to 0-based.
!>
!> Call order: open -> run (modal case: modes; mechanism case: modes and motion to t_end), or
!> for a mechanism case advance(t) repeatedly (the first call prepares: modes, mechanism,
!> consistent start). Body data after the modes; mechanism state after the first advance (or
!> after run without an output folder).
!>
!> This module holds the type and the interfaces of its procedures; the bodies are in the
!> submodules case_run.f90 (open, run, close), case_build.f90 (a case from arrays),
!> case_bodies.f90 (body data) and case_mechanism.f90 (the mechanism session).
module ffrf_capi_case
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t
   use ffrf_core_log, only: logger_t
   use ffrf_input_case, only: case_input_t
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_modes_modal_analysis, only: body_modes_t
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_app_run_options, only: run_options_t
   use ffrf_app_mechanism_session, only: mechanism_session_t
   use ffrf_mpc_interface, only: interface_spec_t
   use ffrf_input_overrides, only: override_t
   implicit none
   private
   public :: ffrf_case_t, FFRF_BAD_CALL, FFRF_RBE2, FFRF_RBE3, FFRF_RBE3_AREA
   public :: FFRF_RBE3_AREA_CONSISTENT

   !> MPC kinds of an interface given from arrays (add_interface): RBE2, RBE3 with uniform
   !> weights (Nastran's default), RBE3 with tributary area weights ('area'), RBE3 with
   !> consistent area weights int N_i dA ('area_consistent'; docs/input.md "RBE3 weights")
   integer, parameter :: FFRF_RBE2 = 1, FFRF_RBE3 = 2, FFRF_RBE3_AREA = 3, &
      FFRF_RBE3_AREA_CONSISTENT = 4

   !> An interface on a node set (add_interface_nodes): its body and the nodes, in the numbering
   !> of the body's mesh once cut (compute_body_modes), with their weights
   type :: node_set_interface_t
      integer :: body = 0
      type(interface_spec_t) :: spec
   end type node_set_interface_t

   !> Status of a call out of order, a bad index or argument, a buffer too small (the C API's
   !> FFRF_BAD_CALL); the other codes are those of ffrf_core_error
   integer, parameter :: FFRF_BAD_CALL = 1

   !> A case (module header).
   type :: ffrf_case_t
      !> The case as read (open)
      type(case_input_t), private :: case
      !> Folders (output_dir = '' with write_output false: nothing written)
      type(run_options_t), private :: options
      logical, private :: write_output = .false.
      !> Silent logger (LOG_QUIET)
      type(logger_t), private :: log
      !> open succeeded / run done / modes available
      logical, private :: opened = .false., ran = .false., have_modes = .false.
      !> The modes of every body (case order; rigid bodies: empty)
      type(body_modes_t), allocatable, private :: modes(:)
      !> The mechanism session (advance, state queries)
      type(mechanism_session_t), private :: session
      !> Time, crank angle, crank speed after a run that wrote results (no session state)
      real(dp), private :: final_state(3) = 0.0_dp
      logical, private :: have_final = .false.
      !> A modal case built from arrays (new): the meshes of its bodies, case order
      type(mesh_t), allocatable, private :: meshes(:)
      logical, private :: from_arrays = .false.
      !> FFRF inertia invariants of each body, computed on the first request (invariant)
      type(flexible_body_t), allocatable, private :: invariants(:)
      logical, allocatable, private :: have_invariants(:)
      !> Interfaces on node sets of a case built from arrays (add_interface_nodes)
      type(node_set_interface_t), allocatable, private :: node_sets(:)
      !> The body poses set (set_pose) as overrides of the case file, in call order: the case is
      !> read again with them, as the driver's --set body[NAME].KEY=...
      type(override_t), allocatable, private :: pose_overrides(:)
      !> The exports set (set_export) as the override run.export, read with the poses
      type(override_t), allocatable, private :: export_override
   contains
      !> An FFRF inertia invariant of a body (theory.md 3.2), by name
      procedure :: invariant => case_invariant
      !> An empty modal case to build from arrays (nothing written)
      procedure :: new => case_new
      !> A body from node coordinates and Tet4/Tet10 connectivity, with its material
      procedure :: add_body => case_add_body
      !> A named set of surface triangles (Tri3/Tri6) of a body, for its interfaces
      procedure :: add_surface => case_add_surface
      !> An interface on a surface: MPC kind, virtual node, reference conditions
      procedure :: add_interface => case_add_interface
      !> An interface on a node set: MPC kind, per-node RBE3 weights, virtual node, RCs
      procedure :: add_interface_nodes => case_add_interface_nodes
      !> Number of modes per body of a case built from arrays
      procedure :: set_num_modes => case_set_num_modes
      !> MPI build: the communicator the case runs on (before run/advance)
      procedure :: set_communicator => case_set_communicator
      !> Read and check a case file
      procedure :: open => case_open
      !> Modes (and motion to t_end for a mechanism case)
      procedure :: run => case_run
      !> Whether the case is a mechanism case
      procedure :: is_mechanism => case_is_mechanism
      !> Number of bodies, a body's name
      procedure :: body_count => case_body_count
      procedure :: body_name => case_body_name
      !> Body data after the modes
      procedure :: frequencies => case_frequencies
      procedure :: body_sizes => case_body_sizes
      procedure :: nodes => case_nodes
      procedure :: mode_shapes => case_mode_shapes
      procedure :: virtual_node_shapes => case_virtual_node_shapes
      procedure :: mass_properties => case_mass_properties
      !> Mechanism: advance, state, host loads
      procedure :: advance => case_advance
      procedure :: crank_state => case_crank_state
      procedure :: time => case_time
      procedure :: body_state => case_body_state
      procedure :: marker_count => case_marker_count
      procedure :: marker_state => case_marker_state
      procedure :: joint_count => case_joint_count
      procedure :: joint_name => case_joint_name
      procedure :: joint_reaction => case_joint_reaction
      procedure :: sensor_count => case_sensor_count
      procedure :: sensor_name => case_sensor_name
      procedure :: sensor_values => case_sensor_values
      !> Coordinate, rate and driving torque or force of the driver of a joint
      procedure :: driver_state => case_driver_state
      procedure :: set_marker_load => case_set_marker_load
      !> Starting pose and velocities of a body (the &body keys), before the first advance
      procedure :: set_pose => case_set_pose
      !> The exports beside the results (&run export), before the run
      procedure :: set_export => case_set_export
      !> Release everything
      procedure :: close => case_close
   end type ffrf_case_t

   interface

      ! --- ffrf_capi_case_run (case_run.f90) -----------------------------------------------------

      !> The start of open and new: a silent log, no restart, mesh_dir and output_dir as given
      !> (absent: ''; results are written only when output_dir is present).
      module subroutine quiet_options(self, mesh_dir, output_dir)
         class(ffrf_case_t), intent(inout) :: self
         character(len=*), intent(in), optional :: mesh_dir, output_dir
      end subroutine quiet_options

      !> Read and check the namelist case `case_file`. mesh_dir: folder of relative mesh files
      !> (absent or '': the case file's folder); output_dir: folder of the results (absent:
      !> nothing is written).
      module subroutine case_open(self, case_file, error, mesh_dir, output_dir)
         class(ffrf_case_t), intent(out) :: self
         character(len=*), intent(in) :: case_file
         type(error_t), allocatable, intent(out) :: error
         character(len=*), intent(in), optional :: mesh_dir, output_dir
      end subroutine case_open

      !> MPI build: run the case on the ranks of `comm` (a Fortran communicator handle, from C
      !> MPI_Comm_c2f), which every rank of it then calls with the same case; before run or
      !> advance. The sequential build refuses it (FFRF_INPUT_ERROR: rebuild with -DFFRF_MPI=ON).
      module subroutine case_set_communicator(self, comm, error)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: comm
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_set_communicator

      !> Raise FFRF_BAD_CALL with `message`.
      module subroutine bad_call(error, message)
         type(error_t), allocatable, intent(out) :: error
         character(len=*), intent(in) :: message
      end subroutine bad_call

      !> FFRF_BAD_CALL unless the case is open.
      module subroutine check_open(self, what, error)
         class(ffrf_case_t), intent(in) :: self
         character(len=*), intent(in) :: what
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_open

      !> The folder of relative mesh files.
      module function mesh_folder(self) result(folder)
         class(ffrf_case_t), intent(in) :: self
         character(len=:), allocatable :: folder
      end function mesh_folder

      !> Modal case: the modes of every body (results written as the driver writes them when an
      !> output folder was given). Mechanism case: the modes, then the motion to t_end (with an
      !> output folder: run_mechanism, the driver's run; else the session, state kept).
      module subroutine case_run(self, error)
         class(ffrf_case_t), intent(inout) :: self
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_run

      !> The case's t_end (mechanism), without preparing.
      module real(dp) function session_end_time(self)
         class(ffrf_case_t), intent(in) :: self
      end function session_end_time

      !> Whether the case is a mechanism case (has &joint groups).
      module logical function case_is_mechanism(self)
         class(ffrf_case_t), intent(in) :: self
      end function case_is_mechanism

      !> Release everything (the object can be opened again); a mechanism advanced with an output
      !> folder but not to t_end gets its results file first (status "stopped: ...").
      module subroutine case_close(self)
         class(ffrf_case_t), intent(inout) :: self
      end subroutine case_close

      ! --- ffrf_capi_case_build (case_build.f90) -------------------------------------------------

      !> An empty modal case to build from arrays (add_body, add_surface, add_interface,
      !> set_num_modes), then run; nothing is written.
      module subroutine case_new(self)
         class(ffrf_case_t), intent(out) :: self
      end subroutine case_new

      !> A body: node coordinates (m) xyz(3, n), tetrahedra tets(4 or 10, m) of node numbers
      !> 1..n in Gmsh order (Tet10: corners, then edges 1-2, 2-3, 3-1, 1-4, 3-4, 2-4 as Gmsh),
      !> isotropic material (Pa, -, kg/m^3).
      module subroutine case_add_body(self, name, xyz, tets, young, poisson, density, error)
         class(ffrf_case_t), intent(inout) :: self
         character(len=*), intent(in) :: name
         real(dp), intent(in) :: xyz(:, :)
         integer, intent(in) :: tets(:, :)
         real(dp), intent(in) :: young, poisson, density
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_add_body

      !> A named set of triangles tris(3 or 6, m) on the surface of body `body`, node numbers
      !> 1..n (an interface names it).
      module subroutine case_add_surface(self, body, name, tris, error)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: body
         character(len=*), intent(in) :: name
         integer, intent(in) :: tris(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_add_surface

      !> An interface of body `body` on its surface `surface` (add_surface): mpc FFRF_RBE2,
      !> FFRF_RBE3 (uniform weights), FFRF_RBE3_AREA (tributary area weights) or
      !> FFRF_RBE3_AREA_CONSISTENT (consistent area weights), virtual node at `position` (m) or,
      !> absent, at the area centroid of the surface, reference conditions rc = forbidden
      !> virtual-node dofs Tx Ty Tz Rx Ry Rz.
      module subroutine case_add_interface(self, body, surface, mpc, rc, error, position)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: body
         character(len=*), intent(in) :: surface
         integer, intent(in) :: mpc
         logical, intent(in) :: rc(6)
         type(error_t), allocatable, intent(out) :: error
         real(dp), intent(in), optional :: position(3)
      end subroutine case_add_interface

      !> An interface of body `body` on the node set `nodes` (node numbers 1..n of add_body, each
      !> once, every one a node of a tetrahedron), called `name`: mpc FFRF_RBE2 or FFRF_RBE3, RBE3
      !> weights w_i > 0 of the nodes (absent: uniform), virtual node at `position` (m) or, absent,
      !> at the weighted centroid of the nodes, reference conditions rc = forbidden virtual-node
      !> dofs Tx Ty Tz Rx Ry Rz. Given the same nodes and weights, it is the surface interface.
      module subroutine case_add_interface_nodes(self, body, name, mpc, nodes, rc, error, weights, &
            position)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: body
         character(len=*), intent(in) :: name
         integer, intent(in) :: mpc
         integer, intent(in) :: nodes(:)
         logical, intent(in) :: rc(6)
         type(error_t), allocatable, intent(out) :: error
         real(dp), intent(in), optional :: weights(:)
         real(dp), intent(in), optional :: position(3)
      end subroutine case_add_interface_nodes

      !> Put the node sets of body `body` (add_interface_nodes) into its resolved interfaces.
      module subroutine attach_node_sets(self, body, specs)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         type(interface_spec_t), intent(inout) :: specs(:)
      end subroutine attach_node_sets

      !> Number of flexible modes per body (free-free bodies: the six rigid modes come on top).
      module subroutine case_set_num_modes(self, num_modes, error)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: num_modes
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_set_num_modes

      ! --- ffrf_capi_case_bodies (case_bodies.f90) -----------------------------------------------

      !> Number of bodies (&body groups).
      module subroutine case_body_count(self, n, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(out) :: n
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_body_count

      !> FFRF_BAD_CALL unless 1 <= body <= number of bodies.
      module subroutine check_body(self, what, body, error)
         class(ffrf_case_t), intent(in) :: self
         character(len=*), intent(in) :: what
         integer, intent(in) :: body
         type(error_t), allocatable, intent(out) :: error
      end subroutine check_body

      !> Name of body `body`.
      module subroutine case_body_name(self, body, name, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         character(len=:), allocatable, intent(out) :: name
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_body_name

      !> Natural frequencies (Hz) of the body's modes (none for a rigid body).
      module subroutine case_frequencies(self, body, hz, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         real(dp), allocatable, intent(out) :: hz(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_frequencies

      !> Mesh nodes, modes and interfaces of a body (0 for a rigid body without a mesh).
      module subroutine case_body_sizes(self, body, num_nodes, num_modes, num_interfaces, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         integer, intent(out) :: num_nodes, num_modes, num_interfaces
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_body_sizes

      !> Node coordinates (m), 3 x num_nodes.
      module subroutine case_nodes(self, body, xyz, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         real(dp), allocatable, intent(out) :: xyz(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_nodes

      !> Mass-normalised mode shapes, (3 num_nodes, num_modes).
      module subroutine case_mode_shapes(self, body, shape, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         real(dp), allocatable, intent(out) :: shape(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_mode_shapes

      !> Virtual-node rows of the modes, (6 num_interfaces, num_modes).
      module subroutine case_virtual_node_shapes(self, body, rows, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         real(dp), allocatable, intent(out) :: rows(:, :)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_virtual_node_shapes

      !> Mass (kg), centre of mass (m) and inertia about it (kg m^2) of a meshed body.
      module subroutine case_mass_properties(self, body, mass, center, inertia, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         real(dp), intent(out) :: mass, center(3), inertia(3, 3)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_mass_properties

      !> The FFRF inertia invariants of a body's modes (docs/theory.md 3.2; flexible_body_t,
      !> exact Gram matrices of the consistent mass matrix, assembled again here once per body),
      !> flattened column-major, by name: 'mass' (kg), 'center_of_mass' (3, m), 'theta_u' (3 x 3,
      !> inertia about the body-frame origin), 'M_PhitPsi' (3 x m), 'M_PhitPsit' (3 x 3m),
      !> 'M_xPsi' (3 x m), 'M_xPsit' (3 x 3m), 'M_PsitPsi' (3m x m), 'M_PsitPsit' (3m x 3m),
      !> 'M_PsiPsi' (m x m), 'K_ff' (m: omega_j^2, 1/s^2).
      module subroutine case_invariant(self, body, name, values, error)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: body
         character(len=*), intent(in) :: name
         real(dp), allocatable, intent(out) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_invariant

      ! --- ffrf_capi_case_mechanism (case_mechanism.f90) -----------------------------------------

      !> Mechanism case: prepare on the first call (modes, mechanism, consistent start), then
      !> integrate up to time t (ffrf_app_mechanism_session).
      module subroutine case_advance(self, t, error)
         class(ffrf_case_t), intent(inout) :: self
         !> Time to reach (s), t_start <= t <= t_end
         real(dp), intent(in) :: t
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_advance

      !> Crank angle (rad, unwrapped) and speed (rad/s) of the current state.
      module subroutine case_crank_state(self, angle, speed, error)
         class(ffrf_case_t), intent(in) :: self
         real(dp), intent(out) :: angle, speed
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_crank_state

      !> Time of the current state and the case's t_end (s).
      module subroutine case_time(self, t, t_end, error)
         class(ffrf_case_t), intent(in) :: self
         real(dp), intent(out) :: t, t_end
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_time

      !> Coordinates and velocities of a body (ffrf_app_mechanism_session body_state).
      module subroutine case_body_state(self, body, q, v, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         real(dp), allocatable, intent(out) :: q(:), v(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_body_state

      !> Number of markers of a body.
      module subroutine case_marker_count(self, body, n, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body
         integer, intent(out) :: n
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_marker_count

      !> Global position (m), velocity (m/s) and angular velocity (rad/s) of a marker.
      module subroutine case_marker_state(self, body, marker, position, velocity, &
            angular_velocity, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: body, marker
         real(dp), intent(out) :: position(3), velocity(3), angular_velocity(3)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_marker_state

      !> Number of joints.
      module subroutine case_joint_count(self, n, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(out) :: n
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_joint_count

      !> Name of joint `joint`.
      module subroutine case_joint_name(self, joint, name, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: joint
         character(len=:), allocatable, intent(out) :: name
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_joint_name

      !> Reaction force (N) and moment (N m) of a joint, global; column 1 on its body 1.
      module subroutine case_joint_reaction(self, joint, force, moment, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: joint
         real(dp), intent(out) :: force(3, 2), moment(3, 2)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_joint_reaction

      !> The driver of joint `joint` (1..num_joints; &driver): its angle or travel, rate and
      !> driving torque or force (ffrf_mbs_joint_driver) at the current state.
      module subroutine case_driver_state(self, joint, values, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: joint
         real(dp), intent(out) :: values(3)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_driver_state

      !> Number of sensors (&sensor groups, then an engine case's crank_angle and crank_speed).
      module subroutine case_sensor_count(self, n, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(out) :: n
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_sensor_count

      !> Name of sensor `sensor`.
      module subroutine case_sensor_name(self, sensor, name, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: sensor
         character(len=:), allocatable, intent(out) :: name
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_sensor_name

      !> Values of sensor `sensor` at the current state (docs/sensors.md).
      module subroutine case_sensor_values(self, sensor, values, error)
         class(ffrf_case_t), intent(in) :: self
         integer, intent(in) :: sensor
         real(dp), allocatable, intent(out) :: values(:)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_sensor_values

      !> Apply a global force (N) and moment (N m) at a marker from now on, until set again.
      module subroutine case_set_marker_load(self, body, marker, force, moment, error)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: body, marker
         real(dp), intent(in) :: force(3), moment(3)
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_set_marker_load

      !> The starting pose of body `body` of a mechanism case, as its &body keys position (m),
      !> orientation (the rotation matrix A, body -> global, its columns the body axes),
      !> velocity (m/s) and angular_velocity (rad/s, global); an absent argument keeps the
      !> case's value. Before the first advance (the pose is the start of the motion). The case
      !> is read again with them as overrides (docs/api.md "Body pose"), so they are checked and
      !> assembled exactly as the namelist's keys; on an error the case is kept as it was.
      module subroutine case_set_pose(self, body, error, position, orientation, velocity, &
            angular_velocity)
         class(ffrf_case_t), intent(inout) :: self
         integer, intent(in) :: body
         type(error_t), allocatable, intent(out) :: error
         real(dp), intent(in), optional :: position(3), orientation(3, 3), velocity(3), &
            angular_velocity(3)
      end subroutine case_set_pose

      !> &run export = formats (a list of export words: 'xdmf'; '' none), before the run or the
      !> first advance; the case is read again with it, as the driver's --set run.export=...
      module subroutine case_set_export(self, formats, error)
         class(ffrf_case_t), intent(inout) :: self
         character(len=*), intent(in) :: formats
         type(error_t), allocatable, intent(out) :: error
      end subroutine case_set_export
   end interface

end module ffrf_capi_case
