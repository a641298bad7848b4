/*
 * Every function of dashpot.h, called from C: its success path and each of its error paths
 * (null handle or output, unknown law, bad parameter, wrong array length, NaN inputs, a
 * panicking or NaN-returning plugin) must return the documented status and leave a message.
 *
 * usage: error_paths PLUGIN_DIR   (a directory with the seed plugins and the faulty fixture)
 * Prints one line per failed expectation and "N passed, M failed" at the end.
 */
#include "dashpot.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

static int passed = 0, failed = 0;

static void expect_status(int line, const char *call, DashpotStatus got, DashpotStatus want, const char *needle) {
    const char *msg = dashpot_last_error();
    int ok = got == want;
    if (ok && want != DASHPOT_OK) ok = msg != NULL && strlen(msg) > 0 && (needle == NULL || strstr(msg, needle) != NULL);
    if (ok) {
        passed++;
    } else {
        failed++;
        printf("FAIL line %d: %s returned %s, want %s (message \"%s\", want it to contain \"%s\")\n", line, call,
               dashpot_status_name((int)got), dashpot_status_name((int)want), msg ? msg : "(null)",
               needle ? needle : "");
    }
}

static void expect_true(int line, const char *what, int cond) {
    if (cond) {
        passed++;
    } else {
        failed++;
        printf("FAIL line %d: %s\n", line, what);
    }
}

#define EXPECT(call, want, needle) expect_status(__LINE__, #call, (call), (want), (needle))
#define CHECK(cond) expect_true(__LINE__, #cond, (cond))
#define CLOSE(a, b, tol) expect_true(__LINE__, #a " close to " #b, fabs((a) - (b)) <= (tol) * fabs(b))

/*
 * The error paths every kind of law shares, one macro per function macro of the header. They
 * use main's registry `reg`, materials `mat` and `badmat`, pairs `pair` and `zero`, and the
 * unknown parameter `bogus_name` = `eps_val`.
 */

/* dashpot_KIND_new (DASHPOT_LAW_FUNCTIONS): law `name` of KIND with its `n` parameters `names`
 * at `good` (at `bad`: out of range, the message naming `bad_needle`); `other` is a law of
 * another kind, `other_kind`. `*out` stays NULL. */
#define EXPECT_NEW_ERRORS(KIND, out, name, names, good, bad, n, bad_needle, other, other_kind)                  \
    do {                                                                                                    \
        EXPECT(dashpot_##KIND##_new(NULL, name, names, good, n, out), DASHPOT_ERR_NULL_POINTER, "registry"); \
        EXPECT(dashpot_##KIND##_new(reg, NULL, names, good, n, out), DASHPOT_ERR_NULL_POINTER, "name");      \
        EXPECT(dashpot_##KIND##_new(reg, name, names, good, n, NULL), DASHPOT_ERR_NULL_POINTER, "out_law");  \
        EXPECT(dashpot_##KIND##_new(reg, name, NULL, good, n, out), DASHPOT_ERR_NULL_POINTER, "param_names"); \
        EXPECT(dashpot_##KIND##_new(reg, other, NULL, NULL, 0, out), DASHPOT_ERR_UNKNOWN_LAW,                \
               "law '" other "' is a " other_kind " law");                                                   \
        EXPECT(dashpot_##KIND##_new(reg, "no-such-law", NULL, NULL, 0, out), DASHPOT_ERR_UNKNOWN_LAW,         \
               "unknown law 'no-such-law'");                                                                  \
        CHECK(strstr(dashpot_last_error(), "available laws") != NULL);                                      \
        EXPECT(dashpot_##KIND##_new(reg, name, bogus_name, eps_val, 1, out), DASHPOT_ERR_UNKNOWN_PARAMETER,   \
               "epsilon");                                                                                    \
        EXPECT(dashpot_##KIND##_new(reg, name, names, bad, n, out), DASHPOT_ERR_INVALID_PARAMETER, bad_needle); \
        CHECK(*(out) == NULL);                                                                               \
    } while (0)

/* A binding `bind` of `law` to `with` (named `with_name`; `bad` is refused as `bad_needle`) into
 * `out` (named `out_name`), which stays NULL. */
#define EXPECT_BIND_ERRORS(bind, law, with, with_name, bad, bad_needle, out, out_name)                        \
    do {                                                                                                    \
        EXPECT(bind(NULL, with, out), DASHPOT_ERR_NULL_POINTER, "law");                                      \
        EXPECT(bind(law, NULL, out), DASHPOT_ERR_NULL_POINTER, with_name);                                   \
        EXPECT(bind(law, with, NULL), DASHPOT_ERR_NULL_POINTER, out_name);                                   \
        EXPECT(bind(law, bad, out), DASHPOT_ERR_INVALID_PAIR, bad_needle);                                   \
        CHECK(*(out) == NULL);                                                                               \
    } while (0)

/* dashpot_KIND_bind_materials (DASHPOT_MODEL_FUNCTIONS) and dashpot_KIND_bind
 * (DASHPOT_PAIR_FUNCTIONS) of `law` into `out`. */
#define EXPECT_BIND_MATERIALS_ERRORS(KIND, law, out)                                                         \
    EXPECT_BIND_ERRORS(dashpot_##KIND##_bind_materials, law, &mat, "materials", &badmat,                     \
                       "effective Young's modulus = 0", out, "out_model")
#define EXPECT_BIND_PAIR_ERRORS(KIND, law, out)                                                              \
    EXPECT_BIND_ERRORS(dashpot_##KIND##_bind, law, &pair, "pair", &zero, "effective mass", out, "out_bound")

/* dashpot_KIND_model_history_slots (DASHPOT_MODEL_FUNCTIONS): `model` keeps `want` slots, which
 * are written to `slots`. */
#define EXPECT_SLOTS(KIND, model, slots, want)                                                               \
    do {                                                                                                    \
        EXPECT(dashpot_##KIND##_model_history_slots(model, &(slots)), DASHPOT_OK, NULL);                    \
        CHECK((slots) == (want));                                                                            \
        EXPECT(dashpot_##KIND##_model_history_slots(NULL, &(slots)), DASHPOT_ERR_NULL_POINTER, "model");    \
        EXPECT(dashpot_##KIND##_model_history_slots(model, NULL), DASHPOT_ERR_NULL_POINTER, "out_slots");   \
        int reads_ = -1;                                                                                    \
        EXPECT(dashpot_##KIND##_model_reads_context(model, &reads_), DASHPOT_OK, NULL);                     \
        CHECK(reads_ == 0);                                                                                  \
        EXPECT(dashpot_##KIND##_model_reads_context(NULL, &reads_), DASHPOT_ERR_NULL_POINTER, "model");     \
        EXPECT(dashpot_##KIND##_model_reads_context(model, NULL), DASHPOT_ERR_NULL_POINTER, "out_reads");   \
    } while (0)

/* The functions of DASHPOT_LAW_FUNCTIONS and DASHPOT_MODEL_FUNCTIONS for law `name` of KIND
 * (parameters as for EXPECT_NEW_ERRORS): the error paths of each, then `model` bound to `mat`,
 * keeping `want` history slots (written to `slots`); `law` is freed, as a model outlives its law. */
#define EXPECT_MODEL(KIND, law, model, name, names, good, bad, n, bad_needle, other, other_kind, slots, want)    \
    do {                                                                                                    \
        EXPECT_NEW_ERRORS(KIND, &law, name, names, good, bad, n, bad_needle, other, other_kind);            \
        EXPECT(dashpot_##KIND##_new(reg, name, names, good, n, &law), DASHPOT_OK, NULL);                    \
        EXPECT_BIND_MATERIALS_ERRORS(KIND, law, &model);                                                     \
        EXPECT(dashpot_##KIND##_bind_materials(law, &mat, &model), DASHPOT_OK, NULL);                       \
        dashpot_##KIND##_free(law);                                                                          \
        law = NULL;                                                                                          \
        EXPECT_SLOTS(KIND, model, slots, want);                                                              \
    } while (0)

/* `*out` bound by `bind` to `with` from law `name` of KIND (its `n` parameters `names` at
 * `values`), the binding returning `want` (a failure's message naming `needle`); `law` is freed
 * (a binding outlives its law). */
#define BIND(KIND, law, name, names, values, n, bind, with, out, want, needle)                                \
    do {                                                                                                    \
        EXPECT(dashpot_##KIND##_new(reg, name, names, values, n, &law), DASHPOT_OK, NULL);                  \
        EXPECT(bind(law, with, out), want, needle);                                                          \
        dashpot_##KIND##_free(law);                                                                          \
        law = NULL;                                                                                          \
    } while (0)

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s PLUGIN_DIR\n", argv[0]);
        return 2;
    }
    /* ---- version and status names ---- */
    CHECK(dashpot_abi_version() == DASHPOT_ABI_VERSION);
    CHECK(strlen(dashpot_version()) > 0);
    CHECK(strcmp(dashpot_status_name(DASHPOT_ERR_PANIC), "DASHPOT_ERR_PANIC") == 0);
    CHECK(strcmp(dashpot_status_name(-7), "DASHPOT_UNKNOWN_STATUS") == 0);
    CHECK(dashpot_last_error() != NULL);

    /* ---- registry ---- */
    DashpotRegistry *reg = NULL;
    const char *dirs[1] = {argv[1]};
    const char *null_dirs[1] = {NULL};
    EXPECT(dashpot_registry_open(dirs, 1, 0, NULL), DASHPOT_ERR_NULL_POINTER, "out_registry");
    EXPECT(dashpot_registry_open(NULL, 1, 0, &reg), DASHPOT_ERR_NULL_POINTER, "dirs");
    EXPECT(dashpot_registry_open(null_dirs, 1, 0, &reg), DASHPOT_ERR_NULL_POINTER, "dirs[0]");
    CHECK(reg == NULL);
    /* no directory at all: an empty registry, not an error; its laws are not found */
    EXPECT(dashpot_registry_open(NULL, 0, 0, &reg), DASHPOT_OK, NULL);
    size_t count = 99;
    EXPECT(dashpot_registry_law_count(reg, &count), DASHPOT_OK, NULL);
    CHECK(count == 0);
    DashpotContactLaw *law = NULL;
    EXPECT(dashpot_contact_new(reg, "hsd", NULL, NULL, 0, &law), DASHPOT_ERR_UNKNOWN_LAW, "none found");
    dashpot_registry_free(reg);
    reg = NULL;

    EXPECT(dashpot_registry_open(dirs, 1, 0, &reg), DASHPOT_OK, NULL);
    CHECK(reg != NULL);
    EXPECT(dashpot_registry_law_count(NULL, &count), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_registry_law_count(reg, NULL), DASHPOT_ERR_NULL_POINTER, "out_count");
    EXPECT(dashpot_registry_law_count(reg, &count), DASHPOT_OK, NULL);
    CHECK(count >= 5);

    size_t idx = 0;
    EXPECT(dashpot_registry_find(reg, "hsd", &idx), DASHPOT_OK, NULL);
    EXPECT(dashpot_registry_find(NULL, "hsd", &idx), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_registry_find(reg, NULL, &idx), DASHPOT_ERR_NULL_POINTER, "name");
    EXPECT(dashpot_registry_find(reg, "hsd", NULL), DASHPOT_ERR_NULL_POINTER, "out_index");
    EXPECT(dashpot_registry_find(reg, "no-such-law", &idx), DASHPOT_ERR_UNKNOWN_LAW, "unknown law 'no-such-law'");
    EXPECT(dashpot_registry_find(reg, "\xff\xfe", &idx), DASHPOT_ERR_INVALID_ARGUMENT, "UTF-8");

    EXPECT(dashpot_registry_find(reg, "hsd", &idx), DASHPOT_OK, NULL);
    DashpotLawInfo info;
    EXPECT(dashpot_registry_law_info(reg, idx, &info), DASHPOT_OK, NULL);
    CHECK(strcmp(info.name, "hsd") == 0);
    CHECK(info.kind == DASHPOT_CONTACT);
    CHECK(info.n_params == 1);
    CHECK(info.end_criterion == DASHPOT_END_OVERLAP);
    CHECK(strstr(info.summary, "Tsuji") != NULL);
    EXPECT(dashpot_registry_law_info(NULL, idx, &info), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_registry_law_info(reg, idx, NULL), DASHPOT_ERR_NULL_POINTER, "out_info");
    EXPECT(dashpot_registry_law_info(reg, 100000, &info), DASHPOT_ERR_INVALID_ARGUMENT, "out of range");

    DashpotParamInfo pinfo;
    EXPECT(dashpot_registry_param_info(reg, idx, 0, &pinfo), DASHPOT_OK, NULL);
    CHECK(strcmp(pinfo.name, "eps") == 0);
    CHECK(strcmp(pinfo.unit, "1") == 0);
    CHECK(pinfo.has_default == 1 && pinfo.default_value == 0.54);
    CHECK(pinfo.min == 0.0 && pinfo.max == 1.0 && pinfo.min_inclusive == 0 && pinfo.max_inclusive == 1);
    EXPECT(dashpot_registry_param_info(NULL, idx, 0, &pinfo), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_registry_param_info(reg, idx, 0, NULL), DASHPOT_ERR_NULL_POINTER, "out_param");
    EXPECT(dashpot_registry_param_info(reg, idx, 1, &pinfo), DASHPOT_ERR_INVALID_ARGUMENT, "law 'hsd' has 1 parameters");
    EXPECT(dashpot_registry_param_info(reg, 100000, 0, &pinfo), DASHPOT_ERR_INVALID_ARGUMENT, "out of range");

    /* ---- pairs ---- */
    DashpotParticle mcc = {0.01, 1500.0, 6.0e9, 0.3};
    DashpotParticle bad = {0.01, 1500.0, 6.0e9, 0.7};
    DashpotPair pair, wall, pm, wm;
    EXPECT(dashpot_pair_spheres(&mcc, &mcc, &pair), DASHPOT_OK, NULL);
    CLOSE(pair.radius, 0.0025, 1e-15);
    CLOSE(pair.mass, M_PI / 12.0 * 1500.0 * 1e-6, 1e-15);
    CLOSE(pair.young, 6.0e9 / (2.0 * (1.0 - 0.09)), 1e-15);
    EXPECT(dashpot_pair_spheres(NULL, &mcc, &pair), DASHPOT_ERR_NULL_POINTER, "a");
    EXPECT(dashpot_pair_spheres(&mcc, NULL, &pair), DASHPOT_ERR_NULL_POINTER, "b");
    EXPECT(dashpot_pair_spheres(&mcc, &mcc, NULL), DASHPOT_ERR_NULL_POINTER, "out_pair");
    EXPECT(dashpot_pair_spheres(&mcc, &bad, &pair), DASHPOT_ERR_INVALID_PAIR, "poisson = 0.7");
    EXPECT(dashpot_pair_wall(&mcc, &wall), DASHPOT_OK, NULL);
    CLOSE(wall.radius, 0.005, 1e-15);
    CLOSE(wall.young, 6.0e9 / 0.91, 1e-15);
    EXPECT(dashpot_pair_wall(NULL, &wall), DASHPOT_ERR_NULL_POINTER, "a");
    EXPECT(dashpot_pair_wall(&mcc, NULL), DASHPOT_ERR_NULL_POINTER, "out_pair");
    EXPECT(dashpot_pair_wall(&bad, &wall), DASHPOT_ERR_INVALID_PAIR, "poisson");
    double m = M_PI / 6.0 * 1500.0 * 1e-6;
    EXPECT(dashpot_pair_from_masses(0.01, m, 6e9, 0.3, 0.01, m, 6e9, 0.3, &pm), DASHPOT_OK, NULL);
    CLOSE(pm.mass, pair.mass, 1e-15);
    CLOSE(pm.radius, pair.radius, 1e-15);
    CLOSE(pm.young, pair.young, 1e-15);
    EXPECT(dashpot_pair_from_masses(0.01, m, 6e9, 0.3, 0.01, m, 6e9, 0.3, NULL), DASHPOT_ERR_NULL_POINTER, "out_pair");
    EXPECT(dashpot_pair_from_masses(0.01, -m, 6e9, 0.3, 0.01, m, 6e9, 0.3, &pm), DASHPOT_ERR_INVALID_PAIR, "mass1");
    EXPECT(dashpot_pair_from_masses(0.01, m, 6e9, 0.3, NAN, m, 6e9, 0.3, &pm), DASHPOT_ERR_INVALID_PAIR, "diameter2");
    EXPECT(dashpot_pair_from_masses(0.01, m, 6e9, 0.3, 0.01, m, 6e9, 0.5, &pm), DASHPOT_ERR_INVALID_PAIR, "particle 2");
    EXPECT(dashpot_pair_wall_from_mass(0.01, m, 6e9, 0.3, &wm), DASHPOT_OK, NULL);
    CLOSE(wm.mass, m, 1e-15);
    CLOSE(wm.young, wall.young, 1e-15);
    EXPECT(dashpot_pair_wall_from_mass(0.01, m, 6e9, 0.3, NULL), DASHPOT_ERR_NULL_POINTER, "out_pair");
    EXPECT(dashpot_pair_wall_from_mass(0.0, m, 6e9, 0.3, &wm), DASHPOT_ERR_INVALID_PAIR, "diameter");
    EXPECT(dashpot_pair_wall_from_mass(0.01, m, -1.0, 0.3, &wm), DASHPOT_ERR_INVALID_PAIR, "young");

    /* ---- contact laws ---- */
    const char *eps_name[1] = {"eps"};
    const char *bogus_name[1] = {"epsilon"};
    const char *null_name[1] = {NULL};
    double eps_val[1] = {0.54}, eps_bad[1] = {1.5};
    EXPECT_NEW_ERRORS(contact, &law, "hsd", eps_name, eps_val, eps_bad, 1, "1.5", "mcnamara-falcon", "restitution");
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, NULL, 1, &law), DASHPOT_ERR_NULL_POINTER, "param_values");
    EXPECT(dashpot_contact_new(reg, "hsd", null_name, eps_val, 1, &law), DASHPOT_ERR_NULL_POINTER, "param_names[0]");
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, eps_val, 1, &law), DASHPOT_OK, NULL);
    CHECK(law != NULL);

    DashpotBoundContact *bound = NULL;
    DashpotPair zero = {0.0, 0.0025, 1e9};
    EXPECT_BIND_PAIR_ERRORS(contact, law, &bound);
    EXPECT(dashpot_contact_bind(law, &pair, &bound), DASHPOT_OK, NULL);
    /* the bound law outlives the law it came from */
    dashpot_contact_free(law);
    law = NULL;

    double K = 0, f = 0;
    EXPECT(dashpot_contact_coefficient(bound, "K", &K), DASHPOT_OK, NULL);
    CLOSE(K, 4.0 / 3.0 * pair.young * sqrt(pair.radius), 1e-14);
    EXPECT(dashpot_contact_coefficient(NULL, "K", &K), DASHPOT_ERR_NULL_POINTER, "bound");
    EXPECT(dashpot_contact_coefficient(bound, NULL, &K), DASHPOT_ERR_NULL_POINTER, "name");
    EXPECT(dashpot_contact_coefficient(bound, "K", NULL), DASHPOT_ERR_NULL_POINTER, "out_value");
    EXPECT(dashpot_contact_coefficient(bound, "Q", &K), DASHPOT_ERR_INVALID_ARGUMENT, "no coefficient 'Q'");

    EXPECT(dashpot_contact_force(bound, 1e-5, 0.0, &f), DASHPOT_OK, NULL);
    CLOSE(f, K * pow(1e-5, 1.5), 1e-14);
    EXPECT(dashpot_contact_force(NULL, 1e-5, 0.0, &f), DASHPOT_ERR_NULL_POINTER, "bound");
    EXPECT(dashpot_contact_force(bound, 1e-5, 0.0, NULL), DASHPOT_ERR_NULL_POINTER, "out_force");

    double d3[3] = {-1e-6, 1e-6, 1e-5}, r3[3] = {1.0, 1.0, 0.0}, o3[3] = {7, 7, 7};
    EXPECT(dashpot_contact_force_batch(bound, d3, 3, r3, 3, o3, 3), DASHPOT_OK, NULL);
    CHECK(o3[0] == 0.0);
    CHECK(o3[1] > K * pow(1e-6, 1.5)); /* approaching: damping adds */
    CLOSE(o3[2], f, 1e-14);
    EXPECT(dashpot_contact_force_batch(bound, d3, 3, r3, 2, o3, 3), DASHPOT_ERR_BAD_LENGTH, "3, 2 and 3");
    EXPECT(dashpot_contact_force_batch(bound, d3, 3, r3, 3, o3, 2), DASHPOT_ERR_BAD_LENGTH, "same length");
    EXPECT(dashpot_contact_force_batch(NULL, d3, 3, r3, 3, o3, 3), DASHPOT_ERR_NULL_POINTER, "bound");
    EXPECT(dashpot_contact_force_batch(bound, NULL, 3, r3, 3, o3, 3), DASHPOT_ERR_NULL_POINTER, "delta");
    EXPECT(dashpot_contact_force_batch(bound, d3, 3, NULL, 3, o3, 3), DASHPOT_ERR_NULL_POINTER, "rate");
    EXPECT(dashpot_contact_force_batch(bound, d3, 3, r3, 3, NULL, 3), DASHPOT_ERR_NULL_POINTER, "out_force");
    EXPECT(dashpot_contact_force_batch(bound, NULL, 0, NULL, 0, NULL, 0), DASHPOT_OK, NULL);
    /* a length past isize::MAX bytes (a negative count cast to size_t) is refused, unread */
    EXPECT(dashpot_contact_force_batch(bound, d3, SIZE_MAX, r3, SIZE_MAX, o3, SIZE_MAX), DASHPOT_ERR_BAD_LENGTH, "isize::MAX");
    EXPECT(dashpot_contact_force_batch(bound, d3, SIZE_MAX / 8 + 1, r3, SIZE_MAX / 8 + 1, o3, SIZE_MAX / 8 + 1), DASHPOT_ERR_BAD_LENGTH, "at most");

    /* ---- a panicking plugin: the error comes back, the handle stays usable ---- */
    const char *at_name[1] = {"at"};
    double at_val[1] = {1e-6};
    const char *bp_name[1] = {"bind_panics"};
    double bp_val[1] = {1.0};
    DashpotContactLaw *panicky = NULL;
    DashpotBoundContact *pb = NULL;
    BIND(contact, panicky, "panicky", at_name, at_val, 1, dashpot_contact_bind, &pair, &pb, DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_force(pb, 1e-5, 1.0, &f), DASHPOT_ERR_PANIC, "deliberate panic at delta = 0.00001");
    EXPECT(dashpot_contact_force_batch(pb, d3, 3, r3, 3, o3, 3), DASHPOT_ERR_PANIC, "contact law 'panicky' panicked");
    EXPECT(dashpot_contact_force(pb, 5e-7, 1.0, &f), DASHPOT_OK, NULL);
    CHECK(f == 5e-7);
    dashpot_bound_contact_free(pb);
    pb = NULL;
    BIND(contact, panicky, "panicky", bp_name, bp_val, 1, dashpot_contact_bind, &pair, &pb, DASHPOT_ERR_PANIC,
         "deliberate panic in bind");
    CHECK(pb == NULL);

    /* ---- a law that returns NaN ---- */
    DashpotContactLaw *nanlaw = NULL;
    DashpotBoundContact *nb = NULL;
    BIND(contact, nanlaw, "nan-force", at_name, at_val, 1, dashpot_contact_bind, &pair, &nb, DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_force(nb, 1e-5, 0.0, &f), DASHPOT_ERR_NON_FINITE, "NaN");
    EXPECT(dashpot_contact_force_batch(nb, d3, 3, r3, 3, o3, 3), DASHPOT_ERR_NON_FINITE, "delta = 1e-5");
    dashpot_bound_contact_free(nb);

    /* ---- the 0.1 batch refuses a NaN overlap (it used to return F = 0 and OK) ---- */
    double dn[3] = {1e-6, NAN, 1e-5}, rn[3] = {0.0, 0.0, INFINITY};
    EXPECT(dashpot_contact_force_batch(bound, dn, 3, r3, 3, o3, 3), DASHPOT_ERR_NON_FINITE, "delta[1] = NaN");
    EXPECT(dashpot_contact_force_batch(bound, d3, 3, rn, 3, o3, 3), DASHPOT_ERR_NON_FINITE, "rate[2] = inf");
    EXPECT(dashpot_contact_force(bound, NAN, 0.0, &f), DASHPOT_ERR_NON_FINITE, "NaN");
    /* a law with history cannot be bound to a pair: it has nowhere to keep it */
    DashpotContactLaw *hist = NULL;
    EXPECT(dashpot_contact_new(reg, "remember-max", NULL, NULL, 0, &hist), DASHPOT_OK, NULL);
    DashpotBoundContact *hb = NULL;
    EXPECT(dashpot_contact_bind(hist, &pair, &hb), DASHPOT_ERR_INVALID_PARAMETER, "history");
    CHECK(hb == NULL);

    /* ---- materials (sdk 0.2) ---- */
    DashpotMaterials mat, wmat, badmat = {0.0, 1e9};
    double g = 6.0e9 / (2.0 * 1.3);
    EXPECT(dashpot_materials_spheres(6.0e9, 0.3, 6.0e9, 0.3, &mat), DASHPOT_OK, NULL);
    CLOSE(mat.young_eff, pair.young, 1e-15);
    CLOSE(mat.shear_eff, g / (2.0 * 1.7), 1e-15); /* 1/G = (2 - nu1)/G1 + (2 - nu2)/G2 */
    EXPECT(dashpot_materials_spheres(6.0e9, 0.3, 6.0e9, 0.3, NULL), DASHPOT_ERR_NULL_POINTER, "out_materials");
    EXPECT(dashpot_materials_spheres(6.0e9, 0.3, 6.0e9, 0.5, &mat), DASHPOT_ERR_INVALID_PAIR, "poisson = 0.5");
    EXPECT(dashpot_materials_spheres(NAN, 0.3, 6.0e9, 0.3, &mat), DASHPOT_ERR_INVALID_PAIR, "young = NaN");
    EXPECT(dashpot_materials_wall(6.0e9, 0.3, &wmat), DASHPOT_OK, NULL);
    CLOSE(wmat.young_eff, wall.young, 1e-15);
    CLOSE(wmat.shear_eff, g / 1.7, 1e-15);
    EXPECT(dashpot_materials_wall(6.0e9, 0.3, NULL), DASHPOT_ERR_NULL_POINTER, "out_materials");
    EXPECT(dashpot_materials_wall(-1.0, 0.3, &wmat), DASHPOT_ERR_INVALID_PAIR, "young = -1");

    /* ---- contact laws bound to materials: per-contact geometry and history ---- */
    DashpotContactModel *cm = NULL;
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, eps_val, 1, &law), DASHPOT_OK, NULL);
    EXPECT_BIND_MATERIALS_ERRORS(contact, law, &cm);
    EXPECT(dashpot_contact_bind_materials(law, &mat, &cm), DASHPOT_OK, NULL);
    dashpot_contact_free(law); /* the model outlives its law */
    law = NULL;
    size_t slots = 99;
    EXPECT_SLOTS(contact, cm, slots, 0);
    /* three sizes in one call: F = (4/3) E sqrt(r_i) delta^(3/2) at rest, whatever the mass */
    double md[3] = {1e-5, 2e-5, 1e-5}, mr[3] = {0.0, 0.0, 0.0};
    double mm[3] = {1e-3, 2e-3, 5e-4}, mrad[3] = {0.0025, 0.001, 0.004}, mo[3] = {7, 7, 7};
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_OK, NULL);
    for (int i = 0; i < 3; i++) CLOSE(mo[i], 4.0 / 3.0 * mat.young_eff * sqrt(mrad[i]) * pow(md[i], 1.5), 1e-14);
    /* the same contact through the 0.1 pair-bound call gives the same force, damping included */
    double one_d[1] = {1e-5}, one_r[1] = {0.7}, one_o[1] = {0}, pm_m[1] = {pair.mass}, pm_r[1] = {pair.radius};
    EXPECT(dashpot_contact_force_batch(bound, one_d, 1, one_r, 1, one_o, 1), DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_model_force_batch(cm, 1, one_d, one_r, pm_m, pm_r, NULL, 0, mo), DASHPOT_OK, NULL);
    CLOSE(mo[0], one_o[0], 1e-15);
    EXPECT(dashpot_contact_model_force_batch(NULL, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NULL_POINTER, "model");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, NULL, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NULL_POINTER, "delta");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, NULL, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NULL_POINTER, "rate");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, NULL, mrad, NULL, 0, mo), DASHPOT_ERR_NULL_POINTER, "mass");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, NULL, NULL, 0, mo), DASHPOT_ERR_NULL_POINTER, "radius");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, NULL), DASHPOT_ERR_NULL_POINTER, "out_force");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, mo, 3, mo), DASHPOT_ERR_BAD_LENGTH, "n_history = 3");
    EXPECT(dashpot_contact_model_force_batch(cm, 0, NULL, NULL, NULL, NULL, NULL, 0, NULL), DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_model_force_batch(cm, SIZE_MAX, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_BAD_LENGTH, "isize::MAX");
    md[1] = NAN;
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NON_FINITE, "delta[1] = NaN");
    md[1] = 2e-5;
    mr[2] = -INFINITY;
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NON_FINITE, "rate[2] = -inf");
    mr[2] = 0.0;
    mm[2] = 0.0;
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NON_FINITE, "mass[2] = 0");
    mm[2] = 5e-4;
    mrad[0] = NAN;
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NON_FINITE, "radius[0] = NaN");
    mrad[0] = 0.0025;
    dashpot_contact_model_free(cm);
    cm = NULL;

    /* history is read and written back in place: remember-max keeps the largest overlap */
    EXPECT(dashpot_contact_bind_materials(hist, &mat, &cm), DASHPOT_OK, NULL);
    EXPECT_SLOTS(contact, cm, slots, 1);
    double hh[3] = {0.0, 3e-5, 0.0};
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, hh, 3, mo), DASHPOT_OK, NULL);
    CHECK(hh[0] == 1e-5 && hh[1] == 3e-5 && hh[2] == 1e-5);
    CHECK(mo[0] == 1e-5 && mo[1] == 3e-5 && mo[2] == 1e-5);
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, hh, 2, mo), DASHPOT_ERR_BAD_LENGTH, "3 × 1");
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 3, mo), DASHPOT_ERR_NULL_POINTER, "history");
    dashpot_contact_model_free(cm);
    dashpot_contact_free(hist);
    cm = NULL;

    /* panics and NaN through the material binding */
    BIND(contact, panicky, "panicky", at_name, at_val, 1, dashpot_contact_bind_materials, &mat, &cm, DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_PANIC, "deliberate panic");
    double small[1] = {5e-7};
    EXPECT(dashpot_contact_model_force_batch(cm, 1, small, mr, mm, mrad, NULL, 0, mo), DASHPOT_OK, NULL);
    CHECK(mo[0] == 5e-7);
    dashpot_contact_model_free(cm);
    cm = NULL;
    BIND(contact, panicky, "panicky", bp_name, bp_val, 1, dashpot_contact_bind_materials, &mat, &cm,
         DASHPOT_ERR_PANIC, "deliberate panic in bind");
    CHECK(cm == NULL);
    BIND(contact, nanlaw, "nan-force", at_name, at_val, 1, dashpot_contact_bind_materials, &mat, &cm, DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_model_force_batch(cm, 3, md, mr, mm, mrad, NULL, 0, mo), DASHPOT_ERR_NON_FINITE, "returned force NaN");
    dashpot_contact_model_free(cm);
    cm = NULL;

    /* ---- tangential laws ---- */
    DashpotTangentialLaw *tl = NULL;
    DashpotTangentialModel *tm = NULL;
    double at_bad[1] = {-1.0};
    EXPECT_MODEL(tangential, tl, tm, "panicky-tangential", at_name, at_val, at_bad, 1, "-1", "hsd", "contact", slots, 3);
    /* the fixture's unit spring: xi += v dt, F = -xi; two contacts, two steps */
    double tn[6] = {0, 0, 1, 0, 0, 1}, tv[6] = {1, 2, 0, -3, 0, 0}, tfn[2] = {1, 1}, tdl[2] = {5e-7, 1e-7};
    double tms[2] = {1e-3, 1e-3}, trd[2] = {1e-3, 1e-3}, th[6] = {0}, tf[6] = {7, 7, 7, 7, 7, 7};
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_OK, NULL);
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_OK, NULL);
    CLOSE(th[0], 2e-3, 1e-15);
    CLOSE(th[1], 4e-3, 1e-15);
    CLOSE(th[3], -6e-3, 1e-15);
    CHECK(th[2] == 0.0 && th[4] == 0.0 && th[5] == 0.0);
    CHECK(tf[0] == -th[0] && tf[1] == -th[1] && tf[3] == -th[3]);
    EXPECT(dashpot_tangential_model_force_batch(NULL, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "model");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, NULL, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "normal");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, NULL, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "velocity");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, NULL, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "normal_force");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, NULL, tms, trd, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "delta");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, NULL, trd, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "mass");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, NULL, th, 6, tf), DASHPOT_ERR_NULL_POINTER, "radius");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, NULL, 6, tf), DASHPOT_ERR_NULL_POINTER, "history");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, NULL), DASHPOT_ERR_NULL_POINTER, "out_force");
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 4, tf), DASHPOT_ERR_BAD_LENGTH, "n_history = 4");
    EXPECT(dashpot_tangential_model_force_batch(tm, 0, 1e-3, NULL, NULL, NULL, NULL, NULL, NULL, NULL, 0, NULL), DASHPOT_OK, NULL);
    tv[4] = NAN;
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NON_FINITE, "velocity[1]");
    tv[4] = 0.0;
    tfn[1] = INFINITY;
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NON_FINITE, "normal_force[1] = inf");
    tfn[1] = 1.0;
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, NAN, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_NON_FINITE, "NaN");
    tdl[0] = 1e-5; /* above `at`: the plugin panics, the handle stays usable */
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_ERR_PANIC, "deliberate tangential panic");
    tdl[0] = 5e-7;
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, th, 6, tf), DASHPOT_OK, NULL);
    dashpot_tangential_model_free(tm);
    tm = NULL;
    BIND(tangential, tl, "panicky-tangential", bp_name, bp_val, 1, dashpot_tangential_bind_materials, &wmat, &tm,
         DASHPOT_ERR_PANIC, "deliberate panic in tangential bind");
    CHECK(tm == NULL);
    BIND(tangential, tl, "nan-tangential", at_name, at_val, 1, dashpot_tangential_bind_materials, &wmat, &tm, DASHPOT_OK,
         NULL);
    EXPECT_SLOTS(tangential, tm, slots, 0);
    tdl[0] = 1e-5;
    EXPECT(dashpot_tangential_model_force_batch(tm, 2, 1e-3, tn, tv, tfn, tdl, tms, trd, NULL, 0, tf), DASHPOT_ERR_NON_FINITE, "on contact 0");
    dashpot_tangential_model_free(tm);

    /* ---- restitution laws ---- */
    DashpotRestitutionLaw *rl = NULL;
    DashpotBoundRestitution *rb = NULL;
    const char *r0_name[1] = {"r0"};
    double r0_val[1] = {0.95}, r0_bad[1] = {-0.5};
    EXPECT_NEW_ERRORS(restitution, &rl, "mcnamara-falcon", r0_name, r0_val, r0_bad, 1, "-0.5", "hsd", "contact");
    EXPECT(dashpot_restitution_new(reg, "mcnamara-falcon", NULL, NULL, 0, &rl), DASHPOT_OK, NULL);
    EXPECT_BIND_PAIR_ERRORS(restitution, rl, &rb);
    EXPECT(dashpot_restitution_bind(rl, &pair, &rb), DASHPOT_OK, NULL);
    double r = 0;
    EXPECT(dashpot_restitution_eval(rb, 0.3, &r), DASHPOT_OK, NULL);
    CLOSE(r, 0.95, 1e-14); /* r(v_y) = r0 (McNamara & Falcon eq. 1) */
    EXPECT(dashpot_restitution_eval(rb, 1.0, &r), DASHPOT_OK, NULL);
    CLOSE(r, 0.95 * pow(1.0 / 0.3, -0.25), 1e-14);
    EXPECT(dashpot_restitution_eval(NULL, 1.0, &r), DASHPOT_ERR_NULL_POINTER, "bound");
    EXPECT(dashpot_restitution_eval(rb, 1.0, NULL), DASHPOT_ERR_NULL_POINTER, "out_restitution");
    double s2[2] = {0.3, 1.0}, o2[2];
    EXPECT(dashpot_restitution_batch(rb, s2, 2, o2, 2), DASHPOT_OK, NULL);
    CLOSE(o2[1], r, 1e-15);
    EXPECT(dashpot_restitution_batch(rb, s2, 2, o2, 1), DASHPOT_ERR_BAD_LENGTH, "2 and 1");
    EXPECT(dashpot_restitution_batch(rb, s2, SIZE_MAX, o2, SIZE_MAX), DASHPOT_ERR_BAD_LENGTH, "isize::MAX");
    EXPECT(dashpot_restitution_batch(NULL, s2, 2, o2, 2), DASHPOT_ERR_NULL_POINTER, "bound");
    EXPECT(dashpot_restitution_batch(rb, NULL, 2, o2, 2), DASHPOT_ERR_NULL_POINTER, "speed");
    EXPECT(dashpot_restitution_batch(rb, s2, 2, NULL, 2), DASHPOT_ERR_NULL_POINTER, "out_restitution");
    dashpot_bound_restitution_free(rb);
    dashpot_restitution_free(rl);
    rb = NULL;
    EXPECT(dashpot_restitution_new(reg, "nan-restitution", NULL, NULL, 0, &rl), DASHPOT_OK, NULL);
    EXPECT(dashpot_restitution_bind(rl, &pair, &rb), DASHPOT_OK, NULL);
    EXPECT(dashpot_restitution_eval(rb, 2.0, &r), DASHPOT_ERR_NON_FINITE, "impact speed");
    EXPECT(dashpot_restitution_batch(rb, s2, 2, o2, 2), DASHPOT_OK, NULL);
    s2[1] = 3.0;
    EXPECT(dashpot_restitution_batch(rb, s2, 2, o2, 2), DASHPOT_ERR_NON_FINITE, "NaN");
    dashpot_bound_restitution_free(rb);
    dashpot_restitution_free(rl);

    /* ---- closed-form calibration ---- */
    DashpotCalibrationTarget t = {0.7, NAN, NAN, DASHPOT_END_OVERLAP};
    double cal[1] = {0};
    size_t nset = 0;
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_OK, NULL);
    CHECK(nset == 1 && cal[0] == 0.7);
    EXPECT(dashpot_calibrate(NULL, "hsd", &t, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_calibrate(reg, NULL, &t, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_NULL_POINTER, "name");
    EXPECT(dashpot_calibrate(reg, "hsd", NULL, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_NULL_POINTER, "target");
    EXPECT(dashpot_calibrate(reg, "hsd", &t, NULL, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_NULL_POINTER, "pair");
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &pair, NULL, NULL, 0, NULL, 1, &nset), DASHPOT_ERR_NULL_POINTER, "out_values");
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &pair, NULL, NULL, 0, cal, 1, NULL), DASHPOT_ERR_NULL_POINTER, "out_n_set");
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &pair, NULL, NULL, 0, cal, 2, &nset), DASHPOT_ERR_BAD_LENGTH, "one slot per parameter");
    EXPECT(dashpot_calibrate(reg, "nope", &t, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_UNKNOWN_LAW, "nope");
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &zero, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_INVALID_PAIR, "effective mass");
    t.end_criterion = 5;
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_INVALID_ARGUMENT, "end_criterion = 5");
    t.end_criterion = DASHPOT_END_OVERLAP;
    t.contact_time = 1e-4; /* HSD has no closed form for a contact time */
    EXPECT(dashpot_calibrate(reg, "hsd", &t, &pair, NULL, NULL, 0, cal, 1, &nset), DASHPOT_ERR_UNSUPPORTED, "no closed-form");

    /* ---- the error message is per thread and survives successful calls ---- */
    EXPECT(dashpot_registry_find(reg, "still-no-such-law", &idx), DASHPOT_ERR_UNKNOWN_LAW, "still-no-such-law");
    EXPECT(dashpot_registry_law_count(reg, &count), DASHPOT_OK, NULL);
    CHECK(strstr(dashpot_last_error(), "still-no-such-law") != NULL);

    /* ---- sdk 0.3: rolling and twisting laws, energy and reach outputs ---- */
    {
        DashpotRollingLaw *rl3 = NULL;
        DashpotRollingModel *rm3 = NULL;
        const char *sds_names[3] = {"k", "gamma", "mu"};
        const double sds_vals[3] = {1000.0, 0.0, 10.0};
        const double sds_bad[3] = {-5.0, 0.0, 10.0};
        size_t rslots = 0;
        EXPECT_MODEL(rolling, rl3, rm3, "rolling-sds", sds_names, sds_vals, sds_bad, 3, "-5", "hsd", "contact", rslots, 6);
        /* one step of a rolling velocity v along x from zero history: ξ = v dt, F_r = −k ξ
           (far below the cap μ F_n), elastic energy k ξ²/2, no dissipation (γ = 0) */
        double rn[3] = {0, 0, 1}, rv[3] = {0.2, 0, 0}, rfn[1] = {1.0}, rdl[1] = {1e-6}, rms[1] = {1e-3}, rrd[1] = {1e-3};
        double rh[6] = {0, 0, 0, 0, 0, 0}, rf[3], rp[1], re[1]; /* ξ, and the dashpot's share */
        int written = -1;
        EXPECT(dashpot_rolling_model_force_batch(rm3, 1, 1e-4, rn, rv, rfn, rdl, rms, rrd, rh, 6, rf, rp, re, &written), DASHPOT_OK, NULL);
        CHECK(fabs(rf[0] - (-1000.0 * 0.2 * 1e-4)) < 1e-15 && rf[1] == 0.0 && rf[2] == 0.0);
        /* no dissipation: the power zero to rounding of the work rate |F| v = 4e-3 W */
        CHECK(fabs(re[0] - 0.5 * 1000.0 * (0.2e-4) * (0.2e-4)) < 1e-18 && fabs(rp[0]) < 1e-12 * 4e-3 && written == 1);
        EXPECT(dashpot_rolling_model_force_batch(NULL, 1, 1e-4, rn, rv, rfn, rdl, rms, rrd, rh, 6, rf, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "model");
        EXPECT(dashpot_rolling_model_force_batch(rm3, 1, 1e-4, NULL, rv, rfn, rdl, rms, rrd, rh, 6, rf, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "normal");
        EXPECT(dashpot_rolling_model_force_batch(rm3, 1, 1e-4, rn, rv, rfn, rdl, rms, rrd, rh, 2, rf, NULL, NULL, NULL), DASHPOT_ERR_BAD_LENGTH, "n_history = 2");
        rv[1] = NAN;
        EXPECT(dashpot_rolling_model_force_batch(rm3, 1, 1e-4, rn, rv, rfn, rdl, rms, rrd, rh, 6, rf, NULL, NULL, NULL), DASHPOT_ERR_NON_FINITE, "NaN");
        dashpot_rolling_model_free(rm3);

        DashpotTwistingLaw *wl3 = NULL;
        DashpotTwistingModel *wm3 = NULL;
        const double tw_vals[3] = {1e-3, 0.0, 1.0};
        size_t wslots = 0;
        EXPECT_MODEL(twisting, wl3, wm3, "twisting-sds", sds_names, tw_vals, sds_bad, 3, "-5", "rolling-sds", "rolling",
                     wslots, 2);
        /* one step of spin rate w: θ = w dt, M = −k θ below the cap μ F_n */
        double wrate[1] = {3.0}, wh[4] = {0, 0, 0, 0}, wt[1];
        EXPECT(dashpot_twisting_model_torque_batch(wm3, 1, 1e-4, rn, wrate, rfn, rdl, rms, rrd, wh, wslots, wt, NULL, NULL, NULL), DASHPOT_OK, NULL);
        CHECK(fabs(wt[0] - (-1e-3 * 3.0 * 1e-4)) < 1e-18);
        EXPECT(dashpot_twisting_model_torque_batch(wm3, 1, 1e-4, rn, NULL, rfn, rdl, rms, rrd, wh, wslots, wt, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "rate");
        EXPECT(dashpot_twisting_model_torque_batch(wm3, 1, 1e-4, rn, wrate, rfn, rdl, rms, rrd, wh, wslots, NULL, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "out_torque");
        dashpot_twisting_model_free(wm3);

        /* Mindlin through the energy batch: one step of slip v below the cap stores
           elastic = k (v dt)^2 / 2 = |F| v dt / 2 and dissipates nothing (no damping); a fast
           slip beyond the cap mu F_n dissipates (power > 0); its history: xi, k_t and the dashpot's share, 7 slots */
        DashpotTangentialLaw *ml = NULL;
        DashpotTangentialModel *mm = NULL;
        EXPECT(dashpot_tangential_new(reg, "mindlin", (const char *[]){"mu"}, (double[]){0.5}, 1, &ml), DASHPOT_OK, NULL);
        EXPECT(dashpot_tangential_bind_materials(ml, &mat, &mm), DASHPOT_OK, NULL);
        double mv[3] = {1e-3, 0, 0}, mh[7] = {0, 0, 0, 0, 0, 0, 0}, mf[3], mp[1] = {-1}, me[1] = {-1};
        written = -1;
        EXPECT(dashpot_tangential_model_force_batch_energy(mm, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, mh, 7, mf, mp, me, &written), DASHPOT_OK, NULL);
        CHECK(written == 1 && mf[0] < 0.0 && fabs(mp[0]) <= 1e-12 * -mf[0] * 1e-3);
        CLOSE(me[0], 0.5 * -mf[0] * 1e-3 * 1e-4, 1e-12);
        mv[0] = 1e3;
        EXPECT(dashpot_tangential_model_force_batch_energy(mm, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, mh, 7, mf, mp, NULL, NULL), DASHPOT_OK, NULL);
        CLOSE(-mf[0], 0.5 * rfn[0], 1e-12);
        CHECK(mp[0] > 0.0);
        EXPECT(dashpot_tangential_model_force_batch_energy(NULL, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, mh, 7, mf, mp, me, &written), DASHPOT_ERR_NULL_POINTER, "model");
        EXPECT(dashpot_tangential_model_force_batch_energy(mm, 1, 1e-4, rn, NULL, rfn, rdl, rms, rrd, mh, 7, mf, mp, me, &written), DASHPOT_ERR_NULL_POINTER, "velocity");
        EXPECT(dashpot_tangential_model_force_batch_energy(mm, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, mh, 1, mf, mp, me, &written), DASHPOT_ERR_BAD_LENGTH, "n_history = 1");
        dashpot_tangential_model_free(mm);
        dashpot_tangential_free(ml);

        /* JKR through the energy batch: formed at touch, its reach is the rupture separation */
        DashpotContactLaw *jkr = NULL;
        DashpotContactModel *jm = NULL;
        const char *w_name[1] = {"w"};
        const double w_val[1] = {0.1};
        EXPECT(dashpot_contact_new(reg, "jkr", w_name, w_val, 1, &jkr), DASHPOT_OK, NULL);
        EXPECT(dashpot_contact_bind_materials(jkr, &mat, &jm), DASHPOT_OK, NULL);
        double jd[1] = {1e-9}, jr[1] = {0.0}, jmass[1] = {1e-3}, jrad[1] = {2.5e-3}, jh[1] = {0}, jf[1], jreach[1], jp[1], je[1];
        EXPECT(dashpot_contact_model_force_batch_energy(jm, 1, jd, jr, jmass, jrad, jh, 1, jf, jreach, jp, je, &written), DASHPOT_OK, NULL);
        double e_eff = mat.young_eff;
        double delta_c = 0.75 * cbrt(M_PI * M_PI * 0.1 * 0.1 * 2.5e-3 / (e_eff * e_eff));
        CHECK(jh[0] == 1.0 && jf[0] < 0.0 && fabs(jreach[0] / delta_c - 1.0) < 1e-12 && written == 1);
        EXPECT(dashpot_contact_model_force_batch_energy(NULL, 1, jd, jr, jmass, jrad, jh, 1, jf, NULL, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "model");
        EXPECT(dashpot_contact_model_force_batch_energy(jm, 1, jd, jr, jmass, jrad, jh, 0, jf, NULL, NULL, NULL, NULL), DASHPOT_ERR_BAD_LENGTH, "n_history = 0");

        /* sdk 0.4: JKR's normal context, its own contact radius a: delta = a^2/R - sqrt(2 pi w a/E),
           positive past touching; then laws that echo the context they receive get exactly it */
        double jx[3] = {-1, -1, -1};
        jd[0] = -0.5 * delta_c;
        EXPECT(dashpot_contact_model_force_batch_context(jm, 1, jd, jr, jmass, jrad, jh, 1, jf, jreach, jp, je, &written, jx), DASHPOT_OK, NULL);
        CHECK(jh[0] == 1.0 && jx[0] > 0.0 && jx[1] > 0.0 && jx[2] == 0.0);
        CHECK(fabs(jx[0] * jx[0] / 2.5e-3 - sqrt(2.0 * M_PI * 0.1 * jx[0] / e_eff) - jd[0]) <= 1e-9 * delta_c);
        EXPECT(dashpot_contact_model_force_batch_context(jm, 1, jd, jr, jmass, jrad, jh, 1, jf, NULL, NULL, NULL, NULL, jx), DASHPOT_OK, NULL);
        EXPECT(dashpot_contact_model_force_batch_context(NULL, 1, jd, jr, jmass, jrad, jh, 1, jf, NULL, NULL, NULL, NULL, jx), DASHPOT_ERR_NULL_POINTER, "model");
        EXPECT(dashpot_contact_model_force_batch_context(jm, 1, jd, jr, jmass, jrad, jh, 1, jf, NULL, NULL, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "out_context");
        EXPECT(dashpot_contact_model_force_batch_context(jm, 0, NULL, NULL, NULL, NULL, NULL, 0, NULL, NULL, NULL, NULL, NULL, NULL), DASHPOT_OK, NULL);
        int reads = -1;
        DashpotTangentialLaw *el = NULL;
        DashpotTangentialModel *em = NULL;
        EXPECT(dashpot_tangential_new(reg, "context-echo", NULL, NULL, 0, &el), DASHPOT_OK, NULL);
        EXPECT(dashpot_tangential_bind_materials(el, &mat, &em), DASHPOT_OK, NULL);
        EXPECT(dashpot_tangential_model_reads_context(em, &reads), DASHPOT_OK, NULL);
        CHECK(reads == 1);
        double ef[3] = {0, 0, 0};
        EXPECT(dashpot_tangential_model_force_batch_context(em, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, jx, NULL, 0, ef, NULL, NULL, NULL), DASHPOT_OK, NULL);
        CHECK(ef[0] == jx[0] && ef[1] == jx[1] && ef[2] == jx[2]);
        /* no context: each contact's default, sqrt(R delta), max(F, 0), 0 */
        EXPECT(dashpot_tangential_model_force_batch_context(em, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, NULL, NULL, 0, ef, NULL, NULL, NULL), DASHPOT_OK, NULL);
        CHECK(ef[0] == sqrt(rrd[0] * rdl[0]) && ef[1] == rfn[0] && ef[2] == 0.0);
        double badx[3] = {1.0, NAN, 0.0};
        EXPECT(dashpot_tangential_model_force_batch_context(em, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, badx, NULL, 0, ef, NULL, NULL, NULL), DASHPOT_ERR_NON_FINITE, "context[0]");
        EXPECT(dashpot_tangential_model_force_batch_context(NULL, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, jx, NULL, 0, ef, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "model");
        dashpot_tangential_model_free(em);
        dashpot_tangential_free(el);
        DashpotRollingLaw *erl = NULL;
        DashpotRollingModel *erm = NULL;
        EXPECT(dashpot_rolling_new(reg, "context-echo-rolling", NULL, NULL, 0, &erl), DASHPOT_OK, NULL);
        EXPECT(dashpot_rolling_bind_materials(erl, &mat, &erm), DASHPOT_OK, NULL);
        EXPECT(dashpot_rolling_model_reads_context(erm, &reads), DASHPOT_OK, NULL);
        CHECK(reads == 1);
        EXPECT(dashpot_rolling_model_force_batch_context(erm, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, jx, NULL, 0, ef, NULL, NULL, &written), DASHPOT_OK, NULL);
        CHECK(ef[0] == jx[0] && ef[1] == jx[1] && ef[2] == jx[2] && written == 0);
        EXPECT(dashpot_rolling_model_force_batch_context(erm, 1, 1e-4, rn, mv, rfn, rdl, rms, rrd, badx, NULL, 0, ef, NULL, NULL, NULL), DASHPOT_ERR_NON_FINITE, "context[0]");
        dashpot_rolling_model_free(erm);
        dashpot_rolling_free(erl);
        DashpotTwistingLaw *ewl = NULL;
        DashpotTwistingModel *ewm = NULL;
        EXPECT(dashpot_twisting_new(reg, "context-echo-twisting", NULL, NULL, 0, &ewl), DASHPOT_OK, NULL);
        EXPECT(dashpot_twisting_bind_materials(ewl, &mat, &ewm), DASHPOT_OK, NULL);
        double et[1] = {0};
        EXPECT(dashpot_twisting_model_torque_batch_context(ewm, 1, 1e-4, rn, wrate, rfn, rdl, rms, rrd, jx, NULL, 0, et, NULL, NULL, NULL), DASHPOT_OK, NULL);
        CHECK(et[0] == jx[0]);
        EXPECT(dashpot_twisting_model_torque_batch_context(ewm, 1, 1e-4, rn, wrate, rfn, rdl, rms, rrd, jx, NULL, 0, NULL, NULL, NULL, NULL), DASHPOT_ERR_NULL_POINTER, "out_torque");
        dashpot_twisting_model_free(ewm);
        dashpot_twisting_free(ewl);
        dashpot_contact_model_free(jm);
        dashpot_contact_free(jkr);
        dashpot_rolling_free(NULL);
        dashpot_rolling_model_free(NULL);
        dashpot_twisting_free(NULL);
        dashpot_twisting_model_free(NULL);

        /* heat (sdk 0.4): heat-radius, H = 2 k a with the default a = sqrt(R delta); the heat
           flow into i is H (T_j - T_i), and exchanging the temperatures negates it exactly */
        DashpotHeatLaw *hl = NULL;
        DashpotHeatModel *hm = NULL;
        const char *k_names[1] = {"k"};
        const double k_vals[1] = {2.0}, k_bad[1] = {-1.0};
        size_t hslots = 7;
        EXPECT_NEW_ERRORS(heat, &hl, "heat-radius", k_names, k_vals, k_bad, 1, "-1", "rolling-sds", "rolling");
        EXPECT(dashpot_heat_new(reg, "heat-radius", k_names, k_vals, 1, &hl), DASHPOT_OK, NULL);
        EXPECT_BIND_MATERIALS_ERRORS(heat, hl, &hm);
        EXPECT(dashpot_heat_bind_materials(hl, &mat, &hm), DASHPOT_OK, NULL);
        dashpot_heat_free(hl);
        EXPECT(dashpot_heat_model_history_slots(hm, &hslots), DASHPOT_OK, NULL);
        CHECK(hslots == 0);
        EXPECT(dashpot_heat_model_history_slots(NULL, &hslots), DASHPOT_ERR_NULL_POINTER, "model");
        EXPECT(dashpot_heat_model_reads_context(hm, &reads), DASHPOT_OK, NULL);
        CHECK(reads == 1);
        EXPECT(dashpot_heat_model_reads_context(NULL, &reads), DASHPOT_ERR_NULL_POINTER, "model");
        double ht[4] = {300.0, 350.0, 350.0, 300.0}, hfn[2] = {1.0, 1.0}, hdl[2] = {1e-6, 1e-6}, hrd[2] = {1e-3, 1e-3};
        double hq[2], hg[2];
        EXPECT(dashpot_heat_model_heat_batch(hm, 2, 1e-5, ht, hfn, hdl, hrd, NULL, NULL, 0, hq, hg), DASHPOT_OK, NULL);
        CLOSE(hg[0], 2.0 * 2.0 * sqrt(1e-3 * 1e-6), 1e-15);
        CHECK(hq[0] == hg[0] * 50.0 && hq[1] == -hq[0]);
        EXPECT(dashpot_heat_model_heat_batch(NULL, 2, 1e-5, ht, hfn, hdl, hrd, NULL, NULL, 0, hq, hg), DASHPOT_ERR_NULL_POINTER, "model");
        EXPECT(dashpot_heat_model_heat_batch(hm, 2, 1e-5, NULL, hfn, hdl, hrd, NULL, NULL, 0, hq, hg), DASHPOT_ERR_NULL_POINTER, "temperature");
        EXPECT(dashpot_heat_model_heat_batch(hm, 2, 1e-5, ht, hfn, hdl, hrd, NULL, NULL, 0, NULL, hg), DASHPOT_ERR_NULL_POINTER, "out_heat");
        EXPECT(dashpot_heat_model_heat_batch(hm, 2, 1e-5, ht, hfn, hdl, hrd, NULL, NULL, 3, hq, hg), DASHPOT_ERR_BAD_LENGTH, "n_history = 3");
        ht[2] = NAN;
        EXPECT(dashpot_heat_model_heat_batch(hm, 2, 1e-5, ht, hfn, hdl, hrd, NULL, NULL, 0, hq, NULL), DASHPOT_ERR_NON_FINITE, "temperature[1]");
        dashpot_heat_model_free(hm);
        dashpot_heat_free(NULL);
        dashpot_heat_model_free(NULL);
    }

    /* ---- freeing null is a no-op ---- */
    dashpot_registry_free(NULL);
    dashpot_contact_free(NULL);
    dashpot_bound_contact_free(NULL);
    dashpot_restitution_free(NULL);
    dashpot_bound_restitution_free(NULL);
    dashpot_contact_model_free(NULL);
    dashpot_tangential_free(NULL);
    dashpot_tangential_model_free(NULL);

    dashpot_bound_contact_free(bound);
    dashpot_registry_free(reg);
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
