/* fix wall/dashpot and fix wall/dashpot/region: granular walls whose contact forces and torques
 * come from dashpot laws (every family: normal, tangential, rolling, twisting) through the
 * dashpot C ABI, evaluated in batch calls by the contact engine pair_style dashpot uses.
 *
 *   fix ID group wall/dashpot MODELS WALLSTYLE args [wiggle dim A period] [shear dim vshear]
 *       [temperature T|v_name] [contacts] [plugin_dir=DIR] [energy=1] [wall=rigid|particle]
 *   fix ID group wall/dashpot/region MODELS region R [temperature T|v_name] [contacts]
 *       [plugin_dir=DIR] [energy=1] [wall=rigid|particle]
 *
 * MODELS, in any of the three syntaxes of pair_style dashpot:
 *   E nu LAW [key=value ...] [tangential LAW ...] [rolling LAW ...] [twisting LAW ...]
 *       [heat LAW ...]             dashpot's own laws; E, nu the particles' Young's modulus and
 *                                  Poisson's ratio
 *   [granular] NORMAL c... [damping D] [tangential T c...] [rolling R c...] [twisting W c...]
 *       [heat radius k|area h] [limit_damping]
 *                                  fix wall/gran granular's model words (the gran-* laws)
 *   hooke|hooke/history|hertz/history kn kt gamman gammat xmu dampflag [limit_damping]
 *                                  fix wall/gran's classic styles
 * WALLSTYLE: xplane|yplane|zplane lo hi (either NULL), zcylinder radius (axis along z through
 * x = y = 0). The options (plugin_dir=, energy=, wall=) may stand anywhere.
 *
 * The semantics are fix wall/gran's: delta = r_i - distance to the wall; the effective mass is
 * the particle's (a rigid body's with fix rigid); the effective radius r_i on a plane,
 * r_i R_w/(r_i + R_w) on a curved wall (R_w = -2 R inside the cylinder, 2 R outside, and the
 * region's own curvature for a region); the tangential force's torque acts at the radius r_i;
 * the relative velocity is v_i - v_wall at the contact point (wiggle: A w sin(w t) along dim,
 * the wall at lo + A (1 - cos w t); shear: vshear along dim, or, on a zcylinder with dim x or y,
 * the cylinder spins about z with surface speed vshear, clockwise for vshear > 0; a moving or
 * rotating region: the region's velocity at the contact point). `wall=particle` (the default of
 * the granular and classic syntaxes) makes the wall of the particle's own material, as fix
 * wall/gran does (E_eff = E/(2 (1 - nu^2))); `wall=rigid` (the default of dashpot's syntax) a
 * rigid wall (E_eff = E/(1 - nu^2)).
 *
 * Heat (as fix wall/gran's): with a heat law, `temperature` gives the wall's temperature, a
 * number or an equal-style variable v_name evaluated every step; each contact adds the heat
 * flow into the atom to LAMMPS's per-atom heatflow (fix property/atom temperature heatflow),
 * which fix heat/flow integrates. The wall is a reservoir: what it gives is not tallied.
 *
 * History: per atom and wall contact (one for a plane or cylinder; up to the region's maximum
 * number of touching contacts for a region, each keyed by the region's wall id), zeroed when the
 * contact ends, carried with the atoms across ranks and into restart files; the wiggle's phase
 * and a region's motion are kept in restart files too.
 *
 * Outputs: a global vector of 10 (extensive): 1-3 the total force the particles exert on the
 * wall, 4 the number of contacts, and with energy=1 the power the contacts dissipate (5: all
 * families, 6-9: normal, tangential, rolling, twisting) and 10 the elastic energy they store
 * (NaN without energy=1). `contacts`: a per-atom array of 8 as fix wall/gran's (1: the number of
 * contacts, 2-4: the wall's force on the atom, 5-7: the (last) contact point, 8: the radius). */
#ifndef DASHPOT_FIX_WALL_DASHPOT_H
#define DASHPOT_FIX_WALL_DASHPOT_H

#include "fix.h"

#include "dashpot_engine.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class FixWallDashpot : public Fix {
 public:
    FixWallDashpot(class LAMMPS *, int, char **);
    ~FixWallDashpot() override;
    int setmask() override;
    void init() override;
    void setup(int) override;
    void post_force(int) override;
    void reset_dt() override {}
    void write_restart(FILE *) override;
    void restart(char *) override;
    double compute_vector(int) override;

    double memory_usage() override;
    void grow_arrays(int) override;
    void copy_arrays(int, int, int) override;
    void set_arrays(int) override;
    int pack_exchange(int, double *) override;
    int unpack_exchange(int, double *) override;
    int pack_restart(int, double *) override;
    void unpack_restart(int, int) override;
    int size_restart(int) override;
    int maxsize_restart() override;

 protected:
    enum WallStyle { XPLANE = 0, YPLANE = 1, ZPLANE = 2, ZCYLINDER, REGION };
    static constexpr int NVECTOR = 10;

    std::string context;    // "fix wall/dashpot", in messages
    int wallstyle;
    double lo, hi, cylradius;
    std::string idregion;
    int wiggle, wshear, axis;
    double amplitude, period, omega_wiggle, vshear;
    bigint time_origin;
    int contacts_flag, energy_flag;
    double wall_temperature;     // the temperature keyword's number (NaN: none, or a variable)
    std::string temperature_var;    // the temperature keyword's v_name (without v_), or empty
    int temperature_ivar;

    // the laws: one spec, bound per atom type (init)
    std::vector<std::string> plugin_dirs;
    dashpot_lmp::ModelTable models;
    int spec_index;
    int rigid_wall;                       // the wall's material: 1 rigid, 0 the particle's (-1 unset)
    double young, poisson;                // the particles' material
    std::vector<int> model_of_type;       // per type, the bound model
    dashpot_lmp::Layout layout;
    dashpot_lmp::ContactEngine engine;

    // per atom: up to nper contacts, each keyed (a region's wall id; 0 for a plane or cylinder)
    // with its record in `store` at slot i * nper + c
    int nper;
    int nmax_atoms;
    std::vector<int> ncontact, key;
    dashpot_lmp::HistoryStore store;
    int restart_mismatch;    // records of another layout met in a restart file (dropped)

    class Fix *fix_rigid;
    std::vector<double> mass_rigid;

    // outputs of the step: this rank's sums, and their reduction
    double sums[NVECTOR], totals[NVECTOR];
    bigint sums_step;
    int reduced;

    /* The per-atom storage for nper contacts per atom (the region fix sets its own nper). */
    void resize_per_atom(int n, int per);
    /* Binds the laws for every atom type and configures the engine. */
    void bind_models();
    /* The effective mass of atom i against the wall. */
    double mass_of(int i) const;
    /* Updates the rigid-body masses after a neighbour-list build. */
    void update_rigid_masses();
    /* Starts a step: outputs cleared, engine reset, the wall's temperature set. */
    void begin_step();
    /* Stages contact c of atom i: n the unit normal from the wall to the particle, delta the
     * overlap, reff the effective radius, vwall the wall's velocity at the contact point. */
    void stage(int i, int c, const double *n, double delta, double reff, const double *vwall);
    /* Evaluates and applies the staged contacts. */
    void flush();
    /* Whether stored contact c of atom i still acts at overlap delta (an adhesive law's reach
     * keeps a contact beyond touching). */
    bool acts(int i, int c, double delta) const;
    /* Forgets stored contact c of atom i (zeroes its record). */
    void forget(int i, int c);
    /* Moves stored contact `from` of atom i (key and record) to `to`, zeroing `from`. */
    void move_contact(int i, int from, int to);
    /* The largest reach of atom i's stored contacts (0 without an adhesive law). */
    double reach_of(int i) const;

 private:
    void parse(int narg, char **arg);
    size_t parse_models(const std::vector<std::string> &w);
    void init_heat();
    void parse_wall(const std::vector<std::string> &w, size_t at);
};

}    // namespace LAMMPS_NS

#endif
