!> The fingerprint of stored modes (ffrf_modes_fingerprint, docs/mode_reuse.md) and its hash
!> (ffrf_core_hash). References: the published 32-bit FNV-1a test vectors ("" 811c9dc5,
!> "a" e40c292c, "foobar" bf9cf968) and an independent Python FNV-1a of the same bytes for the
!> second state and the length-prefixed text and reals; the comparison's verdicts and messages on
!> a two-tetrahedron body built in memory, changed one thing at a time. Exact checks.
module test_modes_fingerprint
   use, intrinsic :: iso_fortran_env, only: int8
   use ffrf_core_kinds, only: dp, ip
   use ffrf_core_error, only: error_t
   use ffrf_core_hash, only: hash_t
   use ffrf_mesh_mesh, only: mesh_t
   use ffrf_mpc_interface, only: interface_t, MPC_RBE3
   use ffrf_modes_input, only: body_spec_t, modes_spec_t
   use ffrf_modes_fingerprint, only: modes_fingerprint_t, make_fingerprint, set_kept_modes, &
      compare_fingerprints, exact_text
   use ffrf_testing, only: unittest_t, new_unittest, check
   implicit none
   private
   public :: collect_modes_fingerprint

contains

   subroutine collect_modes_fingerprint(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('fnv1a_vectors', test_fnv1a_vectors), &
         new_unittest('text_and_reals', test_text_and_reals), &
         new_unittest('exact_text', test_exact_text), &
         new_unittest('same_model', test_same_model), &
         new_unittest('each_difference_named', test_each_difference), &
         new_unittest('count_taken_from_file', test_count_taken)]
   end subroutine collect_modes_fingerprint

   function hash_of_bytes(text) result(hex)
      character(len=*), intent(in) :: text
      character(len=16) :: hex
      type(hash_t) :: h
      integer(int8), parameter :: mold(1) = 0_int8
      if (len(text) > 0) call h%add_bytes(transfer(text, mold))
      hex = h%hex()
   end function hash_of_bytes

   subroutine test_fnv1a_vectors(error)
      type(error_t), allocatable, intent(out) :: error
      call check(error, 'FNV-1a 32 of "", "a", "foobar" = 811c9dc5, e40c292c, bf9cf968 ' // &
         '(second state: Python 0xdeadbeef-based FNV-1a)', &
         hash_of_bytes('') == '811c9dc5deadbeef' .and. hash_of_bytes('a') == &
         'e40c292c1982f98a' .and. hash_of_bytes('foobar') == 'bf9cf9682ab841f6')
   end subroutine test_fnv1a_vectors

   subroutine test_text_and_reals(error)
      type(error_t), allocatable, intent(out) :: error
      type(hash_t) :: a, b
      call a%add_text('B2')
      call b%add_reals([0.1_dp, -2.5_dp, 1.0e300_dp])
      ! Python: FNV-1a of struct.pack('<q', n) + the bytes
      call check(error, 'length-prefixed text and reals = Python f3f47837244dbe3d, ' // &
         '393e25ed7a6c280b (got ' // a%hex() // ', ' // b%hex() // ')', &
         a%hex() == 'f3f47837244dbe3d' .and. b%hex() == '393e25ed7a6c280b')
   end subroutine test_text_and_reals

   subroutine test_exact_text(error)
      type(error_t), allocatable, intent(out) :: error
      real(dp) :: back
      integer :: stat
      character(len=:), allocatable :: third
      third = exact_text(1.0_dp / 3.0_dp)
      read (third, *, iostat=stat) back
      call check(error, 'exact_text: 0.1 -> "0.1", 7850 -> "7850", 1/3 reads back exactly (' // &
         third // ')', exact_text(0.1_dp) == '0.1' .and. exact_text(7850.0_dp) == '7850' .and. &
         stat == 0 .and. back == 1.0_dp / 3.0_dp)
   end subroutine test_exact_text

   !> A Tet4 pair with two RBE3 interfaces.
   subroutine body(mesh, interfaces, material, modes)
      type(mesh_t), intent(out) :: mesh
      type(interface_t), allocatable, intent(out) :: interfaces(:)
      type(body_spec_t), intent(out) :: material
      type(modes_spec_t), intent(out) :: modes
      integer :: k
      mesh%num_nodes = 5
      mesh%nodes_per_tet = 4
      mesh%xyz = reshape([0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, &
         0.0_dp, 0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp, 1.0_dp, 1.0_dp], [3, 5])
      mesh%tets = reshape([1_ip, 2_ip, 3_ip, 4_ip, 2_ip, 3_ip, 4_ip, 5_ip], [4, 2])
      allocate (interfaces(2))
      do k = 1, 2
         interfaces(k)%name = trim(merge('B1', 'B2', k == 1))
         interfaces(k)%mpc = MPC_RBE3
         interfaces(k)%nodes = [int(k, ip), int(k + 1, ip), int(k + 2, ip)]
         interfaces(k)%weights = [1.0_dp, 1.0_dp, 1.0_dp]
         interfaces(k)%virtual_xyz = [0.25_dp, 0.25_dp, real(k, dp)]
      end do
      interfaces(1)%rc(1:3) = .true.
      material%name = 'block'
      modes%num_modes = 10
   end subroutine body

   subroutine test_same_model(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(interface_t), allocatable :: interfaces(:)
      type(body_spec_t) :: material
      type(modes_spec_t) :: modes
      type(modes_fingerprint_t) :: a, b
      character(len=:), allocatable :: difference
      logical :: same
      call body(mesh, interfaces, material, modes)
      call make_fingerprint(mesh, interfaces, material, modes, 10, a)
      call make_fingerprint(mesh, interfaces, material, modes, 10, b)
      call compare_fingerprints(a, b, .false., same, difference)
      call check(error, 'the same model: same, no difference, equal total hashes', same .and. &
         len(difference) == 0 .and. a%total_hash() == b%total_hash())
   end subroutine test_same_model

   subroutine test_each_difference(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh, moved
      type(interface_t), allocatable :: interfaces(:), other(:)
      type(body_spec_t) :: material, softer
      type(modes_spec_t) :: modes, fewer
      type(modes_fingerprint_t) :: stored, here
      call body(mesh, interfaces, material, modes)
      call make_fingerprint(mesh, interfaces, material, modes, 10, stored)
      ! one node moved by one ulp
      moved = mesh
      moved%xyz(1, 5) = nearest(moved%xyz(1, 5), 1.0_dp)
      call make_fingerprint(moved, interfaces, material, modes, 10, here)
      call expect('the mesh differs (node coordinates ''hash ', .false.)
      if (allocated(error)) return
      softer = material
      softer%young = 200.0e9_dp
      call make_fingerprint(mesh, interfaces, softer, modes, 10, here)
      call expect('the material differs (young ''2E+11 Pa'' here, ''2.1E+11 Pa'' in the file)', &
         .false.)
      if (allocated(error)) return
      other = interfaces
      other(2)%rc(1:2) = .true.
      call make_fingerprint(mesh, other, material, modes, 10, here)
      call expect('the interfaces differ (B2: rc ''Tx Ty'' here, ''none'' in the file)', .false.)
      if (allocated(error)) return
      other = interfaces
      other(1)%weights(2) = 2.0_dp
      call make_fingerprint(mesh, other, material, modes, 10, here)
      call expect('the interfaces differ (B1: weights ''hash ', .false.)
      if (allocated(error)) return
      fewer = modes
      fewer%num_modes = 8
      call make_fingerprint(mesh, interfaces, material, fewer, 8, here)
      call expect('the modes specification differs (num_modes ''8'' here, ''10'' in the file)', &
         .false.)
      if (allocated(error)) return
      fewer = modes
      fewer%tolerance = 1.0e-10_dp
      call make_fingerprint(mesh, interfaces, material, fewer, 10, here)
      call expect('the modes specification differs (tolerance ''1E-10'' here, ''1E-09'' in ' // &
         'the file)', .false.)
   contains
      subroutine expect(start, take_count)
         character(len=*), intent(in) :: start
         logical, intent(in) :: take_count
         character(len=:), allocatable :: difference
         logical :: same
         call compare_fingerprints(here, stored, take_count, same, difference)
         call check(error, 'refused with "' // start // '..." (got "' // difference // '")', &
            .not. same .and. index(difference, start) == 1 .and. here%total_hash() /= &
            stored%total_hash())
      end subroutine expect
   end subroutine test_each_difference

   subroutine test_count_taken(error)
      type(error_t), allocatable, intent(out) :: error
      type(mesh_t) :: mesh
      type(interface_t), allocatable :: interfaces(:)
      type(body_spec_t) :: material
      type(modes_spec_t) :: modes
      type(modes_fingerprint_t) :: stored, here
      character(len=:), allocatable :: difference
      logical :: same, same_given
      call body(mesh, interfaces, material, modes)
      call make_fingerprint(mesh, interfaces, material, modes, 20, stored)
      call set_kept_modes(stored, [1, 2, 5], 20)
      call make_fingerprint(mesh, interfaces, material, modes, 12, here)
      call compare_fingerprints(here, stored, .true., same, difference)
      call compare_fingerprints(here, stored, .false., same_given, difference)
      call check(error, 'without num_modes the count and the kept list come from the file; ' // &
         'with it they must match (' // difference // ')', same .and. .not. same_given .and. &
         index(difference, 'num_modes ''12'' here, ''3'' in the file') > 0)
   end subroutine test_count_taken

end module test_modes_fingerprint

program main_modes_fingerprint
   use ffrf_testing, only: unittest_t, run_suite
   use test_modes_fingerprint, only: collect_modes_fingerprint
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_modes_fingerprint(tests)
   call run_suite('modes_fingerprint', tests)
end program main_modes_fingerprint
