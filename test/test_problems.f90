!> Built-in problems: analytic Jacobians against finite differences, and a user
!> problem that supplies only f and g.
module test_problems
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode, only: dp, ode_problem, ode_problem_fd, scheme_type, status_type, new_scheme, &
      integrate_fixed, status_ok, integrate, integrator_options_type, integration_stats_type, &
      matrix_structure_type, dense_structure
   use test_support, only: differenced_brusselator
   use taylorode_base_strings, only: format_integer
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, vdp_split_paper, vdp_split_stiff, &
      linear_test_type, van_der_pol_initial_state, vdp_ic_prepared, test_problem_type, new_test_problem, &
      test_problem_names, test_problem_count, brusselator_type, new_brusselator, orego_type, new_orego, &
      orego_split_bilinear_stiff, pollution_type, new_pollution, medical_akzo_type, new_medical_akzo, hires_type, &
      new_hires, hires_split_reaction_stiff
   implicit none
   private

   public :: collect_problems

   !> Forward differences with increment sqrt(eps) |u| have error ~ sqrt(eps) times
   !> the second derivatives; relative to the Jacobian's size 1e-6 leaves a margin of ~100.
   real(dp), parameter :: fd_tolerance = 1.0e-6_dp

   !> The Brusselator on the dense path: the same problem declaring a dense structure
   type, extends(brusselator_type) :: dense_brusselator
   contains
      procedure :: jacobian_structure => dense_jacobian_structure
   end type dense_brusselator

   !> Van der Pol written as a user without Jacobians would: f and g only
   type, extends(ode_problem_fd) :: vdp_without_jacobians
      real(dp) :: mu = 1.0_dp
      integer :: splitting = vdp_split_paper
   contains
      procedure :: f => user_f
      procedure :: g => user_g
   end type vdp_without_jacobians

   !> A test-set problem written with only f and g (and F = f + g in one call, `rhs`),
   !> counting every call of each: how many evaluations a difference Jacobian takes
   type, extends(ode_problem_fd) :: counted_without_jacobians
      class(test_problem_type), allocatable :: model
      integer :: f_calls = 0, g_calls = 0, rhs_calls = 0, jac_g_calls = 0
   contains
      procedure :: f => counted_f
      procedure :: g => counted_g
      procedure :: rhs => counted_rhs
      procedure :: jacobian_structure => counted_structure
   end type counted_without_jacobians

   !> The same with the model's own dg/dU (df/dU still by differences)
   type, extends(counted_without_jacobians) :: counted_with_jac_g
   contains
      procedure :: jac_g => counted_jac_g
      procedure :: jac_g_band => counted_jac_g_band
   end type counted_with_jac_g

contains

   !> Collect all exported unit tests
   subroutine collect_problems(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("van-der-pol-jacobians", test_van_der_pol_jacobians), &
         new_unittest("linear-test-jacobians", test_linear_test_jacobians), &
         new_unittest("problem-without-jacobians", test_problem_without_jacobians), &
         new_unittest("difference-jacobian-of-rhs", test_difference_jacobian_of_rhs), &
         new_unittest("radau5-without-jacobians", test_radau5_without_jacobians), &
         new_unittest("van-der-pol-initial-states", test_initial_states), &
         new_unittest("test-set-jacobians", test_test_set_jacobians), &
         new_unittest("rhs-and-jac-equal-their-parts", test_rhs_equals_parts), &
         new_unittest("unknown-problem", test_unknown_problem), &
         new_unittest("band-jacobians", test_band_jacobians), &
         new_unittest("banded-path-equals-dense", test_banded_path), &
         new_unittest("pollution-parts-conserve-atoms", test_pollution_conservation), &
         new_unittest("medakzo-band-jacobians", test_medakzo_band_jacobians), &
         new_unittest("medakzo-g-is-linear", test_medakzo_linear_g) &
         ]
   end subroutine collect_problems

   !> Largest difference between analytic and forward-difference Jacobians of f and g,
   !> relative to the largest entry (at least 1).
   subroutine compare_jacobians(error, analytic, differenced, u, label)
      type(error_type), allocatable, intent(out) :: error
      class(ode_problem), intent(inout) :: analytic, differenced
      real(dp), intent(in) :: u(:)
      character(len=*), intent(in) :: label
      real(dp), dimension(size(u), size(u)) :: jac_a, jac_d
      real(dp) :: scale

      call analytic%jac_f(0.0_dp, u, jac_a)
      call differenced%jac_f(0.0_dp, u, jac_d)
      scale = max(1.0_dp, maxval(abs(jac_a)))
      call check(error, maxval(abs(jac_a - jac_d))/scale < fd_tolerance, label//": df/dU")
      if (allocated(error)) return
      call analytic%jac_g(0.0_dp, u, jac_a)
      call differenced%jac_g(0.0_dp, u, jac_d)
      scale = max(1.0_dp, maxval(abs(jac_a)))
      call check(error, maxval(abs(jac_a - jac_d))/scale < fd_tolerance, label//": dg/dU")
   end subroutine compare_jacobians

   subroutine test_van_der_pol_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: analytic
      type(vdp_without_jacobians) :: differenced
      real(dp), parameter :: states(2, 4) = reshape([2.0_dp, -0.6667_dp, -1.5_dp, 1.2e-3_dp, &
         0.3_dp, 4.0_dp, 1.0_dp, -2.0_dp], [2, 4])
      integer :: splitting, i

      do splitting = vdp_split_paper, vdp_split_stiff
         analytic = new_van_der_pol(1000.0_dp, splitting)
         differenced%mu = 1000.0_dp
         differenced%splitting = splitting
         do i = 1, size(states, 2)
            call compare_jacobians(error, analytic, differenced, states(:, i), "Van der Pol")
            if (allocated(error)) return
         end do
      end do
   end subroutine test_van_der_pol_jacobians

   subroutine test_linear_test_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      type(linear_test_type) :: analytic
      real(dp) :: jac(2, 2), v(2), u(2)

      analytic%lambda = (-0.5_dp, 2.0_dp)
      analytic%nu = (-30.0_dp, -4.0_dp)
      u = [0.7_dp, -1.3_dp]
      call analytic%jac_g(0.0_dp, u, jac)
      call analytic%g(0.0_dp, u, v)
      ! linear: g(u) = J u exactly
      call check(error, maxval(abs(matmul(jac, u) - v)) < 1.0e-14_dp, "g = J_g u")
      if (allocated(error)) return
      call analytic%jac_f(0.0_dp, u, jac)
      call analytic%f(0.0_dp, u, v)
      call check(error, maxval(abs(matmul(jac, u) - v)) < 1.0e-14_dp, "f = J_f u")
   end subroutine test_linear_test_jacobians

   !> A user problem with only f and g integrates like the built-in one.
   subroutine test_problem_without_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: analytic
      type(vdp_without_jacobians) :: differenced
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: u_a(2), u_d(2)

      analytic = new_van_der_pol(100.0_dp)
      differenced%mu = 100.0_dp
      u_a = van_der_pol_initial_state(vdp_ic_prepared)
      u_d = u_a
      call new_scheme("i-t-2", scheme, stat)
      call integrate_fixed(analytic, scheme, 0.0_dp, 1.0_dp, 200, u_a, stat)
      call check(error, stat%code, status_ok)
      if (allocated(error)) return
      call new_scheme("i-t-2", scheme, stat)
      call integrate_fixed(differenced, scheme, 0.0_dp, 1.0_dp, 200, u_d, stat)
      call check(error, stat%code, status_ok)
      if (allocated(error)) return
      ! Newton converges to the same U1 with either matrix: only roundoff and the
      ! Newton tolerance (1e-13 relative) separate the two runs.
      call check(error, maxval(abs(u_a - u_d)) < 1.0e-10_dp, "finite-difference run differs")
   end subroutine test_problem_without_jacobians

   !> Without analytic Jacobians, the whole Jacobian J (`jac`, `jac_band`: radau5's,
   !> i-t-1's and i-t-2's) takes one evaluation of F = f + g (`rhs`) per perturbed column
   !> (n + 1 dense on HIRES, lower + upper + 2 for the Brusselator's band) and none of f
   !> or g alone, and equals the analytic J to the differences' accuracy; with the
   !> problem's own dg/dU it stays jac_f by differences of f plus that dg/dU.
   subroutine test_difference_jacobian_of_rhs(error)
      type(error_type), allocatable, intent(out) :: error
      type(counted_without_jacobians) :: problem
      type(counted_with_jac_g) :: with_jac_g
      real(dp), allocatable :: u(:), jac(:, :), exact(:, :)
      integer :: n, lower, upper, repeat

      ! dense: HIRES, n = 8
      allocate (problem%model, source=new_hires())
      n = size(problem%model%u0)
      u = problem%model%u0 + 0.1_dp*problem%model%u0(1)
      allocate (jac(n, n), exact(n, n))
      call problem%model%jac(0.0_dp, u, exact)
      do repeat = 1, 2
         problem%f_calls = 0
         problem%g_calls = 0
         problem%rhs_calls = 0
         call problem%jac(0.0_dp, u, jac)
         call check(error, problem%rhs_calls, n + 1, "dense J: evaluations of F")
         if (allocated(error)) return
         call check(error, problem%f_calls + problem%g_calls, 0, "dense J: evaluations of f or g alone")
         if (allocated(error)) return
         call check(error, maxval(abs(jac - exact))/max(1.0_dp, maxval(abs(exact))) < fd_tolerance, &
            "dense J differs from the analytic one")
         if (allocated(error)) return
      end do
      allocate (with_jac_g%model, source=new_hires())
      call with_jac_g%jac(0.0_dp, u, jac)
      call check(error, with_jac_g%f_calls == n + 1 .and. with_jac_g%g_calls == 0 .and. &
         with_jac_g%rhs_calls == 0 .and. with_jac_g%jac_g_calls == 1, &
         "dense J with the problem's dg/dU: not differences of f plus dg/dU")
      if (allocated(error)) return
      call check(error, maxval(abs(jac - exact))/max(1.0_dp, maxval(abs(exact))) < fd_tolerance, &
         "dense J with the problem's dg/dU differs from the analytic one")
      if (allocated(error)) return
      deallocate (jac, exact, problem%model, with_jac_g%model)

      ! band: the Brusselator on 20 points (n = 40, bandwidths 2 and 2)
      allocate (problem%model, source=new_brusselator(20))
      n = size(problem%model%u0)
      call problem%bandwidths(n, lower, upper)
      u = problem%model%u0 + 0.1_dp
      allocate (jac(lower + upper + 1, n), exact(lower + upper + 1, n))
      call problem%model%jac_band(0.0_dp, u, exact)
      do repeat = 1, 2
         problem%f_calls = 0
         problem%g_calls = 0
         problem%rhs_calls = 0
         call problem%jac_band(0.0_dp, u, jac)
         call check(error, problem%rhs_calls, lower + upper + 2, "band J: evaluations of F")
         if (allocated(error)) return
         call check(error, problem%f_calls + problem%g_calls, 0, "band J: evaluations of f or g alone")
         if (allocated(error)) return
         call check(error, maxval(abs(jac - exact))/max(1.0_dp, maxval(abs(exact))) < fd_tolerance, &
            "band J differs from the analytic one")
         if (allocated(error)) return
      end do
      allocate (with_jac_g%model, source=new_brusselator(20))
      with_jac_g%f_calls = 0
      with_jac_g%jac_g_calls = 0
      call with_jac_g%jac_band(0.0_dp, u, jac)
      call check(error, with_jac_g%f_calls == lower + upper + 2 .and. with_jac_g%g_calls == 0 .and. &
         with_jac_g%rhs_calls == 0 .and. with_jac_g%jac_g_calls == 1, &
         "band J with the problem's dg/dU: not differences of f plus dg/dU")
      if (allocated(error)) return
      call check(error, maxval(abs(jac - exact))/max(1.0_dp, maxval(abs(exact))) < fd_tolerance, &
         "band J with the problem's dg/dU differs from the analytic one")
   end subroutine test_difference_jacobian_of_rhs

   !> radau5 on HIRES and the Brusselator (band) without analytic Jacobians: every
   !> evaluation is one of F (n, or lower + upper + 1, per Jacobian beside the scheme's
   !> own: the differences start from F at the step's start, which the scheme evaluates
   !> anyway; the first Jacobian, which finds how J is formed, at most one more), and the run takes
   !> as many steps as with the analytic Jacobians (within 5 %) to a final state as close
   !> to the tight reference. Also Robertson to t = 1e11, where y1 and y2 fall to 1e-10
   !> and below: with the increment sqrt(eps) max(|u_j|, 1), which swamps them, radau5
   !> took 85 times the steps at rtol 1e-6 (and through the legacy entry ran out of
   !> RADAU5's budget at 1e-7 and tighter); RADAU5's increment, sqrt(eps max(|u_j|,
   !> 1e-5)), is the library's now.
   subroutine test_radau5_without_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(3) = [character(len=11) :: "hires", "brusselator", "robertson"]
      type(counted_without_jacobians) :: problem
      class(test_problem_type), allocatable :: analytic
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats, stats_analytic
      type(status_type) :: stat
      real(dp), allocatable :: u(:), u_analytic(:), reference(:)
      integer :: k, n, lower, upper, per_jacobian
      real(dp) :: error_d, error_a

      do k = 1, size(names)
         call new_test_problem(trim(names(k)), analytic, stat)
         if (names(k) == "robertson") analytic%t_end = 1.0e11_dp
         if (allocated(problem%model)) deallocate (problem%model)
         allocate (problem%model, source=analytic)
         problem%rhs_calls = 0
         n = size(analytic%u0)
         call analytic%bandwidths(n, lower, upper)
         per_jacobian = merge(n, lower + upper + 1, lower < 0)
         options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp*analytic%atol/analytic%rtol)
         ! the reference: radau5 with the analytic Jacobians at 1e-11
         reference = analytic%u0
         call new_scheme("radau5", scheme, stat)
         call integrate(analytic, scheme, analytic%t0, analytic%t_end, reference, &
            integrator_options_type(rtol=1.0e-11_dp, atol=1.0e-11_dp*analytic%atol/analytic%rtol), stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//": reference")
         if (allocated(error)) return
         u_analytic = analytic%u0
         call new_scheme("radau5", scheme, stat)
         call integrate(analytic, scheme, analytic%t0, analytic%t_end, u_analytic, options, stats_analytic, stat)
         call check(error, stat%code, status_ok, trim(names(k))//": analytic")
         if (allocated(error)) return
         u = analytic%u0
         call new_scheme("radau5", scheme, stat)
         call integrate(problem, scheme, analytic%t0, analytic%t_end, u, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//": without Jacobians")
         if (allocated(error)) return
         call check(error, problem%f_calls + problem%g_calls, 0, trim(names(k))//": evaluations of f or g alone")
         if (allocated(error)) return
         ! (the first Jacobian, which finds how J is formed, takes one more when the
         ! scheme has no F at the step's start to difference from)
         call check(error, int(problem%rhs_calls, kind(stats%work%f_evaluations)) - &
            (stats%work%f_evaluations + per_jacobian*stats%work%jac_f_evaluations) <= 1, &
            trim(names(k))//": evaluations of F beside the scheme's own: "//format_integer(int(problem%rhs_calls))// &
            " against "//format_integer(int(stats%work%f_evaluations))//" + "//format_integer(per_jacobian)//" x "// &
            format_integer(int(stats%work%jac_f_evaluations))//" (+ 1)")
         if (allocated(error)) return
         ! (Robertson to 1e11: differences of a J whose entries span 1e-10 ... 1e4 cost
         ! Newton some contraction, 485 steps against 388; 32,917 with the old increment;
         ! Hairer's RADAU5 with IJAC = 0 also takes 1.1-2 times its steps with IJAC = 1)
         call check(error, abs(stats%accepted_steps - stats_analytic%accepted_steps) <= &
            merge(0.3_dp, 0.05_dp, names(k) == "robertson")*stats_analytic%accepted_steps, &
            trim(names(k))//": accepted steps "// &
            format_integer(int(stats%accepted_steps))//" against "//format_integer(int(stats_analytic%accepted_steps)))
         if (allocated(error)) return
         error_d = maxval(abs(u - reference)/(1.0e-6_dp*analytic%atol/analytic%rtol + 1.0e-6_dp*abs(reference)))
         error_a = maxval(abs(u_analytic - reference)/(1.0e-6_dp*analytic%atol/analytic%rtol + &
            1.0e-6_dp*abs(reference)))
         call check(error, error_d <= 2.0_dp*error_a + 1.0_dp, trim(names(k))//": error against the reference")
         if (allocated(error)) return
      end do
   end subroutine test_radau5_without_jacobians

   !> Every problem of the test set: analytic Jacobians of f and g against central
   !> differences at the initial state and at a perturbed state. Central differences
   !> are exact for the quadratic kinetics; with increments 1e-6 max(|u_j|, 1e-3) the
   !> truncation (cubic and trigonometric terms) and roundoff stay below 1e-7 of the
   !> largest entry.
   subroutine test_test_set_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      class(test_problem_type), allocatable :: problem
      type(status_type) :: stat
      real(dp), allocatable :: state(:)
      integer :: k, i, which

      do k = 1, test_problem_count
         call new_test_problem(test_problem_names(k), problem, stat)
         call check(error, stat%code, status_ok, stat%message)
         if (allocated(error)) return
         state = problem%u0
         do which = 1, 2
            if (which == 2) state = problem%u0 + 0.01_dp*(1.0_dp + abs(problem%u0))* &
               [(sin(1.3_dp*i), i=1, size(state))]
            call compare_central(error, problem, 0.3_dp, state, .true., trim(test_problem_names(k)))
            if (allocated(error)) return
            call compare_central(error, problem, 0.3_dp, state, .false., trim(test_problem_names(k)))
            if (allocated(error)) return
         end do
      end do
   end subroutine test_test_set_jacobians

   !> F from `rhs` is f + g and J from `jac` is jac_f + jac_g (and `jac_band`, for a
   !> banded problem, jac_f_band + jac_g_band) to the last bit, and `add_jacobian_product`
   !> is y + alpha J v with J from `jac` (`jac_band`) added column by column to the last
   !> bit (i-t-2's residual takes J F from it: its steps do not depend on whether a
   !> problem has a product of its own), for every problem of the test set (those that
   !> compute F, J or J v in one call and those that keep the defaults), both Van der
   !> Pol, OREGO and HIRES splittings, and a user problem with f and g only (whose J,
   !> differences of F, equals the differences of f plus those of g to fd_tolerance); at
   !> the initial state and at a perturbed one.
   subroutine test_rhs_equals_parts(error)
      type(error_type), allocatable, intent(out) :: error
      class(test_problem_type), allocatable :: problem
      type(van_der_pol_type) :: stiff_split
      type(orego_type) :: bilinear
      type(hires_type) :: reaction_stiff
      type(vdp_without_jacobians) :: user
      type(status_type) :: stat
      integer :: k

      do k = 1, test_problem_count
         call new_test_problem(test_problem_names(k), problem, stat)
         call check(error, stat%code, status_ok, stat%message)
         if (allocated(error)) return
         call compare_rhs(error, problem, problem%u0, trim(test_problem_names(k)))
         if (allocated(error)) return
      end do
      stiff_split = new_van_der_pol(1000.0_dp, vdp_split_stiff)
      call compare_rhs(error, stiff_split, stiff_split%u0, "van der pol, stiff splitting")
      if (allocated(error)) return
      bilinear = new_orego(orego_split_bilinear_stiff)
      call compare_rhs(error, bilinear, bilinear%u0, "orego, bilinear terms stiff")
      if (allocated(error)) return
      reaction_stiff = new_hires(hires_split_reaction_stiff)
      call compare_rhs(error, reaction_stiff, reaction_stiff%u0, "hires, reaction stiff")
      if (allocated(error)) return
      user%mu = 5.0_dp
      call compare_rhs(error, user, [2.0_dp, -0.5_dp], "a problem with the default rhs", differenced=.true.)
   end subroutine test_rhs_equals_parts

   subroutine compare_rhs(error, problem, u0, label, differenced)
      type(error_type), allocatable, intent(out) :: error
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u0(:)
      character(len=*), intent(in) :: label
      !> J by differences of F: equal to jac_f + jac_g to fd_tolerance, not bit for bit
      logical, intent(in), optional :: differenced
      real(dp), allocatable :: u(:), f(:), g(:), whole(:), jac(:, :), jac_f(:, :), jac_g(:, :), band(:, :), &
         band_f(:, :), band_g(:, :), v(:), product(:), expected(:)
      integer :: which, i, j, lower, upper
      allocate (f(size(u0)), g(size(u0)), whole(size(u0)))
      allocate (jac(size(u0), size(u0)), jac_f(size(u0), size(u0)), jac_g(size(u0), size(u0)))
      call problem%bandwidths(size(u0), lower, upper)
      if (lower >= 0) allocate (band(lower + upper + 1, size(u0)), band_f(lower + upper + 1, size(u0)), &
         band_g(lower + upper + 1, size(u0)))
      do which = 1, 2
         u = u0
         if (which == 2) u = u0 + 0.01_dp*(1.0_dp + abs(u0))*[(sin(1.3_dp*i), i=1, size(u0))]
         call problem%f(0.3_dp, u, f)
         call problem%g(0.3_dp, u, g)
         call problem%rhs(0.3_dp, u, whole)
         call check(error, all(whole == f + g), label//": rhs differs from f + g")
         if (allocated(error)) return
         call problem%jac_f(0.3_dp, u, jac_f)
         call problem%jac_g(0.3_dp, u, jac_g)
         call problem%jac(0.3_dp, u, jac)
         if (present(differenced)) then
            call check(error, maxval(abs(jac - (jac_f + jac_g))) <= fd_tolerance*max(1.0_dp, maxval(abs(jac))), &
               label//": jac differs from jac_f + jac_g")
         else
            call check(error, all(jac == jac_f + jac_g), label//": jac differs from jac_f + jac_g")
         end if
         if (allocated(error)) return
         if (lower >= 0) then
            call problem%jac_f_band(0.3_dp, u, band_f)
            call problem%jac_g_band(0.3_dp, u, band_g)
            call problem%jac_band(0.3_dp, u, band)
            call check(error, all(band == band_f + band_g), label//": jac_band differs from jac_f_band + jac_g_band")
            if (allocated(error)) return
         end if
         ! y + alpha J v, J as the default product takes it (jac_band for a banded problem)
         v = whole + [(0.1_dp*cos(0.7_dp*i), i=1, size(u))]
         expected = u - 0.5_dp*whole
         product = expected
         do j = 1, size(u)
            do i = 1, size(u)
               if (lower >= 0) then
                  if (i - j > lower .or. j - i > upper) cycle
                  expected(i) = expected(i) + (0.37_dp*v(j))*band(upper + 1 + i - j, j)
               else
                  expected(i) = expected(i) + (0.37_dp*v(j))*jac(i, j)
               end if
            end do
         end do
         call problem%add_jacobian_product(0.3_dp, u, 0.37_dp, v, product)
         call check(error, all(product == expected), label//": add_jacobian_product differs from y + alpha J v")
         if (allocated(error)) return
      end do
   end subroutine compare_rhs

   subroutine compare_central(error, problem, t, u, of_f, label)
      type(error_type), allocatable, intent(out) :: error
      class(test_problem_type), intent(inout) :: problem
      real(dp), intent(in) :: t, u(:)
      logical, intent(in) :: of_f
      character(len=*), intent(in) :: label
      real(dp) :: jac(size(u), size(u))

      if (of_f) then
         call problem%jac_f(t, u, jac)
      else
         call problem%jac_g(t, u, jac)
      end if
      call check(error, maxval(abs(central_differences(problem, t, u, merge(1, 2, of_f)) - jac))/ &
         max(1.0_dp, maxval(abs(jac))) < 1.0e-7_dp, label//merge(": df/dU", ": dg/dU", of_f)// &
         " differs from central differences")
   end subroutine compare_central

   !> The Jacobian of f (which = 1), g (2) or F = rhs (3) by central differences, with
   !> increments 1e-6 max(|u_j|, 1e-3).
   function central_differences(problem, t, u, which) result(jac)
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, u(:)
      integer, intent(in) :: which
      real(dp), allocatable :: jac(:, :)
      real(dp) :: plus(size(u)), minus(size(u)), probe(size(u)), step
      integer :: j

      allocate (jac(size(u), size(u)))
      do j = 1, size(u)
         step = 1.0e-6_dp*max(abs(u(j)), 1.0e-3_dp)
         probe = u
         probe(j) = u(j) + step
         call evaluate(probe, plus)
         probe(j) = u(j) - step
         call evaluate(probe, minus)
         jac(:, j) = (plus - minus)/(2.0_dp*step)
      end do
   contains
      subroutine evaluate(state, value)
         real(dp), intent(in) :: state(:)
         real(dp), intent(out) :: value(:)
         select case (which)
         case (1)
            call problem%f(t, state, value)
         case (2)
            call problem%g(t, state, value)
         case default
            call problem%rhs(t, state, value)
         end select
      end subroutine evaluate
   end function central_differences

   !> Band Jacobians of the Brusselator (analytic, and the library's grouped
   !> differences) equal the dense analytic ones inside the band and the band holds
   !> every nonzero.
   subroutine test_band_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      type(brusselator_type) :: analytic
      type(differenced_brusselator) :: differenced
      real(dp), allocatable :: dense(:, :), band(:, :), state(:)
      integer :: n, i, j, lower, upper, which

      analytic = new_brusselator(7)
      differenced%model = analytic
      n = size(analytic%u0)
      state = analytic%u0 + 0.1_dp*[(sin(0.7_dp*i), i=1, n)]
      call analytic%bandwidths(n, lower, upper)
      allocate (dense(n, n), band(lower + upper + 1, n))
      do which = 1, 4
         select case (which)
         case (1)
            call analytic%jac_f(0.0_dp, state, dense)
            call analytic%jac_f_band(0.0_dp, state, band)
         case (2)
            call analytic%jac_g(0.0_dp, state, dense)
            call analytic%jac_g_band(0.0_dp, state, band)
         case (3)
            call analytic%jac_f(0.0_dp, state, dense)
            call differenced%jac_f_band(0.0_dp, state, band)
         case (4)
            call analytic%jac_g(0.0_dp, state, dense)
            call differenced%jac_g_band(0.0_dp, state, band)
         end select
         do j = 1, n
            do i = 1, n
               if (i - j > lower .or. j - i > upper) then
                  call check(error, dense(i, j) == 0.0_dp, "nonzero outside the declared band")
               else
                  ! exact for the analytic band, 1e-6 relative for the differences
                  call check(error, abs(band(upper + 1 + i - j, j) - dense(i, j)) <= &
                     1.0e-6_dp*max(1.0_dp, abs(dense(i, j))), "band entry differs, case "//char(48 + which))
               end if
               if (allocated(error)) return
            end do
         end do
      end do
   end subroutine test_band_jacobians

   !> The banded Newton path and the dense one give the same integration.
   subroutine test_banded_path(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(4) = [character(len=9) :: "si-t-2", "i-t-2", "imex-rk21", "ex-t-2"]
      type(brusselator_type) :: banded
      type(dense_brusselator) :: dense
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats_band, stats_dense
      type(status_type) :: stat
      real(dp), allocatable :: u_band(:), u_dense(:)
      integer :: k

      banded = new_brusselator(10)
      dense%brusselator_type = banded
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp)
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u_band = banded%u0
         call integrate(banded, scheme, 0.0_dp, 1.0_dp, u_band, options, stats_band, stat)
         call check(error, stat%code, status_ok, trim(names(k))//" banded")
         if (allocated(error)) return
         call new_scheme(trim(names(k)), scheme, stat)
         u_dense = dense%u0
         call integrate(dense, scheme, 0.0_dp, 1.0_dp, u_dense, options, stats_dense, stat)
         call check(error, stat%code, status_ok, trim(names(k))//" dense")
         if (allocated(error)) return
         ! the same arithmetic up to the order of summation in the LU factorizations
         call check(error, maxval(abs(u_band - u_dense)) < 1.0e-9_dp, trim(names(k))//": banded and dense differ")
         if (allocated(error)) return
         call check(error, stats_band%accepted_steps, stats_dense%accepted_steps, trim(names(k))//": step counts")
         if (allocated(error)) return
      end do
   end subroutine test_banded_path

   !> POLLU's mechanism conserves nitrogen (NO2, NO, PAN, HNO3, NO3 and twice N2O5),
   !> carbon (HCHO, CO, MEO2, CO2, CH3O and twice ALD, C2O3, PAN) and sulphur (SO2, SO4)
   !> reaction by reaction, so f and g each do: w . f = w . g = 0 up to the rounding of
   !> their terms (1e-14 of sum |w_i| |part_i|), at a state where every species is present.
   !> A species mistyped in the mechanism's table breaks one of them.
   subroutine test_pollution_conservation(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), parameter :: nitrogen(20) = [1, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 1, 0, 0, 0, 1, 2]
      real(dp), parameter :: carbon(20) = [0, 0, 0, 0, 0, 0, 1, 1, 2, 1, 2, 1, 2, 1, 0, 0, 0, 0, 0, 0]
      real(dp), parameter :: sulphur(20) = [0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 0, 0]
      real(dp), parameter :: atoms(20, 3) = reshape([nitrogen, carbon, sulphur], [20, 3])
      type(pollution_type) :: problem
      real(dp) :: u(20), part(20)
      integer :: i, which, element

      problem = new_pollution()
      u = problem%u0 + 0.01_dp*(1.0_dp + sin(1.7_dp*[(i, i=1, 20)]))
      do which = 1, 2
         if (which == 1) then
            call problem%f(0.0_dp, u, part)
         else
            call problem%g(0.0_dp, u, part)
         end if
         do element = 1, 3
            call check(error, abs(dot_product(atoms(:, element), part)) <= &
               1.0e-14_dp*dot_product(atoms(:, element), abs(part)), &
               merge("f", "g", which == 1)//" does not conserve element "//char(48 + element))
            if (allocated(error)) return
         end do
      end do
   end subroutine test_pollution_conservation

   !> MEDAKZO's band Jacobians of f, g and F (jac_f_band, jac_g_band, jac_band) against
   !> central differences of f, g and F, on 7 points and on the published 200, before and
   !> after the boundary value drops (t = 0.3, 7), at the initial state and a perturbed
   !> one; the differences vanish outside the band. f and g are bilinear and affine, so
   !> the differences are exact but for rounding: 1e-7 of the largest entry.
   subroutine test_medakzo_band_jacobians(error)
      type(error_type), allocatable, intent(out) :: error
      type(medical_akzo_type) :: problem
      real(dp), allocatable :: u(:)
      integer :: size_case, which, state, time, i

      do size_case = 1, 2
         problem = new_medical_akzo(merge(7, 200, size_case == 1))
         do state = 1, 2
            u = problem%u0
            if (state == 2) u = u + 0.01_dp*(1.0_dp + abs(u))*[(sin(1.3_dp*i), i=1, size(u))]
            do time = 1, 2
               do which = 1, 3
                  call compare_band_central(error, problem, merge(0.3_dp, 7.0_dp, time == 1), u, which)
                  if (allocated(error)) return
               end do
            end do
         end do
      end do
   end subroutine test_medakzo_band_jacobians

   !> MEDAKZO declares g linear: g(t, U) = A U + b(t) with A constant. Its band Jacobian
   !> is the same at every time and state (bit for bit), and g(t, U) - g(t, 0) = A U to
   !> rounding (1e-13 of |A| |U|) before and after the boundary value drops.
   subroutine test_medakzo_linear_g(error)
      type(error_type), allocatable, intent(out) :: error
      type(medical_akzo_type) :: problem
      real(dp), allocatable :: u(:), band(:, :), other(:, :), g(:), g0(:), au(:), scale(:)
      real(dp) :: t
      integer :: n, i, j, k, lower, upper, time

      problem = new_medical_akzo()
      call check(error, problem%linear_g, "MEDAKZO should declare g linear")
      if (allocated(error)) return
      n = size(problem%u0)
      call problem%bandwidths(n, lower, upper)
      allocate (band(lower + upper + 1, n), other(lower + upper + 1, n), g(n), g0(n), au(n), scale(n))
      u = problem%u0 + 0.3_dp*[(sin(0.9_dp*i), i=1, n)]
      call problem%jac_g_band(0.3_dp, problem%u0, band)
      call problem%jac_g_band(7.0_dp, u, other)
      call check(error, all(band == other), "dg/dU changes with t or U")
      if (allocated(error)) return
      do time = 1, 2
         t = merge(0.3_dp, 7.0_dp, time == 1)
         call problem%g(t, u, g)
         call problem%g(t, 0.0_dp*u, g0)
         au = 0.0_dp
         scale = 0.0_dp
         do j = 1, n
            do k = max(1, j - upper), min(n, j + lower)
               au(k) = au(k) + band(upper + 1 + k - j, j)*u(j)
               scale(k) = scale(k) + abs(band(upper + 1 + k - j, j)*u(j))
            end do
         end do
         call check(error, all(abs(g - g0 - au) <= 1.0e-13_dp*scale + tiny(1.0_dp)), &
            "g(t, U) - g(t, 0) differs from A U")
         if (allocated(error)) return
      end do
   end subroutine test_medakzo_linear_g

   !> A band Jacobian (which = 1: jac_f_band, 2: jac_g_band, 3: jac_band) against central
   !> differences of f, g or F = rhs; the differences must vanish outside the band.
   subroutine compare_band_central(error, problem, t, u, which)
      type(error_type), allocatable, intent(out) :: error
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, u(:)
      integer, intent(in) :: which
      character(len=*), parameter :: names(3) = ["jac_f_band", "jac_g_band", "jac_band  "]
      real(dp), allocatable :: band(:, :), differences(:, :)
      real(dp) :: worst, entry
      integer :: i, j, n, lower, upper

      n = size(u)
      call problem%bandwidths(n, lower, upper)
      allocate (band(lower + upper + 1, n))
      if (which == 1) call problem%jac_f_band(t, u, band)
      if (which == 2) call problem%jac_g_band(t, u, band)
      if (which == 3) call problem%jac_band(t, u, band)
      differences = central_differences(problem, t, u, which)
      worst = 0.0_dp
      do j = 1, n
         do i = 1, n
            entry = 0.0_dp
            if (i - j <= lower .and. j - i <= upper) entry = band(upper + 1 + i - j, j)
            worst = max(worst, abs(differences(i, j) - entry))
         end do
      end do
      call check(error, worst/max(1.0_dp, maxval(abs(band))) < 1.0e-7_dp, trim(names(which))// &
         " differs from central differences at t = "//merge("0.3", "7  ", t < 1.0_dp)//", n = "// &
         merge("14 ", "400", n == 14))
   end subroutine compare_band_central

   function dense_jacobian_structure(self, n) result(structure)
      class(dense_brusselator), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = dense_structure()
   end function dense_jacobian_structure

   subroutine test_unknown_problem(error)
      type(error_type), allocatable, intent(out) :: error
      class(test_problem_type), allocatable :: problem
      type(status_type) :: stat
      call new_test_problem("lorenz", problem, stat)
      call check(error, stat%code /= status_ok .and. .not. allocated(problem), "unknown problem accepted")
      if (allocated(error)) return
      call check(error, index(stat%message, "robertson") > 0, "message should list the valid names")
   end subroutine test_unknown_problem

   subroutine test_initial_states(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: u(2)
      u = van_der_pol_initial_state(vdp_ic_prepared)
      call check(error, u(2), -2.0_dp/3.0_dp, thr=1.0e-15_dp)
      if (allocated(error)) return
      u = van_der_pol_initial_state(2)
      call check(error, u(2), 0.0_dp)
   end subroutine test_initial_states

   subroutine user_f(self, t, u, dudt)
      class(vdp_without_jacobians), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = u(2)
      dudt(2) = merge(-u(1), 0.0_dp, self%splitting == vdp_split_paper)
   end subroutine user_f

   subroutine user_g(self, t, u, dudt)
      class(vdp_without_jacobians), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = 0.0_dp
      dudt(2) = self%mu*(1 - u(1)**2)*u(2) - merge(u(1), 0.0_dp, self%splitting == vdp_split_stiff)
   end subroutine user_g

   subroutine counted_f(self, t, u, dudt)
      class(counted_without_jacobians), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      self%f_calls = self%f_calls + 1
      call self%model%f(t, u, dudt)
   end subroutine counted_f

   subroutine counted_g(self, t, u, dudt)
      class(counted_without_jacobians), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      self%g_calls = self%g_calls + 1
      call self%model%g(t, u, dudt)
   end subroutine counted_g

   subroutine counted_rhs(self, t, u, dudt)
      class(counted_without_jacobians), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      self%rhs_calls = self%rhs_calls + 1
      call self%model%rhs(t, u, dudt)
   end subroutine counted_rhs

   function counted_structure(self, n) result(structure)
      class(counted_without_jacobians), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = self%model%jacobian_structure(n)
   end function counted_structure

   subroutine counted_jac_g(self, t, u, jac)
      class(counted_with_jac_g), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      self%jac_g_calls = self%jac_g_calls + 1
      call self%model%jac_g(t, u, jac)
   end subroutine counted_jac_g

   subroutine counted_jac_g_band(self, t, u, band)
      class(counted_with_jac_g), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      self%jac_g_calls = self%jac_g_calls + 1
      call self%model%jac_g_band(t, u, band)
   end subroutine counted_jac_g_band

end module test_problems
