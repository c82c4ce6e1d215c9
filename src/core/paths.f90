!> File-path helpers of the case runners: folder of a file, joining a folder and a name, and a
!> suffix before the extension.
module ffrf_core_paths
   implicit none
   private
   public :: folder_of, join_path, insert_suffix, stem_of

contains

   !> "input/crank.nml" -> "input"; "crank.nml" -> ""; "/crank.nml" -> "/".
   pure function folder_of(path) result(folder)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: folder
      integer :: slash
      slash = index(path, '/', back=.true.)
      folder = ''
      if (slash > 0) folder = path(:slash - 1)
      if (slash == 1) folder = '/'
   end function folder_of

   !> dir/name, or name itself when dir is empty or name is absolute.
   pure function join_path(dir, name) result(path)
      character(len=*), intent(in) :: dir, name
      character(len=:), allocatable :: path
      if (len_trim(dir) == 0 .or. name(1:1) == '/') then
         path = name
      else
         path = trim(dir) // '/' // name
      end if
   end function join_path

   !> "a/b.msh" + "_crank" -> "a/b_crank.msh".
   pure function insert_suffix(path, suffix) result(new_path)
      character(len=*), intent(in) :: path, suffix
      character(len=:), allocatable :: new_path
      character(len=:), allocatable :: stem
      stem = stem_of(path)
      new_path = stem // suffix // path(len(stem) + 1:)
   end function insert_suffix

   !> "a/b.msh" -> "a/b"; a path whose last part has no '.' is its own stem.
   pure function stem_of(path) result(stem)
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: stem
      integer :: dot
      dot = index(path, '.', back=.true.)
      if (dot > index(path, '/', back=.true.)) then
         stem = path(:dot - 1)
      else
         stem = path
      end if
   end function stem_of

end module ffrf_core_paths
