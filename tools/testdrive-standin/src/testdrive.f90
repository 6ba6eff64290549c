!> taylorode's stand-in for the `testdrive` module of fortran-lang/test-drive v0.5.0.
!>
!> Written from scratch by the taylorode project from test-drive's documented
!> public API and observed behaviour, so that taylorode's test suites compile
!> and run unchanged when the real test-drive repository cannot be reached.
!> It contains no test-drive source.
!>
!> It is meant to be as strict as the real one, so that a test which would fail
!> (or not compile) against test-drive v0.5.0 fails here as well:
!>  * error_type is finalized: an error that still holds a failure (or a skip)
!>    when it is deallocated -- typically because a test went on to call another
!>    check after a failed one without returning -- stops the whole run with
!>    "[Fatal] Uncaught error";
!>  * the checks, test_failed and skip_test are impure, as are select_test and
!>    select_suite;
!>  * to_string takes only the value (integer, real or complex), no format;
!>  * a check given a message reports only that message (and `more`);
!>  * the NaN test of the real and complex checks uses ordered comparisons,
!>    which raise IEEE invalid on a NaN (and so trap under -ffpe-trap=invalid).
!> Tests always run serially here; the `parallel` option is accepted and ignored
!> (test-drive only runs them in parallel when built with OpenMP).
module testdrive
   use, intrinsic :: iso_fortran_env, only : error_unit
   implicit none
   private

   public :: error_type, unittest_type, testsuite_type
   public :: new_unittest, new_testsuite
   public :: run_testsuite, run_selected, select_test, select_suite
   public :: check, test_failed, skip_test, to_string
   public :: get_argument, get_variable
   public :: test_interface, collect_interface

   integer, parameter :: sp = selected_real_kind(6)
   integer, parameter :: dp = selected_real_kind(15)
   integer, parameter :: i1 = selected_int_kind(2)
   integer, parameter :: i2 = selected_int_kind(4)
   integer, parameter :: i4 = selected_int_kind(9)
   integer, parameter :: i8 = selected_int_kind(18)

   !> Status codes stored in error_type%stat
   integer, parameter :: success = 0, fatal = 1, skipped = 77

   !> Separator between the lines of a failure message: a line feed and the
   !> indentation that lines up continuation lines under "  Message: "
   character(len=*), parameter :: continued = new_line('a') // "           "

   !> Error raised by a test; a test passed if its error is left unallocated
   type :: error_type
      !> Status: 0 success, 1 failure, 77 skipped
      integer :: stat = success
      !> Description of the failure
      character(len=:), allocatable :: message
   contains
      !> An error that was never handled stops the run
      final :: uncaught_error
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

   !> Check a condition, an exit status, a value against an expected value, or a
   !> real/complex value for NaN; allocates `error` on failure
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

   !> Convert an integer, real or complex value to a character string
   interface to_string
      module procedure :: integer_i1_to_string
      module procedure :: integer_i2_to_string
      module procedure :: integer_i4_to_string
      module procedure :: integer_i8_to_string
      module procedure :: real_sp_to_string
      module procedure :: real_dp_to_string
      module procedure :: complex_sp_to_string
      module procedure :: complex_dp_to_string
   end interface to_string

   !> How far a real or complex value is from the expected one, for messages
   interface difference
      module procedure :: difference_sp
      module procedure :: difference_dp
   end interface difference

   !> NaN test by ordered comparisons (no IEEE intrinsic module)
   interface not_a_number
      module procedure :: not_a_number_sp
      module procedure :: not_a_number_dp
   end interface not_a_number

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
   function select_test(tests, name) result(pos)
      !> Available unit tests
      type(unittest_type), intent(in) :: tests(:)
      !> Name of the wanted test
      character(len=*), intent(in) :: name
      integer :: pos

      do pos = 1, size(tests)
         if (.not. allocated(tests(pos)%name)) cycle
         if (tests(pos)%name == name) return
      end do
      pos = 0
   end function select_test

   !> Index of the test suite called `name`, 0 if there is none
   function select_suite(suites, name) result(pos)
      !> Available test suites
      type(testsuite_type), intent(in) :: suites(:)
      !> Name of the wanted suite
      character(len=*), intent(in) :: name
      integer :: pos

      do pos = 1, size(suites)
         if (.not. allocated(suites(pos)%name)) cycle
         if (suites(pos)%name == name) return
      end do
      pos = 0
   end function select_suite

   ! ------------------------------------------------------------------
   ! Running tests
   ! ------------------------------------------------------------------

   !> Run all unit tests of a suite, adding the number of failures to `stat`
   recursive subroutine run_testsuite(collect, unit, stat, parallel)
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
         write(unit, '(a)') "  Starting " // test_name(testsuite(it)) // " ... (" &
            // to_string(it) // "/" // to_string(size(testsuite)) // ")"
         call run_unittest(testsuite(it), unit, stat)
      end do
   end subroutine run_testsuite

   !> Run only the unit test called `name`; if there is none, list the
   !> available tests and set `stat` to -huge(stat)
   recursive subroutine run_selected(collect, name, unit, stat)
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
      if (pos > 0) then
         call run_unittest(testsuite(pos), unit, stat)
      else
         write(unit, '(a)') "  Available tests:"
         do it = 1, size(testsuite)
            write(unit, '(a)') "  - " // test_name(testsuite(it))
         end do
         stat = -huge(stat)
      end if
   end subroutine run_selected

   !> Run one unit test, report its outcome and count it in `stat`
   recursive subroutine run_unittest(test, unit, stat)
      type(unittest_type), intent(in) :: test
      integer, intent(in) :: unit
      integer, intent(inout) :: stat
      type(error_type), allocatable :: error
      character(len=:), allocatable :: label
      logical :: failed, skip

      if (associated(test%test)) then
         call test%test(error)
      else
         call test_failed(error, "No test procedure associated")
      end if

      failed = allocated(error)
      skip = .false.
      if (failed) skip = error%stat == skipped

      if (skip) then
         label = "[SKIPPED]"
      else
         if (failed .neqv. test%should_fail) stat = stat + 1
         if (failed .and. test%should_fail) then
            label = "[EXPECTED FAIL]"
         else if (failed) then
            label = "[FAILED]"
         else if (test%should_fail) then
            label = "[UNEXPECTED PASS]"
         else
            label = "[PASSED]"
         end if
      end if

      write(unit, '(a)') "       ... " // test_name(test) // " " // label
      if (failed) then
         if (allocated(error%message)) then
            write(unit, '(a)') "  Message: " // error%message
         else
            write(unit, '(a)') "  Message: "
         end if
         ! handled: let it go without escalating
         error%stat = success
         deallocate(error)
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

   !> Finalizer of error_type: an error still holding a failure or a skip was
   !> never handled by the test driver, which is a bug in the test; stop
   subroutine uncaught_error(error)
      type(error_type), intent(inout) :: error

      if (error%stat == success) return
      write(error_unit, '(a)') "[Fatal] Uncaught error"
      if (allocated(error%message)) then
         write(error_unit, '(a)') "Code: " // to_string(error%stat) &
            // " Message: " // error%message
      end if
      error stop
   end subroutine uncaught_error

   ! ------------------------------------------------------------------
   ! Failing and skipping
   ! ------------------------------------------------------------------

   !> Mark the current test as failed
   subroutine test_failed(error, message, more, and_more)
      !> Allocated with stat = 1
      type(error_type), allocatable, intent(out) :: error
      !> Description of the failure
      character(len=*), intent(in) :: message
      !> A second line of the message
      character(len=*), intent(in), optional :: more
      !> A third line of the message
      character(len=*), intent(in), optional :: and_more

      allocate(error)
      error%stat = fatal
      error%message = message
      if (present(more)) error%message = error%message // continued // more
      if (present(and_more)) error%message = error%message // continued // and_more
   end subroutine test_failed

   !> Mark the current test as skipped; the test must return right away
   subroutine skip_test(error, message, more, and_more)
      !> Allocated with stat = 77
      type(error_type), allocatable, intent(out) :: error
      !> Reason for skipping
      character(len=*), intent(in) :: message
      !> A second line of the message
      character(len=*), intent(in), optional :: more
      !> A third line of the message
      character(len=*), intent(in), optional :: and_more

      call test_failed(error, message, more, and_more)
      error%stat = skipped
   end subroutine skip_test

   !> Fail with the caller's message if it gave one, otherwise with `default`
   !> followed by the line `detail`; `more` ends the message in both cases
   subroutine fail(error, message, more, default, detail)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      character(len=*), intent(in) :: default
      character(len=*), intent(in), optional :: detail

      if (present(message)) then
         call test_failed(error, message, more)
      else if (present(detail)) then
         call test_failed(error, default, detail, more)
      else
         call test_failed(error, default, more)
      end if
   end subroutine fail

   ! ------------------------------------------------------------------
   ! Command line and environment
   ! ------------------------------------------------------------------

   !> Command-line argument number `idx`; left unallocated if there is none
   !> (an empty argument gives an empty string)
   subroutine get_argument(idx, arg)
      !> Index of the argument, 0 for the command itself
      integer, intent(in) :: idx
      !> The argument
      character(len=:), allocatable, intent(out) :: arg
      integer :: length, stat

      call get_command_argument(idx, length=length, status=stat)
      if (stat /= 0) return
      allocate(character(len=length) :: arg, stat=stat)
      if (stat /= 0 .or. length == 0) return
      call get_command_argument(idx, arg, status=stat)
      if (stat /= 0) deallocate(arg)
   end subroutine get_argument

   !> Value of the environment variable `var`; left unallocated if it is not
   !> set (a variable set to nothing gives an empty string)
   subroutine get_variable(var, val)
      !> Name of the variable
      character(len=*), intent(in) :: var
      !> Its value
      character(len=:), allocatable, intent(out) :: val
      integer :: length, stat

      call get_environment_variable(var, length=length, status=stat)
      if (stat /= 0) return
      allocate(character(len=length) :: val, stat=stat)
      if (stat /= 0 .or. length == 0) return
      call get_environment_variable(var, val, status=stat)
      if (stat /= 0) deallocate(val)
   end subroutine get_variable

   ! ------------------------------------------------------------------
   ! Checks
   ! ------------------------------------------------------------------

   !> Check that an exit status is zero
   subroutine check_stat(error, stat, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer, intent(in) :: stat
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (stat /= success) call fail(error, message, more, "Non-zero exit code encountered")
   end subroutine check_stat

   !> Check that a logical expression is true
   subroutine check_expression(error, expression, message, more)
      type(error_type), allocatable, intent(out) :: error
      logical, intent(in) :: expression
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (.not. expression) call fail(error, message, more, "Condition not fullfilled")
   end subroutine check_expression

   !> Check a logical value against its expected value
   subroutine check_bool(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      logical, intent(in) :: actual
      logical, intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual .neqv. expected) call fail(error, message, more, "Logical value missmatch", &
         "expected " // logical_letter(expected) // " but got " // logical_letter(actual))
   end subroutine check_bool

   !> Check an integer(i1) value against its expected value
   subroutine check_int_i1(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i1), intent(in) :: actual
      integer(i1), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) call fail(error, message, more, "Integer value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual))
   end subroutine check_int_i1

   !> Check an integer(i2) value against its expected value
   subroutine check_int_i2(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i2), intent(in) :: actual
      integer(i2), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) call fail(error, message, more, "Integer value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual))
   end subroutine check_int_i2

   !> Check an integer(i4) value against its expected value
   subroutine check_int_i4(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i4), intent(in) :: actual
      integer(i4), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) call fail(error, message, more, "Integer value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual))
   end subroutine check_int_i4

   !> Check an integer(i8) value against its expected value
   subroutine check_int_i8(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      integer(i8), intent(in) :: actual
      integer(i8), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) call fail(error, message, more, "Integer value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual))
   end subroutine check_int_i8

   !> Check a character value against its expected value (trailing blanks do
   !> not count, as in the == operator)
   subroutine check_string(error, actual, expected, message, more)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), intent(in) :: actual
      character(len=*), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (actual /= expected) call fail(error, message, more, "Character value missmatch", &
         "expected '" // expected // "' but got '" // actual // "'")
   end subroutine check_string

   !> Check a real(sp) value: first that it is not NaN, then that it differs
   !> from `expected` by at most `thr` (default epsilon), or relatively to
   !> |expected| if `rel` is true.  A NaN difference does not fail.
   subroutine check_float_sp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      real(sp), intent(in) :: actual
      real(sp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      real(sp), intent(in), optional :: thr
      logical, intent(in), optional :: rel
      real(sp) :: diff, tol
      logical :: relative

      call check_float_exceptional_sp(error, actual, message, more)
      if (allocated(error)) return
      tol = epsilon(expected)
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) diff = diff / abs(expected)
      if (diff > tol) call fail(error, message, more, "Floating point value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual) &
         // " " // difference(relative, diff))
   end subroutine check_float_sp

   !> Check a real(dp) value: first that it is not NaN, then that it differs
   !> from `expected` by at most `thr` (default epsilon), or relatively to
   !> |expected| if `rel` is true.  A NaN difference does not fail.
   subroutine check_float_dp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      real(dp), intent(in) :: actual
      real(dp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      real(dp), intent(in), optional :: thr
      logical, intent(in), optional :: rel
      real(dp) :: diff, tol
      logical :: relative

      call check_float_exceptional_dp(error, actual, message, more)
      if (allocated(error)) return
      tol = epsilon(expected)
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) diff = diff / abs(expected)
      if (diff > tol) call fail(error, message, more, "Floating point value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual) &
         // " " // difference(relative, diff))
   end subroutine check_float_dp

   !> Check that a real(sp) value is not NaN
   subroutine check_float_exceptional_sp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      real(sp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (not_a_number(actual)) &
         call fail(error, message, more, "Exceptional value 'not a number' found")
   end subroutine check_float_exceptional_sp

   !> Check that a real(dp) value is not NaN
   subroutine check_float_exceptional_dp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      real(dp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (not_a_number(actual)) &
         call fail(error, message, more, "Exceptional value 'not a number' found")
   end subroutine check_float_exceptional_dp

   !> Check a complex(sp) value: first that neither part is NaN, then the
   !> modulus of its difference from `expected` as for real values
   subroutine check_complex_sp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      complex(sp), intent(in) :: actual
      complex(sp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      real(sp), intent(in), optional :: thr
      logical, intent(in), optional :: rel
      real(sp) :: diff, tol
      logical :: relative

      call check_complex_exceptional_sp(error, actual, message, more)
      if (allocated(error)) return
      tol = epsilon(abs(expected))
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) diff = diff / abs(expected)
      if (diff > tol) call fail(error, message, more, "Floating point value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual) &
         // " " // difference(relative, diff))
   end subroutine check_complex_sp

   !> Check a complex(dp) value: first that neither part is NaN, then the
   !> modulus of its difference from `expected` as for real values
   subroutine check_complex_dp(error, actual, expected, message, more, thr, rel)
      type(error_type), allocatable, intent(out) :: error
      complex(dp), intent(in) :: actual
      complex(dp), intent(in) :: expected
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more
      real(dp), intent(in), optional :: thr
      logical, intent(in), optional :: rel
      real(dp) :: diff, tol
      logical :: relative

      call check_complex_exceptional_dp(error, actual, message, more)
      if (allocated(error)) return
      tol = epsilon(abs(expected))
      if (present(thr)) tol = thr
      relative = .false.
      if (present(rel)) relative = rel
      diff = abs(actual - expected)
      if (relative) diff = diff / abs(expected)
      if (diff > tol) call fail(error, message, more, "Floating point value missmatch", &
         "expected " // to_string(expected) // " but got " // to_string(actual) &
         // " " // difference(relative, diff))
   end subroutine check_complex_dp

   !> Check that neither part of a complex(sp) value is NaN
   subroutine check_complex_exceptional_sp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      complex(sp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (not_a_number(real(actual)) .or. not_a_number(aimag(actual))) &
         call fail(error, message, more, "Exceptional value 'not a number' found")
   end subroutine check_complex_exceptional_sp

   !> Check that neither part of a complex(dp) value is NaN
   subroutine check_complex_exceptional_dp(error, actual, message, more)
      type(error_type), allocatable, intent(out) :: error
      complex(dp), intent(in) :: actual
      character(len=*), intent(in), optional :: message
      character(len=*), intent(in), optional :: more

      if (not_a_number(real(actual)) .or. not_a_number(aimag(actual))) &
         call fail(error, message, more, "Exceptional value 'not a number' found")
   end subroutine check_complex_exceptional_dp

   !> "(difference: D)" for an absolute difference, "(difference: P%)" with P
   !> the whole percent for a relative one
   pure function difference_sp(relative, diff) result(string)
      logical, intent(in) :: relative
      real(sp), intent(in) :: diff
      character(len=:), allocatable :: string

      if (relative) then
         string = "(difference: " // to_string(int(100 * diff)) // "%)"
      else
         string = "(difference: " // to_string(diff) // ")"
      end if
   end function difference_sp

   pure function difference_dp(relative, diff) result(string)
      logical, intent(in) :: relative
      real(dp), intent(in) :: diff
      character(len=:), allocatable :: string

      if (relative) then
         string = "(difference: " // to_string(int(100 * diff)) // "%)"
      else
         string = "(difference: " // to_string(diff) // ")"
      end if
   end function difference_dp

   !> "T" or "F"
   pure function logical_letter(value) result(letter)
      logical, intent(in) :: value
      character(len=1) :: letter

      letter = "F"
      if (value) letter = "T"
   end function logical_letter

   !> A NaN is neither negative nor non-negative; the ordered comparisons raise
   !> IEEE invalid on it, as test-drive's own test does
   elemental function not_a_number_sp(x) result(nan)
      real(sp), intent(in) :: x
      logical :: nan

      nan = .not. (x < 0.0_sp .or. x >= 0.0_sp)
   end function not_a_number_sp

   elemental function not_a_number_dp(x) result(nan)
      real(dp), intent(in) :: x
      logical :: nan

      nan = .not. (x < 0.0_dp .or. x >= 0.0_dp)
   end function not_a_number_dp

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

   !> Convert a real(sp) to a string (list-directed g0 editing)
   pure function real_sp_to_string(val) result(string)
      real(sp), intent(in) :: val
      character(len=:), allocatable :: string
      character(len=64) :: buffer

      write(buffer, '(g0)') val
      string = trim(buffer)
   end function real_sp_to_string

   !> Convert a real(dp) to a string (g0 editing)
   pure function real_dp_to_string(val) result(string)
      real(dp), intent(in) :: val
      character(len=:), allocatable :: string
      character(len=64) :: buffer

      write(buffer, '(g0)') val
      string = trim(buffer)
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
