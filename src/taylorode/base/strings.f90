!> Numbers and words as text, for status messages and reports.
module taylorode_base_strings
   use taylorode_base_kinds, only: dp, i8
   implicit none
   private

   public :: format_real, fixed_length_real, format_count, format_fixed, format_integer, format_number, pad, choose

   !> A whole number as text, without separators
   interface format_integer
      module procedure :: format_default_integer, format_wide_integer
   end interface format_integer

contains

   !> A default-kind integer as text (e.g. 42).
   pure function format_default_integer(n) result(text)
      !> The number
      integer, intent(in) :: n
      character(len=:), allocatable :: text
      character(len=16) :: buffer
      write (buffer, '(i0)') n
      text = trim(buffer)
   end function format_default_integer

   !> A wide integer as text (e.g. 125748).
   pure function format_wide_integer(n) result(text)
      !> The number
      integer(i8), intent(in) :: n
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      write (buffer, '(i0)') n
      text = trim(buffer)
   end function format_wide_integer

   !> A real in scientific notation with `digits` significant digits (e.g. 1.23E-05).
   pure function format_real(x, digits) result(text)
      !> The number
      real(dp), intent(in) :: x
      !> Significant digits (default 3)
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      text = trim(fixed_length_real(x, digits))
   end function format_real

   !> A real as format_real writes it (1.23E-05, -7.927342E+02, 1.0E-300, nan, -inf),
   !> left-adjusted in a fixed-length result to be trimmed: for messages built in
   !> fixed-length buffers, where a deferred-length function result is not thread-safe
   !> with gfortran 12 (what an integration reports must be). Every value is legible:
   !> no field too narrow for a sign, no exponent without its E.
   pure function fixed_length_real(x, digits) result(text)
      !> The number
      real(dp), intent(in) :: x
      !> Significant digits (default 3; 1 to 30)
      integer, intent(in), optional :: digits
      character(len=40) :: text
      character(len=24) :: form
      integer :: d, point
      d = 3
      if (present(digits)) d = min(max(digits, 1), 30)
      if (x /= x) then
         text = "nan"
         return
      end if
      if (abs(x) > huge(x)) then
         text = merge("inf ", "-inf", x > 0.0_dp)
         return
      end if
      ! three exponent digits where two cannot hold the exponent (1e-100, 1e100)
      if (x /= 0.0_dp .and. (abs(x) < 1.0e-99_dp .or. abs(x) >= 1.0e100_dp)) then
         write (form, '("(es", i0, ".", i0, "e3)")') d + 8, d - 1
      else
         write (form, '("(es", i0, ".", i0, "e2)")') d + 7, d - 1
      end if
      write (text, form) x
      text = adjustl(text)
      ! one digit: "1.E+04" reads better as "1E+04"
      if (d == 1) then
         point = index(text, ".")
         text = text(:point - 1)//text(point + 1:)
      end if
   end function fixed_length_real

   !> A real as people write it: whole numbers below 1e9 without decimals (3000),
   !> anything else in scientific notation with 3 digits (1.00E-05).
   pure function format_number(x) result(text)
      !> The number
      real(dp), intent(in) :: x
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      ! written out, not through format_wide_integer and format_real: a deferred-length
      ! function result keeps its length in static memory with gfortran 12
      if (abs(x) < 1.0e9_dp .and. x == aint(x)) then
         write (buffer, '(i0)') int(x, i8)
         text = trim(buffer)
      else
         text = trim(fixed_length_real(x))
      end if
   end function format_number

   !> A real with `decimals` digits after the point (e.g. 0.088).
   pure function format_fixed(x, decimals) result(text)
      !> The number
      real(dp), intent(in) :: x
      !> Digits after the decimal point
      integer, intent(in) :: decimals
      character(len=:), allocatable :: text
      character(len=40) :: buffer, form
      write (form, '("(f0.", i0, ")")') decimals
      write (buffer, form) x
      text = trim(adjustl(buffer))
      if (text(1:1) == ".") text = "0"//text
      if (text(1:min(2, len(text))) == "-.") text = "-0"//text(2:)
      if (decimals == 0 .and. text(len(text):) == ".") text = text(:len(text) - 1)
   end function format_fixed

   !> A count with thousands separators (e.g. 125,748).
   pure function format_count(n) result(text)
      !> The count
      integer(i8), intent(in) :: n
      character(len=:), allocatable :: text
      character(len=24) :: buffer
      character(len=:), allocatable :: digits
      integer :: i, lead
      write (buffer, '(i0)') abs(n)
      digits = trim(buffer)
      lead = mod(len(digits), 3)
      if (lead == 0) lead = 3
      text = digits(:lead)
      do i = lead + 1, len(digits), 3
         text = text//","//digits(i:i + 2)
      end do
      if (n < 0) text = "-"//text
   end function format_count

   !> Text right-aligned in a field of `width` (left-aligned when width < 0).
   pure function pad(text, width) result(padded)
      !> The text
      character(len=*), intent(in) :: text
      !> Field width; negative for left alignment
      integer, intent(in) :: width
      character(len=:), allocatable :: padded
      if (len(text) >= abs(width)) then
         padded = text
      else if (width > 0) then
         padded = repeat(" ", width - len(text))//text
      else
         padded = text//repeat(" ", -width - len(text))
      end if
   end function pad

   !> when_true if the condition holds, else when_false (texts of any lengths).
   pure function choose(condition, when_true, when_false) result(text)
      !> The condition
      logical, intent(in) :: condition
      !> Text when it holds
      character(len=*), intent(in) :: when_true
      !> Text otherwise
      character(len=*), intent(in) :: when_false
      character(len=:), allocatable :: text
      if (condition) then
         text = when_true
      else
         text = when_false
      end if
   end function choose

end module taylorode_base_strings
