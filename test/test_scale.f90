!> Beyond one process: ensembles over threads (the same results as the serial loop,
!> failing members included), Jacobian-vector products, and the reduction hook
!> through which a problem distributed over processes makes every process decide
!> alike (emulated here by a problem whose `reduce` adds what another process would
!> contribute).
module test_scale
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode, only: dp, i8, ode_problem, scheme_type, status_type, new_scheme, integrate, &
      integrator_options_type, integration_stats_type, status_ok, status_max_steps, status_nonfinite, &
      status_evaluation_failed, status_newton_diverged, norm_max, norm_rms, reduce_sum, reduce_max, &
      integrate_ensemble, status_size_mismatch, status_unknown_scheme, status_invalid_argument
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, vdp_split_paper, vdp_split_stiff, &
      brusselator_type, new_brusselator
   use test_support, only: stat_message, run_type, run_app, has_line
   use taylorode_base_strings, only: format_integer
   !$ use omp_lib, only: omp_get_max_threads
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
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

   !> How a flaky member fails
   integer, parameter :: failure_none = 0, failure_nan = 1, failure_fatal = 2, failure_rejections = 3

   !> Van der Pol that goes wrong from a time on: NaN, a fatal rejection, or rejections
   !> it never gets past
   type, extends(van_der_pol_type) :: flaky_vdp_type
      !> failure_* : how it goes wrong after t_bad
      integer :: failure = failure_none
      real(dp) :: t_bad = huge(1.0_dp)
   contains
      procedure :: g => flaky_g
      !> F = f + g with this g (Van der Pol's own one-pass rhs would bypass it)
      procedure :: rhs => flaky_rhs
   end type flaky_vdp_type

contains

   !> Collect all exported unit tests
   subroutine collect_scale(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("ensemble-equals-serial", test_ensemble_equals_serial), &
         new_unittest("ensemble-arguments", test_ensemble_arguments), &
         new_unittest("ensemble-command", test_ensemble_command), &
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

   !> f + g, g with the member's failure.
   subroutine flaky_rhs(self, t, u, dudt)
      class(flaky_vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: g(size(u))
      call self%f(t, u, dudt)
      call self%g(t, u, g)
      dudt = dudt + g
   end subroutine flaky_rhs

   !> g of Van der Pol, then the member's failure after t_bad.
   subroutine flaky_g(self, t, u, dudt)
      class(flaky_vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call self%van_der_pol_type%g(t, u, dudt)
      if (t <= self%t_bad) return
      select case (self%failure)
      case (failure_nan)
         dudt = ieee_value(1.0_dp, ieee_quiet_nan)
      case (failure_fatal)
         call self%reject_evaluation(fatal=.true.)
      case (failure_rejections)
         call self%reject_evaluation()
      end select
   end subroutine flaky_g

   !> 64 Van der Pol members (mu from 6 to 69), a quarter of them fine, the others
   !> failing by NaN, a fatal rejection or rejections they never get past: the
   !> ensemble, on as many threads as OpenMP gives and on one, returns the serial
   !> loop's states (bit for bit, NaN included), statistics and messages.
   subroutine test_ensemble_equals_serial(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: members = 64
      type(flaky_vdp_type) :: problems(members), serial_problems(members)
      type(integrator_options_type) :: options
      type(integration_stats_type) :: serial_stats(members), stats(members)
      type(status_type) :: serial_stat(members), member_stat(members), stat
      class(scheme_type), allocatable :: scheme
      real(dp) :: serial_u(2, members), u(2, members)
      integer :: k, run

      options = integrator_options_type(rtol=1.0e-5_dp, atol=1.0e-5_dp)
      do k = 1, members
         problems(k)%van_der_pol_type = new_van_der_pol(5.0_dp + real(k, dp))
         problems(k)%failure = mod(k, 4)
         problems(k)%t_bad = 0.5_dp + 0.01_dp*k
      end do
      serial_problems = problems
      do k = 1, members
         serial_u(:, k) = problems(k)%u0
         call new_scheme("i-t-2", scheme, stat)
         call integrate(serial_problems(k), scheme, 0.0_dp, 20.0_dp, serial_u(:, k), options, serial_stats(k), &
            serial_stat(k))
      end do
      call check(error, count(serial_stat%code == status_ok) == members/4 .and. &
         count(serial_stat%code == status_nonfinite) == members/4 .and. &
         count(serial_stat%code == status_evaluation_failed) == members/2, &
         "the members should be a quarter fine, a quarter NaN, half rejected")
      if (allocated(error)) return

      do run = 1, 2
         do k = 1, members
            u(:, k) = problems(k)%u0
         end do
         if (run == 1) then
            call integrate_ensemble(problems, "i-t-2", 0.0_dp, 20.0_dp, u, options, stats, member_stat, stat)
         else
            call integrate_ensemble(problems, "i-t-2", 0.0_dp, 20.0_dp, u, options, stats, member_stat, stat, &
               threads=1)
         end if
         call check(error, stat%code == serial_stat(1)%code .and. index(stat_message(stat), "48 of 64") > 0, &
            "the ensemble's status: "//stat_message(stat))
         if (allocated(error)) return
         do k = 1, members
            call check(error, all(transfer(u(:, k), 0_i8, 2) == transfer(serial_u(:, k), 0_i8, 2)) .and. &
               member_stat(k)%code == serial_stat(k)%code .and. &
               stat_message(member_stat(k)) == stat_message(serial_stat(k)) .and. &
               stats(k)%accepted_steps == serial_stats(k)%accepted_steps .and. &
               stats(k)%rejected_steps() == serial_stats(k)%rejected_steps() .and. &
               stats(k)%work%g_evaluations == serial_stats(k)%work%g_evaluations, &
               "member differs from its serial run: "//stat_message(member_stat(k)))
            if (allocated(error)) return
         end do
      end do
      !$ call check(error, omp_get_max_threads() > 1, "built with OpenMP but running on one thread")
   end subroutine test_ensemble_equals_serial

   !> Arguments that do not fit: sizes, an unknown scheme, zero threads; nothing runs.
   subroutine test_ensemble_arguments(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problems(3)
      type(integration_stats_type) :: stats(3)
      type(status_type) :: member_stat(3), stat
      real(dp) :: u(2, 3), u_wrong(2, 2)
      integer :: k
      do k = 1, 3
         problems(k) = new_van_der_pol(10.0_dp)
         u(:, k) = problems(k)%u0
      end do
      u_wrong = u(:, :2)
      call integrate_ensemble(problems, "i-t-2", 0.0_dp, 1.0_dp, u_wrong, integrator_options_type(), stats, &
         member_stat, stat)
      call check(error, stat%code == status_size_mismatch .and. all(member_stat%code == status_size_mismatch) .and. &
         all(u_wrong == u(:, :2)), "sizes: "//stat_message(stat))
      if (allocated(error)) return
      call integrate_ensemble(problems, "i-t-9", 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, &
         member_stat, stat)
      call check(error, stat%code == status_unknown_scheme .and. all(member_stat%code == status_unknown_scheme), &
         "unknown scheme: "//stat_message(stat))
      if (allocated(error)) return
      call integrate_ensemble(problems, "i-t-2", 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, &
         member_stat, stat, threads=0)
      call check(error, stat%code == status_invalid_argument .and. all(stats%accepted_steps == 0), &
         "zero threads: "//stat_message(stat))
   end subroutine test_ensemble_arguments

   !> The app's ensemble command times a small sweep and finds the threaded results equal
   !> to the serial ones; impossible counts are mistakes on the command line.
   subroutine test_ensemble_command(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call run_app("ensemble --members 6 --repeats 1 --scheme si-t-2", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "6 members") .and. &
         has_line(run%stdout, "speed-up") .and. has_line(run%stdout, "bit for bit: yes"), "ensemble command")
      if (allocated(error)) return
      call run_app("ensemble --threads 0", run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "--threads must be at least 1"), &
         "--threads 0 accepted")
      if (allocated(error)) return
      call run_app("vdp --members 3", run)
      call check(error, run%exit_status, 2, "--members accepted by vdp")
   end subroutine test_ensemble_command

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
   !> and RMS norms, zero atol), where the integrator skips the reductions, and it is
   !> called at most nine times per attempt (eleven with atol = 0).
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
         ! the default reduce marks the whole state as here (the integrator then skips the
         ! reductions); an override is called throughout
         call check(error, plain%whole_state_here() .and. .not. counted%whole_state_here(), &
            "whole_state_here: the default reduce should set it, an override not")
         if (allocated(error)) return
         attempts = stats_counted%accepted_steps + stats_counted%rejected_steps()
         ! per attempt (si-t-2, its own error estimate) the outcomes of the step and of the
         ! estimate, the error norm and the norms of what the error becomes in the next
         ! step (unfiltered, and filtered when that is larger), the norms that decide on
         ! the correction of the extrapolated state (what the next step makes of the
         ! estimate, and of the correction, unfiltered and filtered), and with atol = 0 the
         ! largest component for each of the two sets of weights; at most 8 more at the
         ! start (finiteness, the outcome of F0, the weights and norms of the first step
         ! size) and in advance_to (finiteness)
         call check(error, counted%calls >= attempts .and. &
            counted%calls <= merge(11, 9, variant == 3)*attempts + 8, "reduce calls per attempt out of bounds: "// &
            format_integer(counted%calls)//" calls in "//format_integer(attempts)//" attempts")
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
         stats%accepted_steps == 1 .and. stats%rejected_steps() == 1, &
         "a fatal rejection on another process did not stop this one: "//stat_message(stat)//"; "// &
         format_integer(stats%accepted_steps)//" accepted, "//format_integer(stats%rejected_steps())//" rejected, "// &
         format_integer(stats%rejected_evaluation)//" evaluation")
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
         ! two agreements at the start (F at U0 and at the first step size's Euler step),
         ! then three per attempt (step doubling's steps): the eighth is the second
         ! attempt's last, after one accepted step
         problem%at_attempt = 8
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
