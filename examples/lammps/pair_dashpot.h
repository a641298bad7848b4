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
 * `newton off`: each rank then computes every contact of its own atoms and keeps its history
 * with them (fix DASHPOT/HISTORY, created by the pair style). */
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

 private:
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

    // this step's contacts (a = the atom of the lower tag, or the particle against the wall)
    std::vector<int> ca, cb, ckey, cnt, first, order;
    std::vector<double> cdelta, crate, cmass, crad, cnorm, cvel, cra, crb, cfn, cft, chn, cht;
    std::vector<double> saved_hn, saved_ht;
    std::vector<double> sdelta, srate, smass, srad, snorm, svel, sfn, sft, shn, sht;

    void allocate();
    void free_models();
    int key_of(int itype, int jtype) const;
    void bind_models();
    void evaluate(size_t n);
    void check(int status, const char *what);
};

}    // namespace LAMMPS_NS

#endif
