/* fix wall/dashpot and wall/dashpot/region: the contacts' evaluation through the contact
 * engine, the outputs, and the per-atom history records (moved with the atoms, written to
 * restart files). See fix_wall_dashpot.h. */
#include "fix_wall_dashpot.h"

#include "atom.h"
#include "comm.h"
#include "error.h"
#include "input.h"
#include "memory.h"
#include "neighbor.h"
#include "update.h"
#include "variable.h"

#include <mpi.h>

#include <algorithm>
#include <cmath>

using namespace LAMMPS_NS;
using namespace dashpot_lmp;

/* ---------------------------------------------------------------------- the contacts */

void FixWallDashpot::update_rigid_masses()
{
    if (!fix_rigid || (neighbor->ago != 0 && (int) mass_rigid.size() >= atom->nlocal)) return;
    int tmp = 0;
    const int *body = static_cast<int *>(fix_rigid->extract("body", tmp));
    const double *mass_body = static_cast<double *>(fix_rigid->extract("masstotal", tmp));
    const int nlocal = atom->nlocal;
    mass_rigid.assign(nlocal, 0.0);
    if (!body || !mass_body) return;
    for (int i = 0; i < nlocal; i++) mass_rigid[i] = body[i] >= 0 ? mass_body[body[i]] : 0.0;
}

double FixWallDashpot::mass_of(int i) const
{
    if (fix_rigid && i < (int) mass_rigid.size() && mass_rigid[i] > 0.0) return mass_rigid[i];
    return atom->rmass[i];
}

void FixWallDashpot::begin_step()
{
    for (int k = 0; k < NVECTOR; k++) sums[k] = k >= 4 && !energy_flag ? NAN : 0.0;
    sums_step = update->ntimestep;
    reduced = 0;
    if (contacts_flag)
        for (int i = 0; i < atom->nlocal; i++)
            for (int m = 0; m < 8; m++) array_atom[i][m] = 0.0;
    engine.reset();
    if (engine.flags().heat) {
        HeatTarget heat;
        heat.temperature = atom->temperature;
        heat.heatflow = atom->heatflow;
        heat.wall_temperature =
            temperature_ivar >= 0 ? input->variable->compute_equal(temperature_ivar) : wall_temperature;
        if (!std::isfinite(heat.wall_temperature))
            error->all(FLERR, "{}: the wall's temperature is {}, must be finite", context, heat.wall_temperature);
        heat.nlocal = atom->nlocal;
        heat.newton = false;
        engine.set_heat(heat);
    }
}

void FixWallDashpot::stage(int i, int c, const double *n, double delta, double reff, const double *vwall)
{
    const double *v = atom->v[i];
    const int slot = i * nper + c;
    if (engine.stage(model_of_type[atom->type[i]], i, -1, slot, n[0], n[1], n[2], delta, atom->radius[i], 0.0,
                     v[0] - vwall[0], v[1] - vwall[1], v[2] - vwall[2], mass_of(i), reff, atom->omega[i], nullptr))
        flush();
}

/* Evaluates the staged contacts and applies their forces and torques. In a run's setup the
 * forces are recomputed at a state already integrated: the laws get dt = 0 and the history is
 * not stored back (as fix wall/gran does), or the springs would advance twice. */
void FixWallDashpot::flush()
{
    const int n = engine.size();
    if (n == 0) return;
    const bool setup = update->setupflag;
    double **f = atom->f, **torque = atom->torque, **x = atom->x;
    const double *radius = atom->radius;
    try {
        ContactEngine::Chunk &c = engine.evaluate(store, setup ? 0.0 : update->dt, !setup);
        for (int k = 0; k < n; k++) {
            const int i = c.a[k];
            const double *F = c.force + 3 * k, *T = c.ta + 3 * k;
            for (int d = 0; d < 3; d++) {
                f[i][d] += F[d];
                torque[i][d] += T[d];
                sums[d] -= F[d];
            }
            sums[3] += 1.0;
            if (energy_flag)
                for (int q = 0; q < NFAMILY; q++) {
                    sums[4] += c.power[q][k];
                    sums[5 + q] += c.power[q][k];
                    sums[9] += c.elastic[q][k];
                }
            if (contacts_flag) {
                double *a = array_atom[i];
                const double *nv = c.norm + 3 * k;
                const double arm = radius[i] - c.delta[k];
                a[0] += 1.0;
                for (int d = 0; d < 3; d++) {
                    a[1 + d] += F[d];
                    a[4 + d] = x[i][d] - arm * nv[d];
                }
                a[7] = radius[i];
            }
        }
    } catch (std::exception &e) {
        error->one(FLERR, "{}: {}", context, e.what());
    }
    engine.reset();
}

bool FixWallDashpot::acts(int i, int c, double delta) const
{
    if (delta > 0.0) return true;
    if (!layout.adhesive) return false;
    const size_t s = (size_t) i * nper + c;
    return store.touched[s] && -delta <= store.reach[s];
}

void FixWallDashpot::forget(int i, int c)
{
    store.zero((size_t) i * nper + c);
}

void FixWallDashpot::move_contact(int i, int from, int to)
{
    const size_t sf = (size_t) i * nper + from, st = (size_t) i * nper + to;
    key[st] = key[sf];
    for (int q = 0; q < NFAMILY; q++) {
        const int w = layout.width[q];
        std::copy_n(store.fam[q].begin() + sf * w, w, store.fam[q].begin() + st * w);
    }
    if (layout.adhesive) store.reach[st] = store.reach[sf];
    store.touched[st] = store.touched[sf];
    store.zero(sf);
}

double FixWallDashpot::reach_of(int i) const
{
    if (!layout.adhesive) return 0.0;
    double r = 0.0;
    for (int c = 0; c < ncontact[i]; c++) {
        const size_t s = (size_t) i * nper + c;
        if (store.touched[s]) r = std::max(r, store.reach[s]);
    }
    return r;
}

/* 1-3 the force on the wall, 4 the number of contacts, 5 the dissipated power, 6-9 by family,
 * 10 the elastic energy: summed over the ranks once per step, when first asked. */
double FixWallDashpot::compute_vector(int k)
{
    if (!reduced) {
        MPI_Allreduce(sums, totals, NVECTOR, MPI_DOUBLE, MPI_SUM, world);
        reduced = 1;
    }
    return totals[k];
}

/* ---------------------------------------------------------------------- the records */

void FixWallDashpot::resize_per_atom(int n, int per)
{
    if (per != nper || store.size() == 0) {
        nper = per;
        store.assign((size_t) n * per, layout);
        ncontact.assign(n, 0);
        key.assign((size_t) n * per, 0);
    } else {
        const size_t slots = (size_t) n * per;
        for (int q = 0; q < NFAMILY; q++) store.fam[q].resize(slots * layout.width[q], 0.0);
        if (layout.adhesive) store.reach.resize(slots, 0.0);
        store.touched.resize(slots, 0);
        ncontact.resize(n, 0);
        key.resize(slots, 0);
    }
    nmax_atoms = n;
    if (contacts_flag) memory->grow(array_atom, n, 8, "wall/dashpot:array_atom");
    maxexchange = 1 + nper * (1 + layout.nvalues) + (contacts_flag ? 8 : 0);
}

void FixWallDashpot::grow_arrays(int nmax)
{
    if (nmax > nmax_atoms) resize_per_atom(nmax, nper);
}

void FixWallDashpot::copy_arrays(int i, int j, int /*delflag*/)
{
    for (int c = 0; c < nper; c++) {
        const size_t si = (size_t) i * nper + c, sj = (size_t) j * nper + c;
        key[sj] = key[si];
        for (int q = 0; q < NFAMILY; q++) {
            const int w = layout.width[q];
            std::copy_n(store.fam[q].begin() + si * w, w, store.fam[q].begin() + sj * w);
        }
        if (layout.adhesive) store.reach[sj] = store.reach[si];
        store.touched[sj] = store.touched[si];
    }
    ncontact[j] = ncontact[i];
    if (contacts_flag)
        for (int m = 0; m < 8; m++) array_atom[j][m] = array_atom[i][m];
}

void FixWallDashpot::set_arrays(int i)
{
    ncontact[i] = 0;
    for (int c = 0; c < nper; c++) store.zero((size_t) i * nper + c);
    if (contacts_flag)
        for (int m = 0; m < 8; m++) array_atom[i][m] = 0.0;
}

/* An atom's contacts: their count, then each one's key and record. */
int FixWallDashpot::pack_exchange(int i, double *buf)
{
    int m = 0;
    buf[m++] = ncontact[i];
    for (int c = 0; c < ncontact[i]; c++) {
        const size_t s = (size_t) i * nper + c;
        buf[m++] = key[s];
        store.get(s, buf + m);
        m += layout.nvalues;
    }
    if (contacts_flag)
        for (int q = 0; q < 8; q++) buf[m++] = array_atom[i][q];
    return m;
}

int FixWallDashpot::unpack_exchange(int i, double *buf)
{
    int m = 0;
    const int count = (int) buf[m++];
    ncontact[i] = count;
    for (int c = 0; c < nper; c++) {
        const size_t s = (size_t) i * nper + c;
        if (c < count) {
            key[s] = (int) buf[m++];
            store.set(s, buf + m);
            m += layout.nvalues;
        } else {
            store.zero(s);
        }
    }
    if (contacts_flag)
        for (int q = 0; q < 8; q++) array_atom[i][q] = buf[m++];
    return m;
}

/* Restart records: the length (counting itself, the Atom::RESTART convention), the record
 * layout's length, the count, then each contact's key and record. */
int FixWallDashpot::pack_restart(int i, double *buf)
{
    int m = 1;
    buf[m++] = layout.nvalues;
    buf[m++] = ncontact[i];
    for (int c = 0; c < ncontact[i]; c++) {
        const size_t s = (size_t) i * nper + c;
        buf[m++] = key[s];
        store.get(s, buf + m);
        m += layout.nvalues;
    }
    buf[0] = m;
    return m;
}

void FixWallDashpot::unpack_restart(int nlocal, int nth)
{
    double **extra = atom->extra;
    int m = 0;
    for (int k = 0; k < nth; k++) m += static_cast<int>(extra[nlocal][m]);
    const double *buf = &extra[nlocal][m];
    const int nvalues = (int) buf[1], count = (int) buf[2];
    set_arrays(nlocal);
    if (nvalues != layout.nvalues || count > nper) {
        // written by other laws (or another region): the history cannot be read back
        if (count > 0) restart_mismatch++;
        return;
    }
    int q = 3;
    for (int c = 0; c < count; c++) {
        const size_t s = (size_t) nlocal * nper + c;
        key[s] = (int) buf[q++];
        store.set(s, buf + q);
        q += nvalues;
    }
    ncontact[nlocal] = count;
}

int FixWallDashpot::size_restart(int i)
{
    return 3 + ncontact[i] * (1 + layout.nvalues);
}

int FixWallDashpot::maxsize_restart()
{
    return 3 + nper * (1 + layout.nvalues);
}

double FixWallDashpot::memory_usage()
{
    double bytes = (double) store.size() * (layout.nvalues + 1) * sizeof(double);
    bytes += (double) (ncontact.size() + key.size()) * sizeof(int);
    if (contacts_flag) bytes += (double) nmax_atoms * 8 * sizeof(double);
    return bytes;
}
