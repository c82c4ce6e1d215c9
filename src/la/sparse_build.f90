!> ffrf_la_sparse: matrices built: products (Gustavson), sums, CSR from COO triplets, the upper
!> triangle for MUMPS and the graph for METIS.
submodule (ffrf_la_sparse) ffrf_la_sparse_build
   implicit none

contains

   module procedure csr_matmul
      integer(ip), allocatable :: marker(:)
      real(dp), allocatable :: accumulator(:)
      integer(i8) :: total
      integer(ip) :: i, ka, row_start, count, stat
      if (A%num_cols /= B%num_rows) then
         call shape_error(error, 'csr_matmul', A, B, 'the inner dimensions must agree')
         return
      end if
      C%num_rows = A%num_rows
      C%num_cols = B%num_cols
      allocate (C%row_ptr(A%num_rows + 1), marker(B%num_cols))
      marker = 0
      ! symbolic pass: nnz per row
      total = 0
      C%row_ptr(1) = 1
      do i = 1, A%num_rows
         call product_row(i, .false., count)
         total = total + count
         if (total > int(huge(0_ip), i8) - 1) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'csr_matmul: the product has more than ' // &
               to_str(huge(0_ip) - 1) // ' entries (32-bit indices); reduce the problem size')
            return
         end if
         C%row_ptr(i + 1) = C%row_ptr(i) + count
      end do
      allocate (C%col(total), C%val(total), accumulator(B%num_cols), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'csr_matmul: cannot allocate ' // &
            to_str(total) // ' entries for the product')
         return
      end if
      ! numeric pass
      marker = 0
      accumulator = 0.0_dp
      do i = 1, A%num_rows
         row_start = C%row_ptr(i)
         call product_row(i, .true., count)
         call sort_indices(C%col(row_start:row_start + count - 1))
         do ka = row_start, row_start + count - 1
            C%val(ka) = accumulator(C%col(ka))
         end do
      end do
   contains
      !> Row i of A B: the number of its distinct columns (marker(j) = i marks column j seen);
      !> with fill, also its columns into C%col from C%row_ptr(i) on and its sums in accumulator.
      subroutine product_row(i, fill, count)
         integer(ip), intent(in) :: i
         logical, intent(in) :: fill
         integer(ip), intent(out) :: count
         integer(ip) :: ka, kb, j
         count = 0
         do ka = A%row_ptr(i), A%row_ptr(i + 1) - 1
            do kb = B%row_ptr(A%col(ka)), B%row_ptr(A%col(ka) + 1) - 1
               j = B%col(kb)
               if (marker(j) /= i) then
                  marker(j) = i
                  if (fill) then
                     C%col(C%row_ptr(i) + count) = j
                     accumulator(j) = A%val(ka)*B%val(kb)
                  end if
                  count = count + 1
               else if (fill) then
                  accumulator(j) = accumulator(j) + A%val(ka)*B%val(kb)
               end if
            end do
         end do
      end subroutine product_row
   end procedure csr_matmul

   module procedure csr_add
      integer(i8) :: total
      integer(ip) :: i, ka, kb, kc, pass
      if (A%num_rows /= B%num_rows .or. A%num_cols /= B%num_cols) then
         call shape_error(error, 'csr_add', A, B, 'the shapes must agree')
         return
      end if
      C%num_rows = A%num_rows
      C%num_cols = A%num_cols
      allocate (C%row_ptr(A%num_rows + 1))
      C%row_ptr(1) = 1
      ! pass 1 counts the merged rows, pass 2 fills them
      do pass = 1, 2
         total = 0
         do i = 1, A%num_rows
            ka = A%row_ptr(i)
            kb = B%row_ptr(i)
            kc = C%row_ptr(i)
            do while (ka < A%row_ptr(i + 1) .or. kb < B%row_ptr(i + 1))
               if (kb >= B%row_ptr(i + 1)) then
                  if (pass == 2) call put(A%col(ka), alpha*A%val(ka))
                  ka = ka + 1
               else if (ka >= A%row_ptr(i + 1)) then
                  if (pass == 2) call put(B%col(kb), beta*B%val(kb))
                  kb = kb + 1
               else if (A%col(ka) < B%col(kb)) then
                  if (pass == 2) call put(A%col(ka), alpha*A%val(ka))
                  ka = ka + 1
               else if (A%col(ka) > B%col(kb)) then
                  if (pass == 2) call put(B%col(kb), beta*B%val(kb))
                  kb = kb + 1
               else
                  if (pass == 2) call put(A%col(ka), alpha*A%val(ka) + beta*B%val(kb))
                  ka = ka + 1
                  kb = kb + 1
               end if
               total = total + 1
            end do
            if (pass == 1) then
               if (total > int(huge(0_ip), i8) - 1) then
                  call fatal_error(error, FFRF_INPUT_ERROR, 'csr_add: the sum has more than ' // &
                     to_str(huge(0_ip) - 1) // ' entries (32-bit indices)')
                  return
               end if
               C%row_ptr(i + 1) = 1 + int(total, ip)
            end if
         end do
         if (pass == 1) allocate (C%col(total), C%val(total))
      end do
   contains
      subroutine put(j, v)
         integer(ip), intent(in) :: j
         real(dp), intent(in) :: v
         C%col(kc) = j
         C%val(kc) = v
         kc = kc + 1
      end subroutine put
   end procedure csr_add

   module procedure csr_from_coo
      integer(ip), allocatable :: by_col(:), by_row(:), start(:)
      integer(ip) :: k, n, i, j, nnz, last_col, last_row, stat
      n = int(size(rows), ip)
      if (size(cols) /= n .or. size(vals) /= n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'csr_from_coo: rows, cols and vals have ' // &
            to_str(n) // ', ' // to_str(int(size(cols), ip)) // ' and ' // &
            to_str(int(size(vals), ip)) // ' entries; they must have the same size')
         return
      end if
      do k = 1, n
         if (rows(k) < 1 .or. rows(k) > num_rows .or. cols(k) < 1 .or. cols(k) > num_cols) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'csr_from_coo: triplet ' // to_str(k) // &
               ' has (row, col) = (' // to_str(rows(k)) // ', ' // to_str(cols(k)) // &
               '), outside the ' // to_str(num_rows) // ' x ' // to_str(num_cols) // ' matrix')
            return
         end if
      end do
      allocate (by_col(n), by_row(n), start(max(num_rows, num_cols) + 1), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'csr_from_coo: cannot allocate work for ' // &
            to_str(n) // ' triplets')
         return
      end if
      ! stable counting sort by column, then of the column-sorted list by row
      do k = 1, n
         by_row(k) = k
      end do
      call counting_sort(cols, num_cols, by_row, by_col)
      call counting_sort(rows, num_rows, by_col, by_row)
      deallocate (by_col)
      ! merge duplicates
      A%num_rows = num_rows
      A%num_cols = num_cols
      allocate (A%row_ptr(num_rows + 1))
      nnz = 0
      last_row = 0
      last_col = 0
      A%row_ptr = 0
      do k = 1, n
         i = rows(by_row(k))
         j = cols(by_row(k))
         if (i /= last_row .or. j /= last_col) then
            nnz = nnz + 1
            A%row_ptr(i + 1) = A%row_ptr(i + 1) + 1
            last_row = i
            last_col = j
         end if
      end do
      A%row_ptr(1) = 1
      do i = 1, num_rows
         A%row_ptr(i + 1) = A%row_ptr(i + 1) + A%row_ptr(i)
      end do
      allocate (A%col(nnz), A%val(nnz))
      nnz = 0
      last_row = 0
      last_col = 0
      do k = 1, n
         i = rows(by_row(k))
         j = cols(by_row(k))
         if (i /= last_row .or. j /= last_col) then
            nnz = nnz + 1
            A%col(nnz) = j
            A%val(nnz) = vals(by_row(k))
            last_row = i
            last_col = j
         else
            A%val(nnz) = A%val(nnz) + vals(by_row(k))
         end if
      end do
   contains
      !> `sorted` = the items of `order` stably sorted by keys(item), keys in 1..num_keys.
      subroutine counting_sort(keys, num_keys, order, sorted)
         integer(ip), intent(in) :: keys(:), num_keys, order(:)
         integer(ip), intent(out) :: sorted(:)
         integer(ip) :: k, key
         start = 0
         do k = 1, n
            start(keys(k) + 1) = start(keys(k) + 1) + 1
         end do
         start(1) = 1
         do key = 1, num_keys
            start(key + 1) = start(key + 1) + start(key)
         end do
         do k = 1, n
            key = keys(order(k))
            sorted(start(key)) = order(k)
            start(key) = start(key) + 1
         end do
      end subroutine counting_sort
   end procedure csr_from_coo

   module procedure csr_upper_coo
      integer(ip) :: i, k, count
      count = 0
      do i = 1, A%num_rows
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            if (A%col(k) >= i) count = count + 1
         end do
      end do
      allocate (irn(count), jcn(count), vals(count))
      count = 0
      do i = 1, A%num_rows
         do k = A%row_ptr(i), A%row_ptr(i + 1) - 1
            if (A%col(k) >= i) then
               count = count + 1
               irn(count) = i
               jcn(count) = A%col(k)
               vals(count) = A%val(k)
            end if
         end do
      end do
   end procedure csr_upper_coo

   module procedure csr_adjacency
      type(csr_t) :: At
      integer(ip) :: i, ka, kb, count, pass, j, n
      n = A%num_rows
      call csr_transpose(A, At)
      allocate (xadj(n + 1))
      xadj(1) = 1
      do pass = 1, 2
         count = 0
         do i = 1, n
            ka = A%row_ptr(i)
            kb = At%row_ptr(i)
            do while (ka < A%row_ptr(i + 1) .or. kb < At%row_ptr(i + 1))
               if (kb >= At%row_ptr(i + 1)) then
                  j = A%col(ka)
                  ka = ka + 1
               else if (ka >= A%row_ptr(i + 1)) then
                  j = At%col(kb)
                  kb = kb + 1
               else if (A%col(ka) < At%col(kb)) then
                  j = A%col(ka)
                  ka = ka + 1
               else if (A%col(ka) > At%col(kb)) then
                  j = At%col(kb)
                  kb = kb + 1
               else
                  j = A%col(ka)
                  ka = ka + 1
                  kb = kb + 1
               end if
               if (j == i) cycle
               count = count + 1
               if (pass == 2) adjncy(count) = j
            end do
            if (pass == 1) xadj(i + 1) = count + 1
         end do
         if (pass == 1) allocate (adjncy(count))
      end do
   end procedure csr_adjacency

   !> "<what>: A is 3 x 4 but B is 5 x 2; <rule>".
   subroutine shape_error(error, what, A, B, rule)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), intent(in) :: what, rule
      type(csr_t), intent(in) :: A, B
      call fatal_error(error, FFRF_INPUT_ERROR, what // ': A is ' // to_str(A%num_rows) // ' x ' &
         // to_str(A%num_cols) // ' but B is ' // to_str(B%num_rows) // ' x ' // &
         to_str(B%num_cols) // '; ' // rule)
   end subroutine shape_error

end submodule ffrf_la_sparse_build
