!> Helpers shared by the test suites: an independent reference solver and
!> message formatting.
module test_support
   use taylorode, only: dp, ode_problem, status_type
   implicit none
   private

   public :: rk4_reference, stat_message

contains

   !> Classical RK4 with 20000 steps: global error ~ 1e-17 * C, far below what the
   !> order tests resolve (their smallest errors are ~1e-7).
   function rk4_reference(problem, u0, t_end) result(u)
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u0(:), t_end
      real(dp) :: u(size(u0))
      integer, parameter :: n = 20000
      real(dp) :: h, t, k1(size(u0)), k2(size(u0)), k3(size(u0)), k4(size(u0))
      integer :: i
      h = t_end/n
      u = u0
      do i = 0, n - 1
         t = i*h
         call full_rhs(t, u, k1)
         call full_rhs(t + h/2, u + h/2*k1, k2)
         call full_rhs(t + h/2, u + h/2*k2, k3)
         call full_rhs(t + h, u + h*k3, k4)
         u = u + h/6*(k1 + 2*k2 + 2*k3 + k4)
      end do
   contains
      subroutine full_rhs(t, u, dudt)
         real(dp), intent(in) :: t, u(:)
         real(dp), intent(out) :: dudt(:)
         real(dp) :: gu(size(u))
         call problem%f(t, u, dudt)
         call problem%g(t, u, gu)
         dudt = dudt + gu
      end subroutine full_rhs
   end function rk4_reference

   !> The status message, or "ok".
   function stat_message(stat) result(message)
      type(status_type), intent(in) :: stat
      character(len=:), allocatable :: message
      if (allocated(stat%message)) then
         message = stat%message
      else
         message = "ok"
      end if
   end function stat_message

end module test_support
