!> Radau IIA of order 5 (three stages, L-stable), the library's reference solver,
!> as Hairer & Wanner's RADAU5 (Solving Ordinary Differential Equations II,
!> section IV.8, and their radau5.f of 2002).
!>
!> Stage increments Z_i = Y_i - U0 solve Z_i = h sum_j a_ij F(t0 + c_j h, U0 + Z_j);
!> U1 = U0 + Z_3 (stiffly accurate). With W = T^(-1) Z, T from the eigen-decomposition
!> of A^(-1) (one real eigenvalue gamma, one complex pair alpha +- i beta), the
!> simplified Newton iteration splits into one real n x n system with
!> (gamma/h) I - J and one complex n x n system with ((alpha + i beta)/h) I - J,
!> factored through LAPACK in the storage the problem declares (dense, or band
!> through dgbtrf/zgbtrf: the banded Brusselator needs no dense matrix), and
!> written-out LU factors for dense systems of up to `small_lu_max_order` unknowns.
!>
!> What is kept between steps follows RADAU5:
!> - the Jacobian J = J_f + J_g is recomputed after an accepted step only when its
!>   Newton iteration contracted slowly (theta > 0.001), and on a retry only when
!>   it was not computed at this point already;
!> - the factorizations are kept while h is unchanged, and `step_hold` asks the
!>   integrator to keep h when it would grow by a factor in [1, 1.2] after fast
!>   Newton (and not to grow it at all right after a rejection);
!> - Newton starts from the collocation polynomial of the last accepted step,
!>   extrapolated to the new stages (zero before the first accepted step);
!> - Newton stops when theta/(1 - theta) |dW| <= 1 in the weighted RMS norm of the
!>   tolerance the integrator passes, after at most NIT iterations (the integrator's
!>   max_newton_iterations, by default RADAU5's 7), and gives up as soon as the
!>   contraction rate says it would not converge within them (a step without error
!>   estimate, as `integrate_fixed` takes, cannot be shrunk: Newton then goes on while
!>   it contracts, up to 50 iterations);
!> - the error estimate (embedded order 3)
!>     delta = ((gamma/h) I - J)^(-1) [F(t0, U0) + (d1 Z1 + d2 Z2 + d3 Z3)/h]
!>   reuses the real factorization; when it fails the error test at the first step
!>   or on a retry, the integrator asks for it filtered once more with
!>   F(t0, U0 + delta) (`refine_estimate`, RADAU5's ESTRAD);
!> - the collocation polynomial of the accepted step is its dense output
!>   (`dense_output`, RADAU5's CONTR5): output times, observers and events cost no
!>   evaluation of F;
!> - `step_safety` lowers the integrator's kappa after slow Newton,
!>   kappa (1 + 2 nit)/(newt + 2 nit), and `predictive_control` makes the
!>   predictive (Gustafsson) controller the integrator's default for radau5.
!>
!> Tolerances: radau5 uses the integrator's rtol and atol as they are, like every
!> scheme of the library, with RADAU5's weights atol + rtol |U0| from the state at
!> the start of the step (`weights_at_start`); RADAU5's internal transformation
!> rtol' = 0.1 rtol^(2/3) is not applied (the integrator owns the error test).
!> Callers who want RADAU5's meaning of a tolerance pass 0.1 rtol^(2/3) themselves. When the options leave
!> the Newton fraction to the scheme it is RADAU5's FNEWT,
!> max(10 eps / rtol, min(0.03, sqrt(rtol))), of the given rtol.
!>
!> After a Newton failure `failure_factor` gives RADAU5's step-size factor: from the
!> contraction rate when Newton stopped because it would not converge in time,
!> 0.8 min(20, dyth)^(-1/(4 + NIT - 1 - newt)), else 1/2 (before the first accepted
!> step at most the integrator's). What the integrator does not take from RADAU5:
!> the first step size, and (unless `first_step_as_radau5`) the rules before the
!> first accepted step: an error-test rejection there shrinks h by the controller's
!> factor, not RADAU5's 1/10.
!>
!> Mass matrices: with a problem that declares a constant mass matrix M (`has_mass`:
!> M U' = F, M possibly singular, the index-1 differential-algebraic systems RADAU5 is
!> used for) the stage equations are M Z_i = h sum_j a_ij F(Y_j), the two Newton
!> systems (gamma/h) M - J and ((alpha + i beta)/h) M - J, the Newton right-hand sides
!> subtract M W instead of W, and the error estimate multiplies its stage part by M:
!>   delta = ((gamma/h) M - J)^(-1) [F(t0, U0) + M (d1 Z1 + d2 Z2 + d3 Z3)/h],
!> all as radau5.f does (its IJOB 3, 4 and 5). M is asked of the problem once per
!> integration, in the storage of its Jacobian structure.
!>
!> Settings a caller may change after `new_radau5` (the legacy entry maps RADAU5's
!> IWORK(4), WORK(1), WORK(3), WORK(5) and WORK(6) onto them): `zero_start` (Newton from zero
!> stage increments instead of the extrapolated polynomial), `jacobian_reuse` (THET:
!> the contraction rate up to which J serves the next step; negative: a new J after
!> every accepted step) and `hold_low`, `hold_high` (QUOT1, QUOT2); `rounding` (UROUND,
!> WORK(1): the floor of Newton's increment norms and contraction estimate); and
!> `first_step_as_radau5` (the legacy entry sets it): before the first accepted step
!> RADAU5's h/10 after an error-test rejection and its factor after a Newton failure.
!>
!> Counters: one LU factorization counts the real and the complex factorization
!> for one step size (RADAU5's NDEC); one linear solve per Newton iteration (both
!> systems) and per error-estimate solve.
!>
!> The loops over the unknowns of a step are not unrolled (`!GCC$ unroll 1`, which
!> overrides fpm's -funroll-loops): on the problems of two to a few dozen unknowns
!> RADAU5 is used for, an unrolled loop runs through a ladder of remainder tests
!> that costs more than its arithmetic; on large ones the loops are bound by memory.
module taylorode_schemes_radau5
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_ok, status_singular_matrix, &
      status_evaluation_failed, status_nonfinite, &
      status_newton_diverged, status_newton_not_converged
   use taylorode_base_memory, only: sized, out_of_memory, integer_bytes
   use taylorode_linalg_matrix, only: matrix_type, dense_matrix_type, band_matrix_type, new_matrix, storage_dense
   use taylorode_linalg_solver, only: linear_solver_type, new_linear_solver, finite_diagonal
   use taylorode_linalg_complex_solver, only: complex_solver_type, new_complex_solver
   use taylorode_linalg_lapack, only: small_lu_factor, small_lu_solve_reciprocal, small_lu_solve_pair, &
      small_lu_max_order
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_schemes_scheme, only: scheme_type, stability_quotient, evaluate_jac
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: radau5_type, new_radau5, describe_radau5

   real(dp), parameter :: sqrt6 = sqrt(6.0_dp)
   !> Up to this many unknowns, the loops that read what was just stored one value at a
   !> time are kept scalar (on 4 and 8 unknowns the vector loops measured faster)
   integer, parameter :: scalar_loop_max_order = 2
   !> Nodes and the differences the collocation polynomial uses
   real(dp), parameter :: c1 = (4.0_dp - sqrt6)/10.0_dp, c2 = (4.0_dp + sqrt6)/10.0_dp
   real(dp), parameter :: c1m1 = c1 - 1.0_dp, c2m1 = c2 - 1.0_dp, c1mc2 = c1 - c2
   !> Weights of the stage increments in the error estimate
   real(dp), parameter :: dd1 = -(13.0_dp + 7.0_dp*sqrt6)/3.0_dp, dd2 = (-13.0_dp + 7.0_dp*sqrt6)/3.0_dp, &
      dd3 = -1.0_dp/3.0_dp
   real(dp), parameter :: cbrt81 = 81.0_dp**(1.0_dp/3.0_dp), cbrt9 = 9.0_dp**(1.0_dp/3.0_dp)
   !> Real eigenvalue of A^(-1) (1/gamma0, gamma0 the real eigenvalue of A)
   real(dp), parameter :: real_eigenvalue = 30.0_dp/(6.0_dp + cbrt81 - cbrt9)
   real(dp), parameter :: alpha_a = (12.0_dp - cbrt81 + cbrt9)/60.0_dp, &
      beta_a = (cbrt81 + cbrt9)*sqrt(3.0_dp)/60.0_dp
   !> Complex eigenvalue pair of A^(-1): alpha +- i beta
   real(dp), parameter :: alpha = alpha_a/(alpha_a**2 + beta_a**2), beta = beta_a/(alpha_a**2 + beta_a**2)
   !> T (A^(-1) = T diag(gamma, [[alpha, -beta], [beta, alpha]]) T^(-1)) and T^(-1), as radau5.f
   real(dp), parameter :: t11 = 9.1232394870892942792e-02_dp, t12 = -0.14125529502095420843_dp, &
      t13 = -3.0029194105147424492e-02_dp, t21 = 0.24171793270710701896_dp, t22 = 0.20412935229379993199_dp, &
      t23 = 0.38294211275726193779_dp, t31 = 0.96604818261509293619_dp
   real(dp), parameter :: ti11 = 4.3255798900631553510_dp, ti12 = 0.33919925181580986954_dp, &
      ti13 = 0.54177053993587487119_dp, ti21 = -4.1787185915519047273_dp, ti22 = -0.32768282076106238708_dp, &
      ti23 = 0.47662355450055045196_dp, ti31 = -0.50287263494578687595_dp, ti32 = 2.5719269498556054292_dp, &
      ti33 = -0.59603920482822492497_dp

   !> Newton iterations allowed per step by default (RADAU5's NIT)
   integer, parameter :: newton_iteration_limit = 7
   !> Newton iterations allowed per fixed step (no error estimate asked: the caller
   !> cannot shrink the step, so a slowly contracting iteration is carried on)
   integer, parameter :: fixed_step_iterations = 50
   !> Contraction rate at or below which the Jacobian serves the next step (THET)
   real(dp), parameter :: jacobian_reuse_rate = 1.0e-3_dp
   !> Contraction rate from which Newton counts as diverging
   real(dp), parameter :: divergence_rate = 0.99_dp
   !> Step-size factors h_new / h kept as h after fast Newton (QUOT1, QUOT2)
   real(dp), parameter :: default_hold_low = 1.0_dp, default_hold_high = 1.2_dp
   !> RADAU5's step-size factor after an error-test rejection before its first
   !> accepted step
   real(dp), parameter :: first_rejection_shrink = 0.1_dp
   !> FNEWT = max(10 eps / rtol, min(newton_fraction_cap, sqrt(rtol)))
   real(dp), parameter :: newton_fraction_cap = 0.03_dp
   !> Step-size factor after a Newton failure without a contraction rate to go by
   !> (divergence, the iteration limit, a singular matrix, a failed evaluation)
   real(dp), parameter :: failure_halving = 0.5_dp
   !> After a Newton failure predicted from the contraction rate (dyth >= 1): the factor
   !> failure_safety min(dyth, failure_high)^(-1/(4 + NIT - 1 - newt))
   real(dp), parameter :: failure_safety = 0.8_dp, failure_high = 20.0_dp

   !> Radau IIA, order 5, with its order-3 embedded error estimate
   type, extends(scheme_type) :: radau5_type
      !> Jacobian J = J_f + J_g used by the factorizations
      class(matrix_type), allocatable :: jac
      !> (gamma/h) I - J and its factors (band, or dense above small_lu_max_order)
      type(linear_solver_type) :: real_solver
      !> (gamma/h) I - J and its factors for dense systems up to small_lu_max_order, and
      !> the reciprocals of its pivots
      real(dp), allocatable :: small_matrix(:, :), small_inverse_diagonal(:)
      !> ((alpha + i beta)/h) I - J and its factors for those systems, and the
      !> reciprocals of its pivots
      complex(dp), allocatable :: small_complex(:, :), small_complex_inverse_diagonal(:)
      !> Row interchanges of the two small dense factorizations
      integer, allocatable :: small_pivots(:), small_complex_pivots(:)
      !> Whether the small dense path is used
      logical :: small = .false.
      !> ((alpha + i beta)/h) I - J and its factors (band, or dense above small_lu_max_order)
      type(complex_solver_type) :: complex_solver
      !> The problem's constant mass matrix M (with `with_mass`), in the Jacobian's storage
      class(matrix_type), allocatable :: mass
      !> For a dense M, the first and last row of each column that hold entries (found
      !> once M is loaded): its products skip the rows outside them, whose zeros add
      !> nothing (a differential-algebraic system's M is mostly zeros, often a band)
      integer, allocatable :: mass_rows(:, :)
      !> M times the transformed stage increments W (with a mass matrix)
      real(dp), allocatable :: mw(:, :)
      !> Whether the problem has a mass matrix, and whether M has been asked for since
      !> the restart
      logical :: with_mass = .false., mass_loaded = .false.
      !> Stage increments Z (n x 3) and transformed W = T^(-1) Z. Within a Newton
      !> iteration z holds F at the stages, then the right-hand sides and increments of W
      !> (Z = T W follows); after the last one w holds the error estimate (column 1) and
      !> its stage part (column 2), as RADAU5 reuses Z and F
      real(dp), allocatable :: z(:, :), w(:, :)
      !> Collocation polynomial of the last accepted step
      real(dp), allocatable :: polynomial(:, :)
      !> State at the start of the step, F there, a stage state
      real(dp), allocatable :: u_start(:), rhs0(:), stage(:)
      !> Start of the current step
      real(dp) :: t_start = 0.0_dp
      !> Step sizes of the polynomial and of the stages in z, and the one the
      !> factorizations were made for
      real(dp) :: h_polynomial = 0.0_dp, h_stages = 0.0_dp, h_factored = 0.0_dp
      !> Whether a step has been attempted since the restart, a polynomial of an
      !> accepted step exists, z holds the converged stages of the last attempt
      logical :: started = .false., have_polynomial = .false., have_stages = .false.
      !> Whether J serves the current step, was computed at its start point, and
      !> whether factorizations for h_factored exist
      logical :: jacobian_valid = .false., jacobian_fresh = .false., factored = .false.
      !> Whether F(t0, U0) is known for the current step
      logical :: rhs0_valid = .false.
      !> Whether the current attempt repeats one from the same state (a retry)
      logical :: retry = .false.
      !> Newton's contraction rate and its error factor theta/(1 - theta), kept across steps
      real(dp) :: theta = jacobian_reuse_rate, faccon = 1.0_dp
      !> Steps since faccon was last set: RADAU5 raises it to the power 0.8 at the
      !> start of each step; the power is taken only when a test needs its value
      integer :: faccon_raises = 0
      !> Newton iterations of the last attempt
      integer :: newton_count = 0
      !> Step-size factor for a retry should the last attempt have failed
      real(dp) :: retry_factor = failure_halving
      !> Newton iterations allowed in the current step (NIT)
      integer :: iteration_limit = newton_iteration_limit
      !> Start Newton from zero stage increments (RADAU5's IWORK(4) /= 0) instead of the
      !> collocation polynomial of the last step
      logical :: zero_start = .false.
      !> Contraction rate up to which J serves the next step (RADAU5's THET, WORK(3));
      !> negative: a new J after every accepted step
      real(dp) :: jacobian_reuse = jacobian_reuse_rate
      !> After fast Newton an accepted step keeps h when h_new / h is in
      !> [hold_low, hold_high] (RADAU5's QUOT1, QUOT2: WORK(5), WORK(6))
      real(dp) :: hold_low = default_hold_low, hold_high = default_hold_high
      !> Before the first accepted step, RADAU5's rules (its FIRST): an attempt the
      !> error test rejects is retried with h/10, one whose Newton failed with
      !> RADAU5's factor; off (the default), the integrator's controller and at most
      !> its failure factor, as the integrator chooses the first h itself
      logical :: first_step_as_radau5 = .false.
      !> The rounding unit below which Newton's increments and contraction estimate are
      !> not taken (RADAU5's UROUND, WORK(1), which the legacy entry sets; default epsilon)
      real(dp) :: rounding = epsilon(1.0_dp)
   contains
      !> One step of Radau IIA and, when asked, the filtered order-3 error estimate
      procedure :: advance => radau_advance
      procedure :: prepare => radau_prepare
      procedure :: restart => radau_restart
      procedure :: stability => radau_stability
      procedure :: step_safety => radau_step_safety
      procedure :: step_hold => radau_step_hold
      procedure :: newton_fraction => radau_newton_fraction
      procedure :: dense_output => radau_dense_output
      procedure :: failure_factor => radau_failure_factor
      procedure :: first_rejection_factor => radau_first_rejection_factor
      procedure :: refine_estimate => radau_refine_estimate
   end type radau5_type

contains

   !> The Radau IIA (order 5) scheme.
   function new_radau5() result(self)
      type(radau5_type) :: self
      call describe_radau5(self)
   end function new_radau5

   !> Give a radau5 object (default-initialised) its self-description and properties in
   !> place: what new_radau5 returns, without the copy of the whole object its result
   !> costs (the legacy entry's local scheme, one per call).
   subroutine describe_radau5(self)
      !> The scheme
      type(radau5_type), intent(inout) :: self
      self%name = "radau5"
      self%order = 5
      self%nonlinear_order = 5
      self%embedded_order = 3
      self%implicit = .true.
      self%predictive_control = .true.
      self%estimates_own_error = .true.
      self%weights_at_start = .true.
      self%takes_newton_guess = .false.
      self%least_newton_iterations = 1
      self%dense_degree = 3
      self%newton_iterations = newton_iteration_limit
      self%refines_estimate = .true.
      self%solves_mass = .true.
      self%update = "Z_i = h sum_j a_ij F(t0 + c_j h, U0 + Z_j), U1 = U0 + Z_3 (Radau IIA, 3 stages)"
      self%newton_matrices = "(gamma/h) I - J (real n x n), ((alpha + i beta)/h) I - J (complex n x n)"
   end subroutine describe_radau5

   !> Stability function of Radau IIA order 5: the (2, 3) Pade approximation of exp(s), s = z + w.
   pure function radau_stability(self, z, w) result(r)
      class(radau5_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r, s
      s = z + w
      r = stability_quotient(1.0_dp + 2.0_dp*s/5.0_dp + s**2/20.0_dp, &
         1.0_dp - 3.0_dp*s/5.0_dp + 3.0_dp*s**2/20.0_dp - s**3/60.0_dp)
   end function radau_stability

   !> RADAU5's safety factor: kappa, lowered after slow Newton to
   !> kappa (1 + 2 nit) / (newt + 2 nit).
   pure real(dp) function radau_step_safety(self, kappa) result(safety)
      class(radau5_type), intent(in) :: self
      real(dp), intent(in) :: kappa
      real(dp) :: twice_limit
      ! in real arithmetic: 2 nit overflows an integer for a limit near huge(0)
      twice_limit = 2.0_dp*real(self%iteration_limit, dp)
      safety = min(kappa, kappa*(1.0_dp + twice_limit)/(real(self%newton_count, dp) + twice_limit))
   end function radau_step_safety

   !> Keep h for factors in [QUOT1, QUOT2] ([1, 1.2] by default) after fast Newton
   !> (theta <= THET: the factorizations then serve the next step), and never grow h
   !> right after a rejection (RADAU5's HNEW = MIN(HNEW, H), then its test of
   !> QUOT1 <= HNEW/H <= QUOT2 when theta <= THET).
   pure subroutine radau_step_hold(self, low, high)
      class(radau5_type), intent(in) :: self
      real(dp), intent(out) :: low, high
      if (self%theta <= self%jacobian_reuse) then
         low = self%hold_low
         high = self%hold_high
      else
         low = 1.0_dp
         high = 1.0_dp
      end if
      if (self%retry) high = huge(1.0_dp)
   end subroutine radau_step_hold

   !> RADAU5's Newton fraction FNEWT = max(10 eps / rtol, min(0.03, sqrt(rtol))).
   pure real(dp) function radau_newton_fraction(self, tolerance, estimated) result(fraction)
      class(radau5_type), intent(in) :: self
      real(dp), intent(in) :: tolerance
      logical, intent(in) :: estimated
      fraction = max(10.0_dp*epsilon(1.0_dp)/tolerance, min(newton_fraction_cap, sqrt(tolerance)))
   end function radau_newton_fraction

   !> The collocation polynomial of the step just taken as its dense output (RADAU5's
   !> CONTR5): u1 + s (c_1 + (s - c2 + 1) (c_2 + (s - c1 + 1) c_3)), s = theta - 1,
   !> i.e. nodes 1, c2, c1 in theta, through U0 and the stages: points 0, c1, c2, 1. None
   !> for another step or a u1 the integrator changed.
   pure subroutine radau_dense_output(self, t, h, u1, nodes, coefficients, points, degree)
      class(radau5_type), intent(in) :: self
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u1(:)
      real(dp), intent(inout) :: nodes(:)
      real(dp), intent(inout) :: coefficients(:, 0:)
      real(dp), intent(inout) :: points(0:)
      integer, intent(out) :: degree
      integer :: i
      degree = 0
      if (.not. (self%have_stages .and. t == self%t_start .and. h == self%h_stages)) return
      !GCC$ unroll 1
      do i = 1, self%n
         if (u1(i) /= self%u_start(i) + self%z(i, 3)) return
      end do
      degree = 3
      nodes(1:3) = [1.0_dp, c2, c1]
      points(0:3) = [0.0_dp, c1, c2, 1.0_dp]
      coefficients(:, 0) = u1
      call collocation_polynomial(self%z(:, 1), self%z(:, 2), self%z(:, 3), coefficients(:, 1), coefficients(:, 2), &
         coefficients(:, 3))
   end subroutine radau_dense_output

   !> RADAU5's factor after a Newton failure; before the first accepted step at most
   !> the integrator's (unless `first_step_as_radau5`): h is then its first guess,
   !> which may be far too large (RADAU5 starts from 1e-6), and RADAU5's halving would
   !> need many retries to get down.
   pure real(dp) function radau_failure_factor(self, shrink) result(factor)
      class(radau5_type), intent(in) :: self
      real(dp), intent(in) :: shrink
      factor = self%retry_factor
      if (.not. (self%have_polynomial .or. self%first_step_as_radau5)) factor = min(factor, shrink)
   end function radau_failure_factor

   !> With `first_step_as_radau5`, RADAU5's h/10 after an error-test rejection before
   !> the first accepted step (H = H*0.1 while FIRST); else none.
   pure real(dp) function radau_first_rejection_factor(self) result(factor)
      class(radau5_type), intent(in) :: self
      factor = merge(first_rejection_shrink, 0.0_dp, self%first_step_as_radau5)
   end function radau_first_rejection_factor

   !> Forget the Jacobian, the factorizations, the polynomial and the previous step
   !> (new problem or integration).
   subroutine radau_restart(self)
      class(radau5_type), intent(inout) :: self
      self%started = .false.
      self%have_polynomial = .false.
      self%have_stages = .false.
      self%jacobian_valid = .false.
      self%jacobian_fresh = .false.
      self%factored = .false.
      self%rhs0_valid = .false.
      self%retry = .false.
      self%theta = abs(self%jacobian_reuse)
      self%faccon = 1.0_dp
      self%faccon_raises = 0
      self%newton_count = 0
      self%mass_loaded = .false.
   end subroutine radau_restart

   !> Work arrays and matrices in the storage the problem declares (and the mass
   !> matrix's, when the problem has one).
   subroutine radau_prepare(self, problem, n, stat)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      character(len=*), parameter :: what = "radau5's stages and work arrays"
      logical :: resized
      integer :: memory
      resized = self%resize(problem, n, stat)
      if (stat%code /= status_ok) return
      if (resized) then
         self%small = self%structure%storage == storage_dense .and. n <= small_lu_max_order
         call new_matrix(self%jac, n, self%structure, stat)
         if (self%small) then
            ! both factorizations are kept here
            self%real_solver = linear_solver_type()
            self%complex_solver = complex_solver_type()
         else
            if (stat%code == status_ok) call new_linear_solver(self%real_solver, n, self%structure, stat)
            if (stat%code == status_ok) call new_complex_solver(self%complex_solver, n, self%structure, stat)
         end if
         if (stat%code /= status_ok) then
            self%n = 0
            return
         end if
         call sized(self%z, n, 3, what, stat)
         call sized(self%w, n, 3, what, stat)
         call sized(self%polynomial, n, 3, what, stat)
         call sized(self%u_start, n, what, stat)
         call sized(self%rhs0, n, what, stat)
         call sized(self%stage, n, what, stat)
         if (stat%code /= status_ok) then
            self%n = 0
            return
         end if
         ! (at most small_lu_max_order: a few kilobytes)
         if (allocated(self%small_matrix)) deallocate (self%small_matrix, self%small_pivots, &
            self%small_inverse_diagonal, self%small_complex, self%small_complex_pivots, &
            self%small_complex_inverse_diagonal)
         if (self%small) allocate (self%small_matrix(n, n), self%small_pivots(n), self%small_inverse_diagonal(n), &
            self%small_complex(n, n), self%small_complex_pivots(n), self%small_complex_inverse_diagonal(n))
         if (allocated(self%mass)) deallocate (self%mass)
         call self%restart()
      end if
      self%with_mass = problem%has_mass
      self%mass_loaded = .false.
      if (self%with_mass .and. .not. allocated(self%mass)) then
         call new_matrix(self%mass, n, self%structure, stat)
         if (stat%code == status_ok) call sized(self%mw, n, 3, what, stat)
         if (stat%code == status_ok .and. self%structure%storage == storage_dense) then
            if (allocated(self%mass_rows)) deallocate (self%mass_rows)
            allocate (self%mass_rows(2, n), stat=memory)
            if (memory /= 0) call out_of_memory(stat, "the rows of the mass matrix", [2, n], integer_bytes)
         end if
         if (stat%code /= status_ok) then
            if (allocated(self%mass)) deallocate (self%mass)
            self%n = 0
            return
         end if
      end if
   end subroutine radau_prepare

   !> M from the problem, in the storage of its Jacobian structure (once per integration),
   !> and for a dense M the rows of each column that hold entries.
   subroutine load_mass(self, problem)
      type(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer :: i, j, first, last
      select type (mass => self%mass)
      type is (dense_matrix_type)
         call problem%mass_matrix(mass%a)
         do j = 1, self%n
            first = 0
            last = 0
            do i = 1, self%n
               if (mass%a(i, j) /= 0.0_dp) then
                  if (first == 0) first = i
                  last = i
               end if
            end do
            ! (an empty column: rows 1 to 0)
            self%mass_rows(:, j) = [max(first, 1), last]
         end do
      type is (band_matrix_type)
         call problem%mass_matrix_band(mass%ab(mass%fill + 1:, :))
      end select
      self%mass_loaded = .true.
      self%factored = .false.
   end subroutine load_mass

   !> y = y + M x for each column of x and y (one, or the three stages'): a dense M over
   !> the rows of each of its columns that hold entries, all columns of x in one pass
   !> (the same sums as the whole columns': the products of its zeros add exact zeros),
   !> a band M over its band, column by column.
   subroutine add_mass_product(self, m, x, y)
      type(radau5_type), intent(in) :: self
      !> Columns of x and y
      integer, intent(in) :: m
      real(dp), intent(in) :: x(self%n, m)
      real(dp), intent(inout) :: y(self%n, m)
      integer :: s
      select type (mass => self%mass)
      type is (dense_matrix_type)
         call add_columns_product(self%n, m, mass%a, self%mass_rows, x, y)
      class default
         do s = 1, m
            call self%mass%multiply_add(1.0_dp, x(:, s), y(:, s))
         end do
      end select
   end subroutine add_mass_product

   !> y = y + A x over rows(1, j) to rows(2, j) of each column j of A, for the m columns of
   !> x and y at once.
   pure subroutine add_columns_product(n, m, a, rows, x, y)
      integer, intent(in) :: n, m, rows(2, n)
      real(dp), intent(in) :: a(n, n), x(n, m)
      real(dp), intent(inout) :: y(n, m)
      integer :: i, j, s
      real(dp) :: entry
      !GCC$ unroll 1
      do j = 1, n
         !GCC$ unroll 1
         do i = rows(1, j), rows(2, j)
            entry = a(i, j)
            !GCC$ unroll 1
            do s = 1, m
               y(i, s) = y(i, s) + x(j, s)*entry
            end do
         end do
      end do
   end subroutine add_columns_product

   subroutine radau_advance(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)

      integer :: n, i

      n = self%n
      self%retry_factor = failure_halving
      self%iteration_limit = newton%max_iterations
      if (self%with_mass .and. .not. self%mass_loaded) call load_mass(self, problem)
      call begin_step()
      if (.not. self%jacobian_valid) then
         ! F(t, u0), which the error estimate needs, first: a difference Jacobian starts from
         ! it (as RADAU5's does from F(X, Y))
         if (present(delta)) call evaluate_rhs0(self, problem, t)
         if (self%rhs0_valid) then
            call evaluate_jac(problem, t, u0, self%jac, self%counters, stat, self%rhs0)
         else
            call evaluate_jac(problem, t, u0, self%jac, self%counters, stat)
         end if
         if (stat%code /= status_ok) then
            u1 = u0
            return
         end if
         self%jacobian_valid = .true.
         self%jacobian_fresh = .true.
         self%factored = .false.
      end if
      if (.not. self%factored .or. h /= self%h_factored) then
         call factor_matrices(self, h, stat)
         if (stat%code /= status_ok) then
            u1 = u0
            return
         end if
      end if

      call solve_stages(self, problem, t, h, newton%tolerance, present(delta), stat)
      if (stat%code /= status_ok) then
         u1 = u0
         return
      end if
      if (n <= scalar_loop_max_order) then
         ! (a scalar loop, as add_vectors')
         !GCC$ unroll 1
         !GCC$ novector
         do i = 1, n
            u1(i) = u0(i) + self%z(i, 3)
         end do
      else
         !GCC$ unroll 1
         do i = 1, n
            u1(i) = u0(i) + self%z(i, 3)
         end do
      end if
      ! the stages in z give the collocation polynomial (dense output, and the next
      ! step's starting values once this one is accepted)
      self%h_stages = h
      self%have_stages = .true.
      if (present(delta)) then
         call estimate_error(self, problem, t, h, stat)
         ! (a loop: the assignment's copy is unrolled, which costs more on a few unknowns;
         ! on a few, a scalar one, as add_vectors': the solve has just stored the estimate)
         if (n <= scalar_loop_max_order) then
            !GCC$ unroll 1
            !GCC$ novector
            do i = 1, n
               delta(i) = self%w(i, 1)
            end do
         else
            !GCC$ unroll 1
            do i = 1, n
               delta(i) = self%w(i, 1)
            end do
         end if
      end if

   contains

      !> A new step (the previous attempt was accepted) or a retry from the same
      !> state; what is kept from the previous attempt follows from it.
      subroutine begin_step()
         logical :: new_step
         new_step = .true.
         if (self%started) new_step = .not. (t == self%t_start .and. all(u0 == self%u_start))
         self%started = .true.
         if (new_step) then
            if (self%have_stages) then
               ! the last successful attempt was accepted: its polynomial predicts this step
               call stage_polynomial(n, self%z, self%polynomial)
               self%h_polynomial = self%h_stages
               self%have_polynomial = .true.
            end if
            self%retry = .false.
            self%t_start = t
            !GCC$ unroll 1
            do i = 1, n
               self%u_start(i) = u0(i)
            end do
            self%rhs0_valid = .false.
            ! the Jacobian of the previous point serves only after fast Newton there
            if (.not. (newton%reuse_matrix .and. self%theta <= self%jacobian_reuse)) self%jacobian_valid = .false.
            self%jacobian_fresh = .false.
         else
            self%retry = .true.
            if (.not. self%jacobian_fresh) self%jacobian_valid = .false.
         end if
         if (.not. newton%reuse_matrix) self%factored = .false.
         self%have_stages = .false.
      end subroutine begin_step

   end subroutine radau_advance

   !> Factor (gamma/h) I - J and ((alpha + i beta)/h) I - J (M instead of I with a mass
   !> matrix); small dense systems form both from J in one pass and factor them here.
   subroutine factor_matrices(self, h, stat)
      type(radau5_type), intent(inout) :: self
      real(dp), intent(in) :: h
      type(status_type), intent(inout) :: stat
      integer :: info
      real(dp) :: fac1
      complex(dp) :: shift

      self%factored = .false.
      fac1 = real_eigenvalue/h
      shift = cmplx(alpha/h, beta/h, dp)
      if (self%small) then
         select type (jac => self%jac)
         type is (dense_matrix_type)
            call shifted_matrices(self%n, jac%a, .not. self%with_mass, fac1, shift, self%small_matrix, &
               self%small_complex)
         end select
         if (self%with_mass) then
            select type (mass => self%mass)
            type is (dense_matrix_type)
               self%small_matrix = self%small_matrix + fac1*mass%a
               self%small_complex = self%small_complex + shift*mass%a
            end select
         end if
         call small_lu_factor(self%n, self%small_matrix, self%small_pivots, info, self%small_inverse_diagonal)
         if (info /= 0) then
            call set_code(stat, status_singular_matrix)
            return
         end if
         call small_lu_factor(self%n, self%small_complex, self%small_complex_pivots, info, &
            self%small_complex_inverse_diagonal)
         if (info /= 0) call set_code(stat, status_singular_matrix)
         ! an overflow in the elimination (see linear_solver_type%factor)
         if (.not. finite_diagonal(self%n, self%small_matrix)) call set_code(stat, status_nonfinite)
      else
         if (self%with_mass) then
            call self%real_solver%matrix%set_scaled(-1.0_dp, self%jac, stat)
            call self%real_solver%matrix%add_scaled(fac1, self%mass, stat)
         else
            call self%real_solver%matrix%set_scaled(-1.0_dp, self%jac, stat, shift=fac1)
         end if
         if (stat%code == status_ok) call self%real_solver%factor(stat)
         if (stat%code /= status_ok) return
         if (self%with_mass) then
            call self%complex_solver%assemble(shift, self%jac, stat, self%mass)
         else
            call self%complex_solver%assemble(shift, self%jac, stat)
         end if
         if (stat%code == status_ok) call self%complex_solver%factor(stat)
      end if
      self%counters%lu_factorizations = self%counters%lu_factorizations + 1
      if (stat%code /= status_ok) return
      self%factored = .true.
      self%h_factored = h
   end subroutine factor_matrices

   !> -J and -J + 0 i, plus fac1 I and shift I when `shifted` (without a mass matrix):
   !> the two Newton matrices of a small dense system before their factorization. The
   !> arrays are explicit-shape: through the scheme's components every entry reloaded
   !> their descriptors, which cost more than the copy on a few unknowns.
   pure subroutine shifted_matrices(n, jac, shifted, fac1, shift, real_matrix, complex_matrix)
      !> Order
      integer, intent(in) :: n
      !> J
      real(dp), intent(in) :: jac(n, n)
      !> Whether to add the shifts (the mass matrix is added otherwise, afterwards)
      logical, intent(in) :: shifted
      !> gamma/h, the real matrix's shift
      real(dp), intent(in) :: fac1
      !> (alpha + i beta)/h, the complex matrix's shift
      complex(dp), intent(in) :: shift
      !> fac1 I - J
      real(dp), intent(out) :: real_matrix(n, n)
      !> shift I - J
      complex(dp), intent(out) :: complex_matrix(n, n)
      integer :: i, j
      real(dp) :: entry
      !GCC$ unroll 1
      do j = 1, n
         !GCC$ unroll 1
         do i = 1, n
            entry = -jac(i, j)
            real_matrix(i, j) = entry
            complex_matrix(i, j) = cmplx(entry, 0.0_dp, dp)
         end do
         if (shifted) then
            real_matrix(j, j) = real_matrix(j, j) + fac1
            complex_matrix(j, j) = complex_matrix(j, j) + shift
         end if
      end do
   end subroutine shifted_matrices

   !> c = a + b (explicit-shape, as newton_right_hand_sides).
   pure subroutine add_vectors(n, a, b, c)
      !> Length
      integer, intent(in) :: n
      !> The terms
      real(dp), intent(in) :: a(n), b(n)
      !> The sum
      real(dp), intent(out) :: c(n)
      integer :: i
      if (n <= scalar_loop_max_order) then
         ! a scalar loop on one or two unknowns: a vector load of b (the stage increments
         ! Newton has just stored one by one) would wait for those stores to be
         ! complete, as no store forwards into a load that spans two
         !GCC$ unroll 1
         !GCC$ novector
         do i = 1, n
            c(i) = a(i) + b(i)
         end do
      else
         !GCC$ unroll 1
         do i = 1, n
            c(i) = a(i) + b(i)
         end do
      end if
   end subroutine add_vectors

   !> Newton's start: Z at the new stages from the last step's collocation polynomial
   !> (the new step h is ratio times the step it was made on), and W = T^(-1) Z
   !> (explicit-shape, as newton_right_hand_sides).
   pure subroutine extrapolated_stages(n, ratio, polynomial, z, w)
      !> Unknowns
      integer, intent(in) :: n
      !> h over the step of the polynomial
      real(dp), intent(in) :: ratio
      !> The polynomial's coefficient columns
      real(dp), intent(in) :: polynomial(n, 3)
      !> The stage increments and the transformed ones
      real(dp), intent(out) :: z(n, 3), w(n, 3)
      real(dp) :: c1q, c2q, c3q, ak1, ak2, ak3, z1, z2, z3
      integer :: i
      c3q = ratio
      c1q = c1*c3q
      c2q = c2*c3q
      !GCC$ unroll 1
      do i = 1, n
         ak1 = polynomial(i, 1)
         ak2 = polynomial(i, 2)
         ak3 = polynomial(i, 3)
         z1 = c1q*(ak1 + (c1q - c2m1)*(ak2 + (c1q - c1m1)*ak3))
         z2 = c2q*(ak1 + (c2q - c2m1)*(ak2 + (c2q - c1m1)*ak3))
         z3 = c3q*(ak1 + (c3q - c2m1)*(ak2 + (c3q - c1m1)*ak3))
         z(i, 1) = z1
         z(i, 2) = z2
         z(i, 3) = z3
         w(i, 1) = ti11*z1 + ti12*z2 + ti13*z3
         w(i, 2) = ti21*z1 + ti22*z2 + ti23*z3
         w(i, 3) = ti31*z1 + ti32*z2 + ti33*z3
      end do
   end subroutine extrapolated_stages

   !> The transformed Newton right-hand sides in place of the stage values F:
   !> T^(-1) F minus the block diag(gamma/h, [[alpha/h, -beta/h], [beta/h, alpha/h]])
   !> times W (or M W, wm), and the sum of |F| (finite unless some F is NaN or Inf, or
   !> all are so large that it overflows: one test instead of one per value).
   !> Explicit-shape, so that the compiler knows the arrays apart (through the pointers
   !> onto the scheme's arrays it had to assume they might overlap).
   pure subroutine newton_right_hand_sides(n, fac1, alphn, betan, wm, r, magnitude)
      !> Unknowns
      integer, intent(in) :: n
      !> gamma/h, alpha/h, beta/h
      real(dp), intent(in) :: fac1, alphn, betan
      !> W, or M W with a mass matrix
      real(dp), intent(in) :: wm(n, 3)
      !> F at the three stages on entry, the right-hand sides on exit
      real(dp), intent(inout) :: r(n, 3)
      !> Sum of |F|
      real(dp), intent(out) :: magnitude
      real(dp) :: f1, f2, f3
      integer :: i
      magnitude = 0.0_dp
      !GCC$ unroll 1
      do i = 1, n
         f1 = r(i, 1)
         f2 = r(i, 2)
         f3 = r(i, 3)
         magnitude = magnitude + (abs(f1) + abs(f2) + abs(f3))
         r(i, 1) = ti11*f1 + ti12*f2 + ti13*f3 - fac1*wm(i, 1)
         r(i, 2) = ti21*f1 + ti22*f2 + ti23*f3 - alphn*wm(i, 2) + betan*wm(i, 3)
         r(i, 3) = ti31*f1 + ti32*f2 + ti33*f3 - alphn*wm(i, 3) - betan*wm(i, 2)
      end do
   end subroutine newton_right_hand_sides

   !> The Newton update: W = W + the increments (in z on entry), z = T W on exit, and
   !> the sum of the increments' squares in the tolerances (explicit-shape, as
   !> newton_right_hand_sides).
   pure subroutine newton_update(n, tolerance, w, z, sum_squares)
      !> Unknowns
      integer, intent(in) :: n
      !> Absolute accuracy asked of each component of the stage increments
      real(dp), intent(in) :: tolerance(n)
      !> The transformed stage values W
      real(dp), intent(inout) :: w(n, 3)
      !> The increments of W on entry, the stage increments Z = T W on exit
      real(dp), intent(inout) :: z(n, 3)
      !> Sum over the components and stages of (increment / tolerance)^2
      real(dp), intent(out) :: sum_squares
      real(dp) :: inverse, z1, z2, z3, f1, f2, f3
      integer :: i
      sum_squares = 0.0_dp
      !GCC$ unroll 1
      do i = 1, n
         inverse = 1.0_dp/tolerance(i)
         z1 = z(i, 1)
         z2 = z(i, 2)
         z3 = z(i, 3)
         sum_squares = sum_squares + (z1*inverse)**2 + (z2*inverse)**2 + (z3*inverse)**2
         f1 = w(i, 1) + z1
         f2 = w(i, 2) + z2
         f3 = w(i, 3) + z3
         w(i, 1) = f1
         w(i, 2) = f2
         w(i, 3) = f3
         z(i, 1) = t11*f1 + t12*f2 + t13*f3
         z(i, 2) = t21*f1 + t22*f2 + t23*f3
         z(i, 3) = t31*f1 + f2
      end do
   end subroutine newton_update

   !> x**m for m >= 0 by repeated squaring: the products libgcc's __powidf2 forms for
   !> x**m, in the same order (the same value bit for bit), without the call into the
   !> shared library at every Newton iteration.
   pure real(dp) function power_by_squaring(x, m) result(power)
      !> Base
      real(dp), intent(in) :: x
      !> Exponent, at least 0
      integer, intent(in) :: m
      real(dp) :: square
      integer :: k
      k = m
      square = x
      power = 1.0_dp
      if (iand(k, 1) == 1) power = x
      do
         k = ishft(k, -1)
         if (k == 0) exit
         square = square*square
         if (iand(k, 1) == 1) power = power*square
      end do
   end function power_by_squaring

   !> x = ((gamma/h) I - J)^(-1) x with the kept factors.
   subroutine solve_real(self, x, stat)
      type(radau5_type), intent(inout) :: self
      real(dp), contiguous, intent(inout) :: x(:)
      type(status_type), intent(inout) :: stat
      if (self%small) then
         call small_lu_solve_reciprocal(self%n, self%small_matrix, self%small_pivots, x, self%small_inverse_diagonal)
      else
         call self%real_solver%solve(x, stat)
      end if
   end subroutine solve_real

   !> Simplified Newton on the transformed stage system from the extrapolated
   !> collocation polynomial, about u0 = self%u_start; `tolerance` is the absolute
   !> accuracy asked of each component of the stage increments. The loops over
   !> the components are fused: at n = 2 their overhead is most of the work.
   subroutine solve_stages(self, problem, t, h, tolerance, adaptive, stat)
      type(radau5_type), intent(inout), target :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), contiguous, intent(in) :: tolerance(:)
      !> Whether the caller can retry with a smaller step (it asked for the error
      !> estimate): RADAU5's iteration limit and early failure apply. Otherwise
      !> (fixed steps) Newton iterates while it contracts, up to fixed_step_iterations.
      logical, intent(in) :: adaptive
      type(status_type), intent(inout) :: stat

      integer :: n, i, newt, limit
      real(dp) :: fac1, alphn, betan
      real(dp) :: dyno, dynold, thq, thqold, dyth, magnitude, stage_time(3)
      real(dp), contiguous, pointer :: u0(:), z(:, :), w(:, :), r(:, :), stage(:), wm(:, :)

      n = self%n
      u0 => self%u_start
      z => self%z
      w => self%w
      ! F at the stages, the right-hand sides and the increments go where Z was: Z is
      ! T W again at the end of each iteration
      r => self%z
      stage => self%stage
      ! W in the Newton right-hand sides, or M W with a mass matrix
      wm => self%w
      if (self%with_mass) wm => self%mw
      if (self%have_polynomial .and. .not. self%zero_start) then
         call extrapolated_stages(n, h/self%h_polynomial, self%polynomial, z, w)
      else
         !GCC$ unroll 1
         do i = 1, n
            z(i, 1) = 0.0_dp
            z(i, 2) = 0.0_dp
            z(i, 3) = 0.0_dp
            w(i, 1) = 0.0_dp
            w(i, 2) = 0.0_dp
            w(i, 3) = 0.0_dp
         end do
      end if

      fac1 = real_eigenvalue/h
      alphn = alpha/h
      betan = beta/h
      stage_time = [t + c1*h, t + c2*h, t + h]
      self%faccon_raises = self%faccon_raises + 1
      self%theta = abs(self%jacobian_reuse)
      dynold = 1.0_dp
      thqold = 1.0_dp
      newt = 0
      limit = merge(self%iteration_limit, fixed_step_iterations, adaptive)
      do
         if (newt >= limit) then
            call fail(status_newton_not_converged)
            return
         end if
         ! F = f + g at the three stages (the problem's rhs, called directly), each into
         ! its stage's column of z once the stage state is formed (in `stage`, formed
         ! anew for each: the problem may overwrite it); written out, as radau5.f's: a
         ! loop of three trips spilled its registers around each call
         call add_vectors(n, u0, z(:, 1), stage)
         call problem%rhs_scratch(n, stage_time(1), stage, r(:, 1))
         call add_vectors(n, u0, z(:, 2), stage)
         call problem%rhs_scratch(n, stage_time(2), stage, r(:, 2))
         call add_vectors(n, u0, z(:, 3), stage)
         call problem%rhs_scratch(n, stage_time(3), stage, r(:, 3))
         self%counters%f_evaluations = self%counters%f_evaluations + 3
         self%counters%g_evaluations = self%counters%g_evaluations + 3
         if (problem%evaluation_rejected()) then
            call fail(status_evaluation_failed)
            return
         end if
         if (self%with_mass) then
            self%mw = 0.0_dp
            call add_mass_product(self, 3, w, self%mw)
         end if
         call newton_right_hand_sides(n, fac1, alphn, betan, wm, r, magnitude)
         if (.not. ieee_is_finite(magnitude)) then
            call fail(status_nonfinite)
            return
         end if
         if (self%small) then
            call small_lu_solve_pair(n, self%small_matrix, self%small_pivots, self%small_inverse_diagonal, &
               self%small_complex, self%small_complex_pivots, self%small_complex_inverse_diagonal, &
               r(:, 1), r(:, 2), r(:, 3))
         else
            call self%complex_solver%solve_with_real(self%real_solver, r(:, 1), r(:, 2), r(:, 3), stat)
         end if
         if (stat%code /= status_ok) return
         newt = newt + 1
         self%counters%newton_iterations = self%counters%newton_iterations + 1
         self%counters%linear_solves = self%counters%linear_solves + 1

         ! the size of the increments, and the new iterate (unused should the tests below fail)
         call newton_update(n, tolerance, w, z, dyno)
         dyno = sqrt(dyno/real(3*n, dp))
         if (.not. (dyno <= huge(1.0_dp))) then
            call fail(status_newton_diverged)
            return
         end if
         if (newt > 1 .and. newt < limit) then
            thq = dyno/dynold
            if (newt == 2) then
               self%theta = thq
            else
               self%theta = sqrt(thq*thqold)
            end if
            thqold = thq
            if (self%theta < divergence_rate) then
               self%faccon = self%theta/(1.0_dp - self%theta)
               self%faccon_raises = 0
               if (adaptive) then
                  ! the error left after the remaining iterations at this rate
                  dyth = self%faccon*dyno*power_by_squaring(self%theta, limit - 1 - newt)
                  if (dyth >= 1.0_dp) then
                     self%retry_factor = failure_safety*min(failure_high, dyth)** &
                        (-1.0_dp/(3.0_dp + real(limit - newt, dp)))
                     call fail(status_newton_not_converged)
                     return
                  end if
               end if
            else
               call fail(status_newton_diverged)
               return
            end if
         end if
         dynold = max(dyno, self%rounding)
         if (converged()) exit
      end do
      self%newton_count = newt
   contains
      !> A failed solve, by its code alone (nothing is allocated)
      subroutine fail(code)
         integer, intent(in) :: code
         self%newton_count = newt
         call set_code(stat, code)
      end subroutine fail

      !> faccon dyno <= 1 (RADAU5's test). With powers of faccon pending, faccon^p
      !> (0 < p < 1) lies between faccon and 1, which mostly decides the test
      !> without the power.
      logical function converged()
         if (self%faccon_raises > 0) then
            if (max(self%faccon, 1.0_dp)*dyno <= 1.0_dp) then
               converged = .true.
               return
            else if (min(self%faccon, 1.0_dp)*dyno > 1.0_dp) then
               converged = .false.
               return
            end if
            self%faccon = max(self%faccon, self%rounding)**(0.8_dp**self%faccon_raises)
            self%faccon_raises = 0
         end if
         converged = self%faccon*dyno <= 1.0_dp
      end function converged
   end subroutine solve_stages

   !> The collocation polynomial through the stage increments z1, z2, z3 at c1, c2, 1
   !> (and 0 at 0), in RADAU5's divided-difference form a1, a2, a3 (CONT(N+1:4N) of
   !> radau5.f); elemental, so that each use is one loop over the components.
   elemental subroutine collocation_polynomial(z1, z2, z3, a1, a2, a3)
      real(dp), intent(in) :: z1, z2, z3
      real(dp), intent(out) :: a1, a2, a3
      real(dp) :: ak, acont3
      a1 = (z2 - z3)*(1.0_dp/c2m1)
      ak = (z1 - z2)*(1.0_dp/c1mc2)
      acont3 = (ak - z1*(1.0_dp/c1))*(1.0_dp/c2)
      a2 = (ak - a1)*(1.0_dp/c1m1)
      a3 = a2 - acont3
   end subroutine collocation_polynomial

   !> The collocation polynomial of the stage increments z into polynomial (explicit-shape,
   !> as newton_right_hand_sides: on a few unknowns the elemental call's unrolled loop over
   !> array sections of the scheme's components cost more than its arithmetic).
   pure subroutine stage_polynomial(n, z, polynomial)
      !> Unknowns
      integer, intent(in) :: n
      !> The stage increments
      real(dp), intent(in) :: z(n, 3)
      !> The polynomial's coefficient columns
      real(dp), intent(out) :: polynomial(n, 3)
      integer :: i
      !GCC$ unroll 1
      do i = 1, n
         call collocation_polynomial(z(i, 1), z(i, 2), z(i, 3), polynomial(i, 1), polynomial(i, 2), polynomial(i, 3))
      end do
   end subroutine stage_polynomial

   !> delta = ((gamma/h) I - J)^(-1) [F(t0, U0) + (d1 Z1 + d2 Z2 + d3 Z3)/h] (M times the
   !> stage part with a mass matrix; the stage part kept for a filtered estimate).
   subroutine estimate_error(self, problem, t, h, stat)
      type(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      type(status_type), intent(inout) :: stat
      integer :: i
      real(dp) :: hee1, hee2, hee3

      call evaluate_rhs0(self, problem, t)
      hee1 = dd1/h
      hee2 = dd2/h
      hee3 = dd3/h
      ! W is done with once the stages have converged: the estimate and its stage part
      ! go into its first two columns
      associate (estimate => self%w(:, 1), stage_part => self%w(:, 2))
         if (self%with_mass) then
            !GCC$ unroll 1
            do i = 1, self%n
               self%stage(i) = hee1*self%z(i, 1) + hee2*self%z(i, 2) + hee3*self%z(i, 3)
               stage_part(i) = 0.0_dp
            end do
            call add_mass_product(self, 1, self%stage, stage_part)
            call add_vectors(self%n, stage_part, self%rhs0, estimate)
         else
            call estimate_right_side(self%n, hee1, hee2, hee3, self%z, self%rhs0, stage_part, estimate)
         end if
         call solve_real(self, estimate, stat)
      end associate
      self%counters%linear_solves = self%counters%linear_solves + 1
   end subroutine estimate_error

   !> The error estimate's right-hand side without a mass matrix: its stage part
   !> hee1 Z1 + hee2 Z2 + hee3 Z3 and that plus F(t0, U0) (explicit-shape, as
   !> newton_right_hand_sides).
   pure subroutine estimate_right_side(n, hee1, hee2, hee3, z, rhs0, stage_part, estimate)
      !> Unknowns
      integer, intent(in) :: n
      !> The weights d_i/h of the stage increments
      real(dp), intent(in) :: hee1, hee2, hee3
      !> The stage increments
      real(dp), intent(in) :: z(n, 3)
      !> F(t0, U0)
      real(dp), intent(in) :: rhs0(n)
      !> The stage part, and the right-hand side
      real(dp), intent(out) :: stage_part(n), estimate(n)
      real(dp) :: part
      integer :: i
      if (n <= scalar_loop_max_order) then
         ! a scalar loop on one or two unknowns, as add_vectors': Newton has just stored z
         !GCC$ unroll 1
         !GCC$ novector
         do i = 1, n
            part = hee1*z(i, 1) + hee2*z(i, 2) + hee3*z(i, 3)
            stage_part(i) = part
            estimate(i) = part + rhs0(i)
         end do
      else
         !GCC$ unroll 1
         do i = 1, n
            part = hee1*z(i, 1) + hee2*z(i, 2) + hee3*z(i, 3)
            stage_part(i) = part
            estimate(i) = part + rhs0(i)
         end do
      end if
   end subroutine estimate_right_side

   !> F(t, U0) at the start of the step into rhs0, unless it is there already (kept
   !> only when the problem accepted the evaluation).
   subroutine evaluate_rhs0(self, problem, t)
      type(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t
      if (self%rhs0_valid) return
      ! (explicit-shape, as the stages: the legacy entry's FCN without another layer)
      call problem%rhs_values(self%n, t, self%u_start, self%rhs0)
      self%counters%f_evaluations = self%counters%f_evaluations + 1
      self%counters%g_evaluations = self%counters%g_evaluations + 1
      self%rhs0_valid = .not. problem%evaluation_rejected()
   end subroutine evaluate_rhs0

   !> RADAU5's second estimate when the first fails the error test at the first step or
   !> on a retry: delta = ((gamma/h) I - J)^(-1) [F(t0, U0 + delta) + (d1 Z1 + d2 Z2 +
   !> d3 Z3)/h], which damps what the first one lets through in stiff directions. None
   !> for an attempt that follows an accepted step (RADAU5's neither).
   subroutine radau_refine_estimate(self, problem, t, h, delta, refined, stat)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), contiguous, intent(inout) :: delta(:)
      logical, intent(out) :: refined
      type(status_type), intent(inout) :: stat
      integer :: i
      refined = .false.
      if (.not. (self%have_stages .and. t == self%t_start .and. h == self%h_stages)) return
      if (self%have_polynomial .and. .not. self%retry) return
      refined = .true.
      call add_vectors(self%n, self%u_start, delta, self%stage)
      ! the stage part of the first estimate is still in w(:, 2)
      associate (estimate => self%w(:, 1), stage_part => self%w(:, 2))
         ! (self%stage is scratch here)
         call problem%rhs_scratch(self%n, t, self%stage, estimate)
         self%counters%f_evaluations = self%counters%f_evaluations + 1
         self%counters%g_evaluations = self%counters%g_evaluations + 1
         !GCC$ unroll 1
         do i = 1, self%n
            estimate(i) = estimate(i) + stage_part(i)
         end do
         call solve_real(self, estimate, stat)
         self%counters%linear_solves = self%counters%linear_solves + 1
         delta = estimate
      end associate
   end subroutine radau_refine_estimate

end module taylorode_schemes_radau5
