!> The problem a user solves: U' = f(t, U) + g(t, U), f non-stiff, g stiff.
!>
!> Users extend `ode_problem` (and write f, g and both Jacobians) or
!> `ode_problem_fd` (and write only f and g: the Jacobians come from finite
!> differences). Parameters of a problem are components of the extended type.
module taylorode_problem
   use taylorode_kinds, only: dp
   implicit none
   private

   public :: ode_problem, ode_problem_fd, test_problem_type, rhs_interface, jacobian_interface

   !> Abstract problem with a non-stiff part f, a stiff part g and their Jacobians
   type, abstract :: ode_problem
   contains
      !> Non-stiff part f(t, U)
      procedure(rhs_interface), deferred :: f
      !> Stiff part g(t, U)
      procedure(rhs_interface), deferred :: g
      !> Jacobian df/dU
      procedure(jacobian_interface), deferred :: jac_f
      !> Jacobian dg/dU
      procedure(jacobian_interface), deferred :: jac_g
   end type ode_problem

   !> Problem whose Jacobians are approximated by forward differences of f and g
   type, abstract, extends(ode_problem) :: ode_problem_fd
   contains
      !> Forward-difference approximation of df/dU
      procedure :: jac_f => fd_jac_f
      !> Forward-difference approximation of dg/dU
      procedure :: jac_g => fd_jac_g
   end type ode_problem_fd

   !> A ready problem of the library's test set: what it is, where it starts and ends,
   !> the tolerances it is meant to be run with and its published solution at t_end
   type, abstract, extends(ode_problem) :: test_problem_type
      !> Name as users type it (e.g. "robertson")
      character(len=:), allocatable :: name
      !> Standard initial time
      real(dp) :: t0 = 0.0_dp
      !> Standard final time
      real(dp) :: t_end = 1.0_dp
      !> Standard initial state
      real(dp), allocatable :: u0(:)
      !> Recommended relative tolerance
      real(dp) :: rtol = 1.0e-6_dp
      !> Recommended absolute tolerance
      real(dp) :: atol = 1.0e-6_dp
      !> Published solution at t_end, when one exists
      real(dp), allocatable :: reference(:)
      !> Where the definition and the reference values come from
      character(len=:), allocatable :: source
   end type test_problem_type

   abstract interface
      !> Right-hand side part: writes f(t, u) or g(t, u) into `dudt`
      subroutine rhs_interface(self, t, u, dudt)
         import :: ode_problem, dp
         !> The problem (carries its parameters)
         class(ode_problem), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> Value of the part at (t, u), same size as u
         real(dp), intent(out) :: dudt(:)
      end subroutine rhs_interface

      !> Jacobian of a part: writes d(part)/dU at (t, u) into `jac` (n x n, jac(i, j) = d part_i / d u_j)
      subroutine jacobian_interface(self, t, u, jac)
         import :: ode_problem, dp
         !> The problem
         class(ode_problem), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> Jacobian matrix, size(u) x size(u)
         real(dp), intent(out) :: jac(:, :)
      end subroutine jacobian_interface
   end interface

contains

   !> Forward-difference Jacobian of f.
   subroutine fd_jac_f(self, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call forward_difference(self, .true., t, u, jac)
   end subroutine fd_jac_f

   !> Forward-difference Jacobian of g.
   subroutine fd_jac_g(self, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call forward_difference(self, .false., t, u, jac)
   end subroutine fd_jac_g

   !> Column-by-column forward differences of f (`of_f`) or g, with the
   !> increment sqrt(eps) * max(|u_j|, 1) that balances truncation and roundoff.
   subroutine forward_difference(self, of_f, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      logical, intent(in) :: of_f
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      real(dp) :: base(size(u)), shifted(size(u)), probe(size(u))
      real(dp) :: increment
      integer :: j
      call evaluate(u, base)
      probe = u
      do j = 1, size(u)
         increment = sqrt(epsilon(1.0_dp))*max(abs(u(j)), 1.0_dp)
         probe(j) = u(j) + increment
         increment = probe(j) - u(j)
         call evaluate(probe, shifted)
         jac(:, j) = (shifted - base)/increment
         probe(j) = u(j)
      end do
   contains
      subroutine evaluate(state, value)
         real(dp), intent(in) :: state(:)
         real(dp), intent(out) :: value(:)
         if (of_f) then
            call self%f(t, state, value)
         else
            call self%g(t, state, value)
         end if
      end subroutine evaluate
   end subroutine forward_difference

end module taylorode_problem
