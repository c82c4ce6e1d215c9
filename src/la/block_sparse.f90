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
      !> The blocks in the order they were added: row group, column group, offset in values
      integer :: num_blocks = 0
      integer, allocatable :: block_row(:), block_col(:), block_start(:)
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
      !> The entries of A X^T (X of the same column groups) as triplets, block pair by block pair
      procedure :: product_triplets => block_sparse_product_triplets
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
      allocate (self%blocks(size(row_start) - 1), self%values(0), self%block_row(8), &
         self%block_col(8), self%block_start(8))
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
         call grow(self%blocks(g)%group)
         call grow(self%blocks(g)%offset)
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
      if (self%num_blocks == size(self%block_row)) then
         call grow(self%block_row)
         call grow(self%block_col)
         call grow(self%block_start)
      end if
      self%num_blocks = self%num_blocks + 1
      self%block_row(self%num_blocks) = g
      self%block_col(self%num_blocks) = h
      self%block_start(self%num_blocks) = offset
   contains
      !> Twice the room, the entries kept.
      subroutine grow(list)
         integer, allocatable, intent(inout) :: list(:)
         integer, allocatable :: longer(:)
         allocate (longer(2 * size(list)))
         longer(:size(list)) = list
         call move_alloc(longer, list)
      end subroutine grow
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

   !> Where block b (order of addition) sits: rows r0 + 1 .. r0 + height, columns c0 + 1 ..
   !> c0 + width, values offset + 1 .. offset + height width (column-major).
   pure function extent(self, b) result(e)
      type(block_sparse_t), intent(in) :: self
      integer, intent(in) :: b
      !> r0, c0, height, width, offset
      integer :: e(5)
      associate (g => self%block_row(b), h => self%block_col(b))
         e = [self%row_start(g) - 1, self%col_start(h) - 1, self%row_start(g + 1) - &
            self%row_start(g), self%col_start(h + 1) - self%col_start(h), self%block_start(b)]
      end associate
   end function extent

   !> self = a X + b Y + c Z, the pattern the union of theirs; entry by entry the same
   !> expression as the dense a X + b Y + c Z. X, Y, Z have the groups of self.
   subroutine block_sparse_combine(self, a, X, b, Y, c, Z)
      class(block_sparse_t), intent(inout) :: self
      real(dp), intent(in) :: a, b, c
      type(block_sparse_t), intent(in) :: X, Y, Z
      integer :: k, o
      ! the union of the patterns first (zeros), then the values entry by entry
      do k = 1, X%num_blocks
         o = block_offset(self, X%block_row(k), X%block_col(k))
      end do
      do k = 1, Y%num_blocks
         o = block_offset(self, Y%block_row(k), Y%block_col(k))
      end do
      do k = 1, Z%num_blocks
         o = block_offset(self, Z%block_row(k), Z%block_col(k))
      end do
      call self%zero()
      call scaled_into(X, a)
      call scaled_into(Y, b)
      call scaled_into(Z, c)
   contains
      subroutine scaled_into(S, factor)
         type(block_sparse_t), intent(in) :: S
         real(dp), intent(in) :: factor
         integer :: e(5)
         do k = 1, S%num_blocks
            e = extent(S, k)
            o = block_offset(self, S%block_row(k), S%block_col(k))
            self%values(o + 1:o + e(3) * e(4)) = self%values(o + 1:o + e(3) * e(4)) + &
               factor * S%values(e(5) + 1:e(5) + e(3) * e(4))
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
      integer :: k, e(5), ii, jj
      real(dp) :: value
      trans = .false.
      magnitude = .false.
      if (present(transposed)) trans = transposed
      if (present(absolute)) magnitude = absolute
      y = 0.0_dp
      do k = 1, self%num_blocks
         e = extent(self, k)
         do jj = 1, e(4)
            do ii = 1, e(3)
               value = self%values(e(5) + ii + (jj - 1) * e(3))
               if (magnitude) value = abs(value)
               if (trans) then
                  y(e(2) + jj) = y(e(2) + jj) + value * x(e(1) + ii)
               else
                  y(e(1) + ii) = y(e(1) + ii) + value * x(e(2) + jj)
               end if
            end do
         end do
      end do
   end subroutine block_sparse_matvec

   !> Dense copy: A = 0, then each block.
   subroutine block_sparse_to_dense(self, A)
      class(block_sparse_t), intent(in) :: self
      real(dp), intent(out) :: A(:, :)
      integer :: k, e(5)
      A = 0.0_dp
      do k = 1, self%num_blocks
         e = extent(self, k)
         A(e(1) + 1:e(1) + e(3), e(2) + 1:e(2) + e(4)) = reshape(self%values(e(5) + 1:e(5) + &
            e(3) * e(4)), [e(3), e(4)])
      end do
   end subroutine block_sparse_to_dense

   !> The diagonal of a square matrix: entries held on it, zero elsewhere.
   function block_sparse_diagonal(self) result(d)
      class(block_sparse_t), intent(in) :: self
      real(dp) :: d(self%num_rows)
      integer :: k, e(5), r
      d = 0.0_dp
      do k = 1, self%num_blocks
         e = extent(self, k)
         do r = max(e(1), e(2)) + 1, min(e(1) + e(3), e(2) + e(4))
            d(r) = self%values(e(5) + r - e(1) + (r - e(2) - 1) * e(3))
         end do
      end do
   end function block_sparse_diagonal

   !> max_j |A(i, j)| for each row i (0 for a row with no block).
   function block_sparse_row_abs_max(self) result(m)
      class(block_sparse_t), intent(in) :: self
      real(dp) :: m(self%num_rows)
      integer :: k, e(5), jj
      m = 0.0_dp
      do k = 1, self%num_blocks
         e = extent(self, k)
         do jj = 1, e(4)
            m(e(1) + 1:e(1) + e(3)) = max(m(e(1) + 1:e(1) + e(3)), &
               abs(self%values(e(5) + (jj - 1) * e(3) + 1:e(5) + jj * e(3))))
         end do
      end do
   end function block_sparse_row_abs_max

   !> Number of entries held.
   integer function block_sparse_entries(self) result(count)
      class(block_sparse_t), intent(in) :: self
      count = self%used
   end function block_sparse_entries

   !> The entries of the rows `keep_row` keeps (all rows if absent; keep_row(i) is the new
   !> number of row i, 0: left out) as triplets at positions k + 1, ...: row r0 + (new row),
   !> column c0 + column, value rscale(new row) * A (rscale absent: 1), or transposed (row and
   !> column exchanged).
   subroutine block_sparse_triplets(self, r0, c0, irn, jcn, values, k, keep_row, rscale, &
      transposed)
      class(block_sparse_t), intent(in) :: self
      integer, intent(in) :: r0, c0
      integer, intent(inout) :: irn(:), jcn(:)
      real(dp), intent(inout) :: values(:)
      integer, intent(inout) :: k
      !> New number of each row (0: left out), num_rows. Contiguous: with an assumed stride GCC
      !> versions the loops on the stride of keep_row and rscale even when they are absent, a read
      !> of a descriptor field the caller never set (memcheck: "conditional jump depends on
      !> uninitialised value" on the sparse path; the result did not depend on it)
      integer, intent(in), optional, contiguous :: keep_row(:)
      real(dp), intent(in), optional, contiguous :: rscale(:)
      logical, intent(in), optional :: transposed
      integer :: b, e(5), ii, jj, row, col
      real(dp) :: factor
      logical :: trans
      trans = .false.
      if (present(transposed)) trans = transposed
      do b = 1, self%num_blocks
         e = extent(self, b)
         do jj = 1, e(4)
            col = e(2) + jj
            do ii = 1, e(3)
               row = renumbered(e(1) + ii, keep_row)
               if (row == 0) cycle
               factor = scale_at(row, rscale)
               k = k + 1
               if (trans) then
                  irn(k) = c0 + col
                  jcn(k) = r0 + row
               else
                  irn(k) = r0 + row
                  jcn(k) = c0 + col
               end if
               values(k) = factor * self%values(e(5) + ii + (jj - 1) * e(3))
            end do
         end do
      end do
   end subroutine block_sparse_triplets

   !> The entries of A X^T (A this matrix, X with the same column groups) as triplets appended
   !> at k + 1, ... (the arrays grow as needed): row r0 + keep_row(i) for row i of A, column
   !> c0 + keep_col(j) for row j of X (absent: i, j; 0: left out), value rscale(new row)
   !> cscale(new column) (A X^T)(i, j). One entry per row pair of each pair of blocks in one
   !> column group, so a pair of rows meeting in several column groups gives several entries,
   !> to be summed (as MUMPS does). O(sum over column groups of A's blocks x X's blocks there).
   subroutine block_sparse_product_triplets(self, X, r0, c0, irn, jcn, values, k, keep_row, &
      rscale, keep_col, cscale)
      class(block_sparse_t), intent(in) :: self
      type(block_sparse_t), intent(in) :: X
      integer, intent(in) :: r0, c0
      integer, allocatable, intent(inout) :: irn(:), jcn(:)
      real(dp), allocatable, intent(inout) :: values(:)
      integer, intent(inout) :: k
      ! contiguous: as in block_sparse_triplets
      integer, intent(in), optional, contiguous :: keep_row(:), keep_col(:)
      real(dp), intent(in), optional, contiguous :: rscale(:), cscale(:)
      integer, allocatable :: first(:), list(:), fill(:), irn_new(:), jcn_new(:)
      real(dp), allocatable :: values_new(:)
      integer :: groups, b, xb, m, ii, jj, row, col, eA(5), eX(5)
      real(dp) :: factor
      ! X's blocks by column group
      groups = size(X%col_start) - 1
      allocate (first(groups + 1), fill(groups), list(X%num_blocks))
      first = 0
      do xb = 1, X%num_blocks
         first(X%block_col(xb) + 1) = first(X%block_col(xb) + 1) + 1
      end do
      first(1) = 1
      do m = 1, groups
         first(m + 1) = first(m + 1) + first(m)
      end do
      fill = first(:groups)
      do xb = 1, X%num_blocks
         list(fill(X%block_col(xb))) = xb
         fill(X%block_col(xb)) = fill(X%block_col(xb)) + 1
      end do
      do b = 1, self%num_blocks
         eA = extent(self, b)
         do m = first(self%block_col(b)), first(self%block_col(b) + 1) - 1
            xb = list(m)
            eX = extent(X, xb)
            do jj = 1, eX(3)
               col = renumbered(eX(1) + jj, keep_col)
               if (col == 0) cycle
               do ii = 1, eA(3)
                  row = renumbered(eA(1) + ii, keep_row)
                  if (row == 0) cycle
                  factor = scale_at(row, rscale) * scale_at(col, cscale)
                  if (k == size(irn)) then
                     allocate (irn_new(2 * k + 16), jcn_new(2 * k + 16), values_new(2 * k + 16))
                     irn_new(:k) = irn(:k)
                     jcn_new(:k) = jcn(:k)
                     values_new(:k) = values(:k)
                     call move_alloc(irn_new, irn)
                     call move_alloc(jcn_new, jcn)
                     call move_alloc(values_new, values)
                  end if
                  k = k + 1
                  irn(k) = r0 + row
                  jcn(k) = c0 + col
                  ! (A X^T)(i, j) over this column group: row ii of A's block, row jj of X's
                  values(k) = factor * dot_product(self%values(eA(5) + ii:eA(5) + eA(3) * &
                     eA(4):eA(3)), X%values(eX(5) + jj:eX(5) + eX(3) * eX(4):eX(3)))
               end do
            end do
         end do
      end do
   end subroutine block_sparse_product_triplets

   !> keep(i) (the new number of i, 0: left out), or i without keep.
   pure integer function renumbered(i, keep) result(j)
      integer, intent(in) :: i
      integer, intent(in), optional, contiguous :: keep(:)
      j = i
      if (present(keep)) j = keep(i)
   end function renumbered

   !> scale(i), or 1 without scale.
   pure real(dp) function scale_at(i, scale) result(factor)
      integer, intent(in) :: i
      real(dp), intent(in), optional, contiguous :: scale(:)
      factor = 1.0_dp
      if (present(scale)) factor = scale(i)
   end function scale_at

end module ffrf_la_block_sparse
