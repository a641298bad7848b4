/* Unit test of the spec layer (dashpot_spec.cpp), with no LAMMPS: built and run by cargo test
 * (host/capi/tests/lammps/types.rs) as
 *   g++ -std=c++17 test_spec.cpp dashpot_spec.cpp -o test_spec && ./test_spec
 * Prints one line per failed check and exits non-zero if any failed. */
#include "dashpot_spec.h"

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

int main()
{
    dashpot_syntax();
    refusals();
    mixing();
    if (failures) {
        std::printf("%d check(s) failed\n", failures);
        return 1;
    }
    std::printf("spec: all checks passed\n");
    return 0;
}
