/* pair_style dashpot: the forces of a step (see pair_dashpot.h). The neighbour list is walked
 * once; contacts are staged in structure-of-arrays chunks and evaluated by one batch call per
 * family and kind of pair, then their forces, torques and history are applied in one pass. */
#include "pair_dashpot.h"

#include "fix_dashpot_history.h"

#include "dashpot.h"

#include "atom.h"
#include "error.h"
#include "force.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

// contacts per batch call: the chunk's columns (about 20 doubles a contact) stay in L2 cache
static constexpr int CHUNK = 256;

void PairDashpot::Chunk::reserve(const int *ns, bool rolling, bool twisting, bool adhesive, bool energy)
{
    if (!istore.empty()) return;
    istore.resize(4 * CHUNK);
    // delta, rate, mass, rad, fn; norm, vel, ft (3 each); the families' history; vroll, froll
    // (3 each); twist, mtwist; reach; each family's power and elastic energy
    size_t per = 5 + 9 + ns[NORMAL] + ns[TANGENTIAL] + ns[ROLLING] + ns[TWISTING] + (rolling ? 6 : 0) +
        (twisting ? 2 : 0) + (adhesive ? 1 : 0) + (energy ? 2 * NFAMILY : 0);
    dstore.assign((size_t) CHUNK * per, 0.0);
    a = istore.data();
    b = a + CHUNK;
    slot = b + CHUNK;
    key = slot + CHUNK;
    double *p = dstore.data();
    auto take = [&p](int width) {
        double *q = p;
        p += (size_t) CHUNK * width;
        return q;
    };
    delta = take(1);
    rate = take(1);
    mass = take(1);
    rad = take(1);
    fn = take(1);
    norm = take(3);
    vel = take(3);
    ft = take(3);
    for (int f = 0; f < NFAMILY; f++) hist[f] = take(ns[f]);
    if (rolling) {
        vroll = take(3);
        froll = take(3);
    }
    if (twisting) {
        twist = take(1);
        mtwist = take(1);
    }
    if (adhesive) reach = take(1);
    if (energy)
        for (int f = 0; f < NFAMILY; f++) {
            power[f] = take(1);
            elastic[f] = take(1);
        }
}

void PairDashpot::Slots::assign(size_t n, const int *ns, bool adhesive)
{
    for (int f = 0; f < NFAMILY; f++) fam[f].assign(n * ns[f], 0.0);
    reach.assign(adhesive ? n : 0, 0.0);
    touched.assign(n, 0);
}

void PairDashpot::Slots::zero(size_t k, const int *ns)
{
    for (int f = 0; f < NFAMILY; f++)
        for (int q = 0; q < ns[f]; q++) fam[f][k * ns[f] + q] = 0.0;
    if (!reach.empty()) reach[k] = 0.0;
    touched[k] = 0;
}

void PairDashpot::Slots::get(size_t k, const int *ns, double *record) const
{
    for (int f = 0; f < NFAMILY; f++)
        for (int q = 0; q < ns[f]; q++) *record++ = fam[f][k * ns[f] + q];
    if (!reach.empty()) *record = reach[k];
}

void PairDashpot::Slots::set(size_t k, const int *ns, const double *record)
{
    for (int f = 0; f < NFAMILY; f++)
        for (int q = 0; q < ns[f]; q++) fam[f][k * ns[f] + q] = *record++;
    if (!reach.empty()) reach[k] = *record;
    touched[k] = 1;
}

/* Every family's batch call on contacts lo .. lo+m-1 of chunk c, all of kind `key`, in the order
 * normal → tangential → rolling → twisting, with each family's history at hist[f] and an
 * adhesive law's reach written to `reach` (the chunk's columns, or the slots themselves). In a
 * run's setup the forces are recomputed at a state already integrated (after a restart, or
 * between runs): the laws get dt = 0, which gives the force of the stored springs, and the
 * caller does not store the history back (as pair granular does), or the springs would advance
 * twice. */
void PairDashpot::run_laws(Chunk &c, int lo, int m, int key, double *const *hist, double *reach)
{
    const size_t ns = nslots[NORMAL], nt = nslots[TANGENTIAL], nr = nslots[ROLLING], nw = nslots[TWISTING];
    const double dt = update->setupflag ? 0.0 : update->dt;
    const bool en = energy_flag;
    // energy=1: each family's power and elastic energy; a law that does not report them (an
    // older sdk's) leaves NaN
    int written[NFAMILY] = {0, 0, 0, 0};
    auto pw = [&](int f) { return en ? c.power[f] + lo : nullptr; };
    auto el = [&](int f) { return en ? c.elastic[f] + lo : nullptr; };
    auto wr = [&](int f) { return en ? &written[f] : nullptr; };
    double *hn = ns ? hist[NORMAL] : nullptr;
    if (adhesive || en)
        check(dashpot_contact_model_force_batch_energy(cmodel[key], m, c.delta + lo, c.rate + lo, c.mass + lo,
                                                       c.rad + lo, hn, m * ns, c.fn + lo, adhesive ? reach : nullptr,
                                                       pw(NORMAL), el(NORMAL), wr(NORMAL)),
              "dashpot_contact_model_force_batch_energy");
    else
        check(dashpot_contact_model_force_batch(cmodel[key], m, c.delta + lo, c.rate + lo, c.mass + lo, c.rad + lo,
                                                hn, m * ns, c.fn + lo),
              "dashpot_contact_model_force_batch");
    if (tlaw) {
        double *ht = nt ? hist[TANGENTIAL] : nullptr;
        if (en)
            check(dashpot_tangential_model_force_batch_energy(tmodel[key], m, dt, c.norm + 3 * lo, c.vel + 3 * lo,
                                                              c.fn + lo, c.delta + lo, c.mass + lo, c.rad + lo, ht,
                                                              m * nt, c.ft + 3 * lo, pw(TANGENTIAL), el(TANGENTIAL),
                                                              wr(TANGENTIAL)),
                  "dashpot_tangential_model_force_batch_energy");
        else
            check(dashpot_tangential_model_force_batch(tmodel[key], m, dt, c.norm + 3 * lo, c.vel + 3 * lo, c.fn + lo,
                                                       c.delta + lo, c.mass + lo, c.rad + lo, ht, m * nt,
                                                       c.ft + 3 * lo),
                  "dashpot_tangential_model_force_batch");
    }
    if (rlaw)
        check(dashpot_rolling_model_force_batch(rmodel[key], m, dt, c.norm + 3 * lo, c.vroll + 3 * lo, c.fn + lo,
                                                c.delta + lo, c.mass + lo, c.rad + lo,
                                                nr ? hist[ROLLING] : nullptr, m * nr, c.froll + 3 * lo,
                                                pw(ROLLING), el(ROLLING), wr(ROLLING)),
              "dashpot_rolling_model_force_batch");
    if (wlaw)
        check(dashpot_twisting_model_torque_batch(wmodel[key], m, dt, c.norm + 3 * lo, c.twist + lo, c.fn + lo,
                                                  c.delta + lo, c.mass + lo, c.rad + lo,
                                                  nw ? hist[TWISTING] : nullptr, m * nw, c.mtwist + lo,
                                                  pw(TWISTING), el(TWISTING), wr(TWISTING)),
              "dashpot_twisting_model_torque_batch");
    if (en) {
        const bool present[NFAMILY] = {true, tlaw != nullptr, rlaw != nullptr, wlaw != nullptr};
        for (int f = 0; f < NFAMILY; f++)
            if (!present[f] || !written[f]) {
                std::fill(c.power[f] + lo, c.power[f] + lo + m, present[f] ? NAN : 0.0);
                std::fill(c.elastic[f] + lo, c.elastic[f] + lo + m, present[f] ? NAN : 0.0);
            }
    }
}

/* Applies the forces and torques of contacts 0 .. n-1 of chunk c and stores their history
 * back into `slots` (the list's, or the wall's), unless the laws updated it in place (`slots`
 * null); `reach` holds the adhesive law's reach of each contact. Torques: the tangential
 * force's, -r (n x F_t) on each sphere (contact point a radius from each centre: the two-body
 * driver's convention); rolling, R_eff n x F_roll on a and its opposite on b; twisting, M n on a
 * and its opposite on b (LAMMPS pair granular's). */
template <int NS, int NT, int NR> void PairDashpot::scatter(Chunk &c, int n, Slots *slots, const double *reach)
{
    const int ns = NS >= 0 ? NS : nslots[NORMAL], nt = NT >= 0 ? NT : nslots[TANGENTIAL];
    const int nr = NR >= 0 ? NR : nslots[ROLLING], nw = nslots[TWISTING];
    const bool tang = tlaw != nullptr, roll = rlaw != nullptr, twst = wlaw != nullptr, adh = adhesive;
    const bool store = slots != nullptr;
    double *f0 = atom->f[0], *t0 = atom->torque[0];    // contiguous: indexed from the first row
    const double *radius = atom->radius;
    const int nlocal = atom->nlocal;
    const int newton_pair = force->newton_pair;
    const int *ca = c.a, *cb = c.b, *cs = c.slot;
    const double *cn = c.norm, *cfn = c.fn, *cft = c.ft;
    for (int k = 0; k < n; k++) {
        const int a = ca[k], b = cb[k];
        const double nx = cn[3 * k], ny = cn[3 * k + 1], nz = cn[3 * k + 2];
        const double fn = cfn[k];
        double ftx = 0.0, fty = 0.0, ftz = 0.0;
        if (tang) {
            ftx = cft[3 * k];
            fty = cft[3 * k + 1];
            ftz = cft[3 * k + 2];
        }
        const double fx = fn * nx + ftx, fy = fn * ny + fty, fz = fn * nz + ftz;
        // n x Ft: the tangential torque on a is -ra (n x Ft), on b -rb (n x Ft)
        const double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
        // the torque on a that b receives with the opposite sign: rolling and twisting
        double mx = 0.0, my = 0.0, mz = 0.0;
        if (roll) {
            const double *fr = c.froll + 3 * k, reff = c.rad[k];
            mx = reff * (ny * fr[2] - nz * fr[1]);
            my = reff * (nz * fr[0] - nx * fr[2]);
            mz = reff * (nx * fr[1] - ny * fr[0]);
        }
        if (twst) {
            const double m = c.mtwist[k];
            mx += m * nx;
            my += m * ny;
            mz += m * nz;
        }
        if (a < nlocal || newton_pair) {
            const double ra = radius[a];
            double *fa = f0 + 3 * a, *ta = t0 + 3 * a;
            fa[0] += fx;
            fa[1] += fy;
            fa[2] += fz;
            ta[0] += mx - ra * cx;
            ta[1] += my - ra * cy;
            ta[2] += mz - ra * cz;
        }
        if (b >= 0) {
            if (b < nlocal || newton_pair) {
                const double rb = radius[b];
                double *fb = f0 + 3 * b, *tb = t0 + 3 * b;
                fb[0] -= fx;
                fb[1] -= fy;
                fb[2] -= fz;
                tb[0] -= mx + rb * cx;
                tb[1] -= my + rb * cy;
                tb[2] -= mz + rb * cz;
            }
            if (evflag) {
                double r = radius[a] + radius[b] - c.delta[k];
                ev_tally_xyz(a, b, nlocal, newton_pair, 0.0, 0.0, fx, fy, fz, nx * r, ny * r, nz * r);
            }
            // an adhesive contact must stay in the neighbour list as long as it acts
            if (adh && radius[a] + radius[b] + reach[k] > key_cut[c.key[k]])
                error->one(FLERR,
                           "pair dashpot: a contact of law '{}' reaches {} m beyond touching, past the neighbour "
                           "cutoff ({} m for radii {} and {} m): its reach depends on more than the radii it was "
                           "probed at",
                           law_name[NORMAL], reach[k], key_cut[c.key[k]], radius[a], radius[b]);
        } else if (vflag_either) {
            // the wall's reaction, as a pair force between the particle and its contact point
            // on the wall, a distance r = radius - delta below its centre along n = +z
            double r = radius[a] - c.delta[k];
            double v[6] = {0.0, 0.0, r * fz, 0.0, 0.0, 0.0};
            if (vflag_global)
                for (int d = 0; d < 6; d++) virial[d] += v[d];
            if (vflag_atom)
                for (int d = 0; d < 6; d++) vatom[a][d] += v[d];
        }
        if (store) {
            const size_t s = cs[k];
            for (int q = 0; q < ns; q++) slots->fam[NORMAL][s * ns + q] = c.hist[NORMAL][k * ns + q];
            for (int q = 0; q < nt; q++) slots->fam[TANGENTIAL][s * nt + q] = c.hist[TANGENTIAL][k * nt + q];
            for (int q = 0; q < nr; q++) slots->fam[ROLLING][s * nr + q] = c.hist[ROLLING][k * nr + q];
            for (int q = 0; q < nw; q++) slots->fam[TWISTING][s * nw + q] = c.hist[TWISTING][k * nw + q];
            if (adh) slots->reach[s] = reach[k];
            slots->touched[s] = 1;
        }
        if (energy_flag && b >= 0) {
            double *e = slot_energy.data() + (size_t) cs[k] * NENERGY;
            e[NFAMILY] = 0.0;
            for (int f = 0; f < NFAMILY; f++) {
                e[f] = c.power[f][k];
                e[NFAMILY] += c.elastic[f][k];
            }
        }
    }
}

/* Copies the history of the n staged contacts from their slots into the chunk's columns. */
template <int NS, int NT, int NR> void PairDashpot::gather(int n, const Slots &slots)
{
    const int ns = NS >= 0 ? NS : nslots[NORMAL], nt = NT >= 0 ? NT : nslots[TANGENTIAL];
    const int nr = NR >= 0 ? NR : nslots[ROLLING], nw = nslots[TWISTING];
    const int *cs = stage.slot;
    for (int k = 0; k < n; k++) {
        const size_t s = cs[k];
        for (int q = 0; q < ns; q++) stage.hist[NORMAL][k * ns + q] = slots.fam[NORMAL][s * ns + q];
        for (int q = 0; q < nt; q++) stage.hist[TANGENTIAL][k * nt + q] = slots.fam[TANGENTIAL][s * nt + q];
        for (int q = 0; q < nr; q++) stage.hist[ROLLING][k * nr + q] = slots.fam[ROLLING][s * nr + q];
        for (int q = 0; q < nw; q++) stage.hist[TWISTING][k * nw + q] = slots.fam[TWISTING][s * nw + q];
    }
}

/* Orders the n staged contacts by kind of pair into `sorted` (a counting sort); key_count
 * then holds where each kind starts. */
void PairDashpot::sort_chunk(int n)
{
    const int nk = (int) cmodel.size();
    key_count.assign(nk + 1, 0);
    for (int k = 0; k < n; k++) key_count[stage.key[k] + 1]++;
    for (int q = 0; q < nk; q++) key_count[q + 1] += key_count[q];
    key_next.assign(key_count.begin(), key_count.end() - 1);
    Chunk &d = sorted;
    // each column of `width` values per contact, moved to the contact's sorted place
    std::vector<int> &place = sort_place;    // reused: no allocation per step
    place.resize(n);
    for (int k = 0; k < n; k++) place[k] = key_next[stage.key[k]]++;
    auto move = [&](const double *src, double *dst, int width) {
        if (width == 0 || !src) return;
        for (int k = 0; k < n; k++)
            for (int q = 0; q < width; q++) dst[(size_t) place[k] * width + q] = src[(size_t) k * width + q];
    };
    for (int k = 0; k < n; k++) {
        const int p = place[k];
        d.a[p] = stage.a[k];
        d.b[p] = stage.b[k];
        d.slot[p] = stage.slot[k];
        d.key[p] = stage.key[k];
    }
    move(stage.delta, d.delta, 1);
    move(stage.rate, d.rate, 1);
    move(stage.mass, d.mass, 1);
    move(stage.rad, d.rad, 1);
    move(stage.norm, d.norm, 3);
    move(stage.vel, d.vel, 3);
    move(stage.vroll, d.vroll, 3);
    move(stage.twist, d.twist, 1);
    for (int f = 0; f < NFAMILY; f++) move(stage.hist[f], d.hist[f], nslots[f]);
}

/* Evaluates the n contacts staged in `stage`: one batch call per family and kind of pair
 * present (when there are several, through a counting sort into `sorted`), then forces,
 * torques and history. */
template <int NS, int NT, int NR> void PairDashpot::evaluate(int n, bool mixed, bool wall)
{
    if (n == 0) return;
    Slots &sl = wall ? wall_slots : pair_slots;
    const bool keep = nvalues > 0 && !update->setupflag;    // in a run's setup the history must not advance
    // Contacts of consecutive slots (a pile: every pair of the list touches): the laws read and
    // write the slots in place, each family its own array.
    const int slot0 = stage.slot[0];
    if (keep && !mixed && stage.slot[n - 1] - slot0 == n - 1) {
        double *h[NFAMILY];
        for (int f = 0; f < NFAMILY; f++) h[f] = nslots[f] ? sl.fam[f].data() + (size_t) slot0 * nslots[f] : nullptr;
        double *reach = adhesive ? sl.reach.data() + slot0 : nullptr;
        run_laws(stage, 0, n, stage.key[0], h, reach);
        scatter<NS, NT, NR>(stage, n, nullptr, reach);
        std::memset(sl.touched.data() + slot0, 1, n);
        return;
    }
    if (nvalues > 0) gather<NS, NT, NR>(n, sl);
    Chunk &c = mixed ? sorted : stage;
    if (mixed) sort_chunk(n);
    const int nk = mixed ? (int) cmodel.size() : 1;
    for (int q = 0; q < nk; q++) {
        const int lo = mixed ? key_count[q] : 0, m = mixed ? key_count[q + 1] - lo : n;
        if (m == 0) continue;
        double *h[NFAMILY];
        for (int f = 0; f < NFAMILY; f++) h[f] = c.hist[f] + (size_t) lo * nslots[f];
        run_laws(c, lo, m, mixed ? q : c.key[0], h, adhesive ? c.reach + lo : nullptr);
    }
    scatter<NS, NT, NR>(c, n, keep ? &sl : nullptr, c.reach);
}

void PairDashpot::compute(int eflag, int vflag)
{
    ev_init(eflag, vflag);
    const int ns = nslots[NORMAL], nt = nslots[TANGENTIAL], nr = nslots[ROLLING];
    // the history widths of the common laws (hsd; thornton; mindlin, linear-history; rolling
    // sds) as constants
    if (ns == 0 && nt == 4 && nr == 3)
        compute_t<0, 4, 3>();
    else if (ns == 0 && nt == 4 && nr == 0)
        compute_t<0, 4, 0>();
    else if (ns == 0 && nt == 3 && nr == 0)
        compute_t<0, 3, 0>();
    else if (ns == 0 && nt == 0 && nr == 0)
        compute_t<0, 0, 0>();
    else if (ns == 1 && nt == 4 && nr == 0)
        compute_t<1, 4, 0>();
    else if (ns == 1 && nt == 0 && nr == 0)
        compute_t<1, 0, 0>();
    else
        compute_t<-1, -1, -1>();
}

/* The step's forces, with the normal, tangential and rolling history slot counts known at
 * compile time for the common laws (NS, NT, NR < 0: read at run time). */
template <int NS, int NT, int NR> void PairDashpot::compute_t()
{
    double **x = atom->x, **v = atom->v, **omega = atom->omega;
    const double *radius = atom->radius, *rmass = atom->rmass;
    const int *type = atom->type;
    const tagint *tag = atom->tag;
    const int nlocal = atom->nlocal;
    const int inum = list->inum;
    const int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    const int nv = nvalues;
    const int ntp1 = atom->ntypes + 1;
    const int wall_key0 = ntp1 * ntp1;
    const bool roll = rlaw != nullptr, twst = wlaw != nullptr, adh = adhesive;

    // a new list (flagged by the history fix's post_neighbor hooks: LAMMPS's count of builds
    // restarts at every run's setup, so after a run with no build in its steps, such as `run 0`,
    // the count alone would take the next setup's list for the old one)
    if ((nv > 0 || energy_flag) &&
        ((fix_history && fix_history->rebuilt) || slots_ncalls != neighbor->ncalls ||
         (wall_flag && nlocal != nwall_slots)))
        layout_slots();
    Slots &ps = pair_slots;
    unsigned char *stouch = nv > 0 ? ps.touched.data() : nullptr;
    const double *sreach = adh ? ps.reach.data() : nullptr;
    stage.reserve(nslots, roll, twst, adh, energy_flag);
    sorted.reserve(nslots, roll, twst, adh, energy_flag);
    // LAMMPS's per-atom 2D arrays are contiguous: index them from their first row
    const double *x0 = atom->nmax > 0 ? x[0] : nullptr, *v0 = atom->nmax > 0 ? v[0] : nullptr;
    const double *w0 = atom->nmax > 0 ? omega[0] : nullptr;

    // The staging columns, as local pointers the compiler can keep in registers.
    int *__restrict ca = stage.a, *__restrict cb = stage.b, *__restrict cs = stage.slot, *__restrict ck = stage.key;
    double *__restrict cdelta = stage.delta, *__restrict crate = stage.rate, *__restrict cmass = stage.mass;
    double *__restrict crad = stage.rad, *__restrict cnorm = stage.norm, *__restrict cvel = stage.vel;
    double *__restrict cvroll = stage.vroll, *__restrict ctwist = stage.twist;
    int n = 0, key0 = -1;
    bool mixed = false;

    // Stages contact (a, b) (b < 0: the wall) of kind `key` and history slot s (its values are
    // read at evaluation); n points from b to a, dv = v_a - v_b, ra and rb are the distances
    // from the centres to the contact point (the two-body driver's convention; rb = 0 for the
    // wall), reff the effective radius (the rolling velocity's arm).
    auto stage_contact = [&](int key, int a, int b, int s, double nx, double ny, double nz, double delta,
                             double ra, double rb, double dvx, double dvy, double dvz, double meff, double reff,
                             const double *wa, const double *wb) __attribute__((always_inline))
    {
        if (n == 0) key0 = key;
        mixed |= key != key0;
        ca[n] = a;
        cb[n] = b;
        cs[n] = s;
        ck[n] = key;
        cdelta[n] = delta;
        cmass[n] = meff;
        crad[n] = reff;
        crate[n] = -(dvx * nx + dvy * ny + dvz * nz);
        double *cn = cnorm + 3 * n;
        cn[0] = nx;
        cn[1] = ny;
        cn[2] = nz;
        // relative velocity of a's contact point with respect to b's
        double wx = ra * wa[0], wy = ra * wa[1], wz = ra * wa[2];
        if (wb) {
            wx += rb * wb[0];
            wy += rb * wb[1];
            wz += rb * wb[2];
        }
        double *cv = cvel + 3 * n;
        cv[0] = dvx - (wy * nz - wz * ny);
        cv[1] = dvy - (wz * nx - wx * nz);
        cv[2] = dvz - (wx * ny - wy * nx);
        if (roll || twst) {
            // the relative spin w_a - w_b: rolling velocity reff (w_a - w_b) x n, twisting rate
            // (w_a - w_b).n (LAMMPS pair granular's definitions)
            double rx = wa[0], ry = wa[1], rz = wa[2];
            if (wb) {
                rx -= wb[0];
                ry -= wb[1];
                rz -= wb[2];
            }
            if (roll) {
                double *vr = cvroll + 3 * n;
                vr[0] = reff * (ry * nz - rz * ny);
                vr[1] = reff * (rz * nx - rx * nz);
                vr[2] = reff * (rx * ny - ry * nx);
            }
            if (twst) ctwist[n] = rx * nx + ry * ny + rz * nz;
        }
        if (++n == CHUNK) {
            evaluate<NS, NT, NR>(n, mixed, b < 0);
            n = 0;
            mixed = false;
        }
    };

    // 1. Walk the neighbour list once: contacts are staged and evaluated a chunk at a time;
    // history slots follow the list (slot k = the k-th pair), and a pair that has separated
    // (beyond the reach of an adhesive law's last call) has its history zeroed.
    int k = 0;
    for (int ii = 0; ii < inum; ii++) {
        const int i = ilist[ii];
        const int *jlist = firstneigh[i];
        const int jnum = numneigh[i];
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
                if (nv > 0 && stouch[k]) ps.zero(k, nslots);
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
            const double ma = rmass[a], mb = rmass[b], msum = ma + mb;
            // 1/r, 1/(ma + mb) and 1/(ra + rb) from one division
            const double inv = 1.0 / (r * msum * radsum);
            const double rinv = inv * msum * radsum;
            const double *va = v0 + 3 * a, *vb = v0 + 3 * b;
            stage_contact(ta * ntp1 + tb, a, b, k, dx * rinv, dy * rinv, dz * rinv, radsum - r, ra, rb,
                          va[0] - vb[0], va[1] - vb[1], va[2] - vb[2], ma * mb * (inv * r * radsum),
                          ra * rb * (inv * r * msum), w0 + 3 * a, w0 + 3 * b);
        }
    }
    // the pairs' last chunk, not full: a chunk holds pairs or wall contacts, not both
    evaluate<NS, NT, NR>(n, mixed, false);
    n = 0;
    mixed = false;
    if (wall_flag) {
        for (int i = 0; i < nlocal; i++) {
            const double gap = x[i][2] - wall_z;
            Slots &ws = wall_slots;
            if (gap >= radius[i] && !(adh && ws.touched[i] && gap - radius[i] <= ws.reach[i])) {
                if (nv > 0 && ws.touched[i]) ws.zero(i, nslots);
                continue;
            }
            stage_contact(wall_key0 + type[i], i, -1, i, 0.0, 0.0, 1.0, radius[i] - gap, radius[i], 0.0, v[i][0],
                          v[i][1], v[i][2], rmass[i], radius[i], omega[i], nullptr);
        }
    }
    // 2. The wall's last chunk, not full.
    evaluate<NS, NT, NR>(n, mixed, true);
    if (nv > 0) fix_history->stale = 1;
}
