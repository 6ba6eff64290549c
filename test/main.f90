!> Runs every test suite but the accuracy suite (hundreds of integrations: `make test`
!> runs it in the release build, `fpm test --profile release -- accuracy`), one suite
!> (`fpm test -- <suite>`) or one test (`fpm test -- <suite> <test>`), and closes with
!> the line "N passed, N failed".
program tester
   use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
   use testdrive, only: run_selected, new_testsuite, testsuite_type, select_suite, unittest_type, get_argument
   use test_accuracy, only: collect_accuracy
   use test_app, only: collect_app
   use test_base, only: collect_base
   use test_features, only: collect_features
   use test_integrator, only: collect_integrator
   use test_memory, only: collect_memory
   use test_interfaces, only: collect_interfaces
   use test_legacy, only: collect_legacy
   use test_problems, only: collect_problems
   use test_reference, only: collect_reference
   use test_robustness, only: collect_robustness
   use test_scale, only: collect_scale
   use test_schemes, only: collect_schemes
   implicit none

   type(testsuite_type), allocatable :: suites(:)
   character(len=:), allocatable :: suite_name, test_name
   integer :: is, passed, failed
   character(len=*), parameter :: fmt = '("#", *(1x, a))'

   suites = [ &
      new_testsuite("base", collect_base), &
      new_testsuite("problems", collect_problems), &
      new_testsuite("schemes", collect_schemes), &
      new_testsuite("integrator", collect_integrator), &
      new_testsuite("reference", collect_reference), &
      new_testsuite("features", collect_features), &
      new_testsuite("interfaces", collect_interfaces), &
      new_testsuite("legacy", collect_legacy), &
      new_testsuite("app", collect_app), &
      new_testsuite("robustness", collect_robustness), &
      new_testsuite("memory", collect_memory), &
      new_testsuite("scale", collect_scale), &
      new_testsuite("accuracy", collect_accuracy) &
      ]
   passed = 0
   failed = 0

   call get_argument(1, suite_name)
   call get_argument(2, test_name)

   if (allocated(suite_name)) then
      is = select_suite(suites, suite_name)
      if (is < 1 .or. is > size(suites)) then
         write (error_unit, fmt) "Unknown suite:", suite_name
         write (error_unit, fmt) "Available suites:"
         do is = 1, size(suites)
            write (error_unit, fmt) "-", suites(is)%name
         end do
         write (output_unit, '(i0, " passed, ", i0, " failed")') 0, 1
         stop 1, quiet=.true.
      end if
      call run_suite(suites(is), test_name)
   else
      ! the accuracy suite only when asked for: make test runs it in the release build
      do is = 1, size(suites)
         if (suites(is)%name == "accuracy") cycle
         call run_suite(suites(is))
      end do
   end if

   write (output_unit, '(i0, " passed, ", i0, " failed")') passed, failed
   if (failed > 0) stop 1, quiet=.true.

contains

   !> Run every test of a suite, or only the one called `only`, counting outcomes.
   subroutine run_suite(suite, only)
      type(testsuite_type), intent(in) :: suite
      character(len=*), intent(in), optional :: only
      type(unittest_type), allocatable :: tests(:)
      integer :: it, stat

      write (error_unit, fmt) "Testing:", suite%name
      call suite%collect(tests)
      do it = 1, size(tests)
         if (present(only)) then
            if (tests(it)%name /= only) cycle
         end if
         stat = 0
         call run_selected(suite%collect, tests(it)%name, error_unit, stat)
         if (stat == 0) then
            passed = passed + 1
         else
            failed = failed + 1
         end if
      end do
      if (present(only) .and. passed + failed == 0) then
         write (error_unit, fmt) "Unknown test:", only
         write (error_unit, fmt) "Tests of "//suite%name//":"
         do it = 1, size(tests)
            write (error_unit, fmt) "-", tests(it)%name
         end do
         failed = 1
      end if
   end subroutine run_suite

end program tester
