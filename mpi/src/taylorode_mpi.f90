!> taylorode over MPI ranks (build with mpif90): ensembles shared out over the ranks
!> with every rank ending with every result (`distribute_ensemble`), and problems
!> whose state is distributed over the ranks (`distributed_problem_type`).
module taylorode_mpi
   use taylorode_mpi_ensemble, only: distribute_ensemble, ensemble_load_type, schedule_dynamic, schedule_cyclic
   use taylorode_mpi_problem, only: distributed_problem_type
   implicit none
   private

   public :: distribute_ensemble, ensemble_load_type, schedule_dynamic, schedule_cyclic
   public :: distributed_problem_type

end module taylorode_mpi
