!> Semi-implicit Taylor schemes (METHODS.md section 1): g implicit, f explicit.
!>
!>   si-t-1:        U1 = U0 + h (f0 + g(U1))
!>   si-t-2:        U1 = U0 + h (f0 + g(U1)) + h^2/2 [ J_f0 F0 - J_g0 F(U1) ]        (order 2)
!>   si-t-2-paper:  U1 = U0 + h (f0 + g(U1)) + h^2/2 J0 (f0 - g(U1))  as printed in the
!>                  paper; only first order on nonlinear problems (second order on the
!>                  linear test equation), kept to reproduce the paper.
!>
!> Embedded pairs: si-t-1 with si-t-2, si-t-2 with si-t-1, si-t-2-paper with si-t-1.
!>
!> A problem that depends on t is advanced as the autonomous scheme advances (t, U)
!> with t' = 1 (in f): si-t-2 adds h^2/2 (f_t0 - g_t0), si-t-2-paper h^2/2 (f_t0 +
!> g_t0) to the known part of its equation, the time derivatives at U0 by differences
!> in t, and si-t-2's error estimate subtracts h g_t0 from E.
!>
!> The second-order members' Newton matrices I - h J_g1 + h^2/2 P J_g1 (P = J_g0, or
!> J0 for si-t-2-paper; si-t-2 adds h^2/2 J_g0 J_f0) are factored as the stacked
!> matrices [[I - h J_g1, h/2 P], [-h Q, I]] (Q = J_f0 + J_g1 for si-t-2, J_g1 for
!> si-t-2-paper), whose Schur complement they are: no product of Jacobians is formed,
!> and the solves keep their rounding errors at the size of h |lambda| instead of
!> (h |lambda|)^2 (see taylorode_newton_solver).
!>
!> si-t-2 evaluates the stiff g at the start of its step explicitly, in h^2/2 J_f0 F0:
!> an error e of the state it starts from reaches the new state as e + h^2/2 J_f J_g e
!> (besides what the stability function does with it), and with g stiff the second
!> term can exceed e by far (Van der Pol, paper split, h = 5: 2.6e4 times), as no
!> estimate of the step's own error sees. Its step (through `propagated_error`) and
!> its Newton increments (through the system's `propagate`) are therefore also
!> measured by what they become in the next step, M^(-1) h^2/2 J_f J_g e (the next
!> step's implicit solve damps what lands in stiff directions: without M^(-1),
!> Robertson to 1e11 took 100 times the steps for nothing).
module taylorode_schemes_semi_implicit_taylor
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_ok, status_invalid_argument
   use taylorode_base_memory, only: sized
   use taylorode_base_counters, only: counters_type
   use taylorode_linalg_matrix, only: matrix_type, new_matrix, stacked_row_scale
   use taylorode_problem_ode, only: ode_problem, difference_f
   use taylorode_newton_solver, only: newton_settings_type, newton_solver_type, nonlinear_system_type
   use taylorode_schemes_scheme, only: scheme_type, stability_quotient, evaluate_f, evaluate_g, evaluate_jac_f, &
      evaluate_jac_g, evaluate_time_derivative, of_f, of_g
   implicit none
   private

   public :: semi_implicit_taylor_type, new_semi_implicit_taylor
   public :: si_t_1, si_t_2, si_t_2_paper

   !> Member identifiers (also the indices of their Newton solvers)
   integer, parameter :: si_t_1 = 1, si_t_2 = 2, si_t_2_paper = 3

   !> A vector of one member
   type :: member_vector_type
      !> The values
      real(dp), allocatable :: values(:)
   end type member_vector_type

   !> The equation of one member: r(U) = U - known - h g(U) [+ the member's h^2 term]
   type, extends(nonlinear_system_type) :: semi_implicit_system_type
      !> Member being solved
      integer :: member = si_t_1
      !> End of the step and step size
      real(dp) :: t1 = 0.0_dp, h = 0.0_dp
      !> Known part of each member's update (allocated for the members in use)
      type(member_vector_type) :: known(3)
      !> f and g at the current Newton iterate (after an si-t-2 residual f1 holds F = f + g)
      real(dp), allocatable :: f1(:), g1(:)
      !> Jacobians at U0 (jac0 = J_f0 + J_g0, used by si-t-2-paper)
      class(matrix_type), allocatable :: jac_f0, jac_g0, jac0
      !> J_g at the current Newton iterate (si-t-1, si-t-2-paper)
      class(matrix_type), allocatable :: jac_g1
      !> Whether jac_g0 and jac_g1 hold dg/dU of a problem with linear g (kept for the
      !> integration)
      logical :: jac_g0_constant = .false., jac_g1_constant = .false.
      !> J_g0 e (si-t-2's propagated error; U0 - U1 in its step error)
      real(dp), allocatable :: stiff_part(:)
   contains
      procedure :: residual => semi_implicit_residual
      procedure :: newton_matrix => semi_implicit_matrix
      !> si-t-2: h^2/2 J_f0 J_g0 e
      procedure :: propagate => semi_implicit_propagate
   end type semi_implicit_system_type

   !> One member of the semi-implicit Taylor family, with its embedded partner
   type, extends(scheme_type) :: semi_implicit_taylor_type
      !> Member that advances (si_t_1, si_t_2 or si_t_2_paper)
      integer :: member = si_t_2
      !> Member that gives the error estimate
      integer :: partner = si_t_1
      !> f and g at U0
      real(dp), allocatable :: f0(:), g0(:)
      !> df/dt and dg/dt at U0, for a problem that depends on t
      real(dp), allocatable :: f_t0(:), g_t0(:)
      !> The state the values at U0 belong to
      real(dp), allocatable :: u_start(:)
      !> si-t-2's step error before the inverse Newton matrix is applied to it
      real(dp), allocatable :: unfiltered_error(:)
      !> Whether unfiltered_error belongs to the step just taken
      logical :: known_unfiltered_error = .false.
      !> The time the values at U0 belong to
      real(dp) :: t_start = 0.0_dp
      !> Which values at U0 are known: f0, g0 (and F0), the Jacobians J_f0 and J_g0,
      !> the time derivatives f_t0 and g_t0
      logical :: known_f0 = .false., known_g0 = .false., known_jacobians = .false., known_time_derivatives = .false.
      !> Whether each member's Newton solver and matrices exist
      logical :: ready(3) = .false.
      !> The equation being solved
      type(semi_implicit_system_type) :: system
      !> Newton's method for each member, each with its own matrix
      type(newton_solver_type) :: newton(3)
   contains
      !> One step of si-t-1, si-t-2 or si-t-2-paper and, when asked, the embedded difference
      procedure :: advance => semi_implicit_advance
      procedure :: prepare => semi_implicit_prepare
      !> Forget the factored Newton matrix kept between steps
      procedure :: restart => semi_implicit_restart
      !> Below a fraction of a step whose Newton solve kept no digit of its residual
      procedure :: largest_step => semi_implicit_largest_step
      !> si-t-1, si-t-2-paper: M^(-1) v with the member's last Newton matrix
      procedure :: damp_by_step_matrix => semi_implicit_damp
      !> f at the start of the last step
      procedure :: start_part => semi_implicit_start_part
      procedure :: stability => semi_implicit_stability
      !> si-t-2: the filtered trapezoidal defect of the step
      procedure :: step_error => semi_implicit_step_error
      !> si-t-2: h^2/2 J_f0 J_g0 e
      procedure :: propagated_error => semi_implicit_propagated_error
      !> si-t-2: the Newton correction of its locally extrapolated state
      procedure :: extrapolation_correction => semi_implicit_extrapolation_correction
   end type semi_implicit_taylor_type

contains

   !> The semi-implicit Taylor scheme `member` (si_t_1, si_t_2 or si_t_2_paper).
   function new_semi_implicit_taylor(member) result(self)
      !> Which member advances the solution
      integer, intent(in) :: member
      type(semi_implicit_taylor_type) :: self
      self%member = member
      self%implicit = .true.
      select case (member)
      case (si_t_1)
         self%name = "si-t-1"
         self%order = 1
         self%nonlinear_order = 1
         self%partner = si_t_2
         self%embedded_order = 2
         self%update = "U1 = U0 + h (f0 + g(U1))"
         self%newton_linear_in_g = .true.
         self%start_only_part = difference_f
         self%newton_matrices = "I - h J_g(U1)"
      case (si_t_2_paper)
         self%name = "si-t-2-paper"
         self%order = 2
         self%nonlinear_order = 1
         self%partner = si_t_1
         self%embedded_order = 1
         self%update = "U1 = U0 + h (f0 + g(U1)) + h^2/2 J0 (f0 - g(U1))"
         self%start_only_part = difference_f
         self%newton_matrices = "I - h J_g(U1) + h^2/2 J0 J_g(U1)"
      case default
         self%member = si_t_2
         self%name = "si-t-2"
         self%order = 2
         self%nonlinear_order = 2
         self%partner = si_t_1
         self%embedded_order = 1
         self%update = "U1 = U0 + h (f0 + g(U1)) + h^2/2 [J_f0 F0 - J_g0 F(U1)]"
         self%newton_matrices = "I - h J_g(U1) + h^2/2 J_g0 (J_f0 + J_g(U1))"
         self%estimates_step_error = .true.
         self%amplifies_errors = .true.
      end select
   end function new_semi_implicit_taylor

   !> R = (1 + z)/(1 - w) (si-t-1) or (1 + z + (z^2 + zw)/2)/(1 - w + (zw + w^2)/2).
   pure function semi_implicit_stability(self, z, w) result(r)
      class(semi_implicit_taylor_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r
      if (self%member == si_t_1) then
         r = stability_quotient(1.0_dp + z, 1.0_dp - w)
      else
         r = stability_quotient(1.0_dp + z + (z*z + z*w)/2.0_dp, 1.0_dp - w + (z*w + w*w)/2.0_dp)
      end if
   end function semi_implicit_stability

   !> Work arrays; the Newton matrices of the second-order members hold products of
   !> Jacobians and get the bandwidths of a product.
   subroutine semi_implicit_prepare(self, problem, n, stat)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      character(len=*), parameter :: what = "the work arrays of a semi-implicit Taylor scheme"
      integer :: k
      if (.not. self%resize(problem, n, stat)) return
      ! the Newton solvers and matrices of a member are made when it is first used
      do k = 1, size(self%newton)
         self%newton(k) = newton_solver_type()
      end do
      self%ready = .false.
      call sized(self%f0, n, what, stat)
      call sized(self%g0, n, what, stat)
      call sized(self%u_start, n, what, stat)
      call sized(self%unfiltered_error, n, what, stat)
      call sized(self%f_t0, merge(n, 0, .not. problem%autonomous), what, stat)
      call sized(self%g_t0, merge(n, 0, .not. problem%autonomous), what, stat)
      call forget_start(self)
      associate (system => self%system)
         call sized(system%f1, n, what, stat)
         call sized(system%g1, n, what, stat)
         call sized(system%stiff_part, n, what, stat)
         do k = 1, size(system%known)
            if (allocated(system%known(k)%values)) deallocate (system%known(k)%values)
         end do
         if (allocated(system%jac_f0)) deallocate (system%jac_f0)
         if (allocated(system%jac_g0)) deallocate (system%jac_g0)
         if (allocated(system%jac0)) deallocate (system%jac0)
         if (allocated(system%jac_g1)) deallocate (system%jac_g1)
      end associate
      if (stat%code /= status_ok) self%n = 0
   end subroutine semi_implicit_prepare

   !> The Newton solver and the matrices of `member`, made on its first use: si-t-1
   !> needs J_g at the iterate; si-t-2 J_f and J_g at U0 (and J_g at the iterate,
   !> made when a Newton matrix is first built, unless g is linear); si-t-2-paper
   !> both, J_g at the iterate and J0 = J_f0 + J_g0. The second-order members' Newton
   !> solvers are stacked.
   subroutine make_member(self, member, stat)
      class(semi_implicit_taylor_type), intent(inout) :: self
      integer, intent(in) :: member
      type(status_type), intent(inout) :: stat
      if (self%ready(member)) return
      if (member == si_t_1) then
         call self%newton(member)%init(self%n, self%structure, stat)
      else
         call self%newton(member)%init(self%n, self%structure, stat, stacked=.true.)
      end if
      associate (system => self%system)
         if (member /= si_t_2) call make_matrix(system%jac_g1)
         if (member /= si_t_1) then
            call make_matrix(system%jac_f0)
            call make_matrix(system%jac_g0)
         end if
         if (member == si_t_2_paper) call make_matrix(system%jac0)
         call sized(system%known(member)%values, self%n, "the work arrays of a semi-implicit Taylor scheme", stat)
      end associate
      self%ready(member) = stat%code == status_ok
   contains
      subroutine make_matrix(matrix)
         class(matrix_type), allocatable, intent(inout) :: matrix
         if (.not. allocated(matrix) .and. stat%code == status_ok) call new_matrix(matrix, self%n, self%structure, stat)
      end subroutine make_matrix
   end subroutine make_member

   !> The longest step its Newton solvers can still resolve (see scheme_type's
   !> largest_step).
   pure real(dp) function semi_implicit_largest_step(self)
      class(semi_implicit_taylor_type), intent(in) :: self
      semi_implicit_largest_step = minval(self%newton%step_limit)
   end function semi_implicit_largest_step

   subroutine semi_implicit_damp(self, v)
      class(semi_implicit_taylor_type), intent(inout) :: self
      real(dp), contiguous, intent(inout) :: v(:)
      type(status_type) :: stat
      ! (without factors, as after a failed solve, v stays as it is)
      call self%newton(self%member)%apply_inverse(v, self%counters, stat)
   end subroutine semi_implicit_damp

   subroutine semi_implicit_start_part(self, value, at, kept)
      class(semi_implicit_taylor_type), intent(in) :: self
      real(dp), intent(inout) :: value(:)
      real(dp), intent(out) :: at
      logical, intent(out) :: kept
      at = self%t_start
      kept = self%known_f0
      if (kept) value = self%f0
   end subroutine semi_implicit_start_part

   subroutine semi_implicit_restart(self)
      class(semi_implicit_taylor_type), intent(inout) :: self
      call self%newton%forget()
      call forget_start(self)
      self%system%jac_g0_constant = .false.
      self%system%jac_g1_constant = .false.
   end subroutine semi_implicit_restart

   subroutine semi_implicit_advance(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)

      logical :: needed(3)

      needed = .false.
      needed(self%member) = .true.
      if (present(delta)) needed(self%partner) = .true.
      call make_member(self, self%member, stat)
      if (present(delta)) call make_member(self, self%partner, stat)
      if (stat%code /= status_ok) return

      associate (system => self%system)
         system%t1 = t + h
         system%h = h
         ! the values at U0 serve every step from it (step doubling's single and first
         ! half step, a retry after a rejection): computed once per state, or taken over
         ! from the error estimate of the step that ended there
         if (self%known_f0) then
            if (t /= self%t_start .or. any(u0 /= self%u_start)) call forget_start(self)
         end if
         if (.not. self%known_f0) then
            call evaluate_f(problem, t, u0, self%f0, self%counters)
            self%t_start = t
            self%u_start = u0
            self%known_f0 = .true.
         end if
         if ((needed(si_t_2) .or. needed(si_t_2_paper)) .and. .not. self%known_jacobians) then
            call evaluate_jac_f(problem, t, u0, system%jac_f0, self%counters, stat)
            if (stat%code /= status_ok) return
            if (.not. (problem%linear_g .and. system%jac_g0_constant)) then
               call evaluate_jac_g(problem, t, u0, system%jac_g0, self%counters, stat)
               if (stat%code /= status_ok) return
               system%jac_g0_constant = problem%linear_g
            end if
            self%known_jacobians = .true.
         end if
         if ((needed(si_t_2) .or. (needed(si_t_2_paper) .and. .not. problem%autonomous)) .and. &
            .not. self%known_g0) then
            call evaluate_g(problem, t, u0, self%g0, self%counters)
            self%known_g0 = .true.
         end if
         if ((needed(si_t_2) .or. needed(si_t_2_paper)) .and. .not. problem%autonomous .and. &
            .not. self%known_time_derivatives) then
            ! forward from t: inside the step
            call evaluate_time_derivative(problem, of_f, t, h, u0, self%f0, self%f_t0, system%g1, self%counters)
            call evaluate_time_derivative(problem, of_g, t, h, u0, self%g0, self%g_t0, system%g1, self%counters)
            self%known_time_derivatives = .true.
         end if
         ! values the problem rejected are not kept
         if (problem%evaluation_rejected()) call forget_start(self)
         if (needed(si_t_1)) system%known(si_t_1)%values = u0 + h*self%f0
         if (needed(si_t_2)) then
            system%known(si_t_2)%values = u0 + h*self%f0
            ! F0 in f1, free until the residual
            system%f1 = self%f0 + self%g0
            call system%jac_f0%multiply_add(0.5_dp*h*h, system%f1, system%known(si_t_2)%values)
            if (.not. problem%autonomous) system%known(si_t_2)%values = system%known(si_t_2)%values + &
               0.5_dp*h*h*(self%f_t0 - self%g_t0)
         end if
         if (needed(si_t_2_paper)) then
            call system%jac0%set_scaled(1.0_dp, system%jac_f0, stat)
            call system%jac0%add_scaled(1.0_dp, system%jac_g0, stat)
            system%known(si_t_2_paper)%values = u0 + h*self%f0
            call system%jac0%multiply_add(0.5_dp*h*h, self%f0, system%known(si_t_2_paper)%values)
            if (.not. problem%autonomous) system%known(si_t_2_paper)%values = system%known(si_t_2_paper)%values + &
               0.5_dp*h*h*(self%f_t0 + self%g_t0)
         end if
         if (stat%code /= status_ok) return

         system%member = self%member
         system%linear = problem%linear_g .and. self%member == si_t_1
         if (present(guess)) then
            u1 = guess
         else
            u1 = u0
         end if
         call self%newton(self%member)%solve(system, problem, h, newton, u1, self%counters, stat)
         if (stat%code /= status_ok .or. .not. present(delta)) return

         system%member = self%partner
         system%linear = problem%linear_g .and. self%partner == si_t_1
         delta = u1
         call self%newton(self%partner)%solve(system, problem, h, newton, delta, self%counters, stat)
      end associate
      if (stat%code /= status_ok) return
      if (self%order > self%embedded_order) then
         delta = u1 - delta
      else
         delta = delta - u1
      end if
   end subroutine semi_implicit_advance

   !> Forget the values kept at the start of a step.
   elemental subroutine forget_start(self)
      type(semi_implicit_taylor_type), intent(inout) :: self
      self%known_f0 = .false.
      self%known_g0 = .false.
      self%known_jacobians = .false.
      self%known_time_derivatives = .false.
      self%known_unfiltered_error = .false.
   end subroutine forget_start

   !> The local error of the si-t-2 step just taken from (t, u0) to u1. With D = U1 -
   !> U0 - h/2 (F0 + F1), the trapezoidal defect, and E = g1 - g0 - J_g0 (U1 - U0) (- h
   !> g_t0 when the problem depends on t), the
   !> error is -h^3/6 U''' + h^3/2 g''(F, F) + O(h^4) = 2/3 D + h/3 E + O(h^4); the
   !> estimate is that, multiplied by the inverse of the step's Newton matrix (which
   !> leaves it unchanged to O(h^4) and damps the stiff components as the step
   !> does). f and g at U1 serve the next step from U1.
   subroutine semi_implicit_step_error(self, problem, t, h, u0, u1, error, stat)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:), u1(:)
      real(dp), contiguous, intent(out) :: error(:)
      type(status_type), intent(inout) :: stat
      integer :: i
      error = 0.0_dp
      if (self%member /= si_t_2 .or. .not. (self%known_f0 .and. self%known_g0 .and. self%known_jacobians .and. &
         (self%known_time_derivatives .or. problem%autonomous))) then
         call set_code(stat, status_invalid_argument)
         return
      end if
      if (t /= self%t_start .or. any(u0 /= self%u_start)) then
         call set_code(stat, status_invalid_argument)
         return
      end if
      associate (system => self%system)
         call evaluate_f(problem, t + h, u1, system%f1, self%counters)
         call evaluate_g(problem, t + h, u1, system%g1, self%counters)
         if (problem%evaluation_rejected()) return
         do i = 1, size(u1)
            error(i) = (2.0_dp/3.0_dp)*(u1(i) - u0(i) - 0.5_dp*h*((self%f0(i) + self%g0(i)) + system%f1(i) + system%g1(i)))
         end do
         if (.not. (problem%linear_g .and. problem%autonomous)) then
            system%stiff_part = u0 - u1
            error = error + (h/3.0_dp)*(system%g1 - self%g0)
            call system%jac_g0%multiply_add(h/3.0_dp, system%stiff_part, error)
            if (.not. problem%autonomous) error = error - (h*h/3.0_dp)*self%g_t0
         end if
         self%unfiltered_error = error
         call self%newton(si_t_2)%apply_inverse(error, self%counters, stat)
         ! the values at U1 start the next step
         self%t_start = t + h
         self%u_start = u1
         self%f0 = system%f1
         self%g0 = system%g1
         self%known_f0 = .true.
         self%known_g0 = .true.
         self%known_jacobians = .false.
         self%known_time_derivatives = .false.
         self%known_unfiltered_error = stat%code == status_ok
      end associate
   end subroutine semi_implicit_step_error

   !> si-t-2's local extrapolation U = U1 - M^(-1) e (e its step error before the filter,
   !> M the step's Newton matrix) solves r(U) = -e, the step's equation offset by e, only
   !> to first order, and M's J_g may be several steps old: in a stiff direction the
   !> rest can be large, and the next step's h^2/2 J_f0 F0 amplifies it (Van der Pol,
   !> mu = 1e6: kicks to y of a tenth of the tolerance, of one sign, step after step,
   !> until y ran away). The correction is one more Newton step with M, M^(-1) (r(U) +
   !> e); f and g evaluated at U start the next step when it is not applied. The other
   !> members, and an evaluation the problem rejects, give none.
   subroutine semi_implicit_extrapolation_correction(self, problem, t, h, u1, correction, corrected)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u1(:)
      real(dp), contiguous, intent(inout) :: correction(:)
      logical, intent(out) :: corrected
      type(status_type) :: solve_stat
      corrected = .false.
      if (self%member /= si_t_2 .or. .not. self%known_unfiltered_error .or. t + h /= self%t_start) return
      self%known_unfiltered_error = .false.
      ! f and g at U: the next step's values at its start
      call forget_start(self)
      call evaluate_f(problem, t + h, u1, self%f0, self%counters)
      call evaluate_g(problem, t + h, u1, self%g0, self%counters)
      if (problem%evaluation_rejected()) then
         call problem%clear_rejection()
         return
      end if
      self%u_start = u1
      self%known_f0 = .true.
      self%known_g0 = .true.
      associate (system => self%system)
         ! r(U) + e = U - known - h g + h^2/2 J_g0 (f + g) + e
         correction = u1 - system%known(si_t_2)%values - h*self%g0 + self%unfiltered_error
         system%f1 = self%f0 + self%g0
         call system%jac_g0%multiply_add(0.5_dp*h*h, system%f1, correction)
      end associate
      call self%newton(si_t_2)%apply_inverse(correction, self%counters, solve_stat)
      corrected = solve_stat%code == status_ok
   end subroutine semi_implicit_extrapolation_correction

   !> propagated = h^2/2 J_f0 J_g0 error (filtered: M^(-1) times it), with the Jacobians
   !> and the Newton matrix M of the step just taken: what an error of its state adds
   !> to the next step (0 before si-t-2 has taken one).
   subroutine semi_implicit_propagated_error(self, h, error, propagated, filtered)
      class(semi_implicit_taylor_type), intent(inout) :: self
      real(dp), intent(in) :: h
      real(dp), contiguous, intent(in) :: error(:)
      real(dp), contiguous, intent(out) :: propagated(:)
      logical, intent(in) :: filtered
      type(status_type) :: filter_stat
      propagated = 0.0_dp
      if (.not. self%ready(si_t_2)) return
      call amplify(self%system, h, error, propagated)
      if (.not. filtered) return
      call self%newton(si_t_2)%apply_inverse(propagated, self%counters, filter_stat)
      if (filter_stat%code /= status_ok) propagated = 0.0_dp
   end subroutine semi_implicit_propagated_error

   !> si-t-2: propagated = h^2/2 J_f0 J_g0 error (the other members propagate nothing).
   subroutine semi_implicit_propagate(self, error, propagated, active)
      class(semi_implicit_system_type), intent(inout) :: self
      real(dp), intent(in) :: error(:)
      real(dp), intent(out) :: propagated(:)
      logical, intent(out) :: active
      active = self%member == si_t_2
      if (active) call amplify(self, self%h, error, propagated)
   end subroutine semi_implicit_propagate

   !> propagated = h^2/2 J_f0 J_g0 error.
   subroutine amplify(system, h, error, propagated)
      type(semi_implicit_system_type), intent(inout) :: system
      real(dp), intent(in) :: h, error(:)
      real(dp), intent(out) :: propagated(:)
      system%stiff_part = 0.0_dp
      call system%jac_g0%multiply_add(1.0_dp, error, system%stiff_part)
      propagated = 0.0_dp
      call system%jac_f0%multiply_add(0.5_dp*h*h, system%stiff_part, propagated)
   end subroutine amplify

   subroutine semi_implicit_residual(self, problem, u, r, counters)
      class(semi_implicit_system_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      real(dp), contiguous, intent(out) :: r(:)
      type(counters_type), intent(inout) :: counters

      real(dp) :: half_h2

      half_h2 = 0.5_dp*self%h*self%h
      call evaluate_g(problem, self%t1, u, self%g1, counters)
      r = u - self%known(self%member)%values - self%h*self%g1
      select case (self%member)
      case (si_t_2)
         call evaluate_f(problem, self%t1, u, self%f1, counters)
         self%f1 = self%f1 + self%g1
         call self%jac_g0%multiply_add(half_h2, self%f1, r)
      case (si_t_2_paper)
         call self%jac0%multiply_add(half_h2, self%g1, r)
      end select
   end subroutine semi_implicit_residual

   subroutine semi_implicit_matrix(self, problem, u, matrix, counters, stat)
      class(semi_implicit_system_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      class(matrix_type), intent(inout) :: matrix
      type(counters_type), intent(inout) :: counters
      type(status_type), intent(inout) :: stat
      real(dp) :: row_scale

      if (self%member == si_t_2) then
         ! [[I - h J_g1, h/2 J_g0], [-h (J_f0 + J_g1), I]]: J_f from U0, J_g at the
         ! iterate (with g linear: the J_g it already has)
         if (problem%linear_g) then
            call add_si_t_2_blocks(self%jac_g0)
         else
            if (.not. allocated(self%jac_g1)) call new_matrix(self%jac_g1, size(u), self%jac_g0%structure(), stat)
            if (stat%code /= status_ok) return
            call evaluate_jac_g(problem, self%t1, u, self%jac_g1, counters, stat)
            if (stat%code /= status_ok) return
            call add_si_t_2_blocks(self%jac_g1)
         end if
      else
         if (.not. (problem%linear_g .and. self%jac_g1_constant)) then
            call evaluate_jac_g(problem, self%t1, u, self%jac_g1, counters, stat)
            if (stat%code /= status_ok) return
            self%jac_g1_constant = problem%linear_g
         end if
         if (self%member == si_t_2_paper) then
            ! [[I - h J_g1, h/2 J0], [-h J_g1, I]]
            row_scale = stacked_row_scale(self%h*self%jac_g1%largest_magnitude())
            call matrix%add_block(-self%h, self%jac_g1, 1, 1, stat)
            call matrix%add_block(0.5_dp*self%h, self%jac0, 1, 2, stat)
            call matrix%add_block(-row_scale*self%h, self%jac_g1, 2, 1, stat)
         else
            call matrix%add_scaled(-self%h, self%jac_g1, stat)
            call matrix%add_identity(1.0_dp)
            return
         end if
      end if
      call matrix%add_identity(1.0_dp, row_scale)

   contains

      !> The blocks of si-t-2's stacked matrix but the identity, with J_g1 at the iterate
      subroutine add_si_t_2_blocks(jac_g1)
         class(matrix_type), intent(in) :: jac_g1
         row_scale = stacked_row_scale(self%h*max(self%jac_f0%largest_magnitude(), jac_g1%largest_magnitude()))
         call matrix%add_block(-self%h, jac_g1, 1, 1, stat)
         call matrix%add_block(0.5_dp*self%h, self%jac_g0, 1, 2, stat)
         call matrix%add_block(-row_scale*self%h, self%jac_f0, 2, 1, stat)
         call matrix%add_block(-row_scale*self%h, jac_g1, 2, 1, stat)
      end subroutine add_si_t_2_blocks

   end subroutine semi_implicit_matrix

end module taylorode_schemes_semi_implicit_taylor
