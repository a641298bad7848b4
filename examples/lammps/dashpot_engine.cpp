/* The contact engine: see dashpot_engine.h. */
#include "dashpot_engine.h"
#include "dashpot_simd.h"
#include "dashpot_simd_torq.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <utility>

namespace dashpot_lmp {

void HistoryStore::assign(size_t n, const Layout &lay)
{
    layout = lay;
    for (int f = 0; f < NFAMILY; f++) fam[f].assign(n * lay.width[f], 0.0);
    reach.assign(lay.adhesive ? n : 0, 0.0);
    touched.assign(n, 0);
}

void HistoryStore::zero(size_t k)
{
    for (int f = 0; f < NFAMILY; f++) {
        const int w = layout.width[f];
        std::fill(fam[f].begin() + k * w, fam[f].begin() + (k + 1) * w, 0.0);
    }
    if (!reach.empty()) reach[k] = 0.0;
    touched[k] = 0;
}

/* dst[0 .. w) = src[0 .. w): a record's family holds a few values (3 for a tangential or
 * rolling spring), too few for a general loop's set-up to pay. */
static inline void copy_values(double *__restrict dst, const double *__restrict src, int w)
{
    if (w == 3) {
        dst[0] = src[0];
        dst[1] = src[1];
        dst[2] = src[2];
        return;
    }
    for (int q = 0; q < w; q++) dst[q] = src[q];
}

void HistoryStore::get(size_t k, double *record) const
{
    for (int f = 0; f < NFAMILY; f++) {
        const int w = layout.width[f];
        if (w == 0) continue;
        copy_values(record, fam[f].data() + k * w, w);
        record += w;
    }
    if (!reach.empty()) *record = reach[k];
}

void HistoryStore::set(size_t k, const double *record)
{
    for (int f = 0; f < NFAMILY; f++) {
        const int w = layout.width[f];
        if (w == 0) continue;
        copy_values(fam[f].data() + k * w, record, w);
        record += w;
    }
    if (!reach.empty()) reach[k] = *record;
    touched[k] = 1;
}

bool HistoryStore::nonzero(size_t k) const
{
    if (!touched[k]) return false;
    for (int f = 0; f < NFAMILY; f++) {
        const int w = layout.width[f];
        for (int q = 0; q < w; q++)
            if (fam[f][k * w + q] != 0.0) return true;
    }
    return !reach.empty() && reach[k] != 0.0;
}

void ContactEngine::Chunk::reserve(const Layout &lay, const EngineFlags &fl)
{
    const int C = CHUNK;
    istore.assign(4 * C, 0);
    // delta, rate, mass, rad, ra, rb, fn; norm, vel, ft, force, ta, tb (3 each); the families'
    // history; vroll, froll (3 each); twist, mtwist; reach; each family's power and elastic energy
    size_t per = NFIXED + lay.width[NORMAL] + lay.width[TANGENTIAL] + lay.width[ROLLING] + lay.width[TWISTING] +
        (fl.rolling ? 6 : 0) + (fl.twisting ? 2 : 0) + (lay.adhesive ? 1 : 0) + (fl.energy ? 2 * NFAMILY : 0) +
        (fl.context ? 3 : 0) + (fl.heat ? 3 : 0);
    // one double of padding past the last column: the AVX2 loops read each 3-vector 4 wide
    dstore.assign((size_t) C * per + 1, 0.0);
    const std::pair<int **, IntColumn> icols[] = {{&a, A}, {&b, B}, {&slot, SLOT}, {&model, MODEL}};
    for (const auto &col : icols) *col.first = istore.data() + col.second * C;
    double *d = dstore.data();
    const std::pair<double **, DoubleColumn> dcols[] = {
        {&delta, DELTA}, {&rate, RATE}, {&mass, MASS}, {&rad, RAD},   {&ra, RA},       {&rb, RB}, {&fn, FN},
        {&norm, NORM},   {&vel, VEL},   {&ft, FT},     {&force, FORCE}, {&ta, TA}, {&tb, TB}};
    for (const auto &col : dcols) *col.first = d + col.second * C;
    double *p = d + NFIXED * C;
    auto take = [&p](int width) {
        double *q = p;
        p += (size_t) CHUNK * width;
        return width > 0 ? q : nullptr;
    };
    for (int f = 0; f < NFAMILY; f++) hist[f] = take(lay.width[f]);
    vroll = froll = twist = mtwist = reach = nullptr;
    if (fl.rolling) {
        vroll = take(3);
        froll = take(3);
    }
    if (fl.twisting) {
        twist = take(1);
        mtwist = take(1);
    }
    if (lay.adhesive) reach = take(1);
    context = fl.context ? take(3) : nullptr;
    temp = fl.heat ? take(2) : nullptr;
    heat = fl.heat ? take(1) : nullptr;
    for (int f = 0; f < NFAMILY; f++) power[f] = elastic[f] = nullptr;
    if (fl.energy)
        for (int f = 0; f < NFAMILY; f++) {
            power[f] = take(1);
            elastic[f] = take(1);
        }
}

void ContactEngine::configure(const ModelTable *m, const Layout &l, const EngineFlags &f)
{
    models = m;
    lay = l;
    fl = f;
    fl.context = fl.heat = false;
    for (int id = 0; id < models->nmodels(); id++) {
        fl.context = fl.context || models->model(id).any_context;
        fl.heat = fl.heat || models->model(id).heat != nullptr;
    }
    use_regions = fl.regions && models->nmodels() > 1 && models->nmodels() <= MAX_REGIONS;
    if (use_regions) {
        reg.resize(models->nmodels());
        for (auto &c : reg) c.reserve(lay, fl);
        reg_n.assign(models->nmodels(), 0);
        stage_ = Chunk();
        sorted = Chunk();
    } else {
        reg.clear();
        reg_n.clear();
        stage_.reserve(lay, fl);
        sorted.reserve(lay, fl);
    }
    full = taken = -1;
    n = 0;
    mixed = false;
}

/* Orders the staged contacts by model into `sorted` (a counting sort); count[q] .. count[q + 1]
 * is then model q's range. */
void ContactEngine::sort()
{
    const int nm = models->nmodels();
    count.assign(nm + 1, 0);
    Chunk &s = stage_, &d = sorted;
    for (int k = 0; k < n; k++) count[s.model[k] + 1]++;
    for (int q = 0; q < nm; q++) count[q + 1] += count[q];
    next.assign(count.begin(), count.end() - 1);
    place.resize(n);
    for (int k = 0; k < n; k++) place[k] = next[s.model[k]]++;
    auto move = [&](const double *src, double *dst, int width) {
        if (!src) return;
        for (int k = 0; k < n; k++)
            for (int q = 0; q < width; q++) dst[(size_t) place[k] * width + q] = src[(size_t) k * width + q];
    };
    for (int k = 0; k < n; k++) {
        const int p = place[k];
        d.a[p] = s.a[k];
        d.b[p] = s.b[k];
        d.slot[p] = s.slot[k];
        d.model[p] = s.model[k];
    }
    move(s.delta, d.delta, 1);
    move(s.rate, d.rate, 1);
    move(s.mass, d.mass, 1);
    move(s.rad, d.rad, 1);
    move(s.ra, d.ra, 1);
    move(s.rb, d.rb, 1);
    move(s.norm, d.norm, 3);
    move(s.vel, d.vel, 3);
    move(s.vroll, d.vroll, 3);
    move(s.twist, d.twist, 1);
}

/* The copies between the store (record s of a family at s * W) and a chunk's packed columns
 * (contact k at k * w, w <= W the model's own width), with the common widths known at compile
 * time; TOUCH: each copied record is also marked touched (the copy back of the first family
 * with history, whose loop has the slot at hand). */
template <int WIDTH, bool IN, bool TOUCH>
static void copy_records(double *__restrict packed, double *__restrict store, const int *__restrict slot, int m,
                         int w, int W, unsigned char *__restrict touched)
{
    const int width = WIDTH > 0 ? WIDTH : w;
    // a few instructions a record: unrolled, the loop's own count and branch are shared
#pragma GCC unroll 4
    for (int k = 0; k < m; k++) {
        const size_t sk = (size_t) slot[k];
        double *s = store + sk * W, *p = packed + (size_t) k * width;
        for (int q = 0; q < width; q++) {
            if (IN)
                p[q] = s[q];
            else
                s[q] = p[q];
        }
        if (TOUCH) touched[sk] = 1;
    }
}

template <bool IN, bool TOUCH>
static void copy_family(double *packed, double *store, const int *slot, int m, int w, int W,
                        unsigned char *touched = nullptr)
{
    switch (w) {
        case 0: return;
        case 1: return copy_records<1, IN, TOUCH>(packed, store, slot, m, w, W, touched);
        case 2: return copy_records<2, IN, TOUCH>(packed, store, slot, m, w, W, touched);
        case 3: return copy_records<3, IN, TOUCH>(packed, store, slot, m, w, W, touched);
        case 4: return copy_records<4, IN, TOUCH>(packed, store, slot, m, w, W, touched);
        default: return copy_records<0, IN, TOUCH>(packed, store, slot, m, w, W, touched);
    }
}

/* Copies the records of contacts lo .. lo+m-1 (all of model md) from the store into the chunk's
 * columns, packed at the model's own widths from lo * width onwards. */
void ContactEngine::gather(Chunk &c, int lo, int m, const Model &md, const HistoryStore &store)
{
    for (int f = 0; f < NFAMILY; f++)
        copy_family<true, false>(c.hist[f] + (size_t) lo * lay.width[f],
                                 const_cast<double *>(store.fam[f].data()), c.slot + lo, m, md.slots[f],
                                 lay.width[f]);
}

void ContactEngine::store_back(Chunk &c, int lo, int m, const Model &md, HistoryStore &store)
{
    unsigned char *touched = store.touched.data();
    bool marked = false;
    for (int f = 0; f < NFAMILY; f++) {
        double *packed = c.hist[f] + (size_t) lo * lay.width[f];
        if (!marked && md.slots[f] > 0) {
            copy_family<false, true>(packed, store.fam[f].data(), c.slot + lo, m, md.slots[f], lay.width[f],
                                     touched);
            marked = true;
        } else {
            copy_family<false, false>(packed, store.fam[f].data(), c.slot + lo, m, md.slots[f], lay.width[f]);
        }
    }
    if (lay.adhesive) {
        double *reach = store.reach.data();
        for (int k = 0; k < m; k++) reach[c.slot[lo + k]] = c.reach[lo + k];
    }
    if (!marked)
        for (int k = 0; k < m; k++) touched[c.slot[lo + k]] = 1;
}

/* Every family's batch call on contacts lo .. lo+m-1 of chunk c, all of model md, with each
 * family's history at hist[f] and an adhesive law's reach written to `reach`. A family the model
 * lacks gets zero outputs; with energy, a law that does not report its energy (an older sdk's)
 * leaves NaN, an absent family 0. */
void ContactEngine::run_laws(Chunk &c, int lo, int m, const Model &md, double *const *hist, double *reach, double dt)
{
    const size_t ns = md.slots[NORMAL], nt = md.slots[TANGENTIAL], nr = md.slots[ROLLING], nw = md.slots[TWISTING];
    const bool en = fl.energy;
    int written[NFAMILY] = {0, 0, 0, 0};
    auto pw = [&](int f) { return en ? c.power[f] + lo : nullptr; };
    auto el = [&](int f) { return en ? c.elastic[f] + lo : nullptr; };
    auto wr = [&](int f) { return en ? &written[f] : nullptr; };
    double *hn = ns ? hist[NORMAL] : nullptr;
    // sdk 0.4: the normal law also reports each contact's context, which the other families'
    // laws that read it receive
    double *ctx = md.any_context ? c.context + 3 * lo : nullptr;
#if !DASHPOT_LMP_CONTEXT
    (void) ctx;
#else
    if (ctx)
        check_status(dashpot_contact_model_force_batch_context(md.normal, m, c.delta + lo, c.rate + lo, c.mass + lo,
                                                               c.rad + lo, hn, m * ns, c.fn + lo,
                                                               lay.adhesive ? reach : nullptr, pw(NORMAL), el(NORMAL),
                                                               wr(NORMAL), ctx),
                     "dashpot_contact_model_force_batch_context");
    else
#endif
    if (lay.adhesive || en)
        check_status(dashpot_contact_model_force_batch_energy(md.normal, m, c.delta + lo, c.rate + lo, c.mass + lo,
                                                              c.rad + lo, hn, m * ns, c.fn + lo,
                                                              lay.adhesive ? reach : nullptr, pw(NORMAL), el(NORMAL),
                                                              wr(NORMAL)),
                     "dashpot_contact_model_force_batch_energy");
    else
        check_status(dashpot_contact_model_force_batch(md.normal, m, c.delta + lo, c.rate + lo, c.mass + lo,
                                                       c.rad + lo, hn, m * ns, c.fn + lo),
                     "dashpot_contact_model_force_batch");
    if (md.tangential) {
        double *ht = nt ? hist[TANGENTIAL] : nullptr;
#if DASHPOT_LMP_CONTEXT
        if (md.reads_context[TANGENTIAL])
            check_status(dashpot_tangential_model_force_batch_context(
                             md.tangential, m, dt, c.norm + 3 * lo, c.vel + 3 * lo, c.fn + lo, c.delta + lo,
                             c.mass + lo, c.rad + lo, ctx, ht, m * nt, c.ft + 3 * lo, pw(TANGENTIAL), el(TANGENTIAL),
                             wr(TANGENTIAL)),
                         "dashpot_tangential_model_force_batch_context");
        else
#endif
        if (en)
            check_status(dashpot_tangential_model_force_batch_energy(
                             md.tangential, m, dt, c.norm + 3 * lo, c.vel + 3 * lo, c.fn + lo, c.delta + lo,
                             c.mass + lo, c.rad + lo, ht, m * nt, c.ft + 3 * lo, pw(TANGENTIAL), el(TANGENTIAL),
                             wr(TANGENTIAL)),
                         "dashpot_tangential_model_force_batch_energy");
        else
            check_status(dashpot_tangential_model_force_batch(md.tangential, m, dt, c.norm + 3 * lo, c.vel + 3 * lo,
                                                              c.fn + lo, c.delta + lo, c.mass + lo, c.rad + lo, ht,
                                                              m * nt, c.ft + 3 * lo),
                         "dashpot_tangential_model_force_batch");
    } else {
        std::fill(c.ft + 3 * lo, c.ft + 3 * (lo + m), 0.0);
    }
    if (md.rolling) {
        double *hr = nr ? hist[ROLLING] : nullptr;
#if DASHPOT_LMP_CONTEXT
        if (md.reads_context[ROLLING])
            check_status(dashpot_rolling_model_force_batch_context(md.rolling, m, dt, c.norm + 3 * lo,
                                                                   c.vroll + 3 * lo, c.fn + lo, c.delta + lo,
                                                                   c.mass + lo, c.rad + lo, ctx, hr, m * nr,
                                                                   c.froll + 3 * lo, pw(ROLLING), el(ROLLING),
                                                                   wr(ROLLING)),
                         "dashpot_rolling_model_force_batch_context");
        else
#endif
            check_status(dashpot_rolling_model_force_batch(md.rolling, m, dt, c.norm + 3 * lo, c.vroll + 3 * lo,
                                                           c.fn + lo, c.delta + lo, c.mass + lo, c.rad + lo, hr,
                                                           m * nr, c.froll + 3 * lo, pw(ROLLING), el(ROLLING),
                                                           wr(ROLLING)),
                         "dashpot_rolling_model_force_batch");
    } else if (c.froll) {
        std::fill(c.froll + 3 * lo, c.froll + 3 * (lo + m), 0.0);
    }
    if (md.twisting) {
        double *hw = nw ? hist[TWISTING] : nullptr;
#if DASHPOT_LMP_CONTEXT
        if (md.reads_context[TWISTING])
            check_status(dashpot_twisting_model_torque_batch_context(md.twisting, m, dt, c.norm + 3 * lo,
                                                                     c.twist + lo, c.fn + lo, c.delta + lo,
                                                                     c.mass + lo, c.rad + lo, ctx, hw, m * nw,
                                                                     c.mtwist + lo, pw(TWISTING), el(TWISTING),
                                                                     wr(TWISTING)),
                         "dashpot_twisting_model_torque_batch_context");
        else
#endif
            check_status(dashpot_twisting_model_torque_batch(md.twisting, m, dt, c.norm + 3 * lo, c.twist + lo,
                                                             c.fn + lo, c.delta + lo, c.mass + lo, c.rad + lo, hw,
                                                             m * nw, c.mtwist + lo, pw(TWISTING), el(TWISTING),
                                                             wr(TWISTING)),
                         "dashpot_twisting_model_torque_batch");
    } else if (c.mtwist) {
        std::fill(c.mtwist + lo, c.mtwist + lo + m, 0.0);
    }
    if (md.heat) conduct(c, lo, m, md, dt);
    if (en) {
        const bool present[NFAMILY] = {true, md.tangential != nullptr, md.rolling != nullptr, md.twisting != nullptr};
        for (int f = 0; f < NFAMILY; f++)
            if (!present[f] || !written[f]) {
                std::fill(c.power[f] + lo, c.power[f] + lo + m, present[f] ? NAN : 0.0);
                std::fill(c.elastic[f] + lo, c.elastic[f] + lo + m, present[f] ? NAN : 0.0);
            }
    }
}

/* The heat law's batch call on contacts lo .. lo+m-1 (all of model md, all pairs or all wall
 * contacts) with the normal law's force and context, and the heat flows added to the target's
 * heatflow: Q to a, -Q to b, as LAMMPS's pair granular and fix wall/gran add theirs. */
void ContactEngine::conduct(Chunk &c, int lo, int m, const Model &md, double dt)
{
    const HeatTarget &h = heat_target;
    if (!h.heatflow || !h.temperature || m == 0) return;
    const bool wall = c.b[lo] < 0;
    if (wall && !std::isfinite(h.wall_temperature)) return;
    double *tp = c.temp + 2 * lo;
    for (int k = 0; k < m; k++) {
        tp[2 * k] = h.temperature[c.a[lo + k]];
        tp[2 * k + 1] = wall ? h.wall_temperature : h.temperature[c.b[lo + k]];
    }
    const double *ctx = md.reads_context[HEAT] ? c.context + 3 * lo : nullptr;
    check_status(dashpot_heat_model_heat_batch(md.heat, m, dt, tp, c.fn + lo, c.delta + lo, c.rad + lo, ctx, nullptr,
                                               0, c.heat + lo, nullptr),
                 "dashpot_heat_model_heat_batch");
    double *hf = h.heatflow;
    for (int k = lo; k < lo + m; k++) {
        const int a = c.a[k], b = c.b[k];
        const double q = c.heat[k];
        if (a < h.nlocal || h.newton) hf[a] += q;
        if (b >= 0 && (b < h.nlocal || h.newton)) hf[b] -= q;
    }
}

/* The force on a (F_n n + F_t; b takes its opposite) and the torques of contacts lo .. lo+m-1:
 * the tangential force's, -arm (n x F_t) on each body, the arm being the radius or, with
 * granular's convention (HALF), r - delta/2; rolling (ROLL), R_eff n x F_roll on a and its
 * opposite on b; twisting (TWST), M n on a and its opposite on b. Into the chunk's columns, or
 * added to `direct`'s arrays (DIRECT). One loop per combination of the model's families, with
 * no test inside but newton's rule, and the columns read through restrict pointers (they do
 * not alias the atoms' arrays). */
template <bool ROLL, bool TWST, bool HALF, bool DIRECT>
static void torques_of(ContactEngine::Chunk &c, int lo, int m, const ApplyTarget *direct)
{
    using Ch = ContactEngine::Chunk;
    constexpr int C = ContactEngine::CHUNK;
    // the fixed columns from two bases (Chunk's IntColumn, DoubleColumn): few registers held
    double *__restrict d = c.dstore.data();
    const int *__restrict iv = c.istore.data();
    const double *__restrict froll = c.froll, *__restrict mtw = c.mtwist;
    double *__restrict f0 = DIRECT ? direct->f : nullptr, *__restrict t0 = DIRECT ? direct->torque : nullptr;
    const int nlocal = DIRECT ? direct->nlocal : 0;
    const bool newton = DIRECT && direct->newton;
    for (int k = lo; k < lo + m; k++) {
        const double *nv = d + Ch::NORM * C + 3 * k, *ft = d + Ch::FT * C + 3 * k;
        const double nx = nv[0], ny = nv[1], nz = nv[2], fn = d[Ch::FN * C + k];
        const double ftx = ft[0], fty = ft[1], ftz = ft[2];
        const double Fx = fn * nx + ftx, Fy = fn * ny + fty, Fz = fn * nz + ftz;
        const double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
        double mx = 0.0, my = 0.0, mz = 0.0;
        if (ROLL) {
            const double *fr = froll + 3 * k, reff = d[Ch::RAD * C + k];
            mx = reff * (ny * fr[2] - nz * fr[1]);
            my = reff * (nz * fr[0] - nx * fr[2]);
            mz = reff * (nx * fr[1] - ny * fr[0]);
        }
        if (TWST) {
            const double mt = mtw[k];
            mx += mt * nx;
            my += mt * ny;
            mz += mt * nz;
        }
        const double ra = d[Ch::RA * C + k], rb = d[Ch::RB * C + k];
        const double arm_a = HALF ? ra - 0.5 * d[Ch::DELTA * C + k] : ra;
        const double arm_b = HALF ? rb - 0.5 * d[Ch::DELTA * C + k] : rb;
        const double tax = mx - arm_a * cx, tay = my - arm_a * cy, taz = mz - arm_a * cz;
        const double tbx = -mx - arm_b * cx, tby = -my - arm_b * cy, tbz = -mz - arm_b * cz;
        if (!DIRECT) {
            double *F = d + Ch::FORCE * C + 3 * k, *ta = d + Ch::TA * C + 3 * k, *tb = d + Ch::TB * C + 3 * k;
            F[0] = Fx;
            F[1] = Fy;
            F[2] = Fz;
            ta[0] = tax;
            ta[1] = tay;
            ta[2] = taz;
            tb[0] = tbx;
            tb[1] = tby;
            tb[2] = tbz;
            continue;
        }
        const int a = iv[Ch::A * C + k], b = iv[Ch::B * C + k];
        if (a < nlocal || newton) {
            double *fa = f0 + 3 * a, *ta = t0 + 3 * a;
            fa[0] += Fx;
            fa[1] += Fy;
            fa[2] += Fz;
            ta[0] += tax;
            ta[1] += tay;
            ta[2] += taz;
        }
        if (b >= 0 && (b < nlocal || newton)) {
            double *fb = f0 + 3 * b, *tb = t0 + 3 * b;
            fb[0] -= Fx;
            fb[1] -= Fy;
            fb[2] -= Fz;
            tb[0] += tbx;
            tb[1] += tby;
            tb[2] += tbz;
        }
    }
}

/* The kernel for torques_dispatch (dashpot_simd_torq.h). */
struct ScalarTorques {
    template <bool ROLL, bool TWST, bool HALF, bool DIRECT>
    static void run(ContactEngine::Chunk &c, int lo, int m, const ApplyTarget *direct)
    {
        torques_of<ROLL, TWST, HALF, DIRECT>(c, lo, m, direct);
    }
};

void ContactEngine::torques(Chunk &c, int lo, int m, const Model &md, const ApplyTarget *direct)
{
    const bool roll = md.rolling != nullptr, twst = md.twisting != nullptr;
    const bool half = md.arm == TorqueArm::CONTACT_POINT;
    if (simd_avx2()) return torques_avx2(c, lo, m, roll, twst, half, direct);
    const bool flags[4] = {roll, twst, half, direct != nullptr};
    torques_dispatch<ScalarTorques>(c, lo, m, direct, flags);
}

ContactEngine::Chunk &ContactEngine::evaluate(HistoryStore &store, double dt, bool keep, const ApplyTarget *direct)
{
    if (use_regions) {
        const int q = next_region();
        if (q < 0) return reg.front();
        taken = q;
        return evaluate_chunk(reg[q], reg_n[q], q, store, dt, keep, direct);
    }
    if (n == 0) return stage_;
    if (!mixed) return evaluate_chunk(stage_, n, model0, store, dt, keep, direct);
    const bool history = lay.nvalues > 0;
    keep = keep && history;
    sort();
    Chunk &c = sorted;
    for (int q = 0; q + 1 < (int) count.size(); q++) {
        const int lo = count[q], m = count[q + 1] - lo;
        if (m == 0) continue;
        const Model &md = models->model(q);
        if (history) gather(c, lo, m, md, store);
        double *h[NFAMILY];
        for (int f = 0; f < NFAMILY; f++) h[f] = c.hist[f] ? c.hist[f] + (size_t) lo * lay.width[f] : nullptr;
        run_laws(c, lo, m, md, h, c.reach ? c.reach + lo : nullptr, dt);
        if (keep) store_back(c, lo, m, md, store);
        torques(c, lo, m, md, direct);
    }
    return c;
}

/* The n contacts of chunk c, all of one model. */
ContactEngine::Chunk &ContactEngine::evaluate_chunk(Chunk &c, int n, int model, HistoryStore &store, double dt,
                                                    bool keep, const ApplyTarget *direct)
{
    const bool history = lay.nvalues > 0;
    keep = keep && history;
    const Model &md = models->model(model);
    bool fits = true;
    for (int f = 0; f < NFAMILY; f++) fits = fits && md.slots[f] == lay.width[f];
    const int s0 = c.slot[0];
    // contacts of consecutive records (a pile: every pair of the list touches): the laws read
    // and write the store in place, each family its own array
    if (keep && fits && c.slot[n - 1] - s0 == n - 1) {
        double *h[NFAMILY];
        for (int f = 0; f < NFAMILY; f++)
            h[f] = lay.width[f] ? store.fam[f].data() + (size_t) s0 * lay.width[f] : nullptr;
        double *reach = lay.adhesive ? store.reach.data() + s0 : nullptr;
        run_laws(c, 0, n, md, h, reach, dt);
        if (reach) std::memcpy(c.reach, reach, sizeof(double) * n);
        std::memset(store.touched.data() + s0, 1, n);
    } else {
        if (history) gather(c, 0, n, md, store);
        run_laws(c, 0, n, md, c.hist, c.reach, dt);
        if (keep) store_back(c, 0, n, md, store);
    }
    torques(c, 0, n, md, direct);
    return c;
}

}    // namespace dashpot_lmp
