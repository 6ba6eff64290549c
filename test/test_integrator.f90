!> The adaptive integrator: the paper's Van der Pol experiment, tolerance
!> proportionality, controllers, failure statuses, dense output and step history.
module test_integrator
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode_base_strings, only: format_integer, format_real
   use test_support, only: rk4_reference, stat_message
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, &
      vdp_ic_prepared, vdp_ic_unprepared, linear_test_type, new_linear_test, brusselator_type, new_brusselator, &
      orego_type, new_orego, hires_type, new_hires
   use taylorode, only: dp, i8, ode_problem, scheme_type, status_type, new_scheme, integrate, scheme_names, scheme_count, &
      integrator_options_type, integration_stats_type, paper_options, controller_pi, controller_pid, &
      norm_rms, advance_low, step_history_type, write_history_csv, estimate_embedded, estimate_doubling, estimate_defect, &
      attempt_accepted, status_ok, status_invalid_argument, status_size_mismatch, status_nonfinite, &
      status_max_steps, status_step_underflow, status_newton_not_converged, status_singular_matrix, &
      step_observer_type, accepted_step_type, integrator_type
   use taylorode_newton_solver, only: newton_solver_type, nonlinear_system_type, newton_settings_type
   use taylorode_linalg_matrix, only: matrix_type, dense_matrix_type, dense_structure
   use taylorode_base_counters, only: counters_type
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: collect_integrator

   !> Reference values at t = 3000 (METHODS.md section 5)
   real(dp), parameter :: vdp_reference(2, 2) = reshape([ &
      -1.5102139907362793_dp, 1.1791653311113964e-3_dp, &
      -1.5106069367443018_dp, 1.1783800007305336e-3_dp], [2, 2])
   !> Accepted steps of a faithful implementation of the paper's settings
   !> (METHODS.md section 5), by scheme (i-t-1, i-t-2) and initial condition
   integer, parameter :: vdp_accepted(2, 2) = reshape([125756, 125748, 125360, 125357], [2, 2])
   !> Allowed relative deviation of the step counts
   real(dp), parameter :: step_count_tolerance = 0.005_dp

   !> A problem all in g: f = 0 and df/du = 0
   type, abstract, extends(ode_problem) :: stiff_only_problem
   contains
      procedure :: f => zero_f
      procedure :: jac_f => zero_jac
   end type stiff_only_problem

   !> g = u / t: at the end of a step from t = 0 the i-t-1 Newton matrix 1 - h/h is
   !> exactly singular for every power-of-two step size
   type, extends(stiff_only_problem) :: singular_problem
   contains
      procedure :: g => singular_g
      procedure :: jac_g => singular_jac_g
   end type singular_problem

   !> OREGO whose J v is J from `jac` times v, column by column (what the default
   !> add_jacobian_product does), in place of OREGO's own product
   type, extends(orego_type) :: orego_matrix_product
   contains
      procedure :: add_jacobian_product => matrix_product
   end type orego_matrix_product

   !> u' = -1e4 u^3 (all in g): the implicit stage equation of a long step, u + c u^3 =
   !> u0 with c ~ 1e4 h, makes Newton from u0 crawl (a simplified Newton iteration with
   !> the Jacobian at u0 contracts like 1 - 1 / (3 c u0^2)): it converges only once h is
   !> below about 1e-4
   type, extends(stiff_only_problem) :: cubic_decay_problem
   contains
      procedure :: g => cubic_g
      procedure :: jac_g => cubic_jac_g
   end type cubic_decay_problem

   !> u' = u^2 (all in g), u(0) = 1: u = 1/(1 - t) blows up at t = 1
   type, extends(stiff_only_problem) :: blow_up_type
   contains
      procedure :: g => blow_up_g
      procedure :: jac_g => blow_up_jac_g
   end type blow_up_type

   !> u' = -rate u (all in g)
   type, extends(stiff_only_problem) :: linear_decay_problem
      real(dp) :: rate = 1.0_dp
   contains
      procedure :: g => linear_decay_g
      procedure :: jac_g => linear_decay_jac_g
   end type linear_decay_problem

   !> (1 + h + h^2/2) u = 1 for h = 1e17, its Newton matrix stacked as i-t-2's was before
   !> the row scaling of the stacked matrices: [[1 + h, -h/2], [h, 1]], whose LU (the
   !> first row the pivot, 1 + h rounding to h) solves for a correction that cancels to
   !> exactly 0
   type, extends(nonlinear_system_type) :: cancelling_system
      real(dp) :: h = 1.0e17_dp
   contains
      procedure :: residual => cancelling_residual
      procedure :: newton_matrix => cancelling_matrix
   end type cancelling_system

   !> y' = -rate (y - cos t) - sin t (y = cos t + (y(0) - 1) exp(-rate t)): the decay in
   !> g, forced through an f of t alone (its df/du the zero of stiff_only_problem)
   type, extends(linear_decay_problem) :: forced_decay_problem
   contains
      procedure :: f => forced_decay_f
   end type forced_decay_problem

   !> u1' = lambda (u1 - 1 - u2/2), u2' = -u2 (lambda = -1e4, all in g): a stiff relaxation
   !> onto u1 = 1 + c exp(-t), c = (lambda/2)/(lambda + 1)
   type, extends(stiff_only_problem) :: relaxation_problem
      real(dp) :: lambda = -1.0e4_dp
   contains
      procedure :: g => relaxation_g
      procedure :: jac_g => relaxation_jac_g
   end type relaxation_problem

   !> The largest error of u1 at the accepted steps' ends against relaxation_problem's
   !> slow solution, in tolerances
   type, extends(step_observer_type) :: relaxation_observer
      real(dp) :: tol = 1.0e-4_dp, worst = 0.0_dp, c = 0.0_dp
   contains
      procedure :: observe => observe_relaxation
   end type relaxation_observer

   !> u' = -u + H(t - 1): the decay in g, a forcing switched on at t = 1 in f
   type, extends(linear_decay_problem) :: switched_forcing_problem
   contains
      procedure :: f => switched_forcing_f
   end type switched_forcing_problem

   !> A stiff part that returns NaN at every t > 0
   type, extends(ode_problem) :: poisoned_problem
   contains
      procedure :: f => poisoned_f
      procedure :: g => poisoned_g
      procedure :: jac_f => poisoned_jac
      procedure :: jac_g => poisoned_jac
   end type poisoned_problem

contains

   !> Collect all exported unit tests
   subroutine collect_integrator(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("paper-van-der-pol", test_paper_van_der_pol), &
         new_unittest("tolerance-proportionality", test_tolerance_proportionality), &
         new_unittest("defect-estimate", test_defect_estimate), &
         new_unittest("pi-and-pid-controllers", test_pi_pid), &
         new_unittest("advance-with-low-member", test_advance_low), &
         new_unittest("invalid-options", test_invalid_options), &
         new_unittest("maximum-steps", test_max_steps), &
         new_unittest("step-size-underflow", test_step_underflow), &
         new_unittest("first-step-far-from-zero", test_first_step_far_from_zero), &
         new_unittest("non-finite-values", test_nonfinite_values), &
         new_unittest("newton-failures", test_newton_failures), &
         new_unittest("singular-newton-repeatedly", test_singular_repeatedly), &
         new_unittest("newton-failures-retried-until-h-works", test_failures_retried), &
         new_unittest("singular-newton-limit-cumulative", test_singular_cumulative), &
         new_unittest("long-steps-keep-their-digits", test_long_steps_keep_digits), &
         new_unittest("time-keeps-up-with-the-steps", test_time_keeps_up), &
         new_unittest("target-within-roundoff-is-reached", test_target_within_roundoff), &
         new_unittest("solve-without-a-digit-is-singular", test_solve_without_a_digit_singular), &
         new_unittest("second-derivatives-at-the-state-scale", test_second_derivative_scale), &
         new_unittest("forcing-switched-on-late-in-a-step", test_switched_forcing), &
         new_unittest("explicit-steps-stay-stable", test_explicit_stability), &
         new_unittest("tiny-first-step-of-a-problem-in-t", test_tiny_first_step), &
         new_unittest("huge-newton-iteration-limit", test_huge_iteration_limit), &
         new_unittest("one-newton-iteration", test_one_newton_iteration), &
         new_unittest("newton-ends-at-components-at-zero", test_newton_at_zero_components), &
         new_unittest("steps-land-on-output-times", test_steps_land_on_outputs), &
         new_unittest("dense-output", test_dense_output), &
         new_unittest("step-history", test_step_history), &
         new_unittest("measured-times", test_measured_times), &
         new_unittest("library-defaults-on-paper-problem", test_library_defaults), &
         new_unittest("extrapolated-step-stability", test_extrapolated_stability), &
         new_unittest("i-t-2-jacobians-at-newton-matrices", test_it2_jacobians) &
         ]
   end subroutine collect_integrator

   !> The paper's literal experiment with i-t-1 and i-t-2, both initial conditions.
   subroutine test_paper_van_der_pol(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = ["i-t-1", "i-t-2"]
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2), deviation
      integer :: k, ic

      problem = new_van_der_pol(1000.0_dp)
      do k = 1, 2
         do ic = vdp_ic_prepared, vdp_ic_unprepared
            call new_scheme(names(k), scheme, stat)
            u = van_der_pol_initial_state(ic)
            call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, paper_options(), stats, stat)
            call check(error, stat%code, status_ok, names(k)//": "//stat_message(stat))
            if (allocated(error)) return
            call check(error, stats%t_reached, 3000.0_dp, "t_reached")
            if (allocated(error)) return
            deviation = abs(real(stats%accepted_steps - vdp_accepted(k, ic), dp))/vdp_accepted(k, ic)
            call check(error, deviation <= step_count_tolerance, names(k)//" IC"//format_integer(ic)// &
               ": "//format_integer(int(stats%accepted_steps))//" accepted steps, expected "//format_integer(vdp_accepted(k, ic)))
            if (allocated(error)) return
            call check(error, stats%rejected_error > 0 .and. stats%rejected_error < 100, &
               names(k)//": about 35 rejections expected, got "//format_integer(int(stats%rejected_error)))
            if (allocated(error)) return
            if (names(k) == "i-t-2") then
               ! measured: 5.2e-5 (IC1) and 5.9e-5 (IC2)
               call check(error, abs(u(1) - vdp_reference(1, ic)) < 1.0e-2_dp, &
                  "i-t-2 error in y at t = 3000")
               if (allocated(error)) return
            end if
         end do
      end do
   end subroutine test_paper_van_der_pol

   !> Van der Pol mu = 5 on [0, 2] with rtol = atol = tol from 1e-4 to 1e-7, for the
   !> error estimates of the second-order schemes. The embedded pair estimates the
   !> first-order member's error: steps grow like tol^(-1/2) and the global error
   !> comes out proportional to tol (within [0.005, 10] tol, slope in [0.8, 1.3];
   !> measured 0.6-0.7 tol for i-t-2, 0.009-0.08 tol for si-t-2, slopes 1.02 and
   !> 1.15). Step doubling estimates the error of U_{h/2,h/2}, so error per step
   !> control makes steps grow like tol^(-1/3) (slope of log steps in [0.25, 0.42];
   !> measured 0.31-0.34). Advancing with U_{h/2,h/2} the global error grows like
   !> tol^(2/3) (slope in [0.5, 1.0]; measured 0.59 and 0.93, the latter from a
   !> pre-asymptotic loosest point), within [0.1, 100] tol (measured 1.9-39); with its
   !> local extrapolation, third order, like tol (slope in [0.8, 1.3]; measured 0.95,
   !> 1.13), within [0.005, 10] tol (measured 0.38-1.7). si-t-2's estimate of its own
   !> step's error (estimate_defect, its default) controls the error of U1 alike:
   !> steps like tol^(-1/3) (measured 0.36), the error of U1 like tol^(2/3) or more
   !> (measured slope 0.89, 2.1-9.3 tol), and with the local extrapolation U1 minus
   !> the estimate like tol (measured slope 0.96, 0.92-1.6 tol), in the same bounds.
   subroutine test_tolerance_proportionality(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = ["i-t-2 ", "si-t-2"]
      character(len=*), parameter :: variants(5) = [character(len=26) :: " (embedded)", " (doubling)", &
         " (doubling, extrapolated)", " (defect)", " (defect, extrapolated)"]
      real(dp), parameter :: tolerances(4) = [1.0e-4_dp, 1.0e-5_dp, 1.0e-6_dp, 1.0e-7_dp]
      ! global error / tol, and the slope of log error against log tol, per variant
      real(dp), parameter :: low(5) = [0.005_dp, 0.1_dp, 0.005_dp, 0.1_dp, 0.005_dp], &
         high(5) = [10.0_dp, 100.0_dp, 10.0_dp, 100.0_dp, 10.0_dp]
      real(dp), parameter :: slope_low(5) = [0.8_dp, 0.5_dp, 0.8_dp, 0.5_dp, 0.8_dp], &
         slope_high(5) = [1.3_dp, 1.0_dp, 1.3_dp, 1.0_dp, 1.3_dp]
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: reference(2), u(2), errors(size(tolerances)), steps(size(tolerances)), ratio, slope, step_slope
      integer :: k, i, variant
      character(len=:), allocatable :: label

      problem = new_van_der_pol(5.0_dp)
      reference = rk4_reference(problem, [2.0_dp, 0.0_dp], 2.0_dp)
      do variant = 1, size(variants)
         do k = 1, size(names)
            label = trim(names(k))//trim(variants(variant))
            ! the defect estimate is si-t-2's own
            if (variant >= 4 .and. trim(names(k)) /= "si-t-2") cycle
            do i = 1, size(tolerances)
               call new_scheme(trim(names(k)), scheme, stat)
               options%rtol = tolerances(i)
               options%atol = tolerances(i)
               select case (variant)
               case (1); options%error_estimate = estimate_embedded
               case (2, 3); options%error_estimate = estimate_doubling
               case default; options%error_estimate = estimate_defect
               end select
               options%local_extrapolation = variant == 3 .or. variant == 5
               u = [2.0_dp, 0.0_dp]
               call integrate(problem, scheme, 0.0_dp, 2.0_dp, u, options, stats, stat)
               call check(error, stat%code, status_ok, stat_message(stat))
               if (allocated(error)) return
               errors(i) = maxval(abs(u - reference))
               steps(i) = real(stats%accepted_steps, dp)
               ratio = errors(i)/tolerances(i)
               call check(error, ratio > low(variant) .and. ratio < high(variant), label// &
                  ": global error / tol "//format_real(ratio)//" out of range at tol index "//format_integer(i))
               if (allocated(error)) return
            end do
            call check(error, all(errors(2:) < errors(:size(errors) - 1)), &
               label//": the error does not decrease with the tolerance")
            if (allocated(error)) return
            slope = log10(errors(1)/errors(size(errors)))/3.0_dp
            call check(error, slope > slope_low(variant) .and. slope < slope_high(variant), &
               label//": error against tolerance has slope "//format_real(slope))
            if (allocated(error)) return
            step_slope = log10(steps(size(steps))/steps(1))/3.0_dp
            if (variant > 1) then
               call check(error, step_slope > 0.25_dp .and. step_slope < 0.42_dp, &
                  label//": steps grow like tol^-"//format_real(step_slope)//", expected about tol^(-1/3)")
               if (allocated(error)) return
            end if
         end do
      end do
   end subroutine test_tolerance_proportionality

   !> si-t-2's own error estimate is its default: the run with estimate_auto is the
   !> run with estimate_defect, step for step and bit for bit. On the Brusselator with
   !> 32 points (rtol = atol = 1e-6) a step then costs one Newton solve and one solve of
   !> the filter (and, on the few steps where what it leaves would matter, one for the
   !> correction of the extrapolated state), against step doubling's three Newton
   !> solves: at most 3.5 linear solves per accepted step (measured 3.0) against at
   !> least 5 (measured 6.0), both within 10 tol of the reference (measured 0.4 and 1.5
   !> tol). A scheme without
   !> such an estimate (i-t-2) refuses estimate_defect with a message naming it.
   subroutine test_defect_estimate(error)
      type(error_type), allocatable, intent(out) :: error
      type(brusselator_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats_auto, stats_defect, stats_doubling
      type(status_type) :: stat
      real(dp), allocatable :: u_auto(:), u_defect(:), u_doubling(:), reference(:)
      real(dp) :: solves_defect, solves_doubling

      problem = new_brusselator(32)
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp, norm=norm_rms)
      reference = problem%u0
      call new_scheme("radau5", scheme, stat)
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, reference, &
         integrator_options_type(rtol=1.0e-12_dp, atol=1.0e-12_dp), stats_auto, stat)
      call check(error, stat%code, status_ok, "reference: "//stat_message(stat))
      if (allocated(error)) return

      call new_scheme("si-t-2", scheme, stat)
      u_auto = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u_auto, options, stats_auto, stat)
      call check(error, stat%code, status_ok, "estimate_auto: "//stat_message(stat))
      if (allocated(error)) return
      options%error_estimate = estimate_defect
      u_defect = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u_defect, options, stats_defect, stat)
      call check(error, stat%code, status_ok, "estimate_defect: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, all(u_auto == u_defect) .and. stats_auto%accepted_steps == stats_defect%accepted_steps, &
         "si-t-2 with estimate_auto is not the run with estimate_defect")
      if (allocated(error)) return
      options%error_estimate = estimate_doubling
      u_doubling = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u_doubling, options, stats_doubling, stat)
      call check(error, stat%code, status_ok, "estimate_doubling: "//stat_message(stat))
      if (allocated(error)) return
      solves_defect = real(stats_defect%work%linear_solves, dp)/real(stats_defect%accepted_steps, dp)
      solves_doubling = real(stats_doubling%work%linear_solves, dp)/real(stats_doubling%accepted_steps, dp)
      call check(error, solves_defect <= 3.5_dp .and. solves_doubling >= 5.0_dp, "linear solves per step: "// &
         format_real(solves_defect)//" with the defect estimate, "//format_real(solves_doubling)//" doubling")
      if (allocated(error)) return
      call check(error, maxval(abs(u_defect - reference)) < 1.0e-5_dp .and. &
         maxval(abs(u_doubling - reference)) < 1.0e-5_dp, "errors "//format_real(maxval(abs(u_defect - reference)))// &
         " (defect), "//format_real(maxval(abs(u_doubling - reference)))//" (doubling)")
      if (allocated(error)) return

      options%error_estimate = estimate_defect
      call new_scheme("i-t-2", scheme, stat)
      u_defect = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u_defect, options, stats_defect, stat)
      call check(error, stat%code == status_invalid_argument .and. index(stat%message, "i-t-2") > 0, &
         "i-t-2 with estimate_defect: "//stat_message(stat))
   end subroutine test_defect_estimate

   !> The paper's Van der Pol run (atol 1e-5, rtol 0) with the library's defaults
   !> otherwise: step doubling, Newton from the extrapolated state and stopped by its
   !> estimated error. i-t-2 then needs under 10,000 steps (measured 4,753; the paper's
   !> settings: 125,748) and lands within 1e-2 of the reference in y (measured 9e-4).
   !> Starting Newton from the extrapolation saves iterations against starting from
   !> U0 (measured 4.8 against 8.1 per step); the two results differ within the
   !> bound on the error, 1e-2 (measured 2e-3 in y: each solves to Newton's own
   !> tolerance, and the global errors of these runs are of that size).
   subroutine test_library_defaults(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats, stats_plain
      type(status_type) :: stat
      real(dp) :: u(2), u_plain(2)

      problem = new_van_der_pol(1000.0_dp)
      options = integrator_options_type(rtol=0.0_dp, atol=1.0e-5_dp)
      call new_scheme("i-t-2", scheme, stat)
      u = van_der_pol_initial_state(vdp_ic_prepared)
      call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%accepted_steps < 10000, "i-t-2 with the library's defaults took "// &
         format_integer(int(stats%accepted_steps))//" steps")
      if (allocated(error)) return
      call check(error, abs(u(1) - vdp_reference(1, 1)) < 1.0e-2_dp, "error in y at t = 3000: "// &
         format_real(abs(u(1) - vdp_reference(1, 1))))
      if (allocated(error)) return

      options%extrapolate_newton_start = .false.
      u_plain = van_der_pol_initial_state(vdp_ic_prepared)
      call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u_plain, options, stats_plain, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, real(stats%work%newton_iterations, dp)/real(stats%accepted_steps, dp) < &
         real(stats_plain%work%newton_iterations, dp)/real(stats_plain%accepted_steps, dp), &
         "Newton iterations per step: extrapolated start "//format_integer(int(stats%work%newton_iterations))// &
         " against "//format_integer(int(stats_plain%work%newton_iterations))//" from U0")
      if (allocated(error)) return
      call check(error, abs(u(1) - u_plain(1)) < 1.0e-2_dp, "the Newton start changes the solution by "// &
         format_real(abs(u(1) - u_plain(1))))
   end subroutine test_library_defaults

   !> i-t-2 takes J F in its residual from the problem's add_jacobian_product and
   !> evaluates J only where it builds a Newton matrix (twice: J and, for F''[F], J at
   !> U + e F): on OREGO at rtol 1e-6 that is 2 J per factorization, about 0.8 J per
   !> step (7.5 when every residual evaluated J), and one product per Newton iteration.
   !> OREGO's own product and J from `jac` times F give the same run bit for bit.
   subroutine test_it2_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      type(orego_type) :: problem
      type(orego_matrix_product) :: matrix_problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats, matrix_stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:), u_matrix(:)

      problem = new_orego()
      matrix_problem%orego_type = new_orego()
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp)
      call new_scheme("i-t-2", scheme, stat)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, problem%t_end, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%work%jac_f_evaluations, 2*stats%work%lu_factorizations, &
         "Jacobians against factorizations")
      if (allocated(error)) return
      call check(error, stats%work%jacobian_products, stats%work%newton_iterations, &
         "products against Newton iterations")
      if (allocated(error)) return
      call check(error, stats%work%jac_f_evaluations < stats%accepted_steps, "Jacobians: "// &
         format_integer(int(stats%work%jac_f_evaluations))//" in "//format_integer(int(stats%accepted_steps))//" steps")
      if (allocated(error)) return
      u_matrix = matrix_problem%u0
      call integrate(matrix_problem, scheme, 0.0_dp, matrix_problem%t_end, u_matrix, options, matrix_stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, all(u_matrix == u) .and. matrix_stats%accepted_steps == stats%accepted_steps .and. &
         matrix_stats%rejected_steps() == stats%rejected_steps() .and. &
         matrix_stats%work%newton_iterations == stats%work%newton_iterations, &
         "the run with J from jac times F differs from the run with OREGO's product")
   end subroutine test_it2_jacobians

   !> y + alpha J v with J from `jac`, column by column.
   subroutine matrix_product(self, t, u, alpha, v, y)
      class(orego_matrix_product), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: jac(size(u), size(u))
      integer :: j
      call self%jac(t, u, jac)
      do j = 1, size(u)
         y = y + (alpha*v(j))*jac(:, j)
      end do
   end subroutine matrix_product

   !> One adaptive step with step doubling and local extrapolation multiplies the
   !> linear test equation's state by (2^p R(z/2, w/2)^2 - R(z, w)) / (2^p - 1), R
   !> the scheme's own stability function, p its order, and one with the defect
   !> estimate (si-t-2's default) by R - 2/3 D / M (see defect_extrapolated): checked
   !> for every scheme with either default estimate (all but radau5) at eight (z, w) pairs, stiff and
   !> oscillatory ones among them, to 1e-10 relative (the equations are linear, so
   !> one Newton iteration solves them up to the roundoff of Newton matrices whose
   !> condition reaches 1e6 here; the single step stops after it). The step is forced
   !> by h0 = 1 = t_end and tolerances too loose to reject it.
   subroutine test_extrapolated_stability(error)
      type(error_type), allocatable, intent(out) :: error
      complex(dp), parameter :: z(8) = [(-1.0_dp, 0.0_dp), (-0.5_dp, 0.5_dp), (0.0_dp, 1.0_dp), (-0.2_dp, -0.8_dp), &
         (-0.1_dp, 0.0_dp), (0.0_dp, 0.0_dp), (-0.3_dp, 0.2_dp), (0.0_dp, 0.0_dp)]
      complex(dp), parameter :: w(8) = [(-1.0_dp, 0.0_dp), (-10.0_dp, 0.0_dp), (-2.0_dp, 3.0_dp), &
         (-20.0_dp, -10.0_dp), (-1.0e4_dp, 0.0_dp), (0.0_dp, 1.3_dp), (-1.0e6_dp, 1.0e3_dp), (-3.0_dp, 0.0_dp)]
      type(linear_test_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2), doubling
      complex(dp) :: expected
      integer :: k, i

      options = integrator_options_type(rtol=1.0e10_dp, atol=1.0e10_dp, h0=1.0_dp, newton_fraction=1.0e-25_dp)
      do k = 1, scheme_count
         call new_scheme(trim(scheme_names(k)), scheme, stat)
         if (scheme%estimates_own_error) cycle
         doubling = 2.0_dp**scheme%nonlinear_order
         do i = 1, size(z)
            problem = new_linear_test(z(i), w(i))
            u = [1.0_dp, 0.0_dp]
            call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
            call check(error, stat%code == status_ok .and. stats%accepted_steps == 1, trim(scheme_names(k))// &
               ": one accepted step expected at pair "//format_integer(i)//": "//stat_message(stat))
            if (allocated(error)) return
            if (scheme%estimates_step_error) then
               expected = defect_extrapolated(scheme%stability(z(i), w(i)), z(i), w(i))
            else
               expected = (doubling*scheme%stability(z(i)/2.0_dp, w(i)/2.0_dp)**2 - scheme%stability(z(i), w(i)))/ &
                  (doubling - 1.0_dp)
            end if
            call check(error, abs(cmplx(u(1), u(2), dp) - expected) <= 1.0e-10_dp*max(abs(expected), 1.0_dp), &
               trim(scheme_names(k))//": the extrapolated step differs from its stability function at pair "// &
               format_integer(i))
            if (allocated(error)) return
         end do
      end do
   contains
      !> U1 minus the defect estimate on the linear test: R - 2/3 D / M with D = R - 1 -
      !> s/2 (1 + R), s = z + w, and M the si-t-2 Newton matrix 1 - w + w (z + w)/2 (the
      !> one scheme with this estimate)
      pure complex(dp) function defect_extrapolated(r, z, w)
         complex(dp), intent(in) :: r, z, w
         complex(dp) :: s
         s = z + w
         defect_extrapolated = r - (2.0_dp/3.0_dp)*(r - 1.0_dp - 0.5_dp*s*(1.0_dp + r))/ &
            (1.0_dp - w + 0.5_dp*w*s)
      end function defect_extrapolated
   end subroutine test_extrapolated_stability

   !> PI and PID complete the paper's run; their rejections are counted.
   subroutine test_pi_pid(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: controllers(2) = [controller_pi, controller_pid]
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)
      integer :: k

      problem = new_van_der_pol(1000.0_dp)
      do k = 1, size(controllers)
         call new_scheme("i-t-2", scheme, stat)
         options = paper_options()
         options%controller = controllers(k)
         u = van_der_pol_initial_state(vdp_ic_prepared)
         call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, stat_message(stat))
         if (allocated(error)) return
         call check(error, abs(u(1) - vdp_reference(1, 1)) < 1.0e-2_dp, "PI/PID error in y")
         if (allocated(error)) return
         ! a smoother controller rejects fewer steps than it accepts by far
         call check(error, stats%rejected_error < stats%accepted_steps/100, "too many rejections")
         if (allocated(error)) return
         call check(error, stats%rejected_steps() == stats%rejected_error + stats%rejected_newton + &
            stats%rejected_nonfinite, "rejected_steps sums the causes")
         if (allocated(error)) return
         ! with the library's defaults (step doubling) and si-t-2, whose errors vary more
         ! from step to step: a rejection must shrink h whatever the earlier errors were
         ! (the PID terms once asked for growth after a rejection, 10 million times over)
         call new_scheme("si-t-2", scheme, stat)
         options = integrator_options_type(rtol=1.0e-7_dp, atol=1.0e-7_dp, norm=norm_rms, &
            controller=controllers(k), max_steps=100000_i8)
         u = van_der_pol_initial_state(vdp_ic_prepared)
         call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
         call check(error, stat%code == status_ok .and. stats%rejected_error < stats%accepted_steps/4, &
            "si-t-2 with PI/PID and step doubling: "//format_integer(int(stats%rejected_error))//" rejections, "// &
            format_integer(int(stats%accepted_steps))//" steps: "//stat_message(stat))
         if (allocated(error)) return
      end do
   end subroutine test_pi_pid

   !> i-t-2 advancing with its first-order member is i-t-1 with the same estimate.
   subroutine test_advance_low(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats_low, stats_one
      type(status_type) :: stat
      real(dp) :: u_low(2), u_one(2)

      problem = new_van_der_pol(1000.0_dp)
      options = paper_options()
      options%advance = advance_low
      call new_scheme("i-t-2", scheme, stat)
      u_low = van_der_pol_initial_state(vdp_ic_prepared)
      call integrate(problem, scheme, 0.0_dp, 300.0_dp, u_low, options, stats_low, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      options = paper_options()
      call new_scheme("i-t-1", scheme, stat)
      u_one = van_der_pol_initial_state(vdp_ic_prepared)
      call integrate(problem, scheme, 0.0_dp, 300.0_dp, u_one, options, stats_one, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, abs(stats_low%accepted_steps - stats_one%accepted_steps) <= &
         stats_one%accepted_steps/200, "step counts differ")
      if (allocated(error)) return
      call check(error, maxval(abs(u_low - u_one)) < 1.0e-5_dp, "final states differ")
   end subroutine test_advance_low

   subroutine test_invalid_options(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2), nan, u_out(2, 3)

      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      problem = new_van_der_pol(10.0_dp)
      call new_scheme("si-t-2", scheme, stat)

      options = integrator_options_type(rtol=0.0_dp, atol=0.0_dp)
      call expect(status_invalid_argument, "tolerance")
      if (allocated(error)) return
      options = integrator_options_type(rtol=nan)
      call expect(status_invalid_argument, "rtol")
      if (allocated(error)) return
      options = integrator_options_type(atol=-1.0_dp)
      call expect(status_invalid_argument, "atol")
      if (allocated(error)) return
      options = integrator_options_type(h0=-1.0e-3_dp)
      call expect(status_invalid_argument, "h0")
      if (allocated(error)) return
      ! a subnormal first step: 1/h0 overflows (radau5 and imex-rk21 failed with NaN)
      options = integrator_options_type(h0=tiny(1.0_dp)/4.0_dp)
      call expect(status_invalid_argument, "h0")
      if (allocated(error)) return
      options = integrator_options_type(h_max=0.0_dp)
      call expect(status_invalid_argument, "h_max")
      if (allocated(error)) return
      options = integrator_options_type(h_min_relative=1.0_dp)
      call expect(status_invalid_argument, "h_min_relative")
      if (allocated(error)) return
      options = integrator_options_type(h_min_relative=nan)
      call expect(status_invalid_argument, "h_min_relative")
      if (allocated(error)) return
      options = integrator_options_type(kappa=1.5_dp)
      call expect(status_invalid_argument, "kappa")
      if (allocated(error)) return
      options = integrator_options_type(max_steps=0_i8)
      call expect(status_invalid_argument, "max_steps")
      if (allocated(error)) return
      options = integrator_options_type()
      options%atol_vector = [1.0e-6_dp, 1.0e-6_dp, 1.0e-6_dp]
      call expect(status_size_mismatch, "atol_vector")
      if (allocated(error)) return

      ! times, state and dense output arrays
      options = integrator_options_type()
      u = [2.0_dp, 0.0_dp]
      call integrate(problem, scheme, 1.0_dp, 1.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_invalid_argument, "t_end == t0")
      if (allocated(error)) return
      call integrate(problem, scheme, 1.0_dp, 0.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_invalid_argument, "t_end < t0")
      if (allocated(error)) return
      call check(error, index(stat%message, "backward") > 0, stat_message(stat))
      if (allocated(error)) return
      u = [2.0_dp, nan]
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_nonfinite, "NaN initial state")
      if (allocated(error)) return
      u = [2.0_dp, 0.0_dp]
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat, &
         t_out=[0.5_dp, 0.2_dp, 1.0_dp], u_out=u_out)
      call check(error, stat%code, status_invalid_argument, "t_out not ascending")
      if (allocated(error)) return
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat, &
         t_out=[0.5_dp, 1.0_dp], u_out=u_out)
      call check(error, stat%code, status_size_mismatch, "u_out shape")
      if (allocated(error)) return
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat, t_out=[0.5_dp, 1.0_dp])
      call check(error, stat%code == status_invalid_argument .and. index(stat%message, "go together") > 0, &
         "t_out without u_out: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, all(u == [2.0_dp, 0.0_dp]), "rejected input must leave u alone")
   contains
      subroutine expect(code, word)
         integer, intent(in) :: code
         character(len=*), intent(in) :: word
         u = [2.0_dp, 0.0_dp]
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
         call check(error, stat%code, code, word//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, index(stat%message, word) > 0, "message should name "//word//": "//stat_message(stat))
      end subroutine expect
   end subroutine test_invalid_options

   !> h_max tiny and few steps allowed: "maximum steps" with the state at the last
   !> accepted time, strictly between t0 and t_end.
   subroutine test_max_steps(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("i-t-2", scheme, stat)
      options = paper_options()
      options%h_max = 1.0e-3_dp
      options%h0 = 1.0e-3_dp
      options%max_steps = 50
      u = van_der_pol_initial_state(vdp_ic_prepared)
      call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_max_steps, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%t_reached > 0.0_dp .and. stats%t_reached < 3000.0_dp, "t_reached")
      if (allocated(error)) return
      call check(error, stats%accepted_steps + stats%rejected_steps(), 50_i8, "attempts")
      if (allocated(error)) return
      call check(error, all(ieee_is_finite(u)) .and. abs(u(1) - 2.0_dp) < 0.01_dp, "last good state")
      if (allocated(error)) return
      call check(error, stats%work%f_evaluations > 0 .and. stats%work%lu_factorizations > 0, &
         "statistics are kept on failure")
   end subroutine test_max_steps

   !> h_min far above what the layer of Van der Pol needs: step size underflow.
   subroutine test_step_underflow(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("si-t-2", scheme, stat)
      options = paper_options()
      options%h_min = 1.0e-2_dp
      u = van_der_pol_initial_state(vdp_ic_prepared)
      call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_step_underflow, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%t_reached < 3000.0_dp .and. all(ieee_is_finite(u)), "last good state")
      if (allocated(error)) return
      call relative_limit(error)

   contains

      !> h_min_relative: y' = y^2, y(0) = 1, blows up at t = 1, where h shrinks until the
      !> integration gives up; with h_min_relative = 1e-6 it gives up at h <= 1e-6 |t|,
      !> after fewer attempts than at the roundoff of t, and no accepted step is smaller
      subroutine relative_limit(error)
         type(error_type), allocatable, intent(out) :: error
         type(blow_up_type) :: blow_up
         type(integration_stats_type) :: stats_roundoff
         real(dp) :: y(1)
         call new_scheme("radau5", scheme, stat)
         options = integrator_options_type(rtol=1.0e-8_dp, atol=1.0e-8_dp)
         y = 1.0_dp
         call integrate(blow_up, scheme, 0.0_dp, 2.0_dp, y, options, stats_roundoff, stat)
         call check(error, stat%code, status_step_underflow, "at the roundoff of t: "//stat_message(stat))
         if (allocated(error)) return
         options%h_min_relative = 1.0e-6_dp
         y = 1.0_dp
         call integrate(blow_up, scheme, 0.0_dp, 2.0_dp, y, options, stats, stat)
         call check(error, stat%code, status_step_underflow, "h_min_relative = 1e-6: "//stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%accepted_steps + stats%rejected_steps() < stats_roundoff%accepted_steps + &
            stats_roundoff%rejected_steps() .and. stats%h_min_accepted > 1.0e-6_dp*stats%t_reached .and. &
            stats%t_reached < 1.0_dp, "h_min_relative = 1e-6: "//format_integer(stats%accepted_steps + &
            stats%rejected_steps())//" attempts (at the roundoff of t "//format_integer(stats_roundoff% &
            accepted_steps + stats_roundoff%rejected_steps())//"), smallest accepted step "// &
            format_real(stats%h_min_accepted)//" at t up to "//format_real(stats%t_reached))
      end subroutine relative_limit
   end subroutine test_step_underflow

   !> g is NaN at every t > 0: each attempt fails, h shrinks, and after
   !> max_failures attempts the integration returns the initial state.
   subroutine test_nonfinite_values(error)
      type(error_type), allocatable, intent(out) :: error
      type(poisoned_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)
      character(len=*), parameter :: names(2) = ["ex-t-2", "i-t-2 "]
      integer :: k

      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         options = integrator_options_type(h0=0.1_dp, max_failures=4)
         u = [1.0_dp]
         ! ex-t-2 evaluates at the start of a step: its first step from t = 0 is finite
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
         call check(error, stat%code /= status_ok, trim(names(k))//": NaN values must fail")
         if (allocated(error)) return
         call check(error, stat%code == status_nonfinite .or. stat%code == status_newton_not_converged &
            .or. index(stat%message, "NaN") > 0, trim(names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%rejected_nonfinite + stats%rejected_newton, 4_i8, "failed attempts")
         if (allocated(error)) return
         call check(error, all(ieee_is_finite(u)), "the returned state must be the last good one")
         if (allocated(error)) return
      end do
   end subroutine test_nonfinite_values

   !> Where the state and F give no first step (Van der Pol at rest: U0 = F = 0) the
   !> fallback is relative to |t0|: from t0 = 1e12 a step of 1e-6 would be below the
   !> roundoff of t and stop the integration at once.
   subroutine test_first_step_far_from_zero(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("radau5", scheme, stat)
      u = 0.0_dp
      call integrate(problem, scheme, 1.0e12_dp, 1.0e12_dp + 1.0e3_dp, u, integrator_options_type(), stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, all(u == 0.0_dp), "the state at rest stays at rest")
   end subroutine test_first_step_far_from_zero

   !> One Newton iteration allowed and a first step far too large: the step fails
   !> in Newton, shrinks, and after max_failures the status is Newton's.
   subroutine test_newton_failures(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("i-t-2", scheme, stat)
      options = paper_options()
      ! two iterations from the unprepared state with a first step of 1: no convergence
      options%max_newton_iterations = 2
      options%max_failures = 3
      options%h0 = 1.0_dp
      u = van_der_pol_initial_state(vdp_ic_unprepared)
      call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_newton_not_converged, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%rejected_newton, 3_i8, "Newton failures counted")
      if (allocated(error)) return
      call check(error, stats%t_reached, 0.0_dp, "t_reached")
      if (allocated(error)) return
      call check(error, all(u == van_der_pol_initial_state(vdp_ic_unprepared)), "initial state returned")
      if (allocated(error)) return

      ! with enough iterations and a smaller first step the same run succeeds
      options%max_newton_iterations = 10
      options%h0 = 1.0e-2_dp
      call integrate(problem, scheme, 0.0_dp, 30.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
   end subroutine test_newton_failures

   !> A Newton matrix singular at every retry: after max_failures attempts the status
   !> is status_singular_matrix and the initial state comes back.
   subroutine test_singular_repeatedly(error)
      type(error_type), allocatable, intent(out) :: error
      type(singular_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)

      call new_scheme("i-t-1", scheme, stat)
      options = integrator_options_type(h0=0.125_dp, max_failures=3, min_shrink=0.0_dp)
      u = [1.0_dp]
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_singular_matrix, stat_message(stat))
      if (allocated(error)) return
      call check(error, index(stat%message, "singular") > 0 .and. index(stat%message, "3 consecutive") > 0, &
         stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%rejected_newton, 3_i8, "failed attempts")
      if (allocated(error)) return
      call check(error, u(1), 1.0_dp, "initial state returned")
   end subroutine test_singular_repeatedly

   !> u' = -u over [0, 3e34] (rtol = atol = 1e-6), where the steps grow until h |lambda|
   !> passes 1/epsilon. The stacked Newton matrices of i-t-2 and si-t-2 ([[A, B], [C, I]]
   !> with A = 1 + h, C = h here) took A's row for the pivot, recovered the correction
   !> as (r - B y) / A with B y = -r to the last bit, and kept a relative error of about
   !> epsilon h |lambda| / 2: nothing once h |lambda| > 2/epsilon, where it cancelled to
   !> exactly 0 and the iteration took its starting guess (i-t-2 returned status ok with
   !> u = 7.9e9); with the zero correction taken for a singular matrix and the steps held
   !> below it, [0, 3e34] ran into the step budget. The second block rows are now scaled
   !> by 2 where h max|J| > 1/sqrt(epsilon), so that C's rows are the pivots and the
   !> correction is recovered from C x + y = 0 without cancellation: the three stacked
   !> schemes reach u = 0 in a few hundred steps (159 to 222). A correction that
   !> underflowed is no such failure: i-t-1 from u0 = 1e-300 in one step of 1e30 reaches
   !> u = 0 and then corrects by u0 / (1 + h) = 1e-330, zero in double precision (taken for
   !> a singular matrix, the run gave up after 5 attempts).
   subroutine test_long_steps_keep_digits(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: stacked(3) = [character(len=12) :: "i-t-2", "si-t-2", "si-t-2-paper"]
      real(dp), parameter :: tol = 1.0e-6_dp
      type(linear_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)
      integer :: k

      do k = 1, size(stacked)
         call new_scheme(trim(stacked(k)), scheme, stat)
         options = integrator_options_type(rtol=tol, atol=tol, max_steps=20000_i8)
         u = [1.0_dp]
         call integrate(problem, scheme, 0.0_dp, 3.0e34_dp, u, options, stats, stat)
         call check(error, stat%code /= status_ok .or. abs(u(1)) <= tol, trim(stacked(k))// &
            ": status ok with u(3e34) = "//format_real(u(1)))
         if (allocated(error)) return
         call check(error, stat%code, status_ok, trim(stacked(k))//" to 3e34: "//stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%accepted_steps <= 1000_i8, trim(stacked(k))//" to 3e34 in "// &
            format_integer(int(stats%accepted_steps))//" steps")
         if (allocated(error)) return
      end do
      call new_scheme("i-t-1", scheme, stat)
      options = integrator_options_type(rtol=tol, atol=tol, h0=1.0e30_dp)
      u = [1.0e-300_dp]
      call integrate(problem, scheme, 0.0_dp, options%h0, u, options, stats, stat)
      call check(error, stat%code, status_ok, "i-t-1 from 1e-300: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, abs(u(1)) <= 1.0e-300_dp, "i-t-1: u(1e30) = "//format_real(u(1)))
   end subroutine test_long_steps_keep_digits

   !> t + h rounds, and over many steps of one size the roundings have one sign: t fell
   !> behind the time the state was at. radau5 on u' = -u to t = 100 at rtol 1e-13 (atol
   !> 0) holds h constant over 54,821 steps, which fell 1.27e-10 short of t = 100: the
   !> state came back 1273 tolerances off (21,710 to t = 500; OREGO at 1e-13 66 off the
   !> published solution). With t summed compensated (the last step takes what t lacks)
   !> within a tolerance, at t_end and at output times every 1 (steps that land on them).
   subroutine test_time_keeps_up(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), parameter :: tol = 1.0e-13_dp, t_end = 100.0_dp
      type(linear_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1), t_out(100), u_out(1, 100), worst
      integer :: k

      call new_scheme("radau5", scheme, stat)
      options = integrator_options_type(rtol=tol, atol=0.0_dp)
      u = [1.0_dp]
      call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, abs(u(1)/exp(-t_end) - 1.0_dp) <= 2.0_dp*tol, "u(100) off by "// &
         format_real(abs(u(1)/exp(-t_end) - 1.0_dp)/tol)//" tolerances after "// &
         format_integer(int(stats%accepted_steps))//" steps")
      if (allocated(error)) return
      t_out = [(real(k, dp), k = 1, size(t_out))]
      u = [1.0_dp]
      call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, stat, t_out=t_out, u_out=u_out)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      worst = maxval(abs(u_out(1, :)/exp(-t_out) - 1.0_dp))/tol
      call check(error, worst <= 2.0_dp, "outputs off by up to "//format_real(worst)//" tolerances")
   end subroutine test_time_keeps_up

   !> advance_to a target one rounding past t: no step resolves it, and the call failed
   !> with a step-size underflow, which it kept as the next call's first step: every
   !> later call failed at once (an outside audit). Now the target is reached where the
   !> state is (as a step lands on an output time within roundoff), with the output
   !> there, and the next call goes on as before.
   subroutine test_target_within_roundoff(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_type) :: integrator
      type(integrator_options_type) :: options
      type(status_type) :: stat
      real(dp) :: u(1), u_out(1, 1), t_near
      call new_scheme("i-t-2", scheme, stat)
      u = [1.0_dp]
      call integrator%init(problem, scheme, 1.0_dp, u, options, stat)
      call integrator%advance_to(problem, scheme, 1.5_dp, u, stat)
      call check(error, stat%code, status_ok, "to 1.5: "//stat_message(stat))
      if (allocated(error)) return
      t_near = nearest(1.5_dp, 2.0_dp)
      call integrator%advance_to(problem, scheme, t_near, u, stat, t_out=[t_near], u_out=u_out)
      call check(error, stat%code, status_ok, "to 1.5 + 1 ulp: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, integrator%t == t_near .and. u_out(1, 1) == u(1), "t = "//format_real(integrator%t, 17)// &
         ", the output "//format_real(u_out(1, 1), 17)//", u "//format_real(u(1), 17))
      if (allocated(error)) return
      call integrator%advance_to(problem, scheme, 2.0_dp, u, stat)
      call check(error, stat%code, status_ok, "then to 2: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, abs(u(1) - exp(-1.0_dp)) <= 10.0_dp*options%rtol, "u(2) = "//format_real(u(1)))
   end subroutine test_target_within_roundoff

   !> i-t-2's Newton matrix differences J along F over a step e F of sqrt(epsilon) times
   !> |U|; with |U| < 1 it took 1 instead, and where J changes on the scale of U the
   !> difference measured J far from U: on u' = -1e4 u^3 (declared autonomous) to t = 1e25,
   !> with u = 2e-15 there, F''[F] came out 700 times too large and of the wrong sign,
   !> the Newton matrix a fifth of what it is, and Newton failed every other step: 16,691
   !> steps and 9,508 failed attempts (to 1e30 the budget of 100,000 ran out). With |U|
   !> (or h |F| where U = 0): 338 steps, 19 failed attempts.
   subroutine test_second_derivative_scale(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), parameter :: tol = 1.0e-6_dp, t_end = 1.0e25_dp
      type(cubic_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)

      problem%autonomous = .true.
      call new_scheme("i-t-2", scheme, stat)
      options = integrator_options_type(rtol=tol, atol=tol)
      u = [1.0_dp]
      call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, abs(u(1) - 1.0_dp/sqrt(1.0_dp + 2.0e4_dp*t_end)) <= tol, "u(1e25) = "//format_real(u(1)))
      if (allocated(error)) return
      call check(error, stats%accepted_steps <= 1000_i8 .and. stats%rejected_newton <= 100_i8, &
         format_integer(int(stats%accepted_steps))//" steps, "//format_integer(int(stats%rejected_newton))// &
         " failed in Newton")
   end subroutine test_second_derivative_scale

   !> u' = -u + H(t - 1), u(0) = 0, to t = 3 (u(3) = 1 - exp(-2)), the forcing in f: the
   !> explicit schemes, si-t-1 and si-t-2-paper evaluate f at a step's start only (step
   !> doubling at the midpoint too), so a step whose second half held t = 1 went on
   !> without the forcing, its estimate none the wiser: status ok 4.8e-3 off at every
   !> tolerance (4.8e3 tolerances at 1e-6). The stepper's difference of f in t over the
   !> step (at the new state) sees the switch; within 10 tolerances.
   subroutine test_switched_forcing(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(4) = [character(len=12) :: "ex-t-1", "ex-t-2", "si-t-1", "si-t-2-paper"]
      real(dp), parameter :: tol = 1.0e-6_dp
      type(switched_forcing_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1), exact
      integer :: k

      exact = 1.0_dp - exp(-2.0_dp)
      options = integrator_options_type(rtol=tol, atol=tol)
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u = [0.0_dp]
         call integrate(problem, scheme, 0.0_dp, 3.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, abs(u(1) - exact) <= 10.0_dp*(tol + tol*exact), trim(names(k))//": u(3) = "// &
            format_real(u(1))//", "//format_real(abs(u(1) - exact)/(tol + tol*exact))//" tolerances off")
         if (allocated(error)) return
      end do
   end subroutine test_switched_forcing

   !> ex-t-2 on a stiff relaxation (relaxation_problem, declared autonomous) from its slow
   !> solution, rtol = atol = 1e-4, to t = 5: step doubling's estimate vanishes at h lambda
   !> = -8, where R(z) = 1 + z + z^2/2 = R(z/2)^2 = 25, and the controller (growth 5,
   !> shrink 0.2) kept coming back to it: status ok with step ends 773 tolerances off. F's
   !> second difference along the step (the stepper's check for explicit schemes) sees the
   !> amplified mode: within 10 tolerances (1.9).
   subroutine test_explicit_stability(error)
      type(error_type), allocatable, intent(out) :: error
      type(relaxation_problem) :: problem
      type(relaxation_observer) :: observer
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)

      problem%autonomous = .true.
      observer%c = 0.5_dp*problem%lambda/(problem%lambda + 1.0_dp)
      call new_scheme("ex-t-2", scheme, stat)
      options = integrator_options_type(rtol=observer%tol, atol=observer%tol)
      u = [1.0_dp + observer%c, 1.0_dp]
      call integrate(problem, scheme, 0.0_dp, 5.0_dp, u, options, stats, stat, observer=observer)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, observer%worst <= 10.0_dp, "a step end "//format_real(observer%worst)//" tolerances off")
   end subroutine test_explicit_stability

   !> A solve that keeps no digit is a singular matrix: the stacked matrix of
   !> cancelling_system solves for a correction of exactly 0 although the residual is 1;
   !> taking that for convergence returned the starting guess as the solution. Newton
   !> must answer status_singular_matrix and hold later steps below a quarter of h.
   subroutine test_solve_without_a_digit_singular(error)
      type(error_type), allocatable, intent(out) :: error
      type(cancelling_system) :: system
      type(linear_decay_problem) :: problem
      type(newton_solver_type) :: solver
      type(newton_settings_type) :: settings
      type(counters_type) :: counters
      type(status_type) :: stat
      real(dp) :: u(1)

      call solver%init(1, dense_structure(), stat, stacked=.true.)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      settings%tolerance = [1.0e-6_dp]
      u = [0.0_dp]
      call solver%solve(system, problem, system%h, settings, u, counters, stat)
      call check(error, stat%code, status_singular_matrix, "u = "//format_real(u(1))//": "//stat_message(stat))
      if (allocated(error)) return
      call check(error, solver%step_limit, 0.25_dp*system%h, "step limit")
   end subroutine test_solve_without_a_digit_singular

   !> u' = -u (not declared autonomous) from a first step of 1e-300: the second-order
   !> schemes difference g in t over a step/128, whose quadratic's weights b/(a (b - a))
   !> overflowed once a (b - a) underflowed (steps below 1e-154); Inf times the zero
   !> difference made dF/dt NaN, and ex-t-2, i-t-2 and si-t-2 ended with
   !> status_nonfinite at t = 0. They must succeed, as the other schemes do.
   subroutine test_tiny_first_step(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(3) = [character(len=6) :: "ex-t-2", "i-t-2", "si-t-2"]
      real(dp), parameter :: tol = 1.0e-6_dp
      type(linear_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)
      integer :: k

      options = integrator_options_type(rtol=tol, atol=tol, h0=1.0e-300_dp)
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u = [1.0_dp]
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, abs(u(1) - exp(-1.0_dp)) <= 100.0_dp*tol, trim(names(k))//": u(1) = "// &
            format_real(u(1)))
         if (allocated(error)) return
      end do
   end subroutine test_tiny_first_step

   !> si-t-2 on Prothero-Robinson with its forcing in f (y' = -1e4 (y - cos t) - sin t,
   !> y(0) = 2) with output times 0, 0.01, ..., 10 (tol 1e-6): a step ended one rounding
   !> short of an output time (0.08 + 0.05 = 0.12999999999999998, 0.13 ahead), the next
   !> attempt had the output time inside and was retried to end there, with h = 2.8e-17:
   !> status step-size underflow at t = 0.13, where the run without output times
   !> succeeds. A step that lands within roundoff of an output time now ends there.
   subroutine test_steps_land_on_outputs(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: outputs = 1001
      real(dp), parameter :: tol = 1.0e-6_dp
      type(forced_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1), t_out(outputs), u_out(1, outputs), worst
      integer :: k

      problem%rate = 1.0e4_dp
      t_out = [(10.0_dp*real(k - 1, dp)/real(outputs - 1, dp), k=1, outputs)]
      options = integrator_options_type(rtol=tol, atol=tol)
      call new_scheme("si-t-2", scheme, stat)
      u = [2.0_dp]
      call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, options, stats, stat, t_out=t_out, u_out=u_out)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      worst = maxval(abs(u_out(1, :) - (cos(t_out) + exp(-problem%rate*t_out)))/(tol + tol*abs(cos(t_out))))
      call check(error, worst <= 100.0_dp, "output error "//format_real(worst)//" tolerances")
   end subroutine test_steps_land_on_outputs

   !> HIRES from its start, where seven of its eight components are 0, with i-t-1 and the
   !> embedded estimate (i-t-2's Newton for it) at rtol 1e-6, atol 1e-10: the increments
   !> of the components at 0 (1e-41, 1e-28 of their tolerance) were not "within the
   !> rounding of the iterate", and with the first component's below its rounding the
   !> contraction stayed exactly 1; Newton rebuilt its matrix every other iteration
   !> until its limit, at every step size: 123 failed attempts (h down to 1e-82) over the
   !> whole run. An increment within a few ulps of its tolerance is resolved too.
   subroutine test_newton_at_zero_components(error)
      type(error_type), allocatable, intent(out) :: error
      type(hires_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:)

      problem = new_hires()
      call new_scheme("i-t-1", scheme, stat)
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-10_dp, error_estimate=estimate_embedded)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%rejected_newton <= 2_i8, format_integer(int(stats%rejected_newton))// &
         " attempts failed in Newton")
   end subroutine test_newton_at_zero_components

   !> max_newton_iterations = 1: radau5 integrates u' = -u over [0, 1] with it; the other
   !> implicit schemes refuse it, as their Newton takes no first increment of a matrix it
   !> has just built alone (they ran, no solve converged, the step fell to 1e-15 and the
   !> step budget ran out at t = 1e-9; an outside audit); 2 they take. With g declared
   !> linear, si-t-1 and imex-rk21, implicit in g alone, solve in one iteration and take 1.
   subroutine test_one_newton_iteration(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)
      integer :: k
      do k = 1, scheme_count
         call new_scheme(scheme_names(k), scheme, stat)
         if (.not. scheme%implicit) cycle
         options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp, max_newton_iterations=1, &
            max_steps=100000_i8)
         u = [1.0_dp]
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
         if (scheme_names(k) /= "radau5") then
            call check(error, stat%code == status_invalid_argument .and. &
               index(stat_message(stat), "max_newton_iterations") > 0 .and. u(1) == 1.0_dp, &
               trim(scheme_names(k))//" with 1 iteration: "//stat_message(stat))
            if (allocated(error)) return
            options%max_newton_iterations = 2
            call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
         end if
         if (scheme%newton_linear_in_g) then
            call check(error, stat%code, status_ok, trim(scheme_names(k))//" with 2 iterations: "//stat_message(stat))
            if (allocated(error)) return
            problem%linear_g = .true.
            options%max_newton_iterations = 1
            u = [1.0_dp]
            call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
            problem%linear_g = .false.
         end if
         call check(error, stat%code, status_ok, trim(scheme_names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, abs(u(1) - exp(-1.0_dp)) <= 1.0e-3_dp .and. stats%accepted_steps <= 10000_i8, &
            trim(scheme_names(k))//": u(1) = "//format_real(u(1))//" in "//format_integer(int(stats%accepted_steps))// &
            " steps")
         if (allocated(error)) return
      end do
   end subroutine test_one_newton_iteration

   !> radau5 with max_newton_iterations = huge(0) steps as with 1000, both in effect no
   !> limit (Van der Pol, mu = 1e3, from (2, 0) to t = 3000, tol 1e-6): its step safety
   !> (1 + 2 nit) / (newt + 2 nit) overflowed an integer, and took every step short.
   subroutine test_huge_iteration_limit(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: limits(2) = [1000, huge(0)]
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)
      integer(i8) :: accepted(2)
      integer :: k

      problem = new_van_der_pol(1000.0_dp)
      do k = 1, size(limits)
         call new_scheme("radau5", scheme, stat)
         options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp, max_newton_iterations=limits(k))
         u = [2.0_dp, 0.0_dp]
         call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, "limit "//format_integer(limits(k))//": "//stat_message(stat))
         if (allocated(error)) return
         accepted(k) = stats%accepted_steps
      end do
      call check(error, abs(accepted(2) - accepted(1)) <= accepted(1)/10, "accepted steps with the limit 1000: "// &
         format_integer(int(accepted(1)))//", with huge(0): "//format_integer(int(accepted(2))))
   end subroutine test_huge_iteration_limit

   !> A first step far too long for Newton (u' = -1e4 u^3 from u = 1 with h0 = 1e6): the
   !> failed attempts are retried with ever smaller steps until Newton converges, as
   !> RADAU5 does, however many it takes (radau5 fails 18 attempts, i-t-1 16, more than
   !> 10 of them in a row), and the integration succeeds; with options%max_failures = 10
   !> it gives up with Newton's status, as every integration did before the limit
   !> became optional.
   subroutine test_failures_retried(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = [character(len=6) :: "radau5", "i-t-1"]
      type(cubic_decay_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1), exact
      integer :: k

      exact = 1.0_dp/sqrt(1.0_dp + 2.0e4_dp*1.0e6_dp)
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         options = integrator_options_type(rtol=1.0e-4_dp, atol=1.0e-10_dp, h0=1.0e6_dp)
         u = [1.0_dp]
         call integrate(problem, scheme, 0.0_dp, 1.0e6_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%rejected_newton > 10, trim(names(k))//": only "// &
            format_integer(int(stats%rejected_newton))//" Newton failures: the test needs more than 10 in a row")
         if (allocated(error)) return
         call check(error, abs(u(1) - exact) <= 1.0e-2_dp*exact, trim(names(k))//": u(1e6) = "// &
            format_real(u(1))//" against "//format_real(exact))
         if (allocated(error)) return
         options%max_failures = 10
         u = [1.0_dp]
         call integrate(problem, scheme, 0.0_dp, 1.0e6_dp, u, options, stats, stat)
         call check(error, stat%code /= status_ok .and. index(stat%message, "10 consecutive") > 0, &
            trim(names(k))//" with max_failures = 10: "//stat_message(stat))
         if (allocated(error)) return
      end do
   end subroutine test_failures_retried

   !> Singular Newton matrices end a call at the fifth (RADAU5's limit), counted over
   !> the call and not only in a row: i-t-1 on g = u / t meets a singular matrix at
   !> every step from t = 0 whose size is a power of two, and with no limit on
   !> consecutive failures the fifth is the end (status_singular_matrix).
   subroutine test_singular_cumulative(error)
      type(error_type), allocatable, intent(out) :: error
      type(singular_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)

      call new_scheme("i-t-1", scheme, stat)
      u = [1.0_dp]
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, integrator_options_type(h0=0.125_dp, min_shrink=0.0_dp), &
         stats, stat)
      call check(error, stat%code, status_singular_matrix, stat_message(stat))
      if (allocated(error)) return
      call check(error, index(stat%message, "singular in 5 attempts") > 0, stat_message(stat))
      if (allocated(error)) return
      call check(error, stats%rejected_newton, 5_i8, "failed attempts")
   end subroutine test_singular_cumulative

   !> Dense output on a grid against runs that stop exactly at each grid time.
   subroutine test_dense_output(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: n_out = 21
      real(dp), parameter :: tol = 1.0e-6_dp
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: t_out(n_out), u_out(2, n_out), u(2), u_direct(2)
      integer :: k

      problem = new_van_der_pol(5.0_dp)
      options%rtol = tol
      options%atol = tol
      options%norm = norm_rms
      t_out = [(0.1_dp*k, k=0, n_out - 1)]
      call new_scheme("i-t-2", scheme, stat)
      u = [2.0_dp, 0.0_dp]
      call integrate(problem, scheme, 0.0_dp, 2.0_dp, u, options, stats, stat, t_out=t_out, u_out=u_out)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, all(u_out(:, 1) == [2.0_dp, 0.0_dp]), "output at t0")
      if (allocated(error)) return
      call check(error, all(u_out(:, n_out) == u), "output at t_end is the final state")
      if (allocated(error)) return
      do k = 2, n_out - 1
         u_direct = [2.0_dp, 0.0_dp]
         call integrate(problem, scheme, 0.0_dp, t_out(k), u_direct, options, stats, stat)
         call check(error, stat%code, status_ok, stat_message(stat))
         if (allocated(error)) return
         ! both carry a global error of order tol; the interpolant adds O(h^4) ~ tol^2
         call check(error, maxval(abs(u_out(:, k) - u_direct)) < 20*tol, &
            "dense output differs from a direct run at t = 0."//format_integer(k - 1))
         if (allocated(error)) return
      end do
   end subroutine test_dense_output

   !> The history has one row per attempt, in agreement with the statistics, and
   !> its CSV has one line per attempt plus a header.
   subroutine test_step_history(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(step_history_type) :: history
      real(dp) :: u(2)
      integer :: unit, lines, io
      character(len=*), parameter :: csv = "test_step_history.csv"

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("si-t-2", scheme, stat)
      options = paper_options()
      options%history_states = .true.
      u = van_der_pol_initial_state(vdp_ic_unprepared)
      call integrate(problem, scheme, 0.0_dp, 100.0_dp, u, options, stats, stat, history=history)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call check(error, history%count, int(stats%accepted_steps + stats%rejected_steps()), "rows")
      if (allocated(error)) return
      call check(error, count(history%outcome(:history%count) == attempt_accepted), &
         int(stats%accepted_steps), "accepted rows")
      if (allocated(error)) return
      call check(error, abs(sum(history%h(:history%count), &
         mask=history%outcome(:history%count) == attempt_accepted) - 100.0_dp) < 1.0e-9_dp, &
         "accepted steps cover [0, 100]")
      if (allocated(error)) return
      call check(error, all(history%states(:, history%count) == u), "last recorded state")
      if (allocated(error)) return

      call write_history_csv(history, csv, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      open (newunit=unit, file=csv, status="old", action="read")
      lines = 0
      do
         read (unit, *, iostat=io)
         if (io /= 0) exit
         lines = lines + 1
      end do
      close (unit, status="delete")
      call check(error, lines, history%count + 1, "CSV lines")
   end subroutine test_step_history

   !> stats%cpu_seconds and stats%wall_seconds measure the call (a run of a few
   !> thousand steps takes milliseconds, far above the clocks' resolution), and are 0
   !> with options%measure_time off.
   subroutine test_measured_times(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)
      integer :: run

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("si-t-2", scheme, stat)
      options%rtol = 1.0e-6_dp
      options%atol = 1.0e-6_dp
      do run = 1, 2
         options%measure_time = run == 1
         u = van_der_pol_initial_state(vdp_ic_unprepared)
         call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%accepted_steps > 1000, "a run of more than 1000 steps")
         if (allocated(error)) return
         if (options%measure_time) then
            call check(error, stats%wall_seconds > 0.0_dp .and. stats%cpu_seconds >= 0.0_dp, &
               "times measured")
         else
            call check(error, stats%wall_seconds == 0.0_dp .and. stats%cpu_seconds == 0.0_dp, &
               "no times without measure_time")
         end if
         if (allocated(error)) return
      end do
   end subroutine test_measured_times

   subroutine poisoned_f(self, t, u, dudt)
      class(poisoned_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -u
   end subroutine poisoned_f

   subroutine poisoned_g(self, t, u, dudt)
      class(poisoned_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      if (t > 0.0_dp) then
         dudt = ieee_value(1.0_dp, ieee_quiet_nan)
      else
         dudt = -u
      end if
   end subroutine poisoned_g

   subroutine singular_g(self, t, u, dudt)
      class(singular_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = u/max(t, tiny(1.0_dp))
   end subroutine singular_g

   subroutine singular_jac_g(self, t, u, jac)
      class(singular_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 1.0_dp/max(t, tiny(1.0_dp))
   end subroutine singular_jac_g

   subroutine zero_f(self, t, u, dudt)
      class(stiff_only_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = 0.0_dp
   end subroutine zero_f

   subroutine zero_jac(self, t, u, jac)
      class(stiff_only_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
   end subroutine zero_jac

   subroutine blow_up_g(self, t, u, dudt)
      class(blow_up_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = u**2
   end subroutine blow_up_g

   subroutine blow_up_jac_g(self, t, u, jac)
      class(blow_up_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 2.0_dp*u(1)
   end subroutine blow_up_jac_g

   subroutine relaxation_g(self, t, u, dudt)
      class(relaxation_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = [self%lambda*(u(1) - 1.0_dp - 0.5_dp*u(2)), -u(2)]
   end subroutine relaxation_g

   subroutine relaxation_jac_g(self, t, u, jac)
      class(relaxation_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = reshape([self%lambda, 0.0_dp, -0.5_dp*self%lambda, -1.0_dp], [2, 2])
   end subroutine relaxation_jac_g

   subroutine observe_relaxation(self, step, stop)
      class(relaxation_observer), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      logical, intent(inout) :: stop
      real(dp) :: slow
      slow = 1.0_dp + self%c*exp(-step%t_end)
      self%worst = max(self%worst, abs(step%u_end(1) - slow)/(self%tol + self%tol*slow))
   end subroutine observe_relaxation

   subroutine switched_forcing_f(self, t, u, dudt)
      class(switched_forcing_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = merge(1.0_dp, 0.0_dp, t >= 1.0_dp)
   end subroutine switched_forcing_f

   subroutine forced_decay_f(self, t, u, dudt)
      class(forced_decay_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = self%rate*cos(t) - sin(t)
   end subroutine forced_decay_f

   subroutine linear_decay_g(self, t, u, dudt)
      class(linear_decay_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -self%rate*u
   end subroutine linear_decay_g

   subroutine linear_decay_jac_g(self, t, u, jac)
      class(linear_decay_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = -self%rate
   end subroutine linear_decay_jac_g

   subroutine cancelling_residual(self, problem, u, r, counters)
      class(cancelling_system), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      real(dp), contiguous, intent(out) :: r(:)
      type(counters_type), intent(inout) :: counters
      r(1) = (1.0_dp + self%h + 0.5_dp*self%h*self%h)*u(1) - 1.0_dp
   end subroutine cancelling_residual

   subroutine cancelling_matrix(self, problem, u, matrix, counters, stat)
      class(cancelling_system), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      class(matrix_type), intent(inout) :: matrix
      type(counters_type), intent(inout) :: counters
      type(status_type), intent(inout) :: stat
      select type (matrix)
      type is (dense_matrix_type)
         matrix%a = reshape([1.0_dp + self%h, self%h, -0.5_dp*self%h, 1.0_dp], [2, 2])
      end select
   end subroutine cancelling_matrix

   subroutine cubic_g(self, t, u, dudt)
      class(cubic_decay_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -1.0e4_dp*u**3
   end subroutine cubic_g

   subroutine cubic_jac_g(self, t, u, jac)
      class(cubic_decay_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = -3.0e4_dp*u(1)**2
   end subroutine cubic_jac_g

   subroutine poisoned_jac(self, t, u, jac)
      class(poisoned_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = -1.0_dp
   end subroutine poisoned_jac

end module test_integrator
