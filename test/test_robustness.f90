!> Every promise of the README under bad input, faults and threads: each test here
!> failed before the fix it guards (see the reliability issue's list).
module test_robustness
   use testdrive, only: new_unittest, unittest_type, error_type, check, skip_test
   use test_support, only: differenced_brusselator, dense_amplifier_type, dense_akzo_type, scratch, run_type, &
      run_app, run_command, &
      read_lines, line_type, has_line, &
      file_exists, fresh_scratch, app_path, stat_message, c_create, c_free, c_set_option, c_set_bandwidths, message_of, &
      legacy_no_jacobian
   use taylorode, only: dp, i8, ode_problem, ode_problem_fd, scheme_type, new_scheme, integrate, status_type, &
      integrator_options_type, integration_stats_type, step_history_type, write_history_csv, status_ok, &
      status_invalid_argument, status_nonfinite, status_output_error, status_max_steps, &
      status_evaluation_failed, status_newton_not_converged, status_newton_diverged, matrix_structure_type, &
      band_structure, dense_structure, integrator_type, integrate_fixed, status_step_underflow
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, brusselator_type, new_brusselator, &
      transistor_amplifier_type, new_transistor_amplifier, test_problem_type, new_medical_akzo, new_test_problem, &
      test_problem_names
   use taylorode_base_strings, only: format_real, fixed_length_real, format_integer
   use taylorode_base_files, only: text_file_type
   use taylorode_interfaces_legacy, only: legacy_solve, legacy_no_mass, jac_interface
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_positive_inf, ieee_is_finite
   use, intrinsic :: iso_c_binding, only: c_long_long, c_ptr, c_char, c_int, c_double, c_null_char, c_f_pointer, &
      c_associated
   !$ use omp_lib, only: omp_get_max_threads
   implicit none
   private

   public :: collect_robustness

   interface
      !> Heap allocations of this program so far (test/malloc_counter.c; -1 under ASan)
      function allocation_count() result(count) bind(c, name="taylorode_allocation_count")
         import :: c_long_long
         integer(c_long_long) :: count
      end function allocation_count
      !> LAPACK's band LU, called directly with an illegal argument
      subroutine dgbtrf(m, n, kl, ku, ab, ldab, ipiv, info)
         import :: dp
         integer, intent(in) :: m, n, kl, ku, ldab
         real(dp), intent(inout) :: ab(ldab, *)
         integer, intent(out) :: ipiv(*)
         integer, intent(out) :: info
      end subroutine dgbtrf
   end interface

   !> Problems whose non-stiff part is f = -u (Jacobians by differences)
   type, abstract, extends(ode_problem_fd) :: decay_base_type
   contains
      procedure :: f => decay_f
   end type decay_base_type

   !> u' = -u (f) - 2u (g) with a stiff part that is NaN for t > t_bad
   type, extends(decay_base_type) :: poisoned_after_type
      real(dp) :: t_bad = 1.0_dp
   contains
      procedure :: g => poisoned_after_g
   end type poisoned_after_type

   !> u' = -u + g with g = -10 u, whose evaluations are rejected at states with u < limit
   !> (a domain the true solution never leaves, but an overshooting iterate does)
   type, extends(decay_base_type) :: domain_type
      real(dp) :: limit = 0.3_dp
   contains
      procedure :: g => domain_g
   end type domain_type

   !> Linear decay whose declared Jacobian structure is set by the test
   type, extends(decay_base_type) :: declared_band_type
      integer :: lower = 0, upper = 0
   contains
      procedure :: g => coupled_g
      procedure :: jacobian_structure => declared_structure
   end type declared_band_type

   !> u' = -u (f) - 2u (g), dg/dU analytic with its entry (row, 1) replaced by `bad`
   !> (NaN or Inf) for t > t_bad (df/dU by differences); f and g stay finite. Dense, or
   !> band (1, 1)
   type, extends(decay_base_type) :: bad_jacobian_type
      integer :: row = 1
      real(dp) :: t_bad = 0.5_dp, bad = 0.0_dp
      logical :: band = .false.
   contains
      procedure :: g => bad_g
      procedure :: jac_g => bad_jac_g
      procedure :: jac_g_band => bad_jac_g_band
      procedure :: jacobian_structure => bad_structure
   end type bad_jacobian_type

   !> Van der Pol without Jacobians (forward differences), mu = 10
   type, extends(ode_problem_fd) :: vdp_differences_type
   contains
      procedure :: f => vdp_f
      procedure :: g => vdp_g
   end type vdp_differences_type

contains

   !> Collect all exported unit tests
   subroutine collect_robustness(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("no-shell-for-user-text", test_no_shell), &
         new_unittest("write-errors-reported", test_write_errors), &
         new_unittest("full-disk-leaves-files-intact", test_full_disk), &
         new_unittest("file-size-limit-is-a-status", test_file_size_limit), &
         new_unittest("outputs-checked-before-work", test_outputs_checked_first), &
         new_unittest("history-streamed-and-bounded", test_history_streamed), &
         new_unittest("file-that-appeared-kept-unless-replaced", test_file_appeared_kept), &
         new_unittest("history-into-a-named-pipe", test_history_into_pipe), &
         new_unittest("killed-run-leaves-no-temporary", test_killed_run), &
         new_unittest("history-reused", test_history_reused), &
         new_unittest("history-stream-never-left-behind", test_history_stream_completed), &
         new_unittest("concurrent-integrations", test_concurrent_integrations), &
         new_unittest("lapack-never-stops", test_lapack_never_stops), &
         new_unittest("bandwidths-validated", test_bandwidths_validated), &
         new_unittest("options-validated", test_options_validated), &
         new_unittest("pure-relative-tolerance", test_pure_relative), &
         new_unittest("tolerance-below-roundoff", test_tolerance_below_roundoff), &
         new_unittest("nonfinite-reported-as-such", test_nonfinite_reported), &
         new_unittest("nan-jacobian-is-nonfinite", test_nan_jacobian), &
         new_unittest("inf-jacobian-is-nonfinite", test_inf_jacobian), &
         new_unittest("no-allocation-per-step", test_no_allocation_per_step), &
         new_unittest("no-allocation-per-step-test-set", test_no_allocation_test_set), &
         new_unittest("evaluation-rejected", test_evaluation_rejected), &
         new_unittest("command-line-bounded", test_command_line_bounds), &
         new_unittest("numbers-parsed-strictly", test_strict_numbers), &
         new_unittest("options-cross-checked-first", test_options_cross_checked), &
         new_unittest("version-and-help", test_version_and_help), &
         new_unittest("test-driver-lists-suites", test_driver_lists), &
         new_unittest("no-executable-stack", test_no_executable_stack), &
         new_unittest("scheme-prepared-by-init-checked", test_scheme_prepared_checked), &
         new_unittest("c-options-checked", test_c_options_checked), &
         new_unittest("legacy-bandwidths-checked", test_legacy_bandwidths_checked), &
         new_unittest("command-line-mistakes-found-first", test_mistakes_found_first), &
         new_unittest("messages-legible-at-any-t", test_messages_legible) &
         ]
   end subroutine collect_robustness

   ! ------------------------------------------------------------ security, data

   !> (1) Text from the command line never reaches a shell: --out '$(touch ...)' names a
   !> directory, it does not run a command.
   subroutine test_no_shell(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call fresh_scratch()
      call run_command("cd "//scratch//" && "//app_path_from(scratch)//" stability --grid 3 --out '$(touch INJECTED)'", &
         run)
      call check(error, .not. file_exists(scratch//"/INJECTED"), "a shell ran text from the command line")
      if (allocated(error)) return
      call check(error, run%exit_status == 0 .and. file_exists(scratch//"/$(touch INJECTED)/s1_regions.csv"), &
         "the directory is created exactly as named")
   end subroutine test_no_shell

   !> The app's path seen from inside a directory of the build tree
   function app_path_from(directory) result(path)
      character(len=*), intent(in) :: directory
      character(len=:), allocatable :: path
      integer :: k, depth
      path = app_path()
      if (path(1:1) == "/") return
      depth = 1
      do k = 1, len(directory)
         if (directory(k:k) == "/") depth = depth + 1
      end do
      path = repeat("../", depth)//path
   end function app_path_from

   !> (2) Write errors are errors: a full device, a file-size limit mid-file, standard
   !> output on a full device; an existing file is never left truncated.
   subroutine test_write_errors(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: lines(:)
      type(step_history_type) :: history
      type(status_type) :: stat
      integer :: unit

      call fresh_scratch()
      call run_app("vdp --mu 10 --tend 2 --history /dev/full --force", run)
      call check(error, run%exit_status /= 0 .and. has_line(run%stderr, "cannot write"), &
         "history on a full device reported as written")
      if (allocated(error)) return
      call run_command(app_path()//" --version > /dev/full", run)
      call check(error, run%exit_status, 1, "standard output on a full device")
      if (allocated(error)) return

      ! the library's writer: a missing directory and a directory in place of the file
      call write_history_csv(history, scratch//"/missing/h.csv", stat)
      call check(error, stat%code, status_output_error, "write_history_csv into a missing directory")
      if (allocated(error)) return
      call write_history_csv(history, scratch//"/out", stat)
      call check(error, stat%code, status_output_error, "write_history_csv onto a directory")
   end subroutine test_write_errors

   !> (2) On a full file system (a 16 KiB tmpfs) a history that does not fit is an
   !> error, the file that was there is left as it was and no temporary file remains;
   !> the library's writer behaves the same. Skipped where mounting is not allowed.
   subroutine test_full_disk(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: disk = scratch//"/tiny"
      type(run_type) :: run
      type(line_type), allocatable :: lines(:)
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(step_history_type) :: history
      real(dp) :: u(2)
      integer :: unit

      call fresh_scratch()
      call run_command("mkdir -p "//disk//" && mount -t tmpfs -o size=16k tmpfs "//disk, run)
      if (run%exit_status /= 0) then
         call skip_test(error, "cannot mount a small tmpfs here (not root, or not allowed)")
         return
      end if
      open (newunit=unit, file=disk//"/h.csv", status="replace", action="write")
      write (unit, '(a)') "previous contents"
      close (unit)
      call run_app("vdp --mu 10 --tend 20 --history "//disk//"/h.csv --force", run)
      call check(error, run%exit_status /= 0 .and. has_line(run%stderr, "No space left"), &
         "a history that does not fit reported as written")
      if (.not. allocated(error)) then
         call read_lines(disk//"/h.csv", lines)
         call check(error, size(lines) == 1 .and. has_line(lines, "previous contents"), &
            "the existing file was overwritten by a partial one")
      end if
      if (.not. allocated(error)) then
         call run_command("ls "//disk//" | grep -c tmp || true", run)
         call check(error, has_line(run%stdout, "0"), "a temporary file was left behind")
      end if
      if (.not. allocated(error)) then
         problem = new_van_der_pol(10.0_dp)
         call new_scheme("i-t-2", scheme, stat)
         u = problem%u0
         call integrate(problem, scheme, 0.0_dp, 20.0_dp, u, integrator_options_type(), stats, stat, &
            history=history)
         call write_history_csv(history, disk//"/h.csv", stat)
         call check(error, stat%code, status_output_error, "write_history_csv on a full file system")
      end if
      call run_command("umount "//disk, run)
   end subroutine test_full_disk

   !> (2) Under a file-size limit (ulimit -f) the app does not die of SIGXFSZ: a history,
   !> a table or its report that outgrows the limit is an error (exit status 1, "File too
   !> large"), the file that was there is left as it was, no temporary file remains and
   !> no truncated file appears; the outputs that fit are written.
   subroutine test_file_size_limit(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: directory = scratch//"/out"
      type(run_type) :: run
      type(line_type), allocatable :: lines(:)
      integer :: unit

      call fresh_scratch()
      open (newunit=unit, file=directory//"/h.csv", status="replace", action="write")
      write (unit, '(a)') "previous contents"
      close (unit)
      ! the history (1.3 MB) against 8 KiB
      call run_command("( ulimit -f 8; exec "//app_path()//" vdp --mu 10 --tend 20 --history "//directory// &
         "/h.csv --force )", run)
      call check(error, run%exit_status == 1 .and. has_line(run%stderr, "File too large"), &
         "a history beyond the file-size limit: exit status "//format_real(real(run%exit_status, dp), 3))
      if (allocated(error)) return
      call read_lines(directory//"/h.csv", lines)
      call check(error, size(lines) == 1 .and. has_line(lines, "previous contents"), &
         "the existing history was overwritten")
      if (allocated(error)) return
      call expect_no_temporary("the history")
      if (allocated(error)) return
      ! the S1 regions table (0.5 MB) against 8 KiB; the two small tables are written
      call run_command("( ulimit -f 8; exec "//app_path()//" stability --grid 41 --out "//directory//" )", run)
      call check(error, run%exit_status == 1 .and. has_line(run%stderr, "File too large") .and. &
         .not. file_exists(directory//"/s1_regions.csv") .and. file_exists(directory//"/l_stability.csv"), &
         "a table beyond the file-size limit: exit status "//format_real(real(run%exit_status, dp), 3))
      if (allocated(error)) return
      call expect_no_temporary("the tables")
      if (allocated(error)) return
      ! the report itself (2.6 kB) redirected into a file against 1 KiB
      call run_command("( ulimit -f 1; exec "//app_path()//" stability --grid 3 > "//directory//"/report.txt )", run)
      call check(error, run%exit_status == 1 .and. has_line(run%stderr, "standard output: File too large"), &
         "a report beyond the file-size limit: exit status "//format_real(real(run%exit_status, dp), 3))
      if (allocated(error)) return
      ! the report and a table beyond it: both failures are reported (the table's was not)
      call run_command("( ulimit -f 1; exec "//app_path()//" stability --grid 41 --out "//directory// &
         "/both > "//directory//"/report.txt )", run)
      call check(error, run%exit_status == 1 .and. has_line(run%stderr, "s1_regions.csv") .and. &
         has_line(run%stderr, "standard output"), "a report and a table beyond the file-size limit: "// &
         "only one failure reported")

   contains

      subroutine expect_no_temporary(after)
         character(len=*), intent(in) :: after
         call check(error, .not. temporary_file_in(directory), "a temporary file is left after "//after)
      end subroutine expect_no_temporary
   end subroutine test_file_size_limit

   !> Whether a temporary file of the library's file writer (name.tmp-PID-N) is in directory.
   logical function temporary_file_in(directory)
      character(len=*), intent(in) :: directory
      type(run_type) :: listing
      call run_command("ls -a "//directory, listing)
      temporary_file_in = has_line(listing%stdout, ".tmp-")
   end function temporary_file_in

   !> (3) Every output target is checked before any work starts (exit status 2, nothing
   !> written, no run started).
   subroutine test_outputs_checked_first(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      integer :: unit
      call fresh_scratch()
      call run_app("stability --grid 3 --out "//scratch//"/missing/out", run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "not a writable directory"), &
         "--out below a missing directory")
      if (allocated(error)) return
      call run_app("vdp --mu 10 --tend 1 --history "//scratch//"/out", run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "is a directory"), "history onto a directory")
      if (allocated(error)) return
      call run_app('vdp --history ""', run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "needs a file name"), '--history ""')
      if (allocated(error)) return
      call run_app("vdp --mu 10 --tend 1 --history "//scratch//"/missing/h.csv", run)
      call check(error, run%exit_status == 2 .and. size(run%stdout) == 0, "history in a missing directory")
      if (allocated(error)) return
      ! one existing file among the three of stability: nothing is run, nothing written
      open (newunit=unit, file=scratch//"/out/l_stability.csv", status="replace", action="write")
      close (unit)
      call run_app("stability --grid 3 --out "//scratch//"/out", run)
      call check(error, run%exit_status == 2 .and. size(run%stdout) == 0 .and. &
         .not. file_exists(scratch//"/out/s1_regions.csv"), "an existing output found only after the run")
      if (allocated(error)) return
      call run_app("stability --grid 3 --out /proc/taylorode-test", run)
      call check(error, run%exit_status, 2, "an output directory that cannot be created")
   end subroutine test_outputs_checked_first

   !> A file opened not to replace (what the app does without --force, having found no
   !> file at the destination when it started) keeps a file that appeared there before the
   !> commit: status_output_error, the other file as it was, no temporary file left
   !> (rename(2) replaced it); with replace (the default) the new one takes its place.
   !> write_history_csv and stream_to pass the choice on. A file name of 250 bytes is
   !> written too (its temporary name is cut to NAME_MAX).
   subroutine test_file_appeared_kept(error)
      type(error_type), allocatable, intent(out) :: error
      type(text_file_type) :: file
      type(status_type) :: stat
      type(step_history_type) :: history
      type(line_type), allocatable :: lines(:)
      character(len=*), parameter :: name = "appeared.csv"
      integer :: unit

      call fresh_scratch()
      call file%open(scratch//"/out/"//name, stat, replace=.false.)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call file%write_line("new")
      open (newunit=unit, file=scratch//"/out/"//name, status="new", action="write")
      write (unit, '(a)') "user data"
      close (unit)
      call file%commit(stat)
      call read_lines(scratch//"/out/"//name, lines)
      call check(error, stat%code == status_output_error .and. index(stat_message(stat), "exists") > 0 .and. &
         size(lines) == 1, "commit without replace: "//stat_message(stat))
      if (allocated(error)) return
      call check(error, lines(1)%text, "user data")
      if (allocated(error)) return
      call check(error, count_files(scratch//"/out"), 1, "files left in the directory")
      if (allocated(error)) return
      ! the default replaces it
      stat = status_type()
      call file%open(scratch//"/out/"//name, stat)
      call file%write_line("new")
      call file%commit(stat)
      call read_lines(scratch//"/out/"//name, lines)
      call check(error, stat%code == status_ok .and. lines(1)%text == "new", "commit with replace: "// &
         stat_message(stat))
      if (allocated(error)) return
      stat = status_type()
      call write_history_csv(history, scratch//"/out/"//name, stat, replace=.false.)
      call check(error, stat%code, status_output_error, "write_history_csv without replace: "//stat_message(stat))
      if (allocated(error)) return
      ! a name of 250 bytes (its temporary name was 250 + ".tmp-PID-1", beyond NAME_MAX)
      stat = status_type()
      call write_history_csv(history, scratch//"/out/"//repeat("n", 246)//".csv", stat)
      call check(error, stat%code == status_ok .and. file_exists(scratch//"/out/"//repeat("n", 246)//".csv"), &
         "a file name of 250 bytes: "//stat_message(stat))
   contains
      !> Entries of a directory (ls -A | wc -l)
      integer function count_files(directory)
         character(len=*), intent(in) :: directory
         type(line_type), allocatable :: listing(:)
         call execute_command_line("ls -A "//directory//" > "//scratch//"/listing.txt")
         call read_lines(scratch//"/listing.txt", listing)
         count_files = size(listing)
      end function count_files
   end subroutine test_file_appeared_kept

   !> The app writes a history into a named pipe (--force: it exists) for a reader that
   !> is already there: its check of the outputs opened and closed the pipe to probe it,
   !> the reader took that for the end, and the real open waited for another reader for
   !> ever (timeout 30 s here: exit status 124; 2 of 3 runs before).
   subroutine test_history_into_pipe(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(line_type), allocatable :: lines(:)
      call fresh_scratch()
      call run_command("mkfifo "//scratch//"/out/pipe && { cat "//scratch//"/out/pipe > "//scratch// &
         "/out/read.csv & } && timeout 30 "//app_path()//" vdp --mu 1 --tend 1 --dense 2 --history "// &
         scratch//"/out/pipe --force; status=$?; wait; exit $status", run)
      call read_lines(scratch//"/out/read.csv", lines)
      call check(error, run%exit_status == 0 .and. size(lines) > 1, "exit status "// &
         format_integer(run%exit_status)//", "//format_integer(size(lines))//" lines through the pipe")
      if (allocated(error)) return
      call check(error, lines(1)%text(1:4), "step")
   end subroutine test_history_into_pipe

   !> A run ended by SIGINT or SIGTERM while it streams its history (timeout sends the
   !> signal after 1 s of a run that takes tens of seconds) leaves neither the history nor
   !> its temporary file (it left h.csv.tmp-PID-1, 34 MB after a second).
   subroutine test_killed_run(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: signals(2) = ["INT ", "TERM"]
      type(run_type) :: run
      integer :: k
      do k = 1, size(signals)
         call fresh_scratch()
         call run_command("timeout -s "//trim(signals(k))//" 1 "//app_path()//" vdp --mu 1000 --tend 3e6 "// &
            "--history "//scratch//"/out/h.csv", run)
         call check(error, run%exit_status == 124 .and. .not. temporary_file_in(scratch//"/out") .and. &
            .not. file_exists(scratch//"/out/h.csv"), "SIG"//trim(signals(k))//": exit status "// &
            format_integer(run%exit_status)//", a temporary file left: "// &
            merge("yes", "no ", temporary_file_in(scratch//"/out")))
         if (allocated(error)) return
      end do
   end subroutine test_killed_run

   !> (4) A streamed history holds nothing in memory and writes every attempt (the file is
   !> complete when integrate returns; write_history_csv refuses it, and writes nothing);
   !> a bounded one keeps at most its capacity and counts the rest.
   subroutine test_history_streamed(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(step_history_type) :: history
      type(line_type), allocatable :: lines(:)
      real(dp) :: u(2)
      logical :: exists

      call fresh_scratch()
      problem = new_van_der_pol(10.0_dp)
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp, history_states=.true.)
      call new_scheme("i-t-2", scheme, stat)
      call history%stream_to(scratch//"/out/stream.csv", stat)
      call check(error, stat%code, status_ok, "stream_to")
      if (allocated(error)) return
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, options, stats, stat, history=history)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call read_lines(scratch//"/out/stream.csv", lines)
      call check(error, .not. allocated(history%t) .and. size(lines) == history%count + 1 .and. &
         history%count == stats%accepted_steps + stats%rejected_steps(), "streamed rows")
      if (allocated(error)) return
      call check(error, lines(1)%text, "step,t,h,err,outcome,newton_iterations,u1,u2")
      if (allocated(error)) return
      ! its rows are in the file only: written again from memory it is refused (it read
      ! past the arrays before: SIGSEGV), and no file appears
      call write_history_csv(history, scratch//"/out/again.csv", stat)
      inquire (file=scratch//"/out/again.csv", exist=exists)
      call check(error, stat%code == status_invalid_argument .and. .not. exists, "write_history_csv of a "// &
         "streamed history: "//stat_message(stat))
      if (allocated(error)) return

      history = step_history_type(capacity=50)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, options, stats, stat, history=history)
      call check(error, history%count == 50 .and. size(history%t) <= 50 .and. &
         history%dropped == stats%accepted_steps + stats%rejected_steps() - 50, "bounded history")
   end subroutine test_history_streamed

   !> A streamed history is finished in every path, and no temporary file is left behind:
   !> integrate completes the file when it returns (after a failed integration too, and
   !> after a refused call, with the header alone; a file it cannot write is
   !> status_output_error, the integration's own failure kept in the message);
   !> continued calls (advance_to) write one
   !> file, which appears at finish; a history dropped unfinished removes its temporary
   !> file and leaves the destination as it was; a second stream_to drops the first.
   subroutine test_history_stream_completed(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: directory = scratch//"/out"
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(step_history_type) :: history
      type(integrator_type) :: integrator
      type(line_type), allocatable :: lines(:)
      real(dp) :: u(2)
      integer :: k

      call fresh_scratch()
      problem = new_van_der_pol(10.0_dp)
      call new_scheme("i-t-2", scheme, stat)
      ! a failed integration (the step budget) still gets its history
      call history%stream_to(directory//"/failed.csv", stat)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, integrator_options_type(max_steps=5_i8), stats, stat, &
         history=history)
      call read_lines(directory//"/failed.csv", lines)
      call check(error, stat%code == status_max_steps .and. size(lines) == 6, "history of a failed integration: "// &
         format_real(real(size(lines), dp), 2)//" lines")
      if (allocated(error)) return
      ! a history that cannot be written is the call's status, the integration's reason kept
      call history%stream_to("/dev/full", stat)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, integrator_options_type(max_steps=5_i8), stats, stat, &
         history=history)
      call check(error, stat%code == status_output_error .and. index(stat_message(stat), "No space left") > 0 &
         .and. index(stat_message(stat), "maximum number of steps") > 0, stat_message(stat))
      if (allocated(error)) return
      ! a refused call: the header alone
      call history%stream_to(directory//"/refused.csv", stat)
      call integrate(problem, scheme, 1.0_dp, 1.0_dp, u, integrator_options_type(), stats, stat, history=history)
      call read_lines(directory//"/refused.csv", lines)
      call check(error, stat%code == status_invalid_argument .and. size(lines) == 1, "history of a refused call")
      if (allocated(error)) return
      call expect_no_temporary("integrate")
      if (allocated(error)) return
      ! continued calls: one file, at finish
      call history%stream_to(directory//"/continued.csv", stat)
      u = problem%u0
      call integrator%init(problem, scheme, 0.0_dp, u, integrator_options_type(), stat)
      do k = 1, 3
         call integrator%advance_to(problem, scheme, real(k, dp), u, stat, history=history)
      end do
      call check(error, stat%code == status_ok .and. .not. file_exists(directory//"/continued.csv"), &
         "the stream of continued calls appeared before finish")
      if (allocated(error)) return
      call history%finish(stat)
      call read_lines(directory//"/continued.csv", lines)
      call check(error, stat%code == status_ok .and. size(lines) == history%count + 1 .and. &
         integrator%total%accepted_steps + integrator%total%rejected_steps() == history%count, &
         "one file for three continued calls")
      if (allocated(error)) return
      call expect_no_temporary("finish")
      if (allocated(error)) return
      ! dropped unfinished, and replaced by a second stream_to
      call abandon_stream()
      call check(error, .not. file_exists(directory//"/abandoned.csv"), "an unfinished stream appeared")
      if (allocated(error)) return
      call expect_no_temporary("a history dropped unfinished")
      if (allocated(error)) return
      call history%stream_to(directory//"/first.csv", stat)
      call history%stream_to(directory//"/second.csv", stat)
      u = problem%u0
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, stat, history=history)
      call check(error, file_exists(directory//"/second.csv") .and. .not. file_exists(directory//"/first.csv"), &
         "a second stream_to")
      if (allocated(error)) return
      call expect_no_temporary("a second stream_to")

   contains

      !> advance_to into a stream, and the history goes out of scope without finish
      subroutine abandon_stream()
         type(step_history_type) :: dropped
         type(integrator_type) :: continued
         call dropped%stream_to(directory//"/abandoned.csv", stat)
         u = problem%u0
         call continued%init(problem, scheme, 0.0_dp, u, integrator_options_type(), stat)
         call continued%advance_to(problem, scheme, 1.0_dp, u, stat, history=dropped)
      end subroutine abandon_stream

      subroutine expect_no_temporary(after)
         character(len=*), intent(in) :: after
         if (allocated(error)) return
         call check(error, .not. temporary_file_in(directory), "a temporary file is left after "//after)
      end subroutine expect_no_temporary
   end subroutine test_history_stream_completed

   !> (8) One history for several integrations: states off then on, 2 then 3 unknowns.
   subroutine test_history_reused(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      type(declared_band_type) :: three
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(step_history_type) :: history
      real(dp) :: u(2), v(3)

      problem = new_van_der_pol(10.0_dp)
      call new_scheme("i-t-2", scheme, stat)
      u = problem%u0
      options%history_states = .false.
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat, history=history)
      call check(error, stat%code == status_ok .and. .not. allocated(history%states), "first integration")
      if (allocated(error)) return
      u = problem%u0
      options%history_states = .true.
      call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat, history=history)
      call check(error, stat%code == status_ok .and. size(history%states, 1) == 2 .and. &
         history%count == stats%accepted_steps + stats%rejected_steps(), "states switched on")
      if (allocated(error)) return
      call check(error, all(history%states(:, history%count) == u), "last recorded state")
      if (allocated(error)) return
      v = [1.0_dp, 2.0_dp, 3.0_dp]
      call integrate(three, scheme, 0.0_dp, 1.0_dp, v, options, stats, stat, history=history)
      call check(error, stat%code == status_ok .and. size(history%states, 1) == 3 .and. &
         all(history%states(:, history%count) == v), "three unknowns after two")
   end subroutine test_history_reused

   ! ------------------------------------------------------------ library contract

   !> (5) Many integrations at once on separate objects, failing and succeeding ones,
   !> give exactly their serial results, messages included. Threads run when the tests
   !> are built with OpenMP (make test-threads); otherwise the loop runs serially.
   subroutine test_concurrent_integrations(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: members = 64
      real(dp) :: serial_u(2, members), parallel_u(2, members)
      integer :: serial_code(members), parallel_code(members)
      integer(i8) :: serial_steps(members), parallel_steps(members)
      character(len=200) :: serial_message(members), parallel_message(members)
      integer :: k

      do k = 1, members
         call run_member(k, serial_u(:, k), serial_code(k), serial_steps(k), serial_message(k))
      end do
      !$omp parallel do schedule(dynamic)
      do k = 1, members
         call run_member(k, parallel_u(:, k), parallel_code(k), parallel_steps(k), parallel_message(k))
      end do
      !$omp end parallel do
      !$ call check(error, omp_get_max_threads() > 1, "built with OpenMP but running on one thread")
      !$ if (allocated(error)) return
      call check(error, count(serial_code /= status_ok) >= members/4 .and. count(serial_code == status_ok) >= &
         members/4, "the members should mix failures and successes")
      if (allocated(error)) return
      do k = 1, members
         ! bit for bit (NaN included)
         call check(error, all(transfer(parallel_u(:, k), 0_i8, 2) == transfer(serial_u(:, k), 0_i8, 2)) .and. &
            parallel_code(k) == serial_code(k) .and. &
            parallel_steps(k) == serial_steps(k) .and. parallel_message(k) == serial_message(k), &
            "member differs from its serial run: "//trim(parallel_message(k)))
         if (allocated(error)) return
      end do
   end subroutine test_concurrent_integrations

   !> One ensemble member: Van der Pol with its own mu; every fourth member runs into
   !> NaN, every fourth into its step budget, every fourth into Newton failures.
   recursive subroutine run_member(k, u, code, steps, message)
      integer, intent(in) :: k
      real(dp), intent(out) :: u(2)
      integer, intent(out) :: code
      integer(i8), intent(out) :: steps
      character(len=*), intent(out) :: message
      type(van_der_pol_type) :: problem
      type(poisoned_after_type) :: poisoned
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: v(1)

      problem = new_van_der_pol(5.0_dp + real(k, dp))
      options = integrator_options_type(rtol=1.0e-5_dp, atol=1.0e-5_dp)
      call new_scheme(merge("i-t-2 ", "si-t-2", mod(k, 2) == 0), scheme, stat)
      u = problem%u0
      select case (mod(k, 4))
      case (0)
         call integrate(problem, scheme, 0.0_dp, 20.0_dp, u, options, stats, stat)
      case (1)
         poisoned%t_bad = 0.5_dp + 0.01_dp*k
         v = 1.0_dp
         call integrate(poisoned, scheme, 0.0_dp, 2.0_dp, v, options, stats, stat)
         u = [v(1), stats%t_reached]
      case (2)
         options%max_steps = 10 + k
         call integrate(problem, scheme, 0.0_dp, 20.0_dp, u, options, stats, stat)
      case default
         options%max_newton_iterations = 2
         options%max_failures = 2
         options%h0 = 0.5_dp
         problem%mu = 1.0e4_dp
         call integrate(problem, scheme, 0.0_dp, 20.0_dp, u, options, stats, stat)
      end select
      code = stat%code
      steps = stats%accepted_steps + stats%rejected_steps()
      message = ""
      if (allocated(stat%message)) message = stat%message
   end subroutine run_member

   !> (6) LAPACK never prints or stops: called with an illegal argument it returns a
   !> negative info (the library's xerbla), and the wrappers never pass one.
   subroutine test_lapack_never_stops(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: ab(4, 3)
      integer :: pivots(3), info
      ab = 1.0_dp
      call dgbtrf(3, 3, -1, 1, ab, 4, pivots, info)
      call check(error, info, -3, "dgbtrf with kl = -1 must return info = -3")
   end subroutine test_lapack_never_stops

   !> (7) Bandwidths are validated: a band wider than the matrix is dense storage (the
   !> same answer as dense), a negative bandwidth is an error.
   subroutine test_bandwidths_validated(error)
      type(error_type), allocatable, intent(out) :: error
      type(declared_band_type) :: wide, dense, negative
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u_wide(3), u_dense(3)
      character(len=*), parameter :: names(3) = [character(len=8) :: "si-t-2", "i-t-2", "ex-t-2"]
      integer :: k

      wide%lower = 5
      wide%upper = 5
      dense%lower = 2
      dense%upper = 2
      negative%lower = 1
      negative%upper = -2
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u_wide = [1.0_dp, 2.0_dp, 3.0_dp]
         call integrate(wide, scheme, 0.0_dp, 1.0_dp, u_wide, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//" with bandwidths 5, 5 and n = 3: "// &
            stat_message(stat))
         if (allocated(error)) return
         call new_scheme(trim(names(k)), scheme, stat)
         u_dense = [1.0_dp, 2.0_dp, 3.0_dp]
         call integrate(dense, scheme, 0.0_dp, 1.0_dp, u_dense, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//" with bandwidths 2, 2 and n = 3: "// &
            stat_message(stat))
         if (allocated(error)) return
         ! the same arithmetic up to the order of summation in the LU factorizations
         call check(error, maxval(abs(u_wide - u_dense)) <= 1.0e-9_dp, trim(names(k))//": wide band differs by "// &
            format_real(maxval(abs(u_wide - u_dense)), 3))
         if (allocated(error)) return
         call new_scheme(trim(names(k)), scheme, stat)
         u_dense = [1.0_dp, 2.0_dp, 3.0_dp]
         call integrate(negative, scheme, 0.0_dp, 1.0_dp, u_dense, options, stats, stat)
         call check(error, stat%code, status_invalid_argument, trim(names(k))//" with a negative bandwidth")
         if (allocated(error)) return
      end do
   end subroutine test_bandwidths_validated

   !> (9) Options that cannot mean anything are rejected: infinite tolerances, an
   !> infinite q, NaN kappa, one Newton iteration.
   subroutine test_options_validated(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp) :: inf, nan
      inf = ieee_value(1.0_dp, ieee_positive_inf)
      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      call expect_invalid(integrator_options_type(rtol=inf), "rtol")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(atol=inf), "atol")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(atol_vector=[1.0e-6_dp, inf]), "atol_vector")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(q=inf), "q")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(q=0.5_dp), "q")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(kappa=nan), "kappa")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(h_max=inf), "h_max")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(max_growth=inf), "max_growth")
      if (allocated(error)) return
      call expect_invalid(integrator_options_type(max_newton_iterations=-1), "max_newton_iterations")
   contains
      subroutine expect_invalid(options, word)
         type(integrator_options_type), intent(in) :: options
         character(len=*), intent(in) :: word
         type(van_der_pol_type) :: problem
         class(scheme_type), allocatable :: scheme
         type(integration_stats_type) :: stats
         type(status_type) :: stat
         real(dp) :: u(2)
         problem = new_van_der_pol(10.0_dp)
         call new_scheme("i-t-2", scheme, stat)
         u = problem%u0
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, options, stats, stat)
         call check(error, stat%code == status_invalid_argument .and. index(stat_message(stat), word) > 0, &
            "option "//word//" accepted: "//stat_message(stat))
      end subroutine expect_invalid
   end subroutine test_options_validated

   !> (9) Pure relative control (atol = 0) works, also with a component that starts at zero.
   subroutine test_pure_relative(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(4) = [character(len=9) :: "si-t-2", "i-t-2", "imex-rk21", "radau5"]
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2), reference(2)
      integer :: k
      problem = new_van_der_pol(10.0_dp)
      call new_scheme("radau5", scheme, stat)
      reference = [2.0_dp, 0.0_dp]
      call integrate(problem, scheme, 0.0_dp, 5.0_dp, reference, integrator_options_type(rtol=1.0e-12_dp, &
         atol=1.0e-12_dp), stats, stat)
      options = integrator_options_type(rtol=1.0e-6_dp, atol=0.0_dp)
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u = [2.0_dp, 0.0_dp]
         call integrate(problem, scheme, 0.0_dp, 5.0_dp, u, options, stats, stat)
         call check(error, stat%code, status_ok, trim(names(k))//" with atol = 0: "//stat_message(stat))
         if (allocated(error)) return
         ! a relative tolerance of 1e-6 buys a relative accuracy well below 1e-2 here
         call check(error, maxval(abs(u - reference))/maxval(abs(reference)) < 1.0e-2_dp, &
            trim(names(k))//" with atol = 0: inaccurate")
         if (allocated(error)) return
      end do
   end subroutine test_pure_relative

   !> (9) A tolerance below roundoff is raised to what double precision resolves, and
   !> the statistics say so: radau5 weighs at the start of a step, i-t-2 at both ends
   !> (with vector tolerances through the general weights, with scalar ones in one pass;
   !> h0 given, so that the first step size's estimate, which weighs too, is not made).
   subroutine test_tolerance_below_roundoff(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = [character(len=6) :: "radau5", "i-t-2"]
      real(dp), parameter :: t_end(2) = [1.0_dp, 0.01_dp]
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(integrator_options_type) :: options
      real(dp) :: u(2)
      integer :: k, vectors
      problem = new_van_der_pol(1.0_dp)
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         do vectors = 0, 1
            options = integrator_options_type(rtol=1.0e-16_dp, atol=1.0e-16_dp, h0=1.0e-4_dp)
            if (vectors == 1) options%atol_vector = [1.0e-16_dp, 1.0e-16_dp]
            u = problem%u0
            call integrate(problem, scheme, 0.0_dp, t_end(k), u, options, stats, stat)
            call check(error, stat%code == status_ok .and. stats%weights_raised, trim(names(k))// &
               ": 1e-16 not raised: "//stat_message(stat))
            if (allocated(error)) return
            options = integrator_options_type(rtol=1.0e-8_dp, atol=1.0e-8_dp, h0=1.0e-4_dp)
            if (vectors == 1) options%atol_vector = [1.0e-8_dp, 1.0e-8_dp]
            u = problem%u0
            call integrate(problem, scheme, 0.0_dp, t_end(k), u, options, stats, stat)
            call check(error, stat%code == status_ok .and. .not. stats%weights_raised, trim(names(k))// &
               ": 1e-8 must not be raised")
            if (allocated(error)) return
         end do
      end do
   end subroutine test_tolerance_below_roundoff

   !> (10) A stiff part that turns NaN is reported as non-finite (not as a step-size
   !> underflow after creeping up to the NaN point), by every implicit scheme.
   subroutine test_nonfinite_reported(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(5) = [character(len=10) :: "si-t-1", "si-t-2", "i-t-2", "imex-rk21", &
         "radau5"]
      type(poisoned_after_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)
      integer :: k
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u = 1.0_dp
         call integrate(problem, scheme, 0.0_dp, 2.0_dp, u, integrator_options_type(), stats, stat)
         call check(error, stat%code, status_nonfinite, trim(names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%t_reached <= problem%t_bad .and. stats%t_reached > 0.9_dp*problem%t_bad .and. &
            stats%rejected_nonfinite > 0, trim(names(k))//": stopped at the wrong place or without counting")
         if (allocated(error)) return
      end do
   end subroutine test_nonfinite_reported

   !> A Jacobian that is NaN at some state is status_nonfinite, not a Newton failure.
   subroutine test_nan_jacobian(error)
      type(error_type), allocatable, intent(out) :: error
      call check_bad_jacobian(error, ieee_value(1.0_dp, ieee_quiet_nan), "NaN")
   end subroutine test_nan_jacobian

   !> A Jacobian that is Inf at some state is status_nonfinite, not a Newton failure.
   subroutine test_inf_jacobian(error)
      type(error_type), allocatable, intent(out) :: error
      call check_bad_jacobian(error, ieee_value(1.0_dp, ieee_positive_inf), "Inf")
   end subroutine test_inf_jacobian

   !> Every implicit scheme on u' = -3u whose dg/dU has a `bad` entry for t > 0.5 (f
   !> and g finite; Newton matrices made afresh at each solve, so that each scheme
   !> evaluates the Jacobian there): status_nonfinite with a message that names the
   !> Jacobian, the last good state (the exact solution at stats%t_reached, which lies
   !> near 0.5) and its statistics. Through each linear solver: n = 1 (the written-out
   !> small LU), n = 30 dense (LAPACK; the entry below the diagonal, where only L holds
   !> it), n = 30 band (the written-out band LU, the entry below the diagonal too).
   !> Before: status_newton_diverged (with Inf, si-t-1 even accepted its steps: a pivot
   !> of -Inf made every increment 0).
   subroutine check_bad_jacobian(error, bad, word)
      type(error_type), allocatable, intent(out) :: error
      real(dp), intent(in) :: bad
      character(len=*), intent(in) :: word
      character(len=*), parameter :: names(6) = [character(len=10) :: "si-t-1", "si-t-2", "i-t-1", "i-t-2", &
         "imex-rk21", "radau5"]
      character(len=*), parameter :: solvers(3) = [character(len=12) :: "small LU", "dense LAPACK", "band LU"]
      type(bad_jacobian_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:)
      character(len=:), allocatable :: label
      integer :: k, solver
      problem%bad = bad
      do solver = 1, size(solvers)
         select case (solver)
         case (1)
            u = [1.0_dp]
            problem%row = 1
            problem%band = .false.
         case (2)
            u = [(1.0_dp, k=1, 30)]
            problem%row = 30
            problem%band = .false.
         case default
            u = [(1.0_dp, k=1, 30)]
            problem%row = 2
            problem%band = .true.
         end select
         do k = 1, size(names)
            label = word//" Jacobian, "//trim(names(k))//", "//trim(solvers(solver))
            call new_scheme(trim(names(k)), scheme, stat)
            u = 1.0_dp
            ! (matrices not kept: radau5 would keep its Jacobian from before t_bad throughout)
            call integrate(problem, scheme, 0.0_dp, 2.0_dp, u, integrator_options_type(reuse_newton_matrix=.false.), &
               stats, stat)
            call check(error, stat%code, status_nonfinite, label//": "//stat_message(stat))
            if (allocated(error)) return
            call check(error, index(stat_message(stat), "Jacobian") > 0, label//": "//stat_message(stat))
            if (allocated(error)) return
            call check(error, stats%t_reached > 0.3_dp .and. stats%t_reached < 0.8_dp .and. &
               stats%rejected_nonfinite > 0 .and. stats%accepted_steps > 0, label//": stopped at t = "// &
               format_integer(nint(1000*stats%t_reached))//"/1000 or without counting")
            if (allocated(error)) return
            call check(error, all(abs(u - exp(-3.0_dp*stats%t_reached)) <= 1.0e-4_dp), label// &
               ": not the last good state")
            if (allocated(error)) return
         end do
      end do
   end subroutine check_bad_jacobian

   !> (11) The heap allocations of an integration do not grow with its number of steps:
   !> every scheme, finite-difference Jacobians (dense and grouped band, also of a state
   !> that is not contiguous, which the differences must not copy), radau5 with a mass
   !> matrix (band, and dense: its products over the rows that hold entries), the
   !> amplifier's and MEDAKZO's Jacobians asked for dense (a local band of size(u) per
   !> call before), every scheme with dense output at 200 times (the implicit Taylor
   !> schemes' interpolant through the last states allocated at every step before) and
   !> failed attempts included (the test set as it comes: the next test). Compared: [0, 3] against [0, 30] (far more steps; the amplifier [0, 0.001]
   !> against [0, 0.05], the others as noted).
   subroutine test_no_allocation_per_step(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(7) = [character(len=12) :: "ex-t-2", "si-t-1", "si-t-2", &
         "i-t-1", "i-t-2", "imex-rk21", "radau5"]
      type(van_der_pol_type) :: problem
      type(vdp_differences_type) :: differences
      type(differenced_brusselator) :: band
      type(transistor_amplifier_type) :: amplifier
      type(dense_amplifier_type) :: dense_amplifier
      type(dense_akzo_type) :: dense_akzo
      type(integrator_options_type) :: options
      integer :: k

      if (allocation_count() < 0) then
         call skip_test(error, "allocations are not counted under AddressSanitizer")
         return
      end if
      problem = new_van_der_pol(10.0_dp)
      options = integrator_options_type(rtol=1.0e-6_dp, atol=1.0e-6_dp)
      do k = 1, size(names)
         call compare_runs(problem, trim(names(k)), options, 3.0_dp, 30.0_dp, trim(names(k)))
         if (allocated(error)) return
         call compare_runs(problem, trim(names(k)), options, 3.0_dp, 30.0_dp, trim(names(k))//", dense output", &
            dense_output=.true.)
         if (allocated(error)) return
      end do
      call compare_runs(differences, "i-t-2", options, 3.0_dp, 30.0_dp, "dense differences")
      if (allocated(error)) return
      ! a state that is every other entry of an array: the differences must not copy it
      call compare_runs(differences, "radau5", options, 3.0_dp, 30.0_dp, "dense differences from F, strided state", &
         strided=.true.)
      if (allocated(error)) return
      call compare_runs(differences, "i-t-2", options, 3.0_dp, 30.0_dp, "dense differences, strided state", &
         strided=.true.)
      if (allocated(error)) return
      band%model = new_brusselator(20)
      call compare_runs(band, "si-t-2", options, 0.02_dp, 2.0_dp, "grouped band differences")
      if (allocated(error)) return
      call compare_runs(band, "radau5", options, 0.02_dp, 2.0_dp, "grouped band differences from F, strided state", &
         strided=.true.)
      if (allocated(error)) return
      call compare_runs(band, "i-t-2", options, 0.02_dp, 2.0_dp, "grouped band differences, strided state", &
         strided=.true.)
      if (allocated(error)) return
      amplifier = new_transistor_amplifier()
      call compare_runs(amplifier, "radau5", options, 0.001_dp, 0.05_dp, "band mass matrix")
      if (allocated(error)) return
      dense_amplifier%transistor_amplifier_type = amplifier
      call compare_runs(dense_amplifier, "radau5", options, 0.001_dp, 0.05_dp, "dense mass matrix")
      if (allocated(error)) return
      dense_akzo%medical_akzo_type = new_medical_akzo(10)
      call compare_runs(dense_akzo, "radau5", options, 0.1_dp, 10.0_dp, "MEDAKZO, dense")
      if (allocated(error)) return
      options%max_newton_iterations = 2
      call compare_runs(problem, "i-t-2", options, 3.0_dp, 30.0_dp, "failed attempts", failures=.true.)
      if (allocated(error)) return
      call compare_legacy_runs(1, "TAYLORODE")
      if (allocated(error)) return
      call compare_legacy_runs(0, "TAYLORODE without JAC")
   contains
      !> TAYLORODE('radau5') with the user's JAC (ijac = 1) or differences of FCN (0): a
      !> call allocates what its setup needs, the same for 10 times the steps (the first
      !> call is the warm-up).
      subroutine compare_legacy_runs(ijac, label)
         integer, intent(in) :: ijac
         character(len=*), intent(in) :: label
         integer(c_long_long) :: short_run, long_run
         integer :: iwork(20), idid, short_steps
         call radau5_van_der_pol(3.0_dp, legacy_vdp_jacobian, ijac, 2, 0, iwork, idid, short_run)
         call check(error, idid, 1, label//" to 3 (warm-up)")
         if (allocated(error)) return
         call radau5_van_der_pol(3.0_dp, legacy_vdp_jacobian, ijac, 2, 0, iwork, idid, short_run)
         short_steps = iwork(16)
         call check(error, idid, 1, label//" to 3")
         if (allocated(error)) return
         call radau5_van_der_pol(30.0_dp, legacy_vdp_jacobian, ijac, 2, 0, iwork, idid, long_run)
         call check(error, idid, 1, label//" to 30")
         if (allocated(error)) return
         call check(error, iwork(16) > 5*short_steps, label//": runs too alike")
         if (allocated(error)) return
         call check(error, int(long_run), int(short_run), label//": allocations grow with the steps")
      end subroutine compare_legacy_runs
      !> With `strided`, the state is every other entry of an array of twice its size; with
      !> `dense_output`, the solution is asked for at 200 times spread over the span.
      subroutine compare_runs(model, name, options, short_end, long_end, label, failures, strided, dense_output)
         class(ode_problem), intent(inout) :: model
         character(len=*), intent(in) :: name, label
         type(integrator_options_type), intent(in) :: options
         real(dp), intent(in) :: short_end, long_end
         logical, intent(in), optional :: failures, strided, dense_output
         class(scheme_type), allocatable :: scheme
         type(integration_stats_type) :: short_stats, long_stats, stats(3)
         type(status_type) :: stat
         real(dp), allocatable :: u0(:), u(:), storage(:)
         real(dp) :: ends(3), t_out(200)
         real(dp), allocatable :: u_out(:, :)
         integer(c_long_long) :: before, short_run, long_run, runs(3)
         integer :: k, i
         logical :: every_other, outputs
         select type (model)
         type is (differenced_brusselator)
            u0 = model%model%u0
         type is (van_der_pol_type)
            u0 = [2.0_dp, 0.0_dp]
         class is (test_problem_type)
            u0 = model%u0
         class default
            u0 = [2.0_dp, 0.0_dp]
         end select
         every_other = .false.
         if (present(strided)) every_other = strided
         outputs = .false.
         if (present(dense_output)) outputs = dense_output
         allocate (u_out(size(u0), size(t_out)))
         call new_scheme(name, scheme, stat)
         allocate (storage(2*size(u0)))
         u = u0
         ! the first integration sizes the scheme's work arrays
         ends = [0.1_dp*short_end, short_end, long_end]
         do k = 1, 3
            u = u0
            storage(1::2) = u0
            t_out = [(ends(k)*i/real(size(t_out), dp), i=1, size(t_out))]
            before = allocation_count()
            if (outputs) then
               call integrate(model, scheme, 0.0_dp, ends(k), u, options, stats(k), stat, t_out=t_out, u_out=u_out)
            else if (every_other) then
               call integrate(model, scheme, 0.0_dp, ends(k), storage(1::2), options, stats(k), stat)
            else
               call integrate(model, scheme, 0.0_dp, ends(k), u, options, stats(k), stat)
            end if
            runs(k) = allocation_count() - before
         end do
         short_stats = stats(2)
         long_stats = stats(3)
         short_run = runs(2)
         long_run = runs(3)
         call check(error, stat%code, status_ok, label//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, long_stats%accepted_steps > 5*short_stats%accepted_steps, label//": runs too alike")
         if (allocated(error)) return
         if (present(failures)) then
            call check(error, long_stats%rejected_newton > short_stats%rejected_newton, label//": no failed attempts")
            if (allocated(error)) return
         end if
         call check(error, int(long_run), int(short_run), label//": allocations grow with the steps")
      end subroutine compare_runs
   end subroutine test_no_allocation_per_step

   !> (11b) Every problem of the test set through radau5, i-t-2 and si-t-2 (where it
   !> accepts the problem: the amplifier's mass matrix is radau5's alone) with its own
   !> tolerances: the heap allocations of an integration to a tenth of its span (at most
   !> t = 1000) equal those to a hundredth, which takes fewer steps (the problems' own
   !> evaluations and Jacobians included: POLLU's F allocated at every call before).
   subroutine test_no_allocation_test_set(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(3) = [character(len=6) :: "radau5", "i-t-2", "si-t-2"]
      class(test_problem_type), allocatable :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:)
      real(dp) :: span
      integer(c_long_long) :: before, runs(3)
      integer :: i, j, k, steps(3)
      character(len=:), allocatable :: label

      if (allocation_count() < 0) then
         call skip_test(error, "allocations are not counted under AddressSanitizer")
         return
      end if
      do i = 1, size(test_problem_names)
         do j = 1, size(names)
            label = trim(test_problem_names(i))//", "//trim(names(j))
            call new_test_problem(test_problem_names(i), problem, stat)
            call new_scheme(trim(names(j)), scheme, stat)
            span = min(problem%t_end, 1000.0_dp)
            ! (the first integration sizes the scheme's work arrays)
            do k = 1, 3
               u = problem%u0
               before = allocation_count()
               call integrate(problem, scheme, 0.0_dp, span/10.0_dp**(4 - k), u, &
                  integrator_options_type(rtol=problem%rtol, atol=problem%atol), stats, stat)
               runs(k) = allocation_count() - before
               steps(k) = int(stats%accepted_steps)
            end do
            if (problem%has_mass .and. names(j) /= "radau5") cycle
            call check(error, stat%code, status_ok, label//": "//stat_message(stat))
            if (allocated(error)) return
            call check(error, steps(3) > steps(2), label//": runs too alike")
            if (allocated(error)) return
            call check(error, int(runs(3)), int(runs(2)), label//": allocations grow with the steps")
            if (allocated(error)) return
         end do
      end do
   end subroutine test_no_allocation_test_set

   !> (12) A problem can say "I can't evaluate here": an overshooting Newton iterate is
   !> rejected and the step retried (the integration succeeds); a solution that must
   !> leave the domain ends with status_evaluation_failed.
   subroutine test_evaluation_rejected(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(4) = [character(len=9) :: "si-t-2", "i-t-2", "imex-rk21", "radau5"]
      type(domain_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(1)
      integer :: k
      do k = 1, size(names)
         call new_scheme(trim(names(k)), scheme, stat)
         u = 1.0_dp
         problem%limit = 0.3_dp
         ! the true solution exp(-11 t) stays above 0.33 on [0, 0.1]; a first step of 1 does not
         call integrate(problem, scheme, 0.0_dp, 0.1_dp, u, integrator_options_type(h0=0.1_dp, rtol=1.0e-6_dp, &
            atol=1.0e-8_dp, h_max=0.1_dp), stats, stat)
         call check(error, stat%code == status_ok .and. abs(u(1) - exp(-1.1_dp)) < 1.0e-4_dp, &
            trim(names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         u = 1.0_dp
         problem%limit = 0.5_dp
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, stat)
         call check(error, stat%code, status_evaluation_failed, trim(names(k))//" leaving the domain: "// &
            stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%rejected_evaluation > 0 .and. u(1) >= 0.5_dp, trim(names(k))//": last state")
         if (allocated(error)) return
      end do
   end subroutine test_evaluation_rejected

   ! ------------------------------------------------------------ command line

   !> (13) Every count has an upper bound, and vdp has a step budget.
   subroutine test_command_line_bounds(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call expect_status("vdp --dense 2147483647", 2, "at most")
      if (allocated(error)) return
      call expect_status("table --repeats 1000000", 2, "at most")
      if (allocated(error)) return
      call expect_status("stability --grid 100000", 2, "at most")
      if (allocated(error)) return
      call expect_status("bench --min-time 999999", 2, "at most")
      if (allocated(error)) return
      call expect_status("sweep --budget 99999999999999", 2, "at most")
      if (allocated(error)) return
      call expect_status("sweep --tols 1e-1:1e-30", 2, "decades")
      if (allocated(error)) return
      call run_app("vdp --tend 1e300 --budget 2000", run)
      call check(error, run%exit_status == 1 .and. has_line(run%stdout, "maximum steps reached"), &
         "vdp --tend 1e300 must stop at its budget")
   contains
      subroutine expect_status(arguments, expected, words)
         character(len=*), intent(in) :: arguments, words
         integer, intent(in) :: expected
         call run_app(arguments, run)
         call check(error, run%exit_status == expected .and. has_line(run%stderr, words), &
            "taylorode "//arguments)
      end subroutine expect_status
   end subroutine test_command_line_bounds

   !> (14) Numbers are parsed strictly: "1-2" is not 1e-2 and "1+2" not 100, "5 " no number;
   !> arguments keep their trailing blanks.
   subroutine test_strict_numbers(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      character(len=*), parameter :: bad(6) = [character(len=6) :: "1-2", "1+2", "1e", ".", "1.2.3", "0x10"]
      integer :: k
      do k = 1, size(bad)
         call run_app("vdp --mu "//trim(bad(k)), run)
         call check(error, run%exit_status == 2 .and. has_line(run%stderr, "needs a number"), &
            "--mu "//trim(bad(k))//" accepted")
         if (allocated(error)) return
      end do
      call run_app("vdp --mu 1.5e+1 --tend 1 --dense 2", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "mu = 15,"), "--mu 1.5e+1")
      if (allocated(error)) return
      ! an argument is taken as given, blanks at its end too: "5 " is no number (as " 5"
      ! is not), and a file name keeps them (both were cut off)
      call run_app('vdp --mu "5 " --tend 1 --dense 2', run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "needs a number"), '--mu "5 " accepted')
      if (allocated(error)) return
      call fresh_scratch()
      call run_app('vdp --mu 5 --tend 1 --dense 2 --history "'//scratch//'/out/h.csv "', run)
      call check(error, run%exit_status == 0 .and. .not. file_exists(scratch//"/out/h.csv"), &
         '--history "h.csv ": written as h.csv')
      if (allocated(error)) return
      ! (Fortran's inquire drops the blank: the shell looks)
      call run_command('test -s "'//scratch//'/out/h.csv "', run)
      call check(error, run%exit_status, 0, '--history "h.csv ": no file "h.csv "')
   end subroutine test_strict_numbers

   !> (15) Options are cross-checked before any work (no reference run first).
   subroutine test_options_cross_checked(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call run_app("vdp --h0 1 --hmax 0.1", run)
      call check(error, run%exit_status == 2 .and. has_line(run%stderr, "h0 must lie in") .and. &
         size(run%stdout) == 0 .and. .not. has_line(run%stderr, "reference"), "h0 > hmax found after the run")
   end subroutine test_options_cross_checked

   !> (16) --version and help are known.
   subroutine test_version_and_help(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call run_app("--version", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "taylorode 0."), "--version")
      if (allocated(error)) return
      call run_app("help", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "usage: taylorode"), "help")
      if (allocated(error)) return
      call run_app("help sweep", run)
      call check(error, run%exit_status == 0 .and. has_line(run%stdout, "taylorode sweep:"), "help sweep")
   end subroutine test_version_and_help

   !> (16) The test driver, asked for a suite it does not have, lists the suites and
   !> ends without a backtrace.
   subroutine test_driver_lists(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      character(len=4096) :: self
      call get_command_argument(0, self)
      call run_command(trim(self)//" nosuch", run)
      call check(error, run%exit_status /= 0 .and. has_line(run%stderr, "robustness") .and. &
         .not. has_line(run%stderr, "Backtrace"), "unknown suite")
      if (allocated(error)) return
      call run_command(trim(self)//" base nosuch", run)
      call check(error, run%exit_status /= 0 .and. has_line(run%stderr, "number-formats"), "unknown test")
   end subroutine test_driver_lists

   !> (17) The app binary does not need an executable stack.
   subroutine test_no_executable_stack(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call run_command("command -v readelf", run)
      if (run%exit_status /= 0) then
         call skip_test(error, "readelf (binutils) is not installed")
         return
      end if
      call run_command("readelf -lW "//app_path()//" | grep GNU_STACK", run)
      call check(error, run%exit_status == 0 .and. size(run%stdout) == 1, "no GNU_STACK header")
      if (allocated(error)) return
      call check(error, index(run%stdout(1)%text, "RWE") == 0, "executable stack: "//run%stdout(1)%text)
   end subroutine test_no_executable_stack

   ! ------------------------------------------------------------ problems

   subroutine decay_f(self, t, u, dudt)
      class(decay_base_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -u
   end subroutine decay_f

   subroutine poisoned_after_g(self, t, u, dudt)
      class(poisoned_after_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      if (t > self%t_bad) then
         dudt = ieee_value(1.0_dp, ieee_quiet_nan)
      else
         dudt = -2.0_dp*u
      end if
   end subroutine poisoned_after_g

   subroutine domain_g(self, t, u, dudt)
      class(domain_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      if (u(1) < self%limit) call self%reject_evaluation()
      dudt = -10.0_dp*u
   end subroutine domain_g

   subroutine coupled_g(self, t, u, dudt)
      class(declared_band_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      integer :: i
      do i = 1, size(u)
         dudt(i) = -10.0_dp*u(i)
         if (i > 1) dudt(i) = dudt(i) + u(i - 1)
      end do
   end subroutine coupled_g

   function declared_structure(self, n) result(structure)
      class(declared_band_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = band_structure(self%lower, self%upper)
   end function declared_structure

   subroutine vdp_f(self, t, u, dudt)
      class(vdp_differences_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = [u(2), -u(1)]
   end subroutine vdp_f

   subroutine vdp_g(self, t, u, dudt)
      class(vdp_differences_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = [0.0_dp, 10.0_dp*(1.0_dp - u(1)**2)*u(2)]
   end subroutine vdp_g


   ! ------------------------------------------------------------ second campaign

   !> advance_to with another object of the scheme init prepared (or the same one
   !> prepared since for another size, or for a problem whose `autonomous` has changed
   !> since: the schemes keep dF/dt's work arrays only for a problem that depends on t)
   !> is an error, not a crash in unprepared work arrays.
   subroutine test_scheme_prepared_checked(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      type(poisoned_after_type) :: decay
      class(scheme_type), allocatable :: scheme, fresh
      type(integrator_type) :: integrator
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2), wider(4)
      problem = new_van_der_pol(10.0_dp)
      u = problem%u0
      call new_scheme("radau5", scheme, stat)
      call integrator%init(problem, scheme, 0.0_dp, u, integrator_options_type(), stat)
      call check(error, stat%code == status_ok, stat_message(stat))
      if (allocated(error)) return
      call new_scheme("radau5", fresh, stat)
      call integrator%advance_to(problem, fresh, 1.0_dp, u, stat)
      call check(error, stat%code == status_invalid_argument, "a fresh scheme: "//stat_message(stat))
      if (allocated(error)) return
      wider = 1.0_dp
      call integrate(decay, scheme, 0.0_dp, 0.01_dp, wider, integrator_options_type(), &
         stats, stat)
      call integrator%advance_to(problem, scheme, 1.0_dp, u, stat)
      call check(error, stat%code == status_invalid_argument, "a scheme prepared since for 4 unknowns: "// &
         stat_message(stat))
      if (allocated(error)) return
      call new_scheme("si-t-2", scheme, stat)
      u = problem%u0
      call integrator%init(problem, scheme, 0.0_dp, u, integrator_options_type(), stat)
      call check(error, stat%code == status_ok .and. problem%autonomous, "si-t-2: "//stat_message(stat))
      if (allocated(error)) return
      problem%autonomous = .false.
      call integrator%advance_to(problem, scheme, 1.0_dp, u, stat)
      call check(error, stat%code == status_invalid_argument .and. index(stat_message(stat), "autonomous") > 0, &
         "problem%autonomous changed since init: "//stat_message(stat))
      if (allocated(error)) return
      problem%autonomous = .true.
      call integrator%advance_to(problem, scheme, 1.0_dp, u, stat)
      call check(error, stat%code == status_ok, "problem%autonomous as at init again: "//stat_message(stat))
   end subroutine test_scheme_prepared_checked

   !> The C interface checks whole-number options and bandwidths itself (no float to
   !> integer conversion out of range, no allocation of a band wider than the matrix)
   !> and every failing call leaves a message.
   subroutine test_c_options_checked(error)
      type(error_type), allocatable, intent(out) :: error
      type(c_ptr) :: ode
      integer(c_int) :: status
      real(dp) :: nan
      nan = ieee_value(1.0_dp, ieee_quiet_nan)
      ode = c_create("i-t-2"//c_null_char, 2_c_int, status)
      call check(error, status == status_ok .and. c_associated(ode), "taylorode_create")
      if (allocated(error)) return
      call expect_invalid(c_set_option(ode, "controller"//c_null_char, nan), "controller NaN")
      call expect_invalid(c_set_option(ode, "norm"//c_null_char, 1.0e300_dp), "norm 1e300")
      call expect_invalid(c_set_option(ode, "max_steps"//c_null_char, 1.0e30_dp), "max_steps 1e30")
      call expect_invalid(c_set_option(ode, "max_newton_iterations"//c_null_char, 2.5_dp), "2.5 iterations")
      call expect_invalid(c_set_option(ode, "no_such_option"//c_null_char, 1.0_dp), "an unknown option")
      call expect_invalid(c_set_option(ode, "measure_time"//c_null_char, 2.0_dp), "measure_time 2")
      call expect_invalid(c_set_bandwidths(ode, 2000000000_c_int, 2000000000_c_int), "bandwidths 2e9")
      call expect_invalid(c_set_bandwidths(ode, 0_c_int, 2_c_int), "upper bandwidth n")
      if (allocated(error)) return
      status = c_set_option(ode, "controller"//c_null_char, 1.0_dp)
      call check(error, status == status_ok .and. len(message_of(ode)) == 0, "controller 1 and its message cleared")
      if (allocated(error)) return
      status = c_set_option(ode, "measure_time"//c_null_char, 0.0_dp)
      call check(error, status == status_ok, "measure_time 0: "//message_of(ode))
      call c_free(ode)
   contains
      subroutine expect_invalid(code, what)
         integer(c_int), value :: code
         character(len=*), intent(in) :: what
         if (allocated(error)) return
         call check(error, code == status_invalid_argument .and. len(message_of(ode)) > 0, what//": "// &
            message_of(ode))
      end subroutine expect_invalid
   end subroutine test_c_options_checked

   !> TAYLORODE with a band (MLJAC < N) needs both bandwidths in [0, N - 1]: IDID = -1
   !> for a huge MUJAC or a negative MLJAC (no allocation of the band, no crash).
   subroutine test_legacy_bandwidths_checked(error)
      type(error_type), allocatable, intent(out) :: error
      integer, parameter :: cases(2, 4) = reshape([0, huge(1), 1, 1000000, -1, 0, 1, 1], [2, 4])
      integer, parameter :: expected(4) = [-1, -1, -1, 1]
      integer :: iwork(20), idid, k
      do k = 1, size(expected)
         call radau5_van_der_pol(1.0_dp, legacy_no_jacobian, 0, cases(1, k), cases(2, k), iwork, idid)
         call check(error, idid == expected(k), "MLJAC, MUJAC = "//format_real(real(cases(1, k), dp))//", "// &
            format_real(real(cases(2, k), dp)))
         if (allocated(error)) return
      end do
   end subroutine test_legacy_bandwidths_checked

   !> TAYLORODE('radau5') (legacy_solve, the entry's body) on Van der Pol (mu = 10) from
   !> (2, 0) at x = 0 to x_end: RTOL = ATOL = 1e-6, H = 0, WORK = IWORK = 0 on entry, the
   !> bandwidths MLJAC, MUJAC, and jac when ijac = 1; iwork and idid as it returns them,
   !> allocations the heap allocations it made.
   subroutine radau5_van_der_pol(x_end, jac, ijac, mljac, mujac, iwork, idid, allocations)
      real(dp), intent(in) :: x_end
      procedure(jac_interface) :: jac
      integer, intent(in) :: ijac, mljac, mujac
      integer, intent(out) :: iwork(20), idid
      integer(c_long_long), intent(out), optional :: allocations
      real(dp) :: x, y(2), h, rtol(1), atol(1), work(20), rpar(1)
      integer :: ipar(1)
      integer(c_long_long) :: before
      x = 0.0_dp
      y = [2.0_dp, 0.0_dp]
      h = 0.0_dp
      rtol = 1.0e-6_dp
      atol = 1.0e-6_dp
      work = 0.0_dp
      iwork = 0
      before = allocation_count()
      call legacy_solve("radau5", 2, legacy_vdp, legacy_vdp, .false., x, y, x_end, h, rtol, atol, 0, &
         jac, 0, jac, ijac, mljac, mujac, legacy_no_mass, 0, 2, 0, legacy_no_output, 0, work, 20, iwork, 20, &
         rpar, ipar, idid)
      if (present(allocations)) allocations = allocation_count() - before
   end subroutine radau5_van_der_pol

   !> Van der Pol (mu = 10) as FCN(N, X, Y, F, RPAR, IPAR).
   subroutine legacy_vdp(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      f(1) = y(2)
      f(2) = 10.0_dp*(1.0_dp - y(1)**2)*y(2) - y(1)
   end subroutine legacy_vdp

   !> Its Jacobian as JAC(N, X, Y, DFY, LDFY, RPAR, IPAR).
   subroutine legacy_vdp_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy(1, 1) = 0.0_dp
      dfy(1, 2) = 1.0_dp
      dfy(2, 1) = -20.0_dp*y(1)*y(2) - 1.0_dp
      dfy(2, 2) = 10.0_dp*(1.0_dp - y(1)**2)
   end subroutine legacy_vdp_jacobian

   !> A SOLOUT that is never called (IOUT = 0).
   subroutine legacy_no_output(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      irtrn = 0
   end subroutine legacy_no_output


   !> Options a command does not use, options that contradict each other, a default
   !> final time that overflows and an output name the file system refuses: exit status
   !> 2 before any work.
   subroutine test_mistakes_found_first(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      call expect_usage_error("stability --grid 3 --repeats 3", "does not apply")
      call expect_usage_error("vdp --mu 1 --tend 1 --dense 2 --repeats 2", "does not apply")
      call expect_usage_error("table --full --budget 10", "--full")
      call expect_usage_error("vdp --mu 1e308 --dense 2 --budget 100", "--tend")
      call expect_usage_error("vdp --mu 1 --tend 1 --dense 2 --history "//scratch//"/"//repeat("h", 300)//".csv", &
         "cannot write")
   contains
      subroutine expect_usage_error(arguments, words)
         character(len=*), intent(in) :: arguments, words
         if (allocated(error)) return
         call run_app(arguments, run)
         call check(error, run%exit_status == 2 .and. has_line(run%stderr, words) .and. size(run%stdout) == 0, &
            "taylorode "//arguments(:min(len(arguments), 80)))
      end subroutine expect_usage_error
   end subroutine test_mistakes_found_first

   !> Failure messages print every time legibly, before t = 0 and far from it too (a
   !> fixed-width edit descriptor printed asterisks for t < 0 and dropped the E of a
   !> three-digit exponent), and they are still built in fixed-length buffers.
   subroutine test_messages_legible(error)
      type(error_type), allocatable, intent(out) :: error
      type(van_der_pol_type) :: problem
      type(poisoned_after_type) :: poisoned
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(2), v(1)

      problem = new_van_der_pol(10.0_dp)
      call new_scheme("i-t-1", scheme, stat)
      u = problem%u0
      call integrate(problem, scheme, -10.0_dp, -5.0_dp, u, integrator_options_type(max_steps=2_i8), stats, stat)
      call expect(status_max_steps, "reached at t = -")
      u = problem%u0
      call integrate(problem, scheme, -10.0_dp, -5.0_dp, u, integrator_options_type(h_min=0.5_dp), &
         stats, stat)
      call expect(status_step_underflow, "roundoff of t = -1.000000E+01")
      poisoned%t_bad = -9.0_dp
      v = 1.0_dp
      call integrate(poisoned, scheme, -10.0_dp, -5.0_dp, v, integrator_options_type(), stats, stat)
      call expect(status_nonfinite, "at t = -9.")
      poisoned%t_bad = -1.4e-100_dp
      v = 1.0_dp
      call integrate_fixed(poisoned, scheme, -2.0e-100_dp, -1.0e-100_dp, 2, v, stat)
      call expect(status_nonfinite, "(step from t = -1.5000000000000000E-100)")
      if (allocated(error)) return
      call check(error, trim(fixed_length_real(-7.927342e2_dp, 7))//" "//trim(fixed_length_real(1.0e-300_dp, 2))// &
         " "//trim(fixed_length_real(ieee_value(1.0_dp, ieee_quiet_nan)))//" "// &
         trim(fixed_length_real(-ieee_value(1.0_dp, ieee_positive_inf))), "-7.927342E+02 1.0E-300 nan -inf")
   contains
      subroutine expect(code, words)
         integer, intent(in) :: code
         character(len=*), intent(in) :: words
         if (allocated(error)) return
         call check(error, stat%code == code .and. index(stat_message(stat), "*") == 0 .and. &
            index(stat_message(stat), words) > 0, "expected """//words//""" in: "//stat_message(stat))
      end subroutine expect
   end subroutine test_messages_legible

   subroutine bad_g(self, t, u, dudt)
      class(bad_jacobian_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -2.0_dp*u
   end subroutine bad_g

   subroutine bad_jac_g(self, t, u, jac)
      class(bad_jacobian_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      integer :: i
      jac = 0.0_dp
      do i = 1, size(u)
         jac(i, i) = -2.0_dp
      end do
      if (t > self%t_bad) jac(self%row, 1) = self%bad
   end subroutine bad_jac_g

   !> Band (1, 1): entry (i, j) in band(2 + i - j, j)
   subroutine bad_jac_g_band(self, t, u, band)
      class(bad_jacobian_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      band = 0.0_dp
      band(2, :) = -2.0_dp
      if (t > self%t_bad) band(2 + self%row - 1, 1) = self%bad
   end subroutine bad_jac_g_band

   function bad_structure(self, n) result(structure)
      class(bad_jacobian_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      if (self%band) then
         structure = band_structure(1, 1)
      else
         structure = dense_structure()
      end if
   end function bad_structure

end module test_robustness
