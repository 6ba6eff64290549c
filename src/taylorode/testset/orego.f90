!> OREGO, the Oregonator (Hairer & Wanner II, IV.10; Bari test set OREGO).
module taylorode_testset_orego
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: orego_type, new_orego, orego_split_fast_stiff, orego_split_bilinear_stiff

   !> g = the fast first two equations, f = the slow third
   integer, parameter :: orego_split_fast_stiff = 1
   !> g = (s (y2 + y1 - y1 y2), -y1 y2 / s, 0), f = the rest (the split the peer
   !> solvers' IMEX methods are measured with)
   integer, parameter :: orego_split_bilinear_stiff = 2

   !> OREGO, the Oregonator (Hairer & Wanner II, IV.10; Bari test set OREGO), split
   !> by `split`: by default g = the fast first two equations (scaled by s and 1/s),
   !> f = the slow third.
   type, extends(test_problem_type) :: orego_type
      !> Parameters s, w and q of the published problem
      real(dp) :: s = 77.27_dp, w = 0.161_dp, q = 8.375e-6_dp
      !> orego_split_fast_stiff or orego_split_bilinear_stiff
      integer :: split = orego_split_fast_stiff
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => orego_f
      !> Stiff part g
      procedure :: g => orego_g
      !> df/dU, analytic
      procedure :: jac_f => orego_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => orego_jac_g
      !> F = f + g in one pass (either split)
      procedure :: rhs => orego_rhs
      !> J = df/dU + dg/dU in one call: dg/dU with the nonzeros of df/dU added
      procedure :: jac => orego_jac
      !> y + alpha J v without forming J (either split)
      procedure :: add_jacobian_product => orego_add_jacobian_product
   end type orego_type

contains

   !> OREGO from (1, 2, 3) over [0, 360], with the published solution; split as
   !> `split` says (default orego_split_fast_stiff).
   pure function new_orego(split) result(self)
      !> orego_split_fast_stiff or orego_split_bilinear_stiff
      integer, intent(in), optional :: split
      type(orego_type) :: self
      if (present(split)) self%split = split
      self%name = "orego"
      self%autonomous = .true.
      self%t_end = 360.0_dp
      self%u0 = [1.0_dp, 2.0_dp, 3.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%reference = [0.1000814870318523e1_dp, 0.1228178521549917e4_dp, 0.1320554942846706e3_dp]
      self%source = "Hairer & Wanner II, IV.10; Bari test set OREGO (reference values)"
      self%nonnegative = .true.
   end function new_orego

   subroutine orego_f(self, t, u, dudt)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      if (self%split == orego_split_bilinear_stiff) then
         dudt(1) = -self%s*self%q*u(1)**2
         dudt(2) = (u(3) - u(2))/self%s
      else
         dudt(1:2) = 0.0_dp
      end if
      dudt(3) = self%w*(u(1) - u(3))
   end subroutine orego_f

   subroutine orego_g(self, t, u, dudt)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      if (self%split == orego_split_bilinear_stiff) then
         dudt(1) = self%s*(u(2) + u(1) - u(1)*u(2))
         dudt(2) = -u(1)*u(2)/self%s
      else
         dudt(1) = self%s*(u(2) - u(1)*u(2) + u(1) - self%q*u(1)**2)
         dudt(2) = (-u(2) - u(1)*u(2) + u(3))/self%s
      end if
      dudt(3) = 0.0_dp
   end subroutine orego_g

   subroutine orego_jac_f(self, t, u, jac)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      if (self%split == orego_split_bilinear_stiff) then
         jac(1, 1) = -2.0_dp*self%s*self%q*u(1)
         jac(2, 2) = -1.0_dp/self%s
         jac(2, 3) = 1.0_dp/self%s
      end if
      jac(3, 1) = self%w
      jac(3, 3) = -self%w
   end subroutine orego_jac_f

   subroutine orego_jac_g(self, t, u, jac)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 2) = self%s*(1.0_dp - u(1))
      jac(2, 1) = -u(2)/self%s
      if (self%split == orego_split_bilinear_stiff) then
         jac(1, 1) = self%s*(1.0_dp - u(2))
         jac(2, 2) = -u(1)/self%s
      else
         jac(1, 1) = self%s*(1.0_dp - u(2) - 2.0_dp*self%q*u(1))
         jac(2, 2) = -(1.0_dp + u(1))/self%s
         jac(2, 3) = 1.0_dp/self%s
      end if
   end subroutine orego_jac_g

   !> f + g, each part as orego_f and orego_g compute it (a part that is zero is left out).
   subroutine orego_rhs(self, t, u, dudt)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      if (self%split == orego_split_bilinear_stiff) then
         dudt(1) = -self%s*self%q*u(1)**2 + self%s*(u(2) + u(1) - u(1)*u(2))
         dudt(2) = (u(3) - u(2))/self%s + (-u(1)*u(2)/self%s)
      else
         dudt(1) = self%s*(u(2) - u(1)*u(2) + u(1) - self%q*u(1)**2)
         dudt(2) = (-u(2) - u(1)*u(2) + u(3))/self%s
      end if
      dudt(3) = self%w*(u(1) - u(3))
   end subroutine orego_rhs

   !> df/dU + dg/dU: dg/dU, with df/dU's nonzeros added (either split).
   subroutine orego_jac(self, t, u, jac)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call self%jac_g(t, u, jac)
      if (self%split == orego_split_bilinear_stiff) then
         jac(1, 1) = jac(1, 1) + (-2.0_dp*self%s*self%q*u(1))
         jac(2, 2) = jac(2, 2) + (-1.0_dp/self%s)
         jac(2, 3) = jac(2, 3) + 1.0_dp/self%s
      end if
      jac(3, 1) = jac(3, 1) + self%w
      jac(3, 3) = jac(3, 3) - self%w
   end subroutine orego_jac

   !> y + alpha J v with the entries of orego_jac (either split), each row's terms added in the
   !> order of the columns: the same numbers as J from orego_jac times v column by column (the
   !> default), bit for bit.
   subroutine orego_add_jacobian_product(self, t, u, alpha, v, y)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: av(3), j11, j22
      av = alpha*v(1:3)
      if (self%split == orego_split_bilinear_stiff) then
         j11 = self%s*(1.0_dp - u(2)) + (-2.0_dp*self%s*self%q*u(1))
         j22 = -u(1)/self%s + (-1.0_dp/self%s)
      else
         j11 = self%s*(1.0_dp - u(2) - 2.0_dp*self%q*u(1))
         j22 = -(1.0_dp + u(1))/self%s
      end if
      y(1) = y(1) + av(1)*j11
      y(1) = y(1) + av(2)*(self%s*(1.0_dp - u(1)))
      y(2) = y(2) + av(1)*(-u(2)/self%s)
      y(2) = y(2) + av(2)*j22
      y(2) = y(2) + av(3)*(1.0_dp/self%s)
      y(3) = y(3) + av(1)*self%w
      y(3) = y(3) + av(3)*(-self%w)
   end subroutine orego_add_jacobian_product

end module taylorode_testset_orego
