!> Dense output: the solution at requested times, from the cubic Hermite
!> interpolant of each accepted step (values and derivatives F at both ends).
module taylorode_integrate_dense_output
   use taylorode_base_kinds, only: dp
   implicit none
   private

   public :: dense_output_type, hermite_interpolate

   !> Walks through the requested times as the accepted steps pass them
   type :: dense_output_type
      !> F at the start of the current step, and at its end
      real(dp), allocatable :: rhs_start(:), rhs_end(:)
      !> Index of the next output time
      integer :: next = 1
   contains
      !> Begin at t0: output times equal to t0 take the initial state
      procedure :: start
      !> Fill the output times inside an accepted step
      procedure :: emit
   end type dense_output_type

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

   !> Begin at t0 with state u0 and derivative rhs0; output times equal to t0 take u0.
   subroutine start(self, t0, u0, rhs0, t_out, u_out)
      !> The dense output
      class(dense_output_type), intent(inout) :: self
      !> Initial time
      real(dp), intent(in) :: t0
      !> Initial state and F(t0, u0)
      real(dp), intent(in) :: u0(:), rhs0(:)
      !> Ascending output times
      real(dp), intent(in) :: t_out(:)
      !> Output states, one column per time
      real(dp), intent(inout) :: u_out(:, :)
      if (allocated(self%rhs_start)) then
         if (size(self%rhs_start) /= size(u0)) deallocate (self%rhs_start, self%rhs_end)
      end if
      if (.not. allocated(self%rhs_start)) allocate (self%rhs_start(size(u0)), self%rhs_end(size(u0)))
      self%rhs_start = rhs0
      self%next = 1
      do while (self%next <= size(t_out))
         if (t_out(self%next) > t0) exit
         u_out(:, self%next) = u0
         self%next = self%next + 1
      end do
   end subroutine start

   !> For an accepted step from (t_a, u_a) of size h ending at t_b with (u_b, F_b in
   !> rhs_end, set by the caller), fill every output time in (t_a, t_b].
   subroutine emit(self, t_a, h, t_b, u_a, u_b, t_out, u_out)
      !> The dense output; rhs_end holds F(t_b, u_b) on entry
      class(dense_output_type), intent(inout) :: self
      !> Start, size and end of the step (t_b is exactly t_end on the last step)
      real(dp), intent(in) :: t_a, h, t_b
      !> States at both ends
      real(dp), intent(in) :: u_a(:), u_b(:)
      !> Ascending output times
      real(dp), intent(in) :: t_out(:)
      !> Output states, one column per time
      real(dp), intent(inout) :: u_out(:, :)
      do while (self%next <= size(t_out))
         if (t_out(self%next) > t_b) exit
         call hermite_interpolate((t_out(self%next) - t_a)/h, h, u_a, self%rhs_start, u_b, self%rhs_end, &
            u_out(:, self%next))
         self%next = self%next + 1
      end do
      self%rhs_start = self%rhs_end
   end subroutine emit

end module taylorode_integrate_dense_output
