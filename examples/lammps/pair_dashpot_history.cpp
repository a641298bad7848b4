/* pair_style dashpot: the history's layout in neighbour-list order, its copy into fix
 * DASHPOT/HISTORY, and single() (see pair_dashpot.h). */
#include "pair_dashpot.h"

#include "fix_dashpot_history.h"

#include "dashpot.h"

#include "atom.h"
#include "error.h"
#include "neigh_list.h"
#include "neighbor.h"

#include <algorithm>
#include <cmath>
#include <limits>

using namespace LAMMPS_NS;

/* Lays the history out in the order of the neighbour list just built: slot k is the k-th pair
 * (i, j) of the list, and takes the history that pair had, zero if none. The wall's history is
 * laid out per local atom. Runs once per list build (at the first compute after it), never in
 * the steps between. The history comes from the slots of the last layout when no atom has
 * moved since the last compute (fix DASHPOT/HISTORY's records are then stale: every move of an
 * atom, an exchange, a sort or a deletion, refreshes them first), else from the records atom i
 * (or j) carries for that partner. */
void PairDashpot::layout_slots()
{
    const int nv = nvalues;
    const bool carry = nv > 0 && fix_history->stale && slots_ncalls >= 0;
    // the last layout's slots, kept (their arrays reused by the next layout)
    Slots &old_pairs = carry_pairs, &old_wall = carry_wall;
    if (carry) {
        // the last layout's contacts of each local atom, found by the partner's tag
        index_slots();
        std::swap(old_pairs, pair_slots);
        std::swap(old_wall, wall_slots);
    }
    tagint *tag = atom->tag;
    int nlocal = atom->nlocal;
    int inum = list->inum;
    int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    size_t nslot = 0;
    for (int ii = 0; ii < inum; ii++) nslot += (size_t) numneigh[ilist[ii]];
    pair_slots.assign(nslot, nslots, adhesive);
    slot_i.resize(nslot);
    slot_j.resize(nslot);
    slot_ti.resize(nslot);
    slot_tj.resize(nslot);
    slot_first.assign(nlocal, -1);
    if (energy_flag) slot_energy.assign(nslot * NENERGY, 0.0);
    std::vector<double> record(nv > 0 ? nv : 1);
    size_t k = 0;
    for (int ii = 0; ii < inum; ii++) {
        int i = ilist[ii];
        int *jlist = firstneigh[i];
        if (i < nlocal) slot_first[i] = (int) k;
        for (int jj = 0; jj < numneigh[i]; jj++, k++) {
            int j = jlist[jj] & NEIGHMASK;
            slot_i[k] = i;
            slot_j[k] = j;
            slot_ti[k] = tag[i];
            slot_tj[k] = tag[j];
            if (nv == 0) continue;
            // the record is on both atoms when both were owned here; i always is (half list)
            if (carry) {
                int s = carried_slot(i, tag[j]);
                if (s < 0 && j < nlocal) s = carried_slot(j, tag[i]);
                if (s >= 0) {
                    old_pairs.get(s, nslots, record.data());
                    pair_slots.set(k, nslots, record.data());
                }
                continue;
            }
            const double *h = fix_history->find(i, tag[j]);
            if (!h && j < nlocal) h = fix_history->find(j, tag[i]);
            if (h) pair_slots.set(k, nslots, h);
        }
    }
    const int nwall_old = nwall_slots;
    nwall_slots = wall_flag ? nlocal : 0;
    wall_slots.assign(nwall_slots, nslots, adhesive);
    wall_tag.resize(nwall_slots);
    for (int i = 0; i < nwall_slots; i++) {
        wall_tag[i] = tag[i];
        if (carry) {
            if (i < nwall_old && old_wall.touched[i]) {
                old_wall.get(i, nslots, record.data());
                wall_slots.set(i, nslots, record.data());
            }
            continue;
        }
        const double *h = nv > 0 ? fix_history->find(i, 0) : nullptr;
        if (h) wall_slots.set(i, nslots, h);
    }
    slots_ncalls = neighbor->ncalls;
    slots_nlocal = nlocal;
    fix_history->rebuilt = 0;
}

/* Indexes the contacts of the last layout by local atom (no atom has moved since): for each
 * local atom, its partners' tags and the contacts' slots, as history_to_atoms would record
 * them (a contact whose history is all zero is the same as none). */
void PairDashpot::index_slots()
{
    const int n = slots_nlocal;
    carry_first.assign(n + 1, 0);
    const size_t nslot = pair_slots.touched.size();
    std::vector<double> record(nvalues);
    std::vector<unsigned char> &keep = carry_keep;
    keep.assign(nslot, 0);
    for (size_t k = 0; k < nslot; k++) {
        if (!pair_slots.touched[k]) continue;
        pair_slots.get(k, nslots, record.data());
        bool zero = true;
        for (int s = 0; s < nvalues; s++) zero = zero && record[s] == 0.0;
        if (zero) continue;
        keep[k] = 1;
        carry_first[slot_i[k] + 1]++;
        if (slot_j[k] < n) carry_first[slot_j[k] + 1]++;
    }
    for (int i = 0; i < n; i++) carry_first[i + 1] += carry_first[i];
    carry_tag.resize(carry_first[n]);
    carry_slot.resize(carry_first[n]);
    std::vector<int> &next = carry_next;
    next.assign(carry_first.begin(), carry_first.end() - 1);
    for (size_t k = 0; k < nslot; k++) {
        if (!keep[k]) continue;
        int q = next[slot_i[k]]++;
        carry_tag[q] = slot_tj[k];
        carry_slot[q] = (int) k;
        if (slot_j[k] < n) {
            q = next[slot_j[k]]++;
            carry_tag[q] = slot_ti[k];
            carry_slot[q] = (int) k;
        }
    }
}

/* The last layout's slot of local atom i's contact with the partner of tag `partner`, or -1. */
int PairDashpot::carried_slot(int i, tagint partner) const
{
    if (i >= slots_nlocal) return -1;    // an atom inserted since: no contact yet
    for (int q = carry_first[i]; q < carry_first[i + 1]; q++)
        if (carry_tag[q] == partner) return carry_slot[q];
    return -1;
}

void PairDashpot::history_to_atoms()
{
    if (!fix_history) return;
    fix_history->stale = 0;
    if (slots_ncalls < 0) return;    // nothing laid out yet: the records are current
    const int nv = nvalues;
    int nlocal = atom->nlocal;
    fix_history->clear(nlocal);
    bool ok = true;
    std::vector<double> record(nv > 0 ? nv : 1);
    const double *h = record.data();
    size_t nslot = pair_slots.touched.size();
    for (size_t k = 0; k < nslot && ok; k++) {
        if (!pair_slots.touched[k]) continue;
        pair_slots.get(k, nslots, record.data());
        bool zero = true;
        for (int s = 0; s < nv; s++) zero = zero && h[s] == 0.0;
        if (zero) continue;    // the same as no record: zero at first touch
        int i = slot_i[k], j = slot_j[k];
        if (i < nlocal) ok = fix_history->add(i, slot_tj[k], h);
        if (ok && j < nlocal) ok = fix_history->add(j, slot_ti[k], h);
    }
    for (int i = 0; i < nwall_slots && i < nlocal && ok; i++)
        if (wall_slots.touched[i]) {
            wall_slots.get(i, nslots, record.data());
            ok = fix_history->add(i, 0, h);
        }
    if (!ok)
        error->one(FLERR, "pair dashpot: an atom has more than {} contacts (the history fix's capacity)",
                   fix_history->maxpartner);
}

/* The energy=1 values (each family's power, then the elastic energy) the step stored for pair
 * (i, j), found in the pair style's neighbour list (in i's neighbours, or j's when j is owned
 * here too); nullptr when the pair is not in the list. */
const double *PairDashpot::stored_energy(int i, int j) const
{
    if (!energy_flag || slots_ncalls < 0) return nullptr;
    const int nlocal = atom->nlocal;
    for (int pass = 0; pass < 2; pass++) {
        const int a = pass ? j : i, b = pass ? i : j;
        if (a >= nlocal || a >= (int) slot_first.size() || slot_first[a] < 0) continue;
        const int *jlist = list->firstneigh[a];
        for (int jj = 0; jj < list->numneigh[a]; jj++)
            if ((jlist[jj] & NEIGHMASK) == b) return &slot_energy[(size_t) (slot_first[a] + jj) * NENERGY];
    }
    return nullptr;
}

/* One pair for compute pair/local and pair_write: fforce = F_n / r and svector = {F_n, |F_t|,
 * the dissipated power (W) in total and of the normal, tangential, rolling and twisting laws,
 * the stored elastic energy (J), |F_roll| (N), the twisting torque (N m, on the atom of the
 * lower tag, about the normal pointing to it)}. The forces: each law called with the contact's
 * stored history and dt = 0, so that the springs are not advanced (their forces are those the
 * step left). The energy: the laws' own outputs from the step's batch calls, which energy=1
 * asks for (NaN without it, and for a law that does not report energy, an older sdk's). */
double PairDashpot::single(int i, int j, int /*itype*/, int /*jtype*/, double rsq, double /*factor_coul*/,
                           double /*factor_lj*/, double &fforce)
{
    fforce = 0.0;
    for (int q = 0; q < single_extra; q++) svector[q] = 0.0;
    const double *radius = atom->radius, *rmass = atom->rmass;
    const tagint *tag = atom->tag;
    const double radsum = radius[i] + radius[j];
    if (cmodel.empty()) return 0.0;
    std::vector<double> h(nvalues > 0 ? nvalues : 1, 0.0);
    bool stored = false;
    if (fix_history && i < atom->nlocal && nvalues > 0) {
        fix_history->refresh();
        const double *s = fix_history->find(i, tag[j]);
        if (s) {
            std::copy(s, s + nvalues, h.begin());
            stored = true;
        }
    }
    const double r = std::sqrt(rsq);
    double delta = radsum - r;
    if (rsq >= radsum * radsum && !(adhesive && stored && -delta <= h[reach_at])) return 0.0;
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
    double rate = -(dv[0] * nrm[0] + dv[1] * nrm[1] + dv[2] * nrm[2]);
    double meff = rmass[a] * rmass[b] / (rmass[a] + rmass[b]);
    double reff = radius[a] * radius[b] / radsum;
    for (int d = 0; d < 3; d++) {
        const int e = (d + 1) % 3, g = (d + 2) % 3;
        vel[d] = dv[d] - (ws[e] * nrm[g] - ws[g] * nrm[e]);
        vroll[d] = reff * (rel[e] * nrm[g] - rel[g] * nrm[e]);
    }
    double twist = rel[0] * nrm[0] + rel[1] * nrm[1] + rel[2] * nrm[2];
    const int key = key_of(atom->type[a], atom->type[b]);
    auto hist = [&](int f) { return nslots[f] ? h.data() + offset[f] : nullptr; };
    double fn = 0.0, ft[3] = {0, 0, 0}, fr[3] = {0, 0, 0}, mt = 0.0;
    check(dashpot_contact_model_force_batch(cmodel[key], 1, &delta, &rate, &meff, &reff, hist(NORMAL),
                                            nslots[NORMAL], &fn),
          "dashpot_contact_model_force_batch");
    if (tlaw)
        check(dashpot_tangential_model_force_batch(tmodel[key], 1, 0.0, nrm, vel, &fn, &delta, &meff, &reff,
                                                   hist(TANGENTIAL), nslots[TANGENTIAL], ft),
              "dashpot_tangential_model_force_batch");
    if (rlaw)
        check(dashpot_rolling_model_force_batch(rmodel[key], 1, 0.0, nrm, vroll, &fn, &delta, &meff, &reff,
                                                hist(ROLLING), nslots[ROLLING], fr, nullptr, nullptr, nullptr),
              "dashpot_rolling_model_force_batch");
    if (wlaw)
        check(dashpot_twisting_model_torque_batch(wmodel[key], 1, 0.0, nrm, &twist, &fn, &delta, &meff, &reff,
                                                  hist(TWISTING), nslots[TWISTING], &mt, nullptr, nullptr, nullptr),
              "dashpot_twisting_model_torque_batch");
    svector[0] = fn;
    svector[1] = std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
    const double *e = stored_energy(i, j);
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
