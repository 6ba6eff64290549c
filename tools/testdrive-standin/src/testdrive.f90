!> taylorode's stand-in for the `testdrive` module of fortran-lang/test-drive v0.5.0.
!>
!> Written from scratch by the taylorode project from test-drive's documented
!> public API, so that taylorode's test suites compile and run unchanged when
!> the real test-drive repository cannot be reached.  It contains no test-drive
!> source.  Tests always run serially here; the `parallel` option is accepted
!> and ignored.
module testdrive
   use, intrinsic :: ieee_arithmetic, only : ieee_is_nan
   implicit none
   private

   public :: error_type, unittest_type, testsuite_type
   public :: new_unittest, new_testsuite
   public :: run_testsuite, run_selected, select_test, select_suite
   public :: check, test_failed, skip_test, to_string
   public :: test_interface, collect_interface

   integer, parameter :: sp = selected_real_kind(6)
   integer, parameter :: dp = selected_real_kind(15)
   integer, parameter :: i1 = selected_int_kind(2)
   integer, parameter :: i2 = selected_int_kind(4)
   integer, parameter :: i4 = selected_int_kind(9)
   integer, parameter :: i8 = selected_int_kind(18)

   !> Status codes stored in error_type%stat
   integer, parameter :: success = 0, fatal = 1, skipped = 77

   !> Line feed used to separate the lines of an error message
   character(len=*), parameter :: nl = new_line('a')

   !> Error raised by a test; a test passed if its error is left unallocated
   type :: error_type
      !> Status: 0 success, 1 failure, 77 skipped
      integer :: stat = success
      !> Description of the failure (lines separated by new_line('a'))
      character(len=:), allocatable :: message
   end type error_type

   abstract interface
      !> Interface of a single unit test
      subroutine test_interface(error)
         import :: error_type
         !> Allocated by the test if it fails or is skipped
         type(error_type), allocatable, intent(out) :: error
      end subroutine test_interface
   end interface

   !> A named unit test
   type :: unittest_type
      !> Name of the test
      character(len=:), allocatable :: name
      !> Procedure running the test
      procedure(test_interface), pointer, nopass :: test => null()
      !> Whether the test is expected to fail
      logical :: should_fail = .false.
   end type unittest_type

   abstract interface
      !> Interface of a procedure collecting the unit tests of a suite
      subroutine collect_interface(testsuite)
         import :: unittest_type
         !> The collected unit tests
         type(unittest_type), allocatable, intent(out) :: testsuite(:)
      end subroutine collect_interface
   end interface

   !> A named collection of unit tests
   type :: testsuite_type
      !> Name of the suite
      character(len=:), allocatable :: name
      !> Procedure collecting the tests of the suite
      procedure(collect_interface), pointer, nopass :: collect => null()
   end type testsuite_type

   !> Check a condition, a value against an expected value, or a real/complex
   !> value for NaN; allocates `error` on failure
   interface check
      module procedure :: check_stat
      module procedure :: check_expression
      module procedure :: check_bool
      module procedure :: check_int_i1
      module procedure :: check_int_i2
      module procedure :: check_int_i4
      module procedure :: check_int_i8
      module procedure :: check_string
      module procedure :: check_float_sp
      module procedure :: check_float_dp
      module procedure :: check_float_exceptional_sp
      module procedure :: check_float_exceptional_dp
      module procedure :: check_complex_sp
      module procedure :: check_complex_dp
      module procedure :: check_complex_exceptional_sp
      module procedure :: check_complex_exceptional_dp
   end interface check

   !> Convert an integer or real value to a character string
   interface to_string
      module procedure :: integer_i1_to_string
      module procedure :: integer_i2_to_string
      module procedure :: integer_i4_to_string
      module procedure :: integer_i8_to_string
      module procedure :: real_sp_to_string
      module procedure :: real_dp_to_string
   end interface to_string

contains

   ! ------------------------------------------------------------------
   ! Construction and selection
   ! ------------------------------------------------------------------

   !> Create a new unit test
   function new_unittest(name, test, should_fail) result(self)
      !> Name of the test
      character(len=*), intent(in) :: name
      !> Procedure running the test
      procedure(test_interface) :: test
      !> Whether the test is expected to fail (default .false.)
      logical, intent(in), optional :: should_fail
      type(unittest_type) :: self

      self%name = name
      self%test => test
      if (present(should_fail)) self%should_fail = should_fail
   end function new_unittest

   !> Create a new test suite
   function new_testsuite(name, collect) result(self)
      !> Name of the suite
      character(len=*), intent(in) :: name
      !> Procedure collecting the tests of the suite
      procedure(collect_interface) :: collect
      type(testsuite_type) :: self

      self%name = name
      self%collect => collect
   end function new_testsuite

   !> Index of the unit test called `name`, 0 if there is none
   pure function select_test(tests, name) result(pos)
      !> Available unit tests
      type(unittest_type), intent(in) :: tests(:)
      !> Name of the wanted test
      character(len=*), intent(in) :: name
      integer :: pos
      integer :: it

      pos = 0
      do it = 1, size(tests)
         if (.not. allocated(tests(it)%name)) cycle
         if (tests(it)%name == name) then
            pos = it
            return
         end if
      end do
   end function select_test

   !> Index of the test suite called `name`, 0 if there is none
   pure function select_suite(suites, name) result(pos)
      !> Available test suites
      type(testsuite_type), intent(in) :: suites(:)
      !> Name of the wanted suite
      character(len=*), intent(in) :: name
      integer :: pos
      integer :: it

      pos = 0
      do it = 1, size(suites)
         if (.not. allocated(suites(it)%name)) cycle
         if (suites(it)%name == name) then
            pos = it
            return
         end if
      end do
   end function select_suite

   ! ------------------------------------------------------------------
   ! Running tests
   ! ------------------------------------------------------------------

   !> Run all unit tests of a suite, adding the number of failures to `stat`
   subroutine run_testsuite(collect, unit, stat, parallel)
      !> Procedure collecting the tests of the suite
      procedure(collect_interface) :: collect
      !> Unit for the progress report
      integer, intent(in) :: unit
      !> Incremented by the number of failed tests
      integer, intent(inout) :: stat
      !> Accepted for compatibility; tests always run serially here
      logical, intent(in), optional :: parallel
      type(unittest_type), allocatable :: testsuite(:)
      integer :: it

      if (present(parallel)) continue
      ! a defined descriptor keeps gfortran -fcheck from warning; collect
      ! deallocates it on entry (intent(out))
      allocate(testsuite(0))
      call collect(testsuite)
      if (.not. allocated(testsuite)) return
      do it = 1, size(testsuite)
         call write_start(testsuite(it), it, size(testsuite), unit)
         call run_unittest(testsuite(it), unit, stat)
      end do
   end subroutine run_testsuite

   !> Run only the unit test called `name`; if there is none, list the
   !> available tests and set `stat` to -huge(stat)
   subroutine run_selected(collect, name, unit, stat)
      !> Procedure collecting the tests of the suite
      procedure(collect_interface) :: collect
      !> Name of the test to run
      character(len=*), intent(in) :: name
      !> Unit for the progress report
      integer, intent(in) :: unit
      !> Incremented by one if the test fails
      integer, intent(inout) :: stat
      type(unittest_type), allocatable :: testsuite(:)
      integer :: it, pos

      ! a defined descriptor keeps gfortran -fcheck from warning; collect
      ! deallocates it on entry (intent(out))
      allocate(testsuite(0))
      call collect(testsuite)
      if (.not. allocated(testsuite)) allocate(testsuite(0))
      pos = select_test(testsuite, name)
      if (pos > 0 .and. pos <= size(testsuite)) then
         call write_start(testsuite(pos), 1, 1, unit)
         call run_unittest(testsuite(pos), unit, stat)
      else
         write(unit, '(a)') "Available tests:"
         do it = 1, size(testsuite)
            if (allocated(testsuite(it)%name)) &
               write(unit, '(a)') "- " // testsuite(it)%name
         end do
         stat = -huge(stat)
      end if
   end subroutine run_selected

   !> Report that a test starts
   subroutine write_start(test, it, n, unit)
      type(unittest_type), intent(in) :: test
      integer, intent(in) :: it, n, unit

      write(unit, '(a)') "  Starting " // test_name(test) // " ... (" &
         // to_string(it) // "/" // to_string(n) // ")"
   end subroutine write_start

   !> Run one unit test and report its outcome
   subroutine run_unittest(test, unit, stat)
      type(unittest_type), intent(in) :: test
      integer, intent(in) :: unit
      integer, intent(inout) :: stat
      type(error_type), allocatable :: error
      character(len=:), allocatable :: label

      if (associated(test%test)) then
         call test%test(error)
      else
         call test_failed(error, "No test procedure associated")
      end if

      if (allocated(error)) then
         if (error%stat == skipped) then
            label = "[SKIPPED]"
         else if (test%should_fail) then
            label = "[EXPECTED FAIL]"
         else
            label = "[FAILED]"
            stat = stat + 1
         end if
      else
         if (test%should_fail) then
            label = "[UNEXPECTED PASS]"
            stat = stat + 1
         else
            label = "[PASSED]"
         end if
      end if

      write(unit, '(a)') "       ... " // test_name(test) // " " // label
      if (allocated(error)) then
         if (error%stat == skipped .or. .not. test%should_fail) &
            call write_message(error, unit)
      end if
   end subroutine run_unittest

   !> Name of a test, or a placeholder if it has none
   pure function test_name(test) result(name)
      type(unittest_type), intent(in) :: test
      character(len=:), allocatable :: name

      if (allocated(test%name)) then
         name = test%name
      else
         name = "<unnamed>"
      end if
   end function test_name

   !> Write the lines of an error message, indented
   subroutine write_message(error, unit)
      type(error_type), intent(in) :: error
      integer, intent(in) :: unit
      integer :: first, last

      if (.not. allocated(error%message)) return
      first = 1
      do
         last = index(error%message(first:), nl)
         if (last == 0) then
            write(unit, '(a)') "  " // error%message(first:)
            exit
         end if
         write(unit, '(a)') "  " // error%message(first:first+last-2)
         first = first + last
      end do
   end subroutine write_message

   ! ------------------------------------------------------------------
   ! Failing and skipping
   ! ------------------------------------------------------------------

   !> Mark the current test as failed
   pure subroutine test_failed(error, message, more)
      !> Allocated with stat = 1
      type(error_type), allocatable, intent(out) :: error
      !> Description of the failure
      character(len=*), intent(in) :: message
      !> Additional information appended on a new line
      character(len=*), intent(in), optional :: more

      allocate(error)
      error%stat = fatal
      error%message = message
      if (present(more)) error%message = error%message // nl // more
   end subroutine test_failed

   !> Mark the current test as skipped
   pure subroutine skip_test(error, message, more)
      !> Allocated with stat = 77
      type(error_type), allocatable, intent(out) :: error
      !> Reason for skipping
      character(len=*), intent(in) :: message
      !> Additional information appended on a new line
      character(len=*), intent(in), optional :: more

      allocate(error)
      error%stat = skipped
      error%message = message
      if (present(more)) error%message = error%message // nl // more
   end subroutine skip_test

   !> Fail with the user message (or a default) followed by details and `more`
   pure subroutine fail(error, default, message, detail, more)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), intent(in) :: default
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in) :: detail
      character(len=*), intent(in), optional :: more
      character(len=:), allocatable :: text

      if (present(message)) then
         text = message
      else
         text = default
      end if
      if (len(detail) > 0) text = text // nl // detail
      call test_failed(error, text, more)
   end subroutine fail

   ! ------------------------------------------------------------------
   ! Checks
   ! ------------------------------------------------------------------

   !> Check that an exit status is zero
   pure subroutine check_stat(error, stat, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer, intent(in) :: stat
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (stat /= success) then
         call fail(error, "Non-zero exit code encountered", message, &
            "(got exit code " // to_string(stat) // ")", more)
      end if
   end subroutine check_stat

   !> Check that a logical expression is true
   pure subroutine check_expression(error, expression, message, more)
      type(error_type), allocatable, intent(out) :: error
      logical, intent(in) :: expression
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (.not. expression) then
         call fail(error, "Condition not fullfilled", message, "", more)
      end if
   end subroutine check_expression

   !> Check a logical value against its expected value
   pure subroutine check_bool(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      logical, intent(in) :: actual
      logical, intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual .neqv. expected) then
         call fail(error, "Logical value missmatch", message, &
            "(expected " // merge("T", "F", expected) // " but got " &
            // merge("T", "F", actual) // ")", more)
      end if
   end subroutine check_bool

   !> Check an integer(i1) value against its expected value
   pure subroutine check_int_i1(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i1), intent(in) :: actual
      integer(i1), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) then
         call fail(error, "Integer value missmatch", message, "(expected " &
            // to_string(expected) // " but got " // to_string(actual) // ")", more)
      end if
   end subroutine check_int_i1

   !> Check an integer(i2) value against its expected value
   pure subroutine check_int_i2(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i2), intent(in) :: actual
      integer(i2), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) then
         call fail(error, "Integer value missmatch", message, "(expected " &
            // to_string(expected) // " but got " // to_string(actual) // ")", more)
      end if
   end subroutine check_int_i2

   !> Check an integer(i4) value against its expected value
   pure subroutine check_int_i4(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i4), intent(in) :: actual
      integer(i4), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) then
         call fail(error, "Integer value missmatch", message, "(expected " &
            // to_string(expected) // " but got " // to_string(actual) // ")", more)
      end if
   end subroutine check_int_i4

   !> Check an integer(i8) value against its expected value
   pure subroutine check_int_i8(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i8), intent(in) :: actual
      integer(i8), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) then
         call fail(error, "Integer value missmatch", message, "(expected " &
            // to_string(expected) // " but got " // to_string(actual) // ")", more)
      end if
   end subroutine check_int_i8

   !> Check a character string against its expected value
   pure subroutine check_string(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), intent(in) :: actual
      character(len=*), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) then
         call fail(error, "Character string missmatch", message, &
            "(expected '" // expected // "' but got '" // actual // "')", more)
      end if
   end subroutine check_string

   !> Check a real(sp) value against its expected value within a threshold
   !> (absolute, or relative to |expected| if `rel` is true); NaN fails
   pure subroutine check_float_sp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      real(sp), intent(in) :: actual
      real(sp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      !> Threshold (default epsilon(expected))
      real(sp), intent(in), optional :: thr
      !> Compare relative to |expected| (default .false.)
      logical, intent(in), optional :: rel
      real(sp) :: diff, tol
      logical :: relative

      tol = epsilon(expected)
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) tol = tol * abs(expected)
      if (.not. (diff <= tol)) then
         call fail(error, "Floating point value missmatch", message, "(expected " &
            // to_string(expected) // " but got " // to_string(actual) &
            // ", difference " // to_string(diff) // ")", more)
      end if
   end subroutine check_float_sp

   !> Check a real(dp) value against its expected value within a threshold
   !> (absolute, or relative to |expected| if `rel` is true); NaN fails
   pure subroutine check_float_dp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      real(dp), intent(in) :: actual
      real(dp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      !> Threshold (default epsilon(expected))
      real(dp), intent(in), optional :: thr
      !> Compare relative to |expected| (default .false.)
      logical, intent(in), optional :: rel
      real(dp) :: diff, tol
      logical :: relative

      tol = epsilon(expected)
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) tol = tol * abs(expected)
      if (.not. (diff <= tol)) then
         call fail(error, "Floating point value missmatch", message, "(expected " &
            // to_string(expected) // " but got " // to_string(actual) &
            // ", difference " // to_string(diff) // ")", more)
      end if
   end subroutine check_float_dp

   !> Check that a real(sp) value is not NaN
   pure subroutine check_float_exceptional_sp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      real(sp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (ieee_is_nan(actual)) then
         call fail(error, "Exceptional value 'not a number' found", message, "", more)
      end if
   end subroutine check_float_exceptional_sp

   !> Check that a real(dp) value is not NaN
   pure subroutine check_float_exceptional_dp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      real(dp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (ieee_is_nan(actual)) then
         call fail(error, "Exceptional value 'not a number' found", message, "", more)
      end if
   end subroutine check_float_exceptional_dp

   !> Check a complex(sp) value against its expected value within a threshold
   !> on the modulus of the difference; NaN fails
   pure subroutine check_complex_sp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      complex(sp), intent(in) :: actual
      complex(sp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      !> Threshold (default epsilon(real part of expected))
      real(sp), intent(in), optional :: thr
      !> Compare relative to |expected| (default .false.)
      logical, intent(in), optional :: rel
      real(sp) :: diff, tol
      logical :: relative

      tol = epsilon(real(expected))
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) tol = tol * abs(expected)
      if (.not. (diff <= tol)) then
         call fail(error, "Floating point value missmatch", message, "(expected " &
            // complex_sp_to_string(expected) // " but got " &
            // complex_sp_to_string(actual) // ", difference " &
            // to_string(diff) // ")", more)
      end if
   end subroutine check_complex_sp

   !> Check a complex(dp) value against its expected value within a threshold
   !> on the modulus of the difference; NaN fails
   pure subroutine check_complex_dp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      complex(dp), intent(in) :: actual
      complex(dp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      !> Threshold (default epsilon(real part of expected))
      real(dp), intent(in), optional :: thr
      !> Compare relative to |expected| (default .false.)
      logical, intent(in), optional :: rel
      real(dp) :: diff, tol
      logical :: relative

      tol = epsilon(real(expected))
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) tol = tol * abs(expected)
      if (.not. (diff <= tol)) then
         call fail(error, "Floating point value missmatch", message, "(expected " &
            // complex_dp_to_string(expected) // " but got " &
            // complex_dp_to_string(actual) // ", difference " &
            // to_string(diff) // ")", more)
      end if
   end subroutine check_complex_dp

   !> Check that neither part of a complex(sp) value is NaN
   pure subroutine check_complex_exceptional_sp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      complex(sp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (ieee_is_nan(real(actual)) .or. ieee_is_nan(aimag(actual))) then
         call fail(error, "Exceptional value 'not a number' found", message, "", more)
      end if
   end subroutine check_complex_exceptional_sp

   !> Check that neither part of a complex(dp) value is NaN
   pure subroutine check_complex_exceptional_dp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      complex(dp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (ieee_is_nan(real(actual)) .or. ieee_is_nan(aimag(actual))) then
         call fail(error, "Exceptional value 'not a number' found", message, "", more)
      end if
   end subroutine check_complex_exceptional_dp

   ! ------------------------------------------------------------------
   ! String conversion
   ! ------------------------------------------------------------------

   !> Convert an integer(i1) to a string
   pure function integer_i1_to_string(val) result(string)
      integer(i1), intent(in) :: val
      character(len=:), allocatable :: string
      character(len=8) :: buffer

      write(buffer, '(i0)') val
      string = trim(buffer)
   end function integer_i1_to_string

   !> Convert an integer(i2) to a string
   pure function integer_i2_to_string(val) result(string)
      integer(i2), intent(in) :: val
      character(len=:), allocatable :: string
      character(len=8) :: buffer

      write(buffer, '(i0)') val
      string = trim(buffer)
   end function integer_i2_to_string

   !> Convert an integer(i4) to a string
   pure function integer_i4_to_string(val) result(string)
      integer(i4), intent(in) :: val
      character(len=:), allocatable :: string
      character(len=16) :: buffer

      write(buffer, '(i0)') val
      string = trim(buffer)
   end function integer_i4_to_string

   !> Convert an integer(i8) to a string
   pure function integer_i8_to_string(val) result(string)
      integer(i8), intent(in) :: val
      character(len=:), allocatable :: string
      character(len=24) :: buffer

      write(buffer, '(i0)') val
      string = trim(buffer)
   end function integer_i8_to_string

   !> Convert a real(sp) to a string, with an optional edit format such as '(es12.5)'
   pure function real_sp_to_string(val, format) result(string)
      real(sp), intent(in) :: val
      !> Format specification, default '(g0)'
      character(len=*), intent(in), optional :: format
      character(len=:), allocatable :: string
      character(len=128) :: buffer
      integer :: stat

      if (present(format)) then
         write(buffer, format, iostat=stat) val
      else
         write(buffer, '(g0)', iostat=stat) val
      end if
      if (stat == 0) then
         string = trim(adjustl(buffer))
      else
         string = "*"
      end if
   end function real_sp_to_string

   !> Convert a real(dp) to a string, with an optional edit format such as '(es24.16)'
   pure function real_dp_to_string(val, format) result(string)
      real(dp), intent(in) :: val
      !> Format specification, default '(g0)'
      character(len=*), intent(in), optional :: format
      character(len=:), allocatable :: string
      character(len=128) :: buffer
      integer :: stat

      if (present(format)) then
         write(buffer, format, iostat=stat) val
      else
         write(buffer, '(g0)', iostat=stat) val
      end if
      if (stat == 0) then
         string = trim(adjustl(buffer))
      else
         string = "*"
      end if
   end function real_dp_to_string

   !> Convert a complex(sp) to a string "(re, im)"
   pure function complex_sp_to_string(val) result(string)
      complex(sp), intent(in) :: val
      character(len=:), allocatable :: string

      string = "(" // to_string(real(val)) // ", " // to_string(aimag(val)) // ")"
   end function complex_sp_to_string

   !> Convert a complex(dp) to a string "(re, im)"
   pure function complex_dp_to_string(val) result(string)
      complex(dp), intent(in) :: val
      character(len=:), allocatable :: string

      string = "(" // to_string(real(val)) // ", " // to_string(aimag(val)) // ")"
   end function complex_dp_to_string

end module testdrive
