!> Radau IIA of order 5 (three stages, L-stable), the library's reference solver,
!> written from its published definition (Hairer & Wanner, Solving Ordinary
!> Differential Equations II, section IV.8).
!>
!> Stage increments Z_i = Y_i - U0 solve Z_i = h sum_j a_ij F(t0 + c_j h, U0 + Z_j);
!> U1 = U0 + Z_3 (stiffly accurate). The 3n x 3n system is solved by simplified
!> Newton with the real matrix I - h (A x J) through LAPACK; the Jacobian is kept
!> from the previous step while Newton converges well (contraction below 1e-3), and
!> a slowly contracting iteration switches to the exact stage-wise Newton matrix.
!> A dense 3n system costs (3n)^3/3 flops per factorization: sensible up to a few
!> hundred unknowns.
!>
!> The error estimate (embedded order 3) is the filtered difference
!>   delta = (I - h gamma0 J)^(-1) [gamma0 h F(t0, U0) + e1 Z1 + e2 Z2 + e3 Z3],
!> gamma0 the real eigenvalue of A, e = gamma0 (-(13 + 7 sqrt 6), -13 + 7 sqrt 6, -1) / 3.
!> At the first step and on a retry after a rejection the estimate is filtered once
!> more, with F(t0, U0 + delta) in place of F(t0, U0), as Hairer & Wanner recommend
!> for stiff components.
module taylorode_schemes_radau5
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_status, status_ok, status_singular_matrix, &
      status_invalid_argument
   use taylorode_base_counters, only: counters_type
   use taylorode_linalg_matrix, only: matrix_type, dense_matrix_type, dense_structure, new_matrix
   use taylorode_linalg_solver, only: linear_solver_type, new_linear_solver
   use taylorode_problem_ode, only: ode_problem
   use taylorode_newton_solver, only: newton_settings_type, newton_solver_type, nonlinear_system_type
   use taylorode_schemes_scheme, only: scheme_type, stability_quotient, evaluate_rhs, evaluate_jac_f, evaluate_jac_g
   implicit none
   private

   public :: radau5_type, new_radau5

   real(dp), parameter :: sqrt6 = sqrt(6.0_dp)
   !> Nodes
   real(dp), parameter :: radau_c(3) = [(4.0_dp - sqrt6)/10.0_dp, (4.0_dp + sqrt6)/10.0_dp, 1.0_dp]
   !> Coefficient matrix, by columns
   real(dp), parameter :: radau_a(3, 3) = reshape([ &
      (88.0_dp - 7.0_dp*sqrt6)/360.0_dp, (296.0_dp + 169.0_dp*sqrt6)/1800.0_dp, (16.0_dp - sqrt6)/36.0_dp, &
      (296.0_dp - 169.0_dp*sqrt6)/1800.0_dp, (88.0_dp + 7.0_dp*sqrt6)/360.0_dp, (16.0_dp + sqrt6)/36.0_dp, &
      (-2.0_dp + 3.0_dp*sqrt6)/225.0_dp, (-2.0_dp - 3.0_dp*sqrt6)/225.0_dp, 1.0_dp/9.0_dp], [3, 3])
   !> Real eigenvalue of A
   real(dp), parameter :: gamma0 = (6.0_dp + 81.0_dp**(1.0_dp/3.0_dp) - 9.0_dp**(1.0_dp/3.0_dp))/30.0_dp
   !> Weights of the stage increments in the error estimate
   real(dp), parameter :: radau_e(3) = gamma0*[-(13.0_dp + 7.0_dp*sqrt6), -13.0_dp + 7.0_dp*sqrt6, -1.0_dp]/3.0_dp
   !> Newton contraction below which the Jacobian is kept for the next step
   real(dp), parameter :: jacobian_reuse_contraction = 1.0e-3_dp

   !> The stage system r(Z) = Z - h (A x I) F(U0 + Z), Z = (Z1, Z2, Z3) stacked
   type, extends(nonlinear_system_type) :: radau_stage_system_type
      !> Unknowns of the problem
      integer :: n = 0
      !> Start of the step and step size
      real(dp) :: t0 = 0.0_dp, h = 0.0_dp
      !> State at the start of the step
      real(dp), allocatable :: u0(:)
      !> Stage state, F at each stage and work space
      real(dp), allocatable :: stage(:), stage_rhs(:, :), scratch(:)
      !> Jacobian J = J_f + J_g used by the current Newton matrix and error estimate
      type(dense_matrix_type) :: jac
      !> Work matrix for J_g, and the Jacobian at one stage for the exact Newton matrix
      type(dense_matrix_type) :: jac_work, jac_stage
      !> Whether `jac` may serve the next step
      logical :: jacobian_valid = .false.
      !> Whether the Newton matrix of this step has been built
      logical :: matrix_built = .false.
   contains
      procedure :: residual => radau_residual
      procedure :: newton_matrix => radau_matrix
   end type radau_stage_system_type

   !> Radau IIA, order 5, with its order-3 embedded error estimate
   type, extends(scheme_type) :: radau5_type
      !> The stage system of the current step
      type(radau_stage_system_type) :: system
      !> Newton's method on the stage system (one 3n x 3n matrix)
      type(newton_solver_type) :: newton
      !> Stacked stage increments (Z1, Z2, Z3)
      real(dp), allocatable :: increments(:)
      !> F(t0, U0), the error estimate and a filtered state
      real(dp), allocatable :: rhs0(:), estimate(:), filtered(:)
      !> I - h gamma0 J and its factors, for the error estimate
      type(linear_solver_type) :: error_solver
      !> Start of the previous step, to recognise a retry from the same state
      real(dp) :: previous_t0 = -huge(1.0_dp)
      !> Whether any step was attempted since the last restart
      logical :: started = .false.
   contains
      procedure :: advance => radau_advance
      procedure :: prepare => radau_prepare
      procedure :: restart => radau_restart
      procedure :: stability => radau_stability
   end type radau5_type

contains

   !> The Radau IIA (order 5) scheme.
   function new_radau5() result(self)
      type(radau5_type) :: self
      self%name = "radau5"
      self%order = 5
      self%nonlinear_order = 5
      self%embedded_order = 3
      self%implicit = .true.
      self%update = "Z_i = h sum_j a_ij F(t0 + c_j h, U0 + Z_j), U1 = U0 + Z_3 (Radau IIA, 3 stages)"
      self%newton_matrices = "I - h (A x J) (3n x 3n), I - h gamma0 J"
   end function new_radau5

   !> Stability function of Radau IIA order 5: the (2, 3) Pade approximation of exp(s), s = z + w.
   pure function radau_stability(self, z, w) result(r)
      class(radau5_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r, s
      s = z + w
      r = stability_quotient(1.0_dp + 2.0_dp*s/5.0_dp + s**2/20.0_dp, &
         1.0_dp - 3.0_dp*s/5.0_dp + 3.0_dp*s**2/20.0_dp - s**3/60.0_dp)
   end function radau_stability

   !> Forget the kept Jacobian, the factored matrix and the previous step (new problem
   !> or integration).
   subroutine radau_restart(self)
      class(radau5_type), intent(inout) :: self
      call self%newton%forget()
      self%system%jacobian_valid = .false.
      self%started = .false.
   end subroutine radau_restart

   !> Work arrays; radau5 works with dense matrices (3n x 3n Newton system).
   subroutine radau_prepare(self, problem, n, stat)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      if (.not. self%resize(problem, n, stat)) return
      call self%newton%init(3*n, dense_structure(), stat)
      call new_linear_solver(self%error_solver, n, dense_structure(), stat)
      if (allocated(self%increments)) deallocate (self%increments, self%rhs0, self%estimate, self%filtered)
      allocate (self%increments(3*n), self%rhs0(n), self%estimate(n), self%filtered(n))
      associate (system => self%system)
         system%n = n
         if (allocated(system%u0)) deallocate (system%u0, system%stage, system%stage_rhs, system%scratch)
         allocate (system%u0(n), system%stage(n), system%stage_rhs(n, 3), system%scratch(n))
         call new_dense(system%jac)
         call new_dense(system%jac_work)
         call new_dense(system%jac_stage)
      end associate
      if (stat%code /= status_ok) self%n = 0
      call self%restart()
   contains
      subroutine new_dense(matrix)
         type(dense_matrix_type), intent(out) :: matrix
         matrix%n = n
         allocate (matrix%a(n, n), source=0.0_dp)
      end subroutine new_dense
   end subroutine radau_prepare

   subroutine radau_advance(self, problem, t, h, u0, u1, newton, stat, delta)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)

      integer :: n, s
      logical :: retry

      n = size(u0)
      associate (system => self%system)
         retry = .not. self%started
         if (self%started) retry = t == self%previous_t0 .and. all(u0 == system%u0)
         self%started = .true.
         self%previous_t0 = t
         system%t0 = t
         system%h = h
         system%u0 = u0

         ! the stage increments start from the explicit guess Z_j = c_j h F(t0, U0),
         ! which the error estimate reuses; the solution is U0 + Z3
         call evaluate_rhs(problem, t, u0, self%rhs0, system%scratch, self%counters)
         do s = 1, 3
            self%increments((s - 1)*n + 1:s*n) = (radau_c(s)*h)*self%rhs0
         end do
         system%matrix_built = .false.
         u1 = u0
         call self%newton%solve(system, problem, h, newton, self%increments, self%counters, stat)
         system%jacobian_valid = stat%code == status_ok .and. self%newton%last_contraction < jacobian_reuse_contraction
         if (stat%code /= status_ok) return
         u1 = u0 + self%increments(2*n + 1:3*n)
         if (.not. present(delta)) return

         self%estimate = (gamma0*h)*self%rhs0
         do s = 1, 3
            self%estimate = self%estimate + radau_e(s)*self%increments((s - 1)*n + 1:s*n)
         end do
         call self%error_solver%matrix%set_scaled(-h*gamma0, system%jac, stat)
         call self%error_solver%matrix%add_identity(1.0_dp)
         call self%error_solver%factor(stat)
         self%counters%lu_factorizations = self%counters%lu_factorizations + 1
         if (stat%code == status_singular_matrix) then
            call set_status(stat, status_singular_matrix, "radau5: the error estimate matrix is singular")
            return
         end if
         if (stat%code /= status_ok) return
         call self%error_solver%solve(self%estimate, stat)
         self%counters%linear_solves = self%counters%linear_solves + 1

         if (retry) then
            ! first step or a retry after a rejection: filter once more through F at
            ! U0 + delta, which removes the stiff components that inflate the estimate
            self%filtered = u0 + self%estimate
            call evaluate_rhs(problem, t, self%filtered, self%estimate, system%scratch, self%counters)
            self%estimate = (gamma0*h)*self%estimate
            do s = 1, 3
               self%estimate = self%estimate + radau_e(s)*self%increments((s - 1)*n + 1:s*n)
            end do
            call self%error_solver%solve(self%estimate, stat)
            self%counters%linear_solves = self%counters%linear_solves + 1
         end if
      end associate
      delta = self%estimate
   end subroutine radau_advance

   !> r(Z) = Z - h (A x I) F(U0 + Z)
   subroutine radau_residual(self, problem, u, r, counters)
      class(radau_stage_system_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: r(:)
      type(counters_type), intent(inout) :: counters
      integer :: n, s, j

      n = self%n
      do s = 1, 3
         self%stage = self%u0 + u((s - 1)*n + 1:s*n)
         call evaluate_rhs(problem, self%t0 + radau_c(s)*self%h, self%stage, self%stage_rhs(:, s), &
            self%scratch, counters)
      end do
      do s = 1, 3
         r((s - 1)*n + 1:s*n) = u((s - 1)*n + 1:s*n)
         do j = 1, 3
            r((s - 1)*n + 1:s*n) = r((s - 1)*n + 1:s*n) - (self%h*radau_a(s, j))*self%stage_rhs(:, j)
         end do
      end do
   end subroutine radau_residual

   !> Newton matrix of the stage system. The first build of a step uses one
   !> Jacobian J for every stage, I - h (A x J), with J from U0 (or kept from the
   !> previous step when Newton converged fast there): this J also serves the error
   !> estimate. A rebuild within the step (poor contraction) forms the exact
   !> derivative, with J(Y_j) at each stage in block column j.
   subroutine radau_matrix(self, problem, u, matrix, counters, stat)
      class(radau_stage_system_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: u(:)
      class(matrix_type), intent(inout) :: matrix
      type(counters_type), intent(inout) :: counters
      type(status_type), intent(inout) :: stat
      integer :: n, s, j, i, column

      n = self%n
      if (.not. self%matrix_built .and. .not. self%jacobian_valid) then
         call jacobian_at(self%t0, self%u0, self%jac)
      end if
      select type (m => matrix)
      type is (dense_matrix_type)
         do j = 1, 3
            if (self%matrix_built) then
               self%stage = self%u0 + u((j - 1)*n + 1:j*n)
               call jacobian_at(self%t0 + radau_c(j)*self%h, self%stage, self%jac_stage)
            else
               self%jac_stage%a = self%jac%a
            end if
            ! explicit loops: an array assignment here would copy through a temporary
            do s = 1, 3
               do column = 1, n
                  do i = 1, n
                     m%a((s - 1)*n + i, (j - 1)*n + column) = -(self%h*radau_a(s, j))*self%jac_stage%a(i, column)
                  end do
               end do
            end do
         end do
         do i = 1, 3*n
            m%a(i, i) = m%a(i, i) + 1.0_dp
         end do
      class default
         call set_status(stat, status_invalid_argument, "radau5: the stage system needs dense storage")
      end select
      self%matrix_built = .true.
   contains
      subroutine jacobian_at(t, state, jac)
         real(dp), intent(in) :: t, state(:)
         type(dense_matrix_type), intent(inout) :: jac
         call evaluate_jac_f(problem, t, state, jac, counters)
         call evaluate_jac_g(problem, t, state, self%jac_work, counters)
         jac%a = jac%a + self%jac_work%a
      end subroutine jacobian_at
   end subroutine radau_matrix

end module taylorode_schemes_radau5
