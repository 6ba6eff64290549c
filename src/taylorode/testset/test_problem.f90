!> What makes a problem part of the test set: its name, span, initial state,
!> recommended tolerances and published solution.
module taylorode_testset_test_problem
   use taylorode_base_kinds, only: dp
   use taylorode_problem_ode, only: ode_problem
   implicit none
   private

   public :: test_problem_type, unpack_band

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
      !> Whether every component must stay >= 0 (concentrations): the equations are
      !> unstable where one is negative, so run with options%nonnegative set for all
      logical :: nonnegative = .false.
   end type test_problem_type

contains

   !> The dense matrix of a band in LAPACK storage with bandwidths lower and upper (for
   !> the banded problems' Jacobians and mass matrices asked for dense):
   !> dense(i, j) = band(upper + 1 + i - j, j), zero outside the band.
   pure subroutine unpack_band(lower, upper, band, dense)
      !> Lower and upper bandwidths
      integer, intent(in) :: lower, upper
      !> The band
      real(dp), intent(in) :: band(:, :)
      !> The dense matrix
      real(dp), intent(out) :: dense(:, :)
      integer :: i, j
      dense = 0.0_dp
      do j = 1, size(dense, 2)
         do i = max(1, j - upper), min(size(dense, 1), j + lower)
            dense(i, j) = band(upper + 1 + i - j, j)
         end do
      end do
   end subroutine unpack_band

end module taylorode_testset_test_problem
