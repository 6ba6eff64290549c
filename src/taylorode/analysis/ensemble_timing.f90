!> What threads buy an ensemble: the same members integrated by `integrate_ensemble` on
!> one thread and on several, interleaved over repeats (these machines are noisy),
!> wall-clock medians, the speed-up, and whether every threaded run returned the
!> serial run's results bit for bit.
module taylorode_analysis_ensemble_timing
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_problem_ode, only: ode_problem
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_integrate_options, only: integrator_options_type
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_ensemble, only: integrate_ensemble, ensemble_threads
   use taylorode_analysis_work_precision, only: median
   implicit none
   private

   public :: ensemble_timing_type, time_ensemble

   !> Serial against threaded wall-clock time of one ensemble
   type :: ensemble_timing_type
      !> Members, threads of the threaded runs, repeats of each
      integer :: members = 0, threads = 1, repeats = 0
      !> Median wall-clock seconds on one thread and on `threads`
      real(dp) :: serial_seconds = 0.0_dp, threaded_seconds = 0.0_dp
      !> serial_seconds / threaded_seconds
      real(dp) :: speedup = 0.0_dp
      !> Whether every threaded run returned the serial run's states, statistics and
      !> status codes bit for bit
      logical :: identical = .false.
      !> Members that failed (the same in every run when identical)
      integer :: failed_members = 0
      !> Accepted steps of all members together
      integer(i8) :: accepted_steps = 0
   end type ensemble_timing_type

contains

   !> Integrate the ensemble (see integrate_ensemble) `repeats` times on one thread and
   !> as often on `threads` (0: as many as OpenMP gives), alternating, each run from
   !> fresh copies of the problems and of u0; wall-clock medians and the comparison
   !> go into `timing`. stat reports arguments that do not fit and copies that cannot
   !> be allocated (a failed member is a result, counted in timing%failed_members).
   subroutine time_ensemble(problems, scheme_name, t0, t_end, u0, options, threads, repeats, timing, stat)
      !> One problem per member, copied before every run
      class(ode_problem), intent(in) :: problems(:)
      !> The scheme of every member
      character(len=*), intent(in) :: scheme_name
      !> Initial and final time
      real(dp), intent(in) :: t0, t_end
      !> Initial states, u0(:, k) for member k
      real(dp), intent(in) :: u0(:, :)
      !> Tolerances, controller and limits of every member
      type(integrator_options_type), intent(in) :: options
      !> Threads of the threaded runs (0: OpenMP's maximum)
      integer, intent(in) :: threads
      !> Runs of each kind (>= 1)
      integer, intent(in) :: repeats
      !> Medians, speed-up and comparison
      type(ensemble_timing_type), intent(out) :: timing
      !> Arguments that do not fit (sizes, an unknown scheme, repeats or threads out of range)
      type(status_type), intent(out) :: stat
      class(ode_problem), allocatable :: copies(:)
      real(dp), allocatable :: u_serial(:, :), u_threaded(:, :)
      type(integration_stats_type), allocatable :: stats_serial(:), stats_threaded(:)
      type(status_type), allocatable :: member_serial(:), member_threaded(:)
      real(dp), allocatable :: serial_seconds(:), threaded_seconds(:)
      type(status_type) :: ensemble_stat
      class(scheme_type), allocatable :: scheme
      integer :: run, k

      if (repeats < 1 .or. threads < 0) then
         call set_status(stat, status_invalid_argument, "time_ensemble: repeats must be >= 1 and threads >= 0")
         return
      end if
      if (size(u0, 2) /= size(problems)) then
         call set_status(stat, status_size_mismatch, "time_ensemble: u0 must have one column per problem")
         return
      end if
      call new_scheme(scheme_name, scheme, stat)
      if (stat%code /= status_ok) return
      timing%members = size(problems)
      timing%repeats = repeats
      timing%threads = ensemble_threads()
      if (threads > 0) timing%threads = min(threads, timing%threads)
      allocate (serial_seconds(repeats), threaded_seconds(repeats))
      allocate (stats_serial(size(problems)), stats_threaded(size(problems)))
      allocate (member_serial(size(problems)), member_threaded(size(problems)))
      timing%identical = .true.
      do run = 1, repeats
         call timed(1, u_serial, stats_serial, member_serial, serial_seconds(run))
         if (stat%code /= status_ok) return
         call timed(timing%threads, u_threaded, stats_threaded, member_threaded, threaded_seconds(run))
         if (stat%code /= status_ok) return
         do k = 1, size(problems)
            timing%identical = timing%identical .and. &
               all(transfer(u_threaded(:, k), 0_i8, size(u0, 1)) == transfer(u_serial(:, k), 0_i8, size(u0, 1))) .and. &
               member_threaded(k)%code == member_serial(k)%code .and. &
               stats_threaded(k)%accepted_steps == stats_serial(k)%accepted_steps .and. &
               stats_threaded(k)%rejected_steps() == stats_serial(k)%rejected_steps()
         end do
      end do
      timing%serial_seconds = median(serial_seconds)
      timing%threaded_seconds = median(threaded_seconds)
      timing%speedup = timing%serial_seconds/max(timing%threaded_seconds, tiny(1.0_dp))
      timing%failed_members = count(member_serial%code /= status_ok)
      timing%accepted_steps = sum(stats_serial%accepted_steps)

   contains

      !> One run on `thread_count` threads from fresh copies; its wall-clock seconds.
      subroutine timed(thread_count, u, stats, member_stat, seconds)
         integer, intent(in) :: thread_count
         real(dp), allocatable, intent(inout) :: u(:, :)
         type(integration_stats_type), intent(inout) :: stats(:)
         type(status_type), intent(inout) :: member_stat(:)
         real(dp), intent(out) :: seconds
         integer(i8) :: start, finish, rate
         integer :: memory
         seconds = 0.0_dp
         if (allocated(copies)) deallocate (copies)
         allocate (copies, source=problems, stat=memory)
         if (memory == 0 .and. .not. allocated(u)) allocate (u(size(u0, 1), size(u0, 2)), stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "the members' copies and states", [size(u0, 1), size(u0, 2)], real_bytes)
            return
         end if
         u = u0
         call system_clock(start, rate)
         call integrate_ensemble(copies, scheme_name, t0, t_end, u, options, stats, member_stat, ensemble_stat, &
            thread_count)
         call system_clock(finish)
         seconds = real(finish - start, dp)/real(max(rate, 1_i8), dp)
      end subroutine timed

   end subroutine time_ensemble

end module taylorode_analysis_ensemble_timing
