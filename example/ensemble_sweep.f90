!> Many independent integrations at once: Van der Pol for 16 values of mu from 1 to
!> 1000, shared out over OpenMP threads by integrate_ensemble. Each member has its own
!> problem object (and gets a scheme object of its own), so the results are those of
!> the serial loop, bit for bit, whatever the number of threads. Threads need a build
!> with OpenMP:
!>   fpm run --example ensemble_sweep --flag -fopenmp --link-flag -fopenmp
program ensemble_sweep
   use taylorode, only: dp, integrate_ensemble, ensemble_threads, integrator_options_type, &
      integration_stats_type, status_type, status_name
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol
   implicit none

   integer, parameter :: members = 16
   type(van_der_pol_type) :: problems(members)
   type(integrator_options_type) :: options
   type(integration_stats_type) :: stats(members)
   type(status_type) :: member_stat(members), stat
   real(dp) :: u(2, members), mu(members)
   integer :: k

   do k = 1, members
      mu(k) = 10.0_dp**(3.0_dp*real(k - 1, dp)/real(members - 1, dp))
      problems(k) = new_van_der_pol(mu(k))
      u(:, k) = problems(k)%u0
   end do
   options%rtol = 1.0e-6_dp
   options%atol = 1.0e-6_dp

   call integrate_ensemble(problems, "i-t-2", 0.0_dp, 20.0_dp, u, options, stats, member_stat, stat)

   print '(i0, " members on up to ", i0, " thread(s)")', members, ensemble_threads()
   print '(a10, a12, a10, 2a14)', "mu", "status", "steps", "y(20)", "z(20)"
   do k = 1, members
      print '(f10.2, a12, i10, 2es14.5)', mu(k), status_name(member_stat(k)%code), stats(k)%accepted_steps, u(:, k)
   end do
   if (.not. stat%ok()) error stop stat%message
end program ensemble_sweep
