/* pair_style dashpot: granular contact forces and torques from dashpot laws of every family
 * (normal, tangential, rolling, twisting) through the dashpot C ABI
 * (host/capi/include/dashpot.h), with all contacts of a step evaluated in batch calls.
 *
 *   pair_style dashpot NORMAL [key=value ...] [tangential T key=value ...]
 *                      [rolling R key=value ...] [twisting W key=value ...]
 *                      [plugin_dir=DIR ...] [zplane=Z] [energy=1]
 *   pair_coeff I J E nu
 *
 * NORMAL is any dashpot contact law (hsd, lsd, kuwabara-kono, thornton, jkr, dmt, a third-party
 * plugin ...), the key=value pairs after it its parameters; after each of the keywords
 * `tangential`, `rolling` and `twisting` come a law of that family and its parameters (`rolling
 * sds` is short for `rolling rolling-sds`, `twisting marshall` for `twisting twisting-marshall`).
 * Per contact the laws run in LAMMPS pair granular's order, normal (with its damping) →
 * tangential → rolling → twisting, each later family seeing the normal force. Plugins are
 * searched in the plugin_dir directories, then in $DASHPOT_PLUGIN_PATH. zplane=Z adds a flat
 * rigid wall at z = Z (particles above it) under the same laws. pair_coeff gives Young's
 * modulus (Pa) and Poisson's ratio of the particles of types I and J; unset I != J pairs combine
 * the materials of I I and J J. Laws are bound once per pair of materials; each contact's
 * effective mass and radius go with the batch call, so any size distribution works.
 *
 * An adhesive normal law (one whose contacts reach beyond touching, such as jkr) keeps a
 * contact while the overlap is at least minus the reach its last call reported; the neighbour
 * and ghost cutoffs cover 1.5 times the reach probed at the largest radii, and a contact that
 * reaches further stops the run with a message.
 *
 * Needs atom_style sphere (radius, rmass, omega, torque), SI units and comm_modify vel yes.
 * Laws with per-contact history (any tangential, rolling or twisting law, a plastic or adhesive
 * normal law) also need `newton off`: each rank then computes every contact of its own atoms.
 * Between neighbour-list builds the history sits in arrays in list order; fix DASHPOT/HISTORY
 * (created by the pair style) carries it with the atoms across exchanges, sorts and restart
 * files. Restart files also hold pair_style's arguments and pair_coeff's moduli.
 *
 * compute pair/local reads, per pair (single()): p1 the normal force (N), p2 |F_t| (N), p3 the
 * power the contact dissipates (W, all families), p4..p7 that power by family (normal,
 * tangential, rolling, twisting), p8 the elastic energy it stores (J), p9 |F_roll| (N), p10 the
 * twisting torque (N m). p3..p8 are the laws' own energy outputs from the step's batch calls,
 * which energy=1 asks for (NaN without it). */
#ifndef DASHPOT_PAIR_DASHPOT_H
#define DASHPOT_PAIR_DASHPOT_H

#include "pair.h"

#include "dashpot.h"

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
     * rebuilds, into the per-atom records of fix DASHPOT/HISTORY (which move with the atoms).
     * Called by the fix before atoms are exchanged, sorted or written to a restart file. */
    void history_to_atoms();

    /* The families of laws, in the order they run on a contact. */
    enum Family { NORMAL = 0, TANGENTIAL = 1, ROLLING = 2, TWISTING = 3, NFAMILY = 4 };

 private:
    std::vector<std::string> settings_args;    // pair_style's arguments, for restart files
    std::string law_name[NFAMILY];             // empty: the family is absent
    DashpotRegistry *registry;
    DashpotContactLaw *law;
    DashpotTangentialLaw *tlaw;
    DashpotRollingLaw *rlaw;
    DashpotTwistingLaw *wlaw;
    int wall_flag;
    double wall_z;
    int energy_flag;    // the laws report power and elastic energy, kept per contact for single()
    double **young, **poisson;    // per type pair, the material of the I particle ...
    double **young2, **poisson2;  // ... and of the J particle
    std::vector<double> type_radius;    // per type: the largest radius that can exist
    // bound models, per type pair (ntypes+1)^2 then per type against the wall
    std::vector<DashpotContactModel *> cmodel;
    std::vector<DashpotTangentialModel *> tmodel;
    std::vector<DashpotRollingModel *> rmodel;
    std::vector<DashpotTwistingModel *> wmodel;
    std::vector<double> key_cut;    // per pair kind: the interaction cutoff (m)

    // A contact's history record: each family's slots, then (adhesive laws) the reach of its
    // last normal-law call (m), which keeps the contact beyond touching.
    int nslots[NFAMILY], offset[NFAMILY];
    int adhesive, reach_at;    // reach_at: the reach's index in a record
    int nvalues;               // the record's length
    class FixDashpotHistory *fix_history;

    // Per-contact history in neighbour-list order: slot k is the k-th (i, j) pair of the list
    // (ilist order, then jlist order), valid from one list build to the next; the wall's per
    // local atom. One array per family, so that each law reads and writes a run of consecutive
    // slots in place; `touched` is 1 when the slot's history may be non-zero (the contact was
    // evaluated since it was zeroed). A contact's record (fix DASHPOT/HISTORY, restart files)
    // is the families' values in order, then the reach.
 public:
    struct Slots {
        std::vector<double> fam[NFAMILY];    // slot k's values at k * nslots[f]
        std::vector<double> reach;           // an adhesive law's reach after its last call (m)
        std::vector<unsigned char> touched;
        void assign(size_t n, const int *ns, bool adhesive);    // n zeroed slots
        void zero(size_t k, const int *ns);                     // slot k's contact ended
        void get(size_t k, const int *ns, double *record) const;
        void set(size_t k, const int *ns, const double *record);
    };

 private:
    Slots pair_slots, wall_slots;
    Slots carry_pairs, carry_wall;    // the last layout's, while the next is laid out
    std::vector<int> slot_i, slot_j;          // the pair's local indices, for history_to_atoms
    std::vector<tagint> slot_ti, slot_tj;     // and tags (indices may be reused by then)
    std::vector<int> slot_first;              // per local atom i: the slot of its first list pair
    // energy=1: per slot, the step's power of each family (W) and the elastic energy stored (J)
    static constexpr int NENERGY = NFAMILY + 1;
    std::vector<double> slot_energy;
    std::vector<tagint> wall_tag;
    int nwall_slots;
    bigint slots_ncalls;    // neighbor->ncalls when the slots were laid out (-1: never)
    int slots_nlocal;       // atom->nlocal then
    // the last layout's contacts by local atom, for the next layout when no atom has moved:
    // atom i's partners' tags and slots at carry_first[i] .. carry_first[i + 1] - 1
    std::vector<int> carry_first, carry_slot, carry_next;
    std::vector<tagint> carry_tag;
    std::vector<unsigned char> carry_keep;

    // Contacts are staged a chunk at a time in structure-of-arrays columns sized to stay in
    // cache, then evaluated by one batch call per family and kind of pair (bound model)
    // present in the chunk.
 public:
    struct Chunk {
        int *a = nullptr, *b = nullptr;    // a = the atom of the lower tag; b < 0: the wall
        int *slot = nullptr, *key = nullptr;    // history slot (list order, or the atom for the wall); kind
        double *delta = nullptr, *rate = nullptr, *mass = nullptr, *rad = nullptr, *fn = nullptr;
        double *norm = nullptr, *vel = nullptr, *ft = nullptr;
        double *vroll = nullptr, *froll = nullptr;    // rolling velocity R (w_a - w_b) x n, force
        double *twist = nullptr, *mtwist = nullptr;   // twisting rate (w_a - w_b).n, torque
        double *reach = nullptr;                      // the normal law's reach (adhesive laws)
        double *hist[NFAMILY] = {nullptr, nullptr, nullptr, nullptr};    // each family's history
        double *power[NFAMILY] = {nullptr, nullptr, nullptr, nullptr};   // energy=1: W
        double *elastic[NFAMILY] = {nullptr, nullptr, nullptr, nullptr}; // energy=1: J
        std::vector<int> istore;
        std::vector<double> dstore;
        void reserve(const int *nslots, bool rolling, bool twisting, bool adhesive, bool energy);    // once
    };

 private:
    Chunk stage, sorted;    // as gathered; by kind of pair when a chunk mixes kinds
    std::vector<int> key_count, key_next, sort_place;

    void allocate();
    void free_models();
    void free_laws();
    void create_laws(const std::vector<std::string> (&names)[NFAMILY],
                     const std::vector<double> (&values)[NFAMILY], const std::vector<std::string> &dirs);
    void probe_laws();
    template <typename Law, typename Model>
    int slots_of(const Law *l, DashpotStatus (*bind)(const Law *, const DashpotMaterials *, Model **),
                 DashpotStatus (*count)(const Model *, size_t *), void (*release)(Model *), const char *family);
    double probe_reach(DashpotContactModel *m, double radius);
    int key_of(int itype, int jtype) const;
    void bind_key(int key, double e1, double nu1, double e2, double nu2, bool wall);
    void layout_slots();
    void index_slots();
    int carried_slot(int i, tagint partner) const;
    template <int NS, int NT, int NR> void compute_t();
    template <int NS, int NT, int NR> void evaluate(int n, bool mixed, bool wall);
    template <int NS, int NT, int NR> void scatter(Chunk &c, int n, Slots *slots, const double *reach);
    template <int NS, int NT, int NR> void gather(int n, const Slots &slots);
    void sort_chunk(int n);
    void run_laws(Chunk &c, int lo, int m, int key, double *const *hist, double *reach);
    const double *stored_energy(int i, int j) const;
    void check(int status, const char *what);
    void apply_settings(const std::vector<std::string> &args);
};

}    // namespace LAMMPS_NS

#endif
