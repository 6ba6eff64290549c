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
module taylorode_radau
   use taylorode_kinds, only: dp
   use taylorode_status, only: status_type, set_status, status_ok, status_singular_matrix
   use taylorode_problem, only: ode_problem
   use taylorode_scheme, only: implicit_scheme_type
   use taylorode_matrix, only: dense_matrix_type, new_matrix
   implicit none
   private

   public :: radau5_type, new_radau5, radau5_stability

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

   !> Radau IIA, order 5, with its order-3 embedded error estimate
   type, extends(implicit_scheme_type) :: radau5_type
      !> State at the start of the step
      real(dp), allocatable :: u0(:)
      !> Stacked stage increments (Z1, Z2, Z3)
      real(dp), allocatable :: increments(:)
      !> Stage state, F at each stage, F(t0, U0) and the error estimate
      real(dp), allocatable :: stage(:), stage_rhs(:, :), scratch(:), rhs0(:), estimate(:)
      !> Jacobian J = J_f + J_g used by the current Newton matrix and error estimate
      type(dense_matrix_type) :: jac, jac_work
      !> Jacobian at one stage, for the exact Newton matrix of a rebuild
      type(dense_matrix_type) :: jac_stage
      !> I - h gamma0 J and its pivots, for the error estimate
      type(dense_matrix_type) :: error_matrix
      !> Whether `jac` may serve the next step
      logical :: jacobian_valid = .false.
      !> Whether the Newton matrix of this step has been built
      logical :: matrix_built = .false.
      !> Start of the previous step, to recognise a retry from the same state
      real(dp) :: previous_t0 = -huge(1.0_dp)
      !> Whether any step was attempted since the work arrays were prepared
      logical :: started = .false.
   contains
      procedure :: advance => radau_advance
      procedure :: prepare => radau_prepare
      procedure :: residual => radau_residual
      procedure :: iteration_matrix => radau_matrix
      procedure :: restart => radau_restart
   end type radau5_type

contains

   !> Create the Radau IIA (order 5) scheme.
   subroutine new_radau5(self)
      !> The new scheme
      type(radau5_type), intent(out) :: self
      self%name = "radau5"
      self%order = 5
      self%embedded_order = 3
   end subroutine new_radau5

   !> Stability function of Radau IIA order 5: the (2, 3) Pade approximation of exp(z).
   elemental function radau5_stability(z) result(r)
      !> h times the eigenvalue
      complex(dp), intent(in) :: z
      complex(dp) :: r
      r = (1.0_dp + 2.0_dp*z/5.0_dp + z**2/20.0_dp)/(1.0_dp - 3.0_dp*z/5.0_dp + 3.0_dp*z**2/20.0_dp - z**3/60.0_dp)
   end function radau5_stability

   !> Forget the kept Jacobian, the factored matrix and the previous step (new problem
   !> or integration).
   subroutine radau_restart(self)
      class(radau5_type), intent(inout) :: self
      self%systems%factored = .false.
      self%jacobian_valid = .false.
      self%started = .false.
   end subroutine radau_restart

   !> Work arrays; radau5 always works with dense matrices (3n x 3n Newton system).
   subroutine radau_prepare(self, problem, n)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      if (.not. self%resize(problem, n)) return
      call self%prepare_newton(3*n, 1, -1, -1)
      if (allocated(self%u0)) then
         deallocate (self%u0, self%increments, self%stage, self%stage_rhs, self%scratch, self%rhs0, self%estimate)
      end if
      allocate (self%u0(n), self%increments(3*n), self%stage(n), self%stage_rhs(n, 3), self%scratch(n), &
         self%rhs0(n), self%estimate(n))
      call new_dense(self%jac)
      call new_dense(self%jac_work)
      call new_dense(self%jac_stage)
      call new_dense(self%error_matrix)
      call self%restart()
   contains
      subroutine new_dense(matrix)
         type(dense_matrix_type), intent(out) :: matrix
         matrix%n = n
         allocate (matrix%a(n, n), matrix%pivots(n))
         matrix%a = 0.0_dp
      end subroutine new_dense
   end subroutine radau_prepare

   subroutine radau_advance(self, problem, t, h, u0, u1, stat, delta, newton_tolerance)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: newton_tolerance(:)

      integer :: n, s, info
      logical :: retry

      n = size(u0)
      retry = .not. self%started
      if (self%started) retry = t == self%previous_t0 .and. all(u0 == self%u0)
      self%started = .true.
      self%previous_t0 = t
      call self%begin_implicit_step(t, h, u0, newton_tolerance)
      self%u0 = u0

      ! the stage increments start from the explicit guess Z_j = c_j h F(t0, U0),
      ! which the error estimate reuses; the solution is U0 + Z3
      call self%eval_f(problem, t, u0, self%rhs0)
      call self%eval_g(problem, t, u0, self%scratch)
      self%rhs0 = self%rhs0 + self%scratch
      do s = 1, 3
         self%increments((s - 1)*n + 1:s*n) = (radau_c(s)*h)*self%rhs0
      end do
      self%matrix_built = .false.
      u1 = u0
      call self%solve_implicit(problem, 1, self%increments, stat)
      self%jacobian_valid = stat%code == status_ok .and. self%last_contraction < jacobian_reuse_contraction
      if (stat%code /= status_ok) return
      u1 = u0 + self%increments(2*n + 1:3*n)
      if (.not. present(delta)) return

      self%estimate = (gamma0*h)*self%rhs0
      do s = 1, 3
         self%estimate = self%estimate + radau_e(s)*self%increments((s - 1)*n + 1:s*n)
      end do
      call self%error_matrix%set_scaled(-h*gamma0, self%jac)
      call self%error_matrix%add_identity(1.0_dp)
      call self%error_matrix%factor(info)
      self%counters%lu_factorizations = self%counters%lu_factorizations + 1
      if (info /= 0) then
         call set_status(stat, status_singular_matrix, "radau5: the error estimate matrix is singular")
         return
      end if
      call self%error_matrix%solve(self%estimate, info)
      self%counters%linear_solves = self%counters%linear_solves + 1

      if (retry) then
         ! first step or a retry after a rejection: filter once more through F at
         ! U0 + delta, which removes the stiff components that inflate the estimate
         self%stage = u0 + self%estimate
         call self%eval_f(problem, t, self%stage, self%estimate)
         call self%eval_g(problem, t, self%stage, self%scratch)
         self%estimate = (gamma0*h)*(self%estimate + self%scratch)
         do s = 1, 3
            self%estimate = self%estimate + radau_e(s)*self%increments((s - 1)*n + 1:s*n)
         end do
         call self%error_matrix%solve(self%estimate, info)
         self%counters%linear_solves = self%counters%linear_solves + 1
      end if
      delta = self%estimate
   end subroutine radau_advance

   !> r(Z) = Z - h (A x I) F(U0 + Z)
   subroutine radau_residual(self, problem, system, u, r)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: r(:)
      integer :: n, s, j
      real(dp) :: t_stage

      n = self%n
      do s = 1, 3
         t_stage = self%t0 + radau_c(s)*self%h
         self%stage = self%u0 + u((s - 1)*n + 1:s*n)
         call self%eval_f(problem, t_stage, self%stage, self%stage_rhs(:, s))
         call self%eval_g(problem, t_stage, self%stage, self%scratch)
         self%stage_rhs(:, s) = self%stage_rhs(:, s) + self%scratch
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
   subroutine radau_matrix(self, problem, system, u)
      class(radau5_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      integer :: n, s, j, i, column

      n = self%n
      if (.not. self%matrix_built .and. .not. self%jacobian_valid) then
         call jacobian_at(self%t0, self%u0, self%jac)
      end if
      select type (m => self%systems(system)%matrix)
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
      end select
      self%matrix_built = .true.
   contains
      subroutine jacobian_at(t, state, jac)
         real(dp), intent(in) :: t, state(:)
         type(dense_matrix_type), intent(inout) :: jac
         call self%eval_jac_f(problem, t, state, jac)
         call self%eval_jac_g(problem, t, state, self%jac_work)
         jac%a = jac%a + self%jac_work%a
      end subroutine jacobian_at
   end subroutine radau_matrix

end module taylorode_radau
