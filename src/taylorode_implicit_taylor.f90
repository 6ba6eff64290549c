!> Implicit Taylor schemes I-T-1 and I-T-2 (METHODS.md section 1), an embedded pair.
!>
!>   i-t-1:  U1 = U0 + h F(U1)                               Newton matrix I - h J(U1)
!>   i-t-2:  U1 = U0 + h F(U1) - h^2/2 J(U1) F(U1)           Newton matrix I - h J + h^2/2 J^2
!>
!> The i-t-2 matrix omits the second derivatives of F: Newton converges to the
!> same U1, only its rate changes.
module taylorode_implicit_taylor
   use taylorode_kinds, only: dp
   use taylorode_status, only: status_type, status_ok
   use taylorode_problem, only: ode_problem
   use taylorode_scheme, only: implicit_scheme_type
   use taylorode_linalg, only: add_to_diagonal
   implicit none
   private

   public :: implicit_taylor_type, new_implicit_taylor

   !> I-T-1 (order 1) or I-T-2 (order 2); the other member gives the error estimate
   type, extends(implicit_scheme_type) :: implicit_taylor_type
      !> State at the start of the step
      real(dp), allocatable :: u0(:)
      !> f, g and F = f + g at the current iterate
      real(dp), allocatable :: f1(:), g1(:), rhs1(:)
      !> J(U1) F(U1)
      real(dp), allocatable :: jac_rhs1(:)
      !> Jacobians at the current iterate (jac1 = J_f + J_g)
      real(dp), allocatable :: jac_g1(:, :), jac1(:, :)
   contains
      procedure :: advance => implicit_taylor_advance
      procedure :: prepare => implicit_taylor_prepare
      procedure :: residual => implicit_taylor_residual
      procedure :: iteration_matrix => implicit_taylor_matrix
   end type implicit_taylor_type

contains

   !> Create I-T-1 (order = 1) or I-T-2 (order = 2).
   subroutine new_implicit_taylor(self, order)
      !> The new scheme
      type(implicit_taylor_type), intent(out) :: self
      !> 1 or 2
      integer, intent(in) :: order
      self%order = order
      self%embedded_order = 3 - order
      if (order == 1) then
         self%name = "i-t-1"
      else
         self%name = "i-t-2"
      end if
   end subroutine new_implicit_taylor

   subroutine implicit_taylor_prepare(self, n)
      class(implicit_taylor_type), intent(inout) :: self
      integer, intent(in) :: n
      call self%prepare_newton(n)
      if (self%n == n) return
      if (allocated(self%u0)) then
         deallocate (self%u0, self%f1, self%g1, self%rhs1, self%jac_rhs1, self%jac_g1, self%jac1)
      end if
      allocate (self%u0(n), self%f1(n), self%g1(n), self%rhs1(n), self%jac_rhs1(n), &
         self%jac_g1(n, n), self%jac1(n, n))
      self%n = n
   end subroutine implicit_taylor_prepare

   subroutine implicit_taylor_advance(self, problem, t, h, u0, u1, stat, delta, newton_tolerance)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: newton_tolerance(:)

      call self%begin_implicit_step(t, h, u0, newton_tolerance)
      self%u0 = u0
      u1 = u0
      call self%solve_implicit(problem, self%order, u1, stat)
      if (stat%code /= status_ok .or. .not. present(delta)) return

      delta = u1
      call self%solve_implicit(problem, self%embedded_order, delta, stat)
      if (stat%code /= status_ok) return
      if (self%order == 2) then
         delta = u1 - delta
      else
         delta = delta - u1
      end if
   end subroutine implicit_taylor_advance

   !> r(U) = U - U0 - h F(U) [+ h^2/2 J(U) F(U) for order 2]; keeps J(U) for the matrix.
   subroutine implicit_taylor_residual(self, problem, system, u, r)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: r(:)

      real(dp) :: t1

      t1 = self%t0 + self%h
      call self%eval_f(problem, t1, u, self%f1)
      call self%eval_g(problem, t1, u, self%g1)
      self%rhs1 = self%f1 + self%g1
      r = u - self%u0 - self%h*self%rhs1
      if (system == 2) then
         call jacobian_at(self, problem, t1, u)
         self%jac_rhs1 = matmul(self%jac1, self%rhs1)
         r = r + (0.5_dp*self%h*self%h)*self%jac_rhs1
      end if
   end subroutine implicit_taylor_residual

   !> I - h J(U) [+ h^2/2 J(U)^2 for order 2], J(U) reused from the residual for order 2.
   subroutine implicit_taylor_matrix(self, problem, system, u, m)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: m(:, :)

      if (system == 2) then
         m = -self%h*self%jac1 + (0.5_dp*self%h*self%h)*matmul(self%jac1, self%jac1)
      else
         call jacobian_at(self, problem, self%t0 + self%h, u)
         m = -self%h*self%jac1
      end if
      call add_to_diagonal(m, 1.0_dp)
   end subroutine implicit_taylor_matrix

   !> jac1 = J_f(u) + J_g(u)
   subroutine jacobian_at(self, problem, t, u)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      call self%eval_jac_f(problem, t, u, self%jac1)
      call self%eval_jac_g(problem, t, u, self%jac_g1)
      self%jac1 = self%jac1 + self%jac_g1
   end subroutine jacobian_at

end module taylorode_implicit_taylor
