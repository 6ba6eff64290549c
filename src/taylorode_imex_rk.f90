!> The embedded IMEX-RK(2,1) scheme of the paper, for comparison (METHODS.md section 2).
!>
!> gamma = 1 - sqrt(2)/2, c = 1/(2 gamma); implicit tableau A = [[gamma, 0], [1-gamma, gamma]],
!> explicit tableau [[0, 0], [c, 0]], weights b = (1-gamma, gamma), embedded weights (0, 1):
!>
!>   Y1 = U0 + h gamma g(Y1)
!>   Y2 = U0 + h c f(Y1) + h [(1-gamma) g(Y1) + gamma g(Y2)]
!>   U1 = U0 + h [(1-gamma) F(Y1) + gamma F(Y2)],    U^ = U0 + h F(Y2)
!>
!> For problems that depend on t, f is evaluated at the explicit nodes (0, c) and
!> g at the implicit nodes (gamma, 1).
module taylorode_imex_rk
   use taylorode_kinds, only: dp
   use taylorode_status, only: status_type, status_ok
   use taylorode_problem, only: ode_problem
   use taylorode_scheme, only: implicit_scheme_type
   use taylorode_matrix, only: matrix_type, new_matrix
   implicit none
   private

   public :: imex_rk21_type, new_imex_rk21, imex_gamma, imex_c

   !> Diagonal coefficient of the DIRK tableau
   real(dp), parameter :: imex_gamma = 1.0_dp - sqrt(2.0_dp)/2.0_dp
   !> Explicit coupling coefficient
   real(dp), parameter :: imex_c = 1.0_dp/(2.0_dp*imex_gamma)

   !> IMEX-RK(2,1): second-order solution, first-order embedded solution
   type, extends(implicit_scheme_type) :: imex_rk21_type
      !> Known part of the stage equation being solved
      real(dp), allocatable :: known(:)
      !> Stage values and f, g at the stages
      real(dp), allocatable :: y1(:), f_y1(:), g_y1(:), f_y2(:), g_y2(:)
      !> Jacobian dg/dU at the current iterate
      class(matrix_type), allocatable :: jac_g
   contains
      procedure :: advance => imex_advance
      procedure :: prepare => imex_prepare
      procedure :: residual => imex_residual
      procedure :: iteration_matrix => imex_matrix
   end type imex_rk21_type

   !> Implicit nodes of the two stages
   real(dp), parameter :: implicit_nodes(2) = [imex_gamma, 1.0_dp]

contains

   !> Create the IMEX-RK(2,1) scheme.
   subroutine new_imex_rk21(self)
      !> The new scheme
      type(imex_rk21_type), intent(out) :: self
      self%name = "imex-rk21"
      self%order = 2
      self%embedded_order = 1
   end subroutine new_imex_rk21

   !> Work arrays; both stages share the form of their Newton matrix, I - h gamma J_g,
   !> but each keeps its own.
   subroutine imex_prepare(self, problem, n)
      class(imex_rk21_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      if (.not. self%resize(problem, n)) return
      call self%prepare_newton(n, 2, self%kl, self%ku)
      if (allocated(self%known)) deallocate (self%known, self%y1, self%f_y1, self%g_y1, self%f_y2, self%g_y2)
      allocate (self%known(n), self%y1(n), self%f_y1(n), self%g_y1(n), self%f_y2(n), self%g_y2(n))
      call new_matrix(self%jac_g, n, self%kl, self%ku)
   end subroutine imex_prepare

   subroutine imex_advance(self, problem, t, h, u0, u1, stat, delta, newton_tolerance)
      class(imex_rk21_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: newton_tolerance(:)

      call self%begin_implicit_step(t, h, u0, newton_tolerance)

      self%known = u0
      self%y1 = u0
      call self%solve_implicit(problem, 1, self%y1, stat)
      if (stat%code /= status_ok) return
      call self%eval_f(problem, t, self%y1, self%f_y1)
      call self%eval_g(problem, t + imex_gamma*h, self%y1, self%g_y1)

      self%known = u0 + (h*imex_c)*self%f_y1 + (h*(1.0_dp - imex_gamma))*self%g_y1
      u1 = self%y1
      call self%solve_implicit(problem, 2, u1, stat)
      if (stat%code /= status_ok) return
      call self%eval_f(problem, t + imex_c*h, u1, self%f_y2)
      call self%eval_g(problem, t + h, u1, self%g_y2)

      ! u1 holds Y2 until here
      if (present(delta)) delta = u0 + h*(self%f_y2 + self%g_y2)
      u1 = u0 + (h*(1.0_dp - imex_gamma))*(self%f_y1 + self%g_y1) + (h*imex_gamma)*(self%f_y2 + self%g_y2)
      if (present(delta)) delta = u1 - delta
   end subroutine imex_advance

   !> r(Y) = Y - known - h gamma g(Y) for stage `system`
   subroutine imex_residual(self, problem, system, u, r)
      class(imex_rk21_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: r(:)
      call self%eval_g(problem, self%t0 + implicit_nodes(system)*self%h, u, r)
      r = u - self%known - (self%h*imex_gamma)*r
   end subroutine imex_residual

   !> I - h gamma J_g(Y) for stage `system`
   subroutine imex_matrix(self, problem, system, u)
      class(imex_rk21_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      call self%eval_jac_g(problem, self%t0 + implicit_nodes(system)*self%h, u, self%jac_g)
      associate (m => self%systems(system)%matrix)
         call m%set_scaled(-self%h*imex_gamma, self%jac_g)
         call m%add_identity(1.0_dp)
      end associate
   end subroutine imex_matrix

end module taylorode_imex_rk
