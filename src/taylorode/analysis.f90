!> Analyses a user can run on their own problems and schemes: the stability
!> function of a scheme against one real step and its S1 region, observed orders
!> of convergence, work-precision sweeps (timed runs against a reference), the
!> accuracy a scheme achieves against the tolerance on the test set, and what threads
!> buy an ensemble.
module taylorode_analysis
   use taylorode_analysis_stability, only: stability_function, step_stability, s1_supremum, s1_contains, &
      s1_axis_crossings
   use taylorode_analysis_order, only: observed_orders
   use taylorode_analysis_work_precision, only: timed_run_type, timed_run, reference_run, reference_tolerance, &
      median, work_precision_config_type, work_precision_point_type, work_precision, tolerance_scale, &
      progress_interface
   use taylorode_analysis_ensemble_timing, only: ensemble_timing_type, time_ensemble
   use taylorode_analysis_accuracy, only: accuracy_case_type, accuracy_point_type, new_accuracy_case, &
      accuracy_reference, accuracy_run, accuracy_case_names
   implicit none
   private

   public :: stability_function, step_stability, s1_supremum, s1_contains, s1_axis_crossings
   public :: observed_orders
   public :: timed_run_type, timed_run, reference_run, reference_tolerance, median
   public :: work_precision_config_type, work_precision_point_type, work_precision, tolerance_scale, &
      progress_interface
   public :: ensemble_timing_type, time_ensemble
   public :: accuracy_case_type, accuracy_point_type, new_accuracy_case, accuracy_reference, accuracy_run, &
      accuracy_case_names

end module taylorode_analysis
