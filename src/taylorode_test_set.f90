!> The classic stiff test set as ready problems, each split as a user would (the
!> stiff part in g), with analytic Jacobians, standard initial values and time
!> spans, recommended tolerances and, where published, reference solutions.
!>
!> Sources: E. Hairer and G. Wanner, Solving Ordinary Differential Equations II
!> (Springer, 2nd ed. 1996), sections IV.1 and IV.10; F. Mazzia and C. Magherini,
!> Test Set for IVP Solvers (University of Bari, release 2.4, 2008); A. Prothero and
!> A. Robinson, Math. Comp. 28 (1974) 145-162.
module taylorode_test_set
   use taylorode_kinds, only: dp
   use taylorode_status, only: status_type, set_status, status_ok, status_invalid_argument
   use taylorode_problem, only: test_problem_type
   use taylorode_van_der_pol, only: new_van_der_pol, vdp_split_paper, vdp_split_stiff
   use taylorode_linear_test, only: linear_test_type, new_linear_test
   implicit none
   private

   public :: robertson_type, new_robertson, hires_type, new_hires, orego_type, new_orego
   public :: e5_type, new_e5, brusselator_type, new_brusselator
   public :: prothero_robinson_type, new_prothero_robinson
   public :: new_test_problem, test_problem_names, test_problem_count

   !> Number of problems the factory knows
   integer, parameter :: test_problem_count = 9
   !> Names understood by new_test_problem
   character(len=*), parameter :: test_problem_names(test_problem_count) = [character(len=17) :: &
      "vdp", "vdp-stiff", "robertson", "hires", "orego", "e5", "brusselator", "prothero-robinson", "linear"]

   !> Robertson's chemical kinetics (Hairer & Wanner II, IV.1; Bari test set ROBER).
   !> f = the slow reaction (k1 = 0.04), g = the fast ones (k2 = 3e7, k3 = 1e4);
   !> each part conserves y1 + y2 + y3. y2 stays below 4e-5: use atol <= 1e-10.
   type, extends(test_problem_type) :: robertson_type
      real(dp) :: k1 = 0.04_dp, k2 = 3.0e7_dp, k3 = 1.0e4_dp
   contains
      procedure :: f => robertson_f
      procedure :: g => robertson_g
      procedure :: jac_f => robertson_jac_f
      procedure :: jac_g => robertson_jac_g
   end type robertson_type

   !> HIRES, high irradiance responses of photomorphogenesis (Hairer & Wanner II,
   !> IV.10; Bari test set HIRES). f = the reaction 280 y6 y8 and the source 0.0007,
   !> g = the linear exchange terms.
   type, extends(test_problem_type) :: hires_type
   contains
      procedure :: f => hires_f
      procedure :: g => hires_g
      procedure :: jac_f => hires_jac_f
      procedure :: jac_g => hires_jac_g
   end type hires_type

   !> OREGO, the Oregonator (Hairer & Wanner II, IV.10; Bari test set OREGO).
   !> g = the fast first two equations (scaled by s and 1/s), f = the slow third.
   type, extends(test_problem_type) :: orego_type
      real(dp) :: s = 77.27_dp, w = 0.161_dp, q = 8.375e-6_dp
   contains
      procedure :: f => orego_f
      procedure :: g => orego_g
      procedure :: jac_f => orego_jac_f
      procedure :: jac_g => orego_jac_g
   end type orego_type

   !> E5, a chemical pyrolysis (Hairer & Wanner II, IV.10; Bari test set E5).
   !> f = the slow decay A y1 (A = 7.89e-10), g = the fast reactions. Components fall
   !> to 1e-22 (and y1 to 1e-290): use atol around 1e-24 and judge y2, y3 relatively.
   type, extends(test_problem_type) :: e5_type
      real(dp) :: a = 7.89e-10_dp, b = 1.1e7_dp, c = 1.13e3_dp, m = 1.0e6_dp
   contains
      procedure :: f => e5_f
      procedure :: g => e5_g
      procedure :: jac_f => e5_jac_f
      procedure :: jac_g => e5_jac_g
   end type e5_type

   !> The 1D Brusselator by the method of lines (Hairer & Wanner II, IV.10, BRUSS):
   !> N interior points, alpha = 1/50, Dirichlet data u = 1, v = 3, u(x, 0) = 1 + sin(2 pi x),
   !> v(x, 0) = 3, t in [0, 10]. Unknowns interleaved (u1, v1, u2, v2, ...);
   !> f = the reaction, g = the diffusion (with the boundary data). Both Jacobians
   !> have bandwidths 2 and 2: the Newton systems are solved in band storage.
   type, extends(test_problem_type) :: brusselator_type
      !> Interior grid points
      integer :: points = 100
      !> Diffusion coefficient
      real(dp) :: alpha = 1.0_dp/50.0_dp
   contains
      procedure :: f => brusselator_f
      procedure :: g => brusselator_g
      procedure :: jac_f => brusselator_jac_f
      procedure :: jac_g => brusselator_jac_g
      procedure :: bandwidths => brusselator_bandwidths
      procedure :: jac_f_band => brusselator_jac_f_band
      procedure :: jac_g_band => brusselator_jac_g_band
   end type brusselator_type

   !> Prothero-Robinson: y' = L (y - sin t) + cos t, y(0) = 0, exact solution sin t
   !> (Prothero & Robinson 1974). f = cos t, g = L (y - sin t), L < 0 large.
   type, extends(test_problem_type) :: prothero_robinson_type
      !> Stiffness, L < 0
      real(dp) :: l = -1.0e6_dp
   contains
      procedure :: f => pr_f
      procedure :: g => pr_g
      procedure :: jac_f => pr_jac_f
      procedure :: jac_g => pr_jac_g
   end type prothero_robinson_type

contains

   !> Create any problem of the set by name (see test_problem_names) with its
   !> standard settings. An unknown name leaves `problem` unallocated and lists the valid ones.
   subroutine new_test_problem(name, problem, stat)
      !> Name as users type it
      character(len=*), intent(in) :: name
      !> The new problem
      class(test_problem_type), allocatable, intent(out) :: problem
      !> status_invalid_argument for an unknown name
      type(status_type), intent(out) :: stat
      character(len=:), allocatable :: valid
      integer :: i

      select case (trim(adjustl(name)))
      case ("vdp")
         allocate (problem, source=new_van_der_pol(1000.0_dp, vdp_split_paper))
      case ("vdp-stiff")
         allocate (problem, source=new_van_der_pol(1000.0_dp, vdp_split_stiff))
      case ("robertson")
         allocate (problem, source=new_robertson())
      case ("hires")
         allocate (problem, source=new_hires())
      case ("orego")
         allocate (problem, source=new_orego())
      case ("e5")
         allocate (problem, source=new_e5())
      case ("brusselator")
         allocate (problem, source=new_brusselator())
      case ("prothero-robinson")
         allocate (problem, source=new_prothero_robinson())
      case ("linear")
         allocate (problem, source=new_linear_test((-1.0_dp, 2.0_dp), (-10.0_dp, 0.0_dp)))
      case default
         valid = trim(test_problem_names(1))
         do i = 2, test_problem_count
            valid = valid//", "//trim(test_problem_names(i))
         end do
         call set_status(stat, status_invalid_argument, 'unknown problem "'//trim(name)// &
            '"; valid names: '//valid)
         return
      end select
      stat%code = status_ok
   end subroutine new_test_problem

   !> Robertson from (1, 0, 0) to t_end (default 40); the published solution is
   !> attached for t_end = 40 and t_end = 1e11.
   pure function new_robertson(t_end) result(self)
      !> Final time (40 or 1e11 have reference values)
      real(dp), intent(in), optional :: t_end
      type(robertson_type) :: self
      self%name = "robertson"
      self%t_end = 40.0_dp
      if (present(t_end)) self%t_end = t_end
      self%u0 = [1.0_dp, 0.0_dp, 0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-10_dp
      if (self%t_end == 40.0_dp) then
         self%reference = [0.7158270687194048_dp, 9.185534764557822e-6_dp, 0.2841637457458297_dp]
      else if (self%t_end == 1.0e11_dp) then
         self%reference = [0.2083340149701255e-7_dp, 0.8333360770334713e-13_dp, 0.9999999791665050_dp]
      end if
      self%source = "Hairer & Wanner II, IV.1; Bari test set ROBER (reference values)"
   end function new_robertson

   subroutine robertson_f(self, t, u, dudt)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -self%k1*u(1)
      dudt(2) = self%k1*u(1)
      dudt(3) = 0.0_dp
   end subroutine robertson_f

   subroutine robertson_g(self, t, u, dudt)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = self%k3*u(2)*u(3)
      dudt(3) = self%k2*u(2)**2
      dudt(2) = -dudt(1) - dudt(3)
   end subroutine robertson_g

   subroutine robertson_jac_f(self, t, u, jac)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = -self%k1
      jac(2, 1) = self%k1
   end subroutine robertson_jac_f

   subroutine robertson_jac_g(self, t, u, jac)
      class(robertson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 2) = self%k3*u(3)
      jac(1, 3) = self%k3*u(2)
      jac(3, 2) = 2.0_dp*self%k2*u(2)
      jac(2, 2) = -jac(1, 2) - jac(3, 2)
      jac(2, 3) = -jac(1, 3)
   end subroutine robertson_jac_g

   !> HIRES from its standard initial state over [0, 321.8122], with the published solution.
   pure function new_hires() result(self)
      type(hires_type) :: self
      self%name = "hires"
      self%t_end = 321.8122_dp
      self%u0 = [1.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0_dp, 0.0057_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-10_dp
      self%reference = [0.7371312573325668e-3_dp, 0.1442485726316185e-3_dp, 0.5888729740967575e-4_dp, &
         0.1175651343283149e-2_dp, 0.2386356198831331e-2_dp, 0.6238968252742796e-2_dp, &
         0.2849998395185769e-2_dp, 0.2850001604814231e-2_dp]
      self%source = "Hairer & Wanner II, IV.10; Bari test set HIRES (reference values)"
   end function new_hires

   subroutine hires_f(self, t, u, dudt)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: reaction
      reaction = 280.0_dp*u(6)*u(8)
      dudt = 0.0_dp
      dudt(1) = 0.0007_dp
      dudt(6) = -reaction
      dudt(7) = reaction
      dudt(8) = -reaction
   end subroutine hires_f

   subroutine hires_g(self, t, u, dudt)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -1.71_dp*u(1) + 0.43_dp*u(2) + 8.32_dp*u(3)
      dudt(2) = 1.71_dp*u(1) - 8.75_dp*u(2)
      dudt(3) = -10.03_dp*u(3) + 0.43_dp*u(4) + 0.035_dp*u(5)
      dudt(4) = 8.32_dp*u(2) + 1.71_dp*u(3) - 1.12_dp*u(4)
      dudt(5) = -1.745_dp*u(5) + 0.43_dp*u(6) + 0.43_dp*u(7)
      dudt(6) = 0.69_dp*u(4) + 1.71_dp*u(5) - 0.43_dp*u(6) + 0.69_dp*u(7)
      dudt(7) = -1.81_dp*u(7)
      dudt(8) = 1.81_dp*u(7)
   end subroutine hires_g

   subroutine hires_jac_f(self, t, u, jac)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(6, 6) = -280.0_dp*u(8)
      jac(6, 8) = -280.0_dp*u(6)
      jac(7, 6:8:2) = -jac(6, 6:8:2)
      jac(8, 6:8:2) = jac(6, 6:8:2)
   end subroutine hires_jac_f

   subroutine hires_jac_g(self, t, u, jac)
      class(hires_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1:3) = [-1.71_dp, 0.43_dp, 8.32_dp]
      jac(2, 1:2) = [1.71_dp, -8.75_dp]
      jac(3, 3:5) = [-10.03_dp, 0.43_dp, 0.035_dp]
      jac(4, 2:4) = [8.32_dp, 1.71_dp, -1.12_dp]
      jac(5, 5:7) = [-1.745_dp, 0.43_dp, 0.43_dp]
      jac(6, 4:7) = [0.69_dp, 1.71_dp, -0.43_dp, 0.69_dp]
      jac(7, 7) = -1.81_dp
      jac(8, 7) = 1.81_dp
   end subroutine hires_jac_g

   !> OREGO from (1, 2, 3) over [0, 360], with the published solution.
   pure function new_orego() result(self)
      type(orego_type) :: self
      self%name = "orego"
      self%t_end = 360.0_dp
      self%u0 = [1.0_dp, 2.0_dp, 3.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%reference = [0.1000814870318523e1_dp, 0.1228178521549917e4_dp, 0.1320554942846706e3_dp]
      self%source = "Hairer & Wanner II, IV.10; Bari test set OREGO (reference values)"
   end function new_orego

   subroutine orego_f(self, t, u, dudt)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1:2) = 0.0_dp
      dudt(3) = self%w*(u(1) - u(3))
   end subroutine orego_f

   subroutine orego_g(self, t, u, dudt)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = self%s*(u(2) - u(1)*u(2) + u(1) - self%q*u(1)**2)
      dudt(2) = (-u(2) - u(1)*u(2) + u(3))/self%s
      dudt(3) = 0.0_dp
   end subroutine orego_g

   subroutine orego_jac_f(self, t, u, jac)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(3, 1) = self%w
      jac(3, 3) = -self%w
   end subroutine orego_jac_f

   subroutine orego_jac_g(self, t, u, jac)
      class(orego_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = self%s*(1.0_dp - u(2) - 2.0_dp*self%q*u(1))
      jac(1, 2) = self%s*(1.0_dp - u(1))
      jac(2, 1) = -u(2)/self%s
      jac(2, 2) = -(1.0_dp + u(1))/self%s
      jac(2, 3) = 1.0_dp/self%s
   end subroutine orego_jac_g

   !> E5 from (1.76e-3, 0, 0, 0) over [0, 1e13], with the published solution.
   pure function new_e5() result(self)
      type(e5_type) :: self
      self%name = "e5"
      self%t_end = 1.0e13_dp
      self%u0 = [1.76e-3_dp, 0.0_dp, 0.0_dp, 0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-24_dp
      self%reference = [0.1152903278711829e-290_dp, 0.8867655517642120e-22_dp, 0.8854814626268838e-22_dp, 0.0_dp]
      self%source = "Hairer & Wanner II, IV.10; Bari test set E5 (reference values)"
   end function new_e5

   subroutine e5_f(self, t, u, dudt)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = -self%a*u(1)
      dudt(2) = self%a*u(1)
      dudt(3) = self%a*u(1)
      dudt(4) = 0.0_dp
   end subroutine e5_f

   subroutine e5_g(self, t, u, dudt)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: r1, r2, r3
      r1 = self%b*u(1)*u(3)
      r2 = self%m*self%c*u(2)*u(3)
      r3 = self%c*u(4)
      dudt(1) = -r1
      dudt(2) = -r2
      dudt(4) = r1 - r3
      ! y3' = y2' - y4' exactly as computed, so that rounding keeps y2 - y3 - y4 = 0
      dudt(3) = dudt(2) - dudt(4)
   end subroutine e5_g

   subroutine e5_jac_f(self, t, u, jac)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1:3, 1) = [-self%a, self%a, self%a]
   end subroutine e5_jac_f

   subroutine e5_jac_g(self, t, u, jac)
      class(e5_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      real(dp) :: mc
      mc = self%m*self%c
      jac = 0.0_dp
      jac(1, :) = [-self%b*u(3), 0.0_dp, -self%b*u(1), 0.0_dp]
      jac(2, :) = [0.0_dp, -mc*u(3), -mc*u(2), 0.0_dp]
      jac(3, :) = [-self%b*u(3), -mc*u(3), -self%b*u(1) - mc*u(2), self%c]
      jac(4, :) = [self%b*u(3), 0.0_dp, self%b*u(1), -self%c]
   end subroutine e5_jac_g

   !> Brusselator with `points` interior grid points (default 100) over [0, 10].
   pure function new_brusselator(points) result(self)
      !> Interior grid points N (2N unknowns)
      integer, intent(in), optional :: points
      type(brusselator_type) :: self
      real(dp), parameter :: pi = acos(-1.0_dp)
      integer :: i
      if (present(points)) self%points = points
      self%name = "brusselator"
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
      real(dp) :: c, left, right
      integer :: i, species
      real(dp), parameter :: boundary(2) = [1.0_dp, 3.0_dp]
      c = self%alpha*real(self%points + 1, dp)**2
      do i = 1, self%points
         do species = 1, 2
            if (i > 1) then
               left = u(2*(i - 1) + species - 2)
            else
               left = boundary(species)
            end if
            if (i < self%points) then
               right = u(2*(i + 1) + species - 2)
            else
               right = boundary(species)
            end if
            dudt(2*i + species - 2) = c*(left - 2.0_dp*u(2*i + species - 2) + right)
         end do
      end do
   end subroutine brusselator_g

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
   subroutine brusselator_bandwidths(self, n, lower, upper)
      class(brusselator_type), intent(in) :: self
      integer, intent(in) :: n
      integer, intent(out) :: lower, upper
      lower = 2
      upper = 2
   end subroutine brusselator_bandwidths

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

   !> Prothero-Robinson with stiffness L (default -1e6) over [0, 10]; exact solution sin t.
   pure function new_prothero_robinson(l) result(self)
      !> Stiffness, < 0
      real(dp), intent(in), optional :: l
      type(prothero_robinson_type) :: self
      if (present(l)) self%l = l
      self%name = "prothero-robinson"
      self%t_end = 10.0_dp
      self%u0 = [0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%reference = [sin(10.0_dp)]
      self%source = "Prothero & Robinson, Math. Comp. 28 (1974); exact solution sin t"
   end function new_prothero_robinson

   subroutine pr_f(self, t, u, dudt)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = cos(t)
   end subroutine pr_f

   subroutine pr_g(self, t, u, dudt)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = self%l*(u - sin(t))
   end subroutine pr_g

   subroutine pr_jac_f(self, t, u, jac)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
   end subroutine pr_jac_f

   subroutine pr_jac_g(self, t, u, jac)
      class(prothero_robinson_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
      jac(1, 1) = self%l
   end subroutine pr_jac_g

end module taylorode_test_set
