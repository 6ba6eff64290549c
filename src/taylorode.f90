!> The taylorode library, one-step Taylor schemes for stiff ODEs U' = f(t, U) + g(t, U),
!> f non-stiff (explicit), g stiff (implicit).
!>
!> A tour:
!>
!>     use taylorode
!>     type(my_problem_type) :: problem          ! extends ode_problem or ode_problem_fd
!>     class(scheme_type), allocatable :: scheme
!>     type(integrator_options_type) :: options
!>     type(integration_stats_type) :: stats
!>     type(status_type) :: stat
!>     real(dp) :: u(2)
!>     u = [2.0_dp, 0.0_dp]
!>     call new_scheme("i-t-2", scheme, stat)
!>     call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
!>     if (.not. stat%ok()) print *, stat%message
!>
!> Own problems extend `ode_problem` (f, g, jac_f, jac_g) or `ode_problem_fd`
!> (f and g only; Jacobians by finite differences). The classic test problems are
!> in `taylorode_testset`, the analyses (stability, orders, work-precision) in
!> `taylorode_analysis`; neither is compiled into a program that uses only this module.
module taylorode
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, status_name, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_singular_matrix, status_newton_diverged, &
      status_newton_not_converged, status_step_underflow, status_max_steps, status_unknown_scheme, &
      status_evaluation_failed, status_output_error, status_out_of_memory, status_description
   use taylorode_base_counters, only: counters_type
   use taylorode_linalg_matrix, only: matrix_structure_type, dense_structure, band_structure
   use taylorode_problem_ode, only: ode_problem, ode_problem_fd, reduce_sum, reduce_max
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme, scheme_names, scheme_count
   use taylorode_integrate_fixed_step, only: integrate_fixed
   use taylorode_integrate_controller, only: controller_i, controller_pi, controller_pid, controller_predictive, &
      controller_auto, controller_name
   use taylorode_integrate_options, only: integrator_options_type, paper_options, norm_max, norm_rms, &
      advance_scheme, advance_high, advance_low, error_weight_type, validate_options, &
      estimate_auto, estimate_embedded, estimate_doubling, estimate_defect
   use taylorode_integrate_history, only: step_history_type, write_history_csv, attempt_accepted, &
      attempt_rejected_error, attempt_failed_newton, attempt_failed_nonfinite, attempt_failed_evaluation, &
      attempt_rejected_constraint, attempt_rejected_output, attempt_name
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrate, integrator_type
   use taylorode_integrate_ensemble, only: integrate_ensemble, ensemble_threads
   use taylorode_integrate_step, only: accepted_step_type
   use taylorode_integrate_observer, only: step_observer_type
   use taylorode_integrate_events, only: event_functions_type, event_rising, event_falling, event_any
   implicit none
   private

   public :: dp, i8
   public :: status_type, status_name, status_ok, status_invalid_argument, status_size_mismatch, &
      status_nonfinite, status_singular_matrix, status_newton_diverged, status_newton_not_converged, &
      status_step_underflow, status_max_steps, status_unknown_scheme, status_evaluation_failed, &
      status_output_error, status_out_of_memory, status_description
   public :: ode_problem, ode_problem_fd, matrix_structure_type, dense_structure, band_structure
   public :: reduce_sum, reduce_max
   public :: scheme_type, counters_type, new_scheme, scheme_names, scheme_count
   public :: integrate_fixed
   public :: integrate, integrator_type, integration_stats_type, integrator_options_type, paper_options
   public :: integrate_ensemble, ensemble_threads
   public :: accepted_step_type, step_observer_type, event_functions_type, event_rising, event_falling, event_any
   public :: controller_i, controller_pi, controller_pid, controller_predictive, controller_auto, controller_name
   public :: norm_max, norm_rms, advance_scheme, advance_high, advance_low, error_weight_type, validate_options
   public :: estimate_auto, estimate_embedded, estimate_doubling, estimate_defect
   public :: step_history_type, write_history_csv, attempt_accepted, attempt_rejected_error, &
      attempt_failed_newton, attempt_failed_nonfinite, attempt_failed_evaluation, attempt_rejected_constraint, &
      attempt_rejected_output, attempt_name

end module taylorode
