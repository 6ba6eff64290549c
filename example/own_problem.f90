!> Your own problem: Robertson's chemical kinetics written as a user would, with the
!> slow reaction in f and the fast ones in g, the rate constants as components of the
!> type and both Jacobians analytic; integrated to t = 40 with i-t-2.
module robertson_kinetics
   use taylorode, only: dp, ode_problem
   implicit none
   private

   public :: robertson_kinetics_type

   !> y1' = -k1 y1 + k3 y2 y3, y2' = k1 y1 - k3 y2 y3 - k2 y2^2, y3' = k2 y2^2
   type, extends(ode_problem) :: robertson_kinetics_type
      real(dp) :: k1 = 0.04_dp, k2 = 3.0e7_dp, k3 = 1.0e4_dp
   contains
      procedure :: f => slow_reaction
      procedure :: g => fast_reactions
      procedure :: jac_f => slow_jacobian
      procedure :: jac_g => fast_jacobian
   end type robertson_kinetics_type

contains

   !> f(t, u): the slow reaction y1 -> y2
   subroutine slow_reaction(self, t, u, dudt)
      class(robertson_kinetics_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -self%k1*u(1)
      dudt(2) = self%k1*u(1)
      dudt(3) = 0.0_dp
   end subroutine slow_reaction

   !> g(t, u): the fast reactions 2 y2 -> y2 + y3 and y2 + y3 -> y1 + y3
   subroutine fast_reactions(self, t, u, dudt)
      class(robertson_kinetics_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = self%k3*u(2)*u(3)
      dudt(3) = self%k2*u(2)**2
      dudt(2) = -dudt(1) - dudt(3)
   end subroutine fast_reactions

   !> df/du: jac(i, j) = d f_i / d u_j; every entry is written (jac is intent(out))
   subroutine slow_jacobian(self, t, u, jac)
      class(robertson_kinetics_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = -self%k1
      jac(2, 1) = self%k1
   end subroutine slow_jacobian

   !> dg/du
   subroutine fast_jacobian(self, t, u, jac)
      class(robertson_kinetics_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 2) = self%k3*u(3)
      jac(1, 3) = self%k3*u(2)
      jac(3, 2) = 2.0_dp*self%k2*u(2)
      jac(2, :) = -jac(1, :) - jac(3, :)
   end subroutine fast_jacobian

end module robertson_kinetics

program own_problem
   use taylorode, only: dp, scheme_type, new_scheme, integrate, integrator_options_type, &
      integration_stats_type, status_type
   use robertson_kinetics, only: robertson_kinetics_type
   implicit none

   type(robertson_kinetics_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(integrator_options_type) :: options
   type(integration_stats_type) :: stats
   type(status_type) :: stat
   real(dp) :: u(3)

   u = [1.0_dp, 0.0_dp, 0.0_dp]
   problem%autonomous = .true.     ! f and g do not depend on t
   options%rtol = 1.0e-6_dp
   options%atol = 1.0e-10_dp
   call new_scheme("i-t-2", scheme, stat)
   if (.not. stat%ok()) error stop stat%message
   call integrate(problem, scheme, 0.0_dp, 40.0_dp, u, options, stats, stat)
   if (.not. stat%ok()) then
      print '(a, es12.5, 2a)', "stopped at t =", stats%t_reached, ": ", stat%message
      error stop
   end if
   print '(a, 3es17.9)', "u(40) =", u
   print '(a, i0, a, i0, a, i0)', "accepted ", stats%accepted_steps, ", rejected ", stats%rejected_steps(), &
      ", LU factorizations ", stats%work%lu_factorizations
end program own_problem
