!> The C interface (include/taylorode.h): an opaque integrator handle created for a
!> scheme, tolerances and options set by name, C callbacks for f, g and their
!> Jacobians with a user-data pointer, integration in one call or continued call by
!> call, statistics and the last status message. Every function returns a status
!> code (TAYLORODE_OK = 0, the library's status codes otherwise) and never stops or
!> prints. Callbacks return 0 on success, > 0 when they cannot evaluate at the point
!> given (the step is retried with a smaller step) and < 0 to stop the integration.
!>
!> C passes what it likes: a NULL handle, array, name or result pointer is
!> TAYLORODE_INVALID_ARGUMENT (with a message on the handle when there is one), never
!> a dereference (the pointer arguments are optional dummies, absent when NULL); the
!> one exception is taylorode_create's status, which may be NULL. Names are compared
!> exactly, as C strings: "h0 " is no option and "i-t-2 " no scheme. Every function
!> that sets or integrates something leaves taylorode_message empty when it succeeds
!> and the reason when it fails; taylorode_get_stats changes the message only when it
!> fails, so that a failed integration's statistics and message can be read in either order.
module taylorode_interfaces_c
   use, intrinsic :: iso_c_binding, only: c_int, c_long, c_double, c_char, c_ptr, c_funptr, c_null_ptr, &
      c_null_funptr, c_null_char, c_loc, c_f_pointer, c_f_procpointer, c_associated
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch, status_unknown_scheme
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_linalg_matrix, only: matrix_structure_type, band_structure
   use taylorode_problem_ode, only: ode_problem, dense_differences, band_differences, difference_f, difference_g, &
      difference_rhs, full_jacobian, full_band_jacobian
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_integrate_controller, only: controller_i, controller_pi, controller_pid
   use taylorode_integrate_options, only: integrator_options_type, norm_max, norm_rms
   use taylorode_integrate_stats, only: integration_stats_type
   use taylorode_integrate_integrator, only: integrator_type
   implicit none
   private

   public :: taylorode_stats_c

   !> Longest scheme or option name read from a C string (the real ones are far shorter)
   integer, parameter :: max_name_length = 255
   !> What taylorode_message returns for a NULL handle
   character(len=*), parameter :: no_handle_text = "no handle: ode is NULL (did taylorode_create fail?)"
   !> That text as a C string (read-only: threads may share it)
   character(kind=c_char), target, save :: no_handle_message(len(no_handle_text) + 1) = &
      [character(kind=c_char) :: transfer(no_handle_text, [character(kind=c_char) :: "a"], len(no_handle_text)), &
      c_null_char]

   !> What taylorode_get_stats fills (taylorode_stats_t in the header)
   type, bind(c) :: taylorode_stats_c
      !> Accepted and rejected (or failed) steps, evaluations of f and of g, Jacobian
      !> evaluations (of df/dU and dg/dU together), LU factorizations, linear solves
      !> and Newton iterations since taylorode_init
      integer(c_long) :: accepted_steps, rejected_steps, f_evaluations, g_evaluations, jacobian_evaluations, &
         lu_factorizations, linear_solves, newton_iterations
      !> Time reached, the step size the next call starts with, CPU seconds since taylorode_init
      real(c_double) :: t_reached, h_next, cpu_seconds
   end type taylorode_stats_c

   abstract interface
      !> f or g: dudt = part(t, u); returns 0, > 0 (cannot evaluate here) or < 0 (stop)
      integer(c_int) function c_rhs_interface(t, u, dudt, user_data) bind(c)
         import :: c_int, c_double, c_ptr
         real(c_double), value :: t
         real(c_double), intent(in) :: u(*)
         real(c_double), intent(out) :: dudt(*)
         type(c_ptr), value :: user_data
      end function c_rhs_interface
      !> A Jacobian: column-major n x n, or band storage (lower + upper + 1) x n
      integer(c_int) function c_jacobian_interface(t, u, jac, user_data) bind(c)
         import :: c_int, c_double, c_ptr
         real(c_double), value :: t
         real(c_double), intent(in) :: u(*)
         real(c_double), intent(out) :: jac(*)
         type(c_ptr), value :: user_data
      end function c_jacobian_interface
   end interface

   !> The C callbacks as an ode_problem
   type, extends(ode_problem) :: c_problem_type
      type(c_funptr) :: f_callback = c_null_funptr, g_callback = c_null_funptr, jac_f_callback = c_null_funptr, &
         jac_g_callback = c_null_funptr
      type(c_ptr) :: user_data = c_null_ptr
      !> Structure of the Jacobians the user gives (dense unless bandwidths are set)
      type(matrix_structure_type) :: structure
      !> Band Jacobian in contiguous storage for the callback
      real(dp), allocatable :: band_work(:, :)
   contains
      procedure :: f => c_f
      procedure :: g => c_g
      procedure :: jac_f => c_jac_f
      procedure :: jac_g => c_jac_g
      procedure :: jacobian_structure => c_structure
      procedure :: jac_f_band => c_jac_f_band
      procedure :: jac_g_band => c_jac_g_band
      procedure :: jac => c_jac
      procedure :: jac_band => c_jac_band
      procedure :: jac_with_rhs => c_jac_with_rhs
      procedure :: jac_band_with_rhs => c_jac_band_with_rhs
   end type c_problem_type

   !> What a handle points to
   type :: session_type
      integer :: n = 0
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integrator_type) :: integrator
      type(c_problem_type) :: problem
      type(status_type) :: stat
      logical :: started = .false.
      !> The last message, NUL-terminated, for taylorode_message
      character(kind=c_char) :: message(512) = c_null_char
   end type session_type

contains

   !> The session behind a handle (null when the handle is null).
   function session_of(handle) result(session)
      type(c_ptr), intent(in) :: handle
      type(session_type), pointer :: session
      session => null()
      if (c_associated(handle)) call c_f_pointer(handle, session)
   end function session_of

   !> A Fortran string from a NUL-terminated C string (at most max_name_length + 1
   !> characters are read: a longer string comes back too long to be a name).
   !> (A subroutine: a deferred-length function result keeps its length in static
   !> memory with gfortran 12, shared by threads that create sessions at once.)
   subroutine from_c_string(text, value)
      character(kind=c_char), intent(in) :: text(*)
      character(len=:), allocatable, intent(out) :: value
      integer :: k, i
      do k = 1, max_name_length + 1
         if (text(k) == c_null_char) exit
      end do
      allocate (character(len=k - 1) :: value)
      do i = 1, k - 1
         value(i:i) = text(i)
      end do
   end subroutine from_c_string

   !> Whether a C string can be a name as given: not empty, not too long, and without
   !> the blanks at either end that Fortran's comparisons would ignore.
   pure logical function exact_name(value)
      character(len=*), intent(in) :: value
      exact_name = len(value) > 0 .and. len(value) <= max_name_length
      if (exact_name) exact_name = value(1:1) /= " " .and. value(len(value):len(value)) /= " "
   end function exact_name

   !> A call's success: the message is emptied.
   integer(c_int) function succeeded(session) result(code)
      type(session_type), intent(inout) :: session
      code = remember(session, status_type())
   end function succeeded

   !> A call refused for a NULL pointer argument: status_invalid_argument and `message`.
   integer(c_int) function refused(session, message) result(code)
      type(session_type), intent(inout) :: session
      character(len=*), intent(in) :: message
      type(status_type) :: stat
      call set_status(stat, status_invalid_argument, message)
      code = remember(session, stat)
   end function refused

   !> Remember a status and its message; return its code.
   integer(c_int) function remember(session, stat) result(code)
      type(session_type), intent(inout) :: session
      type(status_type), intent(in) :: stat
      integer :: k, length
      session%stat = stat
      session%message = c_null_char
      if (allocated(stat%message)) then
         length = min(len(stat%message), size(session%message) - 1)
         do k = 1, length
            session%message(k) = stat%message(k:k)
         end do
      end if
      code = int(stat%code, c_int)
   end function remember

   !> `taylorode_create`: a handle for `scheme` and n unknowns, or null (the status in
   !> *status: status_invalid_argument for a NULL name, status_unknown_scheme for a
   !> name that is not exactly one of the schemes', status_size_mismatch for n < 1).
   !> status may be NULL: the handle is created all the same, and a failure shows only
   !> as the null handle.
   function taylorode_create(scheme, n, status) result(handle) bind(c, name="taylorode_create")
      character(kind=c_char), intent(in), optional :: scheme(*)
      integer(c_int), value :: n
      integer(c_int), intent(out), optional :: status
      type(c_ptr) :: handle
      type(session_type), pointer :: session
      type(status_type) :: stat
      character(len=:), allocatable :: name
      handle = c_null_ptr
      if (.not. present(scheme)) then
         call report(status_invalid_argument)
         return
      end if
      if (n < 1) then
         call report(status_size_mismatch)
         return
      end if
      call from_c_string(scheme, name)
      if (.not. exact_name(name)) then
         call report(status_unknown_scheme)
         return
      end if
      allocate (session)
      call new_scheme(name, session%scheme, stat)
      call report(stat%code)
      if (stat%code /= status_ok) then
         deallocate (session)
         return
      end if
      session%n = n
      handle = c_loc(session)

   contains

      !> *status = code, when there is a status to write
      subroutine report(code)
         integer, intent(in) :: code
         if (present(status)) status = int(code, c_int)
      end subroutine report
   end function taylorode_create

   !> `taylorode_free`: release a handle (null is fine).
   subroutine taylorode_free(handle) bind(c, name="taylorode_free")
      type(c_ptr), value :: handle
      type(session_type), pointer :: session
      session => session_of(handle)
      if (associated(session)) deallocate (session)
   end subroutine taylorode_free

   !> `taylorode_set_functions`: f and g (NULL: zero), their Jacobians (NULL: differences).
   integer(c_int) function taylorode_set_functions(handle, f, g, jac_f, jac_g, user_data) result(code) &
      bind(c, name="taylorode_set_functions")
      type(c_ptr), value :: handle, user_data
      type(c_funptr), value :: f, g, jac_f, jac_g
      type(session_type), pointer :: session
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      session%problem%f_callback = f
      session%problem%g_callback = g
      session%problem%jac_f_callback = jac_f
      session%problem%jac_g_callback = jac_g
      session%problem%user_data = user_data
      code = succeeded(session)
   end function taylorode_set_functions

   !> `taylorode_set_bandwidths`: banded Jacobians (the callbacks then fill band storage,
   !> jac[(upper + i - j) + (lower + upper + 1) j] = d part_i / d u_j, 0-based).
   integer(c_int) function taylorode_set_bandwidths(handle, lower, upper) result(code) &
      bind(c, name="taylorode_set_bandwidths")
      type(c_ptr), value :: handle
      integer(c_int), value :: lower, upper
      type(session_type), pointer :: session
      type(status_type) :: stat
      real(dp), allocatable :: work(:, :)
      integer :: memory
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (lower < 0 .or. upper < 0 .or. lower > session%n - 1 .or. upper > session%n - 1) then
         call set_status(stat, status_invalid_argument, "taylorode_set_bandwidths: lower and upper must lie "// &
            "in [0, n - 1]")
         code = remember(session, stat)
         return
      end if
      ! the band's rows, lower + upper + 1, are an int of the callbacks' indexing
      if (lower > huge(lower) - 1 - upper) then
         call set_status(stat, status_invalid_argument, "taylorode_set_bandwidths: lower + upper + 1 must not "// &
            "exceed INT_MAX")
         code = remember(session, stat)
         return
      end if
      ! a new work array first: the settings stay as they were when it cannot be allocated
      allocate (work(lower + upper + 1, session%n), stat=memory)
      if (memory /= 0) then
         call out_of_memory(stat, "the band Jacobians' work array", [lower + upper + 1, session%n], real_bytes)
         code = remember(session, stat)
         return
      end if
      call move_alloc(work, session%problem%band_work)
      session%problem%structure = band_structure(lower, upper)
      ! the scheme's matrices were made for the bands at taylorode_init: the integration
      ! cannot go on with others (advance_to read the new work array with the old bands,
      ! past its end); taylorode_init starts it again
      call end_integration(session)
      code = succeeded(session)
   end function taylorode_set_bandwidths

   !> A setting changed after taylorode_init: the integration under way, which init
   !> prepared with the settings before, ends (advance_to asks for taylorode_init again;
   !> it went on with the old settings, and the new ones were silently ignored).
   subroutine end_integration(session)
      type(session_type), intent(inout) :: session
      if (.not. session%started) return
      session%integrator%ready = .false.
      session%started = .false.
   end subroutine end_integration

   !> `taylorode_set_tolerances`: scalar rtol and atol.
   integer(c_int) function taylorode_set_tolerances(handle, rtol, atol) result(code) &
      bind(c, name="taylorode_set_tolerances")
      type(c_ptr), value :: handle
      real(c_double), value :: rtol, atol
      type(session_type), pointer :: session
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      session%options%rtol = rtol
      session%options%atol = atol
      if (allocated(session%options%rtol_vector)) deallocate (session%options%rtol_vector)
      if (allocated(session%options%atol_vector)) deallocate (session%options%atol_vector)
      call end_integration(session)
      code = succeeded(session)
   end function taylorode_set_tolerances

   !> `taylorode_set_tolerance_vectors`: rtol and atol per component (n each, neither NULL).
   integer(c_int) function taylorode_set_tolerance_vectors(handle, rtol, atol) result(code) &
      bind(c, name="taylorode_set_tolerance_vectors")
      type(c_ptr), value :: handle
      real(c_double), intent(in), optional :: rtol(*), atol(*)
      type(session_type), pointer :: session
      type(status_type) :: stat
      real(dp), allocatable :: rtol_copy(:), atol_copy(:)
      integer :: memory
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (.not. (present(rtol) .and. present(atol))) then
         code = refused(session, "taylorode_set_tolerance_vectors: rtol and atol must each point to n values, "// &
            "not NULL")
         return
      end if
      ! copies first: the tolerances stay as they were when they cannot be allocated
      allocate (rtol_copy(session%n), atol_copy(session%n), stat=memory)
      if (memory /= 0) then
         call out_of_memory(stat, "the tolerance vectors", [2, session%n], real_bytes)
         code = remember(session, stat)
         return
      end if
      rtol_copy = rtol(:session%n)
      atol_copy = atol(:session%n)
      call move_alloc(rtol_copy, session%options%rtol_vector)
      call move_alloc(atol_copy, session%options%atol_vector)
      call end_integration(session)
      code = succeeded(session)
   end function taylorode_set_tolerance_vectors

   !> `taylorode_set_option`: a real or whole-number option by name ("h0", "h_min",
   !> "h_min_relative", "h_max", "kappa", "q", "max_growth", "min_shrink", "newton_fraction", "max_steps",
   !> "max_newton_iterations", "max_failures", "reuse_newton_matrix" (0 or 1),
   !> "controller" (0: i, 1: pi, 2: pid), "norm" (0: max, 1: rms)) or the problem's
   !> "autonomous" (1: f and g do not depend on t, 0: they may, the default), exactly
   !> as written here. The integrator checks the values when it starts.
   integer(c_int) function taylorode_set_option(handle, name, value) result(code) &
      bind(c, name="taylorode_set_option")
      type(c_ptr), value :: handle
      character(kind=c_char), intent(in), optional :: name(*)
      real(c_double), value :: value
      type(session_type), pointer :: session
      type(status_type) :: stat
      character(len=:), allocatable :: option
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (.not. present(name)) then
         code = refused(session, "taylorode_set_option: the option's name is NULL")
         return
      end if
      call from_c_string(name, option)
      if (.not. exact_name(option)) then
         ! "h0 " is not "h0", although Fortran's select case would take it for it
         call set_status(stat, status_invalid_argument, 'taylorode_set_option: unknown option "'//option//'"')
         code = remember(session, stat)
         return
      end if
      associate (options => session%options)
         select case (option)
         case ("h0"); options%h0 = value
         case ("h_min"); options%h_min = value
         case ("h_min_relative"); options%h_min_relative = value
         case ("h_max"); options%h_max = value
         case ("kappa"); options%kappa = value
         case ("q"); options%q = value
         case ("max_growth"); options%max_growth = value
         case ("min_shrink"); options%min_shrink = value
         case ("newton_fraction"); options%newton_fraction = value
         case ("max_steps")
            if (whole_number(value, 1.0e18_dp)) options%max_steps = int(value, i8)
         case ("max_newton_iterations")
            if (whole_number(value, real(huge(1), dp))) options%max_newton_iterations = int(value)
         case ("max_failures")
            if (whole_number(value, real(huge(1), dp))) options%max_failures = int(value)
         case ("reuse_newton_matrix")
            if (whole_number(value, 1.0_dp)) options%reuse_newton_matrix = value /= 0.0_dp
         case ("measure_time")
            if (whole_number(value, 1.0_dp)) options%measure_time = value /= 0.0_dp
         case ("controller")
            if (whole_number(value, 2.0_dp)) then
               select case (nint(value))
               case (0); options%controller = controller_i
               case (1); options%controller = controller_pi
               case default; options%controller = controller_pid
               end select
            end if
         case ("norm")
            if (whole_number(value, 1.0_dp)) options%norm = merge(norm_rms, norm_max, value == 1.0_dp)
         case ("autonomous")
            if (whole_number(value, 1.0_dp)) session%problem%autonomous = value == 1.0_dp
         case default
            call set_status(stat, status_invalid_argument, 'taylorode_set_option: unknown option "'//option//'"')
         end select
      end associate
      if (stat%code == status_ok) call end_integration(session)
      code = remember(session, stat)

   contains

      !> Whether value is a whole number that fits the option (its range starts at 0 for
      !> the choices, at any negative number for the counts, which the integrator checks);
      !> stat says why not.
      logical function whole_number(value, largest)
         real(c_double), intent(in) :: value
         real(dp), intent(in) :: largest
         real(dp) :: smallest
         smallest = merge(0.0_dp, -largest, largest <= 2.0_dp)
         whole_number = ieee_is_finite(value)   ! before any comparison: NaN must not reach one
         if (whole_number) whole_number = value >= smallest .and. value <= largest
         if (whole_number) whole_number = value == aint(value)
         if (.not. whole_number) call set_status(stat, status_invalid_argument, "taylorode_set_option: "// &
            option//" must be a whole number in its range")
      end function whole_number
   end function taylorode_set_option

   !> `taylorode_init`: start at (t0, u0) with the current settings.
   integer(c_int) function taylorode_init(handle, t0, u0) result(code) bind(c, name="taylorode_init")
      type(c_ptr), value :: handle
      real(c_double), value :: t0
      real(c_double), intent(in), optional :: u0(*)
      type(session_type), pointer :: session
      type(status_type) :: stat
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (.not. present(u0)) then
         code = refused(session, "taylorode_init: u0 is NULL (it must point to n values)")
         return
      end if
      if (.not. c_associated(session%problem%g_callback) .and. .not. c_associated(session%problem%f_callback)) then
         call set_status(stat, status_invalid_argument, "taylorode_init: set f or g first (taylorode_set_functions)")
         code = remember(session, stat)
         return
      end if
      call session%integrator%init(session%problem, session%scheme, t0, u0(:session%n), session%options, stat)
      session%started = stat%code == status_ok
      code = remember(session, stat)
   end function taylorode_init

   !> `taylorode_advance_to`: continue to t, which must not lie before the current time
   !> (t equal to it returns at once, as the Fortran advance_to does); u holds the state
   !> at the current time on entry (it may have been changed) and at t on exit.
   integer(c_int) function taylorode_advance_to(handle, t, u) result(code) bind(c, name="taylorode_advance_to")
      type(c_ptr), value :: handle
      real(c_double), value :: t
      real(c_double), intent(inout), optional :: u(*)
      type(session_type), pointer :: session
      type(status_type) :: stat
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (.not. present(u)) then
         code = refused(session, "taylorode_advance_to: u is NULL (it must point to n values)")
         return
      end if
      if (.not. session%started) then
         code = refused(session, "taylorode_advance_to: call taylorode_init first (again after a setting "// &
            "changed: settings apply from taylorode_init on)")
         return
      end if
      call session%integrator%advance_to(session%problem, session%scheme, t, u(:session%n), stat)
      code = remember(session, stat)
   end function taylorode_advance_to

   !> `taylorode_integrate`: from t0 to t_end > t0 in one call (init, then advance_to);
   !> t_end <= t0 is refused before anything changes, as the Fortran integrate refuses it.
   integer(c_int) function taylorode_integrate(handle, t0, t_end, u) result(code) bind(c, name="taylorode_integrate")
      type(c_ptr), value :: handle
      real(c_double), value :: t0, t_end
      real(c_double), intent(inout), optional :: u(*)
      type(session_type), pointer :: session
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (.not. present(u)) then
         code = refused(session, "taylorode_integrate: u is NULL (it must point to n values)")
         return
      end if
      if (.not. (ieee_is_finite(t_end) .and. t_end > t0)) then
         code = refused(session, "taylorode_integrate: t_end must be finite and greater than t0 (backward "// &
            "integration is not supported: substitute s = -t)")
         return
      end if
      code = taylorode_init(handle, t0, u)
      if (code /= status_ok) return
      code = taylorode_advance_to(handle, t_end, u)
   end function taylorode_integrate

   !> `taylorode_get_stats`: the statistics since taylorode_init. It only reads: the
   !> message stays the last call's unless stats is NULL.
   integer(c_int) function taylorode_get_stats(handle, stats) result(code) bind(c, name="taylorode_get_stats")
      type(c_ptr), value :: handle
      type(taylorode_stats_c), intent(out), optional :: stats
      type(session_type), pointer :: session
      session => session_of(handle)
      code = status_invalid_argument
      if (.not. associated(session)) return
      if (.not. present(stats)) then
         code = refused(session, "taylorode_get_stats: stats is NULL")
         return
      end if
      associate (total => session%integrator%total)
         stats%accepted_steps = int(total%accepted_steps, c_long)
         stats%rejected_steps = int(total%rejected_steps(), c_long)
         stats%f_evaluations = int(total%work%f_evaluations, c_long)
         stats%g_evaluations = int(total%work%g_evaluations, c_long)
         stats%jacobian_evaluations = int(total%work%jac_f_evaluations + total%work%jac_g_evaluations, c_long)
         stats%lu_factorizations = int(total%work%lu_factorizations, c_long)
         stats%linear_solves = int(total%work%linear_solves, c_long)
         stats%newton_iterations = int(total%work%newton_iterations, c_long)
         stats%t_reached = total%t_reached
         stats%h_next = session%integrator%h
         stats%cpu_seconds = total%cpu_seconds
      end associate
      code = status_ok
   end function taylorode_get_stats

   !> `taylorode_message`: the message of the last call that set a status ("" when it
   !> succeeded), valid until the next call on the handle; for a NULL handle a constant
   !> text that says so. Never NULL.
   function taylorode_message(handle) result(text) bind(c, name="taylorode_message")
      type(c_ptr), value :: handle
      type(c_ptr) :: text
      type(session_type), pointer :: session
      session => session_of(handle)
      if (associated(session)) then
         text = c_loc(session%message)
      else
         text = c_loc(no_handle_message)
      end if
   end function taylorode_message

   !> Call a part's callback; a nonzero return rejects the evaluation (fatal when < 0).
   subroutine call_part(self, callback, t, u, dudt)
      type(c_problem_type), intent(inout) :: self
      type(c_funptr), intent(in) :: callback
      real(dp), intent(in) :: t
      ! (not declared contiguous: for a contiguous dummy gfortran copies an assumed-shape
      ! actual into a new array at every call; the callback's assumed-size arguments
      ! are packed only when the arrays are not contiguous, which the library's are)
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      procedure(c_rhs_interface), pointer :: part
      integer(c_int) :: returned
      if (.not. c_associated(callback)) then
         dudt = 0.0_dp
         return
      end if
      call c_f_procpointer(callback, part)
      returned = part(t, u, dudt, self%user_data)
      if (returned /= 0) call self%reject_evaluation(fatal=returned < 0)
   end subroutine call_part

   !> Call a Jacobian callback into jac; false when there is none.
   logical function call_jacobian(self, callback, t, u, jac) result(called)
      type(c_problem_type), intent(inout) :: self
      type(c_funptr), intent(in) :: callback
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      procedure(c_jacobian_interface), pointer :: jacobian
      integer(c_int) :: returned
      called = c_associated(callback)
      if (.not. called) return
      call c_f_procpointer(callback, jacobian)
      returned = jacobian(t, u, jac, self%user_data)
      if (returned /= 0) call self%reject_evaluation(fatal=returned < 0)
   end function call_jacobian

   subroutine c_f(self, t, u, dudt)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call call_part(self, self%f_callback, t, u, dudt)
   end subroutine c_f

   subroutine c_g(self, t, u, dudt)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call call_part(self, self%g_callback, t, u, dudt)
   end subroutine c_g

   subroutine c_jac_f(self, t, u, jac)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (.not. c_associated(self%f_callback)) then
         jac = 0.0_dp
      else if (.not. call_jacobian(self, self%jac_f_callback, t, u, jac)) then
         call dense_differences(self, difference_f, t, u, jac)
      end if
   end subroutine c_jac_f

   subroutine c_jac_g(self, t, u, jac)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (.not. c_associated(self%g_callback)) then
         jac = 0.0_dp
      else if (.not. call_jacobian(self, self%jac_g_callback, t, u, jac)) then
         call dense_differences(self, difference_g, t, u, jac)
      end if
   end subroutine c_jac_g

   function c_structure(self, n) result(structure)
      class(c_problem_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = self%structure
   end function c_structure

   subroutine c_jac_f_band(self, t, u, band)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (.not. c_associated(self%f_callback)) then
         band = 0.0_dp
      else if (call_jacobian(self, self%jac_f_callback, t, u, self%band_work)) then
         band = self%band_work
      else
         call band_differences(self, difference_f, t, u, band)
      end if
   end subroutine c_jac_f_band

   subroutine c_jac_g_band(self, t, u, band)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (.not. c_associated(self%g_callback)) then
         band = 0.0_dp
      else if (call_jacobian(self, self%jac_g_callback, t, u, self%band_work)) then
         band = self%band_work
      else
         call band_differences(self, difference_g, t, u, band)
      end if
   end subroutine c_jac_g_band

   !> Whether J comes from differences of F = f + g: both parts given, neither Jacobian.
   logical function differences_of_rhs(self)
      type(c_problem_type), intent(in) :: self
      differences_of_rhs = c_associated(self%f_callback) .and. c_associated(self%g_callback) .and. &
         .not. (c_associated(self%jac_f_callback) .or. c_associated(self%jac_g_callback))
   end function differences_of_rhs

   !> Dense J: differences of f + g (one call of each per column) when neither Jacobian is
   !> given, else jac_f + jac_g (the library's sum, with its work matrix).
   subroutine c_jac(self, t, u, jac)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      if (differences_of_rhs(self)) then
         call dense_differences(self, difference_rhs, t, u, jac)
      else
         call full_jacobian(self, t, u, jac)
      end if
   end subroutine c_jac

   !> Band J: grouped differences of f + g when neither Jacobian is given, else
   !> jac_f_band + jac_g_band.
   subroutine c_jac_band(self, t, u, band)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: band(:, :)
      if (differences_of_rhs(self)) then
         call band_differences(self, difference_rhs, t, u, band)
      else
         call full_band_jacobian(self, t, u, band)
      end if
   end subroutine c_jac_band

   !> Dense J given F(t, u): differences from that F when neither Jacobian is given.
   subroutine c_jac_with_rhs(self, t, u, value, jac)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:), value(:)
      real(dp), intent(out) :: jac(:, :)
      if (differences_of_rhs(self)) then
         call dense_differences(self, difference_rhs, t, u, jac, value)
      else
         call self%jac(t, u, jac)
      end if
   end subroutine c_jac_with_rhs

   !> Band J given F(t, u) (see c_jac_with_rhs).
   subroutine c_jac_band_with_rhs(self, t, u, value, band)
      class(c_problem_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:), value(:)
      real(dp), intent(out) :: band(:, :)
      if (differences_of_rhs(self)) then
         call band_differences(self, difference_rhs, t, u, band, value)
      else
         call self%jac_band(t, u, band)
      end if
   end subroutine c_jac_band_with_rhs

end module taylorode_interfaces_c
