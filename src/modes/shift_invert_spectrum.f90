!> The driver of ffrf_modes_shift_invert (theory.md 5.6-5.8): known null vectors deflated, the
!> eigen solve in one or more shift windows, the Sturm counts that prove each window complete,
!> and the recovery when a count comes out short.
!>
!> Windows: the first one at sigma; each further one at the upper boundary of the previous one,
!> a shift placed in a gap of the computed spectrum (never inside a multiplet), factorised once
!> and used twice: its inertia closes the window below it, its factors open the window above
!> it. Everything below a boundary is known and proven, and the vectors of the two windows
!> below it are deflated, so the eigenpairs nearest the new shift are the next ones up.
!>
!> A window [b, s) is proven when count(s) - count(b) (the inertia of the KKT matrix at both
!> ends, deflated null vectors included) equals the eigenpairs found in it plus the deflated
!> null vectors in it. A short count means a missed eigenvalue (the single-vector Lanczos
!> finds one vector of a multiple eigenvalue, then needs rounding to find the others): the
!> recovery solves again at s with everything known deflated, with more vectors each round
!> and the other eigensolver from the third round on.
!>
!> This submodule holds the state of the known pairs and the helpers; solve_shift_invert itself
!> is in its child ffrf_modes_shift_invert_windows (shift_invert_windows.f90).
submodule (ffrf_modes_shift_invert) ffrf_modes_shift_invert_spectrum
   use ffrf_core_error, only: fatal_error, add_context, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: wall_time
   use ffrf_core_kinds, only: pi
   use ffrf_la_sparse, only: csr_matvec, csr_matmat
   use ffrf_modes_block_krylov, only: m_cholesky_qr2
   implicit none

   character(len=*), parameter :: stage = 'modes'
   !> The Sturm shift sits this far above the highest returned eigenvalue, relative to its
   !> distance from sigma: far enough that the inertia there is exact (an eigenvalue is counted
   !> on the wrong side only within about eps lambda_max of s), near enough that an eigenvalue
   !> between the top and s is rare (it is then found by a recovery)
   real(dp), parameter :: STURM_MARGIN = 1.0e-4_dp
   !> Recovery rounds for one window before giving up
   integer, parameter :: MAX_RECOVERIES = 5

   !> The eigenpairs found so far: vectors as the eigensolver returned them, Rayleigh quotients
   !> and the window each came from.
   type :: known_t
      real(dp), allocatable :: z(:, :)
      real(dp), allocatable :: lambda(:)
      integer(ip), allocatable :: window(:)
      integer(ip) :: count = 0
   end type known_t

contains

   !> ARPACK's basis for a single window of num_modes (the log line), capped by the dimension,
   !> by the rule of the eigen solves (arpack_basis_size).
   pure integer(ip) function single_window_ncv(options, dimension) result(ncv)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: dimension
      integer(ip) :: nev
      nev = options%num_modes
      if (options%max_eigenvalue > 0.0_dp .or. nev > options%window_size) &
         nev = min(nev, options%window_size)
      ncv = arpack_basis_size(options, nev, dimension)
   end function single_window_ncv

   !> Boundary between pairs jb and jb + 1 of the ascending lambda: the widest relative gap from
   !> pair jmin on; never inside a multiplet.
   subroutine boundary(lambda, jmin, jb, error)
      real(dp), intent(in) :: lambda(:)
      integer(ip), intent(in) :: jmin
      integer(ip), intent(out) :: jb
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: gap, best
      integer(ip) :: j, first
      jb = 0
      best = 0.0_dp
      do first = jmin, 1, -1
         do j = first, int(size(lambda), ip) - 1
            gap = (lambda(j + 1) - lambda(j)) / max(abs(lambda(j + 1)), abs(lambda(j)), &
               tiny(1.0_dp))
            if (gap > best) then
               best = gap
               jb = j
            end if
         end do
         if (best > 4.0_dp * MULTIPLET_RTOL) return
      end do
      call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: no gap to place a window ' // &
         'boundary among ' // to_str(size(lambda)) // ' eigenvalues ' // &
         to_str(lambda(1), 8) // ' .. ' // to_str(lambda(size(lambda)), 8) // &
         ': they form one multiplet wider than a window')
   end subroutine boundary

   !> The null vectors given, M-orthonormalised, with their M products and Rayleigh quotients.
   subroutine null_vector_deflation(K, M, rigid, deflation, result, log, error)
      type(csr_t), intent(in) :: K, M
      real(dp), intent(in) :: rigid(:, :)
      type(deflation_t), intent(out) :: deflation
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: kx(:)
      integer :: j
      deflation%X = rigid
      allocate (deflation%MX(size(rigid, 1), size(rigid, 2)))
      call csr_matmat(M, deflation%X, deflation%MX)
      call m_orthonormalise(deflation%X, deflation%MX, error)
      if (allocated(error)) then
         call add_context(error, 'shift-invert: the rigid modes given are linearly dependent')
         return
      end if
      allocate (kx(size(rigid, 1)), result%rigid_eigenvalues(size(rigid, 2)))
      do j = 1, size(rigid, 2)
         call csr_matvec(K, deflation%X(:, j), kx)
         result%rigid_eigenvalues(j) = dot_product(deflation%X(:, j), kx)
      end do
      call log%info(stage, to_str(size(rigid, 2)) // ' rigid-body modes deflated exactly ' // &
         '(Rayleigh quotients |x^T K x| <= ' // to_str(maxval(abs(result%rigid_eigenvalues)), &
         2) // ', round-off of 0): never searched for')
   end subroutine null_vector_deflation

   !> The deflated subspace of a window: the null vectors and the known pairs from window
   !> `first_window` on, M-orthonormalised together (Cholesky QR twice; the null vectors,
   !> first and orthonormal already, keep their span).
   subroutine deflation_of(M, null_vectors, known, first_window, deflation, error)
      type(csr_t), intent(in) :: M
      type(deflation_t), intent(in) :: null_vectors
      type(known_t), intent(in) :: known
      integer(ip), intent(in) :: first_window
      type(deflation_t), intent(out) :: deflation
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: columns(:)
      integer(ip) :: i, d0, n, stat
      if (known%count > 0) then
         columns = pack([(i, i=1, known%count)], known%window(1:known%count) >= first_window)
      else
         allocate (columns(0))
      end if
      d0 = 0
      if (allocated(null_vectors%X)) d0 = int(size(null_vectors%X, 2), ip)
      if (d0 + size(columns) == 0) return
      n = int(M%num_rows, ip)
      allocate (deflation%X(n, d0 + size(columns)), deflation%MX(n, d0 + size(columns)), &
         stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate the ' // &
            to_str(d0 + size(columns)) // ' deflated vectors of ' // to_str(n))
         return
      end if
      if (d0 > 0) then
         deflation%X(:, 1:d0) = null_vectors%X
         deflation%MX(:, 1:d0) = null_vectors%MX
      end if
      if (size(columns) == 0) return
      deflation%X(:, d0 + 1:) = known%z(:, columns)
      call csr_matmat(M, deflation%X(:, d0 + 1:), deflation%MX(:, d0 + 1:))
      call m_orthonormalise(deflation%X, deflation%MX, error)
      if (allocated(error)) call add_context(error, 'shift-invert: the known modes to deflate')
   end subroutine deflation_of

   !> X = Q R with Q^T M Q = I (Cholesky QR twice); MX = M X on entry, M Q on exit.
   subroutine m_orthonormalise(X, MX, error)
      real(dp), intent(inout) :: X(:, :), MX(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: info
      call m_cholesky_qr2(X, MX, info)
      if (info /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, 'M-Gram matrix not positive ' // &
         'definite at column ' // to_str(info) // ' (dependent vectors)')
   end subroutine m_orthonormalise

   !> Room for `capacity` pairs of size n.
   subroutine grow(known, n, capacity, error)
      type(known_t), intent(inout) :: known
      integer(ip), intent(in) :: n, capacity
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: z(:, :), lambda(:)
      integer(ip), allocatable :: window(:)
      integer :: stat
      if (allocated(known%z)) then
         if (size(known%z, 2) >= capacity) return
      end if
      allocate (z(n, capacity), lambda(capacity), window(capacity), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate ' // &
            to_str(capacity) // ' eigenvectors of ' // to_str(n))
         return
      end if
      if (known%count > 0) then
         z(:, 1:known%count) = known%z(:, 1:known%count)
         lambda(1:known%count) = known%lambda(1:known%count)
         window(1:known%count) = known%window(1:known%count)
      end if
      call move_alloc(z, known%z)
      call move_alloc(lambda, known%lambda)
      call move_alloc(window, known%window)
   end subroutine grow

   !> Append pairs (columns of z, lambda) found in `window`.
   subroutine add_known(known, z, lambda, window, error)
      type(known_t), intent(inout) :: known
      real(dp), intent(in) :: z(:, :), lambda(:)
      integer(ip), intent(in) :: window
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: m, first
      m = int(size(lambda), ip)
      if (m == 0) return
      if (known%count + m > size(known%z, 2)) then
         call grow(known, int(size(z, 1), ip), max(2 * int(size(known%z, 2), ip), &
            known%count + m), error)
         if (allocated(error)) return
      end if
      first = known%count + 1
      known%z(:, first:first + m - 1) = z
      known%lambda(first:first + m - 1) = lambda
      known%window(first:first + m - 1) = window
      known%count = known%count + m
   end subroutine add_known

   !> Statistics of the eigen shift's factorisation (the slicing path's symmetric indefinite one).
   subroutine record_factors(solver, count, result)
      type(mumps_solver_t), intent(in) :: solver
      integer(ip), intent(in) :: count
      type(eigen_result_t), intent(inout) :: result
      result%sym = solver%sym
      result%factor_entries = solver%factor_entries
      result%num_negative_pivots = solver%num_negative_pivots
      result%factor_memory_mb = solver%memory_used_mb
      result%compressed_factor_entries = solver%compressed_factor_entries
      result%time_factorisation = solver%time_factorisation
      result%num_below_shift = count
   end subroutine record_factors

   !> ", 6 of them the deflated null vectors at 0" or ''.
   function rigid_text(num_rigid) result(text)
      integer(ip), intent(in) :: num_rigid
      character(len=:), allocatable :: text
      text = ''
      if (num_rigid > 0) text = ', ' // to_str(num_rigid) // ' of them the deflated ' // &
         'rigid-body modes at 0 Hz'
   end function rigid_text

   !> Frequency (Hz) of an eigenvalue in (rad/s)^2, negative for a negative one.
   pure real(dp) function frequency_of(lambda) result(hz)
      real(dp), intent(in) :: lambda
      hz = sign(sqrt(abs(lambda)), lambda) / (2.0_dp * pi)
   end function frequency_of

end submodule ffrf_modes_shift_invert_spectrum
