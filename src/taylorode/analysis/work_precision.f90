!> Error against run time: timed runs (median CPU over repeats), the radau5
!> reference solution, and a sweep of schemes over decades of tolerance on a
!> problem of the test set.
module taylorode_analysis_work_precision
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, status_ok
   use taylorode_base_strings, only: fixed_length_real
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_integrate_options, only: integrator_options_type
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrate
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: timed_run_type, timed_run, reference_run, reference_tolerance, median
   public :: work_precision_config_type, work_precision_point_type, work_precision, tolerance_scale
   public :: progress_interface

   !> Tolerance of the reference solver (radau5, rtol = atol)
   real(dp), parameter :: reference_tolerance = 1.0e-12_dp
   !> A run longer than this (CPU seconds) is timed once
   real(dp), parameter :: single_run_seconds = 1.0_dp

   abstract interface
      !> Called with a short message before a run that may take more than a second
      subroutine progress_interface(message)
         !> What is about to run
         character(len=*), intent(in) :: message
      end subroutine progress_interface
   end interface

   !> Outcome of a timed run: the last run's results, median CPU time over the repeats
   type :: timed_run_type
      !> Statistics of the last run
      type(integration_stats_type) :: stats
      !> Status of the last run
      type(status_type) :: stat
      !> Final state
      real(dp), allocatable :: u(:)
      !> Dense output (when output times were given)
      real(dp), allocatable :: u_out(:, :)
      !> Median CPU seconds of the runs
      real(dp) :: cpu_median = 0.0_dp
      !> Runs made
      integer :: runs = 0
   end type timed_run_type

   !> A work-precision sweep: schemes, tolerances rtol = tol from tol_high down to
   !> tol_low by decades (atol = tol times the problem's atol/rtol), timing and budget
   type :: work_precision_config_type
      !> Schemes to run
      character(len=16), allocatable :: schemes(:)
      !> Loosest and tightest tolerance
      real(dp) :: tol_high = 1.0e-2_dp, tol_low = 1.0e-8_dp
      !> Timing repetitions for the median
      integer :: repeats = 5
      !> Attempted steps allowed per run
      integer(i8) :: budget = 2000000_i8
   end type work_precision_config_type

   !> One point of a sweep
   type :: work_precision_point_type
      !> Scheme
      character(len=16) :: scheme = ""
      !> Tolerance (rtol)
      real(dp) :: tol = 0.0_dp
      !> Accepted and rejected steps
      integer(i8) :: accepted = 0, rejected = 0
      !> Median CPU seconds
      real(dp) :: cpu_seconds = 0.0_dp
      !> Timed runs made
      integer :: runs = 0
      !> Status code of the run
      integer :: status = status_ok
      !> max |u - reference| / max |reference| at t_end (-1 when the run failed)
      real(dp) :: error = -1.0_dp
   end type work_precision_point_type

contains

   !> Run `scheme_name` on the problem `repeats` times (once when a run takes more than
   !> a second) and keep the median CPU time; `t_out` asks for dense output.
   subroutine timed_run(problem, scheme_name, options, t0, t_end, u0, repeats, run, t_out)
      !> The problem
      class(test_problem_type), intent(inout) :: problem
      !> Scheme name
      character(len=*), intent(in) :: scheme_name
      !> Integrator options
      type(integrator_options_type), intent(in) :: options
      !> Interval and initial state
      real(dp), intent(in) :: t0, t_end, u0(:)
      !> Timing repetitions
      integer, intent(in) :: repeats
      !> Results
      type(timed_run_type), intent(out) :: run
      !> Output times for dense output
      real(dp), intent(in), optional :: t_out(:)
      class(scheme_type), allocatable :: scheme
      real(dp) :: times(max(repeats, 1))
      integer :: k, memory, outputs

      outputs = 0
      if (present(t_out)) outputs = size(t_out)
      allocate (run%u(size(u0)), stat=memory)
      if (present(t_out) .and. memory == 0) allocate (run%u_out(size(u0), outputs), stat=memory)
      if (memory /= 0) then
         call out_of_memory(run%stat, "the run's state and dense output", [size(u0), 1 + outputs], real_bytes)
         return
      end if
      do k = 1, max(repeats, 1)
         call new_scheme(scheme_name, scheme, run%stat)
         if (run%stat%code /= status_ok) return
         run%u = u0
         if (present(t_out)) then
            call integrate(problem, scheme, t0, t_end, run%u, options, run%stats, run%stat, &
               t_out=t_out, u_out=run%u_out)
         else
            call integrate(problem, scheme, t0, t_end, run%u, options, run%stats, run%stat)
         end if
         times(k) = run%stats%cpu_seconds
         run%runs = k
         if (run%stats%cpu_seconds > single_run_seconds) exit
      end do
      run%cpu_median = median(times(:run%runs))
   end subroutine timed_run

   !> radau5 at rtol = atol = 1e-12 (atol scaled by the problem's atol/rtol when it
   !> has small components), with dense output at t_out, within max_steps attempts
   !> (default 50 million).
   subroutine reference_run(problem, t0, t_end, u0, t_out, u_end, u_out, stat, max_steps)
      !> The problem
      class(test_problem_type), intent(inout) :: problem
      !> Interval, initial state and output times
      real(dp), intent(in) :: t0, t_end, u0(:), t_out(:)
      !> Solution at t_end and at the output times
      real(dp), intent(out) :: u_end(:), u_out(:, :)
      !> Status of the reference run
      type(status_type), intent(out) :: stat
      !> Attempted steps allowed
      integer(i8), intent(in), optional :: max_steps
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats

      options%rtol = reference_tolerance
      options%atol = reference_tolerance*tolerance_scale(problem)
      options%max_steps = 50000000_i8
      if (present(max_steps)) options%max_steps = max_steps
      call new_scheme("radau5", scheme, stat)
      u_end = u0
      call integrate(problem, scheme, t0, t_end, u_end, options, stats, stat, t_out=t_out, u_out=u_out)
   end subroutine reference_run

   !> atol / rtol recommended by the problem, at most 1 (1 when it recommends rtol = 0).
   pure real(dp) function tolerance_scale(problem)
      !> The problem
      class(test_problem_type), intent(in) :: problem
      tolerance_scale = 1.0_dp
      if (problem%rtol > 0.0_dp) tolerance_scale = min(1.0_dp, problem%atol/problem%rtol)
   end function tolerance_scale

   !> Every scheme of the sweep at every tolerance: one point each, the error measured
   !> against the problem's published solution, or against `reference` when given.
   subroutine work_precision(problem, config, reference, points, progress)
      !> The problem
      class(test_problem_type), intent(inout) :: problem
      !> Schemes, tolerances, repeats and budget
      type(work_precision_config_type), intent(in) :: config
      !> Solution at t_end to measure against
      real(dp), intent(in) :: reference(:)
      !> One point per scheme and tolerance, scheme by scheme
      type(work_precision_point_type), allocatable, intent(out) :: points(:)
      !> Called before each run
      procedure(progress_interface), optional :: progress
      type(integrator_options_type) :: options
      type(timed_run_type) :: run
      integer :: k, decade, decades, point

      decades = nint(log10(config%tol_high/config%tol_low)) + 1
      allocate (points(size(config%schemes)*decades))
      point = 0
      do k = 1, size(config%schemes)
         do decade = 0, decades - 1
            point = point + 1
            associate (p => points(point))
               p%scheme = config%schemes(k)
               p%tol = config%tol_high/10.0_dp**decade
               options = integrator_options_type(rtol=p%tol, atol=p%tol*tolerance_scale(problem), &
                  max_steps=config%budget)
               if (present(progress)) call progress("sweep: "//trim(p%scheme)//" tol "// &
                  trim(fixed_length_real(p%tol, 2)))
               call timed_run(problem, trim(p%scheme), options, problem%t0, problem%t_end, problem%u0, &
                  config%repeats, run)
               p%accepted = run%stats%accepted_steps
               p%rejected = run%stats%rejected_steps()
               p%cpu_seconds = run%cpu_median
               p%runs = run%runs
               p%status = run%stat%code
               if (run%stat%code == status_ok) p%error = maxval(abs(run%u - reference))/maxval(abs(reference))
            end associate
         end do
      end do
   end subroutine work_precision

   !> Median of a list of numbers.
   pure function median(values) result(m)
      !> The numbers
      real(dp), intent(in) :: values(:)
      real(dp) :: m, sorted(size(values)), swap
      integer :: i, j
      sorted = values
      do i = 2, size(sorted)
         do j = i, 2, -1
            if (sorted(j - 1) <= sorted(j)) exit
            swap = sorted(j)
            sorted(j) = sorted(j - 1)
            sorted(j - 1) = swap
         end do
      end do
      if (mod(size(sorted), 2) == 1) then
         m = sorted((size(sorted) + 1)/2)
      else
         m = 0.5_dp*(sorted(size(sorted)/2) + sorted(size(sorted)/2 + 1))
      end if
   end function median

end module taylorode_analysis_work_precision
