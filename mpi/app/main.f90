!> A Van der Pol parameter sweep over mu shared out over MPI ranks:
!>
!>   mpirun -np 2 taylorode-mpi-sweep [--members N] [--mu-max M] [--tend T] [--scheme NAME]
!>                                    [--schedule dynamic|cyclic] [--load]
!>
!> Members have mu spread logarithmically over [1, M] (default 32 members, M = 1000,
!> t in [0, 100], i-t-2, rtol = atol = 1e-6). Rank 0 prints one line per member (its
!> statistics and final state in full precision) and the totals: the same bytes for any
!> number of ranks and either schedule. --load adds to standard error how many members
!> and seconds each rank had, the imbalance and the wall-clock time.
program taylorode_mpi_sweep
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use mpi_f08, only: MPI_Init, MPI_Finalize, MPI_Comm_rank, MPI_COMM_WORLD
   use taylorode, only: dp, i8, integrator_options_type, integration_stats_type, status_type, status_ok, &
      status_name, scheme_names
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol
   use taylorode_mpi, only: distribute_ensemble, ensemble_load_type, schedule_dynamic, schedule_cyclic
   implicit none

   type(van_der_pol_type), allocatable :: problems(:)
   type(integrator_options_type) :: options
   type(integration_stats_type), allocatable :: stats(:)
   type(status_type), allocatable :: member_stat(:)
   type(status_type) :: stat
   type(ensemble_load_type) :: load
   real(dp), allocatable :: u(:, :), mu(:)
   integer :: members, schedule, rank, k, i
   real(dp) :: mu_max, t_end
   character(len=:), allocatable :: scheme, mistake
   logical :: show_load

   call MPI_Init()
   call MPI_Comm_rank(MPI_COMM_WORLD, rank)
   call read_command_line()
   if (len(mistake) > 0) then
      if (rank == 0) write (error_unit, '(a)') "taylorode-mpi-sweep: "//mistake
      call MPI_Finalize()
      stop 2, quiet=.true.
   end if

   allocate (problems(members), u(2, members), mu(members), stats(members), member_stat(members))
   do k = 1, members
      mu(k) = mu_max**(real(k - 1, dp)/real(max(members - 1, 1), dp))
      problems(k) = new_van_der_pol(mu(k))
      u(:, k) = problems(k)%u0
   end do
   options%rtol = 1.0e-6_dp
   options%atol = 1.0e-6_dp
   call distribute_ensemble(problems, scheme, 0.0_dp, t_end, u, options, stats, member_stat, stat, &
      schedule=schedule, load=load)

   if (rank == 0) then
      write (output_unit, '("# Van der Pol sweep: ", i0, " members, mu from 1 to ", es10.3, " (logarithmic), ", &
         &"t in [0, ", es10.3, "], ", a, ", rtol = atol = 1e-6")') members, mu_max, t_end, scheme
      write (output_unit, '("# member mu status accepted rejected f_evaluations g_evaluations ", &
         &"newton_iterations y z")')
      do k = 1, members
         write (output_unit, '(i0, 1x, es23.16, 1x, a, 5(1x, i0), 2(1x, es24.16e3))') k, mu(k), &
            underscored(status_name(member_stat(k)%code)), stats(k)%accepted_steps, stats(k)%rejected_steps(), &
            stats(k)%work%f_evaluations, stats(k)%work%g_evaluations, stats(k)%work%newton_iterations, u(:, k)
      end do
      write (output_unit, '("# totals: ", i0, " accepted steps, ", i0, " rejected, ", i0, " members failed")') &
         sum(stats%accepted_steps), sum(stats%rejected_steps()), count(member_stat%code /= status_ok)
      if (show_load) then
         write (error_unit, '("schedule ", a, ", ", i0, " ranks, wall ", f0.3, " s, imbalance ", f0.3)') &
            merge("dynamic", "cyclic ", schedule == schedule_dynamic), size(load%members), load%wall_seconds, &
            load%imbalance()
         do i = 1, size(load%members)
            write (error_unit, '("  rank ", i0, ": ", i0, " members, busy ", f0.3, " s")') i - 1, load%members(i), &
               load%busy_seconds(i)
         end do
      end if
   end if
   call MPI_Finalize()
   if (stat%code /= status_ok) stop 1, quiet=.true.

contains

   !> The options; `mistake` says what is wrong ("" when nothing is).
   subroutine read_command_line()
      character(len=256) :: arg, value
      integer :: position, io
      members = 32
      mu_max = 1000.0_dp
      t_end = 100.0_dp
      scheme = "i-t-2"
      schedule = schedule_dynamic
      show_load = .false.
      mistake = ""
      position = 1
      do while (position <= command_argument_count())
         call get_command_argument(position, arg)
         position = position + 1
         if (arg == "--load") then
            show_load = .true.
            cycle
         end if
         if (position > command_argument_count()) then
            mistake = "unknown option or missing value: "//trim(arg)
            return
         end if
         call get_command_argument(position, value)
         position = position + 1
         io = 0
         select case (arg)
         case ("--members")
            read (value, *, iostat=io) members
            if (io == 0 .and. members < 1) io = 1
         case ("--mu-max")
            read (value, *, iostat=io) mu_max
            if (io == 0 .and. .not. mu_max >= 1.0_dp) io = 1
         case ("--tend")
            read (value, *, iostat=io) t_end
            if (io == 0 .and. .not. t_end > 0.0_dp) io = 1
         case ("--scheme")
            scheme = trim(value)
            if (.not. any(scheme_names == scheme)) io = 1
         case ("--schedule")
            select case (value)
            case ("dynamic"); schedule = schedule_dynamic
            case ("cyclic"); schedule = schedule_cyclic
            case default; io = 1
            end select
         case default
            mistake = "unknown option "//trim(arg)//" (--members N, --mu-max M, --tend T, --scheme NAME, "// &
               "--schedule dynamic|cyclic, --load)"
            return
         end select
         if (io /= 0) then
            mistake = "bad value for "//trim(arg)//": "//trim(value)
            return
         end if
      end do
   end subroutine read_command_line

   !> A status name as one word ("Newton diverged" -> "Newton_diverged").
   pure function underscored(text) result(word)
      character(len=*), intent(in) :: text
      character(len=len(text)) :: word
      integer :: j
      word = text
      do j = 1, len(word)
         if (word(j:j) == " ") word(j:j) = "_"
      end do
   end function underscored

end program taylorode_mpi_sweep
