!> Compressed sparse row matrices (CSR), 1-based. Symmetric matrices (K, M) are kept with both
!> triangles so that products and transposes need no special cases; `csr_upper_coo` hands the
!> upper triangle to MUMPS and `csr_adjacency` the graph to METIS.
!>
!> Every routine that builds a matrix returns sorted, unique columns in each row. Sizes and
!> indices are `integer(ip)` (what MUMPS, METIS and ARPACK take); counts that could pass 2**31
!> are formed in `integer(i8)` first and refused with an error.
module ffrf_la_sparse
   use ffrf_core_kinds, only: dp, ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: csr_t
   public :: csr_matvec, csr_matmat, csr_transpose, csr_matmul, csr_from_coo, csr_upper_coo, csr_adjacency
   public :: csr_identity, csr_get, csr_find, csr_nnz, csr_add, csr_to_dense, sort_indices
   public :: csr_row_gram

   !> A sparse matrix in CSR form. Columns within a row are sorted ascending and unique.
   type :: csr_t
      !> Number of rows
      integer(ip) :: num_rows = 0
      !> Number of columns
      integer(ip) :: num_cols = 0
      !> Start of row i in col/val is row_ptr(i); row_ptr(num_rows+1) = nnz + 1
      integer(ip), allocatable :: row_ptr(:)
      !> Column index of each stored entry
      integer(ip), allocatable :: col(:)
      !> Value of each stored entry
      real(dp), allocatable :: val(:)
   end type csr_t

   interface
      !> C = A B by Gustavson's row-by-row algorithm with a dense marker over the columns of B: a
      !> symbolic pass counts nnz(C) (refused past huge(0_ip)), a numeric pass fills it; each row's
      !> columns are sorted. Structural zeros (cancellation) are kept.
      module subroutine csr_matmul(A, B, C, error)
         !> Left factor, m x k
         type(csr_t), intent(in) :: A
         !> Right factor, k x n
         type(csr_t), intent(in) :: B
         !> Product, m x n
         type(csr_t), intent(out) :: C
         !> Dimension mismatch or too many entries
         type(error_t), allocatable, intent(out) :: error
      end subroutine csr_matmul

      !> C = alpha A + beta B (same shape); the pattern of C is the union of both patterns.
      module subroutine csr_add(alpha, A, beta, B, C, error)
         !> Factor of A
         real(dp), intent(in) :: alpha
         !> First matrix
         type(csr_t), intent(in) :: A
         !> Factor of B
         real(dp), intent(in) :: beta
         !> Second matrix, same shape as A
         type(csr_t), intent(in) :: B
         !> Result
         type(csr_t), intent(out) :: C
         !> Shape mismatch or too many entries
         type(error_t), allocatable, intent(out) :: error
      end subroutine csr_add

      !> Build A from coordinate triplets (rows(k), cols(k), vals(k)), 1-based; duplicates are
      !> summed and each row's columns sorted. Two stable counting sorts (by column, then by row)
      !> order the triplets in O(nnz + n).
      module subroutine csr_from_coo(num_rows, num_cols, rows, cols, vals, A, error)
         !> Number of rows of A
         integer(ip), intent(in) :: num_rows
         !> Number of columns of A
         integer(ip), intent(in) :: num_cols
         !> Row of each triplet, 1..num_rows
         integer(ip), intent(in) :: rows(:)
         !> Column of each triplet, 1..num_cols
         integer(ip), intent(in) :: cols(:)
         !> Value of each triplet
         real(dp), intent(in) :: vals(:)
         !> Result
         type(csr_t), intent(out) :: A
         !> Index out of range or inconsistent sizes
         type(error_t), allocatable, intent(out) :: error
      end subroutine csr_from_coo

      !> The upper triangle (j >= i) of A as 1-based coordinate triplets, the form MUMPS takes for a
      !> symmetric matrix (SYM = 1 or 2: only one triangle may be given). Default integers (ip) for
      !> irn/jcn as in `dmumps_struc.h`.
      module subroutine csr_upper_coo(A, irn, jcn, vals)
         !> Matrix (square, both triangles stored)
         type(csr_t), intent(in) :: A
         !> Row of each entry
         integer(ip), allocatable, intent(out) :: irn(:)
         !> Column of each entry
         integer(ip), allocatable, intent(out) :: jcn(:)
         !> Value of each entry
         real(dp), allocatable, intent(out) :: vals(:)
      end subroutine csr_upper_coo

      !> The graph of the pattern of A + A^T without the diagonal, 1-based, in the (xadj, adjncy)
      !> form METIS_NodeND takes (numflag = 1). A must be square (num_rows = num_cols).
      module subroutine csr_adjacency(A, xadj, adjncy)
         !> Square matrix
         type(csr_t), intent(in) :: A
         !> Start of the neighbours of vertex i in adjncy, size num_rows + 1
         integer(ip), allocatable, intent(out) :: xadj(:)
         !> Neighbours, sorted per vertex, no self loops
         integer(ip), allocatable, intent(out) :: adjncy(:)
      end subroutine csr_adjacency
   end interface

contains

   !> Number of stored entries (0 for a matrix never built).
   pure function csr_nnz(A) result(nnz)
      !> Matrix
      type(csr_t), intent(in) :: A
      integer(ip) :: nnz
      nnz = 0
      if (allocated(A%row_ptr)) nnz = A%row_ptr(A%num_rows + 1) - 1
   end function csr_nnz

   !> Entry A(i, j), 0 if (i, j) is not stored (binary search in the sorted row).
   pure function csr_get(A, i, j) result(value)
      !> Matrix
      type(csr_t), intent(in) :: A
      !> Row, 1..num_rows
      integer(ip), intent(in) :: i
      !> Column, 1..num_cols
      integer(ip), intent(in) :: j
      real(dp) :: value
      integer(ip) :: k
      value = 0.0_dp
      if (i < 1 .or. i > A%num_rows) return
      k = csr_find(A, i, j)
      if (k > 0) value = A%val(k)
   end function csr_get

   !> Position in A%col and A%val of column j in row i of A (0 if not stored); the columns of
   !> each row ascending (binary search).
   pure function csr_find(A, i, j) result(pos)
      type(csr_t), intent(in) :: A
      integer(ip), intent(in) :: i, j
      integer(ip) :: pos, lo, hi, mid
      pos = 0
      lo = A%row_ptr(i)
      hi = A%row_ptr(i + 1) - 1
      do while (lo <= hi)
         mid = lo + (hi - lo)/2
         if (A%col(mid) == j) then
            pos = mid
            return
         else if (A%col(mid) < j) then
            lo = mid + 1
         else
            hi = mid - 1
         end if
      end do
   end function csr_find

   !> The n x n identity.
   subroutine csr_identity(n, A)
      !> Order
      integer(ip), intent(in) :: n
      !> Result
      type(csr_t), intent(out) :: A
      integer(ip) :: i
      A%num_rows = n
      A%num_cols = n
      allocate (A%row_ptr(n + 1), A%col(n), A%val(n))
      A%row_ptr = [(i, i=1, n + 1)]
      A%col = [(i, i=1, n)]
      A%val = 1.0_dp
   end subroutine csr_identity

   !> y = A x. x has num_cols entries, y num_rows.
   pure subroutine csr_matvec(A, x, y)
      !> Matrix
      type(csr_t), intent(in) :: A
      !> Vector, size num_cols
      real(dp), intent(in) :: x(:)
      !> Product, size num_rows
      real(dp), intent(out) :: y(:)
      integer(ip) :: i, k
      real(dp) :: s
      do i = 1, A%num_rows
         s = 0.0_dp
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            s = s + A%val(k)*x(A%col(k))
         end do
         y(i) = s
      end do
   end subroutine csr_matvec

   !> Y = A X for a block of columns X (num_cols x k). The block is transposed so that each
   !> entry of A meets k contiguous values: one pass over A for all k columns.
   subroutine csr_matmat(A, X, Y)
      !> Matrix
      type(csr_t), intent(in) :: A
      !> Columns, num_cols x k
      real(dp), intent(in) :: X(:, :)
      !> Products, num_rows x k
      real(dp), intent(out) :: Y(:, :)
      real(dp), allocatable :: xt(:, :), yt(:, :)
      integer(ip) :: i, k
      xt = transpose(X)
      allocate (yt(size(X, 2), A%num_rows))
      do i = 1, A%num_rows
         yt(:, i) = 0.0_dp
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            yt(:, i) = yt(:, i) + A%val(k) * xt(:, A%col(k))
         end do
      end do
      Y = transpose(yt)
   end subroutine csr_matmat

   !> At = A^T by a counting sort over columns; rows of At come out sorted because the rows of
   !> A are visited in order.
   subroutine csr_transpose(A, At)
      !> Matrix
      type(csr_t), intent(in) :: A
      !> Its transpose
      type(csr_t), intent(out) :: At
      integer(ip) :: i, k, j, nnz
      integer(ip), allocatable :: next(:)
      nnz = csr_nnz(A)
      At%num_rows = A%num_cols
      At%num_cols = A%num_rows
      allocate (At%row_ptr(A%num_cols + 1), At%col(nnz), At%val(nnz), next(A%num_cols + 1))
      At%row_ptr = 0
      do k = 1, nnz
         At%row_ptr(A%col(k) + 1) = At%row_ptr(A%col(k) + 1) + 1
      end do
      At%row_ptr(1) = 1
      do j = 1, A%num_cols
         At%row_ptr(j + 1) = At%row_ptr(j + 1) + At%row_ptr(j)
      end do
      next = At%row_ptr
      do i = 1, A%num_rows
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            j = A%col(k)
            At%col(next(j)) = i
            At%val(next(j)) = A%val(k)
            next(j) = next(j) + 1
         end do
      end do
   end subroutine csr_transpose

   !> Dense copy of A (for tests and small matrices).
   subroutine csr_to_dense(A, dense)
      !> Matrix
      type(csr_t), intent(in) :: A
      !> Dense num_rows x num_cols copy
      real(dp), allocatable, intent(out) :: dense(:, :)
      integer(ip) :: i, k
      allocate (dense(A%num_rows, A%num_cols))
      dense = 0.0_dp
      do i = 1, A%num_rows
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            dense(i, A%col(k)) = dense(i, A%col(k)) + A%val(k)
         end do
      end do
   end subroutine csr_to_dense

   !> Sort integers ascending in place: insertion sort for short lists (rows of FE matrices),
   !> heapsort beyond 32 entries (O(n log n) worst case, no recursion).
   pure subroutine sort_indices(values)
      !> Values to sort
      integer(ip), intent(inout) :: values(:)
      integer(ip) :: n, i, j, key, last
      n = int(size(values), ip)
      if (n <= 32) then
         do i = 2, n
            key = values(i)
            j = i - 1
            do while (j >= 1)
               if (values(j) <= key) exit
               values(j + 1) = values(j)
               j = j - 1
            end do
            values(j + 1) = key
         end do
         return
      end if
      ! heapsort: build a max-heap, then move the maximum to the end
      do i = n/2, 1, -1
         call sift_down(values, i, n)
      end do
      do last = n, 2, -1
         key = values(1)
         values(1) = values(last)
         values(last) = key
         call sift_down(values, 1_ip, last - 1)
      end do
   end subroutine sort_indices

   !> Restore the max-heap property of values(first:limit) below `first`.
   pure subroutine sift_down(values, first, limit)
      integer(ip), intent(inout) :: values(:)
      integer(ip), intent(in) :: first, limit
      integer(ip) :: root, child, tmp
      root = first
      do
         child = 2*root
         if (child > limit) exit
         if (child < limit) then
            if (values(child + 1) > values(child)) child = child + 1
         end if
         if (values(root) >= values(child)) exit
         tmp = values(root)
         values(root) = values(child)
         values(child) = tmp
         root = child
      end do
   end subroutine sift_down

   !> Gram matrix of the rows of A normalised to unit length: gram(i, j) = a_i . a_j / (|a_i| |a_j|)
   !> (A has few rows, e.g. reference-condition constraints). One row at a time is scattered into a
   !> dense vector, so the cost is O(rows * nnz).
   subroutine csr_row_gram(A, gram, row_norm)
      !> Matrix with a handful of rows
      type(csr_t), intent(in) :: A
      !> Normalised Gram matrix, (rows, rows)
      real(dp), allocatable, intent(out) :: gram(:, :)
      !> Euclidean norm of each row
      real(dp), allocatable, intent(out) :: row_norm(:)
      real(dp), allocatable :: work(:)
      integer(ip) :: i, j, p
      allocate (gram(A%num_rows, A%num_rows), row_norm(A%num_rows), work(A%num_cols))
      do i = 1, A%num_rows
         row_norm(i) = max(norm2(A%val(A%row_ptr(i):A%row_ptr(i + 1) - 1)), tiny(1.0_dp))
      end do
      work = 0.0_dp
      do i = 1, A%num_rows
         do p = A%row_ptr(i), A%row_ptr(i + 1) - 1
            work(A%col(p)) = A%val(p) / row_norm(i)
         end do
         do j = 1, A%num_rows
            gram(i, j) = 0.0_dp
            do p = A%row_ptr(j), A%row_ptr(j + 1) - 1
               gram(i, j) = gram(i, j) + work(A%col(p)) * A%val(p) / row_norm(j)
            end do
         end do
         do p = A%row_ptr(i), A%row_ptr(i + 1) - 1
            work(A%col(p)) = 0.0_dp
         end do
      end do
   end subroutine csr_row_gram

end module ffrf_la_sparse
