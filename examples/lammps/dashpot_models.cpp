/* The laws and bound models of an instance: see dashpot_models.h. */
#include "dashpot_models.h"

#include <algorithm>
#include <cmath>

namespace dashpot_lmp {

void check_status(int status, const std::string &what)
{
    if (status != DASHPOT_OK)
        throw SpecError(what + " failed (" + dashpot_status_name(status) + "): " + dashpot_last_error());
}

bool Layout::operator==(const Layout &o) const
{
    for (int f = 0; f < NFAMILY; f++)
        if (width[f] != o.width[f]) return false;
    return adhesive == o.adhesive;
}

ModelTable::~ModelTable()
{
    free_all();
}

void ModelTable::free_model(Model &m)
{
    dashpot_contact_model_free(m.normal);
    dashpot_tangential_model_free(m.tangential);
    dashpot_rolling_model_free(m.rolling);
    dashpot_twisting_model_free(m.twisting);
    dashpot_heat_model_free(m.heat);
}

void ModelTable::free_laws(SpecLaws &l)
{
    dashpot_contact_free(l.normal);
    dashpot_tangential_free(l.tangential);
    dashpot_rolling_free(l.rolling);
    dashpot_twisting_free(l.twisting);
    dashpot_heat_free(l.heat);
}

void ModelTable::clear_models()
{
    for (auto &m : models) free_model(m);
    models.clear();
    model_materials.clear();
}

void ModelTable::free_all()
{
    clear_models();
    for (auto &l : laws) free_laws(l);
    laws.clear();
    dashpot_registry_free(registry);
    registry = nullptr;
}

void ModelTable::open(const std::vector<std::string> &dirs)
{
    free_all();
    if (dashpot_abi_version() != DASHPOT_ABI_VERSION)
        throw SpecError("libdashpot_capi has ABI version " + std::to_string(dashpot_abi_version()) +
                        ", this plugin was built for " + std::to_string(DASHPOT_ABI_VERSION));
    std::vector<const char *> cdirs;
    for (auto &d : dirs) cdirs.push_back(d.c_str());
    check_status(dashpot_registry_open(cdirs.data(), cdirs.size(), 1, &registry), "opening the plugin registry");
}

/* Creates law `name` with `make` (dashpot_KIND_new); a name the registry does not know is tried
 * again with the family's prefix ("sds" for "rolling-sds"), and renamed if that exists. */
template <typename Law, typename Make>
static int make_law(Make make, DashpotRegistry *reg, const char *prefix, LawSpec &spec, Law **out)
{
    std::vector<const char *> keys;
    std::vector<double> values;
    for (auto &p : spec.params) {
        keys.push_back(p.key.c_str());
        values.push_back(p.value);
    }
    int st = make(reg, spec.name.c_str(), keys.data(), values.data(), values.size(), out);
    const std::string pre = std::string(prefix) + "-";
    size_t index = 0;
    // not the short name of a law of this family: a law of another kind keeps its message
    if (st != DASHPOT_ERR_UNKNOWN_LAW || pre == "-" || spec.name.rfind(pre, 0) == 0 ||
        dashpot_registry_find(reg, spec.name.c_str(), &index) == DASHPOT_OK)
        return st;
    // the library's message then names the prefixed name and lists the laws
    st = make(reg, (pre + spec.name).c_str(), keys.data(), values.data(), values.size(), out);
    if (st == DASHPOT_OK) spec.name = pre + spec.name;
    return st;
}

/* The number of history values a law of one family keeps: bound to materials with `bind`,
 * asked with `count`, freed with `release`. */
template <typename Law, typename Model, typename Bind, typename Count, typename Release>
static int slots_of(const Law *l, const DashpotMaterials &m, Bind bind, Count count, Release release,
                    const std::string &what)
{
    if (!l) return 0;
    Model *model = nullptr;
    size_t n = 0;
    check_status(bind(l, &m, &model), "binding the " + what);
    int st = count(model, &n);
    release(model);
    check_status(st, "the " + what + "'s history slots");
    return (int) n;
}

/* The slot counts of spec l's laws and whether its normal law is adhesive (reports a reach
 * beyond touching), probed with the spec's materials (placeholders when it has none: the count
 * of slots does not depend on them). */
void ModelTable::probe(SpecLaws &l, const std::string &context)
{
    DashpotMaterials m;
    const double e = l.spec.has_material ? l.spec.young : 1.0, nu = l.spec.has_material ? l.spec.poisson : 0.3;
    check_status(dashpot_materials_spheres(e, nu, e, nu, &m), context + ": the probe materials");
    l.slots[NORMAL] = slots_of<DashpotContactLaw, DashpotContactModel>(
        l.normal, m, dashpot_contact_bind_materials, dashpot_contact_model_history_slots, dashpot_contact_model_free,
        context + ": normal law '" + l.spec.law[NORMAL].name + "'");
    l.slots[TANGENTIAL] = slots_of<DashpotTangentialLaw, DashpotTangentialModel>(
        l.tangential, m, dashpot_tangential_bind_materials, dashpot_tangential_model_history_slots,
        dashpot_tangential_model_free, context + ": tangential law '" + l.spec.law[TANGENTIAL].name + "'");
    l.slots[ROLLING] = slots_of<DashpotRollingLaw, DashpotRollingModel>(
        l.rolling, m, dashpot_rolling_bind_materials, dashpot_rolling_model_history_slots, dashpot_rolling_model_free,
        context + ": rolling law '" + l.spec.law[ROLLING].name + "'");
    l.slots[TWISTING] = slots_of<DashpotTwistingLaw, DashpotTwistingModel>(
        l.twisting, m, dashpot_twisting_bind_materials, dashpot_twisting_model_history_slots,
        dashpot_twisting_model_free, context + ": twisting law '" + l.spec.law[TWISTING].name + "'");
    // adhesive: a positive reach once a unit-radius contact has formed (any units: only the
    // sign is read). Probed at touching and at two overlaps: a law may count a contact as formed
    // only past touching (LAMMPS's JKR forms at delta > 0, dashpot's jkr at delta >= 0).
    DashpotContactModel *cm = nullptr;
    check_status(dashpot_contact_bind_materials(l.normal, &m, &cm), context + ": binding the normal law");
    double reach = 0.0;
    int st = 0;
    for (double delta : {0.0, 1e-9, 1e-2}) {
        std::vector<double> h(l.slots[NORMAL] > 0 ? l.slots[NORMAL] : 1, 0.0);
        double rate = 0.0, mass = 1.0, radius = 1.0, f = 0.0, r = 0.0;
        st = dashpot_contact_model_force_batch_energy(cm, 1, &delta, &rate, &mass, &radius, h.data(), l.slots[NORMAL],
                                                      &f, &r, nullptr, nullptr, nullptr);
        if (st != 0) break;
        reach = std::max(reach, r);
    }
    dashpot_contact_model_free(cm);
    check_status(st, context + ": probing the normal law's reach");
    l.adhesive = reach > 0.0;
}

int ModelTable::add_spec(const ContactSpec &spec, const std::string &context)
{
    if (!registry) throw SpecError(context + ": no plugin registry (pair_style first)");
    if (!spec.law[NORMAL].present()) throw SpecError(context + ": no normal law");
    for (int s = 0; s < (int) laws.size(); s++)
        if (laws[s].spec.same_laws(spec)) return s;
    SpecLaws l;
    l.spec = spec;
    // freed by free_all if a later step throws
    laws.push_back(l);
    SpecLaws &n = laws.back();
    try {
        check_status(make_law(dashpot_contact_new, registry, "", n.spec.law[NORMAL], &n.normal),
                     context + ": creating the normal law");
        if (n.spec.law[TANGENTIAL].present())
            check_status(make_law(dashpot_tangential_new, registry, "", n.spec.law[TANGENTIAL], &n.tangential),
                         context + ": creating the tangential law");
        if (n.spec.law[ROLLING].present())
            check_status(make_law(dashpot_rolling_new, registry, "rolling", n.spec.law[ROLLING], &n.rolling),
                         context + ": creating the rolling law");
        if (n.spec.law[TWISTING].present())
            check_status(make_law(dashpot_twisting_new, registry, "twisting", n.spec.law[TWISTING], &n.twisting),
                         context + ": creating the twisting law");
        if (n.spec.law[HEAT].present())
            check_status(make_law(dashpot_heat_new, registry, "heat", n.spec.law[HEAT], &n.heat),
                         context + ": creating the heat law");
        probe(n, context);
    } catch (...) {
        free_laws(n);
        laws.pop_back();
        throw;
    }
    // a resolved short name ("sds" -> "rolling-sds") may equal an existing spec: keep one
    for (int s = 0; s + 1 < (int) laws.size(); s++)
        if (laws[s].spec.same_laws(n.spec)) {
            free_laws(n);
            laws.pop_back();
            return s;
        }
    return (int) laws.size() - 1;
}

double ModelTable::param_default(const std::string &law, const std::string &key) const
{
    size_t index = 0;
    check_status(dashpot_registry_find(registry, law.c_str(), &index), "finding law '" + law + "'");
    DashpotLawInfo info;
    check_status(dashpot_registry_law_info(registry, index, &info), "describing law '" + law + "'");
    std::string names;
    for (size_t p = 0; p < info.n_params; p++) {
        DashpotParamInfo pi;
        check_status(dashpot_registry_param_info(registry, index, p, &pi), "describing law '" + law + "'");
        if (key == pi.name) {
            if (!pi.has_default)
                throw SpecError("parameter '" + key + "' of law '" + law +
                                "' has no default (the law derives it from the materials): give it for both types, "
                                "or give the pair of types its own pair_coeff");
            return pi.default_value;
        }
        names += std::string(names.empty() ? "" : ", ") + pi.name;
    }
    throw SpecError("law '" + law + "' has no parameter '" + key + "' (its parameters: " + names + ")");
}

int ModelTable::bind(int s, const Materials &mat, const std::string &context)
{
    for (int id = 0; id < (int) models.size(); id++)
        if (models[id].spec == s && model_materials[id] == mat) return id;
    const SpecLaws &l = laws[s];
    DashpotMaterials m;
    if (mat.rigid_wall)
        check_status(dashpot_materials_wall(mat.e1, mat.nu1, &m), context + ": the materials of a particle and the wall");
    else
        check_status(dashpot_materials_spheres(mat.e1, mat.nu1, mat.e2, mat.nu2, &m),
                     context + ": combining the materials of a pair of types");
    Model md;
    md.spec = s;
    for (int f = 0; f < NFAMILY; f++) md.slots[f] = l.slots[f];
    md.adhesive = l.adhesive;
    md.arm = l.spec.arm;
    try {
        check_status(dashpot_contact_bind_materials(l.normal, &m, &md.normal), context + ": binding the normal law");
        if (l.tangential)
            check_status(dashpot_tangential_bind_materials(l.tangential, &m, &md.tangential),
                         context + ": binding the tangential law");
        if (l.rolling)
            check_status(dashpot_rolling_bind_materials(l.rolling, &m, &md.rolling), context + ": binding the rolling law");
        if (l.twisting)
            check_status(dashpot_twisting_bind_materials(l.twisting, &m, &md.twisting),
                         context + ": binding the twisting law");
        if (l.heat) check_status(dashpot_heat_bind_materials(l.heat, &m, &md.heat), context + ": binding the heat law");
    } catch (...) {
        free_model(md);
        throw;
    }
#if DASHPOT_LMP_CONTEXT
    int reads = 0;
    if (md.tangential && dashpot_tangential_model_reads_context(md.tangential, &reads) == DASHPOT_OK)
        md.reads_context[TANGENTIAL] = reads != 0;
    if (md.rolling && dashpot_rolling_model_reads_context(md.rolling, &reads) == DASHPOT_OK)
        md.reads_context[ROLLING] = reads != 0;
    if (md.twisting && dashpot_twisting_model_reads_context(md.twisting, &reads) == DASHPOT_OK)
        md.reads_context[TWISTING] = reads != 0;
    if (md.heat && dashpot_heat_model_reads_context(md.heat, &reads) == DASHPOT_OK)
        md.reads_context[HEAT] = reads != 0;
    md.any_context = md.reads_context[TANGENTIAL] || md.reads_context[ROLLING] || md.reads_context[TWISTING] ||
        md.reads_context[HEAT];
#endif
    models.push_back(md);
    model_materials.push_back(mat);
    return (int) models.size() - 1;
}

Layout ModelTable::layout() const
{
    Layout lay;
    for (auto &l : laws) {
        for (int f = 0; f < NFAMILY; f++) lay.width[f] = std::max(lay.width[f], l.slots[f]);
        lay.adhesive = lay.adhesive || l.adhesive;
    }
    int at = 0;
    for (int f = 0; f < NFAMILY; f++) {
        lay.offset[f] = at;
        at += lay.width[f];
    }
    lay.reach_at = at;
    lay.nvalues = at + (lay.adhesive ? 1 : 0);
    return lay;
}

bool ModelTable::any(Family f) const
{
    for (auto &l : laws)
        if (l.spec.law[f].present()) return true;
    return false;
}

double ModelTable::probe_reach(int id, double radius) const
{
    const Model &md = models[id];
    double reach = 0.0;
    for (double d : {1e-9 * radius, 1e-2 * radius}) {
        std::vector<double> h(md.slots[NORMAL] > 0 ? md.slots[NORMAL] : 1, 0.0);
        double rate = 0.0, mass = 1.0, f = 0.0, r = 0.0;
        check_status(dashpot_contact_model_force_batch_energy(md.normal, 1, &d, &rate, &mass, &radius, h.data(),
                                                              md.slots[NORMAL], &f, &r, nullptr, nullptr, nullptr),
                     "probing the normal law's reach");
        reach = std::max(reach, r);
    }
    return reach;
}

}    // namespace dashpot_lmp
