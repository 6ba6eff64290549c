!> The base layer: number formatting for messages and reports.
module test_base
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use taylorode, only: dp, i8
   use taylorode_base_strings, only: format_count, format_real, format_fixed
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_positive_inf
   implicit none
   private

   public :: collect_base

contains

   !> Collect all exported unit tests
   subroutine collect_base(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("number-formats", test_formats) &
         ]
   end subroutine collect_base

   subroutine test_formats(error)
      type(error_type), allocatable, intent(out) :: error
      call check(error, format_count(125748_i8), "125,748")
      if (allocated(error)) return
      call check(error, format_count(999_i8), "999")
      if (allocated(error)) return
      call check(error, format_count(-2000000_i8), "-2,000,000")
      if (allocated(error)) return
      call check(error, format_real(5.2123e-5_dp, 3), "5.21E-05")
      if (allocated(error)) return
      call check(error, format_fixed(0.0881_dp, 3), "0.088")
      if (allocated(error)) return
      call check(error, format_real(1.0e4_dp, 1), "1E+04")
      if (allocated(error)) return
      call check(error, format_fixed(626.6_dp, 0), "627")
      if (allocated(error)) return
      ! exponents of three digits and non-finite numbers (no asterisks)
      call check(error, format_real(1.2345e-120_dp, 3), "1.23E-120")
      if (allocated(error)) return
      call check(error, format_real(tiny(1.0_dp), 2), "2.2E-308")
      if (allocated(error)) return
      call check(error, format_real(-huge(1.0_dp), 2), "-1.8E+308")
      if (allocated(error)) return
      call check(error, format_real(ieee_value(1.0_dp, ieee_positive_inf), 2), "inf")
   end subroutine test_formats

end module test_base
