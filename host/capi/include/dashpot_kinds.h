/*
 * dashpot_kinds.h: the functions every kind of law of the dashpot C ABI has, included at the
 * end of dashpot.h (include dashpot.h, not this file). Written by hand beside the generated
 * dashpot.h; host/capi/tests/header.rs checks that each function declared here is exported.
 */

#ifndef DASHPOT_KINDS_H
#define DASHPOT_KINDS_H

/*
 * The functions every kind of law has, declared once per kind. KIND is contact, tangential,
 * restitution, rolling or twisting; Law and Model its handle types.
 *
 * DASHPOT_LAW_FUNCTIONS(KIND, Law):
 *   dashpot_KIND_new(registry, name, param_names, param_values, n_params, &law) creates law
 *     `name` from `n_params` named values (parameters left out take their defaults; values are
 *     checked against the law's schema). Errors: DASHPOT_ERR_NULL_POINTER,
 *     DASHPOT_ERR_UNKNOWN_LAW (also for a law of another kind; the message lists the laws),
 *     DASHPOT_ERR_UNKNOWN_PARAMETER, DASHPOT_ERR_INVALID_PARAMETER (naming the value and its
 *     valid range), DASHPOT_ERR_PANIC. Inputs are copied; `*out_law` is the caller's and may
 *     outlive the registry. param_names/param_values may be null only if n_params is 0.
 *   dashpot_KIND_free(law) frees it (null is ignored); handles bound from it stay valid.
 *
 * DASHPOT_MODEL_FUNCTIONS(KIND, Law, Model): the sdk 0.2/0.3 binding to a pair of materials
 * (dashpot_materials_spheres, dashpot_materials_wall), whose batch call takes each contact's
 * effective mass, radius and history:
 *   dashpot_KIND_bind_materials(law, materials, &model): every constant that depends only on
 *     the materials and the parameters is computed here, once. Errors:
 *     DASHPOT_ERR_NULL_POINTER, DASHPOT_ERR_INVALID_PAIR (a modulus not finite and > 0),
 *     DASHPOT_ERR_INVALID_PARAMETER (the law rejects these materials), DASHPOT_ERR_PANIC.
 *     `*out_model` is the caller's and may outlive the law.
 *   dashpot_KIND_model_free(model) frees it (null is ignored).
 *   dashpot_KIND_model_history_slots(model, &slots): the number of history values (doubles)
 *     the law keeps per contact (0 for a memoryless law). Errors: DASHPOT_ERR_NULL_POINTER.
 *   dashpot_KIND_model_reads_context(model, &reads) (sdk 0.4): reads = 1 when the law reads
 *     the normal law's context (then compute the contexts with
 *     dashpot_contact_model_force_batch_context and pass them to the law's _context batch);
 *     0 for every law of an older sdk and for contact laws. Errors: DASHPOT_ERR_NULL_POINTER.
 *
 * DASHPOT_PAIR_FUNCTIONS(KIND, Law, Bound): the sdk 0.1 binding to one pair (DashpotPair:
 * effective mass, radius and modulus):
 *   dashpot_KIND_bind(law, pair, &bound). Errors: DASHPOT_ERR_NULL_POINTER,
 *     DASHPOT_ERR_INVALID_PAIR (a field not finite and > 0), DASHPOT_ERR_INVALID_PARAMETER
 *     (the law rejects this pair; a contact law with per-contact history, which a pair binding
 *     has nowhere to keep: bind it to materials), DASHPOT_ERR_PANIC. A contact law takes the
 *     shear modulus of two bodies of Poisson's ratio 0.3 (no normal law of the project uses it).
 *   dashpot_bound_KIND_free(bound) frees it (null is ignored).
 *
 * All are thread-safe except that a *_free must not race with any other use of its handle.
 *
 * DASHPOT_CONTACT_BATCH(NAME, OUTPUTS): the batch call of a contact law bound to materials
 * (sdk 0.2, 0.3), the normal force on n contacts, each with its own geometry and history:
 * out_force[i] = F(delta[i], rate[i]; mass[i], radius[i], history[i*slots .. (i+1)*slots]).
 * delta (m), rate (m/s, > 0 approaching), mass (effective mass m1 m2/(m1 + m2), kg; the
 * particle's mass against a wall), radius (effective radius r1 r2/(r1 + r2), m; the particle's
 * radius against a flat wall) and out_force (N, > 0 repulsive; 0 for delta < 0 unless the law
 * is adhesive) hold n values each; history holds n_history = n x slots values (see
 * dashpot_contact_model_history_slots; null with 0 for a memoryless law), read and updated in
 * place. The caller stores the history: zero at a contact's first touch, passed to every batch
 * call, kept when the step is accepted, dropped when the contact ends; for a trial evaluation
 * (an integrator stage) pass a scratch copy.
 *   dashpot_contact_model_force_batch: OUTPUTS empty.
 *   dashpot_contact_model_force_batch_energy: OUTPUTS DASHPOT_REACH_ENERGY_OUTPUTS, sdk 0.3's
 *     outputs, each null or n values: out_reach[i] how far beyond touching the contact still
 *     acts (m: it ends once delta < -reach; 0 for a non-adhesive law), out_power[i] the
 *     dissipated power (W), out_elastic[i] the stored elastic energy (J); *out_energy_written
 *     (may be null) whether the law reported the energy.
 *   dashpot_contact_model_force_batch_context: OUTPUTS DASHPOT_REACH_ENERGY_CONTEXT_OUTPUTS,
 *     those of _energy (each null or n values) and sdk 0.4's out_context, 3n values (required
 *     when n > 0): out_context[3i..3i+3] = the normal context of contact i, what the contact's
 *     other laws read: its contact radius a (m, >= 0; JKR's own a, positive past touching until
 *     rupture), the force their Coulomb-type caps scale with (N, >= 0; max(F, 0) for most laws)
 *     and the normal damping coefficient (N s/m, >= 0: the law's dissipative force is minus it
 *     times the normal relative velocity). A law of an older sdk, or one that reports none of
 *     its own, gives a = sqrt(radius max(delta, 0)), max(F, 0) and 0. A non-finite or negative
 *     field is refused with DASHPOT_ERR_NON_FINITE.
 * Every input is checked inside the plugin, fused with the computation: a NaN or infinite
 * overlap or rate, or a mass or radius not finite and > 0, is refused with
 * DASHPOT_ERR_NON_FINITE naming the array, the index and the value; so is a non-finite force.
 * Errors: DASHPOT_ERR_NULL_POINTER (the handle, or an array when n > 0), DASHPOT_ERR_BAD_LENGTH
 * (n_history != n x slots), DASHPOT_ERR_NON_FINITE (the outputs and history are then partly
 * written), DASHPOT_ERR_PANIC (the handle stays usable). The arrays stay the caller's.
 * Thread-safe with distinct output and history arrays; outputs must not overlap each other or
 * the inputs.
 *
 * DASHPOT_MOTION_BATCH(NAME, Model, INPUT, OUT, OUTPUTS): the batch call of the tangential
 * (dashpot_tangential_model_force_batch, sdk 0.2; dashpot_tangential_model_force_batch_energy,
 * the same force with the energy outputs), rolling and twisting kinds, on n contacts, the
 * history advanced by the step dt (s). Vectors are x y z triples one after the other (3n values;
 * a 2D code sets z = 0). Per contact i: normal[3i..3i+3] the unit normal (from the partner to
 * the particle); INPUT: tangential, velocity[3i..3i+3] the velocity of the particle's contact
 * point relative to the partner's (m/s, omega x r included; the law uses its part in the
 * tangent plane); rolling, velocity[3i..3i+3] the rolling velocity R_eff (w_i - w_j) x n (m/s);
 * twisting, rate[i] the twisting rate (w_i - w_j).n (rad/s); normal_force[i] (N, > 0 repulsive,
 * from the normal law), delta[i] (m), mass[i] (kg) and radius[i] (m) the effective mass and
 * radius; history, n_history = n x slots values stored by the caller as for a contact batch;
 * OUT: tangential, out_force[3i..3i+3] the force on the particle (N, capped by Coulomb's
 * mu F_n); rolling, out_force[3i..3i+3] the rolling force F_r (N: the torque on the particle is
 * R_eff n x F_r, on the partner its opposite; F_r is not applied to the centres); twisting,
 * out_torque[i] the torque about n on the particle (N m; on the partner its opposite). OUTPUTS
 * empty, or DASHPOT_ENERGY_OUTPUTS (sdk 0.3): out_power[i] the power the contact dissipates
 * (W, >= 0) and out_elastic[i] the elastic energy it stores (J), each null when not wanted;
 * *out_energy_written (may be null) 1 when the law reported them (a law of an older sdk does
 * not). Every input is checked inside the plugin (a non-finite vector, normal force or dt too);
 * errors, ownership and thread safety as for a contact batch.
 *
 * DASHPOT_MOTION_BATCH_CONTEXT(NAME, Model, INPUT, OUT, OUTPUTS): the sdk 0.4 form of the batch
 * calls above (dashpot_tangential_model_force_batch_context,
 * dashpot_rolling_model_force_batch_context, dashpot_twisting_model_torque_batch_context), with
 * the energy outputs and one more input after radius: context, null (every contact gets the
 * default context, as in the calls above) or 3n values, context[3i..3i+3] the normal context of
 * contact i as dashpot_contact_model_force_batch_context wrote it (contact radius m, cap force
 * N, damping N s/m; each finite and >= 0, else DASHPOT_ERR_NON_FINITE naming the contact).
 */
#define DASHPOT_LAW_FUNCTIONS(KIND, Law)                                                             \
    enum DashpotStatus dashpot_##KIND##_new(const struct DashpotRegistry *registry, const char *name, \
                                            const char *const *param_names,                          \
                                            const double *param_values, size_t n_params,             \
                                            struct Law **out_law);                                   \
    void dashpot_##KIND##_free(struct Law *law);

#define DASHPOT_MODEL_FUNCTIONS(KIND, Law, Model)                                                    \
    enum DashpotStatus dashpot_##KIND##_bind_materials(const struct Law *law,                        \
                                                       const struct DashpotMaterials *materials,     \
                                                       struct Model **out_model);                    \
    void dashpot_##KIND##_model_free(struct Model *model);                                           \
    enum DashpotStatus dashpot_##KIND##_model_history_slots(const struct Model *model, size_t *out_slots); \
    enum DashpotStatus dashpot_##KIND##_model_reads_context(const struct Model *model, int *out_reads);

#define DASHPOT_ENERGY_OUTPUTS , double *out_power, double *out_elastic, int *out_energy_written
#define DASHPOT_REACH_ENERGY_OUTPUTS , double *out_reach DASHPOT_ENERGY_OUTPUTS
#define DASHPOT_REACH_ENERGY_CONTEXT_OUTPUTS DASHPOT_REACH_ENERGY_OUTPUTS, double *out_context

#define DASHPOT_CONTACT_BATCH(NAME, OUTPUTS)                                                         \
    enum DashpotStatus NAME(const struct DashpotContactModel *model, size_t n, const double *delta,   \
                            const double *rate, const double *mass, const double *radius,             \
                            double *history, size_t n_history, double *out_force OUTPUTS);

#define DASHPOT_MOTION_BATCH(NAME, Model, INPUT, OUT, OUTPUTS)                                      \
    enum DashpotStatus NAME(const struct Model *model, size_t n, double dt, const double *normal,     \
                            const double *INPUT, const double *normal_force, const double *delta,   \
                            const double *mass, const double *radius, double *history,              \
                            size_t n_history, double *OUT OUTPUTS);

#define DASHPOT_MOTION_BATCH_CONTEXT(NAME, Model, INPUT, OUT, OUTPUTS)                              \
    enum DashpotStatus NAME(const struct Model *model, size_t n, double dt, const double *normal,     \
                            const double *INPUT, const double *normal_force, const double *delta,   \
                            const double *mass, const double *radius, const double *context,        \
                            double *history, size_t n_history, double *OUT OUTPUTS);

#define DASHPOT_PAIR_FUNCTIONS(KIND, Law, Bound)                                                     \
    enum DashpotStatus dashpot_##KIND##_bind(const struct Law *law, const struct DashpotPair *pair,  \
                                             struct Bound **out_bound);                              \
    void dashpot_bound_##KIND##_free(struct Bound *bound);

#ifdef __cplusplus
extern "C" {
#endif

DASHPOT_LAW_FUNCTIONS(contact, DashpotContactLaw)
DASHPOT_LAW_FUNCTIONS(tangential, DashpotTangentialLaw)
DASHPOT_LAW_FUNCTIONS(restitution, DashpotRestitutionLaw)
DASHPOT_LAW_FUNCTIONS(rolling, DashpotRollingLaw)
DASHPOT_LAW_FUNCTIONS(twisting, DashpotTwistingLaw)
DASHPOT_LAW_FUNCTIONS(heat, DashpotHeatLaw)

DASHPOT_MODEL_FUNCTIONS(contact, DashpotContactLaw, DashpotContactModel)
DASHPOT_MODEL_FUNCTIONS(tangential, DashpotTangentialLaw, DashpotTangentialModel)
DASHPOT_MODEL_FUNCTIONS(rolling, DashpotRollingLaw, DashpotRollingModel)
DASHPOT_MODEL_FUNCTIONS(twisting, DashpotTwistingLaw, DashpotTwistingModel)
DASHPOT_MODEL_FUNCTIONS(heat, DashpotHeatLaw, DashpotHeatModel)

DASHPOT_PAIR_FUNCTIONS(contact, DashpotContactLaw, DashpotBoundContact)
DASHPOT_PAIR_FUNCTIONS(restitution, DashpotRestitutionLaw, DashpotBoundRestitution)

DASHPOT_CONTACT_BATCH(dashpot_contact_model_force_batch, )
DASHPOT_CONTACT_BATCH(dashpot_contact_model_force_batch_energy, DASHPOT_REACH_ENERGY_OUTPUTS)
DASHPOT_CONTACT_BATCH(dashpot_contact_model_force_batch_context, DASHPOT_REACH_ENERGY_CONTEXT_OUTPUTS)

DASHPOT_MOTION_BATCH(dashpot_tangential_model_force_batch, DashpotTangentialModel, velocity, out_force, )
DASHPOT_MOTION_BATCH(dashpot_tangential_model_force_batch_energy, DashpotTangentialModel, velocity, out_force,
                     DASHPOT_ENERGY_OUTPUTS)
DASHPOT_MOTION_BATCH(dashpot_rolling_model_force_batch, DashpotRollingModel, velocity, out_force, DASHPOT_ENERGY_OUTPUTS)
DASHPOT_MOTION_BATCH(dashpot_twisting_model_torque_batch, DashpotTwistingModel, rate, out_torque, DASHPOT_ENERGY_OUTPUTS)

DASHPOT_MOTION_BATCH_CONTEXT(dashpot_tangential_model_force_batch_context, DashpotTangentialModel, velocity,
                             out_force, DASHPOT_ENERGY_OUTPUTS)
DASHPOT_MOTION_BATCH_CONTEXT(dashpot_rolling_model_force_batch_context, DashpotRollingModel, velocity, out_force,
                             DASHPOT_ENERGY_OUTPUTS)
DASHPOT_MOTION_BATCH_CONTEXT(dashpot_twisting_model_torque_batch_context, DashpotTwistingModel, rate, out_torque,
                             DASHPOT_ENERGY_OUTPUTS)

#ifdef __cplusplus
}  /* extern "C" */
#endif

#endif  /* DASHPOT_KINDS_H */
