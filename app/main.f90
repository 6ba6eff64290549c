!> The taylorode command-line app: reproduces the paper's Table 1, runs Van der Pol
!> with any scheme and setting, sweeps tolerances, checks stability and stiff and
!> extreme cases, and benchmarks.
!>
!> One program unit on purpose: fpm installs the .mod file of every module it
!> builds, so an app made of modules would ship them beside the library's. Nothing
!> typed on the command line reaches a shell; every output target is checked before
!> any work starts and every file is written to a temporary file and renamed into
!> place when complete.
program taylorode_app
   use, intrinsic :: iso_fortran_env, only: error_unit
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan, ieee_value, ieee_quiet_nan
   use taylorode, only: dp, i8, status_type, status_ok, status_invalid_argument, status_nonfinite, &
      status_output_error, status_max_steps, status_unknown_scheme, status_name, scheme_type, new_scheme, scheme_names, &
      scheme_count, integrator_options_type, paper_options, norm_max, norm_rms, controller_i, controller_pi, &
      estimate_auto, estimate_embedded, estimate_doubling, estimate_defect, &
      controller_pid, controller_name, integrate, integration_stats_type, step_history_type
   use taylorode_testset, only: test_problem_type, test_problem_names, new_test_problem, van_der_pol_type, &
      new_van_der_pol, vdp_split_paper, vdp_split_stiff, vdp_ic_unprepared, vdp_ic_prepared, &
      van_der_pol_initial_state, robertson_type, new_robertson, hires_type, new_hires, hires_split_reaction_stiff, &
      new_orego, orego_split_bilinear_stiff, new_e5, brusselator_type, new_brusselator
   use taylorode_analysis, only: timed_run, timed_run_type, reference_run, tolerance_scale, &
      work_precision_config_type, work_precision_point_type, work_precision, step_stability, s1_supremum, &
      s1_axis_crossings, ensemble_timing_type, time_ensemble
   use taylorode_base_status, only: set_status
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, format_number, &
      pad, choose
   use taylorode_base_files, only: text_file_type, make_directory, is_directory, is_writable_directory, &
      parent_directory
   use taylorode_integrate_options, only: validate_options
   implicit none

   !> Version of the app and the library
   character(len=*), parameter :: version = "0.2.0"
   !> Subcommands
   character(len=*), parameter :: command_names(*) = [character(len=9) :: &
      "table", "vdp", "sweep", "stability", "extreme", "bench", "ensemble"]
   !> Options that take a value
   character(len=*), parameter :: valued_options(*) = [character(len=12) :: "--out", "--scheme", "--ic", &
      "--mu", "--tend", "--split", "--rtol", "--atol", "--norm", "--controller", "--h0", "--hmax", &
      "--history", "--dense", "--budget", "--repeats", "--problem", "--schemes", "--tols", "--grid", &
      "--estimate", "--settings", "--problems", "--min-time", "--refs", "--csv", "--members", "--threads"]
   !> Step budget per run of table, sweep and bench unless --budget (or --full for table)
   integer(i8), parameter :: default_budget = 2000000_i8
   !> Step budget of a vdp run (and its reference run) unless --budget
   integer(i8), parameter :: default_vdp_budget = 10000000_i8
   !> Upper bounds of the counts a user may ask for: each keeps a run finite
   integer(i8), parameter :: max_budget = 1000000000_i8
   !> ensemble: final time of every member (mu = 1 oscillates three times, mu = 1000 stays on
   !> its first slow branch: members differ in cost)
   real(dp), parameter :: ensemble_t_end = 20.0_dp
   integer, parameter :: max_dense_points = 1000000, max_repeats = 100, max_grid = 2001, &
      max_decades = 16, max_members = 100000, max_threads = 1024
   !> bench: longest accumulated CPU time per run (--min-time)
   real(dp), parameter :: max_min_time = 3600.0_dp
   !> Problems of the bench command: the peer harness's, and the paper's Van der Pol run
   character(len=*), parameter :: bench_problem_names(*) = [character(len=10) :: "vdp-paper", "vdp1e3_wp", &
      "vdp1e3_up", "rober40", "rober1e11", "hires", "orego", "e5", "bruss32", "bruss512", "bs1000", "bs10000", &
      "bs100000"]
   !> Global error, in the integrator's own weights, that the extreme cases accept: the
   !> number of accepted steps N, at least 100. Error per step control keeps each local
   !> error within the weights, and N of them add up to at most about N where the
   !> problem does not amplify errors (stiff decay usually damps them far below that).
   real(dp), parameter :: accuracy_bound_least = 100.0_dp

   !> What the user asked for
   type :: request_type
      !> Subcommand ("table" when none is given)
      character(len=:), allocatable :: command
      !> --help, help or --version was given
      logical :: help = .false., version = .false.
      !> Directory for CSV files (--out); unallocated: write none
      character(len=:), allocatable :: out_dir
      !> Overwrite existing output files (--force)
      logical :: force = .false.
      !> vdp: scheme, initial condition, mu, final time, splitting
      character(len=:), allocatable :: scheme
      integer :: ic = 1
      real(dp) :: mu = 1000.0_dp
      real(dp) :: t_end = -1.0_dp
      integer :: splitting = vdp_split_paper
      !> Integrator settings (vdp defaults: the paper's)
      type(integrator_options_type) :: options
      !> vdp: step history file (--history); unallocated: none
      character(len=:), allocatable :: history_file
      !> vdp: points of the error grid (--dense)
      integer :: dense_points = 301
      !> table: run the capped schemes to the end (--full)
      logical :: full = .false.
      !> Step budget per run (--budget); 0 until given
      integer(i8) :: budget = 0
      !> Timing repetitions for the median (--repeats)
      integer :: repeats = 5
      !> sweep: problem, schemes and tolerance range (decades from tol_high down to tol_low)
      character(len=:), allocatable :: problem
      character(len=16), allocatable :: schemes(:)
      real(dp) :: tol_high = 1.0e-2_dp, tol_low = 1.0e-8_dp
      !> stability: grid points per axis of the S1 region (--grid)
      integer :: grid = 161
      !> extreme: smaller cases (--quick)
      logical :: quick = .false.
      !> bench: problems, tolerances, CPU seconds accumulated per run, the harness's
      !> reference directory and the CSV file in its columns
      character(len=16), allocatable :: problems(:)
      real(dp), allocatable :: tols(:)
      real(dp) :: min_time = 0.2_dp
      character(len=:), allocatable :: refs_dir, csv_file
      !> ensemble: members and threads (0: as many as OpenMP gives)
      integer :: members = 64, threads = 0
   end type request_type

   !> A problem of the bench command as the peer harness runs it
   type :: bench_problem_type
      !> The harness's name
      character(len=:), allocatable :: name
      !> The problem, with the harness's split
      class(test_problem_type), allocatable :: problem
      !> Initial state, final time and output times (t_end alone, or a grid)
      real(dp), allocatable :: u0(:), t_out(:)
      real(dp) :: t_end = 0.0_dp
      !> Reference solution at the output times
      real(dp), allocatable :: reference(:, :)
      !> Absolute tolerance fixed by the harness (0: atol = tol)
      real(dp) :: atol = 0.0_dp
      !> Components measured, relative or absolute, and output times up to grid_until
      !> (0: all) in the grid error
      integer :: first_component = 1, last_component = 0
      logical :: relative = .false.
      real(dp) :: grid_until = 0.0_dp
      !> The paper's settings instead of rtol = atol = tol (vdp-paper)
      logical :: paper = .false.
   end type bench_problem_type

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

   type(request_type) :: request
   type(table_type), allocatable :: tables(:)
   type(status_type) :: stat, write_stat
   character(len=:), allocatable :: args(:)
   !> A check of the command failed (stability, extreme)
   logical :: checks_failed = .false.
   !> Standard output, written through write(2) so that every failure is seen
   type(text_file_type) :: stdout
   integer :: io

   call stdout%attach(1, "standard output")

   call read_arguments(args)
   call parse_command_line(args, request, stat)
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
   end select
   call write_tables(request, tables, write_stat)
   call finish_output()
   if (stat%code /= status_ok) write (error_unit, '(a)', iostat=io) "taylorode: "//stat%message
   if (write_stat%code /= status_ok) write (error_unit, '(a)', iostat=io) "taylorode: "//write_stat%message
   if (stat%code /= status_ok .or. write_stat%code /= status_ok .or. checks_failed) stop 1, quiet=.true.

contains

   ! ---------------------------------------------------------------- terminal

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

   ! ---------------------------------------------------------------- command line

   !> Parse the arguments (without the program name) into a request; stat says what is
   !> wrong in words a user understands.
   subroutine parse_command_line(args, request, stat)
      character(len=*), intent(in) :: args(:)
      type(request_type), intent(out) :: request
      type(status_type), intent(out) :: stat
      integer :: i
      character(len=:), allocatable :: arg, value

      request%command = "table"
      request%options = paper_options()
      ! vdp --settings library: the library's defaults (with the paper's tolerances and
      ! max norm), which the other options then change
      do i = 1, size(args) - 1
         if (args(i) == "--settings" .and. args(i + 1) == "library") then
            request%options = integrator_options_type(rtol=0.0_dp, atol=1.0e-5_dp, norm=norm_max)
         end if
      end do
      request%scheme = "i-t-2"
      request%problem = "vdp"
      request%schemes = [character(len=16) :: "si-t-1", "si-t-2", "i-t-1", "i-t-2", "radau5"]
      i = 1
      if (size(args) >= 1) then
         arg = trim(args(1))
         if (arg == "help") then
            request%help = .true.
            request%command = ""
            if (size(args) >= 2) request%command = trim(args(2))
            if (len(request%command) > 0 .and. .not. any(command_names == request%command)) then
               call set_status(stat, status_invalid_argument, 'unknown command "'//request%command// &
                  '"; commands: '//join(command_names))
            end if
            return
         end if
         if (arg(1:min(1, len(arg))) /= "-") then
            if (.not. any(command_names == arg)) then
               call set_status(stat, status_invalid_argument, 'unknown command "'//arg//'"; commands: '// &
                  join(command_names))
               return
            end if
            request%command = arg
            i = 2
         end if
      end if
      if (request%command == "sweep") request%schemes = [character(len=16) :: &
         "si-t-1", "si-t-2", "i-t-1", "i-t-2", "imex-rk21", "radau5"]
      if (request%command == "bench") then
         request%options%error_estimate = estimate_auto
         request%schemes = [character(len=16) :: "si-t-2", "i-t-2", "radau5"]
         request%problems = [character(len=16) :: "vdp-paper", "vdp1e3_wp", "vdp1e3_up", "rober40", "rober1e11", &
            "hires", "orego", "e5", "bruss32", "bruss512"]
         request%tol_high = 1.0e-3_dp
      end if

      do while (i <= size(args))
         arg = trim(args(i))
         i = i + 1
         select case (arg)
         case ("-h", "--help")
            request%help = .true.
            if (i == 2) request%command = ""
            cycle
         case ("--version")
            request%version = .true.
            cycle
         case ("--force")
            request%force = .true.
            cycle
         case ("--full")
            if (.not. allowed(request, arg, ["table"], stat)) return
            request%full = .true.
            cycle
         case ("--no-reuse")
            if (.not. allowed(request, arg, ["vdp"], stat)) return
            request%options%reuse_newton_matrix = .false.
            cycle
         case ("--quick")
            if (.not. allowed(request, arg, ["extreme"], stat)) return
            request%quick = .true.
            cycle
         end select
         if (arg(1:min(2, len(arg))) /= "--") then
            call set_status(stat, status_invalid_argument, 'unexpected argument "'//arg//'" (options start with --)')
            return
         end if
         if (.not. any(valued_options == arg)) then
            call set_status(stat, status_invalid_argument, 'unknown option "'//arg//'" for '//request%command// &
               " (see --help)")
            return
         end if
         if (i > size(args)) then
            call set_status(stat, status_invalid_argument, "option "//arg//" needs a value")
            return
         end if
         value = trim(args(i))
         i = i + 1
         if (.not. parse_option(request, arg, value, stat)) return
      end do
      if (request%full .and. request%budget /= 0) then
         call set_status(stat, status_invalid_argument, "--full runs without a budget: drop --budget or --full")
         return
      end if
      if (request%budget == 0) request%budget = merge(default_vdp_budget, default_budget, request%command == "vdp")
      request%tols = [(request%tol_high/10.0_dp**i, i = 0, nint(log10(request%tol_high/request%tol_low)))]
      stat%code = status_ok
   end subroutine parse_command_line

   !> Apply one option with a value; false (and stat) on a mistake.
   logical function parse_option(request, option, value, stat) result(ok)
      type(request_type), intent(inout) :: request
      character(len=*), intent(in) :: option, value
      type(status_type), intent(inout) :: stat
      integer(i8) :: count
      ok = .false.
      select case (option)
      case ("--out")
         if (len(value) == 0) then
            call set_status(stat, status_invalid_argument, "--out needs a directory name"); return
         end if
         request%out_dir = value
      case ("--scheme")
         if (.not. allowed(request, option, ["vdp     ", "ensemble"], stat)) return
         if (.not. known_scheme(value, stat)) return
         request%scheme = value
      case ("--ic")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         select case (value)
         case ("1"); request%ic = 1
         case ("2"); request%ic = 2
         case default
            call set_status(stat, status_invalid_argument, "--ic must be 1 (well prepared) or 2 (unprepared), got "// &
               value); return
         end select
      case ("--mu")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_positive(option, value, request%mu, stat)) return
      case ("--tend")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_positive(option, value, request%t_end, stat)) return
      case ("--split")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         select case (value)
         case ("paper"); request%splitting = vdp_split_paper
         case ("stiff"); request%splitting = vdp_split_stiff
         case default
            call set_status(stat, status_invalid_argument, "--split must be paper or stiff, got "//value); return
         end select
      case ("--rtol")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_real(option, value, request%options%rtol, stat)) return
         if (request%options%rtol < 0.0_dp) then
            call set_status(stat, status_invalid_argument, "--rtol must be >= 0, got "//value); return
         end if
      case ("--atol")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_real(option, value, request%options%atol, stat)) return
         if (request%options%atol < 0.0_dp) then
            call set_status(stat, status_invalid_argument, "--atol must be >= 0, got "//value); return
         end if
      case ("--norm")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         select case (value)
         case ("max"); request%options%norm = norm_max
         case ("rms"); request%options%norm = norm_rms
         case default
            call set_status(stat, status_invalid_argument, "--norm must be max or rms, got "//value); return
         end select
      case ("--controller")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         select case (value)
         case ("i"); request%options%controller = controller_i
         case ("pi"); request%options%controller = controller_pi
         case ("pid"); request%options%controller = controller_pid
         case default
            call set_status(stat, status_invalid_argument, "--controller must be i, pi or pid, got "//value); return
         end select
      case ("--estimate")
         if (.not. allowed(request, option, ["vdp  ", "bench"], stat)) return
         select case (value)
         case ("embedded"); request%options%error_estimate = estimate_embedded
         case ("doubling"); request%options%error_estimate = estimate_doubling
         case ("defect"); request%options%error_estimate = estimate_defect
         case default
            call set_status(stat, status_invalid_argument, "--estimate must be embedded, doubling or defect, got "//value)
            return
         end select
      case ("--settings")
         ! applied before the other options (parse_command_line): only checked here
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (value /= "paper" .and. value /= "library") then
            call set_status(stat, status_invalid_argument, "--settings must be paper or library, got "//value)
            return
         end if
      case ("--h0")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_positive(option, value, request%options%h0, stat)) return
      case ("--hmax")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_positive(option, value, request%options%h_max, stat)) return
      case ("--history")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (len(value) == 0) then
            call set_status(stat, status_invalid_argument, "--history needs a file name"); return
         end if
         request%history_file = value
      case ("--dense")
         if (.not. allowed(request, option, ["vdp"], stat)) return
         if (.not. read_count(option, value, 2_i8, int(max_dense_points, i8), "points", count, stat)) return
         request%dense_points = int(count)
      case ("--budget")
         if (.not. allowed(request, option, ["table", "sweep", "bench", "vdp  "], stat)) return
         if (.not. read_count(option, value, 1_i8, max_budget, "steps", request%budget, stat)) return
      case ("--repeats")
         if (.not. allowed(request, option, ["table   ", "sweep   ", "ensemble"], stat)) return
         if (.not. read_count(option, value, 1_i8, int(max_repeats, i8), "runs", count, stat)) return
         request%repeats = int(count)
      case ("--problem")
         if (.not. allowed(request, option, ["sweep"], stat)) return
         if (.not. any(test_problem_names == value)) then
            call set_status(stat, status_invalid_argument, 'unknown problem "'//value//'"; problems: '// &
               join(test_problem_names)); return
         end if
         request%problem = value
      case ("--schemes")
         if (.not. allowed(request, option, ["sweep", "bench"], stat)) return
         if (.not. split_names(value, scheme_names, "scheme", request%schemes, stat)) return
      case ("--tols")
         if (.not. allowed(request, option, ["sweep", "bench"], stat)) return
         if (.not. tolerance_range(value, request%tol_high, request%tol_low, stat)) return
      case ("--grid")
         if (.not. allowed(request, option, ["stability"], stat)) return
         if (.not. read_count(option, value, 3_i8, int(max_grid, i8), "points", count, stat)) return
         request%grid = int(count)
      case ("--problems")
         if (.not. allowed(request, option, ["bench"], stat)) return
         if (.not. split_names(value, bench_problem_names, "problem", request%problems, stat)) return
      case ("--min-time")
         if (.not. allowed(request, option, ["bench"], stat)) return
         if (.not. read_positive(option, value, request%min_time, stat)) return
         if (request%min_time > max_min_time) then
            call set_status(stat, status_invalid_argument, "--min-time is at most "// &
               format_fixed(max_min_time, 0)//" seconds, got "//value); return
         end if
      case ("--refs")
         if (.not. allowed(request, option, ["bench"], stat)) return
         if (.not. is_directory(value)) then
            call set_status(stat, status_invalid_argument, "--refs: "//value//" is not a directory"); return
         end if
         request%refs_dir = value
      case ("--csv")
         if (.not. allowed(request, option, ["bench"], stat)) return
         if (len(value) == 0) then
            call set_status(stat, status_invalid_argument, "--csv needs a file name"); return
         end if
         request%csv_file = value
      case ("--members")
         if (.not. allowed(request, option, ["ensemble"], stat)) return
         if (.not. read_count(option, value, 1_i8, int(max_members, i8), "members", count, stat)) return
         request%members = int(count)
      case ("--threads")
         if (.not. allowed(request, option, ["ensemble"], stat)) return
         if (.not. read_count(option, value, 1_i8, int(max_threads, i8), "threads", count, stat)) return
         request%threads = int(count)
      end select
      ok = .true.
   end function parse_option

   !> The option belongs to one of these commands.
   logical function allowed(request, option, commands, stat)
      type(request_type), intent(in) :: request
      character(len=*), intent(in) :: option, commands(:)
      type(status_type), intent(inout) :: stat
      allowed = any(commands == request%command)
      if (.not. allowed) call set_status(stat, status_invalid_argument, "option "//option//" does not apply to "// &
         request%command//" (see --help)")
   end function allowed

   logical function known_scheme(name, stat)
      character(len=*), intent(in) :: name
      type(status_type), intent(inout) :: stat
      known_scheme = any(scheme_names == name)
      if (.not. known_scheme) call set_status(stat, status_invalid_argument, 'unknown scheme "'//name// &
         '"; schemes: '//join(scheme_names))
   end function known_scheme

   !> Whether text is a decimal number, strictly: [+-]digits[.digits][e[+-]digits] (or
   !> [+-].digits...), nothing else (Fortran's own reading would take "1-2" for 1e-2).
   logical function is_number(text)
      character(len=*), intent(in) :: text
      integer :: i, digits_before, digits_after, exponent_digits
      is_number = .false.
      i = 1
      if (len(text) == 0) return
      if (scan(text(1:1), "+-") == 1) i = 2
      digits_before = leading_digits(text, i)
      digits_after = 0
      if (i <= len(text)) then
         if (text(i:i) == ".") then
            i = i + 1
            digits_after = leading_digits(text, i)
         end if
      end if
      if (digits_before + digits_after == 0) return
      if (i <= len(text)) then
         if (scan(text(i:i), "eEdD") /= 1) return
         i = i + 1
         if (i <= len(text)) then
            if (scan(text(i:i), "+-") == 1) i = i + 1
         end if
         exponent_digits = leading_digits(text, i)
         if (exponent_digits == 0) return
      end if
      is_number = i > len(text)
   end function is_number

   !> Digits of text from `position` on; position moves past them.
   integer function leading_digits(text, position)
      character(len=*), intent(in) :: text
      integer, intent(inout) :: position
      leading_digits = 0
      do while (position <= len(text))
         if (scan(text(position:position), "0123456789") /= 1) exit
         position = position + 1
         leading_digits = leading_digits + 1
      end do
   end function leading_digits

   !> A finite real number, written strictly (see is_number).
   logical function read_real(option, text, x, stat)
      character(len=*), intent(in) :: option, text
      real(dp), intent(inout) :: x
      type(status_type), intent(inout) :: stat
      integer :: io_status
      real(dp) :: parsed
      read_real = is_number(text)
      if (read_real) then
         read (text, *, iostat=io_status) parsed
         read_real = io_status == 0
      end if
      if (read_real) read_real = ieee_is_finite(parsed)
      if (read_real) then
         x = parsed
      else
         call set_status(stat, status_invalid_argument, option//" needs a number, got "//text)
      end if
   end function read_real

   logical function read_positive(option, text, x, stat)
      character(len=*), intent(in) :: option, text
      real(dp), intent(inout) :: x
      type(status_type), intent(inout) :: stat
      read_positive = read_real(option, text, x, stat)
      if (.not. read_positive) return
      read_positive = x > 0.0_dp
      if (.not. read_positive) call set_status(stat, status_invalid_argument, option//" must be positive, got "//text)
   end function read_positive

   !> A whole number in [low, high], digits only (with an optional sign).
   logical function read_count(option, text, low, high, unit_name, k, stat)
      character(len=*), intent(in) :: option, text, unit_name
      integer(i8), intent(in) :: low, high
      integer(i8), intent(out) :: k
      type(status_type), intent(inout) :: stat
      integer :: io_status, first
      k = 0
      first = 1
      if (len(text) > 0) then
         if (scan(text(1:1), "+-") == 1) first = 2
      end if
      read_count = len(text) >= first .and. len(text) <= 19
      if (read_count) read_count = verify(text(first:), "0123456789") == 0
      if (read_count) then
         read (text, *, iostat=io_status) k
         read_count = io_status == 0
      end if
      if (.not. read_count) then
         call set_status(stat, status_invalid_argument, option//" needs a whole number, got "//text)
         return
      end if
      read_count = k >= low .and. k <= high
      if (.not. read_count) then
         if (k < low) then
            call set_status(stat, status_invalid_argument, option//" must be at least "//format_integer(low)// &
               " "//unit_name//", got "//text)
         else
            call set_status(stat, status_invalid_argument, option//" must be at most "//format_count(high)// &
               " "//unit_name//", got "//text)
         end if
      end if
   end function read_count

   !> A comma-separated list of names, each one of `valid` (what they are: `kind`).
   logical function split_names(text, valid, kind, names, stat)
      character(len=*), intent(in) :: text, valid(:), kind
      character(len=16), allocatable, intent(inout) :: names(:)
      type(status_type), intent(inout) :: stat
      integer :: start, comma, finish
      character(len=16), allocatable :: parsed(:)
      allocate (parsed(0))
      start = 1
      split_names = .false.
      do
         comma = index(text(start:), ",")
         finish = len(text)
         if (comma > 0) finish = start + comma - 2
         if (.not. any(valid == text(start:finish))) then
            call set_status(stat, status_invalid_argument, "unknown "//kind//' "'//text(start:finish)//'"; '// &
               kind//"s: "//join(valid))
            return
         end if
         parsed = [character(len=16) :: parsed, text(start:finish)]
         if (comma == 0) exit
         start = start + comma
      end do
      names = parsed
      split_names = .true.
   end function split_names

   logical function tolerance_range(text, high, low, stat)
      character(len=*), intent(in) :: text
      real(dp), intent(inout) :: high, low
      type(status_type), intent(inout) :: stat
      integer :: colon
      tolerance_range = .false.
      colon = index(text, ":")
      if (colon <= 1 .or. colon == len(text)) then
         call set_status(stat, status_invalid_argument, "--tols takes HIGH:LOW, e.g. 1e-2:1e-8, got "//text); return
      end if
      if (.not. read_real("--tols", text(:colon - 1), high, stat)) return
      if (.not. read_real("--tols", text(colon + 1:), low, stat)) return
      if (.not. (high > 0.0_dp .and. low > 0.0_dp .and. low <= high .and. high < 1.0_dp)) then
         call set_status(stat, status_invalid_argument, "--tols needs 1 > HIGH >= LOW > 0, got "//text); return
      end if
      if (log10(high/low) > real(max_decades - 1, dp)) then
         call set_status(stat, status_invalid_argument, "--tols spans at most "//format_integer(max_decades)// &
            " decades, got "//text); return
      end if
      tolerance_range = .true.
   end function tolerance_range

   !> Cross-checks of the options before any work: --estimate defect only with schemes
   !> that estimate their own step's error; the integrator's own validation of the vdp
   !> settings (h0 within h_max, tolerances, ...).
   subroutine check_request(request, stat)
      type(request_type), intent(in) :: request
      type(status_type), intent(out) :: stat
      integer :: k
      if (request%options%error_estimate == estimate_defect) then
         if (request%command == "vdp") then
            if (.not. estimates_step_error(request%scheme, stat)) return
         else
            do k = 1, size(request%schemes)
               if (.not. estimates_step_error(trim(request%schemes(k)), stat)) return
            end do
         end if
      end if
      if (request%command /= "vdp") return
      ! the default final time is 3 mu
      if (request%t_end <= 0.0_dp .and. request%mu > huge(1.0_dp)/3.0_dp) then
         call set_status(stat, status_invalid_argument, "vdp: the final time 3 mu is too large; give --tend")
         return
      end if
      call validate_options(request%options, 2, stat)
      if (stat%code /= status_ok) stat%message = "vdp: "//stat%message
   end subroutine check_request

   !> Whether the scheme has its own step error estimate (else stat says so).
   logical function estimates_step_error(name, stat)
      character(len=*), intent(in) :: name
      type(status_type), intent(inout) :: stat
      class(scheme_type), allocatable :: scheme
      call new_scheme(name, scheme, stat)
      estimates_step_error = stat%code == status_ok
      if (.not. estimates_step_error) return
      estimates_step_error = scheme%estimates_step_error
      if (.not. estimates_step_error) call set_status(stat, status_invalid_argument, &
         "--estimate defect: "//name//" has no estimate of its own step's error (si-t-2 has)")
   end function estimates_step_error

   !> Names joined by ", ".
   pure function join(names) result(text)
      character(len=*), intent(in) :: names(:)
      character(len=:), allocatable :: text
      integer :: i
      text = trim(names(1))
      do i = 2, size(names)
         text = text//", "//trim(names(i))
      end do
   end function join

   !> Help of a command ("" for the overview).
   function help_text(command) result(text)
      character(len=*), intent(in) :: command
      character(len=:), allocatable :: text
      character(len=1), parameter :: nl = new_line("a")

      select case (command)
      case ("vdp")
         text = "taylorode vdp: one adaptive run on Van der Pol (defaults: the paper's setting)"//nl// &
            "  --scheme NAME      one of "//join(scheme_names)//" (default i-t-2)"//nl// &
            "  --ic 1|2           1 well prepared, 2 unprepared (default 1)"//nl// &
            "  --mu M             stiffness (default 1000)"//nl// &
            "  --tend T           final time (default 3 mu)"//nl// &
            "  --split paper|stiff  paper: g = (0, mu(1-y^2)z); stiff: g = (0, mu(1-y^2)z - y)"//nl// &
            "  --rtol R --atol A  tolerances (default 0 and 1e-5)"//nl// &
            "  --norm max|rms     error norm (default max)"//nl// &
            "  --controller i|pi|pid  step-size controller (default i)"//nl// &
            "  --settings paper|library  the paper's settings (default) or the library's defaults: the"//nl// &
            "                     scheme's best error estimate, Newton started from an extrapolation and"//nl// &
            "                     stopped by its estimated error, the scheme's controller; the paper's"//nl// &
            "                     tolerances either way"//nl// &
            "  --estimate embedded|doubling|defect  error estimate: the embedded pair (the paper's), step"//nl// &
            "                     doubling or si-t-2's estimate of its own step (both: the error of the"//nl// &
            "                     solution returned)"//nl// &
            "  --h0 H --hmax H    first and largest step (default 1e-2 and none)"//nl// &
            "  --no-reuse         factor the Newton matrix in every solve (default: keep it across steps)"//nl// &
            "  --budget N         attempted steps allowed, for the run and for its reference (default "// &
            format_count(default_vdp_budget)//")"//nl// &
            "  --history FILE.csv write every attempted step, streamed (refuses to overwrite without --force)"//nl// &
            "  --dense N          error on an N-point grid against radau5 at 1e-12 (default 301)"
      case ("table")
         text = "taylorode table: the paper's Table 1 (Van der Pol mu = 1000, t in [0, 3000]) reproduced"//nl// &
            "  every scheme of the paper, both initial conditions, plus si-t-2, radau5 and the stiff"//nl// &
            "  splitting; paper's step counts and CPU seconds beside ours"//nl// &
            "  --budget N    step budget per run (default "//format_count(default_budget)// &
            "); capped runs say how far they got"//nl// &
            "  --full        no budget: si-t-2-paper and imex-rk21 need ~50 million steps each"//nl// &
            "  --repeats N   timing runs for the median (default 5, runs over 1 s once)"//nl// &
            "  --out DIR     also write DIR/table1.csv (--force to overwrite)"
      case ("sweep")
         text = "taylorode sweep: error against CPU time (work-precision) over a range of tolerances"//nl// &
            "  --problem P   one of "//join(test_problem_names)//" (default vdp)"//nl// &
            "  --schemes A,B,...  schemes to compare (default si-t-1,si-t-2,i-t-1,i-t-2,imex-rk21,radau5)"//nl// &
            "  --tols HIGH:LOW    rtol = atol from HIGH down to LOW by decades (default 1e-2:1e-8)"//nl// &
            "  --budget N    step budget per run (default "//format_count(default_budget)//")"//nl// &
            "  --repeats N   timing runs for the median (default 5)"//nl// &
            "  --out DIR     also write DIR/sweep.csv (--force to overwrite)"
      case ("stability")
         text = "taylorode stability: stability functions checked against real steps, S1 regions, L-stability"//nl// &
            "  --grid N      points per axis of the S1 grid on [-3, 1] x [-2, 2] (default 161)"//nl// &
            "  --out DIR     also write DIR/stability_check.csv, DIR/s1_regions.csv, DIR/l_stability.csv"
      case ("extreme")
         text = "taylorode extreme: stiff and extreme cases, one pass/fail line each with its figure"//nl// &
            "  Van der Pol mu = 1e6, Robertson to 1e11, w = -1e12, tolerances 1e-2 and 1e-10,"//nl// &
            "  unprepared initial data and deliberately bad input; exit status 1 if any fails."//nl// &
            "  An integration passes when it ends with status ok and its global error, in the"//nl// &
            "  integrator's weights |u - ref| / (atol + rtol |ref|), is at most the number of steps"//nl// &
            "  (at least 100): error per step control lets that many local errors add up"//nl// &
            "  --quick       smaller cases: Van der Pol mu = 1e4, HIRES at 1e-8 instead of 1e-10"//nl// &
            "  --out DIR     also write DIR/extreme.csv"
      case ("bench")
         text = "taylorode bench: work at equal accuracy beside the peer solvers (run with --profile release)"//nl// &
            "  The peer harness's problems, split, initial data, output times and error measure;"//nl// &
            "  rtol = atol = tol, RMS norm, the library's defaults otherwise (vdp-paper: the paper's"//nl// &
            "  settings, tol ignored). Per run: steps, F (= f + g), Jacobian, LU and solve counts per"//nl// &
            "  step, CPU seconds (mean of repeats until --min-time), microseconds per step, error"//nl// &
            "  at t_end and on the output grid against the reference."//nl// &
            "  --problems A,B,...  of "//join(bench_problem_names)//nl// &
            "                (default vdp-paper to bruss512; bs1000 ... bs100000: Brusselator N = 1e3..1e5, t <= 0.5)"//nl// &
            "  --schemes A,B,...   default si-t-2,i-t-2,radau5"//nl// &
            "  --tols HIGH:LOW     tol from HIGH down to LOW by decades (default 1e-3:1e-8)"//nl// &
            "  --min-time S  CPU seconds to accumulate per run (default 0.2)"//nl// &
            "  --refs DIR    reference solutions DIR/<problem>.csv of the peer harness (default:"//nl// &
            "                computed with radau5 at 1e-12)"//nl// &
            "  --budget N    step budget per run (default "//format_count(default_budget)// &
            "); tighter tolerances are skipped after a run reaches it"//nl// &
            "  --estimate embedded|doubling|defect  the error estimate (default: the library's: si-t-2"//nl// &
            "                its estimate of its own step, radau5 its pair, the others step doubling)"//nl// &
            "  --csv FILE    write the rows in the peer harness's columns (solver taylorode_<scheme>, with"//nl// &
            "                --estimate E taylorode_<scheme>_E)"
      case ("ensemble")
         text = "taylorode ensemble: a Van der Pol sweep over mu on one thread and on several (use --profile"//nl// &
            "  release and an OpenMP build: fpm run --profile release --flag -fopenmp --link-flag -fopenmp)"//nl// &
            "  members with mu spread logarithmically over [1, 1000], t in [0, "// &
            format_fixed(ensemble_t_end, 0)//"], rtol = atol = 1e-6;"//nl// &
            "  wall-clock medians of interleaved runs, the speed-up, and a check that the threaded"//nl// &
            "  results equal the serial ones bit for bit (exit status 1 if not)"//nl// &
            "  --members N   members (default 64)"//nl// &
            "  --scheme NAME one of "//join(scheme_names)//" (default i-t-2)"//nl// &
            "  --threads T   threads of the threaded runs (default: as many as OpenMP gives)"//nl// &
            "  --repeats N   runs of each kind for the medians (default 5)"
      case default
         text = "taylorode "//version//": one-step Taylor schemes for stiff ODEs U' = f(U) + g(U)"//nl// &
            "usage: taylorode [COMMAND] [OPTIONS]     (no command: table)"//nl// &
            "  table      the paper's Table 1 reproduced (the main job)"//nl// &
            "  vdp        one Van der Pol run with a summary and optional step history"//nl// &
            "  sweep      error against run time over tolerances"//nl// &
            "  stability  stability functions, S1 regions and L-stability"//nl// &
            "  extreme    stiff and extreme cases, pass/fail"//nl// &
            "  bench      work at equal accuracy on the peer solvers' problems"//nl// &
            "  ensemble   a parameter sweep on one thread and on several: speed-up"//nl// &
            "taylorode COMMAND --help (or taylorode help COMMAND) describes each command;"//nl// &
            "taylorode --version prints the version. Exit status: 0 success, 1 a run or check"//nl// &
            "failed or an output could not be written, 2 a mistake on the command line."
      end select
   end function help_text

   ! ---------------------------------------------------------------- output files

   !> The CSV files a command writes into --out.
   function table_files(command) result(names)
      character(len=*), intent(in) :: command
      character(len=20), allocatable :: names(:)
      select case (command)
      case ("table"); names = [character(len=20) :: "table1.csv"]
      case ("sweep"); names = [character(len=20) :: "sweep.csv"]
      case ("stability"); names = [character(len=20) :: "stability_check.csv", "s1_regions.csv", "l_stability.csv"]
      case ("extreme"); names = [character(len=20) :: "extreme.csv"]
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
      ! the file itself can be created there (a name too long, a file system that refuses it)
      call file%open(path, stat)
      if (stat%code /= status_ok) then
         stat%code = status_invalid_argument
         return
      end if
      call file%discard()
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
         call file%open(path, file_stat)
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

   ! ---------------------------------------------------------------- vdp

   !> taylorode vdp: one run with a summary, the error against radau5 at t_end and on a
   !> grid, and (when asked) the step history, streamed into its file.
   subroutine run_vdp(request, stat)
      type(request_type), intent(in) :: request
      type(status_type), intent(out) :: stat
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: run_stat, reference_stat
      type(step_history_type) :: history
      real(dp) :: t_end, u(2), u_ref(2)
      real(dp), allocatable :: t_out(:), u_out(:, :), u_out_ref(:, :)
      integer :: k

      problem = new_van_der_pol(request%mu, request%splitting, request%ic)
      t_end = problem%t_end
      if (request%t_end > 0.0_dp) t_end = request%t_end
      options = request%options
      options%max_steps = request%budget
      options%history_states = allocated(request%history_file)
      t_out = [(t_end*real(k - 1, dp)/real(request%dense_points - 1, dp), k=1, request%dense_points)]
      allocate (u_out(2, size(t_out)), u_out_ref(2, size(t_out)))

      call new_scheme(request%scheme, scheme, stat)
      if (stat%code /= status_ok) return
      u = problem%u0
      if (allocated(request%history_file)) then
         call history%stream_to(request%history_file, stat)
         if (stat%code /= status_ok) return
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, run_stat, history=history, &
            t_out=t_out, u_out=u_out)
         ! integrate has finished the file: a history that could not be written ends the command
         if (run_stat%code == status_output_error) then
            stat = run_stat
            return
         end if
      else
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, run_stat, t_out=t_out, u_out=u_out)
      end if

      call say("Van der Pol, mu = "//format_number(request%mu)//", IC"//format_integer(request%ic)// &
         ", t in [0, "//format_number(t_end)//"], "//split_name(request%splitting)//" splitting")
      call say("scheme "//request%scheme//", controller "//controller_name(options%controller)// &
         ", rtol "//format_real(options%rtol)//", atol "//format_real(options%atol)//", "// &
         merge("max", "rms", options%norm == norm_max)//" norm, h0 "//format_real(options%h0))
      if (run_stat%code == status_ok) then
         call say("status: ok")
      else
         call say("status: "//status_name(run_stat%code)//": "//run_stat%message)
      end if
      call say("accepted steps "//format_count(stats%accepted_steps)//", rejected "// &
         format_count(stats%rejected_steps())//" (error test "//format_count(stats%rejected_error)// &
         ", Newton "//format_count(stats%rejected_newton)//", non-finite "// &
         format_count(stats%rejected_nonfinite)//")")
      call say("evaluations: f "//format_count(stats%work%f_evaluations)//", g "// &
         format_count(stats%work%g_evaluations)//", Jacobians "// &
         format_count(stats%work%jac_f_evaluations)//" + "//format_count(stats%work%jac_g_evaluations)// &
         ", LU factorizations "//format_count(stats%work%lu_factorizations)//", linear solves "// &
         format_count(stats%work%linear_solves)//", Newton iterations "// &
         format_count(stats%work%newton_iterations))
      call say("accepted h in ["//format_real(stats%h_min_accepted)//", "// &
         format_real(stats%h_max_accepted)//"], CPU "//format_fixed(stats%cpu_seconds, 3)//" s")
      if (allocated(request%history_file)) then
         call say("step history: "//format_integer(history%count)//" attempts, wrote "//request%history_file)
      end if
      if (run_stat%code /= status_ok) then
         call say("error: not measured, the run stopped at t = "//format_real(stats%t_reached))
      else
         call progress("vdp: reference solution (radau5 at 1e-12)")
         call reference_run(problem, 0.0_dp, t_end, problem%u0, t_out, u_ref, u_out_ref, reference_stat, &
            max_steps=request%budget)
         if (reference_stat%code /= status_ok) then
            call say("error: not measured, the reference run stopped ("//status_name(reference_stat%code)//")")
         else
            call say("error at t = "//format_number(t_end)//": y "//format_real(abs(u(1) - u_ref(1)))// &
               ", z "//format_real(abs(u(2) - u_ref(2)))//" (against radau5 at rtol = atol = 1e-12)")
            call say("max error on the "//format_integer(request%dense_points)//"-point grid: "// &
               format_real(maxval(abs(u_out - u_out_ref)))//" (dense output: "// &
               trim(merge("the scheme's own", "cubic Hermite   ", scheme%dense_degree > 0))//")")
         end if
      end if
      stat = run_stat
   end subroutine run_vdp

   ! ---------------------------------------------------------------- table

   !> taylorode table: the paper's Table 1 for both initial conditions, every scheme of
   !> the paper plus si-t-2, radau5 and the stiff splitting.
   subroutine run_table(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), allocatable, intent(inout) :: tables(:)
      type(status_type), intent(out) :: stat
      !> rows: scheme, splitting, index into the paper's columns (0: none)
      character(len=*), parameter :: names(10) = [character(len=12) :: "si-t-1", "si-t-2-paper", &
         "i-t-1", "i-t-2", "imex-rk21", "si-t-2", "radau5", "si-t-1", "si-t-2", "i-t-2"]
      integer, parameter :: splits(10) = [1, 1, 1, 1, 1, 1, 1, 2, 2, 2]
      integer, parameter :: paper_column(10) = [1, 2, 3, 4, 5, 0, 6, 0, 0, 0]
      !> Table 1 of the paper, by initial condition: accepted steps and CPU seconds
      !> (MATLAB) of SI-T-1, SI-T-2, I-T-1, I-T-2, IMEX-RK(2,1) and ode15s
      integer, parameter :: paper_steps(6, 2) = reshape([38602, 38572, 160083, 160103, 2819271, 632, &
         38547, 38563, 159692, 159710, 2804550, 592], [6, 2])
      real(dp), parameter :: paper_cpu(6, 2) = reshape([10.76_dp, 10.75_dp, 26.88_dp, 26.98_dp, 16.65_dp, &
         0.05_dp, 10.96_dp, 10.88_dp, 25.96_dp, 25.99_dp, 16.48_dp, 0.05_dp], [6, 2])
      type(van_der_pol_type) :: problem
      type(integrator_options_type) :: options
      type(timed_run_type) :: run
      real(dp) :: t_out(301), u_ref(2), u_out_ref(2, 301), err_end, err_grid
      integer :: ic, k, table
      character(len=:), allocatable :: steps_text, note, paper_steps_text, paper_cpu_text, label, &
         paper_steps_csv, paper_cpu_csv

      t_out = [(10.0_dp*real(k - 1, dp), k=1, 301)]
      table = new_table(tables, "table1.csv", "ic,scheme,splitting,accepted,rejected,cpu_seconds,runs,"// &
         "status,t_reached,error_t3000,max_error_grid301,paper_steps,paper_cpu_seconds")
      call say("Table 1 of the paper reproduced: Van der Pol mu = 1000, t in [0, 3000], I controller,"// &
         " kappa 0.9, q 2, rtol 0, atol 1e-5, max norm, h0 1e-2")
      if (request%full) then
         call say("every run to the end (--full)")
      else
         call say("step budget "//format_count(request%budget)//" attempts per run (--full lifts it)")
      end if
      call say("CPU: cpu_time() around the integration, median of up to "//format_integer(request%repeats)// &
         " runs (one run when it takes over 1 s); errors in the max norm against radau5 at 1e-12")
      call say("")
      call say(pad("IC", 2)//"  "//pad("scheme", -13)//pad("split", -6)//pad("accepted", 12)// &
         pad("rejected", 9)//pad("CPU s", 9)//pad("err t=3000", 11)//pad("max err grid", 13)// &
         pad("paper steps", 12)//pad("paper CPU s", 12)//"  note")
      do ic = 1, 2
         problem = new_van_der_pol(1000.0_dp, vdp_split_paper, ic)
         call reference_run(problem, 0.0_dp, 3000.0_dp, problem%u0, t_out, u_ref, u_out_ref, stat)
         if (stat%code /= status_ok) return
         do k = 1, size(names)
            problem = new_van_der_pol(1000.0_dp, splits(k), ic)
            options = paper_options()
            if (.not. request%full) options%max_steps = request%budget
            label = trim(names(k))
            call progress("table: IC"//format_integer(ic)//" "//label//" ("//split_name(splits(k))//" splitting)")
            call timed_run(problem, label, options, 0.0_dp, 3000.0_dp, problem%u0, request%repeats, run, t_out)
            note = ""
            if (run%stat%code == status_ok) then
               steps_text = format_count(run%stats%accepted_steps)
               err_end = maxval(abs(run%u - u_ref))
               err_grid = maxval(abs(run%u_out - u_out_ref))
            else
               steps_text = "> "//format_count(run%stats%accepted_steps)
               err_end = -1.0_dp
               err_grid = -1.0_dp
               if (run%stat%code == status_max_steps) then
                  note = "step budget reached, stopped at t = "//format_fixed(run%stats%t_reached, 1)
               else
                  note = status_name(run%stat%code)//" at t = "//format_fixed(run%stats%t_reached, 1)
               end if
            end if
            if (label == "si-t-2-paper") note = join_notes("first order on this problem", note)
            if (label == "radau5") note = join_notes("paper column: ode15s", note)
            paper_steps_text = ""
            paper_cpu_text = ""
            paper_steps_csv = ""
            paper_cpu_csv = ""
            if (paper_column(k) > 0) then
               paper_steps_text = format_count(int(paper_steps(paper_column(k), ic), i8))
               paper_cpu_text = format_fixed(paper_cpu(paper_column(k), ic), 2)
               paper_steps_csv = format_integer(paper_steps(paper_column(k), ic))
               paper_cpu_csv = paper_cpu_text
            end if
            call say(pad(format_integer(ic), 2)//"  "//pad(label, -13)//pad(split_name(splits(k)), -6)// &
               pad(steps_text, 12)//pad(format_count(run%stats%rejected_steps()), 9)// &
               pad(format_fixed(run%cpu_median, 3), 9)//pad(error_text(err_end), 11)// &
               pad(error_text(err_grid), 13)//pad(paper_steps_text, 12)//pad(paper_cpu_text, 12)//"  "//note)
            call add_row(tables(table), format_integer(ic)//","//label//","//split_name(splits(k))//","// &
               format_integer(run%stats%accepted_steps)//","//format_integer(run%stats%rejected_steps())//","// &
               format_real(run%cpu_median, 4)//","//format_integer(run%runs)//","//status_word(run%stat%code)//","// &
               format_real(run%stats%t_reached, 8)//","//error_text(err_end)//","//error_text(err_grid)//","// &
               paper_steps_csv//","//paper_cpu_csv)
         end do
      end do
      stat%code = status_ok
   end subroutine run_table

   ! ---------------------------------------------------------------- sweep

   !> taylorode sweep: error against CPU time for each scheme over decades of tolerance
   !> (rtol = atol = tol, atol scaled for problems with small components).
   subroutine run_sweep(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), allocatable, intent(inout) :: tables(:)
      type(status_type), intent(out) :: stat
      class(test_problem_type), allocatable :: problem
      type(work_precision_config_type) :: config
      type(work_precision_point_type), allocatable :: points(:)
      real(dp), allocatable :: reference(:), u_out_ref(:, :)
      real(dp) :: t_none(0)
      integer :: k, s, table
      character(len=:), allocatable :: reference_text

      call new_test_problem(request%problem, problem, stat)
      if (stat%code /= status_ok) return
      if (allocated(problem%reference)) then
         reference = problem%reference
         reference_text = "the published reference solution"
      else
         call progress("sweep: reference solution (radau5 at 1e-12)")
         allocate (reference(size(problem%u0)), u_out_ref(size(problem%u0), 0))
         call reference_run(problem, problem%t0, problem%t_end, problem%u0, t_none, reference, u_out_ref, stat)
         if (stat%code /= status_ok) return
         reference_text = "radau5 at rtol = 1e-12"
      end if
      table = new_table(tables, "sweep.csv", "problem,scheme,tol,accepted,rejected,cpu_seconds,runs,status,error")
      call say("work-precision on "//problem%name//" over ["//format_number(problem%t0)//", "// &
         format_number(problem%t_end)//"]: rtol = tol, atol = tol * "// &
         format_real(tolerance_scale(problem))//"; error = max|u - ref| / max|ref| at t_end against "//reference_text)
      call say("CPU: median of up to "//format_integer(request%repeats)//" runs; step budget "// &
         format_count(request%budget))
      call say("")
      call say(pad("scheme", -13)//pad("tol", 10)//pad("accepted", 12)//pad("rejected", 10)// &
         pad("CPU s", 10)//pad("error", 11)//"  note")
      config%tol_high = request%tol_high
      config%tol_low = request%tol_low
      config%repeats = request%repeats
      config%budget = request%budget
      do s = 1, size(request%schemes)
         call progress("sweep: "//trim(request%schemes(s)))
         config%schemes = request%schemes(s:s)
         call work_precision(problem, config, reference, points)
         do k = 1, size(points)
            associate (p => points(k))
               call say(pad(trim(p%scheme), -13)//pad(format_real(p%tol, 2), 10)// &
                  pad(format_count(p%accepted), 12)//pad(format_count(p%rejected), 10)// &
                  pad(format_fixed(p%cpu_seconds, 4), 10)//pad(error_text(p%error), 11)//"  "// &
                  choose(p%status == status_ok, "", status_name(p%status)))
               call add_row(tables(table), problem%name//","//trim(p%scheme)//","//format_real(p%tol, 2)//","// &
                  format_integer(p%accepted)//","//format_integer(p%rejected)//","// &
                  format_real(p%cpu_seconds, 4)//","//format_integer(p%runs)//","//status_word(p%status)//","// &
                  error_text(p%error))
            end associate
         end do
      end do
      stat%code = status_ok
   end subroutine run_sweep

   ! ---------------------------------------------------------------- stability

   !> taylorode stability: (1) R(z, w) against one real step, (2) S1 regions and their
   !> axis crossings, (3) |R(z, w)| as Re w -> -1e12.
   subroutine run_stability(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), allocatable, intent(inout) :: tables(:)
      type(status_type), intent(out) :: stat
      class(scheme_type), allocatable :: scheme
      complex(dp) :: z, w, r, r_step
      real(dp) :: deviation, worst, re_z, im_z, sup, left, right, top
      integer :: k, i, j, pairs, check_table, region_table, l_table, e
      character(len=:), allocatable :: name, line

      check_table = new_table(tables, "stability_check.csv", "scheme,pairs,max_relative_deviation")
      region_table = new_table(tables, "s1_regions.csv", "scheme,re_z,im_z,sup_abs_r,inside")
      l_table = new_table(tables, "l_stability.csv", "scheme,re_w,abs_r_formula,abs_r_step")

      call say("(1) one real step of each scheme on u' = lambda u + nu u (2x2 blocks, h = 1)"// &
         " against R(z, w), z = lambda, w = nu")
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         worst = 0.0_dp
         pairs = 0
         do i = 0, 9
            do j = 0, 9
               z = cmplx(-2.5_dp + 0.3_dp*i, -1.5_dp + 0.33_dp*j, dp)
               w = cmplx(-10.0_dp**(0.6_dp*j - 1.0_dp), 2.0_dp*(i - 4.5_dp), dp)
               call step_stability(scheme, z, w, r_step, stat)
               if (stat%code /= status_ok) cycle
               r = scheme%stability(z, w)
               deviation = abs(r_step - r)/max(abs(r), 1.0_dp)
               worst = max(worst, deviation)
               pairs = pairs + 1
            end do
         end do
         call say("  "//pad(name, -13)//pad(format_integer(pairs), 4)//" pairs, largest deviation "// &
            format_real(worst, 2)//" (relative to max(|R|, 1))")
         call add_row(tables(check_table), name//","//format_integer(pairs)//","//format_real(worst, 3))
         if (worst > 1.0e-12_dp .or. pairs < 100) checks_failed = .true.
      end do

      call say("")
      call say("(2) S1 = {z : sup over Re w <= 0 of |R(z, w)| <= 1} on [-3, 1] x [-2, 2], "// &
         format_integer(request%grid)//" x "//format_integer(request%grid)//" points; axis crossings by bisection")
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         do i = 1, request%grid
            re_z = -3.0_dp + 4.0_dp*real(i - 1, dp)/real(request%grid - 1, dp)
            do j = 1, request%grid
               im_z = -2.0_dp + 4.0_dp*real(j - 1, dp)/real(request%grid - 1, dp)
               sup = s1_supremum(scheme, cmplx(re_z, im_z, dp))
               call add_row(tables(region_table), name//","//format_fixed(re_z, 4)//","// &
                  format_fixed(im_z, 4)//","//format_real(sup, 4)//","//merge("1", "0", sup <= 1.0_dp + 1.0e-12_dp))
            end do
         end do
         call s1_axis_crossings(scheme, left, right, top)
         if (left > right) then
            call say("  "//pad(name, -13)//"empty (no z with |R| <= 1 for every Re w <= 0)")
         else
            call say("  "//pad(name, -13)//"real axis ["//crossing(left, -3.0_dp)//", "// &
               crossing(right, 1.0_dp)//"], imaginary axis |Im z| <= "//crossing(top, 2.0_dp))
         end if
      end do

      call say("")
      call say("(3) L-stability: |R(-0.5, w)| for real w -> -1e12 (formula; last column one real step)")
      call say("  "//pad("scheme", -13)//pad("w=-1e0", 10)//pad("w=-1e3", 10)//pad("w=-1e6", 10)// &
         pad("w=-1e9", 10)//pad("w=-1e12", 10)//pad("step 1e12", 11))
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         line = "  "//pad(name, -13)
         do e = 0, 12, 3
            w = cmplx(-10.0_dp**e, 0.0_dp, dp)
            r = scheme%stability((-0.5_dp, 0.0_dp), w)
            call step_stability(scheme, (-0.5_dp, 0.0_dp), w, r_step, stat)
            line = line//pad(format_real(abs(r), 2), 10)
            call add_row(tables(l_table), name//","//format_real(real(w, dp), 2)//","// &
               format_real(abs(r), 4)//","//format_real(abs(r_step), 4))
         end do
         line = line//pad(format_real(abs(r_step), 2), 11)
         call say(line)
      end do
      if (checks_failed) then
         call say("SOME STABILITY CHECKS FAILED")
      else
         call say("every stability function matches one real step of its scheme")
      end if
      stat%code = status_ok
   end subroutine run_stability

   ! ---------------------------------------------------------------- extreme

   !> taylorode extreme: one pass/fail line per stiff or extreme case. An integration
   !> passes when it ends with status ok and its global error in the integrator's own
   !> weights is within the accuracy bound of its scheme's order.
   subroutine run_extreme(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), allocatable, intent(inout) :: tables(:)
      type(status_type), intent(out) :: stat
      character(len=*), parameter :: l_stable(4) = [character(len=6) :: "si-t-1", "si-t-2", "i-t-1", "i-t-2"]
      type(van_der_pol_type) :: vdp
      type(robertson_type) :: robertson
      type(hires_type) :: hires
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: run_stat
      real(dp) :: u2(2), u3(3), u8(8), reference2(2), none(0), none_out(2, 0), nan, tol
      complex(dp) :: r, r_step
      integer :: k, table, i
      logical :: ok

      table = new_table(tables, "extreme.csv", "case,scheme,steps,rejected,figure,status,ok")
      nan = ieee_value(1.0_dp, ieee_quiet_nan)

      ! Van der Pol mu = 1e6 over [0, 3e6] (1e4 with --quick)
      vdp = new_van_der_pol(merge(1.0e4_dp, 1.0e6_dp, request%quick))
      call progress("extreme: reference solution of Van der Pol mu = "//format_real(vdp%mu, 1))
      call reference_run(vdp, 0.0_dp, vdp%t_end, vdp%u0, none, reference2, none_out, stat)
      if (stat%code /= status_ok) return
      do k = 1, size(l_stable)
         call progress("extreme: "//trim(l_stable(k))//" Van der Pol mu = "//format_real(vdp%mu, 1))
         call new_scheme(trim(l_stable(k)), scheme, stat)
         options = integrator_options_type(rtol=1.0e-5_dp, atol=1.0e-5_dp, max_steps=5000000_i8)
         u2 = vdp%u0
         call integrate(vdp, scheme, 0.0_dp, vdp%t_end, u2, options, stats, run_stat)
         call judge_run(tables(table), "vdp mu="//format_real(vdp%mu, 1)//" tol=1e-5", scheme, stats, run_stat, u2, reference2, &
            options)
      end do

      ! Robertson to 1e11 with every component resolved relatively (atol far below y2 ~ 1e-13)
      robertson = new_robertson(1.0e11_dp)
      do k = 1, size(l_stable)
         call progress("extreme: "//trim(l_stable(k))//" Robertson to 1e11")
         call new_scheme(trim(l_stable(k)), scheme, stat)
         options = integrator_options_type(rtol=1.0e-5_dp, atol=1.0e-20_dp, max_steps=5000000_i8)
         u3 = robertson%u0
         call integrate(robertson, scheme, 0.0_dp, robertson%t_end, u3, options, stats, run_stat)
         call judge_run(tables(table), "robertson t=1e11", scheme, stats, run_stat, u3, robertson%reference, options, &
            note=", mass-1 "//format_real(sum(u3) - 1.0_dp, 2), extra_ok=abs(sum(u3) - 1.0_dp) < 1.0e-8_dp)
      end do

      ! the linear test with w = -1e12, one step each: the step must reproduce the
      ! scheme's own R (which damps for the L-stable schemes and grows for the explicit ones)
      do k = 1, scheme_count
         call new_scheme(trim(scheme_names(k)), scheme, run_stat)
         r = scheme%stability((-1.0_dp, 0.0_dp), (-1.0e12_dp, 0.0_dp))
         call step_stability(scheme, (-1.0_dp, 0.0_dp), (-1.0e12_dp, 0.0_dp), r_step, run_stat)
         ok = run_stat%code == status_ok .and. abs(r_step - r) <= 1.0e-12_dp*max(abs(r), 1.0_dp)
         call verdict(tables(table), "linear w=-1e12 one step", trim(scheme_names(k)), "", "|u1| "// &
            format_real(abs(r_step), 2)//choose(abs(r) > 1.0_dp, " (unstable, as its R says)", &
            " (= |R|, damped)"), run_stat, ok)
      end do

      ! tolerances 1e-2 and 1e-10 (1e-8 with --quick) on HIRES
      hires = new_hires()
      do i = 1, 2
         tol = merge(1.0e-2_dp, merge(1.0e-8_dp, 1.0e-10_dp, request%quick), i == 1)
         do k = 3, 4
            call progress("extreme: "//trim(l_stable(k))//" HIRES tol "//format_real(tol, 2))
            call new_scheme(trim(l_stable(k)), scheme, stat)
            options = integrator_options_type(rtol=tol, atol=tol*1.0e-4_dp, max_steps=5000000_i8)
            u8 = hires%u0
            call integrate(hires, scheme, 0.0_dp, hires%t_end, u8, options, stats, run_stat)
            call judge_run(tables(table), "hires tol="//format_real(tol, 2), scheme, stats, run_stat, u8, hires%reference, options)
         end do
      end do

      ! unprepared initial data (IC2), the paper's setting
      vdp = new_van_der_pol(1000.0_dp, vdp_split_paper, vdp_ic_unprepared)
      do k = 1, size(l_stable)
         call progress("extreme: "//trim(l_stable(k))//" Van der Pol IC2")
         call new_scheme(trim(l_stable(k)), scheme, stat)
         options = paper_options()
         u2 = vdp%u0
         call integrate(vdp, scheme, 0.0_dp, vdp%t_end, u2, options, stats, run_stat)
         call judge_run(tables(table), "vdp IC2 (unprepared)", scheme, stats, run_stat, u2, vdp%reference, options)
      end do

      ! deliberately bad input: each must come back with its status, not a crash
      call new_scheme("i-t-2", scheme, stat)
      u2 = [2.0_dp, nan]
      call integrate(vdp, scheme, 0.0_dp, 1.0_dp, u2, paper_options(), stats, run_stat)
      call bad_input(tables(table), "NaN initial state", run_stat, status_nonfinite)
      u2 = vdp%u0
      call integrate(vdp, scheme, 0.0_dp, 1.0_dp, u2, integrator_options_type(rtol=-1.0_dp), stats, run_stat)
      call bad_input(tables(table), "negative rtol", run_stat, status_invalid_argument)
      call integrate(vdp, scheme, 0.0_dp, 1.0_dp, u2, integrator_options_type(h0=-1.0_dp), stats, run_stat)
      call bad_input(tables(table), "negative h0", run_stat, status_invalid_argument)
      call integrate(vdp, scheme, 1.0_dp, 0.0_dp, u2, paper_options(), stats, run_stat)
      call bad_input(tables(table), "t_end < t0", run_stat, status_invalid_argument)
      call integrate(vdp, scheme, 0.0_dp, 3000.0_dp, u2, integrator_options_type(max_steps=100_i8), stats, run_stat)
      call bad_input(tables(table), "100-step budget", run_stat, status_max_steps)
      call new_scheme("rk45", scheme, run_stat)
      call bad_input(tables(table), "unknown scheme rk45", run_stat, status_unknown_scheme)

      if (checks_failed) then
         call say("SOME EXTREME CASES FAILED")
      else
         call say("all extreme cases passed")
      end if
      stat%code = status_ok

   end subroutine run_extreme

   !> An extreme case's integration against its reference: passes with status ok and a
   !> global error, in the weights of its own tolerances, within the bound of its
   !> scheme's order.
   subroutine judge_run(table, label, scheme, stats, run_stat, u, reference, options, note, extra_ok)
      type(table_type), intent(inout) :: table
      character(len=*), intent(in) :: label
      class(scheme_type), intent(in) :: scheme
      type(integration_stats_type), intent(in) :: stats
      type(status_type), intent(in) :: run_stat
      real(dp), intent(in) :: u(:), reference(:)
      type(integrator_options_type), intent(in) :: options
      character(len=*), intent(in), optional :: note
      logical, intent(in), optional :: extra_ok
      real(dp) :: weighted, bound
      logical :: pass
      character(len=:), allocatable :: figure
      weighted = maxval(abs(u - reference)/(options%atol + options%rtol*abs(reference)))
      bound = max(accuracy_bound_least, real(stats%accepted_steps, dp))
      pass = run_stat%code == status_ok .and. all(ieee_is_finite(u)) .and. weighted <= bound
      if (present(extra_ok)) pass = pass .and. extra_ok
      figure = "error "//format_real(weighted, 2)//" x tolerance (bound "//format_real(bound, 1)//")"
      if (run_stat%code == status_ok .and. weighted > bound) figure = figure//", INACCURATE"
      if (present(note)) figure = figure//note
      call verdict(table, label, scheme%name, format_count(stats%accepted_steps)//" steps, ", figure, run_stat, &
         pass, stats%accepted_steps, stats%rejected_steps())
   end subroutine judge_run

   !> One line and one CSV row of an extreme case.
   subroutine verdict(table, label, name, steps, figure, run_stat, ok, accepted, rejected)
      type(table_type), intent(inout) :: table
      character(len=*), intent(in) :: label, name, steps, figure
      type(status_type), intent(in) :: run_stat
      logical, intent(in) :: ok
      integer(i8), intent(in), optional :: accepted, rejected
      character(len=:), allocatable :: status_text, counts
      status_text = status_name(run_stat%code)
      counts = ","
      if (present(accepted)) counts = format_integer(accepted)//","//format_integer(rejected)
      call say(pad(merge("ok  ", "FAIL", ok), -5)//name//" "//label//": "//steps//figure// &
         choose(run_stat%code == status_ok, "", ", "//status_text))
      call add_row(table, label//","//name//","//counts//',"'//figure//'",'//status_text//","//merge("1", "0", ok))
      if (.not. ok) checks_failed = .true.
   end subroutine verdict

   !> A deliberately bad input must come back with the expected status.
   subroutine bad_input(table, label, run_stat, expected)
      type(table_type), intent(inout) :: table
      character(len=*), intent(in) :: label
      type(status_type), intent(in) :: run_stat
      integer, intent(in) :: expected
      logical :: ok
      character(len=:), allocatable :: message
      ok = run_stat%code == expected
      message = ""
      if (allocated(run_stat%message)) message = run_stat%message
      call say(pad(merge("ok  ", "FAIL", ok), -5)//"bad input, "//label//": "//status_name(run_stat%code)// &
         " ("//message//")")
      call add_row(table, "bad input "//label//",,,,"//'"'//message//'",'//status_name(run_stat%code)//","// &
         merge("1", "0", ok))
      if (.not. ok) checks_failed = .true.
   end subroutine bad_input

   ! ---------------------------------------------------------------- bench

   !> taylorode bench: every scheme asked for on the problems of the peer solvers'
   !> harness (their split, initial data, output times and error measure), rtol = atol
   !> = tol in the RMS norm (the peers' setting) with the library's defaults otherwise,
   !> each run repeated until --min-time CPU seconds have accumulated; the pseudo-problem
   !> vdp-paper is the paper's Van der Pol run with the paper's settings (the per-step
   !> cost the hand-coded floor is measured against).
   subroutine run_bench(request, stat)
      type(request_type), intent(in) :: request
      type(status_type), intent(out) :: stat
      type(bench_problem_type) :: bench
      type(text_type), allocatable :: csv_rows(:)
      integer :: p, s, k, rows
      logical :: skip_rest

      allocate (csv_rows(16))
      rows = 0
      call say("bench: rtol = atol = tol (e5: atol 1.7e-24), RMS norm, library defaults otherwise; CPU per run "// &
         "(mean over repeats until "//format_fixed(request%min_time, 2)//" s); per step: evaluations of F = f + g, "// &
         "Jacobians, LU factorizations, linear solves")
      call say(pad("problem", -10)//pad("scheme", -10)//pad("tol", 7)//"  "//pad("status", -8)//pad("steps", 11)// &
         pad("rej", 10)//pad("F/step", 8)//pad("J/step", 8)//pad("LU/step", 8)//pad("sol/step", 9)// &
         pad("CPU s", 10)//pad("us/step", 12)//pad("err_end", 10)//pad("err_grid", 10))
      do p = 1, size(request%problems)
         call make_bench_problem(trim(request%problems(p)), bench, stat)
         if (stat%code /= status_ok) return
         call bench_reference(request, bench, stat)
         if (stat%code /= status_ok) return
         do s = 1, size(request%schemes)
            skip_rest = .false.
            do k = 1, size(request%tols)
               if (bench%paper .and. k > 1) exit
               if (skip_rest) cycle
               call bench_run(request, bench, trim(request%schemes(s)), request%tols(k), csv_rows, rows, skip_rest)
            end do
         end do
      end do
      call say("peak memory of this process: "//format_fixed(real(peak_memory_kib(), dp)/1024.0_dp, 1)//" MiB")
      if (allocated(request%csv_file)) call write_csv(request%csv_file, &
         "solver,problem,tol,rtol,atol,status,steps,rejected,nfe,nfe_expl,nfe_impl,njac,nlu,nniter,cpu_s,reps,"// &
         "err_end,err_grid", csv_rows(:rows), stat)
   end subroutine run_bench

   !> The benchmark problem `name` as the peer harness defines it.
   subroutine make_bench_problem(name, bench, stat)
      character(len=*), intent(in) :: name
      type(bench_problem_type), intent(out) :: bench
      type(status_type), intent(out) :: stat
      integer :: k
      bench%name = name
      select case (name)
      case ("vdp-paper", "vdp1e3_wp", "vdp1e3_up")
         allocate (bench%problem, source=new_van_der_pol(1000.0_dp, vdp_split_paper))
         bench%u0 = van_der_pol_initial_state(merge(vdp_ic_unprepared, vdp_ic_prepared, name == "vdp1e3_up"))
         bench%t_end = 3000.0_dp
         bench%paper = name == "vdp-paper"
         if (.not. bench%paper) bench%t_out = [(10.0_dp*k, k = 0, 300)]
      case ("rober40", "rober1e11")
         allocate (bench%problem, source=new_robertson(merge(40.0_dp, 1.0e11_dp, name == "rober40")))
      case ("hires")
         allocate (bench%problem, source=new_hires(hires_split_reaction_stiff))
      case ("orego")
         allocate (bench%problem, source=new_orego(orego_split_bilinear_stiff))
      case ("e5")
         allocate (bench%problem, source=new_e5())
         bench%t_out = [(1.0e13_dp*10.0_dp**(k - 14), k = 1, 14)]
         bench%atol = 1.7e-24_dp
         bench%first_component = 2
         bench%last_component = 3
         bench%relative = .true.
         bench%grid_until = 1.0e8_dp
      case ("bruss32", "bruss512")
         allocate (bench%problem, source=new_brusselator(merge(32, 512, name == "bruss32")))
      case ("bs1000", "bs10000", "bs100000")
         allocate (bench%problem, source=new_brusselator(merge(1000, merge(10000, 100000, name == "bs10000"), &
            name == "bs1000")))
         bench%t_end = 0.5_dp
      case default
         call set_status(stat, status_invalid_argument, 'unknown bench problem "'//name//'"; problems: '// &
            join(bench_problem_names))
         return
      end select
      if (.not. allocated(bench%u0)) bench%u0 = bench%problem%u0
      if (bench%t_end == 0.0_dp) bench%t_end = bench%problem%t_end
      if (.not. allocated(bench%t_out)) bench%t_out = [bench%t_end]
      bench%t_out(size(bench%t_out)) = bench%t_end
      if (bench%last_component == 0) bench%last_component = size(bench%u0)
      stat%code = status_ok
   end subroutine make_bench_problem

   !> ensemble: a Van der Pol sweep over mu timed on one thread and on several.
   subroutine run_ensemble(request, stat)
      type(request_type), intent(in) :: request
      type(status_type), intent(out) :: stat
      type(van_der_pol_type), allocatable :: problems(:)
      type(integrator_options_type) :: options
      type(ensemble_timing_type) :: timing
      real(dp), allocatable :: u0(:, :)
      character(len=:), allocatable :: scheme
      integer :: k

      scheme = request%scheme
      allocate (problems(request%members), u0(2, request%members))
      do k = 1, request%members
         problems(k) = new_van_der_pol(10.0_dp**(3.0_dp*real(k - 1, dp)/real(max(request%members - 1, 1), dp)))
         u0(:, k) = problems(k)%u0
      end do
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp)
      call progress("ensemble: "//format_integer(request%members)//" members, "//format_integer(request%repeats)// &
         " runs on one thread and as many on several")
      call time_ensemble(problems, scheme, 0.0_dp, ensemble_t_end, u0, options, request%threads, request%repeats, &
         timing, stat)
      if (stat%code /= status_ok) return
      call say("Van der Pol ensemble: "//format_integer(timing%members)//" members, mu from 1 to 1000 "// &
         "(logarithmic), t in [0, "//format_fixed(ensemble_t_end, 0)//"], "//scheme//", rtol = atol = 1e-6; "// &
         format_count(timing%accepted_steps)//" accepted steps in all, "//format_integer(timing%failed_members)// &
         " members failed")
      call say("wall-clock seconds, median of "//format_integer(timing%repeats)//" interleaved runs each:")
      call say("  1 thread:    "//format_fixed(timing%serial_seconds, 3))
      call say("  "//pad(format_integer(timing%threads)//choose(timing%threads == 1, " thread:", " threads:"), -11)// &
         "  "// &
         format_fixed(timing%threaded_seconds, 3)//"   speed-up "//format_fixed(timing%speedup, 2)// &
         choose(timing%threads == 1, "   (one thread: build with OpenMP, see --help)", ""))
      call say("threaded results equal to the serial ones bit for bit: "//choose(timing%identical, "yes", "NO"))
      if (.not. timing%identical) checks_failed = .true.
   end subroutine run_ensemble

   !> The reference solution at the output times: the harness's file DIR/<name>.csv
   !> (--refs), else radau5 at rtol = 1e-12.
   subroutine bench_reference(request, bench, stat)
      type(request_type), intent(in) :: request
      type(bench_problem_type), intent(inout) :: bench
      type(status_type), intent(out) :: stat
      real(dp), allocatable :: u_end(:)
      integer :: unit, io_status, row
      character(len=:), allocatable :: path
      real(dp) :: t_row

      allocate (bench%reference(size(bench%u0), size(bench%t_out)), u_end(size(bench%u0)))
      if (allocated(request%refs_dir)) then
         path = request%refs_dir//"/"//bench%name//".csv"
         open (newunit=unit, file=path, status="old", action="read", iostat=io_status)
         if (io_status == 0) then
            read (unit, *, iostat=io_status)
            do row = 1, size(bench%t_out)
               if (io_status /= 0) exit
               read (unit, *, iostat=io_status) t_row, bench%reference(:, row)
            end do
            close (unit)
            if (io_status == 0) then
               stat%code = status_ok
               return
            end if
            call progress("bench: "//path//" does not hold the reference of "//bench%name//"; computing one")
         end if
      end if
      call progress("bench: reference solution of "//bench%name//" (radau5 at 1e-12)")
      call reference_run(bench%problem, 0.0_dp, bench%t_end, bench%u0, bench%t_out, u_end, bench%reference, stat)
      if (stat%code /= status_ok) stat%message = "bench: the reference run of "//bench%name//" failed: "//stat%message
   end subroutine bench_reference

   !> One problem, scheme and tolerance: repeated runs, one line and one CSV row.
   subroutine bench_run(request, bench, scheme_name, tol, csv_rows, rows, budget_reached)
      type(request_type), intent(in) :: request
      type(bench_problem_type), intent(inout) :: bench
      character(len=*), intent(in) :: scheme_name
      real(dp), intent(in) :: tol
      type(text_type), allocatable, intent(inout) :: csv_rows(:)
      integer, intent(inout) :: rows
      logical, intent(out) :: budget_reached
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: run_stat
      real(dp), allocatable :: u(:), u_out(:, :)
      real(dp) :: cpu, err_end, err_grid, steps
      integer :: reps, k
      character(len=:), allocatable :: status_text, tol_text

      if (bench%paper) then
         options = paper_options()
         tol_text = "paper"
      else
         options = integrator_options_type(rtol=tol, atol=tol, norm=norm_rms, error_estimate=request%options%error_estimate)
         if (bench%atol > 0.0_dp) options%atol = bench%atol
         tol_text = format_real(tol, 1)
      end if
      options%max_steps = request%budget
      call new_scheme(scheme_name, scheme, run_stat)
      ! the states at the output times, when there are more than t_end's
      allocate (u(size(bench%u0)), u_out(size(bench%u0), merge(size(bench%t_out), 0, size(bench%t_out) > 1)))
      call progress("bench: "//bench%name//" "//scheme_name//" "//tol_text)
      cpu = 0.0_dp
      reps = 0
      do
         u = bench%u0
         if (size(bench%t_out) > 1) then
            call integrate(bench%problem, scheme, 0.0_dp, bench%t_end, u, options, stats, run_stat, &
               t_out=bench%t_out, u_out=u_out)
         else
            ! no dense output to pay for when t_end is the only output time
            call integrate(bench%problem, scheme, 0.0_dp, bench%t_end, u, options, stats, run_stat)
         end if
         cpu = cpu + stats%cpu_seconds
         reps = reps + 1
         if (run_stat%code /= status_ok .or. cpu >= request%min_time) exit
      end do
      budget_reached = run_stat%code == status_max_steps
      err_end = ieee_value(1.0_dp, ieee_quiet_nan)
      err_grid = err_end
      if (run_stat%code == status_ok) then
         status_text = "ok"
         err_end = bench_error(bench, u, bench%reference(:, size(bench%t_out)))
         if (size(bench%t_out) > 1) then
            err_grid = 0.0_dp
            do k = 1, size(bench%t_out)
               if (bench%grid_until > 0.0_dp .and. bench%t_out(k) > bench%grid_until) cycle
               err_grid = max(err_grid, bench_error(bench, u_out(:, k), bench%reference(:, k)))
            end do
         end if
      else if (budget_reached) then
         status_text = "budget(t="//format_real(stats%t_reached, 2)//")"
      else
         status_text = "fail("//status_word(run_stat%code)//")"
      end if
      steps = real(max(stats%accepted_steps, 1_i8), dp)
      associate (work => stats%work)
         call say(pad(bench%name, -10)//pad(scheme_name, -10)//pad(tol_text, 7)//"  "//pad(status_text, -8)// &
            pad(format_count(stats%accepted_steps), 11)//pad(format_count(stats%rejected_steps()), 10)// &
            pad(format_fixed(real(max(work%f_evaluations, work%g_evaluations), dp)/steps, 2), 8)// &
            pad(format_fixed(real(max(work%jac_f_evaluations, work%jac_g_evaluations), dp)/steps, 2), 8)// &
            pad(format_fixed(real(work%lu_factorizations, dp)/steps, 2), 8)// &
            pad(format_fixed(real(work%linear_solves, dp)/steps, 2), 9)// &
            pad(format_real(cpu/reps, 3), 10)//pad(format_fixed(1.0e6_dp*cpu/reps/steps, 3), 12)// &
            pad(error_text(err_end), 10)//pad(choose(size(bench%t_out) > 1, error_text(err_grid), "-"), 10))
         if (rows == size(csv_rows)) csv_rows = [csv_rows, csv_rows]
         rows = rows + 1
         csv_rows(rows)%text = "taylorode_"//scheme_name//estimate_suffix(request%options%error_estimate)// &
            ","//bench%name//","//tol_text//","// &
            format_real(options%rtol, 6)//","//format_real(options%atol, 6)//","//status_text//","// &
            format_integer(stats%accepted_steps)//","//format_integer(stats%rejected_steps())//","// &
            format_integer(max(work%f_evaluations, work%g_evaluations))//","// &
            format_integer(work%f_evaluations)//","//format_integer(work%g_evaluations)//","// &
            format_integer(max(work%jac_f_evaluations, work%jac_g_evaluations))//","// &
            format_integer(work%lu_factorizations)//","//format_integer(work%newton_iterations)//","// &
            format_real(cpu/reps, 6)//","//format_integer(reps)//","//csv_number(err_end)//","// &
            choose(size(bench%t_out) > 1, csv_number(err_grid), "")
      end associate
   end subroutine bench_run

   !> The suffix of the CSV solver name for an error estimate asked for by name ("" for
   !> the library's default).
   pure function estimate_suffix(estimate) result(suffix)
      integer, intent(in) :: estimate
      character(len=:), allocatable :: suffix
      select case (estimate)
      case (estimate_embedded); suffix = "_embedded"
      case (estimate_doubling); suffix = "_doubling"
      case (estimate_defect); suffix = "_defect"
      case default; suffix = ""
      end select
   end function estimate_suffix

   !> The harness's error of one output row: the largest |u_i - ref_i| (relative to
   !> |ref_i| for e5) over the measured components.
   pure real(dp) function bench_error(bench, u, reference)
      type(bench_problem_type), intent(in) :: bench
      real(dp), intent(in) :: u(:), reference(:)
      integer :: i
      real(dp) :: difference
      bench_error = 0.0_dp
      do i = bench%first_component, bench%last_component
         difference = abs(u(i) - reference(i))
         if (bench%relative) difference = difference/abs(reference(i))
         if (.not. (difference <= bench_error)) bench_error = difference
      end do
   end function bench_error

   !> A number for the CSV file ("nan" when it is not finite).
   pure function csv_number(x) result(text)
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      if (ieee_is_finite(x)) then
         text = format_real(x, 6)
      else
         text = "nan"
      end if
   end function csv_number

   !> Write a CSV file (header and rows) in one piece.
   subroutine write_csv(path, header, rows, stat)
      character(len=*), intent(in) :: path, header
      type(text_type), intent(in) :: rows(:)
      type(status_type), intent(out) :: stat
      type(text_file_type) :: file
      integer :: r
      call file%open(path, stat)
      if (stat%code /= status_ok) return
      call file%write_line(header)
      do r = 1, size(rows)
         call file%write_line(rows(r)%text)
      end do
      call file%commit(stat)
      if (stat%code == status_ok) call say("wrote "//path)
   end subroutine write_csv

   !> Peak resident memory of this process in KiB (VmHWM of /proc/self/status; 0 when it
   !> cannot be read).
   integer(i8) function peak_memory_kib()
      integer :: unit, io_status
      character(len=256) :: line
      peak_memory_kib = 0
      open (newunit=unit, file="/proc/self/status", status="old", action="read", iostat=io_status)
      if (io_status /= 0) return
      do
         read (unit, '(a)', iostat=io_status) line
         if (io_status /= 0) exit
         if (line(1:6) == "VmHWM:") then
            read (line(7:), *, iostat=io_status) peak_memory_kib
            exit
         end if
      end do
      close (unit)
   end function peak_memory_kib

   ! ---------------------------------------------------------------- formatting

   pure function crossing(x, limit) result(text)
      real(dp), intent(in) :: x, limit
      character(len=:), allocatable :: text
      text = format_fixed(x, 4)
      if (x == limit) text = text//" (edge of the grid)"
   end function crossing

   pure function join_notes(first, second) result(text)
      character(len=*), intent(in) :: first, second
      character(len=:), allocatable :: text
      text = first
      if (len(second) > 0) text = first//"; "//second
   end function join_notes

   pure function error_text(err) result(text)
      real(dp), intent(in) :: err
      character(len=:), allocatable :: text
      text = "n/a"
      if (ieee_is_nan(err)) return
      if (err >= 0.0_dp) text = format_real(err, 2)
   end function error_text

   pure function status_word(code) result(text)
      integer, intent(in) :: code
      character(len=:), allocatable :: text
      integer :: i
      text = status_name(code)
      do i = 1, len(text)
         if (text(i:i) == " ") text(i:i) = "_"
      end do
   end function status_word

   pure function split_name(splitting) result(text)
      integer, intent(in) :: splitting
      character(len=:), allocatable :: text
      if (splitting == vdp_split_stiff) then
         text = "stiff"
      else
         text = "paper"
      end if
   end function split_name

end program taylorode_app
