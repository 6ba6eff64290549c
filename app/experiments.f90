!> The app's experiments on Van der Pol and the test set: one run with a summary
!> (vdp), the paper's Table 1 (table) and work-precision sweeps (sweep). Each
!> returns a report; the app prints it and writes its tables.
module app_experiments
   use taylorode, only: dp, i8, status_type, status_ok, status_max_steps, status_name, scheme_type, new_scheme, &
      integrator_options_type, paper_options, norm_max, controller_name, integrate, integration_stats_type, &
      step_history_type, write_history_csv
   use taylorode_testset, only: test_problem_type, van_der_pol_type, new_van_der_pol, vdp_split_paper, &
      vdp_split_stiff, new_test_problem
   use taylorode_analysis, only: progress_interface, timed_run, timed_run_type, reference_run, tolerance_scale, &
      work_precision_config_type, work_precision_point_type, work_precision
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, format_number, pad, &
      choose
   use app_cli, only: cli_request_type
   use app_report, only: report_type
   implicit none
   private

   public :: run_vdp, run_table, run_sweep, error_text, status_word

   !> Table 1 of the paper, by initial condition: accepted steps and CPU seconds
   !> (MATLAB) of SI-T-1, SI-T-2, I-T-1, I-T-2, IMEX-RK(2,1) and ode15s
   integer, parameter :: paper_steps(6, 2) = reshape([38602, 38572, 160083, 160103, 2819271, 632, &
      38547, 38563, 159692, 159710, 2804550, 592], [6, 2])
   real(dp), parameter :: paper_cpu(6, 2) = reshape([10.76_dp, 10.75_dp, 26.88_dp, 26.98_dp, 16.65_dp, &
      0.05_dp, 10.96_dp, 10.88_dp, 25.96_dp, 25.99_dp, 16.48_dp, 0.05_dp], [6, 2])

contains

   !> taylorode vdp: one run with a summary, the error against radau5 at t_end and
   !> on a grid, and (when asked) the step history.
   subroutine run_vdp(request, report, stat)
      type(cli_request_type), intent(in) :: request
      type(report_type), intent(out) :: report
      type(status_type), intent(out) :: stat
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: run_stat
      type(step_history_type) :: history
      real(dp) :: t_end, u(2), u_ref(2)
      real(dp), allocatable :: t_out(:), u_out(:, :), u_out_ref(:, :)
      integer :: k

      problem = new_van_der_pol(request%mu, request%splitting, request%ic)
      t_end = problem%t_end
      if (request%t_end > 0.0_dp) t_end = request%t_end
      options = request%options
      if (allocated(request%history_file)) options%history_states = .true.
      t_out = [(t_end*real(k - 1, dp)/real(request%dense_points - 1, dp), k=1, request%dense_points)]
      allocate (u_out(2, size(t_out)), u_out_ref(2, size(t_out)))

      call new_scheme(request%scheme, scheme, stat)
      if (stat%code /= status_ok) return
      u = problem%u0
      if (allocated(request%history_file)) then
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, run_stat, history=history, &
            t_out=t_out, u_out=u_out)
      else
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, run_stat, t_out=t_out, u_out=u_out)
      end if
      call reference_run(problem, 0.0_dp, t_end, problem%u0, t_out, u_ref, u_out_ref, stat)
      if (stat%code /= status_ok) return

      call report%add_line("Van der Pol, mu = "//format_number(request%mu)//", IC"//format_integer(request%ic)// &
         ", t in [0, "//format_number(t_end)//"], "//split_name(request%splitting)//" splitting")
      call report%add_line("scheme "//request%scheme//", controller "//controller_name(options%controller)// &
         ", rtol "//format_real(options%rtol)//", atol "//format_real(options%atol)//", "// &
         merge("max", "rms", options%norm == norm_max)//" norm, h0 "//format_real(options%h0))
      if (run_stat%code == status_ok) then
         call report%add_line("status: ok")
      else
         call report%add_line("status: "//status_name(run_stat%code)//": "//run_stat%message)
      end if
      call report%add_line("accepted steps "//format_count(stats%accepted_steps)//", rejected "// &
         format_count(stats%rejected_steps())//" (error test "//format_count(stats%rejected_error)// &
         ", Newton "//format_count(stats%rejected_newton)//", non-finite "// &
         format_count(stats%rejected_nonfinite)//")")
      call report%add_line("evaluations: f "//format_count(stats%work%f_evaluations)//", g "// &
         format_count(stats%work%g_evaluations)//", Jacobians "// &
         format_count(stats%work%jac_f_evaluations)//" + "//format_count(stats%work%jac_g_evaluations)// &
         ", LU factorizations "//format_count(stats%work%lu_factorizations)//", linear solves "// &
         format_count(stats%work%linear_solves)//", Newton iterations "// &
         format_count(stats%work%newton_iterations))
      call report%add_line("accepted h in ["//format_real(stats%h_min_accepted)//", "// &
         format_real(stats%h_max_accepted)//"], CPU "//format_fixed(stats%cpu_seconds, 3)//" s")
      if (run_stat%code == status_ok) then
         call report%add_line("error at t = "//format_number(t_end)//": y "//format_real(abs(u(1) - u_ref(1)))// &
            ", z "//format_real(abs(u(2) - u_ref(2)))//" (against radau5 at rtol = atol = 1e-12)")
         call report%add_line("max error on the "//format_integer(request%dense_points)//"-point grid: "// &
            format_real(maxval(abs(u_out - u_out_ref)))//" (cubic Hermite dense output)")
      else
         call report%add_line("error: not measured, the run stopped at t = "//format_real(stats%t_reached))
      end if
      if (allocated(request%history_file)) then
         call write_history_csv(history, request%history_file, stat)
         if (stat%code /= status_ok) return
         call report%add_line("step history: "//format_integer(history%count)//" attempts, wrote "// &
            request%history_file)
      end if
      stat = run_stat
   end subroutine run_vdp

   !> taylorode table: the paper's Table 1 for both initial conditions, every scheme
   !> of the paper plus si-t-2, radau5 and the stiff splitting.
   subroutine run_table(request, report, stat, progress)
      type(cli_request_type), intent(in) :: request
      type(report_type), intent(out) :: report
      type(status_type), intent(out) :: stat
      procedure(progress_interface), optional :: progress
      !> rows: scheme, splitting, index into the paper's columns (0: none)
      character(len=*), parameter :: names(10) = [character(len=12) :: "si-t-1", "si-t-2-paper", &
         "i-t-1", "i-t-2", "imex-rk21", "si-t-2", "radau5", "si-t-1", "si-t-2", "i-t-2"]
      integer, parameter :: splits(10) = [1, 1, 1, 1, 1, 1, 1, 2, 2, 2]
      integer, parameter :: paper_column(10) = [1, 2, 3, 4, 5, 0, 6, 0, 0, 0]
      type(van_der_pol_type) :: problem
      type(integrator_options_type) :: options
      type(timed_run_type) :: run
      real(dp) :: t_out(301), u_ref(2), u_out_ref(2, 301), err_end, err_grid
      integer :: ic, k, table
      character(len=:), allocatable :: steps_text, note, paper_steps_text, paper_cpu_text, label

      t_out = [(10.0_dp*real(k - 1, dp), k=1, 301)]
      table = report%new_table("table1.csv", "ic,scheme,splitting,accepted,rejected,cpu_seconds,runs,"// &
         "status,t_reached,error_t3000,max_error_grid301,paper_steps,paper_cpu_seconds")
      call report%add_line("Table 1 of the paper reproduced: Van der Pol mu = 1000, t in [0, 3000], I controller,"// &
         " kappa 0.9, q 2, rtol 0, atol 1e-5, max norm, h0 1e-2")
      if (request%full) then
         call report%add_line("every run to the end (--full)")
      else
         call report%add_line("step budget "//format_count(request%budget)//" attempts per run (--full lifts it)")
      end if
      call report%add_line("CPU: cpu_time() around the integration, median of up to "//format_integer(request%repeats)// &
         " runs (one run when it takes over 1 s); errors in the max norm against radau5 at 1e-12")
      call report%add_line("")
      call report%add_line(pad("IC", 2)//"  "//pad("scheme", -13)//pad("split", -6)//pad("accepted", 12)// &
         pad("rejected", 9)//pad("CPU s", 9)//pad("err t=3000", 11)//pad("max err grid", 13)// &
         pad("paper steps", 12)//pad("paper CPU s", 12)//"  note")
      do ic = 1, 2
         problem = new_van_der_pol(1000.0_dp, vdp_split_paper, ic)
         call reference_run(problem, 0.0_dp, 3000.0_dp, problem%u0, t_out, u_ref, u_out_ref, stat)
         if (stat%code /= status_ok) return
         do k = 1, size(names)
            problem = new_van_der_pol(1000.0_dp, splits(k), ic)
            options = paper_options()
            if (.not. request%full) options%max_steps = request%budget
            label = trim(names(k))
            if (present(progress)) call progress("table: IC"//format_integer(ic)//" "//label//" ("// &
               split_name(splits(k))//" splitting)")
            call timed_run(problem, label, options, 0.0_dp, 3000.0_dp, problem%u0, request%repeats, run, t_out)
            note = ""
            if (run%stat%code == status_ok) then
               steps_text = format_count(run%stats%accepted_steps)
               err_end = maxval(abs(run%u - u_ref))
               err_grid = maxval(abs(run%u_out - u_out_ref))
            else
               steps_text = "> "//format_count(run%stats%accepted_steps)
               err_end = -1.0_dp
               err_grid = -1.0_dp
               if (run%stat%code == status_max_steps) then
                  note = "step budget reached, stopped at t = "//format_fixed(run%stats%t_reached, 1)
               else
                  note = status_name(run%stat%code)//" at t = "//format_fixed(run%stats%t_reached, 1)
               end if
            end if
            if (label == "si-t-2-paper") note = join_notes("first order on this problem", note)
            if (label == "radau5") note = join_notes("paper column: ode15s", note)
            paper_steps_text = ""
            paper_cpu_text = ""
            if (paper_column(k) > 0) then
               paper_steps_text = format_count(int(paper_steps(paper_column(k), ic), i8))
               paper_cpu_text = format_fixed(paper_cpu(paper_column(k), ic), 2)
            end if
            call report%add_line(pad(format_integer(ic), 2)//"  "//pad(label, -13)//pad(split_name(splits(k)), -6)// &
               pad(steps_text, 12)//pad(format_count(run%stats%rejected_steps()), 9)// &
               pad(format_fixed(run%cpu_median, 3), 9)//pad(error_text(err_end), 11)// &
               pad(error_text(err_grid), 13)//pad(paper_steps_text, 12)//pad(paper_cpu_text, 12)//"  "//note)
            call report%tables(table)%add_row(format_integer(ic)//","//label//","//split_name(splits(k))//","// &
               format_integer(run%stats%accepted_steps)//","//format_integer(run%stats%rejected_steps())//","// &
               format_real(run%cpu_median, 4)//","//format_integer(run%runs)//","//status_word(run%stat%code)//","// &
               format_real(run%stats%t_reached, 8)//","//error_text(err_end)//","//error_text(err_grid)//","// &
               paper_steps_text_csv(paper_column(k), ic)//","//paper_cpu_text_csv(paper_column(k), ic))
         end do
      end do
      stat%code = status_ok
   end subroutine run_table

   !> taylorode sweep: error against CPU time for each scheme over decades of
   !> tolerance (rtol = atol = tol, atol scaled for problems with small components).
   subroutine run_sweep(request, report, stat, progress)
      type(cli_request_type), intent(in) :: request
      type(report_type), intent(out) :: report
      type(status_type), intent(out) :: stat
      procedure(progress_interface), optional :: progress
      class(test_problem_type), allocatable :: problem
      type(work_precision_config_type) :: config
      type(work_precision_point_type), allocatable :: points(:)
      real(dp), allocatable :: reference(:), u_out_ref(:, :)
      real(dp) :: t_none(0)
      integer :: k, table
      character(len=:), allocatable :: reference_text

      call new_test_problem(request%problem, problem, stat)
      if (stat%code /= status_ok) return
      if (allocated(problem%reference)) then
         reference = problem%reference
         reference_text = "the published reference solution"
      else
         allocate (reference(size(problem%u0)), u_out_ref(size(problem%u0), 0))
         call reference_run(problem, problem%t0, problem%t_end, problem%u0, t_none, reference, u_out_ref, stat)
         if (stat%code /= status_ok) return
         reference_text = "radau5 at rtol = 1e-12"
      end if
      config%schemes = request%schemes
      config%tol_high = request%tol_high
      config%tol_low = request%tol_low
      config%repeats = request%repeats
      config%budget = request%budget
      call work_precision(problem, config, reference, points, progress)

      table = report%new_table("sweep.csv", "problem,scheme,tol,accepted,rejected,cpu_seconds,runs,status,error")
      call report%add_line("work-precision on "//problem%name//" over [" //format_number(problem%t0)//", "// &
         format_number(problem%t_end)//"]: rtol = tol, atol = tol * "// &
         format_real(tolerance_scale(problem))//"; error = max|u - ref| / max|ref| at t_end against "//reference_text)
      call report%add_line("CPU: median of up to "//format_integer(request%repeats)//" runs; step budget "// &
         format_count(request%budget))
      call report%add_line("")
      call report%add_line(pad("scheme", -13)//pad("tol", 10)//pad("accepted", 12)//pad("rejected", 10)// &
         pad("CPU s", 10)//pad("error", 11)//"  note")
      do k = 1, size(points)
         associate (p => points(k))
            call report%add_line(pad(trim(p%scheme), -13)//pad(format_real(p%tol, 2), 10)// &
               pad(format_count(p%accepted), 12)//pad(format_count(p%rejected), 10)// &
               pad(format_fixed(p%cpu_seconds, 4), 10)//pad(error_text(p%error), 11)//"  "// &
               choose(p%status == status_ok, "", status_name(p%status)))
            call report%tables(table)%add_row(problem%name//","//trim(p%scheme)//","//format_real(p%tol, 2)//","// &
               format_integer(p%accepted)//","//format_integer(p%rejected)//","// &
               format_real(p%cpu_seconds, 4)//","//format_integer(p%runs)//","//status_word(p%status)//","// &
               error_text(p%error))
         end associate
      end do
      stat%code = status_ok
   end subroutine run_sweep

   pure function join_notes(first, second) result(text)
      character(len=*), intent(in) :: first, second
      character(len=:), allocatable :: text
      text = first
      if (len(second) > 0) text = first//"; "//second
   end function join_notes

   pure function error_text(err) result(text)
      real(dp), intent(in) :: err
      character(len=:), allocatable :: text
      if (err < 0.0_dp) then
         text = "n/a"
      else
         text = format_real(err, 2)
      end if
   end function error_text

   pure function status_word(code) result(text)
      integer, intent(in) :: code
      character(len=:), allocatable :: text
      integer :: i
      text = status_name(code)
      do i = 1, len(text)
         if (text(i:i) == " ") text(i:i) = "_"
      end do
   end function status_word

   pure function split_name(splitting) result(text)
      integer, intent(in) :: splitting
      character(len=:), allocatable :: text
      if (splitting == vdp_split_stiff) then
         text = "stiff"
      else
         text = "paper"
      end if
   end function split_name

   pure function paper_steps_text_csv(column, ic) result(text)
      integer, intent(in) :: column, ic
      character(len=:), allocatable :: text
      text = ""
      if (column > 0) text = format_integer(paper_steps(column, ic))
   end function paper_steps_text_csv

   pure function paper_cpu_text_csv(column, ic) result(text)
      integer, intent(in) :: column, ic
      character(len=:), allocatable :: text
      text = ""
      if (column > 0) text = format_fixed(paper_cpu(column, ic), 2)
   end function paper_cpu_text_csv

end module app_experiments
