! Fortran interfaces (iso_c_binding) to the dashpot C ABI, include/dashpot.h of host/capi.
! Every function of the header has its interface here (a test fails when one is missing); the C
! header is the reference for each one's contract (ownership, thread safety, the ABI version
! rule). Handles are type(c_ptr); statuses and enums are integer(c_int) with the values of the
! header's enums. Arrays are passed as assumed-size arrays (a C pointer to the first element);
! vectors of the tangential and rolling batches are real(c_double) :: v(3, n), x y z of contact
! i in v(:, i); history(slots, n) holds contact i's history in history(:, i) (pass a 1-element
! dummy when n_history = 0). The functions every kind of law shares (new, free, binding, history
! width, the energy batch) have one abstract interface each, and one procedure line per kind, as
! the header declares them with one macro line per kind.
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

  ! struct DashpotMaterials (sdk 0.2): effective Young's and Mindlin shear moduli (Pa)
  type, bind(c) :: dashpot_materials_t
    real(c_double) :: young_eff, shear_eff
  end type dashpot_materials_t

  ! enum DashpotLawKind
  integer(c_int), parameter :: DASHPOT_CONTACT = 1, DASHPOT_RESTITUTION = 2, DASHPOT_TANGENTIAL = 3, &
    DASHPOT_ROLLING = 4, DASHPOT_TWISTING = 5
  ! enum DashpotEndCriterion
  integer(c_int), parameter :: DASHPOT_END_NONE = 0, DASHPOT_END_OVERLAP = 1, DASHPOT_END_FORCE = 2

  ! struct DashpotLawInfo (strings: type(c_ptr), read them with c_string)
  type, bind(c) :: dashpot_law_info_t
    type(c_ptr) :: name
    integer(c_int) :: kind
    type(c_ptr) :: summary, doc
    integer(c_size_t) :: n_params
    integer(c_int) :: end_criterion
  end type dashpot_law_info_t

  ! struct DashpotParamInfo
  type, bind(c) :: dashpot_param_info_t
    type(c_ptr) :: name, unit, doc
    integer(c_int) :: has_default
    real(c_double) :: default_value, min, max
    integer(c_int) :: min_inclusive, max_inclusive
  end type dashpot_param_info_t

  ! struct DashpotCalibrationTarget (NaN for an absent contact time or impact speed)
  type, bind(c) :: dashpot_calibration_target_t
    real(c_double) :: restitution, contact_time, impact_speed
    integer(c_int32_t) :: end_criterion
  end type dashpot_calibration_target_t

  ! ---- the shapes every kind of law shares ----
  abstract interface
    ! dashpot_KIND_new: param_names is c_loc of an array of c_ptr (or c_null_ptr with n_params = 0)
    function law_new_i(registry, name, param_names, param_values, n_params, law) bind(c)
      import :: c_ptr, c_char, c_double, c_size_t, c_int
      type(c_ptr), value :: registry
      character(kind=c_char), intent(in) :: name(*)
      type(c_ptr), value :: param_names
      real(c_double), intent(in) :: param_values(*)
      integer(c_size_t), value :: n_params
      type(c_ptr), intent(out) :: law
      integer(c_int) :: law_new_i
    end function

    ! every *_free (null is ignored)
    subroutine handle_free_i(handle) bind(c)
      import :: c_ptr
      type(c_ptr), value :: handle
    end subroutine

    ! dashpot_KIND_bind_materials
    function bind_materials_i(law, materials, model) bind(c)
      import :: c_ptr, c_int, dashpot_materials_t
      type(c_ptr), value :: law
      type(dashpot_materials_t), intent(in) :: materials
      type(c_ptr), intent(out) :: model
      integer(c_int) :: bind_materials_i
    end function

    ! dashpot_KIND_model_history_slots
    function history_slots_i(model, slots) bind(c)
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), intent(out) :: slots
      integer(c_int) :: history_slots_i
    end function

    ! dashpot_KIND_model_reads_context (sdk 0.4): reads = 1 when the law reads the normal
    ! law's context (then pass it the contexts of dashpot_contact_model_force_batch_context)
    function reads_context_i(model, reads) bind(c)
      import :: c_ptr, c_int
      type(c_ptr), value :: model
      integer(c_int), intent(out) :: reads
      integer(c_int) :: reads_context_i
    end function

    ! dashpot_KIND_bind (to a pair)
    function bind_pair_i(law, pair, bound) bind(c)
      import :: c_ptr, c_int, dashpot_pair_t
      type(c_ptr), value :: law
      type(dashpot_pair_t), intent(in) :: pair
      type(c_ptr), intent(out) :: bound
      integer(c_int) :: bind_pair_i
    end function

    ! the sdk 0.3 batch of the tangential (force_batch_energy), rolling and twisting kinds:
    ! normal(3, n); velocity(3, n) (tangential, rolling) or rate(n) (twisting); out(3, n) or
    ! out(n); power(n) and elastic(n) the energy outputs, energy_written 1 when the law wrote them
    function energy_batch_i(model, n, dt, normal, velocity, normal_force, delta, mass, radius, history, &
      n_history, out, power, elastic, energy_written) bind(c)
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), value :: dt
      real(c_double), intent(in) :: normal(*), velocity(*), normal_force(*), delta(*), mass(*), radius(*)
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: out(*), power(*), elastic(*)
      integer(c_int), intent(out) :: energy_written
      integer(c_int) :: energy_batch_i
    end function

    ! the sdk 0.4 form of the batch above, with each contact's normal context context(3, n)
    ! (contact radius, cap force, damping: from dashpot_contact_model_force_batch_context), or
    ! c_null_ptr for the defaults
    function context_batch_i(model, n, dt, normal, velocity, normal_force, delta, mass, radius, context, &
      history, n_history, out, power, elastic, energy_written) bind(c)
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), value :: dt
      real(c_double), intent(in) :: normal(*), velocity(*), normal_force(*), delta(*), mass(*), radius(*)
      type(c_ptr), value :: context
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: out(*), power(*), elastic(*)
      integer(c_int), intent(out) :: energy_written
      integer(c_int) :: context_batch_i
    end function

    ! dashpot_heat_model_heat_batch (sdk 0.4): temperature(2, n) = [T_i, T_j] (K); normal_force,
    ! delta, radius (n); context(3, n) or c_null_ptr; out_heat(n) the heat flow into i (W; give
    ! -out_heat to j), out_conductance(n) (W/K) or c_null_ptr
    function heat_batch_i(model, n, dt, temperature, normal_force, delta, radius, context, history, &
      n_history, out_heat, out_conductance) bind(c)
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), value :: dt
      real(c_double), intent(in) :: temperature(*), normal_force(*), delta(*), radius(*)
      type(c_ptr), value :: context
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: out_heat(*)
      type(c_ptr), value :: out_conductance
      integer(c_int) :: heat_batch_i
    end function
  end interface

  procedure(heat_batch_i), bind(c, name='dashpot_heat_model_heat_batch') :: dashpot_heat_model_heat_batch
  procedure(law_new_i), bind(c, name='dashpot_heat_new') :: dashpot_heat_new
  procedure(handle_free_i), bind(c, name='dashpot_heat_free') :: dashpot_heat_free
  procedure(handle_free_i), bind(c, name='dashpot_heat_model_free') :: dashpot_heat_model_free
  procedure(bind_materials_i), bind(c, name='dashpot_heat_bind_materials') :: dashpot_heat_bind_materials
  procedure(history_slots_i), bind(c, name='dashpot_heat_model_history_slots') :: &
    dashpot_heat_model_history_slots
  procedure(reads_context_i), bind(c, name='dashpot_heat_model_reads_context') :: &
    dashpot_heat_model_reads_context

  procedure(law_new_i), bind(c, name='dashpot_contact_new') :: dashpot_contact_new
  procedure(law_new_i), bind(c, name='dashpot_tangential_new') :: dashpot_tangential_new
  procedure(law_new_i), bind(c, name='dashpot_restitution_new') :: dashpot_restitution_new
  procedure(law_new_i), bind(c, name='dashpot_rolling_new') :: dashpot_rolling_new
  procedure(law_new_i), bind(c, name='dashpot_twisting_new') :: dashpot_twisting_new

  procedure(handle_free_i), bind(c, name='dashpot_registry_free') :: dashpot_registry_free
  procedure(handle_free_i), bind(c, name='dashpot_contact_free') :: dashpot_contact_free
  procedure(handle_free_i), bind(c, name='dashpot_tangential_free') :: dashpot_tangential_free
  procedure(handle_free_i), bind(c, name='dashpot_restitution_free') :: dashpot_restitution_free
  procedure(handle_free_i), bind(c, name='dashpot_rolling_free') :: dashpot_rolling_free
  procedure(handle_free_i), bind(c, name='dashpot_twisting_free') :: dashpot_twisting_free
  procedure(handle_free_i), bind(c, name='dashpot_contact_model_free') :: dashpot_contact_model_free
  procedure(handle_free_i), bind(c, name='dashpot_tangential_model_free') :: dashpot_tangential_model_free
  procedure(handle_free_i), bind(c, name='dashpot_rolling_model_free') :: dashpot_rolling_model_free
  procedure(handle_free_i), bind(c, name='dashpot_twisting_model_free') :: dashpot_twisting_model_free
  procedure(handle_free_i), bind(c, name='dashpot_bound_contact_free') :: dashpot_bound_contact_free
  procedure(handle_free_i), bind(c, name='dashpot_bound_restitution_free') :: dashpot_bound_restitution_free

  procedure(bind_materials_i), bind(c, name='dashpot_contact_bind_materials') :: dashpot_contact_bind_materials
  procedure(bind_materials_i), bind(c, name='dashpot_tangential_bind_materials') :: &
    dashpot_tangential_bind_materials
  procedure(bind_materials_i), bind(c, name='dashpot_rolling_bind_materials') :: dashpot_rolling_bind_materials
  procedure(bind_materials_i), bind(c, name='dashpot_twisting_bind_materials') :: dashpot_twisting_bind_materials

  procedure(history_slots_i), bind(c, name='dashpot_contact_model_history_slots') :: &
    dashpot_contact_model_history_slots
  procedure(history_slots_i), bind(c, name='dashpot_tangential_model_history_slots') :: &
    dashpot_tangential_model_history_slots
  procedure(history_slots_i), bind(c, name='dashpot_rolling_model_history_slots') :: &
    dashpot_rolling_model_history_slots
  procedure(history_slots_i), bind(c, name='dashpot_twisting_model_history_slots') :: &
    dashpot_twisting_model_history_slots

  procedure(reads_context_i), bind(c, name='dashpot_contact_model_reads_context') :: &
    dashpot_contact_model_reads_context
  procedure(reads_context_i), bind(c, name='dashpot_tangential_model_reads_context') :: &
    dashpot_tangential_model_reads_context
  procedure(reads_context_i), bind(c, name='dashpot_rolling_model_reads_context') :: &
    dashpot_rolling_model_reads_context
  procedure(reads_context_i), bind(c, name='dashpot_twisting_model_reads_context') :: &
    dashpot_twisting_model_reads_context

  procedure(bind_pair_i), bind(c, name='dashpot_contact_bind') :: dashpot_contact_bind
  procedure(bind_pair_i), bind(c, name='dashpot_restitution_bind') :: dashpot_restitution_bind

  procedure(energy_batch_i), bind(c, name='dashpot_tangential_model_force_batch_energy') :: &
    dashpot_tangential_model_force_batch_energy
  procedure(energy_batch_i), bind(c, name='dashpot_rolling_model_force_batch') :: dashpot_rolling_model_force_batch
  procedure(energy_batch_i), bind(c, name='dashpot_twisting_model_torque_batch') :: dashpot_twisting_model_torque_batch
  procedure(context_batch_i), bind(c, name='dashpot_tangential_model_force_batch_context') :: &
    dashpot_tangential_model_force_batch_context
  procedure(context_batch_i), bind(c, name='dashpot_rolling_model_force_batch_context') :: &
    dashpot_rolling_model_force_batch_context
  procedure(context_batch_i), bind(c, name='dashpot_twisting_model_torque_batch_context') :: &
    dashpot_twisting_model_torque_batch_context

  ! ---- the functions of one kind each ----
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

    function dashpot_registry_law_count(registry, count) bind(c, name='dashpot_registry_law_count')
      import :: c_ptr, c_size_t, c_int
      type(c_ptr), value :: registry
      integer(c_size_t), intent(out) :: count
      integer(c_int) :: dashpot_registry_law_count
    end function

    function dashpot_pair_spheres(a, b, pair) bind(c, name='dashpot_pair_spheres')
      import :: c_int, dashpot_particle_t, dashpot_pair_t
      type(dashpot_particle_t), intent(in) :: a, b
      type(dashpot_pair_t), intent(out) :: pair
      integer(c_int) :: dashpot_pair_spheres
    end function

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

    function dashpot_version() bind(c, name='dashpot_version')
      import :: c_ptr
      type(c_ptr) :: dashpot_version
    end function

    function dashpot_registry_find(registry, name, index) bind(c, name='dashpot_registry_find')
      import :: c_ptr, c_char, c_size_t, c_int
      type(c_ptr), value :: registry
      character(kind=c_char), intent(in) :: name(*)
      integer(c_size_t), intent(out) :: index
      integer(c_int) :: dashpot_registry_find
    end function

    function dashpot_registry_law_info(registry, index, info) bind(c, name='dashpot_registry_law_info')
      import :: c_ptr, c_size_t, c_int, dashpot_law_info_t
      type(c_ptr), value :: registry
      integer(c_size_t), value :: index
      type(dashpot_law_info_t), intent(out) :: info
      integer(c_int) :: dashpot_registry_law_info
    end function

    function dashpot_registry_param_info(registry, law, param, info) bind(c, name='dashpot_registry_param_info')
      import :: c_ptr, c_size_t, c_int, dashpot_param_info_t
      type(c_ptr), value :: registry
      integer(c_size_t), value :: law, param
      type(dashpot_param_info_t), intent(out) :: info
      integer(c_int) :: dashpot_registry_param_info
    end function

    function dashpot_pair_wall(a, pair) bind(c, name='dashpot_pair_wall')
      import :: c_int, dashpot_particle_t, dashpot_pair_t
      type(dashpot_particle_t), intent(in) :: a
      type(dashpot_pair_t), intent(out) :: pair
      integer(c_int) :: dashpot_pair_wall
    end function

    function dashpot_pair_from_masses(diameter1, mass1, young1, poisson1, diameter2, mass2, young2, poisson2, pair) &
      bind(c, name='dashpot_pair_from_masses')
      import :: c_double, c_int, dashpot_pair_t
      real(c_double), value :: diameter1, mass1, young1, poisson1, diameter2, mass2, young2, poisson2
      type(dashpot_pair_t), intent(out) :: pair
      integer(c_int) :: dashpot_pair_from_masses
    end function

    function dashpot_pair_wall_from_mass(diameter, mass, young, poisson, pair) &
      bind(c, name='dashpot_pair_wall_from_mass')
      import :: c_double, c_int, dashpot_pair_t
      real(c_double), value :: diameter, mass, young, poisson
      type(dashpot_pair_t), intent(out) :: pair
      integer(c_int) :: dashpot_pair_wall_from_mass
    end function

    function dashpot_contact_coefficient(bound, name, value) bind(c, name='dashpot_contact_coefficient')
      import :: c_ptr, c_char, c_double, c_int
      type(c_ptr), value :: bound
      character(kind=c_char), intent(in) :: name(*)
      real(c_double), intent(out) :: value
      integer(c_int) :: dashpot_contact_coefficient
    end function

    function dashpot_restitution_eval(bound, speed, restitution) bind(c, name='dashpot_restitution_eval')
      import :: c_ptr, c_double, c_int
      type(c_ptr), value :: bound
      real(c_double), value :: speed
      real(c_double), intent(out) :: restitution
      integer(c_int) :: dashpot_restitution_eval
    end function

    function dashpot_restitution_batch(bound, speed, n_speed, restitution, n_out) &
      bind(c, name='dashpot_restitution_batch')
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: bound
      real(c_double), intent(in) :: speed(*)
      integer(c_size_t), value :: n_speed, n_out
      real(c_double), intent(out) :: restitution(*)
      integer(c_int) :: dashpot_restitution_batch
    end function

    ! fixed_names: c_loc of an array of c_ptr (or c_null_ptr with n_fixed = 0)
    function dashpot_calibrate(registry, name, target, pair, fixed_names, fixed_values, n_fixed, &
      values, n_out, n_set) bind(c, name='dashpot_calibrate')
      import :: c_ptr, c_char, c_double, c_size_t, c_int, dashpot_calibration_target_t, dashpot_pair_t
      type(c_ptr), value :: registry
      character(kind=c_char), intent(in) :: name(*)
      type(dashpot_calibration_target_t), intent(in) :: target
      type(dashpot_pair_t), intent(in) :: pair
      type(c_ptr), value :: fixed_names
      real(c_double), intent(in) :: fixed_values(*)
      integer(c_size_t), value :: n_fixed, n_out
      real(c_double), intent(out) :: values(*)
      integer(c_size_t), intent(out) :: n_set
      integer(c_int) :: dashpot_calibrate
    end function

    ! ---- sdk 0.2: materials, per-contact geometry and history, tangential laws ----

    function dashpot_materials_spheres(young1, poisson1, young2, poisson2, materials) &
      bind(c, name='dashpot_materials_spheres')
      import :: c_double, c_int, dashpot_materials_t
      real(c_double), value :: young1, poisson1, young2, poisson2
      type(dashpot_materials_t), intent(out) :: materials
      integer(c_int) :: dashpot_materials_spheres
    end function

    function dashpot_materials_wall(young, poisson, materials) bind(c, name='dashpot_materials_wall')
      import :: c_double, c_int, dashpot_materials_t
      real(c_double), value :: young, poisson
      type(dashpot_materials_t), intent(out) :: materials
      integer(c_int) :: dashpot_materials_wall
    end function

    ! history(slots, n): contact i's history in history(:, i); pass a 1-element dummy when n_history = 0
    function dashpot_contact_model_force_batch(model, n, delta, rate, mass, radius, history, n_history, force) &
      bind(c, name='dashpot_contact_model_force_batch')
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), intent(in) :: delta(*), rate(*), mass(*), radius(*)
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: force(*)
      integer(c_int) :: dashpot_contact_model_force_batch
    end function

    ! normal(3, n), velocity(3, n), force(3, n); history(slots, n)
    function dashpot_tangential_model_force_batch(model, n, dt, normal, velocity, normal_force, delta, mass, radius, &
      history, n_history, force) bind(c, name='dashpot_tangential_model_force_batch')
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), value :: dt
      real(c_double), intent(in) :: normal(*), velocity(*), normal_force(*), delta(*), mass(*), radius(*)
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: force(*)
      integer(c_int) :: dashpot_tangential_model_force_batch
    end function

    function dashpot_contact_model_force_batch_energy(model, n, delta, rate, mass, radius, history, n_history, &
      force, reach, power, elastic, energy_written) bind(c, name='dashpot_contact_model_force_batch_energy')
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), intent(in) :: delta(*), rate(*), mass(*), radius(*)
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: force(*), reach(*), power(*), elastic(*)
      integer(c_int), intent(out) :: energy_written
      integer(c_int) :: dashpot_contact_model_force_batch_energy
    end function

    ! the sdk 0.4 form: also each contact's normal context, context(3, n) (contact radius, cap
    ! force, damping), for the laws of the contact that read it
    function dashpot_contact_model_force_batch_context(model, n, delta, rate, mass, radius, history, n_history, &
      force, reach, power, elastic, energy_written, context) bind(c, name='dashpot_contact_model_force_batch_context')
      import :: c_ptr, c_double, c_size_t, c_int
      type(c_ptr), value :: model
      integer(c_size_t), value :: n, n_history
      real(c_double), intent(in) :: delta(*), rate(*), mass(*), radius(*)
      real(c_double), intent(inout) :: history(*)
      real(c_double), intent(out) :: force(*), reach(*), power(*), elastic(*), context(*)
      integer(c_int), intent(out) :: energy_written
      integer(c_int) :: dashpot_contact_model_force_batch_context
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
