!> The adaptive integrator: embedded error control with the I, PI and PID
!> controllers (METHODS.md section 3), statistics by cause, optional step history,
!> dense output, an observer and events, failures that return the last good state,
!> and continuation: an `integrator_type` keeps the step size, the controller's
!> memory and (in the scheme) the factored Newton matrices from one `advance_to` to
!> the next, so that many short calls cost what one long call costs.
module taylorode_integrate_integrator
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, describe, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_step_underflow, status_max_steps, status_evaluation_failed, &
      status_output_error, status_out_of_memory, status_description, status_singular_matrix
   use taylorode_base_memory, only: out_of_memory, real_bytes, sized
   use taylorode_base_counters, only: counters_type, operator(+), operator(-)
   use taylorode_base_strings, only: fixed_length_real
   use taylorode_problem_ode, only: ode_problem
   use taylorode_schemes_scheme, only: scheme_type, evaluate_rhs
   use taylorode_integrate_options, only: integrator_options_type, validate_options, estimate_defect, copy_options
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_stepper, only: stepper_type
   use taylorode_integrate_reduction, only: agree_on_outcome, finite_everywhere
   use taylorode_integrate_step, only: accepted_step_type
   use taylorode_integrate_observer, only: step_observer_type
   use taylorode_integrate_events, only: event_functions_type
   use taylorode_integrate_history, only: step_history_type, attempt_accepted, attempt_rejected_error, &
      attempt_failed_nonfinite, attempt_failed_evaluation, attempt_rejected_constraint, attempt_rejected_output
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: integrate, integrator_type

   !> Steps shorter than this many roundoffs of t cannot advance t reliably (the fast
   !> layers of Van der Pol with mu = 1e6 need steps of ~17 roundoffs of t)
   real(dp), parameter :: roundoff_steps = 2.0_dp
   !> What a call with only one of t_out and u_out is told
   character(len=*), parameter :: outputs_together = "integrate: t_out and u_out go together"
   !> States kept for the dense output: the current one and the starts of three steps
   !> before (the interpolant through four states and its error estimate)
   integer, parameter :: ring_size = 4
   !> Attempts of one call whose Newton matrix is singular before the integration gives
   !> up with status_singular_matrix (RADAU5's NSING limit: a singular matrix at one step
   !> size is cured by the next, a matrix singular again and again is the problem's)
   integer, parameter :: singular_limit = 5
   !> A step whose dense output fails its error test in the middle (with events) is
   !> retried with h times 0.9 (1/estimate)^(1/(degree + 1)), at least 0.2 h
   real(dp), parameter :: event_safety = 0.9_dp, min_event_shrink = 0.2_dp
   !> NaN/Inf values or rejected evaluations in attempts that do not get past the point
   !> where the first of them happened, before giving up (when options%max_failures
   !> is 0: no limit on consecutive failures)
   integer, parameter :: trouble_limit = 10
   !> First step relative to max(1, |t0|) when the initial data give none (RADAU5's 1e-6)
   real(dp), parameter :: first_step_fallback = 1.0e-6_dp

   !> An integration that can be continued: `init` once, then `advance_to` as often as
   !> needed with the same problem type and scheme. Between calls the caller may
   !> change the state (operator splitting): the next call starts from the state it
   !> is given, with the step size, the controller's memory and the scheme's factored
   !> Newton matrices kept.
   type :: integrator_type
      !> Tolerances, controller and limits (validated by init)
      type(integrator_options_type) :: options
      !> Current time and the step size the next call starts with
      real(dp) :: t = 0.0_dp, h = 0.0_dp
      !> What t lacks of the time the state is at, t0 plus the steps taken, which t
      !> rounds (compensated summation: t is that time rounded, so that it does not
      !> drift from the state by a rounding of every step; the last step absorbs it)
      real(dp) :: t_low = 0.0_dp
      !> Statistics since init (each call also returns its own)
      type(integration_stats_type) :: total
      !> Unknowns
      integer :: n = 0
      !> Whether init succeeded (advance_to refuses to run otherwise)
      logical :: ready = .false.
      !> Name of the scheme init prepared (later calls must pass the same scheme)
      character(len=:), allocatable :: scheme_name
      !> One attempt's work arrays and the controller's memory
      type(stepper_type) :: stepper
      !> The last accepted step (states and derivatives at both ends), kept when dense
      !> output, events or an observer need it
      type(accepted_step_type) :: step
      !> The last states of the solution (when dense output, events or an observer need
      !> them), newest first from ring_newest: the current state and the starts of the
      !> last three accepted steps, for the interpolant through states and the dense
      !> output's error estimate. Their times:
      real(dp) :: ring_t(ring_size) = 0.0_dp
      !> The states, one column each
      real(dp), allocatable :: ring_u(:, :)
      !> Slot of the newest state
      integer :: ring_newest = 1
      !> States kept (0 to ring_size)
      integer :: ring_count = 0
   contains
      !> Check everything and prepare the scheme at (t0, u0)
      procedure :: init
      !> Integrate from the current time to t_target
      procedure :: advance_to
   end type integrator_type

contains

   !> Integrate U' = f + g from t0 to t_end (> t0) adaptively with `scheme`.
   !>
   !> u holds U(t0) on entry and U(t_end) on success; on failure it holds the last
   !> accepted state, at stats%t_reached, and stat says why. With `t_out` (ascending
   !> times in [t0, t_end]) the solution at those times comes back in u_out(:, k)
   !> from the dense output of each accepted step (the scheme's own continuous
   !> extension, else the cubic Hermite interpolant). With `history`
   !> every attempted step is recorded (a history streamed into a file is finished when
   !> integrate returns, whatever the outcome; one that cannot be written is
   !> status_output_error); `observer` is called after every accepted
   !> step; `events` locates zero crossings (a terminal one ends the integration
   !> there, with status ok). Backward integration (t_end < t0) is not supported:
   !> substitute s = -t.
   !>
   !> Failed attempts (Newton failure, NaN or Inf, an evaluation the problem rejected)
   !> are retried from the same state with a quarter of the step (after a Newton
   !> failure: the scheme's factor, by default the same quarter), for as long as the
   !> step size stays above h_min and the roundoff of t (status_step_underflow, whose
   !> message names the last failure) and the step budget lasts, as RADAU5 does. The
   !> integration also gives up after the fifth attempt of a call whose Newton matrix
   !> is singular (status_singular_matrix, RADAU5's limit), after 10 NaN/Inf or rejected
   !> evaluations without getting past the point where the first of them happened
   !> (status_nonfinite, status_evaluation_failed), and, when options%max_failures > 0,
   !> after that many consecutive failed attempts. Messages are built in fixed-length
   !> buffers, so concurrent integrations on separate objects are safe.
   subroutine integrate(problem, scheme, t0, t_end, u, options, stats, stat, history, t_out, u_out, observer, events)
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
      !> Called after every accepted step
      class(step_observer_type), intent(inout), optional :: observer
      !> Event functions whose crossings are located
      class(event_functions_type), intent(inout), optional :: events
      type(integrator_type) :: integrator

      stats%t_reached = t0
      if (.not. (ieee_is_finite(t_end) .and. t_end > t0)) then
         call set_status(stat, status_invalid_argument, "integrate: t_end must be finite and greater than t0 "// &
            "(backward integration is not supported: substitute s = -t)")
         call complete_stream(history, stat)
         return
      end if
      if (present(t_out) .neqv. present(u_out)) then
         call set_status(stat, status_invalid_argument, outputs_together)
         call complete_stream(history, stat)
         return
      end if
      call integrator%init(problem, scheme, t0, u, options, stat)
      if (stat%code /= status_ok) then
         stats = integrator%total
         stats%t_reached = t0
         call complete_stream(history, stat)
         return
      end if
      ! output arrays are passed on only when given: gfortran builds a descriptor for an
      ! assumed-shape array it passes on, from the strides of an absent one too (arithmetic
      ! on undefined values, which UBSan reports)
      if (present(t_out)) then
         call integrator%advance_to(problem, scheme, t_end, u, stat, stats, history, t_out, u_out, observer, events)
      else
         call integrator%advance_to(problem, scheme, t_end, u, stat, stats, history, observer=observer, events=events)
      end if
      ! the work of init (F at t0 for the first step size) belongs to this integration
      stats%work = integrator%total%work
      call complete_stream(history, stat)
   end subroutine integrate

   !> The end of integrate: a history streamed into a file is finished (renamed into
   !> place when every row was written, else removed). A history that could not be
   !> written makes the call's status status_output_error, with the reason the
   !> integration stopped before, if it did, in the message.
   subroutine complete_stream(history, stat)
      type(step_history_type), intent(inout), optional :: history
      type(status_type), intent(inout) :: stat
      type(status_type) :: file_stat
      if (.not. present(history)) return
      call history%finish(file_stat)
      if (file_stat%code == status_ok) return
      if (stat%code == status_ok .or. stat%code == status_output_error) then
         stat = file_stat
      else
         call set_status(stat, status_output_error, file_stat%message//"; the integration had stopped before: "// &
            stat%message)
      end if
   end subroutine complete_stream

   !> Check the sizes, times, initial state and options, prepare the scheme for the
   !> problem (forgetting what it kept from earlier integrations) and choose the first
   !> step size (options%h0, or 0.01 |U0|_w / |F(U0)|_w; when either norm is tiny, or
   !> the problem has a mass matrix, 1e-6 max(1, |t0|), which stays above the roundoff
   !> of t0).
   subroutine init(self, problem, scheme, t0, u0, options, stat)
      !> The integrator
      class(integrator_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> The scheme
      class(scheme_type), intent(inout) :: scheme
      !> Initial time
      real(dp), intent(in) :: t0
      !> Initial state
      real(dp), intent(in) :: u0(:)
      !> Tolerances, controller and limits
      type(integrator_options_type), intent(in) :: options
      !> Outcome
      type(status_type), intent(out) :: stat
      type(counters_type) :: work_before
      real(dp) :: size_u, size_f
      character(len=300) :: refusal

      self%ready = .false.
      ! the last accepted step of an earlier integration does not precede the first of this one
      self%step%degree = 0
      self%ring_count = 0
      self%total = integration_stats_type()
      self%total%t_reached = t0
      self%t = t0
      self%t_low = 0.0_dp
      self%n = size(u0)
      if (self%n < 1) then
         call set_status(stat, status_size_mismatch, "integrate: the state is empty")
         return
      end if
      if (.not. ieee_is_finite(t0)) then
         call set_status(stat, status_invalid_argument, "integrate: t0 must be finite")
         return
      end if
      if (.not. finite_everywhere(problem, u0)) then
         call set_status(stat, status_nonfinite, "integrate: the initial state contains NaN or Inf")
         return
      end if
      call validate_options(options, self%n, stat)
      if (stat%code /= status_ok) return
      if (allocated(options%nonnegative)) then
         if (any(options%nonnegative .and. u0 < 0.0_dp)) then
            call set_status(stat, status_invalid_argument, "integrate: a component declared nonnegative is "// &
               "negative in the initial state")
            return
         end if
      end if
      if (options%error_estimate == estimate_defect .and. .not. scheme%estimates_step_error) then
         call set_status(stat, status_invalid_argument, "integrate: error_estimate = estimate_defect needs a "// &
            "scheme that estimates the error of its own step (si-t-2); "//scheme%name//" has none")
         return
      end if
      if (scheme%implicit .and. options%max_newton_iterations > 0 .and. &
         options%max_newton_iterations < scheme%least_newton_iterations .and. &
         .not. (problem%linear_g .and. scheme%newton_linear_in_g)) then
         ! (else no solve could converge: the step fell to roundoff, the budget ran out)
         write (refusal, '("integrate: max_newton_iterations must be at least ", i0, " for ", a, &
            &" (its Newton takes no first increment of a new matrix alone; 1 only with g linear for a scheme &
            &implicit in g alone), or 0 for the scheme''s own")') &
            scheme%least_newton_iterations, scheme%name
         call set_status(stat, status_invalid_argument, trim(refusal))
         return
      end if
      call scheme%prepare(problem, self%n, stat)
      if (stat%code /= status_ok) return
      call copy_options(options, self%options, stat)
      if (stat%code /= status_ok) return
      self%scheme_name = scheme%name
      call scheme%restart()
      call self%stepper%start(self%n, scheme, options, stat)
      if (stat%code /= status_ok) return

      self%h = options%h0
      if (self%h == 0.0_dp .and. problem%has_mass) then
         ! F is M U', not U': no estimate from it; RADAU5's first step (1e-6)
         self%h = first_step_fallback*max(1.0_dp, abs(t0))
      else if (self%h == 0.0_dp) then
         ! the Newton guess's array as the estimate's work space (allocated here only when
         ! h is estimated: a run from a given h0 has no use for it unless Newton extrapolates)
         call sized(self%stepper%guess, self%n, "the first step size's work space", stat)
         if (stat%code /= status_ok) return
         work_before = scheme%counters
         call evaluate_start(self, problem, scheme, t0, u0, self%stepper%delta, stat)
         call add_work(self%total, scheme%counters, work_before)
         if (stat%code /= status_ok) return
         call first_step_size()
         if (stat%code /= status_ok) return
      end if
      self%h = min(self%h, options%h_max)
      self%ready = .true.

   contains

      !> The first step size, as Hairer's HINIT chooses it: h = 0.01 |U0|_w / |F0|_w
      !> from the first derivative, then the second derivative estimated from an Euler
      !> step of that size, |F(U0 + h F0) - F0|_w / h (at least |F0|_w), limits h to (0.01 / y'')^(1/p)
      !> (p the scheme's order; at most 100 times the first guess). Without a usable
      !> size (a zero state or derivative) h = 1e-6 max(1, |t0|).
      subroutine first_step_size()
         real(dp) :: second_derivative, limit, fallback
         fallback = first_step_fallback*max(1.0_dp, abs(t0))
         call self%stepper%set_weights(problem, options, u0, u0)
         size_u = self%stepper%weighted_norm(problem, options, u0)
         size_f = self%stepper%weighted_norm(problem, options, self%stepper%delta)
         if (size_u < 1.0e-5_dp .or. size_f < 1.0e-5_dp .or. .not. ieee_is_finite(size_f)) then
            self%h = fallback
         else
            self%h = 0.01_dp*size_u/size_f
         end if
         self%h = min(max(self%h, options%h_min), options%h_max)
         ! F at the end of an Euler step of size h (u_new and the Newton guess as work space)
         self%stepper%u_new = u0 + self%h*self%stepper%delta
         work_before = scheme%counters
         call evaluate_start(self, problem, scheme, t0 + self%h, self%stepper%u_new, self%stepper%guess, stat)
         call add_work(self%total, scheme%counters, work_before)
         if (stat%code /= status_ok) then
            ! an Euler step can leave where F is defined: keep the first guess
            stat = status_type()
            return
         end if
         self%stepper%guess = self%stepper%guess - self%stepper%delta
         second_derivative = self%stepper%weighted_norm(problem, options, self%stepper%guess)/self%h
         second_derivative = max(second_derivative, size_f)
         if (second_derivative <= 1.0e-15_dp) then
            limit = max(fallback, 1.0e-3_dp*self%h)
         else
            limit = (0.01_dp/second_derivative)**(1.0_dp/real(max(scheme%nonlinear_order, 1), dp))
         end if
         self%h = max(min(100.0_dp*self%h, limit), options%h_min)
      end subroutine first_step_size

   end subroutine init

   !> F(t, u) into rhs; a rejected evaluation or NaN/Inf there is an error.
   subroutine evaluate_start(self, problem, scheme, t, u, rhs, stat)
      type(integrator_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      class(scheme_type), intent(inout) :: scheme
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: rhs(:)
      type(status_type), intent(inout) :: stat
      call problem%clear_rejection()
      call evaluate_rhs(problem, t, u, rhs, scheme%counters)
      if (problem%evaluation_rejected()) then
         call set_status(stat, status_evaluation_failed, "integrate: the problem cannot evaluate f or g at the "// &
            "initial state")
         call problem%memory_failure(stat)
      else if (.not. all(ieee_is_finite(rhs))) then
         call set_status(stat, status_nonfinite, "integrate: f or g is NaN or Inf at the initial state")
      end if
      call agree_on_outcome(problem, stat)
      call describe(stat, "integrate: at the initial state")
   end subroutine evaluate_start

   !> Integrate from the current time to t_target (> current time) with the same
   !> problem and scheme as init. u holds the state at the current time on entry (it
   !> may have been changed since the last call) and the state at t_target on exit;
   !> on failure the last accepted state, at stats%t_reached, with stat saying why. A
   !> terminal event or an observer's stop ends the call early with status ok.
   !> options%max_steps bounds the attempts of each call.
   subroutine advance_to(self, problem, scheme, t_target, u, stat, stats, history, t_out, u_out, observer, events)
      !> The integrator, initialized
      class(integrator_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> The scheme init prepared
      class(scheme_type), intent(inout) :: scheme
      !> Where to stop
      real(dp), intent(in) :: t_target
      !> State at the current time on entry, at t_target (or where it stopped) on exit
      real(dp), intent(inout) :: u(:)
      !> Outcome
      type(status_type), intent(out) :: stat
      !> Steps, rejections by cause, evaluations, step sizes and times of this call
      type(integration_stats_type), intent(out), optional :: stats
      !> Every attempted step, when present
      type(step_history_type), intent(inout), optional :: history
      !> Output times (ascending, inside [current time, t_target])
      real(dp), intent(in), optional :: t_out(:)
      !> Dense output, size(u) x size(t_out)
      real(dp), intent(out), optional :: u_out(:, :)
      !> Called after every accepted step
      class(step_observer_type), intent(inout), optional :: observer
      !> Event functions whose crossings are located
      class(event_functions_type), intent(inout), optional :: events

      type(integration_stats_type) :: call_stats
      type(counters_type) :: work_before
      type(status_type) :: step_stat
      real(dp) :: t, h, h_next, h_natural, err, nan, trouble_end, t_stop, h_retry
      ! what t lacks of the state's time before and after the attempted step (self%t_low)
      real(dp) :: t_low, t_low_end
      ! the longest step the scheme's solves can resolve (scheme%largest_step, which
      ! changes only after an attempt with a singular matrix)
      real(dp) :: step_limit
      ! the roundoff of t_target: a step that ends within it of t_target ends there
      real(dp) :: target_roundoff
      integer(i8) :: attempts, newton_before, clock_start, clock_rate, clock_end
      real(dp) :: cpu_start, cpu_end
      integer :: failures, troubles, singular, outcome, next_output, last_failure
      logical :: last, need_step, stop_here, rhs_pending, prebuilt
      ! the end of the attempted step: t + h, or the target or an output time it lands on
      real(dp) :: t_step_end
      character(len=400) :: text

      if (self%options%measure_time) then
         call system_clock(clock_start, clock_rate)
         call cpu_time(cpu_start)
      end if
      work_before = scheme%counters
      t = self%t
      t_low = self%t_low
      call_stats%t_reached = t
      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      need_step = present(t_out) .or. present(observer) .or. present(events)

      call check_call()
      if (stat%code == status_ok .and. present(history)) &
         call history%start(merge(self%n, 0, self%options%history_states), stat)
      ! F at the start, for the cubic Hermite interpolant of the first step (a scheme
      ! with its own dense output, or an implicit one, needs it only when a step has
      ! no dense output of its own and no step before it)
      rhs_pending = scheme%dense_degree > 0 .or. scheme%implicit
      if (stat%code == status_ok .and. need_step) then
         call self%step%reserve(self%n, scheme%dense_degree, stat)
         if (stat%code == status_ok .and. .not. rhs_pending) &
            call evaluate_start(self, problem, scheme, t, u, self%step%rhs_end, stat)
         if (stat%code == status_ok) call start_ring()
      end if
      if (stat%code == status_ok .and. present(events)) call events%start(t, u, stat)
      if (stat%code /= status_ok) then
         call finish()
         return
      end if
      next_output = 1
      prebuilt = .false.
      if (present(t_out)) call emit_outputs_up_to(t)
      call self%stepper%continue_from(u)

      h = self%h
      h_natural = h
      attempts = 0
      failures = 0
      troubles = 0
      singular = 0
      last_failure = status_ok
      trouble_end = t
      step_limit = scheme%largest_step()
      target_roundoff = roundoff_steps*epsilon(1.0_dp)*abs(t_target)
      do while (t < t_target)
         if (attempts >= self%options%max_steps) then
            write (text, '("integrate: maximum number of steps (", i0, ") reached at t = ", a)') &
               self%options%max_steps, trim(fixed_length_real(t, 7))
            call set_status(stat, status_max_steps, trim(text))
            exit
         end if
         h_natural = h
         last = t + h >= t_target - target_roundoff
         if (last) h = (t_target - t) - t_low
         if (last .and. t_target - t <= target_roundoff) then
            ! a target within roundoff of t is where the state is, as a step that ends
            ! within roundoff of an output time ends there (no step resolves the rest; the
            ! call failed with a step-size underflow, and every later one with it)
            t = t_target
            t_low = 0.0_dp
            call_stats%t_reached = t
            if (present(t_out)) then
               do while (next_output <= size(t_out))
                  if (t_out(next_output) > t) exit
                  u_out(:, next_output) = u
                  next_output = next_output + 1
               end do
            end if
            h = h_natural
            exit
         end if
         if (h < self%options%h_min .or. h <= max(roundoff_steps*epsilon(1.0_dp), self%options%h_min_relative)*abs(t) &
            .or. .not. (h > 0.0_dp)) then
            write (text, '("integrate: step size ", a, " below the minimum step or the roundoff of t = ", a)') &
               trim(fixed_length_real(h, 7)), trim(fixed_length_real(t, 7))
            if (failures > 0) write (text, '(a, " after ", i0, " consecutive failed attempts, last: ", a)') &
               trim(text), failures, trim(status_description(last_failure))
            call set_status(stat, status_step_underflow, trim(text))
            ! the next call starts with the step before the cut to the target
            if (last) h = h_natural
            exit
         end if
         attempts = attempts + 1
         newton_before = scheme%counters%newton_iterations
         if (last) then
            t_step_end = t_target
            t_low_end = 0.0_dp
         else
            call add_to_time(t, t_low, h, t_step_end, t_low_end)
         end if
         ! a step that lands within roundoff of an output time ends there, as one that
         ! lands on the target does: t + h could end one rounding short of it, and the
         ! next attempt, with the output time inside, was retried to end there with h =
         ! t_out - t, one rounding of t (a step-size underflow)
         if (present(t_out) .and. .not. last) call land_on_output(t_step_end, t_low_end)
         err = nan
         call self%stepper%attempt(problem, scheme, self%options, t, h, u, outcome, err, h_next, step_stat)
         ! below the steps the scheme's solves cannot resolve (none but after such a solve)
         if (step_stat%code == status_singular_matrix) step_limit = scheme%largest_step()
         h_next = min(h_next, step_limit)

         ! the dense output at an output time inside the step, and with events in the
         ! middle of the step, must pass its error test too: else the step is taken back
         ! and retried shorter (to end at that output time)
         if (outcome == attempt_accepted .and. (present(t_out) .or. present(events))) then
            if (dense_output_rejected(t_step_end, h_retry)) then
               call self%stepper%undo_acceptance()
               outcome = attempt_rejected_output
               h_next = h_retry
            end if
         end if
         if (step_stat%code == status_out_of_memory) then
            ! a work array made during the step (a second factorization, a problem's work
            ! array): retrying cannot help
            write (text, '("integrate: at t = ", a, ":")') trim(fixed_length_real(t, 7))
            if (allocated(step_stat%message)) then
               call set_status(stat, status_out_of_memory, trim(text)//" "//step_stat%message)
            else
               call set_status(stat, status_out_of_memory, trim(text)//" "// &
                  trim(status_description(status_out_of_memory)))
            end if
            exit
         end if
         select case (outcome)
         case (attempt_accepted)
            ! the first step after a failed attempt does not grow h again at once
            if (failures > 0) h_next = min(h_next, h)
            failures = 0
            if (t + h > trouble_end) troubles = 0
            call record_attempt(err, outcome, newton_before, self%stepper%u_new)
            call_stats%accepted_steps = call_stats%accepted_steps + 1
            call_stats%h_min_accepted = min(call_stats%h_min_accepted, h)
            call_stats%h_max_accepted = max(call_stats%h_max_accepted, h)
            stop_here = .false.
            if (need_step) then
               call accept_into_step(t_step_end)
               if (stat%code /= status_ok) exit
            end if
            if (stop_here) then
               t = self%step%t_end
               t_low = 0.0_dp
               u = self%step%u_end
            else
               call copy_state(self%n, self%stepper%u_new, u)
               t = t_step_end
               t_low = t_low_end
            end if
            call_stats%t_reached = t
            if (need_step) call push_ring(t, u)
            h = h_next
            ! a step cut to land on the target does not shrink the next call's first step
            if (last) h = min(max(h_next, h_natural), self%options%h_max)
            if (stop_here) exit
         case (attempt_rejected_error, attempt_rejected_constraint, attempt_rejected_output)
            failures = 0
            call record_attempt(err, outcome, newton_before, u)
            select case (outcome)
            case (attempt_rejected_error)
               call_stats%rejected_error = call_stats%rejected_error + 1
               if (self%total%accepted_steps + call_stats%accepted_steps == 0) &
                  call_stats%rejected_error_start = call_stats%rejected_error_start + 1
            case (attempt_rejected_constraint)
               call_stats%rejected_constraint = call_stats%rejected_constraint + 1
            case default
               call_stats%rejected_output = call_stats%rejected_output + 1
            end select
            h = h_next
         case default
            ! failed attempt: retry from the same state with a smaller step
            failures = failures + 1
            last_failure = step_stat%code
            if (step_stat%code == status_singular_matrix) singular = singular + 1
            select case (outcome)
            case (attempt_failed_nonfinite, attempt_failed_evaluation)
               if (outcome == attempt_failed_nonfinite) then
                  call_stats%rejected_nonfinite = call_stats%rejected_nonfinite + 1
               else
                  call_stats%rejected_evaluation = call_stats%rejected_evaluation + 1
               end if
               if (troubles == 0) trouble_end = t + h
               troubles = troubles + 1
            case default
               call_stats%rejected_newton = call_stats%rejected_newton + 1
               if (step_stat%code == status_singular_matrix) &
                  call_stats%rejected_singular = call_stats%rejected_singular + 1
            end select
            call record_attempt(nan, outcome, newton_before, u)
            if (problem%evaluation_fatal()) then
               write (text, '("integrate: the problem stopped the integration at t = ", a)') &
                  trim(fixed_length_real(t, 7))
               call set_status(stat, status_evaluation_failed, trim(text))
               exit
            end if
            if (self%options%max_failures > 0 .and. failures >= self%options%max_failures) then
               write (text, '("integrate: gave up after ", i0, " consecutive failed attempts at t = ", a, &
                  &", last: ", a)') failures, trim(fixed_length_real(t, 7)), trim(status_description(step_stat%code))
               call set_status(stat, step_stat%code, trim(text))
               exit
            end if
            if (singular >= singular_limit) then
               write (text, '("integrate: the Newton matrix was singular in ", i0, " attempts (the last at t = ", &
                  &a, ", h = ", a, ")")') singular, trim(fixed_length_real(t, 7)), trim(fixed_length_real(h, 7))
               call set_status(stat, status_singular_matrix, trim(text))
               exit
            end if
            if (troubles >= merge(self%options%max_failures, trouble_limit, self%options%max_failures > 0)) then
               write (text, '("integrate: ", a, " in ", i0, " attempts that could not get past t = ", a, &
                  &" (stopped at t = ", a, ")")') trim(status_description(step_stat%code)), troubles, &
                  trim(fixed_length_real(trouble_end, 7)), trim(fixed_length_real(t, 7))
               call set_status(stat, step_stat%code, trim(text))
               exit
            end if
            h = h_next
         end select
         if (present(history)) then
            if (history%failed()) then
               call set_status(stat, status_output_error, "integrate: the step history could not be written")
               exit
            end if
            call history%check_memory(stat)
            if (stat%code /= status_ok) exit
         end if
      end do
      self%t = t
      self%t_low = t_low
      self%h = h
      call finish()

   contains

      !> The call's own checks: init done, the same scheme and size, a target ahead,
      !> a finite state, output times inside the interval.
      subroutine check_call()
         if (.not. self%ready) then
            call set_status(stat, status_invalid_argument, "integrate: the integrator is not initialized")
            return
         end if
         if (size(u) /= self%n) then
            call set_status(stat, status_size_mismatch, "integrate: the state has a different size than at init")
            return
         end if
         ! another object of the same scheme, or the same one prepared since for another size
         if (scheme%name /= self%scheme_name .or. scheme%n /= self%n) then
            call set_status(stat, status_invalid_argument, "integrate: pass the scheme init prepared")
            return
         end if
         ! the schemes keep dF/dt's work arrays only for a problem that depends on t
         if (scheme%autonomous .neqv. problem%autonomous) then
            call set_status(stat, status_invalid_argument, "integrate: problem%autonomous changed since init "// &
               "(the scheme prepared its work arrays for it): call init again")
            return
         end if
         if (.not. (ieee_is_finite(t_target) .and. t_target >= t)) then
            call set_status(stat, status_invalid_argument, "integrate: the target time must be finite and not "// &
               "before the current time (backward integration is not supported: substitute s = -t)")
            return
         end if
         if (.not. finite_everywhere(problem, u)) then
            call set_status(stat, status_nonfinite, "integrate: the state contains NaN or Inf")
            return
         end if
         if (present(t_out) .neqv. present(u_out)) then
            call set_status(stat, status_invalid_argument, outputs_together)
            return
         end if
         if (present(t_out)) then
            if (size(u_out, 1) /= self%n .or. size(u_out, 2) /= size(t_out)) then
               call set_status(stat, status_size_mismatch, "integrate: u_out must be size(u) x size(t_out)")
               return
            end if
            if (size(t_out) > 0) then
               if (.not. all(ieee_is_finite(t_out))) then
                  call set_status(stat, status_invalid_argument, "integrate: t_out must be finite")
                  return
               end if
               if (t_out(1) < t .or. t_out(size(t_out)) > t_target .or. any(t_out(2:) < t_out(:size(t_out) - 1))) then
                  call set_status(stat, status_invalid_argument, &
                     "integrate: t_out must be ascending and inside [t0, t_end]")
                  return
               end if
            end if
            u_out = nan
         end if
      end subroutine check_call

      !> The accepted step [t, t_end_of_step] into self%step with its dense output (unless
      !> the dense output's error test built it already), then events (a terminal
      !> crossing shortens it), dense output and the observer.
      subroutine accept_into_step(t_end_of_step)
         real(dp), intent(in) :: t_end_of_step
         logical :: stop_requested, output_due
         if (scheme%dense_degree > 0 .and. .not. (present(events) .or. present(observer))) then
            ! only output times look at the step: without one inside it, nothing is needed
            output_due = next_output <= size(t_out)
            if (output_due) output_due = t_out(next_output) <= t_end_of_step
            if (.not. output_due) then
               rhs_pending = .true.
               return
            end if
         end if
         associate (step => self%step)
            if (.not. prebuilt) call build_step(t_end_of_step)
            prebuilt = .false.
            if (present(events)) then
               call events%check_step(step, stop_here, t_stop, self%stepper%delta, stat)
               if (stat%code /= status_ok) return
               if (stop_here) then
                  step%t_end = t_stop
                  step%u_end = self%stepper%delta
               end if
            end if
            if (present(t_out)) call emit_outputs_up_to(step%t_end)
            if (present(observer)) then
               stop_requested = .false.
               call observer%observe(step, stop_requested)
               stop_here = stop_here .or. stop_requested
            end if
         end associate
      end subroutine accept_into_step

      !> The step [t, t_end_of_step] to u_new into self%step with its dense output: the
      !> scheme's own; else for an implicit scheme the polynomial through its two ends
      !> and the starts of up to two steps before (with none, F at its start), for an
      !> explicit one the cubic Hermite interpolant from F at both ends.
      subroutine build_step(t_end_of_step)
         real(dp), intent(in) :: t_end_of_step
         integer :: before
         associate (step => self%step)
            step%t_start = t
            step%h = h
            step%t_end = t_end_of_step
            step%u_start = u
            step%u_end = self%stepper%u_new
            call scheme%dense_output(t, h, step%u_end, step%nodes, step%coefficients, step%points, step%degree)
            if (step%degree == 0 .and. scheme%implicit) then
               before = min(self%ring_count - 1, 2)
               if (before == 0) then
                  call evaluate_rhs(problem, t, step%u_start, step%rhs_start, scheme%counters)
                  call step%set_through_states()
               else if (before == 1) then
                  call step%set_through_states(self%ring_t(ring_slot(1)), self%ring_u(:, ring_slot(1)))
               else
                  call step%set_through_states(self%ring_t(ring_slot(1)), self%ring_u(:, ring_slot(1)), &
                     self%ring_t(ring_slot(2)), self%ring_u(:, ring_slot(2)))
               end if
               rhs_pending = .true.
            else if (step%degree == 0) then
               if (rhs_pending) call evaluate_rhs(problem, t, step%u_start, step%rhs_end, scheme%counters)
               step%rhs_start = step%rhs_end
               call evaluate_rhs(problem, t_end_of_step, step%u_end, step%rhs_end, scheme%counters)
               call step%set_hermite()
               rhs_pending = .false.
            else
               rhs_pending = .true.
            end if
         end associate
      end subroutine build_step

      !> The output time within roundoff of a step's end (from next_output on), which the
      !> step then ends at: t_end_of_step becomes it, else stays.
      subroutine land_on_output(t_end_of_step, low_end_of_step)
         !> t + h on entry; the output time within roundoff of it, if there is one
         real(dp), intent(inout) :: t_end_of_step
         !> What t_end_of_step lacks of the state's time (it takes the difference)
         real(dp), intent(inout) :: low_end_of_step
         real(dp) :: roundoff
         integer :: k
         roundoff = roundoff_steps*epsilon(1.0_dp)*abs(t_end_of_step)
         do k = next_output, size(t_out)
            if (t_out(k) >= t_end_of_step - roundoff) then
               if (t_out(k) <= t_end_of_step + roundoff) then
                  ! (exact: the two are within a few roundings of each other)
                  low_end_of_step = low_end_of_step + (t_end_of_step - t_out(k))
                  t_end_of_step = t_out(k)
               end if
               return
            end if
         end do
      end subroutine land_on_output

      !> Whether the dense output of the step just accepted, [t, t_end_of_step], fails its
      !> error test, and the step size to retry with: the error estimated from the newest
      !> state the interpolant does not pass through (interpolation_error), in the
      !> weighted norm, above 1 at an output time inside the step (the retry ends there)
      !> or, with events, which are located on the dense output between output times
      !> too, in the middle of the step, where an interpolant's error is largest (the
      !> retry is shorter by the estimate's order, degree + 1). Without such a state (the
      !> first steps of a call that starts anew) there is no estimate: a step with an
      !> output time inside is retried to end there (an untested interpolant across a long
      !> first step, a large h0 or steps grown fivefold on a problem whose step ends are
      !> exact at any h, was 1e3 tolerances off with status ok); events are located on
      !> it untested.
      logical function dense_output_rejected(t_end_of_step, h_retry)
         real(dp), intent(in) :: t_end_of_step
         real(dp), intent(out) :: h_retry
         real(dp) :: worst
         integer :: k, extra
         logical :: output_inside, testable
         dense_output_rejected = .false.
         h_retry = h
         output_inside = .false.
         if (present(t_out)) then
            if (next_output <= size(t_out)) output_inside = t_out(next_output) > t .and. &
               t_out(next_output) < t_end_of_step
         end if
         if (.not. (output_inside .or. present(events))) return
         call build_step(t_end_of_step)
         prebuilt = .true.
         ! the newest state before the step that the interpolant does not pass through
         extra = 1 + count(self%step%points(:self%step%degree) < 0.0_dp)
         testable = self%ring_count > extra
         if (output_inside) then
            worst = huge(1.0_dp)
            if (testable) then
               worst = 0.0_dp
               do k = next_output, size(t_out)
                  if (t_out(k) >= t_end_of_step) exit
                  worst = max(worst, estimate_at(t_out(k), extra))
               end do
            end if
            if (worst > 1.0_dp) then
               dense_output_rejected = .true.
               h_retry = t_out(next_output) - t
            end if
         end if
         if (present(events) .and. testable) then
            worst = estimate_at(0.5_dp*(t + t_end_of_step), extra)
            if (worst > 1.0_dp) then
               dense_output_rejected = .true.
               h_retry = min(h_retry, h*max(min_event_shrink, &
                  event_safety*(1.0_dp/worst)**(1.0_dp/real(self%step%degree + 1, dp))))
            end if
         end if
         prebuilt = .not. dense_output_rejected
         ! F at the start, which the Hermite interpolant of the retry needs, is in rhs_start
         if (dense_output_rejected .and. .not. rhs_pending) self%step%rhs_end = self%step%rhs_start
      end function dense_output_rejected

      !> The weighted norm of the dense output's estimated error at time t_inside, from the
      !> state `extra` places before the newest.
      real(dp) function estimate_at(t_inside, extra)
         real(dp), intent(in) :: t_inside
         integer, intent(in) :: extra
         call self%step%interpolation_error(t_inside, self%ring_t(ring_slot(extra)), &
            self%ring_u(:, ring_slot(extra)), self%stepper%delta)
         estimate_at = self%stepper%weighted_norm(problem, self%options, self%stepper%delta)
      end function estimate_at

      !> Start the ring of states at the current one, unless it continues the ring
      !> (the state the last call ended in, unchanged by the caller).
      subroutine start_ring()
         integer :: memory
         if (allocated(self%ring_u)) then
            if (size(self%ring_u, 1) /= self%n) deallocate (self%ring_u)
         end if
         if (.not. allocated(self%ring_u)) then
            allocate (self%ring_u(self%n, ring_size), stat=memory)
            if (memory /= 0) then
               call out_of_memory(stat, "the last states of the solution (dense output)", [self%n, ring_size], &
                  real_bytes)
               return
            end if
            self%ring_count = 0
         end if
         if (self%ring_count > 0) then
            if (self%ring_t(self%ring_newest) /= t .or. any(self%ring_u(:, self%ring_newest) /= u)) &
               self%ring_count = 0
         end if
         if (self%ring_count == 0) call push_ring(t, u)
      end subroutine start_ring

      !> The state at time t_new as the newest of the ring.
      subroutine push_ring(t_new, u_new)
         real(dp), intent(in) :: t_new, u_new(:)
         self%ring_newest = modulo(self%ring_newest, ring_size) + 1
         self%ring_t(self%ring_newest) = t_new
         self%ring_u(:, self%ring_newest) = u_new
         self%ring_count = min(self%ring_count + 1, ring_size)
      end subroutine push_ring

      !> Slot of the state `back` places before the newest.
      integer function ring_slot(back)
         integer, intent(in) :: back
         ring_slot = modulo(self%ring_newest - 1 - back, ring_size) + 1
      end function ring_slot

      !> Fill the output times up to t_upto: at the start of the call the current state,
      !> afterwards from the interpolant of the step just accepted.
      subroutine emit_outputs_up_to(t_upto)
         real(dp), intent(in) :: t_upto
         do while (next_output <= size(t_out))
            if (t_out(next_output) > t_upto) exit
            if (t_out(next_output) <= self%t .and. call_stats%accepted_steps == 0) then
               u_out(:, next_output) = u
            else
               call self%step%interpolate(t_out(next_output), u_out(:, next_output))
            end if
            next_output = next_output + 1
         end do
      end subroutine emit_outputs_up_to

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

      !> Work counters and times of this call; the running totals.
      subroutine finish()
         call add_work(call_stats, scheme%counters, work_before)
         if (call_stats%accepted_steps == 0) call_stats%h_min_accepted = 0.0_dp
         call_stats%weights_raised = self%stepper%weights_raised
         if (self%options%measure_time) then
            call cpu_time(cpu_end)
            call system_clock(clock_end)
            call_stats%cpu_seconds = cpu_end - cpu_start
            call_stats%wall_seconds = real(clock_end - clock_start, dp)/real(max(clock_rate, 1_i8), dp)
         end if
         call accumulate(self%total, call_stats)
         if (present(stats)) stats = call_stats
      end subroutine finish

   end subroutine advance_to

   !> to = from, n entries (from contiguous, to perhaps strided: the caller's state),
   !> copied by a loop not unrolled (on a few unknowns the unrolled copy's entry costs
   !> more than the copy)
   pure subroutine copy_state(n, from, to)
      integer, intent(in) :: n
      real(dp), intent(in) :: from(n)
      real(dp), intent(inout) :: to(:)
      integer :: i
      !GCC$ unroll 1
      do i = 1, n
         to(i) = from(i)
      end do
   end subroutine copy_state

   !> stats%work += counters - before.
   pure subroutine add_work(stats, counters, before)
      type(integration_stats_type), intent(inout) :: stats
      type(counters_type), intent(in) :: counters, before
      stats%work = stats%work + (counters - before)
   end subroutine add_work

   !> Running totals: total += one call.
   pure subroutine accumulate(total, call_stats)
      type(integration_stats_type), intent(inout) :: total
      type(integration_stats_type), intent(in) :: call_stats
      total%t_reached = call_stats%t_reached
      total%accepted_steps = total%accepted_steps + call_stats%accepted_steps
      total%rejected_error = total%rejected_error + call_stats%rejected_error
      total%rejected_error_start = total%rejected_error_start + call_stats%rejected_error_start
      total%rejected_newton = total%rejected_newton + call_stats%rejected_newton
      total%rejected_singular = total%rejected_singular + call_stats%rejected_singular
      total%rejected_nonfinite = total%rejected_nonfinite + call_stats%rejected_nonfinite
      total%rejected_evaluation = total%rejected_evaluation + call_stats%rejected_evaluation
      total%rejected_constraint = total%rejected_constraint + call_stats%rejected_constraint
      total%rejected_output = total%rejected_output + call_stats%rejected_output
      total%work = total%work + call_stats%work
      if (call_stats%accepted_steps > 0) then
         total%h_min_accepted = min(total%h_min_accepted, call_stats%h_min_accepted)
         total%h_max_accepted = max(total%h_max_accepted, call_stats%h_max_accepted)
      end if
      total%weights_raised = total%weights_raised .or. call_stats%weights_raised
      total%cpu_seconds = total%cpu_seconds + call_stats%cpu_seconds
      total%wall_seconds = total%wall_seconds + call_stats%wall_seconds
   end subroutine accumulate

   !> The time a step of size h from t (which lacks t_low of the state's time) ends at,
   !> rounded, and what that lacks: t + t_low + h = t_end + t_low_end to a rounding of
   !> t_low's size (Knuth's two-sum gives t + h exactly as a sum of two numbers).
   pure subroutine add_to_time(t, t_low, h, t_end, t_low_end)
      !> Start of the step, and what it lacks of the state's time
      real(dp), intent(in) :: t, t_low
      !> Step size
      real(dp), intent(in) :: h
      !> End of the step, rounded, and what it lacks
      real(dp), intent(out) :: t_end, t_low_end
      real(dp) :: rounded, error, h_part, low
      rounded = t + h
      h_part = rounded - t
      error = (t - (rounded - h_part)) + (h - h_part)
      low = error + t_low
      t_end = rounded + low
      t_low_end = (rounded - t_end) + low
   end subroutine add_to_time

end module taylorode_integrate_integrator
