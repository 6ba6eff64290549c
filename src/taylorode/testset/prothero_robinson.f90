!> The Prothero-Robinson problem y' = L (y - sin t) + cos t, exact solution sin t (Math. Comp. 28 (1974) 145-162).
module taylorode_testset_prothero_robinson
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: prothero_robinson_type, new_prothero_robinson

   !> The Prothero-Robinson problem y' = L (y - sin t) + cos t, y(0) = 0, exact solution sin t
   !> (Prothero & Robinson 1974). f = cos t, g = L (y - sin t), L < 0 large.
   type, extends(test_problem_type) :: prothero_robinson_type
      !> Stiffness, L < 0
      real(dp) :: l = -1.0e6_dp
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => pr_f
      !> Stiff part g
      procedure :: g => pr_g
      !> df/dU, analytic
      procedure :: jac_f => pr_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => pr_jac_g
   end type prothero_robinson_type

contains

   !> Prothero-Robinson with stiffness L (default -1e6) over [0, 10]; exact solution sin t.
   pure function new_prothero_robinson(l) result(self)
      !> Stiffness, < 0
      real(dp), intent(in), optional :: l
      type(prothero_robinson_type) :: self
      if (present(l)) self%l = l
      self%name = "prothero-robinson"
      self%t_end = 10.0_dp
      self%u0 = [0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%reference = [sin(10.0_dp)]
      self%source = "Prothero & Robinson, Math. Comp. 28 (1974); exact solution sin t"
   end function new_prothero_robinson

   subroutine pr_f(self, t, u, dudt)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = cos(t)
   end subroutine pr_f

   subroutine pr_g(self, t, u, dudt)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = self%l*(u - sin(t))
   end subroutine pr_g

   subroutine pr_jac_f(self, t, u, jac)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
   end subroutine pr_jac_f

   subroutine pr_jac_g(self, t, u, jac)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = self%l
   end subroutine pr_jac_g

end module taylorode_testset_prothero_robinson
