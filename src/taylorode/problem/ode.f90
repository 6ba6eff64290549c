!> The problem a user solves: U' = f(t, U) + g(t, U), f non-stiff, g stiff.
!>
!> Users extend `ode_problem` (and write f, g and both Jacobians) or
!> `ode_problem_fd` (and write only f and g: the Jacobians come from finite
!> differences; a type extending it may still override one of them). Parameters of
!> a problem are components of the extended type.
!>
!> A problem that cannot evaluate at the point it is given (a state outside its
!> domain, a table lookup out of range) calls `self%reject_evaluation()` inside f,
!> g or a Jacobian and returns any finite values: the step is retried with a smaller
!> step size, and repeated rejections end the integration with
!> status_evaluation_failed.
!>
!> The default methods keep work arrays (F's g, J's second part, the differences'
!> probes), allocated at their first call: one that cannot be allocated rejects the
!> evaluation fatally, and `memory_failure` tells the integrator, which ends with
!> status_out_of_memory.
!>
!> A problem whose state is distributed over several processes (MPI ranks) holds
!> only its own part of U in the arrays it is given and overrides `reduce`, so that
!> every norm, finiteness check and step decision of the integrator is taken on the
!> whole state and every process decides the same.
module taylorode_problem_ode
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_out_of_memory
   use taylorode_base_memory, only: sized
   use taylorode_linalg_matrix, only: matrix_structure_type, dense_structure, storage_dense, storage_band
   implicit none
   private

   public :: ode_problem, ode_problem_fd, rhs_interface, jacobian_interface, dense_differences, band_differences
   public :: set_difference_rounding
   public :: reduce_sum, reduce_max, difference_f, difference_g, difference_rhs, full_jacobian, full_band_jacobian

   !> `reduce` operation: the sum over the processes
   integer, parameter :: reduce_sum = 1
   !> `reduce` operation: the maximum over the processes
   integer, parameter :: reduce_max = 2

   !> What a difference Jacobian differences: f
   integer, parameter :: difference_f = 1
   !> What a difference Jacobian differences: g
   integer, parameter :: difference_g = 2
   !> What a difference Jacobian differences: F = f + g, one call of `rhs` per perturbation
   integer, parameter :: difference_rhs = 3
   !> The increment of a difference Jacobian in column j is sqrt(eps max(|u_j|, this)),
   !> RADAU5's: a component far below 1 (a concentration of 1e-10) is perturbed by a
   !> fraction of its size, not by sqrt(eps) itself, which swamps it
   real(dp), parameter :: difference_floor = 1.0e-5_dp

   !> How the default `jac` and `jac_band` form J: not yet known (before their first call),
   !> by differences of F (both part Jacobians are the default differences), or from the
   !> part Jacobians (at least one is the problem's own)
   integer, parameter :: parts_unknown = 0, parts_differenced = 1, parts_own = 2

   !> Work arrays of the finite-difference Jacobians, kept between calls
   type :: difference_workspace_type
      real(dp), allocatable :: base(:), shifted(:), probe(:), increment(:)
      !> The size all four have (-1: not known to be the same for all)
      integer :: ready_size = -1
   end type difference_workspace_type

   !> Abstract problem with a non-stiff part f, a stiff part g and their Jacobians
   type, abstract :: ode_problem
      !> Declare g linear: g(t, U) = A U + b(t) with a constant matrix A. The schemes then
      !> evaluate dg/dU once per integration, and solve an implicit equation that is
      !> linear in U with a constant matrix (si-t-1, the stages of imex-rk21) by one
      !> Newton iteration with a matrix factored for the step size at hand, without a
      !> second one to confirm convergence
      logical :: linear_g = .false.
      !> Declare a constant mass matrix M: the problem is then M U' = f(t, U) + g(t, U),
      !> with M from `mass_matrix` (dense) or `mass_matrix_band` (the band storage of the Jacobian
      !> structure, M's bands within the Jacobian's). M may be singular: the equations
      !> whose rows of M are zero are algebraic (an index-1 differential-algebraic
      !> system, whose initial state must satisfy them). Only radau5 solves such a
      !> problem; the other schemes refuse it (status_invalid_argument)
      logical :: has_mass = .false.
      !> Declare f and g independent of t. The second-order Taylor schemes advance a
      !> problem that depends on t as the autonomous scheme advances (t, U) (with t' = 1),
      !> which needs dF/dt: by a difference in t, one more evaluation of F per Newton
      !> iteration of i-t-2 and of f and g per step of ex-t-2, si-t-2 and si-t-2-paper.
      !> An autonomous problem saves them (without dF/dt, a problem that does depend on t
      !> is advanced to first order only)
      logical :: autonomous = .false.
      !> Set by the default `reduce` when first called: the whole state is in this
      !> process, and the integrator's reductions are skipped from then on
      logical, private :: whole_state = .false.
      !> Set by reject_evaluation, cleared by the integrator before each attempt
      logical, private :: rejected = .false.
      !> Set by reject_evaluation(fatal=.true.): the integration stops at once
      logical, private :: fatal = .false.
      !> Why a work array of a default method could not be allocated ("" when none
      !> failed; cleared with the rejection it caused)
      character(len=200), private :: memory = ""
      !> Work arrays of the finite-difference Jacobians
      type(difference_workspace_type), private :: differences
      !> The rounding unit u of the difference Jacobians' increment sqrt(u max(|u_j|, 1e-5))
      real(dp), private :: difference_rounding = epsilon(1.0_dp)
      !> g(t, U) for the default `rhs` (allocated at its first call)
      real(dp), allocatable, private :: rhs_work(:)
      !> dg/dU for the default `jac` and `jac_band` (allocated at their first call)
      real(dp), allocatable, private :: jacobian_work(:, :)
      !> J for the default `add_jacobian_product`, dense or in band storage (allocated at
      !> its first call)
      real(dp), allocatable, private :: product_work(:, :)
      !> How the default `jac` (dense) and `jac_band` form J, found at their first call
      integer, private :: dense_parts = parts_unknown, band_parts = parts_unknown
      !> Set while the default `jac` or `jac_band` asks a part Jacobian whether it is the
      !> default differences: a default then only says so (default_met) and computes nothing
      logical, private :: probing = .false., default_met = .false.
   contains
      !> Non-stiff part f(t, U)
      procedure(rhs_interface), deferred :: f
      !> Stiff part g(t, U)
      procedure(rhs_interface), deferred :: g
      !> Jacobian df/dU
      procedure(jacobian_interface), deferred :: jac_f
      !> Jacobian dg/dU
      procedure(jacobian_interface), deferred :: jac_g
      !> Where the nonzeros of df/dU and dg/dU together can be (default: dense);
      !> a banded problem returns band_structure(lower, upper)
      procedure :: jacobian_structure
      !> The declared structure checked for n unknowns: a band wider than the matrix
      !> is dense, negative bandwidths are rejected
      procedure, non_overridable :: checked_structure
      !> Bandwidths of the declared structure (-1, -1 when dense); declare a band
      !> through `jacobian_structure`, this binding cannot be overridden
      procedure, non_overridable :: bandwidths
      !> df/dU in LAPACK band storage (default: grouped forward differences of f)
      procedure :: jac_f_band
      !> dg/dU in LAPACK band storage (default: grouped forward differences of g)
      procedure :: jac_g_band
      !> The whole right-hand side F(t, U) = f(t, U) + g(t, U), for the schemes that use
      !> only F (radau5); default: f, then g added. Override it when F costs less in one
      !> call; it must equal f + g
      procedure :: rhs
      !> F(t, U) of n unknowns stored contiguously, for the schemes' inner loops, which
      !> call it with explicit-shape arrays (no array descriptors); default: `rhs`.
      !> Override it only to call F without them (the legacy entry's FCN)
      procedure :: rhs_values
      !> F(t, U) as `rhs_values`, of a state the caller no longer needs: the problem may
      !> overwrite it (radau5's stage states); default: `rhs_values`. Override it only to
      !> hand the state to a routine that may write it, without a copy (the legacy
      !> entry's FCN)
      procedure :: rhs_scratch
      !> The whole Jacobian J = df/dU + dg/dU, for the schemes that use only J (i-t-1,
      !> i-t-2, radau5); default: jac_f, then jac_g added, or, when both are the default
      !> differences (`ode_problem_fd`), forward differences of F = `rhs` (one call per
      !> column instead of one of f and one of g). Override it when J costs less in one
      !> call; it must equal jac_f + jac_g
      procedure :: jac => full_jacobian
      !> J = df/dU + dg/dU in LAPACK band storage (default: jac_f_band, then jac_g_band
      !> added, or grouped differences of F when both are the default differences); the
      !> same contract as `jac`
      procedure :: jac_band => full_band_jacobian
      !> J at (t, u) where the caller already has F(t, u) (radau5, at the start of its
      !> step): `jac`, or, when J is differenced from F, the differences from that F (n
      !> evaluations of F instead of n + 1). The same contract as `jac`
      procedure :: jac_with_rhs => full_jacobian_with_rhs
      !> `jac_band` where the caller already has F(t, u) (see `jac_with_rhs`)
      procedure :: jac_band_with_rhs => full_band_jacobian_with_rhs
      !> The constant mass matrix M, dense (asked for when `has_mass` and the Jacobian
      !> structure is dense; default: the identity)
      procedure :: mass_matrix
      !> M in the band storage of the Jacobian structure (asked for when `has_mass` and
      !> the structure is a band; default: the identity)
      procedure :: mass_matrix_band
      !> J_f v, the Jacobian of f times a vector (default: a forward difference of f along v)
      procedure :: jvp_f
      !> J_g v, the Jacobian of g times a vector (default: a forward difference of g along v)
      procedure :: jvp_g
      !> y = y + alpha J v with the whole Jacobian J = df/dU + dg/dU, for the schemes that
      !> use J only in products (i-t-2's residual, at every Newton iteration); default: J
      !> from `jac` (or `jac_band`), exact. Override it with a product that forms no
      !> matrix (i-t-2 then evaluates J only for its Newton matrices); it must equal
      !> y + alpha J v
      procedure :: add_jacobian_product
      !> Combine values over every process that holds a part of the state (default: the
      !> whole state is here, nothing to combine)
      procedure :: reduce
      !> Say, from inside f, g or a Jacobian, that the problem cannot be evaluated at
      !> the point it was given
      procedure, non_overridable :: reject_evaluation
      !> Whether an evaluation was rejected since the last clear_rejection
      procedure, non_overridable :: evaluation_rejected
      !> Whether the rejection asked to stop the integration (no retry)
      procedure, non_overridable :: evaluation_fatal
      !> Forget earlier rejections (the integrator does this before each attempt)
      procedure, non_overridable :: clear_rejection
      !> Whether the default `reduce` has been called: the whole state is in this
      !> process, nothing to combine
      procedure, non_overridable :: whole_state_here
      !> Why an evaluation was rejected for want of memory for a work array (if it was)
      procedure, non_overridable :: memory_failure
   end type ode_problem

   !> Problem whose Jacobians are approximated by forward differences of f and g
   type, abstract, extends(ode_problem) :: ode_problem_fd
   contains
      !> Forward-difference approximation of df/dU
      procedure :: jac_f => fd_jac_f
      !> Forward-difference approximation of dg/dU
      procedure :: jac_g => fd_jac_g
   end type ode_problem_fd

   abstract interface
      !> Right-hand side part: writes f(t, u) or g(t, u) into `dudt`
      subroutine rhs_interface(self, t, u, dudt)
         import :: ode_problem, dp
         !> The problem (carries its parameters)
         class(ode_problem), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> Value of the part at (t, u), same size as u
         real(dp), intent(out) :: dudt(:)
      end subroutine rhs_interface

      !> Jacobian of a part: writes d(part)/dU at (t, u) into `jac` (n x n, jac(i, j) = d part_i / d u_j)
      subroutine jacobian_interface(self, t, u, jac)
         import :: ode_problem, dp
         !> The problem
         class(ode_problem), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> Jacobian matrix, size(u) x size(u)
         real(dp), intent(out) :: jac(:, :)
      end subroutine jacobian_interface
   end interface

contains

   !> Structure of df/dU and dg/dU together for a system of size n: dense unless a
   !> problem overrides it. A banded problem (J(i, j) = 0 for i - j > lower or
   !> j - i > upper) returns band_structure(lower, upper); its Newton systems are then
   !> solved in band storage and its Jacobians come from `jac_f_band` and `jac_g_band`
   !> (the dense `jac_f` and `jac_g` are not called).
   function jacobian_structure(self, n) result(structure)
      !> The problem
      class(ode_problem), intent(in) :: self
      !> Number of unknowns
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = dense_structure()
   end function jacobian_structure

   !> The declared structure for n unknowns, made safe: a band wider than the matrix
   !> (a bandwidth beyond n - 1) is dense storage, so that a problem's own band
   !> Jacobian always meets the layout it declared; a negative bandwidth or an unknown
   !> storage is an error.
   subroutine checked_structure(self, n, structure, stat)
      !> The problem
      class(ode_problem), intent(in) :: self
      !> Number of unknowns
      integer, intent(in) :: n
      !> The structure to use
      type(matrix_structure_type), intent(out) :: structure
      !> status_invalid_argument for an impossible structure
      type(status_type), intent(inout) :: stat
      structure = self%jacobian_structure(n)
      select case (structure%storage)
      case (storage_dense)
      case (storage_band)
         if (structure%lower < 0 .or. structure%upper < 0) then
            call set_status(stat, status_invalid_argument, &
               "problem: the Jacobian bandwidths must be >= 0 (jacobian_structure)")
            structure = dense_structure()
            return
         end if
         if (structure%lower > n - 1 .or. structure%upper > n - 1) structure = dense_structure()
      case default
         call set_status(stat, status_invalid_argument, "problem: unknown Jacobian storage (jacobian_structure)")
         structure = dense_structure()
      end select
   end subroutine checked_structure

   !> Lower and upper bandwidths of the declared Jacobian structure, -1 and -1 when
   !> it is dense.
   subroutine bandwidths(self, n, lower, upper)
      !> The problem
      class(ode_problem), intent(in) :: self
      !> Number of unknowns
      integer, intent(in) :: n
      !> Lower and upper bandwidths, -1 for dense
      integer, intent(out) :: lower, upper
      type(matrix_structure_type) :: structure
      structure = self%jacobian_structure(n)
      lower = -1
      upper = -1
      if (structure%storage == storage_band) then
         lower = structure%lower
         upper = structure%upper
      end if
   end subroutine bandwidths

   !> Say that f, g or a Jacobian cannot be evaluated at the point given (call it from
   !> inside the evaluation and return any finite values): the step is retried with a
   !> smaller step size; with fatal = .true. the integration stops at once instead
   !> (status_evaluation_failed either way when it gives up).
   subroutine reject_evaluation(self, fatal)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Stop the integration instead of retrying (default: retry)
      logical, intent(in), optional :: fatal
      self%rejected = .true.
      if (present(fatal)) self%fatal = self%fatal .or. fatal
   end subroutine reject_evaluation

   !> Whether a rejection since the last clear_rejection asked to stop the integration.
   pure logical function evaluation_fatal(self)
      !> The problem
      class(ode_problem), intent(in) :: self
      evaluation_fatal = self%fatal
   end function evaluation_fatal

   !> Whether an evaluation was rejected since the last clear_rejection.
   pure logical function evaluation_rejected(self)
      !> The problem
      class(ode_problem), intent(in) :: self
      evaluation_rejected = self%rejected
   end function evaluation_rejected

   !> Whether the default `reduce` has been called (the problem does not override it:
   !> the whole state is in this process, and every reduction leaves its values as
   !> they are).
   pure logical function whole_state_here(self)
      !> The problem
      class(ode_problem), intent(in) :: self
      whole_state_here = self%whole_state
   end function whole_state_here

   !> Forget earlier rejections.
   subroutine clear_rejection(self)
      !> The problem
      class(ode_problem), intent(inout) :: self
      self%rejected = .false.
      self%fatal = .false.
      ! the 200 blanks are written only over a message (every attempt clears; the
      ! character's code, as a comparison of strings would call len_trim)
      if (iachar(self%memory(1:1)) /= iachar(" ")) self%memory = ""
   end subroutine clear_rejection

   !> When a default method rejected an evaluation (fatally) because its work array
   !> could not be allocated: stat = that status_out_of_memory and its message;
   !> otherwise stat is left as it is.
   subroutine memory_failure(self, stat)
      !> The problem
      class(ode_problem), intent(in) :: self
      !> Set to the failure, if there was one
      type(status_type), intent(inout) :: stat
      if (len_trim(self%memory) > 0) call set_status(stat, status_out_of_memory, trim(self%memory))
   end subroutine memory_failure

   !> Whether the work array just sized for a default method is there (stat ok); if not,
   !> the evaluation is rejected fatally (memory_failure says why) and value is zeroed
   !> (left as it is otherwise).
   logical function work_ready(self, stat, value)
      class(ode_problem), intent(inout) :: self
      type(status_type), intent(in) :: stat
      real(dp), intent(inout) :: value(..)
      work_ready = stat%code == status_ok
      if (work_ready) return
      self%memory = "out of memory: a work array of the problem"
      if (allocated(stat%message)) self%memory = adjustl(stat%message)
      call self%reject_evaluation(fatal=.true.)
      select rank (value)
      rank (1)
         value = 0.0_dp
      rank (2)
         value = 0.0_dp
      end select
   end function work_ready

   !> df/dU in LAPACK band storage, band(upper + 1 + i - j, j) = df_i/du_j, by
   !> forward differences on groups of columns lower + upper + 1 apart (one f
   !> evaluation per group). Banded problems with analytic Jacobians override it.
   subroutine jac_f_band(self, t, u, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      if (self%probing) then
         self%default_met = .true.
         return
      end if
      call band_differences(self, difference_f, t, u, band)
   end subroutine jac_f_band

   !> dg/dU in LAPACK band storage (see jac_f_band).
   subroutine jac_g_band(self, t, u, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      if (self%probing) then
         self%default_met = .true.
         return
      end if
      call band_differences(self, difference_g, t, u, band)
   end subroutine jac_g_band

   !> F(t, u) = f(t, u) + g(t, u): f into dudt, then g, through a work array the problem
   !> keeps (allocated at the first call, and again only when the size changes).
   subroutine rhs(self, t, u, dudt)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> F(t, u), same size as u
      real(dp), intent(out) :: dudt(:)
      type(status_type) :: stat
      integer :: i
      call sized(self%rhs_work, size(u), "the problem's work array for g", stat)
      if (.not. work_ready(self, stat, dudt)) return
      call self%f(t, u, dudt)
      call self%g(t, u, self%rhs_work)
      do i = 1, size(u)
         dudt(i) = dudt(i) + self%rhs_work(i)
      end do
   end subroutine rhs

   !> F(t, u) of n unknowns: `rhs`.
   subroutine rhs_values(self, n, t, u, dudt)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(n)
      !> F(t, u)
      real(dp), intent(out) :: dudt(n)
      call self%rhs(t, u, dudt)
   end subroutine rhs_values

   !> F(t, u) of n unknowns, u the caller's scratch: `rhs_values`.
   subroutine rhs_scratch(self, n, t, u, dudt)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Unknowns
      integer, intent(in) :: n
      !> Time
      real(dp), intent(in) :: t
      !> State, which the problem may overwrite
      real(dp), intent(inout) :: u(n)
      !> F(t, u)
      real(dp), intent(out) :: dudt(n)
      call self%rhs_values(n, t, u, dudt)
   end subroutine rhs_scratch

   !> J = df/dU + dg/dU: jac_f, then jac_g into a work array the problem keeps, added;
   !> when both are the default differences (`ode_problem_fd`), forward differences of F
   !> (`rhs`, once per column). Which it is, is found at the first call: each part
   !> Jacobian is called while the problem probes, a default then computes nothing and
   !> says so, the problem's own computes its matrix as always (and it is used).
   subroutine full_jacobian(self, t, u, jac)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> J(t, u), size(u) x size(u)
      real(dp), intent(out) :: jac(:, :)
      call sum_of_parts(self, .false., t, u, jac)
   end subroutine full_jacobian

   !> J = df/dU + dg/dU in band storage: jac_f_band, then jac_g_band into a work
   !> array the problem keeps, added; when both are the default grouped differences,
   !> grouped differences of F (`rhs`, once per group of columns), found at the first
   !> call as `jac` finds it.
   subroutine full_band_jacobian(self, t, u, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      call sum_of_parts(self, .true., t, u, band)
   end subroutine full_band_jacobian

   !> full_jacobian (dense) and full_band_jacobian (banded): the part Jacobians added,
   !> or differences of F once both are found to be the default differences; what was
   !> found is kept per storage (dense_parts, band_parts).
   subroutine sum_of_parts(self, banded, t, u, jac)
      class(ode_problem), intent(inout) :: self
      logical, intent(in) :: banded
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      logical :: f_differenced, g_differenced
      integer :: parts
      type(status_type) :: stat

      parts = merge(self%band_parts, self%dense_parts, banded)
      if (parts == parts_differenced) then
         call differences(difference_rhs, jac)
         return
      end if
      call sized(self%jacobian_work, size(jac, 1), size(jac, 2), "the problem's work matrix for dg/dU", stat)
      if (.not. work_ready(self, stat, jac)) return
      if (parts == parts_own) then
         call part_jacobian(.true., jac)
         call part_jacobian(.false., self%jacobian_work)
      else
         self%probing = .true.
         self%default_met = .false.
         call part_jacobian(.true., jac)
         f_differenced = self%default_met
         self%default_met = .false.
         call part_jacobian(.false., self%jacobian_work)
         g_differenced = self%default_met
         self%probing = .false.
         self%default_met = .false.
         if (f_differenced .and. g_differenced) then
            call keep_parts(parts_differenced)
            call differences(difference_rhs, jac)
            return
         end if
         call keep_parts(parts_own)
         if (f_differenced) call differences(difference_f, jac)
         if (g_differenced) call differences(difference_g, self%jacobian_work)
      end if
      jac = jac + self%jacobian_work

   contains

      !> df/dU (of_f) or dg/dU in the storage of the call
      subroutine part_jacobian(of_f, matrix)
         logical, intent(in) :: of_f
         real(dp), intent(out) :: matrix(:, :)
         if (banded .and. of_f) then
            call self%jac_f_band(t, u, matrix)
         else if (banded) then
            call self%jac_g_band(t, u, matrix)
         else if (of_f) then
            call self%jac_f(t, u, matrix)
         else
            call self%jac_g(t, u, matrix)
         end if
      end subroutine part_jacobian

      !> Differences of f, g or F (part) in the storage of the call
      subroutine differences(part, matrix)
         integer, intent(in) :: part
         real(dp), intent(out) :: matrix(:, :)
         if (banded) then
            call band_differences(self, part, t, u, matrix)
         else
            call dense_differences(self, part, t, u, matrix)
         end if
      end subroutine differences

      !> What the probe found, for the storage of the call
      subroutine keep_parts(found)
         integer, intent(in) :: found
         if (banded) then
            self%band_parts = found
         else
            self%dense_parts = found
         end if
      end subroutine keep_parts
   end subroutine sum_of_parts

   !> J at (t, u) given F(t, u): differences of F from it once `jac` has found that both
   !> part Jacobians are the default differences (at its first call, made here when
   !> needed), else `jac`.
   subroutine full_jacobian_with_rhs(self, t, u, value, jac)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> F(t, u)
      real(dp), intent(in) :: value(:)
      !> J(t, u), size(u) x size(u)
      real(dp), intent(out) :: jac(:, :)
      if (self%dense_parts == parts_differenced) then
         call dense_differences(self, difference_rhs, t, u, jac, value)
      else
         call self%jac(t, u, jac)
      end if
   end subroutine full_jacobian_with_rhs

   !> J at (t, u) in band storage given F(t, u) (see full_jacobian_with_rhs).
   subroutine full_band_jacobian_with_rhs(self, t, u, value, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> F(t, u)
      real(dp), intent(in) :: value(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      if (self%band_parts == parts_differenced) then
         call band_differences(self, difference_rhs, t, u, band, value)
      else
         call self%jac_band(t, u, band)
      end if
   end subroutine full_band_jacobian_with_rhs

   !> y = y + alpha J v, J = df/dU + dg/dU from `jac` (dense) or `jac_band` (banded
   !> problems) in a work array the problem keeps (allocated at the first call, and again
   !> only when the shape changes), added column by column: y_i + (alpha v_j) J_ij over
   !> j in increasing order, as the matrices' multiply_add adds (an override that adds
   !> the same terms in the same order returns the same numbers bit for bit).
   subroutine add_jacobian_product(self, t, u, alpha, v, y)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Factor of the product
      real(dp), intent(in) :: alpha
      !> Direction, size of u
      real(dp), intent(in) :: v(:)
      !> y on entry, y + alpha J v on exit
      real(dp), intent(inout) :: y(:)
      type(matrix_structure_type) :: structure
      type(status_type) :: stat
      integer :: n, i, j
      real(dp) :: av

      n = size(u)
      call self%checked_structure(n, structure, stat)
      if (structure%storage == storage_band) then
         call sized(self%product_work, structure%lower + structure%upper + 1, n, &
            "the problem's work matrix for J v", stat)
         if (.not. work_ready(self, stat, y)) return
         call self%jac_band(t, u, self%product_work)
         do j = 1, n
            av = alpha*v(j)
            do i = max(1, j - structure%upper), min(n, j + structure%lower)
               y(i) = y(i) + av*self%product_work(structure%upper + 1 + i - j, j)
            end do
         end do
      else
         call sized(self%product_work, n, n, "the problem's work matrix for J v", stat)
         if (.not. work_ready(self, stat, y)) return
         call self%jac(t, u, self%product_work)
         do j = 1, n
            av = alpha*v(j)
            do i = 1, n
               y(i) = y(i) + av*self%product_work(i, j)
            end do
         end do
      end if
   end subroutine add_jacobian_product

   !> The mass matrix M, m(i, j) = M(i, j) (n x n): called once per integration when
   !> `has_mass`; the default is the identity. A problem that declares `has_mass`
   !> overrides it (or `mass_matrix_band` for a band structure).
   subroutine mass_matrix(self, m)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> M, size(m, 1) = size(m, 2) = n
      real(dp), intent(out) :: m(:, :)
      integer :: i
      m = 0.0_dp
      do i = 1, min(size(m, 1), size(m, 2))
         m(i, i) = 1.0_dp
      end do
   end subroutine mass_matrix

   !> The mass matrix in LAPACK band storage with the Jacobian's bands, band(upper + 1 +
   !> i - j, j) = M(i, j) (the Jacobian structure's upper bandwidth); the default is the
   !> identity.
   subroutine mass_matrix_band(self, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Band storage, (lower + upper + 1) x n
      real(dp), intent(out) :: band(:, :)
      integer :: lower, upper
      call self%bandwidths(size(band, 2), lower, upper)
      band = 0.0_dp
      band(max(upper, 0) + 1, :) = 1.0_dp
   end subroutine mass_matrix_band

   !> J_f(t, u) v by a forward difference of f along v (two evaluations of f); problems
   !> with an analytic product override it.
   subroutine jvp_f(self, t, u, v, jv)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Direction, size of u
      real(dp), intent(in) :: v(:)
      !> J_f v, size of u
      real(dp), intent(out) :: jv(:)
      call directional_difference(self, difference_f, t, u, v, jv)
   end subroutine jvp_f

   !> J_g(t, u) v by a forward difference of g along v (see jvp_f).
   subroutine jvp_g(self, t, u, v, jv)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Direction, size of u
      real(dp), intent(in) :: v(:)
      !> J_g v, size of u
      real(dp), intent(out) :: jv(:)
      call directional_difference(self, difference_g, t, u, v, jv)
   end subroutine jvp_g

   !> Combine `values` elementwise over every process that holds a part of the state:
   !> their sum (reduce_sum) or their maximum (reduce_max), the same result on every
   !> process. The integrator calls it once per weighted norm (maximum: the largest
   !> weighted component; sum: the sum of squares and the number of components), once
   !> per attempted step to agree on its outcome (maximum of the status code and of a
   !> flag for a fatal rejection), once per finiteness check of a state (sum of the
   !> number of NaN and Inf components) and, with a zero absolute tolerance, once per
   !> set of weights (maximum of |U_i|); the default jvp_f and jvp_g once per product.
   !> Every process must call it the same number of times (MPI_Allreduce is collective).
   !> The default does nothing: the whole state is in this process.
   subroutine reduce(self, operation, values)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> reduce_sum or reduce_max
      integer, intent(in) :: operation
      !> This process's values on entry, the combined values on exit
      real(dp), intent(inout) :: values(:)
      self%whole_state = .true.
   end subroutine reduce

   !> Work arrays of the differences for n unknowns (allocated only when n changes);
   !> false, with the evaluation rejected and value zeroed, when they cannot be allocated.
   logical function workspace_ready(self, n, value)
      class(ode_problem), intent(inout) :: self
      integer, intent(in) :: n
      real(dp), intent(out) :: value(..)
      character(len=*), parameter :: what = "the work arrays of the difference Jacobians"
      type(status_type) :: stat
      workspace_ready = self%differences%ready_size == n
      if (workspace_ready) return
      self%differences%ready_size = -1
      call sized(self%differences%base, n, what, stat)
      call sized(self%differences%shifted, n, what, stat)
      call sized(self%differences%probe, n, what, stat)
      call sized(self%differences%increment, n, what, stat)
      workspace_ready = work_ready(self, stat, value)
      if (workspace_ready) self%differences%ready_size = n
   end function workspace_ready

   !> Grouped forward differences of f, g or F = f + g (`part`) into band storage: the
   !> columns j, j + w, j + 2w, ... (w = lower + upper + 1) are perturbed together. The
   !> band is read from the storage it is given: size(band, 1) = lower + upper + 1 with
   !> upper from the checked structure.
   subroutine band_differences(self, part, t, u, band, value)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> difference_f, difference_g or difference_rhs
      integer, intent(in) :: part
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      !> The part at (t, u) when the caller has it (one evaluation fewer)
      real(dp), intent(in), optional :: value(:)
      type(matrix_structure_type) :: structure
      type(status_type) :: stat
      integer :: lower, upper, width, group, i, j, n

      n = size(u)
      call self%checked_structure(n, structure, stat)
      upper = min(structure%upper, size(band, 1) - 1)
      lower = size(band, 1) - 1 - upper
      width = lower + upper + 1
      if (.not. workspace_ready(self, n, band)) return
      associate (base => self%differences%base, shifted => self%differences%shifted, &
         probe => self%differences%probe, increment => self%differences%increment)
         band = 0.0_dp
         if (present(value)) then
            base = value
         else
            ! at the probe, not at u (see difference_columns)
            probe = u
            call evaluate_part(self, part, t, probe, base)
         end if
         do group = 1, min(width, n)
            probe = u
            do j = group, n, width
               increment(j) = sqrt(self%difference_rounding*max(abs(u(j)), difference_floor))
               probe(j) = u(j) + increment(j)
               increment(j) = probe(j) - u(j)
            end do
            call evaluate_part(self, part, t, probe, shifted)
            do j = group, n, width
               do i = max(1, j - upper), min(n, j + lower)
                  band(upper + 1 + i - j, j) = (shifted(i) - base(i))/increment(j)
               end do
            end do
         end do
      end associate
   end subroutine band_differences

   !> Forward-difference Jacobian of f.
   subroutine fd_jac_f(self, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%probing) then
         self%default_met = .true.
         return
      end if
      call dense_differences(self, difference_f, t, u, jac)
   end subroutine fd_jac_f

   !> Forward-difference Jacobian of g.
   subroutine fd_jac_g(self, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      if (self%probing) then
         self%default_met = .true.
         return
      end if
      call dense_differences(self, difference_g, t, u, jac)
   end subroutine fd_jac_g

   !> The rounding unit u of the difference Jacobians' increment sqrt(u max(|u_j|, 1e-5))
   !> (default: epsilon). The legacy entry sets its UROUND (WORK(1), 1e-16 unless given),
   !> with which RADAU5 differences; the caller checks it (in (0, 1)).
   subroutine set_difference_rounding(self, rounding)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> The rounding unit
      real(dp), intent(in) :: rounding
      self%difference_rounding = rounding
   end subroutine set_difference_rounding

   !> Column-by-column forward differences of f, g or F = f + g (`part`), with the
   !> increment sqrt(u max(|u_j|, 1e-5)) (RADAU5's; see difference_floor and
   !> set_difference_rounding).
   subroutine dense_differences(self, part, t, u, jac, value)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> difference_f, difference_g or difference_rhs
      integer, intent(in) :: part
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Jacobian, size(u) x size(u)
      real(dp), intent(out) :: jac(:, :)
      !> The part at (t, u) when the caller has it (one evaluation fewer)
      real(dp), intent(in), optional :: value(:)
      integer :: n
      n = size(u)
      if (.not. workspace_ready(self, n, jac)) return
      call difference_columns(self, part, n, t, u, jac, self%differences%base, self%differences%shifted, &
         self%differences%probe, value)
   end subroutine dense_differences

   !> dense_differences' columns, the work arrays explicit-shape (on a few unknowns the
   !> copies and columns through array descriptors cost more than the evaluations). The
   !> part is evaluated at the probe only, never at the caller's u: evaluate_part passes
   !> its arrays to rhs_values as explicit-shape, which would copy a non-contiguous u.
   subroutine difference_columns(self, part, n, t, u, jac, base, shifted, probe, value)
      class(ode_problem), intent(inout) :: self
      integer, intent(in) :: part, n
      real(dp), intent(in) :: t, u(:)
      real(dp), intent(out) :: jac(:, :)
      !> The work arrays: the part at u, at the probe, and the probe
      real(dp), intent(out) :: base(n), shifted(n), probe(n)
      real(dp), intent(in), optional :: value(:)
      real(dp) :: increment
      integer :: i, j
      !GCC$ unroll 1
      do i = 1, n
         probe(i) = u(i)
      end do
      if (present(value)) then
         !GCC$ unroll 1
         do i = 1, n
            base(i) = value(i)
         end do
      else
         call evaluate_part(self, part, t, probe, base)
      end if
      do j = 1, n
         increment = sqrt(self%difference_rounding*max(abs(u(j)), difference_floor))
         probe(j) = u(j) + increment
         increment = probe(j) - u(j)
         call evaluate_part(self, part, t, probe, shifted)
         !GCC$ unroll 1
         do i = 1, n
            jac(i, j) = (shifted(i) - base(i))/increment
         end do
         probe(j) = u(j)
      end do
   end subroutine difference_columns

   !> (part(t, u + e v) - part(t, u))/e for f or g (`part`), with the increment
   !> e = sqrt(eps) max(|u|_max, 1)/|v|_max taken from the whole state (through
   !> `reduce`), so that every process perturbs its part by the same e.
   subroutine directional_difference(self, part, t, u, v, jv)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> difference_f or difference_g
      integer, intent(in) :: part
      !> Time
      real(dp), intent(in) :: t
      !> State and direction
      real(dp), intent(in) :: u(:), v(:)
      !> The directional difference
      real(dp), intent(out) :: jv(:)
      real(dp) :: sizes(2), increment
      integer :: i
      sizes = 0.0_dp
      do i = 1, size(u)
         sizes(1) = max(sizes(1), abs(u(i)))
         sizes(2) = max(sizes(2), abs(v(i)))
      end do
      call self%reduce(reduce_max, sizes)
      if (sizes(2) == 0.0_dp) then
         jv = 0.0_dp
         return
      end if
      increment = sqrt(epsilon(1.0_dp))*max(sizes(1), 1.0_dp)/sizes(2)
      if (.not. workspace_ready(self, size(u), jv)) return
      associate (base => self%differences%base, probe => self%differences%probe)
         probe = u + increment*v
         call evaluate_part(self, part, t, u, base)
         call evaluate_part(self, part, t, probe, jv)
         jv = (jv - base)/increment
      end associate
   end subroutine directional_difference

   !> f(t, state), g(t, state) or F(t, state) = `rhs_values` as `part` says; state and
   !> value are the differences' work arrays (contiguous: rhs_values takes explicit-shape
   !> arrays, and would copy others).
   subroutine evaluate_part(problem, part, t, state, value)
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: part
      real(dp), intent(in) :: t
      real(dp), intent(in) :: state(:)
      real(dp), intent(out) :: value(:)
      select case (part)
      case (difference_f)
         call problem%f(t, state, value)
      case (difference_g)
         call problem%g(t, state, value)
      case default
         ! explicit-shape: the legacy entry calls FCN from here without array descriptors
         call problem%rhs_values(size(state), t, state, value)
      end select
   end subroutine evaluate_part

end module taylorode_problem_ode
