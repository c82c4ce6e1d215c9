!> Typed Fortran access to the POSIX services of posix.c: file kinds and sizes (a case, mesh or
!> table file must be a regular file of bounded size, never a FIFO, device or folder), atomic
!> rename and durable writes for results files, advisory locks that keep two runs off one
!> output, and the signals that end a run cleanly. Errors come back as error_t objects.
module ffrf_core_posix
   use, intrinsic :: iso_c_binding, only: c_int, c_long_long, c_char, c_null_char
   use ffrf_core_kinds, only: i8
   use ffrf_core_error, only: error_t, fatal_error, FFRF_IO_ERROR
   use ffrf_core_strings, only: to_str
   implicit none
   private
   public :: FILE_MISSING, FILE_REGULAR, FILE_DIRECTORY, FILE_FIFO, FILE_DEVICE, FILE_OTHER
   public :: file_kind, file_kind_name, check_input_file, rename_file, remove_file, sync_file
   public :: lock_file, unlock_file, errno_text
   public :: install_signal_handlers, pending_signal, clear_pending_signal, signal_name
   public :: ERRNO_WOULD_BLOCK
   public :: lock_output, ignore_file_size_signal, copy_file, sync_folder_of, commit_durably
   public :: signals_restart_calls, hold_signals, release_signals, signal_test_point
   public :: create_new_file, same_file, exit_guard, free_space

   !> File kinds (posix.c)
   integer, parameter :: FILE_MISSING = 0, FILE_REGULAR = 1, FILE_DIRECTORY = 2, FILE_FIFO = 3, &
      FILE_DEVICE = 4, FILE_OTHER = 5
   !> What each file kind is called in messages, by kind
   character(len=*), parameter :: FILE_KIND_NAMES(FILE_MISSING:FILE_OTHER) = &
      [character(len=54) :: 'missing', 'a regular file', 'a folder', 'a FIFO (named pipe)', &
      'a device', 'not a regular file (a socket or another special file)']
   !> EWOULDBLOCK (= EAGAIN) on Linux: a lock another process holds
   integer, parameter :: ERRNO_WOULD_BLOCK = 11

   interface
      integer(c_int) function c_file_kind(path, kind, size) bind(c, name='ffrf_file_kind')
         import :: c_int, c_char, c_long_long
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), intent(out) :: kind
         integer(c_long_long), intent(out) :: size
      end function c_file_kind
      integer(c_int) function c_free_space(path, bytes) bind(c, name='ffrf_free_space')
         import :: c_int, c_char, c_long_long
         character(kind=c_char), intent(in) :: path(*)
         integer(c_long_long), intent(out) :: bytes
      end function c_free_space
      integer(c_int) function c_rename(from, to) bind(c, name='ffrf_rename')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: from(*), to(*)
      end function c_rename
      integer(c_int) function c_unlink(path) bind(c, name='ffrf_unlink')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
      end function c_unlink
      integer(c_int) function c_fsync_path(path) bind(c, name='ffrf_fsync_path')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
      end function c_fsync_path
      integer(c_int) function c_lock_file(path, fd) bind(c, name='ffrf_lock_file')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), intent(out) :: fd
      end function c_lock_file
      integer(c_int) function c_unlock_file(path, fd) bind(c, name='ffrf_unlock_file')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value :: fd
      end function c_unlock_file
      subroutine c_errno_text(code, buffer, length) bind(c, name='ffrf_errno_text')
         import :: c_int, c_char
         integer(c_int), value :: code, length
         character(kind=c_char), intent(out) :: buffer(*)
      end subroutine c_errno_text
      integer(c_int) function c_signals_install() bind(c, name='ffrf_signals_install')
         import :: c_int
      end function c_signals_install
      integer(c_int) function c_signal_pending() bind(c, name='ffrf_signal_pending')
         import :: c_int
      end function c_signal_pending
      subroutine c_signal_clear() bind(c, name='ffrf_signal_clear')
      end subroutine c_signal_clear
      subroutine c_signal_name(number, buffer, length) bind(c, name='ffrf_signal_name')
         import :: c_int, c_char
         integer(c_int), value :: number, length
         character(kind=c_char), intent(out) :: buffer(*)
      end subroutine c_signal_name
   end interface

   interface
      integer(c_int) function c_lock_output(path, fd) bind(c, name='ffrf_lock_output')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), intent(out) :: fd
      end function c_lock_output
      integer(c_int) function c_ignore_file_size_signal() &
            bind(c, name='ffrf_ignore_file_size_signal')
         import :: c_int
      end function c_ignore_file_size_signal
      integer(c_int) function c_copy_file(from, to) bind(c, name='ffrf_copy_file')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: from(*), to(*)
      end function c_copy_file
      integer(c_int) function c_signals_restart_calls() &
            bind(c, name='ffrf_signals_restart_calls')
         import :: c_int
      end function c_signals_restart_calls
      integer(c_int) function c_signals_hold(block) bind(c, name='ffrf_signals_hold')
         import :: c_int
         integer(c_int), value :: block
      end function c_signals_hold
      integer(c_int) function c_signals_release() bind(c, name='ffrf_signals_release')
         import :: c_int
      end function c_signals_release
      subroutine c_signal_test_point(stage) bind(c, name='ffrf_signal_test_point')
         import :: c_char
         character(kind=c_char), intent(in) :: stage(*)
      end subroutine c_signal_test_point
      subroutine c_exit_guard(on) bind(c, name='ffrf_exit_guard')
         import :: c_int
         integer(c_int), value :: on
      end subroutine c_exit_guard
      integer(c_int) function c_create_new_file(path) bind(c, name='ffrf_create_new_file')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
      end function c_create_new_file
      integer(c_int) function c_same_file(a, b, a_entry, b_entry, same) &
            bind(c, name='ffrf_same_file')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: a(*), b(*)
         integer(c_int), value :: a_entry, b_entry
         integer(c_int), intent(out) :: same
      end function c_same_file
      integer(c_int) function c_fsync_folder_of(path) bind(c, name='ffrf_fsync_folder_of')
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
      end function c_fsync_folder_of
   end interface

contains

   !> Kind (FILE_*) and size in bytes of what `path` names; an error only when it cannot be
   !> inspected (permissions), not when it is missing.
   subroutine file_kind(path, kind, size_bytes, error)
      character(len=*), intent(in) :: path
      integer, intent(out) :: kind
      integer(i8), intent(out) :: size_bytes
      type(error_t), allocatable, intent(out) :: error
      integer(c_int) :: status, c_kind
      integer(c_long_long) :: c_size
      status = c_file_kind(c_string(path), c_kind, c_size)
      kind = int(c_kind)
      size_bytes = int(c_size, i8)
      call status_error(status, 'inspect "' // path // '"', error)
   end subroutine file_kind

   !> Bytes that may still be written in the file system of `path` (a folder or file).
   subroutine free_space(path, bytes, error)
      character(len=*), intent(in) :: path
      integer(i8), intent(out) :: bytes
      type(error_t), allocatable, intent(out) :: error
      integer(c_long_long) :: c_bytes
      call status_error(c_free_space(c_string(path), c_bytes), 'find the free space of "' // &
         path // '"', error)
      bytes = int(c_bytes, i8)
   end subroutine free_space

   !> "a regular file", "a folder", "a FIFO (named pipe)", ... (FILE_KIND_NAMES; an unknown kind
   !> reads as FILE_OTHER).
   pure function file_kind_name(kind) result(name)
      integer, intent(in) :: kind
      character(len=:), allocatable :: name
      name = trim(FILE_KIND_NAMES(FILE_OTHER))
      if (kind >= FILE_MISSING .and. kind <= FILE_OTHER) name = trim(FILE_KIND_NAMES(kind))
   end function file_kind_name

   !> An input file (`what`: "case file", "mesh file", ...) must exist, be a regular file and
   !> hold at most max_bytes: a FIFO or device would block or never end, a folder cannot be
   !> read. FFRF_IO_ERROR naming the file and what it is otherwise.
   subroutine check_input_file(path, what, max_bytes, error)
      character(len=*), intent(in) :: path, what
      integer(i8), intent(in) :: max_bytes
      type(error_t), allocatable, intent(out) :: error
      integer :: kind
      integer(i8) :: size_bytes
      call file_kind(path, kind, size_bytes, error)
      if (allocated(error)) return
      if (kind == FILE_MISSING) then
         call fatal_error(error, FFRF_IO_ERROR, what // ' "' // path // '" does not exist')
      else if (kind /= FILE_REGULAR) then
         call fatal_error(error, FFRF_IO_ERROR, what // ' "' // path // '" is ' // &
            file_kind_name(kind) // '; give a regular file')
      else if (size_bytes > max_bytes) then
         call fatal_error(error, FFRF_IO_ERROR, what // ' "' // path // '" has ' // &
            to_str(size_bytes) // ' bytes, more than the ' // to_str(max_bytes) // &
            ' allowed for it')
      end if
   end subroutine check_input_file

   !> Rename `from` to `to`, replacing `to` atomically (same file system).
   subroutine rename_file(from, to, error)
      character(len=*), intent(in) :: from, to
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_rename(c_string(from), c_string(to)), &
         'rename "' // from // '" to "' // to // '"', error)
   end subroutine rename_file

   !> Remove a file; a missing one is not an error.
   subroutine remove_file(path, error)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_unlink(c_string(path)), 'remove "' // path // '"', error)
   end subroutine remove_file

   !> Force a closed file's data to the device; reports a full disk the page cache hid.
   subroutine sync_file(path, error)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_fsync_path(c_string(path)), 'write "' // path // '" to disk', error)
   end subroutine sync_file

   !> Take the exclusive lock `path` (created if missing); fd holds it. status 0: taken;
   !> ERRNO_WOULD_BLOCK: another process holds it; else the errno of the failure.
   subroutine lock_file(path, fd, status)
      character(len=*), intent(in) :: path
      integer, intent(out) :: fd, status
      call take_lock(path, .false., fd, status)
   end subroutine lock_file

   !> lock_file (safe = .false.) or lock_output (safe = .true.).
   subroutine take_lock(path, safe, fd, status)
      character(len=*), intent(in) :: path
      logical, intent(in) :: safe
      integer, intent(out) :: fd, status
      integer(c_int) :: c_fd
      if (safe) then
         status = int(c_lock_output(c_string(path), c_fd))
      else
         status = int(c_lock_file(c_string(path), c_fd))
      end if
      fd = int(c_fd)
   end subroutine take_lock

   !> Remove the lock file `path` and release the lock fd holds (fd < 0: nothing held).
   subroutine unlock_file(path, fd)
      character(len=*), intent(in) :: path
      integer, intent(inout) :: fd
      integer(c_int) :: status
      status = c_unlock_file(c_string(path), int(fd, c_int))
      fd = -1
   end subroutine unlock_file

   !> FFRF_IO_ERROR "cannot <action>: <the errno's words>" when a posix.c call returned
   !> status /= 0 (its errno); nothing when it returned 0.
   subroutine status_error(status, action, error)
      integer(c_int), intent(in) :: status
      character(len=*), intent(in) :: action
      type(error_t), allocatable, intent(out) :: error
      if (status /= 0) call fatal_error(error, FFRF_IO_ERROR, 'cannot ' // action // ': ' // &
         errno_text(int(status)))
   end subroutine status_error

   !> The system's words for an errno value ("No space left on device").
   function errno_text(code) result(text)
      integer, intent(in) :: code
      character(len=:), allocatable :: text
      text = c_text(c_errno_text, code, 200)
   end function errno_text

   !> Record SIGTERM, SIGINT, SIGHUP, SIGUSR1 and SIGXCPU instead of dying on them; a run polls
   !> pending_signal() between steps and ends cleanly.
   subroutine install_signal_handlers(error)
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_signals_install(), 'install the signal handlers', error)
   end subroutine install_signal_handlers

   !> The first signal received since install_signal_handlers (0: none).
   integer function pending_signal()
      pending_signal = int(c_signal_pending())
   end function pending_signal

   !> Forget a received signal.
   subroutine clear_pending_signal()
      call c_signal_clear()
   end subroutine clear_pending_signal

   !> "SIGTERM", "SIGUSR1", ... ("signal N" for others).
   function signal_name(number) result(name)
      integer, intent(in) :: number
      character(len=:), allocatable :: name
      name = c_text(c_signal_name, number, 32)
   end function signal_name

   !> The text a posix.c function (c_errno_text, c_signal_name) writes for `code` into a
   !> buffer of `length` bytes, up to its NUL.
   function c_text(write_text, code, length) result(text)
      procedure(c_errno_text) :: write_text
      integer, intent(in) :: code, length
      character(len=:), allocatable :: text
      character(kind=c_char) :: buffer(length)
      call write_text(int(code, c_int), buffer, int(length, c_int))
      text = from_c_buffer(buffer)
   end function c_text

   pure function c_string(text) result(c_text)
      character(len=*), intent(in) :: text
      character(kind=c_char, len=len(text) + 1) :: c_text
      c_text = text // c_null_char
   end function c_string

   pure function from_c_buffer(buffer) result(text)
      character(kind=c_char), intent(in) :: buffer(:)
      character(len=:), allocatable :: text
      integer :: n, k
      n = 0
      do while (n < size(buffer))
         if (buffer(n + 1) == c_null_char) exit
         n = n + 1
      end do
      allocate (character(len=n) :: text)
      do k = 1, n
         text(k:k) = buffer(k)
      end do
   end function from_c_buffer

   ! ---- results files (issue 10, part 1)

   !> lock_file, safe against the lock file being removed by the run that held it (posix.c).
   !> status 0: taken; ERRNO_WOULD_BLOCK: another process holds it; else the errno.
   subroutine lock_output(path, fd, status)
      character(len=*), intent(in) :: path
      integer, intent(out) :: fd, status
      call take_lock(path, .true., fd, status)
   end subroutine lock_output

   !> Make writes past RLIMIT_FSIZE fail with EFBIG instead of killing the run with SIGXFSZ.
   subroutine ignore_file_size_signal()
      integer(c_int) :: status
      status = c_ignore_file_size_signal()
   end subroutine ignore_file_size_signal

   !> Copy `from` to `to` and force `to` to the device (a checkpoint that kill -9 cannot break
   !> once renamed into place). FFRF_IO_ERROR naming `to` on failure (`to` is then incomplete).
   subroutine copy_file(from, to, error)
      character(len=*), intent(in) :: from, to
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_copy_file(c_string(from), c_string(to)), &
         'copy "' // from // '" to "' // to // '"', error)
   end subroutine copy_file

   !> The last steps of every safe write (results, checkpoints' sources, Gmsh views): force the
   !> closed, complete temporary `temp` to the device, rename it over `final`, force the folder
   !> entry. On failure `temp` is removed, `final` is left as it was, and the message reads
   !> `<what> "<final>" not written: <reason>`.
   subroutine commit_durably(temp, final, what, error)
      character(len=*), intent(in) :: temp, final, what
      type(error_t), allocatable, intent(out) :: error
      type(error_t), allocatable :: ignored
      call sync_file(temp, error)
      if (.not. allocated(error)) call rename_file(temp, final, error)
      if (allocated(error)) then
         call remove_file(temp, ignored)
         error%message = what // ' "' // final // '" not written: ' // error%message
         return
      end if
      call sync_folder_of(final, ignored)
   end subroutine commit_durably

   !> Force the folder entry of `path` (after a rename into it) to the device.
   subroutine sync_folder_of(path, error)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_fsync_folder_of(c_string(path)), &
         'write the folder of "' // path // '" to disk', error)
   end subroutine sync_folder_of

   !> After install_signal_handlers: system calls a signal interrupts are restarted (a file
   !> being read when SIGTERM arrives is read on; the run stops at its next check).
   subroutine signals_restart_calls(error)
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_signals_restart_calls(), &
         'set the signal handlers to restart system calls', error)
   end subroutine signals_restart_calls

   !> Around a call into a library that installs signal handlers of its own (METIS_NodeND):
   !> the run signals are blocked in this thread and their handlers saved; release_signals puts
   !> the saved handlers back with sigaction (whatever the library left) and unblocks, which
   !> delivers a signal that arrived meanwhile to them (posix.c, issue 23). Pairs nest.
   subroutine hold_signals(block)
      !> .false.: handlers saved and restored, the signals not blocked (default .true.)
      logical, intent(in), optional :: block
      integer(c_int) :: status, c_block
      c_block = 1
      if (present(block)) c_block = merge(1, 0, block)
      status = c_signals_hold(c_block)
   end subroutine hold_signals

   !> The end of hold_signals (module notes there).
   subroutine release_signals()
      integer(c_int) :: status
      status = c_signals_release()
   end subroutine release_signals

   !> A named point of the run where a test may send signals (FFRF_TEST_SIGNALS=STAGE:N:NAME,
   !> posix.c); nothing without that variable.
   subroutine signal_test_point(stage)
      character(len=*), intent(in) :: stage
      call c_signal_test_point(c_string(stage))
   end subroutine signal_test_point

   !> Create `path` as a new, empty regular file, never through a symbolic link: whatever the
   !> name holds is removed first (a stale temporary file, or a link, not its target), then the
   !> file is created exclusively (O_CREAT | O_EXCL | O_NOFOLLOW). FFRF_IO_ERROR naming the
   !> file when it cannot be made.
   subroutine create_new_file(path, error)
      character(len=*), intent(in) :: path
      type(error_t), allocatable, intent(out) :: error
      call status_error(c_create_new_file(c_string(path)), 'create "' // path // '"', error)
      if (allocated(error)) error%message = error%message // &
         '; check that its folder exists and is writable'
   end subroutine create_new_file

   !> Whether the paths `a` and `b` name one file: the same device and inode when both exist
   !> (links followed), else the same resolved path (the folder's links resolved, the last
   !> component's link followed when it is one). A path flagged `*_entry` stands for its folder
   !> entry instead, a link there not followed (a temporary file, removed and made anew).
   subroutine same_file(a, b, same, error, a_entry, b_entry)
      character(len=*), intent(in) :: a, b
      logical, intent(out) :: same
      type(error_t), allocatable, intent(out) :: error
      logical, intent(in), optional :: a_entry, b_entry
      integer(c_int) :: status, c_same, entry_a, entry_b
      entry_a = 0
      entry_b = 0
      if (present(a_entry)) entry_a = merge(1, 0, a_entry)
      if (present(b_entry)) entry_b = merge(1, 0, b_entry)
      status = c_same_file(c_string(a), c_string(b), entry_a, entry_b, c_same)
      same = c_same /= 0
      call status_error(status, 'compare "' // a // '" with "' // b // '"', error)
   end subroutine same_file

   !> A program's guard (the driver's): while on, an exit the program did not ask for (the
   !> Fortran runtime ending the run when an allocation finds no memory) gets one
   !> "ffrf: error:" line and exit status 4 (posix.c). Off before the program's own exit.
   subroutine exit_guard(on)
      logical, intent(in) :: on
      call c_exit_guard(merge(1_c_int, 0_c_int, on))
   end subroutine exit_guard

end module ffrf_core_posix
