/* fix wall/dashpot: see fix_wall_dashpot.h. This file: the arguments, the laws and the plane and
 * cylinder walls; fix_wall_dashpot_contacts.cpp: the contacts' evaluation, outputs and per-atom
 * history storage; fix_wall_dashpot_region.cpp: the region walls. */
#include "fix_wall_dashpot.h"

#include "dashpot_translate.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "force.h"
#include "input.h"
#include "memory.h"
#include "modify.h"
#include "update.h"
#include "variable.h"

#include <mpi.h>

#include <cmath>
#include <cstring>

using namespace LAMMPS_NS;
using namespace FixConst;
using namespace dashpot_lmp;

static constexpr double BIG = 1.0e20;
static const std::vector<std::string> OPTION_KEYS = {"plugin_dir", "energy", "wall"};
static const std::vector<std::string> WALL_STYLES = {"xplane", "yplane", "zplane", "zcylinder", "region"};

static bool is_number_or_null(const std::string &w)
{
    if (w == "NULL") return true;
    const char *s = w.c_str();
    char *end = nullptr;
    std::strtod(s, &end);
    return !w.empty() && end != s && *end == '\0';
}

static bool is_option(const std::string &w)
{
    const size_t eq = w.find('=');
    if (eq == std::string::npos) return false;
    for (auto &k : OPTION_KEYS)
        if (w.compare(0, eq, k) == 0 && eq == k.size()) return true;
    return false;
}

FixWallDashpot::FixWallDashpot(LAMMPS *lmp, int narg, char **arg) :
    Fix(lmp, narg, arg), wallstyle(-1), lo(-BIG), hi(BIG), cylradius(0.0), wiggle(0), wshear(0), axis(0),
    amplitude(0.0), period(0.0), omega_wiggle(0.0), vshear(0.0), time_origin(0), contacts_flag(0), energy_flag(0),
    wall_temperature(NAN), temperature_ivar(-1), spec_index(-1), rigid_wall(-1), young(1.0), poisson(0.3), nper(1), nmax_atoms(0), restart_mismatch(0),
    fix_rigid(nullptr), sums_step(-1), reduced(0)
{
    context = std::string("fix ") + style;
    if (!atom->radius_flag || !atom->rmass_flag || !atom->omega_flag || !atom->torque_flag)
        error->all(FLERR, "{} requires atom attributes radius, rmass, omega, torque (atom_style sphere)", context);
    parse(narg, arg);

    create_attribute = 1;
    restart_global = 1;
    restart_peratom = 1;
    vector_flag = 1;
    size_vector = NVECTOR;
    global_freq = 1;
    extvector = 1;
    if (contacts_flag) {
        peratom_flag = 1;
        size_peratom_cols = 8;
        peratom_freq = 1;
    }
    for (int k = 0; k < NVECTOR; k++) sums[k] = totals[k] = 0.0;
    time_origin = update->ntimestep;

    resize_per_atom(atom->nmax, 1);
    atom->add_callback(Atom::GROW);
    atom->add_callback(Atom::RESTART);
}

FixWallDashpot::~FixWallDashpot()
{
    if (copymode) return;
    // not registered when a derived constructor failed (the fix is not in the list yet)
    if (modify->get_fix_by_id(id) == this) {
        atom->delete_callback(id, Atom::GROW);
        atom->delete_callback(id, Atom::RESTART);
    }
    if (array_atom) memory->destroy(array_atom);
}

int FixWallDashpot::setmask()
{
    return POST_FORCE;
}

/* The arguments: options (anywhere), the models, the wall style and its arguments, the
 * keywords. */
void FixWallDashpot::parse(int narg, char **arg)
{
    std::vector<std::string> words;
    for (int k = 3; k < narg; k++) {
        std::string w = arg[k];
        if (!is_option(w)) {
            words.push_back(w);
            continue;
        }
        const size_t eq = w.find('=');
        const std::string key = w.substr(0, eq), value = w.substr(eq + 1);
        if (key == "plugin_dir") {
            plugin_dirs.push_back(value);
        } else if (key == "energy") {
            energy_flag = utils::logical(FLERR, value, false, lmp);
        } else {
            if (value == "rigid")
                rigid_wall = 1;
            else if (value == "particle")
                rigid_wall = 0;
            else
                error->all(FLERR, "{}: wall={} is not a wall material (valid: wall=rigid, wall=particle)", context,
                           value);
        }
    }
    if (words.empty())
        error->all(FLERR,
                   "{}: expected the models and a wall style, as in '{} 1e7 0.3 hsd eps=0.5 tangential mindlin "
                   "mu=0.5 zplane 0 NULL'",
                   context, context);
    size_t at = 0;
    try {
        at = parse_models(words);
    } catch (std::exception &e) {
        const std::string what = e.what();
        // the parsers' messages name the command already
        error->all(FLERR, "{}", what.rfind(context, 0) == 0 ? what : context + ": " + what);
    }
    parse_wall(words, at);
}

/* The models' words up to the wall style; returns its index. */
size_t FixWallDashpot::parse_models(const std::vector<std::string> &w)
{
    models.open(plugin_dirs);
    size_t first = 0, end = 0;
    // fix wall/gran's word for its granular models, kept for a drop-in switch
    if (w[0] == "granular") first = 1;
    if (first >= w.size()) throw SpecError("'granular' must be followed by a normal model (hooke, hertz, ...)");
    const std::string &s = w[first];
    // a classic style: its name and six numbers (granular's 'hooke k damp' has two)
    size_t nums = 0;
    while (first + 1 + nums < w.size() && is_number_or_null(w[first + 1 + nums])) nums++;
    const bool classic =
        first == 0 && nums > 0 && (s == "hooke/history" || s == "hertz/history" || (s == "hooke" && nums > 2));
    ContactSpec spec;
    if (classic) {
        GranularWords g = parse_classic(s, w, first + 1, force->nktv2p, context + " " + s, WALL_STYLES, &end);
        spec = translate_granular(g, context, true);
    } else if (is_granular(w, first)) {
        GranularWords g = parse_granular(w, first, context, WALL_STYLES, &end);
        spec = translate_granular(g, context, true);
    } else if (first == 1) {
        throw SpecError("'granular' must be followed by a normal model of pair_style granular and its "
                        "coefficients (hooke, hertz, hertz/material, dmt, jkr), got '" +
                        s + "'");
    } else {
        Parsed p = parse_dashpot(w, 0, {}, true, context, WALL_STYLES);
        end = p.end;
        if (!p.has_laws)
            throw SpecError("no law: give E nu and the laws before the wall style, as in '1e7 0.3 hsd eps=0.5 "
                            "tangential mindlin mu=0.5 zplane 0 NULL', or fix wall/gran's granular words");
        if (!p.spec.has_material)
            throw SpecError("give the particles' Young's modulus and Poisson's ratio before law '" +
                            p.spec.law[NORMAL].name + "', as in '1e7 0.3 " + p.spec.law[NORMAL].name + " ...'");
        spec = p.spec;
        if (rigid_wall < 0) rigid_wall = 1;    // dashpot's own wall: rigid
    }
    if (rigid_wall < 0) rigid_wall = 0;    // fix wall/gran's: the particle's material
    if (spec.has_material) {
        young = spec.young;
        poisson = spec.poisson;
    }
    spec_index = models.add_spec(spec, context);
    layout = models.layout();
    return end;
}

void FixWallDashpot::parse_wall(const std::vector<std::string> &w, size_t i)
{
    const bool region_fix = strcmp(style, "wall/dashpot/region") == 0;
    const std::string styles = region_fix ? "region" : "xplane, yplane, zplane, zcylinder";
    if (i >= w.size())
        error->all(FLERR, "{}: expected a wall style ({}) after the models", context, styles);
    const std::string &ws = w[i];
    auto need = [&](size_t n) {
        if (i + n >= w.size())
            error->all(FLERR, "{}: wall style '{}' takes {} argument{}", context, ws, n, n > 1 ? "s" : "");
    };
    auto number = [&](const std::string &word) { return utils::numeric(FLERR, word, false, lmp); };
    if (region_fix) {
        if (ws != "region")
            error->all(FLERR, "{}: unknown wall style '{}' (valid: region R; planes and cylinders: fix wall/dashpot)",
                       context, ws);
        need(1);
        wallstyle = REGION;
        idregion = w[i + 1];
        i += 2;
    } else if (ws == "xplane" || ws == "yplane" || ws == "zplane") {
        need(2);
        wallstyle = ws == "xplane" ? XPLANE : ws == "yplane" ? YPLANE : ZPLANE;
        lo = w[i + 1] == "NULL" ? -BIG : number(w[i + 1]);
        hi = w[i + 2] == "NULL" ? BIG : number(w[i + 2]);
        if (lo >= hi) error->all(FLERR, "{}: the {} wall's lo {} must be below its hi {}", context, ws, lo, hi);
        i += 3;
    } else if (ws == "zcylinder") {
        need(1);
        wallstyle = ZCYLINDER;
        cylradius = number(w[i + 1]);
        if (!(cylradius > 0.0)) error->all(FLERR, "{}: the zcylinder's radius is {}, must be > 0", context, cylradius);
        i += 2;
    } else if (ws == "region") {
        error->all(FLERR, "{}: a region wall is fix wall/dashpot/region's (valid here: {})", context, styles);
    } else {
        error->all(FLERR, "{}: unknown wall style '{}' (valid: {})", context, ws, styles);
    }
    auto dim = [&](const std::string &d, const char *kw) {
        if (d == "x") return 0;
        if (d == "y") return 1;
        if (d == "z") return 2;
        error->all(FLERR, "{}: {} dimension '{}' (valid: x, y, z)", context, kw, d);
        return 0;
    };
    while (i < w.size()) {
        const std::string &k = w[i];
        if (k == "wiggle" && !region_fix) {
            if (i + 3 >= w.size()) error->all(FLERR, "{}: wiggle takes dim amplitude period", context);
            axis = dim(w[i + 1], "wiggle");
            amplitude = number(w[i + 2]);
            period = number(w[i + 3]);
            if (!(period > 0.0)) error->all(FLERR, "{}: the wiggle's period is {}, must be > 0", context, period);
            wiggle = 1;
            i += 4;
        } else if (k == "shear" && !region_fix) {
            if (i + 2 >= w.size()) error->all(FLERR, "{}: shear takes dim vshear", context);
            axis = dim(w[i + 1], "shear");
            vshear = number(w[i + 2]);
            wshear = 1;
            i += 3;
        } else if (k == "contacts") {
            contacts_flag = 1;
            i += 1;
        } else if (k == "temperature") {
            if (i + 1 >= w.size()) error->all(FLERR, "{}: temperature takes a value T or v_name", context);
            const std::string &t = w[i + 1];
            if (t.rfind("v_", 0) == 0 && t.size() > 2)
                temperature_var = t.substr(2);
            else
                wall_temperature = number(t);
            i += 2;
        } else {
            error->all(FLERR,
                       "{}: unknown keyword '{}' (valid: {}contacts, temperature, plugin_dir=DIR, energy=1, "
                       "wall=rigid|particle)",
                       context, k, region_fix ? "" : "wiggle, shear, ");
        }
    }
    // as fix wall/gran: a heat law and the wall's temperature come together
    const bool heat_law = models.any(HEAT), temperature = temperature_var.size() || !std::isnan(wall_temperature);
    if (heat_law && !temperature)
        error->all(FLERR, "{}: heat law '{}' needs the wall's temperature: add 'temperature T' or 'temperature v_name'",
                   context, models.spec(spec_index).law[HEAT].name);
    if (temperature && !heat_law)
        error->all(FLERR,
                   "{}: 'temperature' needs a heat law in the wall's model (granular syntax: 'heat area h' or "
                   "'heat radius k'; dashpot's: 'heat LAW key=value ...')",
                   context);
    const bool periodic[3] = {domain->xperiodic != 0, domain->yperiodic != 0, domain->zperiodic != 0};
    if (wallstyle <= ZPLANE && periodic[wallstyle])
        error->all(FLERR, "{}: a {} wall in a periodic dimension", context, WALL_STYLES[wallstyle]);
    if (wallstyle == ZCYLINDER && (periodic[0] || periodic[1]))
        error->all(FLERR, "{}: a zcylinder wall needs non-periodic x and y", context);
    if (wiggle && wshear) error->all(FLERR, "{}: wiggle and shear cannot be used together", context);
    if (wiggle && wallstyle == ZCYLINDER && axis != 2)
        error->all(FLERR, "{}: a zcylinder wiggles along z only", context);
    if (wshear && wallstyle <= ZPLANE && axis == wallstyle)
        error->all(FLERR, "{}: shear must be tangential to the wall ({} shears along the other two dimensions)",
                   context, WALL_STYLES[wallstyle]);
    if (wiggle) omega_wiggle = 2.0 * M_PI / period;
}

void FixWallDashpot::init()
{
    if (utils::strmatch(update->integrate_style, "^respa"))
        error->all(FLERR, "{} does not support run_style respa", context);
    fix_rigid = nullptr;
    for (auto *f : modify->get_fix_list())
        if (f->rigid_flag) {
            fix_rigid = f;
            break;
        }
    int dropped = 0;
    MPI_Allreduce(&restart_mismatch, &dropped, 1, MPI_INT, MPI_SUM, world);
    if (dropped > 0 && comm->me == 0)
        error->warning(FLERR,
                       "{}: the wall contacts of {} atoms in the restart file were written with other laws: their "
                       "history starts from zero",
                       context, dropped);
    restart_mismatch = 0;
    init_heat();
    bind_models();
}

/* The wall's temperature variable, and the per-atom arrays a heat law needs. */
void FixWallDashpot::init_heat()
{
    temperature_ivar = -1;
    if (!models.any(HEAT)) return;
    if (!atom->temperature_flag || !atom->heatflow_flag)
        error->all(FLERR,
                   "{}: a heat law needs per-atom temperature and heatflow: add 'fix ID all property/atom "
                   "temperature heatflow' (and 'fix ID all heat/flow constant CP' to integrate the temperatures)",
                   context);
    if (temperature_var.empty()) return;
    temperature_ivar = input->variable->find(temperature_var.c_str());
    if (temperature_ivar < 0)
        error->all(FLERR, "{}: variable '{}' of the wall's temperature does not exist", context, temperature_var);
    if (!input->variable->equalstyle(temperature_ivar))
        error->all(FLERR, "{}: variable '{}' of the wall's temperature is not equal-style", context, temperature_var);
}

/* The laws bound for every atom type (the materials of this run), and the engine configured. */
void FixWallDashpot::bind_models()
{
    const int nt = atom->ntypes;
    models.clear_models();
    model_of_type.assign(nt + 1, -1);
    try {
        for (int t = 1; t <= nt; t++) {
            Materials m;
            m.e1 = young;
            m.nu1 = poisson;
            if (rigid_wall) {
                m.rigid_wall = true;
            } else {
                m.e2 = young;
                m.nu2 = poisson;
            }
            model_of_type[t] = models.bind(spec_index, m, context + ", type " + std::to_string(t));
        }
    } catch (std::exception &e) {
        error->all(FLERR, "{}: {}", context, e.what());
    }
    EngineFlags fl;
    fl.rolling = models.any(ROLLING);
    fl.twisting = models.any(TWISTING);
    fl.energy = energy_flag;
    engine.configure(&models, layout, fl);
}

void FixWallDashpot::setup(int vflag)
{
    post_force(vflag);
}

/* The plane and cylinder walls: each atom of the group touches at most one. */
void FixWallDashpot::post_force(int /*vflag*/)
{
    update_rigid_masses();
    begin_step();
    double wlo = lo, whi = hi;
    double vwall[3] = {0.0, 0.0, 0.0};
    if (wiggle) {
        const double phase = omega_wiggle * (update->ntimestep - time_origin) * update->dt;
        if (wallstyle == axis) {
            wlo = lo + amplitude - amplitude * cos(phase);
            whi = hi + amplitude - amplitude * cos(phase);
        }
        vwall[axis] = amplitude * omega_wiggle * sin(phase);
    } else if (wshear && !(wallstyle == ZCYLINDER && axis != 2)) {
        vwall[axis] = vshear;
    }
    double **x = atom->x;
    const double *radius = atom->radius;
    const int *mask = atom->mask;
    const int nlocal = atom->nlocal;
    for (int i = 0; i < nlocal; i++) {
        if (!(mask[i] & groupbit)) continue;
        double n[3] = {0.0, 0.0, 0.0}, dist = 0.0, rwall = 0.0;
        double vw[3] = {vwall[0], vwall[1], vwall[2]};
        if (wallstyle <= ZPLANE) {
            const int d = wallstyle;
            const double below = x[i][d] - wlo, above = whi - x[i][d];
            // the nearer of the two walls
            const double s = below < above ? below : -above;
            dist = fabs(s);
            n[d] = s > 0.0 || (s == 0.0 && below < above) ? 1.0 : -1.0;
        } else {
            const double rxy = sqrt(x[i][0] * x[i][0] + x[i][1] * x[i][1]);
            const double gap = cylradius - rxy;
            dist = fabs(gap);
            if (dist < radius[i] + reach_of(i) && rxy > 0.0) {
                // from the wall to the particle: inwards inside the cylinder, outwards outside
                const double sgn = gap > 0.0 ? -1.0 : 1.0;
                n[0] = sgn * x[i][0] / rxy;
                n[1] = sgn * x[i][1] / rxy;
                rwall = rxy < cylradius ? -2.0 * cylradius : 2.0 * cylradius;
                if (wshear && axis != 2) {
                    // the cylinder spins about z: its surface moves at vshear, clockwise for vshear > 0
                    vw[0] = vshear * x[i][1] / rxy;
                    vw[1] = -vshear * x[i][0] / rxy;
                    vw[2] = 0.0;
                }
            } else {
                dist = BIG;
            }
        }
        const double delta = radius[i] - dist;
        if (ncontact[i] && !acts(i, 0, delta)) {
            forget(i, 0);
            ncontact[i] = 0;
        }
        if (!ncontact[i]) {
            if (!(delta > 0.0)) continue;
            ncontact[i] = 1;
            key[(size_t) i * nper] = 0;
        }
        const double reff = rwall == 0.0 ? radius[i] : radius[i] * rwall / (radius[i] + rwall);
        stage(i, 0, n, delta, reff, vw);
    }
    flush();
}

/* Restart files: the wiggle's time origin (the wall continues where it was). */
void FixWallDashpot::write_restart(FILE *fp)
{
    if (comm->me != 0) return;
    const double list[2] = {1.0, (double) time_origin};
    int size = sizeof(list);
    fwrite(&size, sizeof(int), 1, fp);
    fwrite(list, sizeof(double), 2, fp);
}

void FixWallDashpot::restart(char *buf)
{
    auto *list = reinterpret_cast<double *>(buf);
    if (list[0] == 1.0) time_origin = (bigint) list[1];
}
