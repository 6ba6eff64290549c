!> What every process holding a part of the state must agree on, combined through
!> the problem's one hook `reduce`: the weighted norms (of the error, of the state and
!> its derivative for the first step size), the largest component of the state (the
!> weights of components with a zero absolute tolerance), the outcome of an attempted
!> step and whether a state is finite. Step decisions follow from these alone, so
!> every process takes the same. In one process (the default `reduce`) each costs
!> one call that does nothing, and the values are those computed without it.
module taylorode_integrate_reduction
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_evaluation_failed
   use taylorode_problem_ode, only: ode_problem, reduce_sum, reduce_max
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: reduced_max, reduced_root_mean_square, agree_on_outcome, finite_everywhere

contains

   !> The largest of this process's x over every process.
   real(dp) function reduced_max(problem, x)
      !> The problem (its `reduce`)
      class(ode_problem), intent(inout) :: problem
      !> This process's value
      real(dp), intent(in) :: x
      real(dp) :: values(1)
      values(1) = x
      if (.not. problem%whole_state_here()) call problem%reduce(reduce_max, values)
      reduced_max = values(1)
   end function reduced_max

   !> sqrt(sum of squares / number of components) over every process, from this
   !> process's sum of squares and number of components.
   real(dp) function reduced_root_mean_square(problem, sum_squares, count)
      !> The problem (its `reduce`)
      class(ode_problem), intent(inout) :: problem
      !> This process's sum of squares
      real(dp), intent(in) :: sum_squares
      !> This process's number of components
      integer, intent(in) :: count
      real(dp) :: values(2)
      values(1) = sum_squares
      values(2) = real(count, dp)
      if (.not. problem%whole_state_here()) call problem%reduce(reduce_sum, values)
      reduced_root_mean_square = sqrt(values(1)/values(2))
   end function reduced_root_mean_square

   !> The outcome of an attempt every process agrees on: the largest status code (a
   !> rejected evaluation before a Newton failure before NaN or Inf, as one process
   !> ranks them). A rejection, fatal or not, on another process is recorded on this
   !> one's problem too, so that the integrator's later questions get the same answers.
   subroutine agree_on_outcome(problem, stat)
      !> The problem (its `reduce`, its rejection flags)
      class(ode_problem), intent(inout) :: problem
      !> This process's outcome on entry, the agreed one on exit (its code only when
      !> another process's outcome wins)
      type(status_type), intent(inout) :: stat
      real(dp) :: values(2)
      logical :: fatal
      if (.not. problem%whole_state_here()) then
         fatal = problem%evaluation_fatal()
         values(1) = real(stat%code, dp)
         values(2) = merge(1.0_dp, 0.0_dp, fatal)
         call problem%reduce(reduce_max, values)
         ! codes are small integers, exact in double precision
         if (int(values(1)) /= stat%code) call set_code(stat, int(values(1)))
         if (values(2) > 0.0_dp .and. .not. fatal) call problem%reject_evaluation(fatal=.true.)
      end if
      ! (after a fatal rejection just recorded, evaluation_rejected is true)
      if (stat%code == status_evaluation_failed .and. .not. problem%evaluation_rejected()) then
         call problem%reject_evaluation()
      end if
   end subroutine agree_on_outcome

   !> Whether v is finite on every process (no NaN or Inf component in any part).
   logical function finite_everywhere(problem, v)
      !> The problem (its `reduce`)
      class(ode_problem), intent(inout) :: problem
      !> This process's part
      real(dp), intent(in) :: v(:)
      real(dp) :: values(1)
      values(1) = real(count(.not. ieee_is_finite(v)), dp)
      if (.not. problem%whole_state_here()) call problem%reduce(reduce_sum, values)
      finite_everywhere = .not. values(1) > 0.0_dp
   end function finite_everywhere

end module taylorode_integrate_reduction
