!> The app's benchmark: time per step of every scheme on the paper's Van der Pol
!> run, the saving of Newton matrix reuse, the share of LAPACK in a 2x2 Newton step,
!> and the growth of the time per step with N on the banded Brusselator.
module app_bench
   use taylorode, only: dp, i8, status_type, status_ok, status_max_steps, scheme_names, scheme_count, &
      integrator_options_type, paper_options
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, brusselator_type, new_brusselator
   use taylorode_analysis, only: progress_interface, timed_run, timed_run_type
   use taylorode_linalg_lapack, only: lu_factor, lu_solve
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, pad, choose
   use app_cli, only: cli_request_type
   use app_report, only: report_type
   implicit none
   private

   public :: run_bench, peak_memory_kib

   !> Brusselator interval of the scaling runs
   real(dp), parameter :: brusselator_t_end = 0.5_dp

contains

   !> taylorode bench: the tables described in the module comment. The Van der Pol runs
   !> stop at the step budget (si-t-2-paper and imex-rk21 need ~50 million steps).
   subroutine run_bench(request, report, stat, progress)
      type(cli_request_type), intent(in) :: request
      type(report_type), intent(out) :: report
      type(status_type), intent(out) :: stat
      procedure(progress_interface), optional :: progress
      type(van_der_pol_type) :: vdp
      type(brusselator_type) :: brusselator
      type(integrator_options_type) :: options
      type(timed_run_type) :: run, run_no_reuse
      real(dp) :: per_step, lapack_seconds, base_per_unknown
      integer :: k, table, points, decade
      character(len=:), allocatable :: name

      table = report%new_table("bench.csv", "problem,scheme,unknowns,accepted,seconds,ns_per_step,"// &
         "f_evaluations,g_evaluations,jacobian_evaluations,lu_factorizations,status,peak_memory_kib")
      call report%add_line("Van der Pol mu = 1000, paper settings (I controller, atol 1e-5, rtol 0), t in [0, 3000];"// &
         " CPU by cpu_time(), median of "//format_integer(request%repeats)//" runs; budget "//format_count(request%budget)// &
         " attempts")
      call report%add_line(pad("scheme", -13)//pad("accepted", 11)//pad("seconds", 9)//pad("ns/step", 9)// &
         pad("f evals", 11)//pad("g evals", 11)//pad("Jac evals", 11)//pad("LU", 9)//"  note")
      vdp = new_van_der_pol(1000.0_dp)
      do k = 1, scheme_count
         name = trim(scheme_names(k))
         options = paper_options()
         options%max_steps = request%budget
         if (present(progress)) call progress("bench: "//name)
         call timed_run(vdp, name, options, 0.0_dp, 3000.0_dp, vdp%u0, request%repeats, run)
         per_step = 1.0e9_dp*run%cpu_median/real(max(run%stats%accepted_steps, 1_i8), dp)
         call report%add_line(pad(name, -13)//pad(format_count(run%stats%accepted_steps), 11)// &
            pad(format_fixed(run%cpu_median, 3), 9)//pad(format_fixed(per_step, 0), 9)// &
            pad(format_count(run%stats%work%f_evaluations), 11)//pad(format_count(run%stats%work%g_evaluations), 11)// &
            pad(format_count(run%stats%work%jac_f_evaluations + run%stats%work%jac_g_evaluations), 11)// &
            pad(format_count(run%stats%work%lu_factorizations), 9)// &
            choose(run%stat%code == status_max_steps, "  budget reached at t = "// &
            format_fixed(run%stats%t_reached, 1), ""))
         call add_csv_row("vdp", name, 2, run, per_step)
         if (name == "i-t-2") then
            lapack_seconds = lapack_time(run%stats%work%lu_factorizations, run%stats%work%linear_solves)
            call report%add_line("  i-t-2: LAPACK (dgetrf + dgetrs on 2x2, timed apart and scaled by the counts) "// &
               format_fixed(1.0e9_dp*lapack_seconds/real(run%stats%accepted_steps, dp), 0)//" ns/step, "// &
               format_fixed(100.0_dp*lapack_seconds/run%cpu_median, 0)//" % of the run")
         end if
      end do

      call report%add_line("")
      call report%add_line("Newton matrix reuse (i-t-2, same run): kept across steps against factored in every solve")
      options = paper_options()
      call timed_run(vdp, "i-t-2", options, 0.0_dp, 3000.0_dp, vdp%u0, request%repeats, run)
      options%reuse_newton_matrix = .false.
      call timed_run(vdp, "i-t-2", options, 0.0_dp, 3000.0_dp, vdp%u0, request%repeats, run_no_reuse)
      call report%add_line("  reuse on:  "//format_count(run%stats%accepted_steps)//" steps, "// &
         format_count(run%stats%work%lu_factorizations)//" LU, "//format_fixed(run%cpu_median, 3)//" s")
      call report%add_line("  reuse off: "//format_count(run_no_reuse%stats%accepted_steps)//" steps, "// &
         format_count(run_no_reuse%stats%work%lu_factorizations)//" LU, "//format_fixed(run_no_reuse%cpu_median, 3)// &
         " s; steps per LU with reuse: "//format_fixed(real(run%stats%accepted_steps, dp)/ &
         real(max(run%stats%work%lu_factorizations, 1_i8), dp), 1))

      call report%add_line("")
      call report%add_line("Brusselator (banded Jacobians, bandwidths 2 + 2), si-t-2, rtol = atol = 1e-6, t in [0, "// &
         format_fixed(brusselator_t_end, 1)//"]; time per step and per unknown, relative to N = 1000")
      call report%add_line(pad("N", 8)//pad("unknowns", 10)//pad("accepted", 10)//pad("seconds", 10)// &
         pad("us/step", 11)//pad("ns/step/unknown", 17)//pad("vs N=1000", 11)//pad("peak MiB", 10))
      base_per_unknown = 0.0_dp
      do decade = 2, 8
         points = 10**decade
         if (points > request%max_points) exit
         brusselator = new_brusselator(points)
         options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp)
         if (present(progress)) call progress("bench: Brusselator N = "//format_integer(points))
         call timed_run(brusselator, "si-t-2", options, 0.0_dp, brusselator_t_end, brusselator%u0, &
            merge(request%repeats, 1, points <= 1000), run)
         per_step = 1.0e9_dp*run%cpu_median/real(max(run%stats%accepted_steps, 1_i8), dp)
         if (points == 1000) base_per_unknown = per_step/real(2*points, dp)
         call report%add_line(pad(format_integer(points), 8)//pad(format_integer(2*points), 10)// &
            pad(format_count(run%stats%accepted_steps), 10)//pad(format_fixed(run%cpu_median, 3), 10)// &
            pad(format_fixed(per_step/1000.0_dp, 1), 11)//pad(format_fixed(per_step/real(2*points, dp), 1), 17)// &
            pad(choose(base_per_unknown > 0.0_dp, format_fixed(per_step/real(2*points, dp)/ &
            max(base_per_unknown, tiny(1.0_dp)), 2), "-"), 11)// &
            pad(format_fixed(real(peak_memory_kib(), dp)/1024.0_dp, 1), 10))
         call add_csv_row("brusselator", "si-t-2", 2*points, run, per_step)
      end do
      stat%code = status_ok

   contains

      subroutine add_csv_row(problem, scheme, unknowns, run, per_step)
         character(len=*), intent(in) :: problem, scheme
         integer, intent(in) :: unknowns
         type(timed_run_type), intent(in) :: run
         real(dp), intent(in) :: per_step
         call report%tables(table)%add_row(problem//","//scheme//","//format_integer(unknowns)//","// &
            format_integer(run%stats%accepted_steps)//","//format_real(run%cpu_median, 4)//","// &
            format_real(per_step, 4)//","//format_integer(run%stats%work%f_evaluations)//","// &
            format_integer(run%stats%work%g_evaluations)//","// &
            format_integer(run%stats%work%jac_f_evaluations + run%stats%work%jac_g_evaluations)//","// &
            format_integer(run%stats%work%lu_factorizations)//","//choose(run%stat%code == status_ok, "ok", "stopped")// &
            ","//format_integer(peak_memory_kib()))
      end subroutine add_csv_row

   end subroutine run_bench

   !> Seconds that `factorizations` dgetrf and `solves` dgetrs calls on a 2x2 Newton
   !> matrix take, timed in a loop of their own.
   real(dp) function lapack_time(factorizations, solves)
      integer(i8), intent(in) :: factorizations, solves
      integer, parameter :: calls = 2000000
      real(dp) :: a(2, 2), lu(2, 2), b(2), start, finish, per_factor, per_solve
      integer :: pivots(2), info, k

      a = reshape([1.0_dp, -2.0e3_dp, 1.0e-2_dp, 3.0e3_dp], [2, 2])
      call cpu_time(start)
      do k = 1, calls
         lu = a
         lu(1, 1) = lu(1, 1) + 1.0e-12_dp*k
         call lu_factor(lu, pivots, info)
      end do
      if (info /= 0) lu = a
      call cpu_time(finish)
      per_factor = (finish - start)/calls
      call cpu_time(start)
      do k = 1, calls
         b = [1.0_dp, 2.0e-3_dp*k]
         call lu_solve(lu, pivots, b, info)
      end do
      call cpu_time(finish)
      per_solve = (finish - start)/calls
      lapack_time = per_factor*real(factorizations, dp) + per_solve*real(solves, dp)
   end function lapack_time

   !> Peak resident memory of this process in KiB (VmHWM of /proc/self/status; 0 when
   !> it cannot be read).
   integer(i8) function peak_memory_kib()
      integer :: unit, io
      character(len=256) :: line
      peak_memory_kib = 0
      open (newunit=unit, file="/proc/self/status", status="old", action="read", iostat=io)
      if (io /= 0) return
      do
         read (unit, '(a)', iostat=io) line
         if (io /= 0) exit
         if (line(1:6) == "VmHWM:") then
            read (line(7:), *, iostat=io) peak_memory_kib
            exit
         end if
      end do
      close (unit)
   end function peak_memory_kib

end module app_bench
