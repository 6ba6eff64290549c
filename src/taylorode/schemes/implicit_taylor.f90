!> Implicit Taylor schemes I-T-1 and I-T-2 (METHODS.md section 1), an embedded pair.
!>
!>   i-t-1:  U1 = U0 + h F(U1)                               Newton matrix I - h J(U1)
!>   i-t-2:  U1 = U0 + h F(U1) - h^2/2 J(U1) F(U1)           Newton matrix I - h J + h^2/2 J^2
!>
!> The paper's i-t-2 matrix omits the second derivatives of F: Newton converges to
!> the same U1, only its rate changes, and on stiff quadratic problems with long
!> steps (Robertson) it diverges. Unless the Newton settings ask for the paper's
!> matrices, the i-t-2 matrix is exact: I - h J + h^2/2 (J^2 + F''(U)[F(U)]), the
!> last term the derivative of J along F, formed by differencing the Jacobians.
!> It is factored as the stacked matrix [[I - h J + h^2/2 F''[F], h/2 J], [-h J, I]],
!> whose Schur complement it is: J^2 is never formed, and the solves keep their
!> rounding errors at the size of h |lambda| instead of (h |lambda|)^2 (see
!> taylorode_newton_solver).
!>
!> The i-t-2 residual needs J(U) F(U) at every iterate: it adds it through the
!> problem's `add_jacobian_product` (exact: a product of the problem's own, else J from
!> `jac` times F), so that J itself is evaluated only where a Newton matrix is built.
!>
!> A problem that depends on t is advanced as the autonomous scheme advances (t, U)
!> with t' = 1: i-t-2's residual has h^2/2 (J F + dF/dt)(t1, U), dF/dt by a backward
!> difference in t (inside the step), and the derivative of J in its Newton matrix is
!> taken along (1, F).
module taylorode_schemes_implicit_taylor
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, status_ok
   use taylorode_base_memory, only: sized
   use taylorode_base_counters, only: counters_type
   use taylorode_linalg_matrix, only: matrix_type, new_matrix, stacked_row_scale
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type, newton_solver_type, nonlinear_system_type
   use taylorode_schemes_scheme, only: scheme_type, stability_quotient, evaluate_jac, evaluate_rhs, &
      evaluate_time_derivative, of_rhs
   implicit none
   private

   public :: implicit_taylor_type, new_implicit_taylor

   !> F at an iterate this many times larger than at the step's start marks the iterate
   !> as off the solution's slow manifold (its stiff components dominate F there)
   real(dp), parameter :: off_manifold_ratio = 10.0_dp
   !> Unknowns up to which the residual's loop is scalar (see first_order_residual)
   integer, parameter :: scalar_residual_limit = 8

   !> The equation of one member: r(U) = U - U0 - h F(U) [+ h^2/2 J(U) F(U) for order 2]
   type, extends(nonlinear_system_type) :: implicit_taylor_system_type
      !> Member (1 or 2)
      integer :: order = 1
      !> End of the step and step size
      real(dp) :: t1 = 0.0_dp, h = 0.0_dp
      !> State at the start of the step
      real(dp), allocatable :: u0(:)
      !> F = f + g at the current iterate
      real(dp), allocatable :: rhs1(:)
      !> dF/dt at the current iterate (i-t-2, a problem that depends on t)
      real(dp), allocatable :: rhs_t1(:)
      !> J = J_f + J_g where the last Newton matrix was built
      class(matrix_type), allocatable :: jac1
      !> Whether the i-t-2 Newton matrix has the second-derivative term; J at U +
      !> epsilon F(U) and that point
      logical :: second_derivatives = .true.
      class(matrix_type), allocatable :: jac_probe
      real(dp), allocatable :: probe(:)
      !> F at the start of the step (evaluated when a Newton matrix with the
      !> second-derivative term is first built in the step, or kept from the last
      !> defect check), and whether it is known
      real(dp), allocatable :: rhs0(:)
      logical :: rhs0_known = .false.
   contains
      procedure :: residual => implicit_taylor_residual
      procedure :: newton_matrix => implicit_taylor_matrix
   end type implicit_taylor_system_type

   !> I-T-1 (order 1) or I-T-2 (order 2); the other member gives the error estimate
   type, extends(scheme_type) :: implicit_taylor_type
      !> The equation being solved
      type(implicit_taylor_system_type) :: system
      !> Newton's method for each member (by order), each with its own matrix
      type(newton_solver_type) :: newton(2)
      !> F at the end of the last step whose defect was checked (F at the start of the
      !> next step when it starts there)
      real(dp), allocatable :: rhs_checked(:)
      !> The state there
      real(dp), allocatable :: u_checked(:)
      !> The time there
      real(dp) :: t_checked = 0.0_dp
      !> Whether rhs_checked holds F at (t_checked, u_checked)
      logical :: checked = .false.
   contains
      !> One step of i-t-1 or i-t-2 and, when asked, the embedded difference
      procedure :: advance => implicit_taylor_advance
      procedure :: prepare => implicit_taylor_prepare
      !> Forget the factored Newton matrix kept between steps
      procedure :: restart => implicit_taylor_restart
      !> Below a fraction of a step whose Newton solve kept no digit of its residual
      procedure :: largest_step => implicit_taylor_largest_step
      procedure :: stability => implicit_taylor_stability
      !> i-t-2: the filtered trapezoidal defect of a step
      procedure :: step_error => implicit_taylor_step_error
      !> Whether rhs_checked holds F at (t, u)
      procedure, private :: holds_rhs_at
   end type implicit_taylor_type

contains

   !> I-T-1 (order = 1) or I-T-2 (order = 2).
   function new_implicit_taylor(order) result(self)
      !> 1 or 2
      integer, intent(in) :: order
      type(implicit_taylor_type) :: self
      self%order = order
      self%embedded_order = 3 - order
      self%nonlinear_order = order
      self%implicit = .true.
      if (order == 1) then
         self%name = "i-t-1"
         self%update = "U1 = U0 + h F(U1)"
         self%newton_matrices = "I - h J(U1)"
      else
         self%name = "i-t-2"
         self%update = "U1 = U0 + h F(U1) - h^2/2 J(U1) F(U1)"
         self%checks_defect = .true.
         self%newton_matrices = "I - h J(U1) + h^2/2 J(U1)^2"
      end if
   end function new_implicit_taylor

   !> R = 1/(1 - s) (i-t-1) or 1/(1 - s (1 - s/2)) (i-t-2), s = z + w.
   pure function implicit_taylor_stability(self, z, w) result(r)
      class(implicit_taylor_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r, s
      s = z + w
      if (self%order == 1) then
         r = stability_quotient((1.0_dp, 0.0_dp), 1.0_dp - s)
      else
         r = stability_quotient((1.0_dp, 0.0_dp), 1.0_dp - s*(1.0_dp - s/2.0_dp))
      end if
   end function implicit_taylor_stability

   !> Work arrays; the i-t-2 Newton solver is stacked.
   subroutine implicit_taylor_prepare(self, problem, n, stat)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      character(len=*), parameter :: what = "the work arrays of an implicit Taylor scheme"
      if (.not. self%resize(problem, n, stat)) return
      call self%newton(1)%init(n, self%structure, stat)
      if (stat%code == status_ok) call self%newton(2)%init(n, self%structure, stat, stacked=.true.)
      call sized(self%rhs_checked, n, what, stat)
      call sized(self%u_checked, n, what, stat)
      self%checked = .false.
      associate (system => self%system)
         call sized(system%u0, n, what, stat)
         call sized(system%rhs1, n, what, stat)
         call sized(system%probe, n, what, stat)
         call sized(system%rhs_t1, merge(n, 0, .not. problem%autonomous), what, stat)
         call sized(system%rhs0, n, what, stat)
         if (stat%code == status_ok) call new_matrix(system%jac1, n, self%structure, stat)
         if (self%order == 2 .and. stat%code == status_ok) call new_matrix(system%jac_probe, n, self%structure, stat)
      end associate
      if (stat%code /= status_ok) self%n = 0
   end subroutine implicit_taylor_prepare

   !> The longest step its Newton solvers can still resolve (see scheme_type's
   !> largest_step).
   pure real(dp) function implicit_taylor_largest_step(self)
      class(implicit_taylor_type), intent(in) :: self
      implicit_taylor_largest_step = minval(self%newton%step_limit)
   end function implicit_taylor_largest_step

   subroutine implicit_taylor_restart(self)
      class(implicit_taylor_type), intent(inout) :: self
      call self%newton%forget()
      self%checked = .false.
   end subroutine implicit_taylor_restart

   subroutine implicit_taylor_advance(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)
      integer :: i

      self%system%t1 = t + h
      self%system%h = h
      ! (the copies below are loops not unrolled: on a few unknowns the unrolled loops'
      ! entries cost more than the copies)
      !GCC$ unroll 1
      do i = 1, size(u0)
         self%system%u0(i) = u0(i)
      end do
      self%system%order = self%order
      self%system%second_derivatives = newton%exact_matrix
      ! F at the start: kept from the last defect check when this step starts there
      self%system%rhs0_known = self%holds_rhs_at(t, u0)
      if (self%system%rhs0_known) self%system%rhs0 = self%rhs_checked
      if (present(guess)) then
         u1 = guess
      else
         !GCC$ unroll 1
         do i = 1, size(u0)
            u1(i) = u0(i)
         end do
      end if
      call self%newton(self%order)%solve(self%system, problem, h, newton, u1, self%counters, stat)
      if (stat%code /= status_ok .or. .not. present(delta)) return

      self%system%order = self%embedded_order
      !GCC$ unroll 1
      do i = 1, size(u1)
         delta(i) = u1(i)
      end do
      call self%newton(self%embedded_order)%solve(self%system, problem, h, newton, delta, self%counters, stat)
      if (stat%code /= status_ok) return
      if (self%order == 2) then
         !GCC$ unroll 1
         do i = 1, size(u1)
            delta(i) = u1(i) - delta(i)
         end do
      else
         !GCC$ unroll 1
         do i = 1, size(u1)
            delta(i) = delta(i) - u1(i)
         end do
      end if
   end subroutine implicit_taylor_advance

   !> Whether rhs_checked holds F at (t, u): the last defect check ended there.
   pure logical function holds_rhs_at(self, t, u)
      class(implicit_taylor_type), intent(in) :: self
      real(dp), intent(in) :: t, u(:)
      holds_rhs_at = self%checked
      if (holds_rhs_at) holds_rhs_at = t == self%t_checked .and. all(u == self%u_checked)
   end function holds_rhs_at

   !> error = M^(-1) 2/3 (u1 - u0 - h/2 (F0 + F1)), M the Newton matrix of i-t-2's last
   !> solve: 2/3 of the trapezoidal defect is i-t-2's local error, -h^3/6 U''', to
   !> O(h^4) (the trapezoidal rule's own defect is -h^3/12 U'''). F1 is F at u1, kept for
   !> the next step's F0; F0 is the F kept from the last check when that ended at
   !> (t, u0), else evaluated.
   subroutine implicit_taylor_step_error(self, problem, t, h, u0, u1, error, stat)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:), u1(:)
      real(dp), contiguous, intent(out) :: error(:)
      type(status_type), intent(inout) :: stat
      integer :: i
      self%checked = self%holds_rhs_at(t, u0)
      if (.not. self%checked) call evaluate_rhs(problem, t, u0, self%rhs_checked, self%counters)
      ! F0 into error, then F1 into rhs_checked
      error = self%rhs_checked
      call evaluate_rhs(problem, t + h, u1, self%rhs_checked, self%counters)
      do i = 1, size(u1)
         error(i) = (2.0_dp/3.0_dp)*(u1(i) - u0(i) - 0.5_dp*h*(error(i) + self%rhs_checked(i)))
      end do
      self%t_checked = t + h
      self%u_checked = u1
      self%checked = .true.
      call self%newton(2)%apply_inverse(error, self%counters, stat)
   end subroutine implicit_taylor_step_error

   !> r(U) = U - U0 - h F(U) [+ h^2/2 (J(U) F(U) + dF/dt(U)) for order 2, J F through the
   !> problem's `add_jacobian_product`, dF/dt = 0 for an autonomous problem]; keeps F(U)
   !> for the matrix.
   subroutine implicit_taylor_residual(self, problem, u, r, counters)
      class(implicit_taylor_system_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      real(dp), contiguous, intent(out) :: r(:)
      type(counters_type), intent(inout) :: counters
      integer :: i

      ! F and J F in one call each (not through counting wrappers: on small systems each
      ! layer of calls costs as much as the arithmetic)
      call problem%rhs(self%t1, u, self%rhs1)
      counters%f_evaluations = counters%f_evaluations + 1
      counters%g_evaluations = counters%g_evaluations + 1
      call first_order_residual(size(u), u, self%u0, self%h, self%rhs1, r)
      if (self%order == 2) then
         call problem%add_jacobian_product(self%t1, u, 0.5_dp*self%h*self%h, self%rhs1, r)
         counters%jacobian_products = counters%jacobian_products + 1
         if (.not. problem%autonomous) then
            call evaluate_time_derivative(problem, of_rhs, self%t1, -self%h, u, self%rhs1, self%rhs_t1, self%probe, &
               counters)
            do i = 1, size(u)
               r(i) = r(i) + 0.5_dp*self%h*self%h*self%rhs_t1(i)
            end do
         end if
      end if
   end subroutine implicit_taylor_residual

   !> r = u - u0 - h F, explicit-shape: through the system's components the loop reloaded
   !> their descriptors at every entry, which on a few unknowns cost more than the
   !> arithmetic. On a few unknowns the loop is scalar: Newton and F have just stored u
   !> and F entry by entry, and the vector loop's paired loads of them wait until those
   !> stores are done (Van der Pol, i-t-2: 11 % of the time per step).
   pure subroutine first_order_residual(n, u, u0, h, rhs, r)
      !> Unknowns
      integer, intent(in) :: n
      !> The iterate, the state at the start of the step, F at the iterate
      real(dp), intent(in) :: u(n), u0(n), rhs(n)
      !> Step size
      real(dp), intent(in) :: h
      !> The residual
      real(dp), intent(out) :: r(n)
      integer :: i
      if (n <= scalar_residual_limit) then
         !GCC$ unroll 1
         !GCC$ novector
         do i = 1, n
            r(i) = u(i) - u0(i) - h*rhs(i)
         end do
      else
         !GCC$ unroll 1
         do i = 1, n
            r(i) = u(i) - u0(i) - h*rhs(i)
         end do
      end if
   end subroutine first_order_residual

   !> I - h J(U), or for order 2 the stacked [[I - h J + h^2/2 F''[F], h/2 J], [-h J, I]]
   !> (F(U) reused from the residual), whose Schur complement is I - h J + h^2/2 (J^2 + F''[F]);
   !> F''[F] is the derivative of J along (1, F) in (t, U) (with dJ/dt when the problem
   !> depends on t, then by a backward difference, inside the step). F there is F at the
   !> iterate, unless that is more than off_manifold_ratio times F at the step's start:
   !> at the root both lie near the solution's slow manifold, but an iterate off it (an
   !> extrapolated guess) has F dominated by its stiff components, orders of magnitude
   !> larger, and the term built with that F makes the slow part of the matrix wrong by as
   !> much (Van der Pol, mu = 1e6, tol 1e-2: Newton's increments in y were 1e-8 of the
   !> distance to the root, it stopped there, and the solution froze at y = 1.98 with
   !> status ok); F at the start is then the better guess of F at the root. Newton
   !> converges to the same root with either: only the matrix changes.
   subroutine implicit_taylor_matrix(self, problem, u, matrix, counters, stat)
      class(implicit_taylor_system_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      class(matrix_type), intent(inout) :: matrix
      type(counters_type), intent(inout) :: counters
      type(status_type), intent(inout) :: stat

      real(dp) :: epsilon_f, side, t_probe, size_now, size_start, size_along, row_scale
      logical :: along_start

      call evaluate_jac(problem, self%t1, u, self%jac1, counters, stat)
      if (stat%code /= status_ok) return
      if (self%order /= 2) then
         call matrix%add_scaled(-self%h, self%jac1, stat)
         call matrix%add_identity(1.0_dp)
      else
         row_scale = stacked_row_scale(self%h*self%jac1%largest_magnitude())
         call matrix%add_block(-self%h, self%jac1, 1, 1, stat)
         call matrix%add_block(0.5_dp*self%h, self%jac1, 1, 2, stat)
         call matrix%add_block(-row_scale*self%h, self%jac1, 2, 1, stat)
         if (self%second_derivatives .and. allocated(self%jac_probe)) then
            if (.not. self%rhs0_known) then
               call evaluate_rhs(problem, self%t1 - self%h, self%u0, self%rhs0, counters)
               self%rhs0_known = .true.
            end if
            size_now = norm2(self%rhs1)
            size_start = norm2(self%rhs0)
            along_start = size_now > off_manifold_ratio*size_start
            ! F''(U)[F] = (J(U + e F) - J(U)) / e, e F of the size of sqrt(eps) max(|U|,
            ! h |F|): relative to U, since J may change on the scale of U (a step of
            ! sqrt(eps) where |U| << 1 measured J far from U: u' = -u^3 at u = 1e-11 had
            ! F''[F] 700 times too large); for a problem in t, along (1, F) in (t, U), e < 0
            ! and t1 + e, e (1, F) of the size of sqrt(eps) max(|U|, 1)
            if (problem%autonomous) then
               side = 1.0_dp
               size_along = merge(size_start, size_now, along_start)
               epsilon_f = sqrt(epsilon(1.0_dp))*max(norm2(u), self%h*size_along)/max(size_along, tiny(1.0_dp))
               t_probe = self%t1
            else
               side = -1.0_dp
               epsilon_f = sqrt(epsilon(1.0_dp))*max(norm2(u), 1.0_dp)/hypot(merge(size_start, size_now, along_start), &
                  1.0_dp)
               t_probe = self%t1 - epsilon_f
            end if
            ! (e = 0: U = 0 and F = 0, along which J does not change)
            if (epsilon_f > 0.0_dp) then
               if (along_start) then
                  self%probe = u + side*epsilon_f*self%rhs0
               else
                  self%probe = u + side*epsilon_f*self%rhs1
               end if
               call evaluate_jac(problem, t_probe, self%probe, self%jac_probe, counters, stat)
               if (stat%code /= status_ok) return
               call self%jac_probe%add_scaled(-1.0_dp, self%jac1, stat)
               call matrix%add_block(0.5_dp*self%h*self%h/(side*epsilon_f), self%jac_probe, 1, 1, stat)
            end if
         end if
         call matrix%add_identity(1.0_dp, row_scale)
      end if
   end subroutine implicit_taylor_matrix

end module taylorode_schemes_implicit_taylor
