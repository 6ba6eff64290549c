!> Files written safely: a text file is written to a temporary file beside its
!> destination and renamed into place only when every line and the close succeeded,
!> so a failure (full disk, permissions) never leaves a truncated or half-overwritten
!> file. Directories are created without a shell, through mkdir(2).
module taylorode_base_files
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
   use taylorode_base_status, only: status_type, set_status, status_ok, status_output_error, &
      status_invalid_argument
   implicit none
   private

   public :: text_file_type, make_directory, is_directory, is_writable_directory, parent_directory

   !> A text file being written: lines go to a temporary file until `commit`
   type :: text_file_type
      !> Destination
      character(len=:), allocatable :: path
      !> The temporary file beside it
      character(len=:), allocatable :: temporary
      !> Fortran unit of the temporary file
      integer :: unit = 0
      !> Whether the temporary file is open
      logical :: is_open = .false.
      !> First write error (0: none)
      integer :: io_error = 0
      !> Its message
      character(len=256) :: io_message = ""
   contains
      !> Start writing `path` (to a temporary file in the same directory)
      procedure :: open => text_file_open
      !> Append one line
      procedure :: write_line => text_file_write_line
      !> Append text to the current line (no line end)
      procedure :: write_part => text_file_write_part
      !> Close and rename into place; on any failure the destination is untouched
      procedure :: commit => text_file_commit
      !> Give up: remove the temporary file
      procedure :: discard => text_file_discard
   end type text_file_type

   interface
      function c_mkdir(path, mode) bind(c, name="mkdir") result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value :: mode
         integer(c_int) :: status
      end function c_mkdir
      function c_rename(from, to) bind(c, name="rename") result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: from(*), to(*)
         integer(c_int) :: status
      end function c_rename
      function c_unlink(path) bind(c, name="unlink") result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int) :: status
      end function c_unlink
      function c_access(path, mode) bind(c, name="access") result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value :: mode
         integer(c_int) :: status
      end function c_access
      function c_getpid() bind(c, name="getpid") result(pid)
         import :: c_int
         integer(c_int) :: pid
      end function c_getpid
   end interface

   !> access(2) modes: write and search permission
   integer(c_int), parameter :: w_ok = 2_c_int, x_ok = 1_c_int
   !> Permissions of a new directory before the umask
   integer(c_int), parameter :: directory_mode = int(o'777', c_int)
   !> Temporary names tried before giving up
   integer, parameter :: temporary_attempts = 1000

contains

   !> The directory part of a path ("." when it has none).
   pure function parent_directory(path) result(parent)
      !> A file or directory path
      character(len=*), intent(in) :: path
      character(len=:), allocatable :: parent
      integer :: slash
      slash = index(path, "/", back=.true.)
      if (slash == 0) then
         parent = "."
      else if (slash == 1) then
         parent = "/"
      else
         parent = path(:slash - 1)
      end if
   end function parent_directory

   !> Whether path names an existing directory.
   function is_directory(path) result(exists)
      !> The path
      character(len=*), intent(in) :: path
      logical :: exists
      if (len(path) == 0) then
         exists = .false.
         return
      end if
      inquire (file=path//"/.", exist=exists)
   end function is_directory

   !> Whether path is a directory this process may create files in.
   function is_writable_directory(path) result(writable)
      !> The path
      character(len=*), intent(in) :: path
      logical :: writable
      writable = is_directory(path)
      if (writable) writable = c_access(path//c_null_char, ior(w_ok, x_ok)) == 0
   end function is_writable_directory

   !> Create the directory `path` (its parent must exist); an existing directory is fine.
   subroutine make_directory(path, stat)
      !> The directory to create, exactly as given
      character(len=*), intent(in) :: path
      !> status_output_error when it cannot be created
      type(status_type), intent(inout) :: stat
      if (is_directory(path)) return
      if (len(path) == 0) then
         call set_status(stat, status_invalid_argument, "an empty directory name")
         return
      end if
      if (c_mkdir(path//c_null_char, directory_mode) /= 0 .and. .not. is_directory(path)) then
         call set_status(stat, status_output_error, "cannot create the directory "//path// &
            " (does its parent directory exist and is it writable?)")
      end if
   end subroutine make_directory

   !> Start writing `path`: a new temporary file in the same directory receives the lines.
   subroutine text_file_open(self, path, stat)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> Destination
      character(len=*), intent(in) :: path
      !> status_output_error when no temporary file can be created there
      type(status_type), intent(inout) :: stat
      character(len=32) :: suffix
      integer :: attempt, io
      self%path = path
      self%io_error = 0
      self%is_open = .false.
      if (len(path) == 0) then
         call set_status(stat, status_invalid_argument, "an empty file name")
         return
      end if
      if (is_directory(path)) then
         call set_status(stat, status_output_error, "cannot write "//path//": it is a directory")
         return
      end if
      do attempt = 1, temporary_attempts
         write (suffix, '(".tmp-", i0, "-", i0)') c_getpid(), attempt
         self%temporary = path//trim(suffix)
         open (newunit=self%unit, file=self%temporary, status="new", action="write", iostat=io, &
            iomsg=self%io_message)
         self%is_open = io == 0
         if (self%is_open) return
         if (.not. is_writable_directory(parent_directory(path))) exit
      end do
      call set_status(stat, status_output_error, "cannot write "//path//": "//trim(self%io_message))
   end subroutine text_file_open

   !> Append one line (errors are remembered and reported by `commit`).
   subroutine text_file_write_line(self, text)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> The line
      character(len=*), intent(in) :: text
      if (.not. self%is_open .or. self%io_error /= 0) return
      write (self%unit, '(a)', iostat=self%io_error, iomsg=self%io_message) text
   end subroutine text_file_write_line

   !> Append text to the current line, without ending it.
   subroutine text_file_write_part(self, text)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> The text
      character(len=*), intent(in) :: text
      if (.not. self%is_open .or. self%io_error /= 0) return
      write (self%unit, '(a)', advance="no", iostat=self%io_error, iomsg=self%io_message) text
   end subroutine text_file_write_part

   !> Close the temporary file and rename it onto the destination. On any failure
   !> (a write, the close or the rename) the temporary file is removed, the
   !> destination is left as it was, and stat says why.
   subroutine text_file_commit(self, stat)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> status_output_error on failure
      type(status_type), intent(inout) :: stat
      integer :: io
      character(len=256) :: message
      if (.not. self%is_open) then
         call set_status(stat, status_output_error, "cannot write "//self%path//": it was not opened")
         return
      end if
      if (self%io_error == 0) then
         flush (self%unit, iostat=self%io_error, iomsg=self%io_message)
      end if
      close (self%unit, iostat=io, iomsg=message)
      self%is_open = .false.
      if (self%io_error == 0 .and. io /= 0) then
         self%io_error = io
         self%io_message = message
      end if
      if (self%io_error == 0) then
         if (c_rename(self%temporary//c_null_char, self%path//c_null_char) == 0) return
         self%io_message = "cannot rename the temporary file into place"
         self%io_error = -1
      end if
      io = c_unlink(self%temporary//c_null_char)
      call set_status(stat, status_output_error, "cannot write "//self%path//": "//trim(self%io_message)// &
         " (the file was left as it was)")
   end subroutine text_file_commit

   !> Give up writing: close and remove the temporary file, leave the destination alone.
   subroutine text_file_discard(self)
      !> The file
      class(text_file_type), intent(inout) :: self
      integer :: io
      if (.not. self%is_open) return
      close (self%unit, status="delete", iostat=io)
      self%is_open = .false.
   end subroutine text_file_discard

end module taylorode_base_files
