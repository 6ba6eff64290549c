!> The 1D Brusselator by the method of lines (Hairer & Wanner II, IV.10, BRUSS), banded.
module taylorode_testset_brusselator
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   use taylorode_linalg_matrix, only: matrix_structure_type, band_structure
   implicit none
   private

   public :: brusselator_type, new_brusselator

   !> The 1D Brusselator by the method of lines (Hairer & Wanner II, IV.10, BRUSS):
   !> N interior points, alpha = 1/50, Dirichlet data u = 1, v = 3, u(x, 0) = 1 + sin(2 pi x),
   !> v(x, 0) = 3, t in [0, 10]. Unknowns interleaved (u1, v1, u2, v2, ...);
   !> f = the reaction, g = the diffusion (with the boundary data). Both Jacobians
   !> have bandwidths 2 and 2: the Newton systems are solved in band storage. g is
   !> declared linear.
   type, extends(test_problem_type) :: brusselator_type
      !> Interior grid points
      integer :: points = 100
      !> Diffusion coefficient
      real(dp) :: alpha = 1.0_dp/50.0_dp
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => brusselator_f
      !> Stiff part g
      procedure :: g => brusselator_g
      !> F = f + g in one pass (no work array of n values, one loop instead of three)
      procedure :: rhs => brusselator_rhs
      !> df/dU, analytic and dense: the schemes call it only for N = 1, where the band covers the whole matrix
      procedure :: jac_f => brusselator_jac_f
      !> dg/dU, analytic and dense (see jac_f)
      procedure :: jac_g => brusselator_jac_g
      procedure :: jacobian_structure => brusselator_structure
      procedure :: jac_f_band => brusselator_jac_f_band
      procedure :: jac_g_band => brusselator_jac_g_band
      !> df/dU + dg/dU in band storage in one pass
      procedure :: jac_band => brusselator_jac_band
      !> y + alpha J v without forming J
      procedure :: add_jacobian_product => brusselator_add_jacobian_product
   end type brusselator_type

contains

   !> Brusselator with `points` interior grid points (default 100) over [0, 10].
   pure function new_brusselator(points) result(self)
      !> Interior grid points N (2N unknowns)
      integer, intent(in), optional :: points
      type(brusselator_type) :: self
      real(dp), parameter :: pi = acos(-1.0_dp)
      integer :: i
      if (present(points)) self%points = points
      self%name = "brusselator"
      self%autonomous = .true.
      ! the diffusion (with its boundary values) is A U + b
      self%linear_g = .true.
      self%t_end = 10.0_dp
      allocate (self%u0(2*self%points))
      do i = 1, self%points
         self%u0(2*i - 1) = 1.0_dp + sin(2.0_dp*pi*real(i, dp)/real(self%points + 1, dp))
         self%u0(2*i) = 3.0_dp
      end do
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%source = "Hairer & Wanner II, IV.10 (BRUSS, one space dimension)"
   end function new_brusselator

   subroutine brusselator_f(self, t, u, dudt)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      integer :: i
      real(dp) :: uuv
      do i = 1, self%points
         uuv = u(2*i - 1)**2*u(2*i)
         dudt(2*i - 1) = 1.0_dp + uuv - 4.0_dp*u(2*i - 1)
         dudt(2*i) = 3.0_dp*u(2*i - 1) - uuv
      end do
   end subroutine brusselator_f

   subroutine brusselator_g(self, t, u, dudt)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: c
      integer :: i, species
      c = self%alpha*real(self%points + 1, dp)**2
      do i = 1, self%points
         do species = 1, 2
            dudt(2*i + species - 2) = diffusion(self%points, c, u, i, species)
         end do
      end do
   end subroutine brusselator_g

   !> The diffusion of species (1: u, 2: v) at point i, c (u_(i-1) - 2 u_i + u_(i+1)),
   !> with the boundary values 1 and 3 beyond the ends: g's term, and F's
   pure real(dp) function diffusion(points, c, u, i, species)
      integer, intent(in) :: points, i, species
      real(dp), intent(in) :: c, u(:)
      real(dp), parameter :: boundary(2) = [1.0_dp, 3.0_dp]
      real(dp) :: left, right
      if (i > 1) then
         left = u(2*(i - 1) + species - 2)
      else
         left = boundary(species)
      end if
      if (i < points) then
         right = u(2*(i + 1) + species - 2)
      else
         right = boundary(species)
      end if
      diffusion = c*(left - 2.0_dp*u(2*i + species - 2) + right)
   end function diffusion

   !> F = f + g: for each point and species the terms of f and of g as brusselator_f
   !> and brusselator_g compute them, added (the same numbers as f, then g added).
   subroutine brusselator_rhs(self, t, u, dudt)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: c, uuv, reaction(2)
      integer :: i, species
      c = self%alpha*real(self%points + 1, dp)**2
      do i = 1, self%points
         uuv = u(2*i - 1)**2*u(2*i)
         reaction(1) = 1.0_dp + uuv - 4.0_dp*u(2*i - 1)
         reaction(2) = 3.0_dp*u(2*i - 1) - uuv
         do species = 1, 2
            dudt(2*i + species - 2) = reaction(species) + diffusion(self%points, c, u, i, species)
         end do
      end do
   end subroutine brusselator_rhs

   subroutine brusselator_jac_f(self, t, u, jac)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      integer :: i
      jac = 0.0_dp
      do i = 1, self%points
         jac(2*i - 1, 2*i - 1) = 2.0_dp*u(2*i - 1)*u(2*i) - 4.0_dp
         jac(2*i - 1, 2*i) = u(2*i - 1)**2
         jac(2*i, 2*i - 1) = 3.0_dp - 2.0_dp*u(2*i - 1)*u(2*i)
         jac(2*i, 2*i) = -u(2*i - 1)**2
      end do
   end subroutine brusselator_jac_f

   subroutine brusselator_jac_g(self, t, u, jac)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      real(dp) :: c
      integer :: k
      c = self%alpha*real(self%points + 1, dp)**2
      jac = 0.0_dp
      do k = 1, size(u)
         jac(k, k) = -2.0_dp*c
         if (k > 2) jac(k, k - 2) = c
         if (k <= size(u) - 2) jac(k, k + 2) = c
      end do
   end subroutine brusselator_jac_g

   !> Lower and upper bandwidths 2 (the diffusion couples points i - 1 and i + 1).
   function brusselator_structure(self, n) result(structure)
      class(brusselator_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = band_structure(2, 2)
   end function brusselator_structure

   !> df/dU in band storage: the 2x2 reaction block of each grid point.
   subroutine brusselator_jac_f_band(self, t, u, band)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      integer :: i
      band = 0.0_dp
      do i = 1, self%points
         band(3, 2*i - 1) = 2.0_dp*u(2*i - 1)*u(2*i) - 4.0_dp
         band(4, 2*i - 1) = 3.0_dp - 2.0_dp*u(2*i - 1)*u(2*i)
         band(2, 2*i) = u(2*i - 1)**2
         band(3, 2*i) = -u(2*i - 1)**2
      end do
   end subroutine brusselator_jac_f_band

   !> dg/dU in band storage: the second difference of each species (offsets -2, 0, +2).
   subroutine brusselator_jac_g_band(self, t, u, band)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      real(dp) :: c
      integer :: j
      c = self%alpha*real(self%points + 1, dp)**2
      band = 0.0_dp
      do j = 1, size(u)
         band(3, j) = -2.0_dp*c
         if (j > 2) band(1, j) = c
         if (j <= size(u) - 2) band(5, j) = c
      end do
   end subroutine brusselator_jac_g_band

   !> J = df/dU + dg/dU in band storage: the diffusion, then each point's reaction block added.
   subroutine brusselator_jac_band(self, t, u, band)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      integer :: i
      call self%jac_g_band(t, u, band)
      do i = 1, self%points
         band(3, 2*i - 1) = band(3, 2*i - 1) + (2.0_dp*u(2*i - 1)*u(2*i) - 4.0_dp)
         band(4, 2*i - 1) = band(4, 2*i - 1) + (3.0_dp - 2.0_dp*u(2*i - 1)*u(2*i))
         band(2, 2*i) = band(2, 2*i) + u(2*i - 1)**2
         band(3, 2*i) = band(3, 2*i) + (-u(2*i - 1)**2)
      end do
   end subroutine brusselator_jac_band

   !> y + alpha J v with the entries of brusselator_jac_band, each row's terms added in the order of
   !> the columns: the same numbers as J from brusselator_jac_band times v column by column (the
   !> default), bit for bit.
   subroutine brusselator_add_jacobian_product(self, t, u, alpha, v, y)
      class(brusselator_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: c, uv2, uu
      integer :: i, k, n
      n = size(u)
      c = self%alpha*real(self%points + 1, dp)**2
      do i = 1, self%points
         uv2 = 2.0_dp*u(2*i - 1)*u(2*i)
         uu = u(2*i - 1)**2
         ! the row of u_i: u_(i-1), u_i, v_i, u_(i+1)
         k = 2*i - 1
         if (k > 2) y(k) = y(k) + (alpha*v(k - 2))*c
         y(k) = y(k) + (alpha*v(k))*(-2.0_dp*c + (uv2 - 4.0_dp))
         y(k) = y(k) + (alpha*v(k + 1))*uu
         if (k <= n - 2) y(k) = y(k) + (alpha*v(k + 2))*c
         ! the row of v_i: v_(i-1), u_i, v_i, v_(i+1)
         k = 2*i
         if (k > 2) y(k) = y(k) + (alpha*v(k - 2))*c
         y(k) = y(k) + (alpha*v(k - 1))*(3.0_dp - uv2)
         y(k) = y(k) + (alpha*v(k))*(-2.0_dp*c + (-uu))
         if (k <= n - 2) y(k) = y(k) + (alpha*v(k + 2))*c
      end do
   end subroutine brusselator_add_jacobian_product

end module taylorode_testset_brusselator
