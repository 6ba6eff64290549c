!> Ensembles over MPI ranks: every rank holds the same members (problems and initial
!> states), the members are shared out over the ranks, and every rank ends with every
!> member's result.
!>
!> Members differ in cost (a stiff member can take a hundred times the steps of a
!> mild one), so the default hands them out dynamically: a counter in an MPI window on
!> rank 0 that each rank increments atomically (MPI_Fetch_and_op) whenever it is free,
!> no rank sitting idle as a master. Members may come with cost estimates; they are
!> then handed out most expensive first, which keeps the last members small. The
!> cyclic split (member k to rank mod(k - 1, ranks)) is there for comparison.
!>
!> Each member is integrated exactly as `integrate` integrates it alone (with a scheme
!> object of its own), so the results do not depend on the number of ranks, on the
!> schedule or on which rank took which member: `-np 1` and `-np 4` return the same
!> bits.
module taylorode_mpi_ensemble
   use, intrinsic :: iso_c_binding, only: c_ptr, c_f_pointer
   use mpi_f08, only: MPI_Comm, MPI_Win, MPI_COMM_WORLD, MPI_INFO_NULL, MPI_INTEGER8, MPI_INTEGER, &
      MPI_DOUBLE_PRECISION, MPI_SUM, MPI_ADDRESS_KIND, MPI_Comm_rank, MPI_Comm_size, MPI_Win_allocate, &
      MPI_Win_lock_all, MPI_Win_unlock_all, MPI_Win_sync, MPI_Win_flush, MPI_Win_free, MPI_Fetch_and_op, &
      MPI_Barrier, MPI_Allgather, MPI_Allgatherv, MPI_Allreduce, MPI_MAX, MPI_IN_PLACE, MPI_SUCCESS
   use taylorode, only: dp, i8, ode_problem, scheme_type, new_scheme, integrate, integrator_options_type, &
      integration_stats_type, status_type, status_ok, status_size_mismatch, status_invalid_argument
   implicit none
   private

   public :: distribute_ensemble, ensemble_load_type, schedule_dynamic, schedule_cyclic

   !> Members handed out one at a time to whichever rank is free (the default)
   integer, parameter :: schedule_dynamic = 1
   !> Member k to rank mod(k - 1, ranks), decided in advance
   integer, parameter :: schedule_cyclic = 2
   !> Characters of a member's status message carried to the other ranks
   integer, parameter :: message_length = 400

   !> How the work fell on the ranks
   type :: ensemble_load_type
      !> Members each rank integrated (index: rank + 1)
      integer, allocatable :: members(:)
      !> Wall-clock seconds each rank spent integrating its members
      real(dp), allocatable :: busy_seconds(:)
      !> Wall-clock seconds of the whole call (the slowest rank's)
      real(dp) :: wall_seconds = 0.0_dp
   contains
      !> Largest busy time over the mean busy time (1: perfect balance)
      procedure :: imbalance
   end type ensemble_load_type

contains

   !> Integrate every member k (problems(k) from u(:, k), t0 to t_end, the scheme
   !> `scheme_name`, the same options) with the members shared out over the ranks of
   !> `comm`; every rank must call it with the same arguments. On return every rank
   !> holds every member's final state u(:, k), statistics stats(k) and outcome
   !> member_stat(k), the same bits whatever the ranks and the schedule. stat is ok
   !> when every member succeeded, else it carries the code of the first that failed;
   !> arguments that do not fit (sizes, an unknown scheme or schedule, an MPI error)
   !> are reported in stat and every member_stat, and nothing is integrated.
   subroutine distribute_ensemble(problems, scheme_name, t0, t_end, u, options, stats, member_stat, stat, comm, &
      schedule, cost, load)
      !> One problem object per member (the same on every rank)
      class(ode_problem), intent(inout) :: problems(:)
      !> The scheme of every member
      character(len=*), intent(in) :: scheme_name
      !> Initial and final time of every member
      real(dp), intent(in) :: t0, t_end
      !> Initial states on entry, final (or last good) states on exit, u(:, k) for member k
      real(dp), intent(inout) :: u(:, :)
      !> Tolerances, controller and limits of every member
      type(integrator_options_type), intent(in) :: options
      !> Statistics of each member
      type(integration_stats_type), intent(out) :: stats(:)
      !> Outcome of each member
      type(status_type), intent(out) :: member_stat(:)
      !> Outcome of the ensemble
      type(status_type), intent(out) :: stat
      !> Communicator of the ranks that share the work (default MPI_COMM_WORLD)
      type(MPI_Comm), intent(in), optional :: comm
      !> schedule_dynamic (default) or schedule_cyclic
      integer, intent(in), optional :: schedule
      !> Estimated cost of each member (any unit): handed out most expensive first
      real(dp), intent(in), optional :: cost(:)
      !> How the work fell on the ranks
      type(ensemble_load_type), intent(out), optional :: load
      type(MPI_Comm) :: communicator
      class(scheme_type), allocatable :: scheme
      integer, allocatable :: order(:), done(:)
      integer :: rank, ranks, members, chosen_schedule, done_count, failed, first_failed, error_code
      integer(i8) :: start, finish, rate
      real(dp) :: busy, wall(1)
      character(len=120) :: summary

      communicator = MPI_COMM_WORLD
      if (present(comm)) communicator = comm
      chosen_schedule = schedule_dynamic
      if (present(schedule)) chosen_schedule = schedule
      members = size(problems)
      call system_clock(start, rate)

      if (size(u, 2) /= members .or. size(stats) /= members .or. size(member_stat) /= members) then
         call set_all(status_size_mismatch, "distribute_ensemble: u must have one column, stats and member_stat "// &
            "one entry per problem")
         return
      end if
      if (present(cost)) then
         if (size(cost) /= members) then
            call set_all(status_size_mismatch, "distribute_ensemble: cost must have one entry per problem")
            return
         end if
      end if
      if (chosen_schedule /= schedule_dynamic .and. chosen_schedule /= schedule_cyclic) then
         call set_all(status_invalid_argument, "distribute_ensemble: schedule must be schedule_dynamic or "// &
            "schedule_cyclic")
         return
      end if
      call new_scheme(scheme_name, scheme, stat)
      if (stat%code /= status_ok) then
         member_stat = stat
         return
      end if
      call MPI_Comm_rank(communicator, rank, error_code)
      if (error_code == MPI_SUCCESS) call MPI_Comm_size(communicator, ranks, error_code)
      if (error_code /= MPI_SUCCESS) then
         call set_all(status_invalid_argument, "distribute_ensemble: the communicator cannot be used")
         return
      end if

      order = handout_order(members, cost)
      allocate (done(0))
      busy = 0.0_dp
      if (chosen_schedule == schedule_cyclic) then
         call run_cyclic()
      else
         call run_dynamic()
      end if
      done_count = size(done)
      call share_results()

      call system_clock(finish)
      if (present(load)) then
         allocate (load%members(ranks), load%busy_seconds(ranks))
         call MPI_Allgather(done_count, 1, MPI_INTEGER, load%members, 1, MPI_INTEGER, communicator)
         call MPI_Allgather(busy, 1, MPI_DOUBLE_PRECISION, load%busy_seconds, 1, MPI_DOUBLE_PRECISION, communicator)
         wall(1) = real(finish - start, dp)/real(max(rate, 1_i8), dp)
         call MPI_Allreduce(MPI_IN_PLACE, wall, 1, MPI_DOUBLE_PRECISION, MPI_MAX, communicator)
         load%wall_seconds = wall(1)
      end if

      failed = count(member_stat%code /= status_ok)
      if (failed == 0) return
      first_failed = findloc(member_stat%code /= status_ok, .true., dim=1)
      write (summary, '("distribute_ensemble: ", i0, " of ", i0, " members failed; the first, member ", i0, ": ")') &
         failed, members, first_failed
      stat%code = member_stat(first_failed)%code
      stat%message = trim(summary)//" "//message_of(member_stat(first_failed))

   contains

      !> The same failure in stat and in every member_stat.
      subroutine set_all(code, message)
         integer, intent(in) :: code
         character(len=*), intent(in) :: message
         stat%code = code
         stat%message = message
         member_stat = stat
      end subroutine set_all

      !> Members order(rank + 1), order(rank + 1 + ranks), ...
      subroutine run_cyclic()
         integer :: position
         do position = rank + 1, members, ranks
            call run_member(order(position))
         end do
      end subroutine run_cyclic

      !> Members in the order of `order`, each to the rank that draws its position from
      !> the shared counter.
      subroutine run_dynamic()
         type(MPI_Win) :: window
         type(c_ptr) :: base
         integer(i8), pointer :: counter
         integer(i8) :: drawn
         integer(MPI_ADDRESS_KIND) :: window_bytes
         window_bytes = merge(8_MPI_ADDRESS_KIND, 0_MPI_ADDRESS_KIND, rank == 0)
         call MPI_Win_allocate(window_bytes, 8, MPI_INFO_NULL, communicator, base, window)
         call MPI_Win_lock_all(0, window)
         if (rank == 0) then
            call c_f_pointer(base, counter)
            counter = 0
            call MPI_Win_sync(window)
         end if
         call MPI_Barrier(communicator)
         do
            call MPI_Fetch_and_op(1_i8, drawn, MPI_INTEGER8, 0, 0_MPI_ADDRESS_KIND, MPI_SUM, window)
            call MPI_Win_flush(0, window)
            if (drawn >= members) exit
            call run_member(order(drawn + 1))
         end do
         call MPI_Win_unlock_all(window)
         call MPI_Win_free(window)
      end subroutine run_dynamic

      !> Member k with a scheme object of its own, timed.
      subroutine run_member(k)
         integer, intent(in) :: k
         class(scheme_type), allocatable :: member_scheme
         integer(i8) :: member_start, member_finish
         call system_clock(member_start)
         call new_scheme(scheme_name, member_scheme, member_stat(k))
         if (member_stat(k)%code == status_ok) then
            call integrate(problems(k), member_scheme, t0, t_end, u(:, k), options, stats(k), member_stat(k))
         end if
         call system_clock(member_finish)
         busy = busy + real(member_finish - member_start, dp)/real(max(rate, 1_i8), dp)
         done = [done, k]
      end subroutine run_member

      !> Every rank's members to every rank: one record of 64-bit words per member
      !> (its index, status code, statistics, state and message, bit for bit).
      subroutine share_results()
         integer(i8), allocatable :: mine(:), everyone(:)
         integer, allocatable :: counts(:), displacements(:)
         integer :: record, stats_words, message_words, j, offset, k, r
         character(len=message_length) :: message
         stats_words = ceiling(real(storage_size(stats(1)))/64.0)
         message_words = message_length/8
         record = 2 + stats_words + size(u, 1) + message_words
         allocate (mine(record*done_count), counts(ranks), displacements(ranks))
         do j = 1, done_count
            k = done(j)
            offset = (j - 1)*record
            message = message_of(member_stat(k))
            mine(offset + 1) = k
            mine(offset + 2) = member_stat(k)%code
            mine(offset + 3:offset + 2 + stats_words) = transfer(stats(k), 0_i8, stats_words)
            offset = offset + 2 + stats_words
            mine(offset + 1:offset + size(u, 1)) = transfer(u(:, k), 0_i8, size(u, 1))
            offset = offset + size(u, 1)
            mine(offset + 1:offset + message_words) = transfer(message, 0_i8, message_words)
         end do
         call MPI_Allgather(record*done_count, 1, MPI_INTEGER, counts, 1, MPI_INTEGER, communicator)
         displacements(1) = 0
         do r = 2, ranks
            displacements(r) = displacements(r - 1) + counts(r - 1)
         end do
         allocate (everyone(sum(counts)))
         call MPI_Allgatherv(mine, record*done_count, MPI_INTEGER8, everyone, counts, displacements, MPI_INTEGER8, &
            communicator)
         do j = 1, size(everyone)/record
            offset = (j - 1)*record
            k = int(everyone(offset + 1))
            member_stat(k)%code = int(everyone(offset + 2))
            stats(k) = transfer(everyone(offset + 3:offset + 2 + stats_words), stats(k))
            offset = offset + 2 + stats_words
            u(:, k) = transfer(everyone(offset + 1:offset + size(u, 1)), 0.0_dp, size(u, 1))
            offset = offset + size(u, 1)
            message = transfer(everyone(offset + 1:offset + message_words), message)
            if (member_stat(k)%code /= status_ok) then
               member_stat(k)%message = trim(message)
            else if (allocated(member_stat(k)%message)) then
               deallocate (member_stat(k)%message)
            end if
         end do
      end subroutine share_results

   end subroutine distribute_ensemble

   !> Positions 1..members in handout order: by decreasing cost (ties and no costs: by index).
   pure function handout_order(members, cost) result(order)
      integer, intent(in) :: members
      real(dp), intent(in), optional :: cost(:)
      integer :: order(members)
      integer :: i, j, swap
      order = [(i, i = 1, members)]
      if (.not. present(cost)) return
      do i = 2, members
         do j = i, 2, -1
            if (cost(order(j - 1)) >= cost(order(j))) exit
            swap = order(j)
            order(j) = order(j - 1)
            order(j - 1) = swap
         end do
      end do
   end function handout_order

   !> The message of a status ("" when it has none).
   pure function message_of(stat) result(message)
      type(status_type), intent(in) :: stat
      character(len=:), allocatable :: message
      message = ""
      if (allocated(stat%message)) message = stat%message
   end function message_of

   !> Largest busy time over the mean (1 is perfect balance, 2 on two ranks means one did nothing).
   pure real(dp) function imbalance(self)
      !> The load
      class(ensemble_load_type), intent(in) :: self
      imbalance = maxval(self%busy_seconds)/max(sum(self%busy_seconds)/real(size(self%busy_seconds), dp), tiny(1.0_dp))
   end function imbalance

end module taylorode_mpi_ensemble
