/* Registers pair_style dashpot with LAMMPS ("plugin load dashpotplugin.so"). */
#include "dashpot_lammps_plugin.h"
#include "pair_dashpot.h"

#ifndef DASHPOT_LAMMPS_VERSION
#error "build with -DDASHPOT_LAMMPS_VERSION='\"22 Jul 2025\"' (the LAMMPS version built against)"
#endif

using namespace LAMMPS_NS;

static void *create_pair_dashpot(void *lmp)
{
    return new PairDashpot(static_cast<LAMMPS *>(lmp));
}

extern "C" void lammpsplugin_init(void *lmp, void *handle, void *register_fn)
{
    dashpot_lmp_plugin_record record;
    record.version = DASHPOT_LAMMPS_VERSION;
    record.style = "pair";
    record.name = "dashpot";
    record.info = "normal contact from any dashpot law through the dashpot C ABI";
    record.author = "dashpot project";
    record.creator.v1 = &create_pair_dashpot;
    record.handle = handle;
    (reinterpret_cast<dashpot_lmp_register_fn>(register_fn))(&record, lmp);
}
