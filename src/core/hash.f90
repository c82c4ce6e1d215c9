!> A 64-bit content hash for fingerprints (the dependencies of stored modes, docs/mode_reuse.md):
!> two independent 32-bit FNV-1a hashes (offset bases 2166136261 and 3735928559, prime
!> 16777619) over the same bytes, shown as 16 hexadecimal digits. Not cryptographic: it tells
!> that two inputs differ, and equal hashes of different inputs are a 2^-64 accident.
!>
!> The 32-bit states live in int64 and every product h * 16777619 < 2^57 stays in range, so
!> no integer overflow happens (the result does not depend on the compiler's wrap-around).
!> Reals are hashed by their bytes (bitwise: 0.0 and -0.0 differ, as they would in a result).
module ffrf_core_hash
   use, intrinsic :: iso_fortran_env, only: int8
   use ffrf_core_kinds, only: dp, ip, i8
   implicit none
   private
   public :: hash_t

   integer(i8), parameter :: FNV_PRIME = 16777619_i8
   integer(i8), parameter :: MASK32 = 4294967295_i8
   !> Mold of transfer() to bytes
   integer(int8), parameter :: BYTE(1) = 0_int8

   !> A running hash: add bytes, text, integers and reals in any order, then hex().
   type :: hash_t
      integer(i8) :: state(2) = [2166136261_i8, 3735928559_i8]
   contains
      procedure :: add_bytes => hash_add_bytes
      procedure :: add_text => hash_add_text
      procedure :: add_reals => hash_add_reals
      procedure :: add_reals_2d => hash_add_reals_2d
      procedure :: add_ints => hash_add_ints
      procedure :: add_ints_2d => hash_add_ints_2d
      procedure :: hex => hash_hex
   end type hash_t

contains

   !> Mix bytes into both states (FNV-1a: h = (h xor byte) * prime mod 2^32), as they are (no
   !> length): the first 8 hex digits of hex() are then the standard 32-bit FNV-1a of the bytes.
   pure subroutine hash_add_bytes(self, bytes)
      class(hash_t), intent(inout) :: self
      integer(int8), intent(in) :: bytes(:)
      integer(i8) :: a, b, byte
      integer :: i
      a = self%state(1)
      b = self%state(2)
      do i = 1, size(bytes)
         byte = iand(int(bytes(i), i8), 255_i8)
         a = iand(ieor(a, byte) * FNV_PRIME, MASK32)
         b = iand(ieor(b, byte) * FNV_PRIME, MASK32)
      end do
      self%state = [a, b]
   end subroutine hash_add_bytes

   !> Add the sizes (8-byte integers), then the bytes: the common step of the typed adds.
   pure subroutine add_sized(self, sizes, bytes)
      class(hash_t), intent(inout) :: self
      !> Length, count or shape of the value
      integer(i8), intent(in) :: sizes(:)
      !> The value's bytes (empty for an empty value)
      integer(int8), intent(in) :: bytes(:)
      call self%add_bytes(transfer(sizes, BYTE))
      call self%add_bytes(bytes)
   end subroutine add_sized

   !> Add a text, with its length first (so that 'ab' + 'c' differs from 'a' + 'bc').
   pure subroutine hash_add_text(self, text)
      class(hash_t), intent(inout) :: self
      character(len=*), intent(in) :: text
      call add_sized(self, [int(len(text), i8)], transfer(text, BYTE))
   end subroutine hash_add_text

   !> Add the bytes of reals (with the count first).
   pure subroutine hash_add_reals(self, values)
      class(hash_t), intent(inout) :: self
      real(dp), intent(in) :: values(:)
      call add_sized(self, [int(size(values), i8)], transfer(values, BYTE))
   end subroutine hash_add_reals

   !> Add the bytes of a real matrix (its two sizes first).
   pure subroutine hash_add_reals_2d(self, values)
      class(hash_t), intent(inout) :: self
      real(dp), intent(in) :: values(:, :)
      call add_sized(self, int(shape(values), i8), transfer(values, BYTE))
   end subroutine hash_add_reals_2d

   !> Add integers (with the count first).
   pure subroutine hash_add_ints(self, values)
      class(hash_t), intent(inout) :: self
      integer(ip), intent(in) :: values(:)
      call add_sized(self, [int(size(values), i8)], transfer(values, BYTE))
   end subroutine hash_add_ints

   !> Add an integer matrix (its two sizes first).
   pure subroutine hash_add_ints_2d(self, values)
      class(hash_t), intent(inout) :: self
      integer(ip), intent(in) :: values(:, :)
      call add_sized(self, int(shape(values), i8), transfer(values, BYTE))
   end subroutine hash_add_ints_2d

   !> The hash as 16 lower-case hexadecimal digits.
   pure function hash_hex(self) result(text)
      class(hash_t), intent(in) :: self
      character(len=16) :: text
      write (text(1:8), '(z8.8)') self%state(1)
      write (text(9:16), '(z8.8)') self%state(2)
      text = lower_hex(text)
   contains
      pure function lower_hex(upper) result(lower)
         character(len=*), intent(in) :: upper
         character(len=len(upper)) :: lower
         integer :: i
         lower = upper
         do i = 1, len(upper)
            if (upper(i:i) >= 'A' .and. upper(i:i) <= 'F') lower(i:i) = &
               achar(iachar(upper(i:i)) + 32)
         end do
      end function lower_hex
   end function hash_hex

end module ffrf_core_hash
