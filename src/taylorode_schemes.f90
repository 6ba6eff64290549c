!> The one place where scheme names are registered: creates a scheme from the
!> name users type.
module taylorode_schemes
   use taylorode_status, only: status_type, set_status, status_unknown_scheme
   use taylorode_scheme, only: scheme_type
   use taylorode_explicit_taylor, only: explicit_taylor_type, new_explicit_taylor
   use taylorode_semi_implicit_taylor, only: semi_implicit_taylor_type, new_semi_implicit_taylor, &
      si_t_1, si_t_2, si_t_2_paper
   use taylorode_implicit_taylor, only: implicit_taylor_type, new_implicit_taylor
   use taylorode_imex_rk, only: imex_rk21_type, new_imex_rk21
   use taylorode_radau, only: radau5_type, new_radau5
   implicit none
   private

   public :: new_scheme, scheme_names, scheme_count

   !> Number of registered schemes
   integer, parameter :: scheme_count = 9
   !> Every registered name, as users type it
   character(len=*), parameter :: scheme_names(scheme_count) = [character(len=12) :: &
      "ex-t-1", "ex-t-2", "si-t-1", "si-t-2", "si-t-2-paper", "i-t-1", "i-t-2", "imex-rk21", "radau5"]

contains

   !> Create the scheme called `name` (case as listed in `scheme_names`).
   !> An unknown name leaves `scheme` unallocated and stat lists the valid names.
   subroutine new_scheme(name, scheme, stat)
      !> Name as users type it, e.g. "i-t-2"
      character(len=*), intent(in) :: name
      !> The new scheme
      class(scheme_type), allocatable, intent(out) :: scheme
      !> status_unknown_scheme for an unknown name
      type(status_type), intent(out) :: stat

      type(explicit_taylor_type) :: explicit
      type(semi_implicit_taylor_type) :: semi_implicit
      type(implicit_taylor_type) :: implicit
      type(imex_rk21_type) :: imex
      type(radau5_type) :: radau
      integer :: i
      character(len=:), allocatable :: valid

      select case (trim(adjustl(name)))
      case ("ex-t-1")
         call new_explicit_taylor(explicit, 1)
         allocate (scheme, source=explicit)
      case ("ex-t-2")
         call new_explicit_taylor(explicit, 2)
         allocate (scheme, source=explicit)
      case ("si-t-1")
         call new_semi_implicit_taylor(semi_implicit, si_t_1)
         allocate (scheme, source=semi_implicit)
      case ("si-t-2")
         call new_semi_implicit_taylor(semi_implicit, si_t_2)
         allocate (scheme, source=semi_implicit)
      case ("si-t-2-paper")
         call new_semi_implicit_taylor(semi_implicit, si_t_2_paper)
         allocate (scheme, source=semi_implicit)
      case ("i-t-1")
         call new_implicit_taylor(implicit, 1)
         allocate (scheme, source=implicit)
      case ("i-t-2")
         call new_implicit_taylor(implicit, 2)
         allocate (scheme, source=implicit)
      case ("imex-rk21")
         call new_imex_rk21(imex)
         allocate (scheme, source=imex)
      case ("radau5")
         call new_radau5(radau)
         allocate (scheme, source=radau)
      case default
         valid = trim(scheme_names(1))
         do i = 2, scheme_count
            valid = valid//", "//trim(scheme_names(i))
         end do
         call set_status(stat, status_unknown_scheme, 'unknown scheme "'//trim(name)// &
            '"; valid names: '//valid)
      end select
   end subroutine new_scheme

end module taylorode_schemes
