!> The one place where schemes are registered: their names, in the order tables
!> list them, and how each is created. Adding a scheme is its module plus one
!> entry in `scheme_names` and one `case` in `new_scheme`; the tests, the analyses
!> and the app iterate over this list.
module taylorode_schemes_registry
   use taylorode_base_status, only: status_type, set_status, status_unknown_scheme
   use taylorode_schemes_scheme, only: scheme_type
   use taylorode_schemes_explicit_taylor, only: new_explicit_taylor
   use taylorode_schemes_semi_implicit_taylor, only: new_semi_implicit_taylor, si_t_1, si_t_2, si_t_2_paper
   use taylorode_schemes_implicit_taylor, only: new_implicit_taylor
   use taylorode_schemes_imex_rk21, only: new_imex_rk21
   use taylorode_schemes_radau5, only: new_radau5
   implicit none
   private

   public :: new_scheme, scheme_names, scheme_count

   !> Every registered name, as users type it
   character(len=*), parameter :: scheme_names(*) = [character(len=12) :: &
      "ex-t-1", "ex-t-2", "si-t-1", "si-t-2", "si-t-2-paper", "i-t-1", "i-t-2", "imex-rk21", "radau5"]
   !> Number of registered schemes
   integer, parameter :: scheme_count = size(scheme_names)

contains

   !> Create the scheme called `name` (as listed in `scheme_names`). An unknown
   !> name leaves `scheme` unallocated and stat lists the valid names.
   subroutine new_scheme(name, scheme, stat)
      !> Name as users type it, e.g. "i-t-2"
      character(len=*), intent(in) :: name
      !> The new scheme
      class(scheme_type), allocatable, intent(out) :: scheme
      !> status_unknown_scheme for an unknown name
      type(status_type), intent(out) :: stat
      character(len=256) :: valid
      integer :: i

      select case (trim(adjustl(name)))
      case ("ex-t-1"); allocate (scheme, source=new_explicit_taylor(1))
      case ("ex-t-2"); allocate (scheme, source=new_explicit_taylor(2))
      case ("si-t-1"); allocate (scheme, source=new_semi_implicit_taylor(si_t_1))
      case ("si-t-2"); allocate (scheme, source=new_semi_implicit_taylor(si_t_2))
      case ("si-t-2-paper"); allocate (scheme, source=new_semi_implicit_taylor(si_t_2_paper))
      case ("i-t-1"); allocate (scheme, source=new_implicit_taylor(1))
      case ("i-t-2"); allocate (scheme, source=new_implicit_taylor(2))
      case ("imex-rk21"); allocate (scheme, source=new_imex_rk21())
      case ("radau5"); allocate (scheme, source=new_radau5())
      case default
         valid = scheme_names(1)
         do i = 2, scheme_count
            valid = trim(valid)//", "//scheme_names(i)
         end do
         call set_status(stat, status_unknown_scheme, 'unknown scheme "'//trim(name)// &
            '"; valid names: '//trim(valid))
      end select
   end subroutine new_scheme

end module taylorode_schemes_registry
