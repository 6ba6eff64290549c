!> Tests of the PETSc package for any number of ranks (mpirun -np 1, 2, ...): rank 0
!> prints "PASS name" or "FAIL name: why" per test and "N passed, N failed"; the exit
!> status is 1 when a test failed. Every rank also solves the whole problem alone with
!> the library's own schemes (banded Newton, LAPACK) to compare with.
program test_petsc
   use, intrinsic :: iso_fortran_env, only: output_unit
   use taylorode, only: dp, i8, scheme_type, new_scheme, integrate, integrate_fixed, integrator_options_type, &
      estimate_embedded, &
      integration_stats_type, status_type, status_ok, status_invalid_argument, reduce_max
   use taylorode_petsc, only: petsc_start, petsc_stop, reaction_diffusion_type, new_reaction_diffusion, &
      grid_taylor_type, new_grid_taylor, integrate_arkimex, arkimex_stats_type, table_imex_rk21, table_si_t_1
   use test_petsc_problems, only: shrinking_mode_type, new_shrinking_mode
   implicit none

   !> Interior points per direction of the comparisons
   integer, parameter :: points = 16
   !> Final time of the comparisons: the bump spreads and decays over a few diffusion times
   real(dp), parameter :: t_end = 0.02_dp

   type(status_type) :: stat
   integer :: passed, failed, rank

   passed = 0
   failed = 0
   call petsc_start(stat)
   if (stat%code /= status_ok) error stop "PETSc did not start"

   call test_agreement("si-t-2")
   call test_agreement("i-t-2")
   call test_second_order("si-t-2")
   call test_second_order("i-t-2")
   call test_first_order("si-t-1")
   call test_non_autonomous_refused()
   call test_arkimex_agreement(table_imex_rk21, "imex-rk21")
   call test_arkimex_agreement(table_si_t_1, "si-t-1")
   call test_arkimex_adaptive()

   if (rank == 0) write (output_unit, '(i0, " passed, ", i0, " failed")') passed, failed
   call petsc_stop()
   if (failed > 0) stop 1, quiet=.true.

contains

   !> Rank 0 reports a test (every rank passes the same verdict: it is computed from
   !> values gathered over the ranks).
   subroutine report(ok, name, why)
      logical, intent(in) :: ok
      character(len=*), intent(in) :: name, why
      if (ok) then
         passed = passed + 1
         if (rank == 0) write (output_unit, '("PASS ", a, ": ", a)') name, why
      else
         failed = failed + 1
         if (rank == 0) write (output_unit, '("FAIL ", a, ": ", a)') name, why
      end if
   end subroutine report

   !> The distributed scheme (matrix-free Newton-Krylov over the ranks) and the library's
   !> scheme of the same name (one rank, banded Newton, LAPACK) take the same adaptive
   !> steps on the reaction-diffusion problem and end at the same state. Both estimate
   !> the error by the embedded pair, and Newton stops when its increment is below 1e-4
   !> of the error weights (1e-8 here; the paper's test) in both, with different linear solvers:
   !> the states may differ by that much, far less than the tolerance 1e-4 by which a
   !> different step sequence or a different scheme would show.
   subroutine test_agreement(name)
      character(len=*), intent(in) :: name
      type(reaction_diffusion_type) :: distributed, alone
      type(grid_taylor_type) :: grid_scheme
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats_distributed, stats_alone
      type(status_type) :: stat_distributed, stat_alone
      real(dp), allocatable :: u(:), u_alone(:), whole(:)
      character(len=160) :: why
      real(dp) :: difference

      call new_reaction_diffusion(distributed, points, points, .false., stat_distributed)
      call new_reaction_diffusion(alone, points, points, .true., stat_alone)
      rank = distributed%grid%rank
      options%rtol = 1.0e-4_dp
      options%atol = 1.0e-4_dp
      options%error_estimate = estimate_embedded
      options%newton_fraction = 1.0e-4_dp
      options%newton_error_estimate = .false.
      allocate (u(distributed%grid%owned), u_alone(alone%grid%owned), whole(points*points))
      call distributed%initial_state(u)
      call alone%initial_state(u_alone)
      call new_grid_taylor(name, grid_scheme, stat_distributed)
      call integrate(distributed, grid_scheme, 0.0_dp, t_end, u, options, stats_distributed, stat_distributed)
      call new_scheme(name, scheme, stat_alone)
      call integrate(alone, scheme, 0.0_dp, t_end, u_alone, options, stats_alone, stat_alone)
      call distributed%grid%gather(u, whole)
      difference = maxval(abs(whole - u_alone))
      write (why, '(a, " / ", a, ", steps ", i0, " + ", i0, " against ", i0, " + ", i0, ", largest difference ", &
         &es9.2)') status_text(stat_distributed), status_text(stat_alone), stats_distributed%accepted_steps, &
         stats_distributed%rejected_steps(), stats_alone%accepted_steps, stats_alone%rejected_steps(), difference
      call report(stat_distributed%code == status_ok .and. stat_alone%code == status_ok .and. &
         stats_distributed%accepted_steps == stats_alone%accepted_steps .and. &
         stats_distributed%rejected_steps() == stats_alone%rejected_steps() .and. difference <= 1.0e-8_dp, &
         "agreement-with-serial-"//name, trim(why))
      call grid_scheme%destroy()
      call distributed%destroy()
      call alone%destroy()
   end subroutine test_agreement

   !> A problem not declared autonomous is refused with a message (these schemes do not
   !> difference F in t), not advanced to first order.
   subroutine test_non_autonomous_refused()
      type(reaction_diffusion_type) :: problem
      type(grid_taylor_type) :: grid_scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:)
      call new_reaction_diffusion(problem, points, points, .false., stat)
      problem%autonomous = .false.
      allocate (u(problem%grid%owned))
      call problem%initial_state(u)
      call new_grid_taylor("si-t-2", grid_scheme, stat)
      call integrate(problem, grid_scheme, 0.0_dp, t_end, u, options, stats, stat)
      call report(stat%code == status_invalid_argument .and. index(stat%message, "autonomous") > 0, &
         "non-autonomous-refused", status_text(stat))
      call grid_scheme%destroy()
      call problem%destroy()
   end subroutine test_non_autonomous_refused

   !> Fixed steps of the distributed scheme on the shrinking mode, whose exact solution
   !> is known: the error falls by 4 when h halves (observed order in [1.9, 2.2] from 80 to
   !> 160 steps, where the errors are ~1e-5, far above Newton's 1e-13).
   subroutine test_second_order(name)
      character(len=*), intent(in) :: name
      real(dp) :: errors(3), order
      character(len=120) :: why
      call fixed_step_errors(name, errors)
      order = log(errors(2)/errors(3))/log(2.0_dp)
      write (why, '("errors ", 3es10.2, ", observed order ", f6.3)') errors, order
      call report(order >= 1.9_dp .and. order <= 2.2_dp, "second-order-"//name, trim(why))
   end subroutine test_second_order

   !> The first-order member: observed order in [0.9, 1.1].
   subroutine test_first_order(name)
      character(len=*), intent(in) :: name
      real(dp) :: errors(3), order
      character(len=120) :: why
      call fixed_step_errors(name, errors)
      order = log(errors(2)/errors(3))/log(2.0_dp)
      write (why, '("errors ", 3es10.2, ", observed order ", f6.3)') errors, order
      call report(order >= 0.9_dp .and. order <= 1.1_dp, "first-order-"//name, trim(why))
   end subroutine test_first_order

   !> Max-norm errors at t = 0.2 against the exact solution after 40, 80 and 160 fixed
   !> steps (i-t-2's Newton iteration needs h below 0.01 on this problem).
   subroutine fixed_step_errors(name, errors)
      character(len=*), intent(in) :: name
      real(dp), intent(out) :: errors(3)
      real(dp), parameter :: t_final = 0.2_dp
      type(shrinking_mode_type) :: problem
      type(grid_taylor_type) :: scheme
      real(dp), allocatable :: u(:), exact(:)
      real(dp) :: largest(1)
      integer :: k
      call new_shrinking_mode(problem, points, stat)
      rank = problem%grid%rank
      call new_grid_taylor(name, scheme, stat)
      allocate (u(problem%grid%owned), exact(problem%grid%owned))
      call problem%exact(t_final, exact)
      do k = 1, 3
         call problem%exact(0.0_dp, u)
         call integrate_fixed(problem, scheme, 0.0_dp, t_final, 40*2**(k - 1), u, stat)
         largest(1) = maxval(abs(u - exact))
         if (stat%code /= status_ok) largest(1) = huge(1.0_dp)
         call problem%reduce(reduce_max, largest)
         errors(k) = largest(1)
      end do
      call scheme%destroy()
      call problem%destroy()
   end subroutine fixed_step_errors

   !> PETSc's TSARKIMEX with the registered table, in fixed steps over the ranks, against
   !> the library's scheme of the same name in fixed steps on one rank: the same method, so
   !> the states agree to the stage equations' tolerance (SNES to 1e-12 relative; 1e-9
   !> absolute after 20 steps leaves a margin of ~100).
   subroutine test_arkimex_agreement(table, name)
      character(len=*), intent(in) :: table, name
      integer, parameter :: steps = 20
      type(reaction_diffusion_type) :: distributed, alone
      class(scheme_type), allocatable :: scheme
      type(arkimex_stats_type) :: ts_stats
      type(status_type) :: stat_ts, stat_alone
      real(dp), allocatable :: u(:), u_alone(:), whole(:)
      character(len=160) :: why
      real(dp) :: difference
      call new_reaction_diffusion(distributed, points, points, .false., stat_ts)
      call new_reaction_diffusion(alone, points, points, .true., stat_alone)
      rank = distributed%grid%rank
      allocate (u(distributed%grid%owned), u_alone(alone%grid%owned), whole(points*points))
      call distributed%initial_state(u)
      call alone%initial_state(u_alone)
      call integrate_arkimex(distributed, table, 0.0_dp, t_end, t_end/steps, .false., 0.0_dp, 0.0_dp, 1.0e-12_dp, u, &
         ts_stats, stat_ts)
      call new_scheme(name, scheme, stat_alone)
      call integrate_fixed(alone, scheme, 0.0_dp, t_end, steps, u_alone, stat_alone)
      call distributed%grid%gather(u, whole)
      difference = maxval(abs(whole - u_alone))
      write (why, '(a, " / ", a, ", ", i0, " TS steps, largest difference ", es9.2)') status_text(stat_ts), &
         status_text(stat_alone), ts_stats%steps, difference
      call report(stat_ts%code == status_ok .and. stat_alone%code == status_ok .and. ts_stats%steps == steps .and. &
         difference <= 1.0e-9_dp, "arkimex-table-"//name, trim(why))
      call distributed%destroy()
      call alone%destroy()
   end subroutine test_arkimex_agreement

   !> PETSc's adaptive controller runs the registered imex-rk21 table to the end on the
   !> shrinking mode; its error against the exact solution stays within 100 times the
   !> tolerance 1e-5 (error per step control over ~tens of steps).
   subroutine test_arkimex_adaptive()
      real(dp), parameter :: t_final = 0.2_dp, tolerance = 1.0e-5_dp
      type(shrinking_mode_type) :: problem
      type(arkimex_stats_type) :: ts_stats
      real(dp), allocatable :: u(:), exact(:)
      real(dp) :: largest(1)
      character(len=160) :: why
      call new_shrinking_mode(problem, points, stat)
      rank = problem%grid%rank
      allocate (u(problem%grid%owned), exact(problem%grid%owned))
      call problem%exact(0.0_dp, u)
      call integrate_arkimex(problem, table_imex_rk21, 0.0_dp, t_final, 1.0e-4_dp, .true., tolerance, tolerance, &
         1.0e-10_dp, u, ts_stats, stat)
      call problem%exact(t_final, exact)
      largest(1) = maxval(abs(u - exact))
      call problem%reduce(reduce_max, largest)
      write (why, '(a, ", ", i0, " steps, ", i0, " rejected, error ", es9.2)') status_text(stat), ts_stats%steps, &
         ts_stats%rejected, largest(1)
      call report(stat%code == status_ok .and. ts_stats%steps > 1 .and. largest(1) <= 100.0_dp*tolerance, &
         "arkimex-adaptive-imex-rk21", trim(why))
      call problem%destroy()
   end subroutine test_arkimex_adaptive

   !> "ok" or the status message.
   function status_text(stat) result(text)
      type(status_type), intent(in) :: stat
      character(len=:), allocatable :: text
      text = "ok"
      if (stat%code /= status_ok) then
         text = "failed"
         if (allocated(stat%message)) text = stat%message
      end if
   end function status_text

end program test_petsc
