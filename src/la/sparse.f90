!> Compressed sparse row matrices (CSR), 1-based. Symmetric matrices (K, M) are kept with both
!> triangles so that products and transposes need no special cases; `csr_upper_coo` hands the
!> upper triangle to MUMPS.
module ffrf_la_sparse
   use ffrf_core_kinds, only: dp, ip, i8
   implicit none
   private
   public :: csr_t

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

end module ffrf_la_sparse
