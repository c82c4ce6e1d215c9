!> Implementation of the shift-invert solver of ffrf_modes_shift_invert, first part: the ARPACK
!> reverse communication loop and the block method on the current factors, the solver choice
!> and its workspace. Its children: shift_invert_factorise.f90 (KKT assembly, MUMPS
!> factorisation with the SPD/indefinite choice and shift retry) and shift_invert_pairs.f90
!> (normalisation and checks of the eigenpairs).
submodule (ffrf_modes_shift_invert) ffrf_modes_shift_invert_lanczos
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use ffrf_core_error, only: fatal_error, add_context, check_solution, FFRF_INPUT_ERROR, &
      FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_core_log, only: wall_time
   use ffrf_core_memory, only: resident_memory_mb
   use ffrf_core_interrupt, only: interrupt_t
   use ffrf_core_posix, only: signal_test_point
   use ffrf_la_sparse, only: csr_add, csr_upper_coo, csr_matvec, csr_row_gram
   use ffrf_la_mumps, only: mumps_solver_t, mumps_ordering_name, MUMPS_SYM_SPD, &
      MUMPS_SYM_INDEFINITE
   use ffrf_la_arpack, only: dsaupd, dseupd
   use ffrf_la_parpack, only: pdsaupd, pdseupd
   use ffrf_core_parallel, only: parallel_t, FFRF_MPI_BUILD, solver_communicator
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_ARPACK
   use ffrf_la_lapack, only: dgemm, dposv
   use ffrf_modes_block_krylov, only: block_krylov_settings_t, block_krylov_stats_t, &
      block_krylov_eigen, default_block_settings
   implicit none

   character(len=*), parameter :: stage = 'modes'

contains

   !> Stable insertion sort (a few dozen values; module header of ffrf_modes_shift_invert).
   module procedure ascending_order
      integer :: i, j
      order = [(int(j, ip), j=1, size(values))]
      do j = 2, size(values)
         i = j
         do while (i > 1)
            if (values(order(i - 1)) <= values(order(i))) exit
            order([i - 1, i]) = order([i, i - 1])
            i = i - 1
         end do
      end do
   end procedure ascending_order

   !> MB of the eigensolver's vectors while the factors live: ARPACK's basis (ncv), workd (3),
   !> resid, the Ritz vectors and the right-hand side; the block method's V and M V (basis +
   !> block each), the block, its M product, the right-hand sides and their copies in the
   !> solve (5 blocks) and the Ritz vectors. Those of one window (nev = min(num_modes,
   !> window_size)); with windows the deflated vectors and their M products on top (the six
   !> rigid ones and two windows). The returned vectors of a sliced run are not counted.
   !> MPI build, ARPACK path (PARPACK): the basis, workd, resid and the Ritz vectors' rows are
   !> a rank's share (1 / num_ranks of them); the gathered Ritz vectors, x and the right-hand
   !> side are whole on every rank.
   pure function eigen_workspace_mb(options, n, nc, ranks) result(mb)
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: n, nc
      type(parallel_t), intent(in) :: ranks
      integer(i8) :: mb, columns
      integer(ip) :: nev
      type(block_krylov_settings_t) :: settings
      logical :: windows
      windows = options%max_eigenvalue > 0.0_dp .or. options%num_modes > options%window_size
      nev = options%num_modes
      if (windows) nev = min(options%num_modes, options%window_size) + window_guard(options)
      if (eigensolver_of(options, n, nc) == 'block') then
         settings = default_block_settings(nev, options%ncv, n - nc)
         columns = 2 * (settings%max_basis + settings%block_size) + 5 * settings%block_size + &
            nev
      else if (FFRF_MPI_BUILD) then
         ! the distributed columns of every rank together, as a whole-column count per rank
         columns = (arpack_basis_size(options, nev, n - nc) + 4 + nev + ranks%num_ranks - 1) &
            / ranks%num_ranks + nev + 2
      else
         columns = arpack_basis_size(options, nev, n - nc) + 6 + nev
      end if
      if (windows) columns = columns + 2 * (6 + 2 * nev)
      mb = (8_i8 * int(n + nc, i8) * columns + 1048575_i8) / 1048576_i8
   end function eigen_workspace_mb

   !> ARPACK's ncv for nev wanted pairs (module header of ffrf_modes_shift_invert).
   module procedure arpack_basis_size
      if (options%ncv > nev .or. (options%ncv > 0 .and. nev == options%num_modes)) then
         ncv = options%ncv
      else
         ncv = max(2 * nev + 1, 20_ip)
      end if
      ncv = min(ncv, dimension)
   end procedure arpack_basis_size

   !> Guard eigenpairs computed above a window so that its upper boundary can sit in a gap of
   !> the spectrum: a tenth of the window, at least 2.
   pure integer(ip) function window_guard(options) result(guard)
      type(eigen_options_t), intent(in) :: options
      guard = max(2_ip, options%window_size / 10)
   end function window_guard

   !> 'block' for eigensolver = 'block', or 'auto' on a constrained dimension of
   !> AUTO_BLOCK_MIN_DOFS or more; else 'arpack'.
   module procedure eigensolver_of
      select case (options%eigensolver)
      case ('block')
         name = 'block'
      case ('arpack')
         name = 'arpack'
      case default
         name = merge('block ', 'arpack', n - nc >= AUTO_BLOCK_MIN_DOFS)
         name = trim(name)
      end select
   end procedure eigensolver_of

   !> One eigen solve on the current factors (module header of ffrf_modes_shift_invert).
   module procedure eigen_window
      real(dp), allocatable :: x(:), kx(:), mx(:), norms(:), raw(:, :)
      integer(ip), allocatable :: order(:)
      integer(i8) :: solves_before
      real(dp) :: time_before
      integer(ip) :: n, j, dimension, ncv
      type(block_krylov_settings_t) :: settings
      type(block_krylov_stats_t) :: stats
      n = M%num_rows
      solves_before = solver%num_solves
      time_before = solver%time_solve
      dimension = n - nc
      if (allocated(deflation%X)) dimension = dimension - int(size(deflation%X, 2), ip)
      ! 'block if possible' (a recovery): the block method when its sizes fit, else ARPACK;
      ! 'block' as asked refuses a problem too small for it (block_krylov_eigen's message)
      if (eigensolver == 'block' .or. (eigensolver == 'block if possible' .and. &
          block_fits(nev, options%ncv, dimension))) then
         ! block shift-invert Lanczos (ffrf_modes_block_krylov) on the KKT factors
         settings = default_block_settings(nev, options%ncv, dimension)
         result%eigensolver = 'block'
         result%block_size = settings%block_size
         result%ncv = settings%max_basis
         if (allocated(deflation%X)) then
            call block_krylov_eigen(M, nc, nev, settings, options%tolerance, &
               options%max_iterations, solver, z, stats, log, error, interrupt, deflation%X, &
               deflation%MX)
         else
            call block_krylov_eigen(M, nc, nev, settings, options%tolerance, &
               options%max_iterations, solver, z, stats, log, error, interrupt)
         end if
         result%num_iterations = result%num_iterations + stats%num_restarts
         result%num_block_solves = result%num_block_solves + stats%num_block_solves
      else
         ncv = arpack_basis_size(options, nev, dimension)
         if (ncv <= nev) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'shift-invert: ncv = ' // to_str(ncv) // &
               ' must exceed ' // to_str(nev) // ' wanted pairs; raise ncv (about twice the ' // &
               'wanted pairs, at most n - num_constraints = ' // to_str(dimension) // ')')
            return
         end if
         result%ncv = ncv
         ! ARPACK keeps its reverse-communication state in SAVEd variables: one eigenproblem at
         ! a time in the process (a serial section), so that distinct handles may run in threads
         call enter_serial_section(SECTION_ARPACK)
         call lanczos(M, options, nev, ncv, nc, sigma, solver, interrupt, deflation, z, result, &
            log, error)
         call leave_serial_section(SECTION_ARPACK)
      end if
      result%num_solves = result%num_solves + (solver%num_solves - solves_before)
      result%time_solves = result%time_solves + (solver%time_solve - time_before)
      if (allocated(error)) return
      if (allocated(deflation%X)) then
         ! what the last projection removes: the round-off the eigen loop let into the basis
         norms = [(norm2(z(:, j)), j=1, nev)]
         raw = z
         call project_deflation(deflation, z)
         call log%debug(stage, 'deflated components removed from the Ritz vectors: ' // &
            to_str(maxval([(norm2(raw(:, j) - z(:, j)) / max(norms(j), tiny(1.0_dp)), &
            j=1, nev)]), 2) // ' of their norm at most')
      end if
      ! Rayleigh quotients of normalised copies (z itself stays as the eigensolver returned it)
      allocate (x(n), kx(n), mx(n), lambda(nev))
      do j = 1, nev
         call csr_matvec(M, z(:, j), mx)
         call csr_matvec(K, z(:, j), kx)
         lambda(j) = dot_product(z(:, j), kx) / max(dot_product(z(:, j), mx), tiny(1.0_dp))
      end do
      order = ascending_order(lambda)
      lambda = lambda(order)
      z = z(:, order)
   end procedure eigen_window

   !> The block method's default sizes fit nev pairs in the dimension (else ARPACK is used).
   pure logical function block_fits(nev, basis, dimension)
      integer(ip), intent(in) :: nev, basis, dimension
      type(block_krylov_settings_t) :: settings
      settings = default_block_settings(nev, basis, dimension)
      block_fits = settings%block_size >= 1 .and. settings%max_basis >= nev + &
         settings%block_size .and. settings%kept >= nev .and. settings%kept + &
         settings%block_size <= settings%max_basis .and. settings%max_basis + &
         settings%block_size <= dimension
   end function block_fits

   !> y = y - X (M X)^T y, twice.
   module procedure project_deflation
      real(dp), allocatable :: coefficients(:, :)
      integer(ip) :: n, d, m, pass
      if (.not. allocated(deflation%X)) return
      n = int(size(y, 1), ip)
      d = int(size(deflation%X, 2), ip)
      m = int(size(y, 2), ip)
      if (d == 0 .or. m == 0) return
      allocate (coefficients(d, m))
      do pass = 1, 2
         call dgemm('T', 'N', d, m, n, 1.0_dp, deflation%MX, n, y, n, 0.0_dp, coefficients, d)
         call dgemm('N', 'N', n, m, d, -1.0_dp, deflation%X, n, coefficients, d, 1.0_dp, y, n)
      end do
   end procedure project_deflation

   !> y = y - X (M X)^T y for one vector, twice (the ARPACK loop).
   subroutine project_vector(deflation, y)
      type(deflation_t), intent(in) :: deflation
      real(dp), contiguous, intent(inout) :: y(:)
      real(dp), allocatable :: coefficients(:)
      integer(ip) :: n, d, pass
      n = int(size(y), ip)
      d = int(size(deflation%X, 2), ip)
      if (d == 0) return
      allocate (coefficients(d))
      do pass = 1, 2
         call dgemm('T', 'N', d, 1_ip, n, 1.0_dp, deflation%MX, n, y, n, 0.0_dp, coefficients, d)
         call dgemm('N', 'N', n, 1_ip, d, -1.0_dp, deflation%X, n, coefficients, d, 1.0_dp, y, n)
      end do
   end subroutine project_vector

   !> ARPACK dsaupd/dseupd, mode 3 with B = M, OP by KKT solves; Ritz vectors z (n x nev).
   !> Called inside the ARPACK serial section (eigen_window). The MPI build runs PARPACK
   !> (pdsaupd/pdseupd) on the solver's ranks: resid, the basis v, workd and the Ritz vectors
   !> are row-distributed (each rank its block of rows, parallel_t%row_block), PARPACK reduces
   !> with MPI_Allreduce; an OP or B product gathers x whole on every rank (n values), forms
   !> M x and solves with MUMPS's centralised right-hand side (rank 0) and broadcast solution,
   !> and keeps the rank's rows; z is gathered whole at the end (docs/mpi.md "MPI build and
   !> runs"). The sequential build calls ARPACK on the whole vectors, as before.
   subroutine lanczos(M, options, nev, ncv, nc, sigma, solver, interrupt, deflation, z, result, &
         log, error)
      type(csr_t), intent(in) :: M
      type(eigen_options_t), intent(in) :: options
      integer(ip), intent(in) :: nev, ncv, nc
      real(dp), intent(in) :: sigma
      type(mumps_solver_t), intent(inout) :: solver
      !> Checked before every solve
      type(interrupt_t), intent(in) :: interrupt
      !> Deflated subspace (rigid modes, modes of earlier windows); none when X is unallocated
      type(deflation_t), intent(in) :: deflation
      real(dp), allocatable, intent(out) :: z(:, :)
      type(eigen_result_t), intent(inout) :: result
      type(logger_t), intent(in) :: log
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: resid(:), v(:, :), workd(:), workl(:), rhs(:), d(:), x(:), &
         z_rows(:, :)
      logical, allocatable :: selected(:)
      integer(ip) :: iparam(11), ipntr(11), ido, info, lworkl, n, x0, y0, stat, rows
      integer :: first, last, comm, j
      real(dp) :: tol
      logical :: deflating, distributed
      type(parallel_t) :: ranks

      n = M%num_rows
      deflating = allocated(deflation%X)
      distributed = FFRF_MPI_BUILD
      ranks = solver%ranks()
      comm = solver_communicator(ranks)
      call ranks%row_block(int(n), first, last)
      rows = int(last - first + 1, ip)
      lworkl = ncv * (ncv + 8)
      allocate (resid(rows), v(rows, ncv), workd(3 * rows), workl(lworkl), selected(ncv), &
                d(nev), z(n, nev), rhs(n + nc), x(n), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate the ' // &
            'Lanczos basis of ' // to_str(rows) // ' x ' // to_str(ncv))
         return
      end if
      if (distributed) call log%debug(stage, 'PARPACK on ' // to_str(ranks%num_ranks) // &
         ' rank(s): rows ' // to_str(first) // '..' // to_str(last) // ' of ' // to_str(n) // &
         ' on rank ' // to_str(ranks%rank))
      ! the start vector of the whole space (the same on every rank), then this rank's rows
      call start_vector(x)
      if (deflating) call project_vector(deflation, x)
      resid = x(first:last)
      tol = options%tolerance
      iparam = 0
      iparam(1) = 1                       ! exact shifts
      iparam(3) = options%max_iterations
      iparam(4) = 1                       ! block size (must be 1)
      iparam(7) = 3                       ! shift-invert mode
      ipntr = 0
      ido = 0
      info = 1                            ! resid holds the start vector
      call signal_test_point('lanczos:before')
      do
         if (distributed) then
            call pdsaupd(comm, ido, 'G', rows, 'LM', nev, tol, resid, ncv, v, rows, iparam, &
                         ipntr, workd, workl, lworkl, info)
         else
            call dsaupd(ido, 'G', n, 'LM', nev, tol, resid, ncv, v, n, iparam, ipntr, workd, &
                        workl, lworkl, info)
         end if
         x0 = ipntr(1)
         y0 = ipntr(2)
         select case (ido)
         case (-1)                        ! y = OP x = (K - sigma M)^-1 M x on null(C)
            call check_interrupt(error)
            if (allocated(error)) return
            call ranks%allgather_rows(workd(x0:x0 + rows - 1), x)
            call csr_matvec(M, x, rhs(1:n))
            call kkt_solve(solver, rhs, n, error)
            if (allocated(error)) return
            if (deflating) call project_vector(deflation, rhs(1:n))
            workd(y0:y0 + rows - 1) = rhs(first:last)
         case (1)                         ! M x is in workd(ipntr(3))
            call check_interrupt(error)
            if (allocated(error)) return
            call ranks%allgather_rows(workd(ipntr(3):ipntr(3) + rows - 1), rhs(1:n))
            call kkt_solve(solver, rhs, n, error)
            if (allocated(error)) return
            if (deflating) call project_vector(deflation, rhs(1:n))
            workd(y0:y0 + rows - 1) = rhs(first:last)
         case (2)                         ! y = M x
            call ranks%allgather_rows(workd(x0:x0 + rows - 1), x)
            call csr_matvec(M, x, rhs(1:n))
            workd(y0:y0 + rows - 1) = rhs(first:last)
         case (99)
            exit
         case default
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ARPACK dsaupd ' // &
               'asked for ido = ' // to_str(ido) // ' (not used in mode 3)')
            return
         end select
      end do
      call signal_test_point('lanczos:after')
      if (distributed) call log%debug(stage, 'PARPACK: this rank holds ' // &
         to_str(real(8_i8 * rows * (ncv + 4), dp) / 1.0e6_dp, 1) // ' MB of Lanczos vectors' // &
         ' (v, resid, workd); resident ' // to_str(resident_memory_mb()) // ' MB on rank ' // &
         to_str(ranks%rank))
      result%num_iterations = result%num_iterations + iparam(3)
      call log%debug(stage, 'dsaupd: info = ' // to_str(info) // ', ' // to_str(iparam(5)) // &
         ' converged, ' // to_str(iparam(9)) // ' OP, ' // to_str(iparam(10)) // ' B, ' // &
         to_str(iparam(11)) // ' reorthogonalisation steps')
      if (info /= 0 .or. iparam(5) < nev) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ' // &
            dsaupd_message(info, iparam(5), nev, ncv, options%max_iterations, n))
         return
      end if

      info = 0
      if (distributed) then
         allocate (z_rows(rows, nev))
         call pdseupd(comm, .true., 'A', selected, d, z_rows, rows, sigma, 'G', rows, 'LM', &
                      nev, tol, resid, ncv, v, rows, iparam, ipntr, workd, workl, lworkl, info)
         ! the Ritz vectors whole on every rank (the pairs' checks and the mode shapes)
         if (info == 0) then
            do j = 1, nev
               call ranks%allgather_rows(z_rows(:, j), z(:, j))
            end do
         end if
      else
         call dseupd(.true., 'A', selected, d, z, n, sigma, 'G', n, 'LM', nev, tol, resid, ncv, &
                     v, n, iparam, ipntr, workd, workl, lworkl, info)
      end if
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: ARPACK dseupd info = ' // &
            to_str(info) // ': ' // dseupd_message(info))
         return
      end if

   contains

      subroutine check_interrupt(error)
         type(error_t), allocatable, intent(out) :: error
         if (solver%num_solves == 5) call signal_test_point('lanczos:during')
         call interrupt%check('in the eigen loop (ARPACK) after ' // &
            to_str(solver%num_solves) // ' solves', error)
      end subroutine check_interrupt

   end subroutine lanczos

   !> rhs(1:n) = M x on entry -> y on exit: solve (5.2b) with zero constraint right-hand side.
   subroutine kkt_solve(solver, rhs, n, error)
      type(mumps_solver_t), intent(inout) :: solver
      real(dp), intent(inout) :: rhs(:)
      integer(ip), intent(in) :: n
      type(error_t), allocatable, intent(out) :: error
      rhs(n + 1:) = 0.0_dp
      call solver%solve(rhs, error)
      call check_solution(error, 'shift-invert, Lanczos solve', all(ieee_is_finite(rhs(1:n))), &
         'shift-invert: the KKT solve returned NaN or Inf; K - sigma M is (nearly) singular: ' &
         // 'move sigma')
   end subroutine kkt_solve

   !> Deterministic start vector in (-0.5, 0.5): Park-Miller minimal standard generator
   !> x <- 16807 x mod (2^31 - 1) from a fixed seed, so identical runs give identical output.
   subroutine start_vector(resid)
      real(dp), intent(out) :: resid(:)
      integer(i8), parameter :: modulus = 2147483647_i8, multiplier = 16807_i8
      integer(i8) :: state
      integer :: i
      state = 20240611_i8
      do i = 1, size(resid)
         state = mod(multiplier * state, modulus)
         resid(i) = real(state, dp) / real(modulus, dp) - 0.5_dp
      end do
   end subroutine start_vector

   !> Text for a dsaupd failure: info /= 0 or fewer converged values than wanted.
   function dsaupd_message(info, nconv, nev, ncv, max_iterations, n) result(text)
      integer(ip), intent(in) :: info, nconv, nev, ncv, max_iterations, n
      character(len=:), allocatable :: text
      select case (info)
      case (0, 1)
         text = 'ARPACK dsaupd converged ' // to_str(nconv) // ' of ' // to_str(nev) // &
            ' eigenvalues in max_iterations = ' // to_str(max_iterations) // ' restarts (info = ' &
            // to_str(info) // '); raise max_iterations or ncv (now ' // to_str(ncv) // &
            '), or put sigma nearer the wanted eigenvalues'
      case (3)
         text = 'ARPACK dsaupd info = 3: no shifts could be applied during a restart; ' // &
            'raise ncv (now ' // to_str(ncv) // ', n = ' // to_str(n) // ')'
      case (-1)
         text = 'ARPACK dsaupd info = -1: n = ' // to_str(n) // ' must be positive'
      case (-2)
         text = 'ARPACK dsaupd info = -2: num_modes = ' // to_str(nev) // ' must be positive'
      case (-3)
         text = 'ARPACK dsaupd info = -3: need num_modes < ncv <= n; num_modes = ' // &
            to_str(nev) // ', ncv = ' // to_str(ncv) // ', n = ' // to_str(n)
      case (-4)
         text = 'ARPACK dsaupd info = -4: max_iterations = ' // to_str(max_iterations) // &
            ' must be positive'
      case (-8)
         text = 'ARPACK dsaupd info = -8: the tridiagonal eigenvalue computation (LAPACK ' // &
            'dsteqr) failed; raise ncv or change sigma'
      case (-9)
         text = 'ARPACK dsaupd info = -9: the start vector is zero in the range of OP; ' // &
            'all of R^n is constrained or M is zero on null(C)'
      case (-9999)
         text = 'ARPACK dsaupd info = -9999: could not build a Lanczos factorisation of ' // &
            'size ncv = ' // to_str(ncv) // ' (invariant subspace of dimension ' // &
            to_str(nconv) // '); lower ncv or num_modes'
      case default
         text = 'ARPACK dsaupd info = ' // to_str(info) // ': invalid argument (ARPACK-NG ' // &
            'SRC/dsaupd.f lists the codes)'
      end select
   end function dsaupd_message

   !> Text for a dseupd failure: a table of the codes ARPACK-NG SRC/dseupd.f returns after a
   !> successful dsaupd.
   function dseupd_message(info) result(text)
      integer(ip), intent(in) :: info
      character(len=:), allocatable :: text
      integer(ip), parameter :: CODES(4) = [-8_ip, -9_ip, -14_ip, -17_ip]
      character(len=*), parameter :: TEXTS(4) = [character(len=112) :: &
         'the Ritz values of the tridiagonal matrix could not be computed (LAPACK dsteqr); ' // &
         'raise ncv or change sigma', &
         'the tridiagonal eigenvector computation (LAPACK dsteqr) failed; raise ncv', &
         'dsaupd found no eigenvalue to sufficient accuracy; raise max_iterations or ncv', &
         'dseupd counted a different number of converged Ritz values than dsaupd; raise ncv ' &
         // 'or loosen tolerance']
      integer :: k
      text = 'invalid argument (ARPACK-NG SRC/dseupd.f lists the codes)'
      do k = 1, size(CODES)
         if (CODES(k) == info) text = trim(TEXTS(k))
      end do
   end function dseupd_message

end submodule ffrf_modes_shift_invert_lanczos
