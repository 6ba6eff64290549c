!> A 2D reaction-diffusion problem on a rectangle (the unit square by default),
!> distributed over the ranks:
!>
!>   U' = f(U) + g(U),   f(U) = U (1 - U),   g(U) = D Laplacian_h U - kappa U^3,
!>
!> on nx x ny interior points with U = 0 on the boundary (five-point Laplacian), from a
!> bump in every unit square of the rectangle. g (the diffusion and a stiff cubic decay) is the stiff part, the logistic
!> growth f the non-stiff one. A problem with other reactions extends it and overrides
!> f and jvp_f (and the stiff part's decay may be set to zero).
!>
!> On one rank the problem is also an ordinary banded problem (natural order,
!> bandwidths nx), so the library's own schemes run it as they run any other.
module taylorode_petsc_reaction_diffusion
   use taylorode, only: dp, status_type, status_ok, matrix_structure_type, band_structure, dense_structure
   use taylorode_petsc_calls, only: new_grid, stencil_center, stencil_west, stencil_east, stencil_south, &
      stencil_north
   use taylorode_petsc_grid_problem, only: grid_problem_type
   implicit none
   private

   public :: reaction_diffusion_type, new_reaction_diffusion

   !> The reaction-diffusion problem on this rank's part of the grid
   type, extends(grid_problem_type) :: reaction_diffusion_type
      !> Diffusion coefficient D and cubic decay rate kappa
      real(dp) :: diffusion = 1.0_dp, decay = 10.0_dp
      !> Grid spacings
      real(dp) :: hx = 0.0_dp, hy = 0.0_dp
      !> Owned-plus-ghost values of the state and of a direction
      real(dp), allocatable, private :: ghosted(:), ghosted_direction(:)
   contains
      procedure :: f => rd_f
      procedure :: g => rd_g
      procedure :: jvp_f => rd_jvp_f
      procedure :: jvp_g => rd_jvp_g
      procedure :: jac_g_stencil => rd_stencil
      procedure :: jacobian_structure => rd_structure
      procedure :: jac_f_band => rd_jac_f_band
      procedure :: jac_g_band => rd_jac_g_band
      !> The initial state at the owned points
      procedure :: initial_state
      !> Release the grid
      procedure :: destroy
   end type reaction_diffusion_type

contains

   !> The problem on nx x ny interior points over every rank (alone = .false.) or on
   !> this rank alone: on the unit square, or with grid spacing `spacing` in both
   !> directions on [0, (nx + 1) spacing] x [0, (ny + 1) spacing] (a domain that grows
   !> with the grid, as weak scaling wants).
   subroutine new_reaction_diffusion(problem, nx, ny, alone, stat, diffusion, decay, spacing)
      !> The problem
      type(reaction_diffusion_type), intent(inout) :: problem
      !> Interior points in x and y
      integer, intent(in) :: nx, ny
      !> On this rank alone
      logical, intent(in) :: alone
      !> Outcome
      type(status_type), intent(out) :: stat
      !> D and kappa (default 1 and 10)
      real(dp), intent(in), optional :: diffusion, decay
      !> Grid spacing in both directions (default: that of the unit square)
      real(dp), intent(in), optional :: spacing
      call new_grid(problem%grid, nx, ny, alone, stat)
      if (stat%code /= status_ok) return
      problem%autonomous = .true.
      if (present(diffusion)) problem%diffusion = diffusion
      if (present(decay)) problem%decay = decay
      problem%hx = 1.0_dp/real(nx + 1, dp)
      problem%hy = 1.0_dp/real(ny + 1, dp)
      if (present(spacing)) then
         problem%hx = spacing
         problem%hy = spacing
      end if
      if (allocated(problem%ghosted)) deallocate (problem%ghosted, problem%ghosted_direction)
      allocate (problem%ghosted(problem%grid%gxm*problem%grid%gym), &
         problem%ghosted_direction(problem%grid%gxm*problem%grid%gym))
   end subroutine new_reaction_diffusion

   !> A bump 0.8 exp(-40 |(x, y) - (0.4, 0.6)|^2) in every unit square (y taken modulo 1)
   !> at the owned points.
   subroutine initial_state(self, u)
      !> The problem
      class(reaction_diffusion_type), intent(in) :: self
      !> U(0) at the owned points
      real(dp), intent(out) :: u(:)
      integer :: i, j, p
      real(dp) :: x, y
      associate (grid => self%grid)
         do j = grid%ys, grid%ys + grid%ym - 1
            do i = grid%xs, grid%xs + grid%xm - 1
               p = (i - grid%xs) + grid%xm*(j - grid%ys) + 1
               x = real(i + 1, dp)*self%hx
               y = real(j + 1, dp)*self%hy
               u(p) = 0.8_dp*exp(-40.0_dp*((x - 0.4_dp)**2 + (y - aint(y) - 0.6_dp)**2))
            end do
         end do
      end associate
   end subroutine initial_state

   !> f(U) = U (1 - U).
   subroutine rd_f(self, t, u, dudt)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = u*(1.0_dp - u)
   end subroutine rd_f

   !> g(U) = D Laplacian_h U - kappa U^3.
   subroutine rd_g(self, t, u, dudt)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      call self%grid%exchange(u, self%ghosted)
      call laplacian(self, self%ghosted, dudt)
      dudt = self%diffusion*dudt - self%decay*u**3
   end subroutine rd_g

   !> J_f v = (1 - 2U) v.
   subroutine rd_jvp_f(self, t, u, v, jv)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:), v(:)
      real(dp), intent(out) :: jv(:)
      jv = (1.0_dp - 2.0_dp*u)*v
   end subroutine rd_jvp_f

   !> J_g v = D Laplacian_h v - 3 kappa U^2 v.
   subroutine rd_jvp_g(self, t, u, v, jv)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:), v(:)
      real(dp), intent(out) :: jv(:)
      call self%grid%exchange(v, self%ghosted_direction)
      call laplacian(self, self%ghosted_direction, jv)
      jv = self%diffusion*jv - 3.0_dp*self%decay*u**2*v
   end subroutine rd_jvp_g

   !> The five-point Laplacian of owned-plus-ghost values at the owned points (zero
   !> beyond the boundary).
   subroutine laplacian(self, ghosted, result)
      class(reaction_diffusion_type), intent(in) :: self
      real(dp), intent(in) :: ghosted(:)
      real(dp), intent(out) :: result(:)
      integer :: i, j, p, q
      real(dp) :: west, east, south, north, rx, ry
      rx = 1.0_dp/self%hx**2
      ry = 1.0_dp/self%hy**2
      associate (grid => self%grid)
         do j = grid%ys, grid%ys + grid%ym - 1
            do i = grid%xs, grid%xs + grid%xm - 1
               p = (i - grid%xs) + grid%xm*(j - grid%ys) + 1
               q = (i - grid%gxs) + grid%gxm*(j - grid%gys) + 1
               west = 0.0_dp
               east = 0.0_dp
               south = 0.0_dp
               north = 0.0_dp
               if (i > 0) west = ghosted(q - 1)
               if (i < grid%nx - 1) east = ghosted(q + 1)
               if (j > 0) south = ghosted(q - grid%gxm)
               if (j < grid%ny - 1) north = ghosted(q + grid%gxm)
               result(p) = rx*(west - 2.0_dp*ghosted(q) + east) + ry*(south - 2.0_dp*ghosted(q) + north)
            end do
         end do
      end associate
   end subroutine laplacian

   !> dg/dU as five-point stencils: D/h^2 to the neighbours, -2D/hx^2 - 2D/hy^2 - 3 kappa U^2
   !> on the point.
   subroutine rd_stencil(self, t, u, stencil)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: stencil(:, :)
      real(dp) :: rx, ry
      rx = self%diffusion/self%hx**2
      ry = self%diffusion/self%hy**2
      stencil(stencil_west, :) = rx
      stencil(stencil_east, :) = rx
      stencil(stencil_south, :) = ry
      stencil(stencil_north, :) = ry
      stencil(stencil_center, :) = -2.0_dp*(rx + ry) - 3.0_dp*self%decay*u**2
   end subroutine rd_stencil

   !> Bandwidths nx in natural order on one rank; dense (not used) on several.
   function rd_structure(self, n) result(structure)
      class(reaction_diffusion_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      if (self%grid%ranks == 1) then
         structure = band_structure(self%grid%nx, self%grid%nx)
      else
         structure = dense_structure()
      end if
   end function rd_structure

   !> df/dU in band storage (one rank): the diagonal 1 - 2U.
   subroutine rd_jac_f_band(self, t, u, band)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      band = 0.0_dp
      band(self%grid%nx + 1, :) = 1.0_dp - 2.0_dp*u
   end subroutine rd_jac_f_band

   !> dg/dU in band storage (one rank, natural order): the five-point stencil.
   subroutine rd_jac_g_band(self, t, u, band)
      class(reaction_diffusion_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      real(dp) :: stencil(5, size(u))
      integer :: i, j, p, nx, upper
      nx = self%grid%nx
      upper = nx
      call self%jac_g_stencil(t, u, stencil)
      band = 0.0_dp
      ! row p of J: band(upper + 1 + p - column, column) = J(p, column)
      do j = 0, self%grid%ny - 1
         do i = 0, nx - 1
            p = i + nx*j + 1
            band(upper + 1, p) = stencil(stencil_center, p)
            if (i > 0) band(upper + 2, p - 1) = stencil(stencil_west, p)
            if (i < nx - 1) band(upper, p + 1) = stencil(stencil_east, p)
            if (j > 0) band(upper + 1 + nx, p - nx) = stencil(stencil_south, p)
            if (j < self%grid%ny - 1) band(upper + 1 - nx, p + nx) = stencil(stencil_north, p)
         end do
      end do
   end subroutine rd_jac_g_band

   !> Release the grid.
   subroutine destroy(self)
      !> The problem
      class(reaction_diffusion_type), intent(inout) :: self
      call self%grid%destroy()
   end subroutine destroy

end module taylorode_petsc_reaction_diffusion
