!> The paper's Van der Pol experiment with the adaptive integrator: mu = 1000,
!> t in [0, 3000], I controller, absolute tolerance 1e-5 in the max norm.
!> Usage: fpm run --example van_der_pol_adaptive [-- SCHEME [IC]]   (default i-t-2, IC 1)
program van_der_pol_adaptive
   use taylorode, only: dp, scheme_type, new_scheme, status_type, integrate, integrator_options_type, &
      paper_options, integration_stats_type
   use taylorode_testset, only: van_der_pol_type, new_van_der_pol, van_der_pol_initial_state
   implicit none

   type(van_der_pol_type) :: problem
   class(scheme_type), allocatable :: scheme
   type(integrator_options_type) :: options
   type(integration_stats_type) :: stats
   type(status_type) :: stat
   character(len=32) :: name, ic_text
   integer :: ic
   real(dp) :: u(2)

   name = "i-t-2"
   ic_text = "1"
   if (command_argument_count() >= 1) call get_command_argument(1, name)
   if (command_argument_count() >= 2) call get_command_argument(2, ic_text)
   read (ic_text, *) ic

   problem = new_van_der_pol(mu=1000.0_dp)
   u = van_der_pol_initial_state(ic)
   options = paper_options()

   call new_scheme(trim(name), scheme, stat)
   if (.not. stat%ok()) error stop stat%message

   call integrate(problem, scheme, 0.0_dp, 3000.0_dp, u, options, stats, stat)
   if (.not. stat%ok()) print '(a)', "stopped: "//stat%message

   print '(a, f10.3, a, 2es24.15)', "t =", stats%t_reached, "   u =", u
   print '(a, i0, a, i0, a, i0, a, i0)', "accepted ", stats%accepted_steps, ", rejected (error) ", &
      stats%rejected_error, ", rejected (Newton) ", stats%rejected_newton, &
      ", LU factorizations ", stats%work%lu_factorizations
   print '(a, f8.3, a)', "CPU ", stats%cpu_seconds, " s"
end program van_der_pol_adaptive
