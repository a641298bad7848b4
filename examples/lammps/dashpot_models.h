/* The models of one pair style instance (or wall fix): the laws of each ContactSpec, created once
 * from the plugin registry, and their models bound to pairs of materials (a pair of particle
 * types, or a particle type and a wall), deduplicated, plus the history record layout all of
 * them share. Uses the dashpot C ABI (dashpot.h), no LAMMPS header. Errors are SpecError
 * exceptions carrying the library's message. */
#ifndef DASHPOT_MODELS_H
#define DASHPOT_MODELS_H

#include "dashpot_spec.h"

#include "dashpot.h"

#include <string>
#include <vector>

namespace dashpot_lmp {

/* The materials a model is bound to: two spheres (E1, nu1 and E2, nu2), or a sphere against a
 * rigid flat wall (E1, nu1 only: dashpot_materials_wall). */
struct Materials {
    double e1 = 0.0, nu1 = 0.0, e2 = 0.0, nu2 = 0.0;
    bool rigid_wall = false;
    bool operator==(const Materials &o) const
    {
        return e1 == o.e1 && nu1 == o.nu1 && e2 == o.e2 && nu2 == o.nu2 && rigid_wall == o.rigid_wall;
    }
};

/* The history record every contact of an instance carries, whatever its model: each family's
 * slots at the largest width any of the instance's laws needs (a model packs its own, smaller
 * width for its batch calls), then, when some normal law is adhesive, the reach of the contact's
 * last normal-law call (length units). */
struct Layout {
    int width[NFAMILY] = {0, 0, 0, 0};
    int offset[NFAMILY] = {0, 0, 0, 0};
    bool adhesive = false;
    int reach_at = 0;
    int nvalues = 0;
    bool operator==(const Layout &o) const;
    bool operator!=(const Layout &o) const { return !(*this == o); }
};

/* One spec's laws bound to one pair of materials. */
struct Model {
    int spec = -1;
    DashpotContactModel *normal = nullptr;
    DashpotTangentialModel *tangential = nullptr;
    DashpotRollingModel *rolling = nullptr;
    DashpotTwistingModel *twisting = nullptr;
    DashpotHeatModel *heat = nullptr;    // sdk 0.4: the heat-conduction law, or none
    int slots[NFAMILY] = {0, 0, 0, 0};
    bool adhesive = false;
    TorqueArm arm = TorqueArm::RADIUS;
    /* sdk 0.4: the family's law reads the normal law's context (contact radius, cap force,
     * damping), which the normal law then reports (any_context) */
    bool reads_context[NLAW] = {false, false, false, false, false};
    bool any_context = false;
};

/* Whether this build's C ABI carries sdk 0.4's normal context. */
#ifdef DASHPOT_REACH_ENERGY_CONTEXT_OUTPUTS
#define DASHPOT_LMP_CONTEXT 1
#else
#define DASHPOT_LMP_CONTEXT 0
#endif

class ModelTable {
 public:
    ModelTable() = default;
    ModelTable(const ModelTable &) = delete;
    ModelTable &operator=(const ModelTable &) = delete;
    ~ModelTable();

    /* Opens the plugin registry: the directories, then $DASHPOT_PLUGIN_PATH. Frees everything
     * held before. */
    void open(const std::vector<std::string> &dirs);
    bool is_open() const { return registry != nullptr; }

    /* Creates the laws of `spec` (a short name after rolling/twisting resolved: "sds" is
     * "rolling-sds") and returns its index; an identical spec returns the existing index.
     * `context` prefixes the messages. */
    int add_spec(const ContactSpec &spec, const std::string &context);
    const ContactSpec &spec(int s) const { return laws[s].spec; }
    int nspecs() const { return (int) laws.size(); }

    /* The default of parameter `key` of law `law` (of any family), from the registry's schema;
     * throws SpecError if the law has no such parameter. */
    double param_default(const std::string &law, const std::string &key) const;

    /* The model of spec s bound to materials m (the same spec and materials: the same model). */
    int bind(int s, const Materials &m, const std::string &context);
    const Model &model(int id) const { return models[id]; }
    int nmodels() const { return (int) models.size(); }
    /* Frees the bound models (the materials may change between runs); the laws stay. */
    void clear_models();

    /* The record layout over every spec added so far. */
    Layout layout() const;
    /* Whether some spec has a law of family f (rolling, twisting, heat). */
    bool any(Family f) const;

    /* The reach (length) of a fresh contact of effective radius `radius` under model id: the
     * largest the normal law reports at a touch and at a 1 % overlap, from zero history. */
    double probe_reach(int id, double radius) const;

 private:
    struct SpecLaws {
        ContactSpec spec;
        DashpotContactLaw *normal = nullptr;
        DashpotTangentialLaw *tangential = nullptr;
        DashpotRollingLaw *rolling = nullptr;
        DashpotTwistingLaw *twisting = nullptr;
        DashpotHeatLaw *heat = nullptr;
        int slots[NFAMILY] = {0, 0, 0, 0};
        bool adhesive = false;
    };
    DashpotRegistry *registry = nullptr;
    std::vector<SpecLaws> laws;
    std::vector<Model> models;
    std::vector<Materials> model_materials;
    void free_all();
    void probe(SpecLaws &l, const std::string &context);
    static void free_laws(SpecLaws &l);
    static void free_model(Model &m);
};

/* Throws SpecError "`what` failed (STATUS): library message" unless status is DASHPOT_OK. */
void check_status(int status, const std::string &what);
/* The same for a name known at compile time (each batch call of a step): no string is made
 * unless the call failed. */
inline void check_status(int status, const char *what)
{
    if (status != DASHPOT_OK) check_status(status, std::string(what));
}

}    // namespace dashpot_lmp

#endif
