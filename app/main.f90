!> The taylorode command-line app: reproduces the paper's Table 1, runs Van der Pol
!> with any scheme and setting, sweeps tolerances, checks stability and stiff and
!> extreme cases, and benchmarks.
!>
!> The program reads the command line (app_cli), checks every output target before any
!> work starts (app_output) and runs one command: table and vdp (app_paper), sweep,
!> stability, extreme and accuracy (app_reports), bench and ensemble (app_bench). Nothing typed
!> on the command line reaches a shell; every file is written to a temporary file and
!> renamed into place when complete; a file-size limit is a failed write like a full
!> disk (SIGXFSZ ignored, app/signals.c). The app's modules are named app_* and are
!> not installed with the library (make install removes their .mod files).
program taylorode_app
   use, intrinsic :: iso_fortran_env, only: error_unit
   use taylorode, only: status_type, status_ok
   use app_cli, only: request_type, version, read_arguments, parse_command_line, check_request
   use app_help, only: help_text
   use app_output, only: table_type, checks_failed, ignore_file_size_signal, start_output, say, finish_output, &
      usage_error, check_outputs, write_tables
   use app_paper, only: run_vdp, run_table
   use app_reports, only: run_sweep, run_stability, run_extreme, run_accuracy
   use app_bench, only: run_bench, run_ensemble
   implicit none

   type(request_type) :: request
   type(table_type), allocatable :: tables(:)
   type(status_type) :: stat, write_stat
   character(len=:), allocatable :: args(:)
   integer, allocatable :: lengths(:)
   integer :: io

   call ignore_file_size_signal()
   call start_output()

   call read_arguments(args, lengths)
   call parse_command_line(args, request, stat, lengths)
   if (stat%code /= status_ok) call usage_error(stat%message)
   if (request%version) then
      call say("taylorode "//version)
      call finish_output()
      stop
   end if
   if (request%help) then
      call say(help_text(request%command))
      call finish_output()
      stop
   end if
   call check_request(request, stat)
   if (stat%code /= status_ok) call usage_error(stat%message)
   call check_outputs(request, stat)
   if (stat%code /= status_ok) call usage_error(stat%message)

   allocate (tables(0))
   select case (request%command)
   case ("vdp")
      call run_vdp(request, stat)
   case ("table")
      call run_table(request, tables, stat)
   case ("sweep")
      call run_sweep(request, tables, stat)
   case ("stability")
      call run_stability(request, tables, stat)
   case ("extreme")
      call run_extreme(request, tables, stat)
   case ("bench")
      call run_bench(request, stat)
   case ("ensemble")
      call run_ensemble(request, stat)
   case ("accuracy")
      call run_accuracy(request, tables, stat)
   end select
   call write_tables(request, tables, write_stat)
   ! the run's and the tables' failures first: finish_output ends the program when standard
   ! output could not be written (a table that failed too went unreported)
   if (stat%code /= status_ok) write (error_unit, '(a)', iostat=io) "taylorode: "//stat%message
   if (write_stat%code /= status_ok) write (error_unit, '(a)', iostat=io) "taylorode: "//write_stat%message
   call finish_output()
   if (stat%code /= status_ok .or. write_stat%code /= status_ok .or. checks_failed) stop 1, quiet=.true.

end program taylorode_app
