!> Explicit Taylor schemes EX-T-1 and EX-T-2 (METHODS.md section 1), an embedded pair.
!>
!>   ex-t-1:  U1 = U0 + h F0
!>   ex-t-2:  U1 = U0 + h F0 + h^2/2 J0 F0,      delta = h^2/2 J0 F0
!>
!> A problem that depends on t gets h^2/2 (J0 F0 + dF/dt) in the second-order term,
!> dF/dt by a difference in t (the scheme applied to (t, U) with t' = 1).
module taylorode_schemes_explicit_taylor
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, set_code, status_ok, status_nonfinite
   use taylorode_base_memory, only: sized
   use taylorode_linalg_matrix, only: matrix_type, new_matrix
   use taylorode_problem_ode, only: ode_problem, difference_rhs
   use taylorode_newton_solver, only: newton_settings_type
   use taylorode_schemes_scheme, only: scheme_type, evaluate_f, evaluate_g, evaluate_jac_f, evaluate_jac_g, &
      evaluate_time_derivative, of_rhs
   use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
   implicit none
   private

   public :: explicit_taylor_type, new_explicit_taylor

   !> EX-T-1 (order 1) or EX-T-2 (order 2); the other member gives the error estimate
   type, extends(scheme_type) :: explicit_taylor_type
      !> f(U0), g(U0) and F0 = f(U0) + g(U0)
      real(dp), allocatable :: f0(:), g0(:), rhs0(:)
      !> h^2/2 J0 F0 (+ h^2/2 dF/dt), the second-order term
      real(dp), allocatable :: taylor2(:)
      !> dF/dt at U0, for a problem that depends on t
      real(dp), allocatable :: rhs_t0(:)
      !> The time of the last step's start (of rhs0)
      real(dp) :: t0 = 0.0_dp
      !> Jacobians at U0
      class(matrix_type), allocatable :: jac_f0, jac_g0
   contains
      !> F at the start of the last step
      procedure :: start_part => explicit_taylor_start_part
      !> One step of ex-t-1 or ex-t-2 and, when asked, the embedded difference
      procedure :: advance => explicit_taylor_advance
      !> Work arrays and Jacobian storage for the problem's structure and n unknowns
      procedure :: prepare => explicit_taylor_prepare
      procedure :: stability => explicit_taylor_stability
   end type explicit_taylor_type

contains

   !> EX-T-1 (order = 1) or EX-T-2 (order = 2).
   function new_explicit_taylor(order) result(self)
      !> 1 or 2
      integer, intent(in) :: order
      type(explicit_taylor_type) :: self
      self%order = order
      self%embedded_order = 3 - order
      self%nonlinear_order = order
      self%implicit = .false.
      self%start_only_part = difference_rhs
      self%newton_matrices = ""
      if (order == 1) then
         self%name = "ex-t-1"
         self%update = "U1 = U0 + h F0"
      else
         self%name = "ex-t-2"
         self%update = "U1 = U0 + h F0 + h^2/2 J0 F0"
      end if
   end function new_explicit_taylor

   subroutine explicit_taylor_start_part(self, value, at, kept)
      class(explicit_taylor_type), intent(in) :: self
      real(dp), intent(inout) :: value(:)
      real(dp), intent(out) :: at
      logical, intent(out) :: kept
      at = self%t0
      kept = allocated(self%rhs0)
      if (kept) value = self%rhs0
   end subroutine explicit_taylor_start_part

   !> R = 1 + s (ex-t-1) or 1 + s + s^2/2 (ex-t-2), s = z + w.
   pure function explicit_taylor_stability(self, z, w) result(r)
      class(explicit_taylor_type), intent(in) :: self
      complex(dp), intent(in) :: z, w
      complex(dp) :: r
      r = 1.0_dp + (z + w)
      if (self%order == 2) r = r + (z + w)**2/2.0_dp
   end function explicit_taylor_stability

   subroutine explicit_taylor_prepare(self, problem, n, stat)
      class(explicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(in) :: problem
      integer, intent(in) :: n
      type(status_type), intent(inout) :: stat
      character(len=*), parameter :: what = "the work arrays of an explicit Taylor scheme"
      if (.not. self%resize(problem, n, stat)) return
      call sized(self%f0, n, what, stat)
      call sized(self%g0, n, what, stat)
      call sized(self%rhs0, n, what, stat)
      call sized(self%taylor2, n, what, stat)
      call sized(self%rhs_t0, merge(n, 0, .not. problem%autonomous), what, stat)
      if (stat%code == status_ok) call new_matrix(self%jac_f0, n, self%structure, stat)
      if (stat%code == status_ok) call new_matrix(self%jac_g0, n, self%structure, stat)
      if (stat%code /= status_ok) self%n = 0
   end subroutine explicit_taylor_prepare

   subroutine explicit_taylor_advance(self, problem, t, h, u0, u1, newton, stat, delta, guess)
      class(explicit_taylor_type), intent(inout) :: self
      class(ode_problem), intent(inout) :: problem
      real(dp), intent(in) :: t, h
      real(dp), intent(in) :: u0(:)
      real(dp), intent(out) :: u1(:)
      type(newton_settings_type), intent(in) :: newton
      type(status_type), intent(inout) :: stat
      real(dp), intent(out), optional :: delta(:)
      real(dp), intent(in), optional :: guess(:)

      call evaluate_f(problem, t, u0, self%f0, self%counters)
      call evaluate_g(problem, t, u0, self%g0, self%counters)
      self%rhs0 = self%f0 + self%g0
      self%t0 = t
      if (.not. all(ieee_is_finite(self%rhs0))) then
         call set_code(stat, status_nonfinite)
         return
      end if
      u1 = u0 + h*self%rhs0
      if (self%order == 1 .and. .not. present(delta)) return

      call evaluate_jac_f(problem, t, u0, self%jac_f0, self%counters, stat)
      call evaluate_jac_g(problem, t, u0, self%jac_g0, self%counters, stat)
      if (stat%code /= status_ok) return
      self%taylor2 = 0.0_dp
      call self%jac_f0%multiply_add(0.5_dp*h*h, self%rhs0, self%taylor2)
      call self%jac_g0%multiply_add(0.5_dp*h*h, self%rhs0, self%taylor2)
      if (.not. problem%autonomous) then
         ! u1 serves as work array, then gets U0 + h F0 again
         call evaluate_time_derivative(problem, of_rhs, t, h, u0, self%rhs0, self%rhs_t0, u1, self%counters)
         self%taylor2 = self%taylor2 + 0.5_dp*h*h*self%rhs_t0
         u1 = u0 + h*self%rhs0
      end if
      if (self%order == 2) u1 = u1 + self%taylor2
      if (present(delta)) delta = self%taylor2
   end subroutine explicit_taylor_advance

end module taylorode_schemes_explicit_taylor
