!> The taylorode command-line app: parses the command line, runs the experiment,
!> prints its report and writes its CSV files when asked to (--out, --history).
program taylorode_app
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use taylorode, only: status_type, status_ok
   use taylorode_cli, only: cli_request_type, parse_command_line, help_text
   use taylorode_report, only: report_type
   use taylorode_experiments, only: run_vdp, run_table, run_sweep
   use taylorode_checks, only: run_stability, run_extreme
   use taylorode_bench, only: run_bench
   implicit none

   type(cli_request_type) :: request
   type(report_type) :: report
   type(status_type) :: stat
   character(len=:), allocatable :: args(:)
   integer :: k

   call read_arguments(args)
   call parse_command_line(args, request, stat)
   if (stat%code /= status_ok) then
      write (error_unit, '(a)') "taylorode: "//stat%message
      write (error_unit, '(a)') "try: taylorode --help"
      error stop 2
   end if
   if (request%help) then
      if (size(args) >= 1 .and. args(1)(1:1) /= "-") then
         write (output_unit, '(a)') help_text(request%command)
      else
         write (output_unit, '(a)') help_text("")
      end if
      stop
   end if
   if (.not. outputs_writable()) error stop 2

   select case (request%command)
   case ("vdp")
      call run_vdp(request, report, stat)
   case ("table")
      call run_table(request, report, stat, progress)
   case ("sweep")
      call run_sweep(request, report, stat, progress)
   case ("stability")
      call run_stability(request, report, stat)
   case ("extreme")
      call run_extreme(request, report, stat, progress)
   case ("bench")
      call run_bench(request, report, stat, progress)
   end select

   do k = 1, report%line_count
      write (output_unit, '(a)') report%lines(k)%text
   end do
   call write_tables()
   if (stat%code /= status_ok .and. request%command /= "vdp") then
      write (error_unit, '(a)') "taylorode: "//stat%message
      error stop 1
   end if
   if (.not. report%passed) error stop 1

contains

   !> Every command-line argument, padded to a common length.
   subroutine read_arguments(args)
      character(len=:), allocatable, intent(out) :: args(:)
      integer :: i, length, longest
      longest = 1
      do i = 1, command_argument_count()
         call get_command_argument(i, length=length)
         longest = max(longest, length)
      end do
      allocate (character(len=longest) :: args(command_argument_count()))
      do i = 1, command_argument_count()
         call get_command_argument(i, args(i))
      end do
   end subroutine read_arguments

   !> The output directory exists (or is created) and no file of this run would be
   !> overwritten without --force.
   logical function outputs_writable()
      logical :: exists
      integer :: status
      outputs_writable = .true.
      if (allocated(request%history_file)) then
         inquire (file=request%history_file, exist=exists)
         if (exists .and. .not. request%force) then
            write (error_unit, '(a)') "taylorode: "//request%history_file//" exists; use --force to overwrite it"
            outputs_writable = .false.
         end if
      end if
      if (allocated(request%out_dir)) then
         call execute_command_line('mkdir -p "'//request%out_dir//'"', exitstat=status)
         if (status /= 0) then
            write (error_unit, '(a)') "taylorode: cannot create the directory "//request%out_dir
            outputs_writable = .false.
         end if
      end if
   end function outputs_writable

   !> Write the report's tables: the history where the user named it, the others
   !> into --out; an existing file is kept unless --force.
   subroutine write_tables()
      integer :: t, r, unit, io
      logical :: exists, failed
      character(len=:), allocatable :: path
      if (.not. allocated(report%tables)) return
      failed = .false.
      do t = 1, size(report%tables)
         path = destination(report%tables(t)%file_name)
         if (len(path) == 0) cycle
         inquire (file=path, exist=exists)
         if (exists .and. .not. request%force) then
            write (error_unit, '(a)') "taylorode: "//path//" exists; not overwritten (use --force)"
            failed = .true.
            cycle
         end if
         open (newunit=unit, file=path, status="replace", action="write", iostat=io)
         if (io /= 0) then
            write (error_unit, '(a)') "taylorode: cannot write "//path
            failed = .true.
            cycle
         end if
         write (unit, '(a)') report%tables(t)%header
         do r = 1, report%tables(t)%count
            write (unit, '(a)') report%tables(t)%rows(r)%text
         end do
         close (unit)
         write (output_unit, '(a)') "wrote "//path
      end do
      if (failed) error stop 1
   end subroutine write_tables

   !> Where a table goes: the history file as named, others into --out, "" for none.
   function destination(file_name) result(path)
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: path
      path = ""
      if (allocated(request%history_file)) then
         if (file_name == request%history_file) then
            path = file_name
            return
         end if
      end if
      if (allocated(request%out_dir)) path = request%out_dir//"/"//file_name
   end function destination

   !> Progress of a long run, on standard error.
   subroutine progress(message)
      character(len=*), intent(in) :: message
      write (error_unit, '(a)') "  ... "//message
   end subroutine progress

end program taylorode_app
