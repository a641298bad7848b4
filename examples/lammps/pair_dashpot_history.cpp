/* pair_style dashpot: the history's layout in neighbour-list order, its copy into the history
 * fix (with newton on, ghosts' records sent to their owners), and single() (see
 * pair_dashpot.h). */
#include "pair_dashpot.h"

#include "fix_dashpot_history.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace LAMMPS_NS;
using namespace dashpot_lmp;

/* Lays the history out in the order of the neighbour list just built: slot k is the k-th pair
 * (i, j) of the list, and takes the record atom i (always owned here: a half list) carries for
 * its partner j, zero if none. The wall's history is laid out per local atom (partner tag 0).
 * Runs once per list build, at the first compute after it; the records are current then: the
 * fix refreshed them before any atom could move (pre_exchange), at the end of the last run, or
 * they came from a restart file. */
void PairDashpot::layout_slots()
{
    const int nv = layout.nvalues;
    const tagint *tag = atom->tag;
    const int nlocal = atom->nlocal;
    const int inum = list->inum;
    const int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    size_t nslot = 0;
    for (int ii = 0; ii < inum; ii++) nslot += (size_t) numneigh[ilist[ii]];
    pair_slots.assign(nslot, layout);
    slot_first.assign(nlocal, -1);
    if ((int) slot_atoms.size() < inum) slot_atoms.resize(inum);
    int natoms = 0;
    if (energy_flag) slot_energy.assign(nslot * NENERGY, 0.0);
    // A size list with history marks each pair that touches as the list is built (bit HISTBITS
    // of j, as for LAMMPS's granular styles): a contact without adhesion keeps its history only
    // while it touches, so only the marked pairs can carry a record into this step.
    const bool marked = nv > 0 && !layout.adhesive && list->history;
    const int touching = 1 << HISTBITS;
    size_t k = 0;
    for (int ii = 0; ii < inum; ii++) {
        const int i = ilist[ii];
        const int jnum = numneigh[i];
        if (i < nlocal) slot_first[i] = (int) k;
        slot_atoms[natoms] = i;    // kept only if i has listed pairs
        natoms += jnum > 0;
        // an atom with no recorded contact: its pairs start from zero
        if (nv == 0 || !fix_history->any(i)) {
            k += jnum;
            continue;
        }
        const int *jlist = firstneigh[i];
        for (int jj = 0; jj < jnum; jj++, k++) {
            const int j = jlist[jj];
            if (marked && !(j & touching)) continue;
            const double *h = fix_history->find(i, tag[j & NEIGHMASK]);
            if (h) pair_slots.set(k, h);
        }
    }
    nslot_atoms = natoms;
    // every slot's pair, in slot order: the walk of each step is one flat loop over them
    if (slot_pairs.size() < nslot) slot_pairs.resize(nslot);
    SlotPair *sp = slot_pairs.data();
    for (int q = 0; q < natoms; q++) {
        const int i = slot_atoms[q];
        const int *jlist = firstneigh[i];
        const int jnum = numneigh[i];
        for (int jj = 0; jj < jnum; jj++, sp++) {
            sp->i = i;
            sp->j = jlist[jj] & NEIGHMASK;
        }
    }
    nwall_slots = wall_flag ? nlocal : 0;
    wall_slots.assign(nwall_slots, layout);
    for (int i = 0; i < nwall_slots && nv > 0; i++) {
        const double *h = fix_history->find(i, 0);
        if (h) wall_slots.set(i, h);
    }
    slots_ncalls = neighbor->ncalls;
    slots_nlocal = nlocal;
    if (fix_history) fix_history->rebuilt = 0;
    dirty = 0;
}

/* The records of every current contact into the fix: a contact oriented from the atom of the
 * lower tag, its record the same on both atoms. With newton off every rank computes all the
 * contacts of its own atoms: the record goes to each owned atom of the pair. With newton on a
 * pair is computed once, on the rank owning i; its record also goes to the ghost j, and a
 * reverse communication brings the ghosts' records to their owners, so that whichever rank
 * computes the contact after the next build finds it. Collective with newton on. */
void PairDashpot::history_to_atoms()
{
    if (!fix_history) return;
    const int nv = layout.nvalues;
    const bool newton = force->newton_pair;
    int any = dirty && slots_ncalls >= 0 && nv > 0;
    if (newton) MPI_Allreduce(MPI_IN_PLACE, &any, 1, MPI_INT, MPI_MAX, world);
    if (!any) return;
    const bool mine = slots_ncalls >= 0;
    const int nlocal = atom->nlocal, nall = nlocal + atom->nghost;
    // the atoms the slots know: owned ones of the layout (later ones were created since: no
    // contact yet), and with newton on every ghost
    fix_history->clear(mine ? (newton ? nall : std::min(slots_nlocal, nlocal)) : 0);
    std::vector<double> record(nv);
    const size_t nslot = mine ? pair_slots.size() : 0;
    // the slots follow the neighbour list they were laid out from (no list is built between a
    // list's post_neighbor and the next exchange), whose atoms keep their indices and tags; the
    // atoms with listed pairs, in list order
    const tagint *tag = atom->tag;
    const unsigned char *touched = pair_slots.touched.data();
    for (int q = 0; nslot > 0 && q < nslot_atoms; q++) {
        const int i = slot_atoms[q];
        const int k = slot_first[i], jnum = list->numneigh[i];
        const int *jlist = list->firstneigh[i];
        for (int jj = 0; jj < jnum; jj++) {
            // a zero record is the same as none: zero at first touch
            if (!touched[k + jj] || !pair_slots.nonzero(k + jj)) continue;
            pair_slots.get(k + jj, record.data());
            const int j = jlist[jj] & NEIGHMASK;
            fix_history->add(i, tag[j], record.data());
            if (newton || j < nlocal) fix_history->add(j, tag[i], record.data());
        }
    }
    for (int i = 0; mine && i < nwall_slots && i < nlocal; i++)
        if (wall_slots.nonzero(i)) {
            wall_slots.get(i, record.data());
            fix_history->add(i, 0, record.data());
        }
    if (newton) comm->reverse_comm_variable(fix_history);
    fix_history->update_maxexchange();
    dirty = 0;
}

/* The slot of pair (i, j) in the pair style's neighbour list (in i's neighbours, or j's when j
 * is owned here too), or -1. */
int PairDashpot::find_slot(int i, int j) const
{
    if (slots_ncalls < 0) return -1;
    const int nlocal = atom->nlocal;
    for (int pass = 0; pass < 2; pass++) {
        const int a = pass ? j : i, b = pass ? i : j;
        if (a >= nlocal || a >= (int) slot_first.size() || slot_first[a] < 0) continue;
        const int *jlist = list->firstneigh[a];
        for (int jj = 0; jj < list->numneigh[a]; jj++)
            if ((jlist[jj] & NEIGHMASK) == b) return slot_first[a] + jj;
    }
    return -1;
}

/* One pair for compute pair/local and pair_write: fforce = F_n / r and svector = {F_n, |F_t|,
 * the dissipated power in total and of the normal, tangential, rolling and twisting laws, the
 * stored elastic energy, |F_roll|, the twisting torque (on the atom of the lower tag, about the
 * normal pointing to it)}. The forces: each law called with the contact's stored history and
 * dt = 0, so that the springs are not advanced (their forces are those the step left). The
 * energy: the laws' own outputs from the step's batch calls, which energy=1 asks for (NaN
 * without it, and for a law that does not report energy, an older sdk's). */
double PairDashpot::single(int i, int j, int /*itype*/, int /*jtype*/, double rsq, double /*factor_coul*/,
                           double /*factor_lj*/, double &fforce)
{
    fforce = 0.0;
    for (int q = 0; q < single_extra; q++) svector[q] = 0.0;
    if (model_of.empty()) return 0.0;
    const double *radius = atom->radius, *rmass = atom->rmass;
    const tagint *tag = atom->tag;
    const double radsum = radius[i] + radius[j];
    const int nv = layout.nvalues;
    std::vector<double> h(nv > 0 ? nv : 1, 0.0);
    const int slot = find_slot(i, j);
    const bool stored = slot >= 0 && nv > 0 && pair_slots.touched[slot];
    if (stored) pair_slots.get(slot, h.data());
    const double r = std::sqrt(rsq);
    double delta = radsum - r;
    if (rsq >= radsum * radsum && !(layout.adhesive && stored && -delta <= h[layout.reach_at])) return 0.0;
    // as compute() sees the contact: oriented from the atom of the lower tag
    const int a = tag[i] < tag[j] ? i : j, b = a == i ? j : i;
    double **x = atom->x, **v = atom->v, **w = atom->omega;
    double nrm[3], dv[3], vel[3], rel[3], vroll[3], ws[3];
    for (int d = 0; d < 3; d++) {
        nrm[d] = (x[a][d] - x[b][d]) / r;
        dv[d] = v[a][d] - v[b][d];
        rel[d] = w[a][d] - w[b][d];
        ws[d] = radius[a] * w[a][d] + radius[b] * w[b][d];
    }
    const double vn = dv[0] * nrm[0] + dv[1] * nrm[1] + dv[2] * nrm[2];
    double rate = -vn;
    double meff = rmass[a] * rmass[b] / (rmass[a] + rmass[b]);
    double reff = radius[a] * radius[b] / radsum;
    for (int d = 0; d < 3; d++) {
        const int e = (d + 1) % 3, g = (d + 2) % 3;
        vel[d] = (dv[d] - vn * nrm[d]) - (ws[e] * nrm[g] - ws[g] * nrm[e]);
        vroll[d] = reff * (rel[e] * nrm[g] - rel[g] * nrm[e]);
    }
    double twist = rel[0] * nrm[0] + rel[1] * nrm[1] + rel[2] * nrm[2];
    const int id = model_of[(size_t) atom->type[a] * (atom->ntypes + 1) + atom->type[b]];
    if (id < 0) return 0.0;
    const Model &md = models.model(id);
    // the record at the layout's widths, packed at the model's
    std::vector<double> hm[NFAMILY];
    for (int f = 0; f < NFAMILY; f++) hm[f].assign(h.begin() + layout.offset[f], h.begin() + layout.offset[f] + md.slots[f]);
    auto hist = [&](int f) { return md.slots[f] ? hm[f].data() : nullptr; };
    double fn = 0.0, ft[3] = {0, 0, 0}, fr[3] = {0, 0, 0}, mt = 0.0;
    try {
        double ctx[3] = {0.0, 0.0, 0.0};
#if DASHPOT_LMP_CONTEXT
        const bool with_ctx = md.any_context;
        double reach = 0.0;
        if (with_ctx)
            check_status(dashpot_contact_model_force_batch_context(md.normal, 1, &delta, &rate, &meff, &reff,
                                                                   hist(NORMAL), md.slots[NORMAL], &fn, &reach,
                                                                   nullptr, nullptr, nullptr, ctx),
                         "dashpot_contact_model_force_batch_context");
        else
#else
        (void) ctx;
#endif
            check_status(dashpot_contact_model_force_batch(md.normal, 1, &delta, &rate, &meff, &reff, hist(NORMAL),
                                                           md.slots[NORMAL], &fn),
                         "dashpot_contact_model_force_batch");
        if (md.tangential) {
#if DASHPOT_LMP_CONTEXT
            if (with_ctx && md.reads_context[TANGENTIAL])
                check_status(dashpot_tangential_model_force_batch_context(md.tangential, 1, 0.0, nrm, vel, &fn, &delta,
                                                                          &meff, &reff, ctx, hist(TANGENTIAL),
                                                                          md.slots[TANGENTIAL], ft, nullptr, nullptr,
                                                                          nullptr),
                             "dashpot_tangential_model_force_batch_context");
            else
#endif
                check_status(dashpot_tangential_model_force_batch(md.tangential, 1, 0.0, nrm, vel, &fn, &delta, &meff,
                                                                  &reff, hist(TANGENTIAL), md.slots[TANGENTIAL], ft),
                             "dashpot_tangential_model_force_batch");
        }
        if (md.rolling) {
#if DASHPOT_LMP_CONTEXT
            if (with_ctx && md.reads_context[ROLLING])
                check_status(dashpot_rolling_model_force_batch_context(md.rolling, 1, 0.0, nrm, vroll, &fn, &delta,
                                                                       &meff, &reff, ctx, hist(ROLLING),
                                                                       md.slots[ROLLING], fr, nullptr, nullptr,
                                                                       nullptr),
                             "dashpot_rolling_model_force_batch_context");
            else
#endif
                check_status(dashpot_rolling_model_force_batch(md.rolling, 1, 0.0, nrm, vroll, &fn, &delta, &meff,
                                                               &reff, hist(ROLLING), md.slots[ROLLING], fr, nullptr,
                                                               nullptr, nullptr),
                             "dashpot_rolling_model_force_batch");
        }
        if (md.twisting) {
#if DASHPOT_LMP_CONTEXT
            if (with_ctx && md.reads_context[TWISTING])
                check_status(dashpot_twisting_model_torque_batch_context(md.twisting, 1, 0.0, nrm, &twist, &fn,
                                                                         &delta, &meff, &reff, ctx, hist(TWISTING),
                                                                         md.slots[TWISTING], &mt, nullptr, nullptr,
                                                                         nullptr),
                             "dashpot_twisting_model_torque_batch_context");
            else
#endif
                check_status(dashpot_twisting_model_torque_batch(md.twisting, 1, 0.0, nrm, &twist, &fn, &delta,
                                                                 &meff, &reff, hist(TWISTING), md.slots[TWISTING],
                                                                 &mt, nullptr, nullptr, nullptr),
                             "dashpot_twisting_model_torque_batch");
        }
    } catch (std::exception &e) {
        fail(e, false);
    }
    if (granular_single) {
        // pair_style granular's columns, on atom i (the contact is computed from the atom of the
        // lower tag: the tangential force changes sign from the other side; the rolling force
        // and the twisting torque about the normal do not)
        const double sign = a == i ? 1.0 : -1.0;
        for (int d = 0; d < 3; d++) {
            svector[d] = sign * ft[d];
            svector[4 + d] = fr[d];
            svector[9 + d] = x[i][d] - x[j][d];
        }
        svector[3] = std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
        svector[7] = std::sqrt(fr[0] * fr[0] + fr[1] * fr[1] + fr[2] * fr[2]);
        svector[8] = mt;
        fforce = fn / r;
        return 0.0;
    }
    svector[0] = fn;
    svector[1] = std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
    const double *e = energy_flag && slot >= 0 ? &slot_energy[(size_t) slot * NENERGY] : nullptr;
    const double nan = std::numeric_limits<double>::quiet_NaN();
    svector[2] = 0.0;
    for (int f = 0; f < NFAMILY; f++) {
        svector[3 + f] = e ? e[f] : nan;
        svector[2] += svector[3 + f];
    }
    svector[7] = e ? e[NFAMILY] : nan;
    svector[8] = std::sqrt(fr[0] * fr[0] + fr[1] * fr[1] + fr[2] * fr[2]);
    svector[9] = mt;
    fforce = fn / r;
    return 0.0;
}
