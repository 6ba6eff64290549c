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
      status_newton_not_converged, status_step_underflow, status_max_steps, status_unknown_scheme
   use taylorode_problem, only: ode_problem, ode_problem_fd, test_problem_type
   use taylorode_scheme, only: scheme_type, counters_type
   use taylorode_schemes, only: new_scheme, scheme_names, scheme_count
   use taylorode_fixed_step, only: integrate_fixed
   use taylorode_van_der_pol, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, &
      vdp_split_paper, vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared
   use taylorode_linear_test, only: linear_test_type, new_linear_test, stability_function
   use taylorode_test_set, only: robertson_type, new_robertson, hires_type, new_hires, orego_type, &
      new_orego, e5_type, new_e5, brusselator_type, new_brusselator, prothero_robinson_type, &
      new_prothero_robinson, new_test_problem, test_problem_names, test_problem_count
   use taylorode_controller, only: controller_i, controller_pi, controller_pid, controller_name
   use taylorode_options, only: integrator_options_type, paper_options, norm_max, norm_rms, &
      advance_scheme, advance_high, advance_low
   use taylorode_history, only: step_history_type, write_history_csv, attempt_accepted, &
      attempt_rejected_error, attempt_failed_newton, attempt_failed_nonfinite, attempt_name
   use taylorode_integrator, only: integrate, integration_stats_type
   implicit none
   private

   public :: dp, i8
   public :: status_type, status_name, status_ok, status_invalid_argument, status_size_mismatch, &
      status_nonfinite, status_singular_matrix, status_newton_diverged, status_newton_not_converged, &
      status_step_underflow, status_max_steps, status_unknown_scheme
   public :: ode_problem, ode_problem_fd, test_problem_type
   public :: scheme_type, counters_type, new_scheme, scheme_names, scheme_count
   public :: integrate_fixed
   public :: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, vdp_split_paper, &
      vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared
   public :: linear_test_type, new_linear_test, stability_function
   public :: robertson_type, new_robertson, hires_type, new_hires, orego_type, new_orego, e5_type, &
      new_e5, brusselator_type, new_brusselator, prothero_robinson_type, new_prothero_robinson, &
      new_test_problem, test_problem_names, test_problem_count
   public :: integrate, integration_stats_type, integrator_options_type, paper_options
   public :: controller_i, controller_pi, controller_pid, controller_name
   public :: norm_max, norm_rms, advance_scheme, advance_high, advance_low
   public :: step_history_type, write_history_csv, attempt_accepted, attempt_rejected_error, &
      attempt_failed_newton, attempt_failed_nonfinite, attempt_name

end module taylorode
