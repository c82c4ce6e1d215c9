!> The RC matrix of a body: full nodal dofs q (3 per node) in terms of reduced coordinates p,
!> q = T p, with optional linear constraints C p = 0 (Cammarata et al. 2022; theory.md section 2).
!>
!> Two formulations give the same constrained normal modes:
!> - 'multipliers' (scalable, default): RBE2 interfaces are eliminated, q_B = F q_V with the
!>   constrained virtual dofs dropped (T = F B2, B2 = the columns of I6 that D does not select,
!>   a sparse T); RBE3 reference conditions D G q_B = 0 stay as constraint rows C, handled by
!>   Lagrange multipliers in the shift-invert operator: nothing dense of the body's size is formed.
!> - 'null_space' (explicit, for verification and small interfaces): B2 = null(D) for RBE2
!>   (T_B = F B2) and B2 = null(D G) for RBE3 (T = blockdiag(B2, I)), both from LAPACK's SVD.
module ffrf_mpc_reduction
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t, fatal_error, add_context, FFRF_INPUT_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: csr_t, csr_from_coo, csr_matmul, csr_transpose, csr_row_gram
   use ffrf_la_dense, only: null_space, symmetric_eigen
   use ffrf_la_lapack, only: dposv
   use ffrf_mpc_interface, only: interface_t, MPC_RBE2, MPC_RBE3, DOF_NAMES
   !> The formulations (FORMULATION_NONE: no reduction built, a body without modes) and their table
   use ffrf_core_choices, only: FORMULATION_NONE, FORMULATION_MULTIPLIERS, FORMULATION_NULL_SPACE, &
      formulation_choices, choice_name
   implicit none
   private
   public :: reduction_t, build_reduction, reduce_matrix, expand_vectors, reduced_coordinates
   public :: add_virtual_node_row, reduce_rows
   public :: FORMULATION_NONE, FORMULATION_MULTIPLIERS, FORMULATION_NULL_SPACE, formulation_name

   !> q = T p with C p = 0.
   type :: reduction_t
      !> FORMULATION_MULTIPLIERS or FORMULATION_NULL_SPACE
      integer :: formulation = FORMULATION_NONE
      !> Number of nodal dofs, 3 * num_nodes
      integer(ip) :: num_full = 0
      !> Number of reduced coordinates p
      integer(ip) :: num_reduced = 0
      !> True when T is the identity (no elimination): reduced matrices are the full ones
      logical :: is_identity = .true.
      !> T, num_full x num_reduced (only when not is_identity)
      type(csr_t) :: T
      !> Constraint rows C, num_constraints x num_reduced (may have no rows)
      type(csr_t) :: C
      !> "interface dof" of each constraint row, for messages
      character(len=80), allocatable :: constraint_labels(:)
      !> Per interface: first reduced column of the block of new columns that replaces its node
      !> dofs, and their number (0: the interface owns no nodes)
      integer(ip), allocatable :: block_first(:), block_columns(:)
      !> Per interface: the block's columns are orthonormal (the SVD null spaces of RBE3 in the
      !> null-space formulation), so B^T B = I
      logical, allocatable :: block_orthonormal(:)
   end type reduction_t

   !> Per-interface dense block: the owned node dofs in terms of new reduced columns.
   type :: owned_block_t
      real(dp), allocatable :: B(:, :)
      integer(ip) :: first_column = 0
   end type owned_block_t

contains

   !> Build T and C for `interfaces` of a body with `num_nodes` nodes.
   subroutine build_reduction(num_nodes, interfaces, formulation, red, error)
      !> Number of body nodes
      integer(ip), intent(in) :: num_nodes
      !> Interfaces with F/G and reference conditions
      type(interface_t), intent(in) :: interfaces(:)
      !> FORMULATION_MULTIPLIERS or FORMULATION_NULL_SPACE
      integer, intent(in) :: formulation
      !> Result
      type(reduction_t), intent(out) :: red
      type(error_t), allocatable, intent(out) :: error
      integer, allocatable :: owner(:)
      integer(ip), allocatable :: column_of(:), rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      type(owned_block_t), allocatable :: blocks(:)
      integer(ip) :: next_column, nnz
      integer :: k, i, c, j, dof

      if (formulation /= FORMULATION_MULTIPLIERS .and. formulation /= FORMULATION_NULL_SPACE) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'formulation = ' // to_str(formulation) // &
            ' is not known; use FORMULATION_MULTIPLIERS or FORMULATION_NULL_SPACE')
         return
      end if
      red%formulation = formulation
      red%num_full = 3 * num_nodes

      ! Which interface's block replaces each node's dofs (0: the node keeps its own dofs).
      allocate (owner(num_nodes), source=0)
      allocate (blocks(size(interfaces)))
      do k = 1, size(interfaces)
         if (.not. owns_nodes(interfaces(k), formulation)) cycle
         do i = 1, size(interfaces(k)%nodes)
            if (owner(interfaces(k)%nodes(i)) /= 0) then
               call fatal_error(error, FFRF_INPUT_ERROR, 'interfaces "' // &
                  interfaces(owner(interfaces(k)%nodes(i)))%name // '" and "' // &
                  interfaces(k)%name // '" share node ' // to_str(interfaces(k)%nodes(i)) // &
                  ': a node can be eliminated by one rigid/null-space interface only; ' // &
                  'use separate faces, RBE3, or formulation = "multipliers"')
               return
            end if
            owner(interfaces(k)%nodes(i)) = k
         end do
         call owned_block(interfaces(k), formulation, blocks(k)%B, error)
         if (allocated(error)) then
            call add_context(error, 'interface "' // interfaces(k)%name // '"')
            return
         end if
      end do

      ! Reduced columns: the dofs of nodes nobody owns, then each owner's new columns.
      allocate (column_of(red%num_full), source=0_ip)
      allocate (red%block_first(size(interfaces)), red%block_columns(size(interfaces)), &
         source=0_ip)
      allocate (red%block_orthonormal(size(interfaces)), source=.false.)
      next_column = 0
      do i = 1, num_nodes
         if (owner(i) /= 0) cycle
         do c = 1, 3
            next_column = next_column + 1
            column_of(3 * (i - 1) + c) = next_column
         end do
      end do
      do k = 1, size(interfaces)
         if (.not. allocated(blocks(k)%B)) cycle
         blocks(k)%first_column = next_column + 1
         red%block_first(k) = next_column + 1
         red%block_columns(k) = int(size(blocks(k)%B, 2), ip)
         red%block_orthonormal(k) = interfaces(k)%mpc == MPC_RBE3
         next_column = next_column + int(size(blocks(k)%B, 2), ip)
      end do
      red%num_reduced = next_column
      red%is_identity = all(owner == 0)

      if (.not. red%is_identity) then
         nnz = count(owner == 0) * 3
         do k = 1, size(interfaces)
            if (allocated(blocks(k)%B)) nnz = nnz + int(count(blocks(k)%B /= 0.0_dp), ip)
         end do
         allocate (rows(nnz), cols(nnz), vals(nnz))
         nnz = 0
         do dof = 1, red%num_full
            if (column_of(dof) == 0) cycle
            nnz = nnz + 1
            rows(nnz) = int(dof, ip)
            cols(nnz) = column_of(dof)
            vals(nnz) = 1.0_dp
         end do
         do k = 1, size(interfaces)
            if (.not. allocated(blocks(k)%B)) cycle
            do i = 1, size(interfaces(k)%nodes)
               do c = 1, 3
                  do j = 1, size(blocks(k)%B, 2)
                     if (blocks(k)%B(3 * (i - 1) + c, j) == 0.0_dp) cycle
                     nnz = nnz + 1
                     rows(nnz) = 3 * (interfaces(k)%nodes(i) - 1) + int(c, ip)
                     cols(nnz) = blocks(k)%first_column + int(j, ip) - 1
                     vals(nnz) = blocks(k)%B(3 * (i - 1) + c, j)
                  end do
               end do
            end do
         end do
         call csr_from_coo(red%num_full, red%num_reduced, rows, cols, vals, red%T, error)
         if (allocated(error)) return
      end if

      call build_constraints(interfaces, formulation, red, error)
   end subroutine build_reduction

   !> An interface replaces its node dofs by a block of new columns when it is an RBE2, or an
   !> RBE3 with reference conditions in the null-space formulation.
   pure logical function owns_nodes(iface, formulation)
      type(interface_t), intent(in) :: iface
      integer, intent(in) :: formulation
      owns_nodes = iface%mpc == MPC_RBE2 .or. &
         (formulation == FORMULATION_NULL_SPACE .and. any(iface%rc))
   end function owns_nodes

   !> The block B (3 nB x new columns) with q_B = B p_new:
   !> RBE2: F B2 with B2 = unselected columns of I6 ('multipliers') or null(D) (SVD);
   !> RBE3: null(D G) (SVD).
   subroutine owned_block(iface, formulation, B, error)
      type(interface_t), intent(in) :: iface
      integer, intent(in) :: formulation
      real(dp), allocatable, intent(out) :: B(:, :)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: D(:, :), B2(:, :), DG(:, :)
      integer :: rank, num_rc, dof, row
      num_rc = count(iface%rc)
      allocate (D(num_rc, 6), source=0.0_dp)
      row = 0
      do dof = 1, 6
         if (.not. iface%rc(dof)) cycle
         row = row + 1
         D(row, dof) = 1.0_dp
      end do
      if (iface%mpc == MPC_RBE2) then
         if (formulation == FORMULATION_MULTIPLIERS) then
            B = iface%F(:, pack([(dof, dof=1, 6)], .not. iface%rc))
         else
            call null_space(D, B2, rank, 1.0e-12_dp, error)
            if (allocated(error)) return
            B = matmul(iface%F, B2)
         end if
      else
         DG = matmul(D, iface%G)
         ! Rotation rows of G scale with 1/length: normalise rows before the rank test.
         do row = 1, num_rc
            DG(row, :) = DG(row, :) / max(norm2(DG(row, :)), tiny(1.0_dp))
         end do
         call null_space(DG, B, rank, 1.0e-10_dp, error)
         if (allocated(error)) return
         if (rank < num_rc) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'the reference conditions have ' // &
               'dependent rows (rank ' // to_str(rank) // ' of ' // to_str(num_rc) // &
               '): the face nodes cannot carry them all; remove a rotation RC')
            return
         end if
      end if
   end subroutine owned_block

   !> Constraint rows C p = 0: RBE3 reference conditions D G q_B = 0 in the multiplier
   !> formulation (C = C_full T when T is not the identity). Dependent rows are refused.
   subroutine build_constraints(interfaces, formulation, red, error)
      type(interface_t), intent(in) :: interfaces(:)
      integer, intent(in) :: formulation
      type(reduction_t), intent(inout) :: red
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: rows(:), cols(:)
      real(dp), allocatable :: vals(:)
      type(csr_t) :: c_reduced
      integer(ip) :: num_rows, nnz
      integer :: k, d

      num_rows = 0
      nnz = 0
      do k = 1, size(interfaces)
         if (.not. is_constraint_interface(interfaces(k), formulation)) cycle
         num_rows = num_rows + count(interfaces(k)%rc)
         nnz = nnz + count(interfaces(k)%rc) * 3 * size(interfaces(k)%nodes)
      end do
      allocate (red%constraint_labels(num_rows), rows(nnz), cols(nnz), vals(nnz))
      num_rows = 0
      nnz = 0
      do k = 1, size(interfaces)
         if (.not. is_constraint_interface(interfaces(k), formulation)) cycle
         do d = 1, 6
            if (.not. interfaces(k)%rc(d)) cycle
            num_rows = num_rows + 1
            red%constraint_labels(num_rows) = 'interface "' // interfaces(k)%name // '" ' // &
               DOF_NAMES(d)
            call add_virtual_node_row(interfaces(k), d, num_rows, rows, cols, vals, nnz)
         end do
      end do
      call reduce_rows(red, num_rows, rows, cols, vals, c_reduced, error)
      if (allocated(error)) return
      red%C = c_reduced
      call check_independent_rows(red, error)
   end subroutine build_constraints

   !> Row r of the virtual-node rows on the full dofs: the row d of interface iface's G
   !> (q_V = G q_B), appended to the COO arrays after entry nnz (nnz counts them).
   subroutine add_virtual_node_row(iface, d, r, rows, cols, vals, nnz)
      type(interface_t), intent(in) :: iface
      !> Virtual-node dof 1..6 (DOF_NAMES)
      integer, intent(in) :: d
      integer(ip), intent(in) :: r
      integer(ip), intent(inout) :: rows(:), cols(:), nnz
      real(dp), intent(inout) :: vals(:)
      integer :: i, c
      do i = 1, size(iface%nodes)
         do c = 1, 3
            nnz = nnz + 1
            rows(nnz) = r
            cols(nnz) = 3 * (iface%nodes(i) - 1) + int(c, ip)
            vals(nnz) = iface%G(d, 3 * (i - 1) + c)
         end do
      end do
   end subroutine add_virtual_node_row

   !> C = C_full T of rows given on the full dofs (COO; C_full itself when T is the identity).
   subroutine reduce_rows(red, num_rows, rows, cols, vals, C, error)
      type(reduction_t), intent(in) :: red
      integer(ip), intent(in) :: num_rows, rows(:), cols(:)
      real(dp), intent(in) :: vals(:)
      type(csr_t), intent(out) :: C
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: c_full
      call csr_from_coo(num_rows, red%num_full, rows, cols, vals, c_full, error)
      if (allocated(error)) return
      if (red%is_identity) then
         C = c_full
      else
         call csr_matmul(c_full, red%T, C, error)
      end if
   end subroutine reduce_rows

   pure logical function is_constraint_interface(iface, formulation)
      type(interface_t), intent(in) :: iface
      integer, intent(in) :: formulation
      is_constraint_interface = iface%mpc == MPC_RBE3 .and. any(iface%rc) .and. &
         formulation == FORMULATION_MULTIPLIERS
   end function is_constraint_interface

   !> The first constraint row that depends on the previous ones is named in the error.
   subroutine check_independent_rows(red, error)
      type(reduction_t), intent(in) :: red
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: gram(:, :), values(:), vectors(:, :), row_norm(:)
      integer :: n, m
      n = red%C%num_rows
      if (n == 0) return
      call csr_row_gram(red%C, gram, row_norm)
      do m = 1, n
         allocate (values(m), vectors(m, m))
         call symmetric_eigen(gram(1:m, 1:m), values, vectors, error)
         if (allocated(error)) return
         if (values(1) <= 1.0e-10_dp) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'reference condition of ' // &
               trim(red%constraint_labels(m)) // ' depends on the previous ones (dependent ' // &
               'row of D G): the interface nodes cannot carry it; remove it from rc')
            return
         end if
         deallocate (values, vectors)
      end do
   end subroutine check_independent_rows

   !> A_r = T^T A T (A itself when T is the identity).
   subroutine reduce_matrix(red, A, A_r, error)
      !> Reduction
      type(reduction_t), intent(in) :: red
      !> Full matrix, both triangles
      type(csr_t), intent(in) :: A
      !> Reduced matrix, both triangles
      type(csr_t), intent(out) :: A_r
      type(error_t), allocatable, intent(out) :: error
      type(csr_t) :: at, tt
      if (red%is_identity) then
         A_r = A
         return
      end if
      call csr_matmul(A, red%T, at, error)
      if (allocated(error)) return
      call csr_transpose(red%T, tt)
      call csr_matmul(tt, at, A_r, error)
   end subroutine reduce_matrix

   !> q = T p for each column.
   subroutine expand_vectors(red, p, q)
      !> Reduction
      type(reduction_t), intent(in) :: red
      !> Reduced vectors, (num_reduced, m)
      real(dp), intent(in) :: p(:, :)
      !> Full vectors, (num_full, m)
      real(dp), allocatable, intent(out) :: q(:, :)
      integer(ip) :: i, k
      if (red%is_identity) then
         q = p
         return
      end if
      allocate (q(red%num_full, size(p, 2)), source=0.0_dp)
      do i = 1, red%T%num_rows
         do k = red%T%row_ptr(i), red%T%row_ptr(i + 1) - 1
            q(i, :) = q(i, :) + red%T%val(k) * p(red%T%col(k), :)
         end do
      end do
   end subroutine expand_vectors

   !> p with T p = q for vectors q in the range of T (columns), as the least-squares solution
   !> p = (T^T T)^-1 T^T q. T^T T is block diagonal: 1 for the nodal dofs T keeps, B^T B for the
   !> block B of an owned interface (at most 6 columns for an RBE2; the identity for the
   !> orthonormal SVD null spaces of an RBE3). Used for the rigid-body motions of the mesh
   !> (ffrf_modes_modal_analysis), which lie in the range of T when the reference conditions
   !> leave them free. `residual`: max over the columns of ||T p - q|| / ||q|| (0 for q in the
   !> range of T, up to round-off).
   subroutine reduced_coordinates(red, q, p, residual, error)
      !> Reduction
      type(reduction_t), intent(in) :: red
      !> Full vectors, (num_full, m)
      real(dp), intent(in) :: q(:, :)
      !> Reduced vectors, (num_reduced, m)
      real(dp), allocatable, intent(out) :: p(:, :)
      !> Largest relative residual ||T p - q|| / ||q|| of the columns
      real(dp), intent(out) :: residual
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: normal(:, :), g(:, :), tq(:, :)
      integer(ip) :: i, k, l, a, b, first, last, c, info
      integer :: blk, j
      residual = 0.0_dp
      if (red%is_identity) then
         p = q
         return
      end if
      ! g = T^T q
      allocate (p(red%num_reduced, size(q, 2)), source=0.0_dp)
      do i = 1, red%T%num_rows
         do k = red%T%row_ptr(i), red%T%row_ptr(i + 1) - 1
            p(red%T%col(k), :) = p(red%T%col(k), :) + red%T%val(k) * q(i, :)
         end do
      end do
      ! (B^T B) p_B = g_B for each owned block whose columns are not orthonormal
      do blk = 1, size(red%block_columns)
         c = red%block_columns(blk)
         if (c == 0 .or. red%block_orthonormal(blk)) cycle
         first = red%block_first(blk)
         last = first + c - 1
         allocate (normal(c, c), source=0.0_dp)
         do i = 1, red%T%num_rows
            do k = red%T%row_ptr(i), red%T%row_ptr(i + 1) - 1
               a = red%T%col(k)
               if (a < first .or. a > last) cycle
               do l = red%T%row_ptr(i), red%T%row_ptr(i + 1) - 1
                  b = red%T%col(l)
                  if (b < first .or. b > last) cycle
                  normal(a - first + 1, b - first + 1) = normal(a - first + 1, b - first + 1) + &
                     red%T%val(k) * red%T%val(l)
               end do
            end do
         end do
         g = p(first:last, :)
         call dposv('U', c, int(size(q, 2), ip), normal, c, g, c, info)
         if (info /= 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'reduced coordinates: the block of ' // &
               'interface ' // to_str(blk) // ' has dependent columns (dposv info = ' // &
               to_str(info) // ')')
            return
         end if
         p(first:last, :) = g
         deallocate (normal)
      end do
      call expand_vectors(red, p, tq)
      do j = 1, size(q, 2)
         residual = max(residual, norm2(tq(:, j) - q(:, j)) / max(norm2(q(:, j)), tiny(1.0_dp)))
      end do
   end subroutine reduced_coordinates

   !> 'multipliers', 'null_space' or 'none' (the &modes key's words), for logs and results.
   pure function formulation_name(formulation) result(name)
      !> FORMULATION_MULTIPLIERS, FORMULATION_NULL_SPACE or FORMULATION_NONE
      integer, intent(in) :: formulation
      character(len=:), allocatable :: name
      name = choice_name(formulation_choices, formulation, 'none')
   end function formulation_name

end module ffrf_mpc_reduction
