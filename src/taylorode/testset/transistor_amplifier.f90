!> The transistor amplifier, an index-1 differential-algebraic system M U' = F(t, U) with
!> a constant singular mass matrix (Hairer & Wanner II, VI.1 and VII; Bari test set
!> TRANSAMP), banded.
module taylorode_testset_transistor_amplifier
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type, unpack_band
   use taylorode_linalg_matrix, only: matrix_structure_type, band_structure
   implicit none
   private

   public :: transistor_amplifier_type, new_transistor_amplifier

   !> Bandwidths of J: f4 and f7 depend on y2 and y5 (two places before), f2 and f5 on y3
   !> and y6 (one place after); M's bands (1, 1) lie inside
   integer, parameter :: lower = 2, upper = 1
   !> Row of the diagonal in band storage
   integer, parameter :: diagonal = upper + 1
   !> Unknowns
   integer, parameter :: unknowns = 8
   !> The circuit's data: operating voltage Ub, the transistors' UF, alpha and beta, the
   !> resistors R0 and R1 = ... = R9, and the capacitors C_k = k 1e-6
   real(dp), parameter :: ub = 6.0_dp, uf = 0.026_dp, alpha = 0.99_dp, beta = 1.0e-6_dp
   real(dp), parameter :: r0 = 1000.0_dp, r = 9000.0_dp
   real(dp), parameter :: c1 = 1.0e-6_dp, c2 = 2.0e-6_dp, c3 = 3.0e-6_dp, c4 = 4.0e-6_dp, c5 = 5.0e-6_dp
   !> Largest exponent of the transistors' exp((U_b - U_e)/UF): the test set's drivers
   !> reject an evaluation beyond it (exp would overflow near 709)
   real(dp), parameter :: largest_exponent = 300.0_dp

   !> TRANSAMP (Bari test set; Hairer & Wanner II, the two-transistor amplifier): the node
   !> potentials y1, ..., y8 of a circuit driven by Ue(t) = 0.1 sin(200 pi t) satisfy
   !> M y' = F(t, y), t in [0, 0.2], with
   !>     M = [-C1 C1; C1 -C1] + [-C2] + [-C3 C3; C3 -C3] + [-C4] + [-C5 C5; C5 -C5]
   !> (blocks along the diagonal: rows 1-2, 3, 4-5, 6, 7-8), singular (rank 5: three
   !> algebraic equations), and
   !>     F1 = (y1 - Ue)/R0,            F2 = y2/R1 + (y2 - Ub)/R2 + (1 - alpha) g(y2 - y3),
   !>     F3 = y3/R3 - g(y2 - y3),      F4 = (y4 - Ub)/R4 + alpha g(y2 - y3),
   !>     F5 = y5/R5 + (y5 - Ub)/R6 + (1 - alpha) g(y5 - y6),
   !>     F6 = y6/R7 - g(y5 - y6),      F7 = (y7 - Ub)/R8 + alpha g(y5 - y6),
   !>     F8 = y8/R9,
   !> g(x) = beta (exp(x/UF) - 1), Ub = 6, UF = 0.026, alpha = 0.99, beta = 1e-6, R0 =
   !> 1000, R1 = ... = R9 = 9000, C_k = k 1e-6; consistent initial values y = (0, 3, 3, 6,
   !> 3, 3, 6, 0). J has bandwidths (2, 1), M (1, 1). Split: f = the sources (Ue(t) and
   !> Ub, independent of y), g = the rest. An evaluation where (y2 - y3)/UF or (y5 -
   !> y6)/UF exceeds 300 is rejected (reject_evaluation), as the test set's drivers do.
   !> Only radau5 solves it (a mass matrix).
   type, extends(test_problem_type) :: transistor_amplifier_type
   contains
      !> Non-stiff part f: the sources
      procedure :: f => amplifier_f
      !> Stiff part g: resistors and transistors
      procedure :: g => amplifier_g
      !> df/dU = 0, dense
      procedure :: jac_f => amplifier_jac_f
      !> dg/dU, dense
      procedure :: jac_g => amplifier_jac_g
      !> Bandwidths 2 and 1
      procedure :: jacobian_structure => amplifier_structure
      !> df/dU = 0 in band storage
      procedure :: jac_f_band => amplifier_jac_f_band
      !> dg/dU in band storage
      procedure :: jac_g_band => amplifier_jac_g_band
      !> M, dense
      procedure :: mass_matrix => amplifier_mass
      !> M in the band storage of the Jacobian structure
      procedure :: mass_matrix_band => amplifier_mass_band
   end type transistor_amplifier_type

contains

   !> The transistor amplifier from its consistent initial state over [0, 0.2], with the
   !> published solution (PSIDE at tolerances 1e-14, Bari test set).
   pure function new_transistor_amplifier() result(self)
      type(transistor_amplifier_type) :: self
      self%name = "transamp"
      self%has_mass = .true.
      self%t_end = 0.2_dp
      self%u0 = [0.0_dp, ub/2.0_dp, ub/2.0_dp, ub, ub/2.0_dp, ub/2.0_dp, ub, 0.0_dp]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%reference = [-0.5562145012262709e-2_dp, 0.3006522471903042e1_dp, 0.2849958788608128e1_dp, &
         0.2926422536206241e1_dp, 0.2704617865010554e1_dp, 0.2761837778393145e1_dp, &
         0.4770927631616772e1_dp, 0.1236995868091548e1_dp]
      self%source = "Hairer & Wanner II (the transistor amplifier); Bari test set TRANSAMP (definition and "// &
         "reference values)"
   end function new_transistor_amplifier

   !> The input Ue(t) = 0.1 sin(200 pi t)
   pure real(dp) function input(t)
      real(dp), intent(in) :: t
      input = 0.1_dp*sin(200.0_dp*acos(-1.0_dp)*t)
   end function input

   subroutine amplifier_f(self, t, u, dudt)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = 0.0_dp
      dudt(1) = -input(t)/r0
      dudt(2) = -ub/r
      dudt(4) = -ub/r
      dudt(5) = -ub/r
      dudt(7) = -ub/r
   end subroutine amplifier_f

   subroutine amplifier_g(self, t, u, dudt)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: g1, g2
      if (.not. in_range(self, u)) then
         dudt = 0.0_dp
         return
      end if
      g1 = beta*(exp((u(2) - u(3))/uf) - 1.0_dp)
      g2 = beta*(exp((u(5) - u(6))/uf) - 1.0_dp)
      dudt(1) = u(1)/r0
      dudt(2) = u(2)/r + u(2)/r + (1.0_dp - alpha)*g1
      dudt(3) = u(3)/r - g1
      dudt(4) = u(4)/r + alpha*g1
      dudt(5) = u(5)/r + u(5)/r + (1.0_dp - alpha)*g2
      dudt(6) = u(6)/r - g2
      dudt(7) = u(7)/r + alpha*g2
      dudt(8) = u(8)/r
   end subroutine amplifier_g

   !> Whether the transistors' exponents are within range; else the evaluation is rejected.
   logical function in_range(self, u)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: u(:)
      in_range = (u(2) - u(3))/uf <= largest_exponent .and. (u(5) - u(6))/uf <= largest_exponent
      if (.not. in_range) call self%reject_evaluation()
   end function in_range

   subroutine amplifier_jac_f(self, t, u, jac)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
   end subroutine amplifier_jac_f

   subroutine amplifier_jac_f_band(self, t, u, band)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      band = 0.0_dp
   end subroutine amplifier_jac_f_band

   subroutine amplifier_jac_g(self, t, u, jac)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      ! (of fixed size: a local array of size(u) would be allocated at every call)
      real(dp) :: band(lower + upper + 1, unknowns)
      call self%jac_g_band(t, u, band)
      call unpack_band(lower, upper, band, jac)
   end subroutine amplifier_jac_g

   !> dg/dU in band storage: band(2 + i - j, j) = dg_i/dy_j.
   subroutine amplifier_jac_g_band(self, t, u, band)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      real(dp) :: d1, d2
      band = 0.0_dp
      if (.not. in_range(self, u)) return
      d1 = beta*exp((u(2) - u(3))/uf)/uf
      d2 = beta*exp((u(5) - u(6))/uf)/uf
      call put(1, 1, 1.0_dp/r0)
      call put(2, 2, 2.0_dp/r + (1.0_dp - alpha)*d1)
      call put(2, 3, -(1.0_dp - alpha)*d1)
      call put(3, 2, -d1)
      call put(3, 3, 1.0_dp/r + d1)
      call put(4, 2, alpha*d1)
      call put(4, 3, -alpha*d1)
      call put(4, 4, 1.0_dp/r)
      call put(5, 5, 2.0_dp/r + (1.0_dp - alpha)*d2)
      call put(5, 6, -(1.0_dp - alpha)*d2)
      call put(6, 5, -d2)
      call put(6, 6, 1.0_dp/r + d2)
      call put(7, 5, alpha*d2)
      call put(7, 6, -alpha*d2)
      call put(7, 7, 1.0_dp/r)
      call put(8, 8, 1.0_dp/r)
   contains
      subroutine put(i, j, value)
         integer, intent(in) :: i, j
         real(dp), intent(in) :: value
         band(diagonal + i - j, j) = value
      end subroutine put
   end subroutine amplifier_jac_g_band

   !> Bandwidths 2 and 1.
   function amplifier_structure(self, n) result(structure)
      class(transistor_amplifier_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = band_structure(lower, upper)
   end function amplifier_structure

   !> M, dense.
   subroutine amplifier_mass(self, m)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(out) :: m(:, :)
      real(dp) :: band(lower + upper + 1, unknowns)
      call self%mass_matrix_band(band)
      call unpack_band(lower, upper, band, m)
   end subroutine amplifier_mass

   !> M in the Jacobian's band storage: band(2 + i - j, j) = M(i, j).
   subroutine amplifier_mass_band(self, band)
      class(transistor_amplifier_type), intent(inout) :: self
      real(dp), intent(out) :: band(:, :)
      band = 0.0_dp
      call pair(1, c1)
      band(diagonal, 3) = -c2
      call pair(4, c3)
      band(diagonal, 6) = -c4
      call pair(7, c5)
   contains
      !> The block [-c c; c -c] at rows and columns k, k + 1
      subroutine pair(k, c)
         integer, intent(in) :: k
         real(dp), intent(in) :: c
         band(diagonal, k) = -c
         band(diagonal, k + 1) = -c
         band(diagonal - 1, k + 1) = c
         band(diagonal + 1, k) = c
      end subroutine pair
   end subroutine amplifier_mass_band

end module taylorode_testset_transistor_amplifier
