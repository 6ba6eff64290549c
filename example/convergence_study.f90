!> Observed order of every scheme with fixed steps on Van der Pol with mu = 1 over
!> [0, 1]. The reference is radau5 with 4096 steps (error ~1e-16, far below every
!> error measured here); radau5 itself is measured with 4 ... 32 steps, where its
!> errors are still well above roundoff.
program convergence_study
   use taylorode, only: dp, scheme_type, new_scheme, status_type, integrate_fixed, scheme_names, scheme_count
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol
   use taylorode_analysis, only: observed_orders
   implicit none

   type(van_der_pol_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(status_type) :: stat
   real(dp), parameter :: u0(2) = [2.0_dp, 0.0_dp], t_end = 1.0_dp
   integer, parameter :: taylor_steps(4) = [40, 80, 160, 320], radau_steps(4) = [4, 8, 16, 32]
   real(dp) :: reference(2), errors(4), orders(3)
   integer :: k

   problem = new_van_der_pol(mu=1.0_dp)
   reference = u0
   call new_scheme("radau5", scheme, stat)
   call integrate_fixed(problem, scheme, 0.0_dp, t_end, 4096, reference, stat)
   if (.not. stat%ok()) error stop stat%message

   print '(a14, a22, 4a12, a)', "scheme", "steps", "error 1", "error 2", "error 3", "error 4", &
      "   observed orders"
   do k = 1, scheme_count
      call new_scheme(trim(scheme_names(k)), scheme, stat)
      if (scheme_names(k) == "radau5") then
         call observed_orders(problem, scheme, 0.0_dp, t_end, u0, reference, radau_steps, errors, orders, stat)
         if (.not. stat%ok()) error stop stat%message
         print '(a14, a22, 4es12.3, 3f7.3)', trim(scheme_names(k)), "4, 8, 16, 32", errors, orders
      else
         call observed_orders(problem, scheme, 0.0_dp, t_end, u0, reference, taylor_steps, errors, orders, stat)
         if (.not. stat%ok()) error stop stat%message
         print '(a14, a22, 4es12.3, 3f7.3)', trim(scheme_names(k)), "40, 80, 160, 320", errors, orders
      end if
   end do
end program convergence_study
