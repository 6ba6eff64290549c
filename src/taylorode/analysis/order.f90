!> Observed order of convergence of a scheme with fixed steps.
module taylorode_analysis_order
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, status_ok, set_status, status_invalid_argument
   use taylorode_problem_ode, only: ode_problem
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_integrate_fixed_step, only: integrate_fixed
   implicit none
   private

   public :: observed_orders

contains

   !> Errors in the max norm at t_end against `reference` with steps(k) fixed steps
   !> each, and the observed orders log(e_k / e_k+1) / log(steps(k+1) / steps(k)).
   subroutine observed_orders(problem, scheme, t0, t_end, u0, reference, steps, errors, orders, stat)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> The scheme
      class(scheme_type), intent(inout) :: scheme
      !> Interval
      real(dp), intent(in) :: t0, t_end
      !> Initial state
      real(dp), intent(in) :: u0(:)
      !> Solution at t_end, accurate far beyond the errors measured
      real(dp), intent(in) :: reference(:)
      !> Numbers of steps, ascending (at least two)
      integer, intent(in) :: steps(:)
      !> Error of each run
      real(dp), intent(out) :: errors(:)
      !> Observed order between consecutive runs (size(steps) - 1 of them)
      real(dp), intent(out) :: orders(:)
      !> Status of the first run that failed
      type(status_type), intent(out) :: stat
      real(dp) :: u(size(u0))
      integer :: k

      if (size(steps) < 2 .or. size(errors) /= size(steps) .or. size(orders) /= size(steps) - 1 .or. &
         size(reference) /= size(u0)) then
         call set_status(stat, status_invalid_argument, "observed_orders: need at least two step counts "// &
            "and matching sizes of errors, orders and reference")
         return
      end if
      do k = 1, size(steps)
         u = u0
         call integrate_fixed(problem, scheme, t0, t_end, steps(k), u, stat)
         if (stat%code /= status_ok) return
         errors(k) = maxval(abs(u - reference))
      end do
      do k = 1, size(steps) - 1
         orders(k) = log(errors(k)/errors(k + 1))/log(real(steps(k + 1), dp)/real(steps(k), dp))
      end do
   end subroutine observed_orders

end module taylorode_analysis_order
