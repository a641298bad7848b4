/* LAMMPS's own granular syntaxes, read verbatim and translated to dashpot's gran-* laws (the
 * plugin dashpot_granular, which carries LAMMPS's sub-models with their physics):
 *
 *   pair_style granular's model, as in pair_coeff I J (and fix wall/gran granular):
 *     NORMAL c... [damping D] [tangential T c...] [rolling R c...] [twisting W c...]
 *     [heat radius k | heat area h | heat none] [limit_damping] [cutoff X]
 *   the classic styles' arguments (pair_style gran/hooke, gran/hooke/history,
 *   gran/hertz/history; fix wall/gran hooke, hooke/history, hertz/history):
 *     kn kt gamman gammat xmu dampflag [limit_damping]
 *
 * A GranularWords keeps the words as LAMMPS reads them, so that two types' models mix as
 * LAMMPS's sub-models mix their coefficients (mix_granular); translate_granular then makes the
 * ContactSpec of the gran-* laws. The table (translation_table) lists every keyword with the law
 * that carries it. No LAMMPS header; errors are SpecError exceptions naming the word and the
 * valid choices. */
#ifndef DASHPOT_TRANSLATE_H
#define DASHPOT_TRANSLATE_H

#include "dashpot_spec.h"

#include <string>
#include <vector>

namespace dashpot_lmp {

/* A row of the translation table: a keyword of one of LAMMPS's sub-models, its coefficients in
 * LAMMPS's order, and the dashpot law (and parameters) that carries it. */
struct TranslationRow {
    const char *family;     // normal, damping, tangential, rolling, twisting, keyword
    const char *keyword;    // as in a granular deck
    const char *coeffs;     // LAMMPS's coefficients
    const char *law;        // the dashpot law (D: the damping's suffix)
    const char *params;     // its parameters, from the coefficients
    const char *status;     // exact, or refused (with why)
};
const std::vector<TranslationRow> &translation_table();

/* Whether words[first..] are granular syntax: a normal model keyword of pair_style granular
 * followed by a number (or NULL) -- dashpot's own laws take key=value. */
bool is_granular(const std::vector<std::string> &words, size_t first);

/* Reads one granular model from words[first..]. `context` names the command in messages. A
 * word of `stop` where a keyword could come ends the model (a wall fix's wall style); `*end`
 * (if given) receives the index of the first word not read. */
GranularWords parse_granular(const std::vector<std::string> &words, size_t first, const std::string &context,
                             const std::vector<std::string> &stop = {}, size_t *end = nullptr);

/* The classic styles: `style` is hooke, hooke/history or hertz/history (gran/ stripped), the
 * arguments kn kt gamman gammat xmu dampflag [limit_damping] from words[first..]; kt NULL is
 * 2/7 kn, gammat NULL is gamman/2, dampflag 0 sets gammat to 0; hertz/history's kn and kt are
 * given in pressure units and divided by nktv2p (the deck's force->nktv2p), as LAMMPS does. */
GranularWords parse_classic(const std::string &style, const std::vector<std::string> &words, size_t first,
                            double nktv2p, const std::string &context, const std::vector<std::string> &stop = {},
                            size_t *end = nullptr);

/* The model of an unset pair I != J from those of I I and J J, as LAMMPS mixes them: the same
 * sub-models (else a SpecError naming both), the moduli by 1/E = (1 - nu1^2)/E1 +
 * (1 - nu2^2)/E2, every other coefficient by its geometric mean, mindlin's NULL kt only if NULL
 * for both, limit_damping if either, the larger cutoff. */
GranularWords mix_granular(const GranularWords &a, const GranularWords &b, int itype, int jtype);

/* The ContactSpec of the gran-* laws carrying model g between two particles. A model with
 * material properties (hertz/material, dmt, jkr) gives the spec its materials (E, nu); a mixed
 * model has none (its laws are bound to the two types' own materials, whose pair modulus is
 * LAMMPS's mixed one), and mindlin's NULL kt is then given explicitly, as LAMMPS computes it
 * from the mixed modulus and Poisson's ratio. The tangential force's torque acts at the
 * contact point (pair_style granular's pairs), or at a radius (classic styles; and a wall's
 * contacts, `wall`, as fix wall/gran applies them). */
ContactSpec translate_granular(const GranularWords &g, const std::string &context, bool wall = false);

/* The name of the gran-* normal law for a normal keyword and a damping keyword
 * ("hertz/material", "coeff_restitution" -> "gran-hertz-material-coeff-restitution"). */
std::string normal_law_name(const std::string &normal, const std::string &damping);

}    // namespace dashpot_lmp

#endif
