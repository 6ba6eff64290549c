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
!> storage when MLJAC < N as RADAU5's (DFY(I - J + MUJAC + 1, J)), no mass matrix
!> (IMAS = 0), SOLOUT(NR, XOLD, X, Y, CONT, LRC, N, RPAR, IPAR, IRTRN) called after
!> every accepted step when IOUT = 1 (IRTRN < 0 stops; TAYLORODE_CONTR(I, S, CONT,
!> LRC) interpolates component I at S inside the step). TAYLORODE_SPLIT takes f and g
!> apart: FCNF, FCNG, JACF (IJACF), JACG (IJACG). RPAR and IPAR are passed to the
!> user's routines untouched.
!>
!> Inputs in IWORK and WORK (0 means the default): IWORK(2) the step budget (100000),
!> IWORK(3) Newton iterations per system (10), WORK(2) the safety factor (0.9),
!> WORK(7) the largest step (XEND - X). Outputs: IWORK(14) evaluations of FCN (f and
!> g together: the larger count), IWORK(15) Jacobian evaluations, IWORK(16) attempted
!> steps, IWORK(17) accepted, IWORK(18) rejected, IWORK(19) LU factorizations,
!> IWORK(20) linear solves; X, Y where the integration stopped, H the next step.
!> IDID: 1 success, 2 stopped by SOLOUT, -1 inconsistent input or unknown scheme, -2
!> step budget, -3 step size too small, -4 Newton matrix repeatedly singular, -5
!> Newton failed repeatedly, -6 NaN or Inf, -7 the problem rejected evaluations, -8
!> memory could not be allocated (the Newton matrices of a large N, say).
module taylorode_interfaces_legacy
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_singular_matrix, status_newton_diverged, &
      status_newton_not_converged, status_step_underflow, status_max_steps, status_unknown_scheme, &
      status_evaluation_failed, status_out_of_memory
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_linalg_matrix, only: matrix_structure_type, band_structure, storage_band
   use taylorode_problem_ode, only: ode_problem, dense_differences, band_differences
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_integrate_options, only: integrator_options_type
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrator_type
   use taylorode_integrate_step, only: accepted_step_type, newton_form, hermite_degree
   use taylorode_integrate_observer, only: step_observer_type
   use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_f_pointer, c_null_ptr
   implicit none
   private

   public :: legacy_solve, legacy_interpolate, fcn_interface, jac_interface, solout_interface

   abstract interface
      !> F = right-hand side (or its non-stiff or stiff part) at (X, Y)
      subroutine fcn_interface(n, x, y, f, rpar, ipar)
         import :: dp
         !> Unknowns
         integer :: n
         !> Time and state (copies: the routine may write them)
         real(dp) :: x, y(n)
         !> The value at (x, y)
         real(dp) :: f(n)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched
         integer :: ipar(*)
      end subroutine fcn_interface
      !> DFY = its Jacobian (dense LDFY x N, or band storage)
      subroutine jac_interface(n, x, y, dfy, ldfy, rpar, ipar)
         import :: dp
         !> Unknowns, and the leading dimension of dfy (n dense, mljac + mujac + 1 band)
         integer :: n, ldfy
         !> Time and state (copies: the routine may write them)
         real(dp) :: x, y(n)
         !> The Jacobian: dfy(i, j) = d part_i / d y_j, or dfy(i - j + mujac + 1, j) in band storage
         real(dp) :: dfy(ldfy, n)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched
         integer :: ipar(*)
      end subroutine jac_interface
      !> Called after each accepted step (and once at the start)
      subroutine solout_interface(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
         import :: dp
         !> Number of the call (1 at the start), length of cont, unknowns
         integer :: nr, lrc, n
         !> Start and end of the step just accepted (both the start time on the first call)
         real(dp) :: xold, x
         !> State at x
         real(dp) :: y(n)
         !> The step, for TAYLORODE_CONTR
         real(dp) :: cont(lrc)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched
         integer :: ipar(*)
         !> Set it negative to stop the integration
         integer :: irtrn
      end subroutine solout_interface
   end interface

   !> The user's routines as an ode_problem
   type, extends(ode_problem) :: legacy_problem_type
      procedure(fcn_interface), pointer, nopass :: fcn_f => null(), fcn_g => null()
      procedure(jac_interface), pointer, nopass :: jac_f_user => null(), jac_g_user => null()
      !> Which parts and Jacobians the user gave
      logical :: has_f = .false., has_jac_f = .false., has_jac_g = .false.
      !> Structure of the Jacobians the user gives (dense unless bandwidths are set)
      type(matrix_structure_type) :: structure
      !> The user's RPAR and IPAR, passed through
      type(c_ptr) :: rpar = c_null_ptr, ipar = c_null_ptr
      !> Work arrays: the state (a copy, as F77 routines may write it) and the Jacobian
      !> in the user's layout
      real(dp), allocatable :: x_state(:), jac_work(:, :)
   contains
      procedure :: f => legacy_f
      procedure :: g => legacy_g
      procedure :: jac_f => legacy_jac_f
      procedure :: jac_g => legacy_jac_g
      procedure :: jacobian_structure => legacy_structure
      procedure :: jac_f_band => legacy_jac_f_band
      procedure :: jac_g_band => legacy_jac_g_band
   end type legacy_problem_type

   !> SOLOUT after every accepted step
   type, extends(step_observer_type) :: legacy_observer_type
      procedure(solout_interface), pointer, nopass :: solout => null()
      type(c_ptr) :: rpar = c_null_ptr, ipar = c_null_ptr
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
   contains
      procedure :: observe => legacy_observe
   end type legacy_observer_type

contains

   !> The integration behind TAYLORODE and TAYLORODE_SPLIT (see the module comment).
   subroutine legacy_solve(scheme_name, n, fcn_f, fcn_g, has_f, x, y, xend, h, rtol, atol, itol, jac_f, ijac_f, &
      jac_g, ijac_g, mljac, mujac, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
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
      !> Final time
      real(dp), intent(in) :: xend
      !> First step size on entry (0: automatic), the next one on exit
      real(dp), intent(inout) :: h
      !> Relative and absolute tolerances, scalars (itol = 0) or arrays of n (itol = 1)
      real(dp), intent(in) :: rtol(*), atol(*)
      !> 0 for scalar tolerances, 1 for one per component
      integer, intent(in) :: itol
      !> Jacobians of f and g, used when ijac_f, ijac_g = 1
      procedure(jac_interface) :: jac_f, jac_g
      !> Whether jac_f and jac_g are given (1) or differences are used (0)
      integer, intent(in) :: ijac_f, ijac_g
      !> Lower and upper bandwidths of the Jacobians (mljac >= n: dense; else both in [0, n - 1])
      integer, intent(in) :: mljac, mujac
      !> Called after every accepted step when iout = 1
      procedure(solout_interface) :: solout
      !> 1 to call solout, 0 not to
      integer, intent(in) :: iout
      !> Lengths of work and iwork (at least 20 each)
      integer, intent(in) :: lwork, liwork
      !> Real inputs (see the module comment)
      real(dp), intent(inout) :: work(*)
      !> Integer inputs and statistics (see the module comment)
      integer, intent(inout) :: iwork(*)
      !> Real data passed to the user's routines untouched
      real(dp), intent(inout), target :: rpar(*)
      !> Integer data passed to the user's routines untouched
      integer, intent(inout), target :: ipar(*)
      !> Outcome
      integer, intent(out) :: idid
      type(legacy_problem_type) :: problem
      type(legacy_observer_type) :: observer
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integrator_type) :: integrator
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      integer :: memory

      idid = -1
      if (n < 1 .or. lwork < 20 .or. liwork < 20 .or. (itol /= 0 .and. itol /= 1) .or. .not. (xend > x)) return
      if (iout /= 0 .and. iout /= 1) return
      ! banded (mljac < n): both bandwidths within the matrix
      if (mljac < n .and. (mljac < 0 .or. mujac < 0 .or. mujac > n - 1)) return
      call new_scheme(scheme_name, scheme, stat)
      if (stat%code /= status_ok) return

      problem%fcn_g => fcn_g
      problem%has_f = has_f
      if (has_f) problem%fcn_f => fcn_f
      problem%has_jac_f = ijac_f == 1
      problem%has_jac_g = ijac_g == 1
      if (problem%has_jac_f) problem%jac_f_user => jac_f
      if (problem%has_jac_g) problem%jac_g_user => jac_g
      if (mljac < n) problem%structure = band_structure(mljac, mujac)
      problem%rpar = c_loc(rpar(1))
      problem%ipar = c_loc(ipar(1))
      allocate (problem%x_state(n), stat=memory)
      if (problem%structure%storage == storage_band) then
         if (memory == 0) allocate (problem%jac_work(problem%structure%lower + problem%structure%upper + 1, n), &
            stat=memory)
      else
         if (memory == 0) allocate (problem%jac_work(n, n), stat=memory)
      end if
      if (memory /= 0) then
         idid = outcome_code(status_out_of_memory)
         return
      end if

      if (itol == 0) then
         options%rtol = rtol(1)
         options%atol = atol(1)
      else
         allocate (options%rtol_vector(n), options%atol_vector(n), stat=memory)
         if (memory /= 0) then
            idid = outcome_code(status_out_of_memory)
            return
         end if
         options%rtol_vector = rtol(:n)
         options%atol_vector = atol(:n)
      end if
      options%h0 = max(h, 0.0_dp)
      options%max_steps = 100000_i8
      if (iwork(2) > 0) options%max_steps = iwork(2)
      if (iwork(3) > 0) options%max_newton_iterations = iwork(3)
      if (work(2) > 0.0_dp) options%kappa = work(2)
      options%h_max = xend - x
      if (work(7) > 0.0_dp) options%h_max = work(7)

      call integrator%init(problem, scheme, x, y, options, stat)
      if (stat%code == status_ok) then
         if (iout == 1) then
            observer%solout => solout
            observer%rpar = problem%rpar
            observer%ipar = problem%ipar
            observer%max_degree = max(hermite_degree, scheme%dense_degree)
            allocate (observer%cont(4 + observer%max_degree + n*(observer%max_degree + 1)), observer%y_copy(n), &
               source=0.0_dp, stat=memory)
            if (memory /= 0) call out_of_memory(stat, "SOLOUT's copy of the step", [observer%max_degree + 2, n], &
               real_bytes)
            if (stat%code == status_ok) call start_solout(observer, x, y, n)
            if (observer%stopped) then
               idid = 2
               return
            end if
            if (stat%code == status_ok) call integrator%advance_to(problem, scheme, xend, y, stat, stats, &
               observer=observer)
         else
            call integrator%advance_to(problem, scheme, xend, y, stat, stats)
         end if
      end if
      x = integrator%total%t_reached
      h = integrator%h
      iwork(14) = int(max(integrator%total%work%f_evaluations, integrator%total%work%g_evaluations))
      iwork(15) = int(max(integrator%total%work%jac_f_evaluations, integrator%total%work%jac_g_evaluations))
      iwork(16) = int(integrator%total%accepted_steps + integrator%total%rejected_steps())
      iwork(17) = int(integrator%total%accepted_steps)
      iwork(18) = int(integrator%total%rejected_steps())
      iwork(19) = int(integrator%total%work%lu_factorizations)
      iwork(20) = int(integrator%total%work%linear_solves)
      idid = outcome_code(stat%code)
      if (stat%code == status_ok .and. observer%stopped) idid = 2
   end subroutine legacy_solve

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

   !> SOLOUT at the start (NR = 1, XOLD = X), as RADAU5 does.
   subroutine start_solout(self, x, y, n)
      type(legacy_observer_type), intent(inout) :: self
      real(dp), intent(in) :: x, y(:)
      integer, intent(in) :: n
      real(dp) :: x_copy
      real(dp), pointer :: rpar(:)
      integer, pointer :: ipar(:)
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
      call c_f_pointer(self%rpar, rpar, [1])
      call c_f_pointer(self%ipar, ipar, [1])
      call self%solout(nr, x_copy, x_copy, self%y_copy, self%cont, lrc, n_copy, rpar, ipar, irtrn)
      self%stopped = irtrn < 0
   end subroutine start_solout

   subroutine legacy_observe(self, step, stop)
      class(legacy_observer_type), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      logical, intent(inout) :: stop
      real(dp), pointer :: rpar(:)
      integer, pointer :: ipar(:)
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
      call c_f_pointer(self%rpar, rpar, [1])
      call c_f_pointer(self%ipar, ipar, [1])
      call self%solout(nr, x_old, x_new, self%y_copy, self%cont, lrc, n, rpar, ipar, irtrn)
      if (irtrn < 0) then
         self%stopped = .true.
         stop = .true.
      end if
   end subroutine legacy_observe

   !> Component i at s of the step packed in cont (TAYLORODE_CONTR).
   pure real(dp) function legacy_interpolate(i, s, cont, lrc) result(value)
      !> Component
      integer, intent(in) :: i
      !> Time inside the step
      real(dp), intent(in) :: s
      !> Length of cont
      integer, intent(in) :: lrc
      !> The step as SOLOUT received it
      real(dp), intent(in) :: cont(lrc)
      real(dp) :: u(1)
      integer :: n, degree, first
      n = nint(cont(3))
      degree = nint(cont(4))
      ! after the room for max_degree nodes: lrc = 4 + max_degree + n (max_degree + 1)
      first = 5 + (lrc - 4 - n)/(n + 1)
      call newton_form(min(max((s - cont(1))/cont(2), 0.0_dp), 1.0_dp), cont(5:4 + degree), &
         reshape(cont(first + i - 1:first - 1 + i + degree*n:n), [1, degree + 1]), u)
      value = u(1)
   end function legacy_interpolate

   !> Call a user's FCN with its RPAR and IPAR (x and y copied: F77 routines may write them).
   subroutine call_fcn(self, fcn, t, u, dudt)
      type(legacy_problem_type), intent(inout) :: self
      procedure(fcn_interface) :: fcn
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp), pointer :: rpar(:)
      integer, pointer :: ipar(:)
      real(dp) :: x
      integer :: n
      call c_f_pointer(self%rpar, rpar, [1])
      call c_f_pointer(self%ipar, ipar, [1])
      x = t
      n = size(u)
      self%x_state = u
      call fcn(n, x, self%x_state, dudt, rpar, ipar)
   end subroutine call_fcn

   !> Call a user's JAC into jac_work.
   subroutine call_jac(self, jac, t, u)
      type(legacy_problem_type), intent(inout) :: self
      procedure(jac_interface) :: jac
      real(dp), intent(in) :: t, u(:)
      real(dp), pointer :: rpar(:)
      integer, pointer :: ipar(:)
      real(dp) :: x
      integer :: n, ldfy
      call c_f_pointer(self%rpar, rpar, [1])
      call c_f_pointer(self%ipar, ipar, [1])
      x = t
      n = size(u)
      ldfy = size(self%jac_work, 1)
      self%x_state = u
      call jac(n, x, self%x_state, self%jac_work, ldfy, rpar, ipar)
   end subroutine call_jac

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

   !> Dense df/dU: the user's JACF, zero without f, forward differences otherwise.
   subroutine legacy_jac_f(self, t, u, jac)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (.not. self%has_f) then
         jac = 0.0_dp
      else if (self%has_jac_f) then
         call call_jac(self, self%jac_f_user, t, u)
         jac = self%jac_work
      else
         call dense_differences(self, .true., t, u, jac)
      end if
   end subroutine legacy_jac_f

   !> Dense dg/dU: the user's JAC(G), forward differences otherwise.
   subroutine legacy_jac_g(self, t, u, jac)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%has_jac_g) then
         call call_jac(self, self%jac_g_user, t, u)
         jac = self%jac_work
      else
         call dense_differences(self, .false., t, u, jac)
      end if
   end subroutine legacy_jac_g

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
         call call_jac(self, self%jac_f_user, t, u)
         band = self%jac_work
      else
         call band_differences(self, .true., t, u, band)
      end if
   end subroutine legacy_jac_f_band

   !> Band dg/dU (see legacy_jac_f_band).
   subroutine legacy_jac_g_band(self, t, u, band)
      class(legacy_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (self%has_jac_g) then
         call call_jac(self, self%jac_g_user, t, u)
         band = self%jac_work
      else
         call band_differences(self, .false., t, u, band)
      end if
   end subroutine legacy_jac_g_band

end module taylorode_interfaces_legacy

!> TAYLORODE, RADAU5's argument list with the scheme's name in front; FCN is the
!> whole right-hand side, treated as stiff (see module taylorode_interfaces_legacy).
subroutine taylorode(scheme, n, fcn, x, y, xend, h, rtol, atol, itol, jac, ijac, mljac, mujac, mas, imas, mlmas, &
   mumas, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
   use taylorode_base_kinds, only: dp
   use taylorode_interfaces_legacy, only: legacy_solve, fcn_interface, jac_interface, solout_interface
   implicit none
   !> Scheme name, as users type it ('radau5', 'i-t-2', ...)
   character(len=*), intent(in) :: scheme
   !> Unknowns
   integer, intent(in) :: n
   !> The right-hand side, FCN(N, X, Y, F, RPAR, IPAR)
   procedure(fcn_interface) :: fcn
   !> Start time on entry, where the integration stopped on exit
   real(dp), intent(inout) :: x
   !> State at x
   real(dp), intent(inout) :: y(n)
   !> Final time, > x
   real(dp), intent(in) :: xend
   !> First step size on entry (0: automatic), the next one on exit
   real(dp), intent(inout) :: h
   !> Relative and absolute tolerances, scalars (itol = 0) or arrays of n (itol = 1)
   real(dp), intent(in) :: rtol(*), atol(*)
   !> 0 for scalar tolerances, 1 for one per component
   integer, intent(in) :: itol
   !> The Jacobian, JAC(N, X, Y, DFY, LDFY, RPAR, IPAR), called when ijac = 1
   procedure(jac_interface) :: jac
   !> 1: jac is given, 0: forward differences
   integer, intent(in) :: ijac
   !> Lower and upper bandwidths of the Jacobian (mljac >= n: dense; else both in [0, n - 1])
   integer, intent(in) :: mljac, mujac
   !> The mass matrix routine of RADAU5's list (never called)
   procedure() :: mas
   !> 0 (no mass matrix); anything else is an error (idid = -1)
   integer, intent(in) :: imas
   !> Bandwidths of the mass matrix (ignored)
   integer, intent(in) :: mlmas, mumas
   !> Called after every accepted step when iout = 1
   procedure(solout_interface) :: solout
   !> 1 to call solout, 0 not to
   integer, intent(in) :: iout
   !> Real inputs: work(2) safety factor, work(7) largest step (0: defaults)
   real(dp), intent(inout) :: work(*)
   !> Integer inputs and statistics: iwork(2) step budget, iwork(3) Newton iterations;
   !> iwork(14:20) evaluations, Jacobians, steps, accepted, rejected, LU, solves
   integer, intent(inout) :: iwork(*)
   !> Lengths of work and iwork (at least 20 each)
   integer, intent(in) :: lwork, liwork
   !> Real data passed to the user's routines untouched
   real(dp), intent(inout), target :: rpar(*)
   !> Integer data passed to the user's routines untouched
   integer, intent(inout), target :: ipar(*)
   !> 1 success, 2 stopped by solout, < 0 failure (see the module comment)
   integer, intent(out) :: idid
   if (imas /= 0) then
      idid = -1
      return
   end if
   call legacy_solve(scheme, n, fcn, fcn, .false., x, y, xend, h, rtol, atol, itol, jac, 0, jac, ijac, mljac, mujac, &
      solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
end subroutine taylorode

!> TAYLORODE_SPLIT, with f (FCNF, explicit in the semi-implicit schemes) and g (FCNG,
!> stiff) apart, each with its Jacobian (IJACF, IJACG = 0: differences).
subroutine taylorode_split(scheme, n, fcnf, fcng, x, y, xend, h, rtol, atol, itol, jacf, ijacf, jacg, ijacg, mljac, &
   mujac, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
   use taylorode_base_kinds, only: dp
   use taylorode_interfaces_legacy, only: legacy_solve, fcn_interface, jac_interface, solout_interface
   implicit none
   !> Scheme name, as users type it ('si-t-2', 'imex-rk21', ...)
   character(len=*), intent(in) :: scheme
   !> Unknowns
   integer, intent(in) :: n
   !> The non-stiff part f and the stiff part g, FCNF(N, X, Y, F, RPAR, IPAR)
   procedure(fcn_interface) :: fcnf, fcng
   !> Start time on entry, where the integration stopped on exit
   real(dp), intent(inout) :: x
   !> State at x
   real(dp), intent(inout) :: y(n)
   !> Final time, > x
   real(dp), intent(in) :: xend
   !> First step size on entry (0: automatic), the next one on exit
   real(dp), intent(inout) :: h
   !> Relative and absolute tolerances, scalars (itol = 0) or arrays of n (itol = 1)
   real(dp), intent(in) :: rtol(*), atol(*)
   !> 0 for scalar tolerances, 1 for one per component
   integer, intent(in) :: itol
   !> The Jacobians of f and g, called when ijacf = 1 and ijacg = 1
   procedure(jac_interface) :: jacf, jacg
   !> 1: the Jacobian is given, 0: forward differences
   integer, intent(in) :: ijacf, ijacg
   !> Lower and upper bandwidths of both Jacobians (mljac >= n: dense; else both in [0, n - 1])
   integer, intent(in) :: mljac, mujac
   !> Called after every accepted step when iout = 1
   procedure(solout_interface) :: solout
   !> 1 to call solout, 0 not to
   integer, intent(in) :: iout
   !> Real inputs (as TAYLORODE)
   real(dp), intent(inout) :: work(*)
   !> Integer inputs and statistics (as TAYLORODE)
   integer, intent(inout) :: iwork(*)
   !> Lengths of work and iwork (at least 20 each)
   integer, intent(in) :: lwork, liwork
   !> Real data passed to the user's routines untouched
   real(dp), intent(inout), target :: rpar(*)
   !> Integer data passed to the user's routines untouched
   integer, intent(inout), target :: ipar(*)
   !> 1 success, 2 stopped by solout, < 0 failure (see the module comment)
   integer, intent(out) :: idid
   call legacy_solve(scheme, n, fcnf, fcng, .true., x, y, xend, h, rtol, atol, itol, jacf, ijacf, jacg, ijacg, mljac, &
      mujac, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
end subroutine taylorode_split

!> TAYLORODE_CONTR(I, S, CONT, LRC), component I at S inside the step SOLOUT was
!> given (RADAU5's CONTR5), from the step's cubic Hermite interpolant.
function taylorode_contr(i, s, cont, lrc) result(value)
   use taylorode_base_kinds, only: dp
   use taylorode_interfaces_legacy, only: legacy_interpolate
   implicit none
   !> Component
   integer, intent(in) :: i
   !> Length of cont
   integer, intent(in) :: lrc
   !> Time inside the step
   real(dp), intent(in) :: s
   !> The step as SOLOUT received it
   real(dp), intent(in) :: cont(lrc)
   real(dp) :: value
   value = legacy_interpolate(i, s, cont, lrc)
end function taylorode_contr
