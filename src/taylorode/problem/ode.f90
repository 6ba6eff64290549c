!> The problem a user solves: U' = f(t, U) + g(t, U), f non-stiff, g stiff.
!>
!> Users extend `ode_problem` (and write f, g and both Jacobians) or
!> `ode_problem_fd` (and write only f and g: the Jacobians come from finite
!> differences). Parameters of a problem are components of the extended type.
module taylorode_problem_ode
   use taylorode_base_kinds, only: dp
   use taylorode_linalg_matrix, only: matrix_structure_type, dense_structure, storage_band
   implicit none
   private

   public :: ode_problem, ode_problem_fd, rhs_interface, jacobian_interface

   !> Abstract problem with a non-stiff part f, a stiff part g and their Jacobians
   type, abstract :: ode_problem
   contains
      !> Non-stiff part f(t, U)
      procedure(rhs_interface), deferred :: f
      !> Stiff part g(t, U)
      procedure(rhs_interface), deferred :: g
      !> Jacobian df/dU
      procedure(jacobian_interface), deferred :: jac_f
      !> Jacobian dg/dU
      procedure(jacobian_interface), deferred :: jac_g
      !> Where the nonzeros of df/dU and dg/dU together can be (default: dense);
      !> a banded problem returns band_structure(lower, upper)
      procedure :: jacobian_structure
      !> Bandwidths of the declared structure (-1, -1 when dense); declare a band
      !> through `jacobian_structure`, this binding cannot be overridden
      procedure, non_overridable :: bandwidths
      !> df/dU in LAPACK band storage (default: grouped forward differences of f)
      procedure :: jac_f_band
      !> dg/dU in LAPACK band storage (default: grouped forward differences of g)
      procedure :: jac_g_band
   end type ode_problem

   !> Problem whose Jacobians are approximated by forward differences of f and g
   type, abstract, extends(ode_problem) :: ode_problem_fd
   contains
      !> Forward-difference approximation of df/dU
      procedure :: jac_f => fd_jac_f
      !> Forward-difference approximation of dg/dU
      procedure :: jac_g => fd_jac_g
   end type ode_problem_fd

   abstract interface
      !> Right-hand side part: writes f(t, u) or g(t, u) into `dudt`
      subroutine rhs_interface(self, t, u, dudt)
         import :: ode_problem, dp
         !> The problem (carries its parameters)
         class(ode_problem), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> Value of the part at (t, u), same size as u
         real(dp), intent(out) :: dudt(:)
      end subroutine rhs_interface

      !> Jacobian of a part: writes d(part)/dU at (t, u) into `jac` (n x n, jac(i, j) = d part_i / d u_j)
      subroutine jacobian_interface(self, t, u, jac)
         import :: ode_problem, dp
         !> The problem
         class(ode_problem), intent(inout) :: self
         !> Time
         real(dp), intent(in) :: t
         !> State
         real(dp), intent(in) :: u(:)
         !> Jacobian matrix, size(u) x size(u)
         real(dp), intent(out) :: jac(:, :)
      end subroutine jacobian_interface
   end interface

contains

   !> Structure of df/dU and dg/dU together for a system of size n: dense unless a
   !> problem overrides it. A banded problem (J(i, j) = 0 for i - j > lower or
   !> j - i > upper) returns band_structure(lower, upper); its Newton systems are then
   !> solved in band storage and its Jacobians come from `jac_f_band` and `jac_g_band`
   !> (the dense `jac_f` and `jac_g` are not called).
   function jacobian_structure(self, n) result(structure)
      !> The problem
      class(ode_problem), intent(in) :: self
      !> Number of unknowns
      integer, intent(in) :: n
      type(matrix_structure_type) :: structure
      structure = dense_structure()
   end function jacobian_structure

   !> Lower and upper bandwidths of the declared Jacobian structure, -1 and -1 when
   !> it is dense.
   subroutine bandwidths(self, n, lower, upper)
      !> The problem
      class(ode_problem), intent(in) :: self
      !> Number of unknowns
      integer, intent(in) :: n
      !> Lower and upper bandwidths, -1 for dense
      integer, intent(out) :: lower, upper
      type(matrix_structure_type) :: structure
      structure = self%jacobian_structure(n)
      lower = -1
      upper = -1
      if (structure%storage == storage_band) then
         lower = structure%lower
         upper = structure%upper
      end if
   end subroutine bandwidths

   !> df/dU in LAPACK band storage, band(upper + 1 + i - j, j) = df_i/du_j, by
   !> forward differences on groups of columns lower + upper + 1 apart (one f
   !> evaluation per group). Banded problems with analytic Jacobians override it.
   subroutine jac_f_band(self, t, u, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      call band_forward_difference(self, .true., t, u, band)
   end subroutine jac_f_band

   !> dg/dU in LAPACK band storage (see jac_f_band).
   subroutine jac_g_band(self, t, u, band)
      !> The problem
      class(ode_problem), intent(inout) :: self
      !> Time
      real(dp), intent(in) :: t
      !> State
      real(dp), intent(in) :: u(:)
      !> Band storage, (lower + upper + 1) x size(u)
      real(dp), intent(out) :: band(:, :)
      call band_forward_difference(self, .false., t, u, band)
   end subroutine jac_g_band

   !> Grouped forward differences of f (`of_f`) or g into band storage.
   subroutine band_forward_difference(self, of_f, t, u, band)
      class(ode_problem), intent(inout) :: self
      logical, intent(in) :: of_f
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: band(:, :)
      real(dp), allocatable :: base(:), shifted(:), probe(:), increment(:)
      integer :: lower, upper, width, group, i, j, n

      n = size(u)
      call self%bandwidths(n, lower, upper)
      width = lower + upper + 1
      allocate (base(n), shifted(n), probe(n), increment(n))
      band = 0.0_dp
      call evaluate_part(self, of_f, t, u, base)
      do group = 1, min(width, n)
         probe = u
         do j = group, n, width
            increment(j) = sqrt(epsilon(1.0_dp))*max(abs(u(j)), 1.0_dp)
            probe(j) = u(j) + increment(j)
            increment(j) = probe(j) - u(j)
         end do
         call evaluate_part(self, of_f, t, probe, shifted)
         do j = group, n, width
            do i = max(1, j - upper), min(n, j + lower)
               band(upper + 1 + i - j, j) = (shifted(i) - base(i))/increment(j)
            end do
         end do
      end do
   end subroutine band_forward_difference

   !> Forward-difference Jacobian of f.
   subroutine fd_jac_f(self, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call forward_difference(self, .true., t, u, jac)
   end subroutine fd_jac_f

   !> Forward-difference Jacobian of g.
   subroutine fd_jac_g(self, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      call forward_difference(self, .false., t, u, jac)
   end subroutine fd_jac_g

   !> Column-by-column forward differences of f (`of_f`) or g, with the
   !> increment sqrt(eps) * max(|u_j|, 1) that balances truncation and roundoff.
   subroutine forward_difference(self, of_f, t, u, jac)
      class(ode_problem_fd), intent(inout) :: self
      logical, intent(in) :: of_f
      real(dp), intent(in) :: t
      real(dp), intent(in) :: u(:)
      real(dp), intent(out) :: jac(:, :)
      real(dp) :: base(size(u)), shifted(size(u)), probe(size(u))
      real(dp) :: increment
      integer :: j
      call evaluate_part(self, of_f, t, u, base)
      probe = u
      do j = 1, size(u)
         increment = sqrt(epsilon(1.0_dp))*max(abs(u(j)), 1.0_dp)
         probe(j) = u(j) + increment
         increment = probe(j) - u(j)
         call evaluate_part(self, of_f, t, probe, shifted)
         jac(:, j) = (shifted - base)/increment
         probe(j) = u(j)
      end do
   end subroutine forward_difference

   !> f(t, state) when `of_f`, else g(t, state).
   subroutine evaluate_part(problem, of_f, t, state, value)
      class(ode_problem), intent(inout) :: problem
      logical, intent(in) :: of_f
      real(dp), intent(in) :: t
      real(dp), intent(in) :: state(:)
      real(dp), intent(out) :: value(:)
      if (of_f) then
         call problem%f(t, state, value)
      else
         call problem%g(t, state, value)
      end if
   end subroutine evaluate_part

end module taylorode_problem_ode
