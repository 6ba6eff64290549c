!> Robertson's chemical kinetics (Hairer & Wanner II, IV.1; Bari test set ROBER).
module taylorode_testset_robertson
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: robertson_type, new_robertson

   !> Robertson's chemical kinetics (Hairer & Wanner II, IV.1; Bari test set ROBER).
   !> f = the slow reaction (k1 = 0.04), g = the fast ones (k2 = 3e7, k3 = 1e4);
   !> each part conserves y1 + y2 + y3. y2 stays below 4e-5: use atol <= 1e-10.
   type, extends(test_problem_type) :: robertson_type
      !> Rate constants of the three reactions
      real(dp) :: k1 = 0.04_dp, k2 = 3.0e7_dp, k3 = 1.0e4_dp
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => robertson_f
      !> Stiff part g
      procedure :: g => robertson_g
      !> df/dU, analytic
      procedure :: jac_f => robertson_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => robertson_jac_g
      !> F = f + g in one pass
      procedure :: rhs => robertson_rhs
      !> J = df/dU + dg/dU in one call: dg/dU with the nonzeros of df/dU added
      procedure :: jac => robertson_jac
      !> y + alpha J v without forming J
      procedure :: add_jacobian_product => robertson_add_jacobian_product
   end type robertson_type

contains

   !> Robertson from (1, 0, 0) to t_end (default 40); the published solution is
   !> attached for t_end = 40 and t_end = 1e11.
   pure function new_robertson(t_end) result(self)
      !> Final time (40 or 1e11 have reference values)
      real(dp), intent(in), optional :: t_end
      type(robertson_type) :: self
      self%name = "robertson"
      self%autonomous = .true.
      self%t_end = 40.0_dp
      if (present(t_end)) self%t_end = t_end
      self%u0 = [1.0_dp, 0.0_dp, 0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-10_dp
      if (self%t_end == 40.0_dp) then
         self%reference = [0.7158270687194048_dp, 9.185534764557822e-6_dp, 0.2841637457458297_dp]
      else if (self%t_end == 1.0e11_dp) then
         self%reference = [0.2083340149701255e-7_dp, 0.8333360770334713e-13_dp, 0.9999999791665050_dp]
      end if
      self%source = "Hairer & Wanner II, IV.1; Bari test set ROBER (reference values)"
      self%nonnegative = .true.
   end function new_robertson

   subroutine robertson_f(self, t, u, dudt)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -self%k1*u(1)
      dudt(2) = self%k1*u(1)
      dudt(3) = 0.0_dp
   end subroutine robertson_f

   subroutine robertson_g(self, t, u, dudt)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = self%k3*u(2)*u(3)
      dudt(3) = self%k2*u(2)**2
      dudt(2) = -dudt(1) - dudt(3)
   end subroutine robertson_g

   subroutine robertson_jac_f(self, t, u, jac)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = -self%k1
      jac(2, 1) = self%k1
   end subroutine robertson_jac_f

   subroutine robertson_jac_g(self, t, u, jac)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 2) = self%k3*u(3)
      jac(1, 3) = self%k3*u(2)
      jac(3, 2) = 2.0_dp*self%k2*u(2)
      jac(2, 2) = -jac(1, 2) - jac(3, 2)
      jac(2, 3) = -jac(1, 3)
   end subroutine robertson_jac_g

   !> f + g, each part as robertson_f and robertson_g compute it.
   subroutine robertson_rhs(self, t, u, dudt)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: slow, fast_1, fast_3
      slow = self%k1*u(1)
      fast_1 = self%k3*u(2)*u(3)
      fast_3 = self%k2*u(2)**2
      dudt(1) = -slow + fast_1
      dudt(2) = slow + (-fast_1 - fast_3)
      dudt(3) = fast_3
   end subroutine robertson_rhs

   !> df/dU + dg/dU: dg/dU, with df/dU's two nonzeros added.
   subroutine robertson_jac(self, t, u, jac)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call self%jac_g(t, u, jac)
      jac(1, 1) = jac(1, 1) - self%k1
      jac(2, 1) = jac(2, 1) + self%k1
   end subroutine robertson_jac

   !> y + alpha J v with the entries of robertson_jac, each row's terms added in the order of the
   !> columns: the same numbers as J from robertson_jac times v column by column (the default), bit
   !> for bit.
   subroutine robertson_add_jacobian_product(self, t, u, alpha, v, y)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: av(3), j12, j13, j32
      av = alpha*v(1:3)
      j12 = self%k3*u(3)
      j13 = self%k3*u(2)
      j32 = 2.0_dp*self%k2*u(2)
      y(1) = y(1) + av(1)*(-self%k1)
      y(1) = y(1) + av(2)*j12
      y(1) = y(1) + av(3)*j13
      y(2) = y(2) + av(1)*self%k1
      y(2) = y(2) + av(2)*(-j12 - j32)
      y(2) = y(2) + av(3)*(-j13)
      y(3) = y(3) + av(2)*j32
   end subroutine robertson_add_jacobian_product

end module taylorode_testset_robertson
