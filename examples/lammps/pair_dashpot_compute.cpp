/* pair_style dashpot: the forces of a step (see pair_dashpot.h). The neighbour list is walked
 * once; contacts are staged in the engine's chunks and evaluated by one batch call per family
 * and bound model, then their forces, torques and history are applied. */
#include "pair_dashpot.h"

#include "dashpot_simd_geom.h"
#include "fix_dashpot_history.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
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
    Candidate *cand = candidates.data();
    if (walked_slots) {
        // walk_slots() left each touching pair's slot only: its atoms are the slot's
        const SlotPair *sp = slot_pairs.data();
        for (int q = 0; q < n; q++) {
            const SlotPair p = sp[cand[q].k];
            cand[q].i = p.i;
            cand[q].j = p.j;
        }
    }
    for (int q = 0; q < n; q++) {
        const double r = std::sqrt(cand[q].r);
        cand[q].r = r;
        cand[q].rinv = 1.0 / r;
    }
    // one bound model (every deck with one set of laws): no lookup of the pair's types
    if (models.nmodels() == 1)
        stage_pairs_of<true>(n);
    else
        stage_pairs_of<false>(n);
}

/* One touching pair's geometry as the engine stages it, from its atoms i, j, slot k, distance r
 * and its inverse: oriented from the atom of the lower tag (the same bits from either side: x_b
 * - x_a is exactly -(x_a - x_b)). ONE: one bound model, no lookup of the pair's types. */
template <bool ONE> struct PairDashpot::PairGeometry {
    const double *radius, *rmass, *x0, *v0, *w0;    // LAMMPS's per-atom 2D arrays are contiguous
    const int *type, *mask, *mof;
    const tagint *tag;
    int nt1, frozen;
    PairGeometry(const PairDashpot &p) :
        radius(p.atom->radius), rmass(p.atom->rmass), x0(p.atom->x[0]), v0(p.atom->v[0]), w0(p.atom->omega[0]),
        type(p.atom->type), mask(p.atom->mask), mof(p.model_of.data()), tag(p.atom->tag), nt1(p.atom->ntypes + 1),
        frozen(p.freeze_group_bit)
    {
    }
    inline void operator()(int i, int j, int k, double r, double rinv, ContactEngine::Geometry &g) const
        __attribute__((always_inline))
    {
        const bool swap = tag[j] < tag[i];
        const int a = swap ? j : i, b = swap ? i : j;
        const double *xa = x0 + 3 * a, *xb = x0 + 3 * b;
        const double dx = xa[0] - xb[0], dy = xa[1] - xb[1], dz = xa[2] - xb[2];
        const double ra = radius[a], rb = radius[b];
        const double radsum = ra + rb;
        const double ma = rmass[a], mb = rmass[b];
        double meff = ma * mb / (ma + mb);
        if (frozen) {
            if (mask[a] & frozen) meff = mb;
            if (mask[b] & frozen) meff = ma;
        }
        const double *va = v0 + 3 * a, *vb = v0 + 3 * b;
        g.model = ONE ? 0 : mof[type[a] * nt1 + type[b]];
        g.a = a;
        g.b = b;
        g.slot = k;
        g.nx = dx * rinv;
        g.ny = dy * rinv;
        g.nz = dz * rinv;
        g.delta = radsum - r;
        g.ra = ra;
        g.rb = rb;
        g.dvx = va[0] - vb[0];
        g.dvy = va[1] - vb[1];
        g.dvz = va[2] - vb[2];
        g.meff = meff;
        g.reff = ra * rb / radsum;
        g.wa = w0 + 3 * a;
        g.wb = w0 + 3 * b;
    }
};

template <bool ONE> void PairDashpot::stage_pairs_of(int n)
{
    const Candidate *__restrict cand = candidates.data();
    const PairGeometry<ONE> pg(*this);
    // one run of contacts per chunk: the engine keeps its columns in registers over the run
    auto geometry = [&](int q, ContactEngine::Geometry &g) __attribute__((always_inline))
    {
        const Candidate &cq = cand[q];
        pg(cq.i, cq.j, cq.k, cq.r, cq.rinv, g);
    };
    for (int q = 0; q < n;) {
        q = engine.stage_run(q, n, geometry);
        if (q < n || engine.size() == ContactEngine::CHUNK) evaluate(pair_slots, false, false);
    }
}

/* The slots laid out for the list (with history or energy), walked four at a time in AVX2
 * (see dashpot_simd_geom.h): a block of slots' touching pairs found, then staged at once, their atoms still
 * in cache; with one bound model (ONE) and neither the rolling nor the twisting columns, staged
 * four at a time in AVX2 too. The same candidates in the same order, the same columns with the
 * same bits, as walk_slots() and stage_pairs(). */
template <bool ONE> void PairDashpot::walk_stage_simd(bool hist, bool adh)
{
    const int nslot = (int) pair_slots.size();
    if (nslot == 0) return;
    constexpr int BLOCK = 512;
    if (touching.size() < BLOCK + 4) touching.resize(BLOCK + 4);
    if (ended.size() < BLOCK) ended.resize(BLOCK);
    static_assert(sizeof(SlotPair) == 2 * sizeof(int), "a slot's pair: two ints");
    static_assert(sizeof(tagint) == sizeof(int), "tags: ints (LAMMPS_SMALLBIG)");
    const int *pairs = reinterpret_cast<const int *>(slot_pairs.data());
    HistoryStore &ps = pair_slots;
    const simd_geom::Slots slots = {pairs, atom->x[0], atom->radius, hist ? ps.touched.data() : nullptr,
                                    adh ? ps.reach.data() : nullptr};
    const simd_geom::Atoms at = {pairs,       atom->x[0], atom->v[0], atom->omega[0], atom->radius,
                                 atom->rmass, atom->tag,  atom->mask, freeze_group_bit};
    const int *kq = touching.data();
    const PairGeometry<ONE> pg(*this);
    // the scalar staging: a block's last pairs (fewer than 4, or the rows that end a chunk), or
    // all of them (several models, spin columns)
    auto geometry = [&](int q, ContactEngine::Geometry &g) __attribute__((always_inline))
    {
        const int k = kq[q], i = pairs[2 * k], j = pairs[2 * k + 1];
        const double *xi = at.x0 + 3 * i, *xj = at.x0 + 3 * j;
        const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
        const double r = std::sqrt(dx * dx + dy * dy + dz * dz);
        pg(i, j, k, r, 1.0 / r, g);
    };
    for (int k0 = 0; k0 < nslot; k0 += BLOCK) {
        int nz = 0;
        const int n = simd_geom::walk(slots, k0, std::min(nslot, k0 + BLOCK), touching.data(), ended.data(), nz);
        for (int q = 0; q < nz; q++) ps.zero(ended[q]);
        for (int q = 0; q < n;) {
            int *iv, k;
            double *dv;
            if (ONE && engine.columns(iv, dv, k)) {
                const int m = std::min(ContactEngine::CHUNK - k, n - q) & ~3;
                if (m > 0) {
                    simd_geom::stage(at, kq + q, m, 0, iv, dv, k);
                    engine.staged(m, 0);
                    q += m;
                }
            }
            q = engine.stage_run(q, n, geometry);
            if (q < n || engine.size() == ContactEngine::CHUNK) evaluate(pair_slots, false, false);
        }
    }
}

/* The walk of the neighbour list's atoms `atoms` (natoms of them, in list order) for a deck with
 * neither history nor energy (with either, walk_slots() walks the slots laid out for the list):
 * each atom's touching pairs are collected as candidates without a branch on each outcome, and
 * staged whenever the next atom's pairs could overflow the candidates. One loop nest with
 * everything in registers (an atom in a dilute flow has one or two listed pairs: the per-atom
 * cost counts). Returns the number of candidates left to stage. */
int PairDashpot::walk_pairs(const int *atoms, int natoms)
{
    if (natoms == 0) return 0;
    const int *__restrict numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    const double *__restrict x0 = atom->x[0];
    const double *__restrict radius = atom->radius;
    int cap = (int) candidates.size();
    Candidate *__restrict cand = candidates.data();
    int n = 0, k = 0;
    for (int ii = 0; ii < natoms; ii++) {
        const int i = atoms[ii];
        const int jnum = numneigh[i];
        // most atoms of a dilute flow have no neighbour within the list's cutoff: nothing of
        // theirs is loaded
        if (jnum == 0) continue;
        if (n + jnum > cap) {
            stage_pairs(n);
            n = 0;
            if (jnum > cap) candidates.resize(jnum);
            cap = (int) candidates.size();
            cand = candidates.data();
        }
        const int *__restrict jl = firstneigh[i];
        const double x = x0[3 * i], y = x0[3 * i + 1], z = x0[3 * i + 2], radi = radius[i];
        for (const int *jend = jl + jnum; jl < jend; jl++, k++) {
            const int j = *jl & NEIGHMASK;
            const double *xj = x0 + 3 * j;
            const double dx = x - xj[0], dy = y - xj[1], dz = z - xj[2];
            const double rsq = dx * dx + dy * dy + dz * dz;
            const double radsum = radi + radius[j];
            cand[n].i = i;
            cand[n].j = j;
            cand[n].k = k;
            cand[n].r = rsq;
            n += rsq < radsum * radsum;
        }
    }
    return n;
}

/* walk_pairs over the slots laid out for this list (with history or energy): one flat loop over
 * the slots' pairs, a block of candidates at a time, with no per-atom work. The same pairs in the
 * same order as walk_pairs, hence the same candidates. */
template <bool ADH, bool HIST> int PairDashpot::walk_slots()
{
    const int nslot = (int) pair_slots.size();
    if (nslot == 0) return 0;
    constexpr int BLOCK = 512;
    if (candidates.size() < BLOCK) candidates.resize(BLOCK);
    if (ended.size() < BLOCK) ended.resize(BLOCK);
    const int cap = (int) candidates.size();
    const SlotPair *__restrict sp = slot_pairs.data();
    const double *__restrict x0 = atom->x[0];
    const double *__restrict radius = atom->radius;
    HistoryStore &ps = pair_slots;
    const unsigned char *__restrict stouch = HIST ? ps.touched.data() : nullptr;
    const double *__restrict sreach = ADH ? ps.reach.data() : nullptr;
    Candidate *const cand = candidates.data();
    int *__restrict zk = ended.data();
    int n = 0;
    for (int k0 = 0; k0 < nslot; k0 += BLOCK) {
        const int k1 = std::min(nslot, k0 + BLOCK);
        if (n + (k1 - k0) > cap) {
            stage_pairs(n);
            n = 0;
        }
        int nz = 0;
        Candidate *__restrict cp = cand + n;    // the next candidate
        for (int k = k0; k < k1; k++) {
            const ptrdiff_t i = sp[k].i, j = sp[k].j;
            const double *xi = x0 + 3 * i, *xj = x0 + 3 * j;
            const double dx = xi[0] - xj[0], dy = xi[1] - xj[1], dz = xi[2] - xj[2];
            const double rsq = dx * dx + dy * dy + dz * dz;
            const double radsum = radius[i] + radius[j];
            int touch = rsq < radsum * radsum;
            if (ADH && stouch[k] > touch) touch = std::sqrt(rsq) - radsum <= sreach[k];
            // the slot only (stage_pairs() reads its atoms back from slot_pairs)
            cp->k = k;
            cp->r = rsq;
            cp += touch;
            // one test, true only for a record left by a contact that has ended (rare): zeroed
            // after the loop, which then calls nothing
            if (HIST && stouch[k] > touch) zk[nz++] = k;
        }
        n = (int) (cp - cand);
        for (int q = 0; q < nz; q++) ps.zero(zk[q]);
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
    const int *ilist = list->ilist;
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

    // 1. Walk the neighbour list once: contacts are staged and evaluated a chunk at a time;
    // history slots follow the list (slot k = the k-th pair), and a pair that has separated
    // (beyond the reach of an adhesive law's last call) has its history zeroed. The walk
    // collects the touching pairs of several atoms without branching on each outcome (in a
    // dilute flow most listed pairs do not touch, and which do is unpredictable); then their
    // distances (square roots and divisions, independent of one another) and their staging.
    // With history (or energy), layout_slots() listed the atoms that have pairs, in list order:
    // the walk skips the others (most atoms of a dilute flow), whose slots are none.
    // On an AVX2 CPU (unless DASHPOT_LMP_SIMD=0), the slots are walked (and, with one model,
    // staged) four at a time.
    int nc;
    walked_slots = hist || energy_flag;
    if (walked_slots && simd_geom::enabled()) {
        // four slots at a time (AVX2)
        if (models.nmodels() == 1)
            walk_stage_simd<true>(hist, adh);
        else
            walk_stage_simd<false>(hist, adh);
        nc = 0;
    } else if (walked_slots) {
        // the slots laid out for this list: one flat loop over their pairs
        if (adh)
            nc = walk_slots<true, true>();
        else if (hist)
            nc = walk_slots<false, true>();
        else
            nc = walk_slots<false, false>();
    } else {
        nc = walk_pairs(ilist, inum);
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
