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

/* Contact k of chunk c reaches past the neighbour cutoff of its pair of types: an error (a cutoff
 * given by the deck too short, or a reach beyond the margin of the one probed in init_one). */
void PairDashpot::reach_error(const ContactEngine::Chunk &c, int k)
{
    const int a = c.a[k], b = c.b[k];
    const double *radius = atom->radius;
    const double cut = key_cut[atom->type[a] * (atom->ntypes + 1) + atom->type[b]];
    error->one(FLERR,
               "pair dashpot: a contact of law '{}' reaches {} beyond touching, past the neighbour "
               "cutoff ({} for radii {} and {}): it would leave the neighbour list while it acts. It "
               "needs a cutoff of at least {} (pair_style dashpot CUTOFF, or pair_coeff's cutoff "
               "keyword; without one, the cutoff covers 1.5 times the reach probed at the largest radii)",
               models.spec(models.model(c.model[k]).spec).law[dashpot_lmp::NORMAL].name, c.reach[k], cut,
               radius[a], radius[b], radius[a] + radius[b] + c.reach[k]);
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

/* Stages the n touching pairs collected in `candidates` (and evaluates every chunk they fill):
 * first their distances, square roots and divisions independent of one another, then the
 * contacts, oriented from the atom of the lower tag. */
void PairDashpot::stage_pairs(int n)
{
    if (n == 0) return;
    const Candidates &cd = candidates;
    const int *ci = cd.i.data(), *cj = cd.j.data(), *ck = cd.k.data();
    double *cr = candidates.r.data(), *cinv = candidates.rinv.data();
    for (int q = 0; q < n; q++) {
        cr[q] = std::sqrt(cr[q]);
        cinv[q] = 1.0 / cr[q];
    }
    const double *radius = atom->radius, *rmass = atom->rmass;
    const int *type = atom->type, *mask = atom->mask;
    const tagint *tag = atom->tag;
    // LAMMPS's per-atom 2D arrays are contiguous: index them from their first row
    const double *x0 = atom->x[0], *v0 = atom->v[0], *w0 = atom->omega[0];
    const int *mof = model_of.data();
    const int nt1 = atom->ntypes + 1;
    const int frozen = freeze_group_bit;
    for (int q = 0; q < n; q++) {
        const int i = ci[q], j = cj[q];
        // the same bits from either side: x_b - x_a is exactly -(x_a - x_b)
        const bool swap = tag[j] < tag[i];
        const int a = swap ? j : i, b = swap ? i : j;
        const double *xa = x0 + 3 * a, *xb = x0 + 3 * b;
        const double dx = xa[0] - xb[0], dy = xa[1] - xb[1], dz = xa[2] - xb[2];
        const double ra = radius[a], rb = radius[b];
        const double radsum = ra + rb;
        const double r = cr[q], rinv = cinv[q];
        const double ma = rmass[a], mb = rmass[b];
        double meff = ma * mb / (ma + mb);
        if (frozen) {
            if (mask[a] & frozen) meff = mb;
            if (mask[b] & frozen) meff = ma;
        }
        const double *va = v0 + 3 * a, *vb = v0 + 3 * b;
        if (engine.stage(mof[type[a] * nt1 + type[b]], a, b, ck[q], dx * rinv, dy * rinv, dz * rinv, radsum - r, ra,
                         rb, va[0] - vb[0], va[1] - vb[1], va[2] - vb[2], meff, ra * rb / radsum, w0 + 3 * a,
                         w0 + 3 * b))
            evaluate(pair_slots, false, false);
    }
}

/* The touching pairs among atom i's jnum neighbours (slots k0 ..): appended to the candidates
 * from n on, without a branch on each outcome; a pair that no longer touches (nor reaches,
 * ADH: within an adhesive law's last reach) has its history zeroed (HIST). Returns the new n. */
template <bool ADH, bool HIST>
static int find_touching(const int *__restrict jlist, int jnum, int i, int k0, const double *xi, double radi,
                         const double *__restrict x0, const double *__restrict radius,
                         const unsigned char *__restrict stouch, const double *__restrict sreach,
                         int *__restrict ci, int *__restrict cj, int *__restrict ck, double *__restrict crsq, int n,
                         HistoryStore &ps)
{
    const double x = xi[0], y = xi[1], z = xi[2];
    for (int jj = 0; jj < jnum; jj++) {
        const int j = jlist[jj] & NEIGHMASK;
        const double *xj = x0 + 3 * j;
        const double dx = x - xj[0], dy = y - xj[1], dz = z - xj[2];
        const double rsq = dx * dx + dy * dy + dz * dz;
        const double radsum = radi + radius[j];
        int touch = rsq < radsum * radsum;
        const int k = k0 + jj;
        if (ADH && stouch[k] > touch) touch = std::sqrt(rsq) - radsum <= sreach[k];
        ci[n] = i;
        cj[n] = j;
        ck[n] = k;
        crsq[n] = rsq;
        n += touch;
        // one test, true only for a record left by a contact that has ended (rare)
        if (HIST && stouch[k] > touch) ps.zero(k);
    }
    return n;
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
    const int *type = atom->type;
    const int nlocal = atom->nlocal;
    const int inum = list->inum;
    const int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    const bool hist = layout.nvalues > 0;
    const bool adh = layout.adhesive;

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
    const double *x0 = atom->nmax > 0 ? x[0] : nullptr;

    // 1. Walk the neighbour list once: contacts are staged and evaluated a chunk at a time;
    // history slots follow the list (slot k = the k-th pair), and a pair that has separated
    // (beyond the reach of an adhesive law's last call) has its history zeroed. The walk
    // collects the touching pairs of several atoms without branching on each outcome (in a
    // dilute flow most listed pairs do not touch, and which do is unpredictable); then their
    // distances (square roots and divisions, independent of one another) and their staging.
    Candidates &cd = candidates;
    int nc = 0;
    int k0 = 0;
    for (int ii = 0; ii < inum; ii++) {
        const int i = ilist[ii];
        const int jnum = numneigh[i];
        // most atoms of a dilute flow have no neighbour within the list's cutoff: nothing of
        // theirs is loaded (the per-atom loads below cost a chute more than its contacts)
        if (jnum == 0) continue;
        if (nc + jnum > (int) cd.i.size()) {
            stage_pairs(nc);
            nc = 0;
            if (jnum > (int) cd.i.size()) cd.resize(jnum);
        }
        const int *jlist = firstneigh[i];
        int *ci = cd.i.data(), *cj = cd.j.data(), *ck = cd.k.data();
        double *crsq = cd.r.data();
        if (adh)
            nc = find_touching<true, true>(jlist, jnum, i, k0, x0 + 3 * i, radius[i], x0, radius, stouch, sreach, ci,
                                           cj, ck, crsq, nc, ps);
        else if (hist)
            nc = find_touching<false, true>(jlist, jnum, i, k0, x0 + 3 * i, radius[i], x0, radius, stouch, sreach, ci,
                                            cj, ck, crsq, nc, ps);
        else
            nc = find_touching<false, false>(jlist, jnum, i, k0, x0 + 3 * i, radius[i], x0, radius, stouch, sreach,
                                             ci, cj, ck, crsq, nc, ps);
        k0 += jnum;
    }
    stage_pairs(nc);
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
