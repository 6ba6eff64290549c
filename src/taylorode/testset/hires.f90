!> HIRES, high irradiance responses of photomorphogenesis (Hairer & Wanner II, IV.10; Bari test set HIRES).
module taylorode_testset_hires
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: hires_type, new_hires, hires_split_exchange_stiff, hires_split_reaction_stiff

   !> g = the linear exchange terms, f = the reaction 280 y6 y8 and the source
   integer, parameter :: hires_split_exchange_stiff = 1
   !> g = the reaction 280 y6 y8, f = the linear terms and the source (the split the
   !> peer solvers' IMEX methods are measured with)
   integer, parameter :: hires_split_reaction_stiff = 2
   !> The constant source of y1
   real(dp), parameter :: source = 0.0007_dp

   !> HIRES, high irradiance responses of photomorphogenesis (Hairer & Wanner II,
   !> IV.10; Bari test set HIRES), split by `split`: by default f = the reaction
   !> 280 y6 y8 and the source 0.0007, g = the linear exchange terms.
   type, extends(test_problem_type) :: hires_type
      !> hires_split_exchange_stiff or hires_split_reaction_stiff
      integer :: split = hires_split_exchange_stiff
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => hires_f
      !> Stiff part g
      procedure :: g => hires_g
      !> df/dU, analytic
      procedure :: jac_f => hires_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => hires_jac_g
      !> y + alpha J v without forming J (either split)
      procedure :: add_jacobian_product => hires_add_jacobian_product
   end type hires_type

contains

   !> HIRES from its standard initial state over [0, 321.8122], with the published
   !> solution; split as `split` says (default hires_split_exchange_stiff).
   pure function new_hires(split) result(self)
      !> hires_split_exchange_stiff or hires_split_reaction_stiff
      integer, intent(in), optional :: split
      type(hires_type) :: self
      if (present(split)) self%split = split
      self%name = "hires"
      self%autonomous = .true.
      self%t_end = 321.8122_dp
      self%u0 = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0057_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-10_dp
      self%reference = [0.7371312573325668e-3_dp, 0.1442485726316185e-3_dp, 0.5888729740967575e-4_dp, &
         0.1175651343283149e-2_dp, 0.2386356198831331e-2_dp, 0.6238968252742796e-2_dp, &
         0.2849998395185769e-2_dp, 0.2850001604814231e-2_dp]
      self%source = "Hairer & Wanner II, IV.10; Bari test set HIRES (reference values)"
      self%nonnegative = .true.
   end function new_hires

   subroutine hires_f(self, t, u, dudt)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      if (self%split == hires_split_reaction_stiff) then
         call exchange_terms(u, dudt)
         dudt(1) = dudt(1) + source
      else
         call reaction_terms(u, dudt)
         dudt(1) = source
      end if
   end subroutine hires_f

   subroutine hires_g(self, t, u, dudt)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      if (self%split == hires_split_reaction_stiff) then
         call reaction_terms(u, dudt)
      else
         call exchange_terms(u, dudt)
      end if
   end subroutine hires_g

   subroutine hires_jac_f(self, t, u, jac)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%split == hires_split_reaction_stiff) then
         call exchange_jacobian(jac)
      else
         call reaction_jacobian(u, jac)
      end if
   end subroutine hires_jac_f

   subroutine hires_jac_g(self, t, u, jac)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%split == hires_split_reaction_stiff) then
         call reaction_jacobian(u, jac)
      else
         call exchange_jacobian(jac)
      end if
   end subroutine hires_jac_g

   !> y + alpha J v with the entries of J = df/dU + dg/dU (the exchange terms and the
   !> reaction, either split), each row's terms added in the order of the columns: the
   !> same numbers as J from `jac` times v column by column (the default), bit for bit.
   subroutine hires_add_jacobian_product(self, t, u, alpha, v, y)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: av(8), r66, r68
      av = alpha*v(1:8)
      r66 = -280.0_dp*u(8)
      r68 = -280.0_dp*u(6)
      y(1) = y(1) + av(1)*(-1.71_dp)
      y(1) = y(1) + av(2)*0.43_dp
      y(1) = y(1) + av(3)*8.32_dp
      y(2) = y(2) + av(1)*1.71_dp
      y(2) = y(2) + av(2)*(-8.75_dp)
      y(3) = y(3) + av(3)*(-10.03_dp)
      y(3) = y(3) + av(4)*0.43_dp
      y(3) = y(3) + av(5)*0.035_dp
      y(4) = y(4) + av(2)*8.32_dp
      y(4) = y(4) + av(3)*1.71_dp
      y(4) = y(4) + av(4)*(-1.12_dp)
      y(5) = y(5) + av(5)*(-1.745_dp)
      y(5) = y(5) + av(6)*0.43_dp
      y(5) = y(5) + av(7)*0.43_dp
      y(6) = y(6) + av(4)*0.69_dp
      y(6) = y(6) + av(5)*1.71_dp
      y(6) = y(6) + av(6)*(-0.43_dp + r66)
      y(6) = y(6) + av(7)*0.69_dp
      y(6) = y(6) + av(8)*r68
      y(7) = y(7) + av(6)*(-r66)
      y(7) = y(7) + av(7)*(-1.81_dp)
      y(7) = y(7) + av(8)*(-r68)
      y(8) = y(8) + av(6)*r66
      y(8) = y(8) + av(7)*1.81_dp
      y(8) = y(8) + av(8)*r68
   end subroutine hires_add_jacobian_product

   !> The reaction 280 y6 y8 (components 6, 7, 8; the others zero).
   pure subroutine reaction_terms(u, dudt)
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: reaction
      reaction = 280.0_dp*u(6)*u(8)
      dudt = 0.0_dp
      dudt(6) = -reaction
      dudt(7) = reaction
      dudt(8) = -reaction
   end subroutine reaction_terms

   !> The linear exchange terms.
   pure subroutine exchange_terms(u, dudt)
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -1.71_dp*u(1) + 0.43_dp*u(2) + 8.32_dp*u(3)
      dudt(2) = 1.71_dp*u(1) - 8.75_dp*u(2)
      dudt(3) = -10.03_dp*u(3) + 0.43_dp*u(4) + 0.035_dp*u(5)
      dudt(4) = 8.32_dp*u(2) + 1.71_dp*u(3) - 1.12_dp*u(4)
      dudt(5) = -1.745_dp*u(5) + 0.43_dp*u(6) + 0.43_dp*u(7)
      dudt(6) = 0.69_dp*u(4) + 1.71_dp*u(5) - 0.43_dp*u(6) + 0.69_dp*u(7)
      dudt(7) = -1.81_dp*u(7)
      dudt(8) = 1.81_dp*u(7)
   end subroutine exchange_terms

   !> Jacobian of the reaction terms.
   pure subroutine reaction_jacobian(u, jac)
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(6, 6) = -280.0_dp*u(8)
      jac(6, 8) = -280.0_dp*u(6)
      jac(7, 6:8:2) = -jac(6, 6:8:2)
      jac(8, 6:8:2) = jac(6, 6:8:2)
   end subroutine reaction_jacobian

   !> Jacobian of the exchange terms (constant).
   pure subroutine exchange_jacobian(jac)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1:3) = [-1.71_dp, 0.43_dp, 8.32_dp]
      jac(2, 1:2) = [1.71_dp, -8.75_dp]
      jac(3, 3:5) = [-10.03_dp, 0.43_dp, 0.035_dp]
      jac(4, 2:4) = [8.32_dp, 1.71_dp, -1.12_dp]
      jac(5, 5:7) = [-1.745_dp, 0.43_dp, 0.43_dp]
      jac(6, 4:7) = [0.69_dp, 1.71_dp, -0.43_dp, 0.69_dp]
      jac(7, 7) = -1.81_dp
      jac(8, 7) = 1.81_dp
   end subroutine exchange_jacobian

end module taylorode_testset_hires
