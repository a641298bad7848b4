/* The contact engine shared by pair_style dashpot and the wall fixes: contacts are staged a
 * chunk at a time in structure-of-arrays columns (in cache), evaluated by one batch call per
 * family and bound model present in the chunk (a counting sort when a chunk mixes models), and
 * their forces and torques computed with the model's conventions; the caller applies them to
 * its atoms. The history lives in a HistoryStore the caller owns (the pair style's slots in
 * neighbour-list order, a wall fix's per-atom slots); the engine reads each contact's record
 * from it and writes it back. No LAMMPS header.
 *
 * Use:
 *   engine.configure(&models, layout, flags);       // once per run (after the models are bound)
 *   for each contact: engine.stage(...);            // returns true when the chunk is full:
 *       Chunk &c = engine.evaluate(store, dt, keep); // then apply c's outputs, engine.reset()
 *   ...and once more for the last, partial chunk.
 * Geometry, per contact: a and b the two bodies' indices (the caller's; b < 0 for a wall), n the
 * unit normal from b to a, delta the overlap (> 0 in contact), the distances ra, rb from each
 * centre to the contact point used for the relative velocity (the radii; 0 for a wall), dv =
 * v_a - v_b at the centres, wa, wb the spins (wb null for a wall that does not spin; a moving or
 * rotating wall passes the velocity of its contact point in dv and its spin in wb), the
 * effective mass and radius, the history slot in the store and the bound model's id. */
#ifndef DASHPOT_ENGINE_H
#define DASHPOT_ENGINE_H

#include "dashpot_models.h"

#include <algorithm>
#include <vector>

namespace dashpot_lmp {

/* Per-contact history records, owned by the caller: record k holds each family's values at
 * k * width[f] of that family's array, the reach of an adhesive law's last call, and whether
 * the record may be non-zero (`touched`: the contact was evaluated since it was zeroed). */
struct HistoryStore {
    std::vector<double> fam[NFAMILY];
    std::vector<double> reach;
    std::vector<unsigned char> touched;
    Layout layout;
    size_t size() const { return touched.size(); }
    /* n zeroed records of the layout */
    void assign(size_t n, const Layout &lay);
    /* record k's contact ended: zero */
    void zero(size_t k);
    /* record k as a flat array of layout.nvalues values (families in order, then the reach) */
    void get(size_t k, double *record) const;
    void set(size_t k, const double *record);
    /* whether record k holds any non-zero value (a zero record is the same as none) */
    bool nonzero(size_t k) const;
};

/* Which optional inputs and outputs the engine carries. */
struct EngineFlags {
    bool rolling = false;     // some model has a rolling law: stage the rolling velocity
    bool twisting = false;    // some model has a twisting law: stage the twisting rate
    bool energy = false;      // ask the laws for their power and elastic energy
    /* Stage each model's contacts in a chunk of its own (up to MAX_REGIONS models; beyond, one
     * chunk sorted by model): no sort, and every batch call on one model. The caller then
     * evaluates one chunk at a time: after stage() returns true, and at the end while size() > 0
     * (see evaluate()). */
    bool regions = false;
    bool context = false;    // set by configure(): some model reads the normal context
    bool heat = false;       // set by configure(): some model has a heat law
};

/* Where evaluate() conducts heat (sdk 0.4), as LAMMPS's fix property/atom temperature heatflow:
 * each contact of a model with a heat law reads the two bodies' temperatures (a wall's own for
 * b < 0) and adds the heat flow Q into a to heatflow[a], -Q to heatflow[b] (a ghost atom takes
 * its share only with newton on, as the forces). A wall whose temperature is not finite (none
 * given) conducts no heat. */
struct HeatTarget {
    const double *temperature = nullptr;    // per atom (local and ghost)
    double *heatflow = nullptr;             // per atom; null: no heat conducted
    double wall_temperature = 0.0;
    int nlocal = 0;
    bool newton = false;
};

/* Where evaluate() may add the forces and torques itself (instead of leaving them in the chunk's
 * force/ta/tb columns): LAMMPS's f and torque arrays, with newton's rule for pairs (a ghost atom
 * takes its share only with newton on); wall contacts (b < 0) only act on a. */
struct ApplyTarget {
    double *f = nullptr, *torque = nullptr;    // 3 per atom, contiguous
    int nlocal = 0;
    bool newton = false;
};

class ContactEngine {
 public:
    static constexpr int CHUNK = 256;    // contacts per batch call: the columns stay in L2 cache
    static constexpr int MAX_REGIONS = 16;

    struct Chunk {
        int *a = nullptr, *b = nullptr, *slot = nullptr, *model = nullptr;
        double *delta = nullptr, *rate = nullptr, *mass = nullptr, *rad = nullptr;
        double *ra = nullptr, *rb = nullptr;    // the radii (the torque arms' base)
        double *norm = nullptr, *vel = nullptr;
        double *vroll = nullptr, *twist = nullptr;
        double *hist[NFAMILY] = {nullptr, nullptr, nullptr, nullptr};
        // outputs: the laws'
        double *fn = nullptr, *ft = nullptr, *froll = nullptr, *mtwist = nullptr, *reach = nullptr;
        double *context = nullptr;    // sdk 0.4: each contact's normal context (3 values)
        double *temp = nullptr, *heat = nullptr;    // heat: [T_a, T_b] per contact, the heat flow into a
        double *power[NFAMILY] = {nullptr, nullptr, nullptr, nullptr};      // energy: power (W)
        double *elastic[NFAMILY] = {nullptr, nullptr, nullptr, nullptr};    // energy: elastic energy (J)
        // outputs: the force on a (b takes its opposite) and the torques on a and b
        double *force = nullptr, *ta = nullptr, *tb = nullptr;
        std::vector<int> istore;
        std::vector<double> dstore;
        void reserve(const Layout &lay, const EngineFlags &fl);
        /* Where the columns every chunk has start, in units of CHUNK from istore's and dstore's
         * first element (reserve() lays them out so): the hot loops address them all from those
         * two pointers, with constant displacements, rather than hold a register for each. */
        enum IntColumn { A = 0, B = 1, SLOT = 2, MODEL = 3 };
        enum DoubleColumn {
            DELTA = 0, RATE = 1, MASS = 2, RAD = 3, RA = 4, RB = 5, FN = 6,
            NORM = 7, VEL = 10, FT = 13, FORCE = 16, TA = 19, TB = 22, NFIXED = 25
        };
    };

    /* The models, the record layout of the store and the flags: columns sized once. */
    void configure(const ModelTable *models, const Layout &lay, const EngineFlags &fl);
    const EngineFlags &flags() const { return fl; }
    /* Where the heat of the contacts evaluated next goes (see HeatTarget); set before each step
     * (the per-atom arrays move as atoms are added). */
    void set_heat(const HeatTarget &h) { heat_target = h; }

    /* The number of staged contacts evaluate() takes next (with regions: those of one model, the
     * full one first); 0 when none is staged. */
    int size() const
    {
        if (!use_regions) return n;
        const int q = next_region();
        return q < 0 ? 0 : reg_n[q];
    }
    /* Forgets the contacts evaluate() took (with regions: that model's only). */
    void reset()
    {
        if (!use_regions) {
            n = 0;
            mixed = false;
            return;
        }
        if (taken >= 0) reg_n[taken] = 0;
        if (taken == full) full = -1;
        taken = -1;
    }

    /* One contact's geometry, as stage() takes it (see the file's head). */
    struct Geometry {
        int model, a, b, slot;
        double nx, ny, nz, delta, ra, rb, dvx, dvy, dvz, meff, reff;
        const double *wa, *wb;
    };
    /* Stages contacts q = first, first + 1, ... before `last`, each described by geom(q, g)
     * (which fills the Geometry g), until the chunk is full; returns the q after the last staged
     * contact: `last` unless the chunk filled (then evaluate, apply, reset and call again from
     * the returned q). The same columns, with the same bits, as stage() called on each, but the
     * columns' addresses and the engine's state stay in registers over the whole run. */
    template <class Geom> inline int stage_run(int first, int last, Geom &&geom) __attribute__((always_inline));

    /* For a caller that writes the staging columns itself (the vectorised staging of
     * dashpot_simd_geom.h): the bases of the staging chunk's int and double columns (see Chunk's
     * IntColumn, DoubleColumn) and its first free row k; false when the engine stages otherwise
     * (a chunk per model, or the rolling and twisting columns): then stage_run. staged(m, model)
     * then takes the m rows written from row k on, all of bound model `model`. */
    bool columns(int *&iv, double *&dv, int &k)
    {
        if (use_regions || fl.rolling || fl.twisting) return false;
        iv = stage_.istore.data();
        dv = stage_.dstore.data();
        k = n;
        return true;
    }
    void staged(int m, int model)
    {
        if (m == 0) return;
        if (n == 0) model0 = model;
        mixed |= model != model0;
        n += m;
    }

    /* Stages one contact; true when the chunk is full (evaluate, apply, reset before the next). */
    inline bool stage(int model, int a, int b, int slot, double nx, double ny, double nz, double delta, double ra,
                      double rb, double dvx, double dvy, double dvz, double meff, double reff, const double *wa,
                      const double *wb) __attribute__((always_inline));

    /* Evaluates the staged contacts: every family's batch call per model, in the order normal ->
     * tangential -> rolling -> twisting, with each contact's record from `store` (written back
     * when `keep`: not in a run's setup, where the forces are recomputed at a state already
     * integrated and dt = 0); then the forces and torques. Returns the chunk holding the
     * contacts and their outputs (sorted by model when the chunk mixed models). With `direct`,
     * the forces and torques go straight to its arrays and the force, ta, tb columns are not
     * written. Throws SpecError with the library's message if a law fails. */
    Chunk &evaluate(HistoryStore &store, double dt, bool keep, const ApplyTarget *direct = nullptr);

 private:
    const ModelTable *models = nullptr;
    Layout lay;
    EngineFlags fl;
    HeatTarget heat_target;
    Chunk stage_, sorted;
    int n = 0, model0 = -1;
    bool mixed = false;
    std::vector<int> count, next, place;
    // regions: one staging chunk per model
    bool use_regions = false;
    std::vector<Chunk> reg;
    std::vector<int> reg_n;
    int full = -1, taken = -1;
    int next_region() const
    {
        if (full >= 0) return full;
        for (int q = 0; q < (int) reg_n.size(); q++)
            if (reg_n[q] > 0) return q;
        return -1;
    }
    template <bool SPIN, class Geom>
    inline int stage_run_to(int first, int last, Geom &geom) __attribute__((always_inline));
    template <class Geom> int stage_run_regions(int first, int last, Geom &geom);
    inline void write(Chunk &c, int k, int model, int a, int b, int slot, double nx, double ny, double nz,
                      double delta, double ra, double rb, double dvx, double dvy, double dvz, double meff,
                      double reff, const double *wa, const double *wb) __attribute__((always_inline));
    Chunk &evaluate_chunk(Chunk &c, int n, int model, HistoryStore &store, double dt, bool keep,
                          const ApplyTarget *direct);
    void sort();
    void gather(Chunk &c, int lo, int m, const Model &md, const HistoryStore &store);
    void store_back(Chunk &c, int lo, int m, const Model &md, HistoryStore &store);
    void run_laws(Chunk &c, int lo, int m, const Model &md, double *const *hist, double *reach, double dt);
    void torques(Chunk &c, int lo, int m, const Model &md, const ApplyTarget *direct);
    void conduct(Chunk &c, int lo, int m, const Model &md, double dt);
};

inline bool ContactEngine::stage(int model, int a, int b, int slot, double nx, double ny, double nz, double delta,
                                 double ra, double rb, double dvx, double dvy, double dvz, double meff, double reff,
                                 const double *wa, const double *wb)
{
    if (use_regions) {
        int &k = reg_n[model];
        write(reg[model], k, model, a, b, slot, nx, ny, nz, delta, ra, rb, dvx, dvy, dvz, meff, reff, wa, wb);
        if (++k < CHUNK) return false;
        full = model;
        return true;
    }
    if (n == 0) model0 = model;
    mixed |= model != model0;
    write(stage_, n, model, a, b, slot, nx, ny, nz, delta, ra, rb, dvx, dvy, dvz, meff, reff, wa, wb);
    return ++n == CHUNK;
}

inline void ContactEngine::write(Chunk &c, int n, int model, int a, int b, int slot, double nx, double ny, double nz,
                                 double delta, double ra, double rb, double dvx, double dvy, double dvz, double meff,
                                 double reff, const double *wa, const double *wb)
{
    c.a[n] = a;
    c.b[n] = b;
    c.slot[n] = slot;
    c.model[n] = model;
    c.delta[n] = delta;
    c.mass[n] = meff;
    c.rad[n] = reff;
    c.ra[n] = ra;
    c.rb[n] = rb;
    const double vn = dvx * nx + dvy * ny + dvz * nz;
    c.rate[n] = -vn;
    double *cn = c.norm + 3 * n;
    cn[0] = nx;
    cn[1] = ny;
    cn[2] = nz;
    // the tangential velocity of a's contact point relative to b's, as LAMMPS's granular model
    // computes it: (dv - (dv.n) n) - (ra wa + rb wb) x n
    double wx = ra * wa[0], wy = ra * wa[1], wz = ra * wa[2];
    if (wb) {
        wx += rb * wb[0];
        wy += rb * wb[1];
        wz += rb * wb[2];
    }
    double *cv = c.vel + 3 * n;
    cv[0] = (dvx - vn * nx) - (wy * nz - wz * ny);
    cv[1] = (dvy - vn * ny) - (wz * nx - wx * nz);
    cv[2] = (dvz - vn * nz) - (wx * ny - wy * nx);
    if (fl.rolling || fl.twisting) {
        // the relative spin wa - wb: rolling velocity reff (wa - wb) x n, twisting rate
        // (wa - wb).n (LAMMPS pair granular's definitions)
        double rx = wa[0], ry = wa[1], rz = wa[2];
        if (wb) {
            rx -= wb[0];
            ry -= wb[1];
            rz -= wb[2];
        }
        if (fl.rolling) {
            double *vr = c.vroll + 3 * n;
            vr[0] = reff * (ry * nz - rz * ny);
            vr[1] = reff * (rz * nx - rx * nz);
            vr[2] = reff * (rx * ny - ry * nx);
        }
        if (fl.twisting) c.twist[n] = rx * nx + ry * ny + rz * nz;
    }
}

template <class Geom> inline int ContactEngine::stage_run(int q, int last, Geom &&geom)
{
    if (use_regions) return stage_run_regions(q, last, geom);
    if (fl.rolling || fl.twisting) return stage_run_to<true>(q, last, geom);
    return stage_run_to<false>(q, last, geom);
}

/* stage_run with a chunk per model: each contact to its model's chunk, until one is full. */
template <class Geom> int ContactEngine::stage_run_regions(int q, int last, Geom &geom)
{
    Geometry g;
    while (q < last) {
        geom(q++, g);
        if (stage(g.model, g.a, g.b, g.slot, g.nx, g.ny, g.nz, g.delta, g.ra, g.rb, g.dvx, g.dvy, g.dvz, g.meff, g.reff,
                  g.wa, g.wb))
            break;
    }
    return q;
}

/* stage_run on the one staging chunk, SPIN: the relative spin's columns (rolling, twisting) are
 * staged too. Each column is written by the same expressions as write()'s. */
template <bool SPIN, class Geom> inline int ContactEngine::stage_run_to(int q, int last, Geom &geom)
{
    int k = n;
    const int end = k + std::min(CHUNK - k, last - q);
    if (k == end) return q;
    // every column at a constant offset from two bases (see Chunk's IntColumn, DoubleColumn)
    int *__restrict iv = stage_.istore.data();
    double *__restrict dv = stage_.dstore.data();
    constexpr int C = CHUNK;
    double *__restrict cvroll = SPIN && fl.rolling ? stage_.vroll : nullptr;
    double *__restrict ctwist = SPIN && fl.twisting ? stage_.twist : nullptr;
    int m0 = k == 0 ? -1 : model0;
    bool mix = mixed;
    Geometry g;
    for (; k < end; k++, q++) {
        geom(q, g);
        if (m0 < 0) m0 = g.model;
        mix |= g.model != m0;
        iv[Chunk::A * C + k] = g.a;
        iv[Chunk::B * C + k] = g.b;
        iv[Chunk::SLOT * C + k] = g.slot;
        iv[Chunk::MODEL * C + k] = g.model;
        dv[Chunk::DELTA * C + k] = g.delta;
        dv[Chunk::MASS * C + k] = g.meff;
        dv[Chunk::RAD * C + k] = g.reff;
        dv[Chunk::RA * C + k] = g.ra;
        dv[Chunk::RB * C + k] = g.rb;
        const double nx = g.nx, ny = g.ny, nz = g.nz, dvx = g.dvx, dvy = g.dvy, dvz = g.dvz;
        const double vn = dvx * nx + dvy * ny + dvz * nz;
        dv[Chunk::RATE * C + k] = -vn;
        double *cn = dv + Chunk::NORM * C + 3 * k;
        cn[0] = nx;
        cn[1] = ny;
        cn[2] = nz;
        const double *wa = g.wa, *wb = g.wb;
        double wx = g.ra * wa[0], wy = g.ra * wa[1], wz = g.ra * wa[2];
        if (wb) {
            wx += g.rb * wb[0];
            wy += g.rb * wb[1];
            wz += g.rb * wb[2];
        }
        double *cv = dv + Chunk::VEL * C + 3 * k;
        cv[0] = (dvx - vn * nx) - (wy * nz - wz * ny);
        cv[1] = (dvy - vn * ny) - (wz * nx - wx * nz);
        cv[2] = (dvz - vn * nz) - (wx * ny - wy * nx);
        if (SPIN) {
            double rx = wa[0], ry = wa[1], rz = wa[2];
            if (wb) {
                rx -= wb[0];
                ry -= wb[1];
                rz -= wb[2];
            }
            if (cvroll) {
                double *vr = cvroll + 3 * k;
                vr[0] = g.reff * (ry * nz - rz * ny);
                vr[1] = g.reff * (rz * nx - rx * nz);
                vr[2] = g.reff * (rx * ny - ry * nx);
            }
            if (ctwist) ctwist[k] = rx * nx + ry * ny + rz * nz;
        }
    }
    n = k;
    model0 = m0;
    mixed = mix;
    return q;
}

}    // namespace dashpot_lmp

#endif
