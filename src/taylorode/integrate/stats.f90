!> What an adaptive integration did and what it cost.
module taylorode_integrate_stats
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_counters, only: counters_type
   implicit none
   private

   public :: integration_stats_type

   !> Steps, rejections by cause, work, step sizes and times of one integration
   type :: integration_stats_type
      !> Time of the returned state (t_end on success, the last accepted time on failure)
      real(dp) :: t_reached = 0.0_dp
      !> Accepted steps
      integer(i8) :: accepted_steps = 0
      !> Steps rejected by the error test
      integer(i8) :: rejected_error = 0
      !> Of these, the ones before the first accepted step of the integration (the search
      !> for a first step size; RADAU5's NREJCT leaves them out)
      integer(i8) :: rejected_error_start = 0
      !> Attempts that failed in Newton (singular matrix, divergence, no convergence)
      integer(i8) :: rejected_newton = 0
      !> Of these, the ones whose Newton matrix was singular (RADAU5's NSTEP leaves them
      !> out: it counts a step once its matrices are factored)
      integer(i8) :: rejected_singular = 0
      !> Attempts that produced NaN or Inf
      integer(i8) :: rejected_nonfinite = 0
      !> Attempts in which the problem rejected an evaluation (reject_evaluation)
      integer(i8) :: rejected_evaluation = 0
      !> Steps rejected because a component declared nonnegative went below 0
      integer(i8) :: rejected_constraint = 0
      !> Steps rejected because their dense output at an output time inside them failed
      !> its error test (retried to end at that time)
      integer(i8) :: rejected_output = 0
      !> Whether error weights were raised to what double precision resolves (tolerances
      !> below about 1e-14 relative ask for more than roundoff allows)
      logical :: weights_raised = .false.
      !> Evaluations and linear algebra of the integration (scheme and integrator together)
      type(counters_type) :: work
      !> Smallest and largest accepted step size
      real(dp) :: h_min_accepted = huge(1.0_dp), h_max_accepted = 0.0_dp
      !> Wall-clock and CPU seconds spent in `integrate`
      real(dp) :: wall_seconds = 0.0_dp, cpu_seconds = 0.0_dp
   contains
      !> All rejected or failed attempts
      procedure :: rejected_steps
   end type integration_stats_type

contains

   !> Rejected plus failed attempts.
   elemental function rejected_steps(self) result(n)
      !> The statistics
      class(integration_stats_type), intent(in) :: self
      integer(i8) :: n
      n = self%rejected_error + self%rejected_newton + self%rejected_nonfinite + self%rejected_evaluation + &
         self%rejected_constraint + self%rejected_output
   end function rejected_steps

end module taylorode_integrate_stats
