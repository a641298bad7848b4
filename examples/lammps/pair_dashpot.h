/* pair_style dashpot: granular contact forces and torques from dashpot laws of every family
 * (normal, tangential, rolling, twisting) through the dashpot C ABI
 * (host/capi/include/dashpot.h), with all contacts of a step evaluated in batch calls.
 *
 *   pair_style dashpot [LAWS] [plugin_dir=DIR ...] [zplane=Z] [energy=1]
 *   pair_coeff I J [E nu] [LAWS]
 *   LAWS = NORMAL [key=value ...] [tangential T key=value ...] [rolling R ...] [twisting W ...]
 *          [heat H key=value ...]
 *
 * NORMAL is any dashpot contact law (hsd, lsd, kuwabara-kono, thornton, jkr, dmt, a third-party
 * plugin ...), the key=value pairs after it its parameters; after each of the keywords
 * `tangential`, `rolling` and `twisting` come a law of that family and its parameters (`rolling
 * sds` is short for `rolling rolling-sds`). Laws given to pair_style apply to every pair of
 * types whose pair_coeff gives none; pair_coeff I J LAWS gives that pair its own. E and nu are
 * Young's modulus and Poisson's ratio: given with I = J, the material of type I (the one its
 * unset pairs and the wall use); given with I != J, of both sides of that pair. Unset I != J
 * pairs mix I I and J J as pair_style granular does (the same laws; parameters: geometric
 * mean; each side its own material). Per contact the laws run in pair_style granular's order,
 * normal (with its damping) -> tangential -> rolling -> twisting. zplane=Z adds a flat rigid
 * wall at z = Z (particles above it) for the types of this instance. Any consistent units.
 *
 * Heat (sdk 0.4): a heat law (`heat H ...`, or granular's `heat radius k` / `heat area h`)
 * reads each atom's temperature and adds the heat flow into it to its heatflow, LAMMPS's fix
 * property/atom temperature heatflow, as pair_style granular does: Q into the lower-ID atom,
 * -Q into its partner (a ghost's share only with newton on; fix heat/flow sums the ghosts' back
 * and integrates). pair_style's zplane wall conducts no heat.
 *
 * Needs atom_style sphere and comm_modify vel yes. Between neighbour-list builds the history
 * sits in arrays in list order; a history fix of its own per instance (ID DASHPOT_HISTORY, or
 * DASHPOT_HISTORY_k for the k-th dashpot sub-style of pair_style hybrid) carries it with the
 * atoms across exchanges, sorts and restart files, with newton on or off. Restart files also
 * hold pair_style's and pair_coeff's arguments.
 *
 * compute pair/local reads, per pair (single()): p1 the normal force, p2 |F_t|, p3 the power the
 * contact dissipates (all families), p4..p7 that power by family, p8 the elastic energy it
 * stores, p9 |F_roll|, p10 the twisting torque. p3..p8 are the laws' own outputs from the step's
 * batch calls, which energy=1 asks for (NaN without it). When every model is in LAMMPS's
 * syntax (and energy=1 is not given), pair_style granular's columns instead: p1..p3 the
 * tangential force on i, p4 its magnitude, p5..p7 the rolling force, p8 its magnitude, p9 the
 * twisting torque, p10..p12 x_i - x_j. */
#ifndef DASHPOT_PAIR_DASHPOT_H
#define DASHPOT_PAIR_DASHPOT_H

#include "pair.h"

#include "dashpot_engine.h"

#include <string>
#include <vector>

namespace LAMMPS_NS {

class PairDashpot : public Pair {
 public:
    PairDashpot(class LAMMPS *);
    ~PairDashpot() override;
    void compute(int, int) override;
    void settings(int, char **) override;
    void coeff(int, char **) override;
    void init_style() override;
    double init_one(int, int) override;
    double single(int, int, int, int, double, double, double, double &) override;
    void write_restart(FILE *) override;
    void read_restart(FILE *) override;
    void write_restart_settings(FILE *) override;
    void read_restart_settings(FILE *) override;

    /* Copies the history of every current contact, held in neighbour-list order between
     * rebuilds, into the per-atom records of the history fix (which move with the atoms); with
     * newton on, the records of ghost atoms go to their owners (a reverse communication: every
     * rank calls it together). Called by the fix before atoms are exchanged and at a run's end
     * and before a restart file is written. */
    void history_to_atoms();

    /* Lays the history out in the order of the neighbour list just built (from the records the
     * fix holds). Called by the fix after every list build. */
    void layout_slots();

    /* compute(): a touching pair found and not yet staged: atoms i, j, slot k, the distance
     * (first its square) and its inverse (one record per pair: one base address in the loops). */
    struct Candidate {
        int i, j, k;
        double r, rinv;
    };

 private:
    using Family = dashpot_lmp::Family;
    static constexpr int NENERGY = dashpot_lmp::NFAMILY + 1;

    // settings
    std::vector<std::string> settings_args;    // pair_style's arguments, for restart files
    std::vector<std::string> plugin_dirs;
    int default_spec;     // the spec of pair_style's laws, -1: none
    double cutoff_global;    // pair_style dashpot CUTOFF (as pair_style granular's), < 0: none
    int granular_single;     // single() fills pair_style granular's columns
    int wall_flag;
    double wall_z;
    int energy_flag;      // the laws report power and elastic energy, kept per contact for single()
    dashpot_lmp::ModelTable models;

    // per pair of types, as pair_coeff set it (I <= J): the spec (-1: pair_style's), the
    // materials given (coeff_e > 0), the words after I J (restart files)
    int **coeff_spec;
    double **coeff_e, **coeff_nu;
    std::vector<std::vector<std::string>> coeff_words;
    // per pair of types, both orders: the bound model of a contact from type I (the lower tag)
    // to type J, its cutoff; per type, the wall's model (-1: none)
    std::vector<int> model_of, wall_model;
    std::vector<double> key_cut;
    std::vector<double> type_radius;    // per type: the largest radius that can exist
    int freeze_group_bit;

    dashpot_lmp::Layout layout;
    dashpot_lmp::ContactEngine engine;
    dashpot_lmp::EngineFlags engine_flags;
    bool engine_ready;    // configured for the models init_one bound (at the first compute)
    class FixDashpotHistory *fix_history;
    std::string fix_id, dummy_id;

    // Per-contact history in neighbour-list order: record k is the k-th (i, j) pair of the list
    // (ilist order, then jlist order), valid from one list build to the next; the wall's per
    // local atom.
    dashpot_lmp::HistoryStore pair_slots, wall_slots;
    std::vector<int> slot_first;              // per local atom i: the slot of its first list pair
    std::vector<int> slot_atoms;              // the atoms with listed pairs, in list order:
    int nslot_atoms;                          // the first nslot_atoms
    struct SlotPair {
        int i, j;
    };
    std::vector<SlotPair> slot_pairs;         // per slot: its pair's atoms (j without its bits)
    std::vector<double> slot_energy;          // energy=1: per slot, each family's power, the elastic energy
    int nwall_slots;
    bigint slots_ncalls;    // neighbor->ncalls when the slots were laid out (-1: never)
    int slots_nlocal;       // atom->nlocal then
    int dirty;              // a compute advanced the slots since history_to_atoms copied them
    std::vector<Candidate> candidates;    // compute(): the touching pairs not yet staged
    std::vector<int> ended;               // compute(): one block's slots whose contact ended
    std::vector<int> touching;            // compute(), AVX2: one block's touching slots
    bool walked_slots = false;            // compute(): the candidates hold their slots only

    void allocate();
    void apply_settings(const std::vector<std::string> &args);
    void set_coeff(int ilo, int ihi, int jlo, int jhi, const std::vector<std::string> &words);
    int spec_of(int i, int j) const;
    void bind_pair(int i, int j);
    void apply(dashpot_lmp::ContactEngine::Chunk &c, int n, bool wall, bool applied);
    /* Stops with an error: contact k of chunk c reaches past the neighbour cutoff. */
    [[noreturn]] void reach_error(const dashpot_lmp::ContactEngine::Chunk &c, int k);
    void evaluate(dashpot_lmp::HistoryStore &store, bool wall, bool all);
    void stage_pairs(int n) __attribute__((noinline));
    template <bool ONE> void stage_pairs_of(int n);
    template <bool ONE> struct PairGeometry;
    template <bool ONE> void walk_stage_simd(bool hist, bool adh);
    int walk_pairs(const int *atoms, int natoms);
    template <bool ADH, bool HIST> int walk_slots();
    int find_slot(int i, int j) const;
    [[noreturn]] void fail(const std::exception &e, bool all);
};

}    // namespace LAMMPS_NS

#endif
