!> A modal case built from arrays (a submodule of ffrf_capi_case): bodies from node coordinates
!> and tetrahedra, surfaces, interfaces on surfaces or node sets, the number of modes.
submodule (ffrf_capi_case) ffrf_capi_case_build
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_kinds, only: ip, i8
   use ffrf_mesh_mesh, only: physical_group_t
   use ffrf_input_interface, only: interface_input_t
   use ffrf_input_body, only: body_input_t
   use ffrf_input_mechanism, only: body_motion_input_t
   use ffrf_mpc_interface, only: WEIGHTING_UNIFORM, WEIGHTING_GIVEN
   implicit none

contains

   module procedure case_new
      call quiet_options(self)
      self%case%file_name = '(arrays)'
      self%case%name = 'arrays'
      allocate (self%case%bodies(0), self%case%motions(0), self%case%interfaces(0), &
         self%meshes(0), self%node_sets(0))
      self%opened = .true.
      self%from_arrays = .true.
   end procedure case_new

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

   module procedure case_add_body
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
   end procedure case_add_body

   !> Move a mesh (its arrays) from `from` to `to`.
   subroutine move_mesh(from, to)
      type(mesh_t), intent(inout) :: from
      type(mesh_t), intent(out) :: to
      to = from
   end subroutine move_mesh

   module procedure case_add_surface
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
   end procedure case_add_surface

   module procedure case_add_interface
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
   end procedure case_add_interface

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

   module procedure case_add_interface_nodes
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
   end procedure case_add_interface_nodes

   module procedure attach_node_sets
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
   end procedure attach_node_sets

   module procedure case_set_num_modes
      call check_building(self, 'set_num_modes', error)
      if (allocated(error)) return
      if (num_modes < 1) then
         call bad_call(error, 'set_num_modes: num_modes = ' // to_str(num_modes) // &
            ', must be at least 1')
         return
      end if
      self%case%modes%num_modes = num_modes
   end procedure case_set_num_modes

end submodule ffrf_capi_case_build
