! Fortran interfaces (iso_c_binding) to the dashpot C ABI, include/dashpot.h of host/capi.
! Hand-written for the functions the examples use; the C header is the reference for the rest
! (ownership, thread safety, the ABI version rule). Handles are type(c_ptr); statuses are
! integer(c_int) with the values of enum DashpotStatus.
module dashpot
  use iso_c_binding
  implicit none

  ! The ABI version these interfaces describe (DASHPOT_ABI_VERSION of dashpot.h; Fortran names
  ! are case-insensitive, so it cannot share the name of the function dashpot_abi_version).
  integer(c_int32_t), parameter :: DASHPOT_INTERFACE_ABI_VERSION = 1
  integer(c_int), parameter :: DASHPOT_OK = 0, DASHPOT_ERR_NULL_POINTER = 1, DASHPOT_ERR_BAD_LENGTH = 2, &
    DASHPOT_ERR_INVALID_ARGUMENT = 3, DASHPOT_ERR_UNKNOWN_LAW = 4, DASHPOT_ERR_UNKNOWN_PARAMETER = 5, &
    DASHPOT_ERR_INVALID_PARAMETER = 6, DASHPOT_ERR_INVALID_PAIR = 7, DASHPOT_ERR_NON_FINITE = 8, &
    DASHPOT_ERR_PANIC = 9, DASHPOT_ERR_UNSUPPORTED = 10, DASHPOT_ERR_LOAD = 11, DASHPOT_ERR_OTHER = 12

  ! struct DashpotParticle
  type, bind(c) :: dashpot_particle_t
    real(c_double) :: diameter, density, young, poisson
  end type dashpot_particle_t

  ! struct DashpotPair
  type, bind(c) :: dashpot_pair_t
    real(c_double) :: mass, radius, young
  end type dashpot_pair_t

  interface
    function dashpot_abi_version() bind(c, name='dashpot_abi_version')
      import :: c_int32_t
      integer(c_int32_t) :: dashpot_abi_version
    end function

    function dashpot_last_error() bind(c, name='dashpot_last_error')
      import :: c_ptr
      type(c_ptr) :: dashpot_last_error
    end function

    function dashpot_status_name(status) bind(c, name='dashpot_status_name')
      import :: c_ptr, c_int
      integer(c_int), value :: status
      type(c_ptr) :: dashpot_status_name
    end function

    ! dirs: a C array of n_dirs C strings (c_loc of an array of c_ptr)
    function dashpot_registry_open(dirs, n_dirs, use_env, registry) bind(c, name='dashpot_registry_open')
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), value :: dirs
      integer(c_size_t), value :: n_dirs
      integer(c_int), value :: use_env
      type(c_ptr), intent(out) :: registry
      integer(c_int) :: dashpot_registry_open
    end function

    subroutine dashpot_registry_free(registry) bind(c, name='dashpot_registry_free')
      import :: c_ptr
      type(c_ptr), value :: registry
    end subroutine

    function dashpot_registry_law_count(registry, count) bind(c, name='dashpot_registry_law_count')
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), value :: registry
      integer(c_size_t), intent(out) :: count
      integer(c_int) :: dashpot_registry_law_count
    end function

    function dashpot_contact_new(registry, name, param_names, param_values, n_params, law) &
      bind(c, name='dashpot_contact_new')
      import :: c_ptr, c_char, c_double, c_size_t, c_int
      type(c_ptr), value :: registry
      character(kind=c_char), intent(in) :: name(*)
      type(c_ptr), value :: param_names
      real(c_double), intent(in) :: param_values(*)
      integer(c_size_t), value :: n_params
      type(c_ptr), intent(out) :: law
      integer(c_int) :: dashpot_contact_new
    end function

    subroutine dashpot_contact_free(law) bind(c, name='dashpot_contact_free')
      import :: c_ptr
      type(c_ptr), value :: law
    end subroutine

    function dashpot_pair_spheres(a, b, pair) bind(c, name='dashpot_pair_spheres')
      import :: c_int, dashpot_particle_t, dashpot_pair_t
      type(dashpot_particle_t), intent(in) :: a, b
      type(dashpot_pair_t), intent(out) :: pair
      integer(c_int) :: dashpot_pair_spheres
    end function

    function dashpot_contact_bind(law, pair, bound) bind(c, name='dashpot_contact_bind')
      import :: c_ptr, c_int, dashpot_pair_t
      type(c_ptr), value :: law
      type(dashpot_pair_t), intent(in) :: pair
      type(c_ptr), intent(out) :: bound
      integer(c_int) :: dashpot_contact_bind
    end function

    subroutine dashpot_bound_contact_free(bound) bind(c, name='dashpot_bound_contact_free')
      import :: c_ptr
      type(c_ptr), value :: bound
    end subroutine

    function dashpot_contact_force(bound, delta, rate, force) bind(c, name='dashpot_contact_force')
      import :: c_ptr, c_double, c_int
      type(c_ptr), value :: bound
      real(c_double), value :: delta, rate
      real(c_double), intent(out) :: force
      integer(c_int) :: dashpot_contact_force
    end function

    function dashpot_contact_force_batch(bound, delta, n_delta, rate, n_rate, force, n_out) &
      bind(c, name='dashpot_contact_force_batch')
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: bound
      real(c_double), intent(in) :: delta(*), rate(*)
      integer(c_size_t), value :: n_delta, n_rate, n_out
      real(c_double), intent(out) :: force(*)
      integer(c_int) :: dashpot_contact_force_batch
    end function

    function dashpot_c_strlen(s) bind(c, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: dashpot_c_strlen
    end function
  end interface

contains

  ! A Fortran copy of a NUL-terminated C string owned by the library.
  function c_string(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    if (.not. c_associated(p)) then
      s = ''
      return
    end if
    n = int(dashpot_c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate (character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function c_string
end module dashpot
