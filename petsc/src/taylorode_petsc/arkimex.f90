!> PETSc's adaptive TS (TSARKIMEX) running the library's IMEX tables (imex-rk21 and
!> si-t-1, registered through TSARKIMEXRegister) on a grid problem: g is the implicit
!> part (TSSetIFunction with U' - g, TSSetIJacobian with shift I - J_g assembled from
!> g's stencil), f the explicit one (TSSetRHSFunction).
module taylorode_petsc_arkimex
   use taylorode, only: dp, status_type
   use taylorode_petsc_calls, only: split_system_type, arkimex_stats_type, run_arkimex, table_imex_rk21, &
      table_si_t_1
   use taylorode_petsc_grid_problem, only: grid_problem_type
   implicit none
   private

   public :: integrate_arkimex, arkimex_stats_type, table_imex_rk21, table_si_t_1

   !> A grid problem seen as PETSc's TS sees a split system
   type, extends(split_system_type) :: split_problem_type
      class(grid_problem_type), pointer :: problem => null()
   contains
      procedure :: nonstiff => split_nonstiff
      procedure :: stiff => split_stiff
      procedure :: stiff_stencil => split_stencil
   end type split_problem_type

contains

   !> Integrate the problem from t0 to t_end with TSARKIMEX and `table` (table_imex_rk21
   !> or table_si_t_1): adaptively with PETSc's controller (rtol, atol) or with fixed
   !> steps h0; the stage equations to a relative residual snes_rtol. u holds this rank's
   !> part of U(t0) on entry and of U(t_end) on exit.
   subroutine integrate_arkimex(problem, table, t0, t_end, h0, adaptive, rtol, atol, snes_rtol, u, stats, stat)
      !> The problem
      class(grid_problem_type), intent(inout), target :: problem
      !> table_imex_rk21 or table_si_t_1
      character(len=*), intent(in) :: table
      !> Start, end, first (or every) step
      real(dp), intent(in) :: t0, t_end, h0
      !> Adaptive (else fixed steps h0)
      logical, intent(in) :: adaptive
      !> Tolerances of the controller and of the stage equations
      real(dp), intent(in) :: rtol, atol, snes_rtol
      !> This rank's part of the state
      real(dp), intent(inout) :: u(:)
      !> Steps, rejections and iterations
      type(arkimex_stats_type), intent(out) :: stats
      !> Outcome
      type(status_type), intent(out) :: stat
      type(split_problem_type) :: split
      split%problem => problem
      call run_arkimex(split, problem%grid, table, t0, t_end, h0, adaptive, rtol, atol, snes_rtol, u, stats, stat)
   end subroutine integrate_arkimex

   subroutine split_nonstiff(self, t, u, dudt)
      class(split_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call self%problem%f(t, u, dudt)
   end subroutine split_nonstiff

   subroutine split_stiff(self, t, u, dudt)
      class(split_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call self%problem%g(t, u, dudt)
   end subroutine split_stiff

   subroutine split_stencil(self, t, u, stencil)
      class(split_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: stencil(:, :)
      call self%problem%jac_g_stencil(t, u, stencil)
   end subroutine split_stencil

end module taylorode_petsc_arkimex
