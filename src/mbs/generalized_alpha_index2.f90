!> The stabilized index-2 formulation of generalized-alpha (ffrf_mbs_generalized_alpha,
!> settings%constraints = GALPHA_INDEX2; theory.md 4.6): Gear-Gupta-Leimkuhler stabilisation as
!> in Arnold, Cardona & Bruls, "A Lie algebra approach to Lie group time integration of
!> constrained systems", in Structure-preserving Integrators in Nonlinear Structural Dynamics
!> and Flexible Multibody Dynamics, CISM 565 (2016) 91-158, and Arnold & Hante, JCND 12 (2017)
!> 021002. The position update gains a second multiplier nu,
!>
!>    q_{n+1} = q_n + h v_n + h^2 ((1/2 - beta) a_n + beta a_{n+1}) + B nu_{n+1},
!>
!> and both Phi(q_{n+1}, t_{n+1}) = 0 and Phi_q v_{n+1} + Phi_t = 0 are imposed, so the
!> constraints need no numerical damping and rho_inf = 1 is accepted. B = Phi_q^T of the kept
!> rows at the step's predictor, each column divided by its largest entry (Arnold et al. take
!> Phi_q(q_{n+1})^T: B differs from it by O(h) on a correction nu of O(h^3), so the order is the
!> same, and q stays linear in the unknowns within a step). The Newton unknowns are
!> [x; y; z]: x the Newmark part of dq (q'' moves by x/(beta h^2 c), q' by x gamma/(beta h)),
!> y the scaled multiplier increment, z the increment of nu, dq = x + B z. The scaled iteration
!> matrix, of order n + 2 nr (S the row scale of kkt_complete, A the index-3 block):
!>
!>    [ A      Phi_q^T S   beta h^2 K_t B ]   x      -beta h^2 r_q
!>    [ S Phi_q   0        S Phi_q B      ]   y  =   -S Phi
!>    [ S Phi_q   0        0              ]   z      -S g beta h / gamma
!>
!> with the velocity row's d(Phi_q q')/dq term left out (it is O(h) against Phi_q gamma /
!> (beta h): a simplified Newton, the solution unchanged).
submodule (ffrf_mbs_generalized_alpha) ffrf_mbs_generalized_alpha_index2
   implicit none

contains

   module procedure index2_direction
      integer :: j
      real(dp) :: largest
      real(dp), allocatable :: row_max(:)
      if (trial%sparse) then
         ! the sparse path keeps Phi_q of the predictor and the column scales
         trial%B_sparse = trial%Phi_sparse
         if (allocated(trial%B_scale)) deallocate (trial%B_scale)
         allocate (trial%B_scale(size(self%active)), row_max(self%nc))
         if (self%nc > 0) row_max = trial%Phi_sparse%row_abs_max()
         do j = 1, size(self%active)
            trial%B_scale(j) = 1.0_dp
            if (row_max(self%active(j)) > 0.0_dp) trial%B_scale(j) = 1.0_dp / &
               row_max(self%active(j))
         end do
      else
         do j = 1, size(self%active)
            trial%B(:, j) = trial%Phi_q(self%active(j), :)
            largest = max_abs(trial%B(:, j))
            if (largest > 0.0_dp) trial%B(:, j) = trial%B(:, j) / largest
         end do
      end if
      trial%velocity_scale = self%beta * h / self%gamma
   end procedure index2_direction

   module procedure index2_blocks
      integer :: n, nr, i
      n = self%n
      nr = size(self%active)
      associate (lu => self%lu)
         lu(:n, n + nr + 1:) = self%beta * h**2 * matmul(self%tangent_K, trial%B)
         lu(n + 1:n + nr, n + nr + 1:) = matmul(lu(n + 1:n + nr, :n), trial%B)
         do i = 1, nr
            lu(n + nr + i, :n) = lu(n + i, :n)
         end do
         lu(n + nr + 1:, n + 1:) = 0.0_dp
      end associate
   end procedure index2_blocks

   module procedure index2_increment
      integer :: nr
      real(dp) :: z(self%nc), correction(self%n)
      nr = size(self%active)
      if (trial%sparse) then
         z = 0.0_dp
         z(self%active) = trial%B_scale * dx(self%n + nr + 1:self%n + 2 * nr)
         call trial%B_sparse%matvec(z, correction, transposed=.true.)
         dq = dx(:self%n) + correction
      else
         dq = dx(:self%n) + matmul(trial%B, dx(self%n + nr + 1:self%n + 2 * nr))
      end if
   end procedure index2_increment

   module procedure index2_sparse_triplets
      real(dp), allocatable :: unit(:), b(:), b_abs(:), y(:), y_abs(:), w(:), w_abs(:)
      integer(ip), allocatable :: irn_new(:), jcn_new(:)
      real(dp), allocatable :: values_new(:)
      integer :: n, nr, i, j, k, column
      integer, allocatable :: keep(:)
      n = self%n
      nr = size(self%active)
      allocate (irn(4 * (n + nr)), jcn(4 * (n + nr)), values(4 * (n + nr)))
      k = 0
      if (all(self%sparse_K%col_start == trial%B_sparse%col_start) .and. &
         all(trial%Phi_sparse%col_start == trial%B_sparse%col_start)) then
         ! block pair by block pair (O(entries) on a chain): K_t B = K_t Phi_q(active, :)^T
         ! diag(B_scale), S Phi_q B likewise with Phi_q of the iterate for the rows
         allocate (keep(self%nc))
         keep = 0
         keep(self%active) = [(i, i=1, nr)]
         call self%sparse_K%product_triplets(trial%B_sparse, 0, n + nr, irn, jcn, values, k, &
            keep_col=keep, cscale=self%beta * h**2 * trial%B_scale)
         call trial%Phi_sparse%product_triplets(trial%B_sparse, n, n + nr, irn, jcn, values, &
            k, keep_row=keep, rscale=self%row_scale, keep_col=keep, cscale=trial%B_scale)
         irn = irn(:k)
         jcn = jcn(:k)
         values = values(:k)
         return
      end if
      ! otherwise one column of B at a time (nr products with K_t and Phi_q)
      allocate (unit(self%nc), b(n), b_abs(n), y(n), y_abs(n), w(self%nc), w_abs(self%nc))
      do j = 1, nr
         ! column j of B: Phi_q(active(j), :) of the predictor times B_scale(j)
         unit = 0.0_dp
         unit(self%active(j)) = trial%B_scale(j)
         call trial%B_sparse%matvec(unit, b, transposed=.true.)
         b_abs = abs(b)
         call self%sparse_K%matvec(b, y)
         call self%sparse_K%matvec(b_abs, y_abs, absolute=.true.)
         call trial%Phi_sparse%matvec(b, w)
         call trial%Phi_sparse%matvec(b_abs, w_abs, absolute=.true.)
         column = n + nr + j
         do i = 1, n
            if (y_abs(i) > 0.0_dp) call put(i, self%beta * h**2 * y(i))
         end do
         do i = 1, nr
            if (w_abs(self%active(i)) > 0.0_dp) call put(n + i, self%row_scale(i) * &
               w(self%active(i)))
         end do
      end do
      irn = irn(:k)
      jcn = jcn(:k)
      values = values(:k)
   contains
      subroutine put(row, value)
         integer, intent(in) :: row
         real(dp), intent(in) :: value
         if (k == size(irn)) then
            allocate (irn_new(2 * k), jcn_new(2 * k), values_new(2 * k))
            irn_new(:k) = irn
            jcn_new(:k) = jcn
            values_new(:k) = values
            call move_alloc(irn_new, irn)
            call move_alloc(jcn_new, jcn)
            call move_alloc(values_new, values)
         end if
         k = k + 1
         irn(k) = int(row, ip)
         jcn(k) = int(column, ip)
         values(k) = value
      end subroutine put
   end procedure index2_sparse_triplets

end submodule ffrf_mbs_generalized_alpha_index2
