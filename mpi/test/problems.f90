!> The problems of the MPI tests: Van der Pol members that fail from a time on, and
!> independent Van der Pol blocks split over the ranks.
module test_mpi_problems
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   use taylorode, only: dp
   use taylorode_testset, only: van_der_pol_type
   use taylorode_mpi, only: distributed_problem_type
   implicit none
   private

   public :: flaky_vdp_type, vdp_blocks_type, failure_none, failure_nan, failure_fatal, failure_rejections, block_mu

   !> How a flaky member fails after t_bad
   integer, parameter :: failure_none = 0, failure_nan = 1, failure_fatal = 2, failure_rejections = 3

   !> Van der Pol that goes wrong from a time on
   type, extends(van_der_pol_type) :: flaky_vdp_type
      integer :: failure = failure_none
      real(dp) :: t_bad = huge(1.0_dp)
   contains
      procedure :: g => flaky_g
   end type flaky_vdp_type

   !> Independent Van der Pol blocks (y, z) with mu = 1 + b/2 for global block b; this
   !> rank holds blocks first_block .. first_block + blocks - 1
   type, extends(distributed_problem_type) :: vdp_blocks_type
      integer :: first_block = 0, blocks = 0
   contains
      procedure :: f => blocks_f
      procedure :: g => blocks_g
      procedure :: jac_f => blocks_jac_f
      procedure :: jac_g => blocks_jac_g
   end type vdp_blocks_type

contains

   !> mu of the local block b.
   pure real(dp) function block_mu(problem, b)
      type(vdp_blocks_type), intent(in) :: problem
      integer, intent(in) :: b
      block_mu = 1.0_dp + 0.5_dp*real(problem%first_block + b - 1, dp)
   end function block_mu

   !> f = (z, 0) per block (Van der Pol in the stiff splitting, g holds the second equation)
   subroutine blocks_f(self, t, u, dudt)
      class(vdp_blocks_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      integer :: b
      do b = 1, self%blocks
         dudt(2*b - 1) = u(2*b)
         dudt(2*b) = 0.0_dp
      end do
   end subroutine blocks_f

   !> g = (0, mu (1 - y^2) z - y) per block
   subroutine blocks_g(self, t, u, dudt)
      class(vdp_blocks_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      integer :: b
      do b = 1, self%blocks
         dudt(2*b - 1) = 0.0_dp
         dudt(2*b) = block_mu(self, b)*(1.0_dp - u(2*b - 1)**2)*u(2*b) - u(2*b - 1)
      end do
   end subroutine blocks_g

   subroutine blocks_jac_f(self, t, u, jac)
      class(vdp_blocks_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      integer :: b
      jac = 0.0_dp
      do b = 1, self%blocks
         jac(2*b - 1, 2*b) = 1.0_dp
      end do
   end subroutine blocks_jac_f

   subroutine blocks_jac_g(self, t, u, jac)
      class(vdp_blocks_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      integer :: b
      real(dp) :: mu
      jac = 0.0_dp
      do b = 1, self%blocks
         mu = block_mu(self, b)
         jac(2*b, 2*b - 1) = -2.0_dp*mu*u(2*b - 1)*u(2*b) - 1.0_dp
         jac(2*b, 2*b) = mu*(1.0_dp - u(2*b - 1)**2)
      end do
   end subroutine blocks_jac_g

   !> g of Van der Pol, then the member's failure after t_bad.
   subroutine flaky_g(self, t, u, dudt)
      class(flaky_vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call self%van_der_pol_type%g(t, u, dudt)
      if (t <= self%t_bad) return
      select case (self%failure)
      case (failure_nan)
         dudt = ieee_value(1.0_dp, ieee_quiet_nan)
      case (failure_fatal)
         call self%reject_evaluation(fatal=.true.)
      case (failure_rejections)
         call self%reject_evaluation()
      end select
   end subroutine flaky_g

end module test_mpi_problems
