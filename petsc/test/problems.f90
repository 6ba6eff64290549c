!> The problem of the order tests: one Fourier mode shrinking under a nonlinear,
!> non-local reaction,
!>
!>   U' = f(U) + g(U),   f(U) = -beta <U, U> U,   g(U) = D Laplacian_h U,
!>
!> with <u, v> = hx hy sum u v over every rank's points. From U(0) = a0 m, m = sin(pi x)
!> sin(pi y) (an eigenvector of Laplacian_h, eigenvalue lambda / D), the solution stays
!> U(t) = a(t) m with a' = lambda a - c a^3, c = beta <m, m>, a Bernoulli equation:
!>
!>   a(t) = (c/lambda + (1/a0^2 - c/lambda) exp(-2 lambda t))^(-1/2),
!>
!> the exact solution of the semi-discrete system itself, so the error of a run is the
!> scheme's alone. The system is autonomous, nonlinear in f (through a sum over the
!> ranks), stiff in g, and never leaves the span of m: the stiff modes stay at zero.
module test_petsc_problems
   use taylorode, only: dp, status_type, status_ok, reduce_sum
   use taylorode_petsc, only: reaction_diffusion_type, new_reaction_diffusion
   implicit none
   private

   public :: shrinking_mode_type, new_shrinking_mode

   real(dp), parameter :: pi = acos(-1.0_dp)

   !> One shrinking mode on a distributed grid
   type, extends(reaction_diffusion_type) :: shrinking_mode_type
      !> Strength of the reaction and the initial amplitude
      real(dp) :: beta = 40.0_dp, amplitude = 1.0_dp
      !> lambda (D times the eigenvalue of m) and <m, m>
      real(dp) :: lambda = 0.0_dp, mass = 0.0_dp
      !> m at the owned points
      real(dp), allocatable :: mode(:)
   contains
      procedure :: f => shrinking_f
      procedure :: jvp_f => shrinking_jvp_f
      !> U(t) at the owned points
      procedure :: exact
   end type shrinking_mode_type

contains

   !> The problem on points x points interior points over every rank.
   subroutine new_shrinking_mode(problem, points, stat)
      type(shrinking_mode_type), intent(inout) :: problem
      integer, intent(in) :: points
      type(status_type), intent(out) :: stat
      real(dp) :: sums(1)
      integer :: i, j, p
      call new_reaction_diffusion(problem%reaction_diffusion_type, points, points, .false., stat, decay=0.0_dp)
      if (stat%code /= status_ok) return
      problem%lambda = -problem%diffusion*(4.0_dp/problem%hx**2*sin(0.5_dp*pi*problem%hx)**2 + &
         4.0_dp/problem%hy**2*sin(0.5_dp*pi*problem%hy)**2)
      associate (grid => problem%grid)
         if (allocated(problem%mode)) deallocate (problem%mode)
         allocate (problem%mode(grid%owned))
         do j = grid%ys, grid%ys + grid%ym - 1
            do i = grid%xs, grid%xs + grid%xm - 1
               p = (i - grid%xs) + grid%xm*(j - grid%ys) + 1
               problem%mode(p) = sin(pi*real(i + 1, dp)*problem%hx)*sin(pi*real(j + 1, dp)*problem%hy)
            end do
         end do
      end associate
      sums(1) = problem%hx*problem%hy*sum(problem%mode**2)
      call problem%reduce(reduce_sum, sums)
      problem%mass = sums(1)
   end subroutine new_shrinking_mode

   !> U(t) = a(t) m.
   subroutine exact(self, t, u)
      class(shrinking_mode_type), intent(in) :: self
      real(dp), intent(in) :: t
      real(dp), intent(out) :: u(:)
      real(dp) :: ratio
      ratio = self%beta*self%mass/self%lambda
      u = self%mode/sqrt(ratio + (1.0_dp/self%amplitude**2 - ratio)*exp(-2.0_dp*self%lambda*t))
   end subroutine exact

   !> <u, v> over every rank.
   real(dp) function inner(self, u, v)
      class(shrinking_mode_type), intent(inout) :: self
      real(dp), intent(in) :: u(:), v(:)
      real(dp) :: sums(1)
      sums(1) = self%hx*self%hy*dot_product(u, v)
      call self%reduce(reduce_sum, sums)
      inner = sums(1)
   end function inner

   !> f(U) = -beta <U, U> U.
   subroutine shrinking_f(self, t, u, dudt)
      class(shrinking_mode_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -self%beta*inner(self, u, u)*u
   end subroutine shrinking_f

   !> J_f v = -beta (<U, U> v + 2 <U, v> U).
   subroutine shrinking_jvp_f(self, t, u, v, jv)
      class(shrinking_mode_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:), v(:)
      real(dp), intent(out) :: jv(:)
      real(dp) :: uu, uv
      uu = inner(self, u, u)
      uv = inner(self, u, v)
      jv = -self%beta*(uu*v + 2.0_dp*uv*u)
   end subroutine shrinking_jvp_f

end module test_petsc_problems
