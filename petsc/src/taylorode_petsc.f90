!> taylorode for one system distributed over MPI ranks through PETSc (build with
!> mpif90 and PETSc's flags): grid problems (`grid_problem_type`, the 2D
!> reaction-diffusion problem), the library's Taylor schemes with matrix-free
!> Newton-Krylov steps and multigrid preconditioners (`grid_taylor_type`, stepped by
!> the library's `integrate`), and PETSc's adaptive TS running the library's IMEX tables
!> (`integrate_arkimex`).
module taylorode_petsc
   use taylorode_petsc_calls, only: petsc_start, petsc_stop, petsc_ranks, grid_type
   use taylorode_petsc_grid_problem, only: grid_problem_type
   use taylorode_petsc_reaction_diffusion, only: reaction_diffusion_type, new_reaction_diffusion
   use taylorode_petsc_taylor, only: grid_taylor_type, new_grid_taylor, grid_taylor_names
   use taylorode_petsc_arkimex, only: integrate_arkimex, arkimex_stats_type, table_imex_rk21, table_si_t_1
   implicit none
   private

   public :: petsc_start, petsc_stop, petsc_ranks, grid_type, grid_problem_type
   public :: reaction_diffusion_type, new_reaction_diffusion
   public :: grid_taylor_type, new_grid_taylor, grid_taylor_names
   public :: integrate_arkimex, arkimex_stats_type, table_imex_rk21, table_si_t_1

end module taylorode_petsc
