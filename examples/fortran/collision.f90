! Two-body collisions through the dashpot C ABI from Fortran (iso_c_binding), with this
! program's own velocity-Verlet loop: the Fortran twin of examples/c/collision.c.
!
! Three head-on collisions of two identical MCC spheres (d = 1 cm, rho = 1500 kg/m^3,
! E = 6 GPa, nu = 0.3) at 0.1, 1 and 5 m/s, all forces of a step in one batch call. A collision
! is over when the overlap returns to 0; realized restitution = separation / impact speed.
!
! usage: collision PLUGIN_DIR [LAW] [eps]      (default: hsd 0.54)
! build: gfortran -O2 dashpot.f90 collision.f90 -L target/release -ldashpot_capi
module dashpot_collision_util
  use iso_c_binding
  use dashpot
  implicit none
contains
  ! Stops with the status name and the library's message when a call failed.
  subroutine check(st, what)
    integer(c_int), intent(in) :: st
    character(*), intent(in) :: what
    if (st /= DASHPOT_OK) then
      write (*, '(a, a, a, a, a, a)') what, ' failed: ', c_string(dashpot_status_name(st)), &
        ': ', c_string(dashpot_last_error()), ''
      stop 1
    end if
  end subroutine check
end module dashpot_collision_util

program collision
  use iso_c_binding
  use dashpot
  use dashpot_collision_util
  implicit none
  integer, parameter :: npair = 3
  real(c_double), parameter :: pi = 3.14159265358979323846d0
  character(len=4096) :: dir, law_name, arg
  character(kind=c_char, len=4097), target :: c_dir
  character(kind=c_char, len=4097) :: c_law
  character(kind=c_char, len=4), target :: c_eps_name
  type(c_ptr), target :: dirs(1), pnames(1)
  real(c_double) :: pvalues(1), eps
  type(c_ptr) :: reg, law, bound
  type(dashpot_particle_t), target :: mcc
  type(dashpot_pair_t), target :: pair
  real(c_double) :: x1(npair), x2(npair), v1(npair), v2(npair), f(npair)
  real(c_double) :: delta(npair), rate(npair), realized(npair), v0(npair)
  integer :: state(npair), k, remaining
  integer(c_size_t) :: nlaws, n
  integer(c_long) :: steps
  real(c_double) :: d, mass, tau, dt

  if (command_argument_count() < 1) then
    write (*, '(a)') 'usage: collision PLUGIN_DIR [LAW] [eps]'
    stop 2
  end if
  if (dashpot_abi_version() /= DASHPOT_INTERFACE_ABI_VERSION) then
    write (*, '(a)') 'dashpot library and module disagree on the ABI version'
    stop 2
  end if
  call get_command_argument(1, dir)
  law_name = 'hsd'
  eps = 0.54d0
  if (command_argument_count() >= 2) call get_command_argument(2, law_name)
  if (command_argument_count() >= 3) then
    call get_command_argument(3, arg)
    read (arg, *) eps
  end if

  c_dir = trim(dir)//c_null_char
  c_law = trim(law_name)//c_null_char
  c_eps_name = 'eps'//c_null_char
  dirs(1) = c_loc(c_dir)
  call check(dashpot_registry_open(c_loc(dirs), 1_c_size_t, 0_c_int, reg), 'dashpot_registry_open')
  call check(dashpot_registry_law_count(reg, nlaws), 'dashpot_registry_law_count')
  write (*, '(i0, a)') nlaws, ' laws loaded'

  pnames(1) = c_loc(c_eps_name)
  pvalues(1) = eps
  call check(dashpot_contact_new(reg, c_law, c_loc(pnames), pvalues, 1_c_size_t, law), 'dashpot_contact_new')
  mcc = dashpot_particle_t(0.01d0, 1500d0, 6d9, 0.3d0)
  call check(dashpot_pair_spheres(mcc, mcc, pair), 'dashpot_pair_spheres')
  call check(dashpot_contact_bind(law, pair, bound), 'dashpot_contact_bind')

  d = mcc%diameter
  mass = pi/6d0*mcc%density*d**3
  v0 = [0.1d0, 1d0, 5d0]
  ! Hertz contact time at the fastest impact (Antypov & Elliott eq. 23) bounds the step.
  tau = 2.214d0*(pair%mass**2/(pair%young**2*d*v0(npair)))**0.2d0
  dt = tau/2000d0
  x1 = 0d0
  x2 = d
  v1 = 0.5d0*v0
  v2 = -0.5d0*v0
  f = 0d0
  state = 0
  realized = -1d0
  n = npair
  remaining = npair
  steps = 0
  do while (remaining > 0 .and. steps < 100000000_c_long)
    v1 = v1 - 0.5d0*dt*f/mass
    v2 = v2 + 0.5d0*dt*f/mass
    x1 = x1 + dt*v1
    x2 = x2 + dt*v2
    delta = d - (x2 - x1)
    rate = v1 - v2
    call check(dashpot_contact_force_batch(bound, delta, n, rate, n, f, n), 'dashpot_contact_force_batch')
    v1 = v1 - 0.5d0*dt*f/mass
    v2 = v2 + 0.5d0*dt*f/mass
    do k = 1, npair
      if (state(k) == 0 .and. delta(k) > 0d0) state(k) = 1
      if (state(k) == 1 .and. delta(k) <= 0d0) then
        state(k) = 2
        realized(k) = (v2(k) - v1(k))/v0(k)
        remaining = remaining - 1
      end if
    end do
    steps = steps + 1
  end do
  write (*, '(a, a, a, f8.6, a, es10.3, a, i0, a)') 'law ', trim(law_name), ' eps ', eps, ' dt ', dt, ' s, ', &
    steps, ' steps'
  do k = 1, npair
    write (*, '(a, f6.3, a, f8.6)') 'v0 ', v0(k), ' m/s realized restitution ', realized(k)
  end do
  call dashpot_bound_contact_free(bound)
  call dashpot_contact_free(law)
  call dashpot_registry_free(reg)
end program collision
