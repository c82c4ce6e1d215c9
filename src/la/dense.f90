!> Small dense linear algebra on top of LAPACK: skew matrices, symmetric eigen decomposition,
!> singular values, null spaces and pseudo-inverses of the 6-column MPC matrices, minimum-norm
!> least squares.
module ffrf_la_dense
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_lapack, only: dgesvd, dsyev, dgelsy
   implicit none
   private
   public :: skew, symmetric_eigen, singular_values, null_space, numerical_rank, &
      min_norm_solve

contains

   !> x = the minimum-norm least-squares solution of A x = b (LAPACK dgelsy, rank from the
   !> relative tolerance rcond): exact for consistent systems even when A has dependent rows.
   subroutine min_norm_solve(a, b, x, rcond, rank, error)
      !> Matrix (m, n)
      real(dp), intent(in) :: a(:, :)
      !> Right-hand side (m)
      real(dp), intent(in) :: b(:)
      !> Solution (n)
      real(dp), intent(out) :: x(:)
      !> Relative rank tolerance
      real(dp), intent(in) :: rcond
      !> Numerical rank found
      integer, intent(out) :: rank
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: work(:), a_copy(:, :), rhs(:, :)
      real(dp) :: query(1)
      integer(ip), allocatable :: pivots(:)
      integer(ip) :: m, n, ld, info, r
      m = int(size(a, 1), ip)
      n = int(size(a, 2), ip)
      ld = max(m, n, 1_ip)
      a_copy = a
      allocate (rhs(ld, 1), source=0.0_dp)
      rhs(1:m, 1) = b
      allocate (pivots(n), source=0_ip)
      call dgelsy(m, n, 1_ip, a_copy, max(m, 1_ip), rhs, ld, pivots, rcond, r, query, -1_ip, &
         info)
      allocate (work(max(1, int(query(1)))))
      call dgelsy(m, n, 1_ip, a_copy, max(m, 1_ip), rhs, ld, pivots, rcond, r, work, &
         int(size(work), ip), info)
      rank = int(r)
      x = rhs(1:n, 1)
      if (info /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'minimum-norm least squares (dgelsy) failed, info = ' // to_str(info))
   end subroutine min_norm_solve

   !> skew(a) b = a x b.
   pure function skew(a) result(s)
      !> Vector a
      real(dp), intent(in) :: a(3)
      real(dp) :: s(3, 3)
      s = reshape([0.0_dp, a(3), -a(2), -a(3), 0.0_dp, a(1), a(2), -a(1), 0.0_dp], [3, 3])
   end function skew

   !> Eigenvalues (ascending) and orthonormal eigenvectors of a symmetric matrix (LAPACK dsyev).
   subroutine symmetric_eigen(a, values, vectors, error)
      !> Symmetric matrix (only the upper triangle is read)
      real(dp), intent(in) :: a(:, :)
      !> Eigenvalues, ascending
      real(dp), intent(out) :: values(:)
      !> Eigenvectors as columns
      real(dp), intent(out) :: vectors(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: work(:)
      real(dp) :: query(1)
      integer(ip) :: n, info
      n = int(size(a, 1), ip)
      vectors = a
      call dsyev('V', 'U', n, vectors, n, values, query, -1_ip, info)
      allocate (work(max(1, int(query(1)))))
      call dsyev('V', 'U', n, vectors, n, values, work, int(size(work), ip), info)
      if (info /= 0) call fatal_error(error, FFRF_NUMERIC_ERROR, &
         'symmetric eigen decomposition (dsyev) failed, info = ' // to_str(info))
   end subroutine symmetric_eigen

   !> Singular values of a (descending) and, optionally, the right singular vectors V (columns).
   subroutine singular_values(a, s, error, v)
      !> Matrix, m x n
      real(dp), intent(in) :: a(:, :)
      !> Singular values, min(m, n), descending
      real(dp), allocatable, intent(out) :: s(:)
      type(error_t), allocatable, intent(out) :: error
      !> Right singular vectors, n x n (all of them, the null space included)
      real(dp), allocatable, intent(out), optional :: v(:, :)
      real(dp), allocatable :: work(:), copy(:, :), vt(:, :)
      real(dp) :: query(1), u_dummy(1, 1)
      integer(ip) :: m, n, info
      character :: jobvt
      m = int(size(a, 1), ip)
      n = int(size(a, 2), ip)
      allocate (s(min(m, n)))
      if (m == 0 .or. n == 0) then
         if (present(v)) v = identity(n)
         return
      end if
      copy = a
      jobvt = 'N'
      if (present(v)) jobvt = 'A'
      allocate (vt(n, n))
      call dgesvd('N', jobvt, m, n, copy, m, s, u_dummy, 1_ip, vt, n, query, -1_ip, info)
      allocate (work(max(1, int(query(1)))))
      call dgesvd('N', jobvt, m, n, copy, m, s, u_dummy, 1_ip, vt, n, work, &
         int(size(work), ip), info)
      if (info /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'singular value decomposition (dgesvd) ' // &
            'did not converge, info = ' // to_str(info))
         return
      end if
      if (present(v)) v = transpose(vt)
   end subroutine singular_values

   !> Number of singular values above rtol * the largest one.
   function numerical_rank(s, rtol) result(rank)
      !> Singular values, descending
      real(dp), intent(in) :: s(:)
      !> Relative tolerance
      real(dp), intent(in) :: rtol
      integer :: rank
      rank = 0
      if (size(s) == 0) return
      if (s(1) <= 0.0_dp) return
      rank = count(s > rtol * s(1))
   end function numerical_rank

   !> Orthonormal basis Z of null(A) (n x (n - rank)), from the SVD; rank counted with rtol.
   subroutine null_space(a, z, rank, rtol, error)
      !> Matrix, m x n
      real(dp), intent(in) :: a(:, :)
      !> Orthonormal null-space basis, columns
      real(dp), allocatable, intent(out) :: z(:, :)
      !> Numerical rank of a
      integer, intent(out) :: rank
      !> Relative singular-value tolerance
      real(dp), intent(in) :: rtol
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: s(:), v(:, :)
      call singular_values(a, s, error, v)
      if (allocated(error)) return
      rank = numerical_rank(s, rtol)
      z = v(:, rank + 1:)
   end subroutine null_space

   pure function identity(n) result(eye)
      integer(ip), intent(in) :: n
      real(dp) :: eye(n, n)
      integer :: i
      eye = 0.0_dp
      do i = 1, n
         eye(i, i) = 1.0_dp
      end do
   end function identity

end module ffrf_la_dense
