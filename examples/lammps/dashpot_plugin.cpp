/* Registers pair_style dashpot and its history fix with LAMMPS ("plugin load dashpotplugin.so"). */
#include "dashpot_lammps_plugin.h"
#include "fix_dashpot_history.h"
#include "fix_wall_dashpot_region.h"
#include "pair_dashpot.h"

#ifndef DASHPOT_LAMMPS_VERSION
#error "build with -DDASHPOT_LAMMPS_VERSION='\"22 Jul 2025\"' (the LAMMPS version built against)"
#endif

using namespace LAMMPS_NS;

static void *create_pair_dashpot(void *lmp)
{
    return new PairDashpot(static_cast<LAMMPS *>(lmp));
}

static void *create_fix_dashpot_history(void *lmp, int argc, char **argv)
{
    return new FixDashpotHistory(static_cast<LAMMPS *>(lmp), argc, argv);
}

template <class F> static void *create_fix(void *lmp, int argc, char **argv)
{
    return new F(static_cast<LAMMPS *>(lmp), argc, argv);
}

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *register_fn)
{
    auto reg = reinterpret_cast<dashpot_lmp_register_fn>(register_fn);
    dashpot_lmp_plugin_record record;
    record.version = DASHPOT_LAMMPS_VERSION;
    record.style = "pair";
    record.name = "dashpot";
    record.info = "granular contact (normal, tangential, rolling, twisting laws with history) from dashpot laws through the C ABI";
    record.author = "dashpot project";
    record.creator.v1 = &create_pair_dashpot;
    record.handle = handle;
    reg(&record, lmp);

    record.style = "fix";
    record.name = "DASHPOT/HISTORY";
    record.info = "per-contact history of pair_style dashpot, moved with the atoms and into restarts";
    record.creator.v2 = &create_fix_dashpot_history;
    reg(&record, lmp);

    record.name = "wall/dashpot";
    record.info = "granular walls (planes, z cylinder) with dashpot laws of every family and their history";
    record.creator.v2 = &create_fix<FixWallDashpot>;
    reg(&record, lmp);

    record.name = "wall/dashpot/region";
    record.info = "granular walls of any region, moving or rotating, with dashpot laws and their history";
    record.creator.v2 = &create_fix<FixWallDashpotRegion>;
    reg(&record, lmp);
}
