!> The timing commands of the taylorode app: `bench` (work at equal accuracy on the
!> peer solvers' problems, with their split, data, output times and error measure) and
!> `ensemble` (a Van der Pol sweep on one thread and on several).
module app_bench
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   use taylorode, only: dp, i8, status_type, status_ok, status_invalid_argument, status_max_steps, scheme_type, &
      new_scheme, integrator_options_type, paper_options, norm_rms, estimate_embedded, estimate_doubling, &
      estimate_defect, integrate, integration_stats_type
   use taylorode_testset, only: test_problem_type, van_der_pol_type, new_van_der_pol, vdp_split_paper, &
      vdp_ic_unprepared, vdp_ic_prepared, van_der_pol_initial_state, new_robertson, new_hires, &
      hires_split_reaction_stiff, new_orego, orego_split_bilinear_stiff, new_e5, new_brusselator
   use taylorode_analysis, only: reference_run, ensemble_timing_type, time_ensemble
   use taylorode_base_status, only: set_status
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, pad, choose
   use app_cli, only: request_type, ensemble_t_end, bench_problem_names, join
   use app_output, only: text_type, checks_failed, say, progress, write_csv, error_text, status_word
   implicit none
   private

   public :: run_bench, run_ensemble

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

contains

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
         "Jacobians, products J v, LU factorizations, linear solves")
      call say(pad("problem", -10)//pad("scheme", -10)//pad("tol", 7)//"  "//pad("status", -8)//pad("steps", 11)// &
         pad("rej", 10)//pad("F/step", 8)//pad("J/step", 8)//pad("Jv/step", 8)//pad("LU/step", 8)// &
         pad("sol/step", 9)// &
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
         "err_end,err_grid", csv_rows(:rows), request%force, stat)
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
            pad(format_fixed(real(work%jacobian_products, dp)/steps, 2), 8)// &
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

end module app_bench
