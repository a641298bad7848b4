/* pair_style dashpot: granular contact forces from any dashpot normal law and, optionally, any
 * dashpot tangential law, through the dashpot C ABI (host/capi/include/dashpot.h), with all
 * contacts of a step evaluated in batch calls.
 *
 *   pair_style dashpot NORMAL [key=value ...] [tangential TANGENTIAL key=value ...]
 *                      [plugin_dir=DIR ...] [zplane=Z]
 *   pair_coeff I J E nu
 *
 * NORMAL is any dashpot contact law (hsd, lsd, kuwabara-kono, thornton, a third-party plugin
 * ...), the key=value pairs after it its parameters; after the keyword `tangential` come a
 * tangential law (mindlin, linear-history, ...) and its parameters. Plugins are searched in the
 * plugin_dir directories, then in $DASHPOT_PLUGIN_PATH. zplane=Z adds a flat rigid wall at
 * z = Z (particles above it) under the same laws. pair_coeff gives Young's modulus (Pa) and
 * Poisson's ratio of the particles of types I and J; unset I != J pairs combine the materials
 * of I I and J J. Laws are bound once per pair of materials; each contact's effective mass and
 * radius go with the batch call, so any size distribution works.
 *
 * Needs atom_style sphere (radius, rmass, omega, torque), SI units and comm_modify vel yes.
 * Laws with per-contact history (any tangential law, a plastic normal law) also need
 * `newton off`: each rank then computes every contact of its own atoms. Between neighbour-list
 * builds the history sits in arrays in list order; fix DASHPOT/HISTORY (created by the pair
 * style) carries it with the atoms across exchanges, sorts and restart files. Restart files
 * also hold pair_style's arguments and pair_coeff's moduli. */
#ifndef DASHPOT_PAIR_DASHPOT_H
#define DASHPOT_PAIR_DASHPOT_H

#include "pair.h"

#include <string>
#include <vector>

struct DashpotRegistry;
struct DashpotContactLaw;
struct DashpotContactModel;
struct DashpotTangentialLaw;
struct DashpotTangentialModel;

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

 private:
    std::vector<std::string> settings_args;    // pair_style's arguments, for restart files
    std::string law_name, tangential_name;
    DashpotRegistry *registry;
    DashpotContactLaw *law;
    DashpotTangentialLaw *tlaw;
    int wall_flag;
    double wall_z;
    double **young, **poisson;    // per type pair, the material of the I particle ...
    double **young2, **poisson2;  // ... and of the J particle
    std::vector<double> type_radius;    // per type: the largest radius that can exist
    // bound models, per type pair (ntypes+1)^2 then per type against the wall
    std::vector<DashpotContactModel *> cmodel;
    std::vector<DashpotTangentialModel *> tmodel;
    int nslots_n, nslots_t, nvalues;    // history slots of the normal and tangential laws
    class FixDashpotHistory *fix_history;

    // Per-contact history in neighbour-list order: slot k is the k-th (i, j) pair of the list
    // (ilist order, then jlist order), valid from one list build to the next. `touched` is 1
    // when the slot's history may be non-zero (the contact was evaluated since it was zeroed).
    std::vector<double> slot_hist;
    std::vector<unsigned char> slot_touched;
    std::vector<int> slot_i, slot_j;          // the pair's local indices, for history_to_atoms
    std::vector<tagint> slot_ti, slot_tj;     // and tags (indices may be reused by then)
    // the same for the zplane wall, per local atom
    std::vector<double> wall_hist;
    std::vector<unsigned char> wall_touched;
    std::vector<tagint> wall_tag;
    int nwall_slots;
    bigint slots_ncalls;    // neighbor->ncalls when the slots were laid out (-1: never)

    // Contacts are staged a chunk at a time in structure-of-arrays columns sized to stay in
    // cache, then evaluated in one normal and one tangential batch call per kind of pair
    // (bound model) present in the chunk.
 public:
    struct Chunk {
        int *a = nullptr, *b = nullptr;    // a = the atom of the lower tag; b < 0: the wall
        int *slot = nullptr, *key = nullptr;    // history slot (list order, or the atom for the wall); kind
        double *delta = nullptr, *rate = nullptr, *mass = nullptr, *rad = nullptr, *fn = nullptr;
        double *norm = nullptr, *vel = nullptr, *ft = nullptr, *hn = nullptr, *ht = nullptr;
        std::vector<int> istore;
        std::vector<double> dstore;
        void reserve(int ns, int nt);    // allocates the columns once
    };

 private:
    Chunk stage, sorted;    // as gathered; by kind of pair when a chunk mixes kinds
    std::vector<int> key_count, key_next;

    void allocate();
    void free_models();
    int key_of(int itype, int jtype) const;
    void layout_slots();
    template <int NS, int NT> void compute_t();
    template <int NS, int NT> void evaluate(int n, bool mixed, bool wall);
    template <int NS, int NT> void scatter(Chunk &c, int n, double *hist, unsigned char *touched, bool direct);
    void run_laws(Chunk &c, int lo, int m, int key, double *ht_direct);
    void check(int status, const char *what);
    void apply_settings(const std::vector<std::string> &args);
};

}    // namespace LAMMPS_NS

#endif
