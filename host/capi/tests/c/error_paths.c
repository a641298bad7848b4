/*
 * Every function of dashpot.h, called from C: its success path and each of its error paths
 * (null handle or output, unknown law, bad parameter, wrong array length, a panicking or
 * NaN-returning plugin) must return the documented status and leave a message.
 *
 * usage: error_paths PLUGIN_DIR   (a directory with the seed plugins and the faulty fixture)
 * Prints one line per failed expectation and "N passed, M failed" at the end.
 */
#include "dashpot.h"

#include <math.h>
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
    EXPECT(dashpot_contact_new(NULL, "hsd", eps_name, eps_val, 1, &law), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_contact_new(reg, NULL, eps_name, eps_val, 1, &law), DASHPOT_ERR_NULL_POINTER, "name");
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, eps_val, 1, NULL), DASHPOT_ERR_NULL_POINTER, "out_law");
    EXPECT(dashpot_contact_new(reg, "hsd", NULL, eps_val, 1, &law), DASHPOT_ERR_NULL_POINTER, "param_names");
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, NULL, 1, &law), DASHPOT_ERR_NULL_POINTER, "param_values");
    EXPECT(dashpot_contact_new(reg, "hsd", null_name, eps_val, 1, &law), DASHPOT_ERR_NULL_POINTER, "param_names[0]");
    EXPECT(dashpot_contact_new(reg, "no-such-law", NULL, NULL, 0, &law), DASHPOT_ERR_UNKNOWN_LAW, "available laws");
    EXPECT(dashpot_contact_new(reg, "mcnamara-falcon", NULL, NULL, 0, &law), DASHPOT_ERR_UNKNOWN_LAW, "restitution law");
    EXPECT(dashpot_contact_new(reg, "hsd", bogus_name, eps_val, 1, &law), DASHPOT_ERR_UNKNOWN_PARAMETER, "epsilon");
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, eps_bad, 1, &law), DASHPOT_ERR_INVALID_PARAMETER, "1.5");
    CHECK(law == NULL);
    EXPECT(dashpot_contact_new(reg, "hsd", eps_name, eps_val, 1, &law), DASHPOT_OK, NULL);
    CHECK(law != NULL);

    DashpotBoundContact *bound = NULL;
    DashpotPair zero = {0.0, 0.0025, 1e9};
    EXPECT(dashpot_contact_bind(NULL, &pair, &bound), DASHPOT_ERR_NULL_POINTER, "law");
    EXPECT(dashpot_contact_bind(law, NULL, &bound), DASHPOT_ERR_NULL_POINTER, "pair");
    EXPECT(dashpot_contact_bind(law, &pair, NULL), DASHPOT_ERR_NULL_POINTER, "out_bound");
    EXPECT(dashpot_contact_bind(law, &zero, &bound), DASHPOT_ERR_INVALID_PAIR, "effective mass");
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

    /* ---- a panicking plugin: the error comes back, the handle stays usable ---- */
    const char *at_name[1] = {"at"};
    double at_val[1] = {1e-6};
    DashpotContactLaw *panicky = NULL;
    DashpotBoundContact *pb = NULL;
    EXPECT(dashpot_contact_new(reg, "panicky", at_name, at_val, 1, &panicky), DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_bind(panicky, &pair, &pb), DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_force(pb, 1e-5, 1.0, &f), DASHPOT_ERR_PANIC, "deliberate panic at delta = 0.00001");
    EXPECT(dashpot_contact_force_batch(pb, d3, 3, r3, 3, o3, 3), DASHPOT_ERR_PANIC, "contact law 'panicky' panicked");
    EXPECT(dashpot_contact_force(pb, 5e-7, 1.0, &f), DASHPOT_OK, NULL);
    CHECK(f == 5e-7);
    dashpot_bound_contact_free(pb);
    dashpot_contact_free(panicky);
    const char *bp_name[1] = {"bind_panics"};
    double bp_val[1] = {1.0};
    EXPECT(dashpot_contact_new(reg, "panicky", bp_name, bp_val, 1, &panicky), DASHPOT_OK, NULL);
    pb = NULL;
    EXPECT(dashpot_contact_bind(panicky, &pair, &pb), DASHPOT_ERR_PANIC, "deliberate panic in bind");
    CHECK(pb == NULL);
    dashpot_contact_free(panicky);

    /* ---- a law that returns NaN ---- */
    DashpotContactLaw *nanlaw = NULL;
    DashpotBoundContact *nb = NULL;
    EXPECT(dashpot_contact_new(reg, "nan-force", at_name, at_val, 1, &nanlaw), DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_bind(nanlaw, &pair, &nb), DASHPOT_OK, NULL);
    EXPECT(dashpot_contact_force(nb, 1e-5, 0.0, &f), DASHPOT_ERR_NON_FINITE, "NaN");
    EXPECT(dashpot_contact_force_batch(nb, d3, 3, r3, 3, o3, 3), DASHPOT_ERR_NON_FINITE, "delta = 1e-5");
    dashpot_bound_contact_free(nb);
    dashpot_contact_free(nanlaw);

    /* ---- restitution laws ---- */
    DashpotRestitutionLaw *rl = NULL;
    DashpotBoundRestitution *rb = NULL;
    const char *r0_name[1] = {"r0"};
    double r0_bad[1] = {-0.5};
    EXPECT(dashpot_restitution_new(NULL, "mcnamara-falcon", NULL, NULL, 0, &rl), DASHPOT_ERR_NULL_POINTER, "registry");
    EXPECT(dashpot_restitution_new(reg, NULL, NULL, NULL, 0, &rl), DASHPOT_ERR_NULL_POINTER, "name");
    EXPECT(dashpot_restitution_new(reg, "mcnamara-falcon", NULL, NULL, 0, NULL), DASHPOT_ERR_NULL_POINTER, "out_law");
    EXPECT(dashpot_restitution_new(reg, "mcnamara-falcon", NULL, r0_bad, 1, &rl), DASHPOT_ERR_NULL_POINTER, "param_names");
    EXPECT(dashpot_restitution_new(reg, "hsd", NULL, NULL, 0, &rl), DASHPOT_ERR_UNKNOWN_LAW, "contact law");
    EXPECT(dashpot_restitution_new(reg, "nope", NULL, NULL, 0, &rl), DASHPOT_ERR_UNKNOWN_LAW, "unknown law 'nope'");
    EXPECT(dashpot_restitution_new(reg, "mcnamara-falcon", bogus_name, eps_val, 1, &rl), DASHPOT_ERR_UNKNOWN_PARAMETER, "epsilon");
    EXPECT(dashpot_restitution_new(reg, "mcnamara-falcon", r0_name, r0_bad, 1, &rl), DASHPOT_ERR_INVALID_PARAMETER, "-0.5");
    EXPECT(dashpot_restitution_new(reg, "mcnamara-falcon", NULL, NULL, 0, &rl), DASHPOT_OK, NULL);
    EXPECT(dashpot_restitution_bind(NULL, &pair, &rb), DASHPOT_ERR_NULL_POINTER, "law");
    EXPECT(dashpot_restitution_bind(rl, NULL, &rb), DASHPOT_ERR_NULL_POINTER, "pair");
    EXPECT(dashpot_restitution_bind(rl, &pair, NULL), DASHPOT_ERR_NULL_POINTER, "out_bound");
    EXPECT(dashpot_restitution_bind(rl, &zero, &rb), DASHPOT_ERR_INVALID_PAIR, "effective mass");
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

    /* ---- freeing null is a no-op ---- */
    dashpot_registry_free(NULL);
    dashpot_contact_free(NULL);
    dashpot_bound_contact_free(NULL);
    dashpot_restitution_free(NULL);
    dashpot_bound_restitution_free(NULL);

    dashpot_bound_contact_free(bound);
    dashpot_registry_free(reg);
    printf("%d passed, %d failed\n", passed, failed);
    return failed == 0 ? 0 : 1;
}
