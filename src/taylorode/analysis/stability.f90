!> Linear stability of a scheme: its stability function R(z, w) checked against one
!> real step of the code on the linear test equation, the region
!> S1 = {z : sup over Re w <= 0 of |R(z, w)| <= 1} of the paper's Fig. 1 and where
!> it meets the axes (METHODS.md section 4).
module taylorode_analysis_stability
   use taylorode_base_kinds, only: dp
   use taylorode_base_status, only: status_type, status_ok
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_registry, only: new_scheme
   use taylorode_testset_linear_test, only: linear_test_type
   use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
   implicit none
   private

   public :: stability_function, step_stability, s1_supremum, s1_contains, s1_axis_crossings

   !> Imaginary parts sampled on the imaginary w axis for the supremum over Re w <= 0
   integer, parameter :: w_samples = 121
   !> |R| <= 1 up to this roundoff counts as inside S1
   real(dp), parameter :: inside_bound = 1.0_dp + 1.0e-12_dp

contains

   !> R(z, w) of the registered scheme called `name`; NaN for a name that is not a scheme.
   function stability_function(name, z, w) result(r)
      !> Scheme name as users type it
      character(len=*), intent(in) :: name
      !> h lambda (non-stiff part)
      complex(dp), intent(in) :: z
      !> h nu (stiff part)
      complex(dp), intent(in) :: w
      complex(dp) :: r
      class(scheme_type), allocatable :: scheme
      type(status_type) :: stat
      call new_scheme(name, scheme, stat)
      if (stat%code == status_ok) then
         r = scheme%stability(z, w)
      else
         r = cmplx(ieee_value(1.0_dp, ieee_quiet_nan), ieee_value(1.0_dp, ieee_quiet_nan), dp)
      end if
   end function stability_function

   !> One real step h = 1 of the scheme on u' = z u + w u from u = 1 (complex numbers
   !> carried by 2x2 blocks): the R(z, w) the code computes.
   subroutine step_stability(scheme, z, w, r, stat)
      !> The scheme
      class(scheme_type), intent(inout) :: scheme
      !> h lambda (f) and h nu (g)
      complex(dp), intent(in) :: z, w
      !> The new state as a complex number
      complex(dp), intent(out) :: r
      !> Status of the step
      type(status_type), intent(out) :: stat
      type(linear_test_type) :: problem
      real(dp) :: u1(2)
      problem%lambda = z
      problem%nu = w
      call scheme%take_step(problem, 0.0_dp, 1.0_dp, [1.0_dp, 0.0_dp], u1, stat)
      r = cmplx(u1(1), u1(2), dp)
   end subroutine step_stability

   !> sup over Re w <= 0 of |R(z, w)|: by the maximum principle the supremum lies on the
   !> imaginary axis or at infinity, sampled at w = i y with y = 0, +-10^(-3..6) and w = -1e12.
   pure real(dp) function s1_supremum(scheme, z) result(sup)
      !> The scheme
      class(scheme_type), intent(in) :: scheme
      !> h lambda
      complex(dp), intent(in) :: z
      integer :: k
      real(dp) :: y
      sup = abs(scheme%stability(z, (0.0_dp, 0.0_dp)))
      sup = max(sup, abs(scheme%stability(z, (-1.0e12_dp, 0.0_dp))))
      do k = 1, (w_samples - 1)/2
         y = 10.0_dp**(-3.0_dp + 9.0_dp*real(k - 1, dp)/real((w_samples - 1)/2 - 1, dp))
         sup = max(sup, abs(scheme%stability(z, cmplx(0.0_dp, y, dp))), &
            abs(scheme%stability(z, cmplx(0.0_dp, -y, dp))))
      end do
   end function s1_supremum

   !> Whether z lies in S1 (up to a roundoff of 1e-12 in |R|).
   pure logical function s1_contains(scheme, z)
      !> The scheme
      class(scheme_type), intent(in) :: scheme
      !> h lambda
      complex(dp), intent(in) :: z
      s1_contains = s1_supremum(scheme, z) <= inside_bound
   end function s1_contains

   !> Where S1 meets the axes inside [-3, 1] x [-2, 2]: [left, right] on the real axis
   !> (left > right when S1 has no real point there) and the largest |Im z| on the
   !> imaginary axis, found by a scan and bisection.
   pure subroutine s1_axis_crossings(scheme, left, right, top)
      !> The scheme
      class(scheme_type), intent(in) :: scheme
      !> Real-axis interval and imaginary-axis extent
      real(dp), intent(out) :: left, right, top
      integer, parameter :: scan = 4001
      real(dp) :: x
      integer :: i

      do i = 1, scan
         x = -3.0_dp + 4.0_dp*real(i - 1, dp)/real(scan - 1, dp)
         if (on_axis(x, .true.)) then
            left = edge(x, -3.0_dp, .true.)
            right = edge(x, 1.0_dp, .true.)
            top = 0.0_dp
            if (on_axis(0.0_dp, .false.)) top = edge(0.0_dp, 2.0_dp, .false.)
            return
         end if
      end do
      left = 1.0_dp
      right = -1.0_dp
      top = 0.0_dp
   contains
      !> x on the real axis, or i x on the imaginary axis (approached from the left half-plane)
      pure logical function on_axis(x, real_axis)
         real(dp), intent(in) :: x
         logical, intent(in) :: real_axis
         if (real_axis) then
            on_axis = s1_contains(scheme, cmplx(x, 0.0_dp, dp))
         else
            on_axis = s1_contains(scheme, cmplx(-1.0e-12_dp, x, dp)) .or. s1_contains(scheme, cmplx(0.0_dp, x, dp))
         end if
      end function on_axis
      !> Bisection for the boundary between a point inside and a limit (the limit when inside)
      pure real(dp) function edge(from, limit, real_axis)
         real(dp), intent(in) :: from, limit
         logical, intent(in) :: real_axis
         real(dp) :: a, b, m
         integer :: it
         a = from
         b = limit
         if (on_axis(b, real_axis)) then
            edge = b
            return
         end if
         do it = 1, 60
            m = 0.5_dp*(a + b)
            if (on_axis(m, real_axis)) then
               a = m
            else
               b = m
            end if
         end do
         edge = a
      end function edge
   end subroutine s1_axis_crossings

end module taylorode_analysis_stability
