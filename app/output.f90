!> What the taylorode app writes: its report on standard output (through write(2), so
!> that every failure to write it is seen), progress on standard error, the CSV tables
!> a command produces and the files they go to. Every output target is checked before
!> any work starts, and every file is written to a temporary file and renamed into
!> place when complete.
module app_output
   use, intrinsic :: iso_fortran_env, only: error_unit
   use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
   use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
   use taylorode, only: dp, status_type, status_ok, status_invalid_argument, status_name
   use taylorode_base_status, only: set_status
   use taylorode_base_strings, only: format_real
   use taylorode_base_files, only: text_file_type, make_directory, is_directory, is_writable_directory, &
      parent_directory, is_special_file, temporary_path
   use app_cli, only: request_type
   implicit none
   private

   public :: text_type, table_type, checks_failed
   public :: ignore_file_size_signal, start_output, say, finish_output, progress, usage_error
   public :: check_outputs, new_table, add_row, write_tables, write_csv, error_text, status_word

   !> One line of text
   type :: text_type
      character(len=:), allocatable :: text
   end type text_type

   !> A CSV table a command produces, written into --out after the run
   type :: table_type
      character(len=:), allocatable :: file_name, header
      type(text_type), allocatable :: rows(:)
      integer :: count = 0
   end type table_type

   !> A check of the command failed (stability, extreme, ensemble): exit status 1
   logical :: checks_failed = .false.
   !> Standard output, written through write(2) so that every failure is seen
   type(text_file_type) :: stdout

   interface
      !> app/signals.c: SIGXFSZ ignored (0), or left as it was (-1)
      function c_ignore_file_size_signal() result(status) bind(c, name="taylorode_app_ignore_file_size_signal")
         import :: c_int
         integer(c_int) :: status
      end function c_ignore_file_size_signal
      function c_remove_on_signal(path) result(status) bind(c, name="taylorode_app_remove_on_signal")
         import :: c_int, c_char
         character(kind=c_char), intent(in) :: path(*)
         integer(c_int) :: status
      end function c_remove_on_signal
   end interface

contains

   !> Let a write beyond the file-size limit (ulimit -f) fail with EFBIG, "File too
   !> large", instead of SIGXFSZ ending the program with its temporary files left
   !> behind: each output then reports the failure and removes its temporary file as it
   !> does on a full disk. The app's decision, not the library's: a library must not
   !> change a process-wide signal disposition under the program that calls it.
   subroutine ignore_file_size_signal()
      integer(c_int) :: status
      status = c_ignore_file_size_signal()   ! when it cannot, the default stays: nothing else to do
   end subroutine ignore_file_size_signal

   !> Write the report to standard output (descriptor 1) from now on.
   subroutine start_output()
      call stdout%attach(1, "standard output")
   end subroutine start_output

   !> Print a line of the report on standard output (failures are remembered).
   subroutine say(line)
      character(len=*), intent(in) :: line
      call stdout%write_line(line)
      call stdout%flush()
   end subroutine say

   !> Close standard output; a failure to write it is an error (exit status 1).
   subroutine finish_output()
      type(status_type) :: output_stat
      integer :: io_status
      call stdout%commit(output_stat)
      if (output_stat%code /= status_ok) then
         write (error_unit, '(a)', iostat=io_status) "taylorode: "//output_stat%message
         stop 1, quiet=.true.
      end if
   end subroutine finish_output

   !> Progress of a long run, on standard error.
   subroutine progress(message)
      character(len=*), intent(in) :: message
      integer :: io_status
      write (error_unit, '(a)', iostat=io_status) "  ... "//message
   end subroutine progress

   !> A mistake on the command line: message, hint, exit status 2.
   subroutine usage_error(message)
      character(len=*), intent(in) :: message
      integer :: io_status
      write (error_unit, '(a)', iostat=io_status) "taylorode: "//message
      write (error_unit, '(a)', iostat=io_status) "try: taylorode --help"
      stop 2, quiet=.true.
   end subroutine usage_error

   !> The CSV files a command writes into --out.
   function table_files(command) result(names)
      character(len=*), intent(in) :: command
      character(len=20), allocatable :: names(:)
      select case (command)
      case ("table"); names = [character(len=20) :: "table1.csv"]
      case ("sweep"); names = [character(len=20) :: "sweep.csv"]
      case ("stability"); names = [character(len=20) :: "stability_check.csv", "s1_regions.csv", "l_stability.csv"]
      case ("extreme"); names = [character(len=20) :: "extreme.csv"]
      case ("accuracy"); names = [character(len=20) :: "accuracy.csv"]
      case default; allocate (names(0))
      end select
   end function table_files

   !> Before any work: the --out directory exists or can be created and is writable, no
   !> file the run will write exists (unless --force) or is a directory, and the step
   !> history goes into a writable directory.
   subroutine check_outputs(request, stat)
      type(request_type), intent(in) :: request
      type(status_type), intent(out) :: stat
      character(len=20), allocatable :: names(:)
      integer :: k

      if (allocated(request%history_file)) call check_target(request%history_file, request%force, stat)
      if (allocated(request%csv_file)) call check_target(request%csv_file, request%force, stat)
      if (stat%code /= status_ok .or. .not. allocated(request%out_dir)) return
      names = table_files(request%command)
      if (size(names) == 0) then
         call set_status(stat, status_invalid_argument, "--out: "//request%command//" writes no tables")
         return
      end if
      if (.not. is_directory(request%out_dir)) then
         if (.not. is_writable_directory(parent_directory(request%out_dir))) then
            call set_status(stat, status_invalid_argument, "cannot create the directory "//request%out_dir// &
               ": its parent "//parent_directory(request%out_dir)//" is not a writable directory")
            return
         end if
         call make_directory(request%out_dir, stat)
         if (stat%code /= status_ok) return
      end if
      do k = 1, size(names)
         call check_target(request%out_dir//"/"//trim(names(k)), request%force, stat)
         if (stat%code /= status_ok) return
      end do
   end subroutine check_outputs

   !> One file to be written: not a directory, kept unless --force, in a writable directory.
   subroutine check_target(path, force, stat)
      character(len=*), intent(in) :: path
      logical, intent(in) :: force
      type(status_type), intent(inout) :: stat
      type(text_file_type) :: file
      logical :: exists
      integer(c_int) :: signal_status
      character(len=:), allocatable :: temporary
      if (is_directory(path)) then
         call set_status(stat, status_invalid_argument, path//" is a directory")
         return
      end if
      inquire (file=path, exist=exists)
      if (exists .and. .not. force) then
         call set_status(stat, status_invalid_argument, path//" exists; use --force to overwrite it")
         return
      end if
      if (.not. is_writable_directory(parent_directory(path))) then
         call set_status(stat, status_invalid_argument, "cannot write "//path//": "//parent_directory(path)// &
            " is not a writable directory")
         return
      end if
      ! a device or a pipe is written in place: not opened to probe it (a named pipe's
      ! reader took the probe's close for the end, and the real open then waited for a
      ! reader for ever)
      if (is_special_file(path)) return
      ! the file itself can be created there (a name too long, a file system that refuses it)
      call file%open(path, stat)
      if (stat%code /= status_ok) then
         stat%code = status_invalid_argument
         return
      end if
      call file%discard()
      ! a run ended by SIGINT, SIGTERM or SIGHUP removes the temporary file it was writing
      ! (a killed --history left tens of MB beside its destination); when it cannot
      ! arrange that, the file is left as before: nothing else to do
      call temporary_path(path, 1, temporary)
      signal_status = c_remove_on_signal(temporary//c_null_char)
   end subroutine check_target

   !> Start a CSV table; returns its index.
   function new_table(tables, file_name, header) result(index)
      type(table_type), allocatable, intent(inout) :: tables(:)
      character(len=*), intent(in) :: file_name, header
      integer :: index
      type(table_type), allocatable :: grown(:)
      allocate (grown(size(tables) + 1))
      grown(:size(tables)) = tables
      grown(size(grown))%file_name = file_name
      grown(size(grown))%header = header
      allocate (grown(size(grown))%rows(64))
      call move_alloc(grown, tables)
      index = size(tables)
   end function new_table

   !> Append a row to a CSV table.
   subroutine add_row(table, row)
      type(table_type), intent(inout) :: table
      character(len=*), intent(in) :: row
      type(text_type), allocatable :: grown(:)
      if (table%count == size(table%rows)) then
         allocate (grown(2*size(table%rows)))
         grown(:table%count) = table%rows(:table%count)
         call move_alloc(grown, table%rows)
      end if
      table%count = table%count + 1
      table%rows(table%count)%text = row
   end subroutine add_row

   !> After the run: write the tables into --out (each complete or not at all) and say
   !> which were written; stat reports the first that could not be.
   subroutine write_tables(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), intent(in) :: tables(:)
      type(status_type), intent(out) :: stat
      type(text_file_type) :: file
      type(status_type) :: file_stat
      integer :: t, r
      character(len=:), allocatable :: path

      if (.not. allocated(request%out_dir)) return
      do t = 1, size(tables)
         path = request%out_dir//"/"//tables(t)%file_name
         file_stat = status_type()
         ! (a file that appeared since check_outputs is kept without --force)
         call file%open(path, file_stat, replace=request%force)
         if (file_stat%code == status_ok) then
            call file%write_line(tables(t)%header)
            do r = 1, tables(t)%count
               call file%write_line(tables(t)%rows(r)%text)
            end do
            call file%commit(file_stat)
         end if
         if (file_stat%code == status_ok) then
            call say("wrote "//path)
         else if (stat%code == status_ok) then
            stat = file_stat
         end if
      end do
   end subroutine write_tables

   !> Write a CSV file (header and rows) in one piece.
   subroutine write_csv(path, header, rows, force, stat)
      character(len=*), intent(in) :: path, header
      type(text_type), intent(in) :: rows(:)
      !> Whether a file at path (one that appeared since check_outputs) may be replaced
      logical, intent(in) :: force
      type(status_type), intent(out) :: stat
      type(text_file_type) :: file
      integer :: r
      call file%open(path, stat, replace=force)
      if (stat%code /= status_ok) return
      call file%write_line(header)
      do r = 1, size(rows)
         call file%write_line(rows(r)%text)
      end do
      call file%commit(stat)
      if (stat%code == status_ok) call say("wrote "//path)
   end subroutine write_csv

   !> An error for a report: "n/a" when it was not measured (negative or NaN).
   pure function error_text(err) result(text)
      real(dp), intent(in) :: err
      character(len=:), allocatable :: text
      text = "n/a"
      if (ieee_is_nan(err)) return
      if (err >= 0.0_dp) text = format_real(err, 2)
   end function error_text

   !> A status name as one word (blanks to underscores), for CSV files.
   pure function status_word(code) result(text)
      integer, intent(in) :: code
      character(len=:), allocatable :: text
      integer :: i
      text = status_name(code)
      do i = 1, len(text)
         if (text(i:i) == " ") text(i:i) = "_"
      end do
   end function status_word

end module app_output
