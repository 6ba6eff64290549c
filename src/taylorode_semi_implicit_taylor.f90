!> Semi-implicit Taylor schemes (METHODS.md section 1): g implicit, f explicit.
!>
!>   si-t-1:        U1 = U0 + h (f0 + g(U1))
!>   si-t-2:        U1 = U0 + h (f0 + g(U1)) + h^2/2 [ J_f0 F0 - J_g0 F(U1) ]        (order 2)
!>   si-t-2-paper:  U1 = U0 + h (f0 + g(U1)) + h^2/2 J0 (f0 - g(U1))  as printed in the
!>                  paper; only first order on nonlinear problems (second order on the
!>                  linear test equation), kept to reproduce the paper.
!>
!> Embedded pairs: si-t-1 with si-t-2, si-t-2 with si-t-1, si-t-2-paper with si-t-1.
module taylorode_semi_implicit_taylor
   use taylorode_kinds, only: dp
   use taylorode_status, only: status_type, status_ok
   use taylorode_problem, only: ode_problem
   use taylorode_scheme, only: implicit_scheme_type
   use taylorode_matrix, only: matrix_type, new_matrix
   implicit none
   private

   public :: semi_implicit_taylor_type, new_semi_implicit_taylor
   public :: si_t_1, si_t_2, si_t_2_paper

   !> Member identifiers (also the identifiers of their nonlinear systems)
   integer, parameter :: si_t_1 = 1, si_t_2 = 2, si_t_2_paper = 3

   !> One member of the semi-implicit Taylor family, with its embedded partner
   type, extends(implicit_scheme_type) :: semi_implicit_taylor_type
      !> Member that advances (si_t_1, si_t_2 or si_t_2_paper)
      integer :: member = si_t_2
      !> Member that gives the error estimate
      integer :: partner = si_t_1
      !> Values at U0: f, g, F = f + g
      real(dp), allocatable :: f0(:), g0(:), rhs0(:)
      !> Jacobians at U0 (jac0 = J_f0 + J_g0, used by si-t-2-paper)
      class(matrix_type), allocatable :: jac_f0, jac_g0, jac0
      !> Known part of each member's update, one column per member
      real(dp), allocatable :: known(:, :)
      !> Values at the current Newton iterate
      real(dp), allocatable :: f1(:), g1(:), work(:)
      class(matrix_type), allocatable :: jac_f1, jac_g1
   contains
      procedure :: advance => semi_implicit_advance
      procedure :: prepare => semi_implicit_prepare
      procedure :: residual => semi_implicit_residual
      procedure :: iteration_matrix => semi_implicit_matrix
   end type semi_implicit_taylor_type

contains

   !> Create the semi-implicit Taylor scheme `member` (si_t_1, si_t_2 or si_t_2_paper).
   subroutine new_semi_implicit_taylor(self, member)
      !> The new scheme
      type(semi_implicit_taylor_type), intent(out) :: self
      !> Which member advances the solution
      integer, intent(in) :: member
      self%member = member
      select case (member)
      case (si_t_1)
         self%name = "si-t-1"
         self%order = 1
         self%partner = si_t_2
         self%embedded_order = 2
      case (si_t_2_paper)
         self%name = "si-t-2-paper"
         self%order = 2
         self%partner = si_t_1
         self%embedded_order = 1
      case default
         self%member = si_t_2
         self%name = "si-t-2"
         self%order = 2
         self%partner = si_t_1
         self%embedded_order = 1
      end select
   end subroutine new_semi_implicit_taylor

   !> Work arrays; the Newton matrices of the second-order members hold products of
   !> Jacobians and get twice the problem's bandwidths.
   subroutine semi_implicit_prepare(self, problem, n)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      if (.not. self%resize(problem, n)) return
      call self%prepare_newton(n, 3, 2*self%kl, 2*self%ku)
      call new_matrix(self%systems(si_t_1)%matrix, n, self%kl, self%ku)
      if (allocated(self%f0)) deallocate (self%f0, self%g0, self%rhs0, self%known, self%f1, self%g1, self%work)
      allocate (self%f0(n), self%g0(n), self%rhs0(n), self%known(n, 3), self%f1(n), self%g1(n), self%work(n))
      call new_matrix(self%jac_f0, n, self%kl, self%ku)
      call new_matrix(self%jac_g0, n, self%kl, self%ku)
      call new_matrix(self%jac0, n, self%kl, self%ku)
      call new_matrix(self%jac_f1, n, self%kl, self%ku)
      call new_matrix(self%jac_g1, n, self%kl, self%ku)
   end subroutine semi_implicit_prepare

   subroutine semi_implicit_advance(self, problem, t, h, u0, u1, stat, delta, newton_tolerance)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: newton_tolerance(:)

      logical :: needed(3)

      call self%begin_implicit_step(t, h, u0, newton_tolerance)
      needed = .false.
      needed(self%member) = .true.
      if (present(delta)) needed(self%partner) = .true.

      call self%eval_f(problem, t, u0, self%f0)
      if (needed(si_t_2) .or. needed(si_t_2_paper)) then
         call self%eval_jac_f(problem, t, u0, self%jac_f0)
         call self%eval_jac_g(problem, t, u0, self%jac_g0)
      end if
      if (needed(si_t_1)) self%known(:, si_t_1) = u0 + h*self%f0
      if (needed(si_t_2)) then
         call self%eval_g(problem, t, u0, self%g0)
         self%rhs0 = self%f0 + self%g0
         self%known(:, si_t_2) = u0 + h*self%f0
         call self%jac_f0%multiply_add(0.5_dp*h*h, self%rhs0, self%known(:, si_t_2))
      end if
      if (needed(si_t_2_paper)) then
         call self%jac0%set_scaled(1.0_dp, self%jac_f0)
         call self%jac0%add_scaled(1.0_dp, self%jac_g0)
         self%known(:, si_t_2_paper) = u0 + h*self%f0
         call self%jac0%multiply_add(0.5_dp*h*h, self%f0, self%known(:, si_t_2_paper))
      end if

      u1 = u0
      call self%solve_implicit(problem, self%member, u1, stat)
      if (stat%code /= status_ok .or. .not. present(delta)) return

      delta = u1
      call self%solve_implicit(problem, self%partner, delta, stat)
      if (stat%code /= status_ok) return
      if (self%order > self%embedded_order) then
         delta = u1 - delta
      else
         delta = delta - u1
      end if
   end subroutine semi_implicit_advance

   subroutine semi_implicit_residual(self, problem, system, u, r)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: r(:)

      real(dp) :: t1, half_h2

      t1 = self%t0 + self%h
      half_h2 = 0.5_dp*self%h*self%h
      call self%eval_g(problem, t1, u, self%g1)
      r = u - self%known(:, system) - self%h*self%g1
      select case (system)
      case (si_t_2)
         call self%eval_f(problem, t1, u, self%f1)
         self%work = self%f1 + self%g1
         call self%jac_g0%multiply_add(half_h2, self%work, r)
      case (si_t_2_paper)
         call self%jac0%multiply_add(half_h2, self%g1, r)
      end select
   end subroutine semi_implicit_residual

   subroutine semi_implicit_matrix(self, problem, system, u)
      class(semi_implicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      integer, intent(in) :: system
      real(dp), intent(in) :: u(:)

      real(dp) :: t1, half_h2

      t1 = self%t0 + self%h
      half_h2 = 0.5_dp*self%h*self%h
      call self%eval_jac_g(problem, t1, u, self%jac_g1)
      associate (m => self%systems(system)%matrix)
         call m%set_scaled(-self%h, self%jac_g1)
         select case (system)
         case (si_t_2)
            call self%eval_jac_f(problem, t1, u, self%jac_f1)
            call self%jac_f1%add_scaled(1.0_dp, self%jac_g1)
            call m%add_product(half_h2, self%jac_g0, self%jac_f1)
         case (si_t_2_paper)
            call m%add_product(half_h2, self%jac0, self%jac_g1)
         end select
         call m%add_identity(1.0_dp)
      end associate
   end subroutine semi_implicit_matrix

end module taylorode_semi_implicit_taylor
