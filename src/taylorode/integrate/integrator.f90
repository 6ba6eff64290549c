!> The adaptive integrator: embedded error control with the I, PI and PID
!> controllers (METHODS.md section 3), statistics by cause, optional step history
!> and dense output, and failures that return the last good state.
module taylorode_integrate_integrator
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_step_underflow, status_max_steps, status_evaluation_failed, &
      status_output_error, status_description
   use taylorode_base_counters, only: counters_type
   use taylorode_problem_ode, only: ode_problem
   use taylorode_schemes_scheme, only: scheme_type, evaluate_rhs
   use taylorode_integrate_options, only: integrator_options_type, validate_options
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_stepper, only: stepper_type
   use taylorode_integrate_dense_output, only: dense_output_type
   use taylorode_integrate_history, only: step_history_type, attempt_accepted, attempt_rejected_error, &
      attempt_failed_nonfinite, attempt_failed_evaluation
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: integrate

   !> Step-size factor after a failed attempt (Newton failure or NaN/Inf values)
   real(dp), parameter :: failure_shrink = 0.25_dp
   !> Steps shorter than this many roundoffs of t cannot advance t reliably (the fast
   !> layers of Van der Pol with mu = 1e6 need steps of ~17 roundoffs of t)
   real(dp), parameter :: roundoff_steps = 2.0_dp

contains

   !> Integrate U' = f + g from t0 to t_end (> t0) adaptively with `scheme`.
   !>
   !> u holds U(t0) on entry and U(t_end) on success; on failure it holds the last
   !> accepted state, at stats%t_reached, and stat says why. With `t_out` (ascending
   !> times in [t0, t_end]) the solution at those times comes back in u_out(:, k)
   !> from the cubic Hermite interpolant of each accepted step. With `history`
   !> every attempted step is recorded. Backward integration (t_end < t0) is not
   !> supported: substitute s = -t.
   !>
   !> Failed attempts (Newton failure, NaN or Inf, an evaluation the problem rejected)
   !> are retried from the same state with a quarter of the step; the integration
   !> gives up after options%max_failures consecutive ones, or after as many NaN/Inf
   !> or rejected evaluations without getting past the point where the first of them
   !> happened (status_nonfinite, status_evaluation_failed). Messages are built in
   !> fixed-length buffers, so concurrent integrations on separate objects are safe.
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
      type(stepper_type) :: stepper
      type(dense_output_type) :: output
      real(dp), allocatable :: scratch(:)
      real(dp) :: t, h, h_next, err, nan, trouble_end
      integer(i8) :: attempts, newton_before, clock_start, clock_rate, clock_end
      real(dp) :: cpu_start, cpu_end
      integer :: failures, troubles, n, outcome
      logical :: last
      character(len=400) :: text

      call system_clock(clock_start, clock_rate)
      call cpu_time(cpu_start)
      work_before = scheme%counters
      stats%t_reached = t0
      n = size(u)
      nan = ieee_value(1.0_dp, ieee_quiet_nan)

      call check_arguments()
      if (stat%code == status_ok) call scheme%prepare(problem, n, stat)
      if (stat%code /= status_ok) then
         call finish()
         return
      end if
      if (present(history)) then
         call history%start(merge(n, 0, options%history_states), stat)
         if (stat%code /= status_ok) then
            call finish()
            return
         end if
      end if
      call scheme%restart()
      call stepper%start(n, scheme, options)
      allocate (scratch(n))

      t = t0
      if (present(t_out) .or. options%h0 == 0.0_dp) then
         ! F(t0, U0) serves dense output and the first step size: it must be usable
         call problem%clear_rejection()
         call evaluate_rhs(problem, t, u, stepper%delta, scratch, scheme%counters)
         if (problem%evaluation_rejected()) then
            call set_status(stat, status_evaluation_failed, &
               "integrate: the problem cannot evaluate f or g at the initial state")
         else if (.not. all(ieee_is_finite(stepper%delta))) then
            call set_status(stat, status_nonfinite, "integrate: f or g is NaN or Inf at the initial state")
         end if
         if (stat%code /= status_ok) then
            call finish()
            return
         end if
      end if
      if (present(t_out)) call output%start(t0, u, stepper%delta, t_out, u_out)
      h = options%h0
      if (h == 0.0_dp) h = initial_step()
      h = min(h, options%h_max)

      attempts = 0
      failures = 0
      troubles = 0
      trouble_end = t0
      err = nan
      do while (t < t_end)
         if (attempts >= options%max_steps) then
            write (text, '("integrate: maximum number of steps (", i0, ") reached at t = ", es13.6e3)') &
               options%max_steps, t
            call set_status(stat, status_max_steps, trim(text))
            exit
         end if
         last = t + h >= t_end - roundoff_steps*epsilon(1.0_dp)*abs(t_end)
         if (last) h = t_end - t
         if (h < options%h_min .or. h <= roundoff_steps*epsilon(1.0_dp)*abs(t)) then
            write (text, '("integrate: step size ", es13.6e3, " below the minimum step or the roundoff of t = ", &
               &es13.6e3)') h, t
            call set_status(stat, status_step_underflow, trim(text))
            exit
         end if
         attempts = attempts + 1
         newton_before = scheme%counters%newton_iterations
         err = nan
         call stepper%attempt(problem, scheme, options, t, h, u, outcome, err, h_next, step_stat)

         select case (outcome)
         case (attempt_accepted)
            failures = 0
            if (t + h > trouble_end) troubles = 0
            call record_attempt(err, outcome, newton_before, stepper%u_new)
            stats%accepted_steps = stats%accepted_steps + 1
            stats%h_min_accepted = min(stats%h_min_accepted, h)
            stats%h_max_accepted = max(stats%h_max_accepted, h)
            if (present(t_out)) call emit_outputs()
            u = stepper%u_new
            if (last) then
               t = t_end
            else
               t = t + h
            end if
            stats%t_reached = t
            h = h_next
         case (attempt_rejected_error)
            failures = 0
            call record_attempt(err, outcome, newton_before, u)
            stats%rejected_error = stats%rejected_error + 1
            h = h_next
         case default
            ! failed attempt: retry from the same state with a smaller step
            failures = failures + 1
            select case (outcome)
            case (attempt_failed_nonfinite, attempt_failed_evaluation)
               if (outcome == attempt_failed_nonfinite) then
                  stats%rejected_nonfinite = stats%rejected_nonfinite + 1
               else
                  stats%rejected_evaluation = stats%rejected_evaluation + 1
               end if
               if (troubles == 0) trouble_end = t + h
               troubles = troubles + 1
            case default
               stats%rejected_newton = stats%rejected_newton + 1
            end select
            call record_attempt(nan, outcome, newton_before, u)
            if (failures >= options%max_failures) then
               write (text, '("integrate: gave up after ", i0, " consecutive failed attempts at t = ", es13.6e3, &
                  &", last: ", a)') failures, t, trim(status_description(step_stat%code))
               call set_status(stat, step_stat%code, trim(text))
               exit
            end if
            if (troubles >= options%max_failures) then
               write (text, '("integrate: ", a, " in ", i0, " attempts that could not get past t = ", es13.6e3, &
                  &" (stopped at t = ", es13.6e3, ")")') trim(status_description(step_stat%code)), troubles, &
                  trouble_end, t
               call set_status(stat, step_stat%code, trim(text))
               exit
            end if
            h = failure_shrink*h
         end select
         if (present(history)) then
            if (history%failed()) then
               call set_status(stat, status_output_error, "integrate: the step history could not be written")
               exit
            end if
         end if
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

      !> h0 = 0.01 |U0|_w / |F(U0)|_w (1e-6 when either is tiny), at most t_end - t0;
      !> F(U0) is in stepper%delta.
      real(dp) function initial_step()
         real(dp) :: size_u, size_f
         call stepper%set_weights(options, u, u)
         size_u = stepper%weighted_norm(options, u)
         size_f = stepper%weighted_norm(options, stepper%delta)
         if (size_u < 1.0e-5_dp .or. size_f < 1.0e-5_dp .or. .not. ieee_is_finite(size_f)) then
            initial_step = 1.0e-6_dp
         else
            initial_step = 0.01_dp*size_u/size_f
         end if
         initial_step = max(min(initial_step, t_end - t0), options%h_min)
      end function initial_step

      !> Dense output inside the accepted step [t, t + h] (t_end on the last step).
      subroutine emit_outputs()
         real(dp) :: t_b
         t_b = merge(t_end, t + h, last)
         call evaluate_rhs(problem, t_b, stepper%u_new, output%rhs_end, scratch, scheme%counters)
         call output%emit(t, h, t_b, u, stepper%u_new, t_out, u_out)
      end subroutine emit_outputs

      !> Append the attempt to the history, when one is kept (with the state after it:
      !> the new state of an accepted step, else the unchanged one).
      subroutine record_attempt(err_value, outcome_value, newton_start, state)
         real(dp), intent(in) :: err_value
         integer, intent(in) :: outcome_value
         integer(i8), intent(in) :: newton_start
         real(dp), intent(in) :: state(:)
         if (.not. present(history)) return
         call history%record(t, h, err_value, outcome_value, &
            int(scheme%counters%newton_iterations - newton_start), state)
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
         stats%weights_raised = stepper%weights_raised
         call cpu_time(cpu_end)
         call system_clock(clock_end)
         stats%cpu_seconds = cpu_end - cpu_start
         stats%wall_seconds = real(clock_end - clock_start, dp)/real(max(clock_rate, 1_i8), dp)
      end subroutine finish

   end subroutine integrate

end module taylorode_integrate_integrator
