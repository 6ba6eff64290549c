!> The command line of the taylorode app: parsing into a request, with a readable
!> message for every mistake, and the help texts. No I/O happens here: the app
!> prints what these procedures return.
module app_cli
   use taylorode, only: dp, i8, status_type, status_ok, integrator_options_type, paper_options, norm_max, norm_rms, &
      controller_i, controller_pi, controller_pid, scheme_names
   use taylorode_base_status, only: set_status, status_invalid_argument
   use taylorode_testset, only: test_problem_names, vdp_split_paper, vdp_split_stiff
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: cli_request_type, parse_command_line, help_text, command_names

   !> Subcommands of the app
   character(len=*), parameter :: command_names(6) = [character(len=9) :: &
      "table", "vdp", "sweep", "stability", "extreme", "bench"]

   !> Options that take a value
   character(len=*), parameter :: valued_options(21) = [character(len=12) :: "--out", "--scheme", "--ic", &
      "--mu", "--tend", "--split", "--rtol", "--atol", "--norm", "--controller", "--h0", "--hmax", &
      "--history", "--dense", "--budget", "--repeats", "--problem", "--schemes", "--tols", "--grid", &
      "--max-points"]

   !> Step budget of a table run unless --full or --budget
   integer(i8), parameter :: default_budget = 2000000_i8

   !> What the user asked for
   type :: cli_request_type
      !> Subcommand ("table" when none is given)
      character(len=:), allocatable :: command
      !> --help was given
      logical :: help = .false.
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
      !> table and sweep: step budget per run (--budget)
      integer(i8) :: budget = default_budget
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
      !> bench: largest Brusselator size (--max-points)
      integer :: max_points = 100000
   end type cli_request_type

contains

   !> Parse the arguments (without the program name) into a request. On failure
   !> stat says what is wrong in words a user understands.
   subroutine parse_command_line(args, request, stat)
      !> Command-line arguments, one per element (trailing blanks ignored)
      character(len=*), intent(in) :: args(:)
      !> The parsed request
      type(cli_request_type), intent(out) :: request
      !> status_invalid_argument with a message on a mistake
      type(status_type), intent(out) :: stat

      integer :: i
      character(len=:), allocatable :: arg, value

      request%command = "table"
      request%options = paper_options()
      request%scheme = "i-t-2"
      request%problem = "vdp"
      request%schemes = [character(len=16) :: "si-t-1", "si-t-2", "i-t-1", "i-t-2", "radau5"]
      i = 1
      if (size(args) >= 1) then
         arg = trim(args(1))
         if (arg(1:min(1, len(arg))) /= "-") then
            if (.not. any(command_names == arg)) then
               call fail('unknown command "'//arg//'"; commands: '//join(command_names))
               return
            end if
            request%command = arg
            i = 2
         end if
      end if
      if (request%command == "sweep") request%schemes = [character(len=16) :: &
         "si-t-1", "si-t-2", "i-t-1", "i-t-2", "imex-rk21", "radau5"]

      do while (i <= size(args))
         arg = trim(args(i))
         i = i + 1
         select case (arg)
         case ("-h", "--help")
            request%help = .true.
            cycle
         case ("--force")
            request%force = .true.
            cycle
         case ("--full")
            if (.not. allowed("table")) return
            request%full = .true.
            cycle
         case ("--no-reuse")
            if (.not. allowed("vdp")) return
            request%options%reuse_newton_matrix = .false.
            cycle
         case ("--quick")
            if (.not. allowed("extreme")) return
            request%quick = .true.
            cycle
         end select
         if (arg(1:min(2, len(arg))) /= "--") then
            call fail('unexpected argument "'//arg//'" (options start with --)')
            return
         end if
         if (.not. any(valued_options == arg)) then
            call fail('unknown option "'//arg//'" for '//request%command//" (see --help)")
            return
         end if
         if (i > size(args)) then
            call fail("option "//arg//" needs a value")
            return
         end if
         value = trim(args(i))
         i = i + 1
         select case (arg)
         case ("--out")
            request%out_dir = value
         case ("--scheme")
            if (.not. allowed("vdp")) return
            if (.not. known_scheme(value)) return
            request%scheme = value
         case ("--ic")
            if (.not. allowed("vdp")) return
            select case (value)
            case ("1"); request%ic = 1
            case ("2"); request%ic = 2
            case default
               call fail("--ic must be 1 (well prepared) or 2 (unprepared), got "//value); return
            end select
         case ("--mu")
            if (.not. allowed("vdp")) return
            if (.not. positive_real(arg, value, request%mu)) return
         case ("--tend")
            if (.not. allowed("vdp")) return
            if (.not. positive_real(arg, value, request%t_end)) return
         case ("--split")
            if (.not. allowed("vdp")) return
            select case (value)
            case ("paper"); request%splitting = vdp_split_paper
            case ("stiff"); request%splitting = vdp_split_stiff
            case default
               call fail("--split must be paper or stiff, got "//value); return
            end select
         case ("--rtol")
            if (.not. allowed("vdp")) return
            if (.not. read_real(arg, value, request%options%rtol)) return
            if (request%options%rtol < 0.0_dp) then
               call fail("--rtol must be >= 0, got "//value); return
            end if
         case ("--atol")
            if (.not. allowed("vdp")) return
            if (.not. read_real(arg, value, request%options%atol)) return
            if (request%options%atol < 0.0_dp) then
               call fail("--atol must be >= 0, got "//value); return
            end if
         case ("--norm")
            if (.not. allowed("vdp")) return
            select case (value)
            case ("max"); request%options%norm = norm_max
            case ("rms"); request%options%norm = norm_rms
            case default
               call fail("--norm must be max or rms, got "//value); return
            end select
         case ("--controller")
            if (.not. allowed("vdp")) return
            select case (value)
            case ("i"); request%options%controller = controller_i
            case ("pi"); request%options%controller = controller_pi
            case ("pid"); request%options%controller = controller_pid
            case default
               call fail("--controller must be i, pi or pid, got "//value); return
            end select
         case ("--h0")
            if (.not. allowed("vdp")) return
            if (.not. positive_real(arg, value, request%options%h0)) return
         case ("--hmax")
            if (.not. allowed("vdp")) return
            if (.not. positive_real(arg, value, request%options%h_max)) return
         case ("--history")
            if (.not. allowed("vdp")) return
            request%history_file = value
         case ("--dense")
            if (.not. allowed("vdp")) return
            if (.not. read_integer(arg, value, request%dense_points)) return
            if (request%dense_points < 2) then
               call fail("--dense needs at least 2 points, got "//value); return
            end if
         case ("--budget")
            if (.not. (allowed("table", "sweep", "bench"))) return
            if (.not. read_integer8(arg, value, request%budget)) return
            if (request%budget < 1) then
               call fail("--budget must be at least 1, got "//value); return
            end if
         case ("--repeats")
            if (.not. read_integer(arg, value, request%repeats)) return
            if (request%repeats < 1) then
               call fail("--repeats must be at least 1, got "//value); return
            end if
         case ("--problem")
            if (.not. allowed("sweep")) return
            if (.not. any(test_problem_names == value)) then
               call fail('unknown problem "'//value//'"; problems: '//join(test_problem_names)); return
            end if
            request%problem = value
         case ("--schemes")
            if (.not. allowed("sweep")) return
            if (.not. split_schemes(value, request%schemes)) return
         case ("--tols")
            if (.not. allowed("sweep")) return
            if (.not. tolerance_range(value, request%tol_high, request%tol_low)) return
         case ("--grid")
            if (.not. allowed("stability")) return
            if (.not. read_integer(arg, value, request%grid)) return
            if (request%grid < 3) then
               call fail("--grid needs at least 3 points, got "//value); return
            end if
         case ("--max-points")
            if (.not. allowed("bench")) return
            if (.not. read_integer(arg, value, request%max_points)) return
            if (request%max_points < 1000) then
               call fail("--max-points must be at least 1000, got "//value); return
            end if
         case default
            call fail('unknown option "'//arg//'" for '//request%command//" (see --help)")
            return
         end select
      end do
      if (request%command == "vdp" .and. request%options%rtol == 0.0_dp .and. request%options%atol == 0.0_dp) then
         call fail("--rtol and --atol cannot both be 0")
         return
      end if
      stat%code = status_ok

   contains

      subroutine fail(message)
         character(len=*), intent(in) :: message
         call set_status(stat, status_invalid_argument, message)
      end subroutine fail

      !> The current option belongs to one of these commands.
      logical function allowed(command, other, third)
         character(len=*), intent(in) :: command
         character(len=*), intent(in), optional :: other, third
         allowed = request%command == command
         if (present(other)) allowed = allowed .or. request%command == other
         if (present(third)) allowed = allowed .or. request%command == third
         if (.not. allowed) call fail("option "//arg//" does not apply to "//request%command//" (see --help)")
      end function allowed

      logical function known_scheme(name)
         character(len=*), intent(in) :: name
         known_scheme = any(scheme_names == name)
         if (.not. known_scheme) call fail('unknown scheme "'//name//'"; schemes: '//join(scheme_names))
      end function known_scheme

      logical function read_real(option, text, x)
         character(len=*), intent(in) :: option, text
         real(dp), intent(inout) :: x
         integer :: io
         real(dp) :: parsed
         read (text, *, iostat=io) parsed
         read_real = io == 0 .and. verify(text, "0123456789+-.eEdD") == 0
         if (read_real) read_real = ieee_is_finite(parsed)
         if (read_real) then
            x = parsed
         else
            call fail(option//" needs a number, got "//text)
         end if
      end function read_real

      logical function positive_real(option, text, x)
         character(len=*), intent(in) :: option, text
         real(dp), intent(inout) :: x
         positive_real = read_real(option, text, x)
         if (.not. positive_real) return
         positive_real = x > 0.0_dp
         if (.not. positive_real) call fail(option//" must be positive, got "//text)
      end function positive_real

      logical function read_integer(option, text, k)
         character(len=*), intent(in) :: option, text
         integer, intent(inout) :: k
         integer :: io, parsed
         read (text, *, iostat=io) parsed
         read_integer = io == 0 .and. verify(text, "0123456789+-") == 0
         if (read_integer) then
            k = parsed
         else
            call fail(option//" needs a whole number, got "//text)
         end if
      end function read_integer

      logical function read_integer8(option, text, k)
         character(len=*), intent(in) :: option, text
         integer(i8), intent(inout) :: k
         integer :: io
         integer(i8) :: parsed
         read (text, *, iostat=io) parsed
         read_integer8 = io == 0 .and. verify(text, "0123456789+-") == 0
         if (read_integer8) then
            k = parsed
         else
            call fail(option//" needs a whole number, got "//text)
         end if
      end function read_integer8

      logical function split_schemes(text, names)
         character(len=*), intent(in) :: text
         character(len=16), allocatable, intent(inout) :: names(:)
         integer :: start, comma
         character(len=16), allocatable :: parsed(:)
         allocate (parsed(0))
         start = 1
         split_schemes = .false.
         do
            comma = index(text(start:), ",")
            if (comma == 0) then
               if (.not. known_scheme(text(start:))) return
               parsed = [character(len=16) :: parsed, text(start:)]
               exit
            end if
            if (.not. known_scheme(text(start:start + comma - 2))) return
            parsed = [character(len=16) :: parsed, text(start:start + comma - 2)]
            start = start + comma
         end do
         names = parsed
         split_schemes = .true.
      end function split_schemes

      logical function tolerance_range(text, high, low)
         character(len=*), intent(in) :: text
         real(dp), intent(inout) :: high, low
         integer :: colon
         tolerance_range = .false.
         colon = index(text, ":")
         if (colon <= 1 .or. colon == len(text)) then
            call fail("--tols takes HIGH:LOW, e.g. 1e-2:1e-8, got "//text); return
         end if
         if (.not. read_real("--tols", text(:colon - 1), high)) return
         if (.not. read_real("--tols", text(colon + 1:), low)) return
         if (.not. (high > 0.0_dp .and. low > 0.0_dp .and. low <= high .and. high < 1.0_dp)) then
            call fail("--tols needs 1 > HIGH >= LOW > 0, got "//text); return
         end if
         tolerance_range = .true.
      end function tolerance_range

   end subroutine parse_command_line

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

   !> Help of a command ("" for the overview), lines separated by new_line.
   function help_text(command) result(text)
      !> Subcommand, or "" for the overview
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
            "  --h0 H --hmax H    first and largest step (default 1e-2 and none)"//nl// &
            "  --no-reuse         factor the Newton matrix in every solve (default: keep it across steps)"//nl// &
            "  --history FILE.csv write every attempted step (refuses to overwrite without --force)"//nl// &
            "  --dense N          error on an N-point grid against radau5 at 1e-12 (default 301)"
      case ("table")
         text = "taylorode table: the paper's Table 1 (Van der Pol mu = 1000, t in [0, 3000]) reproduced"//nl// &
            "  every scheme of the paper, both initial conditions, plus si-t-2, radau5 and the stiff"//nl// &
            "  splitting; paper's step counts and CPU seconds beside ours"//nl// &
            "  --budget N    step budget per run (default 2000000); capped runs say how far they got"//nl// &
            "  --full        no budget: si-t-2-paper and imex-rk21 need ~50 million steps each"//nl// &
            "  --repeats N   timing runs for the median (default 5, runs over 1 s once)"//nl// &
            "  --out DIR     also write DIR/table1.csv (--force to overwrite)"
      case ("sweep")
         text = "taylorode sweep: error against CPU time (work-precision) over a range of tolerances"//nl// &
            "  --problem P   one of "//join(test_problem_names)//" (default vdp)"//nl// &
            "  --schemes A,B,...  schemes to compare (default si-t-1,si-t-2,i-t-1,i-t-2,imex-rk21,radau5)"//nl// &
            "  --tols HIGH:LOW    rtol = atol from HIGH down to LOW by decades (default 1e-2:1e-8)"//nl// &
            "  --budget N    step budget per run (default 2000000)"//nl// &
            "  --repeats N   timing runs for the median (default 5)"//nl// &
            "  --out DIR     also write DIR/sweep.csv (--force to overwrite)"
      case ("stability")
         text = "taylorode stability: stability functions checked against real steps, S1 regions, L-stability"//nl// &
            "  --grid N      points per axis of the S1 grid on [-3, 1] x [-2, 2] (default 161)"//nl// &
            "  --out DIR     also write DIR/stability_check.csv, DIR/s1_regions.csv, DIR/l_stability.csv"
      case ("extreme")
         text = "taylorode extreme: stiff and extreme cases, one pass/fail line each with its figure"//nl// &
            "  Van der Pol mu = 1e6, Robertson to 1e11, w = -1e12, tolerances 1e-2 and 1e-10,"//nl// &
            "  unprepared initial data and deliberately bad input; exit status 1 if any fails"//nl// &
            "  --quick       smaller cases: Van der Pol mu = 1e4, HIRES at 1e-8 instead of 1e-10"//nl// &
            "  --out DIR     also write DIR/extreme.csv"
      case ("bench")
         text = "taylorode bench: time per step (run with --profile release)"//nl// &
            "  Van der Pol mu = 1000 with every scheme (paper settings) and the Brusselator with"//nl// &
            "  N = 100 ... --max-points (default 100000) on the banded path"//nl// &
            "  --budget N    step budget of the Van der Pol runs (default 2000000)"//nl// &
            "  --repeats N   timing runs for the median (default 5)"//nl// &
            "  --out DIR     also write DIR/bench.csv"
      case default
         text = "taylorode: one-step Taylor schemes for stiff ODEs U' = f(U) + g(U)"//nl// &
            "usage: taylorode [COMMAND] [OPTIONS]     (no command: table)"//nl// &
            "  table      the paper's Table 1 reproduced (the main job)"//nl// &
            "  vdp        one Van der Pol run with a summary and optional step history"//nl// &
            "  sweep      error against run time over tolerances"//nl// &
            "  stability  stability functions, S1 regions and L-stability"//nl// &
            "  extreme    stiff and extreme cases, pass/fail"//nl// &
            "  bench      time per step and its growth with problem size"//nl// &
            "taylorode COMMAND --help describes each command."
      end select
   end function help_text

end module app_cli
