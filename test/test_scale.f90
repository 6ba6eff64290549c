!> Beyond one process: Jacobian-vector products, the reduction hook through which a
!> problem distributed over processes makes every process decide alike (emulated here
!> by a problem whose `reduce` adds what another process would contribute).
module test_scale
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode, only: dp, i8, ode_problem, scheme_type, status_type, new_scheme, integrate, &
      integrator_options_type, integration_stats_type, status_ok, status_max_steps, status_nonfinite, &
      status_evaluation_failed, status_newton_diverged, norm_max, norm_rms, reduce_sum, reduce_max
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, vdp_split_paper, vdp_split_stiff, &
      brusselator_type, new_brusselator
   use test_support, only: stat_message
   implicit none
   private

   public :: collect_scale

   !> A forward difference along v with increment sqrt(eps) max(|u|, 1)/|v| has error
   !> ~ sqrt(eps) times second derivatives; 1e-6 relative leaves a margin of ~100
   real(dp), parameter :: jvp_tolerance = 1.0e-6_dp

   !> What the emulated other process contributes to the reductions
   integer, parameter :: remote_nothing = 0, remote_large_error = 1, remote_outcome = 2, remote_nan = 3

   !> Van der Pol whose `reduce` counts its calls and may add another process's part
   type, extends(van_der_pol_type) :: two_process_vdp_type
      !> remote_* : what the other process contributes
      integer :: remote = remote_nothing
      !> remote_outcome: the agreement call at which the other process reports `code`
      integer :: at_attempt = 0
      !> remote_outcome: its status code and whether its rejection is fatal
      integer :: code = status_ok
      logical :: fatal_remote = .false.
      !> Calls so far: all, and those agreeing on an attempt's outcome
      integer :: calls = 0, agreements = 0
   contains
      procedure :: reduce => two_process_reduce
   end type two_process_vdp_type

contains

   !> Collect all exported unit tests
   subroutine collect_scale(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("jvp-differences", test_jvp_differences), &
         new_unittest("reduce-default-changes-nothing", test_reduce_changes_nothing), &
         new_unittest("reduce-remote-error", test_remote_error), &
         new_unittest("reduce-remote-outcome", test_remote_outcome), &
         new_unittest("reduce-remote-nonfinite", test_remote_nonfinite) &
         ]
   end subroutine collect_scale

   !> The other process's part: its error ratio 2 in every norm (it never meets its
   !> tolerance), a status code at one attempt, or a NaN in the first state checked.
   subroutine two_process_reduce(self, operation, values)
      class(two_process_vdp_type), intent(inout) :: self
      integer, intent(in) :: operation
      real(dp), intent(inout) :: values(:)
      self%calls = self%calls + 1
      if (operation == reduce_max .and. size(values) == 2) self%agreements = self%agreements + 1
      select case (self%remote)
      case (remote_large_error)
         if (operation == reduce_max .and. size(values) == 1) values(1) = max(values(1), 2.0_dp)
         ! its sum of squares: ratio 2 in each of its as many components
         if (operation == reduce_sum .and. size(values) == 2) values = [values(1) + 4.0_dp*values(2), &
            2.0_dp*values(2)]
      case (remote_outcome)
         if (operation == reduce_max .and. size(values) == 2 .and. self%agreements == self%at_attempt) then
            values(1) = max(values(1), real(self%code, dp))
            if (self%fatal_remote) values(2) = 1.0_dp
         end if
      case (remote_nan)
         if (operation == reduce_sum .and. size(values) == 1 .and. self%calls == 1) values(1) = values(1) + 1.0_dp
      end select
   end subroutine two_process_reduce

   !> The default jvp_f and jvp_g against the analytic Jacobians times v, on Van der
   !> Pol (both splittings) and the Brusselator; a zero direction gives exactly zero.
   subroutine test_jvp_differences(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: vdp
      type(brusselator_type) :: bruss
      integer :: splitting, k
      real(dp), allocatable :: u(:), v(:)

      do splitting = vdp_split_paper, vdp_split_stiff
         vdp = new_van_der_pol(10.0_dp, splitting)
         do k = 1, 3
            u = [2.0_dp - k, 0.3_dp*k]
            v = [1.0_dp, -0.5_dp*k]*10.0_dp**(k - 2)
            call compare_products(error, vdp, u, v, "van der pol")
            if (allocated(error)) return
         end do
      end do
      bruss = new_brusselator(12)
      u = bruss%u0
      v = [(sin(real(k, dp)), k = 1, size(u))]
      call compare_products(error, bruss, u, v, "brusselator")
      if (allocated(error)) return
      v = 0.0_dp
      call bruss%jvp_g(0.0_dp, u, v, u)
      call check(error, all(u == 0.0_dp), "J_g 0 must be exactly 0")
   end subroutine test_jvp_differences

   !> |jvp - J v| relative to max(1, |J v|) for f and g.
   subroutine compare_products(error, problem, u, v, label)
      type(error_type), allocatable, intent(out) :: error
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:), v(:)
      character(len=*), intent(in) :: label
      real(dp) :: jac(size(u), size(u)), exact(size(u)), product(size(u))
      call problem%jac_f(0.0_dp, u, jac)
      exact = matmul(jac, v)
      call problem%jvp_f(0.0_dp, u, v, product)
      call check(error, maxval(abs(product - exact)) <= jvp_tolerance*max(1.0_dp, maxval(abs(exact))), &
         label//": J_f v")
      if (allocated(error)) return
      call problem%jac_g(0.0_dp, u, jac)
      exact = matmul(jac, v)
      call problem%jvp_g(0.0_dp, u, v, product)
      call check(error, maxval(abs(product - exact)) <= jvp_tolerance*max(1.0_dp, maxval(abs(exact))), &
         label//": J_g v")
   end subroutine compare_products

   !> A `reduce` that combines nothing gives the run of the default bit for bit (max
   !> and RMS norms, zero atol), and it is called at most twice per attempt.
   subroutine test_reduce_changes_nothing(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: plain
      type(two_process_vdp_type) :: counted
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats_plain, stats_counted
      integer :: variant
      real(dp) :: u_plain(2), u_counted(2)
      integer(i8) :: attempts

      do variant = 1, 3
         options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp)
         if (variant >= 2) options%norm = norm_rms
         if (variant == 3) options%atol = 0.0_dp
         plain = new_van_der_pol(10.0_dp)
         counted%van_der_pol_type = new_van_der_pol(10.0_dp)
         counted%calls = 0
         u_plain = plain%u0
         u_counted = counted%u0
         call run(plain, u_plain, stats_plain)
         if (allocated(error)) return
         call run(counted, u_counted, stats_counted)
         if (allocated(error)) return
         call check(error, all(transfer(u_plain, 0_i8, 2) == transfer(u_counted, 0_i8, 2)) .and. &
            stats_plain%accepted_steps == stats_counted%accepted_steps .and. &
            stats_plain%rejected_steps() == stats_counted%rejected_steps(), &
            "a reduce that combines nothing changed the run")
         if (allocated(error)) return
         attempts = stats_counted%accepted_steps + stats_counted%rejected_steps()
         ! per attempt the outcome and the error norm, and with atol = 0 the largest
         ! component for each of the two sets of weights; init: a finiteness check, the
         ! outcome of F0, the weights and two norms; advance_to: a finiteness check
         call check(error, counted%calls >= attempts .and. &
            counted%calls <= merge(4, 2, variant == 3)*attempts + 6, "reduce calls per attempt out of bounds")
         if (allocated(error)) return
      end do
   contains
      subroutine run(problem, u, stats)
         class(ode_problem), intent(inout) :: problem
         real(dp), intent(inout) :: u(:)
         type(integration_stats_type), intent(out) :: stats
         class(scheme_type), allocatable :: scheme
         type(status_type) :: stat
         call new_scheme("si-t-2", scheme, stat)
         call integrate(problem, scheme, 0.0_dp, 20.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, "integration: "//stat_message(stat))
      end subroutine run
   end subroutine test_reduce_changes_nothing

   !> Another process whose part never meets the tolerance: this process, whose own
   !> part would, rejects every step too (max and RMS norms).
   subroutine test_remote_error(error)
      type(error_type), allocatable, intent(out) :: error
      type(two_process_vdp_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)
      integer :: norm

      do norm = norm_max, norm_rms
         problem%van_der_pol_type = new_van_der_pol(10.0_dp)
         problem%remote = remote_large_error
         options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp, norm=norm, max_steps=200_i8)
         call new_scheme("si-t-2", scheme, stat)
         u = problem%u0
         call integrate(problem, scheme, 0.0_dp, 20.0_dp, u, options, stats, stat)
         call check(error, stat%code == status_max_steps .and. stats%accepted_steps == 0 .and. &
            stats%rejected_error == 200, "a step was accepted although another process's error is 2: "// &
            stat_message(stat))
         if (allocated(error)) return
      end do
   end subroutine test_remote_error

   !> Another process's outcome of one attempt is this process's: a rejected
   !> evaluation and a Newton failure are retried, a fatal rejection stops here too.
   subroutine test_remote_outcome(error)
      type(error_type), allocatable, intent(out) :: error
      type(integration_stats_type) :: stats
      type(status_type) :: stat

      call run(status_evaluation_failed, .false., stats, stat)
      call check(error, stat%code == status_ok .and. stats%rejected_evaluation == 1 .and. &
         stats%rejected_newton == 0, "a rejection on another process was not retried: "//stat_message(stat))
      if (allocated(error)) return
      call run(status_newton_diverged, .false., stats, stat)
      call check(error, stat%code == status_ok .and. stats%rejected_newton == 1 .and. &
         stats%rejected_evaluation == 0, "a Newton failure on another process was not retried: "// &
         stat_message(stat))
      if (allocated(error)) return
      call run(status_evaluation_failed, .true., stats, stat)
      call check(error, stat%code == status_evaluation_failed .and. &
         index(stat_message(stat), "stopped the integration") > 0 .and. stats%rejected_evaluation == 1 .and. &
         stats%accepted_steps + stats%rejected_steps() == 3, &
         "a fatal rejection on another process did not stop this one: "//stat_message(stat))
   contains
      subroutine run(code, fatal, stats, stat)
         integer, intent(in) :: code
         logical, intent(in) :: fatal
         type(integration_stats_type), intent(out) :: stats
         type(status_type), intent(out) :: stat
         type(two_process_vdp_type) :: problem
         class(scheme_type), allocatable :: scheme
         real(dp) :: u(2)
         problem%van_der_pol_type = new_van_der_pol(10.0_dp)
         problem%remote = remote_outcome
         ! the first agreement is on F at the initial state: the third attempt's is the fourth
         problem%at_attempt = 4
         problem%code = code
         problem%fatal_remote = fatal
         call new_scheme("i-t-2", scheme, stat)
         u = problem%u0
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, stat)
      end subroutine run
   end subroutine test_remote_outcome

   !> A NaN in another process's part of the initial state stops this one at init.
   subroutine test_remote_nonfinite(error)
      type(error_type), allocatable, intent(out) :: error
      type(two_process_vdp_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2)
      problem%van_der_pol_type = new_van_der_pol(10.0_dp)
      problem%remote = remote_nan
      call new_scheme("si-t-2", scheme, stat)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, stat)
      call check(error, stat%code, status_nonfinite, "NaN on another process: "//stat_message(stat))
   end subroutine test_remote_nonfinite

end module test_scale
