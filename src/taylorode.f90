!> taylorode: one-step Taylor schemes for stiff ODEs U' = f(t, U) + g(t, U),
!> f non-stiff (explicit), g stiff (implicit).
!>
!> A tour:
!>
!>     use taylorode
!>     type(van_der_pol_type) :: problem
!>     class(scheme_type), allocatable :: scheme
!>     type(status_type) :: stat
!>     real(dp) :: u(2)
!>     problem = new_van_der_pol(mu=1000.0_dp)
!>     u = van_der_pol_initial_state(vdp_ic_prepared)
!>     call new_scheme("i-t-2", scheme, stat)
!>     call integrate_fixed(problem, scheme, 0.0_dp, 1.0_dp, 1000, u, stat)
!>     if (.not. stat%ok()) print *, stat%message
!>
!> Own problems extend `ode_problem` (f, g, jac_f, jac_g) or `ode_problem_fd`
!> (f and g only; Jacobians by finite differences).
module taylorode
   use taylorode_kinds, only: dp, i8
   use taylorode_status, only: status_type, status_name, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_singular_matrix, status_newton_diverged, &
      status_newton_not_converged, status_step_underflow, status_max_steps, status_unknown_scheme, &
      status_repeated_failures
   use taylorode_problem, only: ode_problem, ode_problem_fd
   use taylorode_scheme, only: scheme_type, counters_type
   use taylorode_schemes, only: new_scheme, scheme_names, scheme_count
   use taylorode_fixed_step, only: integrate_fixed
   use taylorode_van_der_pol, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, &
      vdp_split_paper, vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared
   use taylorode_linear_test, only: linear_test_type, stability_function
   implicit none
   private

   public :: dp, i8
   public :: status_type, status_name, status_ok, status_invalid_argument, status_size_mismatch, &
      status_nonfinite, status_singular_matrix, status_newton_diverged, status_newton_not_converged, &
      status_step_underflow, status_max_steps, status_unknown_scheme, status_repeated_failures
   public :: ode_problem, ode_problem_fd
   public :: scheme_type, counters_type, new_scheme, scheme_names, scheme_count
   public :: integrate_fixed
   public :: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, vdp_split_paper, &
      vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared
   public :: linear_test_type, stability_function

end module taylorode
