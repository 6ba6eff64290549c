!> The problems of the test set by name, for tools that take a problem name
!> (the app's sweep, the analyses).
module taylorode_testset_registry
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument
   use taylorode_testset_test_problem, only: test_problem_type
   use taylorode_testset_van_der_pol, only: new_van_der_pol, vdp_split_paper, vdp_split_stiff
   use taylorode_testset_linear_test, only: new_linear_test
   use taylorode_testset_robertson, only: new_robertson
   use taylorode_testset_hires, only: new_hires
   use taylorode_testset_orego, only: new_orego
   use taylorode_testset_e5, only: new_e5
   use taylorode_testset_brusselator, only: new_brusselator
   use taylorode_testset_prothero_robinson, only: new_prothero_robinson
   use taylorode_testset_pollution, only: new_pollution
   use taylorode_testset_medical_akzo, only: new_medical_akzo
   use taylorode_testset_transistor_amplifier, only: new_transistor_amplifier
   implicit none
   private

   public :: new_test_problem, test_problem_names, test_problem_count

   !> Names understood by new_test_problem
   character(len=*), parameter :: test_problem_names(*) = [character(len=17) :: &
      "vdp", "vdp-stiff", "robertson", "hires", "orego", "e5", "brusselator", "prothero-robinson", "linear", &
      "pollution", "medakzo", "transamp"]
   !> Number of problems the factory knows
   integer, parameter :: test_problem_count = size(test_problem_names)

contains

   !> Create any problem of the set by name (see test_problem_names) with its
   !> standard settings. An unknown name leaves `problem` unallocated and lists the valid ones.
   subroutine new_test_problem(name, problem, stat)
      !> Name as users type it
      character(len=*), intent(in) :: name
      !> The new problem
      class(test_problem_type), allocatable, intent(out) :: problem
      !> status_invalid_argument for an unknown name
      type(status_type), intent(out) :: stat
      character(len=256) :: valid
      integer :: i

      select case (trim(adjustl(name)))
      case ("vdp")
         allocate (problem, source=new_van_der_pol(1000.0_dp, vdp_split_paper))
      case ("vdp-stiff")
         allocate (problem, source=new_van_der_pol(1000.0_dp, vdp_split_stiff))
      case ("robertson")
         allocate (problem, source=new_robertson())
      case ("hires")
         allocate (problem, source=new_hires())
      case ("orego")
         allocate (problem, source=new_orego())
      case ("e5")
         allocate (problem, source=new_e5())
      case ("brusselator")
         allocate (problem, source=new_brusselator())
      case ("prothero-robinson")
         allocate (problem, source=new_prothero_robinson())
      case ("linear")
         allocate (problem, source=new_linear_test((-1.0_dp, 2.0_dp), (-10.0_dp, 0.0_dp)))
      case ("pollution")
         allocate (problem, source=new_pollution())
      case ("medakzo")
         allocate (problem, source=new_medical_akzo())
      case ("transamp")
         allocate (problem, source=new_transistor_amplifier())
      case default
         valid = trim(test_problem_names(1))
         do i = 2, test_problem_count
            valid = trim(valid)//", "//test_problem_names(i)
         end do
         call set_status(stat, status_invalid_argument, 'unknown problem "'//trim(name)// &
            '"; valid names: '//trim(valid))
         return
      end select
      stat%code = status_ok
   end subroutine new_test_problem

end module taylorode_testset_registry
