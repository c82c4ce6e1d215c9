!> Tests of ffrf_io_hdf5: every kind of dataset and attribute written and read back, the growing
!> time series, the status attribute and the error paths. HDF5 stores IEEE doubles and integers
!> bit for bit, so read-back values must equal the written ones exactly (tolerance 0).
!> Files go to the working directory (ctest runs in the build tree); test_io_hdf5_layout.h5 is
!> kept for tests/postprocess/check_fortran_layout.py, which checks what h5py sees.
module test_io_hdf5
   use ffrf_core_kinds, only: dp, i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_IO_ERROR, FFRF_NUMERIC_ERROR
   use ffrf_core_strings, only: to_str
   use ffrf_io_hdf5, only: h5_file_t, H5_READ_ONLY, H5_READ_WRITE
   use ffrf_testing, only: unittest_t, new_unittest, check_close, check
   implicit none
   private
   public :: collect_io_hdf5

contains

   subroutine collect_io_hdf5(tests)
      type(unittest_t), allocatable, intent(out) :: tests(:)
      tests = [ &
         new_unittest('real_datasets', test_real_datasets), &
         new_unittest('integer_datasets', test_integer_datasets), &
         new_unittest('strings', test_strings), &
         new_unittest('attributes_and_status', test_attributes_and_status), &
         new_unittest('time_series', test_time_series), &
         new_unittest('groups_exists_replace', test_groups_exists_replace), &
         new_unittest('layout_file_for_h5py', test_layout_file_for_h5py), &
         new_unittest('error_uncreatable_file', test_error_uncreatable_file), &
         new_unittest('error_paths', test_error_paths), &
         new_unittest('read_only_file', test_read_only_file)]
   end subroutine collect_io_hdf5

   !> Reals: scalar, 1D, 2D (non-square, so a transposition would show) and an empty 1D,
   !> with their units attributes; written, closed, reopened read-only, compared exactly.
   subroutine test_real_datasets(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      type(h5_file_t) :: file
      real(dp) :: a(3, 5), v(7), s
      real(dp), allocatable :: a_back(:, :), v_back(:), empty_back(:)
      character(len=:), allocatable :: units
      integer :: i, j
      name = scratch('real.h5')
      do j = 1, 5
         do i = 1, 3
            a(i, j) = 10.0_dp * i + j + 1.0_dp / 3.0_dp
         end do
      end do
      v = [(exp(0.37_dp * i), i = 1, 7)]
      call file%create(name, error)
      if (allocated(error)) return
      call file%write_real('/bodies/crank/modes/frequency', v, 'Hz', error)
      if (allocated(error)) return
      call file%write_real('/bodies/crank/mesh/coordinates', a, 'm', error)
      if (allocated(error)) return
      call file%write_real('/bodies/crank/modes/orthonormality_error', 2.5e-13_dp, '1', error)
      if (allocated(error)) return
      call file%write_real('/empty', [real(dp) ::], 'm', error)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return

      call file%open(name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call file%read_real('/bodies/crank/mesh/coordinates', a_back, error)
      if (allocated(error)) return
      call check(error, 'coordinates read back with shape (3, 5), got (' // &
         to_str(size(a_back, 1)) // ', ' // to_str(size(a_back, 2)) // ')', &
         all(shape(a_back) == [3, 5]))
      if (allocated(error)) return
      call check_close(error, 'max |coordinates read - written|', maxval(abs(a_back - a)), &
         0.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      call file%read_real('/bodies/crank/modes/frequency', v_back, error)
      if (allocated(error)) return
      call check(error, 'frequency: 7 values read back', size(v_back) == 7)
      if (allocated(error)) return
      call check_close(error, 'max |frequency read - written|', maxval(abs(v_back - v)), &
         0.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      call file%read_real('/bodies/crank/modes/orthonormality_error', s, error)
      if (allocated(error)) return
      call check_close(error, 'scalar read back', s, 2.5e-13_dp, atol=0.0_dp)
      if (allocated(error)) return
      call file%read_real('/empty', empty_back, error)
      if (allocated(error)) return
      call check(error, 'empty dataset reads back empty', size(empty_back) == 0)
      if (allocated(error)) return
      call file%read_attribute('/bodies/crank/modes/frequency', 'units', units, error)
      if (allocated(error)) return
      call check(error, 'units of frequency = "' // units // '", expected "Hz"', units == 'Hz')
      if (allocated(error)) return
      call file%read_attribute('/bodies/crank/mesh/coordinates', 'units', units, error)
      if (allocated(error)) return
      call check(error, 'units of coordinates = "' // units // '", expected "m"', units == 'm')
      if (allocated(error)) return
      call file%read_attribute('/bodies/crank/modes/orthonormality_error', 'units', units, &
         error)
      if (allocated(error)) return
      call check(error, 'units of a scalar = "' // units // '", expected "1"', units == '1')
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_real_datasets

   !> Integers: default kind and int64 (a value past 2**31 shows truncation), 0D/1D/2D.
   subroutine test_integer_datasets(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      type(h5_file_t) :: file
      integer :: tets(4, 3), tags(5), n
      integer(i8) :: big(2, 2), big1(3), big0
      integer, allocatable :: tets_back(:, :), tags_back(:)
      integer(i8), allocatable :: big_back(:, :), big1_back(:)
      integer :: i
      name = scratch('int.h5')
      tets = reshape([(i, i = 1, 12)], [4, 3])
      tags = [101, 7, -3, 0, 2147483647]
      big = reshape([2_i8**40 + 7_i8, -2_i8**33, 5_i8, 2_i8**62], [2, 2])
      big1 = [1_i8, 2_i8**31, -1_i8]
      call file%create(name, error)
      if (allocated(error)) return
      call file%write_int('/mesh/tets', tets, error)
      if (allocated(error)) return
      call file%write_int('/mesh/node_tags', tags, error)
      if (allocated(error)) return
      call file%write_int('/mesh/num_nodes', 42, error)
      if (allocated(error)) return
      call file%write_int('/counts/big', big, error)
      if (allocated(error)) return
      call file%write_int('/counts/big1', big1, error)
      if (allocated(error)) return
      call file%write_int('/counts/big0', 2_i8**45 + 1_i8, error)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return

      call file%open(name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call file%read_int('/mesh/tets', tets_back, error)
      if (allocated(error)) return
      call check(error, 'tets (4, 3) read back equal', all(shape(tets_back) == [4, 3]) &
         .and. all(tets_back == tets))
      if (allocated(error)) return
      call file%read_int('/mesh/node_tags', tags_back, error)
      if (allocated(error)) return
      call check(error, 'node tags read back equal', size(tags_back) == 5 &
         .and. all(tags_back == tags))
      if (allocated(error)) return
      call file%read_int('/mesh/num_nodes', n, error)
      if (allocated(error)) return
      call check(error, 'scalar int = ' // to_str(n) // ', expected 42', n == 42)
      if (allocated(error)) return
      call file%read_int('/counts/big', big_back, error)
      if (allocated(error)) return
      call check(error, 'int64 (2, 2) read back equal', all(shape(big_back) == [2, 2]) &
         .and. all(big_back == big))
      if (allocated(error)) return
      call file%read_int('/counts/big1', big1_back, error)
      if (allocated(error)) return
      call check(error, 'int64 1D read back equal', all(big1_back == big1))
      if (allocated(error)) return
      call file%read_int('/counts/big0', big0, error)
      if (allocated(error)) return
      call check(error, 'int64 scalar = ' // to_str(big0) // ', expected 2**45 + 1', &
         big0 == 2_i8**45 + 1_i8)
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_integer_datasets

   !> Strings: multi-line text (kept exactly, trailing blank included), the empty string, and a
   !> list of strings of different lengths (each trimmed), including an empty entry.
   subroutine test_strings(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      character(len=*), parameter :: nl = new_line('a')
      character(len=*), parameter :: text = '&modes' // nl // '   num_modes = 20' // nl // &
         '/ '
      type(h5_file_t) :: file
      character(len=:), allocatable :: back, list(:)
      character(len=12) :: stages(4)
      name = scratch('strings.h5')
      stages = [character(len=12) :: 'mesh', 'assembly', '', 'eigensolver']
      call file%create(name, error)
      if (allocated(error)) return
      call file%write_string('/input/namelist', text, error)
      if (allocated(error)) return
      call file%write_string('/bodies/crank/interfaces/B2/rc_dofs', '', error)
      if (allocated(error)) return
      call file%write_string_list('/timings/stage', stages, error)
      if (allocated(error)) return
      call file%write_string_list('/empty_list', stages(1:0), error)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return

      call file%open(name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call file%read_string('/input/namelist', back, error)
      if (allocated(error)) return
      call check(error, 'namelist text read back exactly (got "' // back // '")', back == text &
         .and. len(back) == len(text))
      if (allocated(error)) return
      call file%read_string('/bodies/crank/interfaces/B2/rc_dofs', back, error)
      if (allocated(error)) return
      call check(error, 'empty string read back with length 0, got ' // to_str(len(back)), &
         len(back) == 0)
      if (allocated(error)) return
      call file%read_string_list('/timings/stage', list, error)
      if (allocated(error)) return
      call check(error, 'string list: 4 entries, width 11 (longest), got ' // &
         to_str(size(list)) // ', ' // to_str(len(list)), size(list) == 4 .and. len(list) == 11)
      if (allocated(error)) return
      call check(error, 'string list entries equal', trim(list(1)) == 'mesh' .and. &
         trim(list(2)) == 'assembly' .and. len_trim(list(3)) == 0 .and. &
         trim(list(4)) == 'eigensolver')
      if (allocated(error)) return
      call file%read_string_list('/empty_list', list, error)
      if (allocated(error)) return
      call check(error, 'empty list reads back empty', size(list) == 0)
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_strings

   !> Attributes of every kind on the root, a group and a dataset, replaced in place; the root
   !> status goes running -> complete, and an error message survives a reopen.
   subroutine test_attributes_and_status(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      character(len=*), parameter :: message = 'modes: MUMPS factorisation failed, INFOG(1) = -9'
      type(h5_file_t) :: file
      character(len=:), allocatable :: text
      real(dp) :: x
      integer :: n
      name = scratch('attributes.h5')
      call file%create(name, error)
      if (allocated(error)) return
      call file%set_status('running', error)
      if (allocated(error)) return
      call file%get_status(text, error)
      if (allocated(error)) return
      call check(error, 'status after set_status(running) = "' // text // '"', text == 'running')
      if (allocated(error)) return
      call file%write_real('/bodies/crank/modes/frequency', [1.0_dp, 2.0_dp], 'Hz', error)
      if (allocated(error)) return
      call file%set_attribute('/bodies/crank/modes', 'rc_set', 'RC set 1', error)
      if (allocated(error)) return
      call file%set_attribute('/bodies/crank/modes', 'rc_set', 'RC set 2', error)
      if (allocated(error)) return
      call file%set_attribute('/bodies/crank/modes/frequency', 'shift_hz', -12.5_dp, error)
      if (allocated(error)) return
      call file%set_attribute('/', 'num_bodies', 2, error)
      if (allocated(error)) return
      call file%set_status('complete', error)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return

      call file%open(name, H5_READ_WRITE, error)
      if (allocated(error)) return
      call file%get_status(text, error)
      if (allocated(error)) return
      call check(error, 'status after reopen = "' // text // '", expected complete', &
         text == 'complete')
      if (allocated(error)) return
      call file%read_attribute('/bodies/crank/modes', 'rc_set', text, error)
      if (allocated(error)) return
      call check(error, 'replaced attribute = "' // text // '", expected "RC set 2"', &
         text == 'RC set 2')
      if (allocated(error)) return
      call file%read_attribute('/bodies/crank/modes/frequency', 'shift_hz', x, error)
      if (allocated(error)) return
      call check_close(error, 'real attribute', x, -12.5_dp, atol=0.0_dp)
      if (allocated(error)) return
      call file%read_attribute('/', 'num_bodies', n, error)
      if (allocated(error)) return
      call check(error, 'int attribute = ' // to_str(n) // ', expected 2', n == 2)
      if (allocated(error)) return
      call check(error, 'attribute_exists finds rc_set and not rc_sets', &
         file%attribute_exists('/bodies/crank/modes', 'rc_set') .and. .not. &
         file%attribute_exists('/bodies/crank/modes', 'rc_sets'))
      if (allocated(error)) return
      call file%set_status(message, error)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return
      call file%open(name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call file%get_status(text, error)
      if (allocated(error)) return
      call check(error, 'error status read back = "' // text // '"', text == message)
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_attributes_and_status

   !> Growing series: a 1D series fed one step at a time and then three at once; a 2D series
   !> fed column by column and then a (3, 2) block, flushed between; lengths and contents read
   !> back exactly, 2D in Fortran order (3, num_steps); a wrong row count is refused.
   subroutine test_time_series(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      type(h5_file_t) :: file
      type(error_t), allocatable :: expected_error
      real(dp), allocatable :: t(:), q(:, :)
      real(dp) :: column(3), block(3, 2), expected(3, 7)
      integer(i8) :: num_steps
      character(len=:), allocatable :: units
      integer :: step, i
      name = scratch('series.h5')
      call file%create(name, error)
      if (allocated(error)) return
      call file%create_series('/time/t', 0, 's', error)
      if (allocated(error)) return
      call file%create_series('/bodies/crank/modal_coordinates', 3, '1', error)
      if (allocated(error)) return
      do step = 1, 5
         call file%append('/time/t', 0.001_dp * step, error)
         if (allocated(error)) return
         column = [(real(100 * step + i, dp), i = 1, 3)]
         expected(:, step) = column
         call file%append('/bodies/crank/modal_coordinates', column, error)
         if (allocated(error)) return
         call file%flush(error)
         if (allocated(error)) return
      end do
      call file%append('/time/t', [0.006_dp, 0.007_dp, 0.008_dp], error)
      if (allocated(error)) return
      block = reshape([(real(i, dp) + 0.5_dp, i = 1, 6)], [3, 2])
      expected(:, 6:7) = block
      call file%append('/bodies/crank/modal_coordinates', block, error)
      if (allocated(error)) return
      call file%append('/bodies/crank/modal_coordinates', [1.0_dp, 2.0_dp], expected_error)
      call check(error, 'appending 2 values to a 3-row series fails', &
         allocated(expected_error))
      if (allocated(error)) return
      call check(error, 'its message names the rows: ' // expected_error%message, &
         index(expected_error%message, '3 rows') > 0 .and. &
         index(expected_error%message, name) > 0)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return

      call file%open(name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call file%series_length('/time/t', num_steps, error)
      if (allocated(error)) return
      call check(error, '1D series has 8 steps, got ' // to_str(num_steps), num_steps == 8_i8)
      if (allocated(error)) return
      call file%series_length('/bodies/crank/modal_coordinates', num_steps, error)
      if (allocated(error)) return
      call check(error, '2D series has 7 steps, got ' // to_str(num_steps), num_steps == 7_i8)
      if (allocated(error)) return
      call file%read_real('/time/t', t, error)
      if (allocated(error)) return
      call check_close(error, 'max |t - 0.001 k|', &
         maxval(abs(t - [(0.001_dp * i, i = 1, 8)])), 0.0_dp, atol=0.0_dp)
      if (allocated(error)) return
      call file%read_real('/bodies/crank/modal_coordinates', q, error)
      if (allocated(error)) return
      call check(error, '2D series shape (3, 7)', all(shape(q) == [3, 7]))
      if (allocated(error)) return
      call check_close(error, 'max |q read - appended|', maxval(abs(q - expected)), 0.0_dp, &
         atol=0.0_dp)
      if (allocated(error)) return
      call file%read_attribute('/time/t', 'units', units, error)
      if (allocated(error)) return
      call check(error, 'series units "' // units // '", expected "s"', units == 's')
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_time_series

   !> Intermediate groups appear on demand; exists() tells groups, datasets and absent paths
   !> apart; a dataset is replaced by a new write (new shape); a group is never replaced.
   subroutine test_groups_exists_replace(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      type(h5_file_t) :: file
      type(error_t), allocatable :: expected_error
      real(dp), allocatable :: v(:)
      name = scratch('groups.h5')
      call file%create(name, error)
      if (allocated(error)) return
      call file%write_real('/a/b/c/d', [1.0_dp, 2.0_dp, 3.0_dp], 'm', error)
      if (allocated(error)) return
      call check(error, 'exists: /, /a, /a/b/c, /a/b/c/d', file%exists('/') .and. &
         file%exists('/a') .and. file%exists('/a/b/c') .and. file%exists('/a/b/c/d'))
      if (allocated(error)) return
      call check(error, 'not exists: /x, /a/x/y, /a/b/c/d/e, malformed a/b and /a/', &
         .not. (file%exists('/x') .or. file%exists('/a/x/y') .or. &
         file%exists('/a/b/c/d/e') .or. file%exists('a/b') .or. file%exists('/a/')))
      if (allocated(error)) return
      call file%write_real('/a/b/c/d', [4.0_dp, 5.0_dp], 'm', error)
      if (allocated(error)) return
      call file%read_real('/a/b/c/d', v, error)
      if (allocated(error)) return
      call check(error, 'replaced dataset holds [4, 5]', size(v) == 2 .and. &
         all(v == [4.0_dp, 5.0_dp]))
      if (allocated(error)) return
      call file%write_real('/a/b', 1.0_dp, 'm', expected_error)
      call check(error, 'writing over the group /a/b fails', allocated(expected_error))
      if (allocated(error)) return
      call check(error, 'and /a/b/c/d is still there', file%exists('/a/b/c/d'))
      if (allocated(error)) return
      call file%write_real('/a/b/c/d/e', 1.0_dp, 'm', expected_error)
      call check(error, 'a dataset cannot hold a child', allocated(expected_error))
      if (allocated(error)) return
      call file%write_real('relative/path', 1.0_dp, 'm', expected_error)
      call check(error, 'a relative path is refused', allocated(expected_error))
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_groups_exists_replace

   !> Writes test_io_hdf5_layout.h5 for the h5py side (tests/postprocess/check_fortran_layout.py):
   !> a(i, j) = 10 i + j as Fortran (2, 3) must read in h5py as shape (3, 2) with A[j-1, i-1].
   subroutine test_layout_file_for_h5py(error)
      type(error_t), allocatable, intent(out) :: error
      type(h5_file_t) :: file
      real(dp) :: a(2, 3)
      integer :: i, j
      do j = 1, 3
         do i = 1, 2
            a(i, j) = 10.0_dp * i + j
         end do
      end do
      call file%create(scratch('layout.h5'), error)
      if (allocated(error)) return
      call file%set_status('running', error)
      if (allocated(error)) return
      call file%write_real('/layout/a', a, 'm', error)
      if (allocated(error)) return
      call file%write_int('/layout/tets', reshape([(i, i = 1, 8)], [4, 2]), error)
      if (allocated(error)) return
      call file%write_string_list('/layout/names', [character(len=8) :: 'B1', 'B2', 'B3'], &
         error)
      if (allocated(error)) return
      call file%create_series('/layout/series', 2, 'rad', error)
      if (allocated(error)) return
      call file%append('/layout/series', [1.0_dp, 2.0_dp], error)
      if (allocated(error)) return
      call file%append('/layout/series', [3.0_dp, 4.0_dp], error)
      if (allocated(error)) return
      call file%set_status('complete', error)
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_layout_file_for_h5py

   !> A file in a folder that does not exist cannot be created: FFRF_IO_ERROR naming the file.
   subroutine test_error_uncreatable_file(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=*), parameter :: name = 'no_such_folder_ffrf/sub/results.h5'
      type(h5_file_t) :: file
      type(error_t), allocatable :: expected_error
      call file%create(name, expected_error)
      call check(error, 'create in a missing folder fails', allocated(expected_error))
      if (allocated(error)) return
      call check(error, 'code FFRF_IO_ERROR and the file name in: ' // expected_error%message, &
         expected_error%code == FFRF_IO_ERROR .and. index(expected_error%message, name) > 0)
      if (allocated(error)) return
      call check(error, 'the handle stays closed', .not. file%is_open())
      if (allocated(error)) return
      deallocate (expected_error)
      call file%write_real('/x', 1.0_dp, 'm', expected_error)
      call check(error, 'a write after the failed create fails too', allocated(expected_error))
      if (allocated(error)) return
      call check(error, 'and names the file and path: ' // expected_error%message, &
         index(expected_error%message, name) > 0 .and. &
         index(expected_error%message, '"/x"') > 0)
   end subroutine test_error_uncreatable_file

   !> Missing files and datasets, wrong ranks and types, bad open modes: errors that name the
   !> file and the path.
   subroutine test_error_paths(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      type(h5_file_t) :: file
      type(error_t), allocatable :: e
      real(dp), allocatable :: v(:), a(:, :)
      character(len=:), allocatable :: text
      real(dp) :: x
      name = scratch('errors.h5')
      call file%open('no_such_file_ffrf.h5', H5_READ_ONLY, e)
      call expect(error, e, 'open of a missing file', 'no_such_file_ffrf.h5')
      if (allocated(error)) return
      call file%open(name, 3, e)
      call expect(error, e, 'open mode 3', 'mode 3', 'H5_READ_ONLY or H5_READ_WRITE')
      if (allocated(error)) return
      call file%create(name, error)
      if (allocated(error)) return
      call file%create(name, e)
      call expect(error, e, 'create on an open handle', 'close it first')
      if (allocated(error)) return
      call file%write_real('/m/v', [1.0_dp, 2.0_dp], 'm', error)
      if (allocated(error)) return
      call file%write_string('/m/s', 'text', error)
      if (allocated(error)) return
      call file%write_real('/m/x', 1.0_dp, 'm', error)
      if (allocated(error)) return
      call file%read_real('/m/missing', v, e)
      call expect(error, e, 'read of a missing dataset', name, '"/m/missing"', 'no such')
      if (allocated(error)) return
      call file%read_real('/m/v', a, e)
      call expect(error, e, 'rank mismatch', '"/m/v"', '1 dimensions', 'expects 2')
      if (allocated(error)) return
      call file%read_real('/m', v, e)
      call expect(error, e, 'read of a group', '"/m"')
      if (allocated(error)) return
      call file%read_string('/m/x', text, e)
      call expect(error, e, 'string read of a real', '"/m/x"', 'not a string')
      if (allocated(error)) return
      call file%read_real('/m/s', x, e)
      call expect(error, e, 'real read of a string', '"/m/s"')
      if (allocated(error)) return
      call file%read_attribute('/m/v', 'colour', text, e)
      call expect(error, e, 'missing attribute', '"/m/v"', 'colour')
      if (allocated(error)) return
      call file%set_attribute('/m/none', 'units', 'm', e)
      call expect(error, e, 'attribute on a missing object', '"/m/none"')
      if (allocated(error)) return
      call file%append('/m/v', 1.0_dp, e)
      call expect(error, e, 'append to a fixed-size dataset', '"/m/v"', 'extend')
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return
      call file%write_real('/m/w', 1.0_dp, 'm', e)
      call expect(error, e, 'write after close', name, 'not open')
   end subroutine test_error_paths

   !> A file opened read-only refuses writes and attributes with an error, not a crash.
   subroutine test_read_only_file(error)
      type(error_t), allocatable, intent(out) :: error
      character(len=:), allocatable :: name
      type(h5_file_t) :: file
      type(error_t), allocatable :: e
      name = scratch('read_only.h5')
      call file%create(name, error)
      if (allocated(error)) return
      call file%write_real('/v', 1.0_dp, 'm', error)
      if (allocated(error)) return
      call file%close(error)
      if (allocated(error)) return
      call file%open(name, H5_READ_ONLY, error)
      if (allocated(error)) return
      call file%write_real('/w/x', 1.0_dp, 'm', e)
      call expect(error, e, 'write into a read-only file', name, '/w/x', 'read-only')
      if (allocated(error)) return
      call file%set_status('complete', e)
      call expect(error, e, 'status in a read-only file', name)
      if (allocated(error)) return
      call file%close(error)
   end subroutine test_read_only_file

   !> Fails unless `actual` is an FFRF_IO_ERROR whose message holds every one of the words.
   subroutine expect(error, actual, what, word1, word2, word3)
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable, intent(inout) :: actual
      character(len=*), intent(in) :: what
      character(len=*), intent(in) :: word1
      character(len=*), intent(in), optional :: word2, word3
      if (.not. allocated(actual)) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, what // ': expected an error, got none')
         return
      end if
      if (actual%code /= FFRF_IO_ERROR) then
         call fatal_error(error, FFRF_NUMERIC_ERROR, what // ': code ' // to_str(actual%code) &
            // ', expected FFRF_IO_ERROR: ' // actual%message)
         return
      end if
      call expect_word(word1)
      if (present(word2)) call expect_word(word2)
      if (present(word3)) call expect_word(word3)
      if (.not. allocated(error)) deallocate (actual)
   contains
      subroutine expect_word(word)
         character(len=*), intent(in) :: word
         if (allocated(error)) return
         if (index(actual%message, word) == 0) call fatal_error(error, FFRF_NUMERIC_ERROR, &
            what // ': message lacks "' // word // '": ' // actual%message)
      end subroutine expect_word
   end subroutine expect

   !> `suffix` prefixed by this executable's name ("test_io_hdf5_real.h5"): the files of the
   !> plain and the _checked build of the suite never collide when ctest runs both at once.
   function scratch(suffix) result(name)
      character(len=*), intent(in) :: suffix
      character(len=:), allocatable :: name
      character(len=512) :: program
      call get_command_argument(0, program)
      name = trim(program(index(program, '/', back=.true.) + 1:)) // '_' // suffix
   end function scratch

end module test_io_hdf5

program main_io_hdf5
   use ffrf_testing, only: unittest_t, run_suite
   use test_io_hdf5, only: collect_io_hdf5
   implicit none
   type(unittest_t), allocatable :: tests(:)
   call collect_io_hdf5(tests)
   call run_suite('test_io_hdf5', tests)
end program main_io_hdf5
