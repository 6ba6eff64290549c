!> Tests of taylorode over MPI ranks, for any number of ranks (mpirun -np 1, 2, ...):
!> rank 0 prints "PASS name" or "FAIL name: why" per test and "N passed, N failed";
!> the exit status is 1 when a test failed.
!>
!> - ensemble-*: members shared out over the ranks (dynamic, cyclic, most expensive
!>   first) return the serial loop's states, statistics and messages bit for bit, a
!>   quarter of the members failing in three ways; each member is integrated once.
!> - distributed-*: a system of independent Van der Pol blocks split over the ranks
!>   takes the steps the whole system takes in one process: with explicit schemes and
!>   the max norm bit for bit (its norm is a maximum over the same numbers); with the
!>   RMS norm and an implicit scheme (whose Newton iterations then stop block by block)
!>   to within the tolerance.
program test_mpi
   use, intrinsic :: iso_fortran_env, only: output_unit
   use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Comm, MPI_Comm_rank, MPI_Comm_size, MPI_COMM_WORLD, &
      MPI_COMM_SELF, MPI_Allreduce, MPI_IN_PLACE, MPI_LOGICAL, MPI_LAND
   use taylorode, only: dp, i8, scheme_type, new_scheme, integrate, integrator_options_type, &
      integration_stats_type, status_type, status_ok, norm_max, norm_rms
   use taylorode_testset, only: new_van_der_pol
   use taylorode_mpi, only: distribute_ensemble, ensemble_load_type, schedule_dynamic, schedule_cyclic
   use test_mpi_problems, only: flaky_vdp_type, vdp_blocks_type
   implicit none

   integer :: rank, ranks, passed, failed

   call MPI_Init()
   call MPI_Comm_rank(MPI_COMM_WORLD, rank)
   call MPI_Comm_size(MPI_COMM_WORLD, ranks)
   passed = 0
   failed = 0

   call test_ensemble(schedule_dynamic, .false., "ensemble-dynamic")
   call test_ensemble(schedule_cyclic, .false., "ensemble-cyclic")
   call test_ensemble(schedule_dynamic, .true., "ensemble-most-expensive-first")
   call test_distributed("ex-t-1", norm_max, .true., "distributed-ex-t-1-max-norm")
   call test_distributed("ex-t-2", norm_max, .true., "distributed-ex-t-2-max-norm")
   call test_distributed("ex-t-2", norm_rms, .false., "distributed-ex-t-2-rms-norm")
   call test_distributed("i-t-2", norm_max, .false., "distributed-i-t-2")

   if (rank == 0) write (output_unit, '(i0, " passed, ", i0, " failed")') passed, failed
   call MPI_Finalize()
   if (failed > 0) stop 1, quiet=.true.

contains

   !> Whether `ok` holds on every rank; rank 0 reports it.
   subroutine report(ok, name, why)
      logical, intent(in) :: ok
      character(len=*), intent(in) :: name, why
      logical :: all_ok(1)
      all_ok(1) = ok
      call MPI_Allreduce(MPI_IN_PLACE, all_ok, 1, MPI_LOGICAL, MPI_LAND, MPI_COMM_WORLD)
      if (all_ok(1)) then
         passed = passed + 1
         if (rank == 0) write (output_unit, '("PASS ", a)') name
      else
         failed = failed + 1
         if (rank == 0) write (output_unit, '("FAIL ", a, ": ", a)') name, why
      end if
   end subroutine report

   !> 48 flaky members over the ranks against the serial loop on this rank.
   subroutine test_ensemble(schedule, with_cost, name)
      integer, intent(in) :: schedule
      logical, intent(in) :: with_cost
      character(len=*), intent(in) :: name
      integer, parameter :: members = 48
      type(flaky_vdp_type) :: problems(members), serial_problems(members)
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats(members), serial_stats(members)
      type(status_type) :: member_stat(members), serial_stat(members), stat
      type(ensemble_load_type) :: load
      class(scheme_type), allocatable :: scheme
      real(dp) :: u(2, members), serial_u(2, members), cost(members)
      logical :: same
      integer :: k

      options%rtol = 1.0e-5_dp
      options%atol = 1.0e-5_dp
      do k = 1, members
         problems(k)%van_der_pol_type = new_van_der_pol(5.0_dp + real(k, dp))
         problems(k)%failure = mod(k, 4)
         problems(k)%t_bad = 0.5_dp + 0.01_dp*k
         u(:, k) = problems(k)%u0
         cost(k) = real(mod(7*k, members), dp)
      end do
      serial_problems = problems
      serial_u = u
      do k = 1, members
         call new_scheme("si-t-2", scheme, stat)
         call integrate(serial_problems(k), scheme, 0.0_dp, 10.0_dp, serial_u(:, k), options, serial_stats(k), &
            serial_stat(k))
      end do
      if (with_cost) then
         call distribute_ensemble(problems, "si-t-2", 0.0_dp, 10.0_dp, u, options, stats, member_stat, stat, &
            schedule=schedule, cost=cost, load=load)
      else
         call distribute_ensemble(problems, "si-t-2", 0.0_dp, 10.0_dp, u, options, stats, member_stat, stat, &
            schedule=schedule, load=load)
      end if
      same = all(transfer(u, 0_i8, 2*members) == transfer(serial_u, 0_i8, 2*members))
      do k = 1, members
         same = same .and. member_stat(k)%code == serial_stat(k)%code .and. &
            message_of(member_stat(k)) == message_of(serial_stat(k)) .and. &
            stats(k)%accepted_steps == serial_stats(k)%accepted_steps .and. &
            stats(k)%rejected_steps() == serial_stats(k)%rejected_steps() .and. &
            stats(k)%work%g_evaluations == serial_stats(k)%work%g_evaluations
      end do
      call report(same .and. count(serial_stat%code /= status_ok) == 3*members/4 .and. &
         sum(load%members) == members .and. size(load%members) == ranks .and. stat%code == serial_stat(1)%code, &
         name, "results differ from the serial loop or members lost")
   end subroutine test_ensemble

   !> Blocks over the ranks (6 per rank) against all blocks in this rank alone.
   subroutine test_distributed(scheme_name, norm, bitwise, name)
      character(len=*), intent(in) :: scheme_name
      integer, intent(in) :: norm
      logical, intent(in) :: bitwise
      character(len=*), intent(in) :: name
      integer, parameter :: blocks_per_rank = 6
      type(vdp_blocks_type) :: part, whole
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats_part, stats_whole
      type(status_type) :: stat_part, stat_whole
      real(dp), allocatable :: u_part(:), u_whole(:), mine(:)
      logical :: ok
      character(len=200) :: why

      options%rtol = 1.0e-6_dp
      options%atol = 1.0e-6_dp
      options%norm = norm
      part%comm = MPI_COMM_WORLD
      part%first_block = rank*blocks_per_rank
      part%blocks = blocks_per_rank
      whole%comm = MPI_COMM_SELF
      whole%first_block = 0
      whole%blocks = ranks*blocks_per_rank
      u_part = initial_blocks(part)
      u_whole = initial_blocks(whole)
      call new_scheme(scheme_name, scheme, stat_part)
      call integrate(part, scheme, 0.0_dp, 3.0_dp, u_part, options, stats_part, stat_part)
      call new_scheme(scheme_name, scheme, stat_whole)
      call integrate(whole, scheme, 0.0_dp, 3.0_dp, u_whole, options, stats_whole, stat_whole)
      mine = u_whole(2*part%first_block + 1:2*(part%first_block + part%blocks))
      ok = stat_part%code == status_ok .and. stat_whole%code == status_ok
      if (bitwise) then
         ok = ok .and. all(transfer(u_part, 0_i8, size(u_part)) == transfer(mine, 0_i8, size(mine))) .and. &
            stats_part%accepted_steps == stats_whole%accepted_steps .and. &
            stats_part%rejected_steps() == stats_whole%rejected_steps()
      else
         ! Newton stopping block by block, or partial sums of squares in another order,
         ! change the numbers by far less than the tolerance 1e-6
         ok = ok .and. maxval(abs(u_part - mine)) <= 1.0e-6_dp
      end if
      write (why, '("steps ", i0, " against ", i0, ", largest difference ", es10.3)') stats_part%accepted_steps, &
         stats_whole%accepted_steps, maxval(abs(u_part - mine))
      call report(ok, name, trim(why))
   end subroutine test_distributed

   !> (2, 0) in every block, shifted a little by the block number.
   function initial_blocks(problem) result(u)
      type(vdp_blocks_type), intent(in) :: problem
      real(dp) :: u(2*problem%blocks)
      integer :: b
      do b = 1, problem%blocks
         u(2*b - 1) = 2.0_dp - 0.1_dp*real(problem%first_block + b - 1, dp)
         u(2*b) = 0.0_dp
      end do
   end function initial_blocks

   !> The message of a status ("" when it has none).
   function message_of(stat) result(message)
      type(status_type), intent(in) :: stat
      character(len=:), allocatable :: message
      message = ""
      if (allocated(stat%message)) message = stat%message
   end function message_of

end program test_mpi
