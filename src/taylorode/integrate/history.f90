!> Step history of an adaptive integration (recorded only when asked for) and its
!> CSV writer.
module taylorode_integrate_history
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument
   implicit none
   private

   public :: step_history_type, write_history_csv
   public :: attempt_accepted, attempt_rejected_error, attempt_failed_newton, attempt_failed_nonfinite
   public :: attempt_name

   !> The step passed the error test
   integer, parameter :: attempt_accepted = 0
   !> The error estimate exceeded the tolerance
   integer, parameter :: attempt_rejected_error = 1
   !> Newton failed (singular matrix, divergence, no convergence)
   integer, parameter :: attempt_failed_newton = 2
   !> f or g returned NaN/Inf, or the new state was not finite
   integer, parameter :: attempt_failed_nonfinite = 3

   !> Every attempted step: start time, size, weighted error, outcome, Newton iterations
   type :: step_history_type
      !> Number of attempts recorded
      integer :: count = 0
      !> Start of each attempted step
      real(dp), allocatable :: t(:)
      !> Size of each attempted step
      real(dp), allocatable :: h(:)
      !> Weighted error estimate (NaN when the step failed before it)
      real(dp), allocatable :: err(:)
      !> attempt_accepted, attempt_rejected_error, attempt_failed_newton or attempt_failed_nonfinite
      integer, allocatable :: outcome(:)
      !> Newton iterations spent on the attempt
      integer, allocatable :: newton_iterations(:)
      !> State after the attempt (only with options%history_states), one column per attempt
      real(dp), allocatable :: states(:, :)
   contains
      !> Append one attempt (storage grows geometrically)
      procedure :: record
   end type step_history_type

contains

   !> Append one attempt; `state` is stored only when given.
   pure subroutine record(self, t, h, err, outcome, newton_iterations, state)
      !> The history
      class(step_history_type), intent(inout) :: self
      !> Start of the step
      real(dp), intent(in) :: t
      !> Step size
      real(dp), intent(in) :: h
      !> Weighted error estimate
      real(dp), intent(in) :: err
      !> attempt_* outcome
      integer, intent(in) :: outcome
      !> Newton iterations of the attempt
      integer, intent(in) :: newton_iterations
      !> State after the attempt
      real(dp), intent(in), optional :: state(:)

      if (.not. allocated(self%t)) call grow(self, 1024, state)
      if (self%count == size(self%t)) call grow(self, 2*size(self%t), state)
      self%count = self%count + 1
      self%t(self%count) = t
      self%h(self%count) = h
      self%err(self%count) = err
      self%outcome(self%count) = outcome
      self%newton_iterations(self%count) = newton_iterations
      if (present(state)) self%states(:, self%count) = state
   end subroutine record

   !> Resize the storage to `capacity` attempts, keeping what is recorded.
   pure subroutine grow(self, capacity, state)
      class(step_history_type), intent(inout) :: self
      integer, intent(in) :: capacity
      real(dp), intent(in), optional :: state(:)
      real(dp), allocatable :: real_buffer(:), state_buffer(:, :)
      integer, allocatable :: integer_buffer(:)
      integer :: n

      n = self%count
      allocate (real_buffer(capacity))
      if (n > 0) real_buffer(:n) = self%t(:n)
      call move_alloc(real_buffer, self%t)
      allocate (real_buffer(capacity))
      if (n > 0) real_buffer(:n) = self%h(:n)
      call move_alloc(real_buffer, self%h)
      allocate (real_buffer(capacity))
      if (n > 0) real_buffer(:n) = self%err(:n)
      call move_alloc(real_buffer, self%err)
      allocate (integer_buffer(capacity))
      if (n > 0) integer_buffer(:n) = self%outcome(:n)
      call move_alloc(integer_buffer, self%outcome)
      allocate (integer_buffer(capacity))
      if (n > 0) integer_buffer(:n) = self%newton_iterations(:n)
      call move_alloc(integer_buffer, self%newton_iterations)
      if (present(state)) then
         allocate (state_buffer(size(state), capacity))
         if (n > 0) state_buffer(:, :n) = self%states(:, :n)
         call move_alloc(state_buffer, self%states)
      end if
   end subroutine grow

   !> Word for an attempt outcome, as written in the CSV.
   pure function attempt_name(outcome) result(name)
      !> attempt_* outcome
      integer, intent(in) :: outcome
      character(len=:), allocatable :: name
      select case (outcome)
      case (attempt_accepted); name = "accepted"
      case (attempt_rejected_error); name = "rejected_error"
      case (attempt_failed_newton); name = "failed_newton"
      case (attempt_failed_nonfinite); name = "failed_nonfinite"
      case default; name = "unknown"
      end select
   end function attempt_name

   !> Write the history as CSV: step,t,h,err,outcome,newton_iterations[,u1,u2,...].
   subroutine write_history_csv(history, filename, stat)
      !> The recorded history
      type(step_history_type), intent(in) :: history
      !> Output file (overwritten)
      character(len=*), intent(in) :: filename
      !> status_invalid_argument when the file cannot be written
      type(status_type), intent(out) :: stat

      integer :: unit, io, i, j, n_states
      character(len=256) :: io_message

      open (newunit=unit, file=filename, status="replace", action="write", iostat=io, iomsg=io_message)
      if (io /= 0) then
         call set_status(stat, status_invalid_argument, "cannot write "//filename//": "//trim(io_message))
         return
      end if
      n_states = 0
      if (allocated(history%states)) n_states = size(history%states, 1)
      write (unit, '(a)', advance="no") "step,t,h,err,outcome,newton_iterations"
      do j = 1, n_states
         write (unit, '(a, i0)', advance="no") ",u", j
      end do
      write (unit, '(a)') ""
      do i = 1, history%count
         write (unit, '(i0, 3(",", es24.16e3), ",", a, ",", i0)', advance="no") i, history%t(i), &
            history%h(i), history%err(i), attempt_name(history%outcome(i)), history%newton_iterations(i)
         do j = 1, n_states
            write (unit, '(",", es24.16e3)', advance="no") history%states(j, i)
         end do
         write (unit, '(a)') ""
      end do
      close (unit)
      stat%code = status_ok
   end subroutine write_history_csv

end module taylorode_integrate_history
