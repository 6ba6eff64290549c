!> Reports: the text lines and CSV tables an experiment produces, and number
!> formatting for them. Nothing here writes to a terminal or a file.
module taylorode_report
   use taylorode_kinds, only: dp, i8
   implicit none
   private

   public :: report_type, csv_table_type, text_line_type
   public :: format_real, format_count, format_fixed, pad, choose

   !> One line of text
   type :: text_line_type
      character(len=:), allocatable :: text
   end type text_line_type

   !> A CSV table: a file name, a header line and rows
   type :: csv_table_type
      !> File name (inside the output directory, or a path chosen by the user)
      character(len=:), allocatable :: file_name
      !> Comma-separated column names
      character(len=:), allocatable :: header
      !> Comma-separated rows
      type(text_line_type), allocatable :: rows(:)
      !> Rows in use
      integer :: count = 0
   contains
      !> Append a row
      procedure :: add_row
   end type csv_table_type

   !> What an experiment says (lines for the terminal) and produces (CSV tables)
   type :: report_type
      !> Terminal lines, in order
      type(text_line_type), allocatable :: lines(:)
      !> Lines in use
      integer :: line_count = 0
      !> CSV tables
      type(csv_table_type), allocatable :: tables(:)
      !> False when a check of the experiment failed
      logical :: passed = .true.
   contains
      !> Append a terminal line
      procedure :: add_line
      !> Start a new CSV table and return its index
      procedure :: new_table
   end type report_type

contains

   !> Append a terminal line.
   subroutine add_line(self, text)
      !> The report
      class(report_type), intent(inout) :: self
      !> The line
      character(len=*), intent(in) :: text
      type(text_line_type), allocatable :: grown(:)
      if (.not. allocated(self%lines)) allocate (self%lines(64))
      if (self%line_count == size(self%lines)) then
         allocate (grown(2*size(self%lines)))
         grown(:self%line_count) = self%lines(:self%line_count)
         call move_alloc(grown, self%lines)
      end if
      self%line_count = self%line_count + 1
      self%lines(self%line_count)%text = text
   end subroutine add_line

   !> Start a CSV table with a file name and header; returns its index in tables.
   function new_table(self, file_name, header) result(index)
      !> The report
      class(report_type), intent(inout) :: self
      !> File name
      character(len=*), intent(in) :: file_name
      !> Column names, comma separated
      character(len=*), intent(in) :: header
      integer :: index
      type(csv_table_type), allocatable :: grown(:)
      type(csv_table_type) :: table
      table%file_name = file_name
      table%header = header
      allocate (table%rows(64))
      if (.not. allocated(self%tables)) allocate (self%tables(0))
      allocate (grown(size(self%tables) + 1))
      grown(:size(self%tables)) = self%tables
      grown(size(grown)) = table
      call move_alloc(grown, self%tables)
      index = size(self%tables)
   end function new_table

   !> Append a row to a CSV table.
   subroutine add_row(self, row)
      !> The table
      class(csv_table_type), intent(inout) :: self
      !> Comma-separated values
      character(len=*), intent(in) :: row
      type(text_line_type), allocatable :: grown(:)
      if (self%count == size(self%rows)) then
         allocate (grown(2*size(self%rows)))
         grown(:self%count) = self%rows(:self%count)
         call move_alloc(grown, self%rows)
      end if
      self%count = self%count + 1
      self%rows(self%count)%text = row
   end subroutine add_row

   !> A real in scientific notation with `digits` significant digits (e.g. 1.23e-05).
   pure function format_real(x, digits) result(text)
      !> The number
      real(dp), intent(in) :: x
      !> Significant digits (default 3)
      integer, intent(in), optional :: digits
      character(len=:), allocatable :: text
      character(len=40) :: buffer, form
      integer :: d
      d = 3
      if (present(digits)) d = digits
      if (x /= x) then
         text = "nan"
         return
      end if
      write (form, '("(es", i0, ".", i0, "e2)")') d + 7, d - 1
      write (buffer, form) x
      text = trim(adjustl(buffer))
      ! one digit: "1.E+04" reads better as "1E+04"
      if (d == 1) text = text(:index(text, ".") - 1)//text(index(text, ".") + 1:)
   end function format_real

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

end module taylorode_report
