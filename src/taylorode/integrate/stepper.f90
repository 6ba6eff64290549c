!> One attempted step of the adaptive integrator: the scheme's step from U^n, its
!> error estimate in the weighted norm, the decision (accept, reject, failed) and
!> the controller's next step size.
!>
!> Error weights: w_i = atol_i + rtol max(|U_i^n|, |U_i^{n+1}|), never below
!> `roundoff_weight` times |U_i| (what double precision can resolve); a component
!> with atol_i = 0 that is zero is weighed against the size of the whole state (at
!> least 1), so that pure relative control (atol = 0) works.
module taylorode_integrate_stepper
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_ok, status_nonfinite, &
      status_evaluation_failed
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_integrate_options, only: integrator_options_type, norm_max, advance_high, advance_low
   use taylorode_integrate_controller, only: controller_factor, controller_auto, controller_i, &
      controller_predictive, predictive_factor
   use taylorode_integrate_history, only: attempt_accepted, attempt_rejected_error, &
      attempt_failed_newton, attempt_failed_nonfinite, attempt_failed_evaluation
   use taylorode_integrate_reduction, only: reduced_max, reduced_root_mean_square, agree_on_outcome
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: stepper_type, roundoff_weight

   !> Newton increments are never asked to be smaller than this many roundoffs of |U|
   real(dp), parameter :: newton_roundoff_floor = 10.0_dp
   !> Error weights are never below this fraction of |U_i| (50 roundoffs): a tighter
   !> tolerance asks for more than double precision resolves
   real(dp), parameter :: roundoff_weight = 50.0_dp*epsilon(1.0_dp)

   !> Work arrays and controller memory of the step attempts of one integration
   type :: stepper_type
      !> Candidate new state
      real(dp), allocatable :: u_new(:)
      !> Embedded difference U_high - U_low
      real(dp), allocatable :: delta(:)
      !> Error weights
      real(dp), allocatable :: weights(:)
      !> Newton settings passed to the scheme (tolerance updated every attempt)
      type(newton_settings_type) :: newton
      !> Order exponent of the controller
      real(dp) :: q = 2.0_dp
      !> Weighted errors of the two previous accepted steps (1 when there are none)
      real(dp) :: err_previous = 1.0_dp, err_before = 1.0_dp
      !> Whether some absolute tolerance is zero (weights may then need the state's size)
      logical :: zero_atol = .false.
      !> Whether a weight was raised to the roundoff floor
      logical :: weights_raised = .false.
      !> The controller in use (options%controller, controller_auto resolved)
      integer :: controller = controller_i
      !> Fraction of the weights given to Newton (options%newton_fraction, 0 resolved)
      real(dp) :: newton_fraction = 0.0_dp
      !> Size of the previous accepted step (0 when there is none)
      real(dp) :: h_previous = 0.0_dp
   contains
      !> Prepare for an integration of n unknowns with a scheme and options
      procedure :: start
      !> Weights from two states
      procedure :: set_weights
      !> Max or RMS norm of a vector in the current weights
      procedure :: weighted_norm
      !> One attempt from (t, u) with step h
      procedure :: attempt
   end type stepper_type

contains

   !> Prepare for an integration of n unknowns: work arrays (allocated only when n
   !> changes), the Newton policy of the options and the controller exponent q
   !> (options%q, or the lower order of the scheme's pair plus one). The controller
   !> and the Newton fraction the options leave to the scheme are settled here.
   subroutine start(self, n, scheme, options)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      !> The scheme
      class(scheme_type), intent(in) :: scheme
      !> The options (validated)
      type(integrator_options_type), intent(in) :: options
      if (allocated(self%u_new)) then
         if (size(self%u_new) /= n) deallocate (self%u_new, self%delta, self%weights, self%newton%tolerance)
      end if
      if (.not. allocated(self%u_new)) then
         allocate (self%u_new(n), self%delta(n), self%weights(n), self%newton%tolerance(n))
      end if
      self%newton%max_iterations = options%max_newton_iterations
      self%newton%reuse_matrix = options%reuse_newton_matrix
      self%q = options%q
      if (self%q == 0.0_dp) self%q = real(min(scheme%order, scheme%embedded_order) + 1, dp)
      self%err_previous = 1.0_dp
      self%err_before = 1.0_dp
      if (allocated(options%atol_vector)) then
         self%zero_atol = any(options%atol_vector == 0.0_dp)
      else
         self%zero_atol = options%atol == 0.0_dp
      end if
      ! weights of your own may be zero anywhere: the same fallback guards them
      self%zero_atol = self%zero_atol .or. allocated(options%error_weights)
      self%weights_raised = .false.
      self%h_previous = 0.0_dp
      self%controller = options%controller
      if (self%controller == controller_auto) then
         self%controller = merge(controller_predictive, controller_i, scheme%predictive_control)
      end if
      self%newton_fraction = options%newton_fraction
      if (self%newton_fraction == 0.0_dp) then
         if (options%rtol > 0.0_dp) then
            self%newton_fraction = scheme%newton_fraction(options%rtol)
         else if (allocated(options%atol_vector)) then
            self%newton_fraction = scheme%newton_fraction(maxval(options%atol_vector))
         else
            self%newton_fraction = scheme%newton_fraction(options%atol)
         end if
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
      if (options%norm == norm_max) then
         do i = 1, size(v)
            weighted_norm = max(weighted_norm, abs(v(i))/self%weights(i))
         end do
         weighted_norm = reduced_max(problem, weighted_norm)
      else
         do i = 1, size(v)
            weighted_norm = weighted_norm + (v(i)/self%weights(i))**2
         end do
         weighted_norm = reduced_root_mean_square(problem, weighted_norm, size(v))
      end if
   end function weighted_norm

   !> One attempt from (t, u) with step h. The outcome is attempt_accepted (u_new holds
   !> the new state), attempt_rejected_error, attempt_failed_newton,
   !> attempt_failed_nonfinite or attempt_failed_evaluation (step_stat holds the code);
   !> err is the weighted error (of an attempt that got that far) and h_next the
   !> controller's next step size. Nothing is allocated, failed attempts included.
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
      !> Next step size proposed by the controller (h on a failed attempt)
      real(dp), intent(out) :: h_next
      !> Why a failed attempt failed (its code)
      type(status_type), intent(inout) :: step_stat
      real(dp) :: factor, hold_low, hold_high
      integer :: i

      h_next = h
      call set_code(step_stat, status_ok)
      call self%set_weights(problem, options, u, u)
      ! never ask for more than roundoff allows, nor for a zero tolerance
      do i = 1, size(u)
         self%newton%tolerance(i) = max(self%newton_fraction*self%weights(i), &
            newton_roundoff_floor*epsilon(1.0_dp)*abs(u(i)), tiny(1.0_dp))
      end do
      call problem%clear_rejection()
      call scheme%advance(problem, t, h, u, self%u_new, self%newton, step_stat, self%delta)
      if (problem%evaluation_rejected()) then
         call set_code(step_stat, status_evaluation_failed)
      else if (step_stat%code == status_ok) then
         if (.not. (all(ieee_is_finite(self%u_new)) .and. all(ieee_is_finite(self%delta)))) then
            call set_code(step_stat, status_nonfinite)
         end if
      end if
      call agree_on_outcome(problem, step_stat)
      select case (step_stat%code)
      case (status_ok)
      case (status_evaluation_failed)
         outcome = attempt_failed_evaluation
         return
      case (status_nonfinite)
         outcome = attempt_failed_nonfinite
         return
      case default
         outcome = attempt_failed_newton
         return
      end select

      if (options%advance == advance_high .and. scheme%order < scheme%embedded_order) then
         self%u_new = self%u_new + self%delta
      else if (options%advance == advance_low .and. scheme%order > scheme%embedded_order) then
         self%u_new = self%u_new - self%delta
      end if
      call self%set_weights(problem, options, u, self%u_new)
      err = self%weighted_norm(problem, options, self%delta)
      factor = controller_factor(self%controller, scheme%step_safety(options%kappa), self%q, err, &
         self%err_previous, self%err_before)
      if (self%controller == controller_predictive .and. err <= 1.0_dp .and. self%h_previous > 0.0_dp) then
         factor = min(factor, predictive_factor(options%kappa, self%q, err, self%err_previous, h, self%h_previous))
      end if
      if (options%max_growth > 0.0_dp) factor = min(factor, options%max_growth)
      if (options%min_shrink > 0.0_dp) factor = max(factor, options%min_shrink)
      if (err <= 1.0_dp) then
         call scheme%step_hold(hold_low, hold_high)
         if (factor >= hold_low .and. factor <= hold_high) factor = 1.0_dp
      end if
      h_next = min(factor*h, options%h_max)
      if (err <= 1.0_dp) then
         outcome = attempt_accepted
         self%err_before = self%err_previous
         self%err_previous = err
         self%h_previous = h
      else
         outcome = attempt_rejected_error
      end if
   end subroutine attempt

end module taylorode_integrate_stepper
