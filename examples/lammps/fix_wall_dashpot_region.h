/* fix wall/dashpot/region: a granular wall of any LAMMPS region (moving and rotating ones
 * included) whose contacts take dashpot laws; see fix_wall_dashpot.h for the syntax, the
 * semantics and the outputs.
 *
 *   fix ID group wall/dashpot/region MODELS region R [contacts] [plugin_dir=DIR] [energy=1]
 *       [wall=rigid|particle]
 *
 * Each atom touches the region's surfaces at up to the region's maximum number of touching
 * contacts (Region::tmax), each found by Region::surface with its distance, normal and
 * curvature, and keyed by its wall id (Region::Contact::iwall) so that its history follows it
 * from step to step; a contact the region no longer reports (or that stopped acting) is dropped
 * with its history. A moving or rotating region gives each contact the region's velocity at the
 * contact point (Region::velocity_contact), as fix wall/gran/region does. The region's motion
 * is kept in restart files. */
#ifndef DASHPOT_FIX_WALL_DASHPOT_REGION_H
#define DASHPOT_FIX_WALL_DASHPOT_REGION_H

#include "fix_wall_dashpot.h"

namespace LAMMPS_NS {

class FixWallDashpotRegion : public FixWallDashpot {
 public:
    FixWallDashpotRegion(class LAMMPS *, int, char **);
    void init() override;
    void post_force(int) override;
    void write_restart(FILE *) override;
    void restart(char *) override;

 private:
    class Region *region;
    int motion_resetflag;
    std::vector<int> slot_of;    // per region contact of the current atom: its stored contact
    std::vector<char> alive;     // per stored contact of the current atom: reported and acting
    /* The contacts of atom i after the region reported nc: the stored ones it still reports
     * (and that still act) kept, the others dropped, new touching ones added. */
    void update_contacts(int i, int nc);
    [[noreturn]] void no_region();
};

}    // namespace LAMMPS_NS

#endif
