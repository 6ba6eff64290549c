!> Orders of convergence, stability functions, L-stability and argument checks of
!> every one-step scheme.
module test_schemes
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode_base_strings, only: format_integer, format_real
   use test_support, only: rk4_reference, stat_message
   use taylorode_testset, only: linear_test_type, van_der_pol_type, new_van_der_pol, brusselator_type, &
      new_brusselator, vdp_split_paper, vdp_split_stiff
   use taylorode_analysis, only: stability_function
   use taylorode, only: dp, ode_problem, scheme_type, status_type, new_scheme, scheme_names, integrate, &
      integrator_options_type, integration_stats_type, &
      scheme_count, integrate_fixed, status_ok, status_size_mismatch, status_invalid_argument, status_nonfinite, &
      status_unknown_scheme, status_singular_matrix, status_newton_diverged, &
      status_newton_not_converged
   use taylorode_newton_solver, only: newton_settings_type
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: collect_schemes

   !> Largest allowed gap between observed and theoretical order. The observed order
   !> is taken between N = 160 and 320 steps (8 and 16 for radau5), where the next
   !> error term (one order higher, relative size ~ h) moves it by a few hundredths.
   real(dp), parameter :: order_tolerance = 0.1_dp
   !> One step on the linear test equals R(z, w) up to a few roundoffs. A step
   !> computes with numbers of the size of u0 (= 1 here), so where |R| << 1 comes
   !> from cancellation (IMEX-RK with |w| = 1e4: |R| ~ 1e-4) the roundoff is
   !> relative to max(|R|, |u0|): the bound is 1e-12 * max(|R|, 1).
   real(dp), parameter :: stability_tolerance = 1.0e-12_dp

   !> u' = cos(u) - 2 u^3 - u with f = cos(u) (non-stiff) and g = -2 u^3 - u (stiff):
   !> both parts nonlinear, so the paper's SI-T-2 shows its first order here.
   type, extends(ode_problem) :: cubic_problem
   contains
      procedure :: f => cubic_f
      procedure :: g => cubic_g
      procedure :: jac_f => cubic_jac_f
      procedure :: jac_g => cubic_jac_g
   end type cubic_problem

   !> The cubic problem forced in time, with a Jacobian that depends on t too:
   !> f = cos u + sin 3t, g = -(2 + sin t) u^3 - u + 2 cos 5t
   type, extends(ode_problem) :: forced_cubic_problem
   contains
      procedure :: f => forced_cubic_f
      procedure :: g => forced_cubic_g
      procedure :: jac_f => cubic_jac_f_any
      procedure :: jac_g => forced_cubic_jac_g
   end type forced_cubic_problem

   !> The forced cubic problem made autonomous: (u, tau) with tau' = 1 (in f)
   type, extends(ode_problem) :: augmented_cubic_problem
   contains
      procedure :: f => augmented_cubic_f
      procedure :: g => augmented_cubic_g
      procedure :: jac_f => augmented_cubic_jac_f
      procedure :: jac_g => augmented_cubic_jac_g
   end type augmented_cubic_problem

   !> A stiff part whose Newton iteration runs away: g = -k atan(u), k large
   type, extends(ode_problem) :: runaway_problem
   contains
      procedure :: f => runaway_f
      procedure :: g => runaway_g
      procedure :: jac_f => runaway_jac_f
      procedure :: jac_g => runaway_jac_g
   end type runaway_problem

   !> Steps of the order measurements: low-order schemes, and radau5 (whose errors
   !> reach roundoff beyond 32 steps)
   integer, parameter :: order_steps(2) = [160, 320], order_steps_radau(2) = [8, 16]
   real(dp), parameter :: runaway_k = 1.0e6_dp

contains

   !> Collect all exported unit tests
   subroutine collect_schemes(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("order-nonlinear-scalar", test_order_scalar), &
         new_unittest("order-van-der-pol", test_order_van_der_pol), &
         new_unittest("order-paper-si-t-2-linear", test_order_paper_linear), &
         new_unittest("order-non-autonomous", test_order_non_autonomous), &
         new_unittest("stability-function", test_stability_function), &
         new_unittest("l-stability", test_l_stability), &
         new_unittest("embedded-difference", test_embedded_difference), &
         new_unittest("step-error-estimate", test_step_error), &
         new_unittest("unknown-scheme", test_unknown_scheme), &
         new_unittest("bad-step-input", test_bad_step_input), &
         new_unittest("singular-newton-matrix", test_singular_newton), &
         new_unittest("newton-divergence", test_newton_divergence), &
         new_unittest("newton-first-increment-of-a-new-matrix", test_newton_first_increment), &
         new_unittest("i-t-2-van-der-pol-mu-1e6", test_it2_van_der_pol_mu_1e6), &
         new_unittest("si-t-2-van-der-pol-mu-1e6", test_sit2_van_der_pol_mu_1e6) &
         ]
   end subroutine collect_schemes

   !> Observed order log2(e_N / e_2N) of a scheme with fixed steps.
   subroutine observed_order(error, name, problem, u0, t_end, reference, order, expected)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), intent(in) :: name
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u0(:), t_end, reference(:)
      real(dp), intent(out) :: order
      !> Order the scheme declares for nonlinear problems
      real(dp), intent(out), optional :: expected
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: u(size(u0)), errors(size(order_steps))
      integer :: i, steps(size(order_steps))

      call new_scheme(name, scheme, stat)
      call check(error, stat%code, status_ok, name//": "//stat_message(stat))
      if (allocated(error)) return
      if (present(expected)) expected = real(scheme%nonlinear_order, dp)
      steps = order_steps
      if (name == "radau5") steps = order_steps_radau
      do i = 1, size(steps)
         u = u0
         call integrate_fixed(problem, scheme, 0.0_dp, t_end, steps(i), u, stat)
         call check(error, stat%code, status_ok, name//": "//stat_message(stat))
         if (allocated(error)) return
         errors(i) = maxval(abs(u - reference))
      end do
      order = log(errors(1)/errors(2))/log(2.0_dp)
   end subroutine observed_order

   subroutine test_order_scalar(error)
      type(error_type), allocatable, intent(out) :: error
      type(cubic_problem) :: problem
      real(dp) :: reference(1), order, expected
      integer :: i

      reference = rk4_reference(problem, [1.0_dp], 1.0_dp)
      do i = 1, scheme_count
         call observed_order(error, trim(scheme_names(i)), problem, [1.0_dp], 1.0_dp, reference, order, expected)
         if (allocated(error)) return
         call check(error, order, expected, &
            "order of "//trim(scheme_names(i))//" on u' = cos u - 2u^3 - u", thr=order_tolerance)
         if (allocated(error)) return
      end do
   end subroutine test_order_scalar

   subroutine test_order_van_der_pol(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      real(dp) :: reference(2), order, expected
      integer :: i

      problem = new_van_der_pol(1.0_dp)
      reference = rk4_reference(problem, [2.0_dp, 0.0_dp], 1.0_dp)
      do i = 1, scheme_count
         call observed_order(error, trim(scheme_names(i)), problem, [2.0_dp, 0.0_dp], 1.0_dp, &
            reference, order, expected)
         if (allocated(error)) return
         call check(error, order, expected, &
            "order of "//trim(scheme_names(i))//" on Van der Pol mu = 1", thr=order_tolerance)
         if (allocated(error)) return
      end do
   end subroutine test_order_van_der_pol

   !> Every scheme keeps its order on a problem that depends on t (f, g and J_g do):
   !> the second-order Taylor schemes advance it as they advance the autonomous system
   !> (t, U) with t' = 1 (to 1e-9 at 160 steps: what the differences in t leave, h^4
   !> 1e-5 F_ttt per step), with dF/dt by differences in t. Declared autonomous
   !> (wrongly), ex-t-2, si-t-2 and i-t-2 fall to first order: what dF/dt is for. Over
   !> [0, 0.5] (over [0, 1] i-t-2's next error term still moves its observed order by 0.1).
   subroutine test_order_non_autonomous(error)
      type(error_type), allocatable, intent(out) :: error
      type(forced_cubic_problem) :: problem
      type(augmented_cubic_problem) :: augmented
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp), parameter :: t_end = 0.5_dp
      real(dp) :: reference(1), order, expected, u(1), v(2)
      integer :: i
      character(len=*), parameter :: second_order(4) = [character(len=12) :: "ex-t-2", "si-t-2", "i-t-2", &
         "si-t-2-paper"]

      reference = rk4_reference(problem, [1.0_dp], t_end)
      do i = 1, scheme_count
         call observed_order(error, trim(scheme_names(i)), problem, [1.0_dp], t_end, reference, order, expected)
         if (allocated(error)) return
         call check(error, order, expected, "order of "//trim(scheme_names(i))// &
            " on u' = cos u + sin 3t - (2 + sin t) u^3 - u + 2 cos 5t: "//format_real(order, 3), thr=order_tolerance)
         if (allocated(error)) return
      end do
      augmented%autonomous = .true.
      do i = 1, size(second_order)
         call new_scheme(trim(second_order(i)), scheme, stat)
         u = [1.0_dp]
         call integrate_fixed(problem, scheme, 0.0_dp, t_end, order_steps(1), u, stat)
         v = [1.0_dp, 0.0_dp]
         call integrate_fixed(augmented, scheme, 0.0_dp, t_end, order_steps(1), v, stat)
         call check(error, abs(u(1) - v(1)) < 1.0e-9_dp, trim(second_order(i))//" on (t, U): "// &
            format_real(u(1), 12)//" against "//format_real(v(1), 12))
         if (allocated(error)) return
      end do
      problem%autonomous = .true.
      do i = 1, 3
         call observed_order(error, trim(second_order(i)), problem, [1.0_dp], t_end, reference, order)
         if (allocated(error)) return
         call check(error, order, 1.0_dp, trim(second_order(i))//" without dF/dt", thr=order_tolerance)
         if (allocated(error)) return
      end do
   end subroutine test_order_non_autonomous

   !> The paper's SI-T-2 is second order on the linear test equation (its local
   !> error term J_g f - J_f g vanishes when f and g commute).
   subroutine test_order_paper_linear(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_test_type) :: problem
      real(dp) :: reference(2), order
      complex(dp) :: exact

      problem%lambda = (-1.0_dp, 2.0_dp)
      problem%nu = (-10.0_dp, 0.0_dp)
      exact = exp(problem%lambda + problem%nu)
      reference = [exact%re, exact%im]
      call observed_order(error, "si-t-2-paper", problem, [1.0_dp, 0.0_dp], 1.0_dp, reference, order)
      if (allocated(error)) return
      call check(error, order, 2.0_dp, "order of si-t-2-paper on the linear test", thr=order_tolerance)
   end subroutine test_order_paper_linear

   !> One real step from (1, 0) with h = 1 lands on (Re R(z, w), Im R(z, w)).
   subroutine test_stability_function(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_test_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      complex(dp), parameter :: z(24) = [ &
         (-1.0_dp, 0.0_dp), (-0.5_dp, 0.0_dp), (-2.0_dp, 0.0_dp), (0.3_dp, 0.0_dp), &
         (-0.1_dp, 0.0_dp), (-1.5_dp, 0.0_dp), (-0.7_dp, 0.0_dp), (-3.0_dp, 0.0_dp), &
         (-0.5_dp, 0.5_dp), (-1.0_dp, 1.0_dp), (0.0_dp, 1.0_dp), (-0.2_dp, -0.8_dp), &
         (-2.0_dp, 1.5_dp), (0.1_dp, 0.3_dp), (-0.4_dp, 2.0_dp), (-1.2_dp, -0.6_dp), &
         (-0.3_dp, 0.0_dp), (-0.8_dp, 0.2_dp), (-1.0_dp, 0.0_dp), (-0.05_dp, 0.05_dp), &
         (-0.6_dp, -1.1_dp), (-2.5_dp, 0.0_dp), (0.0_dp, -0.4_dp), (-1.7_dp, 0.9_dp)]
      complex(dp), parameter :: w(24) = [ &
         (-1.0_dp, 0.0_dp), (-10.0_dp, 0.0_dp), (-0.5_dp, 0.0_dp), (-100.0_dp, 0.0_dp), &
         (-1.0e3_dp, 0.0_dp), (-2.0_dp, 0.0_dp), (-0.1_dp, 0.0_dp), (-50.0_dp, 0.0_dp), &
         (-1.0_dp, 0.0_dp), (-5.0_dp, 0.0_dp), (-2.0_dp, 3.0_dp), (-20.0_dp, -10.0_dp), &
         (-1.0_dp, 1.0_dp), (-0.2_dp, 0.7_dp), (-8.0_dp, 8.0_dp), (-3.0_dp, -4.0_dp), &
         (0.0_dp, 2.0_dp), (-1.0e4_dp, 1.0e3_dp), (-0.3_dp, -0.3_dp), (-1.0e6_dp, 0.0_dp), &
         (-7.0_dp, 1.0_dp), (-0.9_dp, 0.0_dp), (-1.5_dp, -0.5_dp), (-12.0_dp, 30.0_dp)]
      real(dp) :: u1(2)
      complex(dp) :: r
      integer :: i, k

      do k = 1, scheme_count
         call new_scheme(trim(scheme_names(k)), scheme, stat)
         do i = 1, size(z)
            problem%lambda = z(i)
            problem%nu = w(i)
            call scheme%take_step(problem, 0.0_dp, 1.0_dp, [1.0_dp, 0.0_dp], u1, stat)
            call check(error, stat%code, status_ok, trim(scheme_names(k))//": "//stat_message(stat))
            if (allocated(error)) return
            r = stability_function(trim(scheme_names(k)), z(i), w(i))
            call check(error, abs(cmplx(u1(1), u1(2), dp) - r) <= stability_tolerance*max(abs(r), 1.0_dp), &
               trim(scheme_names(k))//": one step differs from R(z, w) at pair "//format_integer(i))
            if (allocated(error)) return
         end do
      end do
   end subroutine test_stability_function

   !> w = -1e12: the schemes that declare themselves implicit (semi-implicit
   !> included) damp to 1e-10; explicit ones grow (and return finite numbers and a
   !> success status, not a crash).
   subroutine test_l_stability(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_test_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      complex(dp), parameter :: z(2) = [(-1.0_dp, 0.0_dp), (-0.5_dp, 0.5_dp)]
      real(dp) :: u1(2)
      integer :: i, k
      character(len=:), allocatable :: name

      problem%nu = (-1.0e12_dp, 0.0_dp)
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         do i = 1, size(z)
            problem%lambda = z(i)
            call scheme%take_step(problem, 0.0_dp, 1.0_dp, [1.0_dp, 0.0_dp], u1, stat)
            call check(error, stat%code, status_ok, name//": "//stat_message(stat))
            if (allocated(error)) return
            if (.not. scheme%implicit) then
               call check(error, norm2(u1) > 1.0_dp, name//" should be detected as unstable")
            else
               call check(error, norm2(u1) <= 1.0e-10_dp, name//" does not damp w = -1e12")
            end if
            if (allocated(error)) return
         end do
      end do
   end subroutine test_l_stability

   !> delta = U_high - U_low: check it against separate steps of the two members.
   subroutine test_embedded_difference(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: high, low, pair
      type(status_type) :: stat
      character(len=*), parameter :: pairs(2, 4) = reshape([character(len=12) :: &
         "ex-t-2", "ex-t-1", "si-t-2", "si-t-1", "i-t-2", "i-t-1", "si-t-2-paper", "si-t-1"], [2, 4])
      real(dp) :: u_high(2), u_low(2), u1(2), delta(2)
      real(dp), parameter :: u0(2) = [2.0_dp, -0.5_dp], h = 0.05_dp
      integer :: k

      problem = new_van_der_pol(5.0_dp)
      do k = 1, size(pairs, 2)
         call new_scheme(trim(pairs(1, k)), high, stat)
         call new_scheme(trim(pairs(2, k)), low, stat)
         call high%take_step(problem, 0.0_dp, h, u0, u_high, stat)
         call low%take_step(problem, 0.0_dp, h, u0, u_low, stat)
         ! the advancing member may be either one: both must give the same delta
         call new_scheme(trim(pairs(1, k)), pair, stat)
         call pair%take_step(problem, 0.0_dp, h, u0, u1, stat, delta)
         call check(error, maxval(abs(delta - (u_high - u_low))) <= 1.0e-12_dp, &
            trim(pairs(1, k))//": delta is not U_high - U_low")
         if (allocated(error)) return
         call new_scheme(trim(pairs(2, k)), pair, stat)
         call pair%take_step(problem, 0.0_dp, h, u0, u1, stat, delta)
         if (trim(pairs(1, k)) == "si-t-2-paper") cycle
         call check(error, maxval(abs(delta - (u_high - u_low))) <= 1.0e-12_dp, &
            trim(pairs(2, k))//": delta is not U_high - U_low")
         if (allocated(error)) return
      end do
   end subroutine test_embedded_difference

   !> The estimate of a step's own local error (si-t-2's, and i-t-2's, which checks the
   !> steps of step doubling with it) against the true local error of one step, from
   !> radau5 with 64 steps over [0, h]
   !> (error ~ 1e-18 here), for h = 0.05, 0.025, 0.0125, 0.00625 on three problems:
   !> Van der Pol mu = 1 (g nonlinear: the curvature term of the estimate counts),
   !> u' = cos u - 2u^3 - u (f and g nonlinear) and the Brusselator with 3 points (g
   !> linear). The error is of order 3 in h, the estimate's own error of order 4:
   !> observed orders within 0.3 of 3 and 4 (measured 2.93-3.02 and 3.88-3.97), and
   !> at the smallest h the estimate within 1 % of the error (measured 0.15-0.67 %).
   !> The schemes without such an estimate, and si-t-2 before any step, answer
   !> status_invalid_argument.
   subroutine test_step_error(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: steps = 4
      character(len=*), parameter :: estimating(2) = [character(len=6) :: "si-t-2", "i-t-2"]
      type(van_der_pol_type) :: vdp
      type(cubic_problem) :: cubic
      type(brusselator_type) :: brusselator
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: estimate(6), u1(6)
      integer :: k

      vdp = new_van_der_pol(1.0_dp)
      brusselator = new_brusselator(3)
      do k = 1, size(estimating)
         call check_estimate(trim(estimating(k)), vdp, [2.0_dp, -0.3_dp], "van der pol")
         if (allocated(error)) return
         call check_estimate(trim(estimating(k)), cubic, [0.7_dp], "cubic")
         if (allocated(error)) return
         call check_estimate(trim(estimating(k)), brusselator, brusselator%u0, "brusselator")
         if (allocated(error)) return
      end do

      do k = 1, scheme_count
         call new_scheme(trim(scheme_names(k)), scheme, stat)
         call scheme%take_step(vdp, 0.0_dp, 0.01_dp, [2.0_dp, 0.0_dp], u1(:2), stat)
         stat = status_type()
         call scheme%step_error(vdp, 0.0_dp, 0.01_dp, [2.0_dp, 0.0_dp], u1(:2), estimate(:2), stat)
         call check(error, (stat%code == status_ok) .eqv. (scheme%estimates_step_error .or. scheme%checks_defect), &
            trim(scheme_names(k))//": step_error answers "//stat_message(stat))
         if (allocated(error)) return
      end do
      call new_scheme("si-t-2", scheme, stat)
      call scheme%step_error(vdp, 0.0_dp, 0.01_dp, [2.0_dp, 0.0_dp], u1(:2), estimate(:2), stat)
      call check(error, stat%code, status_invalid_argument, "si-t-2: step_error before any step")
   contains
      subroutine check_estimate(name, problem, u0, label)
         character(len=*), intent(in) :: name
         class(ode_problem), intent(inout) :: problem
         real(dp), intent(in) :: u0(:)
         character(len=*), intent(in) :: label
         class(scheme_type), allocatable :: scheme, reference_scheme
         real(dp) :: u1(size(u0)), exact(size(u0)), estimate(size(u0)), h
         real(dp) :: true_size(steps), miss(steps), order_error, order_miss
         integer :: i
         do i = 1, steps
            h = 0.1_dp/2.0_dp**i
            call new_scheme(name, scheme, stat)
            call scheme%take_step(problem, 0.0_dp, h, u0, u1, stat)
            call scheme%step_error(problem, 0.0_dp, h, u0, u1, estimate, stat)
            call check(error, stat%code, status_ok, name//", "//label//": "//stat_message(stat))
            if (allocated(error)) return
            call new_scheme("radau5", reference_scheme, stat)
            exact = u0
            call integrate_fixed(problem, reference_scheme, 0.0_dp, h, 64, exact, stat)
            true_size(i) = norm2(u1 - exact)
            miss(i) = norm2(u1 - exact - estimate)
         end do
         order_error = log(true_size(steps - 1)/true_size(steps))/log(2.0_dp)
         order_miss = log(miss(steps - 1)/miss(steps))/log(2.0_dp)
         call check(error, abs(order_error - 3.0_dp) < 0.3_dp .and. abs(order_miss - 4.0_dp) < 0.3_dp, &
            name//", "//label//": orders of the error and of the estimate's error "//format_real(order_error)//", "// &
            format_real(order_miss)//" (expected 3 and 4)")
         if (allocated(error)) return
         call check(error, miss(steps) < 0.01_dp*true_size(steps), name//", "//label// &
            ": the estimate misses the error by "// &
            format_real(miss(steps)/true_size(steps))//" of it")
      end subroutine check_estimate
   end subroutine test_step_error

   subroutine test_unknown_scheme(error)
      type(error_type), allocatable, intent(out) :: error
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat

      call new_scheme("rk4", scheme, stat)
      call check(error, stat%code, status_unknown_scheme)
      if (allocated(error)) return
      call check(error, .not. allocated(scheme), "no scheme should be created for an unknown name")
      if (allocated(error)) return
      call check(error, index(stat%message, "rk4") > 0 .and. index(stat%message, "i-t-2") > 0 &
         .and. index(stat%message, "imex-rk21") > 0, "message should name the input and the valid names")
   end subroutine test_unknown_scheme

   subroutine test_bad_step_input(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: u1(2), u_short(1), u(2), nan

      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      problem = new_van_der_pol(10.0_dp)
      call new_scheme("i-t-2", scheme, stat)

      call scheme%take_step(problem, 0.0_dp, 0.1_dp, [2.0_dp, 0.0_dp], u_short, stat)
      call check(error, stat%code, status_size_mismatch, "size mismatch")
      if (allocated(error)) return
      call check(error, len(stat%message) > 0, "size mismatch message")
      if (allocated(error)) return

      call scheme%take_step(problem, 0.0_dp, 0.0_dp, [2.0_dp, 0.0_dp], u1, stat)
      call check(error, stat%code, status_invalid_argument, "h = 0")
      if (allocated(error)) return
      call scheme%take_step(problem, 0.0_dp, -0.1_dp, [2.0_dp, 0.0_dp], u1, stat)
      call check(error, stat%code, status_invalid_argument, "h < 0")
      if (allocated(error)) return
      call check(error, index(stat%message, "step size") > 0, "h message: "//stat%message)
      if (allocated(error)) return

      call scheme%take_step(problem, 0.0_dp, 0.1_dp, [2.0_dp, nan], u1, stat)
      call check(error, stat%code, status_nonfinite, "NaN in the state")
      if (allocated(error)) return
      call check(error, index(stat%message, "NaN") > 0, "NaN message: "//stat%message)
      if (allocated(error)) return

      u = [2.0_dp, 0.0_dp]
      call integrate_fixed(problem, scheme, 0.0_dp, 1.0_dp, 0, u, stat)
      call check(error, stat%code, status_invalid_argument, "zero steps")
      if (allocated(error)) return
      call integrate_fixed(problem, scheme, 1.0_dp, 1.0_dp, 10, u, stat)
      call check(error, stat%code, status_invalid_argument, "empty interval")
      if (allocated(error)) return
      u = [2.0_dp, nan]
      call integrate_fixed(problem, scheme, 0.0_dp, 1.0_dp, 10, u, stat)
      call check(error, stat%code, status_nonfinite, "NaN initial state")
   end subroutine test_bad_step_input

   !> si-t-1 on u' = nu u with h nu = 1: the Newton matrix 1 - h nu is singular.
   subroutine test_singular_newton(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_test_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: u1(2)

      problem%lambda = (-1.0_dp, 0.0_dp)
      problem%nu = (1.0_dp, 0.0_dp)
      call new_scheme("si-t-1", scheme, stat)
      call scheme%take_step(problem, 0.0_dp, 1.0_dp, [1.0_dp, 0.0_dp], u1, stat)
      call check(error, stat%code, status_singular_matrix, stat_message(stat))
      if (allocated(error)) return
      call check(error, index(stat%message, "singular") > 0, "message: "//stat_message(stat))
   end subroutine test_singular_newton

   !> g = -k atan(u) from u0 = 10 with h = 1: Newton overshoots further each time.
   subroutine test_newton_divergence(error)
      type(error_type), allocatable, intent(out) :: error
      type(runaway_problem) :: problem
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: u1(1)

      call new_scheme("i-t-1", scheme, stat)
      call scheme%take_step(problem, 0.0_dp, 1.0_dp, [10.0_dp], u1, stat)
      call check(error, stat%code == status_newton_diverged .or. stat%code == status_newton_not_converged, &
         "expected a Newton failure, got: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, index(stat%message, "Newton") > 0, "message: "//stat_message(stat))
   end subroutine test_newton_divergence

   !> i-t-2's Newton on a long step of Van der Pol (mu = 1000, h = 212 on the slow
   !> branch, the tolerances of rtol = atol = 1e-2) from a guess a little off the slow
   !> manifold, as an extrapolated guess is. The exact Newton matrix built there has a
   !> second-derivative term F''[F] far too large in the slow direction (F is large off
   !> the manifold), so the first increment, 2e-3 of the distance to the root in y, is
   !> far within the tolerance: a stop test that took it as its own error estimate
   !> returned a state 30 Newton tolerances from the root (4 tolerances of the step) with
   !> status ok, and the integration ran half a relaxation late. Now the solve ends
   !> within the Newton tolerance of the root, or fails (the step is then retried
   !> shorter), never ok elsewhere. The root (numpy, Newton with the exact matrix from
   !> the exact solution, residual 9e-9) is checked first: Newton stays there.
   subroutine test_newton_first_increment(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(newton_settings_type) :: newton
      type(status_type) :: stat
      real(dp), parameter :: t0 = 220.04_dp, h = 212.2_dp
      !> On the slow branch at t0, the solution at t0 + h, and the root of i-t-2's equation
      real(dp), parameter :: u0(2) = [1.84265392_dp, -7.69255130e-4_dp]
      real(dp), parameter :: u_exact(2) = [1.66311175_dp, -9.41770363e-4_dp]
      real(dp), parameter :: root(2) = [1.66934524_dp, -9.34309900e-4_dp]
      real(dp) :: u1(2), guess(2), distance

      problem = new_van_der_pol(1000.0_dp)
      call new_scheme("i-t-2", scheme, stat)
      call scheme%prepare(problem, 2, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      newton%tolerance = 0.03_dp*(1.0e-2_dp + 1.0e-2_dp*abs(u0))
      call scheme%advance(problem, t0, h, u0, u1, newton, stat, guess=root)
      call check(error, stat%code, status_ok, "from the root: status "//format_integer(stat%code))
      if (allocated(error)) return
      distance = maxval(abs(u1 - root)/newton%tolerance)
      call check(error, distance <= 0.01_dp, "from the root, Newton moved "//format_real(distance)//" tolerances")
      if (allocated(error)) return

      guess = u0 + 1.1_dp*(u_exact - u0)
      call scheme%restart()
      call scheme%advance(problem, t0, h, u0, u1, newton, stat, guess=guess)
      if (stat%code == status_newton_diverged .or. stat%code == status_newton_not_converged) return
      call check(error, stat%code, status_ok, "status "//format_integer(stat%code))
      if (allocated(error)) return
      distance = maxval(abs(u1 - root)/newton%tolerance)
      call check(error, distance <= 1.0_dp, "Newton stopped "//format_real(distance)// &
         " Newton tolerances from the root: y = "//format_real(u1(1))//", root "//format_real(root(1)))
   end subroutine test_newton_first_increment

   !> i-t-2 on Van der Pol with mu = 1e6: within 100 tolerances at t_end (see
   !> van_der_pol_mu_1e6). Its Newton matrix took F''[F] along F at the iterate, and
   !> an extrapolated guess a little off the slow manifold has F far larger than on it:
   !> Newton's increments in y were 1e-8 of the distance to the root, it stopped there,
   !> and the solution crept, then froze at the fold (1e-3: y = 1.07 from t = 0.9 mu to
   !> the end, 1080 tolerances off; 1e-2 with atol 1e-8 for z: y = 1.98 throughout, 41
   !> steps), with status ok. The term now takes F at the step's start when F at the
   !> iterate is more than 10 times larger (1e-2: 12 tolerances, 1e-3: 40).
   subroutine test_it2_van_der_pol_mu_1e6(error)
      type(error_type), allocatable, intent(out) :: error
      call van_der_pol_mu_1e6(error, "i-t-2", vdp_split_paper)
   end subroutine test_it2_van_der_pol_mu_1e6

   !> si-t-2 with the stiff split (f = (z, 0)) on Van der Pol with mu = 1e6: within 100
   !> tolerances at t_end (see van_der_pol_mu_1e6). Its local extrapolation U1 - M^(-1)
   !> e put z off the slow manifold by what M's linearization missed, its next step's
   !> h^2/2 J_f0 F0 turned that into a kick to y of up to a tenth of the tolerance, of
   !> one sign step after step, and y ran away with status ok (1e-2: y = 1.1e4 at t_end,
   !> 4.6e5 tolerances; 1e-3: 1.2e3 tolerances). The extrapolated state is now corrected
   !> onto the step's equation (1e-2: 0.4 tolerances, 1e-3: 0.2).
   subroutine test_sit2_van_der_pol_mu_1e6(error)
      type(error_type), allocatable, intent(out) :: error
      call van_der_pol_mu_1e6(error, "si-t-2", vdp_split_stiff)
   end subroutine test_sit2_van_der_pol_mu_1e6

   !> The scheme `name` on Van der Pol with mu = 1e6 and `split` over [0, 3 mu] at rtol =
   !> atol = 1e-2 and 1e-3, against radau5 at 1e-10: within 100 tolerances at t_end (the
   !> accuracy suite's bound for second-order schemes).
   subroutine van_der_pol_mu_1e6(error, name, split)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), intent(in) :: name
      integer, intent(in) :: split
      type(van_der_pol_type) :: problem
      real(dp), parameter :: tolerances(2) = [1.0e-2_dp, 1.0e-3_dp]
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: reference(2), u(2), off
      integer :: k
      problem = new_van_der_pol(1.0e6_dp, split)
      call new_scheme("radau5", scheme, stat)
      reference = problem%u0
      call integrate(problem, scheme, 0.0_dp, problem%t_end, reference, integrator_options_type(rtol=1.0e-10_dp, &
         atol=1.0e-10_dp), stats, stat)
      call check(error, stat%code, status_ok, "radau5: "//stat_message(stat))
      if (allocated(error)) return
      call new_scheme(name, scheme, stat)
      do k = 1, size(tolerances)
         options = integrator_options_type(rtol=tolerances(k), atol=tolerances(k))
         u = problem%u0
         call integrate(problem, scheme, 0.0_dp, problem%t_end, u, options, stats, stat)
         call check(error, stat%code, status_ok, name//": "//stat_message(stat))
         if (allocated(error)) return
         off = maxval(abs(u - reference)/(tolerances(k) + tolerances(k)*abs(reference)))
         call check(error, off <= 100.0_dp, name//" at "//format_real(tolerances(k))//": y = "// &
            format_real(u(1))//" at t_end (radau5 "//format_real(reference(1))//"), "//format_real(off)//" tolerances off")
         if (allocated(error)) return
      end do
   end subroutine van_der_pol_mu_1e6

   subroutine cubic_f(self, t, u, dudt)
      class(cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = cos(u)
   end subroutine cubic_f

   subroutine cubic_g(self, t, u, dudt)
      class(cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -2*u**3 - u
   end subroutine cubic_g

   subroutine cubic_jac_f(self, t, u, jac)
      class(cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = -sin(u(1))
   end subroutine cubic_jac_f

   subroutine cubic_jac_g(self, t, u, jac)
      class(cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = -6*u(1)**2 - 1
   end subroutine cubic_jac_g

   subroutine forced_cubic_f(self, t, u, dudt)
      class(forced_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = cos(u) + sin(3*t)
   end subroutine forced_cubic_f

   subroutine forced_cubic_g(self, t, u, dudt)
      class(forced_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -(2 + sin(t))*u**3 - u + 2*cos(5*t)
   end subroutine forced_cubic_g

   subroutine cubic_jac_f_any(self, t, u, jac)
      class(forced_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = -sin(u(1))
   end subroutine cubic_jac_f_any

   subroutine forced_cubic_jac_g(self, t, u, jac)
      class(forced_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = -3*(2 + sin(t))*u(1)**2 - 1
   end subroutine forced_cubic_jac_g

   subroutine augmented_cubic_f(self, t, u, dudt)
      class(augmented_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = cos(u(1)) + sin(3*u(2))
      dudt(2) = 1.0_dp
   end subroutine augmented_cubic_f

   subroutine augmented_cubic_g(self, t, u, dudt)
      class(augmented_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -(2 + sin(u(2)))*u(1)**3 - u(1) + 2*cos(5*u(2))
      dudt(2) = 0.0_dp
   end subroutine augmented_cubic_g

   subroutine augmented_cubic_jac_f(self, t, u, jac)
      class(augmented_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = -sin(u(1))
      jac(1, 2) = 3*cos(3*u(2))
   end subroutine augmented_cubic_jac_f

   subroutine augmented_cubic_jac_g(self, t, u, jac)
      class(augmented_cubic_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = -3*(2 + sin(u(2)))*u(1)**2 - 1
      jac(1, 2) = -cos(u(2))*u(1)**3 - 10*sin(5*u(2))
   end subroutine augmented_cubic_jac_g

   subroutine runaway_f(self, t, u, dudt)
      class(runaway_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = 0.0_dp
   end subroutine runaway_f

   subroutine runaway_g(self, t, u, dudt)
      class(runaway_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -runaway_k*atan(u)
   end subroutine runaway_g

   subroutine runaway_jac_f(self, t, u, jac)
      class(runaway_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
   end subroutine runaway_jac_f

   subroutine runaway_jac_g(self, t, u, jac)
      class(runaway_problem), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = -runaway_k/(1 + u(1)**2)
   end subroutine runaway_jac_g

end module test_schemes
