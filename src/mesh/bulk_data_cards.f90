!> ffrf_mesh_bulk_data: the cards of a deck turned into a mesh_t (docs/input.md "Nastran bulk
!> data"). GRID (basic coordinates, or a CORD2R defined in basic), CTETRA (4 or 10 grids; the
!> Nastran Tet10 order G5 (1,2) G6 (2,3) G7 (3,1) G8 (1,4) G9 (2,4) G10 (3,4) is Gmsh's with
!> the last two swapped), PSOLID (a physical volume named by its id), MAT1 (the volume's
!> material), RBE2 and RBE3 (interfaces named by element id), SPC1 and SET1 (checked, not
!> applied). Other element, mass and rigid-element cards and GRDSET are refused (they change
!> the model); any other card is listed in mesh%ignored_cards and not read.
submodule(ffrf_mesh_bulk_data:ffrf_mesh_bulk_data_fields) ffrf_mesh_bulk_data_cards
   use ffrf_core_choices, only: MPC_RBE2, MPC_RBE3
   use ffrf_la_sparse, only: sort_indices
   implicit none

   !> Cards that change the model and are not read: refused
   character(len=8), parameter :: REFUSED(*) = [character(len=8) :: 'chexa', 'cpenta', &
      'cpyram', 'cquad4', 'cquad8', 'cquadr', 'ctria3', 'ctria6', 'ctriar', 'cshear', 'cbar', &
      'cbeam', 'cbend', 'crod', 'conrod', 'ctube', 'cbush', 'cbush1d', 'celas1', 'celas2', &
      'celas3', 'celas4', 'cdamp1', 'cdamp2', 'cdamp3', 'cdamp4', 'cvisc', 'cgap', 'conm1', &
      'conm2', 'cmass1', 'cmass2', 'cmass3', 'cmass4', 'rbar', 'rbar1', 'rbe1', 'rrod', &
      'rspline', 'rtrplt', 'grdset', 'genel', 'cweld', 'cfast', 'cseam', 'chacab', 'chbdyg']

contains

   module procedure build_mesh
      type(grid_map_t) :: grids
      real(dp), allocatable :: cord(:, :, :)
      integer(i8), allocatable :: cord_id(:), psolid(:, :), mat_id(:)
      real(dp), allocatable :: mat(:, :)
      integer, allocatable :: mat_card(:)
      logical, allocatable :: on_tet(:)
      character(len=8), allocatable :: other(:)
      integer, allocatable :: other_count(:)
      integer(i8) :: duplicate
      integer :: c, k, n

      allocate (cord(3, 4, 0), cord_id(0), psolid(3, 0), mat_id(0), mat(3, 0), mat_card(0))
      allocate (other(0), other_count(0))
      mesh%file_name = trim(deck%files(1))
      ! coordinate systems first: a GRID may come before its CORD2R
      do c = 1, deck%num_cards
         if (deck%name(c) == 'cord2r') call read_cord2r(deck, c, cord_id, cord, error)
         if (allocated(error)) return
      end do
      n = count(deck%name(:deck%num_cards) == 'grid')
      allocate (mesh%xyz(3, n), mesh%node_tags(n), grids%id(n))
      k = 0
      do c = 1, deck%num_cards
         select case (trim(deck%name(c)))
         case ('grid')
            k = k + 1
            call read_grid(deck, c, cord_id, cord, grids%id(k), mesh%xyz(:, k), error)
         case ('mat1')
            call read_mat1(deck, c, mat_id, mat, mat_card, error)
         case ('psolid')
            call read_psolid(deck, c, psolid, error)
         case ('ctetra', 'rbe2', 'rbe3', 'spc1', 'set1', 'cord2r')
         case default
            if (any(REFUSED == deck%name(c))) then
               call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': ffrf ' // &
                  'reads tetrahedra (CTETRA), RBE2 and RBE3 only; without this card the ' // &
                  'model would change: remove it or mesh the part with CTETRA')
               return
            end if
            call tally(other, other_count, deck%name(c))
         end select
         if (allocated(error)) return
      end do
      mesh%num_nodes = n
      mesh%node_tags = grids%id
      call sort_grids(grids, duplicate)
      if (duplicate /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, 'deck ''' // trim(deck%files(1)) // &
            ''': GRID ' // to_str(duplicate) // ' is given twice; grid ids must be unique')
         return
      end if
      call read_tets(deck, grids, psolid, mesh, error)
      if (allocated(error)) return
      call volume_groups(deck, psolid, mat_id, mat, mat_card, mesh, error)
      if (allocated(error)) return
      allocate (on_tet(n), source=.false.)
      do k = 1, mesh%num_tets()
         on_tet(mesh%tets(:, k)) = .true.
      end do
      call read_rbes(deck, grids, on_tet, mesh, error)
      if (allocated(error)) return
      call check_sets(deck, grids, other, other_count, error)
      if (allocated(error)) return
      mesh%ignored_cards = ''
      do k = 1, size(other)
         if (k > 1) mesh%ignored_cards = mesh%ignored_cards // ', '
         mesh%ignored_cards = mesh%ignored_cards // to_upper(other(k)) // ' (' // &
            to_str(other_count(k)) // ')'
      end do
      mesh%nodes_per_tri = 0
      allocate (mesh%tris(0, 0), mesh%tri_tags(0), mesh%tri_entity(0))
      allocate (mesh%other_volume_elements(4, 0))
   end procedure build_mesh

   !> CORD2R CID RID A1 A2 A3 B1 B2 B3 / C1 C2 C3: origin A, z along B - A, x in the plane of C.
   subroutine read_cord2r(deck, c, cord_id, cord, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c
      integer(i8), allocatable, intent(inout) :: cord_id(:)
      !> (3, 4, n): columns 1..3 the axes x, y, z, column 4 the origin, in basic
      real(dp), allocatable, intent(inout) :: cord(:, :, :)
      type(error_t), allocatable, intent(out) :: error
      character(len=2), parameter :: AXES(9) = ['A1', 'A2', 'A3', 'B1', 'B2', 'B3', 'C1', 'C2', &
         'C3']
      real(dp), allocatable :: grown(:, :, :)
      real(dp) :: p(9), x(3), z(3)
      integer(i8) :: id, rid
      integer :: k
      call get_int(deck, c, 1, 'CID', id, error)
      if (.not. allocated(error)) call get_int(deck, c, 2, 'RID', rid, error, 0_i8)
      do k = 1, 9
         if (.not. allocated(error)) call get_real(deck, c, 2 + k, &
            AXES(k), p(k), error, 0.0_dp)
      end do
      if (allocated(error)) return
      if (rid /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': RID = ' // &
            to_str(rid) // '; ffrf reads CORD2R defined in the basic system (RID blank or 0)')
         return
      end if
      if (any(cord_id == id)) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': coordinate ' // &
            'system ' // to_str(id) // ' is given twice')
         return
      end if
      z = p(4:6) - p(1:3)
      x = p(7:9) - p(1:3)
      if (norm2(z) > 0.0_dp) z = z / norm2(z)
      x = x - dot_product(x, z) * z
      if (norm2(z) == 0.0_dp .or. norm2(x) <= 1.0e-12_dp * norm2(p(7:9) - p(1:3))) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': A, B and C ' // &
            'do not define axes (B = A, or C on the line AB)')
         return
      end if
      x = x / norm2(x)
      cord_id = [cord_id, id]
      allocate (grown(3, 4, size(cord_id)))
      grown(:, :, :size(cord_id) - 1) = cord
      grown(:, 1, size(cord_id)) = x
      grown(:, 2, size(cord_id)) = [z(2)*x(3) - z(3)*x(2), z(3)*x(1) - z(1)*x(3), &
         z(1)*x(2) - z(2)*x(1)]
      grown(:, 3, size(cord_id)) = z
      grown(:, 4, size(cord_id)) = p(1:3)
      call move_alloc(grown, cord)
   end subroutine read_cord2r

   !> GRID ID CP X1 X2 X3 CD PS SEID: the position in basic coordinates.
   subroutine read_grid(deck, c, cord_id, cord, id, xyz, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c
      integer(i8), intent(in) :: cord_id(:)
      real(dp), intent(in) :: cord(:, :, :)
      integer(i8), intent(out) :: id
      real(dp), intent(out) :: xyz(3)
      type(error_t), allocatable, intent(out) :: error
      integer(i8) :: cp, cd, seid
      integer :: k, j
      call get_int(deck, c, 1, 'ID', id, error)
      if (.not. allocated(error)) call get_int(deck, c, 2, 'CP', cp, error, 0_i8)
      do k = 1, 3
         if (.not. allocated(error)) call get_real(deck, c, 2 + k, 'X' // to_str(k), xyz(k), &
            error, 0.0_dp)
      end do
      if (.not. allocated(error)) call get_int(deck, c, 6, 'CD', cd, error, 0_i8)
      if (.not. allocated(error)) call get_int(deck, c, 8, 'SEID', seid, error, 0_i8)
      if (allocated(error)) return
      if (id < 1 .or. id > huge(1_ip)) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': grid id ' // &
            to_str(id) // '; give 1 .. ' // to_str(huge(1_ip)))
         return
      end if
      if (len_trim(field(deck, c, 7)) > 0 .or. seid /= 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': PS (permanent ' // &
            'constraints) or SEID (superelement) given; ffrf''s body floats (its reference ' // &
            'conditions are &interface rc): clear fields 7 and 8')
         return
      end if
      do k = 1, 2
         j = 0
         if (k == 1 .and. cp /= 0) j = findloc(cord_id, cp, dim=1)
         if (k == 2 .and. cd /= 0) j = findloc(cord_id, cd, dim=1)
         if (j == 0 .and. (k == 1 .and. cp /= 0 .or. k == 2 .and. cd /= 0)) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': ' // &
               trim(merge('CP', 'CD', k == 1)) // ' = ' // to_str(merge(cp, cd, k == 1)) // &
               ' is no CORD2R of the deck (CORD1R, CORD2C, CORD2S ... are not read)')
            return
         end if
         if (k == 1 .and. j > 0) xyz = cord(:, 4, j) + matmul(cord(:, 1:3, j), xyz)
      end do
   end subroutine read_grid

   !> MAT1 MID E G NU RHO: two of E, G, NU (the third from G = E / (2 (1 + NU))), density.
   subroutine read_mat1(deck, c, mat_id, mat, mat_card, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c
      integer(i8), allocatable, intent(inout) :: mat_id(:)
      !> (3, n): E (Pa), NU, RHO (kg/m^3)
      real(dp), allocatable, intent(inout) :: mat(:, :)
      integer, allocatable, intent(inout) :: mat_card(:)
      type(error_t), allocatable, intent(out) :: error
      real(dp), allocatable :: grown(:, :)
      real(dp) :: e, g, nu, rho
      real(dp), parameter :: BLANK = -huge(1.0_dp)
      integer(i8) :: id
      call get_int(deck, c, 1, 'MID', id, error)
      if (.not. allocated(error)) call get_real(deck, c, 2, 'E', e, error, BLANK)
      if (.not. allocated(error)) call get_real(deck, c, 3, 'G', g, error, BLANK)
      if (.not. allocated(error)) call get_real(deck, c, 4, 'NU', nu, error, BLANK)
      if (.not. allocated(error)) call get_real(deck, c, 5, 'RHO', rho, error, 0.0_dp)
      if (allocated(error)) return
      if (any(mat_id == id)) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': material ' // &
            to_str(id) // ' is given twice')
         return
      end if
      if (count([e, g, nu] == BLANK) > 1) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': give two of E, ' // &
            'G and NU (an isotropic material has two constants)')
         return
      else if (e == BLANK) then
         e = 2.0_dp * (1.0_dp + nu) * g
      else if (nu == BLANK) then
         nu = e / (2.0_dp * g) - 1.0_dp
      else if (g /= BLANK) then
         if (abs(g - e / (2.0_dp * (1.0_dp + nu))) > 1.0e-6_dp * abs(g)) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': E = ' // &
               to_str(e) // ', G = ' // to_str(g) // ' and NU = ' // to_str(nu) // &
               ' disagree (G /= E / (2 (1 + NU))); an isotropic material has two constants: ' // &
               'leave G blank')
            return
         end if
      end if
      mat_id = [mat_id, id]
      mat_card = [mat_card, c]
      allocate (grown(3, size(mat_id)))
      grown(:, :size(mat_id) - 1) = mat
      grown(:, size(mat_id)) = [e, nu, rho]
      call move_alloc(grown, mat)
   end subroutine read_mat1

   !> PSOLID PID MID CORDM IN STRESS ISOP FCTN (structural only; the integration is ffrf's).
   subroutine read_psolid(deck, c, psolid, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c
      !> (3, n): PID, MID, card
      integer(i8), allocatable, intent(inout) :: psolid(:, :)
      type(error_t), allocatable, intent(out) :: error
      integer(i8), allocatable :: grown(:, :)
      integer(i8) :: pid, mid
      call get_int(deck, c, 1, 'PID', pid, error)
      if (.not. allocated(error)) call get_int(deck, c, 2, 'MID', mid, error)
      if (allocated(error)) return
      if (any(psolid(1, :) == pid)) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': property ' // &
            to_str(pid) // ' is given twice')
         return
      end if
      if (pid > huge(1_ip)) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': PID above ' // &
            to_str(huge(1_ip)))
         return
      end if
      select case (to_lower(trim(field(deck, c, 7))))
      case ('', 'smech')
      case default
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': FCTN = ''' // &
            trim(field(deck, c, 7)) // '''; ffrf reads structural solids (SMECH)')
         return
      end select
      allocate (grown(3, size(psolid, 2) + 1))
      grown(:, :size(psolid, 2)) = psolid
      grown(:, size(grown, 2)) = [pid, mid, int(c, i8)]
      call move_alloc(grown, psolid)
   end subroutine read_psolid

   !> CTETRA EID PID G1 .. G4 [G5 .. G10]: the tetrahedra (node indices, Gmsh order).
   subroutine read_tets(deck, grids, psolid, mesh, error)
      type(deck_t), intent(in) :: deck
      type(grid_map_t), intent(in) :: grids
      integer(i8), intent(in) :: psolid(:, :)
      type(mesh_t), intent(inout) :: mesh
      type(error_t), allocatable, intent(out) :: error
      !> Gmsh's position of Nastran's G1..G10
      integer, parameter :: TO_GMSH(10) = [1, 2, 3, 4, 5, 6, 7, 8, 10, 9]
      integer(i8) :: id, pid, g
      integer :: c, k, t, npt, n
      n = count(deck%name(:deck%num_cards) == 'ctetra')
      npt = 0
      t = 0
      allocate (mesh%tet_tags(n), mesh%tet_entity(n))
      do c = 1, deck%num_cards
         if (deck%name(c) /= 'ctetra') cycle
         t = t + 1
         call get_int(deck, c, 1, 'EID', id, error)
         if (.not. allocated(error)) call get_int(deck, c, 2, 'PID', pid, error)
         if (allocated(error)) return
         k = 4
         if (deck%count(c) > 6) k = 10
         if (npt == 0) then
            npt = k
            mesh%nodes_per_tet = npt
            allocate (mesh%tets(npt, n))
         else if (k /= npt) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': ' // &
               to_str(k) // ' grids after CTETRA with ' // to_str(npt) // '; a deck holds ' // &
               'Tet4 or Tet10, not both')
            return
         end if
         if (.not. any(psolid(1, :) == pid)) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': PID = ' // &
               to_str(pid) // ' is no PSOLID of the deck (PSOLID: ' // &
               id_list(psolid(1, :)) // ')')
            return
         end if
         mesh%tet_tags(t) = id
         mesh%tet_entity(t) = int(pid, ip)
         do k = 1, npt
            call get_int(deck, c, 2 + k, 'G' // to_str(k), g, error)
            if (allocated(error)) return
            mesh%tets(TO_GMSH(k), t) = grid_index(grids, g)
            if (mesh%tets(TO_GMSH(k), t) == 0) then
               call missing_grid(deck, c, 2 + k, g, error)
               return
            end if
         end do
      end do
      if (n == 0) allocate (mesh%tets(4, 0))
   end subroutine read_tets

   !> One physical volume per PSOLID of the tetrahedra (name: its id) and its MAT1.
   subroutine volume_groups(deck, psolid, mat_id, mat, mat_card, mesh, error)
      type(deck_t), intent(in) :: deck
      integer(i8), intent(in) :: psolid(:, :), mat_id(:)
      real(dp), intent(in) :: mat(:, :)
      integer, intent(in) :: mat_card(:)
      type(mesh_t), intent(inout) :: mesh
      type(error_t), allocatable, intent(out) :: error
      integer(ip), allocatable :: used(:)
      logical :: has_tets(size(psolid, 2))
      integer :: k, p, m, c
      do k = 1, size(psolid, 2)
         has_tets(k) = any(mesh%tet_entity == psolid(1, k))
      end do
      allocate (used(count(has_tets)))
      used = int(pack(psolid(1, :), has_tets), ip)
      call sort_indices(used)
      allocate (mesh%groups(size(used)), mesh%materials(size(used)))
      do k = 1, size(used)
         p = findloc(psolid(1, :), int(used(k), i8), dim=1)
         c = int(psolid(3, p))
         mesh%groups(k)%dim = 3
         mesh%groups(k)%tag = used(k)
         mesh%groups(k)%name = to_str(used(k))
         mesh%groups(k)%entities = [used(k)]
         m = findloc(mat_id, psolid(2, p), dim=1)
         if (m == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': MID = ' // &
               to_str(psolid(2, p)) // ' is no MAT1 of the deck (MAT1: ' // id_list(mat_id) // &
               '); ffrf reads isotropic MAT1')
            return
         end if
         mesh%materials(k)%volume = used(k)
         mesh%materials(k)%young = mat(1, m)
         mesh%materials(k)%poisson = mat(2, m)
         mesh%materials(k)%density = mat(3, m)
         mesh%materials(k)%origin = 'MAT1 ' // to_str(mat_id(m)) // ' (' // &
            trim(deck%files(deck%file(mat_card(m)))) // ':' // to_str(deck%line(mat_card(m))) // ')'
      end do
   end subroutine volume_groups

   !> RBE2 EID GN CM GM1 ... [ALPHA] and RBE3 EID - REFGRID REFC WT1 C1 G1,1 ... into node sets.
   subroutine read_rbes(deck, grids, on_tet, mesh, error)
      type(deck_t), intent(in) :: deck
      type(grid_map_t), intent(in) :: grids
      !> Grid index is a node of a tetrahedron
      logical, intent(in) :: on_tet(:)
      type(mesh_t), intent(inout) :: mesh
      type(error_t), allocatable, intent(out) :: error
      integer(i8), allocatable :: ids(:)
      real(dp), allocatable :: weights(:)
      integer(i8) :: eid, ref
      integer :: c, n, k, j, f, reference
      n = count(deck%name(:deck%num_cards) == 'rbe2' .or. deck%name(:deck%num_cards) == 'rbe3')
      allocate (mesh%node_sets(n))
      n = 0
      do c = 1, deck%num_cards
         if (deck%name(c) /= 'rbe2' .and. deck%name(c) /= 'rbe3') cycle
         n = n + 1
         call get_int(deck, c, 1, 'EID', eid, error)
         if (allocated(error)) return
         if (deck%name(c) == 'rbe2') then
            f = 2
            call get_int(deck, c, 2, 'GN', ref, error)
            if (.not. allocated(error)) call check_components(deck, c, 3, 'CM', .false., error)
            if (.not. allocated(error)) call id_list_of(deck, c, 4, ids, error)
            if (allocated(error)) return
            allocate (weights(size(ids)), source=1.0_dp)
            mesh%node_sets(n)%rbe = MPC_RBE2
         else
            f = 3
            call get_int(deck, c, 3, 'REFGRID', ref, error)
            if (.not. allocated(error)) call check_components(deck, c, 4, 'REFC', .true., error)
            if (.not. allocated(error)) call weighted_grids(deck, c, ids, weights, error)
            if (allocated(error)) return
            mesh%node_sets(n)%rbe = MPC_RBE3
         end if
         if (size(ids) == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': no grids ' // &
               'besides the reference grid; an interface needs the grids it ties')
            return
         end if
         reference = grid_index(grids, ref)
         if (reference == 0) then
            call missing_grid(deck, c, f, ref, error)
            return
         end if
         if (on_tet(reference)) then
            call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': reference ' // &
               'grid ' // to_str(ref) // ' is a node of a CTETRA; ffrf''s virtual node is a ' // &
               'point of its own: give the reference point a GRID of no element')
            return
         end if
         associate (s => mesh%node_sets(n))
            s%name = to_str(eid)
            s%reference = mesh%xyz(:, reference)
            s%origin = 'element ' // to_str(eid) // ' at ' // trim(deck%files(deck%file(c))) // &
               ':' // to_str(deck%line(c))
            allocate (s%nodes(size(ids)))
            do k = 1, size(ids)
               s%nodes(k) = grid_index(grids, ids(k))
               if (s%nodes(k) == 0 .or. ids(k) == ref) then
                  if (s%nodes(k) == 0) then
                     call missing_grid(deck, c, f + 1, ids(k), error)
                  else
                     call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': grid ' // &
                        to_str(ids(k)) // ' is the reference grid too')
                  end if
                  return
               end if
               j = findloc(ids(:k - 1), ids(k), dim=1)
               if (j > 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': grid ' // &
                     to_str(ids(k)) // ' is listed twice')
                  return
               end if
            end do
            call move_alloc(weights, s%weights)
         end associate
         do k = 1, n - 1
            if (mesh%node_sets(k)%name == mesh%node_sets(n)%name) then
               call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': element ' // &
                  'id ' // to_str(eid) // ' is used by another RBE2/RBE3')
               return
            end if
         end do
      end do
   end subroutine read_rbes

   !> RBE3 from field 5 on: groups WTi Ci Gi,1 Gi,2 ... until UM (refused) or ALPHA (ends).
   subroutine weighted_grids(deck, c, ids, weights, error)
      type(deck_t), intent(in) :: deck
      integer, intent(in) :: c
      integer(i8), allocatable, intent(out) :: ids(:)
      real(dp), allocatable, intent(out) :: weights(:)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: text
      real(dp) :: w
      integer(i8) :: g
      integer :: k, group_start
      logical :: ok
      allocate (ids(0), weights(0))
      k = 5
      group_start = 0
      do while (k <= deck%count(c))
         text = to_lower(trim(field(deck, c, k)))
         if (text == 'alpha') exit
         if (text == 'um') then
            call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, 'UM') // &
               ': UM (other dependent dofs) is not read; the reference grid is the dependent ' // &
               'point of an ffrf interface')
            return
         end if
         if (len(text) == 0) then
            k = k + 1
            cycle
         end if
         call parse_int(text, g, ok)
         if (.not. ok) then
            ! a new group: WTi (real), Ci
            call get_real(deck, c, k, 'WT', w, error)
            if (allocated(error)) return
            if (.not. (w > 0.0_dp)) then
               call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, 'WT') // &
                  ': weight ' // to_str(w) // '; weights must be positive')
               return
            end if
            if (group_start > 0 .and. size(ids) < group_start) exit
            call check_components(deck, c, k + 1, 'C', .false., error)
            if (allocated(error)) return
            group_start = size(ids) + 1
            k = k + 2
            cycle
         end if
         if (group_start == 0) then
            call fatal_error(error, FFRF_INPUT_ERROR, field_where(deck, c, k, 'WT1') // ': ''' // &
               text // ''' where a weight is expected: RBE3 EID - REFGRID REFC WT1 C1 G1,1 ...')
            return
         end if
         ids = [ids, g]
         weights = [weights, w]
         k = k + 1
      end do
      if (size(ids) == 0) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': no weights ' // &
            'and grids (RBE3 without weights); write WT1 C1 G1,1 G1,2 ... after REFC')
      else if (size(ids) < group_start) then
         call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': a weight with ' // &
            'no grids after it; write WTi Ci Gi,1 Gi,2 ...')
      end if
   end subroutine weighted_grids

   !> SPC1 SID C G1 ... grids exist (not applied); SET1 SID ids (not used): listed as read.
   subroutine check_sets(deck, grids, other, other_count, error)
      type(deck_t), intent(in) :: deck
      type(grid_map_t), intent(in) :: grids
      character(len=8), allocatable, intent(inout) :: other(:)
      integer, allocatable, intent(inout) :: other_count(:)
      type(error_t), allocatable, intent(out) :: error
      integer(i8), allocatable :: ids(:)
      integer(i8) :: sid
      integer :: c, k
      do c = 1, deck%num_cards
         select case (trim(deck%name(c)))
         case ('spc1')
            call get_int(deck, c, 1, 'SID', sid, error)
            if (.not. allocated(error)) call check_components(deck, c, 2, 'C', .false., error, &
               any_dofs=.true.)
            if (.not. allocated(error)) call id_list_of(deck, c, 3, ids, error)
            if (allocated(error)) return
            do k = 1, size(ids)
               if (grid_index(grids, ids(k)) == 0) then
                  call fatal_error(error, FFRF_INPUT_ERROR, card_where(deck, c) // ': grid ' // &
                     to_str(ids(k)) // ' is no GRID of the deck')
                  return
               end if
            end do
            call tally(other, other_count, 'spc1')
         case ('set1')
            call get_int(deck, c, 1, 'SID', sid, error)
            k = 2
            if (to_lower(trim(field(deck, c, 2))) == 'skin') k = 3
            if (.not. allocated(error)) call id_list_of(deck, c, k, ids, error)
            if (allocated(error)) return
            call tally(other, other_count, 'set1')
         end select
      end do
   end subroutine check_sets

end submodule ffrf_mesh_bulk_data_cards
