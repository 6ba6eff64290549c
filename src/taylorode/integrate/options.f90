!> Options of the adaptive integrator, their defaults and their validation.
module taylorode_integrate_options
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch
   use taylorode_base_memory, only: out_of_memory, real_bytes
   use taylorode_integrate_controller, only: controller_i, controller_pi, controller_pid, default_kappa, &
      controller_predictive, controller_auto
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: integrator_options_type, scalar_options_type, copy_options, paper_options, validate_options, &
      error_weight_type
   public :: norm_max, norm_rms, advance_scheme, advance_high, advance_low
   public :: estimate_auto, estimate_embedded, estimate_doubling, estimate_defect

   !> err = max_i |delta_i| / w_i (the paper's)
   integer, parameter :: norm_max = 1
   !> err = sqrt(mean_i (delta_i / w_i)^2) (CVODE, ARKODE)
   integer, parameter :: norm_rms = 2
   !> Advance with the scheme the user chose
   integer, parameter :: advance_scheme = 0
   !> Advance with the higher-order member of the embedded pair
   integer, parameter :: advance_high = 1
   !> Advance with the lower-order member of the embedded pair
   integer, parameter :: advance_low = 2
   !> The scheme's best: its embedded pair when that estimates the error of the
   !> solution it returns (radau5), its own estimate of its step's error when it has
   !> one (si-t-2: estimate_defect), step doubling otherwise; the embedded pair
   !> whenever `advance` chooses a member of it
   integer, parameter :: estimate_auto = 0
   !> The difference of the embedded pair (the paper's): for the Taylor pairs it
   !> estimates the error of the lower-order member
   integer, parameter :: estimate_embedded = 1
   !> Step doubling (Richardson): two steps of h/2 and one step of h, err =
   !> |U_{h/2,h/2} - U_h| / (2^p - 1) estimates the error of U_{h/2,h/2} (p: the
   !> scheme's order on nonlinear problems); the solution advances with U_{h/2,h/2},
   !> or with its local extrapolation (options%local_extrapolation)
   integer, parameter :: estimate_doubling = 2
   !> The scheme's own estimate of the local error of its step (`step_error`; si-t-2:
   !> 2/3 of the trapezoidal defect U1 - U0 - h/2 (F0 + F1), corrected for the
   !> curvature of g and multiplied by the inverse of the step's Newton matrix): one
   !> step per attempt, one factorization kept; the solution advances with U1, or
   !> with U1 minus the estimate (options%local_extrapolation)
   integer, parameter :: estimate_defect = 3
   !> Largest controller exponent q accepted
   real(dp), parameter :: max_q = 20.0_dp

   !> Error weights of your own (as ARKODE's WFtolerances): extend it and write
   !> `weights`; the integrator's error test and Newton tolerances then use them
   type, abstract :: error_weight_type
   contains
      !> w_i > 0 for the step from u_old to u_new (the error test is |delta_i| <= w_i)
      procedure(error_weight_interface), deferred :: weights
   end type error_weight_type

   abstract interface
      !> Weights for the step from u_old to u_new; every w_i must be positive and finite.
      subroutine error_weight_interface(self, u_old, u_new, w)
         import :: error_weight_type, dp
         !> The weight function (carries your data)
         class(error_weight_type), intent(in) :: self
         !> States at both ends of the step (equal before the step is taken, and for a
         !> scheme that weighs with the start of the step alone: radau5)
         real(dp), intent(in) :: u_old(:), u_new(:)
         !> The weights
         real(dp), intent(out) :: w(:)
      end subroutine error_weight_interface
   end interface

   !> The settings of `integrate` that are single values: every one but the
   !> per-component settings of integrator_options_type, which extends it (so that a
   !> copy of these is one assignment that allocates nothing).
   type :: scalar_options_type
      !> Relative tolerance (>= 0)
      real(dp) :: rtol = 1.0e-6_dp
      !> Absolute tolerance for every component (>= 0; rtol and atol not both 0)
      real(dp) :: atol = 1.0e-6_dp
      !> norm_max or norm_rms
      integer :: norm = norm_max
      !> controller_i, controller_pi, controller_pid, controller_predictive, or
      !> controller_auto: the scheme's preference (predictive for radau5, I for the others)
      integer :: controller = controller_auto
      !> Safety factor kappa in (0, 1]
      real(dp) :: kappa = default_kappa
      !> Error estimate: estimate_auto, estimate_embedded, estimate_doubling or estimate_defect
      integer :: error_estimate = estimate_auto
      !> Advance with the value the error estimate corrects: with step doubling the
      !> Richardson extrapolation U_{h/2,h/2} + (U_{h/2,h/2} - U_h) / (2^p - 1), of order
      !> p + 1, whose error err bounds (the stability function becomes
      !> (2^p R(z/2)^2 - R(z)) / (2^p - 1): for the L-stable schemes still L-stable and
      !> A(89 deg)-stable); with estimate_defect U1 minus the estimate, of order 3 (on
      !> the linear test R - 2/3 (R (1 - s/2) - (1 + s/2)) / M, s = z + w, M the Newton
      !> matrix: si-t-2 stays L-stable in w, A(89 deg)-stable in w); off: with
      !> U_{h/2,h/2} or U1
      logical :: local_extrapolation = .true.
      !> Order exponent q of the controller, in [1, 20]; 0 takes it from the estimate
      !> (step doubling: the scheme's order + 1; embedded pair: lower order + 1)
      real(dp) :: q = 0.0_dp
      !> First step size; 0 chooses it from the initial data (Hairer's HINIT: first and
      !> second derivatives at U0, one Euler step)
      real(dp) :: h0 = 0.0_dp
      !> Smallest step size allowed (0: only the roundoff limit of t applies)
      real(dp) :: h_min = 0.0_dp
      !> Smallest step size allowed relative to |t|, in [0, 1) (never below the roundoff
      !> of t, 2 epsilon |t|; the legacy entry sets RADAU5's 10 UROUND)
      real(dp) :: h_min_relative = 0.0_dp
      !> Largest step size allowed
      real(dp) :: h_max = huge(1.0_dp)
      !> Largest factor h_new / h after a step (0: no limit)
      real(dp) :: max_growth = 5.0_dp
      !> Smallest factor h_new / h after a step (0: no limit)
      real(dp) :: min_shrink = 0.2_dp
      !> Attempted steps allowed (accepted and rejected)
      integer(i8) :: max_steps = 1000000_i8
      !> Newton iterations allowed per nonlinear system (at least 1); 0: the scheme's
      !> own, 7 for radau5 (RADAU5's NIT), 10 for the others
      integer :: max_newton_iterations = 0
      !> Keep factored Newton matrices across steps while h changes by at most 20 %
      !> and Newton contracts fast (0.1 or better); off: one factorization per solve
      logical :: reuse_newton_matrix = .true.
      !> Newton stops when its error is below this fraction of the weights w_i (usually
      !> below 1: RADAU5's FNEWT, WORK(4)); 0 lets the scheme choose (Hairer's FNEWT =
      !> max(10 eps / rtol, min(0.03, sqrt(rtol))); with the paper's Newton test 1e-4)
      real(dp) :: newton_fraction = 0.0_dp
      !> Newton's stop test estimates the error left from the contraction (RADAU5's
      !> test); off: the last increment must be below the tolerance (the paper's)
      logical :: newton_error_estimate = .true.
      !> Newton matrices with every term of the scheme's equation (i-t-2: the second
      !> derivatives of F along F, by differencing the Jacobians); off: the paper's
      !> matrices, which omit them (Newton then converges more slowly or, with long
      !> steps on stiff quadratic problems, not at all)
      logical :: exact_newton_matrix = .true.
      !> Start Newton's method from the extrapolation of the last accepted step (the
      !> line through its two states); off: from the state at the start of the step
      logical :: extrapolate_newton_start = .true.
      !> Consecutive failed attempts (Newton failure, NaN/Inf values, a rejected
      !> evaluation) before giving up; 0: no limit, as RADAU5 (a failed attempt is retried
      !> with a smaller step until it succeeds or the step size falls below h_min or the
      !> roundoff of t: status_step_underflow, the last failure named in the message)
      integer :: max_failures = 0
      !> advance_scheme, advance_high or advance_low (with the embedded estimate; auto
      !> then means embedded)
      integer :: advance = advance_scheme
      !> With a step history: also record the state after every attempt
      logical :: history_states = .false.
      !> Measure the call's CPU and wall-clock seconds (stats%cpu_seconds,
      !> stats%wall_seconds); off: both are 0 and the call saves its two CPU-time
      !> system calls (about a microsecond, which matters only to many short calls)
      logical :: measure_time = .true.
   end type scalar_options_type

   !> Settings of `integrate`: the single values of scalar_options_type and the
   !> per-component ones. Weights: w_i = atol_i + rtol_i * max(|U_i^n|, |U_i^{n+1}|)
   !> (|U_i^n| alone for radau5, as RADAU5; or your own `error_weights`).
   type, extends(scalar_options_type) :: integrator_options_type
      !> Relative tolerance per component (RADAU5's ITOL = 1); when allocated it replaces `rtol`
      real(dp), allocatable :: rtol_vector(:)
      !> Absolute tolerance per component; when allocated it replaces `atol`
      real(dp), allocatable :: atol_vector(:)
      !> Weights of your own; when allocated they replace rtol and atol
      class(error_weight_type), allocatable :: error_weights
      !> Components that must stay >= 0 (one entry per unknown; unallocated: none), as
      !> concentrations must: a step that makes one negative by at most a tenth of the
      !> tolerance (in the error norm) has it set to 0, a step that makes one more
      !> negative is rejected and retried shorter (the fraction of the step at which it
      !> would reach 0). Without it a loose atol lets a concentration below atol go
      !> negative where the equations are unstable (Robertson: y1 < 0 blows up to 1e7)
      logical, allocatable :: nonnegative(:)
   end type integrator_options_type

contains

   !> The settings of the paper's Van der Pol experiment (METHODS.md section 5):
   !> rtol 0, atol 1e-5, max norm, I controller, kappa 0.9, h0 1e-2, no h_max and no
   !> growth or shrink limits, the embedded pair's error estimate, the paper's Newton
   !> matrices, Newton started from the state at the start of the step and stopped by
   !> its last increment. q is left to the scheme pair: 2 for
   !> every pair of the paper (its setting), 4 for radau5.
   pure function paper_options() result(options)
      type(integrator_options_type) :: options
      options%rtol = 0.0_dp
      options%atol = 1.0e-5_dp
      options%norm = norm_max
      options%controller = controller_i
      options%kappa = default_kappa
      options%h0 = 1.0e-2_dp
      options%h_max = huge(1.0_dp)
      options%max_growth = 0.0_dp
      options%min_shrink = 0.0_dp
      options%max_steps = 100000000_i8
      options%error_estimate = estimate_embedded
      options%extrapolate_newton_start = .false.
      options%newton_error_estimate = .false.
      options%exact_newton_matrix = .false.
   end function paper_options

   !> destination = source, without the stop a failed allocation would be: the
   !> per-component settings are allocated with a status (status_out_of_memory leaves
   !> destination as it was), the single values copied in one assignment that allocates
   !> nothing. (Error weights of your own are copied by an allocation with source=, which
   !> copies their own allocatable components, if they have any, without a status.)
   subroutine copy_options(source, destination, stat)
      !> The options to copy
      type(integrator_options_type), intent(in) :: source
      !> The copy
      type(integrator_options_type), intent(inout) :: destination
      !> status_out_of_memory when the per-component settings cannot be allocated
      type(status_type), intent(inout) :: stat
      real(dp), allocatable :: rtol(:), atol(:)
      logical, allocatable :: nonnegative(:)
      class(error_weight_type), allocatable :: weights
      integer :: memory
      memory = 0
      if (allocated(source%rtol_vector)) allocate (rtol, mold=source%rtol_vector, stat=memory)
      if (memory == 0 .and. allocated(source%atol_vector)) allocate (atol, mold=source%atol_vector, stat=memory)
      if (memory == 0 .and. allocated(source%nonnegative)) &
         allocate (nonnegative, mold=source%nonnegative, stat=memory)
      if (memory == 0 .and. allocated(source%error_weights)) &
         allocate (weights, source=source%error_weights, stat=memory)
      if (memory /= 0) then
         call out_of_memory(stat, "a copy of the options' per-component settings", [3, max(longest(source%rtol_vector), &
            longest(source%atol_vector))], real_bytes)
         return
      end if
      if (allocated(rtol)) rtol(:) = source%rtol_vector
      if (allocated(atol)) atol(:) = source%atol_vector
      if (allocated(nonnegative)) nonnegative(:) = source%nonnegative
      destination%scalar_options_type = source%scalar_options_type
      call move_alloc(rtol, destination%rtol_vector)
      call move_alloc(atol, destination%atol_vector)
      call move_alloc(nonnegative, destination%nonnegative)
      call move_alloc(weights, destination%error_weights)
   contains
      !> Size of a vector (0 when unallocated)
      pure integer function longest(vector)
         real(dp), allocatable, intent(in) :: vector(:)
         longest = 0
         if (allocated(vector)) longest = size(vector)
      end function longest
   end subroutine copy_options

   !> Check every option for a system of n unknowns; stat says which one is wrong.
   !> Every real option must be finite (an infinite tolerance or q is an error, not a
   !> setting). Tolerances below what double precision can deliver are accepted:
   !> `integrate` raises the error weights to that floor and says so in its statistics.
   subroutine validate_options(options, n, stat)
      !> Options to check
      type(integrator_options_type), intent(in) :: options
      !> Number of unknowns
      integer, intent(in) :: n
      !> status_invalid_argument or status_size_mismatch on failure
      type(status_type), intent(inout) :: stat

      logical :: atol_zero

      if (.not. finite_at_least(options%rtol, 0.0_dp)) then
         call invalid("rtol must be finite and >= 0"); return
      end if
      if (allocated(options%rtol_vector)) then
         if (size(options%rtol_vector) /= n) then
            call set_status(stat, status_size_mismatch, "options: rtol_vector must have one entry per unknown")
            return
         end if
         if (.not. all(finite_at_least(options%rtol_vector, 0.0_dp))) then
            call invalid("every rtol_vector entry must be finite and >= 0"); return
         end if
      end if
      if (allocated(options%nonnegative)) then
         if (size(options%nonnegative) /= n) then
            call set_status(stat, status_size_mismatch, "options: nonnegative must have one entry per unknown")
            return
         end if
      end if
      if (allocated(options%atol_vector)) then
         if (size(options%atol_vector) /= n) then
            call set_status(stat, status_size_mismatch, "options: atol_vector must have one entry per unknown")
            return
         end if
         if (.not. all(ieee_is_finite(options%atol_vector))) then
            call invalid("every atol_vector entry must be finite and >= 0"); return
         end if
         if (any(options%atol_vector < 0.0_dp)) then
            call invalid("every atol_vector entry must be finite and >= 0"); return
         end if
         atol_zero = any(options%atol_vector == 0.0_dp)
      else
         if (.not. finite_at_least(options%atol, 0.0_dp)) then
            call invalid("atol must be finite and >= 0"); return
         end if
         atol_zero = options%atol == 0.0_dp
      end if
      if (tolerance_pair_zero(options, n) .and. .not. allocated(options%error_weights)) then
         call invalid("rtol and atol cannot both be zero (tolerances must be positive)"); return
      end if
      if (options%norm /= norm_max .and. options%norm /= norm_rms) then
         call invalid("norm must be norm_max or norm_rms"); return
      end if
      if (all(options%controller /= [controller_i, controller_pi, controller_pid, controller_predictive, &
         controller_auto])) then
         call invalid("controller must be controller_i, controller_pi, controller_pid, controller_predictive "// &
            "or controller_auto"); return
      end if
      if (.not. finite_in(options%kappa, 0.0_dp, 1.0_dp) .or. options%kappa == 0.0_dp) then
         call invalid("kappa must be in (0, 1]"); return
      end if
      if (.not. (options%q == 0.0_dp .or. finite_in(options%q, 1.0_dp, max_q))) then
         call invalid("q must be in [1, 20] (or 0 for the scheme's default)"); return
      end if
      if (.not. finite_at_least(options%h0, 0.0_dp)) then
         call invalid("h0 must be finite and > 0 (or 0 to choose it automatically)"); return
      end if
      if (options%h0 > 0.0_dp .and. options%h0 < tiny(1.0_dp)) then
         ! (1/h0 overflows: the first attempts failed with NaN or Inf)
         call invalid("h0 must not be subnormal (at least 2.2E-308, or 0 to choose it automatically)"); return
      end if
      if (.not. finite_at_least(options%h_min, 0.0_dp)) then
         call invalid("h_min must be finite and >= 0"); return
      end if
      if (.not. finite_in(options%h_min_relative, 0.0_dp, 1.0_dp) .or. options%h_min_relative == 1.0_dp) then
         call invalid("h_min_relative must be finite and in [0, 1)"); return
      end if
      if (.not. finite_at_least(options%h_max, 0.0_dp) .or. options%h_max == 0.0_dp .or. &
         options%h_max < options%h_min) then
         call invalid("h_max must be finite, > 0 and >= h_min"); return
      end if
      if (options%h0 > 0.0_dp .and. (options%h0 < options%h_min .or. options%h0 > options%h_max)) then
         call invalid("h0 must lie in [h_min, h_max]"); return
      end if
      if (.not. (options%max_growth == 0.0_dp .or. finite_in(options%max_growth, 1.0_dp, huge(1.0_dp)))) then
         call invalid("max_growth must be finite and > 1 (or 0 for no limit)"); return
      end if
      if (options%max_growth == 1.0_dp) then
         call invalid("max_growth must be finite and > 1 (or 0 for no limit)"); return
      end if
      if (.not. (options%min_shrink == 0.0_dp .or. finite_in(options%min_shrink, 0.0_dp, 1.0_dp))) then
         call invalid("min_shrink must be in (0, 1) (or 0 for no limit)"); return
      end if
      if (options%min_shrink == 1.0_dp) then
         call invalid("min_shrink must be in (0, 1) (or 0 for no limit)"); return
      end if
      if (options%max_steps < 1) then
         call invalid("max_steps must be at least 1"); return
      end if
      if (options%max_newton_iterations < 0) then
         call invalid("max_newton_iterations must be at least 1 (or 0 for the scheme's own)"); return
      end if
      if (.not. (options%newton_fraction == 0.0_dp .or. (finite_at_least(options%newton_fraction, 0.0_dp) .and. &
         options%newton_fraction > 0.0_dp))) then
         call invalid("newton_fraction must be finite and > 0 (or 0 for the scheme's default)"); return
      end if
      if (options%max_failures < 0) then
         call invalid("max_failures must be >= 0 (0: no limit)"); return
      end if
      if (all(options%advance /= [advance_scheme, advance_high, advance_low])) then
         call invalid("advance must be advance_scheme, advance_high or advance_low"); return
      end if
      if (all(options%error_estimate /= [estimate_auto, estimate_embedded, estimate_doubling, estimate_defect])) then
         call invalid("error_estimate must be estimate_auto, estimate_embedded, estimate_doubling or "// &
            "estimate_defect"); return
      end if
      if (any(options%error_estimate == [estimate_doubling, estimate_defect]) .and. &
         options%advance /= advance_scheme) then
         call invalid("advance_high and advance_low choose a member of the embedded pair: they need "// &
            "error_estimate = estimate_embedded (or estimate_auto)"); return
      end if
      stat%code = status_ok
   contains
      subroutine invalid(message)
         character(len=*), intent(in) :: message
         call set_status(stat, status_invalid_argument, "options: "//message)
      end subroutine invalid
   end subroutine validate_options

   !> Whether some component has both its relative and its absolute tolerance zero.
   pure logical function tolerance_pair_zero(options, n)
      type(integrator_options_type), intent(in) :: options
      integer, intent(in) :: n
      integer :: i
      real(dp) :: rtol_i, atol_i
      tolerance_pair_zero = .false.
      do i = 1, n
         rtol_i = options%rtol
         if (allocated(options%rtol_vector)) rtol_i = options%rtol_vector(i)
         atol_i = options%atol
         if (allocated(options%atol_vector)) atol_i = options%atol_vector(i)
         if (rtol_i == 0.0_dp .and. atol_i == 0.0_dp) tolerance_pair_zero = .true.
      end do
   end function tolerance_pair_zero

   !> x is finite and x >= low (false for NaN).
   elemental logical function finite_at_least(x, low)
      real(dp), intent(in) :: x, low
      finite_at_least = ieee_is_finite(x)
      if (finite_at_least) finite_at_least = x >= low
   end function finite_at_least

   !> x is finite and low <= x <= high (false for NaN).
   elemental logical function finite_in(x, low, high)
      real(dp), intent(in) :: x, low, high
      finite_in = ieee_is_finite(x)
      if (finite_in) finite_in = x >= low .and. x <= high
   end function finite_in

end module taylorode_integrate_options
