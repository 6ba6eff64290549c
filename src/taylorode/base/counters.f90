!> Work counters of a scheme: evaluations, factorizations, solves and Newton
!> iterations, accumulated over all its steps.
module taylorode_base_counters
   use taylorode_base_kinds, only: i8
   implicit none
   private

   public :: counters_type

   !> Work done, accumulated over all steps of a scheme
   type :: counters_type
      !> Evaluations of the non-stiff part f
      integer(i8) :: f_evaluations = 0
      !> Evaluations of the stiff part g
      integer(i8) :: g_evaluations = 0
      !> Evaluations of df/dU
      integer(i8) :: jac_f_evaluations = 0
      !> Evaluations of dg/dU
      integer(i8) :: jac_g_evaluations = 0
      !> LU factorizations
      integer(i8) :: lu_factorizations = 0
      !> Linear solves with an LU factorization
      integer(i8) :: linear_solves = 0
      !> Newton iterations over all nonlinear systems
      integer(i8) :: newton_iterations = 0
   end type counters_type

end module taylorode_base_counters
