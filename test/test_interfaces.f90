!> The interfaces for the codes that use the library, exercised as their users would:
!> the F77 program (built with pkg-config, the same as its RADAU5 version but for the
!> CALL line), the C program (built by its plain Makefile) and the Python script
!> (ctypes and numpy), each against an installed library, a C program that checks the
!> header's promises on bad input (NULL pointers, inexact names, t_end = t0, messages),
!> a Fortran program linked by the README's command line; and the README's code, which
!> must be the examples' code.
!> `make test` installs into build/install and says where through TAYLORODE_PREFIX;
!> without it the tests that need the installation are skipped with that message.
module test_interfaces
   use testdrive, only: new_unittest, unittest_type, error_type, check, skip_test
   use test_support, only: scratch, run_type, run_command, read_lines, line_type, has_line, stat_message
   use taylorode, only: dp, scheme_type, new_scheme, integrate, integrator_options_type, integration_stats_type, &
      status_type, status_ok, status_invalid_argument, status_size_mismatch, status_nonfinite, &
      status_singular_matrix, status_newton_diverged, status_newton_not_converged, status_step_underflow, &
      status_max_steps, status_unknown_scheme, status_evaluation_failed, status_output_error, status_out_of_memory
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol
   use taylorode_base_strings, only: format_real, format_integer
   use taylorode_interfaces_legacy, only: legacy_solve, legacy_interpolate, legacy_no_mass
   implicit none
   private

   public :: collect_interfaces

contains

   !> Collect all exported unit tests
   subroutine collect_interfaces(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("c-header-status-codes", test_header_codes), &
         new_unittest("legacy-f77-robertson", test_legacy_robertson), &
         new_unittest("legacy-solout-dense-output", test_legacy_dense_output), &
         new_unittest("c-van-der-pol", test_c_van_der_pol), &
         new_unittest("c-contract-on-bad-input", test_c_contract), &
         new_unittest("python-van-der-pol", test_python_van_der_pol), &
         new_unittest("fortran-link-line", test_fortran_link_line), &
         new_unittest("readme-code-is-example-code", test_readme_code) &
         ]
   end subroutine collect_interfaces

   !> The installed library (TAYLORODE_PREFIX), or "" when there is none.
   function installation() result(prefix)
      character(len=:), allocatable :: prefix
      character(len=1024) :: value
      integer :: length, status
      logical :: found
      call get_environment_variable("TAYLORODE_PREFIX", value, length, status)
      prefix = ""
      if (status /= 0 .or. length == 0) return
      inquire (file=value(:length)//"/lib/libtaylorode.so", exist=found)
      if (found) prefix = value(:length)
   end function installation

   !> Skip a test that needs the installation when there is none.
   logical function missing_installation(error)
      type(error_type), allocatable, intent(out) :: error
      missing_installation = len(installation()) == 0
      if (missing_installation) call skip_test(error, "needs an installed library: run `make test` (it installs "// &
         "into build/install) or set TAYLORODE_PREFIX")
   end function missing_installation

   !> pkg-config's environment for the installation.
   function pkg_config_environment() result(text)
      character(len=:), allocatable :: text
      text = "export PKG_CONFIG_PATH="//installation()//"/lib/pkgconfig; "
   end function pkg_config_environment

   !> The numbers after `label` on the first line of `lines` that contains it.
   subroutine numbers_after(lines, label, values, found)
      type(line_type), intent(in) :: lines(:)
      character(len=*), intent(in) :: label
      real(dp), intent(out) :: values(:)
      logical, intent(out) :: found
      integer :: k, at, io
      found = .false.
      do k = 1, size(lines)
         at = index(lines(k)%text, label)
         if (at == 0) cycle
         read (lines(k)%text(at + len(label):), *, iostat=io) values
         found = io == 0
         return
      end do
   end subroutine numbers_after

   !> Van der Pol mu = 10 over [0, 10] with i-t-2 at rtol = atol = 1e-8, the run every
   !> interface example makes.
   subroutine fortran_van_der_pol(u, stat)
      real(dp), intent(out) :: u(2)
      type(status_type), intent(out) :: stat
      type(van_der_pol_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      problem = new_van_der_pol(10.0_dp)
      call new_scheme("i-t-2", scheme, stat)
      u = [2.0_dp, 0.0_dp]
      call integrate(problem, scheme, 0.0_dp, 10.0_dp, u, integrator_options_type(rtol=1.0e-8_dp, atol=1.0e-8_dp), &
         stats, stat)
   end subroutine fortran_van_der_pol

   !> The header's status codes are the library's.
   subroutine test_header_codes(error)
      type(error_type), allocatable, intent(out) :: error
      type(line_type), allocatable :: header(:)
      character(len=*), parameter :: names(13) = [character(len=30) :: "TAYLORODE_OK", &
         "TAYLORODE_INVALID_ARGUMENT", "TAYLORODE_SIZE_MISMATCH", "TAYLORODE_NONFINITE", &
         "TAYLORODE_SINGULAR_MATRIX", "TAYLORODE_NEWTON_DIVERGED", "TAYLORODE_NEWTON_NOT_CONVERGED", &
         "TAYLORODE_STEP_UNDERFLOW", "TAYLORODE_MAX_STEPS", "TAYLORODE_UNKNOWN_SCHEME", &
         "TAYLORODE_EVALUATION_FAILED", "TAYLORODE_OUTPUT_ERROR", "TAYLORODE_OUT_OF_MEMORY"]
      integer, parameter :: codes(13) = [status_ok, status_invalid_argument, status_size_mismatch, &
         status_nonfinite, status_singular_matrix, status_newton_diverged, status_newton_not_converged, &
         status_step_underflow, status_max_steps, status_unknown_scheme, status_evaluation_failed, status_output_error, &
         status_out_of_memory]
      real(dp) :: value(1)
      logical :: found
      integer :: k
      call read_lines("include/taylorode.h", header)
      call check(error, size(header) > 0, "include/taylorode.h not found (run the tests from the project root)")
      if (allocated(error)) return
      do k = 1, size(names)
         call numbers_after(header, trim(names(k))//" =", value, found)
         call check(error, found .and. nint(value(1)) == codes(k), trim(names(k))//" differs from the library")
         if (allocated(error)) return
      end do
   end subroutine test_header_codes

   !> The F77 program differs from its RADAU5 version only in the CALL statement, builds
   !> with pkg-config as a legacy Makefile would, and reproduces Robertson's published
   !> solution at t = 40 (rtol 1e-8: relative errors below 1e-6).
   subroutine test_legacy_robertson(error)
      type(error_type), allocatable, intent(out) :: error
      real(dp), parameter :: reference(3) = [0.7158270687194048_dp, 9.185534764557822e-6_dp, 0.2841637457458297_dp]
      type(line_type), allocatable :: ours(:), theirs(:)
      type(run_type) :: run
      real(dp) :: values(4), counts(8)
      logical :: found, in_call
      integer :: k

      call read_lines("example/legacy/robertson.f", ours)
      call read_lines("example/legacy/robertson_radau5.f", theirs)
      call check(error, size(ours) == size(theirs) .and. size(ours) > 0, "the two programs differ in length")
      if (allocated(error)) return
      in_call = .false.
      do k = 1, size(ours)
         ! fixed form: a statement beyond column 72 is silently cut (and an argument lost)
         call check(error, len_trim(ours(k)%text) <= 72 .and. len_trim(theirs(k)%text) <= 72, &
            "a line beyond column 72 at line "//trim(format_real(real(k, dp), 3)))
         if (allocated(error)) return
         if (index(ours(k)%text, "      CALL ") == 1) then
            in_call = .true.
         else if (index(ours(k)%text, "     &") /= 1) then
            in_call = .false.
         end if
         if (ours(k)%text == theirs(k)%text) cycle
         call check(error, in_call, "line "//trim(format_real(real(k, dp), 3))//" differs outside the CALL: "// &
            ours(k)%text)
         if (allocated(error)) return
      end do
      if (missing_installation(error)) return
      call run_command(pkg_config_environment()//"gfortran -O2 -Werror=line-truncation "// &
         "example/legacy/robertson.f $(pkg-config --cflags --libs taylorode) -o "//scratch//"/robertson_f77 && "// &
         scratch//"/robertson_f77", run)
      call check(error, run%exit_status, 0, "build or run of the F77 program failed")
      if (allocated(error)) return
      call numbers_after(run%stdout, "Y =", values(2:4), found)
      call check(error, found .and. has_line(run%stdout, "X =  40.000"), "no final state printed")
      if (allocated(error)) return
      call check(error, maxval(abs(values(2:4) - reference)/reference) < 1.0e-6_dp, "Robertson at t = 40 off by "// &
         format_real(maxval(abs(values(2:4) - reference)/reference), 2))
      if (allocated(error)) return
      call numbers_after(run%stdout, "IDID =", counts(1:1), found)
      call check(error, found .and. nint(counts(1)) == 1, "IDID should be 1")
   end subroutine test_legacy_robertson

   !> The C program, built by its plain Makefile with pkg-config, gives the Fortran
   !> library's answer; 100 continued calls give it to the tolerance.
   subroutine test_c_van_der_pol(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(status_type) :: stat
      real(dp) :: u(2), one_call(2), continued(2)
      logical :: found
      if (missing_installation(error)) return
      call run_command("mkdir -p "//scratch//"/c && "//pkg_config_environment()//"make --no-print-directory -s "// &
         "-C "//scratch//"/c -f $PWD/example/c/Makefile VPATH=$PWD/example/c van_der_pol && "//scratch// &
         "/c/van_der_pol", run)
      call check(error, run%exit_status, 0, "build or run of the C program failed")
      if (allocated(error)) return
      call fortran_van_der_pol(u, stat)
      call check(error, stat%code, status_ok, stat_message(stat))
      if (allocated(error)) return
      call numbers_after(run%stdout, "one call:   y =", one_call(1:1), found)
      call numbers_after(run%stdout, "z =", one_call(2:2), found)
      call check(error, found .and. maxval(abs(one_call - u)) <= 1.0e-14_dp*maxval(abs(u)), &
         "C and Fortran differ: "//format_real(maxval(abs(one_call - u)), 3)//" Fortran y = "//format_real(u(1), 16))
      if (allocated(error)) return
      call numbers_after(run%stdout, "100 calls:  y =", continued(1:1), found)
      call check(error, found .and. abs(continued(1) - u(1)) < 1.0e-6_dp, "100 continued calls differ")
   end subroutine test_c_van_der_pol

   !> The C interface keeps its promises on bad input, as a C program built against the
   !> installation sees them (test/c_interface_contract.c, run in a process of its own):
   !> NULL for any pointer is an error status with a message, never a crash; a NULL
   !> status pointer still creates a handle; names are exact ("h0 " is no option, "
   !> i-t-2" no scheme); t_end = t0 is refused as the Fortran integrate refuses it; a
   !> good call after a failed one leaves the message empty.
   subroutine test_c_contract(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      character(len=:), allocatable :: failed
      integer :: k
      if (missing_installation(error)) return
      call run_command("mkdir -p "//scratch//"/c && "//pkg_config_environment()//"cc -Wall -Wextra -Werror "// &
         "-DTAYLORODE_CONTRACT_PROGRAM test/c_interface_contract.c $(pkg-config --cflags --libs taylorode) -lm "// &
         "-o "//scratch//"/c/contract && "//scratch//"/c/contract", run)
      failed = ""
      do k = 1, size(run%stdout)
         if (index(run%stdout(k)%text, "FAIL") == 1) failed = failed//new_line("a")//run%stdout(k)%text
      end do
      do k = 1, size(run%stderr)
         failed = failed//new_line("a")//run%stderr(k)%text
      end do
      call check(error, run%exit_status == 0 .and. size(run%stdout) > 0, "the C program failed (exit "// &
         "status "//format_integer(run%exit_status)//", "//format_integer(size(run%stdout))//" lines):"//failed)
      if (allocated(error)) return
      call check(error, run%stdout(size(run%stdout))%text, "0 failed")
   end subroutine test_c_contract

   !> SOLOUT's TAYLORODE_CONTR interpolates each step with the integrator's dense output:
   !> on the oscillator y1' = y2, y2' = -y1 over [0, 2 pi] at rtol = atol = 1e-8 it
   !> returns the states SOLOUT is given at both ends of a step and, inside, the exact
   !> solution to 1e-6, for radau5 (its collocation polynomial, no evaluation more than
   !> with IOUT = 0: measured 2.5e-9) and i-t-2 (the cubic Hermite interpolant: 3.6e-8).
   subroutine test_legacy_dense_output(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(2) = [character(len=6) :: "radau5", "i-t-2"]
      real(dp), parameter :: two_pi = 8.0_dp*atan(1.0_dp)
      real(dp) :: x, y(2), h, rtol(1), atol(1), work(20), rpar(5)
      integer :: iwork(20), ipar(1), idid, iout, k, evaluations(0:1)
      rtol = 1.0e-8_dp
      atol = 1.0e-8_dp
      do k = 1, size(names)
         do iout = 0, 1
            x = 0.0_dp
            y = [1.0_dp, 0.0_dp]
            h = 0.0_dp
            work = 0.0_dp
            iwork = 0
            ! worst error inside the steps, worst mismatch at their ends, SOLOUT calls
            rpar = 0.0_dp
            call legacy_solve(trim(names(k)), 2, oscillator, oscillator, .false., x, y, two_pi, h, rtol, atol, 0, &
               oscillator_jacobian, 0, oscillator_jacobian, 1, 2, 2, legacy_no_mass, 0, 2, 0, watch_steps, iout, &
               work, 20, iwork, 20, rpar, ipar, idid)
            call check(error, idid, 1, trim(names(k))//": IDID")
            if (allocated(error)) return
            evaluations(iout) = iwork(14)
         end do
         call check(error, nint(rpar(3)), iwork(17) + 1, trim(names(k))//": one SOLOUT call per step, one at the start")
         if (allocated(error)) return
         call check(error, rpar(2) <= 1.0e-14_dp, trim(names(k))//": CONTR misses the ends of a step by "// &
            format_real(rpar(2)))
         if (allocated(error)) return
         call check(error, rpar(1) <= 1.0e-6_dp, trim(names(k))//": CONTR off the solution by "//format_real(rpar(1)))
         if (allocated(error)) return
         if (k == 1) then
            call check(error, evaluations(1), evaluations(0), "radau5: dense output should cost no evaluation")
            if (allocated(error)) return
         end if
      end do
   end subroutine test_legacy_dense_output

   subroutine oscillator(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      f = [y(2), -y(1)]
   end subroutine oscillator

   subroutine oscillator_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy(1:2, 1:2) = reshape([0.0_dp, -1.0_dp, 1.0_dp, 0.0_dp], [2, 2])
   end subroutine oscillator_jacobian

   !> rpar(1): worst error of CONTR at a quarter and at half of a step; rpar(2): worst
   !> mismatch of CONTR at XOLD and X with the states there; rpar(3): calls.
   subroutine watch_steps(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      integer :: ipar(*)
      real(dp) :: s, theta
      integer :: i, k
      rpar(3) = rpar(3) + 1.0_dp
      if (nr > 1) then
         do i = 1, n
            rpar(2) = max(rpar(2), abs(legacy_interpolate(i, xold, cont, lrc) - rpar(3 + i)), &
               abs(legacy_interpolate(i, x, cont, lrc) - y(i)))
         end do
         do k = 1, 2
            theta = 0.25_dp*real(k, dp)
            s = xold + theta*(x - xold)
            rpar(1) = max(rpar(1), abs(legacy_interpolate(1, s, cont, lrc) - cos(s)), &
               abs(legacy_interpolate(2, s, cont, lrc) + sin(s)))
         end do
      end if
      rpar(4:3 + n) = y
   end subroutine watch_steps

   !> The Python example (ctypes and numpy) gives the Fortran library's answer; skipped
   !> where python3 with numpy is not installed.
   subroutine test_python_van_der_pol(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      type(status_type) :: stat
      real(dp) :: u(2), values(1), python(2)
      logical :: found
      if (missing_installation(error)) return
      call run_command("python3 -c 'import numpy'", run)
      if (run%exit_status /= 0) then
         call skip_test(error, "python3 with numpy is not installed")
         return
      end if
      call run_command("TAYLORODE_PREFIX="//installation()//" python3 example/python/van_der_pol.py", run)
      call check(error, run%exit_status, 0, "the Python example failed")
      if (allocated(error)) return
      call fortran_van_der_pol(u, stat)
      call numbers_after(run%stdout, "y =", values, found)
      python(1) = values(1)
      call numbers_after(run%stdout, "z =", values, found)
      python(2) = values(1)
      call check(error, found .and. maxval(abs(python - u)) <= 1.0e-14_dp*maxval(abs(u)), &
         "Python and Fortran differ: "//format_real(maxval(abs(python - u)), 3))
   end subroutine test_python_van_der_pol

   !> A Fortran program built against the installation with the README's command line
   !> (gfortran -I$PREFIX/include ... -L$PREFIX/lib -Wl,-rpath,$PREFIX/lib -ltaylorode
   !> -llapack -lblas) runs and solves Robertson's problem.
   subroutine test_fortran_link_line(error)
      type(error_type), allocatable, intent(out) :: error
      type(run_type) :: run
      character(len=:), allocatable :: prefix
      if (missing_installation(error)) return
      prefix = installation()
      call run_command("root=$PWD && mkdir -p "//scratch//"/link && cd "//scratch//"/link && "// &
         "gfortran -I"//prefix//"/include $root/example/own_problem.f90 -L"//prefix//"/lib -Wl,-rpath,"// &
         prefix//"/lib -ltaylorode -llapack -lblas -o own_problem && ./own_problem", run)
      call check(error, run%exit_status, 0, "build or run against the installation failed")
      if (allocated(error)) return
      call check(error, has_line(run%stdout, "u(40) ="), "the program printed no result")
   end subroutine test_fortran_link_line

   !> Every ```fortran, ```c and ```python block of README.md is, line for line, part of
   !> a file in example/ (which fpm build, make test and the tests above compile and run),
   !> so that the README shows code that compiles.
   subroutine test_readme_code(error)
      type(error_type), allocatable, intent(out) :: error
      type(line_type), allocatable :: readme(:), block(:)
      type(run_type) :: files
      integer :: k, first, blocks
      character(len=:), allocatable :: fence

      call read_lines("README.md", readme)
      call check(error, size(readme) > 0, "README.md not found (run the tests from the project root)")
      if (allocated(error)) return
      call run_command("find example -type f \( -name '*.f90' -o -name '*.f' -o -name '*.c' -o -name '*.py' \) "// &
         "| sort", files)
      call check(error, files%exit_status == 0 .and. size(files%stdout) > 0, "no files found in example/")
      if (allocated(error)) return
      blocks = 0
      k = 1
      do while (k <= size(readme))
         fence = trim(readme(k)%text)
         if (fence /= "```fortran" .and. fence /= "```c" .and. fence /= "```python") then
            k = k + 1
            cycle
         end if
         first = k + 1
         k = first
         do while (k <= size(readme))
            if (trim(readme(k)%text) == "```") exit
            k = k + 1
         end do
         block = readme(first:k - 1)
         blocks = blocks + 1
         call check(error, size(block) > 0 .and. in_some_file(block, files%stdout), "README.md line "// &
            format_integer(first)//": this block is not part of any file in example/: "//readme(first)%text)
         if (allocated(error)) return
         k = k + 1
      end do
      call check(error, blocks > 0, "README.md has no code blocks")
   end subroutine test_readme_code

   !> Whether the lines of `block` occur one after another in one of the files.
   logical function in_some_file(block, paths) result(found)
      type(line_type), intent(in) :: block(:), paths(:)
      type(line_type), allocatable :: lines(:)
      integer :: p, start, i
      found = .false.
      do p = 1, size(paths)
         call read_lines(paths(p)%text, lines)
         do start = 1, size(lines) - size(block) + 1
            do i = 1, size(block)
               if (lines(start + i - 1)%text /= block(i)%text) exit
            end do
            if (i > size(block)) then
               found = .true.
               return
            end if
         end do
      end do
   end function in_some_file

end module test_interfaces
