/* pair_style dashpot: the forces of a step (see pair_dashpot.h). The neighbour list is walked
 * once; contacts are staged in the engine's chunks and evaluated by one batch call per family
 * and bound model, then their forces, torques and history are applied. */
#include "pair_dashpot.h"

#include "fix_dashpot_history.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <cmath>

using namespace LAMMPS_NS;
using namespace dashpot_lmp;

/* Contact k of chunk c reaches past the neighbour cutoff of its pair of types: an error. */
void PairDashpot::reach_error(const ContactEngine::Chunk &c, int k)
{
    const int a = c.a[k], b = c.b[k];
    const double *radius = atom->radius;
    const double cut = key_cut[atom->type[a] * (atom->ntypes + 1) + atom->type[b]];
    error->one(FLERR,
               "pair dashpot: a contact of law '{}' reaches {} beyond touching, past the neighbour "
               "cutoff ({} for radii {} and {}): its reach depends on more than the radii it was "
               "probed at",
               models.spec(models.model(c.model[k]).spec).law[dashpot_lmp::NORMAL].name, c.reach[k], cut,
               radius[a], radius[b]);
}

/* What the step keeps of the n contacts of chunk c beyond their forces and torques (added by the
 * engine to the atoms): the virial, each pair's energy outputs for single(), and the check that
 * an adhesive contact stays within the neighbour cutoff. With `applied` false (the virial is
 * tallied this step) the forces and torques are applied here, from the chunk's columns. */
void PairDashpot::apply(ContactEngine::Chunk &c, int n, bool wall, bool applied)
{
    double *f0 = atom->f[0], *t0 = atom->torque[0];    // contiguous: indexed from the first row
    const double *radius = atom->radius;
    const int nlocal = atom->nlocal;
    const int newton_pair = force->newton_pair;
    const bool adh = layout.adhesive;
    const int *type = atom->type;
    const int nt1 = atom->ntypes + 1;
    const double *cut = key_cut.data();
    if (applied && !wall && !energy_flag) {
        // the forces applied, no virial nor energy: only an adhesive contact's reach to check
        for (int k = 0; k < n; k++) {
            const int a = c.a[k], b = c.b[k];
            if (adh && radius[a] + radius[b] + c.reach[k] > cut[type[a] * nt1 + type[b]]) reach_error(c, k);
        }
        return;
    }
    for (int k = 0; k < n; k++) {
        const int a = c.a[k], b = c.b[k];
        if (!applied) {
            const double *F = c.force + 3 * k, *ta = c.ta + 3 * k, *tb = c.tb + 3 * k;
            if (a < nlocal || newton_pair)
                for (int d = 0; d < 3; d++) {
                    f0[3 * a + d] += F[d];
                    t0[3 * a + d] += ta[d];
                }
            if (!wall && (b < nlocal || newton_pair))
                for (int d = 0; d < 3; d++) {
                    f0[3 * b + d] -= F[d];
                    t0[3 * b + d] += tb[d];
                }
        }
        if (!wall) {
            if (evflag) {
                const double *F = c.force + 3 * k, *nv = c.norm + 3 * k;
                const double r = radius[a] + radius[b] - c.delta[k];
                ev_tally_xyz(a, b, nlocal, newton_pair, 0.0, 0.0, F[0], F[1], F[2], nv[0] * r, nv[1] * r, nv[2] * r);
            }
            // an adhesive contact must stay in the neighbour list as long as it acts
            if (adh && radius[a] + radius[b] + c.reach[k] > cut[type[a] * nt1 + type[b]]) reach_error(c, k);
            if (energy_flag) {
                double *e = slot_energy.data() + (size_t) c.slot[k] * NENERGY;
                e[dashpot_lmp::NFAMILY] = 0.0;
                for (int f = 0; f < dashpot_lmp::NFAMILY; f++) {
                    e[f] = c.power[f][k];
                    e[dashpot_lmp::NFAMILY] += c.elastic[f][k];
                }
            }
        } else if (vflag_either) {
            // the wall's reaction, as a pair force between the particle and its contact point
            // on the wall, a distance r = radius - delta below its centre along n = +z
            const double r = radius[a] - c.delta[k];
            const double v[6] = {0.0, 0.0, r * c.force[3 * k + 2], 0.0, 0.0, 0.0};
            if (vflag_global)
                for (int d = 0; d < 6; d++) virial[d] += v[d];
            if (vflag_atom)
                for (int d = 0; d < 6; d++) vatom[a][d] += v[d];
        }
    }
}

/* Evaluates and applies the contacts staged in the engine, with their history in `store`. In a
 * run's setup the forces are recomputed at a state already integrated (after a restart, or
 * between runs): the laws get dt = 0, which gives the force of the stored springs, and the
 * history is not stored back (as pair granular does), or the springs would advance twice. */
void PairDashpot::evaluate(HistoryStore &store, bool wall, bool all)
{
    const bool setup = update->setupflag;
    // the forces and torques straight to the atoms, unless the virial needs them
    const bool direct = !(evflag || (wall && vflag_either));
    ApplyTarget target;
    do {
        const int n = engine.size();
        if (n == 0) return;
        target.f = atom->f[0];
        target.torque = atom->torque[0];
        target.nlocal = atom->nlocal;
        target.newton = force->newton_pair;
        try {
            ContactEngine::Chunk &c =
                engine.evaluate(store, setup ? 0.0 : update->dt, !setup, direct ? &target : nullptr);
            if (!direct || layout.adhesive || energy_flag) apply(c, n, wall, direct);
        } catch (std::exception &e) {
            fail(e, false);
        }
        engine.reset();
    } while (all);
}

void PairDashpot::compute(int eflag, int vflag)
{
    ev_init(eflag, vflag);
    if (!engine_ready) {
        engine.configure(&models, layout, engine_flags);
        engine_ready = true;
    }
    if (engine.flags().heat) {
        // LAMMPS's fix property/atom temperature heatflow: fix heat/flow zeroes heatflow before
        // the forces, sends the temperatures to the ghosts, and sums the ghosts' heatflow back
        HeatTarget heat;
        heat.temperature = atom->temperature;
        heat.heatflow = atom->heatflow;
        heat.wall_temperature = NAN;    // pair_style's zplane wall conducts no heat
        heat.nlocal = atom->nlocal;
        heat.newton = force->newton_pair;
        engine.set_heat(heat);
    }
    double **x = atom->x, **v = atom->v, **omega = atom->omega;
    const double *radius = atom->radius, *rmass = atom->rmass;
    const int *type = atom->type, *mask = atom->mask;
    const tagint *tag = atom->tag;
    const int nlocal = atom->nlocal;
    const int inum = list->inum;
    const int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    const bool hist = layout.nvalues > 0;
    const int nt1 = atom->ntypes + 1;
    const bool adh = layout.adhesive;
    const int frozen = freeze_group_bit;

    // a new list (flagged by the history fix's post_neighbor hooks: LAMMPS's count of builds
    // restarts at every run's setup, so after a run with no build in its steps, such as `run 0`,
    // the count alone would take the next setup's list for the old one)
    if ((hist || energy_flag) &&
        ((fix_history && fix_history->rebuilt) || slots_ncalls != neighbor->ncalls ||
         (wall_flag && nlocal != nwall_slots)))
        layout_slots();
    HistoryStore &ps = pair_slots;
    unsigned char *stouch = hist ? ps.touched.data() : nullptr;
    const double *sreach = adh ? ps.reach.data() : nullptr;
    // LAMMPS's per-atom 2D arrays are contiguous: index them from their first row
    const double *x0 = atom->nmax > 0 ? x[0] : nullptr, *v0 = atom->nmax > 0 ? v[0] : nullptr;
    const double *w0 = atom->nmax > 0 ? omega[0] : nullptr;
    const int *mof = model_of.data();

    // 1. Walk the neighbour list once: contacts are staged and evaluated a chunk at a time;
    // history slots follow the list (slot k = the k-th pair), and a pair that has separated
    // (beyond the reach of an adhesive law's last call) has its history zeroed.
    int k = 0;
    for (int ii = 0; ii < inum; ii++) {
        const int i = ilist[ii];
        const int jnum = numneigh[i];
        // most atoms of a dilute flow have no neighbour within the list's cutoff: nothing of
        // theirs is loaded (the per-atom loads below cost a chute more than its contacts)
        if (jnum == 0) continue;
        const int *jlist = firstneigh[i];
        const double xi = x[i][0], yi = x[i][1], zi = x[i][2], radi = radius[i];
        const tagint ti = tag[i];
        const int typei = type[i];
        for (int jj = 0; jj < jnum; jj++, k++) {
            const int j = jlist[jj] & NEIGHMASK;
            const double *xj = x0 + 3 * j;
            double dx = xi - xj[0], dy = yi - xj[1], dz = zi - xj[2];
            const double rsq = dx * dx + dy * dy + dz * dz;
            const double radj = radius[j];
            const double radsum = radi + radj;
            if (rsq >= radsum * radsum && !(adh && stouch[k] && std::sqrt(rsq) - radsum <= sreach[k])) {
                if (hist && stouch[k]) ps.zero(k);
                continue;
            }
            // orient from the lower tag, so that every rank computes a contact the same way
            int a = i, b = j, ta = typei, tb = type[j];
            double ra = radi, rb = radj;
            if (tag[j] < ti) {
                a = j;
                b = i;
                std::swap(ta, tb);
                ra = radj;
                rb = radi;
                dx = -dx;
                dy = -dy;
                dz = -dz;
            }
            const double r = std::sqrt(rsq);
            const double rinv = 1.0 / r;
            const double ma = rmass[a], mb = rmass[b];
            double meff = ma * mb / (ma + mb);
            if (mask[a] & frozen) meff = mb;
            if (mask[b] & frozen) meff = ma;
            const double *va = v0 + 3 * a, *vb = v0 + 3 * b;
            if (engine.stage(mof[ta * nt1 + tb], a, b, k, dx * rinv, dy * rinv, dz * rinv, radsum - r, ra, rb,
                             va[0] - vb[0], va[1] - vb[1], va[2] - vb[2], meff, ra * rb / radsum, w0 + 3 * a,
                             w0 + 3 * b))
                evaluate(ps, false, false);
        }
    }
    // the pairs' last chunks, not full: a chunk holds pairs or wall contacts, not both
    evaluate(ps, false, true);
    if (wall_flag) {
        HistoryStore &ws = wall_slots;
        for (int i = 0; i < nlocal; i++) {
            const int model = wall_model[type[i]];
            if (model < 0) continue;    // a type of another sub-style (pair_style hybrid)
            const double gap = x[i][2] - wall_z;
            if (gap >= radius[i] && !(adh && ws.touched[i] && gap - radius[i] <= ws.reach[i])) {
                if (hist && ws.touched[i]) ws.zero(i);
                continue;
            }
            if (engine.stage(model, i, -1, i, 0.0, 0.0, 1.0, radius[i] - gap, radius[i], 0.0, v[i][0], v[i][1],
                             v[i][2], rmass[i], radius[i], omega[i], nullptr))
                evaluate(ws, true, false);
        }
        // 2. The wall's last chunks, not full.
        evaluate(ws, true, true);
    }
    dirty = 1;
}
