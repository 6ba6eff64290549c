!> Observed order of every scheme with fixed steps on Van der Pol with mu = 1 over
!> [0, 1]. The reference is i-t-2 with 2^16 steps (error ~1e-10, far below the
!> errors measured here).
program convergence_study
   use taylorode, only: dp, van_der_pol_type, new_van_der_pol, scheme_type, new_scheme, &
      status_type, integrate_fixed, scheme_names, scheme_count
   implicit none

   type(van_der_pol_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(status_type) :: stat
   real(dp), parameter :: u0(2) = [2.0_dp, 0.0_dp], t_end = 1.0_dp
   integer, parameter :: steps(4) = [40, 80, 160, 320]
   real(dp) :: reference(2), u(2), errors(size(steps))
   integer :: k, i

   problem = new_van_der_pol(mu=1.0_dp)
   reference = u0
   call new_scheme("i-t-2", scheme, stat)
   call integrate_fixed(problem, scheme, 0.0_dp, t_end, 2**16, reference, stat)
   if (.not. stat%ok()) error stop stat%message

   print '(a14, 4a12, a)', "scheme", "N=40", "N=80", "N=160", "N=320", "   observed orders"
   do k = 1, scheme_count
      call new_scheme(trim(scheme_names(k)), scheme, stat)
      do i = 1, size(steps)
         u = u0
         call integrate_fixed(problem, scheme, 0.0_dp, t_end, steps(i), u, stat)
         if (.not. stat%ok()) error stop stat%message
         errors(i) = maxval(abs(u - reference))
      end do
      print '(a14, 4es12.3, 3f7.3)', trim(scheme_names(k)), errors, &
         log(errors(1:3)/errors(2:4))/log(2.0_dp)
   end do
end program convergence_study
