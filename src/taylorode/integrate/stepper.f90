!> One attempted step of the adaptive integrator: the scheme's step from U^n, its
!> error estimate in the weighted norm, the decision (accept, reject, failed) and
!> the controller's next step size.
!>
!> Error estimates: the embedded pair's difference, or step doubling (two steps of
!> h/2 advance the solution, one step of h beside them gives the Richardson
!> estimate, and with local extrapolation the Richardson-extrapolated value
!> advances; the scheme's Newton solvers keep a factorization for each of h/2 and h),
!> or the scheme's own estimate of its step's error (`step_error`, si-t-2), with which
!> U1 minus the estimate advances when locally extrapolating.
!> Newton's method starts from the line through the last accepted step's two
!> states, extended to the end of the new step (or of each half step).
!>
!> Error weights: w_i = atol_i + rtol max(|U_i^n|, |U_i^{n+1}|) (|U_i^n| alone for a
!> scheme that declares `weights_at_start`, radau5), never below
!> `roundoff_weight` times |U_i| (what double precision can resolve); a component
!> with atol_i = 0 that is zero is weighed against the size of the whole state (at
!> least 1), so that pure relative control (atol = 0) works.
module taylorode_integrate_stepper
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_ok, status_nonfinite, &
      status_evaluation_failed
   use taylorode_base_memory, only: sized
   use taylorode_problem_ode, only: ode_problem, difference_f
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_schemes_scheme, only: scheme_type, evaluate_f, evaluate_rhs
   use taylorode_integrate_options, only: integrator_options_type, norm_max, advance_scheme, advance_high, &
      advance_low, estimate_auto, estimate_embedded, estimate_doubling, estimate_defect
   use taylorode_integrate_controller, only: controller_factor, controller_auto, controller_i, &
      controller_predictive, predictive_factor
   use taylorode_integrate_history, only: attempt_accepted, attempt_rejected_error, &
      attempt_failed_newton, attempt_failed_nonfinite, attempt_failed_evaluation, attempt_rejected_constraint
   use taylorode_integrate_reduction, only: reduced_max, reduced_root_mean_square, agree_on_outcome
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: stepper_type, roundoff_weight, failure_shrink

   !> Up to this many components, the weighted norm's loop is kept scalar (on 4 and 8
   !> the vector loop measured faster)
   integer, parameter :: scalar_norm_max_length = 2

   !> With g linear, an accepted step keeps h unless the controller lets it grow by more
   !> than this factor (RADAU5's QUOT2 = 1.2)
   real(dp), parameter :: linear_hold = 1.2_dp
   !> Newton increments are never asked to be smaller than this many roundoffs of |U|
   real(dp), parameter :: newton_roundoff_floor = 10.0_dp
   !> Error weights are never below this fraction of |U_i| (50 roundoffs): a tighter
   !> tolerance asks for more than double precision resolves
   real(dp), parameter :: roundoff_weight = 50.0_dp*epsilon(1.0_dp)
   !> Step-size factor after a failed attempt (NaN/Inf values, a rejected evaluation,
   !> and a Newton failure unless the scheme proposes its own factor)
   real(dp), parameter :: failure_shrink = 0.25_dp
   !> Components declared nonnegative that went below 0 are set to 0 while their
   !> negative parts are at most this fraction of the tolerance in the error norm
   real(dp), parameter :: projection_limit = 0.1_dp
   !> After a step rejected for a negative component: the retry is this fraction of
   !> the part of the step before the first such component reached 0 along the line
   !> from its start value, and at least constraint_shrink_low of the step
   real(dp), parameter :: constraint_safety = 0.9_dp, constraint_shrink_low = 0.1_dp
   !> For a scheme that amplifies errors (si-t-2): what the step's error becomes in the
   !> next step, which no estimate or local extrapolation removes, must stay within
   !> this fraction of the tolerance
   real(dp), parameter :: propagation_fraction = 0.1_dp
   !> For a scheme that amplifies errors: what the next steps make of the corrections
   !> of locally extrapolated states left out (they can have one sign step after step
   !> along a slow manifold) adds up over the integration to at most this fraction of
   !> the tolerance; beyond it each is applied (see extrapolate_step)
   real(dp), parameter :: correction_budget = 0.1_dp
   !> Step doubling with local extrapolation: the single step's Newton error, which
   !> enters the state divided by 2^p - 1, may be this many times the halves' fraction
   !> of the weights (the two halves' errors enter about twice)
   real(dp), parameter :: whole_to_halves = 3.0_dp
   !> With step doubling, a scheme's filtered trapezoidal defect (2/3 D ~ 2 times the
   !> doubling estimate on a step that follows the solution) must stay within this many
   !> tolerances: on a spurious root of the step's equation it is of the size of the
   !> step's change, where the half steps may agree on it
   real(dp), parameter :: defect_limit = 4.0_dp
   !> For a scheme that evaluates a part P of F at a step's start only, in a problem that
   !> depends on t: h |P(t + h) - 2 P(t + h/2) + P(t)| must stay within this many
   !> tolerances (h^3/4 |U'''| along the step of ex-t-2, where step doubling's estimate is
   !> h^3/24 |U'''|: with 4 it held ex-t-2's steps to 0.88 of their length on a forced
   !> oscillator; h times the jump where P switches inside the step)
   real(dp), parameter :: time_check_limit = 8.0_dp

   !> Work arrays and controller memory of the step attempts of one integration (the
   !> work arrays a run does not use, by its scheme, estimate and options, stay
   !> unallocated)
   type :: stepper_type
      !> Candidate new state
      real(dp), allocatable :: u_new(:)
      !> Embedded difference U_high - U_low
      real(dp), allocatable :: delta(:)
      !> Error weights
      real(dp), allocatable :: weights(:)
      !> Newton settings passed to the scheme (tolerance updated every attempt)
      type(newton_settings_type) :: newton
      !> Step doubling: the settings of the single step of size h, whose Newton error
      !> enters err and the extrapolated state only divided by 2^p - 1 and may be larger
      !> (whole_newton_fraction)
      type(newton_settings_type) :: newton_whole
      !> Step doubling: fraction of the weights left to Newton in the single step,
      !> 0.1 (2^p - 1), so that its Newton error moves err by at most 0.1; with local
      !> extrapolation at most whole_to_halves times the halves' fraction times 2^p - 1,
      !> so that it moves the state about as much as theirs do (from step to step it
      !> can have one sign)
      real(dp) :: whole_newton_fraction = 0.1_dp
      !> Order exponent of the controller
      real(dp) :: q = 2.0_dp
      !> Weighted errors of the two previous accepted steps (1 when there are none)
      real(dp) :: err_previous = 1.0_dp, err_before = 1.0_dp
      !> Whether some absolute tolerance is zero (weights may then need the state's size)
      logical :: zero_atol = .false.
      !> Whether the weights come from the scalar atol and rtol alone (no vectors, no
      !> weights of your own, atol > 0): attempts then weigh in one pass
      !> (scalar_tolerance_weights) instead of through set_weights
      logical :: scalar_tolerances = .false.
      !> Whether a weight was raised to the roundoff floor
      logical :: weights_raised = .false.
      !> The controller in use (options%controller, controller_auto resolved)
      integer :: controller = controller_i
      !> Fraction of the weights given to Newton (options%newton_fraction, 0 resolved)
      real(dp) :: newton_fraction = 0.0_dp
      !> Size of the previous accepted step (0 when there is none)
      real(dp) :: h_previous = 0.0_dp
      !> What the next steps made of the corrections left out so far, in the weighted
      !> norm (schemes that amplify errors; see correction_budget)
      real(dp) :: uncorrected = 0.0_dp
      !> The error estimate in use (estimate_embedded, estimate_doubling or estimate_defect)
      integer :: estimate = estimate_embedded
      !> Step doubling: 1 / (2^p - 1), the Richardson factor of the difference
      real(dp) :: richardson = 1.0_dp
      !> Step doubling: the state after the first half step, and after the whole step
      real(dp), allocatable :: u_half(:), u_whole(:)
      !> Start of the last accepted step and its end (the state the next step starts
      !> from, unless the caller changed it), for the Newton starting guess (when
      !> extrapolating)
      real(dp), allocatable :: u_step_start(:), u_step_end(:)
      !> Newton starting guess (when extrapolating), or the first step size's work space
      real(dp), allocatable :: guess(:)
      !> Whether Newton starts from an extrapolation, and whether one is possible now
      logical :: extrapolate = .false., extrapolation_ready = .false.
      !> The negative parts of the components declared nonnegative (with options%nonnegative)
      real(dp), allocatable :: violation(:)
      !> What the error of the step becomes in the next one (schemes that amplify errors)
      real(dp), allocatable :: propagated(:)
      !> The scheme's correction of its locally extrapolated state (schemes that amplify
      !> errors)
      real(dp), allocatable :: correction(:)
      !> The scheme's filtered trapezoidal defect of the step (schemes that check it)
      real(dp), allocatable :: defect(:)
      !> The second difference in t of the part of F the scheme evaluates at a step's
      !> start only, and one of its values (schemes with such a part)
      real(dp), allocatable :: time_difference(:), time_value(:)
      !> The controller's memory before the last accepted attempt (for undo_acceptance)
      real(dp) :: undo_err_previous = 1.0_dp, undo_err_before = 1.0_dp, undo_h_previous = 0.0_dp
   contains
      !> Prepare for an integration of n unknowns with a scheme and options
      procedure :: start
      !> Weights from two states
      procedure :: set_weights
      !> Max or RMS norm of a vector in the current weights
      procedure :: weighted_norm
      !> One attempt from (t, u) with step h
      procedure :: attempt
      !> Forget the last accepted step when the state no longer continues it
      procedure :: continue_from
      !> Newton starting guess extrapolated from the last accepted step
      procedure :: extrapolate_to
      !> Take back the last accepted attempt (the caller rejects it after all)
      procedure :: undo_acceptance
   end type stepper_type

contains

   !> Prepare for an integration of n unknowns: work arrays (allocated only when n
   !> changes), the Newton policy of the options and the controller exponent q
   !> (options%q, or the lower order of the scheme's pair plus one). The controller
   !> and the Newton fraction the options leave to the scheme are settled here.
   subroutine start(self, n, scheme, options, stat)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      !> The scheme
      class(scheme_type), intent(in) :: scheme
      !> The options (validated)
      type(integrator_options_type), intent(in) :: options
      !> status_out_of_memory when the work arrays cannot be allocated
      type(status_type), intent(inout) :: stat
      character(len=*), parameter :: what = "the stepper's work arrays"
      call sized(self%u_new, n, what, stat)
      call sized(self%delta, n, what, stat)
      call sized(self%weights, n, what, stat)
      call sized(self%newton%tolerance, n, what, stat)
      self%extrapolate = options%extrapolate_newton_start .and. scheme%implicit .and. scheme%takes_newton_guess
      ! (the integrator sizes the guess too when it estimates the first step: its work space)
      call sized(self%guess, merge(n, 0, self%extrapolate), what, stat)
      self%extrapolation_ready = .false.
      call sized(self%u_step_start, merge(n, 0, self%extrapolate), what, stat)
      call sized(self%u_step_end, merge(n, 0, self%extrapolate), what, stat)
      self%newton%max_iterations = options%max_newton_iterations
      if (self%newton%max_iterations == 0) self%newton%max_iterations = scheme%newton_iterations
      self%newton%reuse_matrix = options%reuse_newton_matrix
      self%newton%estimate_error = options%newton_error_estimate
      self%newton%exact_matrix = options%exact_newton_matrix
      self%newton_whole%max_iterations = self%newton%max_iterations
      self%newton_whole%reuse_matrix = self%newton%reuse_matrix
      self%newton_whole%estimate_error = self%newton%estimate_error
      self%newton_whole%exact_matrix = self%newton%exact_matrix
      self%estimate = options%error_estimate
      if (self%estimate == estimate_auto) then
         if (scheme%estimates_own_error .or. options%advance /= advance_scheme) then
            self%estimate = estimate_embedded
         else if (scheme%estimates_step_error) then
            self%estimate = estimate_defect
         else
            self%estimate = estimate_doubling
         end if
      end if
      call sized(self%violation, merge(n, 0, allocated(options%nonnegative)), what, stat)
      call sized(self%propagated, merge(n, 0, scheme%amplifies_errors), what, stat)
      call sized(self%correction, merge(n, 0, scheme%amplifies_errors), what, stat)
      self%uncorrected = 0.0_dp
      call sized(self%defect, merge(n, 0, scheme%checks_defect .and. self%estimate == estimate_doubling), what, stat)
      call sized(self%time_difference, merge(n, 0, scheme%start_only_part /= 0), what, stat)
      call sized(self%time_value, merge(n, 0, scheme%start_only_part /= 0), what, stat)
      ! the states and Newton tolerances of step doubling's half and whole steps
      call sized(self%u_half, merge(n, 0, self%estimate == estimate_doubling), what, stat)
      call sized(self%u_whole, merge(n, 0, self%estimate == estimate_doubling), what, stat)
      call sized(self%newton_whole%tolerance, merge(n, 0, self%estimate == estimate_doubling), what, stat)
      if (stat%code /= status_ok) return
      self%newton%kept_factorizations = merge(2, 1, self%estimate == estimate_doubling)
      self%newton_whole%kept_factorizations = self%newton%kept_factorizations
      if (self%estimate == estimate_doubling) self%richardson = 1.0_dp/(2.0_dp**scheme%nonlinear_order - 1.0_dp)
      self%q = options%q
      if (self%q == 0.0_dp) then
         if (self%estimate == estimate_doubling .or. self%estimate == estimate_defect) then
            self%q = real(scheme%nonlinear_order + 1, dp)
         else
            self%q = real(min(scheme%order, scheme%embedded_order) + 1, dp)
         end if
      end if
      self%err_previous = 1.0_dp
      self%err_before = 1.0_dp
      if (allocated(options%atol_vector)) then
         self%zero_atol = any(options%atol_vector == 0.0_dp)
      else
         self%zero_atol = options%atol == 0.0_dp
      end if
      ! weights of your own may be zero anywhere: the same fallback guards them
      self%zero_atol = self%zero_atol .or. allocated(options%error_weights)
      self%scalar_tolerances = .not. (self%zero_atol .or. allocated(options%atol_vector) .or. &
         allocated(options%rtol_vector))
      self%weights_raised = .false.
      self%h_previous = 0.0_dp
      self%controller = options%controller
      if (self%controller == controller_auto) then
         self%controller = merge(controller_predictive, controller_i, scheme%predictive_control)
      end if
      self%newton_fraction = options%newton_fraction
      if (self%newton_fraction == 0.0_dp) then
         if (options%rtol > 0.0_dp) then
            self%newton_fraction = scheme%newton_fraction(options%rtol, options%newton_error_estimate)
         else if (allocated(options%atol_vector)) then
            self%newton_fraction = scheme%newton_fraction(maxval(options%atol_vector), options%newton_error_estimate)
         else
            self%newton_fraction = scheme%newton_fraction(options%atol, options%newton_error_estimate)
         end if
      end if
      ! the single step's Newton error enters err divided by 2^p - 1, and with local
      ! extrapolation the state too: there kept factorizations left it one sign step after
      ! step, 0.1 of the weights each (i-t-2 on Robertson at 1e-10: 690 tolerances off at
      ! t = 1e6), so it is then held to whole_to_halves times the halves' fraction
      if (self%estimate == estimate_doubling) then
         self%whole_newton_fraction = 0.1_dp/self%richardson
         if (options%local_extrapolation) &
            self%whole_newton_fraction = min(0.1_dp, whole_to_halves*self%newton_fraction)/self%richardson
      end if
   end subroutine start

   !> w_i = atol_i + rtol_i * max(|a_i|, |b_i|) (or the options' own error weights), at
   !> least roundoff_weight * max(|a_i|, |b_i|); a zero weight (atol_i = 0 on a zero
   !> component) becomes rtol_i times the largest |a_j|, |b_j| (at least rtol_i: a state
   !> of zeros is weighed as if of size 1). Weights of your own that are not positive
   !> and finite are raised to that same floor.
   subroutine set_weights(self, problem, options, a, b)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      !> The problem (the largest |a_j|, |b_j| is taken over every process)
      class(ode_problem), intent(inout) :: problem
      !> Tolerances
      type(integrator_options_type), intent(in) :: options
      !> The two states
      real(dp), intent(in) :: a(:), b(:)
      real(dp) :: size_i, atol_i, rtol_i, scale
      integer :: i
      if (allocated(options%error_weights)) then
         call options%error_weights%weights(a, b, self%weights)
         do i = 1, size(a)
            if (.not. ieee_is_finite(self%weights(i))) self%weights(i) = 0.0_dp
         end do
      end if
      atol_i = options%atol
      rtol_i = options%rtol
      do i = 1, size(a)
         size_i = max(abs(a(i)), abs(b(i)))
         if (.not. allocated(options%error_weights)) then
            if (allocated(options%atol_vector)) atol_i = options%atol_vector(i)
            if (allocated(options%rtol_vector)) rtol_i = options%rtol_vector(i)
            self%weights(i) = atol_i + rtol_i*size_i
         end if
         if (self%weights(i) < roundoff_weight*size_i) then
            self%weights(i) = roundoff_weight*size_i
            self%weights_raised = .true.
         end if
      end do
      if (.not. self%zero_atol) return
      scale = 0.0_dp
      do i = 1, size(a)
         scale = max(scale, abs(a(i)), abs(b(i)))
      end do
      scale = reduced_max(problem, scale)
      do i = 1, size(a)
         if (self%weights(i) > 0.0_dp) cycle
         rtol_i = options%rtol
         if (allocated(options%rtol_vector)) rtol_i = options%rtol_vector(i)
         self%weights(i) = max(rtol_i, roundoff_weight)*max(scale, 1.0_dp)
      end do
   end subroutine set_weights

   !> set_weights for scalar tolerances (atol > 0): w_i = atol + rtol max(|a_i|, |b_i|),
   !> at least roundoff_weight max(|a_i|, |b_i|) (raised set when a weight was raised),
   !> in one pass over arrays the compiler can tell apart.
   pure subroutine scalar_tolerance_weights(n, atol, rtol, a, b, weights, raised)
      !> Unknowns (of this process)
      integer, intent(in) :: n
      !> The scalar tolerances
      real(dp), intent(in) :: atol, rtol
      !> The two states
      real(dp), intent(in) :: a(:), b(:)
      !> The weights
      real(dp), intent(out) :: weights(n)
      !> Set when a weight was raised to the roundoff floor (else unchanged)
      logical, intent(inout) :: raised
      integer :: i
      do i = 1, n
         call scalar_weight(atol, rtol, max(abs(a(i)), abs(b(i))), weights(i), raised)
      end do
   end subroutine scalar_tolerance_weights

   !> One weight of scalar tolerances: atol + rtol size_i, at least roundoff_weight
   !> size_i (raised set when it was raised).
   pure subroutine scalar_weight(atol, rtol, size_i, weight, raised)
      !> The scalar tolerances
      real(dp), intent(in) :: atol, rtol
      !> max(|a_i|, |b_i|) of the two states
      real(dp), intent(in) :: size_i
      !> The weight
      real(dp), intent(out) :: weight
      !> Set when the weight was raised to the roundoff floor (else unchanged)
      logical, intent(inout) :: raised
      weight = atol + rtol*size_i
      if (weight < roundoff_weight*size_i) then
         weight = roundoff_weight*size_i
         raised = .true.
      end if
   end subroutine scalar_weight

   !> scalar_tolerance_weights at u alone and Newton's tolerances from them
   !> (newton_tolerances) in one pass (not unrolled: on a few unknowns the unrolled
   !> loop's entry costs more than the pass).
   pure subroutine scalar_weights_and_tolerances(n, atol, rtol, fraction, u, weights, tolerance, raised)
      !> Unknowns (of this process)
      integer, intent(in) :: n
      !> The scalar tolerances
      real(dp), intent(in) :: atol, rtol
      !> Fraction of the weights given to Newton
      real(dp), intent(in) :: fraction
      !> The state at the start of the step (perhaps strided: the caller's)
      real(dp), intent(in) :: u(:)
      !> The weights
      real(dp), intent(out) :: weights(n)
      !> Newton's tolerances
      real(dp), intent(out) :: tolerance(n)
      !> Set when a weight was raised to the roundoff floor (else unchanged)
      logical, intent(inout) :: raised
      integer :: i
      !GCC$ unroll 1
      do i = 1, n
         call scalar_weight(atol, rtol, abs(u(i)), weights(i), raised)
         tolerance(i) = newton_tolerance(fraction, weights(i), u(i))
      end do
   end subroutine scalar_weights_and_tolerances

   !> scalar_tolerance_weights at a and b and this process's part of the weighted norm
   !> of v in them (the largest |v_i| / w_i, or the sum of (v_i / w_i)^2) in one pass,
   !> in the order of weighted_norm's (not unrolled, as there).
   pure subroutine scalar_weights_and_norm(n, atol, rtol, norm, a, b, v, weights, raised, part)
      !> Unknowns (of this process)
      integer, intent(in) :: n
      !> The scalar tolerances
      real(dp), intent(in) :: atol, rtol
      !> norm_max or norm_rms
      integer, intent(in) :: norm
      !> The state at the start of the step (perhaps strided: the caller's)
      real(dp), intent(in) :: a(:)
      !> The new state and the vector whose norm is taken (the stepper's own)
      real(dp), intent(in) :: b(n), v(n)
      !> The weights
      real(dp), intent(out) :: weights(n)
      !> Set when a weight was raised to the roundoff floor (else unchanged)
      logical, intent(inout) :: raised
      !> This process's largest |v_i| / w_i (norm_max) or sum of squares (norm_rms)
      real(dp), intent(out) :: part
      integer :: i
      part = 0.0_dp
      if (norm == norm_max) then
         !GCC$ unroll 1
         do i = 1, n
            call scalar_weight(atol, rtol, max(abs(a(i)), abs(b(i))), weights(i), raised)
            part = max(part, abs(v(i))/weights(i))
         end do
      else
         !GCC$ unroll 1
         do i = 1, n
            call scalar_weight(atol, rtol, max(abs(a(i)), abs(b(i))), weights(i), raised)
            part = part + (v(i)/weights(i))**2
         end do
      end if
   end subroutine scalar_weights_and_norm

   !> Newton's tolerances: the fraction of the weights, but never below what roundoff
   !> allows at u, nor zero.
   pure subroutine newton_tolerances(n, fraction, weights, u, tolerance)
      !> Unknowns (of this process)
      integer, intent(in) :: n
      !> Fraction of the weights given to Newton
      real(dp), intent(in) :: fraction
      !> The error weights
      real(dp), intent(in) :: weights(n)
      !> The state at the start of the step
      real(dp), intent(in) :: u(:)
      !> The tolerances
      real(dp), intent(out) :: tolerance(n)
      integer :: i
      do i = 1, n
         tolerance(i) = newton_tolerance(fraction, weights(i), u(i))
      end do
   end subroutine newton_tolerances

   !> One Newton tolerance: fraction weight, but never below what roundoff allows at
   !> u_i, nor zero.
   pure real(dp) function newton_tolerance(fraction, weight, u_i)
      !> Fraction of the weight given to Newton
      real(dp), intent(in) :: fraction
      !> The error weight
      real(dp), intent(in) :: weight
      !> The component of the state at the start of the step
      real(dp), intent(in) :: u_i
      newton_tolerance = max(fraction*weight, newton_roundoff_floor*epsilon(1.0_dp)*abs(u_i), tiny(1.0_dp))
   end function newton_tolerance

   !> Max or RMS norm of v / w (over every process that holds a part of v).
   real(dp) function weighted_norm(self, problem, options, v)
      !> The stepper (its weights)
      class(stepper_type), intent(in) :: self
      !> The problem (its `reduce`)
      class(ode_problem), intent(inout) :: problem
      !> The norm to use
      type(integrator_options_type), intent(in) :: options
      !> The vector
      real(dp), intent(in) :: v(:)
      integer :: i
      weighted_norm = 0.0_dp
      ! (the loops are chains through weighted_norm: unrolling them gains nothing on many
      ! unknowns and costs the unrolled loop's entry on a few)
      if (options%norm == norm_max) then
         !GCC$ unroll 1
         do i = 1, size(v)
            weighted_norm = max(weighted_norm, abs(v(i))/self%weights(i))
         end do
      else if (size(v) <= scalar_norm_max_length) then
         ! a scalar loop on one or two unknowns: a vector load of v (which the scheme has
         ! just stored one by one) would wait for those stores to be complete, as no
         ! store forwards into a load that spans two
         !GCC$ unroll 1
         !GCC$ novector
         do i = 1, size(v)
            weighted_norm = weighted_norm + (v(i)/self%weights(i))**2
         end do
      else
         !GCC$ unroll 1
         do i = 1, size(v)
            weighted_norm = weighted_norm + (v(i)/self%weights(i))**2
         end do
      end if
      weighted_norm = collective_norm(problem, options%norm, weighted_norm, size(v))
   end function weighted_norm

   !> The weighted norm over every process from this process's part (its largest
   !> |v_i| / w_i, or its sum of squares over n components).
   real(dp) function collective_norm(problem, norm, part, n)
      !> The problem (its `reduce`)
      class(ode_problem), intent(inout) :: problem
      !> norm_max or norm_rms
      integer, intent(in) :: norm
      !> This process's part
      real(dp), intent(in) :: part
      !> This process's number of components
      integer, intent(in) :: n
      if (norm == norm_max) then
         collective_norm = reduced_max(problem, part)
      else
         collective_norm = reduced_root_mean_square(problem, part, n)
      end if
   end function collective_norm

   !> One attempt from (t, u) with step h. The outcome is attempt_accepted (u_new holds
   !> the new state), attempt_rejected_error, attempt_rejected_constraint, attempt_failed_newton,
   !> attempt_failed_nonfinite or attempt_failed_evaluation (step_stat holds the code);
   !> err is the weighted error (of an attempt that got that far) and h_next the
   !> controller's next step size (after a failed attempt: failure_shrink h, or the
   !> scheme's factor after a Newton failure). Nothing is allocated, failed attempts included.
   subroutine attempt(self, problem, scheme, options, t, h, u, outcome, err, h_next, step_stat)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> The scheme, prepared for the problem
      class(scheme_type), intent(inout) :: scheme
      !> The options (validated)
      type(integrator_options_type), intent(in) :: options
      !> Start and size of the step
      real(dp), intent(in) :: t, h
      !> State at t
      real(dp), intent(in) :: u(:)
      !> attempt_* outcome
      integer, intent(out) :: outcome
      !> Weighted error estimate (unchanged when the attempt failed before it)
      real(dp), intent(inout) :: err
      !> Next step size proposed by the controller (smaller after a failed attempt)
      real(dp), intent(out) :: h_next
      !> Why a failed attempt failed (its code)
      type(status_type), intent(inout) :: step_stat
      real(dp) :: factor, hold_low, hold_high, propagation, first_factor, at
      integer :: i, known_points
      logical :: refined, delta_propagated, timed, kept

      h_next = h
      delta_propagated = .false.
      ! the check of time_variation, along the steps' states where step doubling leaves
      ! the part at t and t + h/2 in the scheme; for an explicit scheme with step doubling
      ! in every problem: along the steps F's second difference also sees a mode the step
      ! amplifies where doubling's estimate does not (ex-t-2 at h lambda = -8, where R(z)
      ! = R(z/2)^2 = 25: status ok with states 1e33 tolerances off between the ends)
      timed = scheme%start_only_part /= 0 .and. (.not. problem%autonomous .or. &
         (.not. scheme%implicit .and. self%estimate == estimate_doubling))
      known_points = 0
      call set_code(step_stat, status_ok)
      ! scalar tolerances in one pass here, not through set_weights: with the general
      ! weights inlined into it, its entry cost 1-2 % of an attempt on a few unknowns
      if (self%scalar_tolerances) then
         call scalar_weights_and_tolerances(size(u), options%atol, options%rtol, self%newton_fraction, u, &
            self%weights, self%newton%tolerance, self%weights_raised)
      else
         call self%set_weights(problem, options, u, u)
         call newton_tolerances(size(u), self%newton_fraction, self%weights, u, self%newton%tolerance)
      end if
      if (self%estimate == estimate_doubling) then
         do i = 1, size(u)
            self%newton_whole%tolerance(i) = max(self%newton%tolerance(i), self%whole_newton_fraction*self%weights(i))
         end do
      end if
      if (self%estimate == estimate_doubling) then
         call take_doubled_step()
      else if (self%estimate == estimate_defect) then
         if (self%extrapolate) call self%extrapolate_to(h, u, self%guess)
         call run_scheme(scheme, self%newton, t, h, u, self%u_new)
         if (outcome == attempt_accepted) call estimate_step_error()
         if (outcome == attempt_accepted .and. options%local_extrapolation) call extrapolate_step()
      else
         if (self%extrapolate) call self%extrapolate_to(h, u, self%guess)
         call run_embedded_pair()
         if (outcome == attempt_accepted) then
            if (options%advance == advance_high .and. scheme%order < scheme%embedded_order) then
               self%u_new = self%u_new + self%delta
            else if (options%advance == advance_low .and. scheme%order > scheme%embedded_order) then
               self%u_new = self%u_new - self%delta
            end if
         end if
      end if
      select case (outcome)
      case (attempt_accepted)
      case (attempt_failed_newton)
         h_next = scheme%failure_factor(failure_shrink)*h
         return
      case default
         h_next = failure_shrink*h
         return
      end select
      if (.not. scheme%weights_at_start .and. self%scalar_tolerances .and. .not. allocated(options%nonnegative)) then
         ! the weights at the new state and the error's norm in them in one pass
         call scalar_weights_and_norm(size(u), options%atol, options%rtol, options%norm, u, self%u_new, self%delta, &
            self%weights, self%weights_raised, err)
         err = collective_norm(problem, options%norm, err, size(u))
      else
         if (.not. scheme%weights_at_start) then
            if (self%scalar_tolerances) then
               call scalar_tolerance_weights(size(u), options%atol, options%rtol, u, self%u_new, self%weights, &
                  self%weights_raised)
            else
               call self%set_weights(problem, options, u, self%u_new)
            end if
         end if
         if (allocated(options%nonnegative)) then
            call keep_nonnegative()
            if (outcome == attempt_rejected_constraint) return
         end if
         err = self%weighted_norm(problem, options, self%delta)
      end if
      if (err > 1.0_dp .and. scheme%refines_estimate .and. self%estimate == estimate_embedded) then
         ! the scheme's second estimate, when it has one for this attempt (radau5: RADAU5's
         ! filtered estimate at the first step and on retries)
         call problem%clear_rejection()
         call scheme%refine_estimate(problem, t, h, self%delta, refined, step_stat)
         if (refined) then
            call conclude(size(self%delta), self%delta)
            if (outcome /= attempt_accepted) then
               h_next = failure_shrink*h
               return
            end if
            err = self%weighted_norm(problem, options, self%delta)
         end if
      end if
      if (allocated(self%defect)) err = max(err, self%weighted_norm(problem, options, self%defect)/defect_limit)
      if (timed) err = max(err, time_variation())
      if (scheme%amplifies_errors) then
         ! M^(-1) P delta, which the next step's solve leaves of P delta, only when P
         ! delta itself is too large (a solve saved at most steps)
         if (.not. delta_propagated) call scheme%propagated_error(h, self%delta, self%propagated, filtered=.false.)
         propagation = self%weighted_norm(problem, options, self%propagated)/propagation_fraction
         if (propagation > err) then
            call scheme%propagated_error(h, self%delta, self%propagated, filtered=.true.)
            propagation = self%weighted_norm(problem, options, self%propagated)/propagation_fraction
         end if
         err = max(err, propagation)
      end if
      ! a rejected step shrinks h by the I controller's factor: the PI and PID terms of
      ! earlier (small) errors could otherwise ask for a larger step than the one
      ! just rejected, again and again
      factor = controller_factor(merge(self%controller, controller_i, err <= 1.0_dp), &
         scheme%step_safety(options%kappa), self%q, err, self%err_previous, self%err_before)
      if (self%controller == controller_predictive .and. err <= 1.0_dp .and. self%h_previous > 0.0_dp) then
         factor = min(factor, predictive_factor(options%kappa, self%q, err, self%err_previous, h, self%h_previous))
      end if
      if (options%max_growth > 0.0_dp) factor = min(factor, options%max_growth)
      if (options%min_shrink > 0.0_dp) factor = max(factor, options%min_shrink)
      if (err <= 1.0_dp) then
         call scheme%step_hold(hold_low, hold_high)
         ! with g linear a step of the same size solves its linear equations with the
         ! factors already made, in one iteration: keep h unless it may grow by 20 %
         if (problem%linear_g .and. scheme%implicit) hold_high = max(hold_high, linear_hold)
         if (factor >= hold_low .and. factor <= hold_high) factor = 1.0_dp
      end if
      ! before the first accepted step a scheme may have a rule of its own (radau5 as
      ! RADAU5: h/10), which the options' limits do not bound
      if (err > 1.0_dp .and. self%h_previous == 0.0_dp) then
         first_factor = scheme%first_rejection_factor()
         if (first_factor > 0.0_dp) factor = first_factor
      end if
      h_next = min(factor*h, options%h_max)
      if (err <= 1.0_dp) then
         outcome = attempt_accepted
         self%undo_err_previous = self%err_previous
         self%undo_err_before = self%err_before
         self%undo_h_previous = self%h_previous
         self%err_before = self%err_previous
         self%err_previous = err
         self%h_previous = h
         if (self%extrapolate) then
            self%u_step_start = u
            self%u_step_end = self%u_new
            self%extrapolation_ready = .true.
         end if
      else
         outcome = attempt_rejected_error
      end if

   contains

      !> h |P(t + h) - 2 P(t + h/2) + P(t)|_w / time_check_limit, P the part of F the
      !> scheme evaluates at the step's start only, along the step (step doubling: at u,
      !> u_half, u_new, the first two from the scheme, one evaluation) or at the new state
      !> (three): a P that switches later in the step leaves the scheme's estimate
      !> untouched (its samples are at the start, and step doubling's at the midpoint
      !> too), this sees it. 0 where an evaluation fails (the step's own outcome stands).
      real(dp) function time_variation()
         real(dp) :: failed
         select case (known_points)
         case (2)
            call evaluate_part(t + h, self%time_value)
         case default
            call evaluate_part(t + h, self%time_difference)
            call evaluate_part(t + 0.5_dp*h, self%time_value)
            self%time_difference = self%time_difference - 2.0_dp*self%time_value
            call evaluate_part(t, self%time_value)
         end select
         self%time_difference = h*(self%time_difference + self%time_value)
         ! (what the step's implicit part makes of it: by about h |lambda| less in the
         ! stiff directions of si-t-1 and si-t-2-paper)
         call scheme%damp_by_step_matrix(self%time_difference)
         failed = merge(1.0_dp, 0.0_dp, problem%evaluation_rejected() .or. .not. all(ieee_is_finite(self%time_difference)))
         call problem%clear_rejection()
         time_variation = 0.0_dp
         ! (every process agrees, as the norm is collective)
         if (reduced_max(problem, failed) > 0.0_dp) return
         time_variation = self%weighted_norm(problem, options, self%time_difference)/time_check_limit
      end function time_variation

      !> P at (at, u_new) into value, counted as the scheme's evaluations
      subroutine evaluate_part(at, value)
         real(dp), intent(in) :: at
         real(dp), intent(out) :: value(:)
         if (scheme%start_only_part == difference_f) then
            call evaluate_f(problem, at, self%u_new, value, scheme%counters)
         else
            call evaluate_rhs(problem, at, self%u_new, value, scheme%counters)
         end if
      end subroutine evaluate_part

      !> The scheme's P at time `expected` into value (known_points + 1), else known_points
      !> back to 0 (the three evaluations at the new state then)
      subroutine take_start_part(expected, value)
         real(dp), intent(in) :: expected
         real(dp), intent(inout) :: value(:)
         call scheme%start_part(value, at, kept)
         if (kept .and. at == expected) then
            known_points = known_points + 1
         else
            known_points = 0
         end if
      end subroutine take_start_part

      !> Components declared nonnegative that came out below 0: set to 0 when their
      !> negative parts are within projection_limit in the error norm, else the attempt
      !> is rejected, h_next the part of the step before the first of them reached 0
      !> (from a positive start value, along the line to its new value) times
      !> constraint_safety, at least constraint_shrink_low h (every process agrees).
      subroutine keep_nonnegative()
         real(dp) :: fraction
         integer :: i
         logical :: violated
         violated = .false.
         fraction = 1.0_dp
         do i = 1, size(u)
            self%violation(i) = 0.0_dp
            if (.not. options%nonnegative(i)) cycle
            if (self%u_new(i) >= 0.0_dp) cycle
            violated = .true.
            self%violation(i) = self%u_new(i)
            if (u(i) > 0.0_dp) fraction = min(fraction, u(i)/(u(i) - self%u_new(i)))
         end do
         ! a norm of zeros on every process is 0: the test below is agreed on
         if (self%weighted_norm(problem, options, self%violation) <= projection_limit) then
            if (violated) where (self%violation < 0.0_dp) self%u_new = 0.0_dp
            return
         end if
         outcome = attempt_rejected_constraint
         fraction = -reduced_max(problem, -fraction)
         h_next = max(constraint_shrink_low, constraint_safety*fraction)*h
      end subroutine keep_nonnegative

      !> Two steps of h/2 into u_new (each Newton started from the extrapolation of the
      !> step before it), one step of h by the copy (started from u_new), and the
      !> Richardson estimate of the error of u_new in delta.
      subroutine take_doubled_step()
         real(dp) :: half
         half = 0.5_dp*h
         ! the single step first: the first half starts from the same state (a scheme
         ! that keeps its values at the start of a step computes them once). The single
         ! step and the halves each start from their own extrapolation, not from one
         ! another's results: when a Taylor scheme's polynomial equation has a spurious
         ! root, they then rarely agree on it, and err rejects the step (seeding the
         ! halves with the single step's result saves a Newton iteration a solve, but
         ! let spurious roots through on Van der Pol)
         if (self%extrapolate) call self%extrapolate_to(h, u, self%guess)
         call run_scheme(scheme, self%newton_whole, t, h, u, self%u_whole)
         if (outcome /= attempt_accepted) return
         if (timed) call take_start_part(t, self%time_value)
         if (self%extrapolate) call self%extrapolate_to(half, u, self%guess)
         call run_scheme(scheme, self%newton, t, half, u, self%u_half)
         if (outcome /= attempt_accepted) return
         if (self%extrapolate) self%guess = 2.0_dp*self%u_half - u
         call run_scheme(scheme, self%newton, t + half, half, self%u_half, self%u_new)
         if (outcome /= attempt_accepted) return
         if (known_points == 1) then
            ! P(t, u) - 2 P(t + h/2, u_half), the end's term added by time_variation
            call take_start_part(t + half, self%time_difference)
            if (known_points == 2) self%time_difference = self%time_value - 2.0_dp*self%time_difference
         end if
         self%delta = self%richardson*(self%u_new - self%u_whole)
         if (scheme%checks_defect) then
            call problem%clear_rejection()
            call scheme%step_error(problem, t, h, u, self%u_new, self%defect, step_stat)
            call conclude(size(self%defect), self%defect)
            if (outcome /= attempt_accepted) return
         end if
         if (options%local_extrapolation) self%u_new = self%u_new + self%delta
      end subroutine take_doubled_step

      !> Local extrapolation: u_new minus the scheme's estimate of its error; for a scheme
      !> that amplifies errors minus also its correction of that state to the step's
      !> equation, once what the next steps made of the corrections left out would
      !> exceed correction_budget of the tolerance. What the next step makes of a
      !> correction left out is measured by what its solve leaves of it, amplified (P c,
      !> filtered), or, when the correction is not computed, by P delta of the whole
      !> estimate (in the stiff directions the correction is of the estimate's size), kept
      !> for the error test. An attempt that the error test rejects afterwards still
      !> counts (the sum only errs on the side of correcting).
      subroutine extrapolate_step()
         logical :: corrected
         real(dp) :: left_out
         self%u_new = self%u_new - self%delta
         if (.not. scheme%amplifies_errors) return
         call scheme%propagated_error(h, self%delta, self%propagated, filtered=.false.)
         delta_propagated = .true.
         left_out = self%weighted_norm(problem, options, self%propagated)
         if (self%uncorrected + left_out <= correction_budget) then
            self%uncorrected = self%uncorrected + left_out
            return
         end if
         call scheme%extrapolation_correction(problem, t, h, self%u_new, self%correction, corrected)
         ! every process has a correction or none goes on (the norms below are collective)
         if (reduced_max(problem, merge(0.0_dp, 1.0_dp, corrected)) > 0.0_dp) return
         delta_propagated = .false.
         call scheme%propagated_error(h, self%correction, self%propagated, filtered=.false.)
         left_out = self%weighted_norm(problem, options, self%propagated)
         if (self%uncorrected + left_out > correction_budget) then
            call scheme%propagated_error(h, self%correction, self%propagated, filtered=.true.)
            left_out = self%weighted_norm(problem, options, self%propagated)
         end if
         if (self%uncorrected + left_out <= correction_budget) then
            self%uncorrected = self%uncorrected + left_out
            return
         end if
         self%u_new = self%u_new - self%correction
      end subroutine extrapolate_step

      !> The scheme's estimate of the error of the step it just took, in delta (a failed
      !> evaluation or NaN/Inf values fail the attempt as in the step itself).
      subroutine estimate_step_error()
         call problem%clear_rejection()
         call scheme%step_error(problem, t, h, u, self%u_new, self%delta, step_stat)
         call conclude(size(self%delta), self%delta)
      end subroutine estimate_step_error

      !> One step of `stepper_scheme` with Newton `settings` from (t_from, u_from) into
      !> u_to, started from self%guess when extrapolating; outcome says whether it
      !> succeeded or why not.
      subroutine run_scheme(stepper_scheme, settings, t_from, step, u_from, u_to)
         class(scheme_type), intent(inout) :: stepper_scheme
         type(newton_settings_type), intent(in) :: settings
         real(dp), intent(in) :: t_from, step, u_from(:)
         ! (the stepper's own arrays: contiguous, which makes the checks of conclude cheap)
         real(dp), intent(out), contiguous :: u_to(:)
         call problem%clear_rejection()
         if (self%extrapolate) then
            call stepper_scheme%advance(problem, t_from, step, u_from, u_to, settings, step_stat, guess=self%guess)
         else
            call stepper_scheme%advance(problem, t_from, step, u_from, u_to, settings, step_stat)
         end if
         call conclude(size(u_to), u_to)
      end subroutine run_scheme

      !> run_scheme's step of h from (t, u) with the embedded pair: u_new and the
      !> embedded difference in delta (called once: compiled into attempt, without the
      !> descriptors of a call of its own)
      subroutine run_embedded_pair()
         call problem%clear_rejection()
         if (self%extrapolate) then
            call scheme%advance(problem, t, h, u, self%u_new, self%newton, step_stat, self%delta, self%guess)
         else
            call scheme%advance(problem, t, h, u, self%u_new, self%newton, step_stat, self%delta)
         end if
         call conclude(size(u), self%u_new, self%delta)
      end subroutine run_embedded_pair

      !> The outcome of what the scheme just computed (values, and more values when
      !> given), agreed on by every process: a rejected evaluation, NaN or Inf values,
      !> or the scheme's own failure (Newton's or its linear algebra's).
      subroutine conclude(n, values, more_values)
         ! (explicit-shape: the stepper's own arrays, contiguous, reach it without
         ! descriptors built at every attempt)
         integer, intent(in) :: n
         real(dp), intent(in) :: values(n)
         real(dp), intent(in), optional :: more_values(n)
         if (problem%evaluation_rejected()) then
            call set_code(step_stat, status_evaluation_failed)
            ! status_out_of_memory, when a work array of the problem could not be allocated
            call problem%memory_failure(step_stat)
         else if (step_stat%code == status_ok) then
            if (present(more_values)) then
               if (.not. finite_pair(n, values, more_values)) call set_code(step_stat, status_nonfinite)
            else
               if (.not. finite(n, values)) call set_code(step_stat, status_nonfinite)
            end if
         end if
         call agree_on_outcome(problem, step_stat)
         select case (step_stat%code)
         case (status_ok)
            outcome = attempt_accepted
         case (status_evaluation_failed)
            outcome = attempt_failed_evaluation
         case (status_nonfinite)
            outcome = attempt_failed_nonfinite
         case default
            outcome = attempt_failed_newton
         end select
      end subroutine conclude

   end subroutine attempt

   !> The Newton starting guess for the state a time `offset` after u, when
   !> extrapolating and the last accepted step ended in u: the line through its start
   !> and end, followed at most one step length further. (Extrapolating further, or
   !> along a parabola, amplifies the change of the last step: on Robertson's long
   !> steps that led Newton to spurious roots of the Taylor schemes' polynomial
   !> equations, far from the solution.)
   pure subroutine extrapolate_to(self, offset, u, guess)
      !> The stepper
      class(stepper_type), intent(in) :: self
      !> Time from the start of the new step to the guess
      real(dp), intent(in) :: offset
      !> State at the start of the new step (the end of the last accepted one)
      real(dp), intent(in) :: u(:)
      !> The guess (u when there is nothing to extrapolate from)
      real(dp), intent(out) :: guess(:)
      real(dp) :: ratio
      if (.not. (self%extrapolate .and. self%extrapolation_ready)) then
         guess = u
         return
      end if
      ratio = min(offset/self%h_previous, 1.0_dp)
      guess = u + ratio*(u - self%u_step_start)
   end subroutine extrapolate_to

   !> Take back the last accepted attempt, which the caller rejects after all (the
   !> dense output's error test): the controller's memory is as before it, and the next
   !> Newton start is not extrapolated from it.
   subroutine undo_acceptance(self)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      self%err_previous = self%undo_err_previous
      self%err_before = self%undo_err_before
      self%h_previous = self%undo_h_previous
      self%extrapolation_ready = .false.
   end subroutine undo_acceptance

   !> Whether every entry of v (n of them) is finite.
   pure logical function finite(n, v)
      integer, intent(in) :: n
      real(dp), intent(in) :: v(n)
      integer :: i
      finite = .false.
      ! (not unrolled: on a few unknowns the unrolled loop's entry costs more than the tests)
      !GCC$ unroll 1
      do i = 1, n
         if (.not. ieee_is_finite(v(i))) return
      end do
      finite = .true.
   end function finite

   !> Whether every entry of a and of b (n each) is finite, in one pass.
   pure logical function finite_pair(n, a, b)
      integer, intent(in) :: n
      real(dp), intent(in) :: a(n), b(n)
      integer :: i
      finite_pair = .false.
      !GCC$ unroll 1
      do i = 1, n
         if (.not. (ieee_is_finite(a(i)) .and. ieee_is_finite(b(i)))) return
      end do
      finite_pair = .true.
   end function finite_pair

   !> Keep the last accepted step for extrapolation only if u (the state the next
   !> step starts from) is where it ended: a caller may change the state between calls.
   subroutine continue_from(self, u)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      !> The state the next step starts from
      real(dp), intent(in) :: u(:)
      if (self%extrapolation_ready) self%extrapolation_ready = all(u == self%u_step_end)
   end subroutine continue_from

end module taylorode_integrate_stepper
