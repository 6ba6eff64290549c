!> The linear test problem u' = lambda u + nu u (f = lambda u, g = nu u) with complex
!> lambda and nu carried by one real 2x2 block [[a, -b], [b, a]] each, and the exact
!> stability functions R(z, w), z = h lambda, w = h nu, of every scheme (METHODS.md section 4).
!>
!> The state (x, y) stands for the complex number x + i y, so one step from (1, 0)
!> lands on (Re R, Im R).
module taylorode_linear_test
   use taylorode_kinds, only: dp
   use taylorode_problem, only: test_problem_type
   use taylorode_imex_rk, only: imex_gamma, imex_c
   use taylorode_radau, only: radau5_stability
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: linear_test_type, new_linear_test, stability_function

   !> u' = lambda u + nu u on the real 2-vector representing a complex number
   type, extends(test_problem_type) :: linear_test_type
      !> Eigenvalue of the non-stiff part f
      complex(dp) :: lambda = (0.0_dp, 0.0_dp)
      !> Eigenvalue of the stiff part g
      complex(dp) :: nu = (0.0_dp, 0.0_dp)
   contains
      procedure :: f => linear_f
      procedure :: g => linear_g
      procedure :: jac_f => linear_jac_f
      procedure :: jac_g => linear_jac_g
   end type linear_test_type

contains

   !> The linear test problem with eigenvalues lambda (f) and nu (g), from (1, 0)
   !> over [0, 1]; the exact solution exp(lambda + nu) is attached.
   pure function new_linear_test(lambda, nu) result(self)
      !> Eigenvalue of the non-stiff part
      complex(dp), intent(in) :: lambda
      !> Eigenvalue of the stiff part
      complex(dp), intent(in) :: nu
      type(linear_test_type) :: self
      complex(dp) :: exact
      self%lambda = lambda
      self%nu = nu
      self%name = "linear"
      self%t_end = 1.0_dp
      self%u0 = [1.0_dp, 0.0_dp]
      exact = exp(lambda + nu)
      self%reference = [exact%re, exact%im]
      self%source = "the linear test equation u' = lambda u + nu u (METHODS.md section 4)"
   end function new_linear_test

   !> Exact stability function R(z, w) of the scheme `name`; NaN for a name
   !> that is not a scheme.
   elemental function stability_function(name, z, w) result(r)
      !> Scheme name as users type it
      character(len=*), intent(in) :: name
      !> h lambda (non-stiff part)
      complex(dp), intent(in) :: z
      !> h nu (stiff part)
      complex(dp), intent(in) :: w
      complex(dp) :: r
      complex(dp) :: s, y1, y2

      s = z + w
      select case (name)
      case ("ex-t-1")
         r = 1.0_dp + s
      case ("ex-t-2")
         r = 1.0_dp + s + s*s/2.0_dp
      case ("si-t-1")
         r = (1.0_dp + z)/(1.0_dp - w)
      case ("si-t-2", "si-t-2-paper")
         r = (1.0_dp + z + (z*z + z*w)/2.0_dp)/(1.0_dp - w + (z*w + w*w)/2.0_dp)
      case ("i-t-1")
         r = 1.0_dp/(1.0_dp - s)
      case ("i-t-2")
         r = 1.0_dp/(1.0_dp - s*(1.0_dp - s/2.0_dp))
      case ("imex-rk21")
         y1 = 1.0_dp/(1.0_dp - imex_gamma*w)
         y2 = (1.0_dp + (imex_c*z + (1.0_dp - imex_gamma)*w)*y1)/(1.0_dp - imex_gamma*w)
         r = 1.0_dp + (1.0_dp - imex_gamma)*s*y1 + imex_gamma*s*y2
      case ("radau5")
         r = radau5_stability(s)
      case default
         r = cmplx(ieee_value(1.0_dp, ieee_quiet_nan), ieee_value(1.0_dp, ieee_quiet_nan), dp)
      end select
   end function stability_function

   !> Apply the 2x2 block of the complex number c to u.
   pure subroutine rotate(c, u, v)
      complex(dp), intent(in) :: c
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: v(:)
      v(1) = c%re*u(1) - c%im*u(2)
      v(2) = c%im*u(1) + c%re*u(2)
   end subroutine rotate

   !> The 2x2 block of the complex number c.
   pure subroutine block_of(c, jac)
      complex(dp), intent(in) :: c
      real(dp), intent(out) :: jac(:, :)
      jac(1, 1) = c%re
      jac(1, 2) = -c%im
      jac(2, 1) = c%im
      jac(2, 2) = c%re
   end subroutine block_of

   subroutine linear_f(self, t, u, dudt)
      class(linear_test_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      call rotate(self%lambda, u, dudt)
   end subroutine linear_f

   subroutine linear_g(self, t, u, dudt)
      class(linear_test_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: dudt(:)
      call rotate(self%nu, u, dudt)
   end subroutine linear_g

   subroutine linear_jac_f(self, t, u, jac)
      class(linear_test_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call block_of(self%lambda, jac)
   end subroutine linear_jac_f

   subroutine linear_jac_g(self, t, u, jac)
      class(linear_test_type), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call block_of(self%nu, jac)
   end subroutine linear_jac_g

end module taylorode_linear_test
