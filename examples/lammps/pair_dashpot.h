/* pair_style dashpot: granular normal contact forces from any dashpot law, through the dashpot
 * C ABI (host/capi/include/dashpot.h), with all contacts of a step evaluated in batch calls.
 *
 *   pair_style dashpot LAW [key=value ...] [plugin_dir=DIR ...] [zplane=Z]
 *   pair_coeff I J E nu
 *
 * LAW is any dashpot contact law (hsd, lsd, kuwabara-kono, a third-party plugin ...); the
 * key=value pairs are its parameters. Plugins are searched in the plugin_dir directories, then
 * in $DASHPOT_PLUGIN_PATH. zplane=Z adds a flat rigid wall at z = Z (particles above it) whose
 * contact uses the same law. pair_coeff gives Young's modulus (Pa) and Poisson's ratio of the
 * particles of types I and J; unset I != J pairs combine the materials of I I and J J.
 * Needs atom_style sphere (per-atom radius and mass), SI units and comm_modify vel yes. */
#ifndef DASHPOT_PAIR_DASHPOT_H
#define DASHPOT_PAIR_DASHPOT_H

#include "pair.h"

#include <string>
#include <vector>

struct DashpotRegistry;
struct DashpotContactLaw;
struct DashpotBoundContact;

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

 private:
    /* A kind of particle: what a bound law depends on. */
    struct Species {
        int type;
        double radius, mass;
    };
    static constexpr int MAX_SPECIES = 256;

    std::string law_name;
    DashpotRegistry *registry;
    DashpotContactLaw *law;
    int wall_flag;
    double wall_z;
    double **young, **poisson;    // per type pair, the material of the I particle ...
    double **young2, **poisson2;  // ... and of the J particle
    double max_radius;

    std::vector<Species> species;
    std::vector<int> atom_species;              // per local + ghost atom
    std::vector<DashpotBoundContact *> bound;   // MAX_SPECIES^2 pair slots + MAX_SPECIES wall slots

    // this step's contacts
    std::vector<int> ci, cj, ckey, order, start, fill, used_keys;
    std::vector<int> slot_of_key;    // per pair slot: its place among this step's kinds, or -1
    std::vector<double> cdx, cdy, cdz, crinv, cdelta, crate, cforce, pdelta, prate, pforce;

    void allocate();
    void free_bound();
    void classify_atoms();
    int species_of(int type, double radius, double mass);
    DashpotBoundContact *bound_for(int key);
    void check(int status, const char *what);
};

}    // namespace LAMMPS_NS

#endif
