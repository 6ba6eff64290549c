!> taylorode's stand-in for the `testdrive_version` module of test-drive v0.5.0:
!> the version of the test-drive API this stand-in provides.  Written from
!> scratch by the taylorode project; it contains no test-drive source.
module testdrive_version
   implicit none
   private

   public :: testdrive_version_string, testdrive_version_compact
   public :: get_testdrive_version

   !> Version as text
   character(len=*), parameter :: testdrive_version_string = "0.5.0"

   !> Version as major, minor, patch
   integer, parameter :: testdrive_version_compact(3) = [0, 5, 0]

contains

   !> Any of the version numbers and the version text
   subroutine get_testdrive_version(major, minor, patch, string)
      integer, intent(out), optional :: major, minor, patch
      character(len=:), allocatable, intent(out), optional :: string

      if (present(major)) major = testdrive_version_compact(1)
      if (present(minor)) minor = testdrive_version_compact(2)
      if (present(patch)) patch = testdrive_version_compact(3)
      if (present(string)) string = testdrive_version_string
   end subroutine get_testdrive_version

end module testdrive_version
