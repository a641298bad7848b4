/* fix DASHPOT/HISTORY: see fix_dashpot_history.h. */
#include "fix_dashpot_history.h"

#include "pair_dashpot.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "memory.h"

#include <cstring>

using namespace LAMMPS_NS;

FixDashpotHistory::FixDashpotHistory(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), stale(0), rebuilt(1), nvalues(0), maxpartner(0), npartner(nullptr), partner(nullptr),
    values(nullptr)
{
    if (narg != 5) error->all(FLERR, "fix DASHPOT/HISTORY: expected NVALUES MAXPARTNERS (created by pair dashpot)");
    nvalues = utils::inumeric(FLERR, arg[3], false, lmp);
    maxpartner = utils::inumeric(FLERR, arg[4], false, lmp);
    if (nvalues < 0 || maxpartner < 1) error->all(FLERR, "fix DASHPOT/HISTORY: bad NVALUES or MAXPARTNERS");
    restart_peratom = 1;
    create_attribute = 1;
    grow_arrays(atom->nmax);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
    for (int i = 0; i < atom->nmax; i++) npartner[i] = 0;
}

FixDashpotHistory::~FixDashpotHistory()
{
    atom->delete_callback(id, Atom::GROW);
    atom->delete_callback(id, Atom::RESTART);
    memory->destroy(npartner);
    memory->destroy(partner);
    memory->destroy(values);
}

int FixDashpotHistory::setmask()
{
    return FixConst::PRE_EXCHANGE | FixConst::MIN_PRE_EXCHANGE | FixConst::POST_RUN | FixConst::POST_NEIGHBOR |
        FixConst::MIN_POST_NEIGHBOR;
}

void FixDashpotHistory::pull_from_pair()
{
    stale = 0;
    auto *pair = dynamic_cast<PairDashpot *>(force->pair_match("dashpot", 1));
    if (pair) pair->history_to_atoms();
}

void FixDashpotHistory::setup_pre_exchange()
{
    refresh();
}

// Before an exchange the records are left stale: whatever moves an atom (pack_exchange,
// copy_arrays) or brings one (unpack_exchange) refreshes them first, and when nothing has moved,
// the pair style lays its next slots out from its last ones (a list build on one rank without a
// sort, most of them: no round trip through every atom's records).
void FixDashpotHistory::pre_exchange() {}

void FixDashpotHistory::min_pre_exchange() {}

void FixDashpotHistory::post_run()
{
    refresh();
}

// Every list build, in a run's setup, in its steps and in a minimisation: the pair style's slots
// (in the order of the old list) must be laid out again before its next compute.
void FixDashpotHistory::setup_post_neighbor()
{
    rebuilt = 1;
}

void FixDashpotHistory::post_neighbor()
{
    rebuilt = 1;
}

void FixDashpotHistory::min_post_neighbor()
{
    rebuilt = 1;
}

double FixDashpotHistory::memory_usage()
{
    double n = atom->nmax;
    return n * (sizeof(int) + maxpartner * (sizeof(tagint) + nvalues * sizeof(double)));
}

void FixDashpotHistory::grow_arrays(int nmax)
{
    memory->grow(npartner, nmax, "dashpot/history:npartner");
    memory->grow(partner, nmax, maxpartner, "dashpot/history:partner");
    memory->grow(values, nmax, maxpartner * (nvalues > 0 ? nvalues : 1), "dashpot/history:values");
}

void FixDashpotHistory::copy_arrays(int i, int j, int /*delflag*/)
{
    refresh();
    npartner[j] = npartner[i];
    for (int k = 0; k < npartner[i]; k++) partner[j][k] = partner[i][k];
    std::memcpy(values[j], values[i], sizeof(double) * npartner[i] * nvalues);
}

void FixDashpotHistory::set_arrays(int i)
{
    npartner[i] = 0;
}

int FixDashpotHistory::pack_exchange(int i, double *buf)
{
    refresh();
    int m = 0;
    buf[m++] = npartner[i];
    for (int k = 0; k < npartner[i]; k++) {
        buf[m++] = ubuf(partner[i][k]).d;
        for (int v = 0; v < nvalues; v++) buf[m++] = values[i][k * nvalues + v];
    }
    return m;
}

int FixDashpotHistory::unpack_exchange(int i, double *buf)
{
    refresh();    // the records, not the pair style's slots, now hold this atom's contacts
    int m = 0;
    npartner[i] = (int) buf[m++];
    for (int k = 0; k < npartner[i]; k++) {
        partner[i][k] = (tagint) ubuf(buf[m++]).i;
        for (int v = 0; v < nvalues; v++) values[i][k * nvalues + v] = buf[m++];
    }
    return m;
}

int FixDashpotHistory::pack_restart(int i, double *buf)
{
    refresh();
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
    refresh();
    return 2 + npartner[i] * (1 + nvalues);
}

int FixDashpotHistory::maxsize_restart()
{
    return 2 + maxpartner * (1 + nvalues);
}

const double *FixDashpotHistory::find(int i, tagint p) const
{
    for (int k = 0; k < npartner[i]; k++)
        if (partner[i][k] == p) return &values[i][k * nvalues];
    return nullptr;
}

void FixDashpotHistory::clear(int n)
{
    for (int i = 0; i < n; i++) npartner[i] = 0;
}

bool FixDashpotHistory::add(int i, tagint p, const double *v)
{
    int k = npartner[i];
    if (k >= maxpartner) return false;
    partner[i][k] = p;
    double *dst = &values[i][k * nvalues];
    for (int s = 0; s < nvalues; s++) dst[s] = v[s];    // a few values: no memcpy call
    npartner[i] = k + 1;
    return true;
}
