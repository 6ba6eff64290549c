!> Observers are user code called after every accepted step with the step (its end
!> state and, through `step%interpolate`, the solution anywhere inside it), which may
!> ask the integration to stop there. The step history remains for those who want
!> every attempt stored.
module taylorode_integrate_observer
   use taylorode_integrate_step, only: accepted_step_type
   implicit none
   private

   public :: step_observer_type

   !> Extend it with the data you need and write `observe`
   type, abstract :: step_observer_type
   contains
      !> Called after every accepted step
      procedure(observe_interface), deferred :: observe
   end type step_observer_type

   abstract interface
      !> Look at an accepted step; set stop to end the integration at step%t_end
      !> (status ok, stats%t_reached = step%t_end).
      subroutine observe_interface(self, step, stop)
         import :: step_observer_type, accepted_step_type
         !> The observer (carries your data)
         class(step_observer_type), intent(inout) :: self
         !> The step just accepted
         type(accepted_step_type), intent(in) :: step
         !> Set to .true. to stop after this step
         logical, intent(inout) :: stop
      end subroutine observe_interface
   end interface

end module taylorode_integrate_observer
