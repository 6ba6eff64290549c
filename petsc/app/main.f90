!> The 2D reaction-diffusion problem distributed over the ranks, integrated by the
!> library's adaptive controller with a Taylor scheme whose steps PETSc solves
!> (matrix-free Newton-Krylov, multigrid): the driver of the weak-scaling table.
!>
!>   mpirun -np P taylorode-petsc-rd [--points N] [--scheme NAME] [--tend T] [--tol TOL]
!>                                   [--single-factor]
!>
!> The grid has N x (N P) interior points (N x N per rank; default N = 128) with spacing
!> 1/(N + 1) on [0, 1] x [0, P] (a bump in every unit square: every rank has the same
!> work), D = 1, kappa = 10, t in [0, T] (default 0.002), rtol = atol = TOL (default 1e-4), scheme
!> si-t-2 (or si-t-1, i-t-1, i-t-2). --single-factor preconditions the second-order
!> members with I - h J_g once instead of (I - h J_g / sqrt(2))^2. Rank 0 prints one
!> line: ranks, unknowns, steps, Newton and Krylov iterations, wall-clock seconds.
program taylorode_petsc_rd
   use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
   use taylorode, only: dp, i8, integrate, integrator_options_type, integration_stats_type, status_type, &
      status_ok, reduce_max
   use taylorode_petsc, only: petsc_start, petsc_stop, petsc_ranks, reaction_diffusion_type, &
      new_reaction_diffusion, grid_taylor_type, new_grid_taylor
   implicit none

   type(reaction_diffusion_type) :: problem
   type(grid_taylor_type) :: scheme
   type(integrator_options_type) :: options
   type(integration_stats_type) :: stats
   type(status_type) :: stat
   real(dp), allocatable :: u(:)
   real(dp) :: t_end, tolerance, seconds(1)
   integer :: points, ranks
   integer(i8) :: start, finish, rate
   character(len=:), allocatable :: scheme_name, mistake
   logical :: single_factor

   call petsc_start(stat)
   if (stat%code /= status_ok) error stop "taylorode-petsc-rd: PETSc did not start"
   call read_command_line()
   if (len(mistake) == 0) then
      ranks = petsc_ranks()
      call new_reaction_diffusion(problem, points, points*ranks, .false., stat, spacing=1.0_dp/real(points + 1, dp))
      if (stat%code == status_ok) call new_grid_taylor(scheme_name, scheme, stat)
      if (stat%code /= status_ok) mistake = stat%message
   end if
   if (len(mistake) > 0) then
      write (error_unit, '(a)') "taylorode-petsc-rd: "//mistake
      call petsc_stop()
      stop 2, quiet=.true.
   end if

   scheme%single_factor = single_factor
   options%rtol = tolerance
   options%atol = tolerance
   allocate (u(problem%grid%owned))
   call problem%initial_state(u)
   call system_clock(start, rate)
   call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, stat)
   call system_clock(finish)
   seconds(1) = real(finish - start, dp)/real(rate, dp)
   call problem%reduce(reduce_max, seconds)
   if (problem%grid%rank == 0) then
      write (output_unit, '("ranks ", i0, ", unknowns ", i0, " (", i0, " per rank), ", a, ", t in [0, ", es9.2, &
         &"], tol ", es8.1, ": ", i0, " steps + ", i0, " rejected, ", i0, " Newton iterations, ", i0, &
         &" Krylov iterations (", f0.1, " per solve), ", f0.2, " s, ", a)') ranks, problem%grid%points, &
         problem%grid%owned, scheme_name//merge(" (one factor)", "             ", single_factor), t_end, tolerance, &
         stats%accepted_steps, stats%rejected_steps(), stats%work%newton_iterations, scheme%krylov_iterations(), &
         real(scheme%krylov_iterations(), dp)/real(max(stats%work%linear_solves, 1_i8), dp), seconds(1), &
         merge("ok    ", "failed", stat%code == status_ok)
   end if
   call scheme%destroy()
   call problem%destroy()
   call petsc_stop()
   if (stat%code /= status_ok) stop 1, quiet=.true.

contains

   !> The options; `mistake` says what is wrong ("" when nothing is).
   subroutine read_command_line()
      character(len=256) :: arg, value
      integer :: position, io
      points = 128
      t_end = 0.002_dp
      tolerance = 1.0e-4_dp
      scheme_name = "si-t-2"
      single_factor = .false.
      mistake = ""
      position = 1
      do while (position <= command_argument_count())
         call get_command_argument(position, arg)
         position = position + 1
         if (arg == "--single-factor") then
            single_factor = .true.
            cycle
         end if
         call get_command_argument(position, value)
         position = position + 1
         io = 0
         select case (arg)
         case ("--points")
            read (value, *, iostat=io) points
            if (io == 0 .and. points < 3) io = 1
         case ("--tend")
            read (value, *, iostat=io) t_end
            if (io == 0 .and. .not. t_end > 0.0_dp) io = 1
         case ("--tol")
            read (value, *, iostat=io) tolerance
            if (io == 0 .and. .not. tolerance > 0.0_dp) io = 1
         case ("--scheme")
            scheme_name = trim(value)
         case default
            mistake = "unknown option "//trim(arg)//" (--points N, --scheme NAME, --tend T, --tol TOL, --single-factor)"
            return
         end select
         if (io /= 0) then
            mistake = "bad value for "//trim(arg)//": "//trim(value)
            return
         end if
      end do
   end subroutine read_command_line

end program taylorode_petsc_rd
