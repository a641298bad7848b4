/* fix wall/dashpot/region: see fix_wall_dashpot_region.h. */
#include "fix_wall_dashpot_region.h"

#include "atom.h"
#include "comm.h"
#include "domain.h"
#include "error.h"
#include "region.h"
#include "update.h"

#include <cmath>

using namespace LAMMPS_NS;

FixWallDashpotRegion::FixWallDashpotRegion(LAMMPS *lmp, int narg, char **arg) :
    FixWallDashpot(lmp, narg, arg), region(nullptr), motion_resetflag(0)
{
    region = domain->get_region_by_id(idregion);
    if (!region) no_region();
    if (region->tmax < 1) error->all(FLERR, "{}: region {} has no surface to touch", context, idregion);
    resize_per_atom(atom->nmax, region->tmax);
}

void FixWallDashpotRegion::no_region()
{
    std::string names;
    for (auto *r : domain->get_region_list()) names += std::string(names.empty() ? "" : ", ") + r->id;
    error->all(FLERR, "{}: region {} does not exist (defined regions: {})", context, idregion,
               names.empty() ? "none" : names);
}

void FixWallDashpotRegion::init()
{
    FixWallDashpot::init();
    Region *now = domain->get_region_by_id(idregion);
    if (!now) no_region();
    if (now != region) {
        // the region was deleted and defined again between runs
        if (now->tmax != region->tmax)
            error->all(FLERR, "{}: region {} was redefined with another number of surfaces: define the fix again",
                       context, idregion);
        region = now;
        if (comm->me == 0)
            error->warning(FLERR, "{}: region {} changed between runs: its motion restarts", context, idregion);
        region->reset_vel();
    }
    if (motion_resetflag) {
        if (comm->me == 0)
            error->warning(FLERR, "{}: region {} differs from the one of the restart file: its motion restarts",
                           context, idregion);
        region->reset_vel();
        motion_resetflag = 0;
    }
}

void FixWallDashpotRegion::update_contacts(int i, int nc)
{
    const int nold = ncontact[i];
    // most atoms of a region's fix touch none of its surfaces, now or at the last step
    if (nc == 0 && nold == 0) return;
    const double radius = atom->radius[i];
    int *keys = key.data() + (size_t) i * nper;
    // the common case, one stored contact reported again on its surface and still acting: kept
    if (nc == 1 && nold == 1 && keys[0] == region->contact[0].iwall && acts(i, 0, radius - region->contact[0].r)) {
        slot_of.resize(1);
        slot_of[0] = 0;
        return;
    }
    slot_of.assign(nc, -1);
    alive.assign(nper, 0);
    for (int ic = 0; ic < nc; ic++) {
        const int iwall = region->contact[ic].iwall;
        for (int c = 0; c < nold; c++)
            if (keys[c] == iwall) {
                if (acts(i, c, radius - region->contact[ic].r)) {
                    alive[c] = 1;
                    slot_of[ic] = c;
                }
                break;
            }
    }
    // the stored contacts that ended: dropped, the last one moving into the place
    for (int c = 0; c < ncontact[i];) {
        if (alive[c]) {
            c++;
            continue;
        }
        const int last = ncontact[i] - 1;
        forget(i, c);
        if (last != c) {
            move_contact(i, last, c);
            alive[c] = alive[last];
            for (int ic = 0; ic < nc; ic++)
                if (slot_of[ic] == last) slot_of[ic] = c;
        }
        alive[last] = 0;
        ncontact[i]--;
    }
    // the new ones, touching: a zero history
    for (int ic = 0; ic < nc; ic++)
        if (slot_of[ic] < 0 && radius - region->contact[ic].r > 0.0) {
            const int c = ncontact[i]++;
            forget(i, c);
            keys[c] = region->contact[ic].iwall;
            slot_of[ic] = c;
        }
}

void FixWallDashpotRegion::post_force(int /*vflag*/)
{
    update_rigid_masses();
    begin_step();
    const int dynamic = region->dynamic_check();
    if (dynamic) {
        region->prematch();
        region->set_velocity();
    }
    double **x = atom->x;
    const double *radius = atom->radius;
    const int *mask = atom->mask;
    const int nlocal = atom->nlocal;
    const int tmax = region->tmax;
    const bool adhesive = layout.adhesive;
    for (int i = 0; i < nlocal; i++) {
        if (!(mask[i] & groupbit)) continue;
        int nc = 0;
        // a particle whose centre left the region touches none of its surfaces
        if (region->match(x[i][0], x[i][1], x[i][2])) {
            nc = region->surface(x[i][0], x[i][1], x[i][2], radius[i] + (adhesive ? reach_of(i) : 0.0));
            if (nc > tmax)
                error->one(FLERR, "{}: atom {} touches {} surfaces of region {}, more than its {}", context,
                           atom->tag[i], nc, idregion, tmax);
        }
        // most atoms touch none of the surfaces, now or at the last step: no call
        if (nc == 0 && ncontact[i] == 0) continue;
        update_contacts(i, nc);
        for (int ic = 0; ic < nc; ic++) {
            const int c = slot_of[ic];
            if (c < 0) continue;
            const Region::Contact &rc = region->contact[ic];
            if (!(rc.r > 0.0)) continue;    // the centre on the surface: no normal
            const double n[3] = {rc.delx / rc.r, rc.dely / rc.r, rc.delz / rc.r};
            double vwall[3] = {0.0, 0.0, 0.0};
            if (dynamic) region->velocity_contact(vwall, x[i], ic);
            const double rw = rc.radius;
            const double reff = rw == 0.0 ? radius[i] : radius[i] * rw / (radius[i] + rw);
            stage(i, c, n, radius[i] - rc.r, reff, vwall);
        }
    }
    flush();
}

/* Restart files: the region's motion (as fix wall/gran/region keeps it). */
void FixWallDashpotRegion::write_restart(FILE *fp)
{
    if (comm->me != 0) return;
    int len = 0;
    region->length_restart_string(len);
    fwrite(&len, sizeof(int), 1, fp);
    region->write_restart(fp);
}

void FixWallDashpotRegion::restart(char *buf)
{
    int n = 0;
    if (!region->restart(buf, n)) motion_resetflag = 1;
}
