/* What a contact is made of, as the words of an input deck give it: the spec layer of
 * pair_style dashpot (and of the wall fixes), with no LAMMPS header, so that it can be compiled
 * and tested alone (test_spec.cpp).
 *
 * A ContactSpec names one law per family (normal, tangential, rolling, twisting) with its
 * key=value parameters, the materials (Young's modulus E and Poisson's ratio nu of the particle
 * type), and the geometry conventions the pair style applies around the laws (where the
 * tangential force's torque acts). Parsers read dashpot's own syntax
 *
 *   [E nu] LAW [key=value ...] [tangential LAW [key=value ...]] [rolling LAW ...] [twisting LAW ...]
 *       [heat LAW ...]
 *
 * and mix the specs of two types into the one of an unset pair (as pair_style granular mixes:
 * the laws must be the same, the parameters take their geometric mean). Errors are SpecError
 * exceptions whose message names the bad word and the valid choices; the LAMMPS side turns them
 * into LAMMPS errors. */
#ifndef DASHPOT_SPEC_H
#define DASHPOT_SPEC_H

#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace dashpot_lmp {

/* The families of laws a contact carries: the four that act on the motion (forces and torques,
 * each with its history: NFAMILY), then heat conduction (sdk 0.4), which conducts heat between
 * the two bodies' temperatures and keeps no history here (NLAW laws in all). */
enum Family { NORMAL = 0, TANGENTIAL = 1, ROLLING = 2, TWISTING = 3, NFAMILY = 4, HEAT = 4, NLAW = 5 };

/* "normal", "tangential", "rolling", "twisting", "heat" */
extern const char *const FAMILY_NAME[NLAW];

struct Param {
    std::string key;
    double value;
    bool operator==(const Param &o) const { return key == o.key && value == o.value; }
};

/* One law of one family: its registry name and the parameters given (the others take the law's
 * defaults). An empty name: the family is absent. */
struct LawSpec {
    std::string name;
    std::vector<Param> params;
    bool present() const { return !name.empty(); }
    /* "hsd eps=0.5" */
    std::string describe() const;
    bool operator==(const LawSpec &o) const { return name == o.name && params == o.params; }
};

/* Where the pair style applies the tangential force's torque: at a radius from each centre
 * (dashpot's two-body driver, LAMMPS's classic gran/hooke... styles and walls), or at the contact
 * point, r - delta/2 from each centre (pair_style granular). */
enum class TorqueArm { RADIUS, CONTACT_POINT };

/* One granular model as LAMMPS reads it. */
struct GranularWords {
    std::string normal;    // hooke, hertz, hertz/material, dmt, jkr
    std::vector<double> ncoef;
    std::string damping = "viscoelastic";    // velocity, mass_velocity, viscoelastic, tsuji, coeff_restitution
    std::string tangential;                  // linear_nohistory, linear_history, mindlin, ... (classic: *_classic)
    std::vector<double> tcoef;               // mindlin's kt may be NULL: NaN here
    std::string rolling;                     // sds, or empty
    std::vector<double> rcoef;
    std::string twisting;    // marshall, sds, or empty
    std::vector<double> wcoef;
    std::string heat;    // radius, area, or empty (none)
    std::vector<double> hcoef;
    bool limit_damping = false;
    double cutoff = -1.0;    // pair_coeff's cutoff keyword (< 0: none)
    bool classic = false;    // from a classic style's arguments (torques at a radius from the centres)
    bool mixed = false;      // coefficients mixed from two types (LAMMPS's mixed_coefficients)
    bool present() const { return !normal.empty(); }
    bool operator==(const GranularWords &o) const;
};

/* Which syntax a spec was written in. */
enum class Syntax { DASHPOT, GRANULAR, CLASSIC };

struct ContactSpec {
    LawSpec law[NLAW];    // law[HEAT]: the heat-conduction law, or none
    bool has_material = false;    // E and nu given
    double young = 0.0;           // E (pressure units of the deck), > 0
    double poisson = 0.0;         // nu, -1 < nu < 0.5
    Syntax syntax = Syntax::DASHPOT;
    TorqueArm arm = TorqueArm::RADIUS;
    GranularWords granular;    // the granular or classic words it was translated from (mixing)
    /* the laws in order, "hsd eps=0.5 + mindlin mu=0.5" */
    std::string describe() const;
    /* the same laws and parameters (materials aside) */
    bool same_laws(const ContactSpec &o) const;
};

class SpecError : public std::runtime_error {
 public:
    using std::runtime_error::runtime_error;
};

/* The result of a parse: the spec, and the words the caller's options took (key=value words
 * whose key is one of `option_keys`, in the order given). */
struct Parsed {
    ContactSpec spec;
    std::vector<std::pair<std::string, std::string>> options;
    bool has_laws = false;    // a normal law was given
    size_t end = 0;           // the index of the first word not read (a stop word, or the end)
};

/* Reads a number the way a deck gives it (the whole word; finite). `what` names the argument in
 * the error. */
double parse_number(const std::string &word, const std::string &what);

/* dashpot's own syntax, from words[first..]:
 *   [E nu] [LAW [key=value ...] [tangential LAW ...] [rolling LAW ...] [twisting LAW ...] [heat LAW ...]]
 * `materials`: the words may start with the two numbers E nu (pair_coeff); `context` names the
 * command in messages ("pair_style dashpot", "pair_coeff 1 2"). A family keyword must be
 * followed by a law name (a word that is neither key=value nor a family keyword) and appears
 * once. Words of the form key=value before any law, or with a key in option_keys, are options.
 * A word of `stop` (where a law name or a family keyword could come) ends the parse (a wall
 * fix's wall style: 'zplane', 'region', ...); Parsed::end is its index. */
Parsed parse_dashpot(const std::vector<std::string> &words, size_t first, const std::vector<std::string> &option_keys,
                     bool materials, const std::string &context, const std::vector<std::string> &stop = {});

/* The default value of parameter `key` of law `law` (throws SpecError if the law has no such
 * parameter): the registry's schema, supplied by the caller. */
using ParamDefault = std::function<double(const std::string &law, const std::string &key)>;

/* The spec of an unset pair of types I != J from those of I I and J J, as pair_style granular
 * mixes: every family's law must be the same (else a SpecError naming both and the types);
 * each parameter given for either takes the geometric mean of the two values (the law's default
 * standing for one not given), exact when they are equal; parameters of opposite signs cannot be
 * mixed (a SpecError asks for an explicit pair_coeff). The materials stay those of each type:
 * the caller binds the laws to both. */
/* (Specs translated from granular or classic syntax mix as LAMMPS mixes the sub-models'
 * coefficients, then are translated again: dashpot_translate.h.) */
ContactSpec mix_specs(const ContactSpec &a, const ContactSpec &b, int itype, int jtype, const ParamDefault &default_of);

}    // namespace dashpot_lmp

#endif
