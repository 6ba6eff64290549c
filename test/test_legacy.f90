!> The legacy entry TAYLORODE as a RADAU5 user meets it: RADAU5's settings checked as
!> RADAU5 checks them, TAYLORODE('radau5', ...) integrating as RADAU5 (its tolerances,
!> norm and step-size rules), RADAU5's statistics, the evaluation flag in IPAR, mass
!> matrices, the messages.
module test_legacy
   use testdrive, only: new_unittest, unittest_type, error_type, check
   use test_support, only: stat_message
   use taylorode_base_strings, only: format_real, format_integer
   use taylorode, only: dp, i8, ode_problem, scheme_type, status_type, new_scheme, integrate, &
      integrator_options_type, integration_stats_type, norm_rms, status_ok
   use taylorode_testset, only: new_transistor_amplifier, transistor_amplifier_type
   use taylorode_schemes_radau5, only: radau5_type
   use taylorode_interfaces_legacy, only: legacy_solve, legacy_message, legacy_no_mass, legacy_interpolate
   use taylorode_interfaces_legacy_entry, only: fcn_interface, jac_interface, mas_interface, solout_interface
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
   implicit none
   private

   public :: collect_legacy

   !> Van der Pol's mu, and the problem's span
   real(dp), parameter :: mu = 1000.0_dp, vdp_end = 2.0_dp
   !> Storage large enough for RADAU5 itself on 8 unknowns (4 N^2 + 12 N + 20, 3 N + 20)
   integer, parameter :: lwork = 4*8*8 + 12*8 + 20, liwork = 3*8 + 20

   !> The states of the first calls of recorded_vdp, and how many it recorded
   real(dp) :: recorded_states(2, 8)
   integer :: recorded_calls = 0

   !> The same Van der Pol as `vdp` below, as an ode_problem (F and J in one call each)
   type, extends(ode_problem) :: vdp_type
   contains
      procedure :: f => vdp_zero
      procedure :: g => vdp_rhs
      procedure :: rhs => vdp_rhs
      procedure :: jac_f => vdp_zero_jacobian
      procedure :: jac_g => vdp_jac
      procedure :: jac => vdp_jac
   end type vdp_type

   interface
      !> The legacy entry's external procedures, declared as a program declares them
      subroutine taylorode_message(iwork, text)
         integer, intent(in) :: iwork(*)
         character(len=*), intent(out) :: text
      end subroutine taylorode_message
      subroutine taylorode(scheme, n, fcn, x, y, xend, h, rtol, atol, itol, jac, ijac, mljac, mujac, mas, imas, &
         mlmas, mumas, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
         import :: dp, fcn_interface, jac_interface, mas_interface, solout_interface
         character(len=*), intent(in) :: scheme
         integer, intent(in) :: n, itol, ijac, mljac, mujac, imas, mlmas, mumas, iout, lwork, liwork
         procedure(fcn_interface) :: fcn
         procedure(jac_interface) :: jac
         procedure(mas_interface) :: mas
         procedure(solout_interface) :: solout
         real(dp), intent(inout) :: x, y(n), h, work(*), rpar(*)
         real(dp), intent(in) :: xend, rtol(*), atol(*)
         integer, intent(inout) :: iwork(*), ipar(*)
         integer, intent(out) :: idid
      end subroutine taylorode
      subroutine taylorode_split(scheme, n, fcnf, fcng, x, y, xend, h, rtol, atol, itol, jacf, ijacf, jacg, ijacg, &
         mljac, mujac, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
         import :: dp, fcn_interface, jac_interface, solout_interface
         character(len=*), intent(in) :: scheme
         integer, intent(in) :: n, itol, ijacf, ijacg, mljac, mujac, iout, lwork, liwork
         procedure(fcn_interface) :: fcnf, fcng
         procedure(jac_interface) :: jacf, jacg
         procedure(solout_interface) :: solout
         real(dp), intent(inout) :: x, y(n), h, work(*), rpar(*)
         real(dp), intent(in) :: xend, rtol(*), atol(*)
         integer, intent(inout) :: iwork(*), ipar(*)
         integer, intent(out) :: idid
      end subroutine taylorode_split
      function taylorode_contr(i, s, cont, lrc) result(value)
         import :: dp
         integer, intent(in) :: i, lrc
         real(dp), intent(in) :: s, cont(lrc)
         real(dp) :: value
      end function taylorode_contr
   end interface

contains

   !> Collect all exported unit tests
   subroutine collect_legacy(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("contr-outside-the-step-is-nan", test_contr_outside), &
         new_unittest("contr-extrapolates-as-contr5", test_contr_extrapolates), &
         new_unittest("solout-writes-the-state", test_solout_writes_state), &
         new_unittest("empty-interval-as-radau5", test_empty_interval), &
         new_unittest("singular-attempts-are-not-steps", test_singular_not_steps), &
         new_unittest("radau5-named-with-blanks", test_radau5_named_with_blanks), &
         new_unittest("settings-checked-as-radau5", test_settings_checked), &
         new_unittest("settings-in-range-accepted", test_settings_accepted), &
         new_unittest("radau5-as-radau5", test_radau5_as_radau5), &
         new_unittest("first-rejection-as-radau5", test_first_rejection), &
         new_unittest("first-step-rules-setting", test_first_step_rules), &
         new_unittest("hold-band-as-radau5", test_hold_band), &
         new_unittest("difference-jacobian-from-fcn", test_difference_jacobian), &
         new_unittest("difference-increment-from-uround", test_difference_increment), &
         new_unittest("newton-iterations-honoured", test_newton_iterations), &
         new_unittest("fcn-may-write-x-and-y", test_fcn_writes_arguments), &
         new_unittest("step-budget-statistics", test_budget), &
         new_unittest("step-too-small-as-radau5", test_step_too_small), &
         new_unittest("evaluation-flag", test_evaluation_flag), &
         new_unittest("mass-transistor-amplifier", test_mass_transistor_amplifier), &
         new_unittest("messages", test_messages), &
         new_unittest("external-procedures-as-module", test_external_procedures) &
         ]
   end subroutine collect_legacy

   !> TAYLORODE_CONTR (legacy_interpolate) on a step packed by hand (N = 1, degree 1:
   !> XOLD, H, N, degree, one node, two coefficients) gives the Newton form's value, and
   !> NaN for a component outside 1..N or a CONT whose header does not fit LRC: I = 3
   !> read past the coefficients and I = 1e8 ended in SIGSEGV.
   subroutine test_contr_outside(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: cont(7), value, bad(7)
      integer :: k
      integer, parameter :: outside(3) = [0, 2, 100000000]
      cont = [1.0_dp, 2.0_dp, 1.0_dp, 1.0_dp, 0.25_dp, 3.0_dp, 4.0_dp]
      ! theta = (2 - 1)/2 = 0.5: 3 + (0.5 - 0.25) 4
      value = legacy_interpolate(1, 2.0_dp, cont, 7)
      call check(error, value, 4.0_dp, "inside the step")
      if (allocated(error)) return
      do k = 1, size(outside)
         value = legacy_interpolate(outside(k), 2.0_dp, cont, 7)
         call check(error, ieee_is_nan(value), "I = "//format_integer(outside(k))//": "//format_real(value))
         if (allocated(error)) return
      end do
      bad = cont
      bad(3) = 1.0e300_dp
      call check(error, ieee_is_nan(legacy_interpolate(1, 2.0_dp, bad, 7)), "N = 1e300 in CONT")
      if (allocated(error)) return
      bad = cont
      bad(4) = 5.0_dp
      call check(error, ieee_is_nan(legacy_interpolate(1, 2.0_dp, bad, 7)), "degree 5 in CONT of LRC 7")
      if (allocated(error)) return
      call check(error, ieee_is_nan(legacy_interpolate(1, 2.0_dp, cont, 4)), "LRC = 4")
   end subroutine test_contr_outside

   !> TAYLORODE_CONTR beyond [XOLD, X] extrapolates the step's polynomial, as CONTR5 does
   !> (it gave Y at X before: 0.15 relative at worst here): radau5 on y' = -y at RTOL
   !> 1e-6, the value half a step past each step's end against exp(-S), within 1e-3
   !> (1.4e-4 at worst: a cubic extrapolated beyond the points it was fitted to).
   subroutine test_contr_extrapolates(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(1), h, rpar(2)
      integer :: iwork(liwork), idid
      character(len=:), allocatable :: message
      x = 0.0_dp
      h = 1.0e-3_dp
      call solve_decay("radau5", 1, x, 2.0_dp, h, decay_jacobian, y, iwork, rpar, idid, message, extrapolating)
      call check(error, idid, 1, message)
      if (allocated(error)) return
      call check(error, rpar(2) > 0.0_dp .and. rpar(1) <= 1.0e-3_dp, "largest relative error half a step past X: "// &
         format_real(rpar(1)))
   end subroutine test_contr_extrapolates

   !> RADAU5 hands SOLOUT its Y, and what SOLOUT writes there is the state it goes on
   !> from (they were ignored: SOLOUT was given a copy). y' = -y from 1 over [0, 2], Y
   !> tripled at NR = 1 and halved at the first output past 0.55: Y(2) = 1.5 exp(-2), with
   !> radau5 and i-t-2.
   subroutine test_solout_writes_state(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = [character(len=6) :: "radau5", "i-t-2"]
      real(dp) :: x, y(1), h, rpar(1)
      integer :: iwork(liwork), idid, k
      character(len=:), allocatable :: message
      do k = 1, size(names)
         x = 0.0_dp
         h = 1.0e-3_dp
         call solve_decay(trim(names(k)), 1, x, 2.0_dp, h, decay_jacobian, y, iwork, rpar, idid, message, kicking)
         call check(error, idid, 1, trim(names(k))//": "//message)
         if (allocated(error)) return
         call check(error, abs(y(1) - 1.5_dp*exp(-2.0_dp)) <= 1.0e-4_dp, trim(names(k))//": Y(2) = "// &
            format_real(y(1))//", 1.5 exp(-2) = "//format_real(1.5_dp*exp(-2.0_dp)))
         if (allocated(error)) return
      end do
   end subroutine test_solout_writes_state

   !> X = XEND is a step too small for RADAU5: IDID = -3, H = 0, SOLOUT called once
   !> (at NR = 1), X and Y as given (it was refused with IDID = -1).
   subroutine test_empty_interval(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(1), h, rpar(2)
      integer :: iwork(liwork), idid
      character(len=:), allocatable :: message
      x = 1.0_dp
      h = 1.0e-3_dp
      call solve_decay("radau5", 1, x, 1.0_dp, h, decay_jacobian, y, iwork, rpar, idid, message, extrapolating)
      call check(error, idid, -3, message)
      if (allocated(error)) return
      call check(error, h == 0.0_dp .and. x == 1.0_dp .and. y(1) == 1.0_dp .and. nint(rpar(2)) == 0, &
         "H = "//format_real(h)//", X = "//format_real(x)//", Y = "//format_real(y(1))//", SOLOUT after NR = 1: "// &
         format_integer(nint(rpar(2))))
   end subroutine test_empty_interval

   !> RADAU5 counts a step (NSTEP, IWORK(16)) once its matrices are factored: attempts
   !> with a singular Newton matrix are not steps. y' = -y in two components with a JAC
   !> of 1e300 everywhere (fac I - J is singular at every step size): IDID = -4 with NSTEP
   !> = 0 (it was 5).
   subroutine test_singular_not_steps(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(2), h, rpar(1)
      integer :: iwork(liwork), idid
      character(len=:), allocatable :: message
      x = 0.0_dp
      h = 1.0e-6_dp
      call solve_decay("radau5", 2, x, 2.0_dp, h, huge_jacobian, y, iwork, rpar, idid, message)
      call check(error, idid, -4, "IDID = "//format_integer(idid)//": "//message)
      if (allocated(error)) return
      call check(error, iwork(16) == 0 .and. iwork(17) == 0, "NSTEP = "//format_integer(iwork(16))//", NACCPT = "// &
         format_integer(iwork(17)))
   end subroutine test_singular_not_steps

   !> ' radau5' names radau5 as 'radau5' does, with RADAU5's meaning of RTOL and ATOL:
   !> the name with a leading blank went to the registry's radau5 with the library's
   !> meaning (9 steps against 11, and RADAU5's checks of RTOL and ATOL skipped).
   subroutine test_radau5_named_with_blanks(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(1), h, rpar(1), y_plain(1)
      integer :: iwork(liwork), iwork_plain(liwork), idid
      character(len=:), allocatable :: message
      x = 0.0_dp
      h = 1.0e-3_dp
      call solve_decay("radau5", 1, x, 2.0_dp, h, decay_jacobian, y_plain, iwork_plain, rpar, idid, message)
      call check(error, idid, 1, message)
      if (allocated(error)) return
      x = 0.0_dp
      h = 1.0e-3_dp
      call solve_decay(" radau5 ", 1, x, 2.0_dp, h, decay_jacobian, y, iwork, rpar, idid, message)
      call check(error, idid, 1, message)
      if (allocated(error)) return
      call check(error, all(iwork(14:20) == iwork_plain(14:20)) .and. y(1) == y_plain(1), "' radau5 ': "// &
         format_integer(iwork(16))//" steps, y = "//format_real(y(1), 17)//"; 'radau5': "// &
         format_integer(iwork_plain(16))//" steps, y = "//format_real(y_plain(1), 17))
   end subroutine test_radau5_named_with_blanks

   !> Every setting RADAU5 checks, out of its range, is IDID = -1 with a reason in
   !> IWORK(12) and a message, and the state untouched: IWORK(2) < 0 (it ran with the
   !> default budget before), IWORK(3) < 0, IWORK(5:7) not adding up to N, index-2 or
   !> second-order structure (not supported), WORK(1) outside (1e-19, 1), WORK(2)
   !> outside (0.001, 1), WORK(3) >= 1, WORK(4) <= UROUND / RTOL, WORK(5) > 1, WORK(6) <
   !> 1, WORK(8) > 1, WORK(9) < 1, RTOL <= 10 UROUND or ATOL = 0 (radau5), a NaN H or
   !> WORK entry, a negative IWORK(11), IWORK(5:6) whose sum overflows an integer, WORK(1)
   !> >= 0.1, an XEND - X that overflows; each with its own reason, X, Y and H as given.
   subroutine test_settings_checked(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: cases = 26
      character(len=20) :: label
      real(dp) :: x, x_given, y(2), h, h_given, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(2), idid, k
      character(len=:), allocatable :: message

      do k = 1, cases
         call fresh(x, y, h, rtol, atol, work, iwork)
         select case (k)
         case (1); iwork(2) = -5; label = "IWORK(2) = -5"
         case (2); iwork(3) = -1; label = "IWORK(3) = -1"
         case (3); iwork(5) = 1; label = "IWORK(5) = 1"
         case (4); iwork(5:6) = [1, 1]; label = "IWORK(6) = 1"
         case (5); iwork(9) = -1; label = "IWORK(9) = -1"
         case (6); iwork(9) = 1; label = "IWORK(9) = 1"
         case (7); work(1) = 1.0e-20_dp; label = "WORK(1) = 1e-20"
         case (8); work(1) = 1.0_dp; label = "WORK(1) = 1"
         case (9); work(2) = 1.0e-4_dp; label = "WORK(2) = 1e-4"
         case (10); work(2) = 1.0_dp; label = "WORK(2) = 1"
         case (11); work(3) = 1.0_dp; label = "WORK(3) = 1"
         case (12); work(4) = 1.0e-30_dp; label = "WORK(4) = 1e-30"
         case (13); work(5) = 1.5_dp; label = "WORK(5) = 1.5"
         case (14); work(6) = 0.5_dp; label = "WORK(6) = 0.5"
         case (15); work(8) = 2.0_dp; label = "WORK(8) = 2"
         case (16); work(9) = 0.5_dp; label = "WORK(9) = 0.5"
         case (17); rtol = 1.0e-20_dp; label = "RTOL = 1e-20"
         case (18); atol = 0.0_dp; label = "ATOL = 0"
         case (19); h = ieee_value(1.0_dp, ieee_quiet_nan); label = "H = NaN"
         case (20); iwork(11) = -1; label = "IWORK(11) = -1"
         case (21); work(9) = -2.0_dp; label = "WORK(9) = -2"
         case (22); iwork(6:7) = [0, 1]; iwork(5) = 1; label = "IWORK(7) = 1"
         case (23); work(2) = ieee_value(1.0_dp, ieee_quiet_nan); label = "WORK(2) = NaN"
         ! (their sum overflowed an integer: the sanitized build's report)
         case (24); iwork(5:6) = [huge(0), 1]; label = "IWORK(5) = huge"
         ! (refused later, by the integrator, with "the integration was refused"; radau5's
         ! WORK(1) = 0.5 by its tolerance test, si-t-2's so)
         case (25); work(1) = 0.5_dp; label = "WORK(1) = 0.5"
         case (26); x = -1.0e308_dp; label = "XEND - X overflows"
         end select
         x_given = x
         h_given = h
         call solve_vdp("radau5", x, y, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message, &
            x_end=merge(1.0e308_dp, vdp_end, k == 26))
         call check(error, idid, -1, trim(label)//": IDID")
         if (allocated(error)) return
         call check(error, iwork(12) /= 0 .and. len(message) > 0 .and. index(message, "the integration was refused") == 0 &
            .and. x == x_given .and. y(1) == 2.0_dp .and. (h == h_given .or. (k == 19 .and. h /= h)), &
            trim(label)//": reason "//format_integer(iwork(12))//", message """//message//"""")
         if (allocated(error)) return
      end do
      ! for the other schemes the tolerances keep their meaning: ATOL = 0 is allowed, < 0 not
      call fresh(x, y, h, rtol, atol, work, iwork)
      atol = -1.0_dp
      call solve_vdp("i-t-2", x, y, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message)
      call check(error, idid == -1 .and. index(message, "ATOL(1)") > 0, "i-t-2, ATOL = -1: "//message)
   end subroutine test_settings_checked

   !> Settings within RADAU5's ranges are taken (IDID = 1): the boundary-side values of
   !> each, a huge H (RADAU5 takes H as a guess and clamps it to XEND - X; it was refused
   !> before), and H = 0, which starts with RADAU5's 1e-6 (SOLOUT sees the first step end
   !> at 1e-6).
   subroutine test_settings_accepted(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: cases = 15
      character(len=20) :: label
      real(dp) :: x, y(2), h, rtol(1), atol(1), work(lwork), rpar(2)
      integer :: iwork(liwork), ipar(2), idid, k
      character(len=:), allocatable :: message

      do k = 1, cases
         call fresh(x, y, h, rtol, atol, work, iwork)
         select case (k)
         case (1); iwork(2) = 50000; label = "IWORK(2) = 50000"
         case (2); iwork(3) = 4; label = "IWORK(3) = 4"
         case (3); iwork(4) = 1; label = "IWORK(4) = 1"
         case (4); iwork(8) = 2; label = "IWORK(8) = 2"
         case (5); iwork(1) = 1; label = "IWORK(1) = 1"
         case (6); work(2) = 0.5_dp; label = "WORK(2) = 0.5"
         case (7); work(3) = -1.0_dp; label = "WORK(3) = -1"
         case (8); work(4) = 0.1_dp; label = "WORK(4) = 0.1"
         case (9); work(5:6) = [0.9_dp, 2.0_dp]; label = "WORK(5:6)"
         case (10); work(7) = 0.1_dp; label = "WORK(7) = 0.1"
         case (11); work(8:9) = [0.1_dp, 4.0_dp]; label = "WORK(8:9)"
         case (12); work(1) = 1.0e-15_dp; label = "WORK(1) = 1e-15"
         case (13); h = 1.0e300_dp; label = "H = 1e300"
         case (14); h = -1.0e-3_dp; label = "H = -1e-3"
         case (15); h = 0.0_dp; label = "H = 0"
         end select
         rpar = 0.0_dp
         call solve_vdp("radau5", x, y, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message, output=.true.)
         call check(error, idid, 1, trim(label)//": "//message)
         if (allocated(error)) return
         call check(error, x, vdp_end, trim(label)//": X")
         if (allocated(error)) return
         if (k == 15) then
            call check(error, rpar(1), 1.0e-6_dp, "H = 0: the first step should be RADAU5's 1e-6")
            if (allocated(error)) return
         end if
      end do
   end subroutine test_settings_accepted

   !> TAYLORODE('radau5', ...) is integrate() with RADAU5's settings: rtol' = 0.1
   !> rtol^(2/3), atol' = atol rtol'/rtol, the RMS norm, h0 = H, step-size factors in
   !> [0.2, 8], RADAU5's FNEWT, no limit on failed attempts; the same state to the last
   !> bit, and IWORK(14:20) with RADAU5's meaning: IWORK(18) leaves out the rejections
   !> before the first accepted step, IWORK(20) counts the solves of the Newton
   !> iterations only. Van der Pol (mu = 1e3) at RTOL = ATOL = 1e-6, ITOL = 0 and 1.
   !> Before, TAYLORODE took the tolerances as given (an integration at 1e-6 in the max
   !> norm instead of RADAU5's 2.2e-5 in the RMS norm).
   subroutine test_radau5_as_radau5(error)
      type(error_type), allocatable, intent(out) :: error
      type(vdp_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: x, y(2), u(2), h, rtol(2), atol(2), work(lwork), rpar(1), transformed
      integer :: iwork(liwork), ipar(1), idid, itol
      character(len=:), allocatable :: message

      transformed = 0.1_dp*(1.0e-6_dp)**(2.0_dp/3.0_dp)
      options = integrator_options_type(rtol=transformed, atol=transformed, norm=norm_rms, h0=1.0e-6_dp, &
         h_max=vdp_end, max_growth=8.0_dp, min_shrink=0.2_dp, max_steps=100000_i8, &
         newton_fraction=max(10.0_dp*1.0e-16_dp/transformed, min(0.03_dp, sqrt(transformed))))
      call new_scheme("radau5", scheme, stat)
      u = [2.0_dp, -0.66_dp]
      call integrate(problem, scheme, 0.0_dp, vdp_end, u, options, stats, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      do itol = 0, 1
         call fresh(x, y, h, rtol, atol, work, iwork)
         call solve_vdp("radau5", x, y, h, rtol, atol, itol, work, iwork, rpar, ipar, idid, message)
         call check(error, idid, 1, "IDID")
         if (allocated(error)) return
         call check(error, all(y == u), "ITOL = "//format_integer(itol)//": TAYLORODE and integrate differ by "// &
            format_real(maxval(abs(y - u))))
         if (allocated(error)) return
         call check(error, iwork(16) == stats%accepted_steps + stats%rejected_steps() .and. &
            iwork(17) == stats%accepted_steps .and. iwork(18) == stats%rejected_error - stats%rejected_error_start &
            .and. iwork(19) == stats%work%lu_factorizations .and. iwork(20) == stats%work%newton_iterations .and. &
            iwork(14) == stats%work%f_evaluations .and. iwork(15) == stats%work%jac_f_evaluations, &
            "IWORK(14:20) = "//format_integer(iwork(14))//" "//format_integer(iwork(15))//" "// &
            format_integer(iwork(16))//" "//format_integer(iwork(17))//" "//format_integer(iwork(18))//" "// &
            format_integer(iwork(19))//" "//format_integer(iwork(20)))
         if (allocated(error)) return
      end do
   end subroutine test_radau5_as_radau5

   !> Before its first accepted step RADAU5 retries an attempt the error test rejects
   !> with H/10 (H = H*0.1 while FIRST), not with its controller's factor (at least 0.2
   !> with WORK(8:9)'s defaults): from a first H too large for the tolerance,
   !> TAYLORODE('radau5', ...)'s first accepted step is H times a power of 0.1, the
   !> attempts before it all rejected (IWORK(18) does not count them). Van der Pol,
   !> RTOL = ATOL = 1e-6, H = 1e-2 and 1e-3. Before, with the controller's factor, the
   !> first step from H = 1e-2 ended at 4.26e-4, and the counts differed from Hairer's
   !> RADAU5's on Van der Pol (eps = 1e-6, both starts, RTOL 1e-2 ... 1e-10, H = 1e-6)
   !> in 15 of 18 runs (up to 6 attempts); now in none.
   subroutine test_first_rejection(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(2), h, h_first, h_retried, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(1), idid, start, retries
      character(len=:), allocatable :: message
      logical :: power_of_tenth

      do start = 2, 3
         call fresh(x, y, h, rtol, atol, work, iwork)
         h_first = 10.0_dp**(-start)
         h = h_first
         rpar = 0.0_dp
         call solve_vdp("radau5", x, y, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message, output=.true.)
         call check(error, idid, 1, "H = "//format_real(h_first)//": "//message)
         if (allocated(error)) return
         ! RADAU5's arithmetic: H*0.1, then that times 0.1, ...
         power_of_tenth = .false.
         h_retried = h_first
         do retries = 1, 8
            h_retried = h_retried*0.1_dp
            power_of_tenth = power_of_tenth .or. rpar(1) == h_retried
         end do
         call check(error, power_of_tenth .and. iwork(16) > iwork(17), "H = "//format_real(h_first)// &
            ": the first step ended at "//format_real(rpar(1))//" after "//format_integer(iwork(16) - &
            iwork(17))//" attempts not accepted; RADAU5 retries with H/10 before its first accepted step")
         if (allocated(error)) return
      end do
   end subroutine test_first_rejection

   !> radau5's rules before the first accepted step: by default none after an error-test
   !> rejection (the controller's factor) and after a Newton failure at most the
   !> integrator's factor (its own first h may be far too large); with
   !> first_step_as_radau5 (the legacy entry) RADAU5's: 0.1, and its own factor (1/2
   !> before any Newton contraction is known). Against Hairer's RADAU5 with H = 0.1 and 1
   !> (RTOL 1e-6, seven problems), the counts differed in 13 of 14 runs before and agree
   !> in all now.
   subroutine test_first_step_rules(error)
      type(error_type), allocatable, intent(out) :: error
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      call new_scheme("radau5", scheme, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      select type (scheme)
      type is (radau5_type)
         call check(error, scheme%first_rejection_factor() == 0.0_dp .and. scheme%failure_factor(0.25_dp) == &
            0.25_dp, "default: the controller's factor after a first rejection, the integrator's 0.25 after "// &
            "a first Newton failure; got "//format_real(scheme%first_rejection_factor())//" and "// &
            format_real(scheme%failure_factor(0.25_dp)))
         if (allocated(error)) return
         scheme%first_step_as_radau5 = .true.
         call check(error, scheme%first_rejection_factor() == 0.1_dp .and. scheme%failure_factor(0.25_dp) == &
            0.5_dp, "first_step_as_radau5: RADAU5's 0.1 and 0.5; got "//format_real(scheme%first_rejection_factor()) &
            //" and "//format_real(scheme%failure_factor(0.25_dp)))
      class default
         call check(error, .false., "new_scheme('radau5') is not a radau5_type")
      end select
   end subroutine test_first_step_rules

   !> radau5's band of factors h_new/h for which an accepted step keeps h is RADAU5's:
   !> after fast Newton (theta <= THET) [QUOT1, QUOT2], else none, and right after a
   !> rejection never a larger h (RADAU5's HNEW = MIN(HNEW, H) before its test). With
   !> QUOT1 = 0.9: after a rejection and slow Newton a factor of 0.95 is taken, not held.
   !> Before, the band after a rejection started at QUOT1 whatever theta: against Hairer's
   !> RADAU5 with WORK(5:6) = 0.9, 2 (seven problems, RTOL 1e-3, 1e-6, 1e-9) 12 of 21 runs
   !> had other counts, now 6 (the rest: RADAU5 lengthens the last step to reach XEND when
   !> X + HNEW/QUOT1 >= XEND, and rounding).
   subroutine test_hold_band(error)
      type(error_type), allocatable, intent(out) :: error
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      real(dp) :: low, high
      integer :: k
      logical :: slow, retry
      real(dp), parameter :: quot1 = 0.9_dp, quot2 = 2.0_dp
      call new_scheme("radau5", scheme, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      select type (scheme)
      type is (radau5_type)
         scheme%hold_low = quot1
         scheme%hold_high = quot2
         do k = 0, 3
            slow = k >= 2
            retry = mod(k, 2) == 1
            scheme%theta = merge(10.0_dp, 0.1_dp, slow)*scheme%jacobian_reuse
            scheme%retry = retry
            call scheme%step_hold(low, high)
            ! h kept for factors in [low, high]: RADAU5 keeps h for min(f, 1) (after a
            ! rejection) in [QUOT1, QUOT2] after fast Newton, and takes min(f, 1) h else
            call check(error, low == merge(1.0_dp, quot1, slow) .and. high == merge(huge(1.0_dp), &
               merge(1.0_dp, quot2, slow), retry), "theta "//merge("> THET ", "<= THET", slow)//", "// &
               merge("after a rejection", "after an accepted", retry)//": band ["//format_real(low)//", "// &
               format_real(high)//"]")
            if (allocated(error)) return
         end do
      class default
         call check(error, .false., "new_scheme('radau5') is not a radau5_type")
      end select
   end subroutine test_hold_band

   !> TAYLORODE('radau5', ...) without JAC (IJAC = 0) differences FCN as RADAU5 does: N
   !> calls per Jacobian (F at the step's start is the one the step has), none beside
   !> NFCN + N NJAC in all; the answer that of the run with the analytic Jacobian to 1e-9
   !> relative (RTOL = ATOL = 1e-6: the differences' error, ~1e-8 relative, scales only
   !> Newton's corrections, whose iterates converge to the same collocation solution; the
   !> two runs end 7e-14 apart). Fails when a column is wrong (the iterates then stop
   !> elsewhere) or when F is evaluated once more per Jacobian.
   subroutine test_difference_jacobian(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(2), y_analytic(2), h, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(1), idid, calls, evaluations, jacobians
      character(len=:), allocatable :: message
      call fresh(x, y_analytic, h, rtol, atol, work, iwork)
      call solve_vdp("radau5", x, y_analytic, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message)
      call check(error, idid, 1, "with JAC: "//message)
      if (allocated(error)) return
      call fresh(x, y, h, rtol, atol, work, iwork)
      rpar = 0.0_dp
      call legacy_solve("radau5", 2, counted_vdp, counted_vdp, .false., x, y, vdp_end, h, rtol, atol, 0, &
         vdp_jacobian, 0, vdp_jacobian, 0, 2, 0, legacy_no_mass, 0, 2, 0, no_output, 0, work, size(work), iwork, &
         size(iwork), rpar, ipar, idid, message)
      call check(error, idid, 1, "without JAC: "//message)
      if (allocated(error)) return
      calls = nint(rpar(1))
      evaluations = iwork(14)
      jacobians = iwork(15)
      call check(error, jacobians > 10 .and. calls == evaluations + 2*jacobians, "FCN called "// &
         format_integer(calls)//" times for NFCN = "//format_integer(evaluations)//" and NJAC = "// &
         format_integer(jacobians)//" (N = 2 calls per Jacobian expected)")
      if (allocated(error)) return
      call check(error, maxval(abs(y - y_analytic)) <= 1.0e-9_dp*maxval(abs(y_analytic)), &
         "the differenced run ends "//format_real(maxval(abs(y - y_analytic)))//" from the analytic one")
   end subroutine test_difference_jacobian

   !> Without JAC, TAYLORODE perturbs y_j by sqrt(UROUND max(1e-5, |y_j|)) as RADAU5 does,
   !> UROUND = WORK(1) (1e-16 when 0): the first Jacobian's first column is taken at y0 +
   !> that increment in y_1 (the calls before it evaluate F at y0). Before, the increment
   !> took epsilon = 2.2e-16 whatever WORK(1) said, and Robertson to 1e11 took up to 27 %
   !> more attempts than RADAU5 without JAC (since: RADAU5's counts from RTOL 1e-3 on).
   subroutine test_difference_increment(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), parameter :: rounding_units(2) = [0.0_dp, 1.0e-10_dp]
      real(dp) :: x, y(2), y0(2), h, rtol(1), atol(1), work(lwork), rpar(1), uround, expected, found
      integer :: iwork(liwork), ipar(1), idid, k, call
      character(len=:), allocatable :: message
      do k = 1, size(rounding_units)
         call fresh(x, y, h, rtol, atol, work, iwork)
         y0 = y
         work(1) = rounding_units(k)
         uround = merge(1.0e-16_dp, rounding_units(k), rounding_units(k) == 0.0_dp)
         recorded_calls = 0
         call legacy_solve("radau5", 2, recorded_vdp, recorded_vdp, .false., x, y, 1.0e-3_dp, h, rtol, atol, 0, &
            vdp_jacobian, 0, vdp_jacobian, 0, 2, 0, legacy_no_mass, 0, 2, 0, no_output, 0, work, size(work), &
            iwork, size(iwork), rpar, ipar, idid, message)
         call check(error, idid, 1, "WORK(1) = "//format_real(rounding_units(k))//": "//message)
         if (allocated(error)) return
         expected = (y0(1) + sqrt(uround*max(1.0e-5_dp, abs(y0(1))))) - y0(1)
         found = 0.0_dp
         do call = 1, min(recorded_calls, size(recorded_states, 2))
            if (recorded_states(1, call) /= y0(1) .and. recorded_states(2, call) == y0(2)) then
               found = recorded_states(1, call) - y0(1)
               exit
            end if
         end do
         call check(error, abs(found - expected) <= 1.0e-12_dp*expected, "WORK(1) = "// &
            format_real(rounding_units(k))//": y_1 perturbed by "//format_real(found)//", RADAU5's "// &
            format_real(expected))
         if (allocated(error)) return
      end do
   end subroutine test_difference_increment

   !> IWORK(3) reaches radau5 (RADAU5's NIT): with 2 Newton iterations per attempt no
   !> attempt makes more (IWORK(20) <= 2 IWORK(16)), with the default 7 some do (before:
   !> radau5 took 7 whatever IWORK(3) said).
   subroutine test_newton_iterations(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(2), h, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(1), idid, k
      character(len=:), allocatable :: message

      do k = 1, 2
         call fresh(x, y, h, rtol, atol, work, iwork)
         iwork(3) = merge(0, 2, k == 1)
         call solve_vdp("radau5", x, y, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message)
         call check(error, idid, 1, "IDID")
         if (allocated(error)) return
         call check(error, iwork(20) > 2*iwork(16) .eqv. k == 1, "IWORK(3) = "//format_integer(iwork(3))// &
            ": "//format_integer(iwork(20))//" Newton iterations in "//format_integer(iwork(16))//" attempts")
         if (allocated(error)) return
      end do
   end subroutine test_newton_iterations

   !> X and Y are copies FCN may write (README): a FCN that overwrites them once it has
   !> computed F (Y with NaN, X moved) gives the run of one that does not, to the last
   !> bit, with JAC and without (differences, whose perturbed states FCN is given), through
   !> radau5 (whose stage states FCN is given without a copy: formed anew for each call)
   !> and i-t-2. Fails when a state FCN was given is used after the call.
   subroutine test_fcn_writes_arguments(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = [character(len=6) :: "radau5", "i-t-2"]
      real(dp) :: x, y(2), y_plain(2), h, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(1), idid, k, ijac
      character(len=:), allocatable :: message
      do k = 1, size(names)
         do ijac = 0, 1
            call fresh(x, y_plain, h, rtol, atol, work, iwork)
            call legacy_solve(trim(names(k)), 2, vdp, vdp, .false., x, y_plain, vdp_end, h, rtol, atol, 0, &
               vdp_jacobian, 0, vdp_jacobian, ijac, 2, 0, legacy_no_mass, 0, 2, 0, no_output, 0, work, size(work), &
               iwork, size(iwork), rpar, ipar, idid, message)
            call check(error, idid, 1, trim(names(k))//": "//message)
            if (allocated(error)) return
            call fresh(x, y, h, rtol, atol, work, iwork)
            call legacy_solve(trim(names(k)), 2, scribbling_vdp, scribbling_vdp, .false., x, y, vdp_end, h, rtol, &
               atol, 0, vdp_jacobian, 0, vdp_jacobian, ijac, 2, 0, legacy_no_mass, 0, 2, 0, no_output, 0, work, &
               size(work), iwork, size(iwork), rpar, ipar, idid, message)
            call check(error, idid, 1, trim(names(k))//", FCN writing X and Y: "//message)
            if (allocated(error)) return
            call check(error, all(y == y_plain) .and. x == vdp_end, trim(names(k))//", IJAC = "// &
               format_integer(ijac)//": a FCN writing X and Y changed the run by "//format_real(maxval(abs(y - y_plain))))
            if (allocated(error)) return
         end do
      end do
   end subroutine test_fcn_writes_arguments

   !> At the step budget: IDID = -2, X where it stopped, and IWORK(16) = NMAX + 1 as in
   !> RADAU5 (which counts the attempt that finds the budget spent); the message says so.
   subroutine test_budget(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(2), h, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(1), idid
      character(len=200) :: text
      character(len=:), allocatable :: message

      call fresh(x, y, h, rtol, atol, work, iwork)
      iwork(2) = 20
      call solve_vdp("radau5", x, y, h, rtol, atol, 0, work, iwork, rpar, ipar, idid, message)
      call check(error, idid, -2, "IDID")
      if (allocated(error)) return
      call check(error, iwork(16), 21, "IWORK(16) at the budget")
      if (allocated(error)) return
      call check(error, x > 0.0_dp .and. x < vdp_end, "X where it stopped")
      if (allocated(error)) return
      call taylorode_message(iwork, text)
      call check(error, index(text, "step budget") > 0, "message: "//trim(text))
   end subroutine test_budget

   !> IDID = -3 where RADAU5 stops, 0.1 |H| <= |X| UROUND: y' = y^2, y(0) = 1 blows up
   !> at X = 1, where H shrinks until the call gives up at |H| <= 10 UROUND |X|: no
   !> accepted step is that small (SOLOUT records the smallest X - XOLD, the step to
   !> within the roundings of X and XOLD, a spacing of X), and with UROUND = WORK(1)
   !> = 1e-10 it gives up after fewer attempts than with the default 1e-16. Before, TAYLORODE
   !> went on down to 2 epsilon |X| whatever UROUND: on Robertson with ATOL = RTOL = 1e-2
   !> (a blow-up, which RADAU5 also ends with IDID = -3) 95 attempts against RADAU5's 93,
   !> now 92 (RADAU5 counts the attempt whose H it finds too small).
   subroutine test_step_too_small(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x, y(1), h, rtol(1), atol(1), work(lwork), rpar(1)
      integer :: iwork(liwork), ipar(1), idid, case, attempts(2)
      character(len=:), allocatable :: message
      do case = 1, 2
         work = 0.0_dp
         iwork = 0
         if (case == 2) work(1) = 1.0e-10_dp
         x = 0.0_dp
         y = 1.0_dp
         h = 1.0e-3_dp
         rtol = 1.0e-6_dp
         atol = 1.0e-6_dp
         rpar = huge(1.0_dp)
         call legacy_solve("radau5", 1, squaring, squaring, .false., x, y, 2.0_dp, h, rtol, atol, 0, &
            squaring_jacobian, 1, squaring_jacobian, 1, 1, 0, legacy_no_mass, 0, 1, 0, smallest_step, 1, work, &
            lwork, iwork, liwork, rpar, ipar, idid, message)
         call check(error, idid, -3, "UROUND "//merge("1e-10", "1e-16", case == 2)//": "//message)
         if (allocated(error)) return
         attempts(case) = iwork(16)
         ! (the steps near the blow-up, where X is 1 to within 1e-3)
         call check(error, abs(x - 1.0_dp) < 1.0e-3_dp .and. rpar(1) > 0.999_dp*10.0_dp* &
            merge(1.0e-10_dp, 1.0e-16_dp, case == 2) - spacing(x), &
            "UROUND "//merge("1e-10", "1e-16", case == 2)//": stopped at X = "//format_real(x)// &
            ", smallest accepted step "//format_real(rpar(1)))
         if (allocated(error)) return
      end do
      call check(error, attempts(2) < attempts(1), "UROUND 1e-10: "//format_integer(attempts(2))// &
         " attempts, 1e-16: "//format_integer(attempts(1))//"; a larger UROUND gives up sooner")
   end subroutine test_step_too_small

   !> IWORK(11) = K makes IPAR(K) the evaluation flag: FCN sets it > 0 where it cannot
   !> evaluate (the step is retried shorter) or < 0 to stop. u' = -u on [0, 1], with
   !> FCN refusing x > 0.5: once only (the retry succeeds: IDID = 1), always (IDID = -7,
   !> X <= 0.5), fatally (IDID = -7 at the first refusal); without IWORK(11) the flag is
   !> ignored (IDID = 1). Before, IDID = -7 could not be reached.
   subroutine test_evaluation_flag(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = [character(len=6) :: "radau5", "i-t-2"]
      integer, parameter :: expected(4) = [1, -7, -7, 1]
      real(dp) :: x, y(1), h, rtol(1), atol(1), work(lwork), rpar(2)
      integer :: iwork(liwork), ipar(3), idid, mode, k
      character(len=:), allocatable :: message

      do k = 1, size(names)
         do mode = 1, 4
            work = 0.0_dp
            iwork = 0
            if (mode <= 3) iwork(11) = 2
            x = 0.0_dp
            y = 1.0_dp
            h = 1.0e-3_dp
            rtol = 1.0e-6_dp
            atol = 1.0e-6_dp
            ! ipar(1): how to refuse (1 once, 2 always, 3 fatally); ipar(3): refusals so far
            ipar = [merge(2, mode, mode == 4), 0, 0]
            call legacy_solve(trim(names(k)), 1, refusing_decay, refusing_decay, .false., x, y, 1.0_dp, h, rtol, &
               atol, 0, decay_jacobian, 0, decay_jacobian, 1, 1, 0, legacy_no_mass, 0, 1, 0, no_output, 0, work, &
               lwork, iwork, liwork, rpar, ipar, idid, message)
            call check(error, idid, expected(mode), trim(names(k))//", mode "//format_integer(mode)//": "//message)
            if (allocated(error)) return
            call check(error, ipar(3) > 0, trim(names(k))//": FCN should have refused")
            if (allocated(error)) return
            if (idid == -7) then
               call check(error, x <= 0.5_dp .and. index(message, "IPAR(IWORK(11))") > 0, trim(names(k))// &
                  ": stopped at X = "//format_real(x)//": "//message)
               if (allocated(error)) return
            else
               call check(error, abs(y(1) - exp(-1.0_dp)) < 1.0e-4_dp, trim(names(k))//": y(1) = "//format_real(y(1)))
               if (allocated(error)) return
            end if
         end do
      end do
   end subroutine test_evaluation_flag

   !> The transistor amplifier (an index-1 DAE, M y' = F(t, y), singular M) through
   !> TAYLORODE('radau5', ...) with IMAS = 1, from its published definition written as a
   !> RADAU5 user writes it (the Bari test set's FCN, JAC and MAS, the exp overflow guard
   !> through the evaluation flag): J and M banded (MLJAC = 2, MUJAC = 1, MLMAS = MUMAS =
   !> 1), J dense with M dense (MLMAS = N), J dense with M banded. At RTOL = ATOL = 1e-6
   !> (RADAU5's meaning: 1.0e-5 inside) every one is within 2 RTOL of the published
   !> solution at t = 0.2 (measured: 0.23 banded, 0.63 dense, in 1317 to 1323 attempts;
   !> RADAU5's transformation aims at an error of about RTOL; a dense M's products over a
   !> row range one short of its entries make Newton fail). A mass matrix with another
   !> scheme, or with bands beyond the Jacobian's, is IDID = -1.
   subroutine test_mass_transistor_amplifier(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: layouts(4, 3) = reshape([2, 1, 1, 1, 8, 0, 8, 0, 8, 0, 1, 1], [4, 3])
      type(transistor_amplifier_type) :: amplifier
      real(dp) :: x, y(8), h, rtol(1), atol(1), work(lwork), rpar(1), err
      integer :: iwork(liwork), ipar(1), idid, k
      character(len=:), allocatable :: message

      amplifier = new_transistor_amplifier()
      do k = 1, 5
         work = 0.0_dp
         iwork = 0
         iwork(11) = 1
         x = 0.0_dp
         y = amplifier%u0
         h = 1.0e-6_dp
         rtol = 1.0e-6_dp
         atol = 1.0e-6_dp
         if (k <= 3) then
            call legacy_solve("radau5", 8, amplifier_fcn, amplifier_fcn, .false., x, y, 0.2_dp, h, rtol, atol, 0, &
               amplifier_jac, 0, amplifier_jac, 1, layouts(1, k), layouts(2, k), amplifier_mas, 1, layouts(3, k), &
               layouts(4, k), no_output, 0, work, lwork, iwork, liwork, rpar, ipar, idid, message)
            call check(error, idid, 1, "layout "//format_integer(k)//": "//message)
            if (allocated(error)) return
            err = maxval(abs(y - amplifier%reference)/(atol(1) + rtol(1)*abs(amplifier%reference)))
            call check(error, err <= 2.0_dp, "layout "//format_integer(k)//": "//format_real(err)// &
               " tolerances off the reference")
            if (allocated(error)) return
         else
            ! i-t-2 with a mass matrix; MUMAS = 2 beyond MUJAC = 1
            call legacy_solve(trim(merge("i-t-2 ", "radau5", k == 4)), 8, amplifier_fcn, amplifier_fcn, .false., x, y, &
               0.2_dp, h, rtol, atol, 0, amplifier_jac, 0, amplifier_jac, 1, 2, 1, amplifier_mas, 1, 1, &
               merge(1, 2, k == 4), no_output, 0, work, lwork, iwork, liwork, rpar, ipar, idid, message)
            call check(error, idid == -1 .and. index(message, "mass matrix") > 0, "case "//format_integer(k)// &
               ": "//message)
            if (allocated(error)) return
         end if
      end do
   end subroutine test_mass_transistor_amplifier

   !> Every reason code IWORK(12) can hold has a sentence; TAYLORODE_MESSAGE gives it
   !> (blank after a success), and legacy_solve's message adds the library's own.
   subroutine test_messages(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: reasons(*) = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16, 17, 18, 19, 20, &
         21, 22, 23, 24, 31, 32, 33, 34, 35, 36, 37]
      integer :: k, iwork(20)
      character(len=200) :: text
      character(len=:), allocatable :: expected, sentence
      do k = 1, size(reasons)
         call legacy_message(reasons(k), 1, sentence)
         call check(error, len(sentence) > 10 .and. sentence /= "unknown reason", "reason "//format_integer(reasons(k)))
         if (allocated(error)) return
      end do
      iwork = 0
      call taylorode_message(iwork, text)
      call check(error, text == "", "blank after a success")
      if (allocated(error)) return
      iwork(12:13) = [3, 0]
      call taylorode_message(iwork, text)
      call legacy_message(3, 0, expected)
      call check(error, text, expected, "TAYLORODE_MESSAGE")
      if (allocated(error)) return
      call taylorode_message(iwork, text(:8))
      call check(error, text(:8), expected(:8), "TAYLORODE_MESSAGE cut to its text's length")
   end subroutine test_messages

   !> The external TAYLORODE, TAYLORODE_SPLIT and TAYLORODE_CONTR, which reach the
   !> module through its C-interoperable entries (procedure pointers, the name as
   !> characters), give what legacy_solve and legacy_interpolate give, bit for bit:
   !> radau5 on Van der Pol with SOLOUT interpolating every step at three points, and
   !> si-t-2 with f and g apart (y1' = y2 in f, the rest in g) and both Jacobians.
   subroutine test_external_procedures(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: x(2), y(2, 2), h(2), rtol(1), atol(1), work(lwork, 2), rpar(2, 2)
      integer :: iwork(liwork, 2), ipar(1, 2), idid(2), k
      character(len=*), parameter :: label(2) = [character(len=15) :: "TAYLORODE", "TAYLORODE_SPLIT"]
      do k = 1, 2
         call fresh(x(1), y(:, 1), h(1), rtol, atol, work(:, 1), iwork(:, 1))
         call fresh(x(2), y(:, 2), h(2), rtol, atol, work(:, 2), iwork(:, 2))
         rpar = 0.0_dp
         ! ipar(1): 1 the SOLOUT calls TAYLORODE_CONTR, 0 legacy_interpolate
         ipar(1, :) = [1, 0]
         if (k == 1) then
            call taylorode("radau5", 2, vdp, x(1), y(:, 1), vdp_end, h(1), rtol, atol, 0, vdp_jacobian, 1, 2, 0, &
               legacy_no_mass, 0, 2, 0, interpolating, 1, work(:, 1), lwork, iwork(:, 1), liwork, rpar(:, 1), &
               ipar(:, 1), idid(1))
            call legacy_solve("radau5", 2, vdp, vdp, .false., x(2), y(:, 2), vdp_end, h(2), rtol, atol, 0, &
               vdp_jacobian, 0, vdp_jacobian, 1, 2, 0, legacy_no_mass, 0, 2, 0, interpolating, 1, work(:, 2), lwork, &
               iwork(:, 2), liwork, rpar(:, 2), ipar(:, 2), idid(2))
         else
            call taylorode_split("si-t-2", 2, vdp_f, vdp_g, x(1), y(:, 1), vdp_end, h(1), rtol, atol, 0, &
               vdp_f_jacobian, 1, vdp_g_jacobian, 1, 2, 0, interpolating, 1, work(:, 1), lwork, iwork(:, 1), liwork, &
               rpar(:, 1), ipar(:, 1), idid(1))
            call legacy_solve("si-t-2", 2, vdp_f, vdp_g, .true., x(2), y(:, 2), vdp_end, h(2), rtol, atol, 0, &
               vdp_f_jacobian, 1, vdp_g_jacobian, 1, 2, 0, legacy_no_mass, 0, 2, 0, interpolating, 1, work(:, 2), &
               lwork, iwork(:, 2), liwork, rpar(:, 2), ipar(:, 2), idid(2))
         end if
         call check(error, idid(1) == 1 .and. idid(2) == 1, trim(label(k))//": IDID "//format_integer(idid(1))// &
            " and "//format_integer(idid(2)))
         if (allocated(error)) return
         call check(error, x(1) == x(2) .and. all(y(:, 1) == y(:, 2)) .and. h(1) == h(2) .and. &
            all(iwork(14:20, 1) == iwork(14:20, 2)), trim(label(k))//": X, Y, H or IWORK(14:20) differ from legacy_solve's")
         if (allocated(error)) return
         call check(error, rpar(2, 1) > 0.0_dp .and. all(rpar(:, 1) == rpar(:, 2)), trim(label(k))// &
            ": TAYLORODE_CONTR differs from legacy_interpolate")
         if (allocated(error)) return
      end do
   end subroutine test_external_procedures

   subroutine vdp_zero(self, t, u, dudt)
      class(vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = 0.0_dp
   end subroutine vdp_zero

   subroutine vdp_rhs(self, t, u, dudt)
      class(vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt(1) = u(2)
      dudt(2) = mu*((1.0_dp - u(1)**2)*u(2) - u(1))
   end subroutine vdp_rhs

   subroutine vdp_zero_jacobian(self, t, u, jac)
      class(vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac = 0.0_dp
   end subroutine vdp_zero_jacobian

   subroutine vdp_jac(self, t, u, jac)
      class(vdp_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = 0.0_dp
      jac(1, 2) = 1.0_dp
      jac(2, 1) = mu*(-2.0_dp*u(1)*u(2) - 1.0_dp)
      jac(2, 2) = mu*(1.0_dp - u(1)**2)
   end subroutine vdp_jac

   !> A fresh call on Van der Pol: WORK(1:20) and IWORK(1:20) zero, X = 0, Y = (2, -0.66),
   !> H = 1e-6, RTOL = ATOL = 1e-6
   subroutine fresh(x, y, h, rtol, atol, work, iwork)
      real(dp), intent(out) :: x, y(2), h, rtol(:), atol(:), work(:)
      integer, intent(out) :: iwork(:)
      work = 0.0_dp
      iwork = 0
      x = 0.0_dp
      y = [2.0_dp, -0.66_dp]
      h = 1.0e-6_dp
      rtol = 1.0e-6_dp
      atol = 1.0e-6_dp
   end subroutine fresh

   !> TAYLORODE(scheme, ...) on Van der Pol over [0, vdp_end] with the analytic
   !> Jacobian, dense, no mass matrix; SOLOUT = first_step when `output`, else none
   subroutine solve_vdp(scheme_name, x, y, h, rtol, atol, itol, work, iwork, rpar, ipar, idid, message, output, &
      x_end)
      character(len=*), intent(in) :: scheme_name
      real(dp), intent(inout) :: x, y(2), h, rtol(:), atol(:), work(:), rpar(:)
      integer, intent(in) :: itol
      integer, intent(inout) :: iwork(:), ipar(:)
      integer, intent(out) :: idid
      character(len=:), allocatable, intent(out) :: message
      logical, intent(in), optional :: output
      !> XEND (default vdp_end)
      real(dp), intent(in), optional :: x_end
      logical :: solout
      real(dp) :: xend
      solout = .false.
      if (present(output)) solout = output
      xend = vdp_end
      if (present(x_end)) xend = x_end
      if (solout) then
         call legacy_solve(scheme_name, 2, vdp, vdp, .false., x, y, xend, h, rtol, atol, itol, vdp_jacobian, 0, &
            vdp_jacobian, 1, 2, 0, legacy_no_mass, 0, 2, 0, first_step, 1, work, size(work), iwork, size(iwork), &
            rpar, ipar, idid, message)
      else
         call legacy_solve(scheme_name, 2, vdp, vdp, .false., x, y, xend, h, rtol, atol, itol, vdp_jacobian, 0, &
            vdp_jacobian, 1, 2, 0, legacy_no_mass, 0, 2, 0, no_output, 0, work, size(work), iwork, size(iwork), &
            rpar, ipar, idid, message)
      end if
   end subroutine solve_vdp

   !> TAYLORODE(scheme_name, ...) on y' = -y (plain_decay) in n components from (x, 1) to
   !> x_end, rtol = atol = 1e-6, RADAU5's settings at their defaults, the Jacobian `jac`
   !> (IJAC = 1, dense), SOLOUT `solout` (IOUT = 1) when given, rpar zeroed first
   subroutine solve_decay(scheme_name, n, x, x_end, h, jac, y, iwork, rpar, idid, message, solout)
      character(len=*), intent(in) :: scheme_name
      integer, intent(in) :: n
      real(dp), intent(inout) :: x, h, rpar(:)
      real(dp), intent(in) :: x_end
      procedure(jac_interface) :: jac
      real(dp), intent(out) :: y(n)
      integer, intent(out) :: iwork(liwork), idid
      character(len=:), allocatable, intent(out) :: message
      procedure(solout_interface), optional :: solout
      real(dp) :: rtol(1), atol(1), work(lwork)
      integer :: ipar(1)
      work = 0.0_dp
      iwork = 0
      y = 1.0_dp
      rtol = 1.0e-6_dp
      atol = 1.0e-6_dp
      rpar = 0.0_dp
      if (present(solout)) then
         call legacy_solve(scheme_name, n, plain_decay, plain_decay, .false., x, y, x_end, h, rtol, atol, 0, jac, 0, &
            jac, 1, n, 0, legacy_no_mass, 0, n, 0, solout, 1, work, lwork, iwork, liwork, rpar, ipar, idid, message)
      else
         call legacy_solve(scheme_name, n, plain_decay, plain_decay, .false., x, y, x_end, h, rtol, atol, 0, jac, 0, &
            jac, 1, n, 0, legacy_no_mass, 0, n, 0, no_output, 0, work, lwork, iwork, liwork, rpar, ipar, idid, message)
      end if
   end subroutine solve_decay

   ! ----- the user's routines, as a RADAU5 user writes them -----

   !> Van der Pol, mu = 1e3: y1' = y2, y2' = mu ((1 - y1^2) y2 - y1)
   subroutine vdp(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      f(1) = y(2)
      f(2) = mu*((1.0_dp - y(1)**2)*y(2) - y(1))
   end subroutine vdp

   !> vdp, recording the states of its first calls (recorded_states, recorded_calls)
   subroutine recorded_vdp(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      recorded_calls = recorded_calls + 1
      if (recorded_calls <= size(recorded_states, 2)) recorded_states(:, recorded_calls) = y
      call vdp(n, x, y, f, rpar, ipar)
   end subroutine recorded_vdp

   !> vdp, then X and Y overwritten (Y with NaN), as FCN may
   subroutine scribbling_vdp(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      call vdp(n, x, y, f, rpar, ipar)
      x = -1.0_dp
      y = ieee_value(1.0_dp, ieee_quiet_nan)
   end subroutine scribbling_vdp

   !> vdp, counting its calls in rpar(1)
   subroutine counted_vdp(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      call vdp(n, x, y, f, rpar, ipar)
      rpar(1) = rpar(1) + 1.0_dp
   end subroutine counted_vdp

   !> y' = y^2
   subroutine squaring(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      f = y**2
   end subroutine squaring

   subroutine squaring_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy(1, 1) = 2.0_dp*y(1)
   end subroutine squaring_jacobian

   !> rpar(1) = the smallest accepted step so far
   subroutine smallest_step(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      irtrn = 0
      if (nr > 1) rpar(1) = min(rpar(1), x - xold)
   end subroutine smallest_step

   subroutine vdp_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy(1, 1) = 0.0_dp
      dfy(1, 2) = 1.0_dp
      dfy(2, 1) = mu*(-2.0_dp*y(1)*y(2) - 1.0_dp)
      dfy(2, 2) = mu*(1.0_dp - y(1)**2)
   end subroutine vdp_jacobian

   !> u' = -u, refusing x > 0.5 as ipar(1) says (1 once, 2 always, 3 fatally) through
   !> the flag ipar(2); ipar(3) counts the refusals
   subroutine refusing_decay(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      f = -y
      if (x <= 0.5_dp) return
      if (ipar(1) == 1 .and. ipar(3) > 0) return
      ipar(3) = ipar(3) + 1
      ipar(2) = merge(-1, 1, ipar(1) == 3)
   end subroutine refusing_decay

   subroutine decay_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy(1, 1) = -1.0_dp
   end subroutine decay_jacobian

   !> The transistor amplifier's F (Bari test set TRANSAMP); IPAR(1) = 1 where exp would overflow
   subroutine amplifier_fcn(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      real(dp), parameter :: ub = 6.0_dp, uf = 0.026_dp, alpha = 0.99_dp, beta = 1.0e-6_dp, r0 = 1000.0_dp, &
         r = 9000.0_dp
      real(dp) :: uet, fac1, fac2
      if ((y(2) - y(3))/uf > 300.0_dp .or. (y(5) - y(6))/uf > 300.0_dp) then
         ipar(1) = 1
         return
      end if
      uet = 0.1_dp*sin(200.0_dp*acos(-1.0_dp)*x)
      fac1 = beta*(exp((y(2) - y(3))/uf) - 1.0_dp)
      fac2 = beta*(exp((y(5) - y(6))/uf) - 1.0_dp)
      f(1) = (y(1) - uet)/r0
      f(2) = y(2)/r + (y(2) - ub)/r + (1.0_dp - alpha)*fac1
      f(3) = y(3)/r - fac1
      f(4) = (y(4) - ub)/r + alpha*fac1
      f(5) = y(5)/r + (y(5) - ub)/r + (1.0_dp - alpha)*fac2
      f(6) = y(6)/r - fac2
      f(7) = (y(7) - ub)/r + alpha*fac2
      f(8) = y(8)/r
   end subroutine amplifier_fcn

   !> Its Jacobian, dense (LDFY = N) or in RADAU5's band storage (LDFY = 4: MLJAC = 2, MUJAC = 1)
   subroutine amplifier_jac(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      real(dp), parameter :: uf = 0.026_dp, alpha = 0.99_dp, beta = 1.0e-6_dp, r0 = 1000.0_dp, r = 9000.0_dp
      real(dp) :: d1, d2
      if ((y(2) - y(3))/uf > 300.0_dp .or. (y(5) - y(6))/uf > 300.0_dp) then
         ipar(1) = 1
         return
      end if
      d1 = beta*exp((y(2) - y(3))/uf)/uf
      d2 = beta*exp((y(5) - y(6))/uf)/uf
      dfy = 0.0_dp
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
         if (ldfy == n) then
            dfy(i, j) = value
         else
            dfy(i - j + 2, j) = value
         end if
      end subroutine put
   end subroutine amplifier_jac

   !> Its mass matrix, dense (LMAS = N) or in RADAU5's band storage (LMAS = 3: MLMAS = MUMAS = 1)
   subroutine amplifier_mas(n, am, lmas, rpar, ipar)
      integer :: n, lmas
      real(dp) :: am(lmas, n), rpar(*)
      integer :: ipar(*)
      real(dp) :: c(5)
      c = [1.0e-6_dp, 2.0e-6_dp, 3.0e-6_dp, 4.0e-6_dp, 5.0e-6_dp]
      am = 0.0_dp
      call pair(1, c(1))
      call put(3, 3, -c(2))
      call pair(4, c(3))
      call put(6, 6, -c(4))
      call pair(7, c(5))
   contains
      subroutine pair(k, value)
         integer, intent(in) :: k
         real(dp), intent(in) :: value
         call put(k, k, -value)
         call put(k + 1, k + 1, -value)
         call put(k, k + 1, value)
         call put(k + 1, k, value)
      end subroutine pair
      subroutine put(i, j, value)
         integer, intent(in) :: i, j
         real(dp), intent(in) :: value
         if (lmas == n) then
            am(i, j) = value
         else
            am(i - j + 2, j) = value
         end if
      end subroutine put
   end subroutine amplifier_mas

   !> Van der Pol split (f = (y2, 0), g = (0, mu ((1 - y1^2) y2 - y1))): `vdp` and
   !> `vdp_jacobian` with the other part's rows zeroed
   subroutine vdp_f(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      call vdp(n, x, y, f, rpar, ipar)
      f(2) = 0.0_dp
   end subroutine vdp_f

   subroutine vdp_g(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      call vdp(n, x, y, f, rpar, ipar)
      f(1) = 0.0_dp
   end subroutine vdp_g

   subroutine vdp_f_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      call vdp_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      dfy(2, 1:2) = 0.0_dp
   end subroutine vdp_f_jacobian

   subroutine vdp_g_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      call vdp_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      dfy(1, 1:2) = 0.0_dp
   end subroutine vdp_g_jacobian

   !> rpar(1) += both components at a quarter, half and three quarters of every step,
   !> through TAYLORODE_CONTR when ipar(1) = 1, else legacy_interpolate; rpar(2) counts
   !> the steps
   subroutine interpolating(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      integer :: i, k
      real(dp) :: s
      irtrn = 0
      if (nr == 1) return
      rpar(2) = rpar(2) + 1.0_dp
      do k = 1, 3
         s = xold + 0.25_dp*k*(x - xold)
         do i = 1, n
            if (ipar(1) == 1) then
               rpar(1) = rpar(1) + taylorode_contr(i, s, cont, lrc)
            else
               rpar(1) = rpar(1) + legacy_interpolate(i, s, cont, lrc)
            end if
         end do
      end do
   end subroutine interpolating

   !> y' = -y
   subroutine plain_decay(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      f = -y
   end subroutine plain_decay

   !> A Jacobian of 1e300 everywhere
   subroutine huge_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy(1:n, 1:n) = 1.0e300_dp
   end subroutine huge_jacobian

   !> Y tripled at NR = 1, halved at the first output past 0.55 (rpar(1) = 1 then)
   subroutine kicking(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      irtrn = 0
      if (nr == 1) y = 3.0_dp*y
      if (x >= 0.55_dp .and. rpar(1) == 0.0_dp) then
         y = 0.5_dp*y
         rpar(1) = 1.0_dp
      end if
   end subroutine kicking

   !> rpar(1) = the largest relative error of TAYLORODE_CONTR half a step past X against
   !> exp(-S) (y' = -y from y(0) = 1), rpar(2) = the calls after NR = 1
   subroutine extrapolating(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      real(dp) :: s
      irtrn = 0
      if (nr == 1) return
      s = x + 0.5_dp*(x - xold)
      rpar(1) = max(rpar(1), abs(legacy_interpolate(1, s, cont, lrc) - exp(-s))/exp(-s))
      rpar(2) = rpar(2) + 1.0_dp
   end subroutine extrapolating

   !> A SOLOUT that is never called (IOUT = 0)
   subroutine no_output(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      irtrn = 0
   end subroutine no_output

   !> rpar(1) = where the first step ended (SOLOUT's second call)
   subroutine first_step(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      irtrn = 0
      if (nr == 2) rpar(1) = x
   end subroutine first_step

end module test_legacy
