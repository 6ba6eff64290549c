!> The help texts of the taylorode app: the overview and one text per command.
module app_help
   use taylorode, only: scheme_names
   use taylorode_testset, only: test_problem_names
   use taylorode_analysis, only: accuracy_case_names
   use taylorode_base_strings, only: format_count, format_fixed, format_integer
   use app_cli, only: version, default_budget, default_table_budget, default_vdp_budget, default_accuracy_budget, &
      default_repeats, default_table_repeats, ensemble_t_end, bench_problem_names, join
   implicit none
   private

   public :: help_text

contains

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
            "  --budget N    step budget per run (default "//format_count(default_table_budget)// &
            "); capped runs say how far they got"//nl// &
            "  --full        no budget: si-t-2-paper and imex-rk21 need ~50 million steps each"//nl// &
            "  --repeats N   timing runs for the median (default "//format_integer(default_table_repeats)// &
            ", runs over 1 s once)"//nl// &
            "  --out DIR     also write DIR/table1.csv (--force to overwrite)"
      case ("accuracy")
         text = "taylorode accuracy: the accuracy each scheme achieves against the tolerance on the test set"//nl// &
            "  every scheme on every problem at rtol = tol from HIGH down to LOW by decades (atol = tol times"//nl// &
            "  the problem's atol/rtol, concentrations nonnegative); error in the tolerance's own units,"//nl// &
            "  max |u - ref| / (atol + rtol |ref|), at t_end and the largest on the output grid (dense"//nl// &
            "  output), against radau5 at 1e-12 stepping to each output time; log10 of it in the table"//nl// &
            "  --problems A,B,...  of "//join(accuracy_case_names)//" (default all)"//nl// &
            "  --schemes A,B,...   default all"//nl// &
            "  --tols HIGH:LOW     default 1e-2:1e-8"//nl// &
            "  --budget N    attempted steps per run (default "//format_count(default_accuracy_budget)//")"//nl// &
            "  --out DIR     also write DIR/accuracy.csv (--force to overwrite)"
      case ("sweep")
         text = "taylorode sweep: error against CPU time (work-precision) over a range of tolerances"//nl// &
            "  --problem P   one of "//join(test_problem_names)//" (default vdp)"//nl// &
            "  --schemes A,B,...  schemes to compare (default si-t-1,si-t-2,i-t-1,i-t-2,imex-rk21,radau5)"//nl// &
            "  --tols HIGH:LOW    rtol = atol from HIGH down to LOW by decades (default 1e-2:1e-8)"//nl// &
            "  --budget N    step budget per run (default "//format_count(default_budget)//")"//nl// &
            "  --repeats N   timing runs for the median (default "//format_integer(default_repeats)//")"//nl// &
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
            "  settings, tol ignored). Per run: steps, F (= f + g), Jacobian, product J v, LU and"//nl// &
            "  solve counts per step, CPU seconds (mean of repeats until --min-time), microseconds"//nl// &
            "  per step, error at t_end and on the output grid against the reference."//nl// &
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
            "  --repeats N   runs of each kind for the medians (default "//format_integer(default_repeats)//")"
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
            "  accuracy   the accuracy each scheme achieves against the tolerance, test set wide"//nl// &
            "taylorode COMMAND --help (or taylorode help COMMAND) describes each command;"//nl// &
            "taylorode --version prints the version. Exit status: 0 success, 1 a run or check"//nl// &
            "failed or an output could not be written, 2 a mistake on the command line."
      end select
   end function help_text

end module app_help
