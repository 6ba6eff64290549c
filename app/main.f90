!> The taylorode command-line app: parses the command line, runs the experiment,
!> prints its report and writes its CSV files when asked to (--out, --history).
program taylorode_app
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use taylorode, only: status_type, status_ok, status_invalid_argument
   use app_cli, only: cli_request_type, parse_command_line, help_text
   use app_report, only: report_type
   use app_experiments, only: run_vdp, run_table, run_sweep
   use app_checks, only: run_stability, run_extreme
   use app_bench, only: run_bench
   use app_outputs, only: check_outputs, write_outputs
   use app_progress, only: progress
   implicit none

   type(cli_request_type) :: request
   type(report_type) :: report
   type(status_type) :: stat, write_stat
   character(len=:), allocatable :: args(:)
   integer :: k

   call read_arguments(args)
   call parse_command_line(args, request, stat)
   if (stat%code /= status_ok) then
      write (error_unit, '(a)') "taylorode: "//stat%message
      write (error_unit, '(a)') "try: taylorode --help"
      stop 2, quiet=.true.
   end if
   if (request%help) then
      if (size(args) >= 1 .and. args(1)(1:1) /= "-") then
         write (output_unit, '(a)') help_text(request%command)
      else
         write (output_unit, '(a)') help_text("")
      end if
      stop
   end if
   call check_outputs(request, stat)
   if (stat%code == status_ok) call make_output_directory(stat)
   if (stat%code /= status_ok) then
      write (error_unit, '(a)') "taylorode: "//stat%message
      stop 2, quiet=.true.
   end if

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
   call write_outputs(request, report, write_stat)

   do k = 1, report%line_count
      write (output_unit, '(a)') report%lines(k)%text
   end do
   if (stat%code /= status_ok) write (error_unit, '(a)') "taylorode: "//stat%message
   if (write_stat%code /= status_ok) write (error_unit, '(a)') "taylorode: "//write_stat%message
   if (stat%code /= status_ok .or. write_stat%code /= status_ok .or. .not. report%passed) stop 1, quiet=.true.

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

   !> Create the --out directory when it does not exist.
   subroutine make_output_directory(stat)
      type(status_type), intent(inout) :: stat
      integer :: exit_status
      if (.not. allocated(request%out_dir)) return
      call execute_command_line('mkdir -p "'//request%out_dir//'"', exitstat=exit_status)
      if (exit_status /= 0) then
         stat%code = status_invalid_argument
         stat%message = "cannot create the directory "//request%out_dir
      end if
   end subroutine make_output_directory

end program taylorode_app
