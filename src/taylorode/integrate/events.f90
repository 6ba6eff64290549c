!> Events are user functions e_i(t, U) whose zero crossings are located on the dense
!> output of each accepted step (the scheme's own, else the cubic Hermite
!> interpolant) by the Illinois variant of regula falsi, with a direction filter
!> (rising, falling or both) and a terminal flag (the integration stops at the first terminal crossing, at the
!> located time and interpolated state). Crossings are returned with their times
!> and states, in time order, as CVODE's root finding, scipy's `events` and Julia's
!> callbacks do.
module taylorode_integrate_events
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, status_nonfinite
   use taylorode_base_memory, only: sized, out_of_memory, real_bytes
   use taylorode_integrate_step, only: accepted_step_type
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: event_functions_type, event_rising, event_falling, event_any

   !> Direction of a crossing to report: from negative to positive values ...
   integer, parameter :: event_rising = 1
   !> ... from positive to negative values ...
   integer, parameter :: event_falling = -1
   !> ... or both
   integer, parameter :: event_any = 0
   !> Default accuracy of a located time, relative to the step size
   real(dp), parameter :: default_relative_accuracy = 1.0e-12_dp
   !> Regula falsi iterations before the bracket is taken as it is
   integer, parameter :: max_root_iterations = 200

   !> Extend it, set `count`, `direction` and `terminal`, write `evaluate`; after the
   !> integration `found` crossings are in found_index, found_t and found_u.
   type, abstract :: event_functions_type
      !> Number of event functions
      integer :: count = 0
      !> Per function: event_rising, event_falling or event_any (default: any)
      integer, allocatable :: direction(:)
      !> Per function: stop the integration at its first crossing (default: no)
      logical, allocatable :: terminal(:)
      !> Absolute accuracy of the located times (0: 1e-12 times the step size)
      real(dp) :: time_tolerance = 0.0_dp
      !> Crossings found so far
      integer :: found = 0
      !> Which function crossed, one entry per crossing
      integer, allocatable :: found_index(:)
      !> When it crossed, and the state there (one column per crossing)
      real(dp), allocatable :: found_t(:), found_u(:, :)
      !> The index of the terminal function that stopped the last integration (0: none)
      integer :: stopped_by = 0
      !> Values at the start of the current step and at a probe
      real(dp), allocatable, private :: values_start(:), values_end(:), values_probe(:), u_probe(:)
      !> Crossing times inside the current step, and which functions crossed
      real(dp), allocatable, private :: crossing_t(:)
      !> Where in the current step (fraction of h) each function's bracket starts: 0,
      !> or just after a start exactly at a root (the root of the last terminal stop)
      real(dp), allocatable, private :: theta_start(:)
      logical, allocatable, private :: crossed(:)
   contains
      !> Values of every event function at (t, u)
      procedure(event_values_interface), deferred :: evaluate
      !> Begin (or continue) an integration at (t, u)
      procedure, non_overridable :: start
      !> Find the crossings inside an accepted step; true when a terminal one stops it
      procedure, non_overridable :: check_step
      !> Forget the crossings found so far
      procedure, non_overridable :: clear
   end type event_functions_type

   abstract interface
      !> values(i) = e_i(t, u), i = 1 .. count
      subroutine event_values_interface(self, t, u, values)
         import :: event_functions_type, dp
         !> The event functions (carry your data)
         class(event_functions_type), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> One value per event function
         real(dp), intent(out) :: values(:)
      end subroutine event_values_interface
   end interface

contains

   !> Begin or continue an integration at (t, u): check the settings, size the work
   !> arrays and evaluate the functions there. A function that a terminal crossing
   !> just stopped at counts as exactly zero, so that it is not found again.
   subroutine start(self, t, u, stat)
      !> The event functions
      class(event_functions_type), intent(inout) :: self
      !> Time and state where the integration (re)starts
      real(dp), intent(in) :: t, u(:)
      !> status_invalid_argument for inconsistent settings, status_nonfinite for NaN values
      type(status_type), intent(inout) :: stat
      integer :: previous_stop
      if (self%count < 0) then
         call set_status(stat, status_invalid_argument, "events: count must be >= 0")
         return
      end if
      if (.not. allocated(self%direction)) allocate (self%direction(self%count), source=event_any)
      if (.not. allocated(self%terminal)) allocate (self%terminal(self%count), source=.false.)
      if (size(self%direction) /= self%count .or. size(self%terminal) /= self%count) then
         call set_status(stat, status_invalid_argument, "events: direction and terminal need one entry per function")
         return
      end if
      if (any(abs(self%direction) > 1)) then
         call set_status(stat, status_invalid_argument, "events: direction must be event_rising, event_falling "// &
            "or event_any")
         return
      end if
      if (.not. (ieee_is_finite(self%time_tolerance) .and. self%time_tolerance >= 0.0_dp)) then
         call set_status(stat, status_invalid_argument, "events: time_tolerance must be finite and >= 0")
         return
      end if
      if (allocated(self%values_start)) then
         if (size(self%values_start) /= self%count) then
            deallocate (self%values_start, self%values_end, self%values_probe, self%crossing_t, &
               self%crossed, self%theta_start)
         end if
      end if
      ! one value per event function: a few bytes each
      if (.not. allocated(self%values_start)) then
         allocate (self%values_start(self%count), self%values_end(self%count), self%values_probe(self%count), &
            self%crossing_t(self%count), self%crossed(self%count), self%theta_start(self%count))
      end if
      call sized(self%u_probe, size(u), "the events' probe state", stat)
      if (stat%code /= status_ok) return
      previous_stop = self%stopped_by
      self%stopped_by = 0
      if (self%count == 0) return
      call self%evaluate(t, u, self%values_start)
      if (.not. all(ieee_is_finite(self%values_start))) then
         call set_status(stat, status_nonfinite, "events: an event function is NaN or Inf at the start")
         return
      end if
      if (previous_stop > 0) then
         if (self%found > 0) then
            if (self%found_t(self%found) == t) self%values_start(previous_stop) = 0.0_dp
         end if
      end if
   end subroutine start

   !> Forget the crossings found so far.
   subroutine clear(self)
      !> The event functions
      class(event_functions_type), intent(inout) :: self
      self%found = 0
      self%stopped_by = 0
   end subroutine clear

   !> Find the crossings inside an accepted step (with its dense output),
   !> record them in time order and say whether a terminal one stops the integration;
   !> then t_stop and u_stop are where it stops.
   subroutine check_step(self, step, stop, t_stop, u_stop, stat)
      !> The event functions
      class(event_functions_type), intent(inout) :: self
      !> The accepted step
      type(accepted_step_type), intent(in) :: step
      !> Whether a terminal crossing stops the integration inside the step
      logical, intent(out) :: stop
      !> When it stops
      real(dp), intent(out) :: t_stop
      !> The state there, from the step's interpolant
      real(dp), intent(inout) :: u_stop(:)
      !> status_nonfinite when an event function is NaN or Inf
      type(status_type), intent(inout) :: stat
      integer :: i, first
      real(dp) :: earliest

      stop = .false.
      t_stop = step%t_end
      if (self%count == 0) return
      call self%evaluate(step%t_end, step%u_end, self%values_end)
      if (.not. all(ieee_is_finite(self%values_end))) then
         call set_status(stat, status_nonfinite, "events: an event function is NaN or Inf")
         return
      end if
      call leave_roots(self, step)
      do i = 1, self%count
         self%crossed(i) = crosses(self%values_start(i), self%values_end(i), self%direction(i))
         if (self%crossed(i)) self%crossing_t(i) = locate(self, step, i)
      end do
      ! the first terminal crossing ends the step there
      first = 0
      earliest = huge(1.0_dp)
      do i = 1, self%count
         if (self%crossed(i) .and. self%terminal(i)) then
            if (self%crossing_t(i) < earliest) then
               earliest = self%crossing_t(i)
               first = i
            end if
         end if
      end do
      if (first > 0) then
         stop = .true.
         t_stop = earliest
         do i = 1, self%count
            if (self%crossed(i) .and. self%crossing_t(i) > earliest) self%crossed(i) = .false.
            if (self%crossed(i) .and. self%terminal(i) .and. i /= first) self%crossed(i) = .false.
         end do
         self%stopped_by = first
      end if
      call record_in_time_order(self, step, stat)
      if (stat%code /= status_ok) return
      if (stop) then
         call step%interpolate(t_stop, u_stop)
      else
         self%values_start = self%values_end
      end if
   end subroutine check_step

   !> A function exactly zero at the start of the step (where the last terminal stop
   !> found its root) takes its sign from just inside the step (a probe 1e-8 of the
   !> step in, on the interpolant), so that a crossing later in the same step (a ball
   !> that rises from the ground and falls back within one step) is found and the
   !> root at the start is not found again.
   subroutine leave_roots(self, step)
      class(event_functions_type), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      real(dp), parameter :: probe_fraction = 1.0e-8_dp
      logical :: probed
      integer :: i
      self%theta_start = 0.0_dp
      probed = .false.
      do i = 1, self%count
         if (self%values_start(i) /= 0.0_dp) cycle
         if (.not. probed) then
            call step%interpolate(step%t_start + probe_fraction*step%h, self%u_probe)
            call self%evaluate(step%t_start + probe_fraction*step%h, self%u_probe, self%values_probe)
            probed = .true.
         end if
         if (.not. ieee_is_finite(self%values_probe(i))) cycle
         self%values_start(i) = self%values_probe(i)
         self%theta_start(i) = probe_fraction
      end do
   end subroutine leave_roots

   !> Whether the value goes from a to b across zero in the wanted direction (a
   !> start exactly at zero was found at the previous step's end).
   pure logical function crosses(a, b, direction)
      real(dp), intent(in) :: a, b
      integer, intent(in) :: direction
      crosses = .false.
      if (a < 0.0_dp .and. b >= 0.0_dp) crosses = direction /= event_falling
      if (a > 0.0_dp .and. b <= 0.0_dp) crosses = direction /= event_rising
   end function crosses

   !> The crossing time of function i inside the step: Illinois regula falsi on the
   !> interpolant, to time_tolerance (or 1e-12 of the step).
   real(dp) function locate(self, step, i) result(t_root)
      class(event_functions_type), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      integer, intent(in) :: i
      real(dp) :: theta_a, theta_b, value_a, value_b, theta, value, accuracy
      integer :: iteration, side

      theta_a = self%theta_start(i)
      theta_b = 1.0_dp
      value_a = self%values_start(i)
      value_b = self%values_end(i)
      accuracy = default_relative_accuracy
      if (self%time_tolerance > 0.0_dp) accuracy = max(self%time_tolerance/step%h, epsilon(1.0_dp))
      side = 0
      do iteration = 1, max_root_iterations
         if (theta_b - theta_a <= accuracy .or. value_b == 0.0_dp) exit
         theta = theta_b - value_b*(theta_b - theta_a)/(value_b - value_a)
         theta = min(max(theta, theta_a + 0.25_dp*accuracy), theta_b - 0.25_dp*accuracy)
         call step%interpolate(step%t_start + theta*step%h, self%u_probe)
         call self%evaluate(step%t_start + theta*step%h, self%u_probe, self%values_probe)
         value = self%values_probe(i)
         if (.not. ieee_is_finite(value)) exit
         if (sign(1.0_dp, value) == sign(1.0_dp, value_b) .and. value /= 0.0_dp) then
            theta_b = theta
            value_b = value
            if (side == 1) value_a = 0.5_dp*value_a
            side = 1
         else
            theta_a = theta
            value_a = value
            if (side == -1) value_b = 0.5_dp*value_b
            side = -1
            if (value == 0.0_dp) then
               theta_b = theta
               value_b = 0.0_dp
            end if
         end if
      end do
      t_root = min(step%t_start + theta_b*step%h, step%t_end)
   end function locate

   !> Append the crossings marked in `crossed` in the order of their times.
   subroutine record_in_time_order(self, step, stat)
      class(event_functions_type), intent(inout) :: self
      type(accepted_step_type), intent(in) :: step
      type(status_type), intent(inout) :: stat
      integer :: i, next
      real(dp) :: earliest
      do
         next = 0
         earliest = huge(1.0_dp)
         do i = 1, self%count
            if (self%crossed(i) .and. self%crossing_t(i) < earliest) then
               earliest = self%crossing_t(i)
               next = i
            end if
         end do
         if (next == 0) exit
         self%crossed(next) = .false.
         call append(self, next, earliest, step, stat)
         if (stat%code /= status_ok) return
      end do
   end subroutine record_in_time_order

   !> Record one crossing (storage grows geometrically; allocation happens only when
   !> events are found). status_out_of_memory, with what was found kept, when the
   !> storage cannot grow.
   subroutine append(self, index, t, step, stat)
      class(event_functions_type), intent(inout) :: self
      integer, intent(in) :: index
      real(dp), intent(in) :: t
      type(accepted_step_type), intent(in) :: step
      type(status_type), intent(inout) :: stat
      integer, allocatable :: index_buffer(:)
      real(dp), allocatable :: t_buffer(:), u_buffer(:, :)
      integer :: capacity, n, memory
      n = size(step%u_end)
      capacity = 0
      if (.not. allocated(self%found_t)) then
         capacity = 16
      else if (self%found == size(self%found_t) .or. size(self%found_u, 1) /= n) then
         capacity = max(16, 2*size(self%found_t))
      end if
      if (capacity > 0) then
         allocate (index_buffer(capacity), t_buffer(capacity), u_buffer(n, capacity), stat=memory)
         if (memory /= 0) then
            call out_of_memory(stat, "the events found", [n + 2, capacity], real_bytes)
            return
         end if
         if (.not. allocated(self%found_t)) then
            self%found = 0
         else if (size(self%found_u, 1) == n) then
            index_buffer(:self%found) = self%found_index(:self%found)
            t_buffer(:self%found) = self%found_t(:self%found)
            u_buffer(:, :self%found) = self%found_u(:, :self%found)
         else
            self%found = 0
         end if
         call move_alloc(index_buffer, self%found_index)
         call move_alloc(t_buffer, self%found_t)
         call move_alloc(u_buffer, self%found_u)
      end if
      self%found = self%found + 1
      self%found_index(self%found) = index
      self%found_t(self%found) = t
      call step%interpolate(t, self%found_u(:, self%found))
   end subroutine append

end module taylorode_integrate_events
