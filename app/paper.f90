!> The paper's experiment in the taylorode app: `table` (Table 1 of the paper
!> reproduced, beside the paper's numbers) and `vdp` (one Van der Pol run with any
!> scheme and setting, its error against radau5 and its step history).
module app_paper
   use taylorode, only: dp, i8, status_type, status_ok, status_output_error, status_max_steps, status_name, &
      scheme_type, new_scheme, integrator_options_type, paper_options, norm_max, controller_name, integrate, &
      integration_stats_type, step_history_type
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, vdp_split_paper, vdp_split_stiff
   use taylorode_analysis, only: timed_run, timed_run_type, reference_run
   use taylorode_base_strings, only: format_real, format_count, format_fixed, format_integer, format_number, pad
   use app_cli, only: request_type
   use app_output, only: table_type, say, progress, new_table, add_row, error_text, status_word
   implicit none
   private

   public :: run_vdp, run_table

contains

   !> taylorode vdp: one run with a summary, the error against radau5 at t_end and on a
   !> grid, and (when asked) the step history, streamed into its file.
   subroutine run_vdp(request, stat)
      type(request_type), intent(in) :: request
      type(status_type), intent(out) :: stat
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: run_stat, reference_stat
      type(step_history_type) :: history
      real(dp) :: t_end, u(2), u_ref(2)
      real(dp), allocatable :: t_out(:), u_out(:, :), u_out_ref(:, :)
      integer :: k

      problem = new_van_der_pol(request%mu, request%splitting, request%ic)
      t_end = problem%t_end
      if (request%t_end > 0.0_dp) t_end = request%t_end
      options = request%options
      options%max_steps = request%budget
      options%history_states = allocated(request%history_file)
      t_out = [(t_end*real(k - 1, dp)/real(request%dense_points - 1, dp), k=1, request%dense_points)]
      allocate (u_out(2, size(t_out)), u_out_ref(2, size(t_out)))

      call new_scheme(request%scheme, scheme, stat)
      if (stat%code /= status_ok) return
      u = problem%u0
      if (allocated(request%history_file)) then
         call history%stream_to(request%history_file, stat, replace=request%force)
         if (stat%code /= status_ok) return
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, run_stat, history=history, &
            t_out=t_out, u_out=u_out)
         ! integrate has finished the file: a history that could not be written ends the command
         if (run_stat%code == status_output_error) then
            stat = run_stat
            return
         end if
      else
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, run_stat, t_out=t_out, u_out=u_out)
      end if

      call say("Van der Pol, mu = "//format_number(request%mu)//", IC"//format_integer(request%ic)// &
         ", t in [0, "//format_number(t_end)//"], "//split_name(request%splitting)//" splitting")
      call say("scheme "//request%scheme//", controller "//controller_name(options%controller)// &
         ", rtol "//format_real(options%rtol)//", atol "//format_real(options%atol)//", "// &
         merge("max", "rms", options%norm == norm_max)//" norm, h0 "//format_real(options%h0))
      if (run_stat%code == status_ok) then
         call say("status: ok")
      else
         call say("status: "//status_name(run_stat%code)//": "//run_stat%message)
      end if
      call say("accepted steps "//format_count(stats%accepted_steps)//", rejected "// &
         format_count(stats%rejected_steps())//" (error test "//format_count(stats%rejected_error)// &
         ", Newton "//format_count(stats%rejected_newton)//", non-finite "// &
         format_count(stats%rejected_nonfinite)//")")
      call say("evaluations: f "//format_count(stats%work%f_evaluations)//", g "// &
         format_count(stats%work%g_evaluations)//", Jacobians "// &
         format_count(stats%work%jac_f_evaluations)//" + "//format_count(stats%work%jac_g_evaluations)// &
         ", products J v "//format_count(stats%work%jacobian_products)// &
         ", LU factorizations "//format_count(stats%work%lu_factorizations)//", linear solves "// &
         format_count(stats%work%linear_solves)//", Newton iterations "// &
         format_count(stats%work%newton_iterations))
      call say("accepted h in ["//format_real(stats%h_min_accepted)//", "// &
         format_real(stats%h_max_accepted)//"], CPU "//format_fixed(stats%cpu_seconds, 3)//" s")
      if (allocated(request%history_file)) then
         call say("step history: "//format_integer(history%count)//" attempts, wrote "//request%history_file)
      end if
      if (run_stat%code /= status_ok) then
         call say("error: not measured, the run stopped at t = "//format_real(stats%t_reached))
      else
         call progress("vdp: reference solution (radau5 at 1e-12)")
         call reference_run(problem, 0.0_dp, t_end, problem%u0, t_out, u_ref, u_out_ref, reference_stat, &
            max_steps=request%budget)
         if (reference_stat%code /= status_ok) then
            call say("error: not measured, the reference run stopped ("//status_name(reference_stat%code)//")")
         else
            call say("error at t = "//format_number(t_end)//": y "//format_real(abs(u(1) - u_ref(1)))// &
               ", z "//format_real(abs(u(2) - u_ref(2)))//" (against radau5 at rtol = atol = 1e-12)")
            call say("max error on the "//format_integer(request%dense_points)//"-point grid: "// &
               format_real(maxval(abs(u_out - u_out_ref)))//" (dense output: "// &
               trim(merge("the scheme's own", "cubic Hermite   ", scheme%dense_degree > 0))//")")
         end if
      end if
      stat = run_stat
   end subroutine run_vdp

   !> taylorode table: the paper's Table 1 for both initial conditions, every scheme of
   !> the paper plus si-t-2, radau5 and the stiff splitting.
   subroutine run_table(request, tables, stat)
      type(request_type), intent(in) :: request
      type(table_type), allocatable, intent(inout) :: tables(:)
      type(status_type), intent(out) :: stat
      !> rows: scheme, splitting, index into the paper's columns (0: none)
      character(len=*), parameter :: names(10) = [character(len=12) :: "si-t-1", "si-t-2-paper", &
         "i-t-1", "i-t-2", "imex-rk21", "si-t-2", "radau5", "si-t-1", "si-t-2", "i-t-2"]
      integer, parameter :: splits(10) = [1, 1, 1, 1, 1, 1, 1, 2, 2, 2]
      integer, parameter :: paper_column(10) = [1, 2, 3, 4, 5, 0, 6, 0, 0, 0]
      !> Table 1 of the paper, by initial condition: accepted steps and CPU seconds
      !> (MATLAB) of SI-T-1, SI-T-2, I-T-1, I-T-2, IMEX-RK(2,1) and ode15s
      integer, parameter :: paper_steps(6, 2) = reshape([38602, 38572, 160083, 160103, 2819271, 632, &
         38547, 38563, 159692, 159710, 2804550, 592], [6, 2])
      real(dp), parameter :: paper_cpu(6, 2) = reshape([10.76_dp, 10.75_dp, 26.88_dp, 26.98_dp, 16.65_dp, &
         0.05_dp, 10.96_dp, 10.88_dp, 25.96_dp, 25.99_dp, 16.48_dp, 0.05_dp], [6, 2])
      type(van_der_pol_type) :: problem
      type(integrator_options_type) :: options
      type(timed_run_type) :: run
      real(dp) :: t_out(301), u_ref(2), u_out_ref(2, 301), err_end, err_grid
      integer :: ic, k, table
      character(len=:), allocatable :: steps_text, note, paper_steps_text, paper_cpu_text, label, &
         paper_steps_csv, paper_cpu_csv

      t_out = [(10.0_dp*real(k - 1, dp), k=1, 301)]
      table = new_table(tables, "table1.csv", "ic,scheme,splitting,accepted,rejected,cpu_seconds,runs,"// &
         "status,t_reached,error_t3000,max_error_grid301,paper_steps,paper_cpu_seconds")
      call say("Table 1 of the paper reproduced: Van der Pol mu = 1000, t in [0, 3000], I controller,"// &
         " kappa 0.9, q 2, rtol 0, atol 1e-5, max norm, h0 1e-2")
      if (request%full) then
         call say("every run to the end (--full)")
      else
         call say("step budget "//format_count(request%budget)//" attempts per run (--full lifts it)")
      end if
      call say("CPU: cpu_time() around the integration, median of up to "//format_integer(request%repeats)// &
         " runs (one run when it takes over 1 s); errors in the max norm against radau5 at 1e-12")
      call say("")
      call say(pad("IC", 2)//"  "//pad("scheme", -13)//pad("split", -6)//pad("accepted", 12)// &
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
            call progress("table: IC"//format_integer(ic)//" "//label//" ("//split_name(splits(k))//" splitting)")
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
            paper_steps_csv = ""
            paper_cpu_csv = ""
            if (paper_column(k) > 0) then
               paper_steps_text = format_count(int(paper_steps(paper_column(k), ic), i8))
               paper_cpu_text = format_fixed(paper_cpu(paper_column(k), ic), 2)
               paper_steps_csv = format_integer(paper_steps(paper_column(k), ic))
               paper_cpu_csv = paper_cpu_text
            end if
            call say(pad(format_integer(ic), 2)//"  "//pad(label, -13)//pad(split_name(splits(k)), -6)// &
               pad(steps_text, 12)//pad(format_count(run%stats%rejected_steps()), 9)// &
               pad(format_fixed(run%cpu_median, 3), 9)//pad(error_text(err_end), 11)// &
               pad(error_text(err_grid), 13)//pad(paper_steps_text, 12)//pad(paper_cpu_text, 12)//"  "//note)
            call add_row(tables(table), format_integer(ic)//","//label//","//split_name(splits(k))//","// &
               format_integer(run%stats%accepted_steps)//","//format_integer(run%stats%rejected_steps())//","// &
               format_real(run%cpu_median, 4)//","//format_integer(run%runs)//","//status_word(run%stat%code)//","// &
               format_real(run%stats%t_reached, 8)//","//error_text(err_end)//","//error_text(err_grid)//","// &
               paper_steps_csv//","//paper_cpu_csv)
         end do
      end do
      stat%code = status_ok
   end subroutine run_table

   !> Two notes of a table row joined by "; " (the second may be empty).
   pure function join_notes(first, second) result(text)
      character(len=*), intent(in) :: first, second
      character(len=:), allocatable :: text
      text = first
      if (len(second) > 0) text = first//"; "//second
   end function join_notes

   !> The name of a Van der Pol splitting (paper or stiff).
   pure function split_name(splitting) result(text)
      integer, intent(in) :: splitting
      character(len=:), allocatable :: text
      if (splitting == vdp_split_stiff) then
         text = "stiff"
      else
         text = "paper"
      end if
   end function split_name

end module app_paper
