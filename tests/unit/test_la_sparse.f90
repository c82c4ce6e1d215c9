!> CSR operations against dense computations on small random matrices. Values are drawn from a
!> fixed seed in [-1, 1]; a dense reference sums the same products in a different order, so the
!> tolerance is a few eps times the number of terms (stated per test as 1e-14).
module test_la_sparse
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, FFRF_INPUT_ERROR
   use ffrf_la_sparse, only: csr_t, csr_matvec, csr_transpose, csr_matmul, csr_from_coo, &
      csr_upper_coo, csr_adjacency, csr_identity, csr_get, csr_nnz, csr_add, csr_to_dense, &
      sort_indices
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check
   implicit none
   private
   public :: collect_la_sparse

   !> Absolute tolerance for entries of order 1 built from at most ~10 products
   real(dp), parameter :: TOL = 1.0e-14_dp

contains

   subroutine collect_la_sparse(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('from_coo_sums_duplicates', test_from_coo), &
         new_unittest('from_coo_rejects_bad_index', test_from_coo_bad_index), &
         new_unittest('transpose', test_transpose), &
         new_unittest('matvec', test_matvec), &
         new_unittest('matmul', test_matmul), &
         new_unittest('matmul_rejects_mismatch', test_matmul_mismatch), &
         new_unittest('add', test_add), &
         new_unittest('upper_coo', test_upper_coo), &
         new_unittest('adjacency', test_adjacency), &
         new_unittest('identity_get_nnz', test_identity_get_nnz), &
         new_unittest('sort_indices', test_sort)]
   end subroutine collect_la_sparse

   !> Fixed-seed random sparse matrix as triplets (with duplicates) and its dense sum.
   subroutine random_triplets(m, n, count, fill, rows, cols, vals, dense, seed)
      integer(ip), intent(in) :: m, n, count
      real(dp), intent(in) :: fill
      integer(ip), allocatable, intent(out) :: rows(:), cols(:)
      real(dp), allocatable, intent(out) :: vals(:)
      real(dp), allocatable, intent(out) :: dense(:, :)
      integer, intent(in) :: seed
      integer :: seed_size, k
      integer, allocatable :: seeds(:)
      real(dp) :: r(3)
      call random_seed(size=seed_size)
      seeds = [(seed + 37*k, k=1, seed_size)]
      call random_seed(put=seeds)
      allocate (rows(count), cols(count), vals(count), dense(m, n))
      dense = 0.0_dp
      do k = 1, count
         call random_number(r)
         rows(k) = 1 + min(m - 1, int(r(1)*m, ip))
         cols(k) = 1 + min(n - 1, int(r(2)*n*fill, ip))   ! fill < 1 leaves columns empty
         vals(k) = 2.0_dp*r(3) - 1.0_dp
         dense(rows(k), cols(k)) = dense(rows(k), cols(k)) + vals(k)
      end do
   end subroutine random_triplets

   subroutine random_csr(m, n, count, seed, A, dense, error)
      integer(ip), intent(in) :: m, n, count
      integer, intent(in) :: seed
      type(csr_t), intent(out) :: A
      real(dp), allocatable, intent(out) :: dense(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      call random_triplets(m, n, count, 1.0_dp, rows, cols, vals, dense, seed)
      call csr_from_coo(m, n, rows, cols, vals, A, error)
   end subroutine random_csr

   !> Columns sorted and unique in every row, row_ptr consistent.
   subroutine check_structure(error, what, A)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      type(csr_t), intent(in) :: A
      integer(ip) :: i, k
      logical :: ok
      ok = size(A%row_ptr) == A%num_rows + 1 .and. A%row_ptr(1) == 1
      ok = ok .and. size(A%col) == csr_nnz(A) .and. size(A%val) == csr_nnz(A)
      do i = 1, A%num_rows
         do k = A%row_ptr(i) + 1, A%row_ptr(i + 1) - 1
            ok = ok .and. A%col(k) > A%col(k - 1)
         end do
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            ok = ok .and. A%col(k) >= 1 .and. A%col(k) <= A%num_cols
         end do
      end do
      call check(error, what // ': CSR structure (sorted unique columns in range)', ok)
   end subroutine check_structure

   subroutine check_dense(error, what, A, reference)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what
      type(csr_t), intent(in) :: A
      real(dp), intent(in) :: reference(:, :)
      real(dp), allocatable :: dense(:, :)
      call check(error, what // ': shape', A%num_rows == size(reference, 1) .and. &
         A%num_cols == size(reference, 2))
      if (allocated(error)) return
      call csr_to_dense(A, dense)
      call check_close(error, what // ': max |A - reference|', maxval(abs(dense - reference)), &
         0.0_dp, atol=TOL)
   end subroutine check_dense

   !> Duplicates summed (reference: dense accumulation of the same triplets).
   subroutine test_from_coo(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A
      real(dp), allocatable :: dense(:, :)
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      logical :: seen(9, 7)
      integer :: k
      call random_triplets(9_ip, 7_ip, 120_ip, 0.8_dp, rows, cols, vals, dense, 11)
      call csr_from_coo(9_ip, 7_ip, rows, cols, vals, A, error)
      if (allocated(error)) return
      call check_structure(error, 'from_coo', A)
      if (allocated(error)) return
      seen = .false.
      do k = 1, size(rows)
         seen(rows(k), cols(k)) = .true.
      end do
      call check(error, 'from_coo: duplicates merged (nnz = number of distinct pairs)', &
         csr_nnz(A) == count(seen) .and. csr_nnz(A) < size(rows))
      if (allocated(error)) return
      call check_dense(error, 'from_coo', A, dense)
   end subroutine test_from_coo

   subroutine test_from_coo_bad_index(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      type(csr_t) :: A
      call csr_from_coo(3_ip, 3_ip, [1_ip, 4_ip], [1_ip, 2_ip], [1.0_dp, 2.0_dp], A, expected)
      call check(error, 'row 4 of a 3 x 3 matrix must be refused', allocated(expected))
      if (allocated(error)) return
      call check(error, 'message names the triplet: ' // expected%message, &
         index(expected%message, 'triplet 2') > 0 .and. expected%code == FFRF_INPUT_ERROR)
   end subroutine test_from_coo_bad_index

   subroutine test_transpose(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A, At
      real(dp), allocatable :: dense(:, :)
      call random_csr(8_ip, 5_ip, 25_ip, 3, A, dense, error)
      if (allocated(error)) return
      call csr_transpose(A, At)
      call check_structure(error, 'transpose', At)
      if (allocated(error)) return
      call check_dense(error, 'transpose', At, transpose(dense))
   end subroutine test_transpose

   subroutine test_matvec(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A
      real(dp), allocatable :: dense(:, :)
      real(dp) :: x(6), y(10)
      call random_csr(10_ip, 6_ip, 30_ip, 5, A, dense, error)
      if (allocated(error)) return
      call random_number(x)
      call csr_matvec(A, x, y)
      call check_close(error, 'max |A x - dense A x|', maxval(abs(y - matmul(dense, x))), &
         0.0_dp, atol=TOL)
   end subroutine test_matvec

   !> Rectangular product (7 x 9)(9 x 6) and a sparser one with empty rows and columns.
   subroutine test_matmul(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A, B, C
      real(dp), allocatable :: da(:, :), db(:, :), dc(:, :)
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      call random_csr(7_ip, 9_ip, 20_ip, 7, A, da, error)
      if (allocated(error)) return
      call random_csr(9_ip, 6_ip, 25_ip, 8, B, db, error)
      if (allocated(error)) return
      call csr_matmul(A, B, C, error)
      if (allocated(error)) return
      call check_structure(error, 'matmul', C)
      if (allocated(error)) return
      call check_dense(error, 'matmul', C, matmul(da, db))
      if (allocated(error)) return
      ! 40 x 50 times 50 x 60: rows long enough for the heapsort branch of the column sort
      call random_csr(40_ip, 50_ip, 600_ip, 9, A, da, error)
      if (allocated(error)) return
      call random_triplets(50_ip, 60_ip, 900_ip, 0.9_dp, rows, cols, vals, db, 10)
      call csr_from_coo(50_ip, 60_ip, rows, cols, vals, B, error)
      if (allocated(error)) return
      call csr_matmul(A, B, C, error)
      if (allocated(error)) return
      call check(error, 'matmul: some rows of C exceed 32 entries (heapsort path taken)', &
         maxval(C%row_ptr(2:) - C%row_ptr(:40)) > 32)
      if (allocated(error)) return
      call check_structure(error, 'matmul (large rows)', C)
      if (allocated(error)) return
      dc = matmul(da, db)
      call check_dense(error, 'matmul (large rows)', C, dc)
   end subroutine test_matmul

   subroutine test_matmul_mismatch(error)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: expected
      type(csr_t) :: A, B, C
      call csr_identity(3_ip, A)
      call csr_identity(4_ip, B)
      call csr_matmul(A, B, C, expected)
      call check(error, '(3 x 3)(4 x 4) must be refused', allocated(expected))
   end subroutine test_matmul_mismatch

   subroutine test_add(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A, B, C
      real(dp), allocatable :: da(:, :), db(:, :)
      call random_csr(6_ip, 8_ip, 15_ip, 21, A, da, error)
      if (allocated(error)) return
      call random_csr(6_ip, 8_ip, 15_ip, 22, B, db, error)
      if (allocated(error)) return
      call csr_add(2.0_dp, A, -0.5_dp, B, C, error)
      if (allocated(error)) return
      call check_structure(error, 'add', C)
      if (allocated(error)) return
      call check_dense(error, 'add', C, 2.0_dp*da - 0.5_dp*db)
   end subroutine test_add

   !> Upper triangle of a symmetric matrix: the triplets with j >= i rebuild A = U + U^T - diag.
   subroutine test_upper_coo(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A, At, S
      real(dp), allocatable :: da(:, :), rebuilt(:, :), vals(:)
      integer(ip), allocatable :: irn(:), jcn(:)
      integer :: k
      call random_csr(9_ip, 9_ip, 30_ip, 31, A, da, error)
      if (allocated(error)) return
      call csr_transpose(A, At)
      call csr_add(1.0_dp, A, 1.0_dp, At, S, error)     ! symmetric
      if (allocated(error)) return
      call csr_upper_coo(S, irn, jcn, vals)
      call check(error, 'upper_coo: every triplet has jcn >= irn', all(jcn >= irn))
      if (allocated(error)) return
      allocate (rebuilt(9, 9))
      rebuilt = 0.0_dp
      do k = 1, size(irn)
         rebuilt(irn(k), jcn(k)) = rebuilt(irn(k), jcn(k)) + vals(k)
         if (irn(k) /= jcn(k)) rebuilt(jcn(k), irn(k)) = rebuilt(jcn(k), irn(k)) + vals(k)
      end do
      call check_close(error, 'upper_coo: max |rebuilt - (A + A^T)|', &
         maxval(abs(rebuilt - (da + transpose(da)))), 0.0_dp, atol=TOL)
   end subroutine test_upper_coo

   !> METIS graph of an unsymmetric pattern: j in adj(i) iff A(i,j) or A(j,i) stored, j /= i.
   subroutine test_adjacency(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A
      real(dp), allocatable :: da(:, :)
      integer(ip), allocatable :: xadj(:), adjncy(:)
      logical :: expected(12, 12), got(12, 12)
      integer :: i, k
      call random_csr(12_ip, 12_ip, 40_ip, 41, A, da, error)
      if (allocated(error)) return
      expected = .false.
      do i = 1, 12
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            expected(i, A%col(k)) = .true.
            expected(A%col(k), i) = .true.
         end do
         expected(i, i) = .false.
      end do
      call csr_adjacency(A, xadj, adjncy)
      got = .false.
      do i = 1, 12
         do k = xadj(i), xadj(i + 1) - 1
            got(i, adjncy(k)) = .true.
         end do
      end do
      call check(error, 'adjacency: xadj(1) = 1 and size(adjncy) = xadj(n+1) - 1', &
         xadj(1) == 1 .and. size(adjncy) == xadj(13) - 1)
      if (allocated(error)) return
      call check(error, 'adjacency equals the pattern of A + A^T without diagonal', &
         all(got .eqv. expected) .and. size(adjncy) == count(expected))
   end subroutine test_adjacency

   subroutine test_identity_get_nnz(error)
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: A, Id, C
      real(dp), allocatable :: da(:, :)
      real(dp) :: worst
      integer(ip) :: i, j
      call random_csr(5_ip, 5_ip, 9_ip, 51, A, da, error)
      if (allocated(error)) return
      worst = 0.0_dp
      do j = 1, 5
         do i = 1, 5
            worst = max(worst, abs(csr_get(A, i, j) - da(i, j)))
         end do
      end do
      call check_close(error, 'csr_get against dense (0 where not stored)', worst, 0.0_dp, &
         atol=0.0_dp)
      if (allocated(error)) return
      call check(error, 'csr_nnz counts distinct stored pairs', csr_nnz(A) == count(da /= 0.0_dp))
      if (allocated(error)) return
      call csr_identity(5_ip, Id)
      call csr_matmul(A, Id, C, error)
      if (allocated(error)) return
      call check_dense(error, 'A I', C, da)
      if (allocated(error)) return
      call check(error, 'nnz(I) = 5 and an empty csr_t has nnz 0', &
         csr_nnz(Id) == 5 .and. csr_nnz(C) == csr_nnz(A) .and. csr_nnz(csr_t()) == 0)
   end subroutine test_identity_get_nnz

   subroutine test_sort(error)
      type(error_t), allocatable, intent(out) :: error
      integer(ip) :: short(7), long(100)
      integer :: k
      real(dp) :: r(100)
      short = [5, 3, 9, 1, 3, 7, 2]
      call sort_indices(short)
      call random_number(r)
      long = int(r*1000.0_dp, ip)
      call sort_indices(long)
      call check(error, 'sort_indices ascending (insertion and heapsort paths)', &
         all(short == [1, 2, 3, 3, 5, 7, 9]) .and. all([(long(k) <= long(k + 1), k=1, 99)]))
   end subroutine test_sort

end module test_la_sparse

program main_la_sparse
   use ffrf_testing, only: unittest_t, run_suite
   use test_la_sparse, only: collect_la_sparse
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_la_sparse(tests)
   call run_suite('la_sparse', tests)
end program main_la_sparse
