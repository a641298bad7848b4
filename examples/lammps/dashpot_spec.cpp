/* The spec layer: see dashpot_spec.h. No LAMMPS header. */
#include "dashpot_spec.h"

#include "dashpot_translate.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace dashpot_lmp {

const char *const FAMILY_NAME[NLAW] = {"normal", "tangential", "rolling", "twisting", "heat"};

static std::string number_text(double v)
{
    std::ostringstream s;
    s.precision(17);
    s << v;
    return s.str();
}

std::string LawSpec::describe() const
{
    std::string s = name;
    for (auto &p : params) s += " " + p.key + "=" + number_text(p.value);
    return s;
}

std::string ContactSpec::describe() const
{
    std::string s;
    for (int f = 0; f < NLAW; f++) {
        if (!law[f].present()) continue;
        if (!s.empty()) s += " + ";
        s += law[f].describe();
    }
    return s;
}

bool ContactSpec::same_laws(const ContactSpec &o) const
{
    for (int f = 0; f < NLAW; f++)
        if (!(law[f] == o.law[f])) return false;
    return arm == o.arm && granular == o.granular;
}

double parse_number(const std::string &word, const std::string &what)
{
    const char *s = word.c_str();
    char *end = nullptr;
    errno = 0;
    double v = std::strtod(s, &end);
    if (word.empty() || end == s || *end != '\0' || errno == ERANGE || !std::isfinite(v))
        throw SpecError(what + ": '" + word + "' is not a finite number");
    return v;
}

static bool is_number(const std::string &word)
{
    const char *s = word.c_str();
    char *end = nullptr;
    std::strtod(s, &end);
    return !word.empty() && end != s && *end == '\0';
}

static int family_of(const std::string &word)
{
    for (int f = TANGENTIAL; f < NLAW; f++)
        if (word == FAMILY_NAME[f]) return f;
    return -1;
}

static std::string join(const std::vector<std::string> &v)
{
    std::string s;
    for (size_t i = 0; i < v.size(); i++) s += (i ? ", " : "") + v[i];
    return s;
}

Parsed parse_dashpot(const std::vector<std::string> &words, size_t first, const std::vector<std::string> &option_keys,
                     bool materials, const std::string &context, const std::vector<std::string> &stop)
{
    Parsed out;
    ContactSpec &spec = out.spec;
    size_t i = first;
    const size_t n = words.size();
    if (materials && i < n && is_number(words[i])) {
        if (i + 1 >= n || !is_number(words[i + 1]))
            throw SpecError(context + ": after Young's modulus '" + words[i] +
                            "' comes Poisson's ratio (pair_coeff I J E nu [LAW ...])");
        spec.young = parse_number(words[i], context + ": Young's modulus E");
        spec.poisson = parse_number(words[i + 1], context + ": Poisson's ratio nu");
        if (!(spec.young > 0.0) || !(spec.poisson > -1.0 && spec.poisson < 0.5))
            throw SpecError(context + ": need E > 0 and -1 < nu < 0.5, got E = " + words[i] + ", nu = " + words[i + 1]);
        spec.has_material = true;
        i += 2;
    }
    int family = -1;    // the family whose parameters follow; -1 before any law
    for (; i < n; i++) {
        const std::string &w = words[i];
        bool stops = false;
        for (auto &s : stop) stops = stops || w == s;
        if (stops) break;
        const size_t eq = w.find('=');
        if (eq != std::string::npos && eq > 0) {
            const std::string key = w.substr(0, eq), value = w.substr(eq + 1);
            bool option = false;
            for (auto &k : option_keys) option = option || k == key;
            if (option) {
                out.options.emplace_back(key, value);
                continue;
            }
            if (family < 0) {
                std::string valid = option_keys.empty() ? "" : " (options: " + join(option_keys) + ")";
                throw SpecError(context + ": '" + w + "' comes before any law name: give the normal law first, as in '" +
                                "hsd eps=0.5'" + valid);
            }
            for (auto &p : spec.law[family].params)
                if (p.key == key)
                    throw SpecError(context + ": parameter '" + key + "' of law '" + spec.law[family].name +
                                    "' is given twice");
            spec.law[family].params.push_back(
                {key, parse_number(value, context + ": parameter '" + key + "' of law '" + spec.law[family].name + "'")});
            continue;
        }
        if (eq == 0) throw SpecError(context + ": '" + w + "' has no key before '='");
        const int f = family_of(w);
        if (f >= 0) {
            std::string fam = FAMILY_NAME[f];
            if (family < 0)
                throw SpecError(context + ": '" + fam + "' comes before the normal law: give the normal law first");
            if (spec.law[f].present())
                throw SpecError(context + ": '" + fam + "' must be followed by one " + fam + " law name, once");
            if (i + 1 >= n || words[i + 1].find('=') != std::string::npos || family_of(words[i + 1]) >= 0 ||
                is_number(words[i + 1]))
                throw SpecError(context + ": '" + fam + "' must be followed by one " + fam + " law name" +
                                (i + 1 < n ? ", got '" + words[i + 1] + "'" : ", got nothing") +
                                " (for instance 'tangential mindlin mu=0.5', 'rolling sds k=1e3 mu=0.1', "
                                "'twisting marshall', 'heat heat-area h=5')");
            spec.law[f].name = words[++i];
            family = f;
            continue;
        }
        if (family < 0 && !spec.law[NORMAL].present()) {
            if (is_number(w))
                throw SpecError(context + ": unexpected number '" + w + "'" +
                                (materials ? " (pair_coeff I J E nu [LAW ...] takes two numbers)"
                                           : " where a law name belongs"));
            spec.law[NORMAL].name = w;
            family = NORMAL;
            out.has_laws = true;
            continue;
        }
        throw SpecError(context + ": unexpected word '" + w + "' after law '" + spec.law[family].name +
                        "': expected key=value, 'tangential LAW', 'rolling LAW', 'twisting LAW' or 'heat LAW'" +
                        (stop.empty() ? std::string() : ", or one of: " + join(stop)));
    }
    out.end = i;
    return out;
}

static double mix_value(double a, double b, const std::string &law, const std::string &key, int itype, int jtype)
{
    if (a == b) return a;
    if (a < 0.0 || b < 0.0)
        throw SpecError("cannot mix parameter '" + key + "' of law '" + law + "' for types " + std::to_string(itype) +
                        " and " + std::to_string(jtype) + " (" + number_text(a) + " and " + number_text(b) +
                        "): give pair_coeff " + std::to_string(itype) + " " + std::to_string(jtype) + " explicitly");
    return std::sqrt(a * b);
}

ContactSpec mix_specs(const ContactSpec &a, const ContactSpec &b, int itype, int jtype, const ParamDefault &default_of)
{
    if (a.granular.present() != b.granular.present())
        throw SpecError("cannot mix types " + std::to_string(itype) + " and " + std::to_string(jtype) +
                        ": one's laws are in LAMMPS's granular syntax, the other's in dashpot's: give pair_coeff " +
                        std::to_string(itype) + " " + std::to_string(jtype) + " explicitly");
    if (a.granular.present())
        return translate_granular(mix_granular(a.granular, b.granular, itype, jtype),
                                  "mixing types " + std::to_string(itype) + " and " + std::to_string(jtype));
    ContactSpec m;
    m.syntax = a.syntax;
    m.arm = a.arm;
    const std::string types = std::to_string(itype) + " " + std::to_string(itype) + " and " + std::to_string(jtype) +
        " " + std::to_string(jtype);
    for (int f = 0; f < NLAW; f++) {
        const LawSpec &la = a.law[f], &lb = b.law[f];
        if (la.name != lb.name) {
            auto shown = [](const LawSpec &l) { return l.present() ? "'" + l.name + "'" : std::string("none"); };
            throw SpecError("cannot mix the " + std::string(FAMILY_NAME[f]) + " laws of types " + types + " (" +
                            shown(la) + " and " + shown(lb) + "): give pair_coeff " + std::to_string(itype) + " " +
                            std::to_string(jtype) + " explicitly");
        }
        if (!la.present()) continue;
        LawSpec &l = m.law[f];
        l.name = la.name;
        auto find = [](const LawSpec &s, const std::string &k) -> const Param * {
            for (auto &p : s.params)
                if (p.key == k) return &p;
            return nullptr;
        };
        std::vector<std::string> keys;
        for (auto &p : la.params) keys.push_back(p.key);
        for (auto &p : lb.params)
            if (!find(la, p.key)) keys.push_back(p.key);
        for (auto &k : keys) {
            const Param *pa = find(la, k), *pb = find(lb, k);
            double va = pa ? pa->value : default_of(la.name, k);
            double vb = pb ? pb->value : default_of(la.name, k);
            l.params.push_back({k, mix_value(va, vb, la.name, k, itype, jtype)});
        }
    }
    if (a.arm != b.arm)
        throw SpecError("cannot mix the specs of types " + types + ": one applies granular's conventions, the other "
                        "dashpot's: give pair_coeff " + std::to_string(itype) + " " + std::to_string(jtype) +
                        " explicitly");
    return m;
}

}    // namespace dashpot_lmp
