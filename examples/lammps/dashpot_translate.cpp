/* LAMMPS's granular syntaxes translated to the gran-* laws: see dashpot_translate.h. */
#include "dashpot_translate.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace dashpot_lmp {

namespace {

struct SubModel {
    const char *name;
    int ncoeffs;
};

const SubModel NORMALS[] = {{"hooke", 2}, {"hertz", 2}, {"hertz/material", 3}, {"dmt", 4}, {"jkr", 4}};
const char *const DAMPINGS[] = {"velocity", "mass_velocity", "viscoelastic", "tsuji", "coeff_restitution"};
const SubModel TANGENTIALS[] = {{"linear_nohistory", 2},      {"linear_history", 3},  {"linear_history_classic", 3},
                                {"mindlin", 3},               {"mindlin_rescale", 3}, {"mindlin/force", 3},
                                {"mindlin_rescale/force", 3}, {"mindlin_classic", 3}};
const SubModel ROLLINGS[] = {{"sds", 3}};
const SubModel TWISTINGS[] = {{"marshall", 0}, {"sds", 3}};
const SubModel HEATS[] = {{"none", 0}, {"radius", 1}, {"area", 1}};

template <size_t N> const SubModel *find(const SubModel (&table)[N], const std::string &name)
{
    for (auto &s : table)
        if (name == s.name) return &s;
    return nullptr;
}

template <size_t N> std::string names(const SubModel (&table)[N])
{
    std::string s;
    for (auto &m : table) s += std::string(s.empty() ? "" : ", ") + m.name;
    return s;
}

bool is_number_or_null(const std::string &w)
{
    if (w == "NULL") return true;
    const char *s = w.c_str();
    char *end = nullptr;
    std::strtod(s, &end);
    return !w.empty() && end != s && *end == '\0';
}

bool material(const std::string &normal)
{
    return normal == "hertz/material" || normal == "dmt" || normal == "jkr";
}

bool mindlin(const std::string &t)
{
    return t.rfind("mindlin", 0) == 0;
}

bool cohesive(const std::string &normal)
{
    return normal == "dmt" || normal == "jkr";
}

/* LAMMPS's mixing rules */
double mix_geom(double a, double b)
{
    return std::sqrt(a * b);
}

double mix_stiffness_e(double e1, double e2, double nu1, double nu2)
{
    return 1.0 / ((1.0 - nu1 * nu1) / e1 + (1.0 - nu2 * nu2) / e2);
}

std::string dashes(std::string s)
{
    for (auto &c : s)
        if (c == '_' || c == '/') c = '-';
    return s;
}

}    // namespace

bool GranularWords::operator==(const GranularWords &o) const
{
    auto same = [](const std::vector<double> &a, const std::vector<double> &b) {
        if (a.size() != b.size()) return false;
        for (size_t i = 0; i < a.size(); i++)
            if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
        return true;
    };
    return normal == o.normal && same(ncoef, o.ncoef) && damping == o.damping && tangential == o.tangential &&
        same(tcoef, o.tcoef) && rolling == o.rolling && same(rcoef, o.rcoef) && twisting == o.twisting &&
        same(wcoef, o.wcoef) && heat == o.heat && same(hcoef, o.hcoef) && limit_damping == o.limit_damping && cutoff == o.cutoff && classic == o.classic &&
        mixed == o.mixed;
}

const std::vector<TranslationRow> &translation_table()
{
    static const std::vector<TranslationRow> rows = {
        {"normal", "hooke", "k damp", "gran-hooke-D", "k, damp", "exact"},
        {"normal", "hertz", "k damp", "gran-hertz-D", "k, damp", "exact"},
        {"normal", "hertz/material", "E damp nu", "gran-hertz-material-D", "damp (E, nu: the materials)", "exact"},
        {"normal", "dmt", "E damp nu cohesion", "gran-dmt-D", "damp, cohesion (E, nu: the materials)",
         "exact; D = tsuji, coeff_restitution refused (as LAMMPS)"},
        {"normal", "jkr", "E damp nu cohesion", "gran-jkr-D", "damp, cohesion (E, nu: the materials)",
         "exact; D = tsuji, coeff_restitution refused (as LAMMPS)"},
        {"normal", "mdr", "E nu Y gamma psi_b damp", "", "", "refused: out of scope"},
        {"damping", "velocity", "", "D = velocity", "", "exact"},
        {"damping", "mass_velocity", "", "D = mass-velocity", "", "exact"},
        {"damping", "viscoelastic", "", "D = viscoelastic (the default)", "", "exact"},
        {"damping", "tsuji", "", "D = tsuji", "", "exact"},
        {"damping", "coeff_restitution", "", "D = coeff-restitution", "", "exact"},
        {"tangential", "linear_nohistory", "xt mu", "gran-linear-nohistory", "xt, mu", "exact"},
        {"tangential", "linear_history", "kt xt mu", "gran-linear-history", "kt, xt, mu", "exact"},
        {"tangential", "mindlin", "kt|NULL xt mu", "gran-mindlin", "kt (left out for NULL), xt, mu", "exact"},
        {"tangential", "mindlin_rescale", "kt|NULL xt mu", "gran-mindlin-rescale", "kt, xt, mu", "exact"},
        {"tangential", "mindlin/force", "kt|NULL xt mu", "gran-mindlin-force", "kt, xt, mu", "exact"},
        {"tangential", "mindlin_rescale/force", "kt|NULL xt mu", "gran-mindlin-rescale-force", "kt, xt, mu", "exact"},
        {"rolling", "sds", "k gamma mu", "gran-rolling-sds", "k, gamma, mu", "exact"},
        {"twisting", "marshall", "", "gran-twisting-marshall", "kt, xt, mu of the tangential model", "exact"},
        {"twisting", "sds", "k gamma mu", "gran-twisting-sds", "k, gamma, mu", "exact"},
        {"keyword", "limit_damping", "", "the normal law's limit_damping=1", "", "exact"},
        {"keyword", "cutoff", "X", "the pair's neighbour cutoff", "", "exact"},
        {"heat", "radius", "k", "heat-radius", "k", "exact (a: the normal law's contact radius)"},
        {"heat", "area", "h", "heat-area", "h", "exact (a: the normal law's contact radius)"},
        {"heat", "none", "", "(no heat law)", "", "exact"},
        {"classic", "gran/hooke", "kn kt gamman gammat xmu dampflag",
         "gran-hooke-mass-velocity + gran-linear-nohistory", "k=kn damp=gamman; xt=gammat/gamman mu=xmu", "exact"},
        {"tangential", "linear_history_classic, mindlin_classic", "kt xt mu", "gran-wall-history-classic",
         "kt, xt, mu", "exact"},
        {"classic", "gran/hooke/history", "kn kt gamman gammat xmu dampflag",
         "gran-hooke-mass-velocity + gran-linear-history-classic", "k=kn damp=gamman; kt xt=gammat/gamman mu=xmu",
         "exact"},
        {"classic", "gran/hertz/history", "kn kt gamman gammat xmu dampflag",
         "gran-hertz-viscoelastic + gran-mindlin-classic",
         "k=kn/nktv2p damp=gamman; kt=kt/nktv2p xt=gammat/gamman mu=xmu", "exact"},
    };
    return rows;
}

std::string normal_law_name(const std::string &normal, const std::string &damping)
{
    return "gran-" + dashes(normal) + "-" + dashes(damping);
}

bool is_granular(const std::vector<std::string> &words, size_t first)
{
    if (first + 1 >= words.size()) return false;
    const std::string &w = words[first];
    if (!find(NORMALS, w) && w != "mdr") return false;
    return is_number_or_null(words[first + 1]);
}

/* The coefficients of sub-model `name` (n of them) after words[i]; NULL allowed where
 * `null_ok` (as NaN). */
static std::vector<double> coefficients(const std::vector<std::string> &words, size_t &i, int n,
                                        const std::string &family, const std::string &name, bool null_ok,
                                        const std::string &context)
{
    std::vector<double> c;
    for (int k = 0; k < n; k++) {
        if (i + 1 >= words.size() || !is_number_or_null(words[i + 1]))
            throw SpecError(context + ": " + family + " model '" + name + "' takes " + std::to_string(n) +
                            " coefficients, got " + std::to_string(k) +
                            (i + 1 < words.size() ? " before '" + words[i + 1] + "'" : ""));
        const std::string &w = words[++i];
        if (w == "NULL") {
            if (!(null_ok && k == 0))
                throw SpecError(context + ": NULL is allowed only for the stiffness kt of a mindlin tangential "
                                "model (coefficient " +
                                std::to_string(k + 1) + " of " + family + " model '" + name + "')");
            c.push_back(std::numeric_limits<double>::quiet_NaN());
        } else {
            double v = parse_number(w, context + ": coefficient " + std::to_string(k + 1) + " of " + family +
                                           " model '" + name + "'");
            if (v < 0.0)
                throw SpecError(context + ": coefficient " + std::to_string(k + 1) + " of " + family + " model '" +
                                name + "' is " + w + ", must be >= 0");
            c.push_back(v);
        }
    }
    return c;
}

GranularWords parse_granular(const std::vector<std::string> &words, size_t first, const std::string &context,
                             const std::vector<std::string> &stop, size_t *end)
{
    GranularWords g;
    if (first >= words.size()) throw SpecError(context + ": expected a normal model (" + names(NORMALS) + ")");
    size_t i = first;
    const std::string &nm = words[i];
    if (nm == "mdr") throw SpecError(context + ": normal model 'mdr' is out of the scope of pair_style dashpot");
    const SubModel *n = find(NORMALS, nm);
    if (!n) throw SpecError(context + ": unknown normal model '" + nm + "' (valid: " + names(NORMALS) + ")");
    g.normal = nm;
    g.ncoef = coefficients(words, i, n->ncoeffs, "normal", nm, false, context);
    bool damping_given = false;
    for (i++; i < words.size(); i++) {
        const std::string &w = words[i];
        bool stops = false;
        for (auto &s : stop) stops = stops || w == s;
        if (stops) break;
        auto next = [&](const char *what) -> const std::string & {
            if (i + 1 >= words.size()) throw SpecError(context + ": '" + w + "' must be followed by a " + what);
            return words[++i];
        };
        if (w == "damping") {
            const std::string &d = next("damping model");
            bool ok = false;
            for (auto *name : DAMPINGS) ok = ok || d == name;
            if (!ok)
                throw SpecError(context + ": unknown damping model '" + d +
                                "' (valid: velocity, mass_velocity, viscoelastic, tsuji, coeff_restitution)");
            if (damping_given) throw SpecError(context + ": 'damping' is given twice");
            damping_given = true;
            g.damping = d;
        } else if (w == "tangential" || w == "rolling" || w == "twisting") {
            const std::string &m = next((w + " model").c_str());
            if (w == "tangential") {
                const SubModel *t = find(TANGENTIALS, m);
                if (!t) throw SpecError(context + ": unknown tangential model '" + m + "' (valid: " + names(TANGENTIALS) + ")");
                if (!g.tangential.empty()) throw SpecError(context + ": 'tangential' is given twice");
                g.tangential = m;
                g.tcoef = coefficients(words, i, t->ncoeffs, "tangential", m, mindlin(m), context);
            } else if (w == "rolling") {
                const SubModel *r = find(ROLLINGS, m);
                if (!r) throw SpecError(context + ": unknown rolling model '" + m + "' (valid: " + names(ROLLINGS) + ")");
                if (!g.rolling.empty()) throw SpecError(context + ": 'rolling' is given twice");
                g.rolling = m;
                g.rcoef = coefficients(words, i, r->ncoeffs, "rolling", m, false, context);
            } else {
                const SubModel *t = find(TWISTINGS, m);
                if (!t) throw SpecError(context + ": unknown twisting model '" + m + "' (valid: " + names(TWISTINGS) + ")");
                if (!g.twisting.empty()) throw SpecError(context + ": 'twisting' is given twice");
                g.twisting = m;
                g.wcoef = coefficients(words, i, t->ncoeffs, "twisting", m, false, context);
            }
        } else if (w == "limit_damping") {
            g.limit_damping = true;
        } else if (w == "cutoff") {
            g.cutoff = parse_number(next("cutoff distance"), context + ": cutoff");
            if (!(g.cutoff > 0.0)) throw SpecError(context + ": cutoff must be > 0, got " + words[i]);
        } else if (w == "heat") {
            const std::string &m = next("heat model");
            const SubModel *h = find(HEATS, m);
            if (!h) throw SpecError(context + ": unknown heat model '" + m + "' (valid: " + names(HEATS) + ")");
            if (!g.heat.empty()) throw SpecError(context + ": 'heat' is given twice");
            g.heat = m;
            g.hcoef = coefficients(words, i, h->ncoeffs, "heat", m, false, context);
        } else {
            std::string valid = "damping, tangential, rolling, twisting, heat, limit_damping, cutoff";
            for (auto &s : stop) valid += ", " + s;
            throw SpecError(context + ": unknown keyword '" + w + "' (valid: " + valid + ")");
        }
    }
    if (end) *end = i;
    if (g.tangential.empty())
        throw SpecError(context + ": a granular model needs a tangential model, as in pair_style granular (for "
                        "none: 'tangential linear_nohistory 0 0')");
    if (mindlin(g.tangential) && std::isnan(g.tcoef[0]) && !material(g.normal))
        throw SpecError(context + ": tangential '" + g.tangential +
                        "' with kt NULL takes its stiffness from the materials: it needs a normal model with "
                        "material properties (hertz/material, dmt, jkr), not '" +
                        g.normal + "'");
    if (cohesive(g.normal) && (g.tangential == "mindlin_rescale" || g.tangential == "mindlin_rescale/force"))
        throw SpecError(context + ": tangential '" + g.tangential + "' cannot be used with a cohesive normal model ('" +
                        g.normal + "'), as in pair_style granular");
    if (cohesive(g.normal) && (g.damping == "tsuji" || g.damping == "coeff_restitution"))
        throw SpecError(context + ": damping '" + g.damping + "' cannot be used with a cohesive normal model ('" +
                        g.normal + "'), as in pair_style granular (valid: velocity, mass_velocity, viscoelastic)");
    if (cohesive(g.normal) && g.limit_damping)
        throw SpecError(context + ": limit_damping cannot be used with a cohesive normal model ('" + g.normal +
                        "'), as in pair_style granular");
    return g;
}

GranularWords parse_classic(const std::string &style, const std::vector<std::string> &words, size_t first,
                            double nktv2p, const std::string &context, const std::vector<std::string> &stop,
                            size_t *end)
{
    if (style != "hooke" && style != "hooke/history" && style != "hertz/history")
        throw SpecError(context + ": unknown classic style 'gran/" + style +
                        "' (valid: gran/hooke, gran/hooke/history, gran/hertz/history)");
    size_t last = first;    // the arguments run to a stop word (a wall fix's wall style) or the end
    while (last < words.size()) {
        bool stops = false;
        for (auto &s : stop) stops = stops || words[last] == s;
        if (stops) break;
        last++;
    }
    if (end) *end = last;
    const size_t n = last - first;
    if (n < 6 || n > 7 || (n == 7 && words[first + 6] != "limit_damping"))
        throw SpecError(context + ": gran/" + style + " takes kn kt gamman gammat xmu dampflag [limit_damping], got " +
                        std::to_string(n) + " arguments");
    auto num = [&](size_t k, const char *what) {
        return parse_number(words[first + k], context + ": " + what);
    };
    double kn = num(0, "kn");
    double kt = words[first + 1] == "NULL" ? kn * 2.0 / 7.0 : num(1, "kt");
    double gamman = num(2, "gamman");
    double gammat = words[first + 3] == "NULL" ? 0.5 * gamman : num(3, "gammat");
    double xmu = num(4, "xmu");
    const std::string &df = words[first + 5];
    if (df != "0" && df != "1") throw SpecError(context + ": dampflag is '" + df + "', must be 0 or 1");
    if (df == "0") gammat = 0.0;
    if (kn < 0.0 || kt < 0.0 || gamman < 0.0 || gammat < 0.0 || xmu < 0.0 || xmu > 10000.0)
        throw SpecError(context + ": need kn, kt, gamman, gammat >= 0 and 0 <= xmu <= 10000");
    if (gamman == 0.0 && gammat > 0.0)
        throw SpecError(context + ": gammat > 0 with gamman = 0: the tangential damping is a multiple of the "
                        "normal one (LAMMPS's xt = gammat/gamman), give gamman > 0");
    const double xt = gamman > 0.0 ? gammat / gamman : 0.0;
    GranularWords g;
    g.classic = true;
    g.limit_damping = n == 7;
    if (style == "hertz/history") {
        kn /= nktv2p;
        kt /= nktv2p;
        g.normal = "hertz";
        g.damping = "viscoelastic";
        g.tangential = "mindlin_classic";
        g.tcoef = {kt, xt, xmu};
    } else {
        g.normal = "hooke";
        g.damping = "mass_velocity";
        g.tangential = style == "hooke" ? "linear_nohistory" : "linear_history_classic";
        g.tcoef = style == "hooke" ? std::vector<double>{xt, xmu} : std::vector<double>{kt, xt, xmu};
    }
    g.ncoef = {kn, gamman};
    return g;
}

GranularWords mix_granular(const GranularWords &a, const GranularWords &b, int itype, int jtype)
{
    const std::string types = std::to_string(itype) + " " + std::to_string(itype) + " and " + std::to_string(jtype) +
        " " + std::to_string(jtype);
    auto differ = [&](const char *family, const std::string &x, const std::string &y) {
        if (x != y)
            throw SpecError("cannot mix the " + std::string(family) + " models of types " + types + " ('" +
                            (x.empty() ? "none" : x) + "' and '" + (y.empty() ? "none" : y) + "'): give pair_coeff " +
                            std::to_string(itype) + " " + std::to_string(jtype) + " explicitly");
    };
    differ("normal", a.normal, b.normal);
    differ("damping", a.damping, b.damping);
    differ("tangential", a.tangential, b.tangential);
    differ("rolling", a.rolling, b.rolling);
    differ("twisting", a.twisting, b.twisting);
    // LAMMPS's heat model none is no heat law
    differ("heat", a.heat == "none" ? "" : a.heat, b.heat == "none" ? "" : b.heat);
    if (a.classic != b.classic) throw SpecError("cannot mix a classic and a granular model (types " + types + ")");
    GranularWords m = a;
    auto geom = [](const std::vector<double> &x, const std::vector<double> &y) {
        std::vector<double> r(x.size());
        for (size_t k = 0; k < x.size(); k++) r[k] = mix_geom(x[k], y[k]);
        return r;
    };
    if (material(a.normal)) {
        m.ncoef = geom(a.ncoef, b.ncoef);
        m.ncoef[0] = mix_stiffness_e(a.ncoef[0], b.ncoef[0], a.ncoef[2], b.ncoef[2]);
    } else {
        m.ncoef = geom(a.ncoef, b.ncoef);
    }
    m.tcoef = geom(a.tcoef, b.tcoef);
    if (mindlin(a.tangential) && (std::isnan(a.tcoef[0]) || std::isnan(b.tcoef[0])))
        m.tcoef[0] = std::numeric_limits<double>::quiet_NaN();
    m.rcoef = geom(a.rcoef, b.rcoef);
    m.wcoef = geom(a.wcoef, b.wcoef);
    m.hcoef = geom(a.hcoef, b.hcoef);
    m.limit_damping = a.limit_damping || b.limit_damping;
    m.cutoff = std::max(a.cutoff, b.cutoff);
    m.mixed = true;
    return m;
}

ContactSpec translate_granular(const GranularWords &g, const std::string &context, bool wall)
{
    if (!g.present()) throw SpecError(context + ": no granular model");
    ContactSpec s;
    s.syntax = g.classic ? Syntax::CLASSIC : Syntax::GRANULAR;
    s.arm = g.classic || wall ? TorqueArm::RADIUS : TorqueArm::CONTACT_POINT;
    s.granular = g;
    LawSpec &n = s.law[NORMAL];
    n.name = normal_law_name(g.normal, g.damping);
    double kt_mixed = std::numeric_limits<double>::quiet_NaN();
    if (material(g.normal)) {
        const double e = g.ncoef[0], nu = g.ncoef[2];
        n.params.push_back({"damp", g.ncoef[1]});
        if (g.normal != "hertz/material") n.params.push_back({"cohesion", g.ncoef[3]});
        if (g.mixed) {
            // LAMMPS's mixed modulus e, 1/e = (1 - nu_i^2)/E_i + (1 - nu_j^2)/E_j, is the pair
            // modulus of the two types' own materials, which the laws are bound to (the spec has
            // none of its own); mindlin's NULL stiffness is then 8 G with 1/G = 4 (2 - nu)(1 + nu)/e
            // and nu the geometric mean, as LAMMPS computes it, not the two materials' G
            kt_mixed = 2.0 * e / ((2.0 - nu) * (1.0 + nu));
        } else {
            s.has_material = true;
            s.young = e;
            s.poisson = nu;
        }
    } else {
        n.params.push_back({"k", g.ncoef[0]});
        n.params.push_back({"damp", g.ncoef[1]});
    }
    if (g.limit_damping) n.params.push_back({"limit_damping", 1.0});
    LawSpec &t = s.law[TANGENTIAL];
    // the classic pair styles' own springs; granular's *_classic sub-models (which the classic
    // wall fixes use) are LAMMPS's other bookkeeping of them: one law
    if (g.classic && !wall && g.tangential == "linear_history_classic")
        t.name = "gran-linear-history-classic";
    else if (g.classic && !wall && g.tangential == "mindlin_classic")
        t.name = "gran-mindlin-classic";
    else if (g.tangential == "linear_history_classic" || g.tangential == "mindlin_classic")
        t.name = "gran-wall-history-classic";
    else
        t.name = "gran-" + dashes(g.tangential);
    double kt = std::numeric_limits<double>::quiet_NaN();
    double xt = 0.0, mu = 0.0;
    if (g.tangential == "linear_nohistory") {
        xt = g.tcoef[0];
        mu = g.tcoef[1];
    } else {
        kt = g.tcoef[0];
        if (std::isnan(kt) && g.mixed) kt = kt_mixed;
        xt = g.tcoef[1];
        mu = g.tcoef[2];
        if (!std::isnan(kt)) t.params.push_back({"kt", kt});
    }
    t.params.push_back({"xt", xt});
    t.params.push_back({"mu", mu});
    if (g.rolling == "sds") {
        s.law[ROLLING].name = "gran-rolling-sds";
        s.law[ROLLING].params = {{"k", g.rcoef[0]}, {"gamma", g.rcoef[1]}, {"mu", g.rcoef[2]}};
    }
    if (g.twisting == "sds") {
        s.law[TWISTING].name = "gran-twisting-sds";
        s.law[TWISTING].params = {{"k", g.wcoef[0]}, {"gamma", g.wcoef[1]}, {"mu", g.wcoef[2]}};
    } else if (g.twisting == "marshall") {
        // LAMMPS's marshall takes the tangential model's stiffness, damping and friction
        s.law[TWISTING].name = "gran-twisting-marshall";
        if (!std::isnan(kt)) s.law[TWISTING].params.push_back({"kt", kt});
        s.law[TWISTING].params.push_back({"xt", xt});
        s.law[TWISTING].params.push_back({"mu", mu});
    }
    // LAMMPS's heat models read the normal model's contact radius, as heat-radius and heat-area
    // read the normal law's context
    if (g.heat == "radius") {
        s.law[HEAT].name = "heat-radius";
        s.law[HEAT].params = {{"k", g.hcoef[0]}};
    } else if (g.heat == "area") {
        s.law[HEAT].name = "heat-area";
        s.law[HEAT].params = {{"h", g.hcoef[0]}};
    }
    return s;
}

}    // namespace dashpot_lmp
