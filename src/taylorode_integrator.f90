!> The adaptive integrator: embedded error control with the I, PI and PID
!> controllers (METHODS.md section 3), statistics by cause, optional step history
!> and dense output, and failures that return the last good state.
module taylorode_integrator
   use taylorode_kinds, only: dp, i8
   use taylorode_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_step_underflow, status_max_steps, &
      status_singular_matrix, status_newton_diverged, status_newton_not_converged
   use taylorode_problem, only: ode_problem
   use taylorode_scheme, only: scheme_type, implicit_scheme_type, counters_type
   use taylorode_options, only: integrator_options_type, validate_options, norm_max, &
      advance_high, advance_low
   use taylorode_controller, only: controller_factor
   use taylorode_history, only: step_history_type, attempt_accepted, attempt_rejected_error, &
      attempt_failed_newton, attempt_failed_nonfinite
   use taylorode_strings, only: format_integer, format_real
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: integrate, integration_stats_type

   !> Step-size factor after a failed attempt (Newton failure or NaN/Inf values)
   real(dp), parameter :: failure_shrink = 0.25_dp
   !> Steps shorter than this many roundoffs of t cannot advance t reliably (the fast
   !> layers of Van der Pol with mu = 1e6 need steps of ~17 roundoffs of t)
   real(dp), parameter :: roundoff_steps = 2.0_dp

   !> What an integration did and what it cost
   type :: integration_stats_type
      !> Time of the returned state (t_end on success, the last accepted time on failure)
      real(dp) :: t_reached = 0.0_dp
      !> Accepted steps
      integer(i8) :: accepted_steps = 0
      !> Steps rejected by the error test
      integer(i8) :: rejected_error = 0
      !> Attempts that failed in Newton (singular matrix, divergence, no convergence)
      integer(i8) :: rejected_newton = 0
      !> Attempts that produced NaN or Inf
      integer(i8) :: rejected_nonfinite = 0
      !> Evaluations and linear algebra of the integration (scheme and integrator together)
      type(counters_type) :: work
      !> Smallest and largest accepted step size
      real(dp) :: h_min_accepted = huge(1.0_dp), h_max_accepted = 0.0_dp
      !> Wall-clock and CPU seconds spent in `integrate`
      real(dp) :: wall_seconds = 0.0_dp, cpu_seconds = 0.0_dp
   contains
      !> All rejected or failed attempts
      procedure :: rejected_steps
   end type integration_stats_type

contains

   !> Rejected plus failed attempts.
   elemental function rejected_steps(self) result(n)
      class(integration_stats_type), intent(in) :: self
      integer(i8) :: n
      n = self%rejected_error + self%rejected_newton + self%rejected_nonfinite
   end function rejected_steps

   !> Integrate U' = f + g from t0 to t_end (> t0) adaptively with `scheme`.
   !>
   !> u holds U(t0) on entry and U(t_end) on success; on failure it holds the last
   !> accepted state, at stats%t_reached, and stat says why. With `t_out` (ascending
   !> times in [t0, t_end]) the solution at those times comes back in u_out(:, k)
   !> from the cubic Hermite interpolant of each accepted step. With `history`
   !> every attempted step is recorded. Backward integration (t_end < t0) is not
   !> supported: substitute s = -t.
   subroutine integrate(problem, scheme, t0, t_end, u, options, stats, stat, history, t_out, u_out)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> The scheme (see new_scheme); its embedded pair gives the error estimate
      class(scheme_type), intent(inout) :: scheme
      !> Initial time
      real(dp), intent(in) :: t0
      !> Final time, > t0
      real(dp), intent(in) :: t_end
      !> Initial state on entry, final (or last good) state on exit
      real(dp), intent(inout) :: u(:)
      !> Tolerances, controller and limits
      type(integrator_options_type), intent(in) :: options
      !> Steps, rejections by cause, evaluations, step sizes, times
      type(integration_stats_type), intent(out) :: stats
      !> Outcome
      type(status_type), intent(out) :: stat
      !> Every attempted step, when present
      type(step_history_type), intent(inout), optional :: history
      !> Output times for dense output
      real(dp), intent(in), optional :: t_out(:)
      !> Dense output, size(u) x size(t_out)
      real(dp), intent(out), optional :: u_out(:, :)

      type(counters_type) :: work_before
      type(status_type) :: step_stat
      real(dp), allocatable :: u_new(:), delta(:), weights(:), newton_tolerance(:), scratch(:), rhs_old(:), rhs_new(:)
      real(dp) :: t, h, h_next, err, err_previous, err_before, q, factor, nan
      integer(i8) :: attempts, newton_before, clock_start, clock_rate, clock_end
      real(dp) :: cpu_start, cpu_end
      integer :: failures, n, next_output, outcome
      logical :: last, dense

      call system_clock(clock_start, clock_rate)
      call cpu_time(cpu_start)
      work_before = scheme%counters
      stats%t_reached = t0
      n = size(u)
      dense = present(t_out)
      nan = ieee_value(1.0_dp, ieee_quiet_nan)

      call check_arguments()
      if (stat%code /= status_ok) then
         call finish()
         return
      end if

      allocate (u_new(n), delta(n), weights(n), newton_tolerance(n), scratch(n))
      call scheme%prepare(problem, n)
      call scheme%restart()
      select type (scheme)
      class is (implicit_scheme_type)
         scheme%max_newton_iterations = options%max_newton_iterations
         scheme%reuse_newton_matrix = options%reuse_newton_matrix
      end select
      q = options%q
      if (q == 0.0_dp) q = real(min(scheme%order, scheme%embedded_order) + 1, dp)

      t = t0
      next_output = 1
      if (dense) then
         allocate (rhs_old(n), rhs_new(n))
         call full_rhs(t, u, rhs_old)
         call emit_outputs_at_start()
      end if
      h = options%h0
      if (h == 0.0_dp) h = initial_step()
      h = min(h, options%h_max)

      err_previous = 1.0_dp
      err_before = 1.0_dp
      attempts = 0
      failures = 0
      do while (t < t_end)
         if (attempts >= options%max_steps) then
            call set_status(stat, status_max_steps, "integrate: maximum number of steps ("// &
               format_integer(options%max_steps)//") reached at t = "//format_real(t, 6))
            exit
         end if
         last = t + h >= t_end - roundoff_steps*epsilon(1.0_dp)*abs(t_end)
         if (last) h = t_end - t
         if (h < options%h_min .or. h <= roundoff_steps*epsilon(1.0_dp)*abs(t)) then
            call set_status(stat, status_step_underflow, "integrate: step size "//format_real(h, 6)// &
               " below the minimum step or the roundoff of t = "//format_real(t, 6))
            exit
         end if
         attempts = attempts + 1

         call error_weights(u, u)
         newton_tolerance = options%newton_fraction*weights
         newton_before = scheme%counters%newton_iterations
         step_stat = status_type()
         call scheme%advance(problem, t, h, u, u_new, step_stat, delta, newton_tolerance)
         if (step_stat%code == status_ok) then
            if (.not. (all(ieee_is_finite(u_new)) .and. all(ieee_is_finite(delta)))) then
               call set_status(step_stat, status_nonfinite, "the new state or the error estimate is NaN or Inf")
            end if
         end if

         if (step_stat%code /= status_ok) then
            ! failed attempt: retry from the same state with a smaller step
            failures = failures + 1
            if (step_stat%code == status_nonfinite) then
               stats%rejected_nonfinite = stats%rejected_nonfinite + 1
               outcome = attempt_failed_nonfinite
            else
               stats%rejected_newton = stats%rejected_newton + 1
               outcome = attempt_failed_newton
            end if
            call record_attempt(nan, outcome, newton_before)
            if (failures >= options%max_failures) then
               call set_status(stat, step_stat%code, "integrate: gave up after "//format_integer(int(failures, i8))// &
                  " consecutive failed attempts at t = "//format_real(t, 6)//", last: "//step_stat%message)
               exit
            end if
            h = failure_shrink*h
            cycle
         end if
         failures = 0

         if (options%advance == advance_high .and. scheme%order < scheme%embedded_order) then
            u_new = u_new + delta
         else if (options%advance == advance_low .and. scheme%order > scheme%embedded_order) then
            u_new = u_new - delta
         end if
         call error_weights(u, u_new)
         err = weighted_norm(delta)
         factor = controller_factor(options%controller, options%kappa, q, err, err_previous, err_before)
         if (options%max_growth > 0.0_dp) factor = min(factor, options%max_growth)
         if (options%min_shrink > 0.0_dp) factor = max(factor, options%min_shrink)
         h_next = min(factor*h, options%h_max)

         if (err <= 1.0_dp) then
            call record_attempt(err, attempt_accepted, newton_before, u_new)
            stats%accepted_steps = stats%accepted_steps + 1
            stats%h_min_accepted = min(stats%h_min_accepted, h)
            stats%h_max_accepted = max(stats%h_max_accepted, h)
            if (dense) call emit_outputs(t, h, u, u_new)
            u = u_new
            if (last) then
               t = t_end
            else
               t = t + h
            end if
            stats%t_reached = t
            err_before = err_previous
            err_previous = err
         else
            call record_attempt(err, attempt_rejected_error, newton_before)
            stats%rejected_error = stats%rejected_error + 1
         end if
         h = h_next
      end do
      call finish()

   contains

      !> Validate sizes, times, the initial state and the options.
      subroutine check_arguments()
         if (n < 1) then
            call set_status(stat, status_size_mismatch, "integrate: the state is empty")
            return
         end if
         if (.not. (ieee_is_finite(t0) .and. ieee_is_finite(t_end))) then
            call set_status(stat, status_invalid_argument, "integrate: t0 and t_end must be finite")
            return
         end if
         if (.not. (t_end > t0)) then
            call set_status(stat, status_invalid_argument, "integrate: t_end must be greater than t0 "// &
               "(backward integration is not supported: substitute s = -t)")
            return
         end if
         if (.not. all(ieee_is_finite(u))) then
            call set_status(stat, status_nonfinite, "integrate: the initial state contains NaN or Inf")
            return
         end if
         call validate_options(options, n, stat)
         if (stat%code /= status_ok) return
         if (present(t_out) .neqv. present(u_out)) then
            call set_status(stat, status_invalid_argument, "integrate: t_out and u_out go together")
            return
         end if
         if (present(t_out)) then
            if (size(u_out, 1) /= n .or. size(u_out, 2) /= size(t_out)) then
               call set_status(stat, status_size_mismatch, "integrate: u_out must be size(u) x size(t_out)")
               return
            end if
            if (size(t_out) > 0) then
               if (t_out(1) < t0 .or. t_out(size(t_out)) > t_end .or. &
                  any(t_out(2:) < t_out(:size(t_out) - 1)) .or. any(.not. ieee_is_finite(t_out))) then
                  call set_status(stat, status_invalid_argument, &
                     "integrate: t_out must be ascending and inside [t0, t_end]")
                  return
               end if
            end if
            u_out = nan
         end if
      end subroutine check_arguments

      !> w_i = atol_i + rtol * max(|a_i|, |b_i|)
      subroutine error_weights(a, b)
         real(dp), intent(in) :: a(:), b(:)
         if (allocated(options%atol_vector)) then
            weights = options%atol_vector + options%rtol*max(abs(a), abs(b))
         else
            weights = options%atol + options%rtol*max(abs(a), abs(b))
         end if
      end subroutine error_weights

      !> Max or RMS norm of v / w
      real(dp) function weighted_norm(v)
         real(dp), intent(in) :: v(:)
         if (options%norm == norm_max) then
            weighted_norm = maxval(abs(v)/weights)
         else
            weighted_norm = sqrt(sum((v/weights)**2)/real(n, dp))
         end if
      end function weighted_norm

      !> h0 = 0.01 |U0|_w / |F(U0)|_w (1e-6 when either is tiny), at most t_end - t0.
      real(dp) function initial_step()
         real(dp) :: size_u, size_f
         real(dp), allocatable :: rhs(:)
         allocate (rhs(n))
         call full_rhs(t0, u, rhs)
         call error_weights(u, u)
         size_u = weighted_norm(u)
         size_f = weighted_norm(rhs)
         if (size_u < 1.0e-5_dp .or. size_f < 1.0e-5_dp .or. .not. ieee_is_finite(size_f)) then
            initial_step = 1.0e-6_dp
         else
            initial_step = 0.01_dp*size_u/size_f
         end if
         initial_step = max(min(initial_step, t_end - t0), options%h_min)
      end function initial_step

      !> F = f + g through the scheme's counted evaluations
      subroutine full_rhs(time, state, rhs)
         real(dp), intent(in) :: time, state(:)
         real(dp), intent(out) :: rhs(:)
         call scheme%eval_f(problem, time, state, rhs)
         call scheme%eval_g(problem, time, state, scratch)
         rhs = rhs + scratch
      end subroutine full_rhs

      !> Output times equal to t0 take the initial state.
      subroutine emit_outputs_at_start()
         do while (next_output <= size(t_out))
            if (t_out(next_output) > t0) exit
            u_out(:, next_output) = u
            next_output = next_output + 1
         end do
      end subroutine emit_outputs_at_start

      !> Cubic Hermite interpolation on the accepted step [ts, ts + hs] for every
      !> output time inside it; rhs_old = F(u_a) on entry, F(u_b) on exit.
      subroutine emit_outputs(ts, hs, u_a, u_b)
         real(dp), intent(in) :: ts, hs, u_a(:), u_b(:)
         real(dp) :: theta, h00, h10, h01, h11, t_b
         t_b = merge(t_end, ts + hs, last)
         call full_rhs(t_b, u_b, rhs_new)
         do while (next_output <= size(t_out))
            if (t_out(next_output) > t_b) exit
            theta = (t_out(next_output) - ts)/hs
            h00 = (1.0_dp + 2.0_dp*theta)*(1.0_dp - theta)**2
            h10 = theta*(1.0_dp - theta)**2
            h01 = theta**2*(3.0_dp - 2.0_dp*theta)
            h11 = theta**2*(theta - 1.0_dp)
            u_out(:, next_output) = h00*u_a + (h10*hs)*rhs_old + h01*u_b + (h11*hs)*rhs_new
            next_output = next_output + 1
         end do
         rhs_old = rhs_new
      end subroutine emit_outputs

      !> Append the attempt to the history, when one is kept.
      subroutine record_attempt(err_value, outcome_value, newton_start, state)
         real(dp), intent(in) :: err_value
         integer, intent(in) :: outcome_value
         integer(i8), intent(in) :: newton_start
         real(dp), intent(in), optional :: state(:)
         integer :: iterations
         if (.not. present(history)) return
         iterations = int(scheme%counters%newton_iterations - newton_start)
         if (options%history_states) then
            if (present(state)) then
               call history%record(t, h, err_value, outcome_value, iterations, state)
            else
               call history%record(t, h, err_value, outcome_value, iterations, u)
            end if
         else
            call history%record(t, h, err_value, outcome_value, iterations)
         end if
      end subroutine record_attempt

      !> Work counters and times of this call.
      subroutine finish()
         stats%work%f_evaluations = scheme%counters%f_evaluations - work_before%f_evaluations
         stats%work%g_evaluations = scheme%counters%g_evaluations - work_before%g_evaluations
         stats%work%jac_f_evaluations = scheme%counters%jac_f_evaluations - work_before%jac_f_evaluations
         stats%work%jac_g_evaluations = scheme%counters%jac_g_evaluations - work_before%jac_g_evaluations
         stats%work%lu_factorizations = scheme%counters%lu_factorizations - work_before%lu_factorizations
         stats%work%linear_solves = scheme%counters%linear_solves - work_before%linear_solves
         stats%work%newton_iterations = scheme%counters%newton_iterations - work_before%newton_iterations
         if (stats%accepted_steps == 0) stats%h_min_accepted = 0.0_dp
         call cpu_time(cpu_end)
         call system_clock(clock_end)
         stats%cpu_seconds = cpu_end - cpu_start
         stats%wall_seconds = real(clock_end - clock_start, dp)/real(max(clock_rate, 1_i8), dp)
      end subroutine finish

   end subroutine integrate

end module taylorode_integrator
