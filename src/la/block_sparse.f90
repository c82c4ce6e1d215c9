!> Block-sparse matrices: the rows and the columns are cut into groups (a mechanism's bodies, or
!> single constraint rows), and the matrix holds one dense block per pair of groups that was
!> written to, column-major in one flat array. Blocks appear when first written (`add`) and stay
!> (`zero` keeps the pattern): the pattern only grows, and `version` counts its changes, so a
!> sparse factorisation can keep its analysis while the version stays. Products, the diagonal,
!> row maxima and the triplets cost O(entries held), never O(rows x columns): the iteration
!> matrix of a chain of flexible bodies is handed to MUMPS in this form, as described in
!> docs/performance_threads.md "The iteration matrix: dense or sparse LU".
module ffrf_la_block_sparse
   use ffrf_core_kinds, only: dp
   implicit none
   private
   public :: block_sparse_t

   !> The blocks of one row group: their column groups and where their values start
   type :: block_row_t
      integer :: count = 0
      integer, allocatable :: group(:), offset(:)
   end type block_row_t

   !> A block-sparse matrix (module header).
   type :: block_sparse_t
      !> Rows and columns
      integer :: num_rows = 0, num_cols = 0
      !> First row (column) of each group, and one past the last: groups + 1 entries
      integer, allocatable :: row_start(:), col_start(:)
      !> Group of each row (column)
      integer, allocatable :: row_group(:), col_group(:)
      !> Blocks per row group
      type(block_row_t), allocatable :: blocks(:)
      !> The blocks' values, column-major each; `used` of them hold blocks
      real(dp), allocatable :: values(:)
      integer :: used = 0
      !> Pattern changes (a block added) since init
      integer :: version = 0
   contains
      !> Set the row and column groups; no blocks
      procedure :: init => block_sparse_init
      !> Whether the groups equal these
      procedure :: same_groups => block_sparse_same_groups
      !> All values zero, the pattern kept
      procedure :: zero => block_sparse_zero
      !> A(rows, cols) += B (blocks created as needed)
      procedure :: add => block_sparse_add
      !> A(r0 + 1:, c0 + 1:) += B
      procedure :: add_block => block_sparse_add_block
      !> self = a X + b Y + c Z, entry by entry (X, Y, Z of the same groups)
      procedure :: combine => block_sparse_combine
      !> y = A x, y = A^T x, and with |A|
      procedure :: matvec => block_sparse_matvec
      !> Dense copy (tests, the dense interfaces)
      procedure :: to_dense => block_sparse_to_dense
      !> The diagonal (square matrices), zero where no block holds it
      procedure :: diagonal => block_sparse_diagonal
      !> max_j |A(i, j)| per row
      procedure :: row_abs_max => block_sparse_row_abs_max
      !> Number of entries held (explicit zeros included)
      procedure :: entries => block_sparse_entries
      !> The entries held as triplets (1-based rows and columns, shifted by r0, c0; transposed
      !> if asked), scaled per row by rscale, from position k + 1 on; k is advanced
      procedure :: triplets => block_sparse_triplets
   end type block_sparse_t

contains

   !> Set the groups: rows row_start(g) .. row_start(g + 1) - 1 form row group g (likewise the
   !> columns); empty groups are allowed. No blocks, version 0.
   subroutine block_sparse_init(self, row_start, col_start)
      class(block_sparse_t), intent(out) :: self
      !> First row of each group and one past the last (groups + 1, starting at 1)
      integer, intent(in) :: row_start(:)
      !> First column of each group and one past the last
      integer, intent(in) :: col_start(:)
      integer :: g
      self%row_start = row_start
      self%col_start = col_start
      self%num_rows = row_start(size(row_start)) - 1
      self%num_cols = col_start(size(col_start)) - 1
      allocate (self%row_group(self%num_rows), self%col_group(self%num_cols))
      do g = 1, size(row_start) - 1
         self%row_group(row_start(g):row_start(g + 1) - 1) = g
      end do
      do g = 1, size(col_start) - 1
         self%col_group(col_start(g):col_start(g + 1) - 1) = g
      end do
      allocate (self%blocks(size(row_start) - 1), self%values(0))
   end subroutine block_sparse_init

   !> Whether the row and column groups are these.
   logical function block_sparse_same_groups(self, row_start, col_start) result(same)
      class(block_sparse_t), intent(in) :: self
      integer, intent(in) :: row_start(:), col_start(:)
      same = allocated(self%row_start)
      if (.not. same) return
      same = size(self%row_start) == size(row_start) .and. &
         size(self%col_start) == size(col_start)
      if (same) same = all(self%row_start == row_start) .and. all(self%col_start == col_start)
   end function block_sparse_same_groups

   !> All values zero; the blocks stay.
   subroutine block_sparse_zero(self)
      class(block_sparse_t), intent(inout) :: self
      self%values(:self%used) = 0.0_dp
   end subroutine block_sparse_zero

   !> Offset of block (g, h) in values, created (zero) if absent.
   integer function block_offset(self, g, h) result(offset)
      class(block_sparse_t), intent(inout) :: self
      integer, intent(in) :: g, h
      integer, allocatable :: grown(:)
      real(dp), allocatable :: values(:)
      integer :: i, length, count
      count = self%blocks(g)%count
      do i = 1, count
         if (self%blocks(g)%group(i) == h) then
            offset = self%blocks(g)%offset(i)
            return
         end if
      end do
      ! a new block: grow the row's lists and the values by hand (no constructors)
      if (.not. allocated(self%blocks(g)%group)) allocate (self%blocks(g)%group(4), &
         self%blocks(g)%offset(4))
      if (count == size(self%blocks(g)%group)) then
         allocate (grown(2 * count))
         grown(:count) = self%blocks(g)%group(:count)
         call move_alloc(grown, self%blocks(g)%group)
         allocate (grown(2 * count))
         grown(:count) = self%blocks(g)%offset(:count)
         call move_alloc(grown, self%blocks(g)%offset)
      end if
      length = (self%row_start(g + 1) - self%row_start(g)) * &
         (self%col_start(h + 1) - self%col_start(h))
      if (self%used + length > size(self%values)) then
         allocate (values(max(2 * size(self%values), self%used + length, 64)))
         values(:self%used) = self%values(:self%used)
         call move_alloc(values, self%values)
      end if
      offset = self%used
      self%values(offset + 1:offset + length) = 0.0_dp
      self%used = self%used + length
      self%blocks(g)%count = count + 1
      self%blocks(g)%group(count + 1) = h
      self%blocks(g)%offset(count + 1) = offset
      self%version = self%version + 1
   end function block_offset

   !> A(rows(i), cols(j)) += B(i, j), each entry in its block (created as needed).
   subroutine block_sparse_add(self, rows, cols, B)
      class(block_sparse_t), intent(inout) :: self
      !> Rows and columns of B's entries in A
      integer, intent(in) :: rows(:), cols(:)
      !> The values, size(rows) x size(cols)
      real(dp), intent(in) :: B(:, :)
      integer :: i, j, g, h, last_g, last_h, offset, height, r, c
      last_g = 0
      last_h = 0
      offset = 0
      height = 0
      do j = 1, size(cols)
         c = cols(j)
         h = self%col_group(c)
         do i = 1, size(rows)
            r = rows(i)
            g = self%row_group(r)
            if (g /= last_g .or. h /= last_h) then
               offset = block_offset(self, g, h)
               height = self%row_start(g + 1) - self%row_start(g)
               last_g = g
               last_h = h
            end if
            associate (k => offset + r - self%row_start(g) + 1 + &
               (c - self%col_start(h)) * height)
               self%values(k) = self%values(k) + B(i, j)
            end associate
         end do
      end do
   end subroutine block_sparse_add

   !> A(r0 + i, c0 + j) += B(i, j).
   subroutine block_sparse_add_block(self, r0, c0, B)
      class(block_sparse_t), intent(inout) :: self
      !> Row and column before the block's first
      integer, intent(in) :: r0, c0
      !> The block
      real(dp), intent(in) :: B(:, :)
      integer :: i
      call self%add([(r0 + i, i=1, size(B, 1))], [(c0 + i, i=1, size(B, 2))], B)
   end subroutine block_sparse_add_block

   !> self = a X + b Y + c Z (b and c optional), the pattern the union of theirs; entry by entry
   !> the same expression as the dense a X + b Y + c Z. X, Y, Z have the groups of self.
   subroutine block_sparse_combine(self, a, X, b, Y, c, Z)
      class(block_sparse_t), intent(inout) :: self
      real(dp), intent(in) :: a, b, c
      type(block_sparse_t), intent(in) :: X, Y, Z
      integer :: g, i, o, length
      ! the union of the patterns first (zeros), then the values entry by entry
      call make_room(X)
      call make_room(Y)
      call make_room(Z)
      call self%zero()
      call scaled_into(X, a)
      call scaled_into(Y, b)
      call scaled_into(Z, c)
   contains
      subroutine make_room(S)
         type(block_sparse_t), intent(in) :: S
         do g = 1, size(S%blocks)
            do i = 1, S%blocks(g)%count
               o = block_offset(self, g, S%blocks(g)%group(i))
            end do
         end do
      end subroutine make_room
      subroutine scaled_into(S, factor)
         type(block_sparse_t), intent(in) :: S
         real(dp), intent(in) :: factor
         integer :: h
         do g = 1, size(S%blocks)
            do i = 1, S%blocks(g)%count
               h = S%blocks(g)%group(i)
               length = (S%row_start(g + 1) - S%row_start(g)) * (S%col_start(h + 1) - &
                  S%col_start(h))
               o = block_offset(self, g, h)
               self%values(o + 1:o + length) = self%values(o + 1:o + length) + &
                  factor * S%values(S%blocks(g)%offset(i) + 1:S%blocks(g)%offset(i) + length)
            end do
         end do
      end subroutine scaled_into
   end subroutine block_sparse_combine

   !> y = op(A) x with op(A) = A, or A^T (transposed), of |A| entries (absolute).
   subroutine block_sparse_matvec(self, x, y, transposed, absolute)
      class(block_sparse_t), intent(in) :: self
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: y(:)
      logical, intent(in), optional :: transposed, absolute
      logical :: trans, magnitude
      integer :: g, i, h, r0, c0, height, width, ii, jj, o
      real(dp) :: value
      trans = .false.
      magnitude = .false.
      if (present(transposed)) trans = transposed
      if (present(absolute)) magnitude = absolute
      y = 0.0_dp
      do g = 1, size(self%blocks)
         r0 = self%row_start(g) - 1
         height = self%row_start(g + 1) - self%row_start(g)
         do i = 1, self%blocks(g)%count
            h = self%blocks(g)%group(i)
            c0 = self%col_start(h) - 1
            width = self%col_start(h + 1) - self%col_start(h)
            o = self%blocks(g)%offset(i)
            do jj = 1, width
               do ii = 1, height
                  value = self%values(o + ii + (jj - 1) * height)
                  if (magnitude) value = abs(value)
                  if (trans) then
                     y(c0 + jj) = y(c0 + jj) + value * x(r0 + ii)
                  else
                     y(r0 + ii) = y(r0 + ii) + value * x(c0 + jj)
                  end if
               end do
            end do
         end do
      end do
   end subroutine block_sparse_matvec

   !> Dense copy: A = 0, then each block.
   subroutine block_sparse_to_dense(self, A)
      class(block_sparse_t), intent(in) :: self
      real(dp), intent(out) :: A(:, :)
      integer :: g, i, h, height, width, o
      A = 0.0_dp
      do g = 1, size(self%blocks)
         height = self%row_start(g + 1) - self%row_start(g)
         do i = 1, self%blocks(g)%count
            h = self%blocks(g)%group(i)
            width = self%col_start(h + 1) - self%col_start(h)
            o = self%blocks(g)%offset(i)
            A(self%row_start(g):self%row_start(g + 1) - 1, self%col_start(h): &
               self%col_start(h + 1) - 1) = reshape(self%values(o + 1:o + height * width), &
               [height, width])
         end do
      end do
   end subroutine block_sparse_to_dense

   !> The diagonal of a square matrix: entries held on it, zero elsewhere.
   function block_sparse_diagonal(self) result(d)
      class(block_sparse_t), intent(in) :: self
      real(dp) :: d(self%num_rows)
      integer :: g, i, h, height, o, r
      d = 0.0_dp
      do g = 1, size(self%blocks)
         height = self%row_start(g + 1) - self%row_start(g)
         do i = 1, self%blocks(g)%count
            h = self%blocks(g)%group(i)
            o = self%blocks(g)%offset(i)
            do r = max(self%row_start(g), self%col_start(h)), &
               min(self%row_start(g + 1), self%col_start(h + 1)) - 1
               d(r) = self%values(o + r - self%row_start(g) + 1 + (r - self%col_start(h)) * &
                  height)
            end do
         end do
      end do
   end function block_sparse_diagonal

   !> max_j |A(i, j)| for each row i (0 for a row with no block).
   function block_sparse_row_abs_max(self) result(m)
      class(block_sparse_t), intent(in) :: self
      real(dp) :: m(self%num_rows)
      integer :: g, i, h, height, width, o, ii, jj
      m = 0.0_dp
      do g = 1, size(self%blocks)
         height = self%row_start(g + 1) - self%row_start(g)
         do i = 1, self%blocks(g)%count
            h = self%blocks(g)%group(i)
            width = self%col_start(h + 1) - self%col_start(h)
            o = self%blocks(g)%offset(i)
            do jj = 1, width
               do ii = 1, height
                  m(self%row_start(g) + ii - 1) = max(m(self%row_start(g) + ii - 1), &
                     abs(self%values(o + ii + (jj - 1) * height)))
               end do
            end do
         end do
      end do
   end function block_sparse_row_abs_max

   !> Number of entries held.
   integer function block_sparse_entries(self) result(count)
      class(block_sparse_t), intent(in) :: self
      count = self%used
   end function block_sparse_entries

   !> The entries of the rows `keep` (all rows if absent; a row not kept is skipped, the kept
   !> ones renumbered 1, 2, ... in their order) as triplets at positions k + 1, ...: row
   !> r0 + (new row), column c0 + column, value rscale(new row) * A (rscale absent: 1), or
   !> transposed (row and column exchanged). Entries whose row is not kept are left out.
   subroutine block_sparse_triplets(self, r0, c0, irn, jcn, values, k, keep_row, rscale, &
      transposed)
      class(block_sparse_t), intent(in) :: self
      integer, intent(in) :: r0, c0
      integer, intent(inout) :: irn(:), jcn(:)
      real(dp), intent(inout) :: values(:)
      integer, intent(inout) :: k
      !> New number of each row (0: left out), num_rows
      integer, intent(in), optional :: keep_row(:)
      real(dp), intent(in), optional :: rscale(:)
      logical, intent(in), optional :: transposed
      integer :: g, i, h, height, width, o, ii, jj, row, col
      real(dp) :: factor
      logical :: trans
      trans = .false.
      if (present(transposed)) trans = transposed
      do g = 1, size(self%blocks)
         height = self%row_start(g + 1) - self%row_start(g)
         do i = 1, self%blocks(g)%count
            h = self%blocks(g)%group(i)
            width = self%col_start(h + 1) - self%col_start(h)
            o = self%blocks(g)%offset(i)
            do jj = 1, width
               col = self%col_start(h) + jj - 1
               do ii = 1, height
                  row = self%row_start(g) + ii - 1
                  if (present(keep_row)) row = keep_row(row)
                  if (row == 0) cycle
                  factor = 1.0_dp
                  if (present(rscale)) factor = rscale(row)
                  k = k + 1
                  if (trans) then
                     irn(k) = c0 + col
                     jcn(k) = r0 + row
                  else
                     irn(k) = r0 + row
                     jcn(k) = c0 + col
                  end if
                  values(k) = factor * self%values(o + ii + (jj - 1) * height)
               end do
            end do
         end do
      end do
   end subroutine block_sparse_triplets

end module ffrf_la_block_sparse
