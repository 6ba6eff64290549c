!> Working precision of taylorode.
module taylorode_base_kinds
   use, intrinsic :: iso_fortran_env, only: real64, int64
   implicit none
   private

   public :: dp, i8

   !> Double precision real kind used for every state, time and tolerance
   integer, parameter :: dp = real64
   !> Wide integer kind for counters that can exceed 2**31 (steps, evaluations)
   integer, parameter :: i8 = int64

end module taylorode_base_kinds
