!> A problem on a 2D grid distributed over the ranks through PETSc: each rank holds the
!> values at the points it owns (in the arrays the integrator passes), f and g get their
!> neighbours' values through `grid%exchange`, and `reduce` combines the integrator's
!> norms and decisions over the ranks of the grid. The stiff part's Jacobian is given
!> as a five-point stencil per point (for the preconditioners and PETSc's TS); the
!> schemes of this package use Jacobian-vector products (jvp_f, jvp_g) otherwise.
module taylorode_petsc_grid_problem
   use taylorode, only: dp, ode_problem, reduce_sum
   use taylorode_petsc_calls, only: grid_type, grid_sum, grid_max
   implicit none
   private

   public :: grid_problem_type

   !> A problem whose unknowns live on a distributed 2D grid
   type, abstract, extends(ode_problem) :: grid_problem_type
      !> The grid and this rank's part of it
      type(grid_type) :: grid
   contains
      !> dg/dU at (t, u) as five-point stencils, one column per owned point
      procedure(stencil_interface), deferred :: jac_g_stencil
      !> Sum or maximum over the ranks of the grid
      procedure :: reduce => grid_reduce
      !> No dense Jacobians: an evaluation the problem rejects (see jac_g_stencil, jvp_f, jvp_g)
      procedure :: jac_f => no_dense_jacobian
      !> No dense Jacobians (see jac_f)
      procedure :: jac_g => no_dense_jacobian
   end type grid_problem_type

   abstract interface
      !> stencil(:, p): the coefficients of row p of dg/dU at (t, u), in the order
      !> stencil_center, stencil_west, stencil_east, stencil_south, stencil_north.
      subroutine stencil_interface(self, t, u, stencil)
         import :: grid_problem_type, dp
         !> The problem
         class(grid_problem_type), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> This rank's part of the state
         real(dp), intent(in) :: u(:)
         !> Five coefficients per owned point
         real(dp), intent(out) :: stencil(:, :)
      end subroutine stencil_interface
   end interface

contains

   !> values combined over the ranks of the grid (MPI_Allreduce through PETSc's communicator).
   subroutine grid_reduce(self, operation, values)
      !> The problem
      class(grid_problem_type), intent(inout) :: self
      !> reduce_sum or reduce_max
      integer, intent(in) :: operation
      !> This rank's values on entry, the combined ones on exit
      real(dp), intent(inout) :: values(:)
      call self%grid%reduce_values(merge(grid_sum, grid_max, operation == reduce_sum), values)
   end subroutine grid_reduce

   !> A distributed problem has no dense Jacobian: the evaluation is rejected for good,
   !> so that a scheme that needs one stops with status_evaluation_failed.
   subroutine no_dense_jacobian(self, t, u, jac)
      !> The problem
      class(grid_problem_type), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Not set (zero)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      call self%reject_evaluation(fatal=.true.)
   end subroutine no_dense_jacobian

end module taylorode_petsc_grid_problem
