!> Memory an integration cannot get: it ends with status_out_of_memory and a message
!> that names the array and its size, the last good state and the statistics
!> returned, never a stop of the program. Each test here failed before the fix it
!> guards (the reliability issue's item 1).
module test_memory
   use testdrive, only: new_unittest, unittest_type, error_type, check, skip_test
   use test_support, only: scratch, run_type, run_command, stat_message, c_create, c_free, c_set_functions, &
      c_set_bandwidths, c_set_tolerance_vectors, c_integrate, message_of, legacy_no_jacobian
   use taylorode, only: dp, ode_problem, ode_problem_fd, scheme_type, new_scheme, scheme_names, integrate, &
      integrate_fixed, status_type, status_ok, status_out_of_memory, status_nonfinite, status_invalid_argument, &
      integrator_options_type, integration_stats_type, step_history_type, event_functions_type, &
      matrix_structure_type, band_structure, dense_structure
   use taylorode_base_strings, only: format_integer
   use taylorode_interfaces_legacy, only: legacy_solve, legacy_no_mass
   use, intrinsic :: iso_c_binding, only: c_int, c_long_long, c_double, c_ptr, c_funptr, c_char, c_null_char, &
      c_null_ptr, c_null_funptr, c_funloc, c_loc, c_f_pointer, c_associated
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: collect_memory

   !> Unknowns of a dense problem whose Newton matrix no address space holds (8 n^2 = 2e14 bytes)
   integer, parameter :: huge_order = 5000000
   !> Requests of at least this many bytes fail in the sweeps: above what the Fortran
   !> run-time asks for a formatted write (4176 bytes), at most one state vector below
   integer(c_long_long), parameter :: large_request = 8192_c_long_long
   !> Unknowns of the sweeps' band problems (a state vector: 16384 bytes, above large_request)
   !> and dense ones (their matrices are: 32768 bytes)
   integer, parameter :: band_order = 2048, dense_order = 64

   interface
      !> Heap allocations of this program so far (test/malloc_counter.c; -1 under ASan)
      function allocation_count() result(count) bind(c, name="taylorode_allocation_count")
         import :: c_long_long
         integer(c_long_long) :: count
      end function allocation_count
      !> From now on, requests of at least min_size bytes fail after `allowed` were granted (min_size < 0: none)
      subroutine fail_allocations(min_size, allowed) bind(c, name="taylorode_fail_allocations")
         import :: c_long_long
         integer(c_long_long), value :: min_size, allowed
      end subroutine fail_allocations
      !> Requests of at least that size since fail_allocations
      function large_allocations() result(count) bind(c, name="taylorode_large_allocations")
         import :: c_long_long
         integer(c_long_long) :: count
      end function large_allocations
   end interface

   !> u_i' = -u_i / 2 (f) - u_i + (u_(i-1) + u_(i+1)) / 10 (g), Jacobians by differences;
   !> a declared band (1, 1) when `band`, else dense
   type, extends(ode_problem_fd) :: chain_type
      logical :: band = .false.
   contains
      procedure :: f => chain_f
      procedure :: g => chain_g
      procedure :: jacobian_structure => chain_structure
   end type chain_type

   !> One event function: u_1 - 0.99 (crossed early in the chain's decay)
   type, extends(event_functions_type) :: crossing_type
   contains
      procedure :: evaluate => crossing_evaluate
   end type crossing_type

   !> The ways of running an integration whose large allocations are made to fail:
   !> integrate on the chain with every output the integrator offers (dense output, a
   !> history with states, events, tolerance vectors, a nonnegative mask), integrate_fixed,
   !> the C interface (bandwidths, tolerance vectors, integrate), the legacy interface
   !> (tolerance vectors, SOLOUT)
   integer, parameter :: run_integrate = 1, run_fixed = 2, run_c = 3, run_legacy = 4

   !> One case of the sweep
   type :: memory_case_type
      !> run_integrate, run_fixed, run_c or run_legacy
      integer :: way = run_integrate
      !> The scheme
      character(len=16) :: scheme_name = "i-t-2"
      !> A band problem (else dense)
      logical :: band = .true.
   end type memory_case_type

contains

   !> Collect all exported unit tests
   subroutine collect_memory(testsuite)
      type(unittest_type), allocatable, intent(out) :: testsuite(:)
      testsuite = [ &
         new_unittest("dense-newton-matrix-too-large", test_huge_dense), &
         new_unittest("c-huge-n-is-a-status", test_c_huge), &
         new_unittest("c-band-rows-beyond-int-refused", test_c_band_rows), &
         new_unittest("every-failed-allocation-a-status", test_every_allocation), &
         new_unittest("band-problem-under-address-limit", test_address_limit), &
         new_unittest("work-arrays-only-where-used", test_work_arrays_where_used) &
         ]
   end subroutine collect_memory

   !> A dense problem of 5e6 unknowns, whose Newton matrix (2e14 bytes) exceeds any
   !> address space: every scheme (the explicit ones keep Jacobian matrices too) ends
   !> with status_out_of_memory, a message naming the matrix and its size, the initial
   !> state and time returned. Before: "Error allocating 200000000000000 bytes", exit 1.
   subroutine test_huge_dense(error)
      type(error_type), allocatable, intent(out) :: error
      type(chain_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp), allocatable :: u(:)
      integer :: k
      allocate (u(huge_order))
      do k = 1, size(scheme_names)
         call new_scheme(trim(scheme_names(k)), scheme, stat)
         u = 1.0_dp
         call integrate(problem, scheme, 0.0_dp, 1.0_dp, u, integrator_options_type(), stats, stat)
         call check(error, stat%code, status_out_of_memory, trim(scheme_names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         ! (the stacked matrices of the second-order semi-implicit schemes are of order 2n)
         call check(error, index(stat_message(stat), "out of memory: cannot allocate a dense matrix (5000000 x "// &
            "5000000, 200000000000000 bytes)") > 0 .or. index(stat_message(stat), "out of memory: cannot "// &
            "allocate a dense matrix (10000000 x 10000000, 800000000000000 bytes)") > 0, &
            trim(scheme_names(k))//": "//stat_message(stat))
         if (allocated(error)) return
         call check(error, stats%t_reached == 0.0_dp .and. all(u == 1.0_dp), trim(scheme_names(k))// &
            ": the initial state should come back")
         if (allocated(error)) return
      end do
   end subroutine test_huge_dense

   !> With n = INT_MAX, bandwidths whose rows lower + upper + 1 pass INT_MAX are refused
   !> (TAYLORODE_INVALID_ARGUMENT); the sum overflowed, and 2^30 and 2^30 - 1 were taken
   !> (TAYLORODE_OK) with a work array of no entries.
   subroutine test_c_band_rows(error)
      type(error_type), allocatable, intent(out) :: error
      type(c_ptr) :: ode
      integer(c_int) :: status
      ode = c_create("radau5"//c_null_char, huge(0_c_int), status)
      call check(error, status == status_ok .and. c_associated(ode), "taylorode_create with n = INT_MAX")
      if (allocated(error)) return
      status = c_set_bandwidths(ode, 2_c_int**30, 2_c_int**30 - 1_c_int)
      call check(error, status == status_invalid_argument .and. index(message_of(ode), "INT_MAX") > 0, &
         "lower = 2^30, upper = 2^30 - 1: "//format_integer(int(status))//": "//message_of(ode))
      call c_free(ode)
   end subroutine test_c_band_rows

   !> taylorode_create takes any n (it allocates nothing that grows with n); a band too
   !> wide to allocate and an integration whose dense matrices cannot be allocated are
   !> TAYLORODE_OUT_OF_MEMORY with a message, the state untouched. Before: the
   !> integration stopped the program ("Error allocating ... bytes").
   subroutine test_c_huge(error)
      type(error_type), allocatable, intent(out) :: error
      type(c_ptr) :: ode
      integer(c_int) :: status
      integer(c_int), target :: n
      real(c_double), allocatable :: u(:)
      n = huge_order
      ode = c_create("radau5"//c_null_char, n, status)
      call check(error, status == status_ok .and. c_associated(ode), "taylorode_create with n = 5e6")
      if (allocated(error)) return
      status = c_set_functions(ode, c_null_funptr, c_funloc(c_chain), c_null_funptr, c_null_funptr, c_loc(n))
      ! bandwidths of 2e6: a work array of 1.6e14 bytes
      status = c_set_bandwidths(ode, 2000000_c_int, 2000000_c_int)
      call check(error, status == status_out_of_memory .and. index(message_of(ode), "out of memory: cannot "// &
         "allocate the band Jacobians' work array (4000001 x 5000000") > 0, "taylorode_set_bandwidths: "// &
         format_integer(int(status))//": "//message_of(ode))
      if (allocated(error)) then
         call c_free(ode)
         return
      end if
      allocate (u(n))
      u = 1.0_dp
      status = c_integrate(ode, 0.0_dp, 1.0_dp, u)
      call check(error, status == status_out_of_memory .and. index(message_of(ode), "out of memory: cannot "// &
         "allocate a dense matrix (5000000 x 5000000") > 0 .and. all(u == 1.0_dp), "taylorode_integrate: "// &
         format_integer(int(status))//": "//message_of(ode))
      call c_free(ode)
   end subroutine test_c_huge

   !> Every large allocation of an integration, made to fail in turn (the k-th request
   !> of at least 8192 bytes and every one after it, as when memory runs out, k = 0, 1,
   !> ... until a run gets all it asks for; test/malloc_counter.c): each run ends with
   !> status_out_of_memory and a message, or succeeds, and returns a good state. Every
   !> scheme on a band problem of 2048 unknowns (grouped differences, the problem's own
   !> work arrays) with dense output, a history, events, tolerance vectors and a
   !> nonnegative mask, and on a dense one of 64 (only its matrices are that large);
   !> integrate_fixed; the C and the legacy interfaces. Before: the first allocation
   !> without stat= stopped the program.
   subroutine test_every_allocation(error)
      type(error_type), allocatable, intent(out) :: error
      integer :: k
      if (allocation_count() < 0) then
         call skip_test(error, "allocations cannot be made to fail under AddressSanitizer")
         return
      end if
      do k = 1, size(scheme_names)
         call sweep(error, memory_case_type(run_integrate, scheme_names(k), .true.), "integrate, band")
         if (allocated(error)) return
         call sweep(error, memory_case_type(run_integrate, scheme_names(k), .false.), "integrate, dense")
         if (allocated(error)) return
      end do
      call sweep(error, memory_case_type(run_fixed, "i-t-2", .true.), "integrate_fixed")
      if (allocated(error)) return
      call sweep(error, memory_case_type(run_c, "radau5", .true.), "C interface")
      if (allocated(error)) return
      call sweep(error, memory_case_type(run_legacy, "i-t-2", .true.), "legacy interface")
   end subroutine test_every_allocation

   !> The runs of one case with the large requests failing after 0, 1, 2, ... of them.
   subroutine sweep(error, case, what)
      type(error_type), allocatable, intent(out) :: error
      type(memory_case_type), intent(in) :: case
      character(len=*), intent(in) :: what
      character(len=:), allocatable :: label, message
      integer(c_long_long) :: allowed, requests
      integer :: code
      logical :: state_good
      label = what//", "//trim(case%scheme_name)
      do allowed = 0, 10000
         call run_case(case, allowed, code, message, requests, state_good)
         if (code == status_ok) then
            call check(error, requests <= allowed, label//": succeeded although request "// &
               format_integer(int(allowed + 1))//" failed")
            if (allocated(error)) return
            call check(error, allowed > 0, label//": no large request to fail")
            return
         end if
         call check(error, code == status_out_of_memory .and. index(message, "out of memory: cannot allocate") > 0, &
            label//", request "//format_integer(int(allowed + 1))//" failing: status "//format_integer(code)//": "// &
            message)
         if (allocated(error)) return
         call check(error, state_good, label//", request "//format_integer(int(allowed + 1))// &
            " failing: the state returned is not the last good one")
         if (allocated(error)) return
      end do
      call check(error, .false., label//": still failing after 10000 requests")
   end subroutine sweep

   !> One run of a case with the large requests failing after `allowed` of them: its
   !> outcome as a status code and message, the large requests it made, and whether the
   !> state it returned is a good one (finite, in (0, 1] as the chain's solution, the
   !> initial state when it did not advance). Everything the test itself needs is
   !> allocated before the requests start to fail.
   subroutine run_case(case, allowed, code, message, requests, state_good)
      type(memory_case_type), intent(in) :: case
      integer(c_long_long), intent(in) :: allowed
      integer, intent(out) :: code
      character(len=:), allocatable, intent(out) :: message
      integer(c_long_long), intent(out) :: requests
      logical, intent(out) :: state_good
      real(dp), parameter :: t_end = 0.04_dp
      type(chain_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      type(step_history_type) :: history
      type(crossing_type) :: events
      type(c_ptr) :: ode
      real(dp), allocatable :: u(:), u_out(:, :), tolerances(:)
      real(dp) :: t_out(3), t_reached, h, work(20), rpar(1)
      integer(c_int), target :: n
      integer :: iwork(20), ipar(1), idid
      n = merge(band_order, dense_order, case%band)
      problem%band = case%band
      call new_scheme(trim(case%scheme_name), scheme, stat)
      allocate (u(n), tolerances(n), u_out(n, size(t_out)), options%rtol_vector(n), options%atol_vector(n), &
         options%nonnegative(n))
      u = 1.0_dp
      tolerances = 1.0e-3_dp
      t_reached = 0.0_dp
      options%rtol_vector = tolerances
      options%atol_vector = tolerances
      options%nonnegative = .true.
      options%history_states = .true.
      events%count = 1
      t_out = [0.01_dp, 0.02_dp, 0.03_dp]
      h = 0.0_dp
      work = 0.0_dp
      iwork = 0
      if (case%way == run_c) then
         ode = c_create(trim(case%scheme_name)//c_null_char, n, idid)
         idid = c_set_functions(ode, c_null_funptr, c_funloc(c_chain), c_null_funptr, c_null_funptr, c_loc(n))
      end if

      call fail_allocations(large_request, allowed)
      select case (case%way)
      case (run_integrate)
         call integrate(problem, scheme, 0.0_dp, t_end, u, options, stats, stat, history, t_out, u_out, &
            events=events)
         t_reached = stats%t_reached
      case (run_fixed)
         call integrate_fixed(problem, scheme, 0.0_dp, t_end, 4, u, stat, t_reached)
      case (run_c)
         code = c_set_bandwidths(ode, 1_c_int, 1_c_int)
         if (code == status_ok) code = c_set_tolerance_vectors(ode, tolerances, tolerances)
         if (code == status_ok) code = c_integrate(ode, 0.0_dp, t_end, u)
      case default
         call legacy_solve(trim(case%scheme_name), n, legacy_chain, legacy_chain, .false., t_reached, u, t_end, h, &
            tolerances, tolerances, 1, legacy_no_jacobian, 0, legacy_no_jacobian, 0, 1, 1, legacy_no_mass, 0, 1, &
            1, legacy_watch, 1, work, 20, iwork, 20, rpar, ipar, idid)
      end select
      requests = large_allocations()
      call fail_allocations(-1_c_long_long, 0_c_long_long)

      select case (case%way)
      case (run_integrate, run_fixed)
         code = stat%code
         message = stat_message(stat)
      case (run_c)
         message = message_of(ode)
         call c_free(ode)
      case default
         ! RADAU5's IDID: 1 success, -8 out of memory
         code = merge(status_ok, -1, idid == 1)
         if (idid == -8) code = status_out_of_memory
         message = "IDID = "//format_integer(idid)
         if (idid == -8) message = "out of memory: cannot allocate ("//message//")"
      end select
      state_good = all(ieee_is_finite(u)) .and. all(u > 0.0_dp .and. u <= 1.0_dp) .and. t_reached >= 0.0_dp .and. &
         t_reached <= t_end
      if (t_reached == 0.0_dp .and. case%way /= run_c) state_good = state_good .and. all(u == 1.0_dp)
   end subroutine run_case

   !> A run allocates the work arrays of the state's size that its problem and options
   !> use, no others: on the band chain (2048 unknowns, a state of 16384 bytes, above
   !> large_request), a problem declared to depend on t costs ex-t-2 and i-t-2 one array
   !> more than the same problem declared autonomous (dF/dt), si-t-2 two (df/dt, dg/dt);
   !> i-t-2 extrapolating Newton's starting guess two more than without (the last
   !> accepted step's ends), radau5 none (it extrapolates its own stages); radau5 from a
   !> given h0 one fewer than when it estimates the first step (that estimate's work
   !> space), i-t-2 extrapolating as many (the array is its guess). Before, every run
   !> allocated them all.
   subroutine test_work_arrays_where_used(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: names(3) = [character(len=8) :: "ex-t-2", "i-t-2", "si-t-2"]
      integer, parameter :: time_arrays(3) = [1, 1, 2]
      integer(c_long_long) :: with, without
      integer :: k
      if (allocation_count() < 0) then
         call skip_test(error, "allocations are not counted under AddressSanitizer")
         return
      end if
      do k = 1, size(names)
         with = large_requests(trim(names(k)), autonomous=.false., extrapolate=.true.)
         without = large_requests(trim(names(k)), autonomous=.true., extrapolate=.true.)
         call check(error, with - without == time_arrays(k), trim(names(k))//": "//format_integer(int(with))// &
            " large requests for a problem that depends on t, "//format_integer(int(without))//" for an autonomous one")
         if (allocated(error)) return
      end do
      with = large_requests("i-t-2", autonomous=.true., extrapolate=.true.)
      without = large_requests("i-t-2", autonomous=.true., extrapolate=.false.)
      call check(error, with - without == 2, "i-t-2: "//format_integer(int(with))//" large requests extrapolating "// &
         "Newton's guess, "//format_integer(int(without))//" without")
      if (allocated(error)) return
      with = large_requests("radau5", autonomous=.true., extrapolate=.true.)
      without = large_requests("radau5", autonomous=.true., extrapolate=.false.)
      call check(error, with == without, "radau5: "//format_integer(int(with))//" large requests with the option "// &
         "extrapolate_newton_start, "//format_integer(int(without))//" without")
      if (allocated(error)) return
      ! the first step size's work space only when h is estimated (h0 = 0); an extrapolating
      ! i-t-2 holds that array as Newton's guess anyway
      with = large_requests("radau5", autonomous=.true., extrapolate=.true.)
      without = large_requests("radau5", autonomous=.true., extrapolate=.true., h0=1.0e-4_dp)
      call check(error, with - without == 1, "radau5: "//format_integer(int(with))//" large requests estimating "// &
         "the first step, "//format_integer(int(without))//" from a given h0")
      if (allocated(error)) return
      with = large_requests("i-t-2", autonomous=.true., extrapolate=.true.)
      without = large_requests("i-t-2", autonomous=.true., extrapolate=.true., h0=1.0e-4_dp)
      call check(error, with == without, "i-t-2 extrapolating: "//format_integer(int(with))//" large requests "// &
         "estimating the first step, "//format_integer(int(without))//" from a given h0")
   end subroutine test_work_arrays_where_used

   !> Requests of at least large_request bytes made by one integration of the band chain
   !> with a new scheme object
   function large_requests(scheme_name, autonomous, extrapolate, h0) result(requests)
      character(len=*), intent(in) :: scheme_name
      logical, intent(in) :: autonomous, extrapolate
      !> The first step (default 0: estimated)
      real(dp), intent(in), optional :: h0
      integer(c_long_long) :: requests
      type(chain_type) :: problem
      class(scheme_type), allocatable :: scheme
      type(integrator_options_type) :: options
      type(integration_stats_type) :: stats
      type(status_type) :: stat
      real(dp) :: u(band_order)
      problem%band = .true.
      problem%autonomous = autonomous
      options%extrapolate_newton_start = extrapolate
      if (present(h0)) options%h0 = h0
      call new_scheme(scheme_name, scheme, stat)
      u = 1.0_dp
      call fail_allocations(large_request, huge(1_c_long_long))
      call integrate(problem, scheme, 0.0_dp, 0.04_dp, u, options, stats, stat)
      requests = large_allocations()
      call fail_allocations(-1_c_long_long, 0_c_long_long)
      if (stat%code /= status_ok) requests = -1
   end function large_requests

   !> The band problem of test/c_out_of_memory.c, built against the installation and run
   !> under `ulimit -v` at its own peak address space (small problem) plus 300 MB: the
   !> small problem still succeeds; every scheme on a band problem that needs more, and
   !> a dense one of n = 5e6, ends with TAYLORODE_OUT_OF_MEMORY and a message; the program
   !> exits normally. Before: "Error allocating ... bytes", exit status 1.
   subroutine test_address_limit(error)
      type(error_type), allocatable, intent(out) :: error
      character(len=*), parameter :: program = scratch//"/memory/c_out_of_memory"
      type(run_type) :: run
      character(len=1024) :: prefix
      integer :: length, status, k, peak, io, failures
      logical :: found
      call get_environment_variable("TAYLORODE_PREFIX", prefix, length, status)
      found = status == 0 .and. length > 0
      if (found) inquire (file=prefix(:length)//"/lib/libtaylorode.so", exist=found)
      if (.not. found) then
         call skip_test(error, "needs an installed library: run `make test` (it installs into build/install) "// &
            "or set TAYLORODE_PREFIX")
         return
      end if
      call run_command("mkdir -p "//scratch//"/memory && export PKG_CONFIG_PATH="//prefix(:length)// &
         "/lib/pkgconfig; cc -Wall -Wextra -Werror -DTAYLORODE_MEMORY_PROGRAM test/c_out_of_memory.c "// &
         "$(pkg-config --cflags --libs taylorode) -lm -o "//program//" && "//program//" measure", run)
      peak = 0
      if (run%exit_status == 0 .and. size(run%stdout) > 0) then
         if (index(run%stdout(size(run%stdout))%text, "peak ") == 1) &
            read (run%stdout(size(run%stdout))%text(6:), *, iostat=io) peak
      end if
      call check(error, peak > 0, "the C program could not be built or measured (exit status "// &
         format_integer(run%exit_status)//")")
      if (allocated(error)) return
      call run_command("( ulimit -v "//format_integer(peak + 300000)//"; exec "//program//" )", run)
      call check(error, run%exit_status == 0 .and. size(run%stdout) == 8, "under ulimit -v "// &
         format_integer(peak + 300000)//" kB: exit status "//format_integer(run%exit_status)//", "// &
         format_integer(size(run%stdout))//" lines"//last_lines(run))
      if (allocated(error)) return
      call check(error, index(run%stdout(1)%text, "status 0:") > 0, "the small problem: "//run%stdout(1)%text)
      if (allocated(error)) return
      failures = 0
      do k = 2, size(run%stdout)
         if (index(run%stdout(k)%text, "status 12:") == 0 .or. &
            index(run%stdout(k)%text, "out of memory: cannot allocate") == 0) failures = failures + 1
      end do
      call check(error, failures == 0, "not TAYLORODE_OUT_OF_MEMORY with its message:"//last_lines(run))
   end subroutine test_address_limit

   !> The output of a run, one line each, after a new line.
   function last_lines(run) result(text)
      type(run_type), intent(in) :: run
      character(len=:), allocatable :: text
      integer :: k
      text = ""
      do k = 1, size(run%stdout)
         text = text//new_line("a")//run%stdout(k)%text
      end do
      do k = 1, size(run%stderr)
         text = text//new_line("a")//run%stderr(k)%text
      end do
   end function last_lines

   subroutine chain_f(self, t, u, dudt)
      class(chain_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      dudt = -0.5_dp*u
   end subroutine chain_f

   subroutine chain_g(self, t, u, dudt)
      class(chain_type), intent(inout) :: self
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: dudt(:)
      call chain_values(u, dudt)
   end subroutine chain_g

   !> g of the chain: dudt_i = -u_i + (u_(i-1) + u_(i+1)) / 10
   pure subroutine chain_values(u, dudt)
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      integer :: i, n
      n = size(u)
      do i = 1, n
         dudt(i) = -u(i)
         if (i > 1) dudt(i) = dudt(i) + 0.1_dp*u(i - 1)
         if (i < n) dudt(i) = dudt(i) + 0.1_dp*u(i + 1)
      end do
   end subroutine chain_values

   function chain_structure(self, n) result(structure)
      class(chain_type), intent(in) :: self
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      if (self%band) then
         structure = band_structure(1, 1)
      else
         structure = dense_structure()
      end if
   end function chain_structure

   subroutine crossing_evaluate(self, t, u, values)
      class(crossing_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: values(:)
      values(1) = u(1) - 0.99_dp
   end subroutine crossing_evaluate

   !> The chain's g for the C interface (user data: n)
   integer(c_int) function c_chain(t, u, dudt, user_data) bind(c)
      real(c_double), value :: t
      real(c_double), intent(in) :: u(*)
      real(c_double), intent(out) :: dudt(*)
      type(c_ptr), value :: user_data
      integer(c_int), pointer :: n
      call c_f_pointer(user_data, n)
      call chain_values(u(:n), dudt(:n))
      c_chain = 0
   end function c_chain

   !> The chain's g as FCN(N, X, Y, F, RPAR, IPAR)
   subroutine legacy_chain(n, x, y, f, rpar, ipar)
      integer :: n
      real(dp) :: x, y(n), f(n), rpar(*)
      integer :: ipar(*)
      call chain_values(y, f)
   end subroutine legacy_chain

   !> A SOLOUT that interpolates each step in its middle (TAYLORODE_CONTR's data) and goes on
   subroutine legacy_watch(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
      integer :: nr, lrc, n, ipar(*), irtrn
      real(dp) :: xold, x, y(n), cont(lrc), rpar(*)
      irtrn = 0
      if (.not. all(ieee_is_finite(cont(:lrc)))) irtrn = -1
   end subroutine legacy_watch

end module test_memory
