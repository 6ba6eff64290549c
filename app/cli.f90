!> The command line of the taylorode app: what a user may ask for (request_type), the
!> limits that keep every run finite, and the parsing and cross-checks that turn the
!> arguments into a request or into a message that names the mistake. Nothing typed
!> on the command line reaches a shell.
module app_cli
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use taylorode, only: dp, i8, status_type, status_ok, status_invalid_argument, scheme_type, new_scheme, &
      scheme_names, integrator_options_type, paper_options, norm_max, norm_rms, controller_i, controller_pi, &
      controller_pid, estimate_auto, estimate_embedded, estimate_doubling, estimate_defect
   use taylorode_testset, only: test_problem_names, vdp_split_paper, vdp_split_stiff
   use taylorode_analysis, only: accuracy_case_names
   use taylorode_base_status, only: set_status
   use taylorode_base_strings, only: format_count, format_fixed, format_integer
   use taylorode_base_files, only: is_directory
   use taylorode_integrate_options, only: validate_options
   implicit none
   private

   public :: request_type, read_arguments, parse_command_line, check_request, join
   public :: version, default_budget, default_table_budget, default_vdp_budget, default_accuracy_budget, &
      default_repeats, default_table_repeats, ensemble_t_end, bench_problem_names

   !> Version of the app and the library
   character(len=*), parameter :: version = "0.2.0"
   !> Subcommands
   character(len=*), parameter :: command_names(*) = [character(len=9) :: &
      "table", "vdp", "sweep", "stability", "extreme", "bench", "ensemble", "accuracy"]
   !> Options that take a value
   character(len=*), parameter :: valued_options(*) = [character(len=12) :: "--out", "--scheme", "--ic", &
      "--mu", "--tend", "--split", "--rtol", "--atol", "--norm", "--controller", "--h0", "--hmax", &
      "--history", "--dense", "--budget", "--repeats", "--problem", "--schemes", "--tols", "--grid", &
      "--estimate", "--settings", "--problems", "--min-time", "--refs", "--csv", "--members", "--threads"]
   !> Step budget per run of sweep and bench unless --budget
   integer(i8), parameter :: default_budget = 2000000_i8
   !> Step budget per run of table unless --budget or --full: the paper's runs take at most
   !> 160,000 steps; the two that need tens of millions here stop at it and say where
   integer(i8), parameter :: default_table_budget = 200000_i8
   !> Timing runs for the medians unless --repeats (table: its runs are 0.1 s each, and
   !> the main job stays within seconds)
   integer, parameter :: default_repeats = 5, default_table_repeats = 3
   !> Step budget of a vdp run (and its reference run) unless --budget
   integer(i8), parameter :: default_vdp_budget = 10000000_i8
   !> Step budget per run of accuracy unless --budget (the accuracy suite's)
   integer(i8), parameter :: default_accuracy_budget = 20000_i8
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
      !> Timing repetitions for the median (--repeats); 0 until given
      integer :: repeats = 0
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
      character(len=17), allocatable :: problems(:)
      real(dp), allocatable :: tols(:)
      real(dp) :: min_time = 0.2_dp
      character(len=:), allocatable :: refs_dir, csv_file
      !> ensemble: members and threads (0: as many as OpenMP gives)
      integer :: members = 64, threads = 0
   end type request_type

contains

   !> Every command-line argument, padded to a common length, and its own length (so
   !> that trailing blanks are kept: `--history "h.csv "` named h.csv).
   subroutine read_arguments(args, lengths)
      character(len=:), allocatable, intent(out) :: args(:)
      integer, allocatable, intent(out) :: lengths(:)
      integer :: i, longest
      allocate (lengths(command_argument_count()))
      longest = 1
      do i = 1, command_argument_count()
         call get_command_argument(i, length=lengths(i))
         longest = max(longest, lengths(i))
      end do
      allocate (character(len=longest) :: args(command_argument_count()))
      do i = 1, command_argument_count()
         call get_command_argument(i, args(i))
      end do
   end subroutine read_arguments

   !> Parse the arguments (without the program name) into a request; stat says what is
   !> wrong in words a user understands.
   subroutine parse_command_line(args, request, stat, lengths)
      character(len=*), intent(in) :: args(:)
      type(request_type), intent(out) :: request
      type(status_type), intent(out) :: stat
      !> Each argument's own length (read_arguments'); without it trailing blanks are dropped
      integer, intent(in), optional :: lengths(:)
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
         arg = argument(1)
         if (arg == "help") then
            request%help = .true.
            request%command = ""
            if (size(args) >= 2) request%command = argument(2)
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
      if (request%command == "accuracy") then
         request%schemes = scheme_names
         request%problems = accuracy_case_names
         request%budget = default_accuracy_budget
      end if
      if (request%command == "bench") then
         request%options%error_estimate = estimate_auto
         request%schemes = [character(len=16) :: "si-t-2", "i-t-2", "radau5"]
         request%problems = [character(len=17) :: "vdp-paper", "vdp1e3_wp", "vdp1e3_up", "rober40", "rober1e11", &
            "hires", "orego", "e5", "bruss32", "bruss512"]
         request%tol_high = 1.0e-3_dp
      end if

      do while (i <= size(args))
         arg = argument(i)
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
         value = argument(i)
         i = i + 1
         if (.not. parse_option(request, arg, value, stat)) return
      end do
      if (request%full .and. request%budget /= 0) then
         call set_status(stat, status_invalid_argument, "--full runs without a budget: drop --budget or --full")
         return
      end if
      if (request%budget == 0) then
         select case (request%command)
         case ("vdp"); request%budget = default_vdp_budget
         case ("table"); request%budget = default_table_budget
         case default; request%budget = default_budget
         end select
      end if
      if (request%repeats == 0) request%repeats = merge(default_table_repeats, default_repeats, request%command == "table")
      request%tols = [(request%tol_high/10.0_dp**i, i = 0, nint(log10(request%tol_high/request%tol_low)))]
      stat%code = status_ok

   contains

      !> Argument k as given (with its trailing blanks when the lengths are known)
      function argument(k) result(text)
         integer, intent(in) :: k
         character(len=:), allocatable :: text
         if (present(lengths)) then
            text = args(k)(:lengths(k))
         else
            text = trim(args(k))
         end if
      end function argument

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
         if (.not. allowed(request, option, ["table   ", "sweep   ", "bench   ", "vdp     ", "accuracy"], stat)) &
            return
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
         if (.not. allowed(request, option, ["sweep   ", "bench   ", "accuracy"], stat)) return
         if (.not. split_names(value, scheme_names, "scheme", request%schemes, stat)) return
      case ("--tols")
         if (.not. allowed(request, option, ["sweep   ", "bench   ", "accuracy"], stat)) return
         if (.not. tolerance_range(value, request%tol_high, request%tol_low, stat)) return
      case ("--grid")
         if (.not. allowed(request, option, ["stability"], stat)) return
         if (.not. read_count(option, value, 3_i8, int(max_grid, i8), "points", count, stat)) return
         request%grid = int(count)
      case ("--problems")
         if (.not. allowed(request, option, ["bench   ", "accuracy"], stat)) return
         if (request%command == "accuracy") then
            if (.not. split_names(value, accuracy_case_names, "problem", request%problems, stat)) return
         else
            if (.not. split_names(value, bench_problem_names, "problem", request%problems, stat)) return
         end if
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

   !> Whether name is a scheme (else stat lists the schemes).
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

   !> A finite number > 0, written strictly (see is_number).
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
      character(len=*), allocatable, intent(inout) :: names(:)
      type(status_type), intent(inout) :: stat
      integer :: start, comma, finish
      character(len=len(names)), allocatable :: parsed(:)
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
         parsed = [character(len=len(names)) :: parsed, text(start:finish)]
         if (comma == 0) exit
         start = start + comma
      end do
      names = parsed
      split_names = .true.
   end function split_names

   !> --tols HIGH:LOW: 1 > HIGH >= LOW > 0, at most max_decades decades apart.
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

end module app_cli
