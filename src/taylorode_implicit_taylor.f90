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
   use taylorode_matrix, only: matrix_type, new_matrix
   implicit none
   private

   public :: implicit_taylor_type, new_implicit_taylor

   !> I-T-1 (order 1) or I-T-2 (order 2); the other member gives the error estimate
   type, extends(implicit_scheme_type) :: implicit_taylor_type
      !> State at the start of the step
      real(dp), allocatable :: u0(:)
      !> f, g and F = f + g at the current iterate
      real(dp), allocatable :: f1(:), g1(:), rhs1(:)
      !> Jacobians at the current iterate (jac1 = J_f + J_g)
      class(matrix_type), allocatable :: jac_g1, jac1
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

   !> Work arrays; the i-t-2 Newton matrix holds J^2 and gets twice the bandwidths.
   subroutine implicit_taylor_prepare(self, problem, n)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      if (.not. self%resize(problem, n)) return
      call self%prepare_newton(n, 2, 2*self%kl, 2*self%ku)
      call new_matrix(self%systems(1)%matrix, n, self%kl, self%ku)
      if (allocated(self%u0)) deallocate (self%u0, self%f1, self%g1, self%rhs1)
      allocate (self%u0(n), self%f1(n), self%g1(n), self%rhs1(n))
      call new_matrix(self%jac_g1, n, self%kl, self%ku)
      call new_matrix(self%jac1, n, self%kl, self%ku)
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
         call self%jac1%multiply_add(0.5_dp*self%h*self%h, self%rhs1, r)
      end if
   end subroutine implicit_taylor_residual

   !> I - h J(U) [+ h^2/2 J(U)^2 for order 2], J(U) reused from the residual for order 2.
   subroutine implicit_taylor_matrix(self, problem, system, u)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)

      if (system /= 2) call jacobian_at(self, problem, self%t0 + self%h, u)
      associate (m => self%systems(system)%matrix)
         call m%set_scaled(-self%h, self%jac1)
         if (system == 2) call m%add_product(0.5_dp*self%h*self%h, self%jac1, self%jac1)
         call m%add_identity(1.0_dp)
      end associate
   end subroutine implicit_taylor_matrix

   !> jac1 = J_f(u) + J_g(u)
   subroutine jacobian_at(self, problem, t, u)
      class(implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      call self%eval_jac_f(problem, t, u, self%jac1)
      call self%eval_jac_g(problem, t, u, self%jac_g1)
      call self%jac1%add_scaled(1.0_dp, self%jac_g1)
   end subroutine jacobian_at

end module taylorode_implicit_taylor
