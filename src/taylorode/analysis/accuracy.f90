!> Accuracy against the tolerance ("tolerance proportionality", as the stiff-solver
!> literature reports it): a scheme runs a test-set problem at a tolerance, and its
!> error is measured in the tolerance's own units, at t_end and on an output grid
!> (its dense output), against a reference computed by radau5 at a tight tolerance
!> stepping to each output time (no dense output in the reference).
!>
!> The measure is the one the error weights define: max_i |u_i - ref_i| / (atol_i +
!> rtol |ref_i|), with rtol = tol and atol = tol times the problem's recommended
!> atol/rtol (as work_precision scales it), so that 1 means "as accurate as asked";
!> the components that must stay >= 0 are declared so (options%nonnegative) where
!> the problem says they are concentrations.
module taylorode_analysis_accuracy
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_integrate_options, only: integrator_options_type
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrate, integrator_type
   use taylorode_testset_test_problem, only: test_problem_type
   use taylorode_testset_registry, only: new_test_problem
   use taylorode_testset_robertson, only: new_robertson
   use taylorode_analysis_work_precision, only: tolerance_scale
   implicit none
   private

   public :: accuracy_case_type, accuracy_point_type, new_accuracy_case, accuracy_reference, accuracy_run
   public :: accuracy_case_names

   !> The cases: the problems of the test set with their standard data (Robertson also
   !> to t = 1e11); the transistor amplifier has a mass matrix, which only radau5 solves
   character(len=*), parameter :: accuracy_case_names(*) = [character(len=17) :: "vdp", "vdp-stiff", &
      "robertson", "robertson-1e11", "hires", "orego", "e5", "brusselator", "prothero-robinson", "pollution", &
      "medakzo", "transamp"]
   !> Tolerance of the reference runs (radau5), and of problems with a jump in time,
   !> where a tighter one cannot step across it
   real(dp), parameter :: reference_rtol = 1.0e-12_dp, reference_rtol_jump = 1.0e-10_dp
   !> Tolerance of the reference run of the transistor amplifier: from 1e-10 on, Newton's
   !> tolerance on its algebraic equations falls below what double precision resolves
   !> there (a rounding of the transistor currents, ~1e-2 eps, over the conductances
   !> 1/R ~ 1e-4 is ~2e-14 V) and the steps collapse where the input peaks
   real(dp), parameter :: reference_rtol_dae = 1.0e-9_dp

   !> One problem as the accuracy runs see it
   type :: accuracy_case_type
      !> Case name (see accuracy_case_names)
      character(len=:), allocatable :: name
      !> The problem, with its standard data
      class(test_problem_type), allocatable :: problem
      !> Output times, from t0 to t_end
      real(dp), allocatable :: t_out(:)
      !> Errors are measured at output times up to this one (E5: its reference is
      !> well conditioned to t = 1e8 only); t_end's error only when it is t_end
      real(dp) :: judged_until = huge(1.0_dp)
      !> Where the right-hand side jumps in time (0: nowhere): the reference stops there
      real(dp) :: jump = 0.0_dp
      !> Whether the output times before a relaxation jump are left out (Van der Pol:
      !> the last one before each jump of y, where the phase error of the jump is
      !> multiplied by the speed of the solution at the fold, 1e2 to 1e4 times what it
      !> weighs at t_end on a slow branch)
      logical :: skip_before_jumps = .false.
      !> Whether each output time is judged (set by accuracy_reference)
      logical, allocatable :: judged(:)
      !> The reference solution at the output times
      real(dp), allocatable :: reference(:, :)
      !> The reference's error at t_end against the published solution, in the
      !> tolerance units of the tightest accuracy run (1e-8; -1 without a published one,
      !> or when t_end is not judged)
      real(dp) :: reference_check = -1.0_dp
   end type accuracy_case_type

   !> One run: a scheme at a tolerance on a case
   type :: accuracy_point_type
      !> Scheme
      character(len=16) :: scheme = ""
      !> Tolerance (rtol; atol = tol times the problem's atol/rtol)
      real(dp) :: tol = 0.0_dp
      !> Status code of the run
      integer :: status = status_ok
      !> Accepted steps and attempts rejected or failed
      integer(i8) :: accepted = 0, rejected = 0
      !> Error at t_end and the largest on the output grid, in tolerance units (-1 when
      !> the run failed or t_end is not judged)
      real(dp) :: error_end = -1.0_dp, error_grid = -1.0_dp
      !> Output time of the largest grid error
      real(dp) :: t_worst = 0.0_dp
   end type accuracy_point_type

contains

   !> The case `name` (one of accuracy_case_names): its problem, output grid and what
   !> is judged. status_invalid_argument for an unknown name.
   subroutine new_accuracy_case(name, case, stat)
      !> Case name
      character(len=*), intent(in) :: name
      !> The case (no reference yet)
      type(accuracy_case_type), intent(out) :: case
      !> Outcome
      type(status_type), intent(out) :: stat
      integer :: k, decades
      real(dp) :: t_end

      case%name = name
      select case (name)
      case ("robertson-1e11")
         allocate (case%problem, source=new_robertson(1.0e11_dp))
         stat%code = status_ok
      case default
         call new_test_problem(name, case%problem, stat)
         if (stat%code /= status_ok .or. .not. any(accuracy_case_names == name)) then
            call set_status(stat, status_invalid_argument, 'accuracy: unknown case "'//name//'"')
            return
         end if
      end select
      t_end = case%problem%t_end
      select case (name)
      case ("vdp", "vdp-stiff")
         ! the peer harness's grid: t = 0, 10, ..., 3000
         case%t_out = [(t_end*real(k, dp)/300.0_dp, k=0, 300)]
         case%skip_before_jumps = .true.
      case ("robertson", "robertson-1e11", "e5")
         ! every decade from 1e-5 on (the solutions change on every time scale)
         decades = nint(log10(t_end)) + 5
         case%t_out = [0.0_dp, (10.0_dp**(k - 5), k=0, decades)]
         case%t_out(size(case%t_out)) = t_end
         if (name == "e5") case%judged_until = 1.0e8_dp
      case ("medakzo")
         ! 40 intervals, midpoints: no output time at the jump of the boundary value
         case%t_out = [0.0_dp, (t_end*(real(k, dp) - 0.5_dp)/40.0_dp, k=1, 40), t_end]
         case%jump = 5.0_dp
      case default
         case%t_out = [(t_end*real(k, dp)/40.0_dp, k=0, 40)]
      end select
   end subroutine new_accuracy_case

   !> The reference solution at the output times: radau5 at rtol 1e-12 (1e-10 for a
   !> problem with a jump, restarted there; 1e-9 for the transistor amplifier's DAE),
   !> stepping to each output time; and its check against the published solution at t_end.
   subroutine accuracy_reference(case, stat)
      !> The case
      type(accuracy_case_type), intent(inout) :: case
      !> Outcome of the reference run
      type(status_type), intent(out) :: stat
      class(scheme_type), allocatable :: scheme
      type(integrator_type) :: integrator
      type(integrator_options_type) :: options
      real(dp), allocatable :: u(:)
      real(dp) :: rtol, atol
      integer :: k, n

      n = size(case%problem%u0)
      allocate (case%reference(n, size(case%t_out)))
      rtol = merge(reference_rtol_jump, reference_rtol, case%jump > 0.0_dp)
      if (case%problem%has_mass) rtol = reference_rtol_dae
      options = integrator_options_type(rtol=rtol, atol=rtol*tolerance_scale(case%problem), &
         max_steps=50000000_i8)
      if (case%problem%nonnegative) allocate (options%nonnegative(n), source=.true.)
      call new_scheme("radau5", scheme, stat)
      u = case%problem%u0
      call integrator%init(case%problem, scheme, case%problem%t0, u, options, stat)
      do k = 1, size(case%t_out)
         if (stat%code /= status_ok) return
         if (case%jump > case%t_out(max(k - 1, 1)) .and. case%jump < case%t_out(k)) &
            call integrator%advance_to(case%problem, scheme, case%jump, u, stat)
         if (stat%code /= status_ok) return
         if (case%t_out(k) > integrator%t) call integrator%advance_to(case%problem, scheme, case%t_out(k), u, stat)
         case%reference(:, k) = u
      end do
      if (stat%code /= status_ok) return
      case%judged = case%t_out <= case%judged_until
      if (case%skip_before_jumps) then
         do k = 1, size(case%t_out) - 1
            if (case%reference(1, k)*case%reference(1, k + 1) < 0.0_dp) case%judged(k) = .false.
         end do
      end if
      if (allocated(case%problem%reference) .and. case%judged_until >= case%problem%t_end) &
         case%reference_check = weighted_error(case, 1.0e-8_dp, case%reference(:, size(case%t_out)), &
         case%problem%reference)
   end subroutine accuracy_reference

   !> One run of `scheme_name` at `tol` with dense output at the case's output times,
   !> within `budget` attempted steps; its errors against the reference.
   subroutine accuracy_run(case, scheme_name, tol, budget, point)
      !> The case, with its reference
      type(accuracy_case_type), intent(inout) :: case
      !> Scheme
      character(len=*), intent(in) :: scheme_name
      !> Tolerance
      real(dp), intent(in) :: tol
      !> Attempted steps allowed
      integer(i8), intent(in) :: budget
      !> The result
      type(accuracy_point_type), intent(out) :: point
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:), u_out(:, :)
      real(dp) :: error
      integer :: k, n

      point%scheme = scheme_name
      point%tol = tol
      n = size(case%problem%u0)
      options = integrator_options_type(rtol=tol, atol=tol*tolerance_scale(case%problem), max_steps=budget)
      if (case%problem%nonnegative) allocate (options%nonnegative(n), source=.true.)
      call new_scheme(scheme_name, scheme, stat)
      if (stat%code /= status_ok) then
         point%status = stat%code
         return
      end if
      allocate (u_out(n, size(case%t_out)))
      u = case%problem%u0
      call integrate(case%problem, scheme, case%problem%t0, case%problem%t_end, u, options, stats, stat, &
         t_out=case%t_out, u_out=u_out)
      point%status = stat%code
      point%accepted = stats%accepted_steps
      point%rejected = stats%rejected_steps()
      if (stat%code /= status_ok) return
      if (case%judged_until >= case%problem%t_end) point%error_end = weighted_error(case, tol, u, &
         case%reference(:, size(case%t_out)))
      point%error_grid = 0.0_dp
      do k = 1, size(case%t_out)
         if (.not. case%judged(k)) cycle
         error = weighted_error(case, tol, u_out(:, k), case%reference(:, k))
         if (error > point%error_grid .or. .not. (error == error)) then
            point%error_grid = error
            point%t_worst = case%t_out(k)
         end if
      end do
   end subroutine accuracy_run

   !> max_i |u_i - ref_i| / (atol + tol |ref_i|), atol = tol times the problem's
   !> atol/rtol (NaN where u is NaN).
   pure real(dp) function weighted_error(case, tol, u, reference) result(error)
      type(accuracy_case_type), intent(in) :: case
      real(dp), intent(in) :: tol, u(:), reference(:)
      integer :: i
      real(dp) :: term
      error = 0.0_dp
      do i = 1, size(u)
         term = abs(u(i) - reference(i))/(tol*tolerance_scale(case%problem) + tol*abs(reference(i)))
         if (.not. (term <= error)) error = term
      end do
   end function weighted_error

end module taylorode_analysis_accuracy
