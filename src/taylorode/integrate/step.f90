!> One accepted step as observers, events and dense output see it: where it started
!> and ended, the states at both ends, and the dense output between them: the
!> scheme's own continuous extension when it supplies one (radau5: its collocation
!> polynomial, at no extra evaluation); for the other implicit schemes the cubic
!> through the states at the ends of this step and at the starts of the two before
!> (stiff-safe: F at the end of a long stiff step multiplies the state's error in a
!> stiff direction by h |lambda|, and an interpolant through F inherits that; states
!> carry no such factor); for explicit schemes the cubic Hermite interpolant of the
!> states and derivatives F at both ends.
!>
!> The dense output is a polynomial in theta = (t - t_start)/h in Newton form:
!>
!>   u(theta) = c_0 + (theta - x_1) (c_1 + (theta - x_2) (c_2 + ... + (theta - x_d) c_d))
!>
!> with nodes x_1 .. x_d and coefficient vectors c_0 .. c_d (d = `degree`), a form
!> into which every polynomial fits and that costs d multiply-adds per component.
module taylorode_integrate_step
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type
   use taylorode_base_memory, only: out_of_memory, real_bytes
   implicit none
   private

   public :: accepted_step_type, newton_form, hermite_degree, quadratic_degree

   !> Degree of the cubic Hermite interpolant, the dense output of explicit schemes
   integer, parameter :: hermite_degree = 3
   !> Degree of the interpolant through the two ends of a step and one condition more,
   !> the least dense output of implicit schemes that supply none of their own (one
   !> more for each further state)
   integer, parameter :: quadratic_degree = 2

   !> An accepted step [t_start, t_end] of size h
   type :: accepted_step_type
      !> Start, size and end of the step (t_end is exactly the target on a last step)
      real(dp) :: t_start = 0.0_dp, h = 0.0_dp, t_end = 0.0_dp
      !> States at both ends
      real(dp), allocatable :: u_start(:), u_end(:)
      !> Degree of the dense output (0 until a step has one)
      integer :: degree = 0
      !> Nodes x_1 .. x_degree of its Newton form, in theta = (t - t_start)/h
      real(dp), allocatable :: nodes(:)
      !> Coefficient vectors c_0 .. c_degree of its Newton form, one column each
      real(dp), allocatable :: coefficients(:, :)
      !> F = f + g at both ends, which only the cubic Hermite interpolant uses
      !> (not evaluated when the scheme supplies its own dense output)
      real(dp), allocatable :: rhs_start(:), rhs_end(:)
      !> Interpolation points of the dense output, in theta (0:degree; a point repeated
      !> carries a derivative condition): where it matches the scheme's values
      real(dp), allocatable :: points(:)
   contains
      !> The solution at t in [t_start, t_end] from the dense output
      procedure :: interpolate
      !> The cubic Hermite interpolant of u_start, rhs_start, u_end, rhs_end as the dense output
      procedure :: set_hermite
      !> The polynomial through the step's states and up to two before it as the dense output
      procedure :: set_through_states
      !> Estimate of the dense output's error at t from one more state of the solution
      procedure :: interpolation_error
      !> Work arrays for n unknowns and dense output up to a degree (allocated only when they change)
      procedure :: reserve
   end type accepted_step_type

contains

   !> u = the polynomial in Newton form with the given nodes and coefficient
   !> columns coefficients(:, 0:size(nodes)), at theta.
   pure subroutine newton_form(theta, nodes, coefficients, u)
      !> Where to evaluate
      real(dp), intent(in) :: theta
      !> Nodes x_1 .. x_d
      real(dp), intent(in) :: nodes(:)
      !> Coefficient vectors c_0 .. c_d (at least d + 1 columns)
      real(dp), intent(in) :: coefficients(:, 0:)
      !> Value
      real(dp), intent(out) :: u(:)
      integer :: k
      u = coefficients(:, size(nodes))
      do k = size(nodes), 1, -1
         u = coefficients(:, k - 1) + (theta - nodes(k))*u
      end do
   end subroutine newton_form

   !> The solution at t (clamped to the step) from the dense output: continuous across
   !> steps, with the accuracy of the scheme's continuous extension (radau5: the stage
   !> order 3) or of the cubic Hermite interpolant (third order).
   pure subroutine interpolate(self, t, u)
      !> The step
      class(accepted_step_type), intent(in) :: self
      !> Time inside the step
      real(dp), intent(in) :: t
      !> Interpolated state
      real(dp), intent(out) :: u(:)
      if (t >= self%t_end) then
         u = self%u_end
         return
      end if
      call newton_form(max(0.0_dp, (t - self%t_start)/self%h), self%nodes(:self%degree), self%coefficients, u)
   end subroutine interpolate

   !> The cubic Hermite interpolant of (u_start, h rhs_start) and (u_end, h rhs_end) as
   !> the dense output: nodes 0, 0, 1 (a double node at the start carries the slope).
   pure subroutine set_hermite(self)
      !> The step, with its states and derivatives at both ends
      class(accepted_step_type), intent(inout) :: self
      integer :: i
      real(dp) :: slope_start, slope_end, secant
      self%degree = hermite_degree
      self%nodes(1:3) = [0.0_dp, 0.0_dp, 1.0_dp]
      self%points(0:3) = [0.0_dp, 0.0_dp, 1.0_dp, 1.0_dp]
      do i = 1, size(self%u_start)
         slope_start = self%h*self%rhs_start(i)
         slope_end = self%h*self%rhs_end(i)
         secant = self%u_end(i) - self%u_start(i)
         self%coefficients(i, 0) = self%u_start(i)
         self%coefficients(i, 1) = slope_start
         self%coefficients(i, 2) = secant - slope_start
         self%coefficients(i, 3) = slope_start + slope_end - 2.0_dp*secant
      end do
   end subroutine set_hermite

   !> The polynomial through the states at the ends of the step and at the starts of
   !> up to two steps before (t_before > t_before2) as the dense output: the cubic
   !> through four states, or the quadratic through three, or, with no state before,
   !> the quadratic through the two ends with the slope rhs_start at the start. It uses
   !> no F at the end of the step, where F of a stiff step is unreliable (it multiplies
   !> the state's error in a stiff direction by h |lambda|); states carry no such factor.
   pure subroutine set_through_states(self, t_before, u_before, t_before2, u_before2)
      !> The step, with its states (and rhs_start when no state before is given)
      class(accepted_step_type), intent(inout) :: self
      !> Start of the step before and the state there
      real(dp), intent(in), optional :: t_before, u_before(:)
      !> Start of the step before that one and the state there
      real(dp), intent(in), optional :: t_before2, u_before2(:)
      integer :: i, before
      real(dp) :: theta(2), secant, first, second, third
      before = 0
      if (present(u_before)) before = merge(2, 1, present(u_before2))
      self%degree = quadratic_degree + max(before - 1, 0)
      if (before >= 1) theta(1) = (t_before - self%t_start)/self%h
      if (before == 2) theta(2) = (t_before2 - self%t_start)/self%h
      if (before == 0) then
         self%nodes(1:2) = [0.0_dp, 0.0_dp]
         self%points(0:2) = [0.0_dp, 0.0_dp, 1.0_dp]
      else
         ! Newton form over the points 0, 1, theta(1), theta(2): its nodes 0, 1 (and theta(1)
         ! for the cubic); entry by entry, as an array constructor of the points' variable
         ! length went through a temporary allocated at every step
         self%nodes(1) = 0.0_dp
         self%nodes(2) = 1.0_dp
         self%points(0) = 0.0_dp
         self%points(1) = 1.0_dp
         self%points(2) = theta(1)
         if (before == 2) then
            self%nodes(3) = theta(1)
            self%points(3) = theta(2)
         end if
      end if
      do i = 1, size(self%u_start)
         secant = self%u_end(i) - self%u_start(i)
         self%coefficients(i, 0) = self%u_start(i)
         if (before == 0) then
            ! u_start + theta (h rhs_start + theta (secant - h rhs_start))
            self%coefficients(i, 1) = self%h*self%rhs_start(i)
            self%coefficients(i, 2) = secant - self%h*self%rhs_start(i)
            cycle
         end if
         self%coefficients(i, 1) = secant
         ! divided differences f[1, theta1] and f[0, 1, theta1]
         first = (u_before(i) - self%u_end(i))/(theta(1) - 1.0_dp)
         second = (first - secant)/theta(1)
         self%coefficients(i, 2) = second
         if (before == 2) then
            ! f[theta1, theta2], f[1, theta1, theta2], then f[0, 1, theta1, theta2]
            third = (u_before2(i) - u_before(i))/(theta(2) - theta(1))
            third = (third - first)/(theta(2) - 1.0_dp)
            self%coefficients(i, 3) = (third - second)/theta(2)
         end if
      end do
   end subroutine set_through_states

   !> The error of the dense output at t estimated from one more state u_extra of the
   !> solution at t_extra (before the step): the next term of the interpolant's Newton
   !> series, c (theta - x_0) ... (theta - x_d), c the divided difference over its
   !> points x_j and theta_extra, c = (u_extra - p(theta_extra)) / prod_j (theta_extra - x_j).
   pure subroutine interpolation_error(self, t, t_extra, u_extra, error)
      !> The step, with its dense output
      class(accepted_step_type), intent(in) :: self
      !> Where the error is wanted (inside the step)
      real(dp), intent(in) :: t
      !> Time of the extra state (not an interpolation point) and the state
      real(dp), intent(in) :: t_extra, u_extra(:)
      !> The estimate
      real(dp), intent(out) :: error(:)
      real(dp) :: theta, theta_extra, factor
      integer :: j
      theta = (t - self%t_start)/self%h
      theta_extra = (t_extra - self%t_start)/self%h
      factor = 1.0_dp
      do j = 0, self%degree
         factor = factor*(theta - self%points(j))/(theta_extra - self%points(j))
      end do
      call newton_form(theta_extra, self%nodes(:self%degree), self%coefficients, error)
      error = factor*(u_extra - error)
   end subroutine interpolation_error

   !> Work arrays for n unknowns and dense output up to degree max_degree (at least
   !> the cubic Hermite interpolant's).
   subroutine reserve(self, n, max_degree, stat)
      !> The step
      class(accepted_step_type), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      !> Largest degree of the scheme's own dense output (0: none)
      integer, intent(in) :: max_degree
      !> status_out_of_memory when the arrays cannot be allocated (none is then)
      type(status_type), intent(inout) :: stat
      integer :: degree, memory
      degree = max(hermite_degree, max_degree)
      if (allocated(self%coefficients)) then
         if (size(self%u_start) == n .and. size(self%nodes) == degree) return
      end if
      call release()
      allocate (self%u_start(n), self%u_end(n), self%rhs_start(n), self%rhs_end(n), self%nodes(degree), &
         self%points(0:degree), self%coefficients(n, 0:degree), stat=memory)
      if (memory /= 0) then
         call release()
         call out_of_memory(stat, "the states and the dense output of a step", [5 + degree, n], real_bytes)
      end if
      self%degree = 0
   contains
      !> Every array deallocated (after a failed allocation, some may be allocated)
      subroutine release()
         if (allocated(self%u_start)) deallocate (self%u_start)
         if (allocated(self%u_end)) deallocate (self%u_end)
         if (allocated(self%rhs_start)) deallocate (self%rhs_start)
         if (allocated(self%rhs_end)) deallocate (self%rhs_end)
         if (allocated(self%nodes)) deallocate (self%nodes)
         if (allocated(self%points)) deallocate (self%points)
         if (allocated(self%coefficients)) deallocate (self%coefficients)
      end subroutine release
   end subroutine reserve

end module taylorode_integrate_step
