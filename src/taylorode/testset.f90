!> The classic stiff test set as ready problems (each a `test_problem_type`: span,
!> initial state, recommended tolerances, published solution): Van der Pol (the
!> paper's problem, both splittings and initial conditions), the linear test
!> equation, Robertson, HIRES, OREGO, E5, the banded Brusselator, Prothero-Robinson,
!> POLLU (air pollution chemistry), the banded Medical Akzo Nobel problem and the
!> transistor amplifier (an index-1 differential-algebraic system with a mass matrix,
!> for radau5), and `new_test_problem` to create any of them by name.
module taylorode_testset
   use taylorode_testset_test_problem, only: test_problem_type
   use taylorode_testset_van_der_pol, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, &
      vdp_split_paper, vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared
   use taylorode_testset_linear_test, only: linear_test_type, new_linear_test
   use taylorode_testset_robertson, only: robertson_type, new_robertson
   use taylorode_testset_hires, only: hires_type, new_hires, hires_split_exchange_stiff, hires_split_reaction_stiff
   use taylorode_testset_orego, only: orego_type, new_orego, orego_split_fast_stiff, orego_split_bilinear_stiff
   use taylorode_testset_e5, only: e5_type, new_e5
   use taylorode_testset_brusselator, only: brusselator_type, new_brusselator
   use taylorode_testset_prothero_robinson, only: prothero_robinson_type, new_prothero_robinson
   use taylorode_testset_pollution, only: pollution_type, new_pollution
   use taylorode_testset_medical_akzo, only: medical_akzo_type, new_medical_akzo
   use taylorode_testset_transistor_amplifier, only: transistor_amplifier_type, new_transistor_amplifier
   use taylorode_testset_registry, only: new_test_problem, test_problem_names, test_problem_count
   implicit none
   private

   public :: test_problem_type
   public :: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, vdp_split_paper, &
      vdp_split_stiff, vdp_ic_prepared, vdp_ic_unprepared
   public :: linear_test_type, new_linear_test
   public :: robertson_type, new_robertson, hires_type, new_hires, orego_type, new_orego, e5_type, &
      new_e5, brusselator_type, new_brusselator, prothero_robinson_type, new_prothero_robinson
   public :: pollution_type, new_pollution, medical_akzo_type, new_medical_akzo
   public :: transistor_amplifier_type, new_transistor_amplifier
   public :: hires_split_exchange_stiff, hires_split_reaction_stiff, orego_split_fast_stiff, &
      orego_split_bilinear_stiff
   public :: new_test_problem, test_problem_names, test_problem_count

end module taylorode_testset
