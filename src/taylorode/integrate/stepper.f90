!> One attempted step of the adaptive integrator: the scheme's step from U^n, its
!> error estimate in the weighted norm, the decision (accept, reject, failed) and
!> the controller's next step size.
module taylorode_integrate_stepper
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_nonfinite
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_integrate_options, only: integrator_options_type, norm_max, advance_high, advance_low
   use taylorode_integrate_controller, only: controller_factor, controller_auto, controller_i, &
      controller_predictive, predictive_factor
   use taylorode_integrate_history, only: attempt_accepted, attempt_rejected_error, &
      attempt_failed_newton, attempt_failed_nonfinite
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: stepper_type

   !> Newton increments are never asked to be smaller than this many roundoffs of |U|
   real(dp), parameter :: newton_roundoff_floor = 10.0_dp

   !> Work arrays and controller memory of the step attempts of one integration
   type :: stepper_type
      !> Candidate new state
      real(dp), allocatable :: u_new(:)
      !> Embedded difference U_high - U_low
      real(dp), allocatable :: delta(:)
      !> Error weights w_i = atol_i + rtol max(|U_i^n|, |U_i^{n+1}|)
      real(dp), allocatable :: weights(:)
      !> Newton settings passed to the scheme (tolerance updated every attempt)
      type(newton_settings_type) :: newton
      !> Order exponent of the controller
      real(dp) :: q = 2.0_dp
      !> Weighted errors of the two previous accepted steps (1 when there are none)
      real(dp) :: err_previous = 1.0_dp, err_before = 1.0_dp
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

   !> w_i = atol_i + rtol * max(|a_i|, |b_i|)
   subroutine set_weights(self, options, a, b)
      !> The stepper
      class(stepper_type), intent(inout) :: self
      !> Tolerances
      type(integrator_options_type), intent(in) :: options
      !> The two states
      real(dp), intent(in) :: a(:), b(:)
      if (allocated(options%atol_vector)) then
         self%weights = options%atol_vector + options%rtol*max(abs(a), abs(b))
      else
         self%weights = options%atol + options%rtol*max(abs(a), abs(b))
      end if
   end subroutine set_weights

   !> Max or RMS norm of v / w.
   real(dp) function weighted_norm(self, options, v)
      !> The stepper (its weights)
      class(stepper_type), intent(in) :: self
      !> The norm to use
      type(integrator_options_type), intent(in) :: options
      !> The vector
      real(dp), intent(in) :: v(:)
      if (options%norm == norm_max) then
         weighted_norm = maxval(abs(v)/self%weights)
      else
         weighted_norm = sqrt(sum((v/self%weights)**2)/real(size(v), dp))
      end if
   end function weighted_norm

   !> One attempt from (t, u) with step h. The outcome is attempt_accepted (u_new holds
   !> the new state), attempt_rejected_error, attempt_failed_newton or
   !> attempt_failed_nonfinite (step_stat says why); err is the weighted error (of
   !> an attempt that got that far) and h_next the controller's next step size.
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
      !> Why a failed attempt failed
      type(status_type), intent(out) :: step_stat
      real(dp) :: factor, hold_low, hold_high

      h_next = h
      call self%set_weights(options, u, u)
      ! never ask for more than roundoff allows, nor for a zero tolerance
      self%newton%tolerance = max(self%newton_fraction*self%weights, &
         newton_roundoff_floor*epsilon(1.0_dp)*abs(u), tiny(1.0_dp))
      call scheme%advance(problem, t, h, u, self%u_new, self%newton, step_stat, self%delta)
      if (step_stat%code == status_ok) then
         if (.not. (all(ieee_is_finite(self%u_new)) .and. all(ieee_is_finite(self%delta)))) then
            call set_status(step_stat, status_nonfinite, "the new state or the error estimate is NaN or Inf")
         end if
      end if
      if (step_stat%code == status_nonfinite) then
         outcome = attempt_failed_nonfinite
         return
      else if (step_stat%code /= status_ok) then
         outcome = attempt_failed_newton
         return
      end if

      if (options%advance == advance_high .and. scheme%order < scheme%embedded_order) then
         self%u_new = self%u_new + self%delta
      else if (options%advance == advance_low .and. scheme%order > scheme%embedded_order) then
         self%u_new = self%u_new - self%delta
      end if
      call self%set_weights(options, u, self%u_new)
      err = self%weighted_norm(options, self%delta)
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
