/*
 * Two-body collisions through the dashpot C ABI, with this program's own velocity-Verlet loop.
 *
 * Three independent head-on collisions of two identical spheres (the MCC granule of Antypov &
 * Elliott: d = 1 cm, rho = 1500 kg/m^3, E = 6 GPa, nu = 0.3) at impact speeds 0.1, 1 and 5 m/s
 * are integrated side by side; every step evaluates the normal forces of all three pairs with
 * one call of dashpot_contact_force_batch. A collision is over when the overlap returns to 0;
 * the realized restitution is the ratio of the separation speed to the impact speed.
 *
 * usage: collision PLUGIN_DIR [LAW] [eps]      (default: hsd 0.54)
 * build: cc -O2 -I host/capi/include collision.c -L target/release -ldashpot_capi -lm
 */
#include "dashpot.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define NPAIR 3

static int check(DashpotStatus st, const char *what) {
    if (st != DASHPOT_OK) {
        fprintf(stderr, "%s failed: %s: %s\n", what, dashpot_status_name((int)st), dashpot_last_error());
        return 1;
    }
    return 0;
}

int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s PLUGIN_DIR [LAW] [eps]\n", argv[0]);
        return 2;
    }
    if (dashpot_abi_version() != DASHPOT_ABI_VERSION) {
        fprintf(stderr, "dashpot ABI %u, header %u\n", dashpot_abi_version(), DASHPOT_ABI_VERSION);
        return 2;
    }
    const char *law_name = argc > 2 ? argv[2] : "hsd";
    double eps = argc > 3 ? atof(argv[3]) : 0.54;

    DashpotRegistry *reg = NULL;
    DashpotContactLaw *law = NULL;
    DashpotBoundContact *bound = NULL;
    int rc = 1;

    const char *dirs[1] = {argv[1]};
    if (check(dashpot_registry_open(dirs, 1, 0, &reg), "dashpot_registry_open")) goto done;
    size_t nlaws = 0;
    if (check(dashpot_registry_law_count(reg, &nlaws), "dashpot_registry_law_count")) goto done;
    printf("%zu laws loaded\n", nlaws);

    const char *names[1] = {"eps"};
    double values[1] = {eps};
    if (check(dashpot_contact_new(reg, law_name, names, values, 1, &law), "dashpot_contact_new")) goto done;

    DashpotParticle mcc = {0.01, 1500.0, 6.0e9, 0.3};
    DashpotPair pair;
    if (check(dashpot_pair_spheres(&mcc, &mcc, &pair), "dashpot_pair_spheres")) goto done;
    if (check(dashpot_contact_bind(law, &pair, &bound), "dashpot_contact_bind")) goto done;

    const double d = mcc.diameter;
    const double mass = M_PI / 6.0 * mcc.density * d * d * d; /* each sphere */
    const double v0[NPAIR] = {0.1, 1.0, 5.0};

    /* Hertz contact time at the fastest impact (Antypov & Elliott eq. 23) bounds the step. */
    double tau = 2.214 * pow(pow(pair.mass, 2) / (pow(pair.young, 2) * d * v0[NPAIR - 1]), 0.2);
    double dt = tau / 2000.0;

    double x1[NPAIR], x2[NPAIR], v1[NPAIR], v2[NPAIR], f[NPAIR];
    double delta[NPAIR], rate[NPAIR], eps_realized[NPAIR];
    int state[NPAIR]; /* 0 approaching, 1 in contact, 2 separated */
    for (int k = 0; k < NPAIR; k++) {
        x1[k] = 0.0;
        x2[k] = d; /* just touching */
        v1[k] = 0.5 * v0[k];
        v2[k] = -0.5 * v0[k];
        f[k] = 0.0;
        state[k] = 0;
        eps_realized[k] = NAN;
    }
    long steps = 0;
    for (int remaining = NPAIR; remaining > 0 && steps < 100000000L; steps++) {
        for (int k = 0; k < NPAIR; k++) { /* kick, drift */
            v1[k] -= 0.5 * dt * f[k] / mass;
            v2[k] += 0.5 * dt * f[k] / mass;
            x1[k] += dt * v1[k];
            x2[k] += dt * v2[k];
            delta[k] = d - (x2[k] - x1[k]);
            rate[k] = v1[k] - v2[k];
        }
        if (check(dashpot_contact_force_batch(bound, delta, NPAIR, rate, NPAIR, f, NPAIR),
                  "dashpot_contact_force_batch"))
            goto done;
        for (int k = 0; k < NPAIR; k++) { /* kick */
            v1[k] -= 0.5 * dt * f[k] / mass;
            v2[k] += 0.5 * dt * f[k] / mass;
            if (state[k] == 0 && delta[k] > 0.0) state[k] = 1;
            if (state[k] == 1 && delta[k] <= 0.0) {
                state[k] = 2;
                eps_realized[k] = (v2[k] - v1[k]) / v0[k];
                remaining--;
            }
        }
    }
    printf("law %s eps %.6f dt %.3e s (tau/2000 at %.1f m/s), %ld steps\n", law_name, eps, dt, v0[NPAIR - 1],
           steps);
    for (int k = 0; k < NPAIR; k++)
        printf("v0 %.3f m/s realized restitution %.6f\n", v0[k], eps_realized[k]);
    rc = 0;

done:
    dashpot_bound_contact_free(bound);
    dashpot_contact_free(law);
    dashpot_registry_free(reg);
    return rc;
}
