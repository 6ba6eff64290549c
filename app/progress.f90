!> Progress lines of long runs, on standard error (a module procedure, so that no
!> closure is passed around and the executable needs no executable stack).
module app_progress
   use, intrinsic :: iso_fortran_env, only: error_unit
   implicit none
   private

   public :: progress

contains

   !> Print "  ... message" on standard error.
   subroutine progress(message)
      !> What is about to run
      character(len=*), intent(in) :: message
      write (error_unit, '(a)') "  ... "//message
   end subroutine progress

end module app_progress
