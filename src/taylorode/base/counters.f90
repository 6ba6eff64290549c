!> Work counters of a scheme: evaluations, factorizations, solves and Newton
!> iterations, accumulated over all its steps.
module taylorode_base_counters
   use taylorode_base_kinds, only: i8
   implicit none
   private

   public :: counters_type, operator(+), operator(-)

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
      !> Products J v of the whole Jacobian with a vector (the problem's `jvp`)
      integer(i8) :: jacobian_products = 0
      !> LU factorizations
      integer(i8) :: lu_factorizations = 0
      !> Linear solves with an LU factorization
      integer(i8) :: linear_solves = 0
      !> Newton iterations over all nonlinear systems
      integer(i8) :: newton_iterations = 0
   end type counters_type

   !> Sum of two sets of counters, component by component
   interface operator(+)
      module procedure add_counters
   end interface operator(+)

   !> Difference of two sets of counters (the work done between two readings)
   interface operator(-)
      module procedure subtract_counters
   end interface operator(-)

contains

   !> a + b, component by component.
   elemental function add_counters(a, b) result(total)
      !> The two sets
      type(counters_type), intent(in) :: a, b
      type(counters_type) :: total
      total%f_evaluations = a%f_evaluations + b%f_evaluations
      total%g_evaluations = a%g_evaluations + b%g_evaluations
      total%jac_f_evaluations = a%jac_f_evaluations + b%jac_f_evaluations
      total%jac_g_evaluations = a%jac_g_evaluations + b%jac_g_evaluations
      total%jacobian_products = a%jacobian_products + b%jacobian_products
      total%lu_factorizations = a%lu_factorizations + b%lu_factorizations
      total%linear_solves = a%linear_solves + b%linear_solves
      total%newton_iterations = a%newton_iterations + b%newton_iterations
   end function add_counters

   !> a - b, component by component.
   elemental function subtract_counters(a, b) result(difference)
      !> The later and the earlier reading
      type(counters_type), intent(in) :: a, b
      type(counters_type) :: difference
      difference%f_evaluations = a%f_evaluations - b%f_evaluations
      difference%g_evaluations = a%g_evaluations - b%g_evaluations
      difference%jac_f_evaluations = a%jac_f_evaluations - b%jac_f_evaluations
      difference%jac_g_evaluations = a%jac_g_evaluations - b%jac_g_evaluations
      difference%jacobian_products = a%jacobian_products - b%jacobian_products
      difference%lu_factorizations = a%lu_factorizations - b%lu_factorizations
      difference%linear_solves = a%linear_solves - b%linear_solves
      difference%newton_iterations = a%newton_iterations - b%newton_iterations
   end function subtract_counters

end module taylorode_base_counters
