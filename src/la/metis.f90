!> METIS 5 fill-reducing orderings for the sparse direct solver. Debian's MUMPS is built without
!> METIS (toolchain.md, pitfall 1), so ffrf calls METIS_NodeND itself and hands the permutation to
!> MUMPS (ICNTL(7) = 1, PERM_IN). Debian's metis.h has 32-bit idx_t and real_t (IDXTYPEWIDTH =
!> REALTYPEWIDTH = 32), hence `c_int32_t` throughout. Numbering is 1-based
!> (METIS_OPTION_NUMBERING = 1) so that arrays pass to and from Fortran unchanged.
module ffrf_la_metis
   use ffrf_core_serial_section, only: enter_serial_section, leave_serial_section, SECTION_METIS
   use, intrinsic :: iso_c_binding, only: c_int, c_int32_t, c_ptr, c_null_ptr, c_loc
   use ffrf_core_kinds, only: ip, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_INPUT_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_la_sparse, only: sort_indices
   use ffrf_core_posix, only: hold_signals, release_signals, signal_test_point
   implicit none
   private
   public :: nested_dissection, pattern_adjacency, pattern_nested_dissection

   !> Length of the METIS options array (METIS_NOPTIONS in metis.h)
   integer, parameter :: metis_noptions = 40
   !> 0-based position of METIS_OPTION_NUMBERING in the options array (enum moptions_et)
   integer, parameter :: metis_option_numbering = 17
   !> Return codes (enum rstatus_et)
   integer(c_int), parameter :: metis_ok = 1, metis_error_input = -2, metis_error_memory = -3

   interface
      !> int METIS_SetDefaultOptions(idx_t *options)
      function metis_setdefaultoptions(options) result(stat) bind(c, name='METIS_SetDefaultOptions')
         import :: c_int, c_int32_t
         implicit none
         integer(c_int32_t), intent(out) :: options(*)
         integer(c_int) :: stat
      end function metis_setdefaultoptions

      !> int METIS_NodeND(idx_t *nvtxs, idx_t *xadj, idx_t *adjncy, idx_t *vwgt, idx_t *options,
      !> idx_t *perm, idx_t *iperm). METIS shifts xadj/adjncy to 0-based and back in place, so
      !> they are `inout`; vwgt is passed as NULL (unit vertex weights).
      function metis_nodend(nvtxs, xadj, adjncy, vwgt, options, perm, iperm) result(stat) &
         bind(c, name='METIS_NodeND')
         import :: c_int, c_int32_t, c_ptr
         implicit none
         integer(c_int32_t), intent(in) :: nvtxs
         integer(c_int32_t), intent(inout) :: xadj(*), adjncy(*)
         type(c_ptr), value :: vwgt
         integer(c_int32_t), intent(in) :: options(*)
         integer(c_int32_t), intent(out) :: perm(*), iperm(*)
         integer(c_int) :: stat
      end function metis_nodend
   end interface

contains

   !> Nested-dissection ordering of a graph (METIS_NodeND, 1-based). Row i of the permuted matrix
   !> is row perm(i) of the original one; iperm is the inverse: original vertex i is eliminated at
   !> step iperm(i). MUMPS wants iperm as PERM_IN.
   subroutine nested_dissection(n, xadj, adjncy, perm, iperm, error, weights)
      !> Number of vertices
      integer(ip), intent(in) :: n
      !> Adjacency pointers (size n+1, 1-based; xadj(n+1) - 1 = size(adjncy)); no self loops,
      !> every edge stored in both directions
      integer(ip), intent(in) :: xadj(:)
      !> Neighbours of vertex i in adjncy(xadj(i):xadj(i+1)-1), 1-based
      integer(ip), intent(in) :: adjncy(:)
      !> Fill-reducing permutation (new -> old)
      integer(ip), intent(out) :: perm(:)
      !> Inverse permutation (old -> new)
      integer(ip), intent(out) :: iperm(:)
      type(error_t), allocatable, intent(out) :: error
      !> Vertex weights (e.g. the size of each supervariable); unit weights if absent
      integer(ip), intent(in), optional :: weights(:)
      integer(c_int32_t), allocatable, target :: vwgt(:)
      type(c_ptr) :: vwgt_ptr
      integer(c_int32_t) :: options(0:metis_noptions - 1)
      integer(c_int32_t), allocatable :: xadj_c(:), adjncy_c(:)
      integer(c_int32_t) :: nvtxs
      integer(c_int) :: stat
      integer(ip) :: i, num_edges

      if (n < 0 .or. size(xadj) /= n + 1 .or. size(perm) /= n .or. size(iperm) /= n) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'nested_dissection: n = ' // to_str(n) // &
            ', size(xadj) = ' // to_str(size(xadj)) // ', size(perm) = ' // to_str(size(perm)) // &
            ', size(iperm) = ' // to_str(size(iperm)) // '; need n >= 0, n+1, n and n')
         return
      end if
      if (n == 0) return
      num_edges = xadj(n + 1) - 1
      if (xadj(1) /= 1 .or. num_edges < 0 .or. num_edges > size(adjncy)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'nested_dissection: xadj(1) = ' // &
            to_str(xadj(1)) // ', xadj(n+1) = ' // to_str(xadj(n + 1)) // ' with size(adjncy) = ' &
            // to_str(size(adjncy)) // '; xadj must be 1-based pointers into adjncy')
         return
      end if
      if (num_edges > 0) then
         if (minval(adjncy(1:num_edges)) < 1 .or. maxval(adjncy(1:num_edges)) > n) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'nested_dissection: a neighbour index lies '&
               // 'outside 1..' // to_str(n) // ' (range found ' // &
               to_str(minval(adjncy(1:num_edges))) // '..' // &
               to_str(maxval(adjncy(1:num_edges))) // ')')
            return
         end if
      end if
      ! A graph without edges has nothing to order (and METIS 5.1 rejects an empty adjncy).
      if (num_edges == 0) then
         perm = [(i, i=1, n)]
         iperm = perm
         return
      end if

      stat = metis_setdefaultoptions(options)
      if (stat /= metis_ok) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'METIS_SetDefaultOptions returned ' // &
            to_str(int(stat, ip)))
         return
      end if
      options(metis_option_numbering) = 1
      nvtxs = n
      xadj_c = xadj
      adjncy_c = adjncy(1:num_edges)
      vwgt_ptr = c_null_ptr
      if (present(weights)) then
         vwgt = weights
         vwgt_ptr = c_loc(vwgt)
      end if
      ! METIS 5.1 draws from GKlib's random generator, whose state is a process-wide static:
      ! two orderings at once would interleave its draws and differ from run to run
      call enter_serial_section(SECTION_METIS)
      ! METIS_NodeND installs handlers of its own for SIGTERM and SIGABRT and puts the previous
      ! ones back with SysV signal() (one-shot, no SA_RESTART): the run signals are held
      ! meanwhile and their handlers restored after (ffrf_core_posix hold_signals; issue 23)
      call signal_test_point('ordering:before')
      call hold_signals()
      call signal_test_point('ordering:during')
      stat = metis_nodend(nvtxs, xadj_c, adjncy_c, vwgt_ptr, options, perm, iperm)
      call signal_test_point('ordering:end')
      call release_signals()
      call signal_test_point('ordering:after')
      call leave_serial_section(SECTION_METIS)
      select case (stat)
      case (metis_ok)
      case (metis_error_input)
         call fatal_error(error, FFRF_INPUT_ERROR, 'METIS_NodeND: erroneous input graph (n = ' &
            // to_str(n) // ', ' // to_str(num_edges) // ' adjacency entries); check that the ' &
            // 'graph is symmetric and has no self loops')
      case (metis_error_memory)
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'METIS_NodeND: out of memory ordering a ' &
            // 'graph of ' // to_str(n) // ' vertices and ' // to_str(num_edges) // &
            ' adjacency entries')
      case default
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'METIS_NodeND failed with code ' // &
            to_str(int(stat, ip)) // ' (n = ' // to_str(n) // ')')
      end select
   end subroutine nested_dissection

   !> Symmetric adjacency graph (no self loops, no duplicates) of the sparsity pattern of a
   !> symmetric matrix given as COO entries (irn(k), jcn(k)) of either or both triangles.
   subroutine pattern_adjacency(n, irn, jcn, xadj, adjncy, error)
      !> Matrix order
      integer(ip), intent(in) :: n
      !> Row index of each entry, 1-based
      integer(ip), intent(in) :: irn(:)
      !> Column index of each entry, 1-based
      integer(ip), intent(in) :: jcn(:)
      !> Adjacency pointers (size n+1)
      integer(ip), allocatable, intent(out) :: xadj(:)
      !> Neighbours, sorted within each vertex
      integer(ip), allocatable, intent(out) :: adjncy(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: count(:), fill(:), raw(:)
      integer(i8) :: k, num_offdiag
      integer(ip) :: i, j, p, q, stat, last, start

      if (size(irn) /= size(jcn)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pattern_adjacency: size(irn) = ' // &
            to_str(size(irn)) // ' differs from size(jcn) = ' // to_str(size(jcn)))
         return
      end if
      allocate (count(n), source=0_ip)
      num_offdiag = 0
      do k = 1, size(irn, kind=i8)
         i = irn(k)
         j = jcn(k)
         if (i < 1 .or. i > n .or. j < 1 .or. j > n) then
            call fatal_error(error, FFRF_INPUT_ERROR, 'pattern_adjacency: entry ' // to_str(k) &
               // ' at (' // to_str(i) // ', ' // to_str(j) // ') lies outside the ' // &
               to_str(n) // ' x ' // to_str(n) // ' matrix')
            return
         end if
         if (i == j) cycle
         count(i) = count(i) + 1
         count(j) = count(j) + 1
         num_offdiag = num_offdiag + 2
      end do
      if (num_offdiag > huge(1_ip)) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'pattern_adjacency: ' // to_str(num_offdiag) &
            // ' adjacency entries exceed the 32-bit indices of METIS')
         return
      end if
      ! Raw lists with duplicates (both triangles may be given), then sort and compress each list.
      allocate (xadj(n + 1), raw(num_offdiag), fill(n), stat=stat)
      if (stat /= 0) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, 'pattern_adjacency: cannot allocate ' // &
            to_str(num_offdiag) // ' adjacency entries')
         return
      end if
      call set_offsets()
      fill = xadj(1:n)
      do k = 1, size(irn, kind=i8)
         i = irn(k)
         j = jcn(k)
         if (i == j) cycle
         raw(fill(i)) = j
         fill(i) = fill(i) + 1
         raw(fill(j)) = i
         fill(j) = fill(j) + 1
      end do
      ! Compress in place: sort each list and drop repeats; count(i) becomes the unique count.
      last = 0
      do i = 1, n
         start = xadj(i)
         call sort_indices(raw(start:xadj(i + 1) - 1))
         q = 0
         do p = start, xadj(i + 1) - 1
            if (q > 0) then
               if (raw(p) == raw(last)) cycle
            end if
            last = last + 1
            raw(last) = raw(p)
            q = q + 1
         end do
         count(i) = q
      end do
      call set_offsets()
      adjncy = raw(1:last)
   contains
      !> xadj(1) = 1, xadj(i + 1) = xadj(i) + count(i): list i is xadj(i) : xadj(i + 1) - 1.
      subroutine set_offsets()
         xadj(1) = 1
         do i = 1, n
            xadj(i + 1) = xadj(i) + count(i)
         end do
      end subroutine set_offsets
   end subroutine pattern_adjacency

   !> Nested-dissection ordering of the pattern of a symmetric COO matrix: `pattern_adjacency`,
   !> then consecutive vertices with identical closed neighbourhoods (the x, y, z dofs of a node)
   !> are merged into supervariables, METIS orders the weighted quotient graph (a third of the
   !> size for 3-dof nodes) and the order is expanded back, members kept together.
   subroutine pattern_nested_dissection(n, irn, jcn, perm, iperm, error)
      !> Matrix order
      integer(ip), intent(in) :: n
      !> Row index of each entry, 1-based
      integer(ip), intent(in) :: irn(:)
      !> Column index of each entry, 1-based
      integer(ip), intent(in) :: jcn(:)
      !> Fill-reducing permutation (new -> old)
      integer(ip), intent(out) :: perm(:)
      !> Inverse permutation (old -> new), the PERM_IN of MUMPS
      integer(ip), intent(out) :: iperm(:)
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: xadj(:), adjncy(:), super(:), first(:), qxadj(:), qadj(:)
      integer(ip), allocatable :: qperm(:), qiperm(:), weights(:)
      integer(ip) :: i, s, num_super, p, k, last
      call pattern_adjacency(n, irn, jcn, xadj, adjncy, error)
      if (allocated(error)) return
      if (size(perm) /= n .or. size(iperm) /= n) then
         call nested_dissection(n, xadj, adjncy, perm, iperm, error)
         return
      end if
      ! Supervariables: runs of consecutive vertices with identical closed neighbourhoods.
      allocate (super(n), first(n + 1))
      num_super = 0
      do i = 1, n
         if (i > 1) then
            if (same_closed_neighbourhood(xadj, adjncy, i - 1, i)) then
               super(i) = num_super
               cycle
            end if
         end if
         num_super = num_super + 1
         super(i) = num_super
         first(num_super) = i
      end do
      first(num_super + 1) = n + 1
      if (num_super == n) then
         call nested_dissection(n, xadj, adjncy, perm, iperm, error)
         return
      end if
      ! Quotient graph: the neighbours of a supervariable are those of its first member,
      ! mapped to supervariables (nondecreasing along the sorted list) without repeats or itself.
      allocate (qxadj(num_super + 1), qadj(size(adjncy)), weights(num_super))
      qxadj(1) = 1
      k = 0
      do s = 1, num_super
         i = first(s)
         weights(s) = first(s + 1) - first(s)
         last = 0
         do p = xadj(i), xadj(i + 1) - 1
            if (super(adjncy(p)) == s .or. super(adjncy(p)) == last) cycle
            last = super(adjncy(p))
            k = k + 1
            qadj(k) = last
         end do
         qxadj(s + 1) = k + 1
      end do
      allocate (qperm(num_super), qiperm(num_super))
      call nested_dissection(num_super, qxadj, qadj(1:k), qperm, qiperm, error, weights)
      if (allocated(error)) return
      k = 0
      do s = 1, num_super
         do i = first(qperm(s)), first(qperm(s) + 1) - 1
            k = k + 1
            perm(k) = i
            iperm(i) = k
         end do
      end do
   end subroutine pattern_nested_dissection

   !> Vertices a < b have the same closed neighbourhood: they are adjacent and adj(a) \ {b}
   !> equals adj(b) \ {a} (lists sorted).
   pure logical function same_closed_neighbourhood(xadj, adjncy, a, b) result(same)
      integer(ip), intent(in) :: xadj(:), adjncy(:), a, b
      integer(ip) :: pa, pb, ea, eb
      same = .false.
      if (xadj(a + 1) - xadj(a) /= xadj(b + 1) - xadj(b)) return
      pa = xadj(a)
      pb = xadj(b)
      ea = xadj(a + 1)
      eb = xadj(b + 1)
      do
         if (pa < ea) then
            if (adjncy(pa) == b) pa = pa + 1
         end if
         if (pb < eb) then
            if (adjncy(pb) == a) pb = pb + 1
         end if
         if (pa >= ea .or. pb >= eb) exit
         if (adjncy(pa) /= adjncy(pb)) return
         pa = pa + 1
         pb = pb + 1
      end do
      same = pa >= ea .and. pb >= eb .and. any(adjncy(xadj(a):ea - 1) == b)
   end function same_closed_neighbourhood

end module ffrf_la_metis
