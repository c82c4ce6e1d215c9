!> A reduced flexible body set up (ffrf_mbs_flexible_body): its modes and inertia invariants,
!> markers at virtual nodes, modal damping and the geometric stiffness of a preload.
submodule (ffrf_mbs_flexible_body) ffrf_mbs_flexible_body_setup
   implicit none

contains

   module procedure flexible_body_init
      real(dp), allocatable :: Z(:, :), MZ(:, :), gram(:, :)
      integer :: n, nm, ncol, i, j, c, stat, col_psi, col_psit
      character(len=*), parameter :: where = 'flexible body: '

      n = size(xyz, 2)
      nm = size(shapes, 2)
      if (size(xyz, 1) /= 3 .or. M%num_rows /= 3 * n .or. M%num_cols /= 3 * n .or. &
         size(shapes, 1) /= 3 * n) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'sizes do not match: xyz (' // &
            to_str(size(xyz, 1)) // ', ' // to_str(n) // '), M ' // to_str(M%num_rows) // &
            ' x ' // to_str(M%num_cols) // ', shapes ' // to_str(size(shapes, 1)) // ' rows; ' // &
            'pass xyz(3, n), M 3n x 3n and shapes with 3n rows')
         return
      end if
      if (size(eigenvalues) /= nm .or. size(virtual_shapes, 2) /= nm .or. &
         size(virtual_xyz, 1) /= 3 .or. size(virtual_shapes, 1) /= 6 * size(virtual_xyz, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // to_str(nm) // ' modes but ' // &
            to_str(size(eigenvalues)) // ' eigenvalues, virtual shapes ' // &
            to_str(size(virtual_shapes, 1)) // ' x ' // to_str(size(virtual_shapes, 2)) // &
            ' for ' // to_str(size(virtual_xyz, 2)) // ' virtual nodes; pass one eigenvalue ' // &
            'per mode and 6 virtual-shape rows per virtual node')
         return
      end if
      do j = 1, nm
         if (.not. ieee_is_finite(eigenvalues(j)) .or. eigenvalues(j) < 0.0_dp) then
            call fatal_error(error, FFRF_INPUT_ERROR, where // 'eigenvalue of mode ' // &
               to_str(j) // ' = ' // to_str(eigenvalues(j)) // '; must be finite and >= 0')
            return
         end if
      end do
      if (.not. (all(ieee_is_finite(shapes)) .and. all(ieee_is_finite(xyz)) .and. &
         all(ieee_is_finite(virtual_shapes)) .and. all(ieee_is_finite(virtual_xyz)) .and. &
         all(ieee_is_finite(M%val)))) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'NaN or Inf in the mass matrix, ' // &
            'node coordinates, mode shapes or virtual-node data')
         return
      end if

      self%num_nodes = n
      self%num_modes = nm
      self%num_markers = size(virtual_xyz, 2)
      self%num_coordinates = 7 + nm
      self%stiffness = eigenvalues
      allocate (self%damping(nm), source=0.0_dp)
      self%virtual_shapes = virtual_shapes
      self%virtual_xyz = virtual_xyz
      self%marker_node = [(i, i=1, self%num_markers)]
      allocate (self%marker_frame(3, 3, self%num_markers), source=0.0_dp)
      do i = 1, self%num_markers
         self%marker_frame(:, :, i) = identity3()
      end do
      allocate (self%framed(self%num_markers), source=.false.)

      call check_scalar_mass(M, n, error)
      if (allocated(error)) return

      ! Columns Z = [Phi_t (3), x~ (3), x (1), Psi (m), Psi~ (3m)], theory.md 3.2
      ncol = 7 + 4 * nm
      col_psi = 7
      col_psit = 7 + nm
      allocate (Z(3 * n, ncol), MZ(3 * n, ncol), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, where // 'cannot allocate 2 x ' // &
            to_str(3 * n) // ' x ' // to_str(ncol) // ' reals for the inertia invariants')
         return
      end if
      Z = 0.0_dp
      do i = 1, n
         associate (rows => 3 * (i - 1) + [1, 2, 3])
            Z(rows, 1:3) = identity3()
            Z(rows, 4:6) = skew3(xyz(:, i))
            Z(rows, 7) = xyz(:, i)
            do j = 1, nm
               Z(rows, col_psi + j) = shapes(rows, j)
               Z(rows, col_psit + 3 * (j - 1) + 1:col_psit + 3 * j) = skew3(shapes(rows, j))
            end do
         end associate
      end do
      do c = 1, ncol
         call csr_matvec(M, Z(:, c), MZ(:, c))
      end do
      gram = matmul(transpose(Z), MZ)
      gram = 0.5_dp * (gram + transpose(gram))
      if (.not. all(ieee_is_finite(gram))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, where // 'NaN or Inf in the inertia ' // &
            'invariants Z^T M Z')
         return
      end if

      self%mass = gram(1, 1)
      if (.not. self%mass > 0.0_dp) then
         call fatal_error(error, FFRF_INPUT_ERROR, where // 'mass Phi_t^T M Phi_t = ' // &
            to_str(self%mass) // ' kg; the mass matrix must be positive definite')
         return
      end if
      self%center_of_mass = gram(1:3, 7) / self%mass
      self%theta_u = gram(4:6, 4:6)
      associate (psi => col_psi + [(j, j=1, nm)], psit => col_psit + [(j, j=1, 3 * nm)])
         self%m_phit_psi = gram(1:3, psi)
         self%m_phit_psit = gram(1:3, psit)
         self%m_x_psi = gram(4:6, psi)
         self%m_x_psit = gram(4:6, psit)
         self%m_psit_psi = gram(psit, psi)
         self%m_psit_psit = gram(psit, psit)
         self%m_psi_psi = gram(psi, psi)
      end associate
   end procedure flexible_body_init

   module procedure flexible_body_add_marker
      marker = 0
      if (node < 1 .or. node > size(self%virtual_xyz, 2)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body marker: virtual node ' // &
            to_str(node) // ' out of range 1..' // to_str(size(self%virtual_xyz, 2)) // &
            '; pass an interface number')
         return
      end if
      call check_rotation(frame, 'flexible body marker at interface ' // to_str(node) // &
         ': the frame', error)
      if (allocated(error)) return
      self%num_markers = self%num_markers + 1
      marker = self%num_markers
      self%marker_node = [self%marker_node, node]
      self%marker_frame = reshape([self%marker_frame, frame], [3, 3, marker])
      self%framed = [self%framed, any(frame /= identity3())]
   end procedure flexible_body_add_marker

   module procedure flexible_body_add_point
      real(dp), allocatable :: grown(:, :)
      node = 0
      if (size(rows, 1) /= 6 .or. size(rows, 2) /= self%num_modes) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body point: mode rows ' // &
            to_str(size(rows, 1)) // ' x ' // to_str(size(rows, 2)) // ' for ' // &
            to_str(self%num_modes) // ' modes; pass 6 rows (Tx..Rz) per mode')
         return
      end if
      if (.not. (all(ieee_is_finite(rows)) .and. all(ieee_is_finite(xyz)))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body point: NaN or Inf in its ' // &
            'mode rows or position')
         return
      end if
      node = size(self%virtual_xyz, 2) + 1
      allocate (grown(6 * node, self%num_modes))
      grown(:6 * node - 6, :) = self%virtual_shapes
      grown(6 * node - 5:, :) = rows
      call move_alloc(grown, self%virtual_shapes)
      self%virtual_xyz = reshape([self%virtual_xyz, xyz], [3, node])
   end procedure flexible_body_add_point

   !> M = Ms (x) I3: M applied to p (x) e_c (p a fixed node field) has only c-components, the
   !> same for c = 1, 2, 3, to 1e-12 relative. Else the invariants would not be exact under A.
   subroutine check_scalar_mass(M, n, error)
      type(csr_t), intent(in) :: M
      integer, intent(in) :: n
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: p(:), y(:, :)
      real(dp) :: scale, misfit
      integer :: c, i
      allocate (p(3 * n), y(3 * n, 3))
      do c = 1, 3
         p = 0.0_dp
         do i = 1, n
            p(3 * (i - 1) + c) = 1.0_dp + 0.5_dp * cos(real(i, dp))
         end do
         call csr_matvec(M, p, y(:, c))
      end do
      scale = maxval(abs(y))
      misfit = 0.0_dp
      do c = 1, 3
         do i = 1, n
            misfit = max(misfit, maxval(abs(y(3 * (i - 1) + [1, 2, 3], c) - &
               merge(y(3 * (i - 1) + 1, 1), 0.0_dp, [1, 2, 3] == c))))
         end do
      end do
      if (misfit > 1.0e-12_dp * scale) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: the mass matrix is not of ' // &
            'the form Ms (x) I3 (relative misfit ' // to_str(misfit / scale, 3) // '); the ' // &
            'FFRF invariants need the same scalar mass for x, y and z (consistent or lumped ' // &
            'mass of solid elements)')
      end if
   end subroutine check_scalar_mass

   module procedure flexible_body_set_modal_damping
      real(dp) :: xi(self%num_modes)
      if (size(damping_ratio) /= 1 .and. size(damping_ratio) /= self%num_modes) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: ' // &
            to_str(size(damping_ratio)) // ' damping ratios for ' // to_str(self%num_modes) // &
            ' modes; give one for all or one per mode')
         return
      end if
      if (size(damping_ratio) == 1) then
         xi = damping_ratio(1)
      else
         xi = damping_ratio
      end if
      if (any(.not. ieee_is_finite(xi)) .or. any(xi < 0.0_dp)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: damping ratio ' // &
            to_str(minval(xi)) // ' is negative or not finite; must be >= 0')
         return
      end if
      self%damping = 2.0_dp * xi * sqrt(self%stiffness)
   end procedure flexible_body_set_modal_damping

   module procedure flexible_body_set_geometric_stiffness
      integer :: m
      m = self%num_modes
      if (size(geometric_stiffness, 1) /= m .or. size(geometric_stiffness, 2) /= m .or. &
         size(geometric_stiffness, 3) /= NUM_CENTRIFUGAL_CASES) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: geometric stiffness ' // &
            to_str(size(geometric_stiffness, 1)) // ' x ' // to_str(size(geometric_stiffness, &
            2)) // ' x ' // to_str(size(geometric_stiffness, 3)) // ' for ' // to_str(m) // &
            ' modes; pass one m x m matrix per centrifugal load case (m x m x 6)')
      else if (.not. all(ieee_is_finite(geometric_stiffness))) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'flexible body: NaN or Inf in the ' // &
            'geometric stiffness')
      end if
      if (allocated(error)) return
      self%geometric_stiffness = geometric_stiffness
   end procedure flexible_body_set_geometric_stiffness

end submodule ffrf_mbs_flexible_body_setup
