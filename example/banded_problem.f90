!> A banded problem: Fisher's equation u_t = D u_xx + u (1 - u) on (0, 1), u = 1 at
!> x = 0 and u = 0 at x = 1, by the method of lines on n interior points. The reaction
!> is f, the diffusion g; both Jacobians are tridiagonal, so the problem declares the
!> band (1, 1) and its Newton systems are solved in band storage (n unknowns cost
!> O(n), not O(n^3)). dg/du is written in band storage; df/du comes from grouped
!> forward differences (four evaluations of f for any n: one at u, three perturbed).
module fisher_front
   use taylorode, only: dp, ode_problem_fd, matrix_structure_type, band_structure
   implicit none
   private

   public :: fisher_type

   !> f = u (1 - u), g = D (u(i-1) - 2 u(i) + u(i+1)) / dx^2
   type, extends(ode_problem_fd) :: fisher_type
      real(dp) :: diffusion = 1.0e-3_dp
   contains
      procedure :: f => reaction
      procedure :: g => diffusion_term
      procedure :: jacobian_structure => tridiagonal
      procedure :: jac_g_band => diffusion_band
   end type fisher_type

contains

   subroutine reaction(self, t, u, dudt)
      class(fisher_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = u*(1.0_dp - u)
   end subroutine reaction

   subroutine diffusion_term(self, t, u, dudt)
      class(fisher_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: c
      integer :: n
      n = size(u)
      c = self%diffusion*real(n + 1, dp)**2
      dudt(1) = c*(1.0_dp - 2.0_dp*u(1) + u(2))          ! u = 1 at x = 0
      dudt(2:n - 1) = c*(u(1:n - 2) - 2.0_dp*u(2:n - 1) + u(3:n))
      dudt(n) = c*(u(n - 1) - 2.0_dp*u(n))                ! u = 0 at x = 1
   end subroutine diffusion_term

   !> J(i, j) = 0 for |i - j| > 1, for f and g together
   function tridiagonal(self, n) result(structure)
      class(fisher_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = band_structure(lower=1, upper=1)
   end function tridiagonal

   !> dg/du in LAPACK band storage: band(upper + 1 + i - j, j) = J(i, j), here
   !> band(1, j) = J(j - 1, j), band(2, j) = J(j, j), band(3, j) = J(j + 1, j)
   subroutine diffusion_band(self, t, u, band)
      class(fisher_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      real(dp) :: c
      c = self%diffusion*real(size(u) + 1, dp)**2
      band(1, :) = c                  ! band(1, 1) lies outside the matrix: not used
      band(2, :) = -2.0_dp*c
      band(3, :) = c                  ! band(3, n) likewise
   end subroutine diffusion_band

end module fisher_front

program banded_problem
   use taylorode, only: dp, scheme_type, new_scheme, integrate, integrator_options_type, &
      integration_stats_type, status_type
   use fisher_front, only: fisher_type
   implicit none

   integer, parameter :: n = 500
   type(fisher_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(integration_stats_type) :: stats
   type(status_type) :: stat
   real(dp) :: u(n)
   integer :: front

   u = 0.0_dp
   call new_scheme("i-t-2", scheme, stat)
   if (.not. stat%ok()) error stop stat%message
   call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, integrator_options_type(rtol=1.0e-5_dp, atol=1.0e-7_dp), &
      stats, stat)
   if (.not. stat%ok()) error stop stat%message
   front = count(u > 0.5_dp)
   print '(a, f6.3)', "front (u = 1/2) at t = 10 near x =", real(front, dp)/real(n + 1, dp)
   print '(a, i0, a, i0, a, i0, a, i0)', "unknowns ", n, ", accepted ", stats%accepted_steps, &
      ", LU factorizations ", stats%work%lu_factorizations, ", f evaluations ", stats%work%f_evaluations
end program banded_problem
