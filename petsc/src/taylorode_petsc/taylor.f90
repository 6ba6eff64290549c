!> The library's Taylor schemes for one system distributed over the ranks: si-t-1,
!> si-t-2, i-t-1 and i-t-2 with the same updates, embedded pairs and stability
!> functions as the library's (METHODS.md), stepped by the library's adaptive
!> integrator (its controller, with norms and decisions combined over the ranks by the
!> grid problem's `reduce`). Each nonlinear system is solved by Newton's method whose
!> linear systems go to PETSc's GMRES matrix-free: the Newton matrix is applied through
!> Jacobian-vector products (jvp_f, jvp_g), never assembled,
!>
!>   si-t-1  I - h J_g(U)                          i-t-1  I - h J(U)
!>   si-t-2  I - h J_g(U) + h^2/2 J_g(U0) J(U)      i-t-2  I - h J(U) + h^2/2 J(U)^2
!>
!> and preconditioned by P = I - c h J_g(U) assembled from g's stencil: c = 1 applied
!> once for the first-order members; for the second-order ones c = 1/sqrt(2) applied
!> twice, P^2 = I - sqrt(2) h J_g + h^2/2 J_g^2, which carries the h^2 term of their
!> matrices: I - h J_g alone needs ever more Krylov iterations as h |J_g| grows
!> (`single_factor` shows it). Each factor of P is inverted by one algebraic multigrid
!> cycle. Each member keeps its P, and the multigrid hierarchy built for it, across
!> steps while h changes by at most 20 % and its solves stay cheap (building the
!> hierarchy costs more than a solve). The scheme's work counters count residuals as f
!> and g evaluations, Krylov solves as linear solves and preconditioner set-ups as
!> factorizations. They take autonomous problems (problem%autonomous): the library's
!> own schemes difference F in t where F depends on it, these do not, and refuse such
!> a problem rather than advance it to first order.
module taylorode_petsc_taylor
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   use taylorode, only: dp, i8, scheme_type, new_scheme, ode_problem, status_type, status_ok, reduce_max, &
      reduce_sum
   use taylorode_base_status, only: set_status, set_code, status_invalid_argument, status_unknown_scheme, &
      status_nonfinite, status_newton_diverged, status_newton_not_converged, status_evaluation_failed
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_petsc_calls, only: krylov_type, operator_type
   use taylorode_petsc_grid_problem, only: grid_problem_type
   implicit none
   private

   public :: grid_taylor_type, new_grid_taylor, grid_taylor_names

   !> Members (and the indices of their known parts)
   integer, parameter :: si_t_1 = 1, si_t_2 = 2, i_t_1 = 3, i_t_2 = 4
   !> The embedded partner of each member
   integer, parameter :: partners(4) = [si_t_2, si_t_1, i_t_2, i_t_1]
   !> Scheme names, as the library's
   character(len=*), parameter :: grid_taylor_names(4) = [character(len=6) :: "si-t-1", "si-t-2", "i-t-1", "i-t-2"]
   !> Relative residual reduction of each Krylov solve (Newton's outer iteration makes up
   !> for the rest)
   real(dp), parameter :: default_krylov_rtol = 1.0e-4_dp
   !> Newton is declared divergent when an increment grows this much from the last
   real(dp), parameter :: divergence_growth = 2.0_dp
   !> A preconditioner serves later steps while h differs by at most this fraction from
   !> the h it was built with ...
   real(dp), parameter :: reuse_step_change = 0.2_dp
   !> ... and its last solve took at most this many Krylov iterations
   integer, parameter :: reuse_iterations = 20

   !> The Newton matrix of one member at the current iterate, applied through
   !> Jacobian-vector products
   type, extends(operator_type) :: newton_operator_type
      !> The problem of the step in progress
      class(grid_problem_type), pointer :: problem => null()
      !> Member, start and end of the step, step size
      integer :: member = si_t_2
      real(dp) :: t0 = 0.0_dp, t1 = 0.0_dp, h = 0.0_dp
      !> State at the start of the step and the current iterate
      real(dp), allocatable :: u0(:), u(:)
      !> Work arrays
      real(dp), allocatable :: jv(:), w(:)
   contains
      procedure :: apply => newton_apply
   end type newton_operator_type

   !> One of si-t-1, si-t-2, i-t-1, i-t-2 on a distributed grid problem
   type, extends(scheme_type) :: grid_taylor_type
      !> Member that advances and member that gives the error estimate
      integer :: member = si_t_2, partner = si_t_1
      !> The library's scheme of the same name (its stability function)
      class(scheme_type), allocatable :: serial
      !> GMRES with the multigrid preconditioner of each member (those of the pair are used)
      type(krylov_type) :: krylov(4)
      !> Step size each member's preconditioner was built with (0: none)
      real(dp) :: h_built(4) = 0.0_dp
      !> The Newton matrix being solved with
      type(newton_operator_type) :: operator
      !> Relative residual reduction of each Krylov solve
      real(dp) :: krylov_rtol = default_krylov_rtol
      !> Precondition the second-order members with I - h J_g once instead of
      !> (I - h J_g / sqrt(2))^2 (for comparison)
      logical :: single_factor = .false.
      !> f, g and F at the start of the step; the known part of each member's equation
      real(dp), allocatable :: f0(:), g0(:), rhs0(:), known(:, :)
      !> Newton's residual and increment, F at the iterate, the preconditioner's stencil
      real(dp), allocatable :: residual(:), increment(:), f1(:), g1(:), work(:), stencil(:, :)
   contains
      procedure :: advance => grid_advance
      procedure :: prepare => grid_prepare
      procedure :: stability => grid_stability
      procedure :: restart => grid_restart
      !> Krylov iterations of all solves so far
      procedure :: krylov_iterations
      !> Release the PETSc objects
      procedure :: destroy
   end type grid_taylor_type

contains

   !> The distributed scheme called `name` (one of grid_taylor_names).
   subroutine new_grid_taylor(name, scheme, stat)
      !> si-t-1, si-t-2, i-t-1 or i-t-2
      character(len=*), intent(in) :: name
      !> The scheme
      type(grid_taylor_type), intent(inout) :: scheme
      !> status_unknown_scheme for another name
      type(status_type), intent(out) :: stat
      integer :: k
      k = findloc(grid_taylor_names, name, dim=1)
      if (k == 0) then
         call set_status(stat, status_unknown_scheme, 'grid scheme: unknown name "'//name// &
            '" (si-t-1, si-t-2, i-t-1, i-t-2)')
         return
      end if
      call new_scheme(name, scheme%serial, stat)
      if (stat%code /= status_ok) return
      scheme%name = scheme%serial%name
      scheme%order = scheme%serial%order
      scheme%embedded_order = scheme%serial%embedded_order
      scheme%nonlinear_order = scheme%serial%nonlinear_order
      scheme%implicit = .true.
      scheme%update = scheme%serial%update
      scheme%newton_matrices = scheme%serial%newton_matrices//" (matrix-free, GMRES with multigrid)"
      scheme%member = k
      scheme%partner = partners(k)
   end subroutine new_grid_taylor

   !> The library's stability function of the same scheme.
   pure function grid_stability(self, z, w) result(r)
      class(grid_taylor_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r
      r = self%serial%stability(z, w)
   end function grid_stability

   !> Forget the preconditioners kept from earlier steps.
   subroutine grid_restart(self)
      class(grid_taylor_type), intent(inout) :: self
      self%h_built = 0.0_dp
   end subroutine grid_restart

   !> Work arrays for this rank's n unknowns and the Krylov solvers for the grid.
   subroutine grid_prepare(self, problem, n, stat)
      class(grid_taylor_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      select type (problem)
      class is (grid_problem_type)
         if (.not. problem%autonomous) then
            call set_status(stat, status_invalid_argument, self%name//" (grid): the problem must be autonomous "// &
               "(problem%autonomous): these schemes do not difference F in t")
            return
         end if
         if (.not. self%resize(problem, n, stat)) return
         if (allocated(self%f0)) then
            deallocate (self%f0, self%g0, self%rhs0, self%known, self%residual, self%increment, self%f1, &
               self%g1, self%work, self%stencil)
            deallocate (self%operator%u0, self%operator%u, self%operator%jv, self%operator%w)
         end if
         allocate (self%f0(n), self%g0(n), self%rhs0(n), self%known(n, 4), self%residual(n), self%increment(n), &
            self%f1(n), self%g1(n), self%work(n), self%stencil(5, n))
         allocate (self%operator%u0(n), self%operator%u(n), self%operator%jv(n), self%operator%w(n))
         call self%krylov(self%member)%create(problem%grid, stat)
         if (stat%code == status_ok) call self%krylov(self%partner)%create(problem%grid, stat)
         self%h_built = 0.0_dp
         if (stat%code /= status_ok) self%n = 0
      class default
         call set_status(stat, status_invalid_argument, self%name//" (grid): the problem must extend grid_problem_type")
      end select
   end subroutine grid_prepare

   !> One step of the member from u0 (and of its partner, for delta).
   subroutine grid_advance(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(grid_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)
      select type (problem)
      class is (grid_problem_type)
         if (.not. problem%autonomous) then
            u1 = u0
            call set_code(stat, status_invalid_argument)
            return
         end if
         call advance_on_grid(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class default
         u1 = u0
         call set_code(stat, status_invalid_argument)
      end select
   end subroutine grid_advance

   !> grid_advance with the problem known to live on a grid (and recorded for the operator).
   subroutine advance_on_grid(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(grid_taylor_type), intent(inout) :: self
      class(grid_problem_type), intent(inout), target :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)
      logical :: needed(4)

      needed = .false.
      needed(self%member) = .true.
      if (present(delta)) needed(self%partner) = .true.
      self%operator%problem => problem
      self%operator%t0 = t
      self%operator%t1 = t + h
      self%operator%h = h
      self%operator%u0 = u0

      call problem%f(t, u0, self%f0)
      self%counters%f_evaluations = self%counters%f_evaluations + 1
      if (needed(si_t_1) .or. needed(si_t_2)) self%known(:, si_t_1) = u0 + h*self%f0
      if (needed(si_t_2)) then
         call problem%g(t, u0, self%g0)
         self%counters%g_evaluations = self%counters%g_evaluations + 1
         self%rhs0 = self%f0 + self%g0
         call problem%jvp_f(t, u0, self%rhs0, self%work)
         self%known(:, si_t_2) = self%known(:, si_t_1) + (0.5_dp*h*h)*self%work
      end if

      if (present(guess)) then
         u1 = guess
      else
         u1 = u0
      end if
      call newton_solve(self, problem, self%member, newton, u1, stat)
      if (stat%code == status_ok .and. present(delta)) then
         delta = u1
         call newton_solve(self, problem, self%partner, newton, delta, stat)
         if (stat%code == status_ok) then
            if (self%order > self%embedded_order) then
               delta = u1 - delta
            else
               delta = delta - u1
            end if
         end if
      end if
      nullify (self%operator%problem)
   end subroutine advance_on_grid

   !> Newton's method for `member` from the guess in u: one residual, one Krylov solve
   !> per iteration, the member's preconditioner (re)built at the first iterate unless
   !> it still serves; converged when every |increment_i| <= tolerance_i. Every decision
   !> is taken on values combined over the ranks, so every rank iterates alike. Failures
   !> by their code only (and the preconditioner is then rebuilt at the next solve).
   subroutine newton_solve(self, problem, member, newton, u, stat)
      class(grid_taylor_type), intent(inout) :: self
      class(grid_problem_type), intent(inout) :: problem
      integer, intent(in) :: member
      type(newton_settings_type), intent(in) :: newton
      real(dp), intent(inout) :: u(:)
      type(status_type), intent(inout) :: stat
      real(dp) :: checks(2), size_now, size_before, scale
      integer :: iteration, i, cycles

      self%operator%member = member
      size_before = huge(1.0_dp)
      do iteration = 1, newton%max_iterations
         call residual(self, problem, member, u, self%residual)
         self%counters%newton_iterations = self%counters%newton_iterations + 1
         ! a rejected evaluation or NaN on any rank is every rank's
         checks = [merge(1.0_dp, 0.0_dp, problem%evaluation_rejected()), &
            real(count(.not. ieee_is_finite(self%residual)), dp)]
         call problem%reduce(reduce_sum, checks)
         if (checks(1) > 0.0_dp) then
            call set_code(stat, status_evaluation_failed)
            return
         end if
         if (checks(2) > 0.0_dp) then
            call set_code(stat, status_nonfinite)
            return
         end if
         if (iteration == 1 .and. .not. preconditioner_serves(self, member)) then
            call problem%jac_g_stencil(self%operator%t1, u, self%stencil)
            scale = self%operator%h
            cycles = 1
            if ((member == si_t_2 .or. member == i_t_2) .and. .not. self%single_factor) then
               scale = self%operator%h/sqrt(2.0_dp)
               cycles = 2
            end if
            call self%krylov(member)%set_preconditioner(problem%grid, 1.0_dp, scale, self%stencil, cycles, stat)
            self%counters%lu_factorizations = self%counters%lu_factorizations + 1
            if (stat%code /= status_ok) return
            self%h_built(member) = self%operator%h
         end if
         self%operator%u = u
         self%increment = 0.0_dp
         self%residual = -self%residual
         call self%krylov(member)%solve(self%operator, self%residual, self%increment, self%krylov_rtol, stat)
         self%counters%linear_solves = self%counters%linear_solves + 1
         if (stat%code /= status_ok) then
            self%h_built(member) = 0.0_dp
            return
         end if
         u = u + self%increment
         size_now = 0.0_dp
         do i = 1, size(u)
            size_now = max(size_now, abs(self%increment(i))/newton%tolerance(i))
         end do
         checks(1) = size_now
         call problem%reduce(reduce_max, checks(1:1))
         size_now = checks(1)
         if (size_now <= 1.0_dp) return
         if (iteration > 1 .and. size_now > divergence_growth*size_before) then
            self%h_built(member) = 0.0_dp
            call set_code(stat, status_newton_diverged)
            return
         end if
         size_before = size_now
      end do
      self%h_built(member) = 0.0_dp
      call set_code(stat, status_newton_not_converged)
   end subroutine newton_solve

   !> Whether the member's preconditioner still serves the step in progress.
   logical function preconditioner_serves(self, member)
      class(grid_taylor_type), intent(in) :: self
      integer, intent(in) :: member
      preconditioner_serves = self%h_built(member) > 0.0_dp .and. &
         abs(self%operator%h - self%h_built(member)) <= reuse_step_change*self%h_built(member) .and. &
         self%krylov(member)%iterations <= reuse_iterations
   end function preconditioner_serves

   !> The member's residual at u:
   !>   si-t-1  u - (u0 + h f0) - h g(u)
   !>   si-t-2  u - (u0 + h f0 + h^2/2 J_f0 F0) - h g(u) + h^2/2 J_g0 F(u)
   !>   i-t-1   u - u0 - h F(u)
   !>   i-t-2   u - u0 - h F(u) + h^2/2 J(u) F(u)
   subroutine residual(self, problem, member, u, r)
      class(grid_taylor_type), intent(inout) :: self
      class(grid_problem_type), intent(inout) :: problem
      integer, intent(in) :: member
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: r(:)
      associate (op => self%operator)
         call problem%g(op%t1, u, self%g1)
         self%counters%g_evaluations = self%counters%g_evaluations + 1
         if (member /= si_t_1) then
            call problem%f(op%t1, u, self%f1)
            self%counters%f_evaluations = self%counters%f_evaluations + 1
         end if
         select case (member)
         case (si_t_1)
            r = u - self%known(:, si_t_1) - op%h*self%g1
         case (si_t_2)
            self%work = self%f1 + self%g1
            call problem%jvp_g(op%t0, op%u0, self%work, r)
            r = u - self%known(:, si_t_2) - op%h*self%g1 + (0.5_dp*op%h*op%h)*r
         case (i_t_1)
            r = u - op%u0 - op%h*(self%f1 + self%g1)
         case default
            self%work = self%f1 + self%g1
            call problem%jvp_f(op%t1, u, self%work, r)
            call problem%jvp_g(op%t1, u, self%work, op%jv)
            r = u - op%u0 - op%h*self%work + (0.5_dp*op%h*op%h)*(r + op%jv)
         end select
      end associate
   end subroutine residual

   !> y = (Newton matrix of the member at the current iterate) x.
   subroutine newton_apply(self, x, y)
      class(newton_operator_type), intent(inout) :: self
      real(dp), intent(in) :: x(:)
      real(dp), intent(out) :: y(:)
      associate (problem => self%problem)
         call problem%jvp_g(self%t1, self%u, x, self%jv)
         select case (self%member)
         case (si_t_1)
            y = x - self%h*self%jv
         case (si_t_2)
            call problem%jvp_f(self%t1, self%u, x, self%w)
            self%w = self%w + self%jv
            call problem%jvp_g(self%t0, self%u0, self%w, y)
            y = x - self%h*self%jv + (0.5_dp*self%h*self%h)*y
         case (i_t_1)
            call problem%jvp_f(self%t1, self%u, x, self%w)
            y = x - self%h*(self%w + self%jv)
         case default
            call problem%jvp_f(self%t1, self%u, x, self%w)
            self%w = self%w + self%jv
            call problem%jvp_f(self%t1, self%u, self%w, y)
            call problem%jvp_g(self%t1, self%u, self%w, self%jv)
            y = x - self%h*self%w + (0.5_dp*self%h*self%h)*(y + self%jv)
         end select
      end associate
   end subroutine newton_apply

   !> Krylov iterations of all solves so far.
   integer(i8) function krylov_iterations(self)
      !> The scheme
      class(grid_taylor_type), intent(in) :: self
      krylov_iterations = sum(self%krylov%total_iterations)
   end function krylov_iterations

   !> Release the PETSc objects (before petsc_stop).
   subroutine destroy(self)
      !> The scheme
      class(grid_taylor_type), intent(inout) :: self
      integer :: k
      do k = 1, size(self%krylov)
         call self%krylov(k)%destroy()
      end do
   end subroutine destroy

end module taylorode_petsc_taylor
