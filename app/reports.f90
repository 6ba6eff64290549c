!> The checks and sweeps of the taylorode app: `sweep` (error against CPU time over
!> decades of tolerance), `stability` (stability functions against real steps, S1
!> regions, L-stability), `extreme` (stiff and extreme cases and bad input, one
!> pass/fail line each) and `accuracy` (the accuracy each scheme achieves against the
!> tolerance on the test set).
module app_reports
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   use taylorode, only: dp, i8, status_type, status_ok, status_invalid_argument, status_nonfinite, &
      status_max_steps, status_unknown_scheme, status_name, scheme_type, new_scheme, scheme_names, scheme_count, &
      integrator_options_type, paper_options, integrate, integration_stats_type
   use taylorode_testset, only: test_problem_type, new_test_problem, van_der_pol_type, new_van_der_pol, &
      vdp_split_paper, vdp_ic_unprepared, robertson_type, new_robertson, hires_type, new_hires
   use taylorode_analysis, only: reference_run, tolerance_scale, work_precision_config_type, &
      work_precision_point_type, work_precision, step_stability, s1_supremum, s1_axis_crossings, &
      accuracy_case_type, accuracy_point_type, new_accuracy_case, accuracy_reference, accuracy_run
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, format_number, &
      pad, choose
   use app_cli, only: request_type
   use app_output, only: table_type, checks_failed, say, progress, new_table, add_row, error_text, status_word
   implicit none
   private

   public :: run_sweep, run_stability, run_extreme, run_accuracy

   !> Global error, in the integrator's own weights, that the extreme cases accept: the
   !> number of accepted steps N, at least 100. Error per step control keeps each local
   !> error within the weights, and N of them add up to at most about N where the
   !> problem does not amplify errors (stiff decay usually damps them far below that).
   real(dp), parameter :: accuracy_bound_least = 100.0_dp

contains

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

   !> taylorode accuracy: every scheme asked for on every problem asked for, at rtol from
   !> tol_high down to tol_low by decades: log10 of the error in tolerance units at t_end
   !> and on the output grid (taylorode_analysis_accuracy), a table per problem, and per
   !> scheme the worst over the problems at each tolerance (what the README quotes).
   subroutine run_accuracy(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), allocatable, intent(inout) :: tables(:)
      type(status_type), intent(out) :: stat
      type(accuracy_case_type) :: case
      type(accuracy_point_type) :: point
      real(dp), allocatable :: tols(:), worst_end(:, :), worst_grid(:, :)
      integer, allocatable :: failed(:, :)
      integer :: p, s, k, decades, table
      character(len=:), allocatable :: line

      decades = nint(log10(request%tol_high/request%tol_low)) + 1
      tols = [(request%tol_high/10.0_dp**k, k=0, decades - 1)]
      allocate (worst_end(size(request%schemes), decades), source=-huge(1.0_dp))
      allocate (worst_grid, mold=worst_end)
      worst_grid = -huge(1.0_dp)
      allocate (failed(size(request%schemes), decades), source=0)
      table = new_table(tables, "accuracy.csv", "problem,scheme,tol,status,accepted,rejected,error_end,error_grid,"// &
         "t_worst")
      call say("accuracy against the tolerance: log10 of max |u - ref| / (atol + rtol |ref|), at t_end / the "// &
         "largest on the output grid")
      call say("(rtol = tol, atol = tol times the problem's atol/rtol; reference radau5 at 1e-12; a failure: the "// &
         "status, budget: the "//format_count(request%budget)//" attempted steps per run ran out, refused: the"// &
         " scheme does not take the problem, as radau5 alone takes mass matrices)")
      line = pad("", -13)
      do k = 1, decades
         line = line//pad(format_real(tols(k), 0), 13)
      end do
      do p = 1, size(request%problems)
         call progress("accuracy: "//trim(request%problems(p)))
         call new_accuracy_case(trim(request%problems(p)), case, stat)
         if (stat%code /= status_ok) return
         call accuracy_reference(case, stat)
         if (stat%code /= status_ok) then
            stat%message = "accuracy: the reference run of "//case%name//" failed: "//stat%message
            return
         end if
         call say("")
         call say(case%name//": "//format_integer(size(case%t_out))//" output times")
         call say(line)
         do s = 1, size(request%schemes)
            line = pad(trim(request%schemes(s)), -13)
            do k = 1, decades
               call accuracy_run(case, trim(request%schemes(s)), tols(k), request%budget, point)
               line = line//pad(point_text(point), 13)
               call add_row(tables(table), case%name//","//trim(point%scheme)//","//format_real(point%tol, 0)// &
                  ","//status_word(point%status)//","//format_integer(point%accepted)//","// &
                  format_integer(point%rejected)//","//error_text(point%error_end)//","// &
                  error_text(point%error_grid)//","//format_number(point%t_worst))
               ! a refusal (the scheme does not take this problem: a mass matrix) is no failure
               if (point%status == status_ok) then
                  worst_end(s, k) = max(worst_end(s, k), point%error_end)
                  worst_grid(s, k) = max(worst_grid(s, k), point%error_grid)
               else if (point%status /= status_invalid_argument) then
                  failed(s, k) = failed(s, k) + 1
               end if
            end do
            call say(line)
            line = pad("", -13)
            do k = 1, decades
               line = line//pad(format_real(tols(k), 0), 13)
            end do
         end do
      end do
      call say("")
      call say("worst over the problems (log10 at t_end / on the grid; failed runs, which say so, counted)")
      call say(line)
      do s = 1, size(request%schemes)
         line = pad(trim(request%schemes(s)), -13)
         do k = 1, decades
            line = line//pad(worst_text(worst_end(s, k), worst_grid(s, k), failed(s, k)), 13)
         end do
         call say(line)
      end do
      stat%code = status_ok
   contains
      !> "end/grid" in log10, or what stopped a failed run ("budget": the step budget)
      function point_text(point) result(text)
         type(accuracy_point_type), intent(in) :: point
         character(len=:), allocatable :: text
         if (point%status == status_max_steps) then
            text = "budget"
         else if (point%status == status_invalid_argument) then
            text = "refused"
         else if (point%status /= status_ok) then
            text = status_word(point%status)
            if (len(text) > 12) text = text(:12)
         else
            text = log_text(point%error_end)//"/"//log_text(point%error_grid)
         end if
      end function point_text
      !> the worst end/grid and the number of failed runs
      function worst_text(worst_end, worst_grid, failures) result(text)
         real(dp), intent(in) :: worst_end, worst_grid
         integer, intent(in) :: failures
         character(len=:), allocatable :: text
         text = log_text(worst_end)//"/"//log_text(worst_grid)
         if (failures > 0) text = text//" "//format_integer(failures)//"f"
      end function worst_text
      !> log10 of an error in tolerance units, one decimal ("-" when none)
      function log_text(error) result(text)
         real(dp), intent(in) :: error
         character(len=:), allocatable :: text
         if (error < 0.0_dp) then
            text = "-"
         else
            text = format_fixed(log10(max(error, 1.0e-3_dp)), 1)
         end if
      end function log_text
   end subroutine run_accuracy

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

   !> An axis crossing of an S1 region, marked when it lies on the edge of the grid.
   pure function crossing(x, limit) result(text)
      real(dp), intent(in) :: x, limit
      character(len=:), allocatable :: text
      text = format_fixed(x, 4)
      if (x == limit) text = text//" (edge of the grid)"
   end function crossing

end module app_reports
