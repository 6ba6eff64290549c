!> Step-size controllers (METHODS.md section 3): the paper's I controller and the
!> PI and PID controllers in the form
!>
!>   h_new = kappa h err_n^(-k1/q) err_{n-1}^(k2/q) err_{n-2}^(-k3/q)
!>
!> where err_n is the weighted error of the current step and err_{n-1}, err_{n-2}
!> those of the previous accepted steps, and the predictive controller of
!> Gustafsson as RADAU5 uses it (Hairer & Wanner II, IV.8): after an accepted step
!>
!>   h_new = min(I factor, kappa h (h / h_{n-1}) err_n^(-2/q) max(err_{n-1}, 0.01)^(1/q)),
!>
!> the I factor alone after a rejection or before a second accepted step.
module taylorode_integrate_controller
   use taylorode_base_kinds, only: dp
   implicit none
   private

   public :: controller_i, controller_pi, controller_pid, controller_factor, controller_name
   public :: default_kappa
   public :: controller_predictive, controller_auto, predictive_factor

   !> I controller (the paper's): k = (1, 0, 0)
   integer, parameter :: controller_i = 1
   !> PI controller: k = (0.7, 0.4, 0)
   integer, parameter :: controller_pi = 2
   !> PID controller (SUNDIALS defaults): k = (0.58, 0.21, 0.1)
   integer, parameter :: controller_pid = 3
   !> Predictive controller (Gustafsson; RADAU5's default): the smaller of the I
   !> factor and `predictive_factor` after an accepted step
   integer, parameter :: controller_predictive = 4
   !> The scheme's preference: controller_predictive for a scheme that declares
   !> `predictive_control` (radau5), controller_i for every other
   integer, parameter :: controller_auto = 0
   !> Safety factor of the paper
   real(dp), parameter :: default_kappa = 0.9_dp
   !> Floor of the previous error in the predictive factor (RADAU5's ERRACC)
   real(dp), parameter :: predictive_error_floor = 1.0e-2_dp

   !> Gains (k1, k2, k3) of each controller, by column (the predictive controller's
   !> I factor in the last)
   real(dp), parameter :: gains(3, 4) = reshape([ &
      1.0_dp, 0.0_dp, 0.0_dp, &
      0.7_dp, 0.4_dp, 0.0_dp, &
      0.58_dp, 0.21_dp, 0.1_dp, &
      1.0_dp, 0.0_dp, 0.0_dp], [3, 4])

contains

   !> Factor h_new / h from the current and the two previous weighted errors
   !> (for controller_predictive: its I factor). Errors below roundoff are raised
   !> to epsilon so that the factor stays finite.
   pure function controller_factor(controller, kappa, q, err, err_previous, err_before) result(factor)
      !> controller_i, controller_pi, controller_pid or controller_predictive
      integer, intent(in) :: controller
      !> Safety factor
      real(dp), intent(in) :: kappa
      !> Order exponent (the lower order of the embedded pair plus one)
      real(dp), intent(in) :: q
      !> Weighted error of the current step
      real(dp), intent(in) :: err
      !> Weighted error of the previous accepted step (1 when there is none)
      real(dp), intent(in) :: err_previous
      !> Weighted error of the accepted step before that (1 when there is none)
      real(dp), intent(in) :: err_before
      real(dp) :: factor
      real(dp) :: e0, e1, e2

      e0 = max(err, epsilon(1.0_dp))
      e1 = max(err_previous, epsilon(1.0_dp))
      e2 = max(err_before, epsilon(1.0_dp))
      if (controller == controller_predictive .and. q == 4.0_dp) then
         ! err^(-1/4) as two square roots (a third of the cost of a power)
         factor = kappa/sqrt(sqrt(e0))
         return
      end if
      if (controller == controller_i .and. q == 2.0_dp) then
         ! err^(-1/2) as a square root (the paper's setting; a fifth of the cost of a power)
         factor = kappa/sqrt(e0)
         return
      end if
      ! a zero gain contributes the factor 1 exactly: its power is not computed
      factor = kappa*e0**(-gains(1, controller)/q)
      if (gains(2, controller) /= 0.0_dp) factor = factor*e1**(gains(2, controller)/q)
      if (gains(3, controller) /= 0.0_dp) factor = factor*e2**(-gains(3, controller)/q)
   end function controller_factor

   !> Predictive factor h_new / h after an accepted step of size h whose accepted
   !> predecessor had size h_previous and error err_previous:
   !> kappa (h / h_previous) err^(-2/q) max(err_previous, 0.01)^(1/q).
   pure function predictive_factor(kappa, q, err, err_previous, h, h_previous) result(factor)
      !> Safety factor
      real(dp), intent(in) :: kappa
      !> Order exponent (the lower order of the embedded pair plus one)
      real(dp), intent(in) :: q
      !> Weighted error of the current (accepted) step
      real(dp), intent(in) :: err
      !> Weighted error of the previous accepted step
      real(dp), intent(in) :: err_previous
      !> Size of the current step
      real(dp), intent(in) :: h
      !> Size of the previous accepted step (> 0)
      real(dp), intent(in) :: h_previous
      real(dp) :: factor
      real(dp) :: ratio
      ratio = max(err_previous, predictive_error_floor)/max(err, epsilon(1.0_dp))**2
      if (q == 4.0_dp) then
         factor = kappa*(h/h_previous)*sqrt(sqrt(ratio))
      else
         factor = kappa*(h/h_previous)*ratio**(1.0_dp/q)
      end if
   end function predictive_factor

   !> Name of a controller as users type it ("i", "pi", "pid", "predictive", "auto").
   pure function controller_name(controller) result(name)
      !> controller_i, controller_pi, controller_pid, controller_predictive or controller_auto
      integer, intent(in) :: controller
      character(len=:), allocatable :: name
      select case (controller)
      case (controller_i); name = "i"
      case (controller_pi); name = "pi"
      case (controller_pid); name = "pid"
      case (controller_predictive); name = "predictive"
      case (controller_auto); name = "auto"
      case default; name = "unknown"
      end select
   end function controller_name

end module taylorode_integrate_controller
