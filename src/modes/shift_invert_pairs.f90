!> ffrf_modes_shift_invert: the eigenpairs normalised, sorted and checked (residuals projected
!> onto null(C), M-orthonormality).
submodule (ffrf_modes_shift_invert:ffrf_modes_shift_invert_lanczos) ffrf_modes_shift_invert_pairs
   implicit none

contains

   !> Normalise (x^T M x = 1), Rayleigh quotients, sort ascending, residuals (projected onto
   !> null(C)) and M-orthonormality; fills result%eigenvalues/vectors/residuals.
   module procedure finish_pairs
      real(dp), allocatable :: Kx(:, :), Mx(:, :), lambda(:), gram(:, :), r(:, :)
      integer(ip), allocatable :: order(:)
      real(dp) :: xMx, scale, denominator
      integer(ip) :: n, nev, j, stat

      n = size(z, 1)
      nev = size(z, 2)
      allocate (Kx(n, nev), Mx(n, nev), lambda(nev), gram(nev, nev), r(n, 2 * nev), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: cannot allocate ' // &
            'the residual work arrays (' // to_str(n) // ' x ' // to_str(3 * nev) // ')')
         return
      end if
      do j = 1, nev
         call csr_matvec(M, z(:, j), Mx(:, j))
         xMx = dot_product(z(:, j), Mx(:, j))
         if (.not. (xMx > 0.0_dp) .or. .not. ieee_is_finite(xMx)) then
            call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: Ritz vector ' // &
               to_str(j) // ' has x^T M x = ' // to_str(xMx) // '; M must be positive ' // &
               'definite on null(C)')
            return
         end if
         scale = 1.0_dp / sqrt(xMx)
         z(:, j) = z(:, j) * scale
         Mx(:, j) = Mx(:, j) * scale
         call csr_matvec(K, z(:, j), Kx(:, j))
         lambda(j) = dot_product(z(:, j), Kx(:, j))
      end do

      order = ascending_order(lambda)
      result%num_modes = nev
      result%eigenvalues = lambda(order)
      result%vectors = z(:, order)
      Kx = Kx(:, order)
      Mx = Mx(:, order)

      ! Residuals K x - lambda M x and K x, both projected onto null(C).
      do j = 1, nev
         r(:, j) = Kx(:, j) - result%eigenvalues(j) * Mx(:, j)
         r(:, nev + j) = Kx(:, j)
      end do
      if (C%num_rows > 0) then
         call project_null_space(C, r, error)
         if (allocated(error)) return
      end if
      allocate (result%residuals(nev))
      do j = 1, nev
         denominator = max(norm2(r(:, nev + j)), abs(result%shift) * norm2(Mx(:, j)), &
                           tiny(1.0_dp))
         result%residuals(j) = norm2(r(:, j)) / denominator
      end do

      ! M-orthonormality: X^T (M X) - I.
      call dgemm('T', 'N', nev, nev, n, 1.0_dp, result%vectors, n, Mx, n, 0.0_dp, gram, nev)
      do j = 1, nev
         gram(j, j) = gram(j, j) - 1.0_dp
      end do
      result%orthonormality_error = maxval(abs(gram))
      if (.not. all(ieee_is_finite(result%eigenvalues)) .or. &
          .not. all(ieee_is_finite(result%residuals))) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert: NaN or Inf in the ' // &
            'eigenpairs; K - sigma M is (nearly) singular: move sigma')
      end if
   end procedure finish_pairs

   !> Columns of r replaced by their orthogonal projection P r = r - C^T (C C^T)^-1 C r onto
   !> null(C). C has a handful of rows (reference conditions), so C C^T is a small dense matrix,
   !> solved by Cholesky (LAPACK dposv) after scaling the rows to unit norm.
   module procedure project_null_space
      real(dp), allocatable :: gram(:, :), cr(:, :), row_norm(:)
      integer(ip) :: nc, i, p, info
      nc = C%num_rows
      call csr_row_gram(C, gram, row_norm)
      allocate (cr(nc, size(r, 2)))
      ! C r with the normalised rows.
      cr = 0.0_dp
      do i = 1, nc
         do p = C%row_ptr(i), C%row_ptr(i + 1) - 1
            cr(i, :) = cr(i, :) + C%val(p) / row_norm(i) * r(C%col(p), :)
         end do
      end do
      call dposv('U', nc, int(size(r, 2), ip), gram, nc, cr, nc, info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'shift-invert, residual projection onto ' &
            // 'null(C): the constraint rows are linearly dependent (dposv info = ' // &
            to_str(info) // ')')
         return
      end if
      ! r -= C^T mu
      do i = 1, nc
         do p = C%row_ptr(i), C%row_ptr(i + 1) - 1
            r(C%col(p), :) = r(C%col(p), :) - C%val(p) / row_norm(i) * cr(i, :)
         end do
      end do
   end procedure project_null_space

end submodule ffrf_modes_shift_invert_pairs
