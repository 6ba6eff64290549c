!> The abstract one-step scheme, its evaluation counters and the Newton solver
!> shared by every implicit scheme.
!>
!> A scheme advances U0 at t by one step h to U1 and, when asked, also returns
!> delta = U_high - U_low, the difference between the two members of its
!> embedded pair computed from the same U0 (the adaptive integrator's error
!> estimate). Schemes keep their work arrays between steps: after the first
!> step of a given size no step allocates.
module taylorode_scheme
   use taylorode_kinds, only: dp, i8
   use taylorode_status, only: status_type, set_status, status_ok, status_invalid_argument, &
      status_size_mismatch, status_nonfinite, status_singular_matrix, status_newton_diverged, &
      status_newton_not_converged
   use taylorode_problem, only: ode_problem
   use taylorode_matrix, only: matrix_type, dense_matrix_type, band_matrix_type, new_matrix
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: scheme_type, implicit_scheme_type, counters_type
   public :: default_newton_tolerance, default_max_newton_iterations, newton_system_type

   !> Newton increment tolerance, relative to 1 + |U0|, when the caller gives none
   real(dp), parameter :: default_newton_tolerance = 1.0e-13_dp
   !> Newton iterations allowed for one nonlinear system before the step fails
   integer, parameter :: default_max_newton_iterations = 10
   !> Contraction factor above which the Newton matrix is rebuilt at the current iterate
   real(dp), parameter :: refresh_contraction = 0.25_dp
   !> Contraction factor (after a rebuild) at which the iteration is declared divergent
   real(dp), parameter :: divergence_contraction = 2.0_dp
   !> A factored Newton matrix serves a later step while h differs by at most this
   !> fraction from the h it was built with ...
   real(dp), parameter :: reuse_step_change = 0.2_dp
   !> ... and its last solve contracted at least this fast
   real(dp), parameter :: reuse_contraction = 0.1_dp
   !> Nonlinear systems a scheme may solve per step, each with its own Newton matrix
   integer, parameter :: max_systems = 3

   !> Work counters of a scheme, accumulated over all its steps
   type :: counters_type
      !> Evaluations of the non-stiff part f
      integer(i8) :: f_evaluations = 0
      !> Evaluations of the stiff part g
      integer(i8) :: g_evaluations = 0
      !> Evaluations of df/dU
      integer(i8) :: jac_f_evaluations = 0
      !> Evaluations of dg/dU
      integer(i8) :: jac_g_evaluations = 0
      !> LU factorizations of Newton matrices
      integer(i8) :: lu_factorizations = 0
      !> Linear solves with an LU factorization
      integer(i8) :: linear_solves = 0
      !> Newton iterations over all nonlinear systems
      integer(i8) :: newton_iterations = 0
   end type counters_type

   !> Abstract one-step scheme
   type, abstract :: scheme_type
      !> Name as users type it (e.g. "i-t-2")
      character(len=:), allocatable :: name
      !> Order of the member that advances the solution
      integer :: order = 0
      !> Order of the other member of the embedded pair
      integer :: embedded_order = 0
      !> Work done so far
      type(counters_type) :: counters
      !> Size and Jacobian bandwidths the work arrays are prepared for (kl < 0: dense)
      integer :: n = 0, kl = -2, ku = -2
   contains
      !> One step with argument checks (sizes, h > 0, finite data)
      procedure, non_overridable :: take_step
      !> One step without checks: the drivers call it after checking once
      procedure(advance_interface), deferred :: advance
      !> Allocate work arrays for systems of size n (no-op when already sized)
      procedure(prepare_interface), deferred :: prepare
      !> Forget what is kept from earlier steps (a new integration or a new problem)
      procedure :: restart
      !> Record the size and bandwidths to prepare for; false when unchanged
      procedure, non_overridable :: resize
      !> Counted evaluation of f
      procedure, non_overridable :: eval_f
      !> Counted evaluation of g
      procedure, non_overridable :: eval_g
      !> Counted evaluation of df/dU
      procedure, non_overridable :: eval_jac_f
      !> Counted evaluation of dg/dU
      procedure, non_overridable :: eval_jac_g
   end type scheme_type

   !> The Newton matrix of one nonlinear system of a scheme and what it was built for
   type :: newton_system_type
      !> The matrix, then its LU factors
      class(matrix_type), allocatable :: matrix
      !> Whether the factors are usable
      logical :: factored = .false.
      !> Step size the matrix was built with
      real(dp) :: h_built = 0.0_dp
      !> Contraction of the last solve with these factors
      real(dp) :: contraction = 1.0_dp
   end type newton_system_type

   !> Scheme with nonlinear systems r(U) = 0 solved by Newton's method
   type, abstract, extends(scheme_type) :: implicit_scheme_type
      !> Newton iterations allowed per nonlinear system
      integer :: max_newton_iterations = default_max_newton_iterations
      !> Keep factored Newton matrices across steps while h changes little and
      !> Newton converges fast (otherwise every solve builds its matrix afresh)
      logical :: reuse_newton_matrix = .true.
      !> Start of the current step
      real(dp) :: t0 = 0.0_dp
      !> Size of the current step
      real(dp) :: h = 0.0_dp
      !> Absolute tolerance on each component of a Newton increment for the current step
      real(dp), allocatable :: newton_tolerance(:)
      !> Residual, then the Newton increment
      real(dp), allocatable :: newton_increment(:)
      !> One Newton matrix per nonlinear system
      type(newton_system_type) :: systems(max_systems)
      !> Contraction factor of the last two increments of the last Newton solve
      !> (0 when it converged in one iteration)
      real(dp) :: last_contraction = 0.0_dp
   contains
      !> Residual r(U) of nonlinear system `system` of the current step
      procedure(residual_interface), deferred :: residual
      !> Newton matrix (approximate dr/dU) of system `system`
      procedure(iteration_matrix_interface), deferred :: iteration_matrix
      !> Newton's method for system `system`, from the guess in u
      procedure, non_overridable :: solve_implicit
      !> Allocate the Newton work arrays and matrices
      procedure, non_overridable :: prepare_newton
      !> Set the Newton tolerance of the current step
      procedure, non_overridable :: begin_implicit_step
      !> Forget the factored Newton matrices
      procedure :: restart => implicit_restart
   end type implicit_scheme_type

   abstract interface
      !> Advance u0 at t by h into u1; delta = U_high - U_low when present.
      subroutine advance_interface(self, problem, t, h, u0, u1, stat, delta, newton_tolerance)
         import :: scheme_type, ode_problem, dp, status_type
         !> The scheme
         class(scheme_type), intent(inout) :: self
         !> The problem
         class(ode_problem), intent(inout) :: problem
         !> Start of the step
         real(dp), intent(in) :: t
         !> Step size
         real(dp), intent(in) :: h
         !> State at t
         real(dp), intent(in) :: u0(:)
         !> State at t + h
         real(dp), intent(out) :: u1(:)
         !> Status: Newton failures of the step
         type(status_type), intent(inout) :: stat
         !> Difference of the embedded pair, computed only when present
         real(dp), intent(out), optional :: delta(:)
         !> Absolute tolerance on Newton increments, per component
         real(dp), intent(in), optional :: newton_tolerance(:)
      end subroutine advance_interface

      !> Allocate work arrays (dense or banded as the problem declares) for size n.
      subroutine prepare_interface(self, problem, n)
         import :: scheme_type, ode_problem
         !> The scheme
         class(scheme_type), intent(inout) :: self
         !> The problem (its bandwidths decide the storage)
         class(ode_problem), intent(in) :: problem
         !> Number of unknowns
         integer, intent(in) :: n
      end subroutine prepare_interface

      !> Residual r(u) of nonlinear system `system` of the current step.
      subroutine residual_interface(self, problem, system, u, r)
         import :: implicit_scheme_type, ode_problem, dp
         !> The scheme (holds the data of the current step)
         class(implicit_scheme_type), intent(inout) :: self
         !> The problem
         class(ode_problem), intent(inout) :: problem
         !> Which nonlinear system of the scheme
         integer, intent(in) :: system
         !> Current iterate
         real(dp), intent(in) :: u(:)
         !> Residual at u
         real(dp), intent(out) :: r(:)
      end subroutine residual_interface

      !> Newton matrix of system `system` at u, into self%systems(system)%matrix.
      !> The Newton solver calls it only right after `residual` at the same u, so
      !> values computed there may be reused.
      subroutine iteration_matrix_interface(self, problem, system, u)
         import :: implicit_scheme_type, ode_problem, dp
         !> The scheme
         class(implicit_scheme_type), intent(inout) :: self
         !> The problem
         class(ode_problem), intent(inout) :: problem
         !> Which nonlinear system of the scheme
         integer, intent(in) :: system
         !> Current iterate
         real(dp), intent(in) :: u(:)
      end subroutine iteration_matrix_interface
   end interface

contains

   !> One step of the scheme after checking its arguments: sizes agree, h > 0 and
   !> finite, u0 finite. On any failure stat says why and u1 is set to u0. Each call
   !> is a fresh step: nothing kept from earlier steps (factored Newton matrices) is used.
   subroutine take_step(self, problem, t, h, u0, u1, stat, delta)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Start of the step
      real(dp), intent(in) :: t
      !> Step size, > 0
      real(dp), intent(in) :: h
      !> State at t
      real(dp), intent(in) :: u0(:)
      !> State at t + h
      real(dp), intent(out) :: u1(:)
      !> Status of the step
      type(status_type), intent(out) :: stat
      !> Difference of the embedded pair U_high - U_low, computed only when present
      real(dp), intent(out), optional :: delta(:)

      if (size(u1) /= size(u0)) then
         call set_status(stat, status_size_mismatch, "take_step: u1 has a different size from u0")
         return
      end if
      u1 = u0
      if (present(delta)) then
         if (size(delta) /= size(u0)) then
            call set_status(stat, status_size_mismatch, "take_step: delta has a different size from u0")
            return
         end if
         delta = 0.0_dp
      end if
      if (size(u0) < 1) then
         call set_status(stat, status_size_mismatch, "take_step: the state is empty")
         return
      end if
      if (.not. (h > 0.0_dp) .or. .not. ieee_is_finite(h)) then
         call set_status(stat, status_invalid_argument, "take_step: the step size h must be positive and finite")
         return
      end if
      if (.not. ieee_is_finite(t)) then
         call set_status(stat, status_invalid_argument, "take_step: t is not finite")
         return
      end if
      if (.not. all(ieee_is_finite(u0))) then
         call set_status(stat, status_nonfinite, "take_step: the state u0 contains NaN or Inf")
         return
      end if
      call self%prepare(problem, size(u0))
      call self%restart()
      call self%advance(problem, t, h, u0, u1, stat, delta)
      if (stat%code == status_ok .and. .not. all(ieee_is_finite(u1))) then
         call set_status(stat, status_nonfinite, "take_step: the new state contains NaN or Inf")
      end if
   end subroutine take_step

   !> Forget what is kept from earlier steps; the Taylor schemes keep nothing.
   subroutine restart(self)
      !> The scheme
      class(scheme_type), intent(inout) :: self
   end subroutine restart

   !> Record size n and the problem's bandwidths; true when they differ from what the
   !> work arrays were prepared for (the caller then reallocates).
   logical function resize(self, problem, n)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(in) :: problem
      !> Number of unknowns
      integer, intent(in) :: n
      integer :: kl, ku
      call problem%bandwidths(n, kl, ku)
      resize = .not. (self%n == n .and. self%kl == kl .and. self%ku == ku)
      self%n = n
      self%kl = kl
      self%ku = ku
   end function resize

   !> Counted evaluation of f.
   subroutine eval_f(self, problem, t, u, value)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> f(t, u)
      real(dp), intent(out) :: value(:)
      call problem%f(t, u, value)
      self%counters%f_evaluations = self%counters%f_evaluations + 1
   end subroutine eval_f

   !> Counted evaluation of g.
   subroutine eval_g(self, problem, t, u, value)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> g(t, u)
      real(dp), intent(out) :: value(:)
      call problem%g(t, u, value)
      self%counters%g_evaluations = self%counters%g_evaluations + 1
   end subroutine eval_g

   !> Counted evaluation of df/dU, dense or in band storage.
   subroutine eval_jac_f(self, problem, t, u, jac)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> df/dU at (t, u)
      class(matrix_type), intent(inout) :: jac
      call evaluate_jacobian(problem, .true., t, u, jac)
      self%counters%jac_f_evaluations = self%counters%jac_f_evaluations + 1
   end subroutine eval_jac_f

   !> Counted evaluation of dg/dU, dense or in band storage.
   subroutine eval_jac_g(self, problem, t, u, jac)
      !> The scheme
      class(scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> dg/dU at (t, u)
      class(matrix_type), intent(inout) :: jac
      call evaluate_jacobian(problem, .false., t, u, jac)
      self%counters%jac_g_evaluations = self%counters%jac_g_evaluations + 1
   end subroutine eval_jac_g

   !> The problem's df/dU (`of_f`) or dg/dU into a dense matrix or its band storage.
   subroutine evaluate_jacobian(problem, of_f, t, u, jac)
      class(ode_problem), intent(inout) :: problem
      logical, intent(in) :: of_f
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      class(matrix_type), intent(inout) :: jac
      select type (jac)
      type is (dense_matrix_type)
         if (of_f) then
            call problem%jac_f(t, u, jac%a)
         else
            call problem%jac_g(t, u, jac%a)
         end if
      type is (band_matrix_type)
         if (of_f) then
            call problem%jac_f_band(t, u, jac%ab(jac%kl + 1:, :))
         else
            call problem%jac_g_band(t, u, jac%ab(jac%kl + 1:, :))
         end if
      end select
   end subroutine evaluate_jacobian

   !> Allocate the Newton work arrays for n unknowns and `systems` Newton matrices
   !> with bandwidths kl, ku (kl < 0: dense).
   subroutine prepare_newton(self, n, systems, kl, ku)
      !> The scheme
      class(implicit_scheme_type), intent(inout) :: self
      !> Number of unknowns of each nonlinear system
      integer, intent(in) :: n
      !> Number of nonlinear systems
      integer, intent(in) :: systems
      !> Bandwidths of the Newton matrices (kl < 0: dense)
      integer, intent(in) :: kl, ku
      integer :: k
      if (allocated(self%newton_increment)) deallocate (self%newton_tolerance, self%newton_increment)
      allocate (self%newton_tolerance(n), self%newton_increment(n))
      do k = 1, systems
         call new_matrix(self%systems(k)%matrix, n, kl, ku)
         self%systems(k)%factored = .false.
      end do
   end subroutine prepare_newton

   !> Forget the factored Newton matrices (a new integration or a new problem).
   subroutine implicit_restart(self)
      !> The scheme
      class(implicit_scheme_type), intent(inout) :: self
      self%systems%factored = .false.
   end subroutine implicit_restart

   !> Record t, h and the Newton tolerance for the step about to be taken: the
   !> caller's per-component tolerance, or default_newton_tolerance * (1 + |u0|). A
   !> scheme whose nonlinear system stacks several copies of the state (radau5: three
   !> stages) gets the tolerance repeated for each copy.
   subroutine begin_implicit_step(self, t, h, u0, newton_tolerance)
      !> The scheme
      class(implicit_scheme_type), intent(inout) :: self
      !> Start of the step
      real(dp), intent(in) :: t
      !> Step size
      real(dp), intent(in) :: h
      !> State at t
      real(dp), intent(in) :: u0(:)
      !> Caller's absolute tolerance per component
      real(dp), intent(in), optional :: newton_tolerance(:)
      integer :: n, block
      self%t0 = t
      self%h = h
      n = size(u0)
      do block = 0, size(self%newton_tolerance)/n - 1
         associate (tolerance => self%newton_tolerance(block*n + 1:(block + 1)*n))
            if (present(newton_tolerance)) then
               ! never ask for more than roundoff allows, nor for a zero tolerance
               tolerance = max(newton_tolerance, 10.0_dp*epsilon(1.0_dp)*abs(u0), tiny(1.0_dp))
            else
               tolerance = default_newton_tolerance*(1.0_dp + abs(u0))
            end if
         end associate
      end do
   end subroutine begin_implicit_step

   !> Newton's method for r(u) = 0 (system `system` of the current step), from the
   !> guess in u. The matrix is built and factored at the first iterate, or kept
   !> from an earlier step while h changed by at most 20 % and that solve contracted
   !> by 0.1 or better; it is rebuilt at the current iterate whenever the iteration
   !> contracts poorly or too slowly to converge within the iteration limit. Each
   !> iteration costs one residual and one LU solve.
   !> Converged when every |increment_i| <= newton_tolerance_i.
   subroutine solve_implicit(self, problem, system, u, stat)
      !> The scheme
      class(implicit_scheme_type), intent(inout) :: self
      !> The problem
      class(ode_problem), intent(inout) :: problem
      !> Which nonlinear system of the scheme
      integer, intent(in) :: system
      !> Initial guess on entry, solution on exit
      real(dp), intent(inout) :: u(:)
      !> Status: singular matrix, divergence or no convergence
      type(status_type), intent(inout) :: stat

      integer :: iteration, info, least_iterations
      logical :: rebuild, rebuilt
      real(dp) :: size_now, size_before, contraction

      associate (newton => self%systems(system))
         rebuild = .not. (self%reuse_newton_matrix .and. newton%factored .and. &
            abs(self%h - newton%h_built) <= reuse_step_change*newton%h_built .and. &
            newton%contraction <= reuse_contraction)
         ! with a kept matrix one small increment says little about the error left:
         ! a second iteration measures the contraction
         least_iterations = merge(1, 2, rebuild)
         size_before = huge(1.0_dp)
         self%last_contraction = 0.0_dp
         do iteration = 1, self%max_newton_iterations
            call self%residual(problem, system, u, self%newton_increment)
            self%counters%newton_iterations = self%counters%newton_iterations + 1
            rebuilt = rebuild
            if (rebuild) then
               call self%iteration_matrix(problem, system, u)
               call newton%matrix%factor(info)
               self%counters%lu_factorizations = self%counters%lu_factorizations + 1
               newton%h_built = self%h
               newton%factored = info == 0
               if (info /= 0) then
                  call set_status(stat, status_singular_matrix, &
                     "Newton: the iteration matrix is singular (reduce the step size)")
                  return
               end if
               rebuild = .false.
            end if
            self%newton_increment = -self%newton_increment
            call newton%matrix%solve(self%newton_increment, info)
            self%counters%linear_solves = self%counters%linear_solves + 1
            u = u + self%newton_increment
            if (.not. all(ieee_is_finite(u))) then
               newton%factored = .false.
               call set_status(stat, status_newton_diverged, "Newton: the iterate became NaN or Inf")
               return
            end if
            size_now = maxval(abs(self%newton_increment)/self%newton_tolerance)
            contraction = size_now/size_before
            if (iteration > 1) self%last_contraction = contraction
            if (size_now <= 1.0_dp .and. iteration >= least_iterations) then
               newton%contraction = self%last_contraction
               return
            end if
            if (contraction >= divergence_contraction .and. rebuilt) then
               newton%factored = .false.
               call set_status(stat, status_newton_diverged, "Newton: the iteration diverged")
               return
            end if
            ! rebuild on poor contraction, or when at this rate the iteration limit
            ! would come before convergence
            if (contraction > refresh_contraction) rebuild = .true.
            if (iteration > 1 .and. contraction < 1.0_dp) then
               if (size_now*contraction**(self%max_newton_iterations - iteration)/(1.0_dp - contraction) &
                  > 1.0_dp) rebuild = .true.
            end if
            size_before = size_now
         end do
         newton%factored = .false.
      end associate
      call set_status(stat, status_newton_not_converged, "Newton: no convergence within the iteration limit")
   end subroutine solve_implicit

end module taylorode_scheme
