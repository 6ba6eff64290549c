!> One accepted step as observers, events and dense output see it: where it started
!> and ended, the states and derivatives F at both ends, and the cubic Hermite
!> interpolant between them.
module taylorode_integrate_step
   use taylorode_base_kinds, only: dp
   implicit none
   private

   public :: accepted_step_type, hermite_interpolate

   !> An accepted step [t_start, t_end] of size h
   type :: accepted_step_type
      !> Start, size and end of the step (t_end is exactly the target on a last step)
      real(dp) :: t_start = 0.0_dp, h = 0.0_dp, t_end = 0.0_dp
      !> States at both ends
      real(dp), allocatable :: u_start(:), u_end(:)
      !> F = f + g at both ends
      real(dp), allocatable :: rhs_start(:), rhs_end(:)
   contains
      !> The solution at t in [t_start, t_end] from the cubic Hermite interpolant
      procedure :: interpolate
      !> Work arrays for n unknowns (allocated only when n changes)
      procedure :: reserve
   end type accepted_step_type

contains

   !> The cubic Hermite interpolant at theta = (t - t_a)/h in [0, 1] of a step of size h
   !> from (u_a, F_a) to (u_b, F_b).
   pure subroutine hermite_interpolate(theta, h, u_a, rhs_a, u_b, rhs_b, u)
      !> Position inside the step, (t - t_a)/h
      real(dp), intent(in) :: theta
      !> Step size
      real(dp), intent(in) :: h
      !> State and derivative at the start of the step
      real(dp), intent(in) :: u_a(:), rhs_a(:)
      !> State and derivative at the end of the step
      real(dp), intent(in) :: u_b(:), rhs_b(:)
      !> Interpolated state
      real(dp), intent(out) :: u(:)
      real(dp) :: h00, h10, h01, h11
      h00 = (1.0_dp + 2.0_dp*theta)*(1.0_dp - theta)**2
      h10 = theta*(1.0_dp - theta)**2
      h01 = theta**2*(3.0_dp - 2.0_dp*theta)
      h11 = theta**2*(theta - 1.0_dp)
      u = h00*u_a + (h10*h)*rhs_a + h01*u_b + (h11*h)*rhs_b
   end subroutine hermite_interpolate

   !> The solution at t (clamped to the step) from the cubic Hermite interpolant:
   !> third order, continuous with its derivative across steps.
   pure subroutine interpolate(self, t, u)
      !> The step
      class(accepted_step_type), intent(in) :: self
      !> Time inside the step
      real(dp), intent(in) :: t
      !> Interpolated state
      real(dp), intent(out) :: u(:)
      real(dp) :: theta
      if (t >= self%t_end) then
         u = self%u_end
         return
      end if
      theta = max(0.0_dp, (t - self%t_start)/self%h)
      call hermite_interpolate(theta, self%h, self%u_start, self%rhs_start, self%u_end, self%rhs_end, u)
   end subroutine interpolate

   !> Work arrays for n unknowns.
   pure subroutine reserve(self, n)
      !> The step
      class(accepted_step_type), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      if (allocated(self%u_start)) then
         if (size(self%u_start) == n) return
         deallocate (self%u_start, self%u_end, self%rhs_start, self%rhs_end)
      end if
      allocate (self%u_start(n), self%u_end(n), self%rhs_start(n), self%rhs_end(n))
   end subroutine reserve

end module taylorode_integrate_step
