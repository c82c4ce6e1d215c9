!> Spectra you can trust (issue 22; theory.md 5.6-5.8) on grids of springs and masses whose
!> spectra are known in closed form, with exact multiplicities by symmetry:
!>
!>     lambda = (k/m) sum_d 4 sin^2(i_d pi / (2 (n_d + 1))),  i_d = 1..n_d   (walls on all sides)
!>     lambda = (k/m) sum_d 4 sin^2(i_d pi / (2 n_d)),        i_d = 0..n_d-1 (free: Neumann)
!>
!> A cube grid has triplets (i, i, j) and sextets (i, j, k) that are exact in floating point up
!> to round-off (the matrices are symmetric under permuting the axes), a square grid pairs.
!> Single-vector Lanczos sees one vector of a multiple eigenvalue in exact arithmetic and finds
!> the others only through rounding: the Sturm check must make the result complete.
!> Tolerances: eigenvalues 1e-10 relative (round-off eps lambda_max / lambda of the Rayleigh
!> quotients is below 1e-13 here), residuals 1e-10, M-orthonormality 1e-12 within one window and
!> 1e-9 across windows (eigenvectors of different windows are orthogonal to residual / gap; the
!> vectors of the two windows below are deflated, so the gaps are at least a window wide).
module test_modes_spectrum
   use ffrf_core_kinds, only: dp, ip, pi
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: logger_t, LOG_QUIET, LOG_INFO
   use ffrf_la_sparse, only: csr_t, csr_from_coo
   use ffrf_modes_shift_invert, only: eigen_options_t, eigen_result_t, solve_shift_invert, &
      MULTIPLET_RTOL
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check, report
   use ffrf_test_spring_chain, only: no_constraints, spring, mass
   implicit none
   private
   public :: collect_modes_spectrum

   real(dp), parameter :: rtol_lambda = 1.0e-10_dp, max_residual = 1.0e-10_dp, &
                          max_orthonormality = 1.0e-12_dp, max_orthonormality_windows = 1.0e-9_dp
   character(len=6), parameter :: solvers(2) = ['arpack', 'block ']

contains

   subroutine collect_modes_spectrum(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('cube_grid_multiplets', test_cube_grid_multiplets), &
         new_unittest('num_modes_cuts_a_multiplet', test_cut_multiplet), &
         new_unittest('free_grid_deflated', test_free_grid_deflated), &
         new_unittest('windows_through_pairs', test_windows_through_pairs), &
         new_unittest('bound_on_a_pair', test_bound_on_pair), &
         new_unittest('positive_shift_on_a_pair', test_shift_on_pair), &
         new_unittest('many_modes_windows', test_many_modes_windows), &
         new_unittest('sturm_check_off', test_sturm_off)]
   end subroutine collect_modes_spectrum

   !> 10 x 10 x 10 grid with walls (n = 1000): the lowest modes up to the end of the multiplet
   !> holding the 30th (singles, triplets, sextets) with ARPACK and the block method: every one
   !> to 1e-10, every member of every multiplet, the Sturm count equal to the modes returned.
   !> Without the check (reported, not asserted) the single-vector Lanczos may miss members.
   subroutine test_cube_grid_multiplets(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result, unchecked
      real(dp), allocatable :: exact(:)
      integer(ip) :: nev, s
      call grid([10_ip, 10_ip, 10_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      nev = multiplet_end(exact, 30_ip)
      call report('lowest ' // to_str(nev) // ' of the cube grid: multiplicities ' // &
         multiplicities(exact(1:nev)))
      do s = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=-0.1_dp * exact(1), &
            eigensolver=solvers(s)), result, error)
         if (allocated(error)) return
         call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=-0.1_dp * exact(1), &
            eigensolver=solvers(s), sturm_check=.false.), unchecked, error)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': ' // to_str(result%num_recoveries) // &
            ' recoveries, Sturm count ' // to_str(result%sturm_count) // ' at ' // &
            to_str(result%sturm_shift, 8) // '; without the check ' // &
            to_str(missing(unchecked%eigenvalues, exact(1:nev))) // ' of ' // to_str(nev) // &
            ' missed (max rel. error ' // to_str(maxval(abs(unchecked%eigenvalues - &
            exact(1:nev)) / exact(1:nev)), 2) // ')')
         call check_spectrum(trim(solvers(s)), result, exact(1:nev), max_orthonormality, error)
         if (allocated(error)) return
         call check(error, trim(solvers(s)) // ': Sturm count ' // to_str(result%sturm_count) &
            // ' = ' // to_str(nev) // ' returned', result%sturm_checked .and. &
            result%sturm_count == nev .and. result%sturm_shift > exact(nev) .and. &
            result%sturm_shift < exact(nev + 1))
         if (allocated(error)) return
      end do
   end subroutine test_cube_grid_multiplets

   !> num_modes ends on the first member of a triplet of the cube grid: the whole triplet is
   !> returned (num_multiplet_extra = 2), never one member of it.
   subroutine test_cut_multiplet(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: exact(:)
      integer(ip) :: first, last, s
      call grid([8_ip, 8_ip, 8_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      ! the first triplet: (1, 1, 2)
      first = 2
      last = multiplet_end(exact, first)
      call check(error, 'modes 2..4 form a triplet', last == 4)
      if (allocated(error)) return
      do s = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=first, sigma=-0.1_dp * exact(1), &
            eigensolver=solvers(s)), result, error)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': num_modes = ' // to_str(first) // ' returned ' // &
            to_str(result%num_modes) // ' (' // to_str(result%num_multiplet_extra) // &
            ' to complete the triplet), ' // to_str(result%num_recoveries) // ' recoveries')
         call check(error, trim(solvers(s)) // ': whole triplet returned', &
            result%num_multiplet_extra == last - first)
         if (allocated(error)) return
         call check_spectrum(trim(solvers(s)), result, exact(1:last), max_orthonormality, error)
         if (allocated(error)) return
      end do
   end subroutine test_cut_multiplet

   !> Free (Neumann) 13 x 12 grid: the constant vector is its null vector; deflated (`rigid`),
   !> it is never returned, and num_modes = 1, 2, 3 give the first flexible modes of a 12-mode
   !> run (1e-9, the issue's bound) and of the closed form (1e-10), with both eigensolvers; the
   !> Sturm count includes the deflated null vector.
   subroutine test_free_grid_deflated(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result, reference
      real(dp), allocatable :: exact(:), rigid(:, :)
      integer(ip) :: s, nev
      call grid([13_ip, 12_ip, 1_ip], .false., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      allocate (rigid(K%num_rows, 1), source=1.0_dp)
      do s = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=12, sigma=-0.1_dp * exact(2), &
            eigensolver=solvers(s)), reference, error, rigid)
         if (allocated(error)) return
         call check_spectrum(trim(solvers(s)) // ', 12 modes', reference, exact(2:13), &
            max_orthonormality, error)
         if (allocated(error)) return
         do nev = 1, 3
            call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=-0.1_dp * exact(2), &
               eigensolver=solvers(s)), result, error, rigid)
            if (allocated(error)) return
            call check_close(error, trim(solvers(s)) // ', num_modes = ' // to_str(nev) // &
               ': max rel. difference to the 12-mode run', maxval(abs(result%eigenvalues - &
               reference%eigenvalues(1:nev)) / reference%eigenvalues(1:nev)), 0.0_dp, &
               atol=1.0e-9_dp)
            if (allocated(error)) return
            call check_spectrum(trim(solvers(s)) // ', num_modes = ' // to_str(nev), result, &
               exact(2:nev + 1), max_orthonormality, error)
            if (allocated(error)) return
            call check(error, trim(solvers(s)) // ': null vector deflated and counted ' // &
               '(Sturm ' // to_str(result%sturm_count) // ' = ' // to_str(nev) // ' + 1)', &
               result%num_rigid == 1 .and. result%sturm_count == nev + 1 .and. &
               abs(result%rigid_eigenvalues(1)) <= 1.0e-9_dp * exact(2))
            if (allocated(error)) return
         end do
         call report(trim(solvers(s)) // ': null vector x^T K x = ' // &
            to_str(result%rigid_eigenvalues(1), 2) // ' (lambda_2 = ' // to_str(exact(2), 6) // &
            '), num_modes 1..3 agree with the 12-mode run')
      end do
   end subroutine test_free_grid_deflated

   !> Square 24 x 24 grid with walls (pairs (i, j), (j, i)): every mode below a bound in a gap
   !> after the 60th, by windows of 3 and 5 modes whose natural ends fall inside pairs: exactly
   !> the closed-form set below the bound (count and values), no duplicate, every window proven.
   subroutine test_windows_through_pairs(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: exact(:)
      real(dp) :: bound
      integer(ip) :: nev, s, w
      integer(ip), parameter :: windows(2) = [3_ip, 5_ip]
      call grid([24_ip, 24_ip, 1_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      nev = multiplet_end(exact, 60_ip)
      bound = 0.5_dp * (exact(nev) + exact(nev + 1))
      do s = 1, 2
         do w = 1, 2
            call solve(K, M, C, eigen_options_t(num_modes=10000, sigma=-0.1_dp * exact(1), &
               eigensolver=solvers(s), max_eigenvalue=bound, window_size=windows(w)), result, &
               error)
            if (allocated(error)) return
            call report(trim(solvers(s)) // ', windows of ' // to_str(windows(w)) // ': ' // &
               to_str(result%num_modes) // ' modes in ' // to_str(result%num_windows) // &
               ' windows, ' // to_str(result%num_count_factorisations) // ' count ' // &
               'factorisations, ' // to_str(result%num_recoveries) // ' recoveries, ' // &
               'M-orthonormality ' // to_str(result%orthonormality_error, 2))
            call check(error, 'several windows', result%num_windows >= nev / (windows(w) + 2))
            if (allocated(error)) return
            call check_spectrum(trim(solvers(s)) // ', windows of ' // to_str(windows(w)), &
               result, exact(1:nev), max_orthonormality_windows, error)
            if (allocated(error)) return
            call check(error, 'proven at the bound: Sturm count ' // &
               to_str(result%sturm_count), result%sturm_checked .and. &
               result%sturm_count == nev .and. result%sturm_shift == bound)
            if (allocated(error)) return
         end do
      end do
   end subroutine test_windows_through_pairs

   !> The bound exactly on a pair's eigenvalue (the first pair of the square grid): the
   !> factorisation there is singular, the bound moves up inside the gap, the pair is returned
   !> whole.
   subroutine test_bound_on_pair(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: exact(:)
      integer(ip) :: s
      call grid([16_ip, 16_ip, 1_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      call check(error, 'modes 2 and 3 are a pair', multiplet_end(exact, 2_ip) == 3)
      if (allocated(error)) return
      do s = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=10000, sigma=-0.1_dp * exact(1), &
            eigensolver=solvers(s), max_eigenvalue=exact(2)), result, error)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': bound on lambda_2 = lambda_3 = ' // &
            to_str(exact(2), 12) // ': ' // to_str(result%num_modes) // ' modes, proven at ' // &
            to_str(result%sturm_shift, 12))
         call check_spectrum(trim(solvers(s)), result, exact(1:3), max_orthonormality, error)
         if (allocated(error)) return
      end do
   end subroutine test_bound_on_pair

   !> A positive shift exactly on a pair (lambda_5 = lambda_6 of the 16 x 16 grid): moved off it
   !> once, the 6 nearest modes (below and above it) against the closed form, proven between
   !> a count below the lowest and one above the highest.
   subroutine test_shift_on_pair(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: exact(:), nearest(:)
      integer(ip) :: s
      call grid([16_ip, 16_ip, 1_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      call check(error, 'modes 5 and 6 are a pair', multiplet_end(exact, 5_ip) == 6 .and. &
         exact(5) - exact(4) > 1.0e-3_dp * exact(5))
      if (allocated(error)) return
      do s = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=6, sigma=exact(5), &
            eigensolver=solvers(s)), result, error)
         if (allocated(error)) return
         nearest = nearest_whole(exact, result%shift, 6_ip)
         ! residual bound 1e-9 here: with the shift 1e-4 from a pair the far pairs are
         ! resolved only to the rounding level of the huge Ritz values next to the shift
         call report(trim(solvers(s)) // ': sigma = lambda_5 moved to ' // &
            to_str(result%shift, 12) // ' (' // to_str(result%num_factorisations) // &
            ' factorisations), ' // to_str(result%num_modes) // ' modes, proven in [' // &
            to_str(result%sturm_shift_low, 8) // ', ' // to_str(result%sturm_shift, 8) // ')')
         call check_spectrum(trim(solvers(s)), result, nearest, max_orthonormality, error, &
            residual_bound=1.0e-9_dp)
         if (allocated(error)) return
         call check(error, 'interval counts = modes returned', result%sturm_checked .and. &
            result%sturm_count - result%sturm_count_low == result%num_modes)
         if (allocated(error)) return
      end do
   end subroutine test_shift_on_pair

   !> 130 modes of the square grid by num_modes alone (windows of the default 50): the lowest
   !> 130 (ending at a multiplet) to 1e-10, proven.
   subroutine test_many_modes_windows(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: exact(:)
      integer(ip) :: nev, s
      call grid([30_ip, 30_ip, 1_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      nev = multiplet_end(exact, 130_ip)
      do s = 1, 2
         call solve(K, M, C, eigen_options_t(num_modes=nev, sigma=-0.1_dp * exact(1), &
            eigensolver=solvers(s)), result, error)
         if (allocated(error)) return
         call report(trim(solvers(s)) // ': ' // to_str(result%num_modes) // ' modes in ' // &
            to_str(result%num_windows) // ' windows, ' // to_str(result%num_solves) // &
            ' solves, M-orthonormality ' // to_str(result%orthonormality_error, 2))
         call check(error, 'windows used', result%num_windows >= 3)
         if (allocated(error)) return
         call check_spectrum(trim(solvers(s)), result, exact(1:nev), &
            max_orthonormality_windows, error)
         if (allocated(error)) return
         call check(error, 'proven: Sturm count ' // to_str(result%sturm_count), &
            result%sturm_checked .and. result%sturm_count == nev)
         if (allocated(error)) return
      end do
   end subroutine test_many_modes_windows

   !> sturm_check = .false.: no count factorisation, the result says it is unproven.
   subroutine test_sturm_off(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: K, M, C
      type(eigen_result_t) :: result
      real(dp), allocatable :: exact(:)
      call grid([12_ip, 11_ip, 1_ip], .true., K, M, exact, error)
      if (allocated(error)) return
      call no_constraints(K%num_rows, C)
      call solve(K, M, C, eigen_options_t(num_modes=5, sigma=-0.1_dp * exact(1), &
         sturm_check=.false.), result, error)
      if (allocated(error)) return
      call check(error, 'no Sturm check made', .not. result%sturm_checked .and. &
         result%num_count_factorisations == 0)
      if (allocated(error)) return
      call check_spectrum('unchecked', result, exact(1:5), max_orthonormality, error)
   end subroutine test_sturm_off

   ! ---------------------------------------------------------------------------------------------

   !> solve_shift_invert with a quiet logger.
   subroutine solve(K, M, C, options, result, error, rigid)
      type(csr_t), intent(in) :: K, M, C
      type(eigen_options_t), intent(in) :: options
      type(eigen_result_t), intent(out) :: result
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: rigid(:, :)
      type(logger_t) :: log
      log%level = LOG_QUIET
      if (verbose()) log%level = LOG_INFO
      call solve_shift_invert(K, M, C, options, result, log, error, rigid=rigid)
   end subroutine solve

   !> FFRF_TEST_VERBOSE set: the solver's log on standard output.
   logical function verbose()
      integer :: length
      call get_environment_variable('FFRF_TEST_VERBOSE', length=length)
      verbose = length > 0
   end function verbose

   !> Eigenvalues against `exact` (rtol 1e-10), residuals <= 1e-10, M-orthonormality.
   subroutine check_spectrum(label, result, exact, orthonormality, error, residual_bound)
      character(len=*), intent(in) :: label
      type(eigen_result_t), intent(in) :: result
      real(dp), intent(in) :: exact(:), orthonormality
      type(error_t), allocatable, intent(out) :: error
      real(dp), intent(in), optional :: residual_bound
      real(dp) :: bound
      integer :: j
      bound = max_residual
      if (present(residual_bound)) bound = residual_bound
      call check(error, label // ': ' // to_str(result%num_modes) // ' modes returned, ' // &
         'expected ' // to_str(size(exact)), result%num_modes == size(exact))
      if (allocated(error)) return
      do j = 1, size(exact)
         call check_close(error, label // ': lambda_' // to_str(j), result%eigenvalues(j), &
            exact(j), rtol=rtol_lambda)
         if (allocated(error)) return
      end do
      call check_close(error, label // ': max residual', maxval(result%residuals), 0.0_dp, &
         atol=bound)
      if (allocated(error)) return
      call check_close(error, label // ': M-orthonormality', result%orthonormality_error, &
         0.0_dp, atol=orthonormality)
   end subroutine check_spectrum

   !> Grid of n(1) x n(2) x n(3) masses m on springs k between neighbours (and to walls on every
   !> side when `walls`), and its closed-form eigenvalues, ascending.
   subroutine grid(n, walls, K, M, exact, error)
      integer(ip), intent(in) :: n(3)
      logical, intent(in) :: walls
      type(csr_t), intent(out) :: K, M
      real(dp), allocatable, intent(out) :: exact(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:), s(:, :)
      integer(ip) :: i, j, l, p, d, total, e, neighbours
      integer(ip) :: idx(3), step(3)
      total = product(n)
      step = [1_ip, n(1), n(1) * n(2)]
      allocate (rows(0), cols(0), vals(0))
      do l = 1, n(3)
         do j = 1, n(2)
            do i = 1, n(1)
               idx = [i, j, l]
               p = i + n(1) * (j - 1) + n(1) * n(2) * (l - 1)
               neighbours = 0
               do d = 1, 3
                  if (n(d) == 1) cycle
                  if (walls) then
                     neighbours = neighbours + 2
                  else
                     if (idx(d) > 1) neighbours = neighbours + 1
                     if (idx(d) < n(d)) neighbours = neighbours + 1
                  end if
                  if (idx(d) < n(d)) then
                     rows = [rows, p, p + step(d)]
                     cols = [cols, p + step(d), p]
                     vals = [vals, -spring, -spring]
                  end if
               end do
               rows = [rows, p]
               cols = [cols, p]
               vals = [vals, neighbours * spring]
            end do
         end do
      end do
      call csr_from_coo(total, total, rows, cols, vals, K, error)
      if (allocated(error)) return
      call csr_from_coo(total, total, [(i, i=1, total)], [(i, i=1, total)], &
         [(mass, i=1, total)], M, error)
      if (allocated(error)) return
      ! closed form: one chain factor per dimension
      allocate (s(maxval(n), 3), source=0.0_dp)
      do d = 1, 3
         do i = 1, n(d)
            if (n(d) == 1) then
               s(i, d) = 0.0_dp
            else if (walls) then
               s(i, d) = 4.0_dp * sin(i * pi / (2.0_dp * (n(d) + 1)))**2
            else
               s(i, d) = 4.0_dp * sin((i - 1) * pi / (2.0_dp * n(d)))**2
            end if
         end do
      end do
      allocate (exact(total))
      e = 0
      do l = 1, n(3)
         do j = 1, n(2)
            do i = 1, n(1)
               e = e + 1
               exact(e) = spring / mass * (s(i, 1) + s(j, 2) + s(l, 3))
            end do
         end do
      end do
      call sort(exact)
   end subroutine grid

   !> Index of the last member of the multiplet holding exact(j) (ascending exact).
   pure integer(ip) function multiplet_end(exact, j) result(last)
      real(dp), intent(in) :: exact(:)
      integer(ip), intent(in) :: j
      last = j
      do while (last < size(exact))
         if (exact(last + 1) - exact(last) > MULTIPLET_RTOL * exact(last + 1)) exit
         last = last + 1
      end do
   end function multiplet_end

   !> "1 3 3 1 6 ..." the sizes of the multiplets of an ascending list.
   function multiplicities(values) result(text)
      real(dp), intent(in) :: values(:)
      character(len=:), allocatable :: text
      integer(ip) :: j, last
      text = ''
      j = 1
      do while (j <= size(values))
         last = multiplet_end(values, j)
         text = text // ' ' // to_str(last - j + 1)
         j = last + 1
      end do
   end function multiplicities

   !> Members of exact not matched (1e-10) by a value of found (with multiplicity).
   function missing(found, exact) result(num)
      real(dp), intent(in) :: found(:), exact(:)
      integer :: num
      logical, allocatable :: used(:)
      integer :: i, j
      allocate (used(size(found)), source=.false.)
      num = 0
      do i = 1, size(exact)
         do j = 1, size(found)
            if (.not. used(j) .and. abs(found(j) - exact(i)) <= 1.0e-10_dp * exact(i)) then
               used(j) = .true.
               exit
            end if
         end do
         if (j > size(found)) num = num + 1
      end do
   end function missing

   !> The `count` values nearest sigma, completed to whole multiplets, ascending.
   function nearest_whole(values, sigma, count) result(nearest)
      real(dp), intent(in) :: values(:), sigma
      integer(ip), intent(in) :: count
      real(dp), allocatable :: nearest(:)
      logical, allocatable :: taken(:)
      integer :: j, best
      allocate (taken(size(values)), source=.false.)
      do j = 1, count
         best = minloc(abs(values - sigma), dim=1, mask=.not. taken)
         taken(best) = .true.
      end do
      do j = 1, size(values)
         if (.not. taken(j) .and. any(taken .and. abs(values - values(j)) <= MULTIPLET_RTOL * &
             abs(values(j)))) taken(j) = .true.
      end do
      nearest = pack(values, taken)
   end function nearest_whole

   !> Ascending insertion sort.
   pure subroutine sort(a)
      real(dp), intent(inout) :: a(:)
      real(dp) :: x
      integer :: i, j
      do i = 2, size(a)
         x = a(i)
         j = i - 1
         do while (j >= 1)
            if (a(j) <= x) exit
            a(j + 1) = a(j)
            j = j - 1
         end do
         a(j + 1) = x
      end do
   end subroutine sort

end module test_modes_spectrum

program main_modes_spectrum
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_spectrum, only: collect_modes_spectrum
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_spectrum(tests)
   call run_suite('test_modes_spectrum', tests)
end program main_modes_spectrum
