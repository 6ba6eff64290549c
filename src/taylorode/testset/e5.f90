!> E5, a chemical pyrolysis (Hairer & Wanner II, IV.10; Bari test set E5).
module taylorode_testset_e5
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: e5_type, new_e5

   !> E5, a chemical pyrolysis (Hairer & Wanner II, IV.10; Bari test set E5).
   !> f = the slow decay A y1 (A = 7.89e-10), g = the fast reactions. Components fall
   !> to 1e-22 (and y1 to 1e-290): use atol around 1e-24 and judge y2, y3 relatively.
   type, extends(test_problem_type) :: e5_type
      !> Rate constants A, B, C and the factor M of the published problem
      real(dp) :: a = 7.89e-10_dp, b = 1.1e7_dp, c = 1.13e3_dp, m = 1.0e6_dp
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => e5_f
      !> Stiff part g
      procedure :: g => e5_g
      !> F = f + g in one call
      procedure :: rhs => e5_rhs
      !> df/dU, analytic
      procedure :: jac_f => e5_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => e5_jac_g
      !> J = df/dU + dg/dU in one call: dg/dU with the nonzeros of df/dU added
      procedure :: jac => e5_jac
      !> y + alpha J v without forming J
      procedure :: add_jacobian_product => e5_add_jacobian_product
   end type e5_type

contains

   !> E5 from (1.76e-3, 0, 0, 0) over [0, 1e13], with the published solution.
   pure function new_e5() result(self)
      type(e5_type) :: self
      self%name = "e5"
      self%autonomous = .true.
      self%t_end = 1.0e13_dp
      self%u0 = [1.76e-3_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-24_dp
      self%reference = [0.1152903278711829e-290_dp, 0.8867655517642120e-22_dp, 0.8854814626268838e-22_dp, 0.0_dp]
      self%source = "Hairer & Wanner II, IV.10; Bari test set E5 (reference values)"
      self%nonnegative = .true.
   end function new_e5

   subroutine e5_f(self, t, u, dudt)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -self%a*u(1)
      dudt(2) = self%a*u(1)
      dudt(3) = self%a*u(1)
      dudt(4) = 0.0_dp
   end subroutine e5_f

   subroutine e5_g(self, t, u, dudt)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: r1, r2, r3
      r1 = self%b*u(1)*u(3)
      r2 = self%m*self%c*u(2)*u(3)
      r3 = self%c*u(4)
      dudt(1) = -r1
      dudt(2) = -r2
      dudt(4) = r1 - r3
      ! y3' = y2' - y4' exactly as computed, so that rounding keeps y2 - y3 - y4 = 0
      dudt(3) = dudt(2) - dudt(4)
   end subroutine e5_g

   subroutine e5_rhs(self, t, u, dudt)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: r1, r2, r3, source
      source = self%a*u(1)
      r1 = self%b*u(1)*u(3)
      r2 = self%m*self%c*u(2)*u(3)
      r3 = self%c*u(4)
      ! the sums f + g term by term, as e5_f and e5_g give them
      dudt(1) = -source - r1
      dudt(2) = source - r2
      dudt(3) = source + (-r2 - (r1 - r3))
      dudt(4) = r1 - r3
   end subroutine e5_rhs

   subroutine e5_jac_f(self, t, u, jac)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1:3, 1) = [-self%a, self%a, self%a]
   end subroutine e5_jac_f

   subroutine e5_jac_g(self, t, u, jac)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      real(dp) :: mc
      mc = self%m*self%c
      jac = 0.0_dp
      jac(1, :) = [-self%b*u(3), 0.0_dp, -self%b*u(1), 0.0_dp]
      jac(2, :) = [0.0_dp, -mc*u(3), -mc*u(2), 0.0_dp]
      jac(3, :) = [-self%b*u(3), -mc*u(3), -self%b*u(1) - mc*u(2), self%c]
      jac(4, :) = [self%b*u(3), 0.0_dp, self%b*u(1), -self%c]
   end subroutine e5_jac_g

   !> df/dU + dg/dU: dg/dU, with df/dU's one nonzero column added.
   subroutine e5_jac(self, t, u, jac)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call self%jac_g(t, u, jac)
      jac(1:3, 1) = jac(1:3, 1) + [-self%a, self%a, self%a]
   end subroutine e5_jac

   !> y + alpha J v with the entries of e5_jac, each row's terms added in the order of the columns:
   !> the same numbers as J from e5_jac times v column by column (the default), bit for bit.
   subroutine e5_add_jacobian_product(self, t, u, alpha, v, y)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: av(4), mc, bu1, bu3, mcu2, mcu3
      av = alpha*v(1:4)
      mc = self%m*self%c
      bu1 = self%b*u(1)
      bu3 = self%b*u(3)
      mcu2 = mc*u(2)
      mcu3 = mc*u(3)
      y(1) = y(1) + av(1)*(-bu3 + (-self%a))
      y(1) = y(1) + av(3)*(-bu1)
      y(2) = y(2) + av(1)*self%a
      y(2) = y(2) + av(2)*(-mcu3)
      y(2) = y(2) + av(3)*(-mcu2)
      y(3) = y(3) + av(1)*(-bu3 + self%a)
      y(3) = y(3) + av(2)*(-mcu3)
      y(3) = y(3) + av(3)*(-bu1 - mcu2)
      y(3) = y(3) + av(4)*self%c
      y(4) = y(4) + av(1)*bu3
      y(4) = y(4) + av(3)*bu1
      y(4) = y(4) + av(4)*(-self%c)
   end subroutine e5_add_jacobian_product

end module taylorode_testset_e5
