!> The procedural interface for legacy Fortran: plain subroutines that take the
!> user's external subroutines in the shape RADAU5 and ODEPACK users know, so that a
!> fixed-form program switches to taylorode by changing its CALL line.
!>
!>     CALL TAYLORODE(SCHEME, N, FCN, X, Y, XEND, H, RTOL, ATOL, ITOL, JAC, IJAC,
!>    &               MLJAC, MUJAC, MAS, IMAS, MLMAS, MUMAS, SOLOUT, IOUT,
!>    &               WORK, LWORK, IWORK, LIWORK, RPAR, IPAR, IDID)
!>
!> is RADAU5's argument list with the scheme's name in front: FCN(N, X, Y, F, RPAR,
!> IPAR) is the whole right-hand side (everything stiff), JAC(N, X, Y, DFY, LDFY,
!> RPAR, IPAR) its Jacobian (IJAC = 0: finite differences, JAC is not called), band
!> storage when MLJAC < N as RADAU5's (DFY(I - J + MUJAC + 1, J)), SOLOUT(NR, XOLD,
!> X, Y, CONT, LRC, N, RPAR, IPAR, IRTRN) called after every accepted step when IOUT
!> /= 0 (IRTRN < 0 stops; TAYLORODE_CONTR(I, S, CONT, LRC) interpolates component I at
!> S inside the step). TAYLORODE_SPLIT takes f and g apart: FCNF, FCNG, JACF (IJACF),
!> JACG (IJACG). RPAR and IPAR are passed to the user's routines untouched.
!>
!> IWORK(1:10) and WORK(1:9) are RADAU5's settings with RADAU5's defaults and checks
!> (an out-of-range value is IDID = -1, never a silent default; see the README for the
!> table and for what differs); TAYLORODE('radau5', ...) integrates as RADAU5 does
!> (RADAU5's tolerance transformation, RMS norm and step-size rules), the other schemes
!> keep the library's meaning of a tolerance. IWORK(11) = K > 0 makes IPAR(K) the
!> evaluation flag: set to 0 before every call of FCN or JAC, which sets it > 0 when it
!> cannot evaluate at the point given (the step is retried shorter) or < 0 to stop
!> (IDID = -7). Outputs: IWORK(12) the reason of a negative IDID (TAYLORODE_MESSAGE
!> turns it into a sentence), IWORK(13) the component or setting it concerns,
!> IWORK(14:20) RADAU5's statistics; X, Y where the integration stopped, H the next
!> step. IDID: 1 success, 2 stopped by SOLOUT, -1 inconsistent input or unknown scheme,
!> -2 step budget, -3 step size too small, -4 Newton matrix repeatedly singular, -5
!> Newton failed repeatedly (only with a failure limit, which the legacy entry does not
!> set), -6 NaN or Inf, -7 the problem rejected evaluations, -8 memory could not be
!> allocated (the Newton matrices of a large N, say).
module taylorode_interfaces_legacy
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, status_ok, status_singular_matrix, status_newton_diverged, &
      status_newton_not_converged, status_step_underflow, status_max_steps, status_nonfinite, &
      status_evaluation_failed, status_out_of_memory, set_status
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_linalg_matrix, only: matrix_structure_type, band_structure, storage_band
   use taylorode_problem_ode, only: ode_problem, dense_differences, band_differences, difference_f, difference_g, &
      difference_rhs, set_difference_rounding
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_schemes_radau5, only: radau5_type, describe_radau5
   use taylorode_integrate_options, only: integrator_options_type, norm_rms
   use taylorode_integrate_controller, only: controller_auto, controller_i
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrator_type
   use taylorode_integrate_step, only: accepted_step_type, hermite_degree
   use taylorode_integrate_observer, only: step_observer_type
   use taylorode_interfaces_legacy_entry, only: fcn_interface, jac_interface, mas_interface, solout_interface
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan, ieee_value, ieee_quiet_nan
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_funptr, c_f_procpointer, c_associated
   implicit none
   private

   public :: legacy_solve, legacy_interpolate, legacy_message, legacy_no_mass, fcn_interface, jac_interface, &
      mas_interface, solout_interface
   public :: legacy_solve_entry, legacy_interpolate_entry, legacy_message_entry

   !> Why a call ended with a negative IDID (IWORK(12)); legacy_message says it in words
   integer, parameter :: reason_none = 0, reason_storage = 1, reason_size = 2, reason_interval = 3, &
      reason_tolerance = 4, reason_uround = 5, reason_budget_setting = 6, reason_newton_setting = 7, &
      reason_index_sum = 8, reason_index_high = 9, reason_second_order = 10, reason_second_order_unsupported = 11, &
      reason_safety = 12, reason_jacobian_reuse = 13, reason_newton_stop = 14, reason_hold = 15, &
      reason_step_factors = 16, reason_largest_step = 17, reason_bandwidths = 18, reason_mass_bandwidths = 19, &
      reason_mass_scheme = 20, reason_scheme = 21, reason_flag = 22, reason_first_step = 23, reason_work_number = 24
   integer, parameter :: reason_budget = 31, reason_underflow = 32, reason_singular = 33, reason_newton = 34, &
      reason_nonfinite = 35, reason_evaluation = 36, reason_failed = 37, reason_memory = 38
   !> RADAU5's defaults: step budget NMAX, rounding unit, first step for H = 0, step-size
   !> factor bounds 1/FACL and 1/FACR
   integer, parameter :: default_budget = 100000
   real(dp), parameter :: default_uround = 1.0e-16_dp, default_first_step = 1.0e-6_dp
   real(dp), parameter :: default_min_shrink = 0.2_dp, default_max_growth = 8.0_dp

   !> The user's routines as an ode_problem
   type, extends(ode_problem) :: legacy_problem_type
      procedure(fcn_interface), pointer, nopass :: fcn_f => null(), fcn_g => null()
      procedure(jac_interface), pointer, nopass :: jac_f_user => null(), jac_g_user => null()
      !> Which parts and Jacobians the user gave
      logical :: has_f = .false., has_jac_f = .false., has_jac_g = .false.
      !> Structure of the Jacobians the user gives (dense unless bandwidths are set)
      type(matrix_structure_type) :: structure
      !> The user's RPAR and IPAR, passed through (views of their first entries, IPAR's up
      !> to the evaluation flag: contiguous, so that they reach the F77 routines as they are)
      real(dp), pointer, contiguous :: rpar(:) => null()
      integer, pointer, contiguous :: ipar(:) => null()
      !> IPAR(flag) is the evaluation flag (0: none)
      integer :: flag = 0
      !> The user's MAS, and the bandwidths of M as it gives it (n, n: dense)
      procedure(mas_interface), pointer, nopass :: mas => null()
      integer :: mass_lower = 0, mass_upper = 0
      !> Work arrays: the state (a copy, as F77 routines may write it), f when both parts
      !> are given, the Jacobian in the user's layout (both parts given), M as MAS gives it
      real(dp), allocatable :: x_state(:), g_work(:), jac_work(:, :), mass_work(:, :)
   contains
      procedure :: f => legacy_f
      procedure :: g => legacy_g
      procedure :: rhs => legacy_rhs
      procedure :: rhs_values => legacy_rhs_values
      procedure :: rhs_scratch => legacy_rhs_scratch
      procedure :: jac_f => legacy_jac_f
      procedure :: jac_g => legacy_jac_g
      procedure :: jac => legacy_jac
      procedure :: jacobian_structure => legacy_structure
      procedure :: jac_f_band => legacy_jac_f_band
      procedure :: jac_g_band => legacy_jac_g_band
      procedure :: jac_band => legacy_jac_band
      procedure :: jac_with_rhs => legacy_jac_with_rhs
      procedure :: jac_band_with_rhs => legacy_jac_band_with_rhs
      procedure :: mass_matrix => legacy_mass
      procedure :: mass_matrix_band => legacy_mass_band
   end type legacy_problem_type

   !> SOLOUT after every accepted step
   type, extends(step_observer_type) :: legacy_observer_type
      procedure(solout_interface), pointer, nopass :: solout => null()
      !> The user's RPAR and IPAR (as legacy_problem_type keeps them)
      real(dp), pointer, contiguous :: rpar(:) => null()
      integer, pointer, contiguous :: ipar(:) => null()
      integer :: calls = 0
      !> The step for TAYLORODE_CONTR: t_start, h, n, the degree d of the dense output, its
      !> nodes (room for max_degree) and coefficient columns 0 .. d (n each)
      real(dp), allocatable :: cont(:)
      !> Largest degree of the dense output (the scheme's own or the cubic Hermite one)
      integer :: max_degree = hermite_degree
      !> The copy of the state SOLOUT is given (it may write it)
      real(dp), allocatable :: y_copy(:)
      !> SOLOUT asked to stop
      logical :: stopped = .false.
      !> SOLOUT wrote Y (RADAU5 goes on from the state SOLOUT leaves)
      logical :: y_changed = .false.
   contains
      procedure :: observe => legacy_observe
   end type legacy_observer_type

contains

   !> The integration behind TAYLORODE and TAYLORODE_SPLIT (see the module comment):
   !> RADAU5's settings checked and mapped onto the library's options, the integration,
   !> and RADAU5's outputs. `message` (for callers in Fortran) says why when idid < 0.
   subroutine legacy_solve(scheme_name, n, fcn_f, fcn_g, has_f, x, y, xend, h, rtol, atol, itol, jac_f, ijac_f, &
      jac_g, ijac_g, mljac, mujac, mas, imas, mlmas, mumas, solout, iout, work, lwork, iwork, liwork, rpar, ipar, &
      idid, message)
      !> Scheme name, as users type it
      character(len=*), intent(in) :: scheme_name
      !> Unknowns
      integer, intent(in) :: n
      !> The non-stiff part (ignored when has_f is false) and the stiff part
      procedure(fcn_interface) :: fcn_f, fcn_g
      !> Whether fcn_f is given
      logical, intent(in) :: has_f
      !> Start time on entry, where the integration stopped on exit
      real(dp), intent(inout) :: x
      !> State at x
      real(dp), intent(inout) :: y(n)
      !> Final time, > x
      real(dp), intent(in) :: xend
      !> First step size guess on entry (0: RADAU5's 1e-6 for radau5, automatic for the
      !> others), the next one on exit
      real(dp), intent(inout) :: h
      !> Relative and absolute tolerances, scalars (itol = 0) or arrays of n (itol /= 0)
      real(dp), intent(in) :: rtol(*), atol(*)
      !> 0 for scalar tolerances, anything else for one per component
      integer, intent(in) :: itol
      !> Jacobians of f and g, used when ijac_f, ijac_g = 1
      procedure(jac_interface) :: jac_f, jac_g
      !> Whether jac_f and jac_g are given (1) or differences are used (0)
      integer, intent(in) :: ijac_f, ijac_g
      !> Lower and upper bandwidths of the Jacobians (mljac >= n: dense; else both in [0, n - 1])
      integer, intent(in) :: mljac, mujac
      !> The mass matrix routine (called once when imas /= 0)
      procedure(mas_interface) :: mas
      !> 0: M = I; otherwise M comes from mas (radau5 only)
      integer, intent(in) :: imas
      !> Bandwidths of M (mlmas = n: dense; else band storage, within the Jacobian's bands)
      integer, intent(in) :: mlmas, mumas
      !> Called after every accepted step when iout /= 0
      procedure(solout_interface) :: solout
      !> 0: never call solout
      integer, intent(in) :: iout
      !> Lengths of work and iwork (at least 20 each)
      integer, intent(in) :: lwork, liwork
      !> Real settings WORK(1:9) (see the module comment)
      real(dp), intent(inout) :: work(*)
      !> Integer settings IWORK(1:11) and outputs IWORK(12:20)
      integer, intent(inout) :: iwork(*)
      !> Real data passed to the user's routines untouched
      real(dp), intent(inout), target :: rpar(*)
      !> Integer data passed to the user's routines untouched
      integer, intent(inout), target :: ipar(*)
      !> Outcome
      integer, intent(out) :: idid
      !> Why the call failed (empty when idid > 0)
      character(len=:), allocatable, intent(out), optional :: message
      type(legacy_problem_type) :: problem
      type(legacy_observer_type) :: observer
      ! radau5, RADAU5's own scheme, is a local object (no heap allocation of 1.8 kB, whose
      ! malloc consolidated the allocator's free lists on every call); the others come
      ! from the registry
      type(radau5_type), target :: radau_scheme
      class(scheme_type), allocatable, target :: named_scheme
      class(scheme_type), pointer :: scheme
      type(integrator_options_type) :: options
      type(integrator_type) :: integrator
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      integer :: reason, detail, memory
      logical :: radau, refused, empty

      idid = -1
      if (present(message)) message = ""
      if (lwork < 20 .or. liwork < 20) then
         if (liwork >= 13) iwork(12:13) = [reason_storage, 0]
         if (present(message)) call legacy_message(reason_storage, 0, message)
         return
      end if
      iwork(12:13) = 0
      radau = trim(adjustl(scheme_name)) == "radau5"   ! (as new_scheme reads a name)
      empty = xend == x
      call read_settings(reason, detail)
      if (reason /= reason_none) then
         if (reason == reason_memory) idid = outcome_code(status_out_of_memory)
         call refuse(reason, detail, "")
         return
      end if

      problem%fcn_g => fcn_g
      problem%has_f = has_f
      if (has_f) problem%fcn_f => fcn_f
      problem%has_jac_f = ijac_f == 1
      problem%has_jac_g = ijac_g == 1
      if (problem%has_jac_f) problem%jac_f_user => jac_f
      if (problem%has_jac_g) problem%jac_g_user => jac_g
      if (mljac < n) problem%structure = band_structure(mljac, mujac)
      problem%rpar => rpar(1:1)
      problem%ipar => ipar(1:max(1, iwork(11)))
      problem%flag = iwork(11)
      allocate (problem%x_state(n), stat=memory)
      if (has_f .and. memory == 0) then
         allocate (problem%g_work(n), stat=memory)
         if (memory == 0) then
            if (problem%structure%storage == storage_band) then
               allocate (problem%jac_work(problem%structure%lower + problem%structure%upper + 1, n), stat=memory)
            else
               allocate (problem%jac_work(n, n), stat=memory)
            end if
         end if
      end if
      if (imas /= 0 .and. memory == 0) then
         problem%has_mass = .true.
         problem%mas => mas
         if (mlmas == n) then
            problem%mass_lower = n
            problem%mass_upper = n
            allocate (problem%mass_work(n, n), stat=memory)
         else
            problem%mass_lower = mlmas
            problem%mass_upper = mumas
            allocate (problem%mass_work(mlmas + mumas + 1, n), stat=memory)
         end if
      end if
      if (memory /= 0) then
         idid = outcome_code(status_out_of_memory)
         call refuse(reason_memory, 0, "")
         return
      end if

      call integrator%init(problem, scheme, x, y, options, stat)
      refused = stat%code /= status_ok
      if (.not. refused) then
         if (iout /= 0) then
            observer%solout => solout
            observer%rpar => problem%rpar
            observer%ipar => problem%ipar
            observer%max_degree = max(hermite_degree, scheme%dense_degree)
            ! LRC, an integer, must count CONT: beyond huge(0) it is as if out of memory
            memory = 1
            if (4_i8 + observer%max_degree + int(n, i8)*(observer%max_degree + 1) <= huge(0)) &
               allocate (observer%cont(4 + observer%max_degree + n*(observer%max_degree + 1)), observer%y_copy(n), &
               source=0.0_dp, stat=memory)
            if (memory /= 0) call out_of_memory(stat, "SOLOUT's copy of the step", [observer%max_degree + 2, n], &
               real_bytes)
            if (stat%code == status_ok) call start_solout(observer, x, y, n)
            ! (SOLOUT is given Y itself in RADAU5: what it writes there is the state)
            if (stat%code == status_ok) y = observer%y_copy
            if (observer%stopped) then
               idid = 2
               return
            end if
         end if
         if (stat%code == status_ok .and. empty) then
            ! RADAU5 takes X = XEND for a step too small (IDID = -3, H = 0)
            call set_status(stat, status_step_underflow, "X = XEND: there is no interval to integrate over")
         else if (stat%code == status_ok) then
            call advance_from_solout_changes()
         end if
      end if
      ! (a refusal of the integrator's leaves X and H as given, as RADAU5's refusals do)
      if (.not. refused) then
         x = integrator%total%t_reached
         h = merge(0.0_dp, integrator%h, empty)
      end if
      associate (total => integrator%total)
         iwork(14) = int(max(total%work%f_evaluations, total%work%g_evaluations))
         iwork(15) = int(max(total%work%jac_f_evaluations, total%work%jac_g_evaluations))
         ! RADAU5's NSTEP: the attempts whose matrices were factored
         iwork(16) = int(total%accepted_steps + total%rejected_steps() - total%rejected_singular)
         iwork(17) = int(total%accepted_steps)
         ! RADAU5's NREJCT: error-test rejections after the first accepted step
         iwork(18) = int(total%rejected_error - total%rejected_error_start)
         iwork(19) = int(total%work%lu_factorizations)
         ! RADAU5's NSOL: the solves of the Newton iterations, not the error estimate's
         iwork(20) = int(merge(total%work%newton_iterations, total%work%linear_solves, radau))
      end associate
      idid = outcome_code(stat%code)
      ! RADAU5 counts the attempt that finds the budget spent: NSTEP = NMAX + 1
      if (idid == -2) iwork(16) = iwork(16) + 1
      if (stat%code == status_ok .and. observer%stopped) idid = 2
      if (idid < 0) call refuse(outcome_reason(idid), 0, stat%message)

   contains

      !> advance_to XEND, and on again from each state SOLOUT writes (RADAU5 hands SOLOUT
      !> its Y; advance_to takes a changed state), within one budget of NMAX attempts.
      subroutine advance_from_solout_changes()
         integer(i8) :: budget, used
         budget = integrator%options%max_steps
         used = 0
         do
            if (iout /= 0) then
               call integrator%advance_to(problem, scheme, xend, y, stat, stats, observer=observer)
            else
               call integrator%advance_to(problem, scheme, xend, y, stat, stats)
            end if
            if (stat%code /= status_ok .or. .not. observer%y_changed) exit
            y = observer%y_copy
            observer%y_changed = .false.
            if (observer%stopped .or. integrator%total%t_reached >= xend) exit
            used = used + stats%accepted_steps + stats%rejected_steps()
            if (used >= budget) then
               call set_status(stat, status_max_steps, "the step budget NMAX ran out")
               exit
            end if
            integrator%options%max_steps = budget - used
         end do
         integrator%options%max_steps = budget
      end subroutine advance_from_solout_changes

      !> RADAU5's settings, checked as RADAU5 checks them, into the options and the scheme.
      subroutine read_settings(reason, detail)
         integer, intent(out) :: reason, detail
         real(dp) :: uround, rtol_i, atol_i, quotient, hmax, first_rtol, safe, thet, fnewt, quot1, quot2, facl, &
            facr, first
         integer :: i, components, nind(3), m1, m2
         type(status_type) :: scheme_stat

         detail = 0
         reason = reason_size
         if (n < 1) return
         reason = reason_interval
         if (.not. (ieee_is_finite(x) .and. ieee_is_finite(xend) .and. xend >= x)) return
         ! XEND - X finite, tested by halves (the difference itself would overflow)
         if (.not. (0.5_dp*xend - 0.5_dp*x < 0.5_dp*huge(1.0_dp))) return
         reason = reason_scheme
         if (radau) then
            call describe_radau5(radau_scheme)
            scheme => radau_scheme
         else
            call new_scheme(scheme_name, named_scheme, scheme_stat)
            if (scheme_stat%code /= status_ok) return
            scheme => named_scheme
         end if
         ! WORK(1:9) and H must be numbers (RADAU5 does not check: NaN passes its tests)
         reason = reason_work_number
         do i = 1, 9
            detail = i
            if (ieee_is_nan(work(i))) return
         end do
         detail = 0
         reason = reason_first_step
         if (ieee_is_nan(h)) return
         ! WORK(1): the rounding unit (RADAU5's UROUND: tolerance and Newton checks, H = 0)
         reason = reason_uround
         uround = default_uround
         if (work(1) /= 0.0_dp) uround = work(1)
         ! (RADAU5 takes up to 1; from 0.1 on its test of a too small step, 0.1 |H| <=
         ! |X| UROUND, holds for any H within |X|: refused with this reason, not later)
         if (.not. (uround > 1.0e-19_dp .and. uround < 0.1_dp)) return
         ! RADAU5 differences its Jacobian with the increment sqrt(UROUND max(1e-5, |y_j|))
         call set_difference_rounding(problem, uround)
         ! tolerances: radau5 takes RADAU5's rtol' = 0.1 rtol^(2/3), atol' = atol rtol'/rtol
         reason = reason_tolerance
         components = merge(1, n, itol == 0)
         if (itol /= 0) then
            allocate (options%rtol_vector(n), options%atol_vector(n), stat=memory)
            if (memory /= 0) then
               reason = reason_memory
               return
            end if
         end if
         do i = 1, components
            detail = i
            rtol_i = rtol(i)
            atol_i = atol(i)
            if (.not. (ieee_is_finite(rtol_i) .and. ieee_is_finite(atol_i))) return
            if (radau) then
               if (atol_i <= 0.0_dp .or. rtol_i <= 10.0_dp*uround) return
               quotient = atol_i/rtol_i
               rtol_i = 0.1_dp*rtol_i**(2.0_dp/3.0_dp)
               atol_i = rtol_i*quotient
            else if (rtol_i < 0.0_dp .or. atol_i < 0.0_dp .or. (rtol_i == 0.0_dp .and. atol_i == 0.0_dp)) then
               return
            end if
            if (itol == 0) then
               options%rtol = rtol_i
               options%atol = atol_i
            else
               options%rtol_vector(i) = rtol_i
               options%atol_vector(i) = atol_i
            end if
            if (i == 1) first_rtol = rtol_i
         end do
         detail = 0
         ! IWORK(2): the step budget
         reason = reason_budget_setting
         if (iwork(2) < 0) return
         options%max_steps = merge(default_budget, iwork(2), iwork(2) == 0)
         ! nowhere in RADAU5's arguments to report times
         options%measure_time = .false.
         ! IWORK(3): Newton iterations per step (0: the scheme's own, RADAU5's 7 for radau5)
         reason = reason_newton_setting
         if (iwork(3) < 0) return
         options%max_newton_iterations = iwork(3)
         ! IWORK(4): Newton from zero increments, i.e. from the state at the start of the step
         options%extrapolate_newton_start = iwork(4) == 0
         ! IWORK(5:7): index-1, 2 and 3 variables (only index 1: higher ones are not supported)
         reason = reason_index_sum
         nind = iwork(5:7)
         if (nind(1) == 0) nind(1) = n
         if (sum(int(nind, i8)) /= n) return
         reason = reason_index_high
         if (nind(2) /= 0 .or. nind(3) /= 0) return
         ! IWORK(8): 1 (or 0) the predictive controller, 2 the classical one
         options%controller = merge(controller_auto, controller_i, iwork(8) <= 1)
         ! IWORK(9:10): the structure y_i' = y_(i+M2), i <= M1, of second-order systems
         reason = reason_second_order
         m1 = iwork(9)
         m2 = iwork(10)
         if (m1 == 0) m2 = n
         if (m2 == 0) m2 = m1
         if (m1 < 0 .or. m2 < 0 .or. m1 + m2 > n) return
         reason = reason_second_order_unsupported
         if (m1 > 0) return
         ! WORK(2): the safety factor
         reason = reason_safety
         safe = 0.9_dp
         if (work(2) /= 0.0_dp) safe = work(2)
         if (.not. (safe > 0.001_dp .and. safe < 1.0_dp)) return
         options%kappa = safe
         ! WORK(3): the contraction rate up to which the Jacobian serves the next step (radau5)
         reason = reason_jacobian_reuse
         thet = 0.001_dp
         if (work(3) /= 0.0_dp) thet = work(3)
         if (.not. (thet < 1.0_dp)) return
         ! WORK(4): Newton's stop criterion (radau5: RADAU5's FNEWT by default)
         reason = reason_newton_stop
         if (work(4) /= 0.0_dp) then
            fnewt = work(4)
            if (.not. (fnewt > uround/first_rtol .and. ieee_is_finite(fnewt))) return
            options%newton_fraction = fnewt
         else if (radau) then
            options%newton_fraction = max(10.0_dp*uround/first_rtol, min(0.03_dp, sqrt(first_rtol)))
         end if
         ! WORK(5:6): the band of h_new / h in which h is kept (radau5)
         reason = reason_hold
         quot1 = 1.0_dp
         quot2 = 1.2_dp
         if (work(5) /= 0.0_dp) quot1 = work(5)
         if (work(6) /= 0.0_dp) quot2 = work(6)
         if (.not. (quot1 <= 1.0_dp .and. quot2 >= 1.0_dp .and. quot1 > 0.0_dp .and. ieee_is_finite(quot2))) return
         ! WORK(7): the largest step
         reason = reason_largest_step
         hmax = xend - x
         ! (X = XEND takes no step)
         if (empty) hmax = huge(1.0_dp)
         if (work(7) /= 0.0_dp) hmax = min(abs(work(7)), hmax)
         if (.not. (hmax > 0.0_dp)) return
         options%h_max = hmax
         ! WORK(8:9): bounds of h_new / h (RADAU5's 0.2 and 8 for radau5, the library's for the others)
         reason = reason_step_factors
         if (work(8) /= 0.0_dp) then
            facl = 1.0_dp/work(8)
            if (.not. (facl > 1.0_dp .and. ieee_is_finite(facl))) return
            options%min_shrink = work(8)
         else if (radau) then
            options%min_shrink = default_min_shrink
         end if
         if (work(9) /= 0.0_dp) then
            facr = 1.0_dp/work(9)
            if (.not. (facr < 1.0_dp .and. facr > 0.0_dp)) return
            options%max_growth = work(9)
         else if (radau) then
            options%max_growth = default_max_growth
         end if
         ! the Jacobian's bands
         reason = reason_bandwidths
         if (mljac < n .and. (mljac < 0 .or. mujac < 0 .or. mujac > n - 1)) return
         ! the mass matrix (radau5 only): dense (MLMAS = N) with a dense Jacobian, or a band
         ! within the Jacobian's
         if (imas /= 0) then
            reason = reason_mass_scheme
            if (.not. radau) return
            reason = reason_mass_bandwidths
            if (mlmas /= n) then
               if (mlmas < 0 .or. mumas < 0) return
               if (mljac < n) then
                  if (mlmas > mljac .or. mumas > mujac) return
               else if (mlmas > n .or. mumas > n) then
                  return
               end if
            else if (mljac < n) then
               return
            end if
         end if
         ! IWORK(11): the evaluation flag's place in IPAR
         reason = reason_flag
         if (iwork(11) < 0) return
         ! H: a guess; |H| <= 10 UROUND is RADAU5's 1e-6 for radau5, automatic for the others
         first = abs(h)
         if (first <= 10.0_dp*uround) first = merge(default_first_step, 0.0_dp, radau)
         options%h0 = min(first, hmax)
         ! IDID = -3 when 0.1 |H| <= |X| UROUND, as RADAU5 decides it
         options%h_min_relative = 10.0_dp*uround
         if (radau) then
            options%norm = norm_rms
            select type (scheme)
            type is (radau5_type)
               scheme%zero_start = iwork(4) /= 0
               scheme%jacobian_reuse = thet
               scheme%hold_low = quot1
               scheme%hold_high = quot2
               scheme%first_step_as_radau5 = .true.
               scheme%rounding = uround
            end select
         end if
         reason = reason_none
      end subroutine read_settings

      !> idid = -1 (or the outcome's code), IWORK(12:13) and the message for a reason.
      subroutine refuse(why, which, library_message)
         integer, intent(in) :: why, which
         character(len=*), intent(in) :: library_message
         iwork(12) = why
         iwork(13) = which
         if (present(message)) then
            call legacy_message(why, which, message)
            if (len_trim(library_message) > 0) message = message//" ("//trim(library_message)//")"
         end if
      end subroutine refuse
   end subroutine legacy_solve

   !> legacy_solve for the external TAYLORODE and TAYLORODE_SPLIT (legacy_entry.f90), its
   !> arguments C-interoperable: the user's routines as C function pointers to them, the
   !> scheme's name as characters and their number. Through it those external procedures
   !> use no module of the library, and so gfortran does not save, clear and restore the
   !> floating-point environment around them, which it does around every procedure whose
   !> scope reaches an IEEE module through USE (0.2 us a call). Not for other callers.
   subroutine legacy_solve_entry(scheme_name, name_length, n, fcn_f, fcn_g, has_f, x, y, xend, h, rtol, atol, &
      itol, jac_f, ijac_f, jac_g, ijac_g, mljac, mujac, mas, imas, mlmas, mumas, solout, iout, work, lwork, iwork, &
      liwork, rpar, ipar, idid) bind(c, name="taylorode_legacy_solve_entry")
      !> Scheme name, as characters
      character(kind=c_char), intent(in) :: scheme_name(*)
      !> Its number of characters
      integer(c_int), value :: name_length
      !> Unknowns
      integer(c_int), intent(in) :: n
      !> The non-stiff part (a pointer to an fcn_interface routine; not called unless
      !> has_f is 1) and the stiff part
      type(c_funptr), value :: fcn_f, fcn_g
      !> 1 when fcn_f is given, else 0
      integer(c_int), value :: has_f
      !> Start time on entry, where the integration stopped on exit
      real(c_double), intent(inout) :: x
      !> State at x
      real(c_double), intent(inout) :: y(n)
      !> Final time
      real(c_double), intent(in) :: xend
      !> First step size guess on entry, the next one on exit
      real(c_double), intent(inout) :: h
      !> Tolerances, scalars (itol = 0) or arrays of n
      real(c_double), intent(in) :: rtol(*), atol(*)
      !> 0 for scalar tolerances
      integer(c_int), intent(in) :: itol
      !> The Jacobians of f and g (pointers to jac_interface routines), used when 1 is given
      type(c_funptr), value :: jac_f, jac_g
      !> Whether jac_f and jac_g are given (1) or differences are used (0)
      integer(c_int), intent(in) :: ijac_f, ijac_g
      !> Bandwidths of the Jacobians
      integer(c_int), intent(in) :: mljac, mujac
      !> The mass matrix routine (a pointer to a mas_interface routine; null: none)
      type(c_funptr), value :: mas
      !> 0: M = I
      integer(c_int), intent(in) :: imas
      !> Bandwidths of M
      integer(c_int), intent(in) :: mlmas, mumas
      !> Called after every accepted step when iout /= 0 (a pointer to a solout_interface routine)
      type(c_funptr), value :: solout
      !> 0: never call solout
      integer(c_int), intent(in) :: iout
      !> Lengths of work and iwork
      integer(c_int), intent(in) :: lwork, liwork
      !> Real settings
      real(c_double), intent(inout) :: work(*)
      !> Integer settings and outputs
      integer(c_int), intent(inout) :: iwork(*)
      !> The caller's real data, passed to the user's routines untouched
      real(c_double), intent(inout), target :: rpar(*)
      !> The caller's integer data, passed to the user's routines untouched
      integer(c_int), intent(inout), target :: ipar(*)
      !> Outcome
      integer(c_int), intent(out) :: idid
      procedure(fcn_interface), pointer :: fcn_f_routine, fcn_g_routine
      procedure(jac_interface), pointer :: jac_f_routine, jac_g_routine
      procedure(mas_interface), pointer :: mas_routine
      procedure(solout_interface), pointer :: solout_routine
      character(len=max(name_length, 0)) :: name
      integer :: i
      do i = 1, len(name)
         name(i:i) = scheme_name(i)
      end do
      call c_f_procpointer(fcn_f, fcn_f_routine)
      call c_f_procpointer(fcn_g, fcn_g_routine)
      call c_f_procpointer(jac_f, jac_f_routine)
      call c_f_procpointer(jac_g, jac_g_routine)
      mas_routine => legacy_no_mass
      if (c_associated(mas)) call c_f_procpointer(mas, mas_routine)
      call c_f_procpointer(solout, solout_routine)
      call legacy_solve(name, n, fcn_f_routine, fcn_g_routine, has_f == 1, x, y, xend, h, rtol, atol, itol, &
         jac_f_routine, ijac_f, jac_g_routine, ijac_g, mljac, mujac, mas_routine, imas, mlmas, mumas, solout_routine, &
         iout, work, lwork, iwork, liwork, rpar, ipar, idid)
   end subroutine legacy_solve_entry

   !> legacy_interpolate for the external TAYLORODE_CONTR (see legacy_solve_entry).
   pure function legacy_interpolate_entry(i, s, cont, lrc) result(value) bind(c, name="taylorode_legacy_interpolate_entry")
      !> Component
      integer(c_int), intent(in) :: i
      !> Time inside the step
      real(c_double), intent(in) :: s
      !> Length of cont
      integer(c_int), intent(in) :: lrc
      !> The step as SOLOUT received it
      real(c_double), intent(in) :: cont(lrc)
      real(c_double) :: value
      value = legacy_interpolate(i, s, cont, lrc)
   end function legacy_interpolate_entry

   !> legacy_message for the external TAYLORODE_MESSAGE (see legacy_solve_entry): the
   !> sentence in text(1:text_length), cut or padded with blanks.
   subroutine legacy_message_entry(reason, detail, text, text_length) bind(c, name="taylorode_legacy_message_entry")
      !> IWORK(12) and IWORK(13)
      integer(c_int), intent(in) :: reason, detail
      !> The sentence
      character(kind=c_char), intent(out) :: text(*)
      !> Its room
      integer(c_int), value :: text_length
      character(len=:), allocatable :: sentence
      integer :: i
      call legacy_message(reason, detail, sentence)
      do i = 1, text_length
         text(i) = " "
         if (i <= len(sentence)) text(i) = sentence(i:i)
      end do
   end subroutine legacy_message_entry

   !> RADAU5's IDID for a status code.
   pure integer function outcome_code(code)
      integer, intent(in) :: code
      select case (code)
      case (status_ok); outcome_code = 1
      case (status_max_steps); outcome_code = -2
      case (status_step_underflow); outcome_code = -3
      case (status_singular_matrix); outcome_code = -4
      case (status_newton_diverged, status_newton_not_converged); outcome_code = -5
      case (status_nonfinite); outcome_code = -6
      case (status_evaluation_failed); outcome_code = -7
      case (status_out_of_memory); outcome_code = -8
      case default; outcome_code = -1
      end select
   end function outcome_code

   !> The reason code (IWORK(12)) of a failed integration's IDID.
   pure integer function outcome_reason(idid)
      integer, intent(in) :: idid
      select case (idid)
      case (-2); outcome_reason = reason_budget
      case (-3); outcome_reason = reason_underflow
      case (-4); outcome_reason = reason_singular
      case (-5); outcome_reason = reason_newton
      case (-6); outcome_reason = reason_nonfinite
      case (-7); outcome_reason = reason_evaluation
      case (-8); outcome_reason = reason_memory
      case default; outcome_reason = reason_failed
      end select
   end function outcome_reason

   !> What IWORK(12) = reason (and IWORK(13) = detail, a component or setting) says, in
   !> words (TAYLORODE_MESSAGE).
   pure subroutine legacy_message(reason, detail, text)
      !> IWORK(12)
      integer, intent(in) :: reason
      !> IWORK(13)
      integer, intent(in) :: detail
      !> The sentence
      character(len=:), allocatable, intent(out) :: text
      character(len=12) :: number
      write (number, '(i0)') detail
      select case (reason)
      case (reason_none); text = ""
      case (reason_storage); text = "LWORK and LIWORK must be at least 20"
      case (reason_size); text = "N must be at least 1"
      case (reason_interval); text = "X and XEND must be finite, XEND >= X and XEND - X finite (backward "// &
         "integration is not supported: substitute s = -x)"
      case (reason_tolerance); text = "RTOL("//trim(number)//") or ATOL("//trim(number)//") out of range: for "// &
         "radau5 (as RADAU5) ATOL > 0 and RTOL > 10 UROUND, for the other schemes both >= 0 and not both 0, finite"
      case (reason_uround); text = "WORK(1), the rounding unit UROUND, must be in (1e-19, 0.1) (0: 1e-16)"
      case (reason_budget_setting); text = "IWORK(2), the step budget, must be >= 0 (0: 100000)"
      case (reason_newton_setting); text = "IWORK(3), the Newton iterations per step, must be >= 0 (0: the "// &
         "scheme's own, 7 for radau5)"
      case (reason_index_sum); text = "IWORK(5) + IWORK(6) + IWORK(7) must equal N (IWORK(5) = 0: N)"
      case (reason_index_high); text = "index-2 and index-3 variables (IWORK(6), IWORK(7) > 0) are not supported"
      case (reason_second_order); text = "IWORK(9) = M1 and IWORK(10) = M2 must be >= 0 with M1 + M2 <= N"
      case (reason_second_order_unsupported); text = "the second-order structure IWORK(9) = M1 > 0 is not "// &
         "supported: give the whole Jacobian (and mass matrix) with M1 = 0"
      case (reason_safety); text = "WORK(2), the safety factor, must be in (0.001, 1) (0: 0.9)"
      case (reason_jacobian_reuse); text = "WORK(3), the contraction rate up to which the Jacobian is kept, "// &
         "must be < 1 (0: 0.001)"
      case (reason_newton_stop); text = "WORK(4), Newton's stop criterion, must be > UROUND / RTOL(1) (RADAU5's "// &
         "transformed RTOL for radau5) and finite (0: RADAU5's default)"
      case (reason_hold); text = "WORK(5) must be in (0, 1] and WORK(6) >= 1, finite (0: 1 and 1.2)"
      case (reason_step_factors); text = "WORK(8) must be in (0, 1) and WORK(9) > 1 (0: 0.2 and 8)"
      case (reason_largest_step); text = "WORK(7), the largest step, must be a number (0: XEND - X)"
      case (reason_bandwidths); text = "with MLJAC < N (band storage) both MLJAC and MUJAC must be in [0, N - 1]"
      case (reason_mass_bandwidths); text = "the mass matrix's bands must be >= 0 and within the Jacobian's "// &
         "(MLMAS <= MLJAC, MUMAS <= MUJAC; MLMAS = N: dense, which needs a dense Jacobian)"
      case (reason_mass_scheme); text = "a mass matrix (IMAS /= 0) needs the scheme radau5"
      case (reason_scheme); text = "unknown scheme name"
      case (reason_flag); text = "IWORK(11), the place of the evaluation flag in IPAR, must be >= 0"
      case (reason_first_step); text = "H must be a number"
      case (reason_work_number); text = "WORK("//trim(number)//") must be a number (NaN is not a setting)"
      case (reason_budget); text = "the step budget IWORK(2) was spent before XEND (IDID = -2)"
      case (reason_underflow); text = "the step size fell below the roundoff of X (IDID = -3)"
      case (reason_singular); text = "the Newton matrix was singular repeatedly (IDID = -4)"
      case (reason_newton); text = "Newton's method failed repeatedly (IDID = -5)"
      case (reason_nonfinite); text = "NaN or Inf from FCN, JAC or a step, repeatedly at the same point, or in "// &
         "the initial state (IDID = -6)"
      case (reason_evaluation); text = "FCN or JAC rejected its evaluations through the flag IPAR(IWORK(11)) "// &
         "(IDID = -7)"
      case (reason_failed); text = "the integration was refused"
      case (reason_memory); text = "memory could not be allocated (IDID = -8)"
      case default; text = "unknown reason"
      end select
   end subroutine legacy_message

   !> SOLOUT at the start (NR = 1, XOLD = X), as RADAU5 does.
   subroutine start_solout(self, x, y, n)
      type(legacy_observer_type), intent(inout) :: self
      real(dp), intent(in) :: x, y(:)
      integer, intent(in) :: n
      real(dp) :: x_copy
      integer :: irtrn, nr, lrc, n_copy
      x_copy = x
      self%y_copy = y
      self%cont(1:4) = [x, 1.0_dp, real(n, dp), 0.0_dp]
      self%cont(5 + self%max_degree:4 + self%max_degree + n) = y
      self%calls = 1
      nr = 1
      lrc = size(self%cont)
      n_copy = n
      irtrn = 0
      call self%solout(nr, x_copy, x_copy, self%y_copy, self%cont, lrc, n_copy, self%rpar, self%ipar, irtrn)
      self%stopped = irtrn < 0
   end subroutine start_solout

   subroutine legacy_observe(self, step, stop)
      class(legacy_observer_type), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      logical, intent(inout) :: stop
      real(dp) :: x_old, x_new
      integer :: irtrn, n, lrc, nr, first, k
      n = size(step%u_end)
      self%cont(1:4) = [step%t_start, step%h, real(n, dp), real(step%degree, dp)]
      self%cont(5:4 + step%degree) = step%nodes(:step%degree)
      first = 5 + self%max_degree
      ! column by column (a reshape would build a temporary of the whole step)
      do k = 0, step%degree
         self%cont(first + k*n:first - 1 + (k + 1)*n) = step%coefficients(:, k)
      end do
      self%calls = self%calls + 1
      nr = self%calls
      lrc = size(self%cont)
      x_old = step%t_start
      x_new = step%t_end
      self%y_copy = step%u_end
      irtrn = 0
      call self%solout(nr, x_old, x_new, self%y_copy, self%cont, lrc, n, self%rpar, self%ipar, irtrn)
      self%stopped = irtrn < 0
      self%y_changed = any(self%y_copy /= step%u_end)
      stop = self%stopped .or. self%y_changed
   end subroutine legacy_observe

   !> Component i at s of the step packed in cont (TAYLORODE_CONTR): the step's Newton
   !> form (newton_form's arithmetic, for one component).
   pure real(dp) function legacy_interpolate(i, s, cont, lrc) result(value)
      !> Component
      integer, intent(in) :: i
      !> Time inside the step
      real(dp), intent(in) :: s
      !> Length of cont
      integer, intent(in) :: lrc
      !> The step as SOLOUT received it
      real(dp), intent(in) :: cont(lrc)
      real(dp) :: theta
      integer :: n, degree, first, k
      ! NaN for a component outside 1..N, or a CONT that is not one SOLOUT was given
      value = ieee_value(value, ieee_quiet_nan)
      if (lrc < 5) return
      if (.not. (cont(3) >= 1.0_dp .and. cont(3) <= real(lrc, dp) .and. cont(4) >= 0.0_dp .and. &
         cont(4) <= real(lrc, dp))) return
      n = nint(cont(3))
      degree = nint(cont(4))
      if (i < 1 .or. i > n) return
      ! after the room for max_degree nodes: lrc = 4 + max_degree + n (max_degree + 1);
      ! coefficient k of component i at first + k n + i - 1, node k at 4 + k
      first = 5 + (lrc - 4 - n)/(n + 1)
      if (degree > first - 5 .or. first + degree*n + n - 1 > lrc) return
      ! (beyond [XOLD, X] the polynomial extrapolates, as CONTR5's does)
      theta = (s - cont(1))/cont(2)
      value = cont(first + degree*n + i - 1)
      do k = degree, 1, -1
         value = cont(first + (k - 1)*n + i - 1) + (theta - cont(4 + k))*value
      end do
   end function legacy_interpolate


   !> Call a user's FCN with its RPAR and IPAR (x and y copied: F77 routines may write
   !> them); with the evaluation flag, IPAR(flag) is 0 before the call and read after it.
   subroutine call_fcn(self, fcn, t, u, dudt)
      type(legacy_problem_type), intent(inout) :: self
      procedure(fcn_interface) :: fcn
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: x
      integer :: n, i
      x = t
      n = size(u)
      ! (a loop, as in legacy_rhs_values: the assignment checks x_state's allocation)
      !GCC$ unroll 1
      do i = 1, n
         self%x_state(i) = u(i)
      end do
      if (self%flag > 0) self%ipar(self%flag) = 0
      call fcn(n, x, self%x_state, dudt, self%rpar, self%ipar)
      if (self%flag > 0) then
         call read_flag(self, self%ipar(self%flag))
         ! the values of a refused evaluation are not used; no NaN is left behind
         if (self%ipar(self%flag) /= 0) dudt = 0.0_dp
      end if
   end subroutine call_fcn

   !> Call a user's JAC into jac (n x n dense, or its band storage: ldfy rows), flag as
   !> call_fcn. Explicit-shape: a contiguous jac (the dense Jacobian) reaches JAC with no
   !> descriptor built on the way; a band section is copied in and out at the call, as
   !> the F77 DFY needs it.
   subroutine call_jac(self, jac_user, n, t, u, ldfy, jac)
      type(legacy_problem_type), intent(inout) :: self
      procedure(jac_interface) :: jac_user
      integer, intent(in) :: n, ldfy
      real(dp), intent(in) :: t, u(n)
      real(dp), intent(out) :: jac(ldfy, n)
      real(dp) :: x
      integer :: n_copy, ldfy_copy, i
      x = t
      n_copy = n
      ldfy_copy = ldfy
      !GCC$ unroll 1
      do i = 1, n
         self%x_state(i) = u(i)
      end do
      if (self%flag > 0) self%ipar(self%flag) = 0
      call jac_user(n_copy, x, self%x_state, jac, ldfy_copy, self%rpar, self%ipar)
      if (self%flag > 0) then
         call read_flag(self, self%ipar(self%flag))
         if (self%ipar(self%flag) /= 0) jac = 0.0_dp
      end if
   end subroutine call_jac

   !> What FCN or JAC said through the evaluation flag: > 0 retry shorter, < 0 stop.
   subroutine read_flag(self, flag)
      type(legacy_problem_type), intent(inout) :: self
      integer, intent(in) :: flag
      if (flag > 0) call self%reject_evaluation()
      if (flag < 0) call self%reject_evaluation(fatal=.true.)
   end subroutine read_flag

   subroutine legacy_f(self, t, u, dudt)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      if (self%has_f) then
         call call_fcn(self, self%fcn_f, t, u, dudt)
      else
         dudt = 0.0_dp
      end if
   end subroutine legacy_f

   subroutine legacy_g(self, t, u, dudt)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call call_fcn(self, self%fcn_g, t, u, dudt)
   end subroutine legacy_g

   !> F = f + g: FCN alone in one call (TAYLORODE; legacy_rhs_values), or FCNF and FCNG
   !> added.
   subroutine legacy_rhs(self, t, u, dudt)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      integer :: i
      if (self%has_f .or. self%flag > 0) then
         call call_fcn(self, self%fcn_g, t, u, dudt)
         if (.not. self%has_f) return
         call call_fcn(self, self%fcn_f, t, u, self%g_work)
         do i = 1, size(u)
            dudt(i) = dudt(i) + self%g_work(i)
         end do
         return
      end if
      call legacy_rhs_values(self, size(u), t, u, dudt)
   end subroutine legacy_rhs

   !> F = f + g of n unknowns: FCN alone called here with the state copied, no array
   !> descriptors (the hot path of radau5's stages), else legacy_rhs.
   subroutine legacy_rhs_values(self, n, t, u, dudt)
      class(legacy_problem_type), intent(inout) :: self
      integer, intent(in) :: n
      real(dp), intent(in) :: t, u(n)
      real(dp), intent(out) :: dudt(n)
      real(dp) :: x
      integer :: i
      if (self%has_f .or. self%flag > 0) then
         call legacy_rhs(self, t, u, dudt)
         return
      end if
      x = t
      ! a loop through the component, which gcc cannot prove apart from u: it keeps the
      ! loop, where a copy between arrays it can tell apart becomes a call of memcpy,
      ! slower on a few unknowns (this is radau5's stage evaluation); not unrolled, as the
      ! unrolled loop's entry costs more than two or three copies
      !GCC$ unroll 1
      do i = 1, n
         self%x_state(i) = u(i)
      end do
      call self%fcn_g(n, x, self%x_state, dudt, self%rpar, self%ipar)
   end subroutine legacy_rhs_values

   !> F = f + g of n unknowns at the caller's scratch state: FCN alone called with it
   !> (FCN may write it, as RADAU5's FCN may write the stage states it is given), else
   !> legacy_rhs.
   subroutine legacy_rhs_scratch(self, n, t, u, dudt)
      class(legacy_problem_type), intent(inout) :: self
      integer, intent(in) :: n
      real(dp), intent(in) :: t
      real(dp), intent(inout) :: u(n)
      real(dp), intent(out) :: dudt(n)
      real(dp) :: x
      if (self%has_f .or. self%flag > 0) then
         call legacy_rhs(self, t, u, dudt)
         return
      end if
      x = t
      call self%fcn_g(n, x, u, dudt, self%rpar, self%ipar)
   end subroutine legacy_rhs_scratch

   !> Dense df/dU: the user's JACF, zero without f, forward differences otherwise.
   subroutine legacy_jac_f(self, t, u, jac)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (.not. self%has_f) then
         jac = 0.0_dp
      else if (self%has_jac_f) then
         call call_jac(self, self%jac_f_user, size(u), t, u, size(jac, 1), jac)
      else
         call dense_differences(self, difference_f, t, u, jac)
      end if
   end subroutine legacy_jac_f

   !> Dense dg/dU: the user's JAC(G), forward differences otherwise.
   subroutine legacy_jac_g(self, t, u, jac)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%has_jac_g) then
         call call_jac(self, self%jac_g_user, size(u), t, u, size(jac, 1), jac)
      else
         call dense_differences(self, difference_g, t, u, jac)
      end if
   end subroutine legacy_jac_g

   !> Dense J: the user's JAC in one call straight into jac (TAYLORODE), else jac_f + jac_g;
   !> without JACF and JACG, differences of FCNF + FCNG (one call of each per column).
   subroutine legacy_jac(self, t, u, jac)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%has_f .and. .not. (self%has_jac_f .or. self%has_jac_g)) then
         call dense_differences(self, difference_rhs, t, u, jac)
      else if (self%has_f) then
         call self%jac_f(t, u, jac)
         call self%jac_g(t, u, self%jac_work)
         jac = jac + self%jac_work
      else
         call self%jac_g(t, u, jac)
      end if
   end subroutine legacy_jac

   function legacy_structure(self, n) result(structure)
      class(legacy_problem_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = self%structure
   end function legacy_structure

   !> Band df/dU: the user's JACF in RADAU5's band layout (the same as LAPACK's), zero
   !> without f, grouped differences otherwise.
   subroutine legacy_jac_f_band(self, t, u, band)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (.not. self%has_f) then
         band = 0.0_dp
      else if (self%has_jac_f) then
         call call_jac(self, self%jac_f_user, size(u), t, u, size(band, 1), band)
      else
         call band_differences(self, difference_f, t, u, band)
      end if
   end subroutine legacy_jac_f_band

   !> Band dg/dU (see legacy_jac_f_band).
   subroutine legacy_jac_g_band(self, t, u, band)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (self%has_jac_g) then
         call call_jac(self, self%jac_g_user, size(u), t, u, size(band, 1), band)
      else
         call band_differences(self, difference_g, t, u, band)
      end if
   end subroutine legacy_jac_g_band

   !> Band J: the user's JAC in one call (TAYLORODE), else jac_f_band + jac_g_band;
   !> without JACF and JACG, grouped differences of FCNF + FCNG.
   subroutine legacy_jac_band(self, t, u, band)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (self%has_f .and. .not. (self%has_jac_f .or. self%has_jac_g)) then
         call band_differences(self, difference_rhs, t, u, band)
      else if (self%has_f) then
         call self%jac_f_band(t, u, band)
         call self%jac_g_band(t, u, self%jac_work)
         band = band + self%jac_work
      else
         call self%jac_g_band(t, u, band)
      end if
   end subroutine legacy_jac_band

   !> Which part J is differenced from: F (FCNF + FCNG, or FCN alone in TAYLORODE, called
   !> through legacy_rhs_values) when neither JAC(G) nor JACF is given; 0 when a Jacobian
   !> routine is given.
   pure integer function differenced_part(self)
      class(legacy_problem_type), intent(in) :: self
      differenced_part = 0
      if (self%has_jac_f .or. self%has_jac_g) return
      differenced_part = difference_rhs
   end function differenced_part

   !> Dense J given F(t, u): without Jacobian routines, differences from that F (N
   !> evaluations, as RADAU5's from F(X, Y)); TAYLORODE's JAC called here (no f); else
   !> legacy_jac.
   subroutine legacy_jac_with_rhs(self, t, u, value, jac)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:), value(:)
      real(dp), intent(out) :: jac(:, :)
      if (differenced_part(self) /= 0) then
         call dense_differences(self, differenced_part(self), t, u, jac, value)
      else if (.not. self%has_f) then
         call call_jac(self, self%jac_g_user, size(u), t, u, size(jac, 1), jac)
      else
         call self%jac(t, u, jac)
      end if
   end subroutine legacy_jac_with_rhs

   !> Band J given F(t, u) (see legacy_jac_with_rhs).
   subroutine legacy_jac_band_with_rhs(self, t, u, value, band)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:), value(:)
      real(dp), intent(out) :: band(:, :)
      if (differenced_part(self) /= 0) then
         call band_differences(self, differenced_part(self), t, u, band, value)
      else
         call self%jac_band(t, u, band)
      end if
   end subroutine legacy_jac_band_with_rhs

   !> M, dense: the user's MAS (dense, or its band expanded).
   subroutine legacy_mass(self, m)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(out) :: m(:, :)
      integer :: i, j
      call call_mas(self)
      if (self%mass_lower >= size(m, 1)) then
         m = self%mass_work
      else
         m = 0.0_dp
         do j = 1, size(m, 2)
            do i = max(1, j - self%mass_upper), min(size(m, 1), j + self%mass_lower)
               m(i, j) = self%mass_work(self%mass_upper + 1 + i - j, j)
            end do
         end do
      end if
   end subroutine legacy_mass

   !> M in the Jacobian's band storage: the user's band MAS, moved to the Jacobian's rows.
   subroutine legacy_mass_band(self, band)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(out) :: band(:, :)
      integer :: i, j
      call call_mas(self)
      band = 0.0_dp
      do j = 1, size(band, 2)
         do i = max(1, j - self%mass_upper), min(size(band, 2), j + self%mass_lower)
            band(self%structure%upper + 1 + i - j, j) = self%mass_work(self%mass_upper + 1 + i - j, j)
         end do
      end do
   end subroutine legacy_mass_band

   !> The user's MAS(N, AM, LMAS, RPAR, IPAR) into mass_work.
   subroutine call_mas(self)
      type(legacy_problem_type), intent(inout) :: self
      integer :: n, lmas
      n = size(self%mass_work, 2)
      lmas = size(self%mass_work, 1)
      self%mass_work = 0.0_dp
      call self%mas(n, self%mass_work, lmas, self%rpar, self%ipar)
   end subroutine call_mas

   !> A MAS for calls without a mass matrix (TAYLORODE_SPLIT); never called.
   subroutine legacy_no_mass(n, am, lmas, rpar, ipar)
      !> Unknowns, leading dimension of am
      integer :: n, lmas
      !> The mass matrix (left as it is)
      real(dp) :: am(lmas, n)
      !> The caller's real data
      real(dp) :: rpar(*)
      !> The caller's integer data
      integer :: ipar(*)
   end subroutine legacy_no_mass

end module taylorode_interfaces_legacy
