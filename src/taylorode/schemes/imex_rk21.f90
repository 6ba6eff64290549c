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
module taylorode_schemes_imex_rk21
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, status_ok
   use taylorode_base_memory, only: sized
   use taylorode_base_counters, only: counters_type
   use taylorode_linalg_matrix, only: matrix_type, new_matrix
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type, newton_solver_type, nonlinear_system_type
   use taylorode_schemes_scheme, only: scheme_type, stability_quotient, evaluate_f, evaluate_g, evaluate_jac_g
   implicit none
   private

   public :: imex_rk21_type, new_imex_rk21

   !> Diagonal coefficient of the DIRK tableau
   real(dp), parameter :: imex_gamma = 1.0_dp - sqrt(2.0_dp)/2.0_dp
   !> Explicit coupling coefficient
   real(dp), parameter :: imex_c = 1.0_dp/(2.0_dp*imex_gamma)
   !> Implicit nodes of the two stages
   real(dp), parameter :: implicit_nodes(2) = [imex_gamma, 1.0_dp]

   !> A stage equation: r(Y) = Y - known - h gamma g(t_stage, Y)
   type, extends(nonlinear_system_type) :: imex_stage_type
      !> Time of the stage's g and step size
      real(dp) :: t_stage = 0.0_dp, h = 0.0_dp
      !> Known part of the stage equation
      real(dp), allocatable :: known(:)
      !> Jacobian dg/dU at the current iterate
      class(matrix_type), allocatable :: jac_g
      !> Whether jac_g holds dg/dU of a problem with linear g (kept for the integration)
      logical :: jac_g_constant = .false.
   contains
      procedure :: residual => imex_residual
      procedure :: newton_matrix => imex_matrix
   end type imex_stage_type

   !> IMEX-RK(2,1): second-order solution, first-order embedded solution
   type, extends(scheme_type) :: imex_rk21_type
      !> The stage equation being solved
      type(imex_stage_type) :: stage
      !> Stage values and f, g at the stages
      real(dp), allocatable :: y1(:), f_y1(:), g_y1(:), f_y2(:), g_y2(:)
      !> Newton's method for both stages: they share the matrix I - h gamma J_g (kept
      !> from stage 1 for stage 2 while it serves)
      type(newton_solver_type) :: newton
   contains
      !> One step of IMEX-RK(2,1) and, when asked, the embedded first-order difference
      procedure :: advance => imex_advance
      !> Work arrays, stage systems and Newton solvers for the problem's structure and n unknowns
      procedure :: prepare => imex_prepare
      !> Forget the factored stage matrices kept between steps
      procedure :: restart => imex_restart
      !> Below a fraction of a step whose Newton solve kept no digit of its residual
      procedure :: largest_step => imex_largest_step
      procedure :: stability => imex_stability
   end type imex_rk21_type

contains

   !> The IMEX-RK(2,1) scheme.
   function new_imex_rk21() result(self)
      type(imex_rk21_type) :: self
      self%name = "imex-rk21"
      self%order = 2
      self%nonlinear_order = 2
      self%embedded_order = 1
      self%implicit = .true.
      self%newton_linear_in_g = .true.
      self%update = "Y1 = U0 + h gamma g(Y1); Y2 = U0 + h c f(Y1) + h [(1-gamma) g(Y1) + gamma g(Y2)]; "// &
         "U1 = U0 + h [(1-gamma) F(Y1) + gamma F(Y2)]"
      self%newton_matrices = "I - h gamma J_g (one for both stages)"
   end function new_imex_rk21

   !> Y1 = 1/(1 - gamma w), Y2 = (1 + (c z + (1 - gamma) w) Y1)/(1 - gamma w),
   !> R = 1 + (1 - gamma)(z + w) Y1 + gamma (z + w) Y2.
   pure function imex_stability(self, z, w) result(r)
      class(imex_rk21_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r, y1, y2
      y1 = stability_quotient((1.0_dp, 0.0_dp), 1.0_dp - imex_gamma*w)
      y2 = stability_quotient(1.0_dp + (imex_c*z + (1.0_dp - imex_gamma)*w)*y1, 1.0_dp - imex_gamma*w)
      r = 1.0_dp + (1.0_dp - imex_gamma)*(z + w)*y1 + imex_gamma*(z + w)*y2
   end function imex_stability

   subroutine imex_prepare(self, problem, n, stat)
      class(imex_rk21_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      character(len=*), parameter :: what = "imex-rk21's work arrays"
      if (.not. self%resize(problem, n, stat)) return
      call self%newton%init(n, self%structure, stat)
      call sized(self%stage%known, n, what, stat)
      call sized(self%y1, n, what, stat)
      call sized(self%f_y1, n, what, stat)
      call sized(self%g_y1, n, what, stat)
      call sized(self%f_y2, n, what, stat)
      call sized(self%g_y2, n, what, stat)
      if (stat%code == status_ok) call new_matrix(self%stage%jac_g, n, self%structure, stat)
      if (stat%code /= status_ok) self%n = 0
   end subroutine imex_prepare

   !> The longest step its Newton solvers can still resolve (see scheme_type's
   !> largest_step).
   pure real(dp) function imex_largest_step(self)
      class(imex_rk21_type), intent(in) :: self
      imex_largest_step = self%newton%step_limit
   end function imex_largest_step

   subroutine imex_restart(self)
      class(imex_rk21_type), intent(inout) :: self
      call self%newton%forget()
      self%stage%jac_g_constant = .false.
   end subroutine imex_restart

   subroutine imex_advance(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(imex_rk21_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)

      self%stage%h = h
      self%stage%linear = problem%linear_g
      self%stage%t_stage = t + implicit_nodes(1)*h
      self%stage%known = u0
      if (present(guess)) then
         self%y1 = u0 + imex_gamma*(guess - u0)
      else
         self%y1 = u0
      end if
      call self%newton%solve(self%stage, problem, h, newton, self%y1, self%counters, stat)
      if (stat%code /= status_ok) return
      call evaluate_f(problem, t, self%y1, self%f_y1, self%counters)
      ! g at a stage from its own equation, Y = known + h gamma g(Y): no evaluation
      self%g_y1 = (self%y1 - self%stage%known)/(h*imex_gamma)

      self%stage%t_stage = t + implicit_nodes(2)*h
      self%stage%known = u0 + (h*imex_c)*self%f_y1 + (h*(1.0_dp - imex_gamma))*self%g_y1
      if (present(guess)) then
         u1 = guess
      else
         u1 = self%y1
      end if
      call self%newton%solve(self%stage, problem, h, newton, u1, self%counters, stat)
      if (stat%code /= status_ok) return
      call evaluate_f(problem, t + imex_c*h, u1, self%f_y2, self%counters)
      self%g_y2 = (u1 - self%stage%known)/(h*imex_gamma)

      ! u1 holds Y2 until here
      if (present(delta)) delta = u0 + h*(self%f_y2 + self%g_y2)
      u1 = u0 + (h*(1.0_dp - imex_gamma))*(self%f_y1 + self%g_y1) + (h*imex_gamma)*(self%f_y2 + self%g_y2)
      if (present(delta)) delta = u1 - delta
   end subroutine imex_advance

   !> r(Y) = Y - known - h gamma g(t_stage, Y)
   subroutine imex_residual(self, problem, u, r, counters)
      class(imex_stage_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      real(dp), contiguous, intent(out) :: r(:)
      type(counters_type), intent(inout) :: counters
      call evaluate_g(problem, self%t_stage, u, r, counters)
      r = u - self%known - (self%h*imex_gamma)*r
   end subroutine imex_residual

   !> I - h gamma J_g(t_stage, Y)
   subroutine imex_matrix(self, problem, u, matrix, counters, stat)
      class(imex_stage_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      class(matrix_type), intent(inout) :: matrix
      type(counters_type), intent(inout) :: counters
      type(status_type), intent(inout) :: stat
      if (.not. (problem%linear_g .and. self%jac_g_constant)) then
         call evaluate_jac_g(problem, self%t_stage, u, self%jac_g, counters, stat)
         if (stat%code /= status_ok) return
         self%jac_g_constant = problem%linear_g
      end if
      call matrix%add_scaled(-self%h*imex_gamma, self%jac_g, stat)
      call matrix%add_identity(1.0_dp)
   end subroutine imex_matrix

end module taylorode_schemes_imex_rk21
