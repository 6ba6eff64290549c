!> Newton's method as a component: a scheme describes each nonlinear system it
!> solves (a residual and a Newton matrix, `nonlinear_system_type`) and holds one
!> `newton_solver_type` per distinct Newton matrix. Everything a solve depends on
!> (the step size, the tolerances, the iteration limit) comes in as arguments.
!>
!> A Newton matrix of the form M = A - B C (the second-order Taylor schemes: I - h J +
!> h^2/2 J^2 and its relatives) is not formed: a solver made `stacked` factors the
!> matrix [[A, B], [C, I]] of twice the order instead, whose Schur complement is M,
!> and solves M x = b as [[A, B], [C, I]] [x; y] = [b; 0]. M's condition number grows
!> like (h |lambda|)^2 for a stiff eigenvalue lambda, the stacked matrix's like h
!> |lambda|: the rounding errors of the solves (which break the linear invariants the
!> schemes keep exactly, such as E5's y2 - y3 - y4 = 0, by eps times the condition
!> number at every step) shrink by a factor h |lambda|.
module taylorode_newton_solver
   use taylorode_base_kinds, only: dp, i8
   use taylorode_base_status, only: status_type, set_code, status_ok, status_newton_diverged, &
      status_newton_not_converged, status_nonfinite, status_evaluation_failed, status_singular_matrix
   use taylorode_base_counters, only: counters_type
   use taylorode_base_memory, only: sized
   use taylorode_linalg_matrix, only: matrix_type, matrix_structure_type, stacked_structure
   use taylorode_linalg_solver, only: linear_solver_type, new_linear_solver
   use taylorode_problem_ode, only: ode_problem
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: newton_settings_type, newton_solver_type, nonlinear_system_type
   public :: default_newton_tolerance, default_max_newton_iterations

   !> Newton increment tolerance, relative to 1 + |U0|, when the caller gives none
   real(dp), parameter :: default_newton_tolerance = 1.0e-13_dp
   !> Newton iterations allowed for one nonlinear system before the step fails
   integer, parameter :: default_max_newton_iterations = 10
   !> Contraction factor above which the Newton matrix is rebuilt at the current iterate
   real(dp), parameter :: refresh_contraction = 0.25_dp
   !> Contraction factor, of two increments with a matrix built in the same solve, at
   !> which the iteration is declared divergent
   real(dp), parameter :: divergence_contraction = 2.0_dp
   !> After a solve that kept no digit of its residual at step h, steps are held below
   !> this fraction of h (the limit of the stacked matrices lies near h |lambda| =
   !> 1/epsilon; a half would fail again once or twice, each failure counting towards
   !> the integrator's limit of singular matrices)
   real(dp), parameter :: step_limit_fraction = 0.25_dp
   !> An increment of at most this many units of rounding of the iterate, or of its
   !> tolerance, in every component, is all the iteration can resolve
   real(dp), parameter :: rounding_ulps = 4.0_dp
   !> A factored Newton matrix serves a later step while h differs by at most this
   !> fraction from the h it was built with ...
   real(dp), parameter :: reuse_step_change = 0.2_dp
   !> ... and its last solve contracted at least this fast
   real(dp), parameter :: reuse_contraction = 0.1_dp

   !> How a step's nonlinear systems are to be solved
   type :: newton_settings_type
      !> Absolute tolerance on each component of a Newton increment (size of the state;
      !> a system that stacks several copies of the state uses it for each copy)
      real(dp), allocatable :: tolerance(:)
      !> Iterations allowed per nonlinear system
      integer :: max_iterations = default_max_newton_iterations
      !> Keep a factored Newton matrix across steps while h changes by at most 20 % and
      !> the last solve contracted by 0.1 or better (off: one factorization per solve)
      logical :: reuse_matrix = .true.
      !> Stop when the error left, estimated from the contraction as
      !> theta/(1 - theta) |increment|, is within the tolerance (RADAU5's test; the first
      !> increment of a matrix kept from an earlier solve must itself be within it, that
      !> of a matrix built in this solve is not accepted alone); off:
      !> when the last increment is, with a second iteration whenever the matrix was kept
      logical :: estimate_error = .true.
      !> Newton matrices with every term of the equation's derivative (i-t-2: the second
      !> derivatives of F along F); off: the paper's matrices, which omit them
      logical :: exact_matrix = .true.
      !> Factored Newton matrices a solver keeps, for as many step sizes (1, or 2 for
      !> step doubling, which alternates between h/2 and h)
      integer :: kept_factorizations = 1
   end type newton_settings_type

   !> A nonlinear system r(u) = 0 of a scheme, with the data of the current step
   type, abstract :: nonlinear_system_type
      !> Whether the residual is linear in u (set by the scheme for each solve): Newton
      !> with a matrix factored for exactly this step size then solves it in one
      !> iteration, and stops there
      logical :: linear = .false.
   contains
      !> Residual r(u)
      procedure(residual_interface), deferred :: residual
      !> Newton matrix (approximate dr/du) at u, assembled into `matrix` (for a stacked
      !> solver: the blocks A, B, C of [[A, B], [C, I]], see `add_block`)
      procedure(newton_matrix_interface), deferred :: newton_matrix
      !> What an error of the solution adds to the next step's equation, beyond itself
      !> (default: nothing)
      procedure :: propagate
   end type nonlinear_system_type

   !> A factored Newton matrix and what it was built for
   type :: kept_factorization_type
      !> The Newton matrix and its factors
      type(linear_solver_type) :: linear
      !> Step size the factored matrix was built with
      real(dp) :: h_built = 0.0_dp
      !> Contraction of the last solve with these factors
      real(dp) :: contraction = 1.0_dp
      !> When it last served a solve (a count of solves), for replacing the oldest
      integer(i8) :: last_used = 0
   end type kept_factorization_type

   !> Newton's method with one Newton matrix (its factors kept for up to two step
   !> sizes) and what each was built for
   type :: newton_solver_type
      !> Factored Newton matrices; the second is allocated when settings ask for it
      type(kept_factorization_type) :: kept(2)
      !> Unknowns, for a second factorization allocated later
      integer :: m = 0
      !> Matrix structure, for a second factorization allocated later (of the stacked
      !> matrix for a stacked solver)
      type(matrix_structure_type) :: structure
      !> Whether the Newton matrix A - B C is factored as [[A, B], [C, I]], of order 2m
      logical :: stacked = .false.
      !> The stacked right-hand side [b; 0] and solution [x; y], interleaved
      real(dp), allocatable :: stacked_vector(:)
      !> Solves so far
      integer(i8) :: solves = 0
      !> Contraction factor of the last two increments of the last solve (0 when it
      !> converged in one iteration)
      real(dp) :: last_contraction = 0.0_dp
      !> Residual, then the Newton increment
      real(dp), allocatable :: increment(:)
      !> What the increment becomes in the next step (systems that propagate errors)
      real(dp), allocatable :: propagated(:)
      !> 1 / tolerance of the current solve (the increments are measured by products)
      real(dp), allocatable :: inverse_tolerance(:)
      !> The kept factorization the last solve used
      integer :: last_slot = 1
      !> A quarter of the shortest step at which a solve kept no digit of its residual
      !> (huge: none since the last `forget`): longer steps cannot be solved for
      real(dp) :: step_limit = huge(1.0_dp)
   contains
      !> Allocate for systems of size m with a Newton matrix of the given structure
      procedure :: init
      !> Solve a system from the guess in u
      procedure :: solve
      !> Forget the factors (a new integration or a new problem)
      procedure :: forget
      !> x = M^(-1) x with the Newton matrix the last solve used
      procedure :: apply_inverse
   end type newton_solver_type

   abstract interface
      !> Residual r(u) of the system for the current step.
      subroutine residual_interface(self, problem, u, r, counters)
         import :: nonlinear_system_type, ode_problem, dp, counters_type
         !> The system (holds the data of the current step)
         class(nonlinear_system_type), intent(inout) :: self
         !> The problem
         class(ode_problem), intent(inout) :: problem
         !> Current iterate
         real(dp), intent(in) :: u(:)
         !> Residual at u
         real(dp), contiguous, intent(out) :: r(:)
         !> Evaluations are counted here
         type(counters_type), intent(inout) :: counters
      end subroutine residual_interface

      !> Newton matrix at u. Newton calls it only right after `residual` at the same u,
      !> so values computed there may be reused. For a stacked solver `matrix` has order
      !> 2m and receives the blocks A, B, C of [[A, B], [C, I]] (the identity included),
      !> block (r, c) entry (i, j) at row 2i - 2 + r, column 2j - 2 + c.
      subroutine newton_matrix_interface(self, problem, u, matrix, counters, stat)
         import :: nonlinear_system_type, ode_problem, dp, matrix_type, counters_type, status_type
         !> The system
         class(nonlinear_system_type), intent(inout) :: self
         !> The problem
         class(ode_problem), intent(inout) :: problem
         !> Current iterate
         real(dp), intent(in) :: u(:)
         !> The matrix to assemble
         class(matrix_type), intent(inout) :: matrix
         !> Evaluations are counted here
         type(counters_type), intent(inout) :: counters
         !> Storage mismatches of the assembly
         type(status_type), intent(inout) :: stat
      end subroutine newton_matrix_interface
   end interface

contains

   !> propagated = P e, what an error e of the solution adds to the right-hand side of
   !> the next step's equation beyond e itself (a scheme that evaluates a stiff part
   !> explicitly there amplifies it: si-t-2), with active = .true.; Newton's stop test
   !> then also measures its increments by M^(-1) P e, what they become in the next
   !> step, so that what Newton leaves undone stays small there too. The default, for
   !> systems whose errors the next step does not amplify, sets active = .false.
   subroutine propagate(self, error, propagated, active)
      !> The system
      class(nonlinear_system_type), intent(inout) :: self
      !> The error of the solution (a Newton increment)
      real(dp), intent(in) :: error(:)
      !> P e
      real(dp), intent(out) :: propagated(:)
      !> Whether the system propagates errors (else propagated is not set)
      logical, intent(out) :: active
      active = .false.
   end subroutine propagate

   !> Allocate for systems of m unknowns whose Newton matrix has the given structure
   !> (with `stacked`: whose Newton matrix A - B C is factored as [[A, B], [C, I]], the
   !> blocks A, B, C of that structure).
   subroutine init(self, m, structure, stat, stacked)
      !> The solver
      class(newton_solver_type), intent(inout) :: self
      !> Unknowns of the system
      integer, intent(in) :: m
      !> Storage and bandwidths of the Newton matrix (of its blocks when stacked)
      type(matrix_structure_type), intent(in) :: structure
      !> status_invalid_argument for an impossible structure, status_out_of_memory
      type(status_type), intent(inout) :: stat
      !> Whether the Newton matrix is factored as a stacked block matrix (default: no)
      logical, intent(in), optional :: stacked
      character(len=*), parameter :: what = "the Newton solver's work arrays"
      self%m = m
      self%stacked = .false.
      if (present(stacked)) self%stacked = stacked
      self%structure = structure
      if (self%stacked) self%structure = stacked_structure(structure)
      call new_linear_solver(self%kept(1)%linear, merge(2*m, m, self%stacked), self%structure, stat)
      ! a second factorization is allocated again when a solve asks for it
      self%kept(2) = kept_factorization_type()
      call sized(self%increment, m, what, stat)
      call sized(self%inverse_tolerance, m, what, stat)
      call sized(self%propagated, m, what, stat)
      call sized(self%stacked_vector, merge(2*m, 0, self%stacked), what, stat)
      call self%forget()
   end subroutine init

   !> Forget the factored matrices.
   elemental subroutine forget(self)
      !> The solver
      class(newton_solver_type), intent(inout) :: self
      self%kept%linear%factored = .false.
      self%kept%contraction = 1.0_dp
      self%step_limit = huge(1.0_dp)
   end subroutine forget

   !> x = M^(-1) x with the factored Newton matrix of the last solve (a filter for
   !> error estimates: it damps the components along the stiff directions as the
   !> step damps them). status_invalid_argument (code only) when it holds no factors.
   subroutine apply_inverse(self, x, counters, stat)
      !> The solver, after a successful solve
      class(newton_solver_type), intent(inout) :: self
      !> Vector on entry, M^(-1) times it on exit
      real(dp), contiguous, intent(inout) :: x(:)
      !> The linear solve is counted here
      type(counters_type), intent(inout) :: counters
      !> status_invalid_argument when there are no factors
      type(status_type), intent(inout) :: stat
      call solve_linear(self, self%last_slot, x, stat)
      counters%linear_solves = counters%linear_solves + 1
   end subroutine apply_inverse

   !> x = M^(-1) x with the factors kept in `slot`: directly, or for a stacked solver
   !> as the first half of [[A, B], [C, I]]^(-1) [x; 0].
   subroutine solve_linear(self, slot, x, stat)
      !> The solver
      class(newton_solver_type), intent(inout) :: self
      !> The kept factorization to use
      integer, intent(in) :: slot
      !> Right-hand side on entry, solution on exit
      real(dp), contiguous, intent(inout) :: x(:)
      !> status_invalid_argument when there are no factors
      type(status_type), intent(inout) :: stat
      if (self%stacked) then
         call self%kept(slot)%linear%solve_stacked(size(x), x, self%stacked_vector, stat)
      else
         call self%kept(slot)%linear%solve(x, stat)
      end if
   end subroutine solve_linear

   !> Newton's method for system%residual(u) = 0 from the guess in u. The matrix is
   !> built and factored at the first iterate, or kept from an earlier solve while h
   !> changed by at most 20 % and that solve contracted by 0.1 or better; it is
   !> rebuilt at the current iterate whenever the iteration contracts poorly or too
   !> slowly to converge within the iteration limit. Each iteration costs one
   !> residual and one LU solve. Converged when the error left, estimated as
   !> theta/(1 - theta) max_i |increment_i| / tolerance_i with theta the contraction
   !> of the last two increments with one matrix, is at most 1 (the first increment of a
   !> kept matrix counts as its own estimate, that of a matrix just built as none, an
   !> increment that did not contract as none; one within the rounding of the iterate
   !> ends the iteration) (or, without
   !> settings%estimate_error, when every |increment_i| <= tolerance_i), and what the
   !> increment becomes in the next step (`propagate`) is within the tolerances too.
   !> A failure is reported by its code alone (no message is built, nothing is
   !> allocated): status_singular_matrix (a zero pivot, or a zero correction of a nonzero
   !> residual that did not underflow), status_newton_diverged,
   !> status_newton_not_converged, status_nonfinite (the residual, that is f or g, gave
   !> NaN or Inf, or a Jacobian did) or
   !> status_evaluation_failed (the problem rejected an evaluation).
   subroutine solve(self, system, problem, h, settings, u, counters, stat)
      !> The solver
      class(newton_solver_type), intent(inout) :: self
      !> The system to solve, set up for the current step
      class(nonlinear_system_type), intent(inout) :: system
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Step size the system belongs to (decides whether kept factors still serve)
      real(dp), intent(in) :: h
      !> Tolerance, iteration limit and reuse policy
      type(newton_settings_type), intent(in) :: settings
      !> Initial guess on entry, solution on exit
      real(dp), intent(inout) :: u(:)
      !> Evaluations, factorizations, solves and iterations are counted here
      type(counters_type), intent(inout) :: counters
      !> Outcome (singular matrix, divergence or no convergence)
      type(status_type), intent(inout) :: stat

      integer :: iteration, least_iterations, m, slot
      logical :: rebuild, known, fresh, first, estimated, finite, solved
      real(dp) :: size_now, size_before, contraction, error_factor, residual_largest

      m = size(u)
      call invert_tolerances(m, size(settings%tolerance), settings%tolerance, self%inverse_tolerance)
      call choose_factorization(slot, rebuild, stat)
      if (stat%code /= status_ok) return
      self%solves = self%solves + 1
      self%kept(slot)%last_used = self%solves
      self%last_slot = slot
      ! with a kept matrix one small increment says little about the error left:
      ! a second iteration measures the contraction
      least_iterations = merge(1, 2, rebuild .or. settings%estimate_error)
      ! the first increment of a kept matrix is its own error estimate: a contraction
      ! carried over from another solve (RADAU5's FACCON**0.8) says little about this
      ! one, and accepting a first increment far above the tolerance let si-t-2 stop
      ! short of the solution at the folds of Van der Pol (mu = 1e6: error 3.5 instead
      ! of 0.14, 2.6 times the steps). A matrix built at an iterate off the solution's
      ! manifold can make its first increment far too small (i-t-2's second-derivative
      ! term: 2e-3 of the distance to the root on Van der Pol's slow branch), so a new
      ! matrix's first increment is never accepted alone; its contraction is measured
      ! with the same matrix (a rebuilt matrix starts the measurement afresh)
      error_factor = 1.0_dp
      estimated = .true.
      size_before = huge(1.0_dp)
      fresh = .false.
      solved = .false.
      do iteration = 1, settings%max_iterations
         call system%residual(problem, u, self%increment, counters)
         counters%newton_iterations = counters%newton_iterations + 1
         if (problem%evaluation_rejected()) then
            call set_code(stat, status_evaluation_failed)
            return
         end if
         ! the residual is finite (else f or g gave NaN or Inf); its negative is the
         ! right-hand side of the Newton correction
         call negate_finite(m, self%increment, finite, residual_largest)
         if (.not. finite) then
            call set_code(stat, status_nonfinite)
            return
         end if
         if (rebuild) then
            ! a new matrix: its contraction is measured afresh
            size_before = huge(1.0_dp)
            fresh = .true.
            call self%kept(slot)%linear%matrix%set_zero()
            call system%newton_matrix(problem, u, self%kept(slot)%linear%matrix, counters, stat)
            if (stat%code /= status_ok) return
            call self%kept(slot)%linear%factor(stat)
            counters%lu_factorizations = counters%lu_factorizations + 1
            self%kept(slot)%h_built = h
            if (stat%code /= status_ok) return
            rebuild = .false.
         end if
         call solve_linear(self, slot, self%increment, stat)
         counters%linear_solves = counters%linear_solves + 1
         if (stat%code /= status_ok) return
         ! the update and the size of the increment in the tolerances
         call add_increment(m, self%increment, self%inverse_tolerance, u, size_now, finite)
         if (.not. finite) then
            call set_code(stat, status_newton_diverged)
            self%kept(slot)%linear%factored = .false.
            return
         end if
         ! a zero correction of a nonzero residual is no sign of convergence unless it
         ! underflowed: else the solve kept no digit of the residual, the matrix being
         ! singular in working precision (the stacked matrices' Schur complement once
         ! h |lambda| nears 1/epsilon, where 1 + h |lambda| rounds to h |lambda|, and i-t-2
         ! or si-t-2 would accept their starting guess, however wrong)
         if (size_now == 0.0_dp) then
            if (residual_largest > 0.0_dp) then
               if (.not. correction_underflows()) then
                  self%kept(slot)%linear%factored = .false.
                  self%step_limit = min(self%step_limit, step_limit_fraction*h)
                  call set_code(stat, status_singular_matrix)
                  return
               end if
            end if
         end if
         ! after an exactly zero increment the contraction is unknown: it then neither
         ! triggers a rebuild nor a divergence verdict, and the factors are not kept
         known = size_before > 0.0_dp
         ! a linear system with a matrix exact for this step is solved (up to roundoff)
         if (system%linear .and. self%kept(slot)%h_built == h) then
            solved = .true.
            exit
         end if
         if (.not. settings%estimate_error .and. size_now <= 1.0_dp .and. iteration >= least_iterations) then
            if (propagation_within(1.0_dp)) then
               solved = .true.
               exit
            end if
            if (stat%code /= status_ok) return
         end if
         ! (nothing to compare the first increment with: its contraction counts as 0)
         first = size_before == huge(1.0_dp)
         contraction = 0.0_dp
         if (known .and. .not. first) contraction = size_now/size_before
         if (settings%estimate_error) then
            if (first) then
               ! a matrix built in this solve says nothing yet of the nonlinearity
               ! between the iterate and the solution: its first increment is no error
               ! estimate (one kept from a solve that contracted well is taken as one)
               estimated = .not. fresh
               error_factor = 1.0_dp
            else if (known) then
               ! an increment that did not contract estimates nothing either
               estimated = contraction < 1.0_dp
               if (estimated) error_factor = contraction/(1.0_dp - contraction)
            end if
            ! an increment within the rounding of the iterate cannot be resolved further
            ! (looked at only where it changes the verdict)
            if (size_now <= 1.0_dp .and. (.not. estimated .or. error_factor > 1.0_dp)) then
               if (within_rounding(m, self%increment, self%inverse_tolerance, u)) then
                  estimated = .true.
                  error_factor = min(error_factor, 1.0_dp)
               end if
            end if
            if (estimated .and. error_factor*size_now <= 1.0_dp) then
               if (propagation_within(error_factor)) then
                  solved = .true.
                  exit
               end if
               if (stat%code /= status_ok) return
            end if
         end if
         if (known .and. contraction >= divergence_contraction .and. fresh) then
            self%kept(slot)%linear%factored = .false.
            call set_code(stat, status_newton_diverged)
            return
         end if
         ! rebuild on poor contraction, or when at this rate the iteration limit
         ! would come before convergence
         if (known .and. contraction > refresh_contraction) rebuild = .true.
         if (known .and. .not. first .and. contraction < 1.0_dp .and. .not. rebuild) then
            if (too_slow(size_now, contraction, settings%max_iterations - iteration)) rebuild = .true.
         end if
         size_before = size_now
      end do
      if (.not. solved) then
         self%kept(slot)%linear%factored = .false.
         call set_code(stat, status_newton_not_converged)
         return
      end if
      ! the contraction of the last two increments (0 after one iteration, huge when it
      ! is unknown), kept for the decision to reuse the factors
      self%last_contraction = 0.0_dp
      if (iteration > 1) then
         self%last_contraction = huge(1.0_dp)
         if (known) self%last_contraction = size_now/size_before
      end if
      self%kept(slot)%contraction = self%last_contraction

   contains

      !> The kept factorization to use (a slot whose step size is within 20 % of h and
      !> whose last solve contracted by 0.1 or better), or the one to rebuild: the
      !> other slot while a second one is allowed, else the one used longest ago.
      subroutine choose_factorization(slot, rebuild, stat)
         integer, intent(out) :: slot
         logical, intent(out) :: rebuild
         type(status_type), intent(inout) :: stat
         integer :: j, slots
         real(dp) :: best
         slots = max(1, min(settings%kept_factorizations, size(self%kept)))
         slot = 0
         best = huge(1.0_dp)
         do j = 1, slots
            associate (kept => self%kept(j))
               if (.not. allocated(kept%linear%matrix)) cycle
               if (.not. (settings%reuse_matrix .and. kept%linear%factored .and. &
                  abs(h - kept%h_built) <= reuse_step_change*kept%h_built .and. &
                  kept%contraction <= reuse_contraction)) cycle
               if (abs(h - kept%h_built) < best) then
                  best = abs(h - kept%h_built)
                  slot = j
               end if
            end associate
         end do
         rebuild = slot == 0
         if (.not. rebuild) return
         slot = 1
         do j = 2, slots
            if (.not. allocated(self%kept(j)%linear%matrix)) then
               ! the second factorization is allocated when it is first asked for
               call new_linear_solver(self%kept(j)%linear, merge(2*self%m, self%m, self%stacked), self%structure, stat)
               slot = j
               return
            end if
            if (self%kept(j)%last_used < self%kept(slot)%last_used) slot = j
         end do
      end subroutine choose_factorization

      !> Whether what the last increment becomes in the next step (the system's
      !> `propagate`, P d), times factor, is within the tolerances: P d itself when it
      !> is, else M^(-1) P d (one more solve), what the next step's implicit solve leaves
      !> of it. True for systems that propagate nothing.
      logical function propagation_within(factor)
         real(dp), intent(in) :: factor
         logical :: propagates
         call system%propagate(self%increment, self%propagated, propagates)
         propagation_within = .true.
         if (.not. propagates) return
         if (factor*weighted_size(self%propagated) <= 1.0_dp) return
         call solve_linear(self, slot, self%propagated, stat)
         counters%linear_solves = counters%linear_solves + 1
         propagation_within = factor*weighted_size(self%propagated) <= 1.0_dp .and. stat%code == status_ok
      end function propagation_within

      !> Whether the zero correction of the last iteration underflowed: the residual
      !> at u again, scaled by a power of 2 to a largest entry near 1 (exactly), has a
      !> correction that is not zero. A solve that cancels the residual away gives
      !> zero at any scale.
      logical function correction_underflows()
         real(dp) :: largest
         logical :: residual_finite
         correction_underflows = .false.
         call system%residual(problem, u, self%increment, counters)
         if (problem%evaluation_rejected()) return
         call negate_finite(m, self%increment, residual_finite, largest)
         if (.not. (residual_finite .and. largest > 0.0_dp)) return
         self%increment(1:m) = scale(self%increment(1:m), -exponent(largest))
         call solve_linear(self, slot, self%increment, stat)
         counters%linear_solves = counters%linear_solves + 1
         if (stat%code /= status_ok) return
         correction_underflows = any(self%increment(1:m) /= 0.0_dp)
         self%increment(1:m) = 0.0_dp
      end function correction_underflows

      !> max_i |v_i| / tolerance_i
      real(dp) function weighted_size(v)
         real(dp), intent(in) :: v(:)
         integer :: j
         weighted_size = 0.0_dp
         do j = 1, m
            weighted_size = max(weighted_size, abs(v(j))*self%inverse_tolerance(j))
         end do
      end function weighted_size

   end subroutine solve

   !> inverse(i) = 1 / tolerance(k) for the m unknowns of a system, k running through
   !> the n tolerances again for each copy of the state a system stacks (explicit-shape,
   !> as negate_finite).
   pure subroutine invert_tolerances(m, n, tolerance, inverse)
      integer, intent(in) :: m, n
      real(dp), intent(in) :: tolerance(n)
      real(dp), intent(out) :: inverse(m)
      integer :: i, k
      k = 0
      !GCC$ unroll 1
      do i = 1, m
         k = k + 1
         if (k > n) k = 1
         inverse(i) = 1.0_dp/tolerance(k)
      end do
   end subroutine invert_tolerances

   !> v = -v, stopping at the first entry that is not finite (finite false), and the
   !> largest |v_i|; explicit-shape so that the loop does not reload the solver's
   !> descriptors at every entry (on a few unknowns that cost more than the arithmetic).
   pure subroutine negate_finite(m, v, finite, largest)
      integer, intent(in) :: m
      real(dp), intent(inout) :: v(m)
      logical, intent(out) :: finite
      real(dp), intent(out) :: largest
      integer :: i
      finite = .false.
      largest = 0.0_dp
      !GCC$ unroll 1
      do i = 1, m
         if (.not. ieee_is_finite(v(i))) return
         largest = max(largest, abs(v(i)))
         v(i) = -v(i)
      end do
      finite = .true.
   end subroutine negate_finite

   !> Whether an iteration that contracts by `contraction` (0 <= contraction < 1) from an
   !> increment of size_now leaves more than 1 after `remaining` more iterations:
   !> size_now contraction**remaining / (1 - contraction) > 1. The rounded power of a
   !> contraction below 1 is at most the contraction itself, so that the power (a call)
   !> is taken only when the first factor does not decide already.
   pure logical function too_slow(size_now, contraction, remaining)
      real(dp), intent(in) :: size_now, contraction
      integer, intent(in) :: remaining
      too_slow = .false.
      if (remaining >= 1 .and. size_now*contraction/(1.0_dp - contraction) <= 1.0_dp) return
      too_slow = size_now*contraction**remaining/(1.0_dp - contraction) > 1.0_dp
   end function too_slow

   !> u = u + increment, entry by entry, stopping at the first u_i that is not finite
   !> (finite false); size_now = max_i |increment_i| / tolerance_i (explicit-shape, as
   !> negate_finite).
   pure subroutine add_increment(m, increment, inverse_tolerance, u, size_now, finite)
      integer, intent(in) :: m
      real(dp), intent(in) :: increment(m), inverse_tolerance(m)
      ! assumed-shape: the caller's state is passed as it is (an explicit-shape dummy
      ! would have it copied in and out wherever it is not known to be contiguous)
      real(dp), intent(inout) :: u(:)
      real(dp), intent(out) :: size_now
      logical, intent(out) :: finite
      integer :: i
      size_now = 0.0_dp
      finite = .false.
      !GCC$ unroll 1
      do i = 1, m
         u(i) = u(i) + increment(i)
         if (.not. ieee_is_finite(u(i))) return
         size_now = max(size_now, abs(increment(i))*inverse_tolerance(i))
      end do
      finite = .true.
   end subroutine add_increment

   !> Whether every |increment_i| of the increment just added to u is within rounding_ulps
   !> ulps of |u_i| or of tolerance_i (a component at 0 has no ulps to speak of: HIRES's
   !> second from its start, whose increments of 1e-41, 1e-28 of its tolerance, kept
   !> i-t-1's Newton for its error estimate from ending at every step size)
   !> (explicit-shape, as negate_finite).
   pure logical function within_rounding(m, increment, inverse_tolerance, u)
      integer, intent(in) :: m
      real(dp), intent(in) :: increment(m), inverse_tolerance(m)
      real(dp), intent(in) :: u(:)
      integer :: i
      within_rounding = .false.
      !GCC$ unroll 1
      do i = 1, m
         if (.not. (abs(increment(i)) <= rounding_ulps*epsilon(1.0_dp)*abs(u(i)) &
            .or. abs(increment(i))*inverse_tolerance(i) <= rounding_ulps*epsilon(1.0_dp))) return
      end do
      within_rounding = .true.
   end function within_rounding

end module taylorode_newton_solver
