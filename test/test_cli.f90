!> The app's command line (every error path) and the output of each command on
!> small problem sizes.
module test_cli
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode, only: dp, i8, status_type, status_ok, controller_pid, norm_rms, vdp_split_stiff
   use taylorode_cli, only: cli_request_type, parse_command_line, help_text, command_names
   use taylorode_report, only: report_type
   use taylorode_strings, only: format_count, format_real, format_fixed
   use taylorode_experiments, only: run_vdp, run_table, run_sweep
   use taylorode_checks, only: run_stability, run_extreme
   use taylorode_bench, only: run_bench
   use taylorode_outputs, only: check_outputs, write_outputs, table_destination
   implicit none
   private

   public :: collect_cli

contains

   !> Collect all exported unit tests
   subroutine collect_cli(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("parse-defaults", test_parse_defaults), &
         new_unittest("parse-vdp-options", test_parse_vdp), &
         new_unittest("parse-errors", test_parse_errors), &
         new_unittest("help-texts", test_help), &
         new_unittest("number-formats", test_formats), &
         new_unittest("vdp-report", test_vdp_report), &
         new_unittest("table-report", test_table_report), &
         new_unittest("sweep-report", test_sweep_report), &
         new_unittest("stability-report", test_stability_report), &
         new_unittest("extreme-report", test_extreme_report), &
         new_unittest("bench-report", test_bench_report), &
         new_unittest("output-files", test_output_files) &
         ]
   end subroutine collect_cli

   subroutine test_parse_defaults(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      character(len=1) :: none(0)
      call parse_command_line(none, request, stat)
      call check(error, stat%code, status_ok)
      if (allocated(error)) return
      call check(error, request%command, "table", "no command runs the table")
      if (allocated(error)) return
      call check(error, .not. allocated(request%out_dir) .and. .not. request%force, "no output by default")
      if (allocated(error)) return
      call check(error, request%budget, 2000000_i8, "default budget")
   end subroutine test_parse_defaults

   subroutine test_parse_vdp(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      call parse_command_line([character(len=12) :: "vdp", "--scheme", "si-t-2", "--ic", "2", "--mu", "500", &
         "--tend", "10", "--split", "stiff", "--rtol", "1e-6", "--atol", "1e-8", "--norm", "rms", &
         "--controller", "pid", "--h0", "1e-3", "--hmax", "0.5", "--history", "h.csv", "--dense", "11"], &
         request, stat)
      call check(error, stat%code, status_ok, "valid vdp options rejected")
      if (allocated(error)) return
      call check(error, request%scheme == "si-t-2" .and. request%ic == 2 .and. request%mu == 500.0_dp .and. &
         request%t_end == 10.0_dp .and. request%splitting == vdp_split_stiff, "vdp problem options")
      if (allocated(error)) return
      call check(error, request%options%rtol == 1.0e-6_dp .and. request%options%atol == 1.0e-8_dp .and. &
         request%options%norm == norm_rms .and. request%options%controller == controller_pid .and. &
         request%options%h0 == 1.0e-3_dp .and. request%options%h_max == 0.5_dp, "vdp integrator options")
      if (allocated(error)) return
      call check(error, request%history_file == "h.csv" .and. request%dense_points == 11, "vdp outputs")
   end subroutine test_parse_vdp

   !> Every mistake gives a message that names what is wrong.
   subroutine test_parse_errors(error)
      type(error_type), allocatable, intent(out) :: error
      call expect([character(len=10) :: "plot"], "unknown command")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--frobnicate", "1"], "unknown option")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--mu"], "needs a value")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--bogus"], "unknown option")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--mu", "abc"], "needs a number")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--mu", "-5"], "must be positive")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--mu", "nan"], "needs a number")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--ic", "3"], "--ic must be 1")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--scheme", "rk4"], "unknown scheme")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--split", "both"], "--split must be")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--norm", "l2"], "--norm must be")
      if (allocated(error)) return
      call expect([character(len=12) :: "vdp", "--controller", "p"], "--controller must be")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--rtol", "-1"], "--rtol must be >= 0")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--atol", "-1"], "--atol must be >= 0")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--atol", "0"], "cannot both be 0")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--h0", "0"], "must be positive")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--dense", "1"], "at least 2 points")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--dense", "2.5"], "whole number")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "extra"], "unexpected argument")
      if (allocated(error)) return
      call expect([character(len=10) :: "table", "--scheme", "i-t-2"], "does not apply to table")
      if (allocated(error)) return
      call expect([character(len=10) :: "table", "--budget", "0"], "--budget must be")
      if (allocated(error)) return
      call expect([character(len=10) :: "table", "--repeats", "0"], "--repeats must be")
      if (allocated(error)) return
      call expect([character(len=10) :: "sweep", "--problem", "lorenz"], "unknown problem")
      if (allocated(error)) return
      call expect([character(len=10) :: "sweep", "--schemes", "i-t-2,rk4"], "unknown scheme")
      if (allocated(error)) return
      call expect([character(len=10) :: "sweep", "--tols", "1e-2"], "HIGH:LOW")
      if (allocated(error)) return
      call expect([character(len=10) :: "sweep", "--tols", "1e-8:1e-2"], "HIGH >= LOW")
      if (allocated(error)) return
      call expect([character(len=10) :: "sweep", "--tols", "1e-2:x"], "needs a number")
      if (allocated(error)) return
      call expect([character(len=10) :: "stability", "--grid", "2"], "at least 3")
      if (allocated(error)) return
      call expect([character(len=12) :: "bench", "--max-points", "10"], "at least 1000")
      if (allocated(error)) return
      call expect([character(len=10) :: "vdp", "--full"], "does not apply to vdp")
   contains
      subroutine expect(args, words)
         character(len=*), intent(in) :: args(:), words
         type(cli_request_type) :: request
         type(status_type) :: stat
         call parse_command_line(args, request, stat)
         call check(error, stat%code /= status_ok, "accepted: "//trim(args(size(args))))
         if (allocated(error)) return
         call check(error, index(stat%message, words) > 0, 'message "'//stat%message//'" lacks "'//words//'"')
      end subroutine expect
   end subroutine test_parse_errors

   subroutine test_help(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      integer :: k
      do k = 1, size(command_names)
         call check(error, index(help_text(trim(command_names(k))), "taylorode "//trim(command_names(k))) == 1, &
            "help of "//trim(command_names(k)))
         if (allocated(error)) return
      end do
      call check(error, index(help_text(""), "usage: taylorode") > 0, "overview help")
      if (allocated(error)) return
      call parse_command_line([character(len=6) :: "sweep", "--help"], request, stat)
      call check(error, stat%code == status_ok .and. request%help .and. request%command == "sweep", "--help")
   end subroutine test_help

   subroutine test_formats(error)
      type(error_type), allocatable, intent(out) :: error
      call check(error, format_count(125748_i8), "125,748")
      if (allocated(error)) return
      call check(error, format_count(999_i8), "999")
      if (allocated(error)) return
      call check(error, format_count(-2000000_i8), "-2,000,000")
      if (allocated(error)) return
      call check(error, format_real(5.2123e-5_dp, 3), "5.21E-05")
      if (allocated(error)) return
      call check(error, format_fixed(0.0881_dp, 3), "0.088")
      if (allocated(error)) return
      call check(error, format_real(1.0e4_dp, 1), "1E+04")
      if (allocated(error)) return
      call check(error, format_fixed(626.6_dp, 0), "627")
   end subroutine test_formats

   subroutine test_vdp_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      call parse_command_line([character(len=10) :: "vdp", "--mu", "10", "--tend", "5", "--dense", "6", &
         "--history", "h.csv"], request, stat)
      call run_vdp(request, report, stat)
      call check(error, stat%code, status_ok, "vdp run")
      if (allocated(error)) return
      call check(error, has_line(report, "accepted steps") .and. has_line(report, "error at t = ") .and. &
         has_line(report, "6-point grid") .and. has_line(report, "LU factorizations"), "vdp summary lines")
      if (allocated(error)) return
      call check(error, size(report%tables), 1, "one table: the history")
      if (allocated(error)) return
      call check(error, report%tables(1)%file_name, "h.csv")
      if (allocated(error)) return
      call check(error, report%tables(1)%header, "step,t,h,err,outcome,newton_iterations,y,z")
      if (allocated(error)) return
      call check(error, report%tables(1)%count > 10, "history rows")
      if (allocated(error)) return
      call check(error, count_commas(report%tables(1)%rows(1)%text), 7, "history columns")
   end subroutine test_vdp_report

   !> The table with a 3000-step budget: 20 rows, capped rows say how far they got.
   subroutine test_table_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      integer :: k
      call parse_command_line([character(len=10) :: "table", "--budget", "3000", "--repeats", "1"], request, stat)
      call run_table(request, report, stat)
      call check(error, stat%code, status_ok, "table run")
      if (allocated(error)) return
      call check(error, report%tables(1)%count, 20, "two ICs x ten rows")
      if (allocated(error)) return
      call check(error, has_line(report, "paper steps") .and. has_line(report, "stopped at t = ") .and. &
         has_line(report, "> 2,99"), "budget and paper columns")
      if (allocated(error)) return
      do k = 1, report%tables(1)%count
         call check(error, count_commas(report%tables(1)%rows(k)%text), 12, "CSV columns")
         if (allocated(error)) return
      end do
      call check(error, index(report%tables(1)%rows(1)%text, "1,si-t-1,paper,") == 1, "first row")
   end subroutine test_table_report

   subroutine test_sweep_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      call parse_command_line([character(len=14) :: "sweep", "--problem", "hires", "--schemes", "i-t-2,radau5", &
         "--tols", "1e-3:1e-4", "--repeats", "1"], request, stat)
      call check(error, stat%code, status_ok, "sweep options")
      if (allocated(error)) return
      call run_sweep(request, report, stat)
      call check(error, stat%code, status_ok, "sweep run")
      if (allocated(error)) return
      call check(error, report%tables(1)%count, 4, "two schemes x two tolerances")
      if (allocated(error)) return
      call check(error, index(report%tables(1)%rows(4)%text, "hires,radau5,1.0E-04,") == 1, &
         "row format: "//report%tables(1)%rows(4)%text)
      if (allocated(error)) return
      call check(error, has_line(report, "published reference"), "reference named")
   end subroutine test_sweep_report

   !> A 5 x 5 S1 grid: the check table has one row per scheme and passes; the
   !> region table one row per scheme and grid point; the known crossings appear.
   subroutine test_stability_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      call parse_command_line([character(len=10) :: "stability", "--grid", "5"], request, stat)
      call run_stability(request, report, stat)
      call check(error, stat%code == status_ok .and. report%passed, "stability run")
      if (allocated(error)) return
      call check(error, report%tables(1)%count, 9, "check rows")
      if (allocated(error)) return
      call check(error, report%tables(2)%count, 9*25, "S1 grid rows")
      if (allocated(error)) return
      ! si-t-1: the disc |1 + z| <= 1 meets the real axis in [-2, 0]
      call check(error, has_line(report, "si-t-1       real axis [-2.0000, 0.0000]"), "si-t-1 crossing")
      if (allocated(error)) return
      call check(error, has_line(report, "ex-t-2       empty"), "explicit S1 empty")
   end subroutine test_stability_report

   !> The quick extreme cases pass, one CSV row and one ok line per case.
   subroutine test_extreme_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      integer :: k, ok_lines
      call parse_command_line([character(len=8) :: "extreme", "--quick"], request, stat)
      call run_extreme(request, report, stat)
      call check(error, stat%code == status_ok .and. report%passed, "extreme --quick should pass")
      if (allocated(error)) return
      ok_lines = 0
      do k = 1, report%line_count
         if (index(report%lines(k)%text, "ok   ") == 1) ok_lines = ok_lines + 1
      end do
      call check(error, ok_lines, report%tables(1)%count, "one ok line per case")
      if (allocated(error)) return
      call check(error, report%tables(1)%count, 31, "cases")
      if (allocated(error)) return
      do k = 1, report%tables(1)%count
         call check(error, count_separators(report%tables(1)%rows(k)%text), 6, &
            "CSV columns: "//report%tables(1)%rows(k)%text)
         if (allocated(error)) return
      end do
      call check(error, has_line(report, "ok   i-t-2 vdp mu=1E+04"), "Van der Pol line")
   end subroutine test_extreme_report

   !> The benchmark on a small budget: one row per scheme and per Brusselator size,
   !> the reuse comparison and the LAPACK share.
   subroutine test_bench_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      integer :: k
      call parse_command_line([character(len=12) :: "bench", "--budget", "20000", "--max-points", "1000", &
         "--repeats", "1"], request, stat)
      call check(error, stat%code, status_ok, "bench options")
      if (allocated(error)) return
      call run_bench(request, report, stat)
      call check(error, stat%code, status_ok, "bench run")
      if (allocated(error)) return
      call check(error, report%tables(1)%count, 9 + 2, "nine schemes and two Brusselator sizes")
      if (allocated(error)) return
      do k = 1, report%tables(1)%count
         call check(error, count_commas(report%tables(1)%rows(k)%text), 11, "CSV columns")
         if (allocated(error)) return
      end do
      call check(error, has_line(report, "reuse off:") .and. has_line(report, "% of the run") .and. &
         has_line(report, "budget reached"), "bench sections")
   end subroutine test_bench_report

   !> Files are written only where asked for and never overwritten without --force.
   subroutine test_output_files(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: directory = "build/test-outputs"
      type(cli_request_type) :: request
      type(status_type) :: stat
      type(report_type) :: report
      integer :: table, unit

      call execute_command_line("rm -rf "//directory//" && mkdir -p "//directory)
      table = report%new_table("t.csv", "a,b")
      call report%tables(table)%add_row("1,2")

      ! no --out: nothing is written
      call parse_command_line([character(len=10) :: "stability"], request, stat)
      call write_outputs(request, report, stat)
      call check(error, stat%code == status_ok .and. report%line_count == 0, "wrote without --out")
      if (allocated(error)) return

      call parse_command_line([character(len=20) :: "stability", "--out", directory], request, stat)
      call check(error, table_destination(request, "t.csv"), directory//"/t.csv")
      if (allocated(error)) return
      call write_outputs(request, report, stat)
      call check(error, stat%code == status_ok .and. report%line_count == 1, "first write")
      if (allocated(error)) return
      call write_outputs(request, report, stat)
      call check(error, stat%code /= status_ok .and. index(stat%message, "use --force") > 0, &
         "an existing file must be kept without --force")
      if (allocated(error)) return
      call parse_command_line([character(len=20) :: "stability", "--out", directory, "--force"], request, stat)
      call write_outputs(request, report, stat)
      call check(error, stat%code, status_ok, "--force overwrites")
      if (allocated(error)) return

      ! a step history that exists is refused before the run
      open (newunit=unit, file=directory//"/h.csv", status="replace", action="write")
      close (unit)
      call parse_command_line([character(len=30) :: "vdp", "--history", directory//"/h.csv"], request, stat)
      call check_outputs(request, stat)
      call check(error, stat%code /= status_ok .and. index(stat%message, "exists") > 0, "history overwritten")
      if (allocated(error)) return
      call parse_command_line([character(len=30) :: "vdp", "--history", directory//"/h.csv", "--force"], &
         request, stat)
      call check_outputs(request, stat)
      call check(error, stat%code, status_ok, "history with --force")
      if (allocated(error)) return
      call check(error, table_destination(request, directory//"/h.csv"), directory//"/h.csv")
      call execute_command_line("rm -rf "//directory)
   end subroutine test_output_files

   !> Field separators: commas outside double quotes.
   integer function count_separators(text)
      character(len=*), intent(in) :: text
      integer :: k
      logical :: quoted
      count_separators = 0
      quoted = .false.
      do k = 1, len(text)
         if (text(k:k) == '"') quoted = .not. quoted
         if (.not. quoted .and. text(k:k) == ",") count_separators = count_separators + 1
      end do
   end function count_separators

   logical function has_line(report, text)
      type(report_type), intent(in) :: report
      character(len=*), intent(in) :: text
      integer :: k
      has_line = .false.
      do k = 1, report%line_count
         if (index(report%lines(k)%text, text) > 0) has_line = .true.
      end do
   end function has_line

   integer function count_commas(text)
      character(len=*), intent(in) :: text
      integer :: k
      count_commas = 0
      do k = 1, len(text)
         if (text(k:k) == ",") count_commas = count_commas + 1
      end do
   end function count_commas

end module test_cli
