!> Van der Pol's equation, the paper's test problem (METHODS.md section 5):
!>
!>   y' = z,   z' = mu (1 - y^2) z - y
!>
!> Paper splitting:  f = (z, -y),  g = (0, mu (1 - y^2) z).
!> Stiff splitting:  f = (z, 0),   g = (0, mu (1 - y^2) z - y).
module taylorode_testset_van_der_pol
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state
   public :: vdp_split_paper, vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared

   !> f = (z, -y), g = (0, mu (1 - y^2) z)
   integer, parameter :: vdp_split_paper = 1
   !> f = (z, 0), g = (0, mu (1 - y^2) z - y)
   integer, parameter :: vdp_split_stiff = 2
   !> IC1, well prepared: y = 2, z = y / (1 - y^2)
   integer, parameter :: vdp_ic_prepared = 1
   !> IC2, unprepared: y = 2, z = 0
   integer, parameter :: vdp_ic_unprepared = 2

   !> Reference values at t = 3000 for mu = 1000 (METHODS.md section 5), by initial condition
   real(dp), parameter :: reference_mu_1000(2, 2) = reshape([ &
      -1.5102139907362793_dp, 1.1791653311113964e-3_dp, &
      -1.5106069367443018_dp, 1.1783800007305336e-3_dp], [2, 2])

   !> Van der Pol oscillator with stiffness parameter mu
   type, extends(test_problem_type) :: van_der_pol_type
      !> Stiffness parameter
      real(dp) :: mu = 1000.0_dp
      !> vdp_split_paper or vdp_split_stiff
      integer :: splitting = vdp_split_paper
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => vdp_f
      !> Stiff part g
      procedure :: g => vdp_g
      !> F = f + g in one call (either splitting)
      procedure :: rhs => vdp_rhs
      !> df/dU, analytic
      procedure :: jac_f => vdp_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => vdp_jac_g
      !> J = df/dU + dg/dU in one pass (either splitting)
      procedure :: jac => vdp_jac
      !> y + alpha J v without forming J (either splitting)
      procedure :: add_jacobian_product => vdp_add_jacobian_product
   end type van_der_pol_type

contains

   !> Create the problem with parameter mu, a splitting (default: the paper's) and
   !> the paper's time span [0, 3 mu] from IC1 (or `ic`). The paper's tolerances
   !> (atol 1e-5, rtol 0) are the recommended ones; for mu = 1000 the reference
   !> solution at t = 3000 of METHODS.md section 5 is attached.
   pure function new_van_der_pol(mu, splitting, ic) result(self)
      !> Stiffness parameter
      real(dp), intent(in) :: mu
      !> vdp_split_paper (default) or vdp_split_stiff
      integer, intent(in), optional :: splitting
      !> vdp_ic_prepared (default) or vdp_ic_unprepared
      integer, intent(in), optional :: ic
      type(van_der_pol_type) :: self
      integer :: initial

      self%mu = mu
      if (present(splitting)) self%splitting = splitting
      initial = vdp_ic_prepared
      if (present(ic)) initial = ic
      self%name = "vdp"
      self%autonomous = .true.
      self%t0 = 0.0_dp
      self%t_end = 3.0_dp*mu
      self%u0 = van_der_pol_initial_state(initial)
      self%rtol = 0.0_dp
      self%atol = 1.0e-5_dp
      if (mu == 1000.0_dp .and. (initial == vdp_ic_prepared .or. initial == vdp_ic_unprepared)) then
         self%reference = reference_mu_1000(:, initial)
      end if
      self%source = "Boscarino & Macca, section 5; reference values: METHODS.md section 5"
   end function new_van_der_pol

   !> The paper's initial states: IC1 (vdp_ic_prepared) or IC2 (vdp_ic_unprepared).
   pure function van_der_pol_initial_state(ic) result(u)
      !> vdp_ic_prepared or vdp_ic_unprepared
      integer, intent(in) :: ic
      real(dp) :: u(2)
      u(1) = 2.0_dp
      if (ic == vdp_ic_prepared) then
         u(2) = u(1)/(1.0_dp - u(1)**2)
      else
         u(2) = 0.0_dp
      end if
   end function van_der_pol_initial_state

   subroutine vdp_f(self, t, u, dudt)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = u(2)
      if (self%splitting == vdp_split_paper) then
         dudt(2) = -u(1)
      else
         dudt(2) = 0.0_dp
      end if
   end subroutine vdp_f

   subroutine vdp_g(self, t, u, dudt)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = 0.0_dp
      dudt(2) = self%mu*(1.0_dp - u(1)**2)*u(2)
      if (self%splitting == vdp_split_stiff) dudt(2) = dudt(2) - u(1)
   end subroutine vdp_g

   subroutine vdp_rhs(self, t, u, dudt)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = u(2)
      dudt(2) = self%mu*(1.0_dp - u(1)**2)*u(2) - u(1)
   end subroutine vdp_rhs

   subroutine vdp_jac_f(self, t, u, jac)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 2) = 1.0_dp
      if (self%splitting == vdp_split_paper) jac(2, 1) = -1.0_dp
   end subroutine vdp_jac_f

   subroutine vdp_jac_g(self, t, u, jac)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(2, 1) = -2.0_dp*self%mu*u(1)*u(2)
      jac(2, 2) = self%mu*(1.0_dp - u(1)**2)
      if (self%splitting == vdp_split_stiff) jac(2, 1) = jac(2, 1) - 1.0_dp
   end subroutine vdp_jac_g

   subroutine vdp_jac(self, t, u, jac)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = 0.0_dp
      jac(1, 2) = 1.0_dp
      jac(2, 1) = -2.0_dp*self%mu*u(1)*u(2) - 1.0_dp
      jac(2, 2) = self%mu*(1.0_dp - u(1)**2)
   end subroutine vdp_jac

   !> y + alpha J v with the entries of vdp_jac, each row's terms added in the order of the columns:
   !> the same numbers as J from vdp_jac times v column by column (the default), bit for bit.
   subroutine vdp_add_jacobian_product(self, t, u, alpha, v, y)
      class(van_der_pol_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: av1, av2
      av1 = alpha*v(1)
      av2 = alpha*v(2)
      y(1) = y(1) + av2
      y(2) = y(2) + av1*(-2.0_dp*self%mu*u(1)*u(2) - 1.0_dp)
      y(2) = y(2) + av2*(self%mu*(1.0_dp - u(1)**2))
   end subroutine vdp_add_jacobian_product

end module taylorode_testset_van_der_pol
