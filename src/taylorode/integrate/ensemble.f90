!> Ensembles are many independent integrations (a parameter sweep, uncertainty
!> quantification, one chemistry system per grid cell) shared out over OpenMP threads.
!>
!> Each member is integrated exactly as `integrate` would integrate it alone, with its
!> own problem object and a scheme object of its own, so the results do not depend on
!> the number of threads or on which thread took which member: they are those of the
!> serial loop, bit for bit. Members are handed out one at a time as threads become
!> free (members differ in cost). Without OpenMP (a build without -fopenmp) the same
!> code runs the members one after another.
module taylorode_integrate_ensemble
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_size_mismatch, &
      status_invalid_argument
   use taylorode_problem_ode, only: ode_problem
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_integrate_options, only: integrator_options_type
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrate
   !$ use omp_lib, only: omp_get_max_threads
   implicit none
   private

   public :: integrate_ensemble, ensemble_threads

contains

   !> Integrate every member k: U' = f_k + g_k with problems(k) from t0 to t_end,
   !> starting from u(:, k), with the scheme called `scheme_name` and the same options.
   !>
   !> On return u(:, k), stats(k) and member_stat(k) are what `integrate` returns for
   !> member k alone (the last good state and why it stopped, for a member that
   !> failed). stat is ok when every member succeeded; otherwise it carries the code of
   !> the first member that failed and says how many did. Arguments that do not fit
   !> together (sizes, an unknown scheme) are reported in stat and in every member_stat,
   !> and nothing is integrated. `threads` caps the threads (default: OpenMP's own
   !> choice; 1 runs the serial loop).
   subroutine integrate_ensemble(problems, scheme_name, t0, t_end, u, options, stats, member_stat, stat, threads)
      !> One problem object per member (members share nothing)
      class(ode_problem), intent(inout) :: problems(:)
      !> The scheme every member uses (see scheme_names)
      character(len=*), intent(in) :: scheme_name
      !> Initial and final time of every member
      real(dp), intent(in) :: t0, t_end
      !> Initial states on entry, final (or last good) states on exit: u(:, k) for member k
      real(dp), intent(inout) :: u(:, :)
      !> Tolerances, controller and limits of every member
      type(integrator_options_type), intent(in) :: options
      !> Statistics of each member
      type(integration_stats_type), intent(out) :: stats(:)
      !> Outcome of each member
      type(status_type), intent(out) :: member_stat(:)
      !> Outcome of the ensemble: ok when every member succeeded
      type(status_type), intent(out) :: stat
      !> Largest number of threads to use (>= 1)
      integer, intent(in), optional :: threads
      class(scheme_type), allocatable :: scheme
      integer :: k, thread_count, failed, first_failed
      character(len=120) :: summary

      if (size(u, 2) /= size(problems) .or. size(stats) /= size(problems) .or. &
         size(member_stat) /= size(problems)) then
         call set_status(stat, status_size_mismatch, "integrate_ensemble: u must have one column, stats and "// &
            "member_stat one entry per problem")
         member_stat = stat
         return
      end if
      call new_scheme(scheme_name, scheme, stat)
      if (stat%code == status_ok .and. present(threads)) then
         if (threads < 1) call set_status(stat, status_invalid_argument, "integrate_ensemble: threads must be >= 1")
      end if
      if (stat%code /= status_ok) then
         member_stat = stat
         return
      end if
      thread_count = ensemble_threads()
      if (present(threads)) thread_count = min(threads, thread_count)

      !$omp parallel do schedule(dynamic, 1) num_threads(thread_count) default(shared) private(k)
      do k = 1, size(problems)
         call integrate_member(problems(k), scheme_name, t0, t_end, u(:, k), options, stats(k), member_stat(k))
      end do
      !$omp end parallel do

      failed = count(member_stat%code /= status_ok)
      if (failed == 0) return
      first_failed = findloc(member_stat%code /= status_ok, .true., dim=1)
      write (summary, '("integrate_ensemble: ", i0, " of ", i0, " members failed; the first, member ", i0, ": ")') &
         failed, size(problems), first_failed
      ! the member's message as it is (a function returning it, of deferred length, would
      ! keep that length in static memory with gfortran 12: ensembles may run at once)
      if (allocated(member_stat(first_failed)%message)) then
         call set_status(stat, member_stat(first_failed)%code, trim(summary)//" "//member_stat(first_failed)%message)
      else
         call set_status(stat, member_stat(first_failed)%code, trim(summary)//" ")
      end if
   end subroutine integrate_ensemble

   !> The number of threads an ensemble uses by default: OpenMP's maximum, 1 in a build
   !> without OpenMP.
   integer function ensemble_threads()
      ensemble_threads = 1
      !$ ensemble_threads = omp_get_max_threads()
   end function ensemble_threads

   !> One member with a scheme object of its own.
   subroutine integrate_member(problem, scheme_name, t0, t_end, u, options, stats, stat)
      class(ode_problem), intent(inout) :: problem
      character(len=*), intent(in) :: scheme_name
      real(dp), intent(in) :: t0, t_end
      real(dp), intent(inout) :: u(:)
      type(integrator_options_type), intent(in) :: options
      type(integration_stats_type), intent(out) :: stats
      type(status_type), intent(out) :: stat
      class(scheme_type), allocatable :: scheme
      call new_scheme(scheme_name, scheme, stat)
      if (stat%code /= status_ok) return
      call integrate(problem, scheme, t0, t_end, u, options, stats, stat)
   end subroutine integrate_member

end module taylorode_integrate_ensemble
