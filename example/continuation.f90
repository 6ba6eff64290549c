!> Continuation, an observer and events on Van der Pol (mu = 1000, the paper's
!> problem): one integrator is initialized once and advanced to t = 500, 1000, ...,
!> 3000 call by call (step size, controller memory and factored Newton matrices are
!> kept between calls); an observer sees every accepted step; an event function
!> locates every zero of y on the dense output.
module vdp_watchers
   use taylorode, only: dp, step_observer_type, accepted_step_type, event_functions_type
   implicit none
   private

   public :: step_watch_type, zeros_of_y_type

   !> Counts the accepted steps and keeps the smallest one
   type, extends(step_observer_type) :: step_watch_type
      integer :: steps = 0
      real(dp) :: h_smallest = huge(1.0_dp)
   contains
      procedure :: observe => watch
   end type step_watch_type

   !> One event function, e_1(t, u) = y
   type, extends(event_functions_type) :: zeros_of_y_type
   contains
      procedure :: evaluate => y_itself
   end type zeros_of_y_type

contains

   subroutine watch(self, step, stop)
      class(step_watch_type), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      logical, intent(inout) :: stop      ! set it to end the integration after this step
      self%steps = self%steps + 1
      self%h_smallest = min(self%h_smallest, step%h)
   end subroutine watch

   subroutine y_itself(self, t, u, values)
      class(zeros_of_y_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: values(:)
      values(1) = u(1)
   end subroutine y_itself

end module vdp_watchers

program continuation
   use taylorode, only: dp, scheme_type, new_scheme, integrator_type, paper_options, status_type, event_any
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, vdp_ic_prepared
   use vdp_watchers, only: step_watch_type, zeros_of_y_type
   implicit none

   type(van_der_pol_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(integrator_type) :: integrator
   type(step_watch_type) :: watch
   type(zeros_of_y_type) :: zeros
   type(status_type) :: stat
   real(dp) :: u(2)
   integer :: k

   problem = new_van_der_pol(mu=1000.0_dp)
   u = van_der_pol_initial_state(vdp_ic_prepared)
   zeros = zeros_of_y_type(count=1, direction=[event_any], terminal=[.false.])
   call new_scheme("i-t-2", scheme, stat)
   if (.not. stat%ok()) error stop stat%message

   call integrator%init(problem, scheme, 0.0_dp, u, paper_options(), stat)
   if (.not. stat%ok()) error stop stat%message
   do k = 1, 6
      call integrator%advance_to(problem, scheme, 500.0_dp*k, u, stat, observer=watch, events=zeros)
      if (.not. stat%ok()) error stop stat%message
      print '(a, f7.1, a, 2es16.8)', "t =", integrator%t, "   u =", u
   end do
   print '(a, i0, a, es9.2)', "accepted steps seen by the observer: ", watch%steps, ", smallest h ", watch%h_smallest
   print '(a, i0, a, *(f9.3))', "zeros of y: ", zeros%found, " at t =", zeros%found_t(:zeros%found)
end program continuation
