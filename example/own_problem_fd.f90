!> A problem that writes only f, g and one Jacobian: a pendulum with strong damping,
!> theta' = omega, omega' = -sin(theta) - c omega. The stiff part g = (0, -c omega) has
!> a one-line Jacobian, written here; df/du comes from forward differences, which
!> extending `ode_problem_fd` provides. Integrated to t = 10 with si-t-2.
module damped_pendulum
   use taylorode, only: dp, ode_problem_fd
   implicit none
   private

   public :: damped_pendulum_type

   !> f = (omega, -sin theta) non-stiff, g = (0, -c omega) stiff
   type, extends(ode_problem_fd) :: damped_pendulum_type
      real(dp) :: damping = 1.0e4_dp
   contains
      procedure :: f => swing
      procedure :: g => friction
      procedure :: jac_g => friction_jacobian   ! jac_f: forward differences of f
   end type damped_pendulum_type

contains

   subroutine swing(self, t, u, dudt)
      class(damped_pendulum_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = u(2)
      dudt(2) = -sin(u(1))
   end subroutine swing

   subroutine friction(self, t, u, dudt)
      class(damped_pendulum_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = 0.0_dp
      dudt(2) = -self%damping*u(2)
   end subroutine friction

   subroutine friction_jacobian(self, t, u, jac)
      class(damped_pendulum_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(2, 2) = -self%damping
   end subroutine friction_jacobian

end module damped_pendulum

program own_problem_fd
   use taylorode, only: dp, scheme_type, new_scheme, integrate, integrator_options_type, &
      integration_stats_type, status_type
   use damped_pendulum, only: damped_pendulum_type
   implicit none

   type(damped_pendulum_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(integration_stats_type) :: stats
   type(status_type) :: stat
   real(dp) :: u(2)

   u = [1.0_dp, 0.0_dp]
   call new_scheme("si-t-2", scheme, stat)
   if (.not. stat%ok()) error stop stat%message
   call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-8_dp), &
      stats, stat)
   if (.not. stat%ok()) error stop stat%message
   print '(a, 2es17.9)', "theta, omega at t = 10:", u
   print '(a, i0, a, i0, a, i0)', "accepted ", stats%accepted_steps, ", f evaluations ", stats%work%f_evaluations, &
      " (differences included), df/du evaluations ", stats%work%jac_f_evaluations
end program own_problem_fd
