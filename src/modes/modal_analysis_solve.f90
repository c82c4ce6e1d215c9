!> ffrf_modes_modal_analysis: the eigen solve of the reduced system (shift-invert or Craig-
!> Bampton), rigid-body modes, shapes at the virtual nodes and the zero-energy check.
submodule (ffrf_modes_modal_analysis) ffrf_modes_modal_analysis_solve
   implicit none

contains

   module procedure solve_modes
      type(eigen_options_t) :: options
      type(stage_timer_t) :: timer
      real(dp), allocatable :: psi(:, :), rigid(:, :)
      integer :: num_rigid, first, k, num_modes
      character(len=:), allocatable :: tag

      tag = body%name
      call timer%begin()
      num_rigid = 0
      if (body%basis /= BASIS_CRAIG_BAMPTON) num_rigid = body%rc%num_free
      options%num_modes = modes%num_modes
      if (modes%shift_hz == 0.0_dp) then
         options%sigma = sigma_of_shift(auto_shift_hz)
         call log%info('modes', tag // ': automatic shift ' // to_str(auto_shift_hz, 4) // &
            ' Hz (sigma = ' // to_str(options%sigma, 4) // ' s^-2)')
      else
         options%sigma = sigma_of_shift(modes%shift_hz)
      end if
      options%sturm_check = modes%sturm_check
      if (modes%max_frequency_hz > 0.0_dp) options%max_eigenvalue = &
         sigma_of_shift(modes%max_frequency_hz)
      options%tolerance = modes%tolerance
      options%ncv = int(modes%lanczos_vectors, kind(options%ncv))
      options%parallel = ranks
      options%out_of_core = modes%out_of_core
      options%ooc_directory = modes%ooc_directory
      options%memory_limit_mb = modes%memory_limit_mb
      options%compression_tolerance = modes%compression_tolerance
      options%eigensolver = modes%eigensolver
      options%stop_on_signal = modes%stop_on_signal
      if (body%basis == BASIS_CRAIG_BAMPTON) then
         call solve_craig_bampton(body, options, red, K_r, M_r, log, times, error)
         return
      end if
      if (num_rigid > 0) then
         ! The rigid motions the reference conditions leave free, from the geometry
         call rigid_body_modes(body%mesh%xyz, body%rc, red, rigid, error)
         if (allocated(error)) return
         call solve_shift_invert(K_r, M_r, red%C, options, body%eigen, log, error, rigid=rigid)
      else
         call solve_shift_invert(K_r, M_r, red%C, options, body%eigen, log, error)
      end if
      if (allocated(error)) return
      call times%add(tag // ': ordering', body%eigen%time_ordering)
      call times%add(tag // ': analysis', body%eigen%time_analysis)
      call times%add(tag // ': factorisation', body%eigen%time_factorisation)
      call times%add(tag // ': eigen loop', body%eigen%time_lanczos)
      call times%add(tag // ': Sturm check', body%eigen%time_sturm)
      call times%add(tag // ': eigen check', body%eigen%time_check)

      first = 1
      associate (lambda => body%eigen%eigenvalues)
         if (num_rigid > 0) then
            body%rigid_frequency_hz = [(frequency_of(body%eigen%rigid_eigenvalues(k)), &
               k=1, num_rigid)]
            call log%info('modes', tag // ': ' // to_str(num_rigid) // ' rigid-body modes ' // &
               'from the geometry, deflated (' // to_str(maxval(abs(body%rigid_frequency_hz)), &
               3) // ' Hz at most: round-off of 0)')
            ! Six rigid motions removed exactly: a flexible mode at ~0 Hz is another motion
            ! without strain
            if (lambda(1) < ZERO_ENERGY_FRACTION * sigma_of_shift(-100.0_dp * auto_shift_hz)) then
               call zero_energy_error(body, frequency_of(lambda(1)), count(lambda < &
                  ZERO_ENERGY_FRACTION * sigma_of_shift(-100.0_dp * auto_shift_hz)), error)
               return
            end if
         end if
         num_modes = size(lambda)
         if (any(lambda <= 0.0_dp)) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'a constrained mode has a ' // &
               'non-positive eigenvalue ' // to_str(minval(lambda)) // &
               ': the reference conditions do not remove all rigid motions')
            return
         end if
         body%frequency_hz = [(frequency_of(lambda(k)), k=1, size(lambda))]
      end associate
      body%residual = body%eigen%residuals(first:)
      body%orthonormality_error = body%eigen%orthonormality_error
      if (.not. all(ieee_is_finite(body%residual)) .or. maxval(body%residual) > 1.0e-6_dp) then
         if (body%rc%free_free .and. abs(body%eigen%shift) < sigma_of_shift(-auto_shift_hz)) &
            then
            ! A free-free K - sigma M has condition ~ lambda_max / |sigma| near the rigid modes:
            ! before they were deflated (theory.md 5.6) the free-free Tet10 beam's residuals were
            ! 3e-5 at 1 Hz and 4e-7 at 10 Hz; now 3.5e-11 at both (test_stability_free_body),
            ! so this message is a last resort
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'eigenpair residual ' // &
               to_str(maxval(body%residual), 3) // ' exceeds 1e-6: the modes are not ' // &
               'accurate; this free-free body has six rigid-body modes at 0 Hz and the shift ' &
               // to_str(frequency_of(body%eigen%shift), 4) // ' Hz lies closer to them than ' &
               // 'the automatic shift (' // to_str(auto_shift_hz, 4) // ' Hz), so K - sigma M ' &
               // 'is nearly singular; use shift_hz = 0 (automatic) or a shift farther from 0 Hz')
         else
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'eigenpair residual ' // &
               to_str(maxval(body%residual), 3) // ' exceeds 1e-6: the modes are not ' // &
               'accurate; try a shift closer to the wanted frequencies (shift_hz) or a finer ' // &
               'tolerance')
         end if
         return
      end if

      call timer%begin()
      call expand_vectors(red, body%eigen%vectors(:, first:), psi)
      call set_shapes(body, psi)
      call times%add(tag // ': mode shapes', timer%seconds())
      if (len_trim(modes%rc_label) > 0) tag = tag // ', ' // trim(modes%rc_label)
      call log%info('modes', tag // ': ' // &
         to_str(num_modes) // ' modes, ' // to_str(body%frequency_hz(1), 6) // ' .. ' // &
         to_str(body%frequency_hz(num_modes), 6) // ' Hz, max residual ' // &
         to_str(maxval(body%residual), 2) // ', M-orthonormality ' // &
         to_str(body%orthonormality_error, 2) // ' ... ' // to_str(body%eigen%time_total, 3) // &
         ' s')
      do k = 1, num_modes
         call log%debug('modes', '  mode ' // to_str(k) // ': ' // &
            to_str(body%frequency_hz(k), 10) // ' Hz, residual ' // to_str(body%residual(k), 3))
      end do
   end procedure solve_modes

   !> Craig-Bampton basis (src/modes/craig_bampton.f90): num_modes fixed-interface modes plus
   !> the static constraint modes of the non-RC virtual-node dofs, orthonormalised by
   !> Rayleigh-Ritz so that Psi^T M Psi = I and Psi^T K Psi = diag(omega^2) as the flexible body
   !> expects; body%eigen keeps the fixed-interface solve's statistics.
   subroutine solve_craig_bampton(body, options, red, K_r, M_r, log, times, error)
      type(body_modes_t), intent(inout) :: body
      !> Tolerance, ncv; num_modes = the fixed-interface modes (shift: 0, craig_bampton_modes)
      type(eigen_options_t), intent(in) :: options
      type(reduction_t), intent(in) :: red
      type(csr_t), intent(in) :: K_r, M_r
      type(logger_t), intent(in) :: log
      type(stage_times_t), intent(inout) :: times
      type(error_t), allocatable, intent(out) :: error
      type(cb_result_t) :: cb
      type(stage_timer_t) :: timer
      real(dp), allocatable :: psi(:, :)
      integer :: k, num_modes

      if (body%rc%free_free) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'basis = ''craig_bampton'' needs ' // &
            'reference conditions on the interfaces (the floating frame); this body has ' // &
            'none: give an RC set or use basis = ''rc_normal''')
         return
      end if
      call craig_bampton_modes(K_r, M_r, red, body%interfaces, options%num_modes, options, log, &
         cb, error)
      if (allocated(error)) return
      body%eigen = cb%fixed
      call times%add(body%name // ': ordering', cb%fixed%time_ordering)
      call times%add(body%name // ': analysis', cb%fixed%time_analysis)
      call times%add(body%name // ': factorisation', cb%fixed%time_factorisation)
      call times%add(body%name // ': eigen loop', cb%fixed%time_lanczos)
      call times%add(body%name // ': eigen check', cb%fixed%time_check)
      call times%add(body%name // ': static modes', cb%time_static_solves)
      call times%add(body%name // ': Rayleigh-Ritz', cb%time_rayleigh_ritz)
      if (any(cb%eigenvalues <= 0.0_dp)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Craig-Bampton: a Ritz value ' // &
            to_str(minval(cb%eigenvalues)) // ' is not positive: the reference conditions ' // &
            'do not remove all rigid motions')
         return
      end if
      num_modes = size(cb%eigenvalues)
      body%num_static = cb%num_static
      body%frequency_hz = [(frequency_of(cb%eigenvalues(k)), k=1, num_modes)]
      body%fixed_interface_hz = [(frequency_of(cb%fixed_eigenvalues(k)), k=1, &
         size(cb%fixed_eigenvalues))]
      body%residual = cb%residuals
      body%orthonormality_error = cb%orthonormality_error
      if (body%orthonormality_error > 1.0e-8_dp) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'Craig-Bampton: the Ritz vectors are ' // &
            'M-orthonormal only to ' // to_str(body%orthonormality_error, 3) // ' (> 1e-8): ' // &
            'the basis is (nearly) dependent')
         return
      end if

      call timer%begin()
      call expand_vectors(red, cb%vectors, psi)
      call set_shapes(body, psi)
      call times%add(body%name // ': mode shapes', timer%seconds())
      call log%info('modes', body%name // ': Craig-Bampton basis, ' // to_str(cb%num_static) // &
         ' static + ' // to_str(cb%num_fixed) // ' fixed-interface modes (fixed interface ' // &
         to_str(body%fixed_interface_hz(1), 6) // ' .. ' // &
         to_str(body%fixed_interface_hz(size(body%fixed_interface_hz)), 6) // ' Hz): ' // &
         to_str(num_modes) // ' Ritz modes ' // to_str(body%frequency_hz(1), 6) // ' .. ' // &
         to_str(body%frequency_hz(num_modes), 6) // ' Hz, M-orthonormality ' // &
         to_str(body%orthonormality_error, 2))
      do k = 1, num_modes
         call log%debug('modes', '  Ritz mode ' // to_str(k) // ': ' // &
            to_str(body%frequency_hz(k), 10) // ' Hz, distance from a normal mode ' // &
            to_str(body%residual(k), 3))
      end do
   end subroutine solve_craig_bampton

   !> The rigid-body modes of the reduced body (theory.md 5.6): the rigid motions of the mesh
   !> that the reference conditions leave free (rc%free_motions: all six for a free-free body),
   !> u(x) = t + theta x (x - x_ref) at every node, in the reduced coordinates p with T p = u
   !> (ffrf_mpc_reduction: RBE2 faces as the motion of their virtual node, null-space blocks by
   !> projection), checked to lie in the range of T and in null(C) (the RBE3 reference
   !> conditions of the multiplier form), both to 1e-10 relative.
   subroutine rigid_body_modes(xyz, rc, red, rigid, error)
      !> Node positions of the body (3, num_nodes), m
      real(dp), intent(in) :: xyz(:, :)
      !> The RC set's free motions
      type(rc_summary_t), intent(in) :: rc
      !> RC matrix q = T p and constraint rows C p = 0
      type(reduction_t), intent(in) :: red
      !> Rigid-body modes in the reduced coordinates, (num_reduced, rc%num_free)
      real(dp), allocatable, intent(out) :: rigid(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: q(:, :), cp(:)
      real(dp) :: t(3), theta(3), r(3), residual, row_norm
      integer(ip) :: i, j, p
      integer :: stat
      allocate (q(3 * size(xyz, 2), rc%num_free), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'rigid-body modes: cannot allocate ' // &
            to_str(rc%num_free) // ' vectors of ' // to_str(3 * size(xyz, 2)))
         return
      end if
      do j = 1, int(rc%num_free, ip)
         t = rc%free_motions(1:3, j)
         theta = rc%free_motions(4:6, j) / rc%length
         do i = 1, int(size(xyz, 2), ip)
            r = xyz(:, i) - rc%reference_point
            q(3 * i - 2:3 * i, j) = t + [theta(2) * r(3) - theta(3) * r(2), &
               theta(3) * r(1) - theta(1) * r(3), theta(1) * r(2) - theta(2) * r(1)]
         end do
      end do
      call reduced_coordinates(red, q, rigid, residual, error)
      if (allocated(error)) return
      if (residual > 1.0e-10_dp) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'rigid-body modes: a rigid motion the ' // &
            'reference conditions leave free is not in the range of the RC matrix T ' // &
            '(relative residual ' // to_str(residual, 3) // ')')
         return
      end if
      if (red%C%num_rows == 0) return
      allocate (cp(red%C%num_rows))
      do j = 1, int(rc%num_free, ip)
         do i = 1, red%C%num_rows
            cp(i) = 0.0_dp
            row_norm = 0.0_dp
            do p = red%C%row_ptr(i), red%C%row_ptr(i + 1) - 1
               cp(i) = cp(i) + red%C%val(p) * rigid(red%C%col(p), j)
               row_norm = row_norm + red%C%val(p)**2
            end do
            cp(i) = abs(cp(i)) / max(sqrt(row_norm) * norm2(rigid(:, j)), tiny(1.0_dp))
         end do
         if (maxval(cp) > 1.0e-10_dp) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'rigid-body modes: rigid motion ' // &
               to_str(j) // ' violates a reference-condition row (relative ' // &
               to_str(maxval(cp), 3) // ')')
            return
         end if
      end do
   end subroutine rigid_body_modes

   !> The error of a free body whose spectrum holds motions without strain besides the rigid
   !> ones removed: names the cause found in the mesh (parts joined only at nodes or edges),
   !> else what remains possible.
   subroutine zero_energy_error(body, hz, num_zero, error)
      type(body_modes_t), intent(in) :: body
      !> Frequency of the first flexible mode (Hz)
      real(dp), intent(in) :: hz
      !> Flexible modes at ~0 Hz
      integer, intent(in) :: num_zero
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: num_parts
      integer(ip), allocatable :: part_of_tet(:)
      character(len=:), allocatable :: text
      text = 'free body: ' // to_str(num_zero) // ' flexible mode(s) at ' // &
         to_str(hz, 3) // ' Hz besides the ' // to_str(body%rc%num_free) // &
         ' rigid-body modes, which are removed exactly from the geometry: the mesh moves ' // &
         'without strain in another way. '
      call face_connected_parts(body%mesh, num_parts, part_of_tet)
      if (num_parts > 1) then
         text = text // 'Its tetrahedra form ' // to_str(num_parts) // ' parts that share ' // &
            'no face, only nodes or edges (a hinge), e.g. tetrahedron ' // &
            to_str(body%mesh%tet_tags(first_of_part(part_of_tet, 2_ip))) // ' in part 2: ' // &
            'join the volumes along faces (BooleanFragments before meshing) or make each ' // &
            'part a body of its own'
      else
         text = text // 'Its tetrahedra share faces (one connected piece, no hinge): ' // &
            'check for elements with no stiffness (E) or a mechanism in the interfaces'
      end if
      call fatal_error(error, FFRF_NUMERIC_ERROR, text)
   end subroutine zero_energy_error

   !> First tetrahedron of part p.
   pure integer(ip) function first_of_part(part_of_tet, p) result(first)
      integer(ip), intent(in) :: part_of_tet(:), p
      integer(ip) :: e
      first = 1
      do e = 1, int(size(part_of_tet), ip)
         if (part_of_tet(e) == p) then
            first = e
            return
         end if
      end do
   end function first_of_part

   !> body%shape = psi (moved) and the virtual-node rows psi_V = G psi_B of every interface.
   subroutine set_shapes(body, psi)
      type(body_modes_t), intent(inout) :: body
      !> Mode shapes (3 num_nodes, num_modes); deallocated on return
      real(dp), allocatable, intent(inout) :: psi(:, :)
      integer :: k, i, num_modes
      num_modes = size(psi, 2)
      call move_alloc(psi, body%shape)
      if (allocated(body%virtual_node_shape)) deallocate (body%virtual_node_shape)
      allocate (body%virtual_node_shape(6 * size(body%interfaces), num_modes))
      do k = 1, size(body%interfaces)
         associate (f => body%interfaces(k))
            do i = 1, num_modes
               body%virtual_node_shape(6 * k - 5:6 * k, i) = matmul(f%G, &
                  gather_dofs(body%shape(:, i), f%nodes))
            end do
         end associate
      end do
   end subroutine set_shapes

   pure function frequency_of(lambda) result(hz)
      real(dp), intent(in) :: lambda
      real(dp) :: hz
      hz = sign(sqrt(abs(lambda)), lambda) / (2.0_dp * pi)
   end function frequency_of

   !> The 3 dofs of each node in `nodes`, in order.
   pure function gather_dofs(q, nodes) result(q_b)
      real(dp), intent(in) :: q(:)
      integer(ip), intent(in) :: nodes(:)
      real(dp) :: q_b(3 * size(nodes))
      integer :: i
      do i = 1, size(nodes)
         q_b(3 * i - 2:3 * i) = q(3 * nodes(i) - 2:3 * nodes(i))
      end do
   end function gather_dofs
end submodule ffrf_modes_modal_analysis_solve
