!> The taylorode executable as its users run it: every command-line mistake (exit
!> status 2 and a message that names it), the help texts, and each command's
!> terminal report and CSV files on small problem sizes.
module test_app
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode_base_kinds, only: dp
   use test_support, only: scratch, line_type, run_type, run_app, read_lines, has_line, count_separators, &
      file_exists, fresh_scratch
   implicit none
   private

   public :: collect_app

contains

   !> Collect all exported unit tests
   subroutine collect_app(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("default-command", test_default_command), &
         new_unittest("vdp-options", test_vdp_options), &
         new_unittest("command-line-errors", test_command_line_errors), &
         new_unittest("help-texts", test_help), &
         new_unittest("vdp-report", test_vdp_report), &
         new_unittest("table-report", test_table_report), &
         new_unittest("sweep-report", test_sweep_report), &
         new_unittest("stability-report", test_stability_report), &
         new_unittest("extreme-report", test_extreme_report), &
         new_unittest("bench-report", test_bench_report), &
         new_unittest("accuracy-report", test_accuracy_report), &
         new_unittest("output-files", test_output_files) &
         ]
   end subroutine collect_app

   !> No command runs the paper's table and writes no file.
   subroutine test_default_command(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call fresh_scratch()
      call run_app("--budget 1000 --repeats 1", run)
      call check(error, run%exit_status, 0, "table with a small budget")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "Table 1 of the paper") .and. has_line(run%stdout, "step budget 1,000"), &
         "the default command is the table")
      if (allocated(error)) return
      call check(error, .not. file_exists(scratch//"/out/table1.csv") .and. .not. file_exists("table1.csv"), &
         "a file was written without --out")
   end subroutine test_default_command

   !> Every vdp option reaches the run (the summary repeats the settings).
   subroutine test_vdp_options(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call run_app("vdp --scheme si-t-2 --ic 2 --mu 500 --tend 10 --split stiff --rtol 1e-6 --atol 1e-8 "// &
         "--norm rms --controller pid --h0 1e-3 --hmax 0.5 --dense 11", run)
      call check(error, run%exit_status, 0, "valid vdp options rejected")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "Van der Pol, mu = 500, IC2, t in [0, 10], stiff splitting"), &
         "vdp problem options")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "scheme si-t-2, controller pid, rtol 1.00E-06, atol 1.00E-08, "// &
         "rms norm, h0 1.00E-03"), "vdp integrator options")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "11-point grid"), "vdp dense output points")
   end subroutine test_vdp_options

   !> Every mistake exits with status 2 and a message that names what is wrong.
   subroutine test_command_line_errors(error)
      type(error_type), allocatable, intent(out) :: error
      call expect("plot", "unknown command")
      if (allocated(error)) return
      call expect("vdp --frobnicate 1", "unknown option")
      if (allocated(error)) return
      call expect("vdp --mu", "needs a value")
      if (allocated(error)) return
      call expect("vdp --bogus", "unknown option")
      if (allocated(error)) return
      call expect("vdp --mu abc", "needs a number")
      if (allocated(error)) return
      call expect("vdp --mu -5", "must be positive")
      if (allocated(error)) return
      call expect("vdp --mu nan", "needs a number")
      if (allocated(error)) return
      call expect("vdp --ic 3", "--ic must be 1")
      if (allocated(error)) return
      call expect("vdp --scheme rk4", "unknown scheme")
      if (allocated(error)) return
      call expect("vdp --split both", "--split must be")
      if (allocated(error)) return
      call expect("vdp --norm l2", "--norm must be")
      if (allocated(error)) return
      call expect("vdp --controller p", "--controller must be")
      if (allocated(error)) return
      call expect("vdp --rtol -1", "--rtol must be >= 0")
      if (allocated(error)) return
      call expect("vdp --atol -1", "--atol must be >= 0")
      if (allocated(error)) return
      call expect("vdp --atol 0", "cannot both be zero")
      if (allocated(error)) return
      call expect("vdp --h0 0", "must be positive")
      if (allocated(error)) return
      call expect("vdp --dense 1", "at least 2 points")
      if (allocated(error)) return
      call expect("vdp --dense 2.5", "whole number")
      if (allocated(error)) return
      call expect("vdp extra", "unexpected argument")
      if (allocated(error)) return
      call expect("table --scheme i-t-2", "does not apply to table")
      if (allocated(error)) return
      call expect("table --budget 0", "--budget must be")
      if (allocated(error)) return
      call expect("table --repeats 0", "--repeats must be")
      if (allocated(error)) return
      call expect("sweep --problem lorenz", "unknown problem")
      if (allocated(error)) return
      call expect("sweep --schemes i-t-2,rk4", "unknown scheme")
      if (allocated(error)) return
      call expect("sweep --tols 1e-2", "HIGH:LOW")
      if (allocated(error)) return
      call expect("sweep --tols 1e-8:1e-2", "HIGH >= LOW")
      if (allocated(error)) return
      call expect("sweep --tols 1e-2:x", "needs a number")
      if (allocated(error)) return
      call expect("stability --grid 2", "at least 3")
      if (allocated(error)) return
      call expect("bench --problems vdp,lorenz", "unknown problem")
      if (allocated(error)) return
      call expect("bench --min-time 0", "--min-time must be positive")
      if (allocated(error)) return
      call expect("bench --refs /nonexistent", "not a directory")
      if (allocated(error)) return
      call expect("vdp --full", "does not apply to vdp")
      if (allocated(error)) return
      call expect("vdp --estimate defect", "i-t-2 has no estimate of its own step's error")
      if (allocated(error)) return
      call expect("bench --estimate defect --schemes si-t-2,radau5", "radau5 has no estimate")
      if (allocated(error)) return
      call expect("vdp --estimate halving", "embedded, doubling or defect")
   contains
      subroutine expect(arguments, words)
         character(len=*), intent(in) :: arguments, words
         type(run_type) :: run
         call run_app(arguments, run)
         call check(error, run%exit_status, 2, "exit status of: taylorode "//arguments)
         if (allocated(error)) return
         call check(error, has_line(run%stderr, words), 'taylorode '//arguments//': the message lacks "'//words//'"')
      end subroutine expect
   end subroutine test_command_line_errors

   !> Each command's help starts with its name; the overview shows the usage.
   subroutine test_help(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: commands(7) = [character(len=9) :: &
         "table", "vdp", "sweep", "stability", "extreme", "bench", "accuracy"]
      type(run_type) :: run
      integer :: k
      do k = 1, size(commands)
         call run_app(trim(commands(k))//" --help", run)
         call check(error, run%exit_status == 0 .and. size(run%stdout) > 1, "help of "//trim(commands(k)))
         if (allocated(error)) return
         call check(error, index(run%stdout(1)%text, "taylorode "//trim(commands(k))) == 1, &
            "help of "//trim(commands(k))//" starts with its name")
         if (allocated(error)) return
      end do
      call run_app("table --help", run)
      call check(error, has_line(run%stdout, "step budget per run (default 200,000)") .and. &
         has_line(run%stdout, "timing runs for the median (default 3,"), "the main job's budget and repeats")
      if (allocated(error)) return
      call run_app("--help", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "usage: taylorode"), "overview help")
   end subroutine test_help

   !> One vdp run with its step history file.
   subroutine test_vdp_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: history(:)
      call fresh_scratch()
      call run_app("vdp --mu 10 --tend 5 --dense 6 --history "//scratch//"/out/h.csv", run)
      call check(error, run%exit_status, 0, "vdp run")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "accepted steps") .and. has_line(run%stdout, "error at t = ") .and. &
         has_line(run%stdout, "6-point grid") .and. has_line(run%stdout, "LU factorizations"), "vdp summary lines")
      if (allocated(error)) return
      call read_lines(scratch//"/out/h.csv", history)
      call check(error, size(history) > 10, "history rows")
      if (allocated(error)) return
      call check(error, history(1)%text, "step,t,h,err,outcome,newton_iterations,u1,u2")
      if (allocated(error)) return
      call check(error, count_separators(history(2)%text), 7, "history columns")
   end subroutine test_vdp_report

   !> The table with a 3000-step budget: 20 rows, capped rows say how far they got.
   subroutine test_table_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: table(:)
      integer :: k
      call fresh_scratch()
      call run_app("table --budget 3000 --repeats 1 --out "//scratch//"/out", run)
      call check(error, run%exit_status, 0, "table run")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "paper steps") .and. has_line(run%stdout, "stopped at t = ") .and. &
         has_line(run%stdout, "> 2,99"), "budget and paper columns")
      if (allocated(error)) return
      call read_lines(scratch//"/out/table1.csv", table)
      call check(error, size(table), 21, "header and two ICs x ten rows")
      if (allocated(error)) return
      do k = 2, size(table)
         call check(error, count_separators(table(k)%text), 12, "CSV columns")
         if (allocated(error)) return
      end do
      call check(error, index(table(2)%text, "1,si-t-1,paper,") == 1, "first row")
   end subroutine test_table_report

   subroutine test_sweep_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: table(:)
      call fresh_scratch()
      call run_app("sweep --problem hires --schemes i-t-2,radau5 --tols 1e-3:1e-4 --repeats 1 --out "// &
         scratch//"/out", run)
      call check(error, run%exit_status, 0, "sweep run")
      if (allocated(error)) return
      call read_lines(scratch//"/out/sweep.csv", table)
      call check(error, size(table), 5, "header and two schemes x two tolerances")
      if (allocated(error)) return
      call check(error, index(table(5)%text, "hires,radau5,1.0E-04,") == 1, "row format: "//table(5)%text)
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "published reference"), "reference named")
   end subroutine test_sweep_report

   !> A 5 x 5 S1 grid: the check table has one row per scheme and passes; the
   !> region table one row per scheme and grid point; the known crossings appear.
   subroutine test_stability_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: table(:)
      call fresh_scratch()
      call run_app("stability --grid 5 --out "//scratch//"/out", run)
      call check(error, run%exit_status, 0, "stability run")
      if (allocated(error)) return
      call read_lines(scratch//"/out/stability_check.csv", table)
      call check(error, size(table), 1 + 9, "check rows")
      if (allocated(error)) return
      call read_lines(scratch//"/out/s1_regions.csv", table)
      call check(error, size(table), 1 + 9*25, "S1 grid rows")
      if (allocated(error)) return
      ! si-t-1: the disc |1 + z| <= 1 meets the real axis in [-2, 0]
      call check(error, has_line(run%stdout, "si-t-1       real axis [-2.0000, 0.0000]"), "si-t-1 crossing")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "ex-t-2       empty"), "explicit S1 empty")
   end subroutine test_stability_report

   !> The quick extreme cases: one line and one CSV row per case, the CSV verdict equal
   !> to the line's, the exit status saying whether all passed; the cases the library
   !> is known to get right (i-t-2 and the one-step and bad-input cases) pass.
   subroutine test_extreme_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: table(:)
      integer :: k, ok_lines, fail_lines, ok_rows
      call fresh_scratch()
      call run_app("extreme --quick --out "//scratch//"/out", run)
      ok_lines = 0
      fail_lines = 0
      do k = 1, size(run%stdout)
         if (index(run%stdout(k)%text, "ok   ") == 1) ok_lines = ok_lines + 1
         if (index(run%stdout(k)%text, "FAIL ") == 1) fail_lines = fail_lines + 1
         if (index(run%stdout(k)%text, " i-t-2 ") == 5 .or. index(run%stdout(k)%text, " one step:") > 0 .or. &
            index(run%stdout(k)%text, "bad input") > 0) then
            call check(error, index(run%stdout(k)%text, "ok   ") == 1, "expected to pass: "//run%stdout(k)%text)
            if (allocated(error)) return
         end if
      end do
      call check(error, run%exit_status, merge(0, 1, fail_lines == 0), "exit status against the verdicts")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "all extreme cases passed") .eqv. fail_lines == 0, "closing line")
      if (allocated(error)) return
      call read_lines(scratch//"/out/extreme.csv", table)
      call check(error, size(table) - 1, 31, "cases")
      if (allocated(error)) return
      call check(error, ok_lines + fail_lines, size(table) - 1, "one line per case")
      if (allocated(error)) return
      ok_rows = 0
      do k = 2, size(table)
         call check(error, count_separators(table(k)%text), 6, "CSV columns: "//table(k)%text)
         if (allocated(error)) return
         if (table(k)%text(len(table(k)%text):) == "1") ok_rows = ok_rows + 1
      end do
      call check(error, ok_rows, ok_lines, "CSV verdicts against the lines")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "ok   i-t-2 vdp mu=1E+04"), "Van der Pol line")
   end subroutine test_extreme_report

   !> The benchmark on two problems and two schemes: one line and one CSV row (the peer
   !> harness's 18 columns) per run, the paper's run once per scheme, every run ok and
   !> within 100 x tol of the reference (Robertson's error in the harness's measure).
   subroutine test_bench_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: table(:)
      integer :: k
      call fresh_scratch()
      call run_app("bench --problems vdp-paper,rober40 --schemes i-t-2,radau5 --tols 1e-4:1e-5 --min-time 0.001 "// &
         "--csv "//scratch//"/bench.csv", run)
      call check(error, run%exit_status, 0, "bench run")
      if (allocated(error)) return
      call read_lines(scratch//"/bench.csv", table)
      call check(error, size(table) - 1, 2 + 2*2, "rows: vdp-paper per scheme, rober40 per scheme and tolerance")
      if (allocated(error)) return
      call check(error, table(1)%text, "solver,problem,tol,rtol,atol,status,steps,rejected,nfe,nfe_expl,nfe_impl,"// &
         "njac,nlu,nniter,cpu_s,reps,err_end,err_grid", "the harness's header")
      if (allocated(error)) return
      do k = 2, size(table)
         call check(error, count_separators(table(k)%text), 17, "CSV columns")
         if (allocated(error)) return
         call check(error, index(table(k)%text, ",ok,") > 0, "run status: "//table(k)%text)
         if (allocated(error)) return
      end do
      call check(error, has_line(run%stdout, "vdp-paper i-t-2       paper  ok          125,748"), &
         "the paper's run keeps its 125,748 steps")
      if (allocated(error)) return
      do k = 4, size(table)
         call check(error, csv_field(table(k)%text, 17) < 100.0_dp*csv_field(table(k)%text, 4), &
            "error at t_end: "//table(k)%text)
         if (allocated(error)) return
      end do
   end subroutine test_bench_report

   !> The accuracy report on two problems, two schemes, two tolerances: a table per problem
   !> and the worst over both, one CSV row per run, every run ok and within the accuracy
   !> suite's bounds (100 tolerances at t_end, 1000 on the grid); a run out of budget says so.
   subroutine test_accuracy_report(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: table(:)
      integer :: k
      call fresh_scratch()
      call run_app("accuracy --problems robertson,hires --schemes i-t-2,radau5 --tols 1e-3:1e-4 --out "// &
         scratch//"/out", run)
      call check(error, run%exit_status, 0, "accuracy run")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "robertson: 9 output times") .and. &
         has_line(run%stdout, "hires: ") .and. has_line(run%stdout, "worst over the problems"), "report sections")
      if (allocated(error)) return
      call read_lines(scratch//"/out/accuracy.csv", table)
      call check(error, size(table), 1 + 2*2*2, "header and two problems x two schemes x two tolerances")
      if (allocated(error)) return
      call check(error, table(1)%text, "problem,scheme,tol,status,accepted,rejected,error_end,error_grid,t_worst")
      if (allocated(error)) return
      do k = 2, size(table)
         call check(error, index(table(k)%text, ",ok,") > 0, "run status: "//table(k)%text)
         if (allocated(error)) return
         call check(error, csv_field(table(k)%text, 7) >= 0.0_dp .and. csv_field(table(k)%text, 7) <= 100.0_dp .and. &
            csv_field(table(k)%text, 8) <= 1000.0_dp, "error in tolerances: "//table(k)%text)
         if (allocated(error)) return
      end do
      call check(error, index(table(2)%text, "robertson,i-t-2,1E-03,ok,") == 1, "row format: "//table(2)%text)
      if (allocated(error)) return
      call run_app("accuracy --problems hires --schemes ex-t-1 --tols 1e-3:1e-3 --budget 50", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "ex-t-1              budget") .and. &
         has_line(run%stdout, "ex-t-1              -/- 1f"), "a run out of budget: budget, counted as failed")
   end subroutine test_accuracy_report

   !> Field k (1-based) of a CSV row, read as a number.
   real(dp) function csv_field(row, k)
      character(len=*), intent(in) :: row
      integer, intent(in) :: k
      integer :: i, start, field, io_status
      start = 1
      field = 1
      csv_field = -1.0_dp
      do i = 1, len(row) + 1
         if (i > len(row)) then
            if (field == k) read (row(start:), *, iostat=io_status) csv_field
            return
         end if
         if (row(i:i) == ",") then
            if (field == k) then
               read (row(start:i - 1), *, iostat=io_status) csv_field
               return
            end if
            field = field + 1
            start = i + 1
         end if
      end do
   end function csv_field

   !> Files are written only where asked for and never overwritten without --force.
   subroutine test_output_files(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      integer :: unit
      call fresh_scratch()
      call run_app("stability --grid 3 --out "//scratch//"/out", run)
      call check(error, run%exit_status == 0 .and. file_exists(scratch//"/out/s1_regions.csv"), "first write")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "wrote "//scratch//"/out/s1_regions.csv"), "written files are named")
      if (allocated(error)) return
      call run_app("stability --grid 3 --out "//scratch//"/out", run)
      call check(error, run%exit_status /= 0 .and. has_line(run%stderr, "use --force"), &
         "an existing file must be kept without --force")
      if (allocated(error)) return
      call run_app("stability --grid 3 --out "//scratch//"/out --force", run)
      call check(error, run%exit_status, 0, "--force overwrites")
      if (allocated(error)) return

      ! a step history that exists is refused before the run
      open (newunit=unit, file=scratch//"/out/h.csv", status="replace", action="write")
      close (unit)
      call run_app("vdp --mu 10 --tend 1 --history "//scratch//"/out/h.csv", run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "exists"), "history overwritten")
      if (allocated(error)) return
      call run_app("vdp --mu 10 --tend 1 --history "//scratch//"/out/h.csv --force", run)
      call check(error, run%exit_status, 0, "history with --force")
   end subroutine test_output_files

end module test_app
