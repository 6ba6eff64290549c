!> Helpers shared by the test suites: an independent reference solver, message
!> formatting, and the C and legacy interfaces as their callers see them.
module test_support
   use taylorode, only: dp, ode_problem, status_type, matrix_structure_type
   use taylorode_linalg_matrix, only: dense_structure
   use taylorode_testset, only: brusselator_type, transistor_amplifier_type, medical_akzo_type
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_ptr, c_funptr, c_null_char, c_f_pointer
   implicit none
   private

   public :: rk4_reference, stat_message, differenced_brusselator, dense_amplifier_type, dense_akzo_type
   public :: scratch, line_type, run_type, run_app, read_lines, has_line, count_separators, file_exists, &
      fresh_scratch, app_path, run_command
   public :: c_create, c_free, c_set_option, c_set_functions, c_set_bandwidths, c_set_tolerance_vectors, c_integrate, &
      c_message, message_of, legacy_no_jacobian

   !> The Brusselator with bandwidths but no analytic band Jacobians: the band
   !> Jacobians come from the library's grouped finite differences
   type, extends(ode_problem) :: differenced_brusselator
      type(brusselator_type) :: model
   contains
      procedure :: f => differenced_f
      procedure :: g => differenced_g
      procedure :: jac_f => differenced_jac_f
      procedure :: jac_g => differenced_jac_g
      procedure :: jacobian_structure => differenced_structure
   end type differenced_brusselator

   !> The transistor amplifier declaring a dense Jacobian: its J and M then come dense
   type, extends(transistor_amplifier_type) :: dense_amplifier_type
   contains
      procedure :: jacobian_structure => dense_amplifier_structure
   end type dense_amplifier_type

   !> MEDAKZO declaring a dense Jacobian: its J then comes dense (from its band)
   type, extends(medical_akzo_type) :: dense_akzo_type
   contains
      procedure :: jacobian_structure => dense_akzo_structure
   end type dense_akzo_type

   interface
      !> The C interface, called as C would (include/taylorode.h)
      function c_create(scheme, n, status) result(handle) bind(c, name="taylorode_create")
         import :: c_ptr, c_char, c_int
         character(kind=c_char), intent(in) :: scheme(*)
         integer(c_int), value :: n
         integer(c_int), intent(out) :: status
         type(c_ptr) :: handle
      end function c_create
      subroutine c_free(handle) bind(c, name="taylorode_free")
         import :: c_ptr
         type(c_ptr), value :: handle
      end subroutine c_free
      integer(c_int) function c_set_option(handle, name, value) bind(c, name="taylorode_set_option")
         import :: c_ptr, c_char, c_int, c_double
         type(c_ptr), value :: handle
         character(kind=c_char), intent(in) :: name(*)
         real(c_double), value :: value
      end function c_set_option
      integer(c_int) function c_set_bandwidths(handle, lower, upper) bind(c, name="taylorode_set_bandwidths")
         import :: c_ptr, c_int
         type(c_ptr), value :: handle
         integer(c_int), value :: lower, upper
      end function c_set_bandwidths
      integer(c_int) function c_set_functions(handle, f, g, jac_f, jac_g, user_data) &
         bind(c, name="taylorode_set_functions")
         import :: c_ptr, c_funptr, c_int
         type(c_ptr), value :: handle, user_data
         type(c_funptr), value :: f, g, jac_f, jac_g
      end function c_set_functions
      integer(c_int) function c_set_tolerance_vectors(handle, rtol, atol) &
         bind(c, name="taylorode_set_tolerance_vectors")
         import :: c_ptr, c_int, c_double
         type(c_ptr), value :: handle
         real(c_double), intent(in) :: rtol(*), atol(*)
      end function c_set_tolerance_vectors
      integer(c_int) function c_integrate(handle, t0, t_end, u) bind(c, name="taylorode_integrate")
         import :: c_ptr, c_int, c_double
         type(c_ptr), value :: handle
         real(c_double), value :: t0, t_end
         real(c_double), intent(inout) :: u(*)
      end function c_integrate
      function c_message(handle) result(text) bind(c, name="taylorode_message")
         import :: c_ptr
         type(c_ptr), value :: handle
         type(c_ptr) :: text
      end function c_message
   end interface

   !> Scratch directory of the tests that run programs and write files (inside the build tree)
   character(len=*), parameter :: scratch = "build/test-app"

   !> One line of a captured output
   type :: line_type
      character(len=:), allocatable :: text
   end type line_type

   !> What one run of the app printed and returned
   type :: run_type
      integer :: exit_status = -1
      type(line_type), allocatable :: stdout(:), stderr(:)
   end type run_type

contains

   !> The app built beside this test program (fpm puts both under the same profile directory).
   function app_path() result(path)
      character(len=:), allocatable :: path
      character(len=4096) :: self
      integer :: slash
      call get_command_argument(0, self)
      slash = index(self, "/test/", back=.true.)
      if (slash == 0) then
         path = "taylorode"
      else
         path = self(:slash)//"app/taylorode"
      end if
   end function app_path

   !> Run the app with `arguments` (fixed text of the tests, read by a shell) and
   !> capture its output.
   subroutine run_app(arguments, run)
      character(len=*), intent(in) :: arguments
      type(run_type), intent(out) :: run
      call run_command(app_path()//" "//arguments, run)
   end subroutine run_app

   !> Run a shell command line of the tests (which may name the app through
   !> app_path()) and capture what it prints; its own redirections come first.
   subroutine run_command(command_line, run)
      character(len=*), intent(in) :: command_line
      type(run_type), intent(out) :: run
      integer :: command_status
      call execute_command_line("mkdir -p "//scratch)
      call execute_command_line("{ "//command_line//" ; } > "//scratch//"/stdout 2> "//scratch//"/stderr", &
         exitstat=run%exit_status, cmdstat=command_status)
      if (command_status /= 0) run%exit_status = -1
      call read_lines(scratch//"/stdout", run%stdout)
      call read_lines(scratch//"/stderr", run%stderr)
   end subroutine run_command

   !> Every line of a text file (none when it does not exist).
   subroutine read_lines(path, lines)
      character(len=*), intent(in) :: path
      type(line_type), allocatable, intent(out) :: lines(:)
      type(line_type), allocatable :: grown(:)
      character(len=4096) :: buffer
      integer :: unit, io, count, length
      allocate (lines(0))
      open (newunit=unit, file=path, status="old", action="read", iostat=io)
      if (io /= 0) return
      count = 0
      do
         read (unit, '(a)', iostat=io, size=length, advance="no") buffer
         if (is_iostat_end(io)) exit
         if (count == size(lines)) then
            allocate (grown(max(16, 2*count)))
            grown(:count) = lines(:count)
            call move_alloc(grown, lines)
         end if
         count = count + 1
         lines(count)%text = buffer(:length)
      end do
      close (unit)
      lines = lines(:count)
   end subroutine read_lines

   !> Whether any line contains `text`.
   logical function has_line(lines, text)
      type(line_type), intent(in) :: lines(:)
      character(len=*), intent(in) :: text
      integer :: k
      has_line = .false.
      do k = 1, size(lines)
         if (index(lines(k)%text, text) > 0) has_line = .true.
      end do
   end function has_line

   !> Field separators: commas outside double quotes.
   integer function count_separators(text)
      character(len=*), intent(in) :: text
      integer :: k
      logical :: quoted
      count_separators = 0
      quoted = .false.
      do k = 1, len(text)
         if (text(k:k) == '"') quoted = .not. quoted
         if (.not. quoted .and. text(k:k) == ",") count_separators = count_separators + 1
      end do
   end function count_separators

   logical function file_exists(path)
      character(len=*), intent(in) :: path
      inquire (file=path, exist=file_exists)
   end function file_exists

   !> A fresh scratch directory for output files.
   subroutine fresh_scratch()
      call execute_command_line("rm -rf "//scratch//" && mkdir -p "//scratch//"/out")
   end subroutine fresh_scratch


   !> Classical RK4 with 20000 steps: global error ~ 1e-17 * C, far below what the
   !> order tests resolve (their smallest errors are ~1e-7).
   function rk4_reference(problem, u0, t_end) result(u)
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u0(:), t_end
      real(dp) :: u(size(u0))
      integer, parameter :: n = 20000
      real(dp) :: h, t, k1(size(u0)), k2(size(u0)), k3(size(u0)), k4(size(u0))
      integer :: i
      h = t_end/n
      u = u0
      do i = 0, n - 1
         t = i*h
         call full_rhs(t, u, k1)
         call full_rhs(t + h/2, u + h/2*k1, k2)
         call full_rhs(t + h/2, u + h/2*k2, k3)
         call full_rhs(t + h, u + h*k3, k4)
         u = u + h/6*(k1 + 2*k2 + 2*k3 + k4)
      end do
   contains
      subroutine full_rhs(t, u, dudt)
         real(dp), intent(in) :: t, u(:)
         real(dp), intent(out) :: dudt(:)
         real(dp) :: gu(size(u))
         call problem%f(t, u, dudt)
         call problem%g(t, u, gu)
         dudt = dudt + gu
      end subroutine full_rhs
   end function rk4_reference

   subroutine differenced_f(self, t, u, dudt)
      class(differenced_brusselator), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call self%model%f(t, u, dudt)
   end subroutine differenced_f

   subroutine differenced_g(self, t, u, dudt)
      class(differenced_brusselator), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call self%model%g(t, u, dudt)
   end subroutine differenced_g

   subroutine differenced_jac_f(self, t, u, jac)
      class(differenced_brusselator), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      call self%model%jac_f(t, u, jac)
   end subroutine differenced_jac_f

   subroutine differenced_jac_g(self, t, u, jac)
      class(differenced_brusselator), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      call self%model%jac_g(t, u, jac)
   end subroutine differenced_jac_g

   function differenced_structure(self, n) result(structure)
      class(differenced_brusselator), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = self%model%jacobian_structure(n)
   end function differenced_structure

   function dense_amplifier_structure(self, n) result(structure)
      class(dense_amplifier_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = dense_structure()
   end function dense_amplifier_structure

   function dense_akzo_structure(self, n) result(structure)
      class(dense_akzo_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = dense_structure()
   end function dense_akzo_structure

   !> The text taylorode_message returns.
   function message_of(ode) result(text)
      type(c_ptr), intent(in) :: ode
      character(len=:), allocatable :: text
      character(kind=c_char), pointer :: chars(:)
      integer :: k
      call c_f_pointer(c_message(ode), chars, [512])
      text = ""
      do k = 1, size(chars)
         if (chars(k) == c_null_char) exit
         text = text//chars(k)
      end do
   end function message_of

   !> A JAC that is never called (IJAC = 0).
   subroutine legacy_no_jacobian(n, x, y, dfy, ldfy, rpar, ipar)
      integer :: n, ldfy
      real(dp) :: x, y(n), dfy(ldfy, n), rpar(*)
      integer :: ipar(*)
      dfy = 0.0_dp
   end subroutine legacy_no_jacobian

   !> The status message, or "ok".
   function stat_message(stat) result(message)
      type(status_type), intent(in) :: stat
      character(len=:), allocatable :: message
      if (allocated(stat%message)) then
         message = stat%message
      else
         message = "ok"
      end if
   end function stat_message

end module test_support
