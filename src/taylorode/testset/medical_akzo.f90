!> The Medical Akzo Nobel problem: radio-labelled antibodies entering tumour tissue,
!> a reaction-diffusion PDE by the method of lines (Bari test set MEDAKZO), banded.
module taylorode_testset_medical_akzo
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, status_ok
   use taylorode_base_memory, only: sized
   use taylorode_testset_test_problem, only: test_problem_type, unpack_band
   use taylorode_linalg_matrix, only: matrix_structure_type, band_structure
   implicit none
   private

   public :: medical_akzo_type, new_medical_akzo

   !> Bandwidths of J: the diffusion couples u_j with u_(j-1) and u_(j+1), two places away
   integer, parameter :: lower = 2, upper = 2
   !> Row of the diagonal in band storage
   integer, parameter :: diagonal = upper + 1

   !> MEDAKZO (Bari test set): u_t = u_xx - k u v, v_t = -k u v for x > 0, written in
   !> zeta = x/(x + c) and semi-discretized on the points zeta_j = j/N (dzeta = 1/N):
   !> u_j' = alpha_j (u_(j+1) - u_(j-1))/(2 dzeta) + beta_j (u_(j-1) - 2 u_j + u_(j+1))/dzeta^2
   !> - k u_j v_j, v_j' = -k u_j v_j, j = 1, ..., N, with alpha_j = 2 (zeta_j - 1)^3/c^2,
   !> beta_j = (zeta_j - 1)^4/c^2, k = 100, c = 4, u_0 = phi(t) (2 for t <= 5, 0 after),
   !> u_(N+1) = u_(N-1); u = 0 and v = 1 at t = 0, t in [0, 20]. Unknowns interleaved
   !> (u1, v1, u2, v2, ...): J has bandwidths 2 and 2, the Newton systems are banded.
   !> Split: g = the diffusion and advection (with the boundary value), f = the reaction.
   !> g is the stiff part: its spectral radius is 9.0e3 for N = 200 and grows as N^2. The
   !> reaction's are 0 and -k (u_j + v_j): at most 300 in modulus (u <= 2, v <= 1) and
   !> 199 along the solution, whatever N. g(t, U) = A U + b(t), A fixed by the grid,
   !> b(t) = (beta_1/dzeta^2 - alpha_1/(2 dzeta)) phi(t) e_1: g is declared linear.
   !> phi jumps at t = 5: integrate to 5 and restart there, as the test set's drivers do.
   !> N >= 2.
   type, extends(test_problem_type) :: medical_akzo_type
      !> Grid points N (2N unknowns)
      integer :: points = 200
      !> Rate constant k of the reaction
      real(dp) :: k = 100.0_dp
      !> Length scale c of the map from x to zeta
      real(dp) :: c = 4.0_dp
      !> Boundary value phi of u until t = switch_time, 0 after
      real(dp) :: boundary_value = 2.0_dp
      !> Time at which the boundary value drops to 0
      real(dp) :: switch_time = 5.0_dp
      !> The band of a Jacobian asked for dense (allocated at the first such request: a
      !> local array of this size would be allocated at every call)
      real(dp), allocatable :: band_work(:, :)
   contains
      !> Non-stiff part f: the reaction
      procedure :: f => akzo_f
      !> Stiff part g: diffusion and advection with the boundary value
      procedure :: g => akzo_g
      !> F = f + g in one call
      procedure :: rhs => akzo_rhs
      !> df/dU, dense: jac_f_band unpacked (the schemes use the band)
      procedure :: jac_f => akzo_jac_f
      !> dg/dU, dense: jac_g_band unpacked
      procedure :: jac_g => akzo_jac_g
      !> Bandwidths 2 and 2
      procedure :: jacobian_structure => akzo_structure
      !> df/dU in band storage: the 2 x 2 reaction block of each point
      procedure :: jac_f_band => akzo_jac_f_band
      !> dg/dU in band storage: the three-point stencil of the u's
      procedure :: jac_g_band => akzo_jac_g_band
      !> J = df/dU + dg/dU in band storage in one call
      procedure :: jac_band => akzo_jac_band
      !> y + alpha J v without forming J
      procedure :: add_jacobian_product => akzo_add_jacobian_product
   end type medical_akzo_type

contains

   !> MEDAKZO on `points` grid points (default 200, the published size) over [0, 20];
   !> the published solution at t = 20 (all 400 components) is attached for N = 200.
   pure function new_medical_akzo(points) result(self)
      !> Grid points N >= 2 (2N unknowns)
      integer, intent(in), optional :: points
      type(medical_akzo_type) :: self
      integer :: j
      if (present(points)) self%points = points
      self%name = "medakzo"
      ! g = A U + b(t), A constant
      self%linear_g = .true.
      self%t_end = 20.0_dp
      self%u0 = [(0.0_dp, 1.0_dp, j=1, self%points)]
      self%rtol = 1.0e-6_dp
      self%atol = 1.0e-6_dp
      self%nonnegative = .true.
      if (self%points == 200) self%reference = published_solution()
      self%source = "Bari test set MEDAKZO (R. van der Hout, Akzo Nobel; medakzo.f: equations and the "// &
         "reference solution, PSIDE at rtol = atol = 1e-10 in Cray double precision)"
   end function new_medical_akzo

   !> The stencil of u_j: g_u(j) = low u_(j-1) + mid u_j + high u_(j+1).
   pure subroutine stencil(self, j, low, mid, high)
      class(medical_akzo_type), intent(in) :: self
      integer, intent(in) :: j
      real(dp), intent(out) :: low, mid, high
      real(dp) :: dzeta, zeta, w, diffusion, advection
      dzeta = 1.0_dp/real(self%points, dp)
      zeta = real(j, dp)*dzeta
      w = (zeta - 1.0_dp)**2/self%c
      ! beta/dzeta^2 and alpha/(2 dzeta)
      diffusion = w*w/dzeta**2
      advection = (zeta - 1.0_dp)*w/(self%c*dzeta)
      low = diffusion - advection
      mid = -2.0_dp*diffusion
      high = diffusion + advection
   end subroutine stencil

   !> u_0(t) = phi(t)
   pure real(dp) function boundary(self, t)
      class(medical_akzo_type), intent(in) :: self
      real(dp), intent(in) :: t
      boundary = merge(self%boundary_value, 0.0_dp, t <= self%switch_time)
   end function boundary

   subroutine akzo_f(self, t, u, dudt)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = 0.0_dp
      call add_reaction(self, u, dudt)
   end subroutine akzo_f

   !> The reaction -k u_j v_j added to both equations of every point.
   pure subroutine add_reaction(self, u, dudt)
      class(medical_akzo_type), intent(in) :: self
      real(dp), intent(in) :: u(:)
      real(dp), intent(inout) :: dudt(:)
      real(dp) :: reaction
      integer :: j
      do j = 1, self%points
         reaction = -self%k*u(2*j - 1)*u(2*j)
         dudt(2*j - 1) = dudt(2*j - 1) + reaction
         dudt(2*j) = dudt(2*j) + reaction
      end do
   end subroutine add_reaction

   subroutine akzo_g(self, t, u, dudt)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      real(dp) :: low, mid, high, left, right
      integer :: j, n
      n = self%points
      ! u_(j-1), carried along: phi(t) at the first point
      left = boundary(self, t)
      do j = 1, n
         call stencil(self, j, low, mid, high)
         if (j < n) then
            right = u(2*j + 1)
         else
            right = u(2*n - 3)
         end if
         dudt(2*j - 1) = low*left + mid*u(2*j - 1) + high*right
         dudt(2*j) = 0.0_dp
         left = u(2*j - 1)
      end do
   end subroutine akzo_g

   !> f + g: g, then the reaction added (f is the reaction added to zero).
   subroutine akzo_rhs(self, t, u, dudt)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      call self%g(t, u, dudt)
      call add_reaction(self, u, dudt)
   end subroutine akzo_rhs

   subroutine akzo_jac_f(self, t, u, jac)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      if (.not. band_work_ready(self, size(u), jac)) return
      call self%jac_f_band(t, u, self%band_work)
      call unpack_band(lower, upper, self%band_work, jac)
   end subroutine akzo_jac_f

   subroutine akzo_jac_g(self, t, u, jac)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      if (.not. band_work_ready(self, size(u), jac)) return
      call self%jac_g_band(t, u, self%band_work)
      call unpack_band(lower, upper, self%band_work, jac)
   end subroutine akzo_jac_g

   !> Whether band_work has n columns (allocated once for a problem size); when it
   !> cannot be allocated, the evaluation is rejected fatally (the integration stops
   !> with a status), jac is zeroed and the result is false.
   logical function band_work_ready(self, n, jac)
      class(medical_akzo_type), intent(inout) :: self
      integer, intent(in) :: n
      real(dp), intent(out) :: jac(:, :)
      type(status_type) :: stat
      call sized(self%band_work, lower + upper + 1, n, "MEDAKZO's band Jacobian", stat)
      band_work_ready = stat%code == status_ok
      if (band_work_ready) return
      call self%reject_evaluation(fatal=.true.)
      jac = 0.0_dp
   end function band_work_ready

   !> Lower and upper bandwidths 2.
   function akzo_structure(self, n) result(structure)
      class(medical_akzo_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = band_structure(lower, upper)
   end function akzo_structure

   !> df/dU in band storage: -k (v_j, u_j) in both rows of point j.
   subroutine akzo_jac_f_band(self, t, u, band)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      band = 0.0_dp
      call add_reaction_band(self, u, band)
   end subroutine akzo_jac_f_band

   !> The reaction's 2 x 2 block of every point added to a band: d(-k u_j v_j)/d(u_j, v_j)
   !> = -k (v_j, u_j) in the rows of u_j and v_j.
   pure subroutine add_reaction_band(self, u, band)
      class(medical_akzo_type), intent(in) :: self
      real(dp), intent(in) :: u(:)
      real(dp), intent(inout) :: band(:, :)
      integer :: j
      do j = 1, self%points
         band(diagonal, 2*j - 1) = band(diagonal, 2*j - 1) + (-self%k*u(2*j))
         band(diagonal + 1, 2*j - 1) = band(diagonal + 1, 2*j - 1) + (-self%k*u(2*j))
         band(diagonal - 1, 2*j) = band(diagonal - 1, 2*j) + (-self%k*u(2*j - 1))
         band(diagonal, 2*j) = band(diagonal, 2*j) + (-self%k*u(2*j - 1))
      end do
   end subroutine add_reaction_band

   !> dg/dU in band storage: column 2j - 1 holds the coefficients of u_j in the rows of
   !> u_(j-1), u_j and u_(j+1) (offsets -2, 0, +2); at j = N the reflected u_(N+1) = u_(N-1)
   !> adds the high coefficient of u_N to its low one.
   subroutine akzo_jac_g_band(self, t, u, band)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      real(dp) :: low, mid, high
      integer :: j, n, column
      n = self%points
      band = 0.0_dp
      do j = 1, n
         call stencil(self, j, low, mid, high)
         ! u_j's row 2j - 1 has low in the column of u_(j-1), two to the left
         column = 2*j - 1
         band(diagonal, column) = mid
         if (j > 1) band(diagonal + 2, column - 2) = low
         if (j < n) then
            band(diagonal - 2, column + 2) = high
         else
            band(diagonal + 2, column - 2) = low + high
         end if
      end do
   end subroutine akzo_jac_g_band

   !> J = df/dU + dg/dU in band storage: the diffusion, then each point's reaction block added.
   subroutine akzo_jac_band(self, t, u, band)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      call self%jac_g_band(t, u, band)
      call add_reaction_band(self, u, band)
   end subroutine akzo_jac_band

   !> y + alpha J v with the entries of akzo_jac_band (the stencil, whose boundary value phi(t)
   !> does not depend on U, and the reaction), each row's terms added in the order of the columns:
   !> the same numbers as J from akzo_jac_band times v column by column (the default), bit for bit.
   subroutine akzo_add_jacobian_product(self, t, u, alpha, v, y)
      class(medical_akzo_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(in) :: alpha
      real(dp), intent(in) :: v(:)
      real(dp), intent(inout) :: y(:)
      real(dp) :: low, mid, high, ku_odd, ku_even
      integer :: j, n, k
      n = self%points
      do j = 1, n
         call stencil(self, j, low, mid, high)
         ku_even = -self%k*u(2*j)
         ku_odd = -self%k*u(2*j - 1)
         ! the row of u_j: u_(j-1) (u_(n-1) twice at the far end), u_j, v_j, u_(j+1)
         k = 2*j - 1
         if (j > 1) then
            if (j < n) then
               y(k) = y(k) + (alpha*v(k - 2))*low
            else
               y(k) = y(k) + (alpha*v(k - 2))*(low + high)
            end if
         end if
         y(k) = y(k) + (alpha*v(k))*(mid + ku_even)
         y(k) = y(k) + (alpha*v(k + 1))*ku_odd
         if (j < n) y(k) = y(k) + (alpha*v(k + 2))*high
         ! the row of v_j: u_j, v_j
         y(k + 1) = y(k + 1) + (alpha*v(k))*ku_even
         y(k + 1) = y(k + 1) + (alpha*v(k + 1))*ku_odd
      end do
   end subroutine akzo_add_jacobian_product

   !> The test set's solution at t = 20 for N = 200 (medakzo.f, all 400 components;
   !> the v's below about 1e-100 are at the level of that computation's rounding).
   pure function published_solution() result(y)
      real(dp) :: y(400)
      y = [ &
         0.5113983840919909e-5_dp, 0.1925112884312553e-143_dp, 0.1027858770570419e-4_dp, 0.1890518289312031e-142_dp, &
         0.1549349862635799e-4_dp, 0.1774199325357386e-142_dp, 0.2075835344757462e-4_dp, 0.5897341137981092e-143_dp, &
         0.2607273610116854e-4_dp, 0.1093527900908030e-143_dp, 0.3143617475695002e-4_dp, 0.1188834841626416e-144_dp, &
         0.3684813884509626e-4_dp, 0.9968323236025642e-147_dp, 0.4230803594492533e-4_dp, -0.2801994001528093e-146_dp, &
         0.4781520853483223e-4_dp, -0.7337417669341249e-147_dp, 0.5336893059800053e-4_dp, -0.1209033101530330e-147_dp, &
         0.5896840407836044e-4_dp, -0.1430357497530360e-148_dp, 0.6461275518112516e-4_dp, -0.1063952641824646e-149_dp, &
         0.7030103051210320e-4_dp, 0.7939969136126717e-152_dp, 0.7603219304985662e-4_dp, 0.1568246940545520e-150_dp, &
         0.8180511794465543e-4_dp, 0.4074950357924872e-150_dp, 0.8761858813806752e-4_dp, 0.5592746648679992e-150_dp, &
         0.9347128979692480e-4_dp, -0.5510388943414421e-151_dp, 0.9936180755532036e-4_dp, -0.2724738349250769e-149_dp, &
         0.1052886195582220e-3_dp, -0.9327772452398718e-149_dp, 0.1112500923002360e-3_dp, -0.2182885200987554e-148_dp, &
         0.1172444752530255e-3_dp, -0.4041450806475518e-148_dp, 0.1232698952748828e-3_dp, -0.5608157478395261e-148_dp, &
         0.1293243507959787e-3_dp, -0.2639662630908699e-148_dp, 0.1354057057728661e-3_dp, 0.1801866277537073e-147_dp, &
         0.1415116834059119e-3_dp, 0.8464449882759417e-147_dp, 0.1476398596134615e-3_dp, 0.2245234937355967e-146_dp, &
         0.1537876562567258e-3_dp, 0.3359213489153582e-146_dp, 0.1599523341096154e-3_dp, -0.3085721171916412e-146_dp, &
         0.1661309855680449e-3_dp, -0.4465322607423735e-145_dp, 0.1723205270935920e-3_dp, -0.1970925996866384e-144_dp, &
         0.1785176913868402e-3_dp, -0.6070953121563027e-144_dp, 0.1847190192862588e-3_dp, -0.1412011918930335e-143_dp, &
         0.1909208513890961e-3_dp, -0.2378861987352203e-143_dp, 0.1971193193914910e-3_dp, -0.2380432473186974e-143_dp, &
         0.2033103371458565e-3_dp, -0.6522557638254663e-145_dp, 0.2094895914345677e-3_dp, 0.1784305601809064e-143_dp, &
         0.2156525324601176e-3_dp, -0.1007474781780816e-142_dp, 0.2217943640531935e-3_dp, -0.5281511349479423e-142_dp, &
         0.2279100336016016e-3_dp, -0.1117525482975987e-141_dp, 0.2339942217046434e-3_dp, -0.1127916494884468e-141_dp, &
         0.2400413315594459e-3_dp, -0.1633306916231411e-142_dp, 0.2460454780878912e-3_dp, 0.2708874035585891e-143_dp, &
         0.2520004768152150e-3_dp, -0.2501941069702609e-142_dp, 0.2578998325140575e-3_dp, -0.2642308070750020e-141_dp, &
         0.2637367276308081e-3_dp, -0.3684887530751217e-139_dp, 0.2695040105145025e-3_dp, -0.3647274179805887e-138_dp, &
         0.2751941834723564e-3_dp, -0.1255641406397419e-137_dp, 0.2807993906802854e-3_dp, -0.1694257216823904e-138_dp, &
         0.2863114059815211e-3_dp, -0.1785516142939602e-136_dp, 0.2917216206117258e-3_dp, -0.3935939757647002e-135_dp, &
         0.2970210308948898e-3_dp, -0.2514765666933440e-134_dp, 0.3022002259608294e-3_dp, -0.7200873856605984e-134_dp, &
         0.3072493755423352e-3_dp, -0.7539683247227422e-134_dp, 0.3121582179180383e-3_dp, 0.3738577086039426e-135_dp, &
         0.3169160480759169e-3_dp, -0.2493582962172335e-131_dp, 0.3215117061821543e-3_dp, 0.3039632438293726e-130_dp, &
         0.3259335664508512e-3_dp, 0.5321044068586611e-128_dp, 0.3301695265219917e-3_dp, -0.1918129324351378e-126_dp, &
         0.3342069974681551e-3_dp, -0.1336929159252586e-124_dp, 0.3380328945648600e-3_dp, 0.9521748754010357e-123_dp, &
         0.3416336289752354e-3_dp, 0.1001197393324181e-120_dp, 0.3449951005170561e-3_dp, 0.2703860993866771e-119_dp, &
         0.3481026916991771e-3_dp, 0.4365133580297076e-119_dp, 0.3509412632351946e-3_dp, 0.4898111237855383e-115_dp, &
         0.3534951512648823e-3_dp, 0.1621439381962246e-112_dp, 0.3557481665387581e-3_dp, 0.3003220203772183e-110_dp, &
         0.3576835958481664e-3_dp, 0.5931668289615909e-108_dp, 0.3592842060126915e-3_dp, 0.2235590472383775e-105_dp, &
         0.3605322507686931e-3_dp, 0.1025457293602057e-102_dp, 0.3614094809374544e-3_dp, 0.3496613568296336e-100_dp, &
         0.3618971582890092e-3_dp, 0.4767073568395508e-98_dp, 0.3619760735583436e-3_dp, -0.2410784286794997e-95_dp, &
         0.3616265691144918e-3_dp, -0.9188398110576038e-93_dp, 0.3608285668302233e-3_dp, 0.1146623087995081e-89_dp, &
         0.3595616017506735e-3_dp, 0.1649638439865233e-86_dp, 0.3578048622135169e-3_dp, 0.1215140240350217e-83_dp, &
         0.3555372371311931e-3_dp, 0.7134490346394154e-81_dp, 0.3527373712073181e-3_dp, 0.4502515392738464e-78_dp, &
         0.3493837289247301e-3_dp, 0.7138395988310312e-75_dp, 0.3454546682115489e-3_dp, 0.9941693919247076e-71_dp, &
         0.3409285247640208e-3_dp, 0.2012859826753015e-66_dp, 0.3357837080804970e-3_dp, 0.3598261520662423e-62_dp, &
         0.3299988103392750e-3_dp, 0.5466580008990664e-58_dp, 0.3235527293336597e-3_dp, 0.6945384844951550e-54_dp, &
         0.3164248067597393e-3_dp, 0.7275415527806026e-50_dp, 0.3085949832350532e-3_dp, 0.6193143746524996e-46_dp, &
         0.3000439715082906e-3_dp, 0.4219255556214135e-42_dp, 0.2907534493998412e-3_dp, 0.2263678154715720e-38_dp, &
         0.2807062740884081e-3_dp, 0.9401607967545219e-35_dp, 0.2698867194275612e-3_dp, 0.2968231730793053e-31_dp, &
         0.2582807380350103e-3_dp, 0.6987463944434805e-28_dp, 0.2458762499428408e-3_dp, 0.1201641789884051e-24_dp, &
         0.2326634596245027e-3_dp, 0.1477169946829840e-21_dp, 0.2186352032185982e-3_dp, 0.1268462422099779e-18_dp, &
         0.2037873277440060e-3_dp, 0.7425015664001834e-16_dp, 0.1881191040379240e-3_dp, 0.2886826929895103e-13_dp, &
         0.1716336750388461e-3_dp, 0.7252477041900172e-11_dp, 0.1543385408702044e-3_dp, 0.1143390654212691e-8_dp, &
         0.1362460820444338e-3_dp, 0.1096625145716966e-6_dp, 0.1173741304462833e-3_dp, 0.6190822732534586e-5_dp, &
         0.9774701310627047e-4_dp, 0.1986273404756002e-3_dp, 0.7740788649977313e-4_dp, 0.3489773624098464e-2_dp, &
         0.5657119003189305e-4_dp, 0.3234526094359604e-1_dp, 0.3643334879766658e-4_dp, 0.1548747348410801e0_dp, &
         0.2003152841880950e-4_dp, 0.4026980529594953e0_dp, 0.9608297851720770e-5_dp, 0.6649744834198490e0_dp, &
         0.4215537698495267e-5_dp, 0.8409284546320647e0_dp, 0.1753504402754791e-5_dp, 0.9314946676956936e0_dp, &
         0.7048158429518009e-6_dp, 0.9720896201631835e0_dp, 0.2760943506466737e-6_dp, 0.9890204872799944e0_dp, &
         0.1057554501281432e-6_dp, 0.9957930123519514e0_dp, 0.3965142250779033e-7_dp, 0.9984246531478463e0_dp, &
         0.1455273204279008e-7_dp, 0.9994229325942358e0_dp, 0.5226348147846279e-8_dp, 0.9997932125999319e0_dp, &
         0.1835610545325733e-8_dp, 0.9999275409325039e0_dp, 0.6301078589385454e-9_dp, 0.9999751869380269e0_dp, &
         0.2112538351365564e-9_dp, 0.9999917015131560e0_dp, 0.6912550453447044e-10_dp, 0.9999972914302640e0_dp, &
         0.2205932132514696e-10_dp, 0.9999991378543379e0_dp, 0.6860095639285670e-11_dp, 0.9999997325855174e0_dp, &
         0.2077324462852526e-11_dp, 0.9999999192384585e0_dp, 0.6120038908594393e-12_dp, 0.9999999762710279e0_dp, &
         0.1752695518797070e-12_dp, 0.9999999932230490e0_dp, 0.4875001992978682e-13_dp, 0.9999999981203191e0_dp, &
         0.1315706848908981e-13_dp, 0.9999999994941428e0_dp, 0.3442274192104633e-14_dp, 0.9999999998680372e0_dp, &
         0.8721783456154470e-15_dp, 0.9999999999666630e0_dp, 0.2137938962858872e-15_dp, 0.9999999999918528e0_dp, &
         0.5064735930780995e-16_dp, 0.9999999999980759e0_dp, 0.1158284928109727e-16_dp, 0.9999999999995613e0_dp, &
         0.2554350586347124e-17_dp, 0.9999999999999036e0_dp, 0.5425563935887811e-18_dp, 0.9999999999999796e0_dp, &
         0.1108623976460997e-18_dp, 0.9999999999999958e0_dp, 0.2176490922739810e-19_dp, 0.9999999999999992e0_dp, &
         0.4100180074816888e-20_dp, 0.9999999999999998e0_dp, 0.7401919443964595e-21_dp, 0.1000000000000000e1_dp, &
         0.1278745657114596e-21_dp, 0.1000000000000000e1_dp, 0.2111087049605767e-22_dp, 0.1000000000000000e1_dp, &
         0.3325632734364699e-23_dp, 0.1000000000000000e1_dp, 0.4991515592566292e-24_dp, 0.1000000000000000e1_dp, &
         0.7126950428617158e-25_dp, 0.1000000000000000e1_dp, 0.9664740804131475e-26_dp, 0.1000000000000000e1_dp, &
         0.1242716896959521e-26_dp, 0.1000000000000000e1_dp, 0.1512543532243458e-27_dp, 0.1000000000000000e1_dp, &
         0.1739533019752215e-28_dp, 0.1000000000000000e1_dp, 0.1886942537979667e-29_dp, 0.1000000000000000e1_dp, &
         0.1926965705022792e-30_dp, 0.1000000000000000e1_dp, 0.1849021812823421e-31_dp, 0.1000000000000000e1_dp, &
         0.1663798767415642e-32_dp, 0.1000000000000000e1_dp, 0.1401076830818626e-33_dp, 0.1000000000000000e1_dp, &
         0.1101818149402153e-34_dp, 0.1000000000000000e1_dp, 0.8074224739509168e-36_dp, 0.1000000000000000e1_dp, &
         0.5501249196662931e-37_dp, 0.1000000000000000e1_dp, 0.3476859813132770e-38_dp, 0.1000000000000000e1_dp, &
         0.2033489290876775e-39_dp, 0.1000000000000000e1_dp, 0.1097880013869247e-40_dp, 0.1000000000000000e1_dp, &
         0.5457825200381417e-42_dp, 0.1000000000000000e1_dp, 0.2491675366427318e-43_dp, 0.1000000000000000e1_dp, &
         0.1041801880291617e-44_dp, 0.1000000000000000e1_dp, 0.3978066491064419e-46_dp, 0.1000000000000000e1_dp, &
         0.1383174699098532e-47_dp, 0.1000000000000000e1_dp, 0.4365911791079500e-49_dp, 0.1000000000000000e1_dp, &
         0.1247057764661705e-50_dp, 0.1000000000000000e1_dp, 0.3212728839963712e-52_dp, 0.1000000000000000e1_dp, &
         0.7439366703571565e-54_dp, 0.1000000000000000e1_dp, 0.1542770387822259e-55_dp, 0.1000000000000000e1_dp, &
         0.2854454245592573e-57_dp, 0.1000000000000000e1_dp, 0.4693220411250150e-59_dp, 0.1000000000000000e1_dp, &
         0.6828458274546624e-61_dp, 0.1000000000000000e1_dp, 0.8752952529541412e-63_dp, 0.1000000000000000e1_dp, &
         0.9838541433761416e-65_dp, 0.1000000000000000e1_dp, 0.9649177728609193e-67_dp, 0.1000000000000000e1_dp, &
         0.8213596936190817e-69_dp, 0.1000000000000000e1_dp, 0.6033986647865674e-71_dp, 0.1000000000000000e1_dp, &
         0.3802531117966294e-73_dp, 0.1000000000000000e1_dp, 0.2042261117698575e-75_dp, 0.1000000000000000e1_dp, &
         0.9282595096128614e-78_dp, 0.1000000000000000e1_dp, 0.3543587864454877e-80_dp, 0.1000000000000000e1_dp, &
         0.1126779423370979e-82_dp, 0.1000000000000000e1_dp, 0.2957534367766753e-85_dp, 0.1000000000000000e1_dp, &
         0.6344600529877694e-88_dp, 0.1000000000000000e1_dp, 0.1100279075462365e-90_dp, 0.1000000000000000e1_dp, &
         0.1523845293461783e-93_dp, 0.1000000000000000e1_dp, 0.1662696161555950e-96_dp, 0.1000000000000000e1_dp, &
         0.1407578290673998e-99_dp, 0.1000000000000000e1_dp, 0.9086150803567186e-103_dp, 0.1000000000000000e1_dp, &
         0.4384339596163745e-106_dp, 0.1000000000000000e1_dp, 0.1545482064392824e-109_dp, 0.1000000000000000e1_dp, &
         0.3874172613928345e-113_dp, 0.1000000000000000e1_dp, 0.6689452219441953e-117_dp, 0.1000000000000000e1_dp, &
         0.7655680935317283e-121_dp, 0.1000000000000000e1_dp, 0.5538543899545850e-125_dp, 0.1000000000000000e1_dp, &
         0.2386173886563501e-129_dp, 0.1000000000000000e1_dp, 0.5664887497790931e-134_dp, 0.1000000000000000e1_dp, &
         0.6671124967149171e-139_dp, 0.1000000000000000e1_dp, 0.3351973480286951e-144_dp, 0.1000000000000000e1_dp, &
         0.5684315818559200e-150_dp, 0.1000000000000000e1_dp, 0.2142121793294590e-156_dp, 0.1000000000000000e1_dp, &
         0.6727117900187205e-164_dp, 0.1000000000000000e1_dp, 0.0000000000000000e0_dp, 0.1000000000000000e1_dp]
   end function published_solution

end module taylorode_testset_medical_akzo
