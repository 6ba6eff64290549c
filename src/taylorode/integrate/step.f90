!> One accepted step as observers, events and dense output see it: where it started
!> and ended, the states at both ends, and the dense output between them: the
!> scheme's own continuous extension when it supplies one (radau5: its collocation
!> polynomial, at no extra evaluation); for the other implicit schemes the quadratic
!> through the states at the ends of this step and at the start of the one before
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
   implicit none
   private

   public :: accepted_step_type, newton_form, hermite_degree, quadratic_degree

   !> Degree of the cubic Hermite interpolant, the dense output of explicit schemes
   integer, parameter :: hermite_degree = 3
   !> Degree of the interpolant through three states, the dense output of implicit
   !> schemes that supply none of their own
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
      !> Start of the step before (t_before < t_start), for the quadratic through three states
      real(dp) :: t_before = 0.0_dp
      !> State at t_before
      real(dp), allocatable :: u_before(:)
   contains
      !> The solution at t in [t_start, t_end] from the dense output
      procedure :: interpolate
      !> The cubic Hermite interpolant of u_start, rhs_start, u_end, rhs_end as the dense output
      procedure :: set_hermite
      !> The quadratic through u_before, u_start, u_end (or u_start, rhs_start, u_end) as the dense output
      procedure :: set_quadratic
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

   !> The quadratic through (t_before, u_before), (t_start, u_start) and (t_end, u_end)
   !> as the dense output (nodes 0, 1), or, when no state before is known, the one
   !> through u_start and u_end with the slope rhs_start at the start. Its error is
   !> O(h^3), the local error of a second-order step, and it uses no F at the end of
   !> the step, where F of a stiff step is unreliable.
   pure subroutine set_quadratic(self, before_known)
      !> The step, with its states (and rhs_start when no state before is known)
      class(accepted_step_type), intent(inout) :: self
      !> Whether u_before and t_before hold the start of the step before
      logical, intent(in) :: before_known
      integer :: i
      real(dp) :: ratio, secant
      self%degree = quadratic_degree
      self%nodes(1:2) = [0.0_dp, 1.0_dp]
      ratio = 0.0_dp
      if (before_known) ratio = (self%t_start - self%t_before)/self%h
      do i = 1, size(self%u_start)
         secant = self%u_end(i) - self%u_start(i)
         self%coefficients(i, 0) = self%u_start(i)
         self%coefficients(i, 1) = secant
         if (before_known) then
            ! second divided difference over theta = -ratio, 0, 1
            self%coefficients(i, 2) = (secant - (self%u_start(i) - self%u_before(i))/ratio)/(1.0_dp + ratio)
         else
            ! the slope at theta = 0 is h rhs_start
            self%coefficients(i, 2) = secant - self%h*self%rhs_start(i)
         end if
      end do
   end subroutine set_quadratic

   !> Work arrays for n unknowns and dense output up to degree max_degree (at least
   !> the cubic Hermite interpolant's).
   pure subroutine reserve(self, n, max_degree)
      !> The step
      class(accepted_step_type), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      !> Largest degree of the scheme's own dense output (0: none)
      integer, intent(in) :: max_degree
      integer :: degree
      degree = max(hermite_degree, max_degree)
      if (allocated(self%u_start)) then
         if (size(self%u_start) == n .and. size(self%nodes) == degree) return
         deallocate (self%u_start, self%u_end, self%rhs_start, self%rhs_end, self%u_before, self%nodes, &
            self%coefficients)
      end if
      allocate (self%u_start(n), self%u_end(n), self%rhs_start(n), self%rhs_end(n), self%u_before(n), &
         self%nodes(degree), self%coefficients(n, 0:degree))
      self%degree = 0
   end subroutine reserve

end module taylorode_integrate_step
