/* fix DASHPOT/HISTORY: see fix_dashpot_history.h. */
#include "fix_dashpot_history.h"

#include "pair_dashpot.h"

#include "atom.h"
#include "comm.h"
#include "error.h"

#include <mpi.h>

#include <algorithm>

using namespace LAMMPS_NS;

FixDashpotHistory::FixDashpotHistory(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), pair(nullptr), rebuilt(1), nvalues(0)
{
    if (narg != 4) error->all(FLERR, "fix DASHPOT/HISTORY: expected NVALUES (created by pair dashpot)");
    nvalues = utils::inumeric(FLERR, arg[3], false, lmp);
    if (nvalues < 0) error->all(FLERR, "fix DASHPOT/HISTORY: NVALUES = {} must be >= 0", nvalues);
    restart_peratom = 1;
    restart_global = 1;    // write_restart() refreshes the records before they are packed
    create_attribute = 1;
    maxexchange_dynamic = 1;
    grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
}

FixDashpotHistory::~FixDashpotHistory()
{
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
}

int FixDashpotHistory::setmask()
{
    return FixConst::PRE_EXCHANGE | FixConst::MIN_PRE_EXCHANGE | FixConst::POST_RUN | FixConst::POST_NEIGHBOR |
        FixConst::MIN_POST_NEIGHBOR;
}

void FixDashpotHistory::refresh()
{
    if (pair) pair->history_to_atoms();
}

// Atoms may leave this rank, be sorted, created or deleted next: the records take the pair
// style's current history first (every rank together: with newton on this communicates).
void FixDashpotHistory::pre_exchange()
{
    refresh();
}

void FixDashpotHistory::min_pre_exchange()
{
    refresh();
}

// between runs atoms may be created, deleted, read or written
void FixDashpotHistory::post_run()
{
    refresh();
}

void FixDashpotHistory::write_restart(FILE *fp)
{
    refresh();
    if (comm->me == 0) {
        int size = 0;
        fwrite(&size, sizeof(int), 1, fp);
    }
}

// Every list build, in a run's setup, in its steps and in a minimisation: the pair style lays its
// slots out again in the order of the new list (here, as LAMMPS's fix neigh/history does, rather
// than in the pair's compute).
void FixDashpotHistory::setup_post_neighbor()
{
    post_neighbor();
}

void FixDashpotHistory::post_neighbor()
{
    rebuilt = 1;
    if (pair) pair->layout_slots();
}

void FixDashpotHistory::min_post_neighbor()
{
    post_neighbor();
}

double FixDashpotHistory::memory_usage()
{
    double bytes = 0.0;
    for (size_t i = 0; i < partner.size(); i++)
        bytes += partner[i].capacity() * sizeof(tagint) + values[i].capacity() * sizeof(double);
    return bytes + partner.size() * 2 * sizeof(std::vector<double>);
}

void FixDashpotHistory::grow_arrays(int nmax)
{
    if ((int) partner.size() < nmax) {
        partner.resize(nmax);
        values.resize(nmax);
    }
}

void FixDashpotHistory::copy_arrays(int i, int j, int /*delflag*/)
{
    partner[j] = partner[i];
    values[j] = values[i];
}

void FixDashpotHistory::set_arrays(int i)
{
    partner[i].clear();
    values[i].clear();
}

int FixDashpotHistory::pack_exchange(int i, double *buf)
{
    int m = 0;
    const int np = (int) partner[i].size();
    buf[m++] = np;
    for (int k = 0; k < np; k++) {
        buf[m++] = ubuf(partner[i][k]).d;
        for (int v = 0; v < nvalues; v++) buf[m++] = values[i][(size_t) k * nvalues + v];
    }
    return m;
}

int FixDashpotHistory::unpack_exchange(int i, double *buf)
{
    int m = 0;
    const int np = (int) buf[m++];
    partner[i].resize(np);
    values[i].resize((size_t) np * nvalues);
    for (int k = 0; k < np; k++) {
        partner[i][k] = (tagint) ubuf(buf[m++]).i;
        for (int v = 0; v < nvalues; v++) values[i][(size_t) k * nvalues + v] = buf[m++];
    }
    return m;
}

int FixDashpotHistory::pack_restart(int i, double *buf)
{
    // buf[0] is the record's length, counting itself (the Atom::RESTART convention)
    int m = pack_exchange(i, buf + 1) + 1;
    buf[0] = m;
    return m;
}

void FixDashpotHistory::unpack_restart(int nlocal, int nth)
{
    double **extra = atom->extra;
    int m = 0;
    for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
    unpack_exchange(nlocal, &extra[nlocal][m + 1]);
}

int FixDashpotHistory::size_restart(int i)
{
    return 2 + (int) partner[i].size() * (1 + nvalues);
}

int FixDashpotHistory::maxsize_restart()
{
    int mine = 0, all = 0;
    for (int i = 0; i < atom->nlocal; i++) mine = std::max(mine, (int) partner[i].size());
    MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MAX, world);
    return 2 + all * (1 + nvalues);
}

// newton on: the records of ghost atoms, sent to their owners, which append them
int FixDashpotHistory::pack_reverse_comm_size(int n, int first)
{
    int m = 0;
    for (int i = first; i < first + n; i++) m += 1 + (int) partner[i].size() * (1 + nvalues);
    return m;
}

int FixDashpotHistory::pack_reverse_comm(int n, int first, double *buf)
{
    int m = 0;
    for (int i = first; i < first + n; i++) m += pack_exchange(i, buf + m);
    return m;
}

void FixDashpotHistory::unpack_reverse_comm(int n, int *list, double *buf)
{
    int m = 0;
    for (int q = 0; q < n; q++) {
        const int j = list[q];
        const int np = (int) buf[m++];
        for (int k = 0; k < np; k++) {
            partner[j].push_back((tagint) ubuf(buf[m++]).i);
            values[j].insert(values[j].end(), buf + m, buf + m + nvalues);
            m += nvalues;
        }
    }
}

const double *FixDashpotHistory::find(int i, tagint p) const
{
    const std::vector<tagint> &pt = partner[i];
    for (size_t k = 0; k < pt.size(); k++)
        if (pt[k] == p) return &values[i][k * nvalues];
    return nullptr;
}

void FixDashpotHistory::clear(int n)
{
    if ((int) partner.size() < n) grow_arrays(n);
    for (int i = 0; i < n; i++) {
        partner[i].clear();
        values[i].clear();
    }
}

void FixDashpotHistory::add(int i, tagint p, const double *record)
{
    partner[i].push_back(p);
    values[i].insert(values[i].end(), record, record + nvalues);
}

void FixDashpotHistory::update_maxexchange()
{
    size_t most = 0;
    for (int i = 0; i < atom->nlocal; i++) most = std::max(most, partner[i].size());
    maxexchange = 1 + (int) most * (1 + nvalues);
}
