!> The files a run of the app writes: the step history where the user names it
!> and the other CSV tables in the --out directory, never overwriting an existing
!> file without --force. Only files the user asked for are touched.
module app_outputs
   use taylorode, only: status_type, status_ok, status_invalid_argument
   use taylorode_base_status, only: set_status
   use app_cli, only: cli_request_type
   use app_report, only: report_type
   implicit none
   private

   public :: check_outputs, write_outputs, table_destination

contains

   !> Before a run: refuse a step-history file that exists unless --force.
   subroutine check_outputs(request, stat)
      !> The parsed command line
      type(cli_request_type), intent(in) :: request
      !> status_invalid_argument when a file would be overwritten
      type(status_type), intent(out) :: stat
      logical :: exists
      if (allocated(request%history_file)) then
         inquire (file=request%history_file, exist=exists)
         if (exists .and. .not. request%force) then
            call set_status(stat, status_invalid_argument, request%history_file// &
               " exists; use --force to overwrite it")
         end if
      end if
   end subroutine check_outputs

   !> Where a table goes: the history file as named, the others into --out, "" for none.
   function table_destination(request, file_name) result(path)
      !> The parsed command line
      type(cli_request_type), intent(in) :: request
      !> The table's file name
      character(len=*), intent(in) :: file_name
      character(len=:), allocatable :: path
      path = ""
      if (allocated(request%history_file)) then
         if (file_name == request%history_file) then
            path = file_name
            return
         end if
      end if
      if (allocated(request%out_dir)) path = request%out_dir//"/"//file_name
   end function table_destination

   !> After a run: write the report's tables that were asked for and add a
   !> "wrote PATH" line for each; an existing file is kept unless --force, and stat
   !> reports the first file that could not be written.
   subroutine write_outputs(request, report, stat)
      !> The parsed command line
      type(cli_request_type), intent(in) :: request
      !> The run's report
      type(report_type), intent(inout) :: report
      !> status_invalid_argument for a file kept or not writable
      type(status_type), intent(out) :: stat
      integer :: t, r, unit, io
      logical :: exists
      character(len=:), allocatable :: path

      if (.not. allocated(report%tables)) return
      do t = 1, size(report%tables)
         path = table_destination(request, report%tables(t)%file_name)
         if (len(path) == 0) cycle
         inquire (file=path, exist=exists)
         if (exists .and. .not. request%force) then
            if (stat%code == status_ok) call set_status(stat, status_invalid_argument, path// &
               " exists; not overwritten (use --force)")
            cycle
         end if
         open (newunit=unit, file=path, status="replace", action="write", iostat=io)
         if (io /= 0) then
            if (stat%code == status_ok) call set_status(stat, status_invalid_argument, "cannot write "//path)
            cycle
         end if
         write (unit, '(a)') report%tables(t)%header
         do r = 1, report%tables(t)%count
            write (unit, '(a)') report%tables(t)%rows(r)%text
         end do
         close (unit)
         call report%add_line("wrote "//path)
      end do
   end subroutine write_outputs

end module app_outputs
