!> Status codes and the status object every fallible library procedure returns.
!>
!> The library never stops and never prints: a procedure that can fail sets a
!> `status_type` (an integer code from the named constants below plus a readable
!> message) and returns; the caller decides what to do.
module taylorode_base_status
   implicit none
   private

   public :: status_type, set_status, set_code, describe, status_name
   public :: status_ok, status_invalid_argument, status_size_mismatch, status_nonfinite, &
      status_singular_matrix, status_newton_diverged, status_newton_not_converged, &
      status_step_underflow, status_max_steps, status_unknown_scheme, status_evaluation_failed, &
      status_output_error, status_out_of_memory, status_description

   !> Success
   integer, parameter :: status_ok = 0
   !> An argument or option is out of its valid range (h <= 0, tolerance <= 0, NaN option, ...)
   integer, parameter :: status_invalid_argument = 1
   !> Arrays passed together do not have matching sizes
   integer, parameter :: status_size_mismatch = 2
   !> The state, a right-hand side value or a Jacobian is NaN or infinite
   integer, parameter :: status_nonfinite = 3
   !> The Newton iteration matrix is singular (LAPACK dgetrf info > 0)
   integer, parameter :: status_singular_matrix = 4
   !> The Newton iteration diverged (growing increments or non-finite iterate)
   integer, parameter :: status_newton_diverged = 5
   !> The Newton iteration did not converge within the allowed number of iterations
   integer, parameter :: status_newton_not_converged = 6
   !> The step size fell below the minimum step or below the roundoff of t
   integer, parameter :: status_step_underflow = 7
   !> The maximum number of steps was reached before the end of the interval
   integer, parameter :: status_max_steps = 8
   !> A scheme name that the factory does not know
   integer, parameter :: status_unknown_scheme = 9
   !> The problem said it cannot evaluate f, g or a Jacobian at the requested point
   !> (see ode_problem%reject_evaluation), repeatedly
   integer, parameter :: status_evaluation_failed = 10
   !> A file could not be written completely (nothing partial is left behind)
   integer, parameter :: status_output_error = 11
   !> Memory for an array the computation needs could not be allocated (the message says
   !> which and how many bytes); the highest code, so that it prevails when processes agree
   integer, parameter :: status_out_of_memory = 12

   !> Outcome of a library call: `code == status_ok` means success
   type :: status_type
      !> One of the `status_*` constants
      integer :: code = status_ok
      !> Human-readable explanation, allocated when `code /= status_ok`
      character(len=:), allocatable :: message
   contains
      !> True when the call succeeded
      procedure :: ok => status_is_ok
   end type status_type

contains

   !> True when the status reports success.
   elemental function status_is_ok(self) result(ok)
      !> The status
      class(status_type), intent(in) :: self
      logical :: ok
      ok = self%code == status_ok
   end function status_is_ok

   !> Record a failure (or success, with `status_ok`) and its message. Should even the
   !> message's few bytes not be available, the code is recorded without it
   !> (`status_description` says what it means).
   pure subroutine set_status(stat, code, message)
      !> Status to overwrite
      type(status_type), intent(inout) :: stat
      !> One of the `status_*` constants
      integer, intent(in) :: code
      !> Explanation for the caller
      character(len=*), intent(in) :: message
      character(len=:), allocatable :: text
      integer :: memory
      allocate (character(len=len(message)) :: text, stat=memory)
      if (memory == 0) text(:) = message
      stat%code = code
      call move_alloc(text, stat%message)
   end subroutine set_status

   !> Record an outcome by its code alone, without building a message: what a step
   !> attempt does inside an integration, where a failure is retried and allocating
   !> a message each time would cost a heap allocation. `describe` adds the message.
   elemental subroutine set_code(stat, code)
      !> Status to overwrite
      type(status_type), intent(inout) :: stat
      !> One of the `status_*` constants
      integer, intent(in) :: code
      stat%code = code
      if (allocated(stat%message)) deallocate (stat%message)
   end subroutine set_code

   !> Give a failure that carries only its code the standard sentence for that code.
   pure subroutine describe(stat, prefix)
      !> The status
      type(status_type), intent(inout) :: stat
      !> Who reports it, e.g. "take_step"
      character(len=*), intent(in) :: prefix
      if (stat%code == status_ok .or. allocated(stat%message)) return
      call set_status(stat, stat%code, prefix//": "//trim(status_description(stat%code)))
   end subroutine describe

   !> Short name of a status code, for tables and logs.
   pure function status_name(code) result(name)
      !> One of the `status_*` constants
      integer, intent(in) :: code
      character(len=:), allocatable :: name
      select case (code)
      case (status_ok); name = "ok"
      case (status_invalid_argument); name = "invalid argument"
      case (status_size_mismatch); name = "size mismatch"
      case (status_nonfinite); name = "non-finite value"
      case (status_singular_matrix); name = "singular Newton matrix"
      case (status_newton_diverged); name = "Newton diverged"
      case (status_newton_not_converged); name = "Newton not converged"
      case (status_step_underflow); name = "step size underflow"
      case (status_max_steps); name = "maximum steps reached"
      case (status_unknown_scheme); name = "unknown scheme"
      case (status_evaluation_failed); name = "evaluation failed"
      case (status_output_error); name = "output error"
      case (status_out_of_memory); name = "out of memory"
      case default; name = "unknown status"
      end select
   end function status_name

   !> A sentence saying what a status code means, for callers that got a code without
   !> a message (fixed text: safe to use from any thread).
   pure function status_description(code) result(text)
      !> One of the `status_*` constants
      integer, intent(in) :: code
      character(len=80) :: text
      select case (code)
      case (status_ok); text = "success"
      case (status_invalid_argument); text = "an argument or option is out of its valid range"
      case (status_size_mismatch); text = "arrays passed together do not have matching sizes"
      case (status_nonfinite); text = "a value (of f, g, a Jacobian or the state) became NaN or Inf"
      case (status_singular_matrix); text = "the Newton iteration matrix is singular (reduce the step size)"
      case (status_newton_diverged); text = "the Newton iteration diverged"
      case (status_newton_not_converged); text = "the Newton iteration did not converge within the iteration limit"
      case (status_step_underflow); text = "the step size fell below the minimum step or the roundoff of t"
      case (status_max_steps); text = "the maximum number of steps was reached"
      case (status_unknown_scheme); text = "unknown scheme name"
      case (status_evaluation_failed); text = "the problem could not evaluate f, g or a Jacobian"
      case (status_output_error); text = "a file could not be written"
      case (status_out_of_memory); text = "memory could not be allocated"
      case default; text = "unknown status"
      end select
   end function status_description

end module taylorode_base_status
