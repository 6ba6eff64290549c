!> Fixed-step integration, for convergence studies and for users who choose h themselves.
module taylorode_integrate_fixed_step
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, set_code, status_description, status_ok, &
      status_invalid_argument, status_nonfinite, status_evaluation_failed, status_out_of_memory
   use taylorode_base_strings, only: fixed_length_real
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_schemes_scheme, only: scheme_type, default_newton_settings
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: integrate_fixed

contains

   !> Integrate from t0 to t_end with n_steps equal steps of the scheme.
   !> On return u holds the state at t_end, or on failure the last good state,
   !> which t_reached (when present) gives the time of.
   subroutine integrate_fixed(problem, scheme, t0, t_end, n_steps, u, stat, t_reached)
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> The scheme (see new_scheme)
      class(scheme_type), intent(inout) :: scheme
      !> Initial time
      real(dp), intent(in) :: t0
      !> Final time, > t0
      real(dp), intent(in) :: t_end
      !> Number of steps, >= 1
      integer, intent(in) :: n_steps
      !> Initial state on entry, final (or last good) state on exit
      real(dp), intent(inout) :: u(:)
      !> Status of the integration
      type(status_type), intent(out) :: stat
      !> Time of the returned state
      real(dp), intent(out), optional :: t_reached

      real(dp) :: h, t
      real(dp), allocatable :: u_new(:)
      type(newton_settings_type) :: newton
      integer :: i
      integer(i8) :: step
      character(len=160) :: where

      t = t0
      if (present(t_reached)) t_reached = t0
      if (n_steps < 1) then
         call set_status(stat, status_invalid_argument, "integrate_fixed: n_steps must be at least 1")
         return
      end if
      if (.not. (ieee_is_finite(t0) .and. ieee_is_finite(t_end)) .or. .not. (t_end > t0)) then
         call set_status(stat, status_invalid_argument, "integrate_fixed: need finite t0 < t_end")
         return
      end if
      h = (t_end - t0)/real(n_steps, dp)
      allocate (u_new(size(u)), stat=i)
      if (i /= 0) then
         call out_of_memory(stat, "integrate_fixed's new state", [size(u)], real_bytes)
         return
      end if
      call scheme%take_step(problem, t, h, u, u_new, stat)   ! checks the arguments and restarts the scheme
      if (stat%code /= status_ok) return
      u = u_new
      ! a 64-bit counter: to n_steps = huge(0) a default integer's increment overflows
      ! after the last step, and the loop did not end
      do step = 2_i8, int(n_steps, i8)
         t = t0 + real(step - 1_i8, dp)*h
         call default_newton_settings(u, newton, stat)
         if (stat%code /= status_ok) then
            if (present(t_reached)) t_reached = t
            return
         end if
         call problem%clear_rejection()
         call scheme%advance(problem, t, h, u, u_new, newton, stat)
         if (problem%evaluation_rejected()) then
            call set_code(stat, status_evaluation_failed)
            call problem%memory_failure(stat)
         else if (stat%code == status_ok .and. .not. all(ieee_is_finite(u_new))) then
            call set_code(stat, status_nonfinite)
         end if
         if (stat%code /= status_ok) then
            write (where, '(a, ": ", a, " (step from t = ", a, ")")') "integrate_fixed", &
               trim(status_description(stat%code)), trim(fixed_length_real(t, 17))
            if (stat%code == status_out_of_memory .and. allocated(stat%message)) then
               ! the message says what could not be allocated
               call set_status(stat, stat%code, trim(where)//": "//stat%message)
            else
               call set_status(stat, stat%code, trim(where))
            end if
            if (present(t_reached)) t_reached = t
            return
         end if
         u = u_new
      end do
      if (present(t_reached)) t_reached = t_end
   end subroutine integrate_fixed

end module taylorode_integrate_fixed_step
