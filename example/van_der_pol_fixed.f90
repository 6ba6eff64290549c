!> Van der Pol (mu = 1000, the paper's splitting) from the well-prepared initial
!> state, 20000 fixed steps of i-t-2 over [0, 2]. Copy and change the scheme name,
!> mu or the number of steps.
program van_der_pol_fixed
   use taylorode, only: dp, scheme_type, new_scheme, status_type, integrate_fixed
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state, vdp_ic_prepared
   implicit none

   type(van_der_pol_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(status_type) :: stat
   real(dp) :: u(2)

   problem = new_van_der_pol(mu=1000.0_dp)
   u = van_der_pol_initial_state(vdp_ic_prepared)

   call new_scheme("i-t-2", scheme, stat)
   if (.not. stat%ok()) error stop stat%message

   call integrate_fixed(problem, scheme, 0.0_dp, 2.0_dp, 20000, u, stat)
   if (.not. stat%ok()) error stop stat%message

   print '(a, es23.15, a, es23.15)', "y(2) =", u(1), "   z(2) =", u(2)
   print '(a, i0, a, i0, a, i0)', "f evaluations: ", scheme%counters%f_evaluations, &
      ", LU factorizations: ", scheme%counters%lu_factorizations, &
      ", Newton iterations: ", scheme%counters%newton_iterations
end program van_der_pol_fixed
