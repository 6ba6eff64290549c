!> The external procedures of the procedural interface for legacy Fortran (TAYLORODE,
!> TAYLORODE_SPLIT, TAYLORODE_CONTR, TAYLORODE_MESSAGE; see taylorode_interfaces_legacy)
!> and what they need to call it: the shapes of the user's routines and the
!> C-interoperable entries of taylorode_interfaces_legacy. The external procedures use
!> this module alone, which reaches no IEEE module: gfortran saves, clears and restores
!> the floating-point environment around every procedure whose own scope reaches one
!> through USE (0.2 us a call, an eighth of a one-step TAYLORODE call before). A module
!> procedure is not wrapped for its module's use of one; an external procedure that uses
!> such a module is.
module taylorode_interfaces_legacy_entry
   use taylorode_base_kinds, only: dp
   use, intrinsic :: iso_c_binding, only: c_int, c_double, c_char, c_funptr, c_funloc, c_null_funptr
   implicit none
   private

   public :: dp, fcn_interface, jac_interface, mas_interface, solout_interface, c_funloc, c_null_funptr
   public :: legacy_solve_entry, legacy_interpolate_entry, legacy_message_entry

   abstract interface
      !> F = right-hand side (or its non-stiff or stiff part) at (X, Y)
      subroutine fcn_interface(n, x, y, f, rpar, ipar)
         import :: dp
         !> Unknowns
         integer :: n
         !> Time and state (copies: the routine may write them)
         real(dp) :: x, y(n)
         !> The value at (x, y)
         real(dp) :: f(n)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched (IPAR(IWORK(11)): the
         !> evaluation flag when IWORK(11) > 0)
         integer :: ipar(*)
      end subroutine fcn_interface
      !> DFY = its Jacobian (dense LDFY x N, or band storage)
      subroutine jac_interface(n, x, y, dfy, ldfy, rpar, ipar)
         import :: dp
         !> Unknowns, and the leading dimension of dfy (n dense, mljac + mujac + 1 band)
         integer :: n, ldfy
         !> Time and state (copies: the routine may write them)
         real(dp) :: x, y(n)
         !> The Jacobian: dfy(i, j) = d part_i / d y_j, or dfy(i - j + mujac + 1, j) in band storage
         real(dp) :: dfy(ldfy, n)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched
         integer :: ipar(*)
      end subroutine jac_interface
      !> AM = the constant mass matrix M (RADAU5's MAS): dense LMAS x N when MLMAS = N, else
      !> AM(I - J + MUMAS + 1, J) = M(I, J)
      subroutine mas_interface(n, am, lmas, rpar, ipar)
         import :: dp
         !> Unknowns, and the leading dimension of am (n dense, mlmas + mumas + 1 band)
         integer :: n, lmas
         !> The mass matrix
         real(dp) :: am(lmas, n)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched
         integer :: ipar(*)
      end subroutine mas_interface
      !> Called after each accepted step (and once at the start)
      subroutine solout_interface(nr, xold, x, y, cont, lrc, n, rpar, ipar, irtrn)
         import :: dp
         !> Number of the call (1 at the start), length of cont, unknowns
         integer :: nr, lrc, n
         !> Start and end of the step just accepted (both the start time on the first call)
         real(dp) :: xold, x
         !> State at x
         real(dp) :: y(n)
         !> The step, for TAYLORODE_CONTR
         real(dp) :: cont(lrc)
         !> The caller's real data, passed through untouched
         real(dp) :: rpar(*)
         !> The caller's integer data, passed through untouched
         integer :: ipar(*)
         !> Set it negative to stop the integration
         integer :: irtrn
      end subroutine solout_interface
   end interface

   !> legacy_solve with C-interoperable arguments (defined in taylorode_interfaces_legacy
   !> under this binding name; the arguments as there)
   interface
      subroutine legacy_solve_entry(scheme_name, name_length, n, fcn_f, fcn_g, has_f, x, y, xend, h, rtol, atol, &
         itol, jac_f, ijac_f, jac_g, ijac_g, mljac, mujac, mas, imas, mlmas, mumas, solout, iout, work, lwork, &
         iwork, liwork, rpar, ipar, idid) bind(c, name="taylorode_legacy_solve_entry")
         import :: c_int, c_double, c_char, c_funptr
         character(kind=c_char), intent(in) :: scheme_name(*)
         integer(c_int), value :: name_length
         integer(c_int), intent(in) :: n
         type(c_funptr), value :: fcn_f, fcn_g
         integer(c_int), value :: has_f
         real(c_double), intent(inout) :: x, y(n)
         real(c_double), intent(in) :: xend
         real(c_double), intent(inout) :: h
         real(c_double), intent(in) :: rtol(*), atol(*)
         integer(c_int), intent(in) :: itol
         type(c_funptr), value :: jac_f, jac_g
         integer(c_int), intent(in) :: ijac_f, ijac_g, mljac, mujac
         type(c_funptr), value :: mas
         integer(c_int), intent(in) :: imas, mlmas, mumas
         type(c_funptr), value :: solout
         integer(c_int), intent(in) :: iout, lwork, liwork
         real(c_double), intent(inout) :: work(*)
         integer(c_int), intent(inout) :: iwork(*)
         real(c_double), intent(inout), target :: rpar(*)
         integer(c_int), intent(inout), target :: ipar(*)
         integer(c_int), intent(out) :: idid
      end subroutine legacy_solve_entry
   end interface

   !> legacy_interpolate with C-interoperable arguments (defined in
   !> taylorode_interfaces_legacy under this binding name)
   interface
      pure function legacy_interpolate_entry(i, s, cont, lrc) result(value) &
         bind(c, name="taylorode_legacy_interpolate_entry")
         import :: c_int, c_double
         integer(c_int), intent(in) :: i, lrc
         real(c_double), intent(in) :: s, cont(lrc)
         real(c_double) :: value
      end function legacy_interpolate_entry
   end interface

   !> legacy_message into text(1:text_length) (defined in taylorode_interfaces_legacy
   !> under this binding name)
   interface
      subroutine legacy_message_entry(reason, detail, text, text_length) bind(c, name="taylorode_legacy_message_entry")
         import :: c_int, c_char
         integer(c_int), intent(in) :: reason, detail
         character(kind=c_char), intent(out) :: text(*)
         integer(c_int), value :: text_length
      end subroutine legacy_message_entry
   end interface

end module taylorode_interfaces_legacy_entry

!> TAYLORODE, RADAU5's argument list with the scheme's name in front; FCN is the
!> whole right-hand side, treated as stiff (see module taylorode_interfaces_legacy).
subroutine taylorode(scheme, n, fcn, x, y, xend, h, rtol, atol, itol, jac, ijac, mljac, mujac, mas, imas, mlmas, &
   mumas, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
   use taylorode_interfaces_legacy_entry, only: dp, legacy_solve_entry, fcn_interface, jac_interface, mas_interface, &
      solout_interface, c_funloc
   implicit none
   !> Scheme name, as users type it ('radau5', 'i-t-2', ...)
   character(len=*), intent(in) :: scheme
   !> Unknowns
   integer, intent(in) :: n
   !> The right-hand side, FCN(N, X, Y, F, RPAR, IPAR)
   procedure(fcn_interface) :: fcn
   !> Start time on entry, where the integration stopped on exit
   real(dp), intent(inout) :: x
   !> State at x
   real(dp), intent(inout) :: y(n)
   !> Final time, > x
   real(dp), intent(in) :: xend
   !> First step size guess on entry (0: RADAU5's 1e-6 for radau5, automatic for the
   !> others), the next one on exit
   real(dp), intent(inout) :: h
   !> Relative and absolute tolerances, scalars (itol = 0) or arrays of n (itol /= 0)
   real(dp), intent(in) :: rtol(*), atol(*)
   !> 0 for scalar tolerances, anything else for one per component
   integer, intent(in) :: itol
   !> The Jacobian, JAC(N, X, Y, DFY, LDFY, RPAR, IPAR), called when ijac = 1
   procedure(jac_interface) :: jac
   !> 1: jac is given, 0: forward differences
   integer, intent(in) :: ijac
   !> Lower and upper bandwidths of the Jacobian (mljac >= n: dense; else both in [0, n - 1])
   integer, intent(in) :: mljac, mujac
   !> The mass matrix, MAS(N, AM, LMAS, RPAR, IPAR), called once when imas /= 0
   procedure(mas_interface) :: mas
   !> 0: M = I; otherwise M comes from mas (radau5 only)
   integer, intent(in) :: imas
   !> Bandwidths of the mass matrix (mlmas = n: dense; else within the Jacobian's bands)
   integer, intent(in) :: mlmas, mumas
   !> Called after every accepted step when iout /= 0
   procedure(solout_interface) :: solout
   !> 0: never call solout
   integer, intent(in) :: iout
   !> Real settings WORK(1:9) (RADAU5's; 0: defaults)
   real(dp), intent(inout) :: work(*)
   !> Integer settings IWORK(1:11) (RADAU5's and the evaluation flag); outputs IWORK(12:20):
   !> the reason of a failure and its detail, evaluations, Jacobians, steps, accepted,
   !> rejected, LU, solves
   integer, intent(inout) :: iwork(*)
   !> Lengths of work and iwork (at least 20 each)
   integer, intent(in) :: lwork, liwork
   !> Real data passed to the user's routines untouched
   real(dp), intent(inout), target :: rpar(*)
   !> Integer data passed to the user's routines untouched
   integer, intent(inout), target :: ipar(*)
   !> 1 success, 2 stopped by solout, < 0 failure (see the module comment)
   integer, intent(out) :: idid
   call legacy_solve_entry(scheme, len(scheme), n, c_funloc(fcn), c_funloc(fcn), 0, x, y, xend, h, rtol, atol, itol, &
      c_funloc(jac), 0, c_funloc(jac), ijac, mljac, mujac, c_funloc(mas), imas, mlmas, mumas, c_funloc(solout), iout, &
      work, lwork, iwork, liwork, rpar, ipar, idid)
end subroutine taylorode

!> TAYLORODE_SPLIT, with f (FCNF, explicit in the semi-implicit schemes) and g (FCNG,
!> stiff) apart, each with its Jacobian (IJACF, IJACG = 0: differences); no mass matrix.
subroutine taylorode_split(scheme, n, fcnf, fcng, x, y, xend, h, rtol, atol, itol, jacf, ijacf, jacg, ijacg, mljac, &
   mujac, solout, iout, work, lwork, iwork, liwork, rpar, ipar, idid)
   use taylorode_interfaces_legacy_entry, only: dp, legacy_solve_entry, fcn_interface, jac_interface, &
      solout_interface, c_funloc, c_null_funptr
   implicit none
   !> Scheme name, as users type it ('si-t-2', 'imex-rk21', ...)
   character(len=*), intent(in) :: scheme
   !> Unknowns
   integer, intent(in) :: n
   !> The non-stiff part f and the stiff part g, FCNF(N, X, Y, F, RPAR, IPAR)
   procedure(fcn_interface) :: fcnf, fcng
   !> Start time on entry, where the integration stopped on exit
   real(dp), intent(inout) :: x
   !> State at x
   real(dp), intent(inout) :: y(n)
   !> Final time, > x
   real(dp), intent(in) :: xend
   !> First step size guess on entry (0: RADAU5's 1e-6 for radau5, automatic for the
   !> others), the next one on exit
   real(dp), intent(inout) :: h
   !> Relative and absolute tolerances, scalars (itol = 0) or arrays of n (itol /= 0)
   real(dp), intent(in) :: rtol(*), atol(*)
   !> 0 for scalar tolerances, anything else for one per component
   integer, intent(in) :: itol
   !> The Jacobians of f and g, JACF(N, X, Y, DFY, LDFY, RPAR, IPAR), called when ijacf = 1 and ijacg = 1
   procedure(jac_interface) :: jacf, jacg
   !> 1: the Jacobian is given, 0: forward differences
   integer, intent(in) :: ijacf, ijacg
   !> Lower and upper bandwidths of both Jacobians (mljac >= n: dense; else both in [0, n - 1])
   integer, intent(in) :: mljac, mujac
   !> Called after every accepted step when iout /= 0
   procedure(solout_interface) :: solout
   !> 0: never call solout
   integer, intent(in) :: iout
   !> Real settings (as TAYLORODE)
   real(dp), intent(inout) :: work(*)
   !> Integer settings and outputs (as TAYLORODE)
   integer, intent(inout) :: iwork(*)
   !> Lengths of work and iwork (at least 20 each)
   integer, intent(in) :: lwork, liwork
   !> Real data passed to the user's routines untouched
   real(dp), intent(inout), target :: rpar(*)
   !> Integer data passed to the user's routines untouched
   integer, intent(inout), target :: ipar(*)
   !> 1 success, 2 stopped by solout, < 0 failure (see the module comment)
   integer, intent(out) :: idid
   call legacy_solve_entry(scheme, len(scheme), n, c_funloc(fcnf), c_funloc(fcng), 1, x, y, xend, h, rtol, atol, itol, &
      c_funloc(jacf), ijacf, c_funloc(jacg), ijacg, mljac, mujac, c_null_funptr, 0, n, 0, c_funloc(solout), iout, &
      work, lwork, iwork, liwork, rpar, ipar, idid)
end subroutine taylorode_split

!> TAYLORODE_CONTR(I, S, CONT, LRC), component I at S inside the step SOLOUT was
!> given (RADAU5's CONTR5), from the step's dense output.
function taylorode_contr(i, s, cont, lrc) result(value)
   use taylorode_interfaces_legacy_entry, only: dp, legacy_interpolate_entry
   implicit none
   !> Component
   integer, intent(in) :: i
   !> Length of cont
   integer, intent(in) :: lrc
   !> Time inside the step
   real(dp), intent(in) :: s
   !> The step as SOLOUT received it
   real(dp), intent(in) :: cont(lrc)
   real(dp) :: value
   value = legacy_interpolate_entry(i, s, cont, lrc)
end function taylorode_contr

!> TAYLORODE_MESSAGE(IWORK, TEXT): why the last TAYLORODE or TAYLORODE_SPLIT call with
!> this IWORK ended with a negative IDID, in words (from IWORK(12) and IWORK(13); blank
!> after a success). TEXT is cut to its declared length (200 characters hold every one).
subroutine taylorode_message(iwork, text)
   use taylorode_interfaces_legacy_entry, only: legacy_message_entry
   implicit none
   !> The IWORK of the call
   integer, intent(in) :: iwork(*)
   !> The message (CHARACTER*(*))
   character(len=*), intent(out) :: text
   call legacy_message_entry(iwork(12), iwork(13), text, len(text))
end subroutine taylorode_message
