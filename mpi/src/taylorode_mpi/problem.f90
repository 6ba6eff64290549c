!> One system distributed over MPI ranks: each rank holds its part of the state, and
!> the problem's `reduce` combines the integrator's norms, step outcomes and
!> finiteness checks over the ranks (MPI_Allreduce), so that every rank takes the same
!> steps. A problem whose parts are coupled exchanges the values it needs from other
!> ranks inside f and g (every rank evaluates them equally often). Newton's method of
!> the library's implicit schemes works on each rank's part alone: it serves parts
!> that are not coupled (blocks of independent systems); coupled systems with
!> implicit schemes go through the PETSc package (petsc/).
module taylorode_mpi_problem
   use mpi_f08, only: MPI_Comm, MPI_COMM_WORLD, MPI_Allreduce, MPI_IN_PLACE, MPI_DOUBLE_PRECISION, MPI_SUM, MPI_MAX
   use taylorode, only: dp, ode_problem, reduce_sum
   implicit none
   private

   public :: distributed_problem_type

   !> A problem whose state is distributed over the ranks of `comm`
   type, abstract, extends(ode_problem) :: distributed_problem_type
      !> The ranks that hold the parts of the state
      type(MPI_Comm) :: comm = MPI_COMM_WORLD
   contains
      !> Sum or maximum over the ranks of comm
      procedure :: reduce => allreduce_values
   end type distributed_problem_type

contains

   !> values combined over the ranks of comm (MPI_Allreduce, in place).
   subroutine allreduce_values(self, operation, values)
      !> The problem
      class(distributed_problem_type), intent(inout) :: self
      !> reduce_sum or reduce_max
      integer, intent(in) :: operation
      !> This rank's values on entry, the combined ones on exit
      real(dp), intent(inout) :: values(:)
      if (operation == reduce_sum) then
         call MPI_Allreduce(MPI_IN_PLACE, values, size(values), MPI_DOUBLE_PRECISION, MPI_SUM, self%comm)
      else
         call MPI_Allreduce(MPI_IN_PLACE, values, size(values), MPI_DOUBLE_PRECISION, MPI_MAX, self%comm)
      end if
   end subroutine allreduce_values

end module taylorode_mpi_problem
