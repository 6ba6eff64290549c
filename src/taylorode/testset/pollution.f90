!> POLLU, the chemistry of the air pollution model of the Dutch National Institute of
!> Public Health and the Environment (Verwer 1994; Bari test set POLLU).
module taylorode_testset_pollution
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: pollution_type, new_pollution

   !> Number of reactions of the mechanism
   integer, parameter :: reaction_count = 25
   !> Species (unknowns)
   integer, parameter :: species = 20
   !> Rate constants k1 ... k25 (per minute, or per ppm per minute for the reactions
   !> of two species), as published
   real(dp), parameter :: rate_constants(reaction_count) = [0.35_dp, 26.6_dp, 1.23e4_dp, 8.6e-4_dp, &
      8.2e-4_dp, 1.5e4_dp, 1.3e-4_dp, 2.4e4_dp, 1.65e4_dp, 9.0e3_dp, 0.022_dp, 1.2e4_dp, 1.88_dp, &
      1.63e4_dp, 4.8e6_dp, 3.5e-4_dp, 0.0175_dp, 1.0e8_dp, 4.44e11_dp, 1240.0_dp, 2.1_dp, 5.78_dp, &
      0.0474_dp, 1780.0_dp, 3.12_dp]
   !> Reactants of reaction j: the species reactants(1, j) and, when nonzero, reactants(2, j);
   !> its rate is r_j = k_j times their concentrations
   integer, parameter :: reactants(2, reaction_count) = reshape([1, 0, 2, 4, 5, 2, 7, 0, 7, 0, 7, 6, &
      9, 0, 9, 6, 11, 2, 11, 1, 13, 0, 10, 2, 14, 0, 1, 6, 3, 0, 4, 0, 4, 0, 16, 0, 16, 0, 17, 6, &
      19, 0, 19, 0, 1, 4, 19, 1, 20, 0], [2, reaction_count])
   !> Products of reaction j (zero: none; a species listed twice is made twice)
   integer, parameter :: products(3, reaction_count) = reshape([2, 3, 0, 1, 0, 0, 1, 6, 0, 5, 5, 8, &
      8, 0, 0, 5, 8, 0, 10, 5, 8, 11, 0, 0, 1, 10, 12, 13, 0, 0, 11, 1, 0, 14, 1, 0, 7, 5, 0, &
      15, 0, 0, 4, 0, 0, 16, 0, 0, 3, 0, 0, 6, 6, 0, 3, 0, 0, 18, 5, 0, 2, 0, 0, 1, 3, 0, &
      19, 0, 0, 20, 0, 0, 19, 1, 0], [3, reaction_count])
   !> The rate constant that separates the fast reactions (k >= 1e3) from the slow ones
   !> (k <= 26.6): no published constant lies between 26.6 and 1240
   real(dp), parameter :: fast_rate = 1.0e3_dp
   !> Which reactions are fast (in g)
   logical, parameter :: fast(reaction_count) = rate_constants >= fast_rate

   !> POLLU (Verwer 1994; Bari test set POLLU): 20 species (NO2, NO, O3P, O3, HO2, OH,
   !> HCHO, CO, ALD, MEO2, C2O3, CO2, PAN, CH3O, HNO3, O1D, SO2, SO4, NO3, N2O5, in ppm)
   !> in 25 reactions over [0, 60] minutes. Split by the rate constant: g = the twelve
   !> fast reactions, k >= 1e3 (3, 6, 8, 9, 10, 12, 14, 15, 18, 19, 20, 24), f = the
   !> thirteen slow ones, k <= 26.6 (1, 2, 4, 5, 7, 11, 13, 16, 17, 21, 22, 23, 25);
   !> no constant lies in between. Measured along radau5's solution: the eigenvalues of
   !> df/dU stay within |lambda| <= 7.9 per minute (NO3's photolysis, k21 + k22), those
   !> of dg/dU reach 4.4e11 (O1D, k18 + k19). Each part conserves nitrogen, carbon and
   !> sulphur, as every reaction does. Components span 0.32 down to 4e-18 (O1D); the
   !> test set measures them with atol = rtol.
   type, extends(test_problem_type) :: pollution_type
   contains
      !> Non-stiff part f: the slow reactions
      procedure :: f => pollution_f
      !> Stiff part g: the fast reactions
      procedure :: g => pollution_g
      !> F = f + g in one pass over the reaction rates
      procedure :: rhs => pollution_rhs
      !> df/dU, analytic
      procedure :: jac_f => pollution_jac_f
      !> dg/dU, analytic
      procedure :: jac_g => pollution_jac_g
      !> J = df/dU + dg/dU in one call
      procedure :: jac => pollution_jac
   end type pollution_type

contains

   !> POLLU from its published initial state (NO 0.2, O3 0.04, HCHO 0.1, CO 0.3,
   !> ALD 0.01, SO2 0.007 ppm, the rest 0) over [0, 60], with the published solution.
   pure function new_pollution() result(self)
      type(pollution_type) :: self
      self%name = "pollution"
      self%autonomous = .true.
      self%t_end = 60.0_dp
      allocate (self%u0(species), source=0.0_dp)
      self%u0([2, 4, 7, 8, 9, 17]) = [0.2_dp, 0.04_dp, 0.1_dp, 0.3_dp, 0.01_dp, 0.007_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%nonnegative = .true.
      self%reference = [0.5646255480022769e-01_dp, 0.1342484130422339e+00_dp, 0.4139734331099427e-08_dp, &
         0.5523140207484359e-02_dp, 0.2018977262302196e-06_dp, 0.1464541863493966e-06_dp, &
         0.7784249118997964e-01_dp, 0.3245075353396018e+00_dp, 0.7494013383880406e-02_dp, &
         0.1622293157301561e-07_dp, 0.1135863833257075e-07_dp, 0.2230505975721359e-02_dp, &
         0.2087162882798630e-03_dp, 0.1396921016840158e-04_dp, 0.8964884856898295e-02_dp, &
         0.4352846369330103e-17_dp, 0.6899219696263405e-02_dp, 0.1007803037365946e-03_dp, &
         0.1772146513969984e-05_dp, 0.5682943292316392e-04_dp]
      self%source = "Verwer, SIAM J. Sci. Comput. 15 (1994) 1243-1259; Bari test set POLLU "// &
         "(pollu.f: equations and the reference solution, RADAU5 at rtol = atol = 1.1e-18 in Cray double precision)"
   end function new_pollution

   subroutine pollution_f(self, t, u, dudt)
      class(pollution_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      call balance(reaction_rates(u), .false., dudt)
   end subroutine pollution_f

   subroutine pollution_g(self, t, u, dudt)
      class(pollution_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      call balance(reaction_rates(u), .true., dudt)
   end subroutine pollution_g

   !> f + g from one evaluation of the rates, each part summed as pollution_f and
   !> pollution_g sum it.
   subroutine pollution_rhs(self, t, u, dudt)
      class(pollution_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      ! (of fixed size: a local array of size(u) would be allocated at every call)
      real(dp) :: rates(reaction_count), fast_part(species)
      rates = reaction_rates(u)
      call balance(rates, .false., dudt)
      call balance(rates, .true., fast_part)
      dudt = dudt + fast_part
   end subroutine pollution_rhs

   subroutine pollution_jac_f(self, t, u, jac)
      class(pollution_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call balance_jacobian(u, .false., jac)
   end subroutine pollution_jac_f

   subroutine pollution_jac_g(self, t, u, jac)
      class(pollution_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call balance_jacobian(u, .true., jac)
   end subroutine pollution_jac_g

   !> df/dU + dg/dU, each part summed as pollution_jac_f and pollution_jac_g sum it.
   subroutine pollution_jac(self, t, u, jac)
      class(pollution_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      real(dp) :: fast_part(species, species)
      call balance_jacobian(u, .false., jac)
      call balance_jacobian(u, .true., fast_part)
      jac = jac + fast_part
   end subroutine pollution_jac

   !> The 25 reaction rates r_j = k_j [reactant 1] [reactant 2] at the state u.
   pure function reaction_rates(u) result(rates)
      real(dp), intent(in) :: u(:)
      real(dp) :: rates(reaction_count)
      integer :: j
      do j = 1, reaction_count
         rates(j) = rate_constants(j)*u(reactants(1, j))
         if (reactants(2, j) > 0) rates(j) = rates(j)*u(reactants(2, j))
      end do
   end function reaction_rates

   !> The production minus the loss of every species by the fast reactions
   !> (`stiff`) or by the slow ones.
   pure subroutine balance(rates, stiff, dudt)
      real(dp), intent(in) :: rates(:)
      logical, intent(in) :: stiff
      real(dp), intent(out) :: dudt(:)
      integer :: j
      dudt = 0.0_dp
      do j = 1, reaction_count
         if (fast(j) .eqv. stiff) call add_reaction(j, rates(j), dudt)
      end do
   end subroutine balance

   !> The Jacobian of `balance`: column by column, d r_j / d u_c spread over the
   !> species reaction j consumes and makes.
   pure subroutine balance_jacobian(u, stiff, jac)
      real(dp), intent(in) :: u(:)
      logical, intent(in) :: stiff
      real(dp), intent(out) :: jac(:, :)
      integer :: j, first, second
      jac = 0.0_dp
      do j = 1, reaction_count
         if (fast(j) .neqv. stiff) cycle
         first = reactants(1, j)
         second = reactants(2, j)
         if (second > 0) then
            call add_reaction(j, rate_constants(j)*u(second), jac(:, first))
            call add_reaction(j, rate_constants(j)*u(first), jac(:, second))
         else
            call add_reaction(j, rate_constants(j), jac(:, first))
         end if
      end do
   end subroutine balance_jacobian

   !> Reaction j at the rate `rate`: subtracted from its reactants, added to its products.
   pure subroutine add_reaction(j, rate, dudt)
      integer, intent(in) :: j
      real(dp), intent(in) :: rate
      real(dp), intent(inout) :: dudt(:)
      integer :: i
      do i = 1, 2
         if (reactants(i, j) > 0) dudt(reactants(i, j)) = dudt(reactants(i, j)) - rate
      end do
      do i = 1, 3
         if (products(i, j) > 0) dudt(products(i, j)) = dudt(products(i, j)) + rate
      end do
   end subroutine add_reaction

end module taylorode_testset_pollution
