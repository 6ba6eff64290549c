!> The linear test problem u' = lambda u + nu u (f = lambda u, g = nu u) with complex
!> lambda and nu carried by one real 2x2 block [[a, -b], [b, a]] each (METHODS.md
!> section 4): one step of a scheme from (1, 0) lands on its R(z, w), z = h lambda, w = h nu.
!>
!> The state (x, y) stands for the complex number x + i y, so one step from (1, 0)
!> lands on (Re R, Im R).
module taylorode_testset_linear_test
   use taylorode_base_kinds, only: dp
   use taylorode_testset_test_problem, only: test_problem_type
   implicit none
   private

   public :: linear_test_type, new_linear_test

   !> u' = lambda u + nu u on the real 2-vector representing a complex number
   type, extends(test_problem_type) :: linear_test_type
      !> Eigenvalue of the non-stiff part f
      complex(dp) :: lambda = (0.0_dp, 0.0_dp)
      !> Eigenvalue of the stiff part g
      complex(dp) :: nu = (0.0_dp, 0.0_dp)
   contains
      !> Non-stiff part f (the problem's description gives the split)
      procedure :: f => linear_f
      !> Stiff part g
      procedure :: g => linear_g
      !> df/dU, analytic
      procedure :: jac_f => linear_jac_f
      !> dg/dU, analytic
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
      self%autonomous = .true.
      self%t_end = 1.0_dp
      self%u0 = [1.0_dp, 0.0_dp]
      exact = exp(lambda + nu)
      self%reference = [exact%re, exact%im]
      self%source = "the linear test equation u' = lambda u + nu u (METHODS.md section 4)"
   end function new_linear_test

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

end module taylorode_testset_linear_test
