!> Step history of an adaptive integration, recorded only when asked for: kept in
!> memory (optionally bounded), or streamed row by row into a CSV file so that a
!> long run holds nothing in memory. One row format serves both.
module taylorode_integrate_history
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_output_error, status_out_of_memory
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_base_files, only: text_file_type
   implicit none
   private

   public :: step_history_type, write_history_csv
   public :: attempt_accepted, attempt_rejected_error, attempt_failed_newton, attempt_failed_nonfinite, &
      attempt_failed_evaluation, attempt_rejected_constraint, attempt_rejected_output
   public :: attempt_name

   !> The step passed the error test
   integer, parameter :: attempt_accepted = 0
   !> The error estimate exceeded the tolerance
   integer, parameter :: attempt_rejected_error = 1
   !> Newton failed (singular matrix, divergence, no convergence)
   integer, parameter :: attempt_failed_newton = 2
   !> f or g returned NaN/Inf, or the new state was not finite
   integer, parameter :: attempt_failed_nonfinite = 3
   !> The problem could not evaluate f, g or a Jacobian at a point of the step
   integer, parameter :: attempt_failed_evaluation = 4
   !> A component declared nonnegative went below 0 by more than the step may set right
   integer, parameter :: attempt_rejected_constraint = 5
   !> The step passed the error test, but its dense output at an output time inside it did not
   integer, parameter :: attempt_rejected_output = 6

   !> Column names before the state columns
   character(len=*), parameter :: header = "step,t,h,err,outcome,newton_iterations"

   !> Every attempted step: start time, size, weighted error, outcome, Newton iterations
   !> (and the state after it when options%history_states is set). `integrate` starts
   !> the history afresh on entry, so one history may serve several integrations.
   !>
   !> Streamed into a file (`stream_to`), the rows go to a temporary file beside it that
   !> is renamed into place by `finish` when every row was written (else removed):
   !> `integrate` finishes the stream when it returns; continued calls (`advance_to`)
   !> write one file, which the caller finishes after the last call. A history that is
   !> dropped unfinished (it goes out of scope, is deallocated, or streams anew) removes
   !> its temporary file and leaves the destination as it was. A streaming history must
   !> not be copied (the copies would share one file).
   type :: step_history_type
      !> Attempts recorded (kept in memory, or written to the stream)
      integer :: count = 0
      !> At most this many attempts are kept in memory (0: no bound); later ones are
      !> counted in `dropped`
      integer :: capacity = 0
      !> Attempts not kept because the capacity was reached
      integer(i8) :: dropped = 0
      !> Start of each attempted step
      real(dp), allocatable :: t(:)
      !> Size of each attempted step
      real(dp), allocatable :: h(:)
      !> Weighted error estimate (NaN when the step failed before it)
      real(dp), allocatable :: err(:)
      !> attempt_* outcome of each attempt
      integer, allocatable :: outcome(:)
      !> Newton iterations spent on each attempt
      integer, allocatable :: newton_iterations(:)
      !> State after each attempt (only with options%history_states), one column per attempt
      real(dp), allocatable :: states(:, :)
      !> Number of state columns of the current integration
      integer :: state_columns = 0
      !> Why the storage in memory could not grow ("" while it could; the attempts after
      !> it are not kept)
      character(len=200), private :: memory_failure = ""
      !> The CSV file rows are streamed to (see stream_to)
      type(text_file_type), private :: stream
      !> Whether rows go to the stream instead of memory, and whether its header is out
      logical, private :: streaming = .false., header_written = .false.
   contains
      !> Begin an integration with `state_columns` states per row (0: none)
      procedure :: start
      !> Append one attempt
      procedure :: record
      !> Send every following row into a CSV file (written safely: see `finish`)
      procedure :: stream_to
      !> Complete the stream: the file appears only when every row was written
      procedure :: finish
      !> Whether writing the stream failed
      procedure :: failed
      !> status_out_of_memory when the storage in memory could not grow
      procedure :: check_memory
      !> A stream never finished is removed (its temporary file)
      final :: drop_unfinished_stream
   end type step_history_type

contains

   !> Word for an attempt outcome, as written in the CSV.
   pure function attempt_name(outcome) result(name)
      !> attempt_* outcome
      integer, intent(in) :: outcome
      character(len=:), allocatable :: name
      name = trim(outcome_word(outcome))
   end function attempt_name

   !> The same word in a fixed-length result (what the row writer uses: deferred-length
   !> results inside expressions are not thread-safe with gfortran 12).
   pure function outcome_word(outcome) result(name)
      integer, intent(in) :: outcome
      character(len=19) :: name
      select case (outcome)
      case (attempt_accepted); name = "accepted"
      case (attempt_rejected_error); name = "rejected_error"
      case (attempt_failed_newton); name = "failed_newton"
      case (attempt_failed_nonfinite); name = "failed_nonfinite"
      case (attempt_failed_evaluation); name = "failed_evaluation"
      case (attempt_rejected_constraint); name = "rejected_constraint"
      case (attempt_rejected_output); name = "rejected_output"
      case default; name = "unknown"
      end select
   end function outcome_word

   !> Begin an integration: in memory, forget what earlier integrations recorded; in a
   !> stream, write the header once (a stream collects the calls of one continued
   !> integration, with the same number of state columns, until `finish`).
   subroutine start(self, state_columns, stat)
      !> The history
      class(step_history_type), intent(inout) :: self
      !> States per row (0 for none)
      integer, intent(in) :: state_columns
      !> status_invalid_argument when a stream already has other columns
      type(status_type), intent(inout) :: stat
      if (self%streaming) then
         if (self%header_written) then
            if (state_columns /= self%state_columns) call set_status(stat, status_invalid_argument, &
               "step history: the stream already has other state columns")
            return
         end if
         self%state_columns = state_columns
         call write_header(self%stream, state_columns)
         self%header_written = .true.
         return
      end if
      self%count = 0
      self%dropped = 0
      self%state_columns = state_columns
      self%memory_failure = ""
      if (allocated(self%t)) deallocate (self%t)
      if (allocated(self%h)) deallocate (self%h)
      if (allocated(self%err)) deallocate (self%err)
      if (allocated(self%outcome)) deallocate (self%outcome)
      if (allocated(self%newton_iterations)) deallocate (self%newton_iterations)
      if (allocated(self%states)) deallocate (self%states)
   end subroutine start

   !> The header line: step,t,h,err,outcome,newton_iterations,u1,u2,...
   subroutine write_header(file, columns)
      type(text_file_type), intent(inout) :: file
      integer, intent(in) :: columns
      character(len=16) :: name
      integer :: j
      call file%write_part(header)
      do j = 1, columns
         write (name, '(",u", i0)') j
         call file%write_part(trim(name))
      end do
      call file%write_line("")
   end subroutine write_header

   !> Append one attempt; the state is stored only when the history has state columns.
   subroutine record(self, t, h, err, outcome, newton_iterations, state)
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
      real(dp), intent(in) :: state(:)

      self%count = self%count + 1
      if (self%streaming) then
         call write_row(self%stream, self%count, t, h, err, outcome, newton_iterations, &
            state(:min(size(state), self%state_columns)))
         return
      end if
      if (self%capacity > 0 .and. self%count > self%capacity) then
         self%count = self%capacity
         self%dropped = self%dropped + 1
         return
      end if
      if (.not. allocated(self%t)) then
         call grow(self, 1024)
      else if (self%count > size(self%t)) then
         call grow(self, 2*size(self%t))
      end if
      if (len_trim(self%memory_failure) > 0) then
         ! the storage could not grow: this attempt is not kept (the integration stops)
         self%count = self%count - 1
         return
      end if
      self%t(self%count) = t
      self%h(self%count) = h
      self%err(self%count) = err
      self%outcome(self%count) = outcome
      self%newton_iterations(self%count) = newton_iterations
      if (self%state_columns > 0) self%states(:, self%count) = state(:self%state_columns)
   end subroutine record

   !> Resize the storage to `capacity` attempts (at most self%capacity), keeping what is
   !> recorded; the storage stays as it was when the new one cannot be allocated
   !> (self%memory says so).
   subroutine grow(self, capacity)
      class(step_history_type), intent(inout) :: self
      integer, intent(in) :: capacity
      real(dp), allocatable :: t_buffer(:), h_buffer(:), err_buffer(:), state_buffer(:, :)
      integer, allocatable :: outcome_buffer(:), iterations_buffer(:)
      integer :: n, new_size, memory
      type(status_type) :: stat

      n = self%count - 1
      new_size = capacity
      if (self%capacity > 0) new_size = min(new_size, self%capacity)
      allocate (t_buffer(new_size), h_buffer(new_size), err_buffer(new_size), outcome_buffer(new_size), &
         iterations_buffer(new_size), state_buffer(self%state_columns, merge(new_size, 0, self%state_columns > 0)), &
         stat=memory)
      if (memory /= 0) then
         call out_of_memory(stat, "the step history", [new_size, 5 + self%state_columns], real_bytes)
         self%memory_failure = stat%message
         return
      end if
      if (n > 0) then
         t_buffer(:n) = self%t(:n)
         h_buffer(:n) = self%h(:n)
         err_buffer(:n) = self%err(:n)
         outcome_buffer(:n) = self%outcome(:n)
         iterations_buffer(:n) = self%newton_iterations(:n)
      end if
      call move_alloc(t_buffer, self%t)
      call move_alloc(h_buffer, self%h)
      call move_alloc(err_buffer, self%err)
      call move_alloc(outcome_buffer, self%outcome)
      call move_alloc(iterations_buffer, self%newton_iterations)
      if (self%state_columns > 0) then
         if (n > 0) state_buffer(:, :n) = self%states(:, :n)
         call move_alloc(state_buffer, self%states)
      end if
   end subroutine grow

   !> One CSV row: step,t,h,err,outcome,newton_iterations[,u1,...].
   subroutine write_row(file, step, t, h, err, outcome, newton_iterations, state)
      type(text_file_type), intent(inout) :: file
      integer, intent(in) :: step, outcome, newton_iterations
      real(dp), intent(in) :: t, h, err, state(:)
      character(len=160) :: fields
      character(len=32) :: value
      integer :: j
      write (fields, '(i0, 3(",", es24.16e3), ",", a, ",", i0)') step, t, h, err, trim(outcome_word(outcome)), &
         newton_iterations
      if (size(state) == 0) then
         call file%write_line(trim(fields))
         return
      end if
      call file%write_part(trim(fields))
      do j = 1, size(state)
         write (value, '(",", es24.16e3)') state(j)
         call file%write_part(trim(value))
      end do
      call file%write_line("")
   end subroutine write_row

   !> Send every following row into the CSV file `path`, written to a temporary file
   !> beside it until `finish` renames it into place (`integrate` finishes it when it
   !> returns). A stream not yet finished is dropped first (its destination left as it was).
   subroutine stream_to(self, path, stat, replace)
      !> The history
      class(step_history_type), intent(inout) :: self
      !> Destination (an existing file is replaced only by a complete new one)
      character(len=*), intent(in) :: path
      !> status_output_error when the file cannot be created (left as it was otherwise)
      type(status_type), intent(inout) :: stat
      !> Whether a file at path may be replaced (default true; false: one there when the
      !> stream is finished is kept, and finish fails)
      logical, intent(in), optional :: replace
      type(status_type) :: open_stat
      if (self%streaming) call self%stream%discard()
      self%streaming = .false.
      call self%stream%open(path, open_stat, replace)
      if (open_stat%code /= status_ok) then
         stat = open_stat
         return
      end if
      self%streaming = .true.
      self%header_written = .false.
      self%count = 0
   end subroutine stream_to

   !> Complete the stream: the file is renamed into place when every row was written,
   !> else it is removed and stat says why (the destination is left as it was).
   subroutine finish(self, stat)
      !> The history
      class(step_history_type), intent(inout) :: self
      !> status_output_error on failure
      type(status_type), intent(inout) :: stat
      if (.not. self%streaming) return
      if (.not. self%header_written) call write_header(self%stream, 0)
      call self%stream%commit(stat)
      self%streaming = .false.
   end subroutine finish

   !> What finalizing a history does: a stream never finished is discarded, so that no
   !> temporary file outlives its history.
   subroutine drop_unfinished_stream(self)
      !> The history
      type(step_history_type), intent(inout) :: self
      if (self%streaming) call self%stream%discard()
      self%streaming = .false.
   end subroutine drop_unfinished_stream

   !> stat = status_out_of_memory, with its message, when the storage in memory could not
   !> grow (the integration should stop); else stat is left as it is.
   subroutine check_memory(self, stat)
      !> The history
      class(step_history_type), intent(in) :: self
      !> Set to the failure, if there was one
      type(status_type), intent(inout) :: stat
      if (len_trim(self%memory_failure) > 0) call set_status(stat, status_out_of_memory, trim(self%memory_failure))
   end subroutine check_memory

   !> Whether a write to the stream has failed (the integration should stop).
   logical function failed(self)
      !> The history
      class(step_history_type), intent(in) :: self
      failed = self%streaming .and. self%stream%io_error /= 0
   end function failed

   !> Write a history kept in memory as CSV: step,t,h,err,outcome,newton_iterations[,u1,...].
   !> The file appears only when it was written completely.
   subroutine write_history_csv(history, filename, stat, replace)
      !> The recorded history
      type(step_history_type), intent(in) :: history
      !> Output file (replaced by a complete new one)
      character(len=*), intent(in) :: filename
      !> status_output_error when the file cannot be written, status_invalid_argument for
      !> a history whose steps are not in memory (it was streamed to a file)
      type(status_type), intent(out) :: stat
      !> Whether a file at filename may be replaced (default true; false: one there when
      !> the file is complete is kept, status_output_error)
      logical, intent(in), optional :: replace
      type(text_file_type) :: file
      real(dp) :: no_state(0)
      integer :: i

      ! (a streamed history counts its rows but keeps none: they were read past the arrays)
      if (history%count > rows_in_memory(history)) then
         call set_status(stat, status_invalid_argument, "write_history_csv: the history keeps no steps in memory "// &
            "(it was streamed to a file)")
         return
      end if
      call file%open(filename, stat, replace)
      if (stat%code /= status_ok) return
      call write_header(file, history%state_columns)
      do i = 1, history%count
         if (history%state_columns > 0) then
            call write_row(file, i, history%t(i), history%h(i), history%err(i), history%outcome(i), &
               history%newton_iterations(i), history%states(:, i))
         else
            call write_row(file, i, history%t(i), history%h(i), history%err(i), history%outcome(i), &
               history%newton_iterations(i), no_state)
         end if
      end do
      call file%commit(stat)
   end subroutine write_history_csv

   !> The attempts a history holds in memory: the rows of its arrays (0 where one is not
   !> allocated; the states' columns too when it records states).
   pure integer function rows_in_memory(history) result(rows)
      type(step_history_type), intent(in) :: history
      rows = 0
      if (.not. (allocated(history%t) .and. allocated(history%h) .and. allocated(history%err) .and. &
         allocated(history%outcome) .and. allocated(history%newton_iterations))) return
      rows = min(size(history%t), size(history%h), size(history%err), size(history%outcome), &
         size(history%newton_iterations))
      if (history%state_columns > 0) then
         if (.not. allocated(history%states)) then
            rows = 0
         else if (size(history%states, 1) < history%state_columns) then
            rows = 0
         else
            rows = min(rows, size(history%states, 2))
         end if
      end if
   end function rows_in_memory

end module taylorode_integrate_history
