!> The body data of an ffrf_case_t after its modes (a submodule of ffrf_capi_case): names,
!> frequencies, sizes, nodes, mode shapes, virtual-node rows, mass properties, invariants.
submodule (ffrf_capi_case) ffrf_capi_case_bodies
   use ffrf_core_strings, only: to_str
   use ffrf_core_kinds, only: i8
   use ffrf_la_sparse, only: csr_t
   use ffrf_fe_material, only: material_t
   use ffrf_fe_assembly, only: assemble_stiffness_mass
   use ffrf_core_kinds, only: pi
   implicit none

contains

   module procedure case_body_count
      n = 0
      call check_open(self, 'body_count', error)
      if (.not. allocated(error)) n = size(self%case%bodies)
   end procedure case_body_count

   module procedure check_body
      call check_open(self, what, error)
      if (allocated(error)) return
      if (body < 1 .or. body > size(self%case%bodies)) call bad_call(error, what // ': body ' // &
         to_str(body - 1) // ' does not exist; the case has ' // &
         to_str(size(self%case%bodies)) // ' bodies, 0..' // &
         to_str(size(self%case%bodies) - 1))
   end procedure check_body

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

   module procedure case_body_name
      name = ''
      call check_body(self, 'body_name', body, error)
      if (.not. allocated(error)) name = trim(self%case%bodies(body)%name)
   end procedure case_body_name

   module procedure case_frequencies
      allocate (hz(0))
      call check_modes(self, 'body_frequencies', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%frequency_hz)) hz = self%modes(body)%frequency_hz
   end procedure case_frequencies

   module procedure case_body_sizes
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
   end procedure case_body_sizes

   module procedure case_nodes
      allocate (xyz(3, 0))
      call check_modes(self, 'body_nodes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%mesh%xyz)) xyz = self%modes(body)%mesh%xyz
   end procedure case_nodes

   module procedure case_mode_shapes
      allocate (shape(0, 0))
      call check_modes(self, 'body_mode_shapes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%shape)) shape = self%modes(body)%shape
   end procedure case_mode_shapes

   module procedure case_virtual_node_shapes
      allocate (rows(0, 0))
      call check_modes(self, 'body_virtual_node_shapes', body, error)
      if (allocated(error)) return
      if (allocated(self%modes(body)%virtual_node_shape)) rows = &
         self%modes(body)%virtual_node_shape
   end procedure case_virtual_node_shapes

   module procedure case_mass_properties
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
   end procedure case_mass_properties

   module procedure case_invariant
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
   end procedure case_invariant

end submodule ffrf_capi_case_bodies
