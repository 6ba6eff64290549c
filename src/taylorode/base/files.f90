!> Files written safely: a text file is written to a temporary file beside its
!> destination and renamed into place only when every byte was written and the file
!> closed without error, so a failure (full disk, file-size limit, permissions)
!> never leaves a truncated or half-overwritten file. A destination that exists and
!> is not a regular file (a device such as /dev/stdout, a named pipe) is written in
!> place instead, never replaced.
!>
!> The bytes go through POSIX open(2), write(2) and close(2), whose every result is
!> checked (the Fortran runtime does not report every failed write). Directories are
!> created without a shell, through mkdir(2); file types come from statx(2). Linux.
!> A write beyond a file-size limit fails (EFBIG) only in a process that ignores
!> SIGXFSZ, whose default action ends the process first; signal dispositions are the
!> program's to choose (the app ignores it), never changed here.
module taylorode_base_files
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_int8_t, c_int16_t, c_size_t, &
      c_ptr, c_long, c_f_pointer
   use taylorode_base_status, only: status_type, set_status, status_output_error, status_invalid_argument
   use taylorode_base_memory, only: out_of_memory
   implicit none
   private

   public :: text_file_type, make_directory, is_directory, is_writable_directory, parent_directory, is_special_file, &
      temporary_path

   !> Bytes collected before each write(2)
   integer, parameter :: buffer_size = 65536
   !> Longest file name (one path component) of the file systems (NAME_MAX)
   integer, parameter :: name_max = 255

   !> A text file being written: lines go to a temporary file until `commit`
   type :: text_file_type
      !> Destination
      character(len=:), allocatable :: path
      !> The file the bytes go to (a temporary file beside the destination, or the
      !> destination itself when it is a device or a pipe)
      character(len=:), allocatable :: temporary
      !> Its file descriptor (-1: none)
      integer(c_int) :: descriptor = -1_c_int
      !> Whether the destination itself is being written
      logical :: in_place = .false.
      !> Whether `commit` may replace a destination that exists by then
      logical :: replace = .true.
      !> Bytes not yet written (allocated when the file is opened)
      character(len=:), allocatable :: buffer
      !> How many bytes of the buffer are in use
      integer :: used = 0
      !> First error (0: none)
      integer :: io_error = 0
      !> What the first error was
      character(len=256) :: io_message = ""
   contains
      !> Start writing `path` (to a temporary file in the same directory)
      procedure :: open => text_file_open
      !> Write to a descriptor that is already open (1: standard output)
      procedure :: attach => text_file_attach
      !> Hand what was written so far to the operating system
      procedure :: flush => text_file_flush
      !> Append one line
      procedure :: write_line => text_file_write_line
      !> Append text to the current line (no line end)
      procedure :: write_part => text_file_write_part
      !> Write everything, close and rename into place; on failure nothing changes
      procedure :: commit => text_file_commit
      !> Give up: remove the temporary file
      procedure :: discard => text_file_discard
   end type text_file_type

   interface
      function c_open(path, flags, mode) bind(c, name="open") result(descriptor)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int), value :: flags, mode
         integer(c_int) :: descriptor
      end function c_open
      function c_write(descriptor, bytes, count) bind(c, name="write") result(written)
         import :: c_int, c_char, c_size_t, c_long
         integer(c_int), value :: descriptor
         character(kind=c_char), intent(in) :: bytes(*)
         integer(c_size_t), value :: count
         integer(c_long) :: written
      end function c_write
      function c_close(descriptor) bind(c, name="close") result(status)
         import :: c_int
         integer(c_int), value :: descriptor
         integer(c_int) :: status
      end function c_close
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
      function c_link(existing, new) bind(c, name="link") result(status)
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: existing(*), new(*)
         integer(c_int) :: status
      end function c_link
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
      function c_statx(directory, path, flags, mask, buffer) bind(c, name="statx") result(status)
         import :: c_int, c_char, c_int8_t
         integer(c_int), value :: directory, flags, mask
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int8_t), intent(out) :: buffer(*)
         integer(c_int) :: status
      end function c_statx
      function c_errno_location() bind(c, name="__errno_location") result(location)
         import :: c_ptr
         type(c_ptr) :: location
      end function c_errno_location
      function c_strerror(code) bind(c, name="strerror") result(text)
         import :: c_int, c_ptr
         integer(c_int), value :: code
         type(c_ptr) :: text
      end function c_strerror
   end interface

   !> open(2) flags (Linux): write only, create, fail if it exists
   integer(c_int), parameter :: o_wronly = 1_c_int, o_creat = int(o'100', c_int), o_excl = int(o'200', c_int)
   !> Permissions of new files and directories before the umask
   integer(c_int), parameter :: file_mode = int(o'666', c_int), directory_mode = int(o'777', c_int)
   !> access(2) modes: existence, write and search permission
   integer(c_int), parameter :: f_ok = 0_c_int, w_ok = 2_c_int, x_ok = 1_c_int
   !> statx(2): relative to the working directory, the file type wanted, struct statx
   !> size and the offset of its 16-bit stx_mode (a layout fixed on every architecture)
   integer(c_int), parameter :: at_fdcwd = -100_c_int, statx_type = 1_c_int
   integer, parameter :: statx_size = 256, statx_mode_offset = 28
   !> File type bits of a mode, and the type of a regular file
   integer, parameter :: mode_type_mask = int(o'170000'), mode_regular = int(o'100000')
   !> errno of an existing file (EEXIST)
   integer, parameter :: errno_exists = 17
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

   !> Whether path exists and is something other than a regular file or a directory
   !> (a device, a pipe, a socket): such a destination is written in place.
   function is_special_file(path) result(special)
      !> The path
      character(len=*), intent(in) :: path
      !> Whether it is a device, a pipe or a socket
      logical :: special
      integer(c_int8_t) :: buffer(statx_size)
      integer :: mode
      special = .false.
      if (len(path) == 0 .or. is_directory(path)) return
      if (c_statx(at_fdcwd, path//c_null_char, 0_c_int, statx_type, buffer) /= 0) return
      mode = iand(int(transfer(buffer(statx_mode_offset + 1:statx_mode_offset + 2), 0_c_int16_t)), int(z'FFFF'))
      special = iand(mode, mode_type_mask) /= mode_regular
   end function is_special_file

   !> The C library's text for the current errno.
   function last_error() result(text)
      character(len=128) :: text
      integer(c_int), pointer :: code
      character(kind=c_char), pointer :: chars(:)
      integer :: k
      call c_f_pointer(c_errno_location(), code)
      call c_f_pointer(c_strerror(code), chars, [len(text)])
      text = ""
      do k = 1, len(text)
         if (chars(k) == c_null_char) exit
         text(k:k) = chars(k)
      end do
   end function last_error

   !> errno now.
   integer function last_errno()
      integer(c_int), pointer :: code
      call c_f_pointer(c_errno_location(), code)
      last_errno = code
   end function last_errno

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
         call set_status(stat, status_output_error, "cannot create the directory "//path//": "// &
            trim(last_error()))
      end if
   end subroutine make_directory

   !> Start writing `path`: a new temporary file in the same directory receives the
   !> bytes (the destination itself when it is a device or a pipe).
   subroutine text_file_open(self, path, stat, replace)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> Destination
      character(len=*), intent(in) :: path
      !> status_output_error when it cannot be opened
      type(status_type), intent(inout) :: stat
      !> Whether `commit` may replace a file at path that exists by then (default true;
      !> false: such a file is kept and commit fails)
      logical, intent(in), optional :: replace
      integer :: attempt, memory
      self%replace = .true.
      if (present(replace)) self%replace = replace
      self%path = path
      self%io_error = 0
      self%used = 0
      self%descriptor = -1_c_int
      self%in_place = .false.
      if (.not. allocated(self%buffer)) then
         allocate (character(len=buffer_size) :: self%buffer, stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "a file's write buffer", [buffer_size], 1)
            return
         end if
      end if
      if (len(path) == 0) then
         call set_status(stat, status_invalid_argument, "an empty file name")
         return
      end if
      if (is_directory(path)) then
         call set_status(stat, status_output_error, "cannot write "//path//": it is a directory")
         return
      end if
      ! (the temporary name is cut to fit, the destination's cannot be)
      if (len(path) - index(path, "/", back=.true.) > name_max) then
         call set_status(stat, status_output_error, "cannot write "//path//": File name too long")
         return
      end if
      if (is_special_file(path)) then
         self%in_place = .true.
         self%temporary = path
         self%descriptor = c_open(path//c_null_char, o_wronly, 0_c_int)
      else
         do attempt = 1, temporary_attempts
            call temporary_path(path, attempt, self%temporary)
            self%descriptor = c_open(self%temporary//c_null_char, ior(o_wronly, ior(o_creat, o_excl)), file_mode)
            if (self%descriptor >= 0) exit
            if (last_errno() /= errno_exists) exit
         end do
      end if
      if (self%descriptor < 0) call set_status(stat, status_output_error, "cannot write "//path//": "// &
         trim(last_error()))
   end subroutine text_file_open

   !> The temporary file `open` writes for path in its attempt'th try: path.tmp-PID-attempt
   !> beside it, the last component cut where that would pass name_max bytes (a file name
   !> of 250 bytes could not be written: its temporary name was too long).
   subroutine temporary_path(path, attempt, name)
      !> The destination
      character(len=*), intent(in) :: path
      !> Which try (1 unless a file of that name was there)
      integer, intent(in) :: attempt
      !> The temporary file's path
      character(len=:), allocatable, intent(out) :: name
      character(len=32) :: suffix
      integer :: directory_end
      write (suffix, '(".tmp-", i0, "-", i0)') c_getpid(), attempt
      directory_end = index(path, "/", back=.true.)
      name = path(:min(len(path), directory_end + name_max - len_trim(suffix)))//trim(suffix)
   end subroutine temporary_path

   !> Write to a descriptor that is already open (e.g. 1, standard output), in place;
   !> `commit` writes what is left and closes it.
   subroutine text_file_attach(self, descriptor, name)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> The open descriptor
      integer, intent(in) :: descriptor
      !> What to call it in messages
      character(len=*), intent(in) :: name
      self%path = name
      self%temporary = name
      self%io_error = 0
      self%used = 0
      self%in_place = .true.
      self%descriptor = int(descriptor, c_int)
      if (.not. allocated(self%buffer)) allocate (character(len=buffer_size) :: self%buffer)
   end subroutine text_file_attach

   !> Hand what was written so far to the operating system (errors are remembered).
   subroutine text_file_flush(self)
      !> The file
      class(text_file_type), intent(inout) :: self
      if (self%descriptor < 0 .or. self%io_error /= 0 .or. self%used == 0) return
      call write_buffer(self)
   end subroutine text_file_flush

   !> Append text to the current line, without ending it (errors are remembered and
   !> reported by `commit`).
   subroutine text_file_write_part(self, text)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> The text
      character(len=*), intent(in) :: text
      integer :: start, piece
      if (self%descriptor < 0 .or. self%io_error /= 0) return
      start = 1
      do while (start <= len(text))
         if (self%used == buffer_size) call write_buffer(self)
         if (self%io_error /= 0) return
         piece = min(len(text) - start + 1, buffer_size - self%used)
         self%buffer(self%used + 1:self%used + piece) = text(start:start + piece - 1)
         self%used = self%used + piece
         start = start + piece
      end do
   end subroutine text_file_write_part

   !> Append one line.
   subroutine text_file_write_line(self, text)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> The line
      character(len=*), intent(in) :: text
      call self%write_part(text)
      call self%write_part(new_line("a"))
   end subroutine text_file_write_line

   !> Hand the collected bytes to write(2), all of them or an error.
   subroutine write_buffer(self)
      type(text_file_type), intent(inout) :: self
      integer(c_long) :: written
      integer :: start
      start = 1
      do while (start <= self%used)
         written = c_write(self%descriptor, self%buffer(start:self%used), int(self%used - start + 1, c_size_t))
         if (written <= 0) then
            self%io_error = -1
            self%io_message = last_error()
            return
         end if
         start = start + int(written)
      end do
      self%used = 0
   end subroutine write_buffer

   !> Write what is left, close, and rename the temporary file onto the destination (or,
   !> opened with replace false, link it there, which fails where a file exists by then).
   !> On any failure (a write, the close, the rename or link) the temporary file is
   !> removed, the destination is left as it was, and stat says why.
   subroutine text_file_commit(self, stat)
      !> The file
      class(text_file_type), intent(inout) :: self
      !> status_output_error on failure
      type(status_type), intent(inout) :: stat
      integer(c_int) :: ignored
      if (self%descriptor < 0) then
         call set_status(stat, status_output_error, "cannot write "//self%path//": it was not opened")
         return
      end if
      if (self%io_error == 0 .and. self%used > 0) call write_buffer(self)
      if (c_close(self%descriptor) /= 0 .and. self%io_error == 0) then
         self%io_error = -1
         self%io_message = last_error()
      end if
      self%descriptor = -1_c_int
      if (self%in_place) then
         if (self%io_error /= 0) call set_status(stat, status_output_error, "cannot write "//self%path//": "// &
            trim(self%io_message))
         return
      end if
      if (self%io_error == 0 .and. self%replace) then
         if (c_rename(self%temporary//c_null_char, self%path//c_null_char) == 0) return
         self%io_error = -1
         self%io_message = last_error()
      else if (self%io_error == 0) then
         ! link(2) fails where the destination exists (rename(2) would replace it): a
         ! file that appeared since the caller checked is kept. Where the file system has
         ! no hard links, rename(2) if nothing is there (a race left open only there)
         if (c_link(self%temporary//c_null_char, self%path//c_null_char) == 0) then
            ignored = c_unlink(self%temporary//c_null_char)
            return
         end if
         if (last_errno() == errno_exists) then
            self%io_message = "it exists by now"
         else if (c_access(self%path//c_null_char, f_ok) /= 0) then
            if (c_rename(self%temporary//c_null_char, self%path//c_null_char) == 0) return
            self%io_message = last_error()
         else
            self%io_message = "it exists by now"
         end if
         self%io_error = -1
      end if
      ignored = c_unlink(self%temporary//c_null_char)
      call set_status(stat, status_output_error, "cannot write "//self%path//": "//trim(self%io_message)// &
         " (the file was left as it was)")
   end subroutine text_file_commit

   !> Give up writing: close and remove the temporary file, leave the destination alone.
   subroutine text_file_discard(self)
      !> The file
      class(text_file_type), intent(inout) :: self
      integer(c_int) :: ignored
      if (self%descriptor < 0) return
      ignored = c_close(self%descriptor)
      self%descriptor = -1_c_int
      if (.not. self%in_place) ignored = c_unlink(self%temporary//c_null_char)
   end subroutine text_file_discard

end module taylorode_base_files
