!> The consistent starting state of a mechanism (ffrf_mbs_mechanism): the pose assembled by
!> minimum-norm Gauss-Newton and the velocities projected onto the joints (LAPACK dgelsy).
submodule (ffrf_mbs_mechanism) ffrf_mbs_mechanism_start
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_kinds, only: ip
   use ffrf_core_error, only: fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_mbs_rotation, only: euler_rotation, euler_g, rotated_vector_jacobian
   use ffrf_la_lapack, only: dgelsy
   implicit none

   !> Unit x axis
   real(dp), parameter :: e_x(3) = [1.0_dp, 0.0_dp, 0.0_dp]
   !> Relative rank tolerance of the least-squares solves (dgelsy rcond)
   real(dp), parameter :: rank_rcond = 1.0e-10_dp

contains

   !> Solve Phi(q, t) = 0 from an approximate q by Gauss-Newton, each step the minimum-norm
   !> least-squares correction (dgelsy). With rotor_angle, the rotor's rotation about z is fixed
   !> too (equation n(angle) . A e_x = 0, as the drive) and becomes the unwrapping reference.
   !> Converged when max |Phi| <= tolerance (default 1e-12).
   module procedure mechanism_assemble
      real(dp), allocatable :: a(:, :), rhs(:, :), phi(:), jac(:, :)
      real(dp) :: tol, violation
      integer :: rows, it, k
      logical :: with_rotor
      tol = 1.0e-12_dp
      if (present(tolerance)) tol = tolerance
      with_rotor = present(rotor_angle)
      if (with_rotor .and. self%rotor == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism assembly: a rotor angle was ' // &
            'given but no rotor body is set; call set_rotor first')
         return
      end if
      rows = self%nc
      if (with_rotor) rows = rows + 1
      allocate (a(rows, self%n), rhs(max(rows, self%n), 1), phi(self%nc), jac(self%nc, self%n))
      violation = huge(1.0_dp)
      do it = 1, 50
         call self%constraints(q, t, phi, error)
         if (allocated(error)) return
         rhs = 0.0_dp
         rhs(1:self%nc, 1) = -phi
         call self%constraint_jacobian(q, t, jac, error)
         if (allocated(error)) return
         a(1:self%nc, :) = jac
         if (with_rotor) then
            k = self%bodies(self%rotor)%offset
            a(rows, :) = 0.0_dp
            a(rows, k + 4:k + 7) = matmul(drive_normal(rotor_angle), &
               rotated_vector_jacobian(q(k + 4:k + 7), e_x))
            rhs(rows, 1) = -dot_product(drive_normal(rotor_angle), &
               matmul(euler_rotation(q(k + 4:k + 7)), e_x))
         end if
         violation = maxval(abs(rhs(1:rows, 1)))
         if (present(iterations)) iterations = it - 1
         if (violation <= tol) exit
         call least_squares(a, rhs, 'assembly', error)
         if (allocated(error)) return
         q = q + rhs(1:self%n, 1)
      end do
      if (.not. (violation <= tol)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism assembly: Gauss-Newton did ' &
            // 'not reach max |Phi| <= ' // to_str(tol) // ' in 50 iterations (last ' // &
            to_str(violation) // '); start from poses closer to the assembled ones')
         return
      end if
      if (with_rotor) call self%set_rotor_reference(q, rotor_angle)
   end procedure mechanism_assemble

   !> Velocities v with Phi_q v = -Phi_t, and the rotor speed if given, in the minimum-norm
   !> least-squares sense (dgelsy); error if the residual exceeds 1e-10 of the scale.
   module procedure mechanism_initial_velocities
      real(dp), allocatable :: a(:, :), rhs(:, :), rate(:), jac(:, :)
      real(dp) :: residual, scale
      integer :: rows, k, b, row, attempt
      v = 0.0_dp
      if (present(rotor_speed) .and. self%rotor == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'mechanism initial velocities: a rotor ' // &
            'speed was given but no rotor body is set; call set_rotor first')
         return
      end if
      allocate (rate(self%nc), jac(self%nc, self%n))
      call self%constraint_jacobian(q, t, jac, error)
      if (allocated(error)) return
      call self%constraint_rate(q, t, rate, error)
      if (allocated(error)) return
      ! The bodies start undeformed and moving rigidly: every modal velocity zero (a flexible
      ! body whose interface ring rotates in its modes (issue 30) would otherwise
      ! get the minimum-norm split, a twist rate that leaves that interface at rest).
      ! Without a rigid motion that meets the constraints, the minimum-norm solution of all.
      do attempt = 1, 2
         rows = self%nc
         if (present(rotor_speed)) rows = rows + 1
         if (attempt == 1) rows = rows + count_modal()
         if (allocated(a)) deallocate (a, rhs)
         allocate (a(rows, self%n), rhs(max(rows, self%n), 1))
         a = 0.0_dp
         rhs = 0.0_dp
         a(1:self%nc, :) = jac
         rhs(1:self%nc, 1) = -rate
         row = self%nc
         if (present(rotor_speed)) then
            k = self%bodies(self%rotor)%offset
            row = row + 1
            ! omega_z = e_z^T G(theta) theta_dot: the third row of G
            a(row, k + 4:k + 7) = row3(euler_g(q(k + 4:k + 7)))
            rhs(row, 1) = rotor_speed
         end if
         if (attempt == 1) then
            do b = 1, size(self%bodies)
               do k = 8, self%bodies(b)%body%num_coordinates
                  row = row + 1
                  a(row, self%bodies(b)%offset + k) = 1.0_dp
               end do
            end do
         end if
         if (present(guess)) rhs(1:rows, 1) = rhs(1:rows, 1) - matmul(a, guess)
         call least_squares(a, rhs, 'initial velocities', error)
         if (allocated(error)) return
         v = rhs(1:self%n, 1)
         if (present(guess)) v = v + guess
         residual = maxval(abs(matmul(jac, v) + rate))
         if (count_modal() == 0 .or. residual <= 1.0e-10_dp * max(maxval(abs(rate)), 1.0_dp) * &
            max(maxval(abs(v)), 1.0_dp)) exit
      end do
      scale = max(maxval(abs(rate)), 1.0_dp) * max(maxval(abs(v)), 1.0_dp)
      if (present(rotor_speed)) then
         residual = max(residual, abs(self%rotor_speed(q, v) - rotor_speed))
      end if
      if (.not. residual <= 1.0e-10_dp * scale) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism initial velocities: the ' // &
            'velocity constraints cannot be met, residual ' // to_str(residual) // &
            ' (a rotor speed inconsistent with a drive?)')
      end if

   contains

      !> Modal coordinates of all bodies (coordinates beyond R and theta).
      integer function count_modal()
         integer :: bb
         count_modal = 0
         do bb = 1, size(self%bodies)
            count_modal = count_modal + max(self%bodies(bb)%body%num_coordinates - 7, 0)
         end do
      end function count_modal

   end procedure mechanism_initial_velocities

   !> Third row of a 3 x 4 matrix.
   pure function row3(matrix) result(row)
      real(dp), intent(in) :: matrix(3, 4)
      real(dp) :: row(4)
      row = matrix(3, :)
   end function row3

   !> rhs(1:n) <- minimum-norm least-squares solution of a x = rhs(1:m) (dgelsy; a destroyed).
   subroutine least_squares(a, rhs, what, error)
      real(dp), intent(inout) :: a(:, :)
      real(dp), intent(inout) :: rhs(:, :)
      character(len=*), intent(in) :: what
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: m, n, rank, info, lwork
      integer(ip), allocatable :: jpvt(:)
      real(dp), allocatable :: work(:)
      real(dp) :: query(1)
      integer :: i
      real(dp) :: norm
      m = int(size(a, 1), ip)
      n = int(size(a, 2), ip)
      if (m == 0 .or. n == 0) return
      ! Equilibrate the rows (metres and dimensionless axis products mix)
      do i = 1, size(a, 1)
         norm = maxval(abs(a(i, :)))
         if (norm > 0.0_dp) then
            a(i, :) = a(i, :) / norm
            rhs(i, 1) = rhs(i, 1) / norm
         end if
      end do
      allocate (jpvt(n))
      jpvt = 0
      call dgelsy(m, n, 1_ip, a, m, rhs, int(size(rhs, 1), ip), jpvt, rank_rcond, rank, query, &
         -1_ip, info)
      lwork = max(1_ip, int(query(1), ip))
      allocate (work(lwork))
      call dgelsy(m, n, 1_ip, a, m, rhs, int(size(rhs, 1), ip), jpvt, rank_rcond, rank, work, &
         lwork, info)
      if (info /= 0 .or. .not. all(ieee_is_finite(rhs))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'mechanism ' // what // ': least-squares ' &
            // 'solve failed (dgelsy info = ' // to_str(info) // ')')
      end if
   end subroutine least_squares

end submodule ffrf_mbs_mechanism_start
