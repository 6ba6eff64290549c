!> The app's checks: stability functions against real steps, S1 regions and
!> L-stability (stability), and the stiff and extreme cases (extreme).
module app_checks
   use taylorode, only: dp, i8, status_type, status_ok, status_name, status_nonfinite, status_invalid_argument, &
      status_unknown_scheme, status_max_steps, scheme_type, new_scheme, scheme_names, scheme_count, &
      integrator_options_type, paper_options, integrate, integration_stats_type
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, vdp_split_paper, &
      vdp_ic_unprepared, robertson_type, new_robertson, hires_type, new_hires
   use taylorode_analysis, only: progress_interface, reference_run, step_stability, s1_supremum, s1_axis_crossings
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, format_number, pad, &
      choose
   use app_cli, only: cli_request_type
   use app_report, only: report_type
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_finite
   implicit none
   private

   public :: run_stability, run_extreme

contains

   !> taylorode stability: (1) R(z, w) against one real step, (2) S1 regions and their
   !> axis crossings, (3) |R(z, w)| as Re w -> -1e12.
   subroutine run_stability(request, report, stat)
      type(cli_request_type), intent(in) :: request
      type(report_type), intent(out) :: report
      type(status_type), intent(out) :: stat
      class(scheme_type), allocatable :: scheme
      complex(dp) :: z, w, r, r_step
      real(dp) :: deviation, worst, re_z, im_z, sup, left, right, top
      integer :: k, i, j, pairs, check_table, region_table, l_table, e
      character(len=:), allocatable :: name, line

      check_table = report%new_table("stability_check.csv", "scheme,pairs,max_relative_deviation")
      region_table = report%new_table("s1_regions.csv", "scheme,re_z,im_z,sup_abs_r,inside")
      l_table = report%new_table("l_stability.csv", "scheme,re_w,abs_r_formula,abs_r_step")

      call report%add_line("(1) one real step of each scheme on u' = lambda u + nu u (2x2 blocks, h = 1)"// &
         " against R(z, w), z = lambda, w = nu")
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         worst = 0.0_dp
         pairs = 0
         do i = 0, 9
            do j = 0, 9
               z = cmplx(-2.5_dp + 0.3_dp*i, -1.5_dp + 0.33_dp*j, dp)
               w = cmplx(-10.0_dp**(0.6_dp*j - 1.0_dp), 2.0_dp*(i - 4.5_dp), dp)
               call step_stability(scheme, z, w, r_step, stat)
               if (stat%code /= status_ok) cycle
               r = scheme%stability(z, w)
               deviation = abs(r_step - r)/max(abs(r), 1.0_dp)
               worst = max(worst, deviation)
               pairs = pairs + 1
            end do
         end do
         call report%add_line("  "//pad(name, -13)//pad(format_integer(pairs), 4)//" pairs, largest deviation "// &
            format_real(worst, 2)//" (relative to max(|R|, 1))")
         call report%tables(check_table)%add_row(name//","//format_integer(pairs)//","//format_real(worst, 3))
         if (worst > 1.0e-12_dp) report%passed = .false.
      end do

      call report%add_line("")
      call report%add_line("(2) S1 = {z : sup over Re w <= 0 of |R(z, w)| <= 1} on [-3, 1] x [-2, 2], "// &
         format_integer(request%grid)//" x "//format_integer(request%grid)//" points; axis crossings by bisection")
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         do i = 1, request%grid
            re_z = -3.0_dp + 4.0_dp*real(i - 1, dp)/real(request%grid - 1, dp)
            do j = 1, request%grid
               im_z = -2.0_dp + 4.0_dp*real(j - 1, dp)/real(request%grid - 1, dp)
               sup = s1_supremum(scheme, cmplx(re_z, im_z, dp))
               call report%tables(region_table)%add_row(name//","//format_fixed(re_z, 4)//","// &
                  format_fixed(im_z, 4)//","//format_real(sup, 4)//","//merge("1", "0", sup <= 1.0_dp + 1.0e-12_dp))
            end do
         end do
         call s1_axis_crossings(scheme, left, right, top)
         if (left > right) then
            call report%add_line("  "//pad(name, -13)//"empty (no z with |R| <= 1 for every Re w <= 0)")
         else
            call report%add_line("  "//pad(name, -13)//"real axis ["//crossing(left, -3.0_dp)//", "// &
               crossing(right, 1.0_dp)//"], imaginary axis |Im z| <= "//crossing(top, 2.0_dp))
         end if
      end do

      call report%add_line("")
      call report%add_line("(3) L-stability: |R(-0.5, w)| for real w -> -1e12 (formula; last column one real step)")
      call report%add_line("  "//pad("scheme", -13)//pad("w=-1e0", 10)//pad("w=-1e3", 10)//pad("w=-1e6", 10)// &
         pad("w=-1e9", 10)//pad("w=-1e12", 10)//pad("step 1e12", 11))
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         call new_scheme(name, scheme, stat)
         line = "  "//pad(name, -13)
         do e = 0, 12, 3
            w = cmplx(-10.0_dp**e, 0.0_dp, dp)
            r = scheme%stability((-0.5_dp, 0.0_dp), w)
            call step_stability(scheme, (-0.5_dp, 0.0_dp), w, r_step, stat)
            line = line//pad(format_real(abs(r), 2), 10)
            call report%tables(l_table)%add_row(name//","//format_real(real(w, dp), 2)//","// &
               format_real(abs(r), 4)//","//format_real(abs(r_step), 4))
         end do
         line = line//pad(format_real(abs(r_step), 2), 11)
         call report%add_line(line)
      end do
      stat%code = status_ok
   end subroutine run_stability

   pure function crossing(x, limit) result(text)
      real(dp), intent(in) :: x, limit
      character(len=:), allocatable :: text
      text = format_fixed(x, 4)
      if (x == limit) text = text//" (edge of the grid)"
   end function crossing

   !> taylorode extreme: one pass/fail line per stiff or extreme case.
   subroutine run_extreme(request, report, stat, progress)
      type(cli_request_type), intent(in) :: request
      type(report_type), intent(out) :: report
      type(status_type), intent(out) :: stat
      procedure(progress_interface), optional :: progress
      character(len=*), parameter :: l_stable(4) = [character(len=6) :: "si-t-1", "si-t-2", "i-t-1", "i-t-2"]
      type(van_der_pol_type) :: vdp
      type(robertson_type) :: robertson
      type(hires_type) :: hires
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: run_stat
      real(dp) :: u2(2), u3(3), u8(8), reference2(2), reference8(8), none(0), none_out(2, 0), err, nan
      real(dp) :: tol
      complex(dp) :: r, r_step
      integer :: k, table, i
      logical :: ok

      table = report%new_table("extreme.csv", "case,scheme,steps,rejected,figure,status,ok")
      nan = ieee_value(1.0_dp, ieee_quiet_nan)

      ! Van der Pol mu = 1e6 over [0, 3e6] (1e4 with --quick)
      vdp = new_van_der_pol(merge(1.0e4_dp, 1.0e6_dp, request%quick))
      call reference_run(vdp, 0.0_dp, vdp%t_end, vdp%u0, none, reference2, none_out, stat)
      if (stat%code /= status_ok) return
      do k = 1, size(l_stable)
         if (present(progress)) call progress("extreme: "//trim(l_stable(k))//" Van der Pol mu = "// &
            format_real(vdp%mu, 1))
         call new_scheme(trim(l_stable(k)), scheme, stat)
         options = integrator_options_type(rtol=1.0e-5_dp, atol=1.0e-5_dp, max_steps=5000000_i8)
         u2 = vdp%u0
         call integrate(vdp, scheme, 0.0_dp, vdp%t_end, u2, options, stats, run_stat)
         err = abs(u2(1) - reference2(1))
         ok = run_stat%code == status_ok
         call verdict("vdp mu="//format_real(vdp%mu, 1)//" tol=1e-5", trim(l_stable(k)), stats, "err y "//format_real(err, 2), &
            run_stat, ok)
      end do

      ! Robertson to 1e11
      robertson = new_robertson(1.0e11_dp)
      do k = 1, size(l_stable)
         call new_scheme(trim(l_stable(k)), scheme, stat)
         options = integrator_options_type(rtol=robertson%rtol, atol=robertson%atol)
         u3 = robertson%u0
         call integrate(robertson, scheme, 0.0_dp, robertson%t_end, u3, options, stats, run_stat)
         err = maxval(abs(u3 - robertson%reference)/robertson%reference)
         ok = run_stat%code == status_ok .and. abs(sum(u3) - 1.0_dp) < 1.0e-8_dp .and. all(ieee_is_finite(u3))
         call verdict("robertson t=1e11", trim(l_stable(k)), stats, "rel err "//format_real(err, 2)// &
            ", mass-1 "//format_real(sum(u3) - 1.0_dp, 2), run_stat, ok)
      end do

      ! the linear test with w = -1e12, one step each: the step must reproduce the
      ! scheme's own R (which damps for the L-stable schemes and grows for the explicit ones)
      do k = 1, scheme_count
         call new_scheme(trim(scheme_names(k)), scheme, run_stat)
         r = scheme%stability((-1.0_dp, 0.0_dp), (-1.0e12_dp, 0.0_dp))
         call step_stability(scheme, (-1.0_dp, 0.0_dp), (-1.0e12_dp, 0.0_dp), r_step, run_stat)
         ok = run_stat%code == status_ok .and. abs(r_step - r) <= 1.0e-12_dp*max(abs(r), 1.0_dp)
         call verdict("linear w=-1e12 one step", trim(scheme_names(k)), stats, "|u1| "// &
            format_real(abs(r_step), 2)//choose(abs(r) > 1.0_dp, " (unstable, as its R says)", ""), &
            run_stat, ok, steps_known=.false.)
      end do

      ! tolerances 1e-2 and 1e-10 (1e-8 with --quick) on HIRES
      hires = new_hires()
      do i = 1, 2
         tol = merge(1.0e-2_dp, merge(1.0e-8_dp, 1.0e-10_dp, request%quick), i == 1)
         do k = 3, 4
            if (present(progress)) call progress("extreme: "//trim(l_stable(k))//" HIRES tol "//format_real(tol, 2))
            call new_scheme(trim(l_stable(k)), scheme, stat)
            options = integrator_options_type(rtol=tol, atol=tol*1.0e-4_dp, max_steps=5000000_i8)
            u8 = hires%u0
            call integrate(hires, scheme, 0.0_dp, hires%t_end, u8, options, stats, run_stat)
            reference8 = hires%reference
            err = maxval(abs(u8 - reference8))/maxval(abs(reference8))
            ok = run_stat%code == status_ok .and. all(ieee_is_finite(u8))
            call verdict("hires tol="//format_real(tol, 2), trim(l_stable(k)), stats, "rel err "// &
               format_real(err, 2), run_stat, ok)
         end do
      end do

      ! unprepared initial data (IC2), the paper's setting
      vdp = new_van_der_pol(1000.0_dp, vdp_split_paper, vdp_ic_unprepared)
      do k = 1, size(l_stable)
         call new_scheme(trim(l_stable(k)), scheme, stat)
         options = paper_options()
         u2 = vdp%u0
         call integrate(vdp, scheme, 0.0_dp, vdp%t_end, u2, options, stats, run_stat)
         err = abs(u2(1) - vdp%reference(1))
         ok = run_stat%code == status_ok .and. err < 1.0e-2_dp
         call verdict("vdp IC2 (unprepared)", trim(l_stable(k)), stats, "err y "//format_real(err, 2), run_stat, ok)
      end do

      ! deliberately bad input: each must come back with its status, not a crash
      call new_scheme("i-t-2", scheme, stat)
      u2 = [2.0_dp, nan]
      call integrate(vdp, scheme, 0.0_dp, 1.0_dp, u2, paper_options(), stats, run_stat)
      call bad_input("NaN initial state", run_stat, status_nonfinite)
      u2 = vdp%u0
      call integrate(vdp, scheme, 0.0_dp, 1.0_dp, u2, integrator_options_type(rtol=-1.0_dp), stats, run_stat)
      call bad_input("negative rtol", run_stat, status_invalid_argument)
      call integrate(vdp, scheme, 0.0_dp, 1.0_dp, u2, integrator_options_type(h0=-1.0_dp), stats, run_stat)
      call bad_input("negative h0", run_stat, status_invalid_argument)
      call integrate(vdp, scheme, 1.0_dp, 0.0_dp, u2, paper_options(), stats, run_stat)
      call bad_input("t_end < t0", run_stat, status_invalid_argument)
      call integrate(vdp, scheme, 0.0_dp, 3000.0_dp, u2, integrator_options_type(max_steps=100_i8), stats, run_stat)
      call bad_input("100-step budget", run_stat, status_max_steps)
      call new_scheme("rk45", scheme, run_stat)
      call bad_input("unknown scheme rk45", run_stat, status_unknown_scheme)

      if (report%passed) then
         call report%add_line("all extreme cases passed")
      else
         call report%add_line("SOME EXTREME CASES FAILED")
      end if
      stat%code = status_ok

   contains

      subroutine verdict(label, name, stats, figure, run_stat, ok, steps_known)
         character(len=*), intent(in) :: label, name, figure
         type(integration_stats_type), intent(in) :: stats
         type(status_type), intent(in) :: run_stat
         logical, intent(in) :: ok
         logical, intent(in), optional :: steps_known
         character(len=:), allocatable :: steps, status_text
         steps = format_count(stats%accepted_steps)//" steps, "
         if (present(steps_known)) then
            if (.not. steps_known) steps = ""
         end if
         status_text = status_name(run_stat%code)
         call report%add_line(pad(merge("ok  ", "FAIL", ok), -5)//name//" "//label//": "//steps//figure// &
            choose(run_stat%code == status_ok, "", ", "//status_text))
         call report%tables(table)%add_row(label//","//name//","//choose(len(steps) > 0, &
            format_integer(stats%accepted_steps), "")//","//format_integer(stats%rejected_steps())//',"'//figure//'",'// &
            status_text//","//merge("1", "0", ok))
         if (.not. ok) report%passed = .false.
      end subroutine verdict

      subroutine bad_input(label, run_stat, expected)
         character(len=*), intent(in) :: label
         type(status_type), intent(in) :: run_stat
         integer, intent(in) :: expected
         logical :: ok
         character(len=:), allocatable :: message
         ok = run_stat%code == expected
         message = ""
         if (allocated(run_stat%message)) message = run_stat%message
         call report%add_line(pad(merge("ok  ", "FAIL", ok), -5)//"bad input, "//label//": "// &
            status_name(run_stat%code)//" ("//message//")")
         call report%tables(table)%add_row("bad input "//label//",,,,"//'"'//message//'",'// &
            status_name(run_stat%code)//","//merge("1", "0", ok))
         if (.not. ok) report%passed = .false.
      end subroutine bad_input

   end subroutine run_extreme

end module app_checks
