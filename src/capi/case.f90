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
module ffrf_capi_case
   use ffrf_core_kinds, only: dp
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, stage_times_t, LOG_QUIET
   use ffrf_core_paths, only: folder_of
   use ffrf_input_case, only: case_input_t, read_case
   use ffrf_core_kinds, only: ip, i8
   use ffrf_mesh_mesh, only: mesh_t, physical_group_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_mechanism, only: body_motion_input_t
   use ffrf_modes_modal_analysis, only: body_modes_t, compute_body_modes
   use ffrf_app_body_modes, only: compute_body_modes_from_file
   use ffrf_model_model, only: model_t, build_model
   use ffrf_la_sparse, only: csr_t
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_mbs_flexible_body, only: flexible_body_t
   use ffrf_core_kinds, only: pi
   use ffrf_app_run_options, only: run_options_t
   use ffrf_core_parallel, only: parallel_of_communicator, use_ranks
   use ffrf_app_modal_run, only: run_modal
   use ffrf_app_mechanism_run, only: run_mechanism
   use ffrf_app_mechanism_session, only: mechanism_session_t, move_modes
   use ffrf_mpc_interface, only: interface_spec_t, WEIGHTING_UNIFORM, WEIGHTING_GIVEN
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
      !> Release everything
      procedure :: close => case_close
   end type ffrf_case_t

contains

   !> Read and check the namelist case `case_file`. mesh_dir: folder of relative mesh files
   !> (absent or '': the case file's folder); output_dir: folder of the results (absent:
   !> nothing is written).
   subroutine case_open(self, case_file, error, mesh_dir, output_dir)
      class(ffrf_case_t), intent(out) :: self
      character(len=*), intent(in) :: case_file
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: mesh_dir, output_dir
      self%log%level = LOG_QUIET
      self%options%log_level = LOG_QUIET
      self%options%mesh_dir = ''
      if (present(mesh_dir)) self%options%mesh_dir = mesh_dir
      self%options%output_dir = ''
      self%write_output = present(output_dir)
      if (present(output_dir)) self%options%output_dir = output_dir
      self%options%restart_file = ''
      call read_case(case_file, self%case, error)
      if (allocated(error)) return
      self%opened = .true.
   end subroutine case_open

   !> An empty modal case to build from arrays (add_body, add_surface, add_interface,
   !> set_num_modes), then run; nothing is written.
   subroutine case_new(self)
      class(ffrf_case_t), intent(out) :: self
      self%log%level = LOG_QUIET
      self%options%log_level = LOG_QUIET
      self%options%mesh_dir = ''
      self%options%output_dir = ''
      self%options%restart_file = ''
      self%case%file_name = '(arrays)'
      self%case%name = 'arrays'
      allocate (self%case%bodies(0), self%case%motions(0), self%case%interfaces(0), &
         self%meshes(0), self%node_sets(0))
      self%opened = .true.
      self%from_arrays = .true.
   end subroutine case_new

   !> FFRF_BAD_CALL unless the case is built from arrays and has not run.
   subroutine check_building(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      if (.not. (self%opened .and. self%from_arrays)) then
         call bad_call(error, what // ': only for a case made by ffrf_case_new')
      else if (self%ran) then
         call bad_call(error, what // ': the case has run; build a new one')
      end if
   end subroutine check_building

   !> A body: node coordinates (m) xyz(3, n), tetrahedra tets(4 or 10, m) of node numbers
   !> 1..n in Gmsh order (Tet10: corners, then edges 1-2, 2-3, 3-1, 1-4, 3-4, 2-4 as Gmsh),
   !> isotropic material (Pa, -, kg/m^3).
   subroutine case_add_body(self, name, xyz, tets, young, poisson, density, error)
      class(ffrf_case_t), intent(inout) :: self
      character(len=*), intent(in) :: name
      real(dp), intent(in) :: xyz(:, :)
      integer, intent(in) :: tets(:, :)
      real(dp), intent(in) :: young, poisson, density
      type(error_t), allocatable, intent(out) :: error
      type(body_input_t), allocatable :: bodies(:)
      type(body_motion_input_t), allocatable :: motions(:)
      type(mesh_t), allocatable :: meshes(:)
      integer :: n, k
      call check_building(self, 'add_body', error)
      if (allocated(error)) return
      if (len_trim(name) == 0 .or. len_trim(name) > 64) then
         call bad_call(error, 'add_body: the name must have 1 to 64 characters')
      else if (any(self%case%bodies%name == name)) then
         call bad_call(error, 'add_body: a body "' // trim(name) // '" exists already')
      else if (size(xyz, 1) /= 3 .or. size(xyz, 2) < 4) then
         call bad_call(error, 'add_body "' // trim(name) // '": ' // to_str(size(xyz, 2)) // &
            ' nodes; a body needs at least 4')
      else if (size(tets, 1) /= 4 .and. size(tets, 1) /= 10) then
         call bad_call(error, 'add_body "' // trim(name) // '": ' // to_str(size(tets, 1)) // &
            ' nodes per tetrahedron; give 4 (Tet4) or 10 (Tet10)')
      else if (size(tets, 2) < 1) then
         call bad_call(error, 'add_body "' // trim(name) // '": no tetrahedra')
      else if (minval(tets) < 1 .or. maxval(tets) > size(xyz, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'add_body "' // trim(name) // '": node ' // &
            'numbers of the tetrahedra must lie in 0..' // to_str(size(xyz, 2) - 1) // &
            ' (C, 0-based); found ' // to_str(minval(tets) - 1) // '..' // &
            to_str(maxval(tets) - 1))
      else if (.not. all(abs(xyz) <= huge(1.0_dp))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'add_body "' // trim(name) // &
            '": a node coordinate is not finite')
      end if
      if (allocated(error)) return
      n = size(self%case%bodies)
      allocate (bodies(n + 1), motions(n + 1), meshes(n + 1))
      bodies(:n) = self%case%bodies
      motions(:n) = self%case%motions
      do k = 1, n
         call move_mesh(self%meshes(k), meshes(k))
      end do
      bodies(n + 1)%name = name
      bodies(n + 1)%young = young
      bodies(n + 1)%poisson = poisson
      bodies(n + 1)%density = density
      ! the body is cut from its mesh by name: the mesh's one volume group below
      bodies(n + 1)%volumes(1) = name
      associate (mesh => meshes(n + 1))
         mesh%num_nodes = size(xyz, 2)
         mesh%xyz = xyz
         mesh%node_tags = [(int(k, i8), k=1, size(xyz, 2))]
         mesh%nodes_per_tet = size(tets, 1)
         mesh%tets = int(tets, ip)
         mesh%tet_tags = [(int(k, i8), k=1, size(tets, 2))]
         mesh%tet_entity = [(1_ip, k=1, size(tets, 2))]
         mesh%nodes_per_tri = 0
         allocate (mesh%tris(3, 0), mesh%tri_tags(0), mesh%tri_entity(0), mesh%groups(1))
         mesh%groups(1)%dim = 3
         mesh%groups(1)%tag = 1
         mesh%groups(1)%name = trim(name)
         mesh%groups(1)%entities = [1_ip]
         mesh%file_name = '(arrays of body "' // trim(name) // '")'
      end associate
      call move_alloc(bodies, self%case%bodies)
      call move_alloc(motions, self%case%motions)
      call move_alloc(meshes, self%meshes)
   end subroutine case_add_body

   !> Move a mesh (its arrays) from `from` to `to`.
   subroutine move_mesh(from, to)
      type(mesh_t), intent(inout) :: from
      type(mesh_t), intent(out) :: to
      to = from
   end subroutine move_mesh

   !> A named set of triangles tris(3 or 6, m) on the surface of body `body`, node numbers
   !> 1..n (an interface names it).
   subroutine case_add_surface(self, body, name, tris, error)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: body
      character(len=*), intent(in) :: name
      integer, intent(in) :: tris(:, :)
      type(error_t), allocatable, intent(out) :: error
      type(physical_group_t), allocatable :: groups(:)
      integer :: entity, n, k
      call check_building(self, 'add_surface', error)
      if (.not. allocated(error)) call check_body(self, 'add_surface', body, error)
      if (allocated(error)) return
      associate (mesh => self%meshes(body))
         if (len_trim(name) == 0 .or. len_trim(name) > 64) then
            call bad_call(error, 'add_surface: the name must have 1 to 64 characters')
         else if (mesh%find_group(2_ip, name) > 0) then
            call bad_call(error, 'add_surface: body "' // trim(self%case%bodies(body)%name) // &
               '" has a surface "' // trim(name) // '" already')
         else if (size(tris, 1) /= 3 .and. size(tris, 1) /= 6) then
            call bad_call(error, 'add_surface "' // trim(name) // '": ' // &
               to_str(size(tris, 1)) // ' nodes per triangle; give 3 or 6')
         else if (size(tris, 2) < 1) then
            call bad_call(error, 'add_surface "' // trim(name) // '": no triangles')
         else if (mesh%nodes_per_tri > 0 .and. size(tris, 1) /= mesh%nodes_per_tri) then
            call bad_call(error, 'add_surface "' // trim(name) // '": ' // &
               to_str(size(tris, 1)) // ' nodes per triangle, the body''s other surfaces ' &
               // 'have ' // to_str(mesh%nodes_per_tri))
         else if (minval(tris) < 1 .or. maxval(tris) > mesh%num_nodes) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'add_surface "' // trim(name) // &
               '": node numbers must lie in 0..' // to_str(mesh%num_nodes - 1) // &
               ' (C, 0-based)')
         end if
         if (allocated(error)) return
         entity = size(mesh%groups)
         if (mesh%nodes_per_tri == 0) deallocate (mesh%tris)
         mesh%nodes_per_tri = size(tris, 1)
         if (.not. allocated(mesh%tris)) allocate (mesh%tris(size(tris, 1), 0))
         mesh%tris = reshape([reshape(mesh%tris, [size(mesh%tris)]), &
            reshape(int(tris, ip), [size(tris)])], [size(tris, 1), size(mesh%tris, 2) + &
            size(tris, 2)])
         n = size(mesh%tri_tags)
         mesh%tri_tags = [mesh%tri_tags, [(int(n + k, i8), k=1, size(tris, 2))]]
         mesh%tri_entity = [mesh%tri_entity, [(int(entity, ip), k=1, size(tris, 2))]]
         ! surfaces (dim 2, tags 1..) before the volume (dim 3): sorted by dimension, then tag
         allocate (groups(size(mesh%groups) + 1))
         groups(:entity - 1) = mesh%groups(:entity - 1)
         groups(entity)%dim = 2
         groups(entity)%tag = entity
         groups(entity)%name = trim(name)
         groups(entity)%entities = [int(entity, ip)]
         groups(entity + 1) = mesh%groups(entity)
         call move_alloc(groups, mesh%groups)
      end associate
   end subroutine case_add_surface

   !> An interface of body `body` on its surface `surface` (add_surface): mpc FFRF_RBE2,
   !> FFRF_RBE3 (uniform weights), FFRF_RBE3_AREA (tributary area weights) or
   !> FFRF_RBE3_AREA_CONSISTENT (consistent area weights), virtual node at `position` (m) or,
   !> absent, at the area centroid of the surface, reference conditions rc = forbidden
   !> virtual-node dofs Tx Ty Tz Rx Ry Rz.
   subroutine case_add_interface(self, body, surface, mpc, rc, error, position)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: body
      character(len=*), intent(in) :: surface
      integer, intent(in) :: mpc
      logical, intent(in) :: rc(6)
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: position(3)
      call check_building(self, 'add_interface', error)
      if (.not. allocated(error)) call check_body(self, 'add_interface', body, error)
      if (allocated(error)) return
      if (self%meshes(body)%find_group(2_ip, surface) == 0) then
         call bad_call(error, 'add_interface: body "' // trim(self%case%bodies(body)%name) // &
            '" has no surface "' // trim(surface) // '"; add it with add_surface first')
         return
      end if
      if (mpc < FFRF_RBE2 .or. mpc > FFRF_RBE3_AREA_CONSISTENT) then
         call bad_call(error, 'add_interface: mpc = ' // to_str(mpc) // '; give FFRF_RBE2 (' &
            // to_str(FFRF_RBE2) // '), FFRF_RBE3 (' // to_str(FFRF_RBE3) // &
            '), FFRF_RBE3_AREA (' // to_str(FFRF_RBE3_AREA) // ') or ' // &
            'FFRF_RBE3_AREA_CONSISTENT (' // to_str(FFRF_RBE3_AREA_CONSISTENT) // ')')
         return
      end if
      if (any(self%case%interfaces%body == self%case%bodies(body)%name .and. &
         self%case%interfaces%name == surface)) then
         call bad_call(error, 'add_interface: surface "' // trim(surface) // '" of body "' // &
            trim(self%case%bodies(body)%name) // '" has an interface already')
         return
      end if
      call append_interface(self, body, surface, mpc, rc, position)
   end subroutine case_add_interface

   !> Append the &interface of an interface given from arrays: mpc FFRF_RBE2, FFRF_RBE3,
   !> FFRF_RBE3_AREA or FFRF_RBE3_AREA_CONSISTENT, virtual node at `position` or the centroid.
   subroutine append_interface(self, body, name, mpc, rc, position)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: body
      character(len=*), intent(in) :: name
      integer, intent(in) :: mpc
      logical, intent(in) :: rc(6)
      real(dp), intent(in), optional :: position(3)
      character(len=2), parameter :: dof_names(6) = ['Tx', 'Ty', 'Tz', 'Rx', 'Ry', 'Rz']
      type(interface_input_t) :: input
      integer :: k
      input%body = self%case%bodies(body)%name
      input%name = name
      input%mpc = merge('RBE2', 'RBE3', mpc == FFRF_RBE2)
      if (mpc == FFRF_RBE3_AREA) input%weighting = 'area'
      if (mpc == FFRF_RBE3_AREA_CONSISTENT) input%weighting = 'area_consistent'
      if (present(position)) then
         input%virtual_node = 'position'
         input%position = position
      end if
      input%rc = ''
      do k = 1, 6
         if (rc(k)) input%rc = trim(input%rc) // ' ' // dof_names(k)
      end do
      input%rc = adjustl(input%rc)
      self%case%interfaces = [self%case%interfaces, input]
   end subroutine append_interface

   !> An interface of body `body` on the node set `nodes` (node numbers 1..n of add_body, each
   !> once, every one a node of a tetrahedron), called `name`: mpc FFRF_RBE2 or FFRF_RBE3, RBE3
   !> weights w_i > 0 of the nodes (absent: uniform), virtual node at `position` (m) or, absent,
   !> at the weighted centroid of the nodes, reference conditions rc = forbidden virtual-node
   !> dofs Tx Ty Tz Rx Ry Rz. Given the same nodes and weights, it is the surface interface.
   subroutine case_add_interface_nodes(self, body, name, mpc, nodes, rc, error, weights, &
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
      type(node_set_interface_t) :: node_set
      integer(ip), allocatable :: new_index(:)
      character(len=:), allocatable :: what
      integer :: j, k
      call check_building(self, 'add_interface_nodes', error)
      if (.not. allocated(error)) call check_body(self, 'add_interface_nodes', body, error)
      if (allocated(error)) return
      what = 'add_interface_nodes "' // trim(name) // '": '
      associate (mesh => self%meshes(body), body_name => self%case%bodies(body)%name)
         if (len_trim(name) == 0 .or. len_trim(name) > 64) then
            call bad_call(error, 'add_interface_nodes: the name must have 1 to 64 characters')
         else if (mpc /= FFRF_RBE2 .and. mpc /= FFRF_RBE3) then
            call bad_call(error, what // 'mpc = ' // to_str(mpc) // '; give FFRF_RBE2 (' // &
               to_str(FFRF_RBE2) // ') or FFRF_RBE3 (' // to_str(FFRF_RBE3) // '); RBE3 ' // &
               'weights come with the nodes')
         else if (size(nodes) < 1) then
            call bad_call(error, what // 'no nodes; give at least one')
         else if (any(self%case%interfaces%body == body_name .and. &
            self%case%interfaces%name == name) .or. mesh%find_group(2_ip, name) > 0) then
            call bad_call(error, what // 'body "' // trim(body_name) // '" has an interface ' // &
               'or a surface of that name already')
         else if (present(weights)) then
            if (mpc == FFRF_RBE2) then
               call bad_call(error, what // 'weights are for an RBE3 (mpc = FFRF_RBE3)')
            else if (size(weights) /= size(nodes)) then
               call bad_call(error, what // to_str(size(weights)) // ' weights for ' // &
                  to_str(size(nodes)) // ' nodes')
            end if
         end if
         if (allocated(error)) return
         ! new_index: 1 for a node of a tetrahedron, -k once listed at position k
         allocate (new_index(mesh%num_nodes), source=0_ip)
         do j = 1, size(mesh%tets, 2)
            do k = 1, size(mesh%tets, 1)
               new_index(mesh%tets(k, j)) = 1
            end do
         end do
         do k = 1, size(nodes)
            if (nodes(k) < 1 .or. nodes(k) > mesh%num_nodes) then
               call fatal_error(error, FFRF_INPUT_ERROR, what // 'node ' // &
                  to_str(nodes(k) - 1) // ' (position ' // to_str(k - 1) // ') is not in ' // &
                  '0..' // to_str(mesh%num_nodes - 1) // ' (C, 0-based)')
            else if (new_index(nodes(k)) == 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, what // 'node ' // &
                  to_str(nodes(k) - 1) // ' (C, 0-based) is not a node of any tetrahedron')
            else if (new_index(nodes(k)) < 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, what // 'node ' // &
                  to_str(nodes(k) - 1) // ' (C, 0-based) is listed twice, at positions ' // &
                  to_str(-new_index(nodes(k)) - 1) // ' and ' // to_str(k - 1))
            else if (present(weights)) then
               if (.not. (weights(k) > 0.0_dp .and. weights(k) <= huge(1.0_dp))) then
                  call fatal_error(error, FFRF_INPUT_ERROR, what // 'weight ' // &
                     to_str(k - 1) // ' (C, 0-based) is ' // to_str(weights(k)) // &
                     '; RBE3 weights must be positive and finite')
               end if
            end if
            if (allocated(error)) return
            new_index(nodes(k)) = -k
         end do
         ! the body's mesh loses the nodes of no tetrahedron when it is cut (extract_body):
         ! node i becomes the number of used nodes up to i
         new_index = merge(1_ip, 0_ip, new_index /= 0)
         do k = 2, size(new_index)
            new_index(k) = new_index(k - 1) + new_index(k)
         end do
      end associate
      node_set%body = body
      node_set%spec%name = name
      node_set%spec%nodes = new_index(nodes)
      node_set%spec%weighting = WEIGHTING_UNIFORM
      if (present(weights)) then
         node_set%spec%weighting = WEIGHTING_GIVEN
         node_set%spec%weights = weights
      end if
      call append_interface(self, body, name, mpc, rc, position)
      self%node_sets = [self%node_sets, node_set]
   end subroutine case_add_interface_nodes

   !> Put the node sets of body `body` (add_interface_nodes) into its resolved interfaces.
   subroutine attach_node_sets(self, body, specs)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      type(interface_spec_t), intent(inout) :: specs(:)
      integer :: i, k
      do k = 1, size(self%node_sets)
         if (self%node_sets(k)%body /= body) cycle
         do i = 1, size(specs)
            if (specs(i)%name /= self%node_sets(k)%spec%name) cycle
            specs(i)%nodes = self%node_sets(k)%spec%nodes
            specs(i)%weighting = self%node_sets(k)%spec%weighting
            if (allocated(self%node_sets(k)%spec%weights)) &
               specs(i)%weights = self%node_sets(k)%spec%weights
         end do
      end do
   end subroutine attach_node_sets

   !> Number of flexible modes per body (free-free bodies: the six rigid modes come on top).
   subroutine case_set_num_modes(self, num_modes, error)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: num_modes
      type(error_t), allocatable, intent(out) :: error
      call check_building(self, 'set_num_modes', error)
      if (allocated(error)) return
      if (num_modes < 1) then
         call bad_call(error, 'set_num_modes: num_modes = ' // to_str(num_modes) // &
            ', must be at least 1')
         return
      end if
      self%case%modes%num_modes = num_modes
   end subroutine case_set_num_modes

   !> MPI build: run the case on the ranks of `comm` (a Fortran communicator handle, from C
   !> MPI_Comm_c2f), which every rank of it then calls with the same case; before run or
   !> advance. The sequential build refuses it (FFRF_INPUT_ERROR: rebuild with -DFFRF_MPI=ON).
   subroutine case_set_communicator(self, comm, error)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: comm
      type(error_t), allocatable, intent(out) :: error
      call check_open(self, 'set_communicator', error)
      if (allocated(error)) return
      if (self%ran .or. self%session%prepared) then
         call bad_call(error, 'set_communicator: the case has run already; set the ' // &
            'communicator before ffrf_case_run and ffrf_mechanism_advance')
         return
      end if
      call parallel_of_communicator(comm, self%options%parallel, error)
   end subroutine case_set_communicator

   !> Raise FFRF_BAD_CALL with `message`.
   subroutine bad_call(error, message)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: message
      call fatal_error(error, FFRF_BAD_CALL, message)
   end subroutine bad_call

   !> FFRF_BAD_CALL unless the case is open.
   subroutine check_open(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      if (.not. self%opened) call bad_call(error, what // ': the case is not open ' // &
         '(ffrf_case_open failed or was not called)')
   end subroutine check_open

   !> The folder of relative mesh files.
   function mesh_folder(self) result(folder)
      class(ffrf_case_t), intent(in) :: self
      character(len=:), allocatable :: folder
      folder = self%options%mesh_dir
      if (len(folder) == 0) folder = folder_of(self%case%file_name)
   end function mesh_folder

   !> Modal case: the modes of every body (results written as the driver writes them when an
   !> output folder was given). Mechanism case: the modes, then the motion to t_end (with an
   !> output folder: run_mechanism, the driver's run; else the session, state kept).
   subroutine case_run(self, error)
      class(ffrf_case_t), intent(inout) :: self
      type(error_t), allocatable, intent(out) :: error
      type(stage_times_t) :: times
      type(model_t) :: model
      integer :: k
      call check_open(self, 'run', error)
      if (allocated(error)) return
      if (self%ran) then
         call bad_call(error, 'run: the case has already run')
         return
      end if
      if (self%case%is_mechanism .and. self%session%prepared) then
         if (self%write_output) then
            call bad_call(error, 'run: the mechanism was advanced already; with an output ' &
               // 'folder run writes the whole run from t_start: open the case again')
            return
         end if
      end if
      if (size(self%case%bodies) == 0) then
         call bad_call(error, 'run: the case has no bodies; add one with ffrf_case_add_body')
         return
      end if
      self%ran = .true.
      call use_ranks(self%options%parallel)
      if (.not. self%case%is_mechanism) then
         if (self%write_output) then
            call run_modal(self%case, self%options, self%log, error, self%modes)
         else
            ! as run_modal: the case resolved once by the model (rigid flags, interfaces, modes)
            call build_model(self%case, model, error)
            if (allocated(error)) then
               call add_context(error, self%case%file_name)
               return
            end if
            allocate (self%modes(size(self%case%bodies)))
            do k = 1, size(self%case%bodies)
               if (model%bodies(k)%rigid) cycle
               associate (body => model%bodies(k))
                  if (self%from_arrays) then
                     call attach_node_sets(self, k, body%interfaces)
                     call compute_body_modes(self%meshes(k), body%spec, body%interfaces, &
                        body%modes, self%log, times, self%modes(k), error)
                  else
                     call compute_body_modes_from_file(body%body, body%interfaces, body%modes, &
                        mesh_folder(self), self%log, times, self%modes(k), error)
                  end if
               end associate
               if (allocated(error)) then
                  call add_context(error, self%case%file_name)
                  exit
               end if
            end do
         end if
         self%have_modes = .not. allocated(error)
         return
      end if
      if (self%write_output) then
         call run_mechanism(self%case, self%options, self%log, error, self%modes, &
            self%final_state)
         self%have_final = .true.
         self%have_modes = allocated(self%modes)
         return
      end if
      call self%advance(session_end_time(self), error)
   end subroutine case_run

   !> The case's t_end (mechanism), without preparing.
   real(dp) function session_end_time(self)
      class(ffrf_case_t), intent(in) :: self
      session_end_time = self%case%mechanism%integrator%t_end
   end function session_end_time

   !> Whether the case is a mechanism case (has &joint groups).
   logical function case_is_mechanism(self)
      class(ffrf_case_t), intent(in) :: self
      case_is_mechanism = self%opened .and. self%case%is_mechanism
   end function case_is_mechanism

   !> Number of bodies (&body groups).
   subroutine case_body_count(self, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_open(self, 'body_count', error)
      if (.not. allocated(error)) n = size(self%case%bodies)
   end subroutine case_body_count

   !> FFRF_BAD_CALL unless 1 <= body <= number of bodies.
   subroutine check_body(self, what, body, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      call check_open(self, what, error)
      if (allocated(error)) return
      if (body < 1 .or. body > size(self%case%bodies)) call bad_call(error, what // ': body ' // &
         to_str(body - 1) // ' does not exist; the case has ' // &
         to_str(size(self%case%bodies)) // ' bodies, 0..' // &
         to_str(size(self%case%bodies) - 1))
   end subroutine check_body

   !> FFRF_BAD_CALL unless the body exists and the modes have been computed.
   subroutine check_modes(self, what, body, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body
      type(error_t), allocatable, intent(out) :: error
      call check_body(self, what, body, error)
      if (allocated(error)) return
      if (.not. self%have_modes) call bad_call(error, what // ': no modes yet; call ' // &
         'ffrf_case_run first (mechanism case: or ffrf_mechanism_advance)')
   end subroutine check_modes

   !> Name of body `body`.
   subroutine case_body_name(self, body, name, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      name = ''
      call check_body(self, 'body_name', body, error)
      if (.not. allocated(error)) name = trim(self%case%bodies(body)%name)
   end subroutine case_body_name

   !> Natural frequencies (Hz) of the body's modes (none for a rigid body).
   subroutine case_frequencies(self, body, hz, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: hz(:)
      type(error_t), allocatable, intent(out) :: error
      allocate (hz(0))
      call check_modes(self, 'body_frequencies', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%frequency_hz)) hz = self%modes(body)%frequency_hz
   end subroutine case_frequencies

   !> Mesh nodes, modes and interfaces of a body (0 for a rigid body without a mesh).
   subroutine case_body_sizes(self, body, num_nodes, num_modes, num_interfaces, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      integer, intent(out) :: num_nodes, num_modes, num_interfaces
      type(error_t), allocatable, intent(out) :: error
      num_nodes = 0
      num_modes = 0
      num_interfaces = 0
      call check_modes(self, 'body_sizes', body, error)
      if (allocated(error)) return
      associate (m => self%modes(body))
         if (allocated(m%mesh%xyz)) num_nodes = size(m%mesh%xyz, 2)
         if (allocated(m%frequency_hz)) num_modes = size(m%frequency_hz)
         if (allocated(m%interfaces)) num_interfaces = size(m%interfaces)
      end associate
   end subroutine case_body_sizes

   !> Node coordinates (m), 3 x num_nodes.
   subroutine case_nodes(self, body, xyz, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: xyz(:, :)
      type(error_t), allocatable, intent(out) :: error
      allocate (xyz(3, 0))
      call check_modes(self, 'body_nodes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%mesh%xyz)) xyz = self%modes(body)%mesh%xyz
   end subroutine case_nodes

   !> Mass-normalised mode shapes, (3 num_nodes, num_modes).
   subroutine case_mode_shapes(self, body, shape, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: shape(:, :)
      type(error_t), allocatable, intent(out) :: error
      allocate (shape(0, 0))
      call check_modes(self, 'body_mode_shapes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%shape)) shape = self%modes(body)%shape
   end subroutine case_mode_shapes

   !> Virtual-node rows of the modes, (6 num_interfaces, num_modes).
   subroutine case_virtual_node_shapes(self, body, rows, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: rows(:, :)
      type(error_t), allocatable, intent(out) :: error
      allocate (rows(0, 0))
      call check_modes(self, 'body_virtual_node_shapes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%virtual_node_shape)) rows = &
         self%modes(body)%virtual_node_shape
   end subroutine case_virtual_node_shapes

   !> Mass (kg), centre of mass (m) and inertia about it (kg m^2) of a meshed body.
   subroutine case_mass_properties(self, body, mass, center, inertia, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), intent(out) :: mass, center(3), inertia(3, 3)
      type(error_t), allocatable, intent(out) :: error
      mass = 0.0_dp
      center = 0.0_dp
      inertia = 0.0_dp
      call check_modes(self, 'body_mass_properties', body, error)
      if (allocated(error)) return
      if (.not. allocated(self%modes(body)%mesh%xyz)) then
         call bad_call(error, 'body_mass_properties: body "' // &
            trim(self%case%bodies(body)%name) // '" has no mesh; its mass is the &body input')
         return
      end if
      mass = self%modes(body)%mass
      center = self%modes(body)%center_of_mass
      inertia = self%modes(body)%inertia
   end subroutine case_mass_properties

   !> The FFRF inertia invariants of a body's modes (docs/theory.md 3.2; flexible_body_t,
   !> exact Gram matrices of the consistent mass matrix, assembled again here once per body),
   !> flattened column-major, by name: 'mass' (kg), 'center_of_mass' (3, m), 'theta_u' (3 x 3,
   !> inertia about the body-frame origin), 'M_PhitPsi' (3 x m), 'M_PhitPsit' (3 x 3m),
   !> 'M_xPsi' (3 x m), 'M_xPsit' (3 x 3m), 'M_PsitPsi' (3m x m), 'M_PsitPsit' (3m x 3m),
   !> 'M_PsiPsi' (m x m), 'K_ff' (m: omega_j^2, 1/s^2).
   subroutine case_invariant(self, body, name, values, error)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: body
      character(len=*), intent(in) :: name
      real(dp), allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M
      real(dp), allocatable :: virtual_xyz(:, :)
      integer :: i, nt
      allocate (values(0))
      call check_modes(self, 'body_invariant', body, error)
      if (allocated(error)) return
      associate (modes => self%modes(body))
         if (.not. allocated(modes%frequency_hz)) then
            call bad_call(error, 'body_invariant: body "' // trim(self%case%bodies(body)%name) &
               // '" has no modes (rigid)')
            return
         end if
         if (size(modes%frequency_hz) == 0) then
            call bad_call(error, 'body_invariant: body "' // trim(self%case%bodies(body)%name) &
               // '" has no modes (rigid)')
            return
         end if
         if (.not. allocated(self%invariants)) then
            allocate (self%invariants(size(self%modes)), self%have_invariants(size(self%modes)))
            self%have_invariants = .false.
         end if
         if (.not. self%have_invariants(body)) then
            nt = size(modes%mesh%tets, 2)
            call assemble_stiffness_mass(modes%mesh%xyz, modes%mesh%tets, &
               [(int(i, i8), i=1, nt)], material_t(self%case%bodies(body)%young, &
               self%case%bodies(body)%poisson, self%case%bodies(body)%density, &
               self%case%bodies(body)%name), K, M, error)
            if (allocated(error)) return
            allocate (virtual_xyz(3, size(modes%interfaces)))
            do i = 1, size(modes%interfaces)
               virtual_xyz(:, i) = modes%interfaces(i)%virtual_xyz
            end do
            call self%invariants(body)%init(M, modes%mesh%xyz, modes%shape, &
               (2.0_dp * pi * modes%frequency_hz)**2, modes%virtual_node_shape, virtual_xyz, &
               error)
            if (allocated(error)) return
            self%have_invariants(body) = .true.
         end if
      end associate
      associate (f => self%invariants(body))
         select case (name)
         case ('mass')
            values = [f%mass]
         case ('center_of_mass')
            values = f%center_of_mass
         case ('theta_u')
            values = reshape(f%theta_u, [9])
         case ('M_PhitPsi')
            values = reshape(f%m_phit_psi, [size(f%m_phit_psi)])
         case ('M_PhitPsit')
            values = reshape(f%m_phit_psit, [size(f%m_phit_psit)])
         case ('M_xPsi')
            values = reshape(f%m_x_psi, [size(f%m_x_psi)])
         case ('M_xPsit')
            values = reshape(f%m_x_psit, [size(f%m_x_psit)])
         case ('M_PsitPsi')
            values = reshape(f%m_psit_psi, [size(f%m_psit_psi)])
         case ('M_PsitPsit')
            values = reshape(f%m_psit_psit, [size(f%m_psit_psit)])
         case ('M_PsiPsi')
            values = reshape(f%m_psi_psi, [size(f%m_psi_psi)])
         case ('K_ff')
            values = f%stiffness
         case default
            call bad_call(error, 'body_invariant: no invariant "' // name // '"; the ' // &
               'invariants are mass, center_of_mass, theta_u, M_PhitPsi, M_PhitPsit, ' // &
               'M_xPsi, M_xPsit, M_PsitPsi, M_PsitPsit, M_PsiPsi, K_ff')
         end select
      end associate
   end subroutine case_invariant

   !> FFRF_BAD_CALL unless the case is a mechanism case with a prepared session.
   subroutine check_session(self, what, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      call check_open(self, what, error)
      if (allocated(error)) return
      if (.not. self%case%is_mechanism) then
         call bad_call(error, what // ': "' // self%case%file_name // '" is a modal case ' // &
            '(no &joint groups); only a mechanism case moves')
      else if (.not. self%session%prepared) then
         if (self%have_final) then
            call bad_call(error, what // ': not available after ffrf_case_run with an ' // &
               'output folder (the run is over); open the case without one to query the state')
         else
            call bad_call(error, what // ': the mechanism is not prepared yet; call ' // &
               'ffrf_mechanism_advance first (advance to t_start only prepares)')
         end if
      end if
   end subroutine check_session

   !> Mechanism case: prepare on the first call (modes, mechanism, consistent start), then
   !> integrate up to time t (ffrf_app_mechanism_session).
   subroutine case_advance(self, t, error)
      class(ffrf_case_t), intent(inout) :: self
      !> Time to reach (s), t_start <= t <= t_end
      real(dp), intent(in) :: t
      type(error_t), allocatable, intent(out) :: error
      type(stage_times_t) :: times
      integer :: k
      call check_open(self, 'mechanism_advance', error)
      if (allocated(error)) return
      if (.not. self%case%is_mechanism) then
         call bad_call(error, 'mechanism_advance: "' // self%case%file_name // '" is a ' // &
            'modal case (no &joint groups); only a mechanism case moves')
         return
      end if
      if (self%have_final) then
         call bad_call(error, 'mechanism_advance: the case has run to t_end with an output ' &
            // 'folder; open it again to advance it')
         return
      end if
      if (.not. self%session%prepared) then
         ! a time beyond t_end is refused before the modes are computed (session_advance
         ! checks it again with the h of the automatic model)
         associate (settings => self%case%mechanism%integrator)
            if (.not. (t <= settings%t_end + 1.0e-6_dp * settings%h)) then
               call fatal_error(error, FFRF_INPUT_ERROR, self%case%file_name // &
                  ': mechanism: advance to t = ' // to_str(t, 12) // ' s, beyond the ' // &
                  'case''s t_end = ' // to_str(settings%t_end, 12) // ' s; raise ' // &
                  '&integrator t_end')
               return
            end if
         end associate
         call use_ranks(self%options%parallel)
         if (self%write_output .and. self%options%parallel%is_root()) then
            ! recorded as the driver's run (ffrf_app_mechanism_session); the session keeps its
            ! modes for the results file and the animations (MPI: rank 0 records)
            call self%session%prepare(self%case, mesh_folder(self), self%log, times, error, &
               options=self%options)
         else
            call self%session%prepare(self%case, mesh_folder(self), self%log, times, error)
         end if
         if (allocated(error)) return
         allocate (self%modes(size(self%session%bodies)))
         do k = 1, size(self%session%bodies)
            if (self%write_output) then
               self%modes(k) = self%session%bodies(k)%modes
            else
               call move_modes(self%session%bodies(k)%modes, self%modes(k))
            end if
         end do
         self%have_modes = .true.
      end if
      call self%session%advance(t, error)
      if (allocated(error)) then
         ! (a recorded run's error names the case already)
         if (index(error%message, self%case%file_name // ':') /= 1) call add_context(error, &
            self%case%file_name)
      end if
   end subroutine case_advance

   !> Crank angle (rad, unwrapped) and speed (rad/s) of the current state.
   subroutine case_crank_state(self, angle, speed, error)
      class(ffrf_case_t), intent(in) :: self
      real(dp), intent(out) :: angle, speed
      type(error_t), allocatable, intent(out) :: error
      angle = 0.0_dp
      speed = 0.0_dp
      if (self%have_final) then
         angle = self%final_state(2)
         speed = self%final_state(3)
         return
      end if
      call check_session(self, 'crank_state', error)
      if (allocated(error)) return
      angle = self%session%crank_angle()
      speed = self%session%crank_speed()
   end subroutine case_crank_state

   !> Time of the current state and the case's t_end (s).
   subroutine case_time(self, t, t_end, error)
      class(ffrf_case_t), intent(in) :: self
      real(dp), intent(out) :: t, t_end
      type(error_t), allocatable, intent(out) :: error
      t = 0.0_dp
      t_end = 0.0_dp
      if (self%have_final) then
         t = self%final_state(1)
         t_end = session_end_time(self)
         return
      end if
      call check_session(self, 'mechanism_time', error)
      if (allocated(error)) return
      t = self%session%time()
      t_end = self%session%end_time()
   end subroutine case_time

   !> Coordinates and velocities of a body (ffrf_app_mechanism_session body_state).
   subroutine case_body_state(self, body, q, v, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      real(dp), allocatable, intent(out) :: q(:), v(:)
      type(error_t), allocatable, intent(out) :: error
      allocate (q(0), v(0))
      call check_session(self, 'body_state', error)
      if (.not. allocated(error)) call check_body(self, 'body_state', body, error)
      if (.not. allocated(error)) call self%session%body_state(body, q, v, error)
   end subroutine case_body_state

   !> Number of markers of a body.
   subroutine case_marker_count(self, body, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_session(self, 'marker_count', error)
      if (.not. allocated(error)) call check_body(self, 'marker_count', body, error)
      if (.not. allocated(error)) n = self%session%num_markers(body)
   end subroutine case_marker_count

   !> FFRF_BAD_CALL unless the marker exists on the body.
   subroutine check_marker(self, what, body, marker, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: body, marker
      type(error_t), allocatable, intent(out) :: error
      integer :: n
      call check_session(self, what, error)
      if (.not. allocated(error)) call check_body(self, what, body, error)
      if (allocated(error)) return
      n = self%session%num_markers(body)
      if (marker < 1 .or. marker > n) call bad_call(error, what // ': marker ' // &
         to_str(marker - 1) // ' does not exist; body "' // trim(self%case%bodies(body)%name) &
         // '" has ' // to_str(n) // ' markers, 0..' // to_str(n - 1))
   end subroutine check_marker

   !> Global position (m), velocity (m/s) and angular velocity (rad/s) of a marker.
   subroutine case_marker_state(self, body, marker, position, velocity, angular_velocity, &
         error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: body, marker
      real(dp), intent(out) :: position(3), velocity(3), angular_velocity(3)
      type(error_t), allocatable, intent(out) :: error
      position = 0.0_dp
      velocity = 0.0_dp
      angular_velocity = 0.0_dp
      call check_marker(self, 'marker_state', body, marker, error)
      if (.not. allocated(error)) call self%session%marker_motion(body, marker, position, &
         velocity, angular_velocity, error)
   end subroutine case_marker_state

   !> Number of joints.
   subroutine case_joint_count(self, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_session(self, 'joint_count', error)
      if (.not. allocated(error)) n = self%session%num_joints()
   end subroutine case_joint_count

   !> FFRF_BAD_CALL unless the joint exists.
   subroutine check_joint(self, what, joint, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: joint
      type(error_t), allocatable, intent(out) :: error
      call check_session(self, what, error)
      if (allocated(error)) return
      if (joint < 1 .or. joint > self%session%num_joints()) call bad_call(error, what // &
         ': joint ' // to_str(joint - 1) // ' does not exist; the case has ' // &
         to_str(self%session%num_joints()) // ' joints')
   end subroutine check_joint

   !> Name of joint `joint`.
   subroutine case_joint_name(self, joint, name, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: joint
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      name = ''
      call check_joint(self, 'joint_name', joint, error)
      if (.not. allocated(error)) name = self%session%mech%joints(joint)%name
   end subroutine case_joint_name

   !> Reaction force (N) and moment (N m) of a joint, global; column 1 on its body 1.
   subroutine case_joint_reaction(self, joint, force, moment, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: joint
      real(dp), intent(out) :: force(3, 2), moment(3, 2)
      type(error_t), allocatable, intent(out) :: error
      force = 0.0_dp
      moment = 0.0_dp
      call check_joint(self, 'joint_reaction', joint, error)
      if (.not. allocated(error)) call self%session%joint_reaction(joint, force, moment, error)
   end subroutine case_joint_reaction

   !> The driver of joint `joint` (1..num_joints; &driver): its angle or travel, rate and
   !> driving torque or force (ffrf_mbs_joint_driver) at the current state.
   subroutine case_driver_state(self, joint, values, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: joint
      real(dp), intent(out) :: values(3)
      type(error_t), allocatable, intent(out) :: error
      integer :: d
      values = 0.0_dp
      call check_joint(self, 'driver_state', joint, error)
      if (allocated(error)) return
      d = 0
      associate (s => self%session)
         if (allocated(s%mech%drivers)) d = findloc(s%mech%drivers%joint, joint, dim=1)
         if (d == 0) then
            call bad_call(error, 'driver_state: joint ' // to_str(joint - 1) // ' ("' // &
               s%mech%joints(joint)%name // '") has no driver; add &driver joint = ''' // &
               s%mech%joints(joint)%name // ''' to the case')
            return
         end if
         values = s%mech%driver_state(d, s%integrator%q, s%integrator%v, s%integrator%lambda)
      end associate
   end subroutine case_driver_state

   !> Number of sensors (&sensor groups, then an engine case's crank_angle and crank_speed).
   subroutine case_sensor_count(self, n, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(out) :: n
      type(error_t), allocatable, intent(out) :: error
      n = 0
      call check_session(self, 'sensor_count', error)
      if (.not. allocated(error)) n = self%session%num_sensors()
   end subroutine case_sensor_count

   !> FFRF_BAD_CALL unless the sensor exists.
   subroutine check_sensor(self, what, sensor, error)
      class(ffrf_case_t), intent(in) :: self
      character(len=*), intent(in) :: what
      integer, intent(in) :: sensor
      type(error_t), allocatable, intent(out) :: error
      call check_session(self, what, error)
      if (allocated(error)) return
      if (sensor < 1 .or. sensor > self%session%num_sensors()) call bad_call(error, what // &
         ': sensor ' // to_str(sensor - 1) // ' does not exist; the case has ' // &
         to_str(self%session%num_sensors()) // ' sensors')
   end subroutine check_sensor

   !> Name of sensor `sensor`.
   subroutine case_sensor_name(self, sensor, name, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: sensor
      character(len=:), allocatable, intent(out) :: name
      type(error_t), allocatable, intent(out) :: error
      name = ''
      call check_sensor(self, 'sensor_name', sensor, error)
      if (.not. allocated(error)) call self%session%sensor_name(sensor, name, error)
   end subroutine case_sensor_name

   !> Values of sensor `sensor` at the current state (docs/sensors.md).
   subroutine case_sensor_values(self, sensor, values, error)
      class(ffrf_case_t), intent(in) :: self
      integer, intent(in) :: sensor
      real(dp), allocatable, intent(out) :: values(:)
      type(error_t), allocatable, intent(out) :: error
      allocate (values(0))
      call check_sensor(self, 'sensor_values', sensor, error)
      if (.not. allocated(error)) call self%session%sensor_values(sensor, values, error)
   end subroutine case_sensor_values

   !> Apply a global force (N) and moment (N m) at a marker from now on, until set again.
   subroutine case_set_marker_load(self, body, marker, force, moment, error)
      class(ffrf_case_t), intent(inout) :: self
      integer, intent(in) :: body, marker
      real(dp), intent(in) :: force(3), moment(3)
      type(error_t), allocatable, intent(out) :: error
      call check_marker(self, 'marker_set_load', body, marker, error)
      if (.not. allocated(error)) call self%session%set_marker_load(body, marker, force, &
         moment, error)
   end subroutine case_set_marker_load

   !> Release everything (the object can be opened again); a mechanism advanced with an output
   !> folder but not to t_end gets its results file first (status "stopped: ...").
   subroutine case_close(self)
      class(ffrf_case_t), intent(inout) :: self
      call self%session%finish()
      call reset(self)
   contains
      subroutine reset(self)
         class(ffrf_case_t), intent(out) :: self
         self%opened = .false.
      end subroutine reset
   end subroutine case_close

end module ffrf_capi_case
