!> The abstract one-step scheme and the counted evaluations every scheme uses.
!>
!> A scheme advances U0 at t by one step h to U1 and, when asked, also returns
!> delta = U_high - U_low, the difference between the two members of its embedded
!> pair computed from the same U0 (the adaptive integrator's error estimate). A
!> scheme describes itself: its name, the orders of its pair, whether it solves
!> nonlinear systems and which, its update formula and its stability function
!> R(z, w) on the linear test u' = lambda u + nu u (z = h lambda from f, w = h nu
!> from g). Schemes keep their work arrays between steps: after the first step of
!> a given size no step allocates.
module taylorode_schemes_scheme
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, set_code, describe, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_evaluation_failed
   use taylorode_base_counters, only: counters_type
   use taylorode_base_memory, only: sized
   use taylorode_linalg_matrix, only: matrix_type, dense_matrix_type, band_matrix_type, &
      matrix_structure_type
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type, default_newton_tolerance, default_max_newton_iterations
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: scheme_type, default_newton_settings, default_newton_fraction, stability_quotient
   public :: evaluate_f, evaluate_g, evaluate_rhs, evaluate_jac_f, evaluate_jac_g, evaluate_jac
   public :: evaluate_time_derivative, of_f, of_g, of_rhs

   !> The part of F a time derivative is taken of: f, g, or F = f + g (one call of `rhs`)
   integer, parameter :: of_f = 1, of_g = 2, of_rhs = 3

   !> Fraction of the error weights below which Newton increments must fall with the
   !> paper's Newton test, for schemes that take the integrator's default
   !> (options%newton_fraction = 0)
   real(dp), parameter :: default_newton_fraction = 1.0e-4_dp
   !> Largest fraction of the error weights left to Newton when its stop test
   !> estimates the error (FNEWT = max(10 eps / tol, min(cap, sqrt(tol))), Hairer's)
   real(dp), parameter :: estimated_newton_fraction_cap = 0.03_dp

   !> Abstract one-step scheme
   type, abstract :: scheme_type
      !> Name as users type it (e.g. "i-t-2")
      character(len=:), allocatable :: name
      !> Order of the member that advances the solution
      integer :: order = 0
      !> Order of the other member of the embedded pair
      integer :: embedded_order = 0
      !> Order observed on nonlinear problems (below `order` only for the paper's
      !> SI-T-2, second order on the linear test equation only)
      integer :: nonlinear_order = 0
      !> Whether a step solves nonlinear systems (Newton's method)
      logical :: implicit = .false.
      !> The update, as METHODS.md writes it
      character(len=:), allocatable :: update
      !> The Newton matrices a step factors ("" for an explicit scheme)
      character(len=:), allocatable :: newton_matrices
      !> Work done so far
      type(counters_type) :: counters
      !> Size the work arrays are prepared for (0: none yet)
      integer :: n = 0
      !> Jacobian structure the work arrays are prepared for
      type(matrix_structure_type) :: structure
      !> Whether the problem the work arrays are prepared for is autonomous (the work
      !> arrays of dF/dt are then left out)
      logical :: autonomous = .false.
      !> Whether the integrator's default controller (controller_auto) is the
      !> predictive one for this scheme (radau5), else the I controller
      logical :: predictive_control = .false.
      !> Whether the embedded difference estimates the error of the solution the scheme
      !> returns (radau5) rather than that of the lower-order member (the Taylor and
      !> IMEX pairs): the integrator's default error control then uses the pair
      logical :: estimates_own_error = .false.
      !> Whether the error test weighs with the state at the start of the step alone,
      !> atol + rtol |U^n| (RADAU5's SCAL), instead of atol + rtol max(|U^n|, |U^{n+1}|)
      logical :: weights_at_start = .false.
      !> Whether its Newton iteration starts from a guess the integrator gives (the
      !> extrapolated last step); radau5 starts from its own collocation polynomial
      logical :: takes_newton_guess = .true.
      !> Fewest Newton iterations a solve of the scheme can converge in: 2 with the
      !> library's Newton, which takes no first increment of a matrix it has just built
      !> alone; radau5's own iteration 1
      integer :: least_newton_iterations = 2
      !> Whether its Newton systems are linear when g is (problem%linear_g): implicit in g
      !> alone (si-t-1, imex-rk21), one iteration with the exact matrix solves them
      logical :: newton_linear_in_g = .false.
      !> Whether `step_error` estimates the local error of the step just taken (the
      !> second-order Taylor schemes: their filtered trapezoidal defect)
      logical :: estimates_step_error = .false.
      !> Degree of the continuous extension the scheme supplies through `dense_output`
      !> (0: none; the integrator then interpolates with the cubic Hermite interpolant)
      integer :: dense_degree = 0
      !> Whether `step_error` also serves as a check of the steps with step doubling: the
      !> filtered trapezoidal defect of a step that does not follow the solution (a
      !> spurious root of a Taylor scheme's equation, a step across a fold of a slow
      !> manifold) is of the size of the step's change, where the half steps may agree
      !> on it (i-t-2)
      logical :: checks_defect = .false.
      !> The part of F the scheme evaluates at a step's start only (difference_rhs: F, the
      !> explicit schemes; difference_f: f, si-t-1 and si-t-2-paper), 0 for none: in a
      !> problem that depends on t it cannot see that part change later in the step, and
      !> the stepper differences it in t over the step (a forcing switched on in a step's
      !> second half went unnoticed: 2.6e5 tolerances off with status ok); the difference
      !> goes through `damp_by_step_matrix`, as the step's implicit part damps what the
      !> change does. si-t-2, whose update follows f to second order in t, does not take
      !> it: the second difference far overstated its error (Prothero-Robinson with the
      !> forcing t^2 in f, exact in 11 steps, took 13,923)
      integer :: start_only_part = 0
      !> Whether an error of the state a step starts from reaches the new state amplified
      !> beyond what the stability function says (si-t-2: its h^2/2 J_f0 F0 evaluates the
      !> stiff g at the start explicitly); `propagated_error` says by how much
      logical :: amplifies_errors = .false.
      !> Newton iterations per system when the options leave the limit to the scheme
      !> (options%max_newton_iterations = 0): 10, radau5 7 (RADAU5's NIT)
      integer :: newton_iterations = default_max_newton_iterations
      !> Whether it solves M U' = F with a problem's constant mass matrix (radau5); the
      !> others refuse a problem that declares one
      logical :: solves_mass = .false.
      !> Whether `refine_estimate` may give a second, filtered error estimate when the
      !> embedded one fails the error test (radau5, as RADAU5's ESTRAD)
      logical :: refines_estimate = .false.
   contains
      !> One step with argument checks (sizes, h > 0, finite data)
      procedure, non_overridable :: take_step
      !> One step without checks: the drivers call it after checking once
      procedure(advance_interface), deferred :: advance
      !> Allocate work arrays for the problem's structure and n unknowns
      procedure(prepare_interface), deferred :: prepare
      !> Stability function R(z, w) on the linear test equation
      procedure(stability_interface), deferred :: stability
      !> Forget what is kept from earlier steps (a new integration or a new problem)
      procedure :: restart
      !> Record the size and structure to prepare for; false when unchanged
      procedure, non_overridable :: resize
      ! Step-control hooks the integrator asks after each successful step; the
      ! defaults leave its step control exactly as it is without them.
      !> Safety factor of the next step size (default: the integrator's kappa)
      procedure :: step_safety
      !> Band of factors h_new / h for which an accepted step keeps h (default: none)
      procedure :: step_hold
      !> Newton fraction of the error weights when options leave it to the scheme
      procedure :: newton_fraction
      !> Step-size factor for the retry after a Newton failure (default: the integrator's)
      procedure :: failure_factor
      !> The longest step the scheme's solves can still resolve (default: no limit)
      procedure :: largest_step
      !> v = M^(-1) v with the Newton matrix of the scheme's last solve (default: v as it is)
      procedure :: damp_by_step_matrix
      !> The part start_only_part of F at the start of the scheme's step, if it keeps it
      procedure :: start_part
      !> Step-size factor after an error-test rejection before the first accepted step
      !> (default: none, the controller's)
      procedure :: first_rejection_factor
      !> The scheme's own dense output of the step it just took (default: none)
      procedure :: dense_output
      !> Estimate of the local error of the step just taken (default: none)
      procedure :: step_error
      !> What an error of the state the step just taken ended in adds to the next step
      procedure :: propagated_error
      !> A second estimate of the step's error when the first failed the error test
      procedure :: refine_estimate
      !> The correction that puts a locally extrapolated state onto the step's equation
      procedure :: extrapolation_correction
   end type scheme_type

   abstract interface
      !> Advance u0 at t by one step h to u1 (and the embedded difference in delta).
      !> An implicit scheme starts Newton's method for the state at t + h from `guess`
      !> when given (else from u0); explicit schemes and radau5 (its own predictor) ignore it.
      subroutine advance_interface(self, problem, t, h, u0, u1, newton, stat, delta, guess)
         import :: scheme_type, ode_problem, dp, status_type, newton_settings_type
         !> The scheme
         class(scheme_type), intent(inout) :: self
         !> The problem
         class(ode_problem), intent(inout) :: problem
         !> Start of the step
         real(dp), intent(in) :: t
         !> Step size
         real(dp), intent(in) :: h
         !> State at t
         real(dp), intent(in) :: u0(:)
         !> State at t + h
         real(dp), intent(out) :: u1(:)
         !> Newton tolerances, iteration limit and reuse policy (implicit schemes)
         type(newton_settings_type), intent(in) :: newton
         !> Outcome (Newton failures of the step)
         type(status_type), intent(inout) :: stat
         !> Difference of the embedded pair, computed only when present
         real(dp), intent(out), optional :: delta(:)
         !> Approximation of the state at t + h to start Newton's method from
         real(dp), intent(in), optional :: guess(:)
      end subroutine advance_interface

      !> Allocate work arrays (dense or banded as the problem declares) for size n.
      subroutine prepare_interface(self, problem, n, stat)
         import :: scheme_type, ode_problem, status_type
         !> The scheme
         class(scheme_type), intent(inout) :: self
         !> The problem (its Jacobian structure decides the storage)
         class(ode_problem), intent(in) :: problem
         !> Number of unknowns
         integer, intent(in) :: n
         !> status_invalid_argument for a structure that does not fit n
         type(status_type), intent(inout) :: stat
      end subroutine prepare_interface

      !> R(z, w): one step from u0 = 1 of u' = lambda u + nu u, z = h lambda (f), w = h nu (g).
      pure function stability_interface(self, z, w) result(r)
         import :: scheme_type, dp
         !> The scheme
         class(scheme_type), intent(in) :: self
         !> h lambda (non-stiff part)
         complex(dp), intent(in) :: z
         !> h nu (stiff part)
         complex(dp), intent(in) :: w
         complex(dp) :: r
      end function stability_interface
   end interface

contains

   !> One step of the scheme after checking its arguments: sizes agree, h > 0 and
   !> finite, u0 finite. On any failure stat says why (status_evaluation_failed when the
   !> problem rejected an evaluation) and u1 is set to u0. Each call
   !> is a fresh step: nothing kept from earlier steps (factored Newton matrices) is
   !> used, and Newton iterates to default_newton_tolerance * (1 + |u0|).
   subroutine take_step(self, problem, t, h, u0, u1, stat, delta)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Start of the step
      real(dp), intent(in) :: t
      !> Step size, > 0
      real(dp), intent(in) :: h
      !> State at t
      real(dp), intent(in) :: u0(:)
      !> State at t + h
      real(dp), intent(out) :: u1(:)
      !> Status of the step
      type(status_type), intent(out) :: stat
      !> Difference of the embedded pair U_high - U_low, computed only when present
      real(dp), intent(out), optional :: delta(:)
      type(newton_settings_type) :: newton

      if (size(u1) /= size(u0)) then
         call set_status(stat, status_size_mismatch, "take_step: u1 has a different size from u0")
         return
      end if
      u1 = u0
      if (present(delta)) then
         if (size(delta) /= size(u0)) then
            call set_status(stat, status_size_mismatch, "take_step: delta has a different size from u0")
            return
         end if
         delta = 0.0_dp
      end if
      if (size(u0) < 1) then
         call set_status(stat, status_size_mismatch, "take_step: the state is empty")
         return
      end if
      if (.not. (h > 0.0_dp) .or. .not. ieee_is_finite(h)) then
         call set_status(stat, status_invalid_argument, "take_step: the step size h must be positive and finite")
         return
      end if
      if (.not. ieee_is_finite(t)) then
         call set_status(stat, status_invalid_argument, "take_step: t is not finite")
         return
      end if
      if (.not. all(ieee_is_finite(u0))) then
         call set_status(stat, status_nonfinite, "take_step: the state u0 contains NaN or Inf")
         return
      end if
      call self%prepare(problem, size(u0), stat)
      if (stat%code /= status_ok) return
      call self%restart()
      call default_newton_settings(u0, newton, stat)
      if (stat%code /= status_ok) return
      call problem%clear_rejection()
      call self%advance(problem, t, h, u0, u1, newton, stat, delta)
      if (problem%evaluation_rejected()) then
         call set_status(stat, status_evaluation_failed, &
            "take_step: the problem could not evaluate f, g or a Jacobian during the step")
         call problem%memory_failure(stat)
      else if (stat%code == status_ok .and. .not. all(ieee_is_finite(u1))) then
         call set_status(stat, status_nonfinite, "take_step: the new state contains NaN or Inf")
      end if
      call describe(stat, "take_step")
   end subroutine take_step

   !> numerator / denominator for a stability function: at a pole (denominator exactly
   !> zero) the huge real number, so that |R| > 1 there and nothing divides by zero.
   elemental function stability_quotient(numerator, denominator) result(r)
      !> Numerator and denominator of R(z, w)
      complex(dp), intent(in) :: numerator, denominator
      complex(dp) :: r
      if (denominator == (0.0_dp, 0.0_dp)) then
         r = cmplx(huge(1.0_dp), 0.0_dp, dp)
      else
         r = numerator/denominator
      end if
   end function stability_quotient

   !> Newton settings of a step taken without an integrator: increments below
   !> default_newton_tolerance * (1 + |u0|), default iteration limit, matrices kept.
   pure subroutine default_newton_settings(u0, newton, stat)
      !> State at the start of the step
      real(dp), intent(in) :: u0(:)
      !> The settings; the tolerance is (re)allocated only when its size changes
      type(newton_settings_type), intent(inout) :: newton
      !> status_out_of_memory when the tolerances cannot be allocated
      type(status_type), intent(inout) :: stat
      call sized(newton%tolerance, size(u0), "the Newton tolerances", stat)
      if (stat%code /= status_ok) return
      newton%tolerance = default_newton_tolerance*(1.0_dp + abs(u0))
   end subroutine default_newton_settings

   !> Forget what is kept from earlier steps; the explicit schemes keep nothing.
   subroutine restart(self)
      !> The scheme
      class(scheme_type), intent(inout) :: self
   end subroutine restart

   !> Safety factor for the step size proposed after the last step; the default is
   !> the integrator's kappa unchanged (radau5 lowers it after slow Newton).
   pure real(dp) function step_safety(self, kappa)
      !> The scheme
      class(scheme_type), intent(in) :: self
      !> The integrator's safety factor
      real(dp), intent(in) :: kappa
      step_safety = kappa
   end function step_safety

   !> After an accepted step, a proposed factor h_new / h in [low, high] keeps h
   !> (so that factored matrices serve the next step). Default: low = high = 1,
   !> which changes nothing.
   pure subroutine step_hold(self, low, high)
      !> The scheme
      class(scheme_type), intent(in) :: self
      !> Lower and upper end of the band
      real(dp), intent(out) :: low, high
      low = 1.0_dp
      high = 1.0_dp
   end subroutine step_hold

   !> Fraction of the error weights to which Newton iterates when the options
   !> leave it to the scheme; `tolerance` is rtol (atol when rtol = 0). With a stop
   !> test that estimates Newton's error (`estimated`), Hairer's FNEWT, max(10 eps /
   !> tol, min(0.03, sqrt(tol))): what Newton leaves in each step can have one sign
   !> step after step (a kept matrix converges from one side), and a scheme of order 2
   !> takes ~tol^(-1/2) steps, so that sqrt(tol) keeps their sum within a fixed number
   !> of tolerances where 0.03 alone let it grow as tol^(-1/2) (i-t-2 on the pollution
   !> problem: 2, 4, 20, 170 tolerances at 1e-7 ... 1e-10); with the paper's test on
   !> the last increment, 1e-4.
   pure real(dp) function newton_fraction(self, tolerance, estimated)
      !> The scheme
      class(scheme_type), intent(in) :: self
      !> The integrator's relative tolerance (its absolute one when rtol = 0)
      real(dp), intent(in) :: tolerance
      !> Whether Newton's stop test estimates the error left
      logical, intent(in) :: estimated
      if (estimated) then
         newton_fraction = max(10.0_dp*epsilon(1.0_dp)/tolerance, min(estimated_newton_fraction_cap, &
            sqrt(tolerance)))
      else
         newton_fraction = default_newton_fraction
      end if
   end function newton_fraction

   !> Factor h_new / h for the retry after the last attempt failed in Newton's method
   !> (or its linear algebra); the default is the integrator's factor unchanged
   !> (radau5 takes RADAU5's, from the contraction rate Newton had).
   pure real(dp) function failure_factor(self, shrink)
      !> The scheme
      class(scheme_type), intent(in) :: self
      !> The integrator's factor after a failed attempt
      real(dp), intent(in) :: shrink
      failure_factor = shrink
   end function failure_factor

   !> The longest step the scheme can take: after a Newton solve that kept no digit of
   !> its residual (a stacked matrix once h |lambda| nears 1/epsilon) the steps are held
   !> below a fraction of that step; the default is no limit (huge).
   pure real(dp) function largest_step(self)
      !> The scheme
      class(scheme_type), intent(in) :: self
      largest_step = huge(1.0_dp)
   end function largest_step

   !> v = M^(-1) v, M the Newton matrix of the scheme's last solve: what the implicit
   !> part of its step makes of a perturbation of the step's equation (the stepper's
   !> check of a part of F evaluated at the start only). The default, for schemes that
   !> solve nothing, leaves v as it is.
   subroutine damp_by_step_matrix(self, v)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> Vector on entry, M^(-1) v on exit
      real(dp), contiguous, intent(inout) :: v(:)
   end subroutine damp_by_step_matrix

   !> value = the part `start_only_part` of F at the state the scheme's next step would
   !> start from (that of its last step, or its end once an estimate evaluated it there),
   !> and its time, when the scheme keeps it (kept); the default keeps none.
   subroutine start_part(self, value, at, kept)
      !> The scheme
      class(scheme_type), intent(in) :: self
      !> The part (when kept)
      real(dp), intent(inout) :: value(:)
      !> Its time (when kept)
      real(dp), intent(out) :: at
      !> Whether the scheme keeps it
      logical, intent(out) :: kept
      at = 0.0_dp
      kept = .false.
   end subroutine start_part

   !> Factor h_new / h after the error test rejected an attempt before the first
   !> accepted step of an integration, in place of the controller's (and of the
   !> options' limits on it); 0, the default, leaves it to the controller (radau5 as
   !> RADAU5, `first_step_as_radau5`: 0.1).
   pure real(dp) function first_rejection_factor(self)
      !> The scheme
      class(scheme_type), intent(in) :: self
      first_rejection_factor = 0.0_dp
   end function first_rejection_factor

   !> The scheme's continuous extension of the step it just took, from t with size h to
   !> u1, as a polynomial in theta = (t' - t)/h in Newton form (see
   !> taylorode_integrate_step): nodes(1:degree) and coefficient columns 0:degree, and
   !> the points 0:degree in theta where it matches the scheme's values.
   !> degree = 0 says it has none for this step (a step it did not take, or a u1 the
   !> integrator changed); the default has none at all.
   pure subroutine dense_output(self, t, h, u1, nodes, coefficients, points, degree)
      !> The scheme
      class(scheme_type), intent(in) :: self
      !> Start and size of the step
      real(dp), intent(in) :: t, h
      !> State the integrator accepted at t + h
      real(dp), intent(in) :: u1(:)
      !> Nodes of the Newton form (size dense_degree at least)
      real(dp), intent(inout) :: nodes(:)
      !> Coefficient vectors of the Newton form (columns 0:dense_degree at least)
      real(dp), intent(inout) :: coefficients(:, 0:)
      !> Interpolation points (0:dense_degree at least)
      real(dp), intent(inout) :: points(0:)
      !> Degree written (0: none)
      integer, intent(out) :: degree
      degree = 0
   end subroutine dense_output

   !> Estimate of the local error U1 - u(t + h) of a step from (t, u0) to u1, for
   !> schemes that declare `estimates_step_error` (of the step just taken) or
   !> `checks_defect` (of any step from u0 with the last Newton matrix); the default
   !> has none and says so (status_invalid_argument, code only).
   subroutine step_error(self, problem, t, h, u0, u1, error, stat)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Start and size of the step
      real(dp), intent(in) :: t, h
      !> States at both ends of the step
      real(dp), intent(in) :: u0(:), u1(:)
      !> The estimate
      real(dp), contiguous, intent(out) :: error(:)
      !> Outcome
      type(status_type), intent(inout) :: stat
      error = 0.0_dp
      call set_code(stat, status_invalid_argument)
   end subroutine step_error

   !> propagated = P error: what an error of the state the step just taken (size h) ended
   !> in adds to the equation of a next step like it, beyond the error itself, for
   !> schemes that declare `amplifies_errors`; with `filtered`, M^(-1) P error, what the
   !> next step's solve leaves of it (M the step's Newton matrix). The default leaves
   !> propagated at 0.
   subroutine propagated_error(self, h, error, propagated, filtered)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> Size of the step just taken
      real(dp), intent(in) :: h
      !> The error (an estimate of the step's)
      real(dp), contiguous, intent(in) :: error(:)
      !> What it adds to the next step
      real(dp), contiguous, intent(out) :: propagated(:)
      !> Whether to apply M^(-1)
      logical, intent(in) :: filtered
      propagated = 0.0_dp
   end subroutine propagated_error

   !> For a scheme whose step solves an equation: the correction that puts u1, the state
   !> of the step just taken (size h from t) minus its `step_error` (local
   !> extrapolation), onto that equation offset by the error (the integrator subtracts
   !> it when leaving it would matter). The default has none.
   subroutine extrapolation_correction(self, problem, t, h, u1, correction, corrected)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Start and size of the step
      real(dp), intent(in) :: t, h
      !> The extrapolated state
      real(dp), intent(in) :: u1(:)
      !> The correction, when `corrected`
      real(dp), contiguous, intent(inout) :: correction(:)
      !> Whether a correction was computed
      logical, intent(out) :: corrected
      corrected = .false.
   end subroutine extrapolation_correction

   !> A second estimate of the error of the step just taken (size h from t), asked for
   !> when its embedded estimate `delta` failed the error test, for schemes that declare
   !> `refines_estimate`: delta is replaced and `refined` set when the scheme has one for
   !> this attempt (radau5 at the first step and on retries, as RADAU5). The default has
   !> none.
   subroutine refine_estimate(self, problem, t, h, delta, refined, stat)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Start and size of the step just taken
      real(dp), intent(in) :: t, h
      !> The estimate on entry, the refined one on exit when `refined`
      real(dp), contiguous, intent(inout) :: delta(:)
      !> Whether delta was replaced
      logical, intent(out) :: refined
      !> Outcome (an evaluation that failed)
      type(status_type), intent(inout) :: stat
      refined = .false.
   end subroutine refine_estimate

   !> Record size n, the problem's (checked) Jacobian structure and whether it is
   !> autonomous; true when they differ from what the work arrays were prepared for (the
   !> caller then reallocates). An impossible structure, or a mass matrix the scheme does not
   !> solve, leaves stat set and returns false.
   logical function resize(self, problem, n, stat)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(in) :: problem
      !> Number of unknowns
      integer, intent(in) :: n
      !> status_invalid_argument for an impossible structure
      type(status_type), intent(inout) :: stat
      type(matrix_structure_type) :: structure
      resize = .false.
      if (problem%has_mass .and. .not. self%solves_mass) then
         call set_status(stat, status_invalid_argument, "the problem has a mass matrix (M U' = F), which only "// &
            "radau5 solves; "//self%name//" does not")
         return
      end if
      call problem%checked_structure(n, structure, stat)
      if (stat%code /= status_ok) return
      resize = .not. (self%n == n .and. self%structure%storage == structure%storage .and. &
         self%structure%lower == structure%lower .and. self%structure%upper == structure%upper .and. &
         (self%autonomous .eqv. problem%autonomous))
      self%n = n
      self%structure = structure
      self%autonomous = problem%autonomous
   end function resize

   !> Counted d(part)/dt at (t, u), part f, g or F (of_f, of_g, of_rhs), by the
   !> second-order one-sided difference through part(t, u) = value (known to the
   !> caller), part(t + d, u) and part(t + 2d, u), d of the sign of `step`, |d| =
   !> |step|/128 (at least 64 eps |t|). The schemes use h^2/2 dF/dt: the difference's
   !> own error, d^2/3 F_ttt, adds 1e-5 h^4 F_ttt to a step, and its rounding error is
   !> 1e-13 of the change of F over the step, smooth in U to what Newton resolves (a
   !> difference over sqrt(eps) |t| would leave 1e-8 of it, noise that stops Newton).
   !> A scheme takes it into its step (step = h forward from the start, -h backward
   !> from the end), so that no difference reaches across a step's end, where a
   !> problem may jump in t.
   subroutine evaluate_time_derivative(problem, part, t, step, u, value, derivative, work, counters)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> of_f, of_g or of_rhs
      integer, intent(in) :: part
      !> Time
      real(dp), intent(in) :: t
      !> The step the difference is taken into: its length and side of t
      real(dp), intent(in) :: step
      !> State
      real(dp), intent(in) :: u(:)
      !> part(t, u)
      real(dp), intent(in) :: value(:)
      !> d(part)/dt at (t, u)
      real(dp), intent(out) :: derivative(:)
      !> Work array of the size of u
      real(dp), intent(out) :: work(:)
      !> Work counters
      type(counters_type), intent(inout) :: counters
      real(dp) :: d, a, b, ratio_ba, ratio_ab
      integer :: i
      d = sign(max(abs(step)/128.0_dp, 64.0_dp*epsilon(1.0_dp)*abs(t)), step)
      ! the offsets as the times represent them; the quadratic through the three values,
      ! differentiated at t, weighs them b/(a (b - a)), -a/(b (b - a)) and minus their sum
      a = (t + d) - t
      b = (t + 2.0_dp*d) - t
      ratio_ba = b/a
      ratio_ab = a/b
      call evaluate_part(t + a, derivative)
      call evaluate_part(t + b, work)
      ! as differences, exactly 0 where part does not depend on t; divided by b - a
      ! last, for a (b - a) underflows once a step is below 1e-154 (its weight was Inf,
      ! and Inf times a zero difference NaN)
      do i = 1, size(u)
         derivative(i) = (ratio_ba*(derivative(i) - value(i)) - ratio_ab*(work(i) - value(i)))/(b - a)
      end do
   contains
      !> part(time, u), counted
      subroutine evaluate_part(time, result)
         real(dp), intent(in) :: time
         real(dp), intent(out) :: result(:)
         select case (part)
         case (of_f)
            call evaluate_f(problem, time, u, result, counters)
         case (of_g)
            call evaluate_g(problem, time, u, result, counters)
         case default
            call evaluate_rhs(problem, time, u, result, counters)
         end select
      end subroutine evaluate_part
   end subroutine evaluate_time_derivative

   !> Counted evaluation of f.
   subroutine evaluate_f(problem, t, u, value, counters)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> f(t, u)
      real(dp), intent(out) :: value(:)
      !> Work counters
      type(counters_type), intent(inout) :: counters
      call problem%f(t, u, value)
      counters%f_evaluations = counters%f_evaluations + 1
   end subroutine evaluate_f

   !> Counted evaluation of g.
   subroutine evaluate_g(problem, t, u, value, counters)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> g(t, u)
      real(dp), intent(out) :: value(:)
      !> Work counters
      type(counters_type), intent(inout) :: counters
      call problem%g(t, u, value)
      counters%g_evaluations = counters%g_evaluations + 1
   end subroutine evaluate_g

   !> Counted evaluation of F = f + g in one call of the problem's `rhs`.
   subroutine evaluate_rhs(problem, t, u, value, counters)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> F(t, u)
      real(dp), intent(out) :: value(:)
      !> Work counters
      type(counters_type), intent(inout) :: counters
      call problem%rhs(t, u, value)
      counters%f_evaluations = counters%f_evaluations + 1
      counters%g_evaluations = counters%g_evaluations + 1
   end subroutine evaluate_rhs

   !> Counted evaluation of df/dU, dense or in band storage, checked for NaN and Inf.
   subroutine evaluate_jac_f(problem, t, u, jac, counters, stat)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> df/dU at (t, u), in the storage the problem declared
      class(matrix_type), intent(inout) :: jac
      !> Work counters
      type(counters_type), intent(inout) :: counters
      !> status_nonfinite when an entry is NaN or Inf
      type(status_type), intent(inout) :: stat
      select type (jac)
      type is (dense_matrix_type)
         call problem%jac_f(t, u, jac%a)
      type is (band_matrix_type)
         call problem%jac_f_band(t, u, jac%ab(jac%fill + 1:, :))
      end select
      counters%jac_f_evaluations = counters%jac_f_evaluations + 1
      if (.not. jac%all_finite()) call set_code(stat, status_nonfinite)
   end subroutine evaluate_jac_f

   !> Counted evaluation of J = df/dU + dg/dU in one call (the problem's `jac`, or
   !> `jac_band`; `jac_with_rhs`, `jac_band_with_rhs` when F(t, u) is given), dense or in
   !> band storage, checked for NaN and Inf; it counts as one evaluation of each.
   subroutine evaluate_jac(problem, t, u, jac, counters, stat, rhs_value)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> J at (t, u), in the storage the problem declared
      class(matrix_type), intent(inout) :: jac
      !> Work counters
      type(counters_type), intent(inout) :: counters
      !> status_nonfinite when an entry is NaN or Inf
      type(status_type), intent(inout) :: stat
      !> F(t, u), when the caller has it (a difference Jacobian then starts from it)
      real(dp), intent(in), optional :: rhs_value(:)
      select type (jac)
      type is (dense_matrix_type)
         if (present(rhs_value)) then
            call problem%jac_with_rhs(t, u, rhs_value, jac%a)
         else
            call problem%jac(t, u, jac%a)
         end if
      type is (band_matrix_type)
         if (present(rhs_value)) then
            call problem%jac_band_with_rhs(t, u, rhs_value, jac%ab(jac%fill + 1:, :))
         else
            call problem%jac_band(t, u, jac%ab(jac%fill + 1:, :))
         end if
      end select
      counters%jac_f_evaluations = counters%jac_f_evaluations + 1
      counters%jac_g_evaluations = counters%jac_g_evaluations + 1
      if (.not. jac%all_finite()) call set_code(stat, status_nonfinite)
   end subroutine evaluate_jac

   !> Counted evaluation of dg/dU, dense or in band storage, checked for NaN and Inf.
   subroutine evaluate_jac_g(problem, t, u, jac, counters, stat)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> dg/dU at (t, u), in the storage the problem declared
      class(matrix_type), intent(inout) :: jac
      !> Work counters
      type(counters_type), intent(inout) :: counters
      !> status_nonfinite when an entry is NaN or Inf
      type(status_type), intent(inout) :: stat
      select type (jac)
      type is (dense_matrix_type)
         call problem%jac_g(t, u, jac%a)
      type is (band_matrix_type)
         call problem%jac_g_band(t, u, jac%ab(jac%fill + 1:, :))
      end select
      counters%jac_g_evaluations = counters%jac_g_evaluations + 1
      if (.not. jac%all_finite()) call set_code(stat, status_nonfinite)
   end subroutine evaluate_jac_g

end module taylorode_schemes_scheme
