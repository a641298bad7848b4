/* Unit test of the spec layer (dashpot_spec.cpp, dashpot_translate.cpp), with no LAMMPS: built and run by cargo test
 * (host/capi/tests/lammps/types.rs) as
 *   g++ -std=c++17 test_spec.cpp dashpot_spec.cpp dashpot_translate.cpp -o test_spec && ./test_spec
 * Prints one line per failed check and exits non-zero if any failed. */
#include "dashpot_spec.h"
#include "dashpot_translate.h"

#include <cmath>
#include <cstdio>
#include <string>

using namespace dashpot_lmp;

static int failures = 0;

#define CHECK(cond)                                                                                \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            std::printf("FAILED %s:%d: %s\n", __FILE__, __LINE__, #cond);                          \
            failures++;                                                                            \
        }                                                                                          \
    } while (0)

static std::vector<std::string> words(const std::string &line)
{
    std::vector<std::string> w;
    size_t i = 0;
    while (i < line.size()) {
        while (i < line.size() && line[i] == ' ') i++;
        size_t j = i;
        while (j < line.size() && line[j] != ' ') j++;
        if (j > i) w.push_back(line.substr(i, j - i));
        i = j;
    }
    return w;
}

/* The message of the SpecError that parsing `line` throws ("" if none). */
static std::string refusal(const std::string &line, bool materials = false,
                           const std::vector<std::string> &options = {"plugin_dir", "zplane", "energy"})
{
    try {
        parse_dashpot(words(line), 0, options, materials, "pair_style dashpot");
    } catch (SpecError &e) {
        return e.what();
    }
    return "";
}

static bool has(const std::string &text, const std::string &part)
{
    bool ok = text.find(part) != std::string::npos;
    if (!ok) std::printf("  in: %s\n  no: %s\n", text.c_str(), part.c_str());
    return ok;
}

static void dashpot_syntax()
{
    Parsed p = parse_dashpot(words("hsd eps=0.5 plugin_dir=/x tangential mindlin mu=0.5 rolling sds k=1e3 "
                                   "gamma=0.1 mu=0.2 twisting marshall zplane=0"),
                             0, {"plugin_dir", "zplane", "energy"}, false, "pair_style dashpot");
    CHECK(p.has_laws);
    CHECK(p.spec.law[NORMAL].name == "hsd" && p.spec.law[NORMAL].params.size() == 1);
    CHECK(p.spec.law[NORMAL].params[0].key == "eps" && p.spec.law[NORMAL].params[0].value == 0.5);
    CHECK(p.spec.law[TANGENTIAL].name == "mindlin" && p.spec.law[TANGENTIAL].params[0].value == 0.5);
    CHECK(p.spec.law[ROLLING].name == "sds" && p.spec.law[ROLLING].params.size() == 3);
    CHECK(p.spec.law[TWISTING].name == "marshall" && p.spec.law[TWISTING].params.empty());
    CHECK(p.options.size() == 2 && p.options[0].first == "plugin_dir" && p.options[0].second == "/x");
    CHECK(p.options[1].first == "zplane" && p.options[1].second == "0");
    CHECK(!p.spec.has_material);
    CHECK(p.spec.describe() == "hsd eps=0.5 + mindlin mu=0.5 + sds k=1000 gamma=0.10000000000000001 mu=0.20000000000000001 "
                               "+ marshall");

    // options alone: no laws
    p = parse_dashpot(words("plugin_dir=/a plugin_dir=/b"), 0, {"plugin_dir"}, false, "pair_style dashpot");
    CHECK(!p.has_laws && p.options.size() == 2);

    // materials first (pair_coeff)
    p = parse_dashpot(words("1e7 0.3 jkr w=0.5"), 0, {}, true, "pair_coeff 1 1");
    CHECK(p.spec.has_material && p.spec.young == 1e7 && p.spec.poisson == 0.3 && p.spec.law[NORMAL].name == "jkr");
    p = parse_dashpot(words("1e5 0.25"), 0, {}, true, "pair_coeff 1 1");
    CHECK(p.spec.has_material && !p.has_laws);

    // a heat law is one more family, given by its keyword
    p = parse_dashpot(words("1e7 0.3 hsd eps=0.5 heat heat-radius-corrected k=2 young_real=1e11"), 0, {}, true,
                      "pair_coeff 1 1");
    CHECK(p.spec.law[HEAT].name == "heat-radius-corrected" && p.spec.law[HEAT].params.size() == 2);
    CHECK(p.spec.describe() == "hsd eps=0.5 + heat-radius-corrected k=2 young_real=100000000000");
    CHECK(has(refusal("hsd heat"), "'heat' must be followed by one heat law name, got nothing"));
    CHECK(has(refusal("heat heat-area h=1"), "'heat' comes before the normal law"));
}

static void refusals()
{
    // issue 37: a family keyword followed by an option is a missing law, not a law named so
    CHECK(has(refusal("hsd tangential plugin_dir=/x"),
              "'tangential' must be followed by one tangential law name, got 'plugin_dir=/x'"));
    CHECK(has(refusal("hsd eps=0.5 rolling"), "'rolling' must be followed by one rolling law name, got nothing"));
    CHECK(has(refusal("hsd twisting sds k=1 twisting sds k=2"), "'twisting' must be followed by one twisting law name, once"));
    CHECK(has(refusal("eps=0.5 hsd"), "'eps=0.5' comes before any law name"));
    CHECK(has(refusal("eps=0.5 hsd"), "options: plugin_dir, zplane, energy"));
    CHECK(has(refusal("tangential mindlin"), "'tangential' comes before the normal law"));
    CHECK(has(refusal("hsd eps=abc"), "parameter 'eps' of law 'hsd': 'abc' is not a finite number"));
    CHECK(has(refusal("hsd eps=nan"), "is not a finite number"));
    CHECK(has(refusal("hsd eps=0.5 eps=0.6"), "parameter 'eps' of law 'hsd' is given twice"));
    CHECK(has(refusal("hsd eps=0.5 bogus"), "unexpected word 'bogus' after law 'hsd'"));
    CHECK(has(refusal("hsd =3"), "'=3' has no key"));
    CHECK(has(refusal("1e7", true), "after Young's modulus '1e7' comes Poisson's ratio"));
    CHECK(has(refusal("1e7 0.7 hsd", true), "need E > 0 and -1 < nu < 0.5, got E = 1e7, nu = 0.7"));
    CHECK(has(refusal("-1e7 0.3 hsd", true), "need E > 0"));
    CHECK(has(refusal("1e7 0.3 5 hsd", true), "unexpected number '5'"));
    // where plugin_dir is no option (pair_coeff), it reads as a parameter of the law
    CHECK(has(refusal("hsd plugin_dir=/x", false, {}), "parameter 'plugin_dir' of law 'hsd': '/x' is not a finite number"));
}

static double fake_default(const std::string &law, const std::string &key)
{
    if (law == "mindlin" && key == "mu") return 0.5;
    throw SpecError("law '" + law + "' has no parameter '" + key + "'");
}

static void mixing()
{
    auto spec = [](const std::string &line) {
        return parse_dashpot(words(line), 0, {}, true, "pair_coeff").spec;
    };
    ContactSpec a = spec("1e7 0.3 hsd eps=0.81 tangential mindlin mu=0.2");
    ContactSpec b = spec("2e7 0.2 hsd eps=0.25 tangential mindlin");
    ContactSpec m = mix_specs(a, b, 1, 2, fake_default);
    CHECK(m.law[NORMAL].name == "hsd" && std::fabs(m.law[NORMAL].params[0].value - 0.45) < 1e-15);
    // mu given for type 1 only: the law's default (0.5) stands for type 2's
    CHECK(m.law[TANGENTIAL].params.size() == 1 && std::fabs(m.law[TANGENTIAL].params[0].value - std::sqrt(0.1)) < 1e-15);
    // equal values stay exact
    ContactSpec c = spec("1e7 0.3 hsd eps=0.3");
    CHECK(mix_specs(c, c, 1, 2, fake_default).law[NORMAL].params[0].value == 0.3);
    std::string msg;
    try {
        mix_specs(a, spec("1e7 0.3 lsd eps=0.5 tangential mindlin"), 1, 3, fake_default);
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "cannot mix the normal laws of types 1 1 and 3 3 ('hsd' and 'lsd'): give pair_coeff 1 3"));
    msg.clear();
    try {
        mix_specs(a, spec("1e7 0.3 hsd eps=0.5"), 1, 2, fake_default);
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "cannot mix the tangential laws of types 1 1 and 2 2 ('mindlin' and none)"));
    msg.clear();
    try {
        mix_specs(spec("1 0.3 thing x=-1"), spec("1 0.3 thing x=2"), 1, 2, fake_default);
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "cannot mix parameter 'x' of law 'thing' for types 1 and 2 (-1 and 2)"));
}


static const Param *param(const LawSpec &l, const std::string &key)
{
    for (auto &p : l.params)
        if (p.key == key) return &p;
    return nullptr;
}

static bool param_is(const LawSpec &l, const std::string &key, double v)
{
    const Param *p = param(l, key);
    bool ok = p && std::fabs(p->value - v) <= 1e-15 * std::fabs(v);
    if (!ok) std::printf("  %s: %s is %s, expected %.17g\n", l.name.c_str(), key.c_str(), p ? std::to_string(p->value).c_str() : "absent", v);
    return ok;
}

static ContactSpec granular(const std::string &line)
{
    return translate_granular(parse_granular(words(line), 0, "pair_coeff 1 1"), "pair_coeff 1 1");
}

static std::string granular_refusal(const std::string &line)
{
    try {
        granular(line);
    } catch (SpecError &e) {
        return e.what();
    }
    return "";
}

static void granular_syntax()
{
    CHECK(is_granular(words("hertz/material 1e5 0.2 0.3"), 0));
    CHECK(is_granular(words("jkr 1000 50 0.3 10"), 0));
    CHECK(!is_granular(words("jkr w=0.5"), 0));
    CHECK(!is_granular(words("hsd eps=0.5"), 0));
    CHECK(!is_granular(words("1e7 0.3 hertz"), 0));

    // in.pour.drum's type 1
    ContactSpec s = granular("hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 damping tsuji");
    CHECK(s.law[NORMAL].name == "gran-hertz-material-tsuji" && param_is(s.law[NORMAL], "damp", 0.2));
    CHECK(s.law[NORMAL].params.size() == 1);
    CHECK(s.has_material && s.young == 1e5 && s.poisson == 0.3);
    CHECK(s.law[TANGENTIAL].name == "gran-mindlin" && !param(s.law[TANGENTIAL], "kt"));
    CHECK(param_is(s.law[TANGENTIAL], "xt", 1.0) && param_is(s.law[TANGENTIAL], "mu", 0.5));
    CHECK(s.arm == TorqueArm::CONTACT_POINT && !s.law[ROLLING].present() && !s.law[TWISTING].present());
    CHECK(translate_granular(s.granular, "wall", true).arm == TorqueArm::RADIUS);

    // in.pour.flatwall's types
    s = granular("jkr 1000.0 50.0 0.3 10 tangential mindlin 800.0 1.0 0.5 rolling sds 500.0 200.0 0.5 twisting marshall");
    CHECK(s.law[NORMAL].name == "gran-jkr-viscoelastic" && param_is(s.law[NORMAL], "damp", 50.0));
    CHECK(param_is(s.law[NORMAL], "cohesion", 10.0) && s.young == 1000.0);
    CHECK(param_is(s.law[TANGENTIAL], "kt", 800.0));
    CHECK(s.law[ROLLING].name == "gran-rolling-sds" && param_is(s.law[ROLLING], "k", 500.0));
    CHECK(param_is(s.law[ROLLING], "gamma", 200.0) && param_is(s.law[ROLLING], "mu", 0.5));
    CHECK(s.law[TWISTING].name == "gran-twisting-marshall" && param_is(s.law[TWISTING], "kt", 800.0));
    CHECK(param_is(s.law[TWISTING], "xt", 1.0) && param_is(s.law[TWISTING], "mu", 0.5));
    s = granular("hertz 200.0 20.0 tangential linear_history 300.0 1.0 0.1 limit_damping cutoff 1.5");
    CHECK(s.law[NORMAL].name == "gran-hertz-viscoelastic" && param_is(s.law[NORMAL], "k", 200.0));
    CHECK(param_is(s.law[NORMAL], "damp", 20.0) && param_is(s.law[NORMAL], "limit_damping", 1.0) && !s.has_material);
    CHECK(s.law[TANGENTIAL].name == "gran-linear-history" && param_is(s.law[TANGENTIAL], "kt", 300.0));
    CHECK(s.granular.cutoff == 1.5);
    s = granular("hooke 1e5 0.5 damping coeff_restitution tangential linear_nohistory 0 0");
    CHECK(s.law[NORMAL].name == "gran-hooke-coeff-restitution" && s.law[TANGENTIAL].name == "gran-linear-nohistory");
    CHECK(param_is(s.law[TANGENTIAL], "xt", 0.0) && !param(s.law[TANGENTIAL], "kt"));
    s = granular("hertz/material 1e5 0.2 0.3 damping mass_velocity tangential mindlin_rescale/force 100 1 0.5");
    CHECK(s.law[NORMAL].name == "gran-hertz-material-mass-velocity" && s.law[TANGENTIAL].name == "gran-mindlin-rescale-force");

    // a wall fix's words: the model ends at its wall style
    size_t end = 0;
    std::vector<std::string> w = words("hertz/material 1e5 0.1 0.3 tangential linear_nohistory 0 0 zplane 0 NULL");
    parse_granular(w, 0, "fix wall", {"xplane", "yplane", "zplane", "zcylinder", "region"}, &end);
    CHECK(end == 8 && w[end] == "zplane");
    Parsed p = parse_dashpot(words("hsd eps=0.5 tangential mindlin mu=0.3 region drum contacts"), 0, {}, false,
                             "fix wall", {"region", "zplane"});
    CHECK(p.end == 5 && p.spec.law[TANGENTIAL].name == "mindlin");

    // the classic styles (examples/pour/in.pour: gran/hooke/history 2000.0 NULL 50.0 NULL 0.5 0)
    GranularWords c = parse_classic("hooke/history", words("2000.0 NULL 50.0 NULL 0.5 0"), 0, 1.0, "pair_style");
    s = translate_granular(c, "pair_style");
    CHECK(s.law[NORMAL].name == "gran-hooke-mass-velocity" && param_is(s.law[NORMAL], "k", 2000.0));
    CHECK(param_is(s.law[NORMAL], "damp", 50.0) && s.arm == TorqueArm::RADIUS);
    CHECK(s.law[TANGENTIAL].name == "gran-linear-history-classic" && param_is(s.law[TANGENTIAL], "kt", 2000.0 * 2.0 / 7.0));
    CHECK(param_is(s.law[TANGENTIAL], "xt", 0.0) && param_is(s.law[TANGENTIAL], "mu", 0.5));    // dampflag 0
    c = parse_classic("hertz/history", words("4000.0 NULL 100.0 NULL 0.5 1 limit_damping"), 0, 2.0, "pair_style");
    s = translate_granular(c, "pair_style");
    CHECK(s.law[NORMAL].name == "gran-hertz-viscoelastic" && param_is(s.law[NORMAL], "k", 2000.0));
    CHECK(param_is(s.law[NORMAL], "limit_damping", 1.0));
    CHECK(s.law[TANGENTIAL].name == "gran-mindlin-classic" && param_is(s.law[TANGENTIAL], "kt", 4000.0 / 7.0));
    CHECK(param_is(s.law[TANGENTIAL], "xt", 0.5));    // gammat NULL = gamman/2, over gamman
    c = parse_classic("hooke", words("2000 1000 50 20 0.5 1"), 0, 1.0, "pair_style");
    s = translate_granular(c, "pair_style");
    CHECK(s.law[TANGENTIAL].name == "gran-linear-nohistory" && param_is(s.law[TANGENTIAL], "xt", 0.4));

    // mixing two hertz/material types: LAMMPS's mixed modulus, mindlin's NULL kt made explicit
    ContactSpec a = granular("hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5");
    ContactSpec b = granular("hertz/material 2e5 0.8 0.2 tangential mindlin NULL 0.5 0.3");
    ContactSpec m = mix_specs(a, b, 1, 2, fake_default);
    const double emix = 1.0 / ((1.0 - 0.09) / 1e5 + (1.0 - 0.04) / 2e5), nu = std::sqrt(0.3 * 0.2);
    CHECK(!m.has_material);    // bound to the two types' own materials: LAMMPS's mixed modulus exactly
    CHECK(param_is(m.law[NORMAL], "damp", std::sqrt(0.2 * 0.8)));
    CHECK(param_is(m.law[TANGENTIAL], "kt", 2.0 * emix / ((2.0 - nu) * (1.0 + nu))));
    CHECK(param_is(m.law[TANGENTIAL], "xt", std::sqrt(0.5)) && param_is(m.law[TANGENTIAL], "mu", std::sqrt(0.15)));
    std::string msg;
    try {
        mix_specs(a, granular("hooke 1 1 tangential mindlin 1 1 0.5"), 1, 2, fake_default);
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "cannot mix the normal models of types 1 1 and 2 2 ('hertz/material' and 'hooke')"));
    msg.clear();
    try {
        mix_specs(a, parse_dashpot(words("1e5 0.3 hsd"), 0, {}, true, "pair_coeff").spec, 1, 2, fake_default);
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "one's laws are in LAMMPS's granular syntax, the other's in dashpot's"));

    // refusals name the word and the choices
    CHECK(has(granular_refusal("hertz/material 1e5 0.2"), "normal model 'hertz/material' takes 3 coefficients, got 2"));
    CHECK(has(granular_refusal("hertz/material 1e5 0.2 0.3"), "needs a tangential model"));
    CHECK(has(granular_refusal("hooke 1 1 tangential mindlin NULL 1 0.5"),
              "needs a normal model with material properties (hertz/material, dmt, jkr), not 'hooke'"));
    CHECK(has(granular_refusal("hooke 1 NULL tangential linear_nohistory 0 0"), "NULL is allowed only for"));
    CHECK(has(granular_refusal("hooke 1 1 damping bogus tangential linear_nohistory 0 0"),
              "unknown damping model 'bogus' (valid: velocity, mass_velocity, viscoelastic, tsuji, coeff_restitution)"));
    CHECK(has(granular_refusal("hooke 1 1 tangential linear_nohistory 0 0 sideways"), "unknown keyword 'sideways'"));
    CHECK(has(granular_refusal("hooke 1 1 tangential mindlin_classics 1 1 0"), "unknown tangential model 'mindlin_classics'"));
    CHECK(has(granular_refusal("jkr 1 1 0.3 1 tangential linear_nohistory 0 0 limit_damping"),
              "limit_damping cannot be used with a cohesive normal model"));
    CHECK(has(granular_refusal("dmt 1 1 0.3 1 tangential mindlin_rescale 1 1 0.5"), "cannot be used with a cohesive"));
    CHECK(has(granular_refusal("jkr 1 1 0.3 1 damping tsuji tangential linear_nohistory 0 0"),
              "damping 'tsuji' cannot be used with a cohesive normal model ('jkr')"));
    // granular's *_classic sub-models (the classic walls' springs) and the classic pair styles'
    CHECK(granular("hooke 1 1 tangential linear_history_classic 1 0 0.5").law[TANGENTIAL].name ==
          "gran-wall-history-classic");
    CHECK(translate_granular(parse_classic("hertz/history", words("1 NULL 1 NULL 0.5 1"), 0, 1.0, "fix"), "fix", true)
              .law[TANGENTIAL]
              .name == "gran-wall-history-classic");
    // heat: LAMMPS's radius and area models are heat-radius and heat-area with the same
    // coefficient; none is no law; mixed as the geometric mean; refusals name the choices
    ContactSpec h = granular("hertz/material 1e5 0.2 0.3 tangential mindlin NULL 1.0 0.5 heat area 5.0");
    CHECK(h.law[HEAT].name == "heat-area" && h.law[HEAT].params.size() == 1 && h.law[HEAT].params[0].key == "h" &&
          h.law[HEAT].params[0].value == 5.0);
    h = granular("hooke 1 1 tangential linear_nohistory 0 0 heat radius 2.5 limit_damping");
    CHECK(h.law[HEAT].name == "heat-radius" && h.law[HEAT].params[0].key == "k" && h.law[HEAT].params[0].value == 2.5);
    CHECK(!granular("hooke 1 1 tangential linear_nohistory 0 0 heat none").law[HEAT].present());
    CHECK(has(granular_refusal("hooke 1 1 tangential linear_nohistory 0 0 heat volume 1"),
              "unknown heat model 'volume' (valid: none, radius, area)"));
    CHECK(has(granular_refusal("hooke 1 1 tangential linear_nohistory 0 0 heat area"), "heat model 'area' takes 1"));
    CHECK(has(granular_refusal("hooke 1 1 tangential linear_nohistory 0 0 heat area -1"), "must be >= 0"));
    CHECK(has(granular_refusal("hooke 1 1 tangential linear_nohistory 0 0 heat area 1 heat area 2"),
              "'heat' is given twice"));
    {
        GranularWords a = parse_granular(words("hooke 1 1 tangential linear_nohistory 0 0 heat area 4"), 0, "t");
        GranularWords b = parse_granular(words("hooke 1 1 tangential linear_nohistory 0 0 heat area 9"), 0, "t");
        ContactSpec m = translate_granular(mix_granular(a, b, 1, 2), "t");
        CHECK(m.law[HEAT].name == "heat-area" && m.law[HEAT].params[0].value == 6.0);
        GranularWords c = parse_granular(words("hooke 1 1 tangential linear_nohistory 0 0 heat radius 9"), 0, "t");
        msg.clear();
        try {
            mix_granular(a, c, 1, 2);
        } catch (SpecError &e) {
            msg = e.what();
        }
        CHECK(has(msg, "cannot mix the heat models of types 1 1 and 2 2 ('area' and 'radius')"));
    }
    CHECK(has(granular_refusal("mdr 1 0.3 1 1 0.5 0.1 tangential linear_nohistory 0 0"), "out of the scope"));
    CHECK(has(granular_refusal("hooke -1 1 tangential linear_nohistory 0 0"), "must be >= 0"));
    msg.clear();
    try {
        parse_classic("hooke/history", words("2000 NULL 50 NULL 0.5"), 0, 1.0, "pair_style dashpot gran/hooke/history");
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "takes kn kt gamman gammat xmu dampflag [limit_damping], got 5 arguments"));
    msg.clear();
    try {
        parse_classic("hooke/histories", words("2000 NULL 50 NULL 0.5 0"), 0, 1.0, "pair_style");
    } catch (SpecError &e) {
        msg = e.what();
    }
    CHECK(has(msg, "valid: gran/hooke, gran/hooke/history, gran/hertz/history"));
    CHECK(translation_table().size() > 20);
}

int main()
{
    dashpot_syntax();
    refusals();
    mixing();
    granular_syntax();
    if (failures) {
        std::printf("%d check(s) failed\n", failures);
        return 1;
    }
    std::printf("spec: all checks passed\n");
    return 0;
}
