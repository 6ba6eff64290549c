!> Reports: the text lines and CSV tables an experiment produces. Nothing here
!> writes to a terminal or a file.
module app_report
   implicit none
   private

   public :: report_type, csv_table_type, text_line_type

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

end module app_report
