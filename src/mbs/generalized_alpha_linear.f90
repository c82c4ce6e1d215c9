!> The linear algebra of the generalized-alpha iteration matrix (ffrf_mbs_generalized_alpha,
!> a submodule of the step): its sparse assembly (block-sparse, for MUMPS), the round-off floors of
!> the convergence tests, the solves with its factors, the products M q'' and Phi_q^T lambda of
!> a trial from the dense or the block-sparse matrices.
submodule (ffrf_mbs_generalized_alpha) ffrf_mbs_generalized_alpha_linear
   implicit none

contains

   !> (generalized_alpha.f90, interface)
   module procedure sparse_assemble
      integer(ip), allocatable :: irn(:), jcn(:), irn_nu(:), jcn_nu(:)
      real(dp), allocatable :: values(:), row_max(:), values_nu(:)
      integer, allocatable :: keep_row(:)
      real(dp) :: reference
      integer :: n, nr, i, k, capacity, order
      n = self%n
      nr = size(self%active)
      associate (A => self%sparse_A, Phi => trial%Phi_sparse)
         if (.not. A%same_groups(self%sparse_K%row_start, self%sparse_K%col_start)) &
            call A%init(self%sparse_K%row_start, self%sparse_K%col_start)
         call A%combine(self%beta * h**2, self%sparse_K, 1.0_dp / c_af, trial%M_sparse, &
            self%gamma * h, self%sparse_C)
         reference = 0.0_dp
         if (n > 0) reference = maxval(abs(A%diagonal()))
         if (reference <= 0.0_dp) reference = 1.0_dp
         if (allocated(self%row_scale)) then
            if (size(self%row_scale) /= nr) deallocate (self%row_scale)
         end if
         if (.not. allocated(self%row_scale)) allocate (self%row_scale(nr))
         allocate (keep_row(self%nc))
         keep_row = 0
         if (self%nc > 0) then
            row_max = Phi%row_abs_max()
            do i = 1, nr
               keep_row(self%active(i)) = i
               self%row_scale(i) = 1.0_dp
               if (row_max(self%active(i)) > 0.0_dp) self%row_scale(i) = reference / &
                  row_max(self%active(i))
            end do
         end if
         ! Index 2 (theory.md 4.6): the velocity rows, a copy of S Phi_q's, the zero diagonal
         ! of the nu rows besides the multipliers', then nu's columns (index2_sparse_triplets)
         order = n + nr
         if (allocated(trial%g)) order = n + 2 * nr
         capacity = A%entries() + order - n
         if (self%nc > 0) capacity = capacity + 3 * Phi%entries()
         allocate (irn(capacity), jcn(capacity), values(capacity))
         k = 0
         call A%triplets(0, 0, irn, jcn, values, k)
         if (self%nc > 0) then
            call Phi%triplets(n, 0, irn, jcn, values, k, keep_row, self%row_scale)
            call Phi%triplets(n, 0, irn, jcn, values, k, keep_row, self%row_scale, &
               transposed=.true.)
            if (order > n + nr) call Phi%triplets(n + nr, 0, irn, jcn, values, k, keep_row, &
               self%row_scale)
         end if
         do i = 1, order - n
            irn(k + i) = int(n + i, ip)
            jcn(k + i) = int(n + i, ip)
            values(k + i) = 0.0_dp
         end do
         k = k + order - n
      end associate
      if (order > n + nr) then
         call index2_sparse_triplets(self, h, trial, irn_nu, jcn_nu, values_nu)
         call self%sparse%factor(order, [irn(:k), irn_nu], [jcn(:k), jcn_nu], &
            [values(:k), values_nu], singular, error)
      else
         call self%sparse%factor(order, irn(:k), jcn(:k), values(:k), singular, error)
      end if
   end procedure sparse_assemble

   !> (generalized_alpha.f90, interface)
   module procedure noise_floor
      real(dp), allocatable :: u(:), noise(:), x(:), terms(:), size_inertia(:), &
         size_reaction(:), inertia(:), reaction(:), all_rows(:)
      real(dp) :: bh2, signum
      integer :: n, nr, i, pattern, order
      n = self%n
      nr = size(self%active)
      bh2 = self%beta * h**2
      ! Index 2 (theory.md 4.6): the velocity rows and nu's columns
      order = n + nr
      if (allocated(trial%g)) order = n + 2 * nr
      allocate (u(n), terms(n), noise(order), x(order), size_inertia(n), size_reaction(n), &
         inertia(n), reaction(n))
      u = epsilon(1.0_dp) * abs(trial%q)
      call trial_products(trial, .true., size_inertia, size_reaction)
      call trial_products(trial, .false., inertia, reaction)
      terms = size_inertia + size_reaction + abs(inertia + reaction - trial%r_q)
      if (allocated(self%constraint_floor)) deallocate (self%constraint_floor)
      allocate (self%constraint_floor(order - n))
      ! Index 2: the floor of the velocity rows, |Phi_q| eps |q'| beta h / gamma, after Phi's
      if (trial%sparse) then
         call self%sparse_K%matvec(u, x(:n), absolute=.true.)
         self%residual_floor = x(:n) + epsilon(1.0_dp) * terms
         allocate (all_rows(self%nc))
         if (self%nc > 0) call trial%Phi_sparse%matvec(u, all_rows, absolute=.true.)
         self%constraint_floor(:nr) = all_rows(self%active)
         if (order > n + nr) then
            call trial%Phi_sparse%matvec(epsilon(1.0_dp) * abs(trial%v), all_rows, &
               absolute=.true.)
            self%constraint_floor(nr + 1:) = trial%velocity_scale * all_rows(self%active)
         end if
      else
         self%residual_floor = matmul(abs(self%tangent_K), u) + epsilon(1.0_dp) * terms
         self%constraint_floor(:nr) = matmul(abs(trial%Phi_q(self%active, :)), u)
         if (order > n + nr) self%constraint_floor(nr + 1:) = trial%velocity_scale * &
            matmul(abs(trial%Phi_q(self%active, :)), epsilon(1.0_dp) * abs(trial%v))
      end if
      noise(:n) = bh2 * self%residual_floor
      do i = 1, order - n
         noise(n + i) = self%row_scale(mod(i - 1, nr) + 1) * self%constraint_floor(i)
      end do
      self%increment_floor = [(0.0_dp, i=1, n + nr)]
      do pattern = 1, 2
         do i = 1, order
            ! pattern 1: alternating signs; pattern 2: signs of sin(i^2) (no period)
            if (pattern == 1) then
               signum = merge(1.0_dp, -1.0_dp, mod(i, 2) == 0)
            else
               signum = merge(1.0_dp, -1.0_dp, sin(real(i, dp)**2) >= 0.0_dp)
            end if
            x(i) = signum * noise(i)
         end do
         call solve_iteration(self, x, error)
         if (allocated(error)) return
         if (order > n + nr) x(:n) = index2_increment(self, trial, x)
         self%increment_floor = max(self%increment_floor, abs(x(:n + nr)))
      end do
      if (nr > 0) self%increment_floor(n + 1:) = self%row_scale * &
         self%increment_floor(n + 1:) / bh2
      self%h_floor = h
   end procedure noise_floor

   !> (generalized_alpha.f90, interface)
   module procedure solve_iteration
      logical :: singular
      if (size(x) < self%settings%sparse_threshold) then
         call kkt_solve(self%lu, self%pivots, x)
         return
      end if
      if (.not. associated(self%sparse)) allocate (self%sparse)
      if (.not. self%sparse%is_factorised()) then
         ! after import_state (factor is called first there: h_factored < 0); a guard
         call self%sparse%refactor(singular, error)
         if (.not. allocated(error) .and. singular) call fatal_error(error, &
            FFRF_NUMERIC_ERROR, 'the restored iteration matrix is singular')
         if (allocated(error)) return
      end if
      call self%sparse%solve(x, error)
   end procedure solve_iteration

   !> (generalized_alpha.f90, interface)
   module procedure trial_products
      if (trial%sparse) then
         if (absolute) then
            call trial%M_sparse%matvec(abs(trial%qdd), inertia, absolute=.true.)
            call trial%Phi_sparse%matvec(abs(trial%lambda), reaction, transposed=.true., &
               absolute=.true.)
         else
            call trial%M_sparse%matvec(trial%qdd, inertia)
            call trial%Phi_sparse%matvec(trial%lambda, reaction, transposed=.true.)
         end if
      else if (absolute) then
         inertia = matmul(abs(trial%M), abs(trial%qdd))
         reaction = matmul(abs(trial%lambda), abs(trial%Phi_q))
      else
         inertia = matmul(trial%M, trial%qdd)
         reaction = matmul(trial%lambda, trial%Phi_q)
      end if
   end procedure trial_products

end submodule ffrf_mbs_generalized_alpha_linear
